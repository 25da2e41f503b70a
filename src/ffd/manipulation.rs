//! Direct manipulation (paper Section 4) and injective DMFFD by adaptive subdivision of the
//! drags (Section 8, Appendix `InjectSubdiv`).
//!
//! A constraint is a point `F` of the parameter domain (world space for an undeformed
//! lattice, `X ≡ U`) and its intended motion `ΔF`. The lattice change solving `B ΔP = ΔF`
//! (eq. 3) with the least `‖ΔP‖` is `ΔP = Bᵀ (B Bᵀ)⁻¹ ΔF` (eq. 4), `B` the basis matrix of eq. 2
//! (row `i`: the tensor-product basis weights of the control points at constraint point `i`).
//!
//! Injective DMFFD replaces one drag by an ordered sequence of lattice changes, each an FFD of
//! the undeformed lattice plus `ΔP_k`, each certified injective by the chosen test; a drag that
//! fails is split into `(F, ½ΔF)` then `(F + ½ΔF, ½ΔF)`, up to a maximum depth.

use super::injectivity::{check_injectivity, CheckOptions, InjectivityVerdict};
use super::jacobian::basis_at;
use super::lattice::{Lattice, Point};
use super::sufficient::{
    conic_f64, conic_test_exact, conic_test_fast, phi_test_exact, phi_test_fast,
};
use super::sufficient::{ConicOptions, Scope, SufficientVerdict};
use super::FfdError;
use crate::bernstein::Limits;
use crate::num::{rational_to_f64, rational_to_string, Rational};
use crate::Path;
use num_traits::Zero;
use serde_json::{json, Value};

/// A direct-manipulation constraint: move parameter point `point` by `delta`.
#[derive(Clone, Debug, PartialEq)]
pub struct Constraint {
    /// The parameter point that is dragged.
    pub point: Point,
    /// Where its image moves: `F(point) += delta`.
    pub delta: Point,
}

/// The sparse basis matrix `B` of eq. 2.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct BasisMatrix {
    /// Lattice point index of each column, in order of first appearance.
    pub columns: Vec<usize>,
    /// Per row (constraint): `(column, weight)` for every influencing control point.
    pub rows: Vec<Vec<(usize, Rational)>>,
}

/// `B` for the given parameter points (eq. 2): weights `N_i(u) N_j(v) N_k(w)`.
pub(crate) fn basis_matrix(l: &Lattice, points: &[Point]) -> Result<BasisMatrix, FfdError> {
    let order = l.order();
    let mut columns: Vec<usize> = Vec::new();
    let mut column_of = std::collections::HashMap::new();
    let mut rows = Vec::with_capacity(points.len());
    for (r, u) in points.iter().enumerate() {
        l.check_inside(u).map_err(|e| FfdError::Input {
            lattice: 0,
            field: format!("constraints[{r}].point"),
            why: e.to_string(),
        })?;
        let per_axis: Vec<(usize, Vec<Rational>)> = (0..3)
            .map(|a| {
                let (first, vals, _) = basis_at(&l.knots(a), order[a] - 1, &u[a], None);
                (first, vals)
            })
            .collect();
        let mut row = Vec::new();
        for k in 0..order[2] {
            for j in 0..order[1] {
                for i in 0..order[0] {
                    let w = &per_axis[0].1[i] * &per_axis[1].1[j] * &per_axis[2].1[k];
                    if w.is_zero() {
                        continue;
                    }
                    let idx = l.index(per_axis[0].0 + i, per_axis[1].0 + j, per_axis[2].0 + k);
                    let col = *column_of.entry(idx).or_insert_with(|| {
                        columns.push(idx);
                        columns.len() - 1
                    });
                    row.push((col, w));
                }
            }
        }
        rows.push(row);
    }
    Ok(BasisMatrix { columns, rows })
}

