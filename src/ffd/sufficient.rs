//! The sufficient injectivity tests of the paper's Section 7, exact and certified `f64`.
//!
//! * **phi test** (eq. 7): every determinant scalar `φ = det[P̃^(u), P̃^(v), P̃^(w)]` formed from
//!   the difference vectors local to a cell is positive. `det J` is a positive combination of
//!   them (eq. 6), so this implies injectivity. Computed as `(P̃^(u) × P̃^(v)) · P̃^(w)` (eq. 9).
//! * **Bézier-coefficient variant**: every Bézier coefficient of `det J` on every cell is
//!   positive (the N&S test stopped at depth 0). The Bézier coefficients are convex
//!   combinations of the B-spline control scalars, themselves positive combinations of the φ
//!   (NOTES), so phi ⇒ Bézier ⇒ N&S.
//! * **conic-hull hodograph test** (Section 7, Appendix `InjectiveTest`): with
//!   `t = (b² + c²)/a²` the squared tangent of a `u`-difference's angle to the `u` axis
//!   (`a ≤ 0` fails), `m` the cell's maximum per axis and `θ = arctan √m`: pass iff
//!   `θ_u + θ_v < π/2` and `θ_× + θ_w < π/2` with `sin²θ_× = sin²θ_u + sin²θ_v` (eq. 10).
//!   Exactly, without trigonometry: `θ_u + θ_v < π/2 ⟺ m_u m_v < 1`, `sin²θ = m/(1+m)`, and
//!   with `s = sin²θ_u + sin²θ_v`, `θ_× + θ_w < π/2 ⟺ s (1 + m_w) < 1`.
//!
//! Scopes: per cell (each cell's local difference vectors; the lattice passes when every cell
//! does), or the whole lattice (one set of vectors or cones for the entire hyperpatch — faster,
//! weaker). The conic test also takes a subdivision depth: each cell's Bézier net is split
//! into `8^depth` sub-nets and the cones are formed from each sub-net's hodograph (the
//! section's last paragraph: "recursively subdividing hyperpatch cells").

use super::fast::{jacobian_cell_fast, JacobianWorkspace};
use super::jacobian::{jacobian_cell_scaled, scaled_net};
use super::lattice::{Basis, Lattice};
use super::FfdError;
use crate::bernstein::{Bernstein, ScaledBernstein};
use crate::num::{gamma, rational_to_f64, Interval, Rational, Sign};
use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::{One, Signed, Zero};

/// The outcome of a sufficient test.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SufficientVerdict {
    /// The test proves injectivity.
    Injective,
    /// The test does not prove injectivity; `cell` is where it first failed (`None`: the
    /// whole-lattice scope). The deformation may still be injective.
    NotProven {
        /// Where it failed (`None` for the whole-lattice scope).
        cell: Option<[usize; 3]>,
    },
    /// Fast path only: rounding left the outcome open at `cell`.
    Uncertain {
        /// Where (`None` for the whole-lattice scope).
        cell: Option<[usize; 3]>,
    },
}

impl SufficientVerdict {
    /// `Positive` (proven injective), `Negative` (not proven), `Uncertain`.
    pub fn sign(&self) -> Sign {
        match self {
            SufficientVerdict::Injective => Sign::Positive,
            SufficientVerdict::NotProven { .. } => Sign::Negative,
            SufficientVerdict::Uncertain { .. } => Sign::Uncertain,
        }
    }
}

/// Where the vectors or cones are gathered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scope {
    /// Each cell's own Bézier differences.
    PerCell,
    /// The whole lattice's differences at once (the paper's scope).
    Lattice,
}

/// A difference vector, exact.
type Vec3 = [Rational; 3];

