//! A small statistical battery for the kernels' generators, each test on the streams as the
//! kernels draw them (many short streams keyed by index and pass):
//!
//! - `uniformity`: chi-square of draws over 4096 equal bins (fine bins catch coarse outputs);
//! - `serial`: lag-1..8 correlation along one long stream, the largest |z| = |r|·√n;
//! - `pairs`: chi-square of successive pairs (draws 2k, 2k + 1 of a stream) over 64 × 64 bins;
//! - `index_neighbours`, `pass_neighbours`: chi-square over 64 × 64 bins of the k-th draws of
//!   streams (i, p) and (i + 1, p), and of (i, p) and (i, p + 1): independent streams fill
//!   the square evenly.
//!
//! Each test fails at significance [`SIGNIFICANCE`] (the chi-squares through the
//! Wilson–Hilferty approximation of the quantile, the lags with a Bonferroni split).

use super::StreamRng;

/// The chance that a good generator fails any one test.
pub const SIGNIFICANCE: f64 = 0.001;
/// Draws per stream in the stream-wise tests: as many as a photon pass takes.
const DRAWS: u32 = 8;
const SEED: u32 = 1;
const SALT: u32 = crate::rng::PHOTON_STREAM;
const FINE_BINS: usize = 4096;
const SIDE: usize = 64;
const LAGS: usize = 8;

/// One test's result.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    pub test: &'static str,
    /// "chi2" or "max_abs_z".
    pub kind: &'static str,
    pub statistic: f64,
    /// The statistic's critical value at [`SIGNIFICANCE`]; it passes below.
    pub limit: f64,
    pub passed: bool,
}

/// Runs every test on about `n` draws each (n ≥ 2¹⁶).
pub fn run<G: StreamRng>(n: u32) -> Vec<Outcome> {
    vec![
        uniformity::<G>(n),
        serial::<G>(n),
        pairs::<G>(n),
        index_neighbours::<G>(n),
        pass_neighbours::<G>(n),
    ]
}

fn outcome(test: &'static str, kind: &'static str, statistic: f64, limit: f64) -> Outcome {
    Outcome {
        test,
        kind,
        statistic,
        limit,
        passed: statistic.is_finite() && statistic < limit,
    }
}

fn bin(v: f32, bins: usize) -> usize {
    ((v as f64 * bins as f64) as usize).min(bins - 1)
}

/// Pearson's statistic of `counts` against equal expectations.
fn chi_square(counts: &[u32]) -> f64 {
    let total: u64 = counts.iter().map(|&c| u64::from(c)).sum();
    let expected = total as f64 / counts.len() as f64;
    counts
        .iter()
        .map(|&c| (f64::from(c) - expected).powi(2) / expected)
        .sum()
}

/// The upper `alpha` point of the standard normal (Abramowitz & Stegun 26.2.23, |error| <
/// 4.5e-4, plenty for a critical value).
pub fn normal_upper(alpha: f64) -> f64 {
    let t = (-2.0 * alpha.ln()).sqrt();
    t - (2.515517 + 0.802853 * t + 0.010328 * t * t)
        / (1.0 + 1.432788 * t + 0.189269 * t * t + 0.001308 * t * t * t)
}

/// The upper `alpha` point of chi-square with `df` degrees of freedom (Wilson–Hilferty).
pub fn chi_square_upper(df: f64, alpha: f64) -> f64 {
    let c = 2.0 / (9.0 * df);
    df * (1.0 - c + normal_upper(alpha) * c.sqrt()).powi(3)
}

fn uniformity<G: StreamRng>(n: u32) -> Outcome {
    let mut counts = vec![0u32; FINE_BINS];
    for index in 0..n / DRAWS {
        let mut rng = G::start(SEED, SALT, 0, index);
        for _ in 0..DRAWS {
            counts[bin(rng.next_f32(), FINE_BINS)] += 1;
        }
    }
    let limit = chi_square_upper((FINE_BINS - 1) as f64, SIGNIFICANCE);
    outcome("uniformity", "chi2", chi_square(&counts), limit)
}

fn serial<G: StreamRng>(n: u32) -> Outcome {
    let mut rng = G::start(SEED, SALT, 0, 0);
    let draws: Vec<f64> = (0..n).map(|_| f64::from(rng.next_f32())).collect();
    let mean = draws.iter().sum::<f64>() / f64::from(n);
    let variance = draws.iter().map(|x| (x - mean).powi(2)).sum::<f64>();
    let worst = (1..=LAGS)
        .map(|lag| {
            let covariance: f64 = draws
                .iter()
                .zip(&draws[lag..])
                .map(|(a, b)| (a - mean) * (b - mean))
                .sum();
            (covariance / variance).abs() * f64::from(n).sqrt()
        })
        .fold(0.0, f64::max);
    // Two-sided, split over the lags.
    let limit = normal_upper(SIGNIFICANCE / (2 * LAGS) as f64);
    outcome("serial", "max_abs_z", worst, limit)
}