/// `B` in `f64` (eq. 2), rows indexed by lattice point; constraint points rounded to `f64`.
struct BasisMatrixF64 {
    rows: Vec<Vec<(usize, f64)>>,
}

fn basis_matrix_f64(l: &Lattice, constraints: &[Constraint]) -> Result<BasisMatrixF64, FfdError> {
    use super::deform::basis_f64;
    let order = l.order();
    let counts = l.counts();
    let knots: [Vec<f64>; 3] = [0, 1, 2].map(|a| l.knots(a).iter().map(rational_to_f64).collect());
    let mut rows = Vec::with_capacity(constraints.len());
    for (r, c) in constraints.iter().enumerate() {
        l.check_inside(&c.point).map_err(|e| FfdError::Input {
            lattice: 0,
            field: format!("constraints[{r}].point"),
            why: e.to_string(),
        })?;
        let mut vals = [[0.0f64; super::lattice::MAX_ORDER]; 3];
        let first: [usize; 3] = [0, 1, 2].map(|a| {
            basis_f64(
                &knots[a],
                order[a] - 1,
                counts[a],
                rational_to_f64(&c.point[a]),
                &mut vals[a],
            )
        });
        let mut row = Vec::with_capacity(order.iter().product());
        for k in 0..order[2] {
            for j in 0..order[1] {
                for i in 0..order[0] {
                    let w = vals[0][i] * vals[1][j] * vals[2][k];
                    if w != 0.0 {
                        row.push((l.index(first[0] + i, first[1] + j, first[2] + k), w));
                    }
                }
            }
        }
        rows.push(row);
    }
    Ok(BasisMatrixF64 { rows })
}

/// `B Bᵀ` (r × r), exactly.
fn gram(b: &BasisMatrix) -> Vec<Vec<Rational>> {
    let r = b.rows.len();
    let mut dense: Vec<Vec<Rational>> = vec![vec![Rational::zero(); b.columns.len()]; r];
    for (i, row) in b.rows.iter().enumerate() {
        for (c, w) in row {
            dense[i][*c] = w.clone();
        }
    }
    (0..r)
        .map(|i| {
            (0..r)
                .map(|j| {
                    b.rows[i]
                        .iter()
                        .map(|(c, w)| w * &dense[j][*c])
                        .fold(Rational::zero(), |a, x| a + x)
                })
                .collect()
        })
        .collect()
}

/// Solves `G Y = D` exactly by Gaussian elimination with row pivoting; a zero pivot means the
/// constraints are dependent (`B` rank-deficient): the error names the constraint.
fn solve_exact_system(
    mut g: Vec<Vec<Rational>>,
    mut d: Vec<Point>,
) -> Result<Vec<Point>, FfdError> {
    let n = g.len();
    let mut perm: Vec<usize> = (0..n).collect();
    for col in 0..n {
        let Some(p) = (col..n).find(|&r| !g[r][col].is_zero()) else {
            return Err(FfdError::RankDeficient {
                constraint: perm[col],
            });
        };
        g.swap(col, p);
        d.swap(col, p);
        perm.swap(col, p);
        let pivot = g[col][col].clone();
        for r in col + 1..n {
            if g[r][col].is_zero() {
                continue;
            }
            let f = &g[r][col] / &pivot;
            let pivot_row = g[col].clone();
            for (x, p) in g[r][col..].iter_mut().zip(&pivot_row[col..]) {
                *x -= &f * p;
            }
            let dc = d[col].clone();
            for (x, y) in d[r].iter_mut().zip(dc.iter()) {
                *x -= &f * y;
            }
        }
    }
    let mut y: Vec<Point> = vec![Default::default(); n];
    for r in (0..n).rev() {
        let mut acc = d[r].clone();
        for c in r + 1..n {
            for a in 0..3 {
                acc[a] -= &g[r][c] * &y[c][a];
            }
        }
        y[r] = acc.map(|v| v / &g[r][r]);
    }
    Ok(y)
}