/// The difference vectors local to `cell` (`None`: the whole lattice), per axis `x`:
/// `P_{…,i,…} − P_{…,i−1,…}` along `x` over the control points that influence the cell.
pub(crate) fn local_differences(l: &Lattice, cell: Option<[usize; 3]>) -> [Vec<Vec3>; 3] {
    let counts = l.counts();
    let order = l.order();
    let range = |a: usize| -> (usize, usize) {
        match (cell, l.basis()) {
            (Some(c), Basis::Bspline) => (c[a], c[a] + order[a]),
            _ => (0, counts[a]),
        }
    };
    let (r0, r1, r2) = (range(0), range(1), range(2));
    let mut out: [Vec<Vec3>; 3] = Default::default();
    for (x, diffs) in out.iter_mut().enumerate() {
        for k in r2.0..r2.1 {
            for j in r1.0..r1.1 {
                for i in r0.0..r0.1 {
                    let idx = [i, j, k];
                    if idx[x] == [r0, r1, r2][x].0 {
                        continue;
                    }
                    let mut prev = idx;
                    prev[x] -= 1;
                    let p = &l.points()[l.index(i, j, k)];
                    let q = &l.points()[l.index(prev[0], prev[1], prev[2])];
                    diffs.push([0, 1, 2].map(|c| &p[c] - &q[c]));
                }
            }
        }
    }
    out
}

fn cells_of(l: &Lattice, scope: Scope) -> Vec<Option<[usize; 3]>> {
    match scope {
        Scope::PerCell => (0..l.cell_count()).map(|c| Some(l.cell_index(c))).collect(),
        Scope::Lattice => vec![None],
    }
}

/// Integer vectors over one common denominator (signs of determinants unchanged).
fn to_integers(sets: &[Vec<Vec3>; 3]) -> [Vec<[BigInt; 3]>; 3] {
    let den = sets
        .iter()
        .flatten()
        .flatten()
        .fold(BigInt::one(), |acc, c| acc.lcm(c.denom()));
    [0, 1, 2].map(|x| {
        sets[x]
            .iter()
            .map(|v| [0, 1, 2].map(|c| v[c].numer() * (&den / v[c].denom())))
            .collect()
    })
}

/// The phi test (eq. 7), exactly: every `φ > 0`.
pub fn phi_test_exact(l: &Lattice, scope: Scope) -> SufficientVerdict {
    for cell in cells_of(l, scope) {
        let [u, v, w] = to_integers(&local_differences(l, cell));
        for a in &u {
            for b in &v {
                let n = [
                    &a[1] * &b[2] - &a[2] * &b[1],
                    &a[2] * &b[0] - &a[0] * &b[2],
                    &a[0] * &b[1] - &a[1] * &b[0],
                ];
                for c in &w {
                    let phi = &n[0] * &c[0] + &n[1] * &c[1] + &n[2] * &c[2];
                    if !phi.is_positive() {
                        return SufficientVerdict::NotProven { cell };
                    }
                }
            }
        }
    }
    SufficientVerdict::Injective
}

/// `f64` difference vectors: each component is the exact difference rounded to nearest
/// (relative error ≤ u in the normal range), or `None` if some component is outside the
/// safe range.
fn to_f64(sets: &[Vec<Vec3>; 3]) -> Option<[Vec<[f64; 3]>; 3]> {
    let mut ok = true;
    let out = [0, 1, 2].map(|x| {
        sets[x]
            .iter()
            .map(|v| {
                [0, 1, 2].map(|c| {
                    let f = rational_to_f64(&v[c]);
                    let m = f.abs();
                    if !f.is_finite() || m > 1e75 || (m != 0.0 && m < 1e-75) {
                        ok = false;
                    }
                    f
                })
            })
            .collect()
    });
    ok.then_some(out)
}

/// The phi test in `f64`: each `φ` is certified by `|fl(φ) − φ| ≤ γ₆ Σ|terms|` (three
/// rounded inputs, two products, two sums; the six terms bounded by `‖a‖₁‖b‖₁‖c‖₁`).
pub fn phi_test_fast(l: &Lattice, scope: Scope) -> SufficientVerdict {
    let g = gamma(8);
    for cell in cells_of(l, scope) {
        let Some([u, v, w]) = to_f64(&local_differences(l, cell)) else {
            return SufficientVerdict::Uncertain { cell };
        };
        let norm = |x: &[f64; 3]| x[0].abs() + x[1].abs() + x[2].abs();
        let wn: Vec<f64> = w.iter().map(norm).collect();
        for a in &u {
            let an = norm(a);
            for b in &v {
                let n = [
                    a[1] * b[2] - a[2] * b[1],
                    a[2] * b[0] - a[0] * b[2],
                    a[0] * b[1] - a[1] * b[0],
                ];
                let abn = an * norm(b);
                for (c, cn) in w.iter().zip(&wn) {
                    let phi = n[0] * c[0] + n[1] * c[1] + n[2] * c[2];
                    let err = g * abn * cn * (1.0 + g);
                    if phi <= -err {
                        return SufficientVerdict::NotProven { cell };
                    }
                    if phi <= err {
                        return SufficientVerdict::Uncertain { cell };
                    }
                }
            }
        }
    }
    SufficientVerdict::Injective
}

