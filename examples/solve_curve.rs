//! Certified roots and curves: the intersection points of a circle and a cubic, then the
//! curve where a sphere meets a plane, traced with its topology and re-checked.
//!
//! `cargo run --example solve_curve [SYSTEM.json]` (a square system is solved, one equation
//! fewer than unknowns is traced).

use geocert::solve::{
    solve, system_from_json, trace, verify_curves, verify_root, CurveEnd, CurveOptions,
    SolveOptions,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let given = std::env::args()
        .nth(1)
        .map(std::fs::read_to_string)
        .transpose()?;
    let roots = given.clone().unwrap_or_else(|| {
        // x² + y² = 1 and x − 2y + x³/3 = 0 on [−2, 2]².
        r#"{"box": [["-2","2"],["-2","2"]], "equations": [
            {"terms": [[[2,0],1],[[0,2],1],[[0,0],-1]]},
            {"terms": [[[1,0],1],[[0,1],-2],[[3,0],"1/3"]]}]}"#
            .into()
    });
    let system = system_from_json(&roots)?;
    if system.equations.len() == system.unknowns() {
        let s = solve(&system, &SolveOptions::new())?;
        for r in &s.roots {
            println!(
                "root {:?} ± {:.1e}: {}",
                r.approx,
                r.error_bound,
                verify_root(&system, &r.bounds, &r.certificate)?
            );
        }
        println!("{} clusters", s.clusters.len());
        if given.is_some() {
            return Ok(());
        }
    }
    let curve = given.unwrap_or_else(|| {
        // x² + y² + z² = 1/2 and z = x/3 + 1/5 on [−1, 1]³: one closed loop.
        r#"{"box": [["-1","1"],["-1","1"],["-1","1"]], "equations": [
            {"terms": [[[2,0,0],1],[[0,2,0],1],[[0,0,2],1],[[0,0,0],"-1/2"]]},
            {"terms": [[[0,0,1],1],[[1,0,0],"-1/3"],[[0,0,0],"-1/5"]]}]}"#
            .into()
    });
    let system = system_from_json(&curve)?;
    let c = trace(&system, &CurveOptions::new().with_extreme_axis(Some(0)))?;
    for (i, k) in c.components.iter().enumerate() {
        let ends: Vec<String> = k
            .ends
            .iter()
            .map(|e| match e {
                CurveEnd::Face { axis, upper, .. } => {
                    format!("face x{axis} = {}", if *upper { "b" } else { "a" })
                }
                CurveEnd::Cluster { group, .. } => format!("cluster group {group}"),
            })
            .collect();
        println!(
            "component {i}: {} vertices, closed {}, ends {ends:?}, within {:.2e} of the curve",
            k.points.len(),
            k.closed,
            k.hausdorff_bound
        );
    }
    for e in &c.extremes {
        println!(
            "extreme in x at {:?} on component {:?}",
            e.root.approx, e.component
        );
    }
    println!("checker: {}", verify_curves(&system, &c)?);
    Ok(())
}