/// The exact least-norm lattice change `ΔP = Bᵀ (B Bᵀ)⁻¹ ΔF` (eq. 4), one entry per lattice
/// point (zero where a point influences no constraint). `B ΔP = ΔF` holds exactly.
pub fn solve_exact(l: &Lattice, constraints: &[Constraint]) -> Result<Vec<Point>, FfdError> {
    let points: Vec<Point> = constraints.iter().map(|c| c.point.clone()).collect();
    let b = basis_matrix(l, &points)?;
    let y = solve_exact_system(
        gram(&b),
        constraints.iter().map(|c| c.delta.clone()).collect(),
    )?;
    let mut delta: Vec<Point> = vec![Default::default(); l.points().len()];
    for (i, row) in b.rows.iter().enumerate() {
        for (c, w) in row {
            let idx = b.columns[*c];
            for a in 0..3 {
                delta[idx][a] += w * &y[i][a];
            }
        }
    }
    Ok(delta)
}

/// The same in `f64`: `B Bᵀ` (symmetric positive definite when the constraints are
/// independent) by a Cholesky factorisation that touches only its nonzero entries (far-apart
/// constraints give zero blocks). A pivot below `1e-12 ×` the largest diagonal entry reports
/// the constraint as dependent.
#[allow(clippy::needless_range_loop)] // matrix indices pick rows and columns
pub fn solve_fast(l: &Lattice, constraints: &[Constraint]) -> Result<Vec<[f64; 3]>, FfdError> {
    let b = basis_matrix_f64(l, constraints)?;
    let rows = &b.rows;
    let n = rows.len();
    // G = B Bᵀ through a column-indexed scatter of each row.
    let mut scatter = vec![0.0f64; l.points().len()];
    let mut g = vec![vec![0.0f64; n]; n];
    for i in 0..n {
        for (c, w) in &rows[i] {
            scatter[*c] = *w;
        }
        for j in 0..=i {
            let v: f64 = rows[j].iter().map(|(c, w)| w * scatter[*c]).sum();
            g[i][j] = v;
            g[j][i] = v;
        }
        for (c, _) in &rows[i] {
            scatter[*c] = 0.0;
        }
    }
    let scale = (0..n).map(|i| g[i][i]).fold(0.0f64, f64::max);
    // Cholesky G = L Lᵀ, skipping structural zeros.
    let mut lo = vec![vec![0.0f64; n]; n];
    for j in 0..n {
        let d = g[j][j] - (0..j).map(|k| lo[j][k] * lo[j][k]).sum::<f64>();
        if d.is_nan() || d <= 1e-12 * scale {
            return Err(FfdError::RankDeficient { constraint: j });
        }
        lo[j][j] = d.sqrt();
        for i in j + 1..n {
            if g[i][j] == 0.0 && (0..j).all(|k| lo[i][k] == 0.0 || lo[j][k] == 0.0) {
                continue;
            }
            let s = g[i][j] - (0..j).map(|k| lo[i][k] * lo[j][k]).sum::<f64>();
            lo[i][j] = s / lo[j][j];
        }
    }
    let mut delta = vec![[0.0f64; 3]; l.points().len()];
    for a in 0..3 {
        let rhs: Vec<f64> = constraints
            .iter()
            .map(|c| rational_to_f64(&c.delta[a]))
            .collect();
        // Forward then backward substitution.
        let mut z = vec![0.0f64; n];
        for i in 0..n {
            z[i] = (rhs[i] - (0..i).map(|k| lo[i][k] * z[k]).sum::<f64>()) / lo[i][i];
        }
        let mut y = vec![0.0f64; n];
        for i in (0..n).rev() {
            y[i] = (z[i] - (i + 1..n).map(|k| lo[k][i] * y[k]).sum::<f64>()) / lo[i][i];
        }
        for (i, row) in rows.iter().enumerate() {
            for (c, w) in row {
                delta[*c][a] += w * y[i];
            }
        }
    }
    Ok(delta)
}