/// The Bézier-coefficient variant, exactly: every Bézier coefficient of `det J` positive.
pub fn bezier_coefficient_test_exact(l: &Lattice) -> Result<SufficientVerdict, FfdError> {
    for (c, net) in l.bezier_nets().iter().enumerate() {
        let j = jacobian_cell_scaled(net)?;
        if !j.all_positive() {
            return Ok(SufficientVerdict::NotProven {
                cell: Some(l.cell_index(c)),
            });
        }
    }
    Ok(SufficientVerdict::Injective)
}

/// The Bézier-coefficient variant in certified `f64`.
pub fn bezier_coefficient_test_fast(l: &Lattice) -> SufficientVerdict {
    let deg = l.order().map(|o| o - 1);
    let mut ws = JacobianWorkspace::default();
    let mut uncertain = None;
    for (c, net) in l.bezier_nets().iter().enumerate() {
        let cell = Some(l.cell_index(c));
        let (pts, eta) = super::injectivity::net_f64(net);
        let Ok(f) = jacobian_cell_fast(&pts, deg, eta, &mut ws) else {
            uncertain.get_or_insert(cell);
            continue;
        };
        if f.coeffs().iter().any(|&x| x < -f.err()) {
            return SufficientVerdict::NotProven { cell };
        }
        if f.coeffs().iter().any(|&x| x <= f.err()) {
            uncertain.get_or_insert(cell);
        }
    }
    match uncertain {
        Some(cell) => SufficientVerdict::Uncertain { cell },
        None => SufficientVerdict::Injective,
    }
}

/// Options of the conic-hull test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct ConicOptions {
    /// The lattice's own differences, or each cell's.
    pub scope: Scope,
    /// Octree depth of Bézier subdivision per cell (0: the paper's test on the lattice's own
    /// differences; only with `Scope::PerCell`).
    pub subdivision_depth: u32,
}

crate::choice::setters!(ConicOptions {
    with_scope => scope: Scope,
    with_subdivision_depth => subdivision_depth: u32,
});

impl Default for ConicOptions {
    fn default() -> Self {
        ConicOptions {
            scope: Scope::PerCell,
            subdivision_depth: 0,
        }
    }
}

/// The maximal `t = (b² + c²)/a²` per axis over integer difference vectors (`t` is invariant
/// under a common positive scale, so numerators over a shared denominator suffice), compared
/// by cross-multiplication; `None` when some `a ≤ 0` (`FindDeviation` fails).
fn max_deviations(sets: &[Vec<[BigInt; 3]>; 3]) -> Option<[Rational; 3]> {
    let mut out: [Rational; 3] = Default::default();
    for (x, o) in out.iter_mut().enumerate() {
        let (mut bn, mut bd) = (BigInt::zero(), BigInt::one());
        for v in &sets[x] {
            let a = &v[x];
            if !a.is_positive() {
                return None;
            }
            let (b, c) = (&v[(x + 1) % 3], &v[(x + 2) % 3]);
            let n = b * b + c * c;
            let d = a * a;
            if &n * &bd > &bn * &d {
                (bn, bd) = (n, d);
            }
        }
        *o = Rational::new(bn, bd);
    }
    Some(out)
}

/// The cone conditions on the maximal squared tangents, exactly.
fn cones_pass_exact(m: &[Rational; 3]) -> bool {
    let one = Rational::one();
    if &m[0] * &m[1] >= one {
        return false;
    }
    let s = &m[0] / (&one + &m[0]) + &m[1] / (&one + &m[1]);
    s * (&one + &m[2]) < one
}

/// One conic test on a set of integer difference vectors, exactly.
fn conic_on_exact(sets: &[Vec<[BigInt; 3]>; 3]) -> bool {
    max_deviations(sets).is_some_and(|m| cones_pass_exact(&m))
}

