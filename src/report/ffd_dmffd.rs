//! The shape of the FFD paper's Fig. 6: injective DMFFD on domes of 145, 545 and 2113
//! vertices under drags of types 1S…2L, timed, and every step re-checked by the N&S test.
//!
//! The dome (octahedral, squashed to 0.6 of its radius) sits in the middle of a tricubic
//! uniform B-spline lattice of 4×4×4 cells (domain `[0,4]³`, `X ≡ U`). Type 1 pushes the apex
//! straight down through the base (overextension); type 2 drags two opposite points of the
//! rim region sideways in opposite directions (a twist). S, M, L scale the constraint vectors by
//! ½, 1 and 1½, as in the paper.

use crate::ffd::deform::deform_points_fast;
use crate::ffd::manipulation::{
    injective_drag, solve_exact, Constraint, DragOptions, DragStep, DragTest,
};
use crate::ffd::{check_injectivity, Basis, CheckOptions, InjectivityVerdict, Lattice};
use crate::mesh::shapes::squashed_hemisphere;
use crate::num::{rational_from_f64, rational_to_f64};
use std::time::Instant;

/// One cell of the table.
#[derive(Clone, Debug)]
pub struct DmffdRow {
    pub vertices: usize,
    /// `1S` … `2L`.
    pub kind: String,
    /// Median wall time of drag (f64 solve, certified f64 conic test) plus mesh deformation.
    pub seconds: f64,
    /// Certified steps and the deepest split of the f64 run.
    pub steps: usize,
    pub depth: u32,
    /// How many of those steps the filtered N&S test proves injective (all, or a bug).
    pub steps_verified: usize,
    /// Every mesh vertex stayed inside the domain through every step.
    pub mesh_deformed: bool,
    /// Largest distance between a constraint's composed image and its target (f64 run).
    pub max_constraint_error: f64,
}

/// Per drag type (mesh independent): the exact run and the one-step (conventional) DMFFD.
#[derive(Clone, Debug)]
pub struct DmffdDrag {
    pub kind: String,
    /// Exact rationals, exact conic test: seconds, steps; the composition meets every
    /// constraint exactly (checked).
    pub exact_seconds: f64,
    pub exact_steps: usize,
    pub exact_meets_constraints: bool,
    /// Steps with the N&S test as the certifier instead of the conic test (exact path).
    pub ns_steps: usize,
    /// The N&S verdict on conventional one-step DMFFD of the same constraints.
    pub one_step: String,
}

/// The table: rows per mesh and type, and per-type exact figures.
#[derive(Clone, Debug)]
pub struct DmffdTable {
    pub rows: Vec<DmffdRow>,
    pub drags: Vec<DmffdDrag>,
    pub runs: usize,
}

const KINDS: [(&str, u8, f64); 6] = [
    ("1S", 1, 0.5),
    ("1M", 1, 1.0),
    ("1L", 1, 1.5),
    ("2S", 2, 0.5),
    ("2M", 2, 1.0),
    ("2L", 2, 1.5),
];
const SQUASH: f64 = 0.6;
const BASE: [f64; 3] = [2.0, 2.0, 1.6];

fn point(p: [f64; 3]) -> [crate::num::Rational; 3] {
    p.map(|x| rational_from_f64(x, "constraint").expect("finite"))
}

/// The constraints of drag `ty` scaled by `scale`, in the lattice's parameter space.
pub fn constraints(ty: u8, scale: f64) -> Vec<Constraint> {
    let on_dome = |x: f64, y: f64| {
        let z = SQUASH * (1.0 - x * x - y * y).max(0.0).sqrt();
        [BASE[0] + x, BASE[1] + y, BASE[2] + z]
    };
    let c = |at: [f64; 3], d: [f64; 3]| Constraint {
        point: point(at),
        delta: point(d.map(|x| x * scale)),
    };
    match ty {
        1 => vec![c(on_dome(0.0, 0.0), [0.0, 0.0, -1.2])],
        _ => vec![
            c(on_dome(0.75, 0.0), [0.0, 1.0, 0.0]),
            c(on_dome(-0.75, 0.0), [0.0, -1.0, 0.0]),
        ],
    }
}

fn shape() -> Lattice {
    Lattice::identity(Basis::Bspline, [4, 4, 4], [4, 4, 4]).expect("valid shape")
}

