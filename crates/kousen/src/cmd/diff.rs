//! `kousen diff A B`: how far image A is from the reference B, as the figures of
//! [`crate::image_metrics`], one "name value" line each; optionally also as JSON.

use anyhow::bail;
use serde_json::{Value, json};

use crate::cli::DiffArgs;
use crate::image_io::read_image;
use crate::image_metrics::{crop, mean_ratio, rel_mse, rmse};

pub fn run(args: &DiffArgs) -> anyhow::Result<()> {
    let mut image = read_image(&args.image)?;
    let mut reference = read_image(&args.reference)?;
    if (image.width, image.height) != (reference.width, reference.height) {
        bail!(
            "{} is {}x{} but {} is {}x{}: the images must be the same size",
            args.image.display(),
            image.width,
            image.height,
            args.reference.display(),
            reference.width,
            reference.height
        );
    }
    if let Some(window) = args.window {
        let [x, y, w, h] = window;
        if u64::from(x) + u64::from(w) > u64::from(image.width)
            || u64::from(y) + u64::from(h) > u64::from(image.height)
        {
            bail!(
                "--window {x},{y},{w},{h} reaches outside the {}x{} images",
                image.width,
                image.height
            );
        }
        image = crop(&image, window);
        reference = crop(&reference, window);
    }
    let ratio = mean_ratio(&image, &reference);
    // The names are a contract for scripts: printed as "name value", the same keys in JSON.
    let figures = [
        ("rel_mse", rel_mse(&image, &reference)),
        ("rmse", rmse(&image, &reference)),
        ("mean_ratio", ratio.overall),
        ("mean_ratio_r", ratio.rgb[0]),
        ("mean_ratio_g", ratio.rgb[1]),
        ("mean_ratio_b", ratio.rgb[2]),
    ];
    for (name, value) in figures {
        println!("{name} {value}");
    }
    if let Some(path) = &args.json {
        let mut report = json!({
            "image": args.image.display().to_string(),
            "reference": args.reference.display().to_string(),
            "width": image.width,
            "height": image.height,
        });
        if let Some(window) = args.window {
            report["window"] = json!(window);
        }
        for (name, value) in figures {
            // Non-finite figures (the mean ratio against a black reference) become null.
            report[name] = Value::from(value);
        }
        let text = serde_json::to_string_pretty(&report)? + "\n";
        crate::output_file::write_atomically(path, text.as_bytes())?;
    }
    Ok(())
}