/// Hodograph differences of an integer (sub)net (numerators; the shared denominator is
/// irrelevant to the cone test).
fn scaled_net_differences(net: &[ScaledBernstein; 3]) -> [Vec<[BigInt; 3]>; 3] {
    let d = net[0].degrees().to_vec();
    let stride = [1, d[0] + 1, (d[0] + 1) * (d[1] + 1)];
    let mut out: [Vec<[BigInt; 3]>; 3] = Default::default();
    for (x, diffs) in out.iter_mut().enumerate() {
        for k in 0..=d[2] {
            for j in 0..=d[1] {
                for i in 0..=d[0] {
                    if [i, j, k][x] == d[x] {
                        continue;
                    }
                    let at = i * stride[0] + j * stride[1] + k * stride[2];
                    diffs.push(
                        [0, 1, 2].map(|c| {
                            &net[c].numerators()[at + stride[x]] - &net[c].numerators()[at]
                        }),
                    );
                }
            }
        }
    }
    out
}

/// Sub-nets of a 3-coordinate net after `depth` octree levels, `split` halving one coordinate
/// along one axis (every coordinate is split alike).
fn octree<P>(net: [P; 3], depth: u32, split: impl Fn(&P, usize) -> (P, P)) -> Vec<[P; 3]> {
    let mut nets = vec![net];
    for _ in 0..depth {
        let mut next = Vec::with_capacity(nets.len() * 8);
        for n in nets {
            let mut parts = vec![n];
            for axis in 0..3 {
                parts = parts
                    .into_iter()
                    .flat_map(|p| {
                        let [(l0, r0), (l1, r1), (l2, r2)] =
                            [split(&p[0], axis), split(&p[1], axis), split(&p[2], axis)];
                        [[l0, l1, l2], [r0, r1, r2]]
                    })
                    .collect();
            }
            next.extend(parts);
        }
        nets = next;
    }
    nets
}

/// Integer sub-nets after `depth` octree levels of de Casteljau at ½ (all three coordinates
/// split alike, so they keep one shared denominator).
fn subdivide_scaled(net: [ScaledBernstein; 3], depth: u32) -> Vec<[ScaledBernstein; 3]> {
    octree(net, depth, |c, axis| c.split_half(axis).expect("axis < 3"))
}

/// Hodograph differences of a Bézier (sub)net: per axis `x`, `b_{…,i+1,…} − b_{…,i,…}`.
fn net_differences<T: crate::num::Field>(net: &[Bernstein<T>; 3]) -> [Vec<[T; 3]>; 3] {
    let d = net[0].degrees().to_vec();
    let mut out: [Vec<[T; 3]>; 3] = Default::default();
    for (x, diffs) in out.iter_mut().enumerate() {
        for k in 0..=d[2] {
            for j in 0..=d[1] {
                for i in 0..=d[0] {
                    let idx = [i, j, k];
                    if idx[x] == d[x] {
                        continue;
                    }
                    let mut next = idx;
                    next[x] += 1;
                    diffs.push([0, 1, 2].map(|c| net[c].coeff(&next).sub(net[c].coeff(&idx))));
                }
            }
        }
    }
    out
}

/// Sub-nets of a Bézier net after `depth` octree levels of de Casteljau at ½.
fn subdivide<T: crate::num::Field>(net: [Bernstein<T>; 3], depth: u32) -> Vec<[Bernstein<T>; 3]> {
    let half = T::from_ratio(1, 2);
    octree(net, depth, |c, axis| {
        c.split(axis, &half).expect("axis < 3")
    })
}

/// The conic-hull hodograph test (Appendix `InjectiveTest`), exactly.
pub fn conic_test_exact(l: &Lattice, opts: ConicOptions) -> SufficientVerdict {
    if opts.subdivision_depth > 0 && opts.scope == Scope::PerCell {
        for (c, net) in l.bezier_nets().into_iter().enumerate() {
            let Ok(scaled) = scaled_net(&net) else {
                return SufficientVerdict::NotProven {
                    cell: Some(l.cell_index(c)),
                };
            };
            for sub in subdivide_scaled(scaled, opts.subdivision_depth) {
                if !conic_on_exact(&scaled_net_differences(&sub)) {
                    return SufficientVerdict::NotProven {
                        cell: Some(l.cell_index(c)),
                    };
                }
            }
        }
        return SufficientVerdict::Injective;
    }
    for cell in cells_of(l, opts.scope) {
        if !conic_on_exact(&to_integers(&local_differences(l, cell))) {
            return SufficientVerdict::NotProven { cell };
        }
    }
    SufficientVerdict::Injective
}