/// Which test certifies each step of an injective drag.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DragTest {
    /// The conic-hull hodograph test (the paper's choice).
    Conic,
    /// The phi test (eq. 7).
    Phi,
    /// The necessary-and-sufficient test.
    Exact,
}

crate::choice::named_enum!(DragTest {
    Conic => "conic",
    Phi => "phi",
    Exact => "exact",
});

/// Options of [`injective_drag`].
#[derive(Clone, Copy, Debug)]
#[non_exhaustive]
pub struct DragOptions {
    /// The test that certifies each step.
    pub test: DragTest,
    /// Deepest halving (`InjectSubdiv`'s maximum recursion depth).
    pub max_depth: u32,
    /// The solve and the sufficient tests: [`Path::Exact`] (the default) in rationals, every
    /// constraint met exactly; [`Path::Fast`] or [`Path::Filtered`] in `f64` (a Cholesky
    /// solve), each step's rounded lattice certified by the certified-`f64` tests.
    pub path: Path,
    /// Path and limits of the N&S test when `test` is `Exact` (every path is rigorous;
    /// `Filtered` is the fastest).
    pub ns_path: Path,
    /// Limits of each N&S test.
    pub limits: Limits,
}

crate::choice::setters!(DragOptions {
    with_test => test: DragTest,
    with_max_depth => max_depth: u32,
    with_path => path: Path,
    with_ns_path => ns_path: Path,
    with_limits => limits: Limits,
});

impl Default for DragOptions {
    fn default() -> Self {
        DragOptions {
            test: DragTest::Conic,
            max_depth: 8,
            path: Path::Exact,
            ns_path: Path::Filtered,
            limits: Limits::default(),
        }
    }
}

/// One certified step: the constraints it meets and its lattice (undeformed plus `ΔP`).
#[derive(Clone, Debug, PartialEq)]
pub struct DragStep {
    /// The halving depth this step came from (0: the whole drag).
    pub depth: u32,
    /// The constraints this step meets.
    pub constraints: Vec<Constraint>,
    /// The lattice after this step (undeformed plus its `ΔP`).
    pub lattice: Lattice,
}

/// Is `l` injective by `test` (certified verdicts only)?
fn certified(l: &Lattice, opts: &DragOptions) -> bool {
    let sufficient = |v: SufficientVerdict| v == SufficientVerdict::Injective;
    match (opts.test, opts.path == Path::Exact) {
        (DragTest::Conic, true) => sufficient(conic_test_exact(l, ConicOptions::default())),
        (DragTest::Conic, false) => sufficient(conic_test_fast(l, ConicOptions::default())),
        (DragTest::Phi, true) => sufficient(phi_test_exact(l, Scope::PerCell)),
        (DragTest::Phi, false) => sufficient(phi_test_fast(l, Scope::PerCell)),
        (DragTest::Exact, _) => check_injectivity(
            l,
            CheckOptions {
                path: opts.ns_path,
                limits: opts.limits,
            },
        )
        .is_ok_and(|r| matches!(r.verdict, InjectivityVerdict::Injective { .. })),
    }
}

/// Injective DMFFD (Appendix `InjectSubdiv`): the ordered, certified steps whose composition
/// moves every constraint point by its full `delta`. `shape` gives the basis, orders and cells
/// (its points are ignored: every step deforms the undeformed lattice of that shape). Fails
/// with [`FfdError::DragNotInjective`] when some piece still fails at `max_depth`.
pub fn injective_drag(
    shape: &Lattice,
    constraints: &[Constraint],
    opts: DragOptions,
) -> Result<Vec<DragStep>, FfdError> {
    let identity = Lattice::identity(shape.basis(), shape.order(), shape.cells())?;
    let mut steps = Vec::new();
    subdivide_drag(&identity, constraints.to_vec(), 0, &opts, &mut steps)?;
    Ok(steps)
}

