//! FFD injectivity: check every lattice of a JSON file (default `examples/ffd/three.json`) on
//! the filtered path and re-verify each certificate through the other Jacobian route.
//!
//! `cargo run --example ffd_check [LATTICES.json]`

use geocert::ffd::{
    check_injectivity, lattices_from_json, verify_injectivity_certificate, CheckOptions,
    InjectivityCertificate,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let file = std::env::args()
        .nth(1)
        .unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/examples/ffd/three.json").into());
    let lattices = lattices_from_json(&std::fs::read_to_string(&file)?)?;
    for (i, lattice) in lattices.iter().enumerate() {
        let report = check_injectivity(lattice, CheckOptions::new())?;
        print!(
            "lattice {i}: {} ({} leaves)",
            report.verdict.name(),
            report.leaves
        );
        match InjectivityCertificate::from_report(lattice, &report) {
            Some(certificate) => println!("; {}", verify_injectivity_certificate(&certificate)?),
            None => println!("; no certificate (undecided)"),
        }
    }
    Ok(())
}