/// Upper and lower enclosures of the cone quantities in interval arithmetic.
fn conic_on_intervals(sets: &[Vec<[Interval; 3]>; 3]) -> Sign {
    let mut m = [Interval::point(0.0); 3];
    let mut uncertain = false;
    for x in 0..3 {
        for v in &sets[x] {
            let a = v[x];
            match a.sign() {
                Sign::Positive => {}
                Sign::Uncertain => {
                    uncertain = true;
                    continue;
                }
                _ => return Sign::Negative,
            }
            let (b, c) = (v[(x + 1) % 3], v[(x + 2) % 3]);
            let t = (b * b + c * c) / (a * a);
            m[x] = Interval::new(m[x].lo.max(t.lo.max(0.0)), m[x].hi.max(t.hi));
        }
    }
    let one = Interval::point(1.0);
    let first = (m[0] * m[1] - one).sign();
    let s = m[0] / (one + m[0]) + m[1] / (one + m[1]);
    let second = (s * (one + m[2]) - one).sign();
    match (first, second) {
        (Sign::Negative, Sign::Negative) if !uncertain => Sign::Positive,
        (Sign::Positive | Sign::Zero, _) => Sign::Negative,
        (Sign::Negative, Sign::Positive | Sign::Zero) if !uncertain => Sign::Negative,
        _ => Sign::Uncertain,
    }
}

/// The conic-hull test in certified `f64`: a verdict is certified or `Uncertain`. On lattices
/// whose points are exactly `f64` the depth-0 test runs in plain `f64` with a-priori relative
/// error bounds (`conic_f64`); otherwise, and with subdivision, in outward-rounded intervals.
pub fn conic_test_fast(l: &Lattice, opts: ConicOptions) -> SufficientVerdict {
    if opts.subdivision_depth == 0 {
        if let Some(pts) = l.points_f64() {
            if let Some(v) = conic_f64(l, pts, opts.scope) {
                return v;
            }
        }
    }
    let decide = |sets: &[Vec<[Interval; 3]>; 3], cell| match conic_on_intervals(sets) {
        Sign::Positive => None,
        Sign::Negative => Some(SufficientVerdict::NotProven { cell }),
        _ => Some(SufficientVerdict::Uncertain { cell }),
    };
    if opts.subdivision_depth > 0 && opts.scope == Scope::PerCell {
        for (c, net) in l.bezier_nets().into_iter().enumerate() {
            let inet = net.clone().map(|p| p.map(Interval::from_rational));
            for sub in subdivide(inet, opts.subdivision_depth) {
                if let Some(v) = decide(&net_differences(&sub), Some(l.cell_index(c))) {
                    return v;
                }
            }
        }
        return SufficientVerdict::Injective;
    }
    for cell in cells_of(l, opts.scope) {
        let d = local_differences(l, cell);
        let sets = [0, 1, 2].map(|x| {
            d[x].iter()
                .map(|v| [0, 1, 2].map(|c| Interval::from_rational(&v[c])))
                .collect::<Vec<_>>()
        });
        if let Some(v) = decide(&sets, cell) {
            return v;
        }
    }
    SufficientVerdict::Injective
}

/// Relative error of a computed `t = (b² + c²)/a²` from `f64` points: three rounded
/// differences (each squared), two products, one sum, one division: `γ₁₀` covers it.
const T_REL: usize = 10;

