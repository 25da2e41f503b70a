//! The FFD injectivity campaign behind `reports/ffd.md`: exact-vs-fast agreement, false
//! rejection rates of the sufficient tests, per-cell timings, and Gmsh's `minDetJac` on the
//! same cells in the same run.

use super::campaign::median;
use crate::bernstein::Limits;
use crate::ffd::jacobian::jacobian_cell_scaled;
use crate::ffd::sufficient::{
    bezier_coefficient_test_exact, bezier_coefficient_test_fast, conic_test_exact, conic_test_fast,
    phi_test_exact, phi_test_fast, ConicOptions, Scope, SufficientVerdict,
};
use crate::ffd::{
    check_injectivity, verify_injectivity_certificate, Basis, CheckOptions, InjectivityCertificate,
    InjectivityVerdict, Lattice,
};
use crate::num::{rational_from_f64, Rational, Sign};
use std::path::Path;
use std::time::Instant;

/// Deterministic generator (same constants as the proofs').
struct Rng(u64);
impl Rng {
    fn unit(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64) / ((1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// Amplitudes of the perturbation mix (fractions of the cell size).
pub const AMPLITUDES: [f64; 6] = [0.05, 0.1, 0.15, 0.2, 0.25, 0.3];

/// `n` lattices of the given shape perturbed from the identity by uniform noise in
/// `[−a, a]` per coordinate, `a` cycling through [`AMPLITUDES`]; points are `f64`.
pub fn perturbed_lattices(
    seed: u64,
    n: usize,
    basis: Basis,
    order: [usize; 3],
    cells: [usize; 3],
) -> Vec<Lattice> {
    let id = Lattice::identity(basis, order, cells).expect("valid shape");
    let mut rng = Rng(seed);
    (0..n)
        .map(|k| {
            let a = AMPLITUDES[k % AMPLITUDES.len()];
            let pts = id
                .points()
                .iter()
                .map(|p| {
                    [0, 1, 2].map(|c| {
                        let x = crate::num::rational_to_f64(&p[c]) + a * rng.unit();
                        rational_from_f64(x, "x").expect("finite")
                    })
                })
                .collect();
            Lattice::new(basis, order, cells, pts).expect("same shape")
        })
        .collect()
}

/// Verdict counts of one path.
#[derive(Clone, Debug, Default)]
pub struct PathCounts {
    pub injective: usize,
    pub not_injective: usize,
    pub undecided: usize,
    pub uncertain: usize,
}

impl PathCounts {
    fn add(&mut self, v: &InjectivityVerdict) {
        match v {
            InjectivityVerdict::Injective { .. } => self.injective += 1,
            InjectivityVerdict::NotInjective { .. } => self.not_injective += 1,
            InjectivityVerdict::Undecided { .. } => self.undecided += 1,
            InjectivityVerdict::Uncertain { .. } => self.uncertain += 1,
        }
    }
}

/// A sufficient test's record against the N&S verdict.
#[derive(Clone, Debug, Default)]
pub struct Rejections {
    pub test: String,
    /// Lattices the N&S test proved injective.
    pub injective: usize,
    /// Of those, how many the test failed to prove (false rejections).
    pub rejected: usize,
    /// Fast-path verdicts that were uncertain.
    pub uncertain: usize,
    /// Times the test claimed injective where N&S did not (must be 0).
    pub unsound: usize,
}

/// One family's results.
#[derive(Clone, Debug, Default)]
pub struct Family {
    pub name: String,
    pub lattices: usize,
    pub exact: PathCounts,
    pub fast: PathCounts,
    pub filtered: PathCounts,
    pub filtered_agrees: usize,
    pub contradictions: usize,
    pub certificates_checked: usize,
    pub certificates_refused: usize,
    pub rejections: Vec<Rejections>,
    /// Median milliseconds per lattice: exact, fast, filtered.
    pub ms: [f64; 3],
}

/// Gmsh's numbers on the benchmark cells.
#[derive(Clone, Debug)]
pub struct GmshRun {
    pub version: String,
    pub cells: usize,
    /// Median seconds for the whole batch.
    pub batch_seconds: f64,
    /// Cells where Gmsh's `minDetJac > 0` disagrees with geocert's exact verdict.
    pub sign_disagreements: usize,
    /// Where Gmsh's value falls against geocert's certified bracket `[lower, upper]` of the
    /// true minimum (`lower` from the leaves, `upper` the smallest exact corner value):
    /// below (a looser lower bound), inside, above (overestimating the minimum).
    pub below: usize,
    pub inside: usize,
    pub above: usize,
}

/// The whole campaign.
#[derive(Clone, Debug)]
pub struct FfdCampaign {
    pub seed: u64,
    pub limits: Limits,
    pub families: Vec<Family>,
    /// Batch timings over the tricubic benchmark cells (median seconds of 3 runs).
    pub bench_cells: usize,
    pub batch_seconds: Vec<(String, f64)>,
    pub gmsh: Result<GmshRun, String>,
    /// Worked example: the lattice JSON, the `--json` line, the certificate, the check.
    pub example: [String; 4],
    /// The Fig. 6-shaped injective DMFFD table.
    pub dmffd: super::ffd_dmffd::DmffdTable,
}

fn sufficient_row(
    test: &str,
    results: &[(Sign, Sign)], // (N&S exact, test)
) -> Rejections {
    let mut r = Rejections {
        test: test.into(),
        ..Default::default()
    };
    for &(ns, t) in results {
        if t == Sign::Uncertain {
            r.uncertain += 1;
        }
        if ns == Sign::Positive {
            r.injective += 1;
            if t != Sign::Positive {
                r.rejected += 1;
            }
        } else if t == Sign::Positive && ns == Sign::Negative {
            r.unsound += 1;
        }
    }
    r
}

fn run_family(name: &str, lattices: &[Lattice], limits: Limits, certify: usize) -> Family {
    let mut f = Family {
        name: name.into(),
        lattices: lattices.len(),
        ..Default::default()
    };
    let mut times: [Vec<f64>; 3] = Default::default();
    let mut tests: Vec<(String, Vec<(Sign, Sign)>)> = [
        "conic (per cell), exact",
        "conic (per cell), f64",
        "conic (whole lattice), exact",
        "conic (per cell, subdivided once), exact",
        "phi (per cell), exact",
        "phi (per cell), f64",
        "Bézier coefficients, exact",
        "Bézier coefficients, f64",
    ]
    .iter()
    .map(|s| (s.to_string(), Vec::new()))
    .collect();
    for (i, l) in lattices.iter().enumerate() {
        let run = |path| {
            let t = Instant::now();
            let r = check_injectivity(l, CheckOptions { path, limits }).expect("valid lattice");
            (r, t.elapsed().as_secs_f64() * 1e3)
        };
        let (exact, te) = run(crate::Path::Exact);
        let (fast, tf) = run(crate::Path::Fast);
        let (filtered, tl) = run(crate::Path::Filtered);
        for (k, t) in [te, tf, tl].into_iter().enumerate() {
            times[k].push(t);
        }
        f.exact.add(&exact.verdict);
        f.fast.add(&fast.verdict);
        f.filtered.add(&filtered.verdict);
        let es = exact.verdict.sign();
        if filtered.verdict.name() == exact.verdict.name() {
            f.filtered_agrees += 1;
        }
        if fast.verdict.sign().contradicts(es) || filtered.verdict.sign().contradicts(es) {
            f.contradictions += 1;
        }
        if i < certify {
            for r in [&exact, &filtered] {
                if let Some(c) = InjectivityCertificate::from_report(l, r) {
                    f.certificates_checked += 1;
                    if verify_injectivity_certificate(&c).is_err() {
                        f.certificates_refused += 1;
                    }
                }
            }
        }
        let conic = |scope, depth| ConicOptions {
            scope,
            subdivision_depth: depth,
        };
        let sv: [SufficientVerdict; 8] = [
            conic_test_exact(l, conic(Scope::PerCell, 0)),
            conic_test_fast(l, conic(Scope::PerCell, 0)),
            conic_test_exact(l, conic(Scope::Lattice, 0)),
            conic_test_exact(l, conic(Scope::PerCell, 1)),
            phi_test_exact(l, Scope::PerCell),
            phi_test_fast(l, Scope::PerCell),
            bezier_coefficient_test_exact(l).expect("valid lattice"),
            bezier_coefficient_test_fast(l),
        ];
        for ((_, rows), v) in tests.iter_mut().zip(sv) {
            rows.push((es, v.sign()));
        }
    }
    f.rejections = tests
        .iter()
        .map(|(name, rows)| sufficient_row(name, rows))
        .collect();
    f.ms = [0, 1, 2].map(|k| median(times[k].clone()));
    f
}

/// Batch seconds (median of 3 runs) of `f` over all lattices.
fn batch(lattices: &[Lattice], f: impl Fn(&Lattice)) -> f64 {
    let runs: Vec<f64> = (0..3)
        .map(|_| {
            let t = Instant::now();
            for l in lattices {
                f(l);
            }
            t.elapsed().as_secs_f64()
        })
        .collect();
    median(runs)
}

/// geocert's exact knowledge of a cell's minimum of `det J`.
struct ExactMin {
    sign: Sign,
    /// Certified lower bound.
    lower: Option<Rational>,
    /// An exact value of `det J` somewhere in the cell (so an upper bound of the minimum).
    upper: Rational,
}

/// Runs Gmsh on the cells through `benches/peers/gmsh_mindetjac.py`, with the interpreter in
/// `.venv-peers/` if `benches/peers/setup.sh` made one, else `python3`.
fn gmsh_run(root: &Path, cells: &[Lattice], exact: &[ExactMin]) -> Result<GmshRun, String> {
    let script = root.join("benches/peers/gmsh_mindetjac.py");
    if !script.exists() {
        return Err(
            "benches/peers/gmsh_mindetjac.py not found (run from the repository root)".into(),
        );
    }
    let venv = root.join(".venv-peers/bin/python");
    let python = if venv.exists() {
        venv
    } else {
        "python3".into()
    };
    let nets: Vec<Vec<[f64; 3]>> = cells
        .iter()
        .map(|l| l.points_f64().expect("f64 cells").to_vec())
        .collect();
    let input = std::env::temp_dir().join(format!("geocert-gmsh-{}.json", std::process::id()));
    std::fs::write(&input, serde_json::json!({ "cells": nets }).to_string())
        .map_err(|e| e.to_string())?;
    let out = std::process::Command::new(&python)
        .arg(&script)
        .arg(&input)
        .arg("5")
        .output()
        .map_err(|e| format!("could not run {}: {e}", python.display()));
    let _ = std::fs::remove_file(&input);
    let out = out?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        return Err(format!(
            "Gmsh not available ({}); run benches/peers/setup.sh",
            err.lines().last().unwrap_or("no output")
        ));
    }
    let v: serde_json::Value =
        serde_json::from_slice(&out.stdout).map_err(|e| format!("Gmsh output: {e}"))?;
    let secs: Vec<f64> = v["seconds"]
        .as_array()
        .ok_or("Gmsh output without seconds")?
        .iter()
        .filter_map(|x| x.as_f64())
        .collect();
    let mins: Vec<f64> = v["min_det"]
        .as_array()
        .ok_or("Gmsh output without min_det")?
        .iter()
        .filter_map(|x| x.as_f64())
        .collect();
    if mins.len() != cells.len() {
        return Err("Gmsh returned a different number of cells".into());
    }
    let (mut sign_disagreements, mut below, mut inside, mut above) = (0, 0, 0, 0);
    for (g, e) in mins.iter().zip(exact) {
        let gs = if *g > 0.0 {
            Sign::Positive
        } else {
            Sign::Negative
        };
        if e.sign != Sign::Uncertain && gs != e.sign {
            sign_disagreements += 1;
        }
        let Ok(g) = rational_from_f64(*g, "g") else {
            continue;
        };
        match &e.lower {
            Some(lo) if &g < lo => below += 1,
            _ if g > e.upper => above += 1,
            Some(_) => inside += 1,
            None => {}
        }
    }
    Ok(GmshRun {
        version: v["gmsh"].as_str().unwrap_or("?").to_string(),
        cells: cells.len(),
        batch_seconds: median(secs),
        sign_disagreements,
        below,
        inside,
        above,
    })
}

/// The worked example: an order-3 Bézier cell with exact rational points, twisted about the
/// `w` axis.
fn worked_example(limits: Limits) -> [String; 4] {
    let id = Lattice::identity(Basis::Bezier, [3, 3, 3], [1, 1, 1]).expect("valid");
    let fifth = Rational::new(1.into(), 5.into());
    let pts: Vec<[Rational; 3]> = id
        .points()
        .iter()
        .map(|p| {
            let s = &fifth * &p[2];
            // x ← x − s·(y − ½), y ← y + s·(x − ½): a shear-like twist growing with w.
            let half = Rational::new(1.into(), 2.into());
            [
                &p[0] - &s * (&p[1] - &half),
                &p[1] + &s * (&p[0] - &half),
                p[2].clone(),
            ]
        })
        .collect();
    let l = Lattice::new(Basis::Bezier, [3, 3, 3], [1, 1, 1], pts).expect("valid");
    let r = check_injectivity(
        &l,
        CheckOptions {
            path: crate::Path::Filtered,
            limits,
        },
    )
    .expect("valid");
    let cert = InjectivityCertificate::from_report(&l, &r)
        .map(|c| serde_json::to_string_pretty(&c).unwrap_or_default())
        .unwrap_or_default();
    let line = serde_json::to_string(&r.to_json()).unwrap_or_default();
    let check = InjectivityCertificate::from_report(&l, &r)
        .map(|c| match verify_injectivity_certificate(&c) {
            Ok(m) => format!("valid: {m}"),
            Err(e) => format!("invalid: {e}"),
        })
        .unwrap_or_default();
    [
        serde_json::to_string(&l.to_json()).unwrap_or_default(),
        line,
        cert,
        check,
    ]
}

/// Runs the campaign: `n_cells` tricubic Bézier cells and `n_bspline` order-4 2×2×2 B-spline
/// lattices (and as many order-3 ones).
pub fn ffd_campaign(root: &Path, seed: u64, n_cells: usize, n_bspline: usize) -> FfdCampaign {
    let limits = Limits {
        max_depth: 10,
        max_boxes: 20_000,
        time_limit: Some(std::time::Duration::from_secs(5)),
    };
    let cells = perturbed_lattices(seed, n_cells, Basis::Bezier, [4, 4, 4], [1, 1, 1]);
    let b4 = perturbed_lattices(seed + 1, n_bspline, Basis::Bspline, [4, 4, 4], [2, 2, 2]);
    let b3 = perturbed_lattices(seed + 2, n_bspline, Basis::Bspline, [3, 3, 3], [2, 2, 2]);
    let families = vec![
        run_family("tricubic Bézier cells (order 4)", &cells, limits, 20),
        run_family("B-spline order 4, 2×2×2 cells", &b4, limits, 2),
        run_family("B-spline order 3, 2×2×2 cells", &b3, limits, 3),
    ];
    let opts = |path| CheckOptions { path, limits };
    let batch_seconds = vec![
        (
            "N&S filtered".to_string(),
            batch(&cells, |l| {
                let _ = check_injectivity(l, opts(crate::Path::Filtered));
            }),
        ),
        (
            "N&S fast".to_string(),
            batch(&cells, |l| {
                let _ = check_injectivity(l, opts(crate::Path::Fast));
            }),
        ),
        (
            "N&S exact".to_string(),
            batch(&cells, |l| {
                let _ = check_injectivity(l, opts(crate::Path::Exact));
            }),
        ),
        (
            "conic hull (per cell), f64".to_string(),
            batch(&cells, |l| {
                let _ = conic_test_fast(l, ConicOptions::default());
            }),
        ),
        (
            "phi (per cell), f64".to_string(),
            batch(&cells, |l| {
                let _ = phi_test_fast(l, Scope::PerCell);
            }),
        ),
    ];
    let exact: Vec<ExactMin> = cells
        .iter()
        .map(|l| {
            let r = check_injectivity(l, opts(crate::Path::Exact)).expect("valid");
            // det J at the 8 corners, exactly: the corner Bézier coefficients.
            let j = jacobian_cell_scaled(&l.bezier_nets()[0]).expect("valid");
            let mut upper = (0..8)
                .map(|c| j.coeff_value(j.vertex_index(c)))
                .min()
                .expect("8 corners");
            if let InjectivityVerdict::NotInjective { det, .. } = &r.verdict {
                upper = upper.min(det.clone());
            }
            ExactMin {
                sign: r.verdict.sign(),
                lower: r.min_det_lower_bound,
                upper,
            }
        })
        .collect();
    let gmsh = gmsh_run(root, &cells, &exact);
    FfdCampaign {
        seed,
        limits,
        families,
        bench_cells: cells.len(),
        batch_seconds,
        gmsh,
        example: worked_example(limits),
        dmffd: super::ffd_dmffd::fig6_table(7),
    }
}

/// Whether the campaign found nothing wrong.
pub fn campaign_ok(c: &FfdCampaign) -> bool {
    super::ffd_dmffd::dmffd_ok(&c.dmffd)
        && c.families.iter().all(|f| {
            f.contradictions == 0
                && f.certificates_refused == 0
                && f.rejections.iter().all(|r| r.unsound == 0)
        })
}