fn subdivide_drag(
    identity: &Lattice,
    constraints: Vec<Constraint>,
    depth: u32,
    opts: &DragOptions,
    steps: &mut Vec<DragStep>,
) -> Result<(), FfdError> {
    if depth >= opts.max_depth {
        return Err(FfdError::DragNotInjective {
            depth,
            first_point: constraints
                .first()
                .map(|c| {
                    c.point
                        .iter()
                        .map(rational_to_string)
                        .collect::<Vec<_>>()
                        .join(", ")
                })
                .unwrap_or_default(),
        });
    }
    let lattice = if opts.path == Path::Exact {
        let lattice = identity.displaced(&solve_exact(identity, &constraints)?)?;
        certified(&lattice, opts).then_some(lattice)
    } else {
        let d = solve_fast(identity, &constraints)?;
        let pts: Vec<[f64; 3]> = identity
            .points()
            .iter()
            .zip(&d)
            .map(|(p, dp)| [0, 1, 2].map(|a| rational_to_f64(&p[a]) + dp[a]))
            .collect();
        if pts.iter().flatten().any(|x| !x.is_finite()) {
            return Err(FfdError::FastUnfit("the f64 solve overflowed"));
        }
        // The conic test runs on the f64 points directly; a lattice is built only for a
        // certified step (or when another test needs one).
        let quick = match opts.test {
            DragTest::Conic => conic_f64(identity, &pts, Scope::PerCell),
            _ => None,
        };
        match quick {
            Some(SufficientVerdict::Injective) => Some(Lattice::from_f64(
                identity.basis(),
                identity.order(),
                identity.cells(),
                pts,
            )?),
            Some(_) => None,
            None => {
                let lattice =
                    Lattice::from_f64(identity.basis(), identity.order(), identity.cells(), pts)?;
                certified(&lattice, opts).then_some(lattice)
            }
        }
    };
    if let Some(lattice) = lattice {
        steps.push(DragStep {
            depth,
            constraints,
            lattice,
        });
        return Ok(());
    }
    let half = Rational::new(1.into(), 2.into());
    let first: Vec<Constraint> = constraints
        .iter()
        .map(|c| Constraint {
            point: c.point.clone(),
            delta: c.delta.clone().map(|d| d * &half),
        })
        .collect();
    let second: Vec<Constraint> = constraints
        .iter()
        .map(|c| Constraint {
            point: [0, 1, 2].map(|a| &c.point[a] + &c.delta[a] * &half),
            delta: c.delta.clone().map(|d| d * &half),
        })
        .collect();
    subdivide_drag(identity, first, depth + 1, opts, steps)?;
    subdivide_drag(identity, second, depth + 1, opts, steps)
}

/// Applies the steps in order to a parameter point (each step is the FFD of its lattice),
/// exactly. On exact-path steps a constraint point's images stay small rationals; through
/// rounded (`f64`) steps the digits grow like `degree^steps`: use
/// [`deform_points_fast`](super::deform::deform_points_fast) there.
pub fn compose(steps: &[DragStep], point: &Point) -> Result<Point, FfdError> {
    let mut x = point.clone();
    for s in steps {
        x = s.lattice.deform(&x)?;
    }
    Ok(x)
}

