//! Built-in analytic volumes, sampled and quantised to bytes like CT data (so every sample is an
//! exact small integer): a sphere's distance ramp, a gyroid, and a sparse "fuel-like" field of
//! a few Gaussian blobs on an empty background.

use super::{DiamondError, Field};

/// The names [`builtin_volume`] knows.
pub const BUILTIN_VOLUMES: [&str; 3] = ["sphere", "gyroid", "fuel"];

/// The built-in volume `name` with `side³` samples (`side ≥ 3`; `2^N + 1` needs no padding).
pub fn builtin_volume(name: &str, side: usize) -> Result<Field<3>, DiamondError> {
    if !(3..=1025).contains(&side) {
        return Err(DiamondError::Volume(format!(
            "built-in volumes have 3 to 1025 samples per side, not {side}"
        )));
    }
    let s = (side - 1) as f64;
    let sample: Box<dyn Fn(f64, f64, f64) -> f64> = match name {
        // 255 at the centre falling linearly to 0 at distance 0.5 (unit cube coordinates).
        "sphere" => Box::new(|x, y, z| {
            let r = ((x - 0.5).powi(2) + (y - 0.5).powi(2) + (z - 0.5).powi(2)).sqrt();
            255.0 * (1.0 - 2.0 * r).max(0.0)
        }),
        // sin x cos y + sin y cos z + sin z cos x over three periods, mapped to 0..255.
        "gyroid" => Box::new(|x, y, z| {
            let k = 6.0 * std::f64::consts::PI;
            let (x, y, z) = (k * x, k * y, k * z);
            let g = x.sin() * y.cos() + y.sin() * z.cos() + z.sin() * x.cos();
            127.5 + 127.5 * (g / 1.5).clamp(-1.0, 1.0)
        }),
        // Five blobs of different widths and heights; most of the volume is exactly 0.
        "fuel" => Box::new(|x, y, z| {
            const BLOBS: [([f64; 3], f64, f64); 5] = [
                ([0.30, 0.35, 0.40], 0.06, 255.0),
                ([0.62, 0.55, 0.35], 0.045, 200.0),
                ([0.50, 0.70, 0.65], 0.08, 230.0),
                ([0.72, 0.28, 0.70], 0.03, 180.0),
                ([0.40, 0.50, 0.72], 0.05, 150.0),
            ];
            let v: f64 = BLOBS
                .iter()
                .map(|&(c, w, a)| {
                    let d2 = (x - c[0]).powi(2) + (y - c[1]).powi(2) + (z - c[2]).powi(2);
                    a * (-d2 / (2.0 * w * w)).exp()
                })
                .sum();
            if v < 1.0 {
                0.0
            } else {
                v.min(255.0)
            }
        }),
        _ => {
            return Err(DiamondError::Volume(format!(
                "no built-in volume {name:?} (known: {})",
                BUILTIN_VOLUMES.join(", ")
            )))
        }
    };
    let mut values = Vec::with_capacity(side * side * side);
    for k in 0..side {
        for j in 0..side {
            for i in 0..side {
                let v = sample(i as f64 / s, j as f64 / s, k as f64 / s);
                values.push(v.round().clamp(0.0, 255.0));
            }
        }
    }
    Field::pad([side; 3], &values)
}
