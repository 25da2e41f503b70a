//! Bernstein positivity: decide `p > 0` on the unit box for a polynomial given as JSON
//! (`{"degrees": [..], "coeffs": [..]}`; default: a bivariate one whose minimum is 1/10) on all
//! three paths, and re-check the certificate.
//!
//! `cargo run --example positivity [POLY.json]`

use geocert::bernstein::{
    certificate_for, poly_from_json, prove_positive, verify_certificate_file, PositivityOptions,
};
use geocert::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let value: serde_json::Value = match std::env::args().nth(1) {
        Some(file) => serde_json::from_str(&std::fs::read_to_string(file)?)?,
        // (s − ½)² + t + 1/10, degrees (2, 1).
        None => serde_json::json!({
            "degrees": [2, 1],
            "coeffs": ["7/20", "-3/20", "7/20", "27/20", "17/20", "27/20"],
        }),
    };
    let p = poly_from_json(&value)?;
    for path in [Path::Exact, Path::Fast, Path::Filtered] {
        let verdict = prove_positive(&p, &PositivityOptions::new().with_path(path))?;
        match certificate_for(&p, &verdict) {
            Some(c) => println!("{path}: {}", verify_certificate_file(&c)?),
            None => println!("{path}: {verdict:?}"),
        }
    }
    Ok(())
}