/// Chi-square of a 64 × 64 histogram of `pairs` (x, y) in [0, 1)².
fn square(pairs: impl Iterator<Item = (f32, f32)>) -> f64 {
    let mut counts = vec![0u32; SIDE * SIDE];
    for (x, y) in pairs {
        counts[bin(x, SIDE) * SIDE + bin(y, SIDE)] += 1;
    }
    chi_square(&counts)
}

fn square_limit() -> f64 {
    chi_square_upper((SIDE * SIDE - 1) as f64, SIGNIFICANCE)
}

fn pairs<G: StreamRng>(n: u32) -> Outcome {
    let pairs = (0..n / DRAWS).flat_map(|index| {
        let mut rng = G::start(SEED, SALT, 0, index);
        (0..DRAWS / 2).map(move |_| (rng.next_f32(), rng.next_f32()))
    });
    outcome("pairs", "chi2", square(pairs), square_limit())
}

/// Pairs of the k-th draws of stream `a(j)` and stream `b(j)`, for j < n / DRAWS.
fn neighbour_square<G: StreamRng>(n: u32, streams: impl Fn(u32) -> (G, G)) -> f64 {
    square((0..n / DRAWS).flat_map(|j| {
        let (mut a, mut b) = streams(j);
        (0..DRAWS).map(move |_| (a.next_f32(), b.next_f32()))
    }))
}

fn index_neighbours<G: StreamRng>(n: u32) -> Outcome {
    // Disjoint pairs (2j, 2j + 1), so no stream is counted twice.
    let statistic = neighbour_square::<G>(n, |j| {
        (
            G::start(SEED, SALT, 3, 2 * j),
            G::start(SEED, SALT, 3, 2 * j + 1),
        )
    });
    outcome("index_neighbours", "chi2", statistic, square_limit())
}

fn pass_neighbours<G: StreamRng>(n: u32) -> Outcome {
    let statistic = neighbour_square::<G>(n, |j| {
        let pass = 2 * (j % 32);
        (
            G::start(SEED, SALT, pass, j),
            G::start(SEED, SALT, pass + 1, j),
        )
    });
    outcome("pass_neighbours", "chi2", statistic, square_limit())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::{FractSin, Pcg, TalkFloat, Tea};

    const N: u32 = 1 << 19;

    fn failures<G: StreamRng>() -> Vec<Outcome> {
        run::<G>(N).into_iter().filter(|o| !o.passed).collect()
    }

    #[test]
    fn critical_values_match_tables() {
        // z at 0.001 is 3.090; chi-square(4095) at 0.999 is about 4383 (Wilson–Hilferty is
        // within 0.1 of the exact value at this size).
        assert!((normal_upper(0.001) - 3.090).abs() < 1e-3);
        assert!((chi_square_upper(4095.0, 0.001) - 4383.0).abs() < 3.0);
        assert!((chi_square_upper(10.0, 0.001) - 29.59).abs() < 0.3);
    }

    #[test]
    fn pcg_passes_every_test() {
        assert_eq!(failures::<Pcg>(), vec![]);
    }

    #[test]
    fn talk_float_passes_every_test() {
        assert_eq!(failures::<TalkFloat>(), vec![]);
    }

    #[test]
    fn tea_passes_every_test() {
        assert_eq!(failures::<Tea>(), vec![]);
    }

    /// The battery can fail: the noise function's coarse f32 fraction leaves most of the fine
    /// uniformity bins empty.
    #[test]
    fn fract_sin_fails_uniformity() {
        let failed: Vec<&str> = failures::<FractSin>().iter().map(|o| o.test).collect();
        assert!(failed.contains(&"uniformity"), "failed: {failed:?}");
    }

    /// A bare LCG's low bits (seeded with the index alone) fail the neighbour test: stream
    /// i + 1 is stream i shifted by a constant.
    #[test]
    fn bare_lcg_fails_index_neighbours() {
        struct Lcg(u32);
        impl StreamRng for Lcg {
            const NAME: &'static str = "lcg";
            fn start(_: u32, _: u32, pass: u32, index: u32) -> Self {
                Lcg(index ^ (pass << 20))
            }
            fn next_f32(&mut self) -> f32 {
                self.0 = self.0.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                (self.0 & 0xffff) as f32 / 65_536.0
            }
        }
        let failed: Vec<&str> = failures::<Lcg>().iter().map(|o| o.test).collect();
        assert!(failed.contains(&"index_neighbours"), "failed: {failed:?}");
    }
}