/// The depth-0 conic test on exact `f64` points in plain `f64`. `fl(p₁ − p₀)` has the sign of
/// the exact difference, so `a ≤ 0` is decided exactly; every `t` is within relative `γ₁₀`
/// of the exact value, and the cone conditions are monotone in the `m`s, so evaluating them
/// on inflated (deflated) maxima certifies a pass (a failure). `None` when magnitudes leave
/// the range where relative bounds hold (the caller falls back to intervals).
pub(crate) fn conic_f64(l: &Lattice, pts: &[[f64; 3]], scope: Scope) -> Option<SufficientVerdict> {
    let counts = l.counts();
    let stride = [1, counts[0], counts[0] * counts[1]];
    let n = pts.len();
    if n != counts[0] * counts[1] * counts[2] {
        return None;
    }
    // t per point and axis: the difference ending at that point (NaN: none; −1: a ≤ 0).
    // One window covering the whole lattice (a Bézier cell, or the lattice scope) needs no
    // table: the maxima are taken on the fly.
    let single = scope == Scope::Lattice || l.basis() == Basis::Bezier;
    let mut t = if single {
        Vec::new()
    } else {
        vec![[f64::NAN; 3]; n]
    };
    let mut m_all = [0.0f64; 3];
    let mut at = 0;
    for k in 0..counts[2] {
        for j in 0..counts[1] {
            for i in 0..counts[0] {
                let idx = [i, j, k];
                let p = pts[at];
                for x in 0..3 {
                    if idx[x] == 0 {
                        continue;
                    }
                    let q = pts[at - stride[x]];
                    let d = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
                    let (a, b, c) = match x {
                        0 => (d[0], d[1], d[2]),
                        1 => (d[1], d[2], d[0]),
                        _ => (d[2], d[0], d[1]),
                    };
                    // Outside the range where relative error bounds hold: the caller falls back.
                    let big = a.abs().max(b.abs()).max(c.abs());
                    let tiny = (a != 0.0 && a.abs() < 1e-150)
                        | (b != 0.0 && b.abs() < 1e-150)
                        | (c != 0.0 && c.abs() < 1e-150);
                    if big > 1e150 || tiny {
                        return None;
                    }
                    let tx = if a <= 0.0 {
                        if single {
                            return Some(SufficientVerdict::NotProven {
                                cell: (scope == Scope::PerCell).then_some([0, 0, 0]),
                            });
                        }
                        -1.0
                    } else {
                        (b * b + c * c) / (a * a)
                    };
                    if single {
                        m_all[x] = m_all[x].max(tx);
                    } else {
                        t[at][x] = tx;
                    }
                }
                at += 1;
            }
        }
    }
    let g = gamma(T_REL as u32);
    let g8 = gamma(8);
    let order = l.order();
    let window = |cell: Option<[usize; 3]>, a: usize| -> (usize, usize) {
        match (cell, l.basis()) {
            (Some(c), Basis::Bspline) => (c[a], c[a] + order[a]),
            _ => (0, counts[a]),
        }
    };
    let cells: Box<dyn Iterator<Item = Option<[usize; 3]>>> = match scope {
        Scope::PerCell => Box::new((0..l.cell_count()).map(|c| Some(l.cell_index(c)))),
        Scope::Lattice => Box::new(std::iter::once(None)),
    };
    let mut uncertain = None;
    for cell in cells {
        let w = [window(cell, 0), window(cell, 1), window(cell, 2)];
        let mut m = [0.0f64; 3];
        if single {
            m = m_all;
        } else {
            for k in w[2].0..w[2].1 {
                for j in w[1].0..w[1].1 {
                    let row = stride[1] * j + stride[2] * k;
                    for i in w[0].0..w[0].1 {
                        let tt = &t[row + i];
                        // The differences inside the window: skip its first layer per axis.
                        let inside = [i != w[0].0, j != w[1].0, k != w[2].0];
                        for x in 0..3 {
                            if inside[x] {
                                if tt[x] < 0.0 {
                                    return Some(SufficientVerdict::NotProven { cell });
                                }
                                m[x] = m[x].max(tt[x]);
                            }
                        }
                    }
                }
            }
        }
        let hi = m.map(|v| v * (1.0 + g) * (1.0 + 2.0 * g));
        let lo = m.map(|v| v * (1.0 - g) * (1.0 - 2.0 * g));
        // Each condition evaluated in f64 on bounds, itself with relative error ≤ γ₈.
        let cond = |m: &[f64; 3]| -> (f64, f64) {
            let first = m[0] * m[1];
            let s = m[0] / (1.0 + m[0]) + m[1] / (1.0 + m[1]);
            (first, s * (1.0 + m[2]))
        };
        let (f_hi, s_hi) = cond(&hi);
        let (f_lo, s_lo) = cond(&lo);
        if f_hi * (1.0 + g8) < 1.0 && s_hi * (1.0 + g8) < 1.0 {
            continue;
        }
        if f_lo * (1.0 - g8) >= 1.0 || s_lo * (1.0 - g8) >= 1.0 {
            return Some(SufficientVerdict::NotProven { cell });
        }
        uncertain.get_or_insert(cell);
    }
    Some(match uncertain {
        Some(cell) => SufficientVerdict::Uncertain { cell },
        None => SufficientVerdict::Injective,
    })
}
