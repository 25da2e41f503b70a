//! The silhouette systems for `reports/solve.md`: eq. 3's `Z₀ = {F̃ = G̃ = H = 0}` of every
//! patch of the built-in sweeps ([`crate::sweep::t_extreme_systems`]), solved on their box
//! (`u`, `v` and `t` rescaled to `[0, 1]`) beside msolve and PHCpack in the same run.

use super::solve::{
    find_msolve, median, meets, run_msolve, run_phc_within, timed, Case, Poly, EXACT_SYSTEMS,
    POSITIVE_DIMENSIONAL,
};
use crate::bernstein::Bernstein;
use crate::num::Rational;
use crate::solve::System;
use crate::Path as Arith;
use num_traits::{One, Zero};
use std::fmt::Write as _;
use std::path::Path;
use std::time::Duration;

/// The scenes whose systems are solved.
const SCENES: [&str; 5] = [
    "sphere-line",
    "sphere-cone",
    "ellipsoid-line",
    "ellipsoid-turn",
    "tuba",
];

/// PHCpack's budget per system (it runs on each scene's first patch only: its homotopy
/// follows as many paths as the systems' mixed volume, thousands here).
const PHC_TIMEOUT: Duration = Duration::from_secs(30);

/// One scene's systems.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SilhouetteRow {
    /// The built-in scene.
    pub scene: String,
    /// Systems (patches).
    pub systems: usize,
    /// The largest degree per variable `(u, v, t)` over the systems' equations.
    pub degrees: [usize; 3],
    /// Certified roots (the `t`-extreme points) and clusters on the filtered path.
    pub roots: usize,
    /// Clusters on the filtered path.
    pub clusters: usize,
    /// Median and largest filtered time per system, ms.
    pub filtered_ms: (f64, f64),
    /// The exact path on the first few systems (`EXACT_SYSTEMS`): median ms, and whether its
    /// roots and clusters matched the filtered path's (same count, boxes meeting).
    pub exact: (f64, bool),
    /// msolve per system: how many it answered as positive-dimensional, how many it isolated
    /// with exactly our roots in the box, and its median ms; or why it did not run.
    pub msolve: Result<(usize, usize, f64), String>,
    /// PHCpack on the first system: its real solutions in the box, whether they match our
    /// roots (within 1e-6), and its time; or why not.
    pub phc: Result<(usize, bool, f64), String>,
}

/// `p` in the power basis of its unit variables.
fn power_form(p: &Bernstein<Rational>) -> Poly {
    let d = p.degrees().to_vec();
    let mut out = Poly::new();
    for (flat, c) in p.to_power().into_iter().enumerate() {
        if c.is_zero() {
            continue;
        }
        let mut rest = flat;
        let e: Vec<usize> = d
            .iter()
            .map(|&dk| {
                let x = rest % (dk + 1);
                rest /= dk + 1;
                x
            })
            .collect();
        out.insert(e, c);
    }
    out
}

/// Solves every built-in scene's silhouette systems on every available solver.
pub fn silhouette_campaign(root: &Path) -> Vec<SilhouetteRow> {
    let msolve = find_msolve(root);
    let unit = vec![(Rational::zero(), Rational::one()); 3];
    let mut rows = Vec::new();
    for name in SCENES {
        let systems = match crate::sweep::builtin_scene(name)
            .and_then(|s| crate::sweep::t_extreme_systems(&s))
        {
            Ok(s) => s,
            Err(_) => continue,
        };
        let unit_systems: Vec<System> = systems
            .iter()
            .filter_map(|s| System::new(unit.clone(), s.equations.clone()).ok())
            .collect();
        let mut degrees = [0; 3];
        for s in &unit_systems {
            for e in &s.equations {
                for (k, d) in e.degrees().iter().enumerate() {
                    degrees[k] = degrees[k].max(*d);
                }
            }
        }
        let cases: Vec<Case> = unit_systems
            .iter()
            .map(|s| Case {
                polys: s.equations.iter().map(power_form).collect(),
                domain: unit.clone(),
                roots: None,
            })
            .collect();
        let (mut roots, mut clusters, mut times) = (0, 0, Vec::new());
        let mut filtered = Vec::new();
        for s in &unit_systems {
            let (sol, secs) = timed(s, Arith::Filtered);
            roots += sol.roots.len();
            clusters += sol.clusters.len();
            times.push(1e3 * secs);
            filtered.push(sol);
        }
        let (mut exact_times, mut same) = (Vec::new(), true);
        for (s, f) in unit_systems.iter().zip(&filtered).take(EXACT_SYSTEMS) {
            let (sol, secs) = timed(s, Arith::Exact);
            exact_times.push(1e3 * secs);
            same &= sol.roots.len() == f.roots.len()
                && sol.clusters.len() == f.clusters.len()
                && sol
                    .roots
                    .iter()
                    .all(|r| f.roots.iter().any(|g| meets(&r.bounds, &g.bounds)));
        }
        let msolve_row = msolve.as_ref().map_err(Clone::clone).and_then(|bin| {
            let (mut positive, mut agree, mut t) = (0, 0, Vec::new());
            for (k, (case, sol)) in cases.iter().zip(&filtered).enumerate() {
                let started = std::time::Instant::now();
                match run_msolve(bin, case, &format!("sil-{name}-{k}")) {
                    Ok((boxes, secs)) => {
                        t.push(1e3 * secs);
                        let inside: Vec<_> = boxes
                            .iter()
                            .filter(|b| {
                                b.iter()
                                    .all(|(lo, hi)| lo > &Rational::zero() && hi < &Rational::one())
                            })
                            .collect();
                        if inside.len() == sol.roots.len()
                            && inside
                                .iter()
                                .all(|b| sol.roots.iter().any(|r| meets(&r.bounds, b)))
                        {
                            agree += 1;
                        }
                    }
                    Err(e) if e == POSITIVE_DIMENSIONAL => {
                        t.push(1e3 * started.elapsed().as_secs_f64());
                        positive += 1;
                    }
                    Err(e) => return Err(e),
                }
            }
            Ok((positive, agree, median(t)))
        });
        let phc =
            run_phc_within(root, &cases[..1.min(cases.len())], Some(PHC_TIMEOUT)).map(|results| {
                let (real, secs) = results.into_iter().next().unwrap_or_default();
                let inside: Vec<Vec<f64>> = real
                    .into_iter()
                    .filter(|p| p.iter().all(|&x| 0.0 < x && x < 1.0))
                    .collect();
                let ours = filtered.first().map_or(&[][..], |s| s.roots.as_slice());
                let matches = inside.len() == ours.len()
                    && ours.iter().all(|r| {
                        inside
                            .iter()
                            .any(|p| p.iter().zip(&r.approx).all(|(x, y)| (x - y).abs() <= 1e-6))
                    });
                (inside.len(), matches, 1e3 * secs)
            });
        rows.push(SilhouetteRow {
            scene: name.into(),
            systems: unit_systems.len(),
            degrees,
            roots,
            clusters,
            filtered_ms: (
                median(times.clone()),
                times.iter().copied().fold(0.0, f64::max),
            ),
            exact: (median(exact_times), same),
            msolve: msolve_row,
            phc,
        });
    }
    rows
}