/// Parses `{"constraints": [{"point": [x,y,z], "delta": [dx,dy,dz]}, …]}` (numbers exact as
/// `f64`, or `"p/q"` strings).
pub fn constraints_from_json(text: &str) -> Result<Vec<Constraint>, FfdError> {
    let v: Value = serde_json::from_str(text)?;
    let bad = |field: String, why: String| FfdError::Input {
        lattice: 0,
        field,
        why,
    };
    let items = v
        .get("constraints")
        .and_then(Value::as_array)
        .ok_or_else(|| bad("constraints".into(), "missing or not an array".into()))?;
    if items.is_empty() {
        return Err(bad("constraints".into(), "at least one constraint".into()));
    }
    items
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let triple = |f: &str| -> Result<Point, FfdError> {
                let field = format!("constraints[{i}].{f}");
                let arr = c
                    .get(f)
                    .and_then(Value::as_array)
                    .filter(|a| a.len() == 3)
                    .ok_or_else(|| bad(field.clone(), "expected [x, y, z]".into()))?;
                let mut out: Point = Default::default();
                for (a, x) in arr.iter().enumerate() {
                    out[a] = crate::bernstein::io::parse_number(x)
                        .map_err(|why| bad(format!("{field}[{a}]"), why.to_string()))?;
                }
                Ok(out)
            };
            Ok(Constraint {
                point: triple("point")?,
                delta: triple("delta")?,
            })
        })
        .collect()
}