fn composed_error(steps: &[DragStep], cs: &[Constraint]) -> f64 {
    let lattices: Vec<Lattice> = steps.iter().map(|s| s.lattice.clone()).collect();
    let mut pts: Vec<[f64; 3]> = cs
        .iter()
        .map(|c| c.point.clone().map(|x| rational_to_f64(&x)))
        .collect();
    if deform_points_fast(&lattices, None, &mut pts).is_err() {
        return f64::INFINITY;
    }
    cs.iter()
        .zip(&pts)
        .map(|(c, p)| {
            (0..3)
                .map(|a| (p[a] - rational_to_f64(&(&c.point[a] + &c.delta[a]))).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .fold(0.0, f64::max)
}

/// Runs the table: `runs` timed repetitions per cell (median reported).
pub fn fig6_table(runs: usize) -> DmffdTable {
    let shape = shape();
    let fast = DragOptions {
        test: DragTest::Conic,
        path: crate::Path::Fast,
        ..Default::default()
    };
    let mut rows = Vec::new();
    for n in [8u32, 16, 32] {
        let dome = squashed_hemisphere(n, SQUASH);
        let placed: Vec<[f64; 3]> = dome
            .vertices
            .iter()
            .map(|v| [0, 1, 2].map(|a| v[a] + BASE[a]))
            .collect();
        for (kind, ty, scale) in KINDS {
            let cs = constraints(ty, scale);
            let mut times = Vec::with_capacity(runs);
            let mut last = None;
            for _ in 0..runs.max(1) {
                let t = Instant::now();
                let steps = injective_drag(&shape, &cs, fast);
                let mut pts = placed.clone();
                let deformed = match &steps {
                    Ok(s) => {
                        let ls: Vec<Lattice> = s.iter().map(|x| x.lattice.clone()).collect();
                        deform_points_fast(&ls, None, &mut pts).is_ok()
                    }
                    Err(_) => false,
                };
                times.push(t.elapsed().as_secs_f64());
                last = Some((steps, deformed));
            }
            times.sort_by(f64::total_cmp);
            let (steps, mesh_deformed) = last.expect("at least one run");
            let steps = steps.unwrap_or_default();
            let verified = steps
                .iter()
                .filter(|s| {
                    check_injectivity(&s.lattice, CheckOptions::default())
                        .is_ok_and(|r| matches!(r.verdict, InjectivityVerdict::Injective { .. }))
                })
                .count();
            rows.push(DmffdRow {
                vertices: dome.vertices.len(),
                kind: kind.to_string(),
                seconds: times[times.len() / 2],
                steps: steps.len(),
                depth: steps.iter().map(|s| s.depth).max().unwrap_or(0),
                steps_verified: verified,
                mesh_deformed,
                max_constraint_error: composed_error(&steps, &cs),
            });
        }
    }
    let drags = KINDS
        .iter()
        .map(|&(kind, ty, scale)| {
            let cs = constraints(ty, scale);
            let exact = DragOptions {
                test: DragTest::Conic,
                ..Default::default()
            };
            let t = Instant::now();
            let steps = injective_drag(&shape, &cs, exact).unwrap_or_default();
            let exact_seconds = t.elapsed().as_secs_f64();
            let meets = !steps.is_empty()
                && cs.iter().all(|c| {
                    crate::ffd::manipulation::compose(&steps, &c.point)
                        .is_ok_and(|x| (0..3).all(|a| x[a] == &c.point[a] + &c.delta[a]))
                });
            let ns = DragOptions {
                test: DragTest::Exact,
                ..Default::default()
            };
            let ns_steps = injective_drag(&shape, &cs, ns).map_or(0, |s| s.len());
            let one_step = solve_exact(&shape, &cs)
                .and_then(|d| shape.displaced(&d))
                .and_then(|l| check_injectivity(&l, CheckOptions::default()))
                .map_or_else(|e| format!("error: {e}"), |r| r.verdict.name().to_string());
            DmffdDrag {
                kind: kind.to_string(),
                exact_seconds,
                exact_steps: steps.len(),
                exact_meets_constraints: meets,
                ns_steps,
                one_step,
            }
        })
        .collect();
    DmffdTable {
        rows,
        drags,
        runs: runs.max(1),
    }
}

/// Whether every step was verified and every exact composition met its constraints.
pub fn dmffd_ok(t: &DmffdTable) -> bool {
    t.rows.iter().all(|r| {
        r.steps > 0
            && r.mesh_deformed
            && r.steps_verified == r.steps
            && r.max_constraint_error < 1e-9
    }) && t.drags.iter().all(|d| d.exact_meets_constraints)
}