/// The report's section.
pub fn silhouette_markdown(rows: &[SilhouetteRow]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "\n## Silhouette systems\n\nThe square systems of the swept-volume family: per patch \
         of each built-in scene, `Z₀ = {{F̃ = G̃ = H = 0}}` of the silhouette paper's eq. 3 \
         (`H = F_u G_v − F_v G_u`), whose roots are the silhouette's `t`-extreme points, on \
         `[0,1]² × [a, b]` with `t` rescaled to `[0, 1]` (`sweep::t_extreme_systems`). The \
         same polynomials, in the power basis of the unit variables, go to msolve and \
         PHCpack. Our times are per system on one thread; the exact path runs on the first \
         {EXACT_SYSTEMS} systems of each scene and must match the filtered path (same roots \
         and clusters). PHCpack runs on each scene's first system only, stopped after {} s.\n",
        PHC_TIMEOUT.as_secs()
    );
    let _ = writeln!(
        s,
        "| scene | systems | degrees (u, v, t) | roots | clusters | ours ms median (max), filtered | ours ms, exact | exact = filtered | msolve | msolve ms | PHCpack (first system) |\n|---|---:|---|---:|---:|---|---:|---|---|---:|---|"
    );
    for r in rows {
        let (ms_text, ms_time) = match &r.msolve {
            Ok((positive, agree, t)) => (
                if *positive == r.systems {
                    format!("positive-dimensional over ℂ³ on all {positive}: no point isolated")
                } else {
                    format!(
                        "positive-dimensional over ℂ³ on {positive}/{}; the others' roots in the \
                         box equal to ours on {agree}/{}",
                        r.systems,
                        r.systems - positive
                    )
                },
                format!("{t:.1}"),
            ),
            Err(e) => (format!("not run: {e}"), "—".into()),
        };
        let phc = match &r.phc {
            Ok((n, matches, t)) => format!(
                "{n} real solutions in the box, {} ours, {t:.0} ms",
                if *matches { "equal to" } else { "unlike" }
            ),
            Err(e) => e.clone(),
        };
        let _ = writeln!(
            s,
            "| {} | {} | ({}, {}, {}) | {} | {} | {:.1} ({:.1}) | {:.1} | {} | {ms_text} | {ms_time} | {phc} |",
            r.scene,
            r.systems,
            r.degrees[0],
            r.degrees[1],
            r.degrees[2],
            r.roots,
            r.clusters,
            r.filtered_ms.0,
            r.filtered_ms.1,
            r.exact.0,
            if r.exact.1 { "yes" } else { "**no**" },
        );
    }
    if rows
        .iter()
        .any(|r| matches!(r.msolve, Ok((positive, _, _)) if positive > 0))
    {
        let _ = writeln!(
            s,
            "\nmsolve answers `[1, n, -1, []]` where the system's solution set over ℂ³ has \
             positive dimension; it then isolates no point at all, while on the box the \
             subdivision certifies every root and reports what it cannot certify."
        );
    }
    s
}