/// The JSON form of a drag's steps.
pub fn steps_to_json(steps: &[DragStep]) -> Value {
    let s = |p: &Point| p.iter().map(rational_to_string).collect::<Vec<_>>();
    Value::Array(
        steps
            .iter()
            .map(|st| {
                json!({
                    "depth": st.depth,
                    "constraints": st.constraints.iter().map(|c| json!({"point": s(&c.point), "delta": s(&c.delta)})).collect::<Vec<_>>(),
                    "lattice": st.lattice.to_json(),
                })
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ffd::Basis;
    use num_bigint::BigInt;

    fn q(n: i64, d: i64) -> Rational {
        Rational::new(BigInt::from(n), BigInt::from(d))
    }
    fn p(x: (i64, i64), y: (i64, i64), z: (i64, i64)) -> Point {
        [q(x.0, x.1), q(y.0, y.1), q(z.0, z.1)]
    }
    fn add(a: &Point, b: &Point) -> Point {
        [0, 1, 2].map(|i| &a[i] + &b[i])
    }

    #[test]
    fn exact_solve_meets_every_constraint_exactly() {
        let id = Lattice::identity(Basis::Bspline, [4, 4, 4], [2, 2, 2]).unwrap();
        let cs = vec![
            Constraint {
                point: p((1, 1), (1, 1), (1, 1)),
                delta: p((1, 3), (-1, 5), (0, 1)),
            },
            Constraint {
                point: p((1, 3), (3, 2), (7, 4)),
                delta: p((0, 1), (1, 7), (-2, 9)),
            },
            Constraint {
                point: p((2, 1), (0, 1), (1, 2)),
                delta: p((-1, 4), (0, 1), (1, 8)),
            },
        ];
        let dp = solve_exact(&id, &cs).unwrap();
        let moved = id.displaced(&dp).unwrap();
        for c in &cs {
            assert_eq!(moved.deform(&c.point).unwrap(), add(&c.point, &c.delta));
        }
        // The f64 solve agrees to rounding.
        let fast = solve_fast(&id, &cs).unwrap();
        for (e, f) in dp.iter().zip(&fast) {
            for a in 0..3 {
                assert!((rational_to_f64(&e[a]) - f[a]).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn least_norm_change_lies_in_the_row_space() {
        // ΔP = Bᵀy: a point influencing no constraint does not move.
        let id = Lattice::identity(Basis::Bspline, [3, 3, 3], [3, 3, 3]).unwrap();
        let cs = vec![Constraint {
            point: p((1, 2), (1, 2), (1, 2)),
            delta: p((1, 4), (0, 1), (0, 1)),
        }];
        let dp = solve_exact(&id, &cs).unwrap();
        let b = basis_matrix(&id, &[cs[0].point.clone()]).unwrap();
        for (i, d) in dp.iter().enumerate() {
            if !b.columns.contains(&i) {
                assert!(d.iter().all(Zero::is_zero), "point {i} moved");
            }
        }
        // Weights of a partition of unity sum to one.
        let sum = b.rows[0]
            .iter()
            .fold(Rational::zero(), |acc, (_, w)| acc + w);
        assert_eq!(sum, q(1, 1));
    }

    #[test]
    fn dependent_constraints_are_a_clear_error() {
        let id = Lattice::identity(Basis::Bezier, [3, 3, 3], [1, 1, 1]).unwrap();
        let c = Constraint {
            point: p((1, 2), (1, 3), (1, 4)),
            delta: p((1, 10), (0, 1), (0, 1)),
        };
        let twice = vec![c.clone(), c];
        assert_eq!(
            solve_exact(&id, &twice),
            Err(FfdError::RankDeficient { constraint: 1 })
        );
        assert_eq!(
            solve_fast(&id, &twice),
            Err(FfdError::RankDeficient { constraint: 1 })
        );
        let outside = vec![Constraint {
            point: p((3, 2), (0, 1), (0, 1)),
            delta: p((0, 1), (0, 1), (0, 1)),
        }];
        assert!(matches!(
            solve_exact(&id, &outside),
            Err(FfdError::Input { .. })
        ));
    }

    /// A drag far beyond the constraint's volume of influence (overextension, Section 8).
    fn long_drag() -> (Lattice, Vec<Constraint>) {
        let shape = Lattice::identity(Basis::Bspline, [3, 3, 3], [2, 2, 2]).unwrap();
        let cs = vec![Constraint {
            point: p((1, 2), (1, 1), (1, 1)),
            delta: p((3, 2), (0, 1), (0, 1)),
        }];
        (shape, cs)
    }

    #[test]
    fn injective_drag_splits_and_composes_to_the_constraints() {
        let (shape, cs) = long_drag();
        // One step is not injective by any test: the N&S test finds a witness.
        let one = shape.displaced(&solve_exact(&shape, &cs).unwrap()).unwrap();
        let r = check_injectivity(&one, CheckOptions::default()).unwrap();
        assert!(matches!(r.verdict, InjectivityVerdict::NotInjective { .. }));
        for test in [DragTest::Conic, DragTest::Exact] {
            let opts = DragOptions {
                test,
                ..Default::default()
            };
            let steps = injective_drag(&shape, &cs, opts).unwrap();
            assert!(steps.len() >= 2, "{test:?}: {} steps", steps.len());
            for s in &steps {
                assert!(certified(&s.lattice, &opts));
                let r = check_injectivity(&s.lattice, CheckOptions::default()).unwrap();
                assert!(matches!(r.verdict, InjectivityVerdict::Injective { .. }));
            }
            for c in &cs {
                assert_eq!(compose(&steps, &c.point).unwrap(), add(&c.point, &c.delta));
            }
        }
    }

    #[test]
    fn drag_reports_the_depth_it_gave_up_at() {
        let (shape, cs) = long_drag();
        let opts = DragOptions {
            max_depth: 1,
            ..Default::default()
        };
        assert!(matches!(
            injective_drag(&shape, &cs, opts),
            Err(FfdError::DragNotInjective { depth: 1, .. })
        ));
    }

    #[test]
    fn constraints_parse_with_field_errors() {
        let cs = constraints_from_json(
            r#"{"constraints": [{"point": [0.5, "1/3", 1], "delta": [0, 0, "-1/8"]}]}"#,
        )
        .unwrap();
        assert_eq!(cs[0].point, p((1, 2), (1, 3), (1, 1)));
        assert_eq!(cs[0].delta, p((0, 1), (0, 1), (-1, 8)));
        let e =
            constraints_from_json(r#"{"constraints": [{"point": [0, 0], "delta": [0, 0, 0]}]}"#)
                .unwrap_err();
        assert!(e.to_string().contains("constraints[0].point"), "{e}");
        let e = constraints_from_json(
            r#"{"constraints": [{"point": [0, 0, "1/0"], "delta": [0, 0, 0]}]}"#,
        )
        .unwrap_err();
        assert!(e.to_string().contains("constraints[0].point[2]"), "{e}");
    }
}
