//! How far an image A is from a reference B: the figures `kousen diff` prints.
//!
//! Means run over every pixel and every channel (3N values for N pixels), in f64:
//! - relMSE = mean((A − B)² / (B² + 0.01)): the squared error relative to the reference, the
//!   0.01 ([`REL_MSE_EPSILON`]) keeping black reference pixels from dominating;
//! - RMSE = sqrt(mean((A − B)²));
//! - mean ratio = mean(A) / mean(B), per channel and over all channels: 1 when A is unbiased
//!   (NaN or infinite when B's mean is 0).

use render::Image;

/// The term added to B² in the denominator of the relMSE.
pub const REL_MSE_EPSILON: f64 = 1e-2;

/// mean((A − B)² / (B² + 0.01)) over every pixel and channel; B is the reference.
///
/// # Panics
/// If the images differ in size.
pub fn rel_mse(a: &Image, b: &Image) -> f64 {
    mean_over_channels(a, b, |a, b| (a - b).powi(2) / (b * b + REL_MSE_EPSILON))
}

/// sqrt(mean((A − B)²)) over every pixel and channel.
///
/// # Panics
/// If the images differ in size.
pub fn rmse(a: &Image, b: &Image) -> f64 {
    mean_over_channels(a, b, |a, b| (a - b).powi(2)).sqrt()
}

/// The rectangle `[x, y, width, height]` of `image`, which must lie inside it.
pub fn crop(image: &Image, [x, y, width, height]: [u32; 4]) -> Image {
    let pixels = (y..y + height)
        .flat_map(|row| {
            let start = (row * image.width + x) as usize;
            image.pixels[start..start + width as usize].iter().copied()
        })
        .collect();
    Image::new(width, height, pixels)
}

/// mean(A) / mean(B).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeanRatio {
    /// Per channel: red, green, blue.
    pub rgb: [f64; 3],
    /// Over all three channels.
    pub overall: f64,
}

/// mean(A) / mean(B), per channel and over all channels (the sizes may differ).
pub fn mean_ratio(a: &Image, b: &Image) -> MeanRatio {
    let (sum_a, sum_b) = (channel_means(a), channel_means(b));
    MeanRatio {
        rgb: [0, 1, 2].map(|c| sum_a[c] / sum_b[c]),
        overall: sum_a.iter().sum::<f64>() / sum_b.iter().sum::<f64>(),
    }
}

fn channel_means(image: &Image) -> [f64; 3] {
    let mut sum = [0.0f64; 3];
    for p in &image.pixels {
        for (s, c) in sum.iter_mut().zip(p.to_array()) {
            *s += f64::from(c);
        }
    }
    sum.map(|s| s / image.pixels.len() as f64)
}

/// The mean of `term(a, b)` over corresponding channels of corresponding pixels.
fn mean_over_channels(a: &Image, b: &Image, term: impl Fn(f64, f64) -> f64) -> f64 {
    assert!(
        (a.width, a.height) == (b.width, b.height) && a.pixels.len() == b.pixels.len(),
        "images differ in size: {}x{} and {}x{}",
        a.width,
        a.height,
        b.width,
        b.height
    );
    let mut sum = 0.0;
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        for c in 0..3 {
            sum += term(f64::from(p[c]), f64::from(q[c]));
        }
    }
    sum / (3 * a.pixels.len()) as f64
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    fn constant(width: u32, height: u32, value: Vec3) -> Image {
        Image::new(width, height, vec![value; (width * height) as usize])
    }

    #[test]
    fn identical_images_have_no_error_and_ratio_one() {
        let pixels = (0..12).map(|i| Vec3::new(i as f32, 0.5, 2.0 * i as f32 + 1.0));
        let image = Image::new(4, 3, pixels.collect());
        assert_eq!(rel_mse(&image, &image), 0.0);
        assert_eq!(rmse(&image, &image), 0.0);
        let ratio = mean_ratio(&image, &image);
        assert_eq!(ratio.rgb, [1.0; 3]);
        assert_eq!(ratio.overall, 1.0);
    }

    #[test]
    fn crop_takes_the_rectangle_row_by_row() {
        let image = Image::new(4, 3, (0..12).map(|i| Vec3::splat(i as f32)).collect());
        let window = crop(&image, [1, 1, 2, 2]);
        assert_eq!((window.width, window.height), (2, 2));
        let values: Vec<f32> = window.pixels.iter().map(|p| p.x).collect();
        assert_eq!(values, [5.0, 6.0, 9.0, 10.0]);
        assert_eq!(crop(&image, [0, 0, 4, 3]), image);
    }

    #[test]
    fn constant_offset_gives_the_closed_form() {
        // B = (0.5, 1, 2) everywhere, A = B + 0.25: all exact in f32.
        let b = [0.5, 1.0, 2.0];
        let d = 0.25;
        let reference = constant(3, 2, Vec3::from_array(b.map(|v| v as f32)));
        let image = constant(3, 2, Vec3::from_array(b.map(|v| (v + d) as f32)));

        let expected_rel_mse = b.iter().map(|v| d * d / (v * v + 0.01)).sum::<f64>() / 3.0;
        assert!((rel_mse(&image, &reference) - expected_rel_mse).abs() < 1e-15);
        assert!((rmse(&image, &reference) - d).abs() < 1e-15);

        let ratio = mean_ratio(&image, &reference);
        for (r, b) in ratio.rgb.iter().zip(b) {
            assert!((r - (b + d) / b).abs() < 1e-15);
        }
        assert!((ratio.overall - (3.5 + 3.0 * d) / 3.5).abs() < 1e-15);
    }

    #[test]
    fn rel_mse_is_relative_to_the_reference_not_the_image() {
        let reference = constant(1, 1, Vec3::splat(1.0));
        let image = constant(1, 1, Vec3::splat(3.0));
        assert!((rel_mse(&image, &reference) - 4.0 / 1.01).abs() < 1e-12);
        assert!((rel_mse(&reference, &image) - 4.0 / 9.01).abs() < 1e-12);
    }

    #[test]
    #[should_panic(expected = "differ in size")]
    fn different_sizes_panic() {
        rel_mse(&constant(2, 1, Vec3::ONE), &constant(1, 2, Vec3::ONE));
    }
}
