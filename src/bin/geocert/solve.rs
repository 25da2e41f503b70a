//! `geocert solve`: every root of a polynomial system on a box, certified, and
//! `geocert solve verify-cert`: the independent re-check of a root-certificate file.

use crate::out::{choice, pretty, read, status, write};
use clap::Subcommand;
use geocert::bernstein::Limits;
use geocert::num::rational_to_string;
use geocert::solve::{
    solution_certificate, solve, system_from_json, verify_solution_certificate, ClusterReason,
    SolveOptions,
};
use geocert::Path;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub(crate) struct Args {
    #[command(subcommand)]
    verify: Option<Verify>,
    /// `{"box": [["a","b"], ..], "equations": [{"degrees", "coeffs"} | {"terms": [[[e..], c], ..]}, ..]}`.
    #[arg(required = true)]
    system: Option<PathBuf>,
    #[arg(long, default_value_t = Path::Filtered, value_parser = choice::<Path>(Path::NAMES))]
    path: Path,
    /// Deepest subdivision level, counted per side (a box split this many times along every
    /// axis that is neither culled nor certified is reported as a cluster).
    #[arg(long, default_value_t = 40)]
    max_depth: u32,
    /// Refine certified roots to boxes of this width relative to the domain (0: keep the
    /// first certified box).
    #[arg(long, default_value_t = 1e-15)]
    tol: f64,
    /// Most boxes examined.
    #[arg(long, default_value_t = 200_000)]
    max_boxes: usize,
    /// Wall-clock budget in seconds.
    #[arg(long)]
    time_limit: Option<f64>,
    /// Write the roots' certificates here.
    #[arg(long)]
    cert: Option<PathBuf>,
    #[arg(long)]
    json: bool,
}

#[derive(Subcommand)]
enum Verify {
    /// Re-check every root of a certificate file written by `solve --cert`.
    VerifyCert {
        /// The certificate file.
        file: PathBuf,
    },
}

pub(crate) fn run(a: Args) -> Result<ExitCode, String> {
    if let Some(Verify::VerifyCert { file }) = a.verify {
        return verify(&file);
    }
    let file = a.system.ok_or("a system file is required")?;
    let system = system_from_json(&read(&file)?).map_err(|e| format!("{}: {e}", file.display()))?;
    let time_limit = crate::out::time_limit(a.time_limit)?;
    if !(a.tol.is_finite() && a.tol >= 0.0) {
        return Err(format!(
            "--tol must be a non-negative number, got {}",
            a.tol
        ));
    }
    let opts = SolveOptions::new()
        .with_path(a.path)
        .with_tolerance(a.tol)
        .with_limits(
            Limits::new()
                .with_max_depth(a.max_depth)
                .with_max_boxes(a.max_boxes)
                .with_time_limit(time_limit),
        );
    let clock = std::time::Instant::now();
    let solution = solve(&system, &opts).map_err(|e| format!("{}: {e}", file.display()))?;
    let seconds = clock.elapsed().as_secs_f64();
    if let Some(c) = &a.cert {
        write(c, pretty(&solution_certificate(&system, &solution))?)?;
    }
    let exact_box = |b: &[(geocert::num::Rational, geocert::num::Rational)]| {
        b.iter()
            .map(|(lo, hi)| [rational_to_string(lo), rational_to_string(hi)])
            .collect::<Vec<_>>()
    };
    if a.json {
        let v = serde_json::json!({
            "roots": solution.roots.iter().map(|r| serde_json::json!({
                "box": exact_box(&r.bounds),
                "approx": r.approx,
                "error_bound": r.error_bound,
                "certificate": "miranda+diagonal-dominance",
            })).collect::<Vec<_>>(),
            "clusters": solution.clusters.iter().map(|c| serde_json::json!({
                "box": exact_box(&c.bounds),
                "reason": c.reason,
                "max_abs_f": c.max_abs_f,
            })).collect::<Vec<_>>(),
            "boxes_visited": solution.boxes_visited,
            "seconds": seconds,
            "path": solution.path.name(),
        });
        println!("{v}");
    } else {
        println!(
            "{} certified roots, {} clusters, {} boxes in {seconds:.4} s ({} path)",
            solution.roots.len(),
            solution.clusters.len(),
            solution.boxes_visited,
            solution.path
        );
        for r in &solution.roots {
            println!("  root {:?} ± {:.1e}", r.approx, r.error_bound);
        }
        for c in &solution.clusters {
            let why = match c.reason {
                ClusterReason::DepthLimit => "depth limit",
                ClusterReason::DomainBoundary => "on the domain boundary",
                ClusterReason::Budget => "box or time budget",
                ClusterReason::Uncertain => "rounding (fast path)",
            };
            let centre: Vec<f64> = c
                .bounds
                .iter()
                .map(|(lo, hi)| {
                    geocert::num::rational_to_f64(
                        &((lo + hi) / geocert::num::Rational::from_integer(2.into())),
                    )
                })
                .collect();
            println!("  cluster near {centre:?} ({why}), |f| ≤ {:?}", c.max_abs_f);
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn verify(file: &std::path::Path) -> Result<ExitCode, String> {
    let outcomes = verify_solution_certificate(&read(file)?)
        .map_err(|e| format!("{}: {e}", file.display()))?;
    let mut ok = true;
    for (i, o) in outcomes.iter().enumerate() {
        match o {
            Ok(c) => println!("root {i}: valid: {c}"),
            Err(e) => {
                ok = false;
                println!("root {i}: invalid: {e}");
            }
        }
    }
    Ok(status(ok))
}
