//! `geocert solve`: every root of a polynomial system on a box, certified, and
//! `geocert solve verify-cert`: the independent re-check of a root-certificate file.

use crate::out::{choice, pretty, read, status, write};
use clap::Subcommand;
use geocert::bernstein::Limits;
use geocert::num::rational_to_string;
use geocert::solve::{
    curve_certificate, piecewise_curve_certificate, piecewise_solution_certificate,
    piecewise_system_from_json, solve_piecewise, trace_piecewise, verify_curve_certificate,
    verify_solution_certificate, Cluster, ClusterReason, CurveEnd, CurveOptions, PiecewiseSystem,
    SolveOptions, CURVE_CERTIFICATE_KIND,
};
use geocert::Path;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub(crate) struct Args {
    #[command(subcommand)]
    verify: Option<Verify>,
    /// `{"box": [["a","b"], ..], "equations": [{"degrees", "coeffs"} | {"terms": [[[e..], c], ..]} | {"rational": {"numerator", "denominator"}} | {"bspline": {"orders", "knots", "coeffs"}}, ..]}`.
    #[arg(required = true)]
    system: Option<PathBuf>,
    #[arg(long, default_value_t = Path::Filtered, value_parser = choice::<Path>(Path::NAMES))]
    path: Path,
    /// Deepest subdivision level, counted per side (a box split this many times along every
    /// axis that is neither culled nor certified is reported as a cluster) [default: 40;
    /// with --curves 16].
    #[arg(long)]
    max_depth: Option<u32>,
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
    /// Write the roots' (or the curve's) certificates here.
    #[arg(long)]
    cert: Option<PathBuf>,
    /// Trace the solution curve of n − 1 equations in n unknowns instead of isolating roots.
    #[arg(long)]
    curves: bool,
    /// With --curves: the widest arc box relative to the domain's side.
    #[arg(long, default_value_t = 1.0 / 16.0)]
    resolution: f64,
    /// With --curves: report the curve's extreme points along this axis (0-based).
    #[arg(long)]
    extreme_axis: Option<usize>,
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
    let file = a.system.clone().ok_or("a system file is required")?;
    let system = piecewise_system_from_json(&read(&file)?)
        .map_err(|e| format!("{}: {e}", file.display()))?;
    let time_limit = crate::out::time_limit(a.time_limit)?;
    if !(a.tol.is_finite() && a.tol >= 0.0) {
        return Err(format!(
            "--tol must be a non-negative number, got {}",
            a.tol
        ));
    }
    if a.curves {
        return curves(&a, &file, &system, time_limit);
    }
    let opts = SolveOptions::new()
        .with_path(a.path)
        .with_tolerance(a.tol)
        .with_limits(
            Limits::new()
                .with_max_depth(a.max_depth.unwrap_or(40))
                .with_max_boxes(a.max_boxes)
                .with_time_limit(time_limit),
        );
    let clock = std::time::Instant::now();
    let solution =
        solve_piecewise(&system, &opts).map_err(|e| format!("{}: {e}", file.display()))?;
    let seconds = clock.elapsed().as_secs_f64();
    if let Some(c) = &a.cert {
        write(
            c,
            pretty(&piecewise_solution_certificate(&system, &solution))?,
        )?;
    }
    if a.json {
        let v = serde_json::json!({
            "roots": solution.roots.iter().map(|r| {
                let mut root = serde_json::json!({
                    "box": exact_box(&r.bounds),
                    "approx": r.approx,
                    "error_bound": r.error_bound,
                    "certificate": "miranda+diagonal-dominance",
                });
                if let Some(p) = &r.certificate.point {
                    root["point"] = p.iter().map(rational_to_string).collect();
                    root["certificate"] = "miranda+diagonal-dominance+exact-zero".into();
                }
                root
            }).collect::<Vec<_>>(),
            "clusters": solution.clusters.iter().map(cluster_json).collect::<Vec<_>>(),
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
            match &r.certificate.point {
                Some(p) => {
                    let p: Vec<String> = p.iter().map(rational_to_string).collect();
                    println!(
                        "  root [{}] exactly, on the domain boundary (its box reaches across it)",
                        p.join(", ")
                    );
                }
                None => println!("  root {:?} ± {:.1e}", r.approx, r.error_bound),
            }
        }
        for c in &solution.clusters {
            let why = match c.reason {
                ClusterReason::DepthLimit => "depth limit",
                ClusterReason::DomainBoundary => "on the domain boundary",
                ClusterReason::Budget => "box or time budget",
                ClusterReason::Uncertain => "rounding (fast path)",
                ClusterReason::Singular => "a singular root (a group of undecided boxes)",
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
    let text = read(file)?;
    let kind = serde_json::from_str::<serde_json::Value>(&text)
        .ok()
        .and_then(|v| v.get("kind").and_then(|k| k.as_str()).map(String::from));
    if kind.as_deref() == Some(CURVE_CERTIFICATE_KIND) {
        return match verify_curve_certificate(&text)
            .map_err(|e| format!("{}: {e}", file.display()))?
        {
            Ok(c) => {
                println!("curve: valid: {c}");
                Ok(status(true))
            }
            Err(e) => {
                println!("curve: invalid: {e}");
                Ok(status(false))
            }
        };
    }
    let outcomes =
        verify_solution_certificate(&text).map_err(|e| format!("{}: {e}", file.display()))?;
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

fn exact_box(b: &[(geocert::num::Rational, geocert::num::Rational)]) -> Vec<[String; 2]> {
    b.iter()
        .map(|(lo, hi)| [rational_to_string(lo), rational_to_string(hi)])
        .collect()
}

fn cluster_json(c: &Cluster) -> serde_json::Value {
    serde_json::json!({
        "box": exact_box(&c.bounds),
        "reason": c.reason,
        "max_abs_f": c.max_abs_f,
    })
}

/// `solve --curves`: trace the solution curve.
fn curves(
    a: &Args,
    file: &std::path::Path,
    system: &PiecewiseSystem,
    time_limit: Option<std::time::Duration>,
) -> Result<ExitCode, String> {
    if !(a.resolution.is_finite() && a.resolution > 0.0) {
        return Err(format!(
            "--resolution must be a positive number, got {}",
            a.resolution
        ));
    }
    let depth = a
        .max_depth
        .unwrap_or(CurveOptions::default().limits.max_depth);
    let opts = CurveOptions::new()
        .with_path(a.path)
        .with_resolution(a.resolution)
        .with_extreme_axis(a.extreme_axis)
        .with_tolerance(if a.tol > 0.0 { a.tol.max(1e-15) } else { 1e-12 })
        .with_limits(
            Limits::new()
                .with_max_depth(depth)
                .with_max_boxes(a.max_boxes)
                .with_time_limit(time_limit),
        );
    let clock = std::time::Instant::now();
    let c = trace_piecewise(system, &opts).map_err(|e| format!("{}: {e}", file.display()))?;
    let seconds = clock.elapsed().as_secs_f64();
    if let Some(path) = &a.cert {
        let cert = match system.polynomial() {
            Some(p) => curve_certificate(p, &c),
            None => piecewise_curve_certificate(system, &c),
        };
        write(path, pretty(&cert)?)?;
    }
    let end_json = |e: &CurveEnd| match *e {
        CurveEnd::Face { point, axis, upper } => serde_json::json!({
            "point": point, "face": [axis, if upper { "upper" } else { "lower" }],
        }),
        CurveEnd::Cluster {
            point,
            cluster,
            group,
        } => serde_json::json!({
            "point": point, "cluster": cluster, "cluster_group": group,
        }),
    };
    if a.json {
        let v = serde_json::json!({
            "curves": c.components.iter().map(|k| serde_json::json!({
                "polyline": k.points.iter().map(|&p| &c.points[p].root.approx).collect::<Vec<_>>(),
                "points": k.points,
                "closed": k.closed,
                "ends": k.ends.iter().map(end_json).collect::<Vec<_>>(),
                "hausdorff_bound": k.hausdorff_bound,
                "vertex_error": k.points.iter().map(|&p| c.points[p].root.error_bound).fold(0.0, f64::max),
            })).collect::<Vec<_>>(),
            "extremes": c.extremes.iter().map(|e| serde_json::json!({
                "box": exact_box(&e.root.bounds),
                "approx": e.root.approx,
                "error_bound": e.root.error_bound,
                "component": e.component,
            })).collect::<Vec<_>>(),
            "extreme_clusters": c.extreme_clusters.iter().map(cluster_json).collect::<Vec<_>>(),
            "clusters": c.clusters.iter().map(cluster_json).collect::<Vec<_>>(),
            "cluster_groups": c.cluster_groups,
            "points": c.points.len(),
            "arcs": c.arcs.len(),
            "boxes_visited": c.boxes_visited,
            "cross_sections": c.cross_sections,
            "seconds": seconds,
            "path": c.path.name(),
        });
        println!("{v}");
    } else {
        println!(
            "{} components ({} closed), {} arcs through {} certified points, {} clusters in {} \
             groups, {} boxes and {} cross-sections in {seconds:.4} s ({} path)",
            c.components.len(),
            c.components.iter().filter(|k| k.closed).count(),
            c.arcs.len(),
            c.points.len(),
            c.clusters.len(),
            c.cluster_groups.len(),
            c.boxes_visited,
            c.cross_sections,
            c.path
        );
        for (i, k) in c.components.iter().enumerate() {
            let ends: Vec<String> = k
                .ends
                .iter()
                .map(|e| match *e {
                    CurveEnd::Face { axis, upper, .. } => {
                        format!("face x{axis} = {}", if upper { "b" } else { "a" })
                    }
                    CurveEnd::Cluster { group, .. } => format!("cluster group {group}"),
                })
                .collect();
            println!(
                "  component {i}: {} vertices, {}, within {:.1e} of the curve",
                k.points.len(),
                if k.closed {
                    "closed loop".to_string()
                } else {
                    format!("from {}", ends.join(" to "))
                },
                k.hausdorff_bound
            );
        }
        for e in &c.extremes {
            println!(
                "  extreme {:?} ± {:.1e} on component {}",
                e.root.approx,
                e.root.error_bound,
                e.component.map_or("?".into(), |k| k.to_string())
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}
