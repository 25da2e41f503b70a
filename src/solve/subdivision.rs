//! The subdivision, written once over the coefficient field: exact rationals for the
//! reference path, outward-rounded intervals for the fast one.

use super::{
    Cluster, ClusterReason, RationalBox, Root, RootCertificate, Solution, SolveError, SolveOptions,
    System,
};
use crate::bernstein::{Bernstein, ScaledBernstein};
use crate::num::{rational_from_f64, rational_to_f64, Field, Interval, Rational, Sign};
use crate::Path;
use num_traits::{One, Signed, Zero};
use std::time::Instant;

/// What the subdivision needs of a coefficient beyond [`Field`]: enclosures of `|c|`.
pub(super) trait Coefficient: Field {
    /// An upper bound of `|c|` (exact for rationals).
    fn abs_upper(&self) -> Self;
    /// A lower bound of `|c|`, `0` when `c` may be zero.
    fn abs_lower(&self) -> Self;
    /// `max(self, o)` of two upper bounds.
    fn max_upper(&self, o: &Self) -> Self;
    /// `min(self, o)` of two lower bounds.
    fn min_lower(&self, o: &Self) -> Self;
    /// A certified upper bound of `|c|` as an `f64`.
    fn abs_upper_f64(&self) -> f64;
    /// Certified `f64` bounds `lo ≤ c ≤ hi`.
    fn bounds_f64(&self) -> (f64, f64);
    /// Whether the arithmetic is exact (no decision is ever left open by rounding).
    const EXACT: bool;
}

impl Coefficient for Rational {
    const EXACT: bool = true;
    fn abs_upper(&self) -> Self {
        self.abs()
    }
    fn abs_lower(&self) -> Self {
        self.abs()
    }
    fn max_upper(&self, o: &Self) -> Self {
        if self >= o {
            self.clone()
        } else {
            o.clone()
        }
    }
    fn min_lower(&self, o: &Self) -> Self {
        if self <= o {
            self.clone()
        } else {
            o.clone()
        }
    }
    fn abs_upper_f64(&self) -> f64 {
        let i = Interval::from_rational(self);
        i.lo.abs().max(i.hi.abs())
    }
    fn bounds_f64(&self) -> (f64, f64) {
        let i = Interval::from_rational(self);
        (i.lo, i.hi)
    }
}

impl Coefficient for Interval {
    const EXACT: bool = false;
    fn abs_upper(&self) -> Self {
        Interval::point(self.lo.abs().max(self.hi.abs()))
    }
    fn abs_lower(&self) -> Self {
        let m = if self.lo > 0.0 {
            self.lo
        } else if self.hi < 0.0 {
            -self.hi
        } else {
            0.0
        };
        Interval::point(m)
    }
    fn max_upper(&self, o: &Self) -> Self {
        Interval::point(self.hi.max(o.hi))
    }
    fn min_lower(&self, o: &Self) -> Self {
        Interval::point(self.lo.min(o.lo))
    }
    fn abs_upper_f64(&self) -> f64 {
        self.lo.abs().max(self.hi.abs())
    }
    fn bounds_f64(&self) -> (f64, f64) {
        (self.lo, self.hi)
    }
}

/// A box of the subdivision: its place in the unit box, the equations restricted to it.
struct Node<T> {
    lo: Vec<Rational>,
    hi: Vec<Rational>,
    polys: Vec<Bernstein<T>>,
    depth: u32,
}

/// The sign all of `p`'s coefficients share strictly, if they do (`Uncertain` when rounding
/// leaves it open, `Zero` when they do not share one).
pub(super) fn strict_sign<T: Field>(p: &Bernstein<T>) -> Sign {
    shared_sign(p.coeffs().iter().map(Field::sign))
}

/// The strict sign all of `signs` share (`Uncertain` when one is uncertain and none decides
/// against, `Zero` when one is zero or two differ).
pub(super) fn shared_sign(signs: impl IntoIterator<Item = Sign>) -> Sign {
    let mut out = None;
    let mut uncertain = false;
    for s in signs {
        match s {
            Sign::Uncertain => uncertain = true,
            Sign::Zero => return Sign::Zero,
            s => match out {
                None => out = Some(s),
                Some(o) if o != s => return Sign::Zero,
                _ => {}
            },
        }
    }
    match (out, uncertain) {
        (_, true) => Sign::Uncertain,
        (Some(s), false) => s,
        (None, false) => Sign::Zero,
    }
}

/// Per polynomial, a certified upper bound of its absolute value on the box (the largest
/// coefficient magnitude: convex-hull property).
pub(super) fn max_abs<T: Coefficient>(polys: &[Bernstein<T>]) -> Vec<f64> {
    polys
        .iter()
        .map(|p| {
            p.coeffs()
                .iter()
                .map(Coefficient::abs_upper_f64)
                .fold(0.0, f64::max)
        })
        .collect()
}

/// Outcome of one decision: proved, refuted, or left open by rounding.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Decision {
    Yes,
    No,
    Uncertain,
}

/// Culling: some equation is of one strict sign on the box (convex hull).
pub(super) fn root_free<T: Field>(polys: &[Bernstein<T>]) -> Decision {
    let mut uncertain = false;
    for p in polys {
        match strict_sign(p) {
            Sign::Positive | Sign::Negative => return Decision::Yes,
            Sign::Uncertain => uncertain = true,
            Sign::Zero => {}
        }
    }
    if uncertain {
        Decision::Uncertain
    } else {
        Decision::No
    }
}

/// `g = A f`: each `g_i = Σ_j A_ij f_j` (all equations share their degrees), coefficient by
/// coefficient over the row's non-zero entries ([`Field::combine`]).
pub(super) fn precondition<T: Field>(
    a: &[Vec<Rational>],
    f: &[Bernstein<T>],
) -> Result<Vec<Bernstein<T>>, SolveError> {
    precondition_until(a, f, |_| false).map(|g| g.unwrap_or_default())
}

/// [`precondition`] row by row, stopping with `None` at the first row `g_i` for which
/// `stop(g_i)` holds (the rows after it are not formed).
fn precondition_until<T: Field>(
    a: &[Vec<Rational>],
    f: &[Bernstein<T>],
    stop: impl Fn(&Bernstein<T>) -> bool,
) -> Result<Option<Vec<Bernstein<T>>>, SolveError> {
    let degrees = f[0].degrees().to_vec();
    if let Some(p) = f.iter().find(|p| p.degrees() != degrees.as_slice()) {
        return Err(SolveError::Field {
            field: "equations".into(),
            why: format!(
                "preconditioning needs equal degrees, found {degrees:?} and {:?}",
                p.degrees()
            ),
        });
    }
    let mut g = Vec::with_capacity(f.len());
    for row in a {
        let (weights, polys): (Vec<T>, Vec<&[T]>) = row
            .iter()
            .zip(f)
            .filter(|(aij, _)| !aij.is_zero())
            .map(|(aij, fj)| (T::from_rational(aij), fj.coeffs()))
            .unzip();
        let coeffs = if polys.is_empty() {
            vec![T::zero(); f[0].coeffs().len()]
        } else {
            T::combine(&weights, &polys)
        };
        let gi = Bernstein::new(degrees.clone(), coeffs)?;
        if stop(&gi) {
            return Ok(None);
        }
        g.push(gi);
    }
    Ok(Some(g))
}

/// An approximate inverse of the Jacobian at the box centre, in `f64` rounded to 24 bits, as
/// exact rationals (the identity where the Jacobian is singular or not finite, and in one
/// unknown, where every non-zero scale leaves Miranda's signs and the derivative's sign as
/// they are).
fn preconditioner<T: Field>(polys: &[Bernstein<T>]) -> Result<Vec<Vec<Rational>>, SolveError> {
    // Only an approximation is needed: the coefficients rounded to f64.
    let n = polys.len();
    if n == 1 {
        return Ok(vec![vec![<Rational as One>::one()]]);
    }
    let j = polys
        .iter()
        .map(|p| gradient_at_centre(p.coeffs().iter().map(Field::approx).collect(), p.degrees()))
        .collect();
    Ok(rounded_inverse(j))
}

/// The gradient at the centre of the unit box of the Bernstein polynomial `(degrees,
/// coeffs)`, in `f64`: de Casteljau at ½ from the outermost axis in, each axis's derivative
/// read off its last level (`d·(b₁ − b₀)`) and carried through the remaining axes' steps.
fn gradient_at_centre(coeffs: Vec<f64>, degrees: &[usize]) -> Vec<f64> {
    let mid = |a: f64, b: f64| 0.5 * (a + b);
    let mut value = coeffs;
    // (axis, that derivative restricted to the axes still to reduce)
    let mut partials: Vec<(usize, Vec<f64>)> = Vec::with_capacity(degrees.len());
    for axis in (0..degrees.len()).rev() {
        let len = degrees[axis] + 1;
        let inner = value.len() / len;
        for (_, d) in &mut partials {
            let mut out = Vec::with_capacity(inner);
            crate::num::field::eval_slabs(d, len, inner, mid, &mut out);
            *d = out;
        }
        let derivative = if len == 1 {
            vec![0.0; inner]
        } else {
            // Down to the last two slabs b₀, b₁.
            for r in 1..len - 1 {
                crate::num::field::reduce_level(&mut value, len - r, inner, &mid);
            }
            let (b0, b1) = value[..2 * inner].split_at(inner);
            let d = degrees[axis] as f64;
            let derivative = b0.iter().zip(b1).map(|(x, y)| d * (y - x)).collect();
            let next = b0.iter().zip(b1).map(|(x, y)| mid(*x, *y)).collect();
            value = next;
            derivative
        };
        partials.push((axis, derivative));
    }
    let mut gradient = vec![0.0; degrees.len()];
    for (axis, d) in partials {
        gradient[axis] = d[0];
    }
    gradient
}

/// The inverse of the `f64` matrix `j` (the identity where it is singular or not finite),
/// each entry rounded to 24 significant bits and taken exactly.
pub(super) fn rounded_inverse(j: Vec<Vec<f64>>) -> Vec<Vec<Rational>> {
    let n = j.len();
    let inverse = invert(j).unwrap_or_else(|| {
        (0..n)
            .map(|i| (0..n).map(|k| f64::from(u8::from(i == k))).collect())
            .collect()
    });
    inverse
        .iter()
        .map(|row| {
            row.iter()
                // Rounded to 24 significant bits: any matrix is allowed, and short entries keep
                // the exact path's coefficients of `A f` short.
                .map(|&x| {
                    rational_from_f64(f64::from(x as f32), "preconditioner").unwrap_or_default()
                })
                .collect()
        })
        .collect()
}

/// Gauss–Jordan inversion with partial pivoting in `f64`; `None` when singular or not finite.
pub(super) fn invert(mut m: Vec<Vec<f64>>) -> Option<Vec<Vec<f64>>> {
    let n = m.len();
    let mut inv: Vec<Vec<f64>> = (0..n)
        .map(|i| (0..n).map(|k| f64::from(u8::from(i == k))).collect())
        .collect();
    for c in 0..n {
        let p = (c..n).max_by(|&a, &b| m[a][c].abs().total_cmp(&m[b][c].abs()))?;
        if m[p][c] == 0.0 || !m[p][c].is_finite() {
            return None;
        }
        m.swap(c, p);
        inv.swap(c, p);
        let d = m[c][c];
        for k in 0..n {
            m[c][k] /= d;
            inv[c][k] /= d;
        }
        for r in 0..n {
            if r != c {
                let f = m[r][c];
                for k in 0..n {
                    m[r][k] -= f * m[c][k];
                    inv[r][k] -= f * inv[c][k];
                }
            }
        }
    }
    inv.iter().flatten().all(|x| x.is_finite()).then_some(inv)
}

/// Miranda's test on `g`: per `i`, `g_i` of one strict sign on the face `t_i = 0` and of the
/// other on `t_i = 1`. Returns the lower faces' signs.
fn miranda<T: Field>(g: &[Bernstein<T>]) -> Result<(Decision, Vec<i8>), SolveError> {
    let mut signs = Vec::with_capacity(g.len());
    let mut uncertain = false;
    for (i, gi) in g.iter().enumerate() {
        let lower = strict_sign(&gi.face(i, false)?);
        let upper = strict_sign(&gi.face(i, true)?);
        match (lower, upper) {
            (Sign::Negative, Sign::Positive) => signs.push(-1),
            (Sign::Positive, Sign::Negative) => signs.push(1),
            (Sign::Uncertain, _) | (_, Sign::Uncertain) => {
                uncertain = true;
                signs.push(0);
            }
            _ => return Ok((Decision::No, signs)),
        }
    }
    Ok((
        if uncertain {
            Decision::Uncertain
        } else {
            Decision::Yes
        },
        signs,
    ))
}

/// Uniqueness: the interval Jacobian of `g` (entries enclosed by the coefficients of the
/// partial derivatives) is strictly diagonally dominant by rows.
fn diagonally_dominant<T: Coefficient>(g: &[Bernstein<T>]) -> Result<Decision, SolveError> {
    let n = g.len();
    let mut uncertain = false;
    for (i, gi) in g.iter().enumerate() {
        let mut diag: Option<T> = None;
        let mut off = T::zero();
        for k in 0..n {
            let d = if gi.degrees()[k] == 0 {
                Bernstein::constant(vec![0; n], T::zero())
            } else {
                gi.derivative(k)?
            };
            if k == i {
                let s = strict_sign(&d);
                match s {
                    Sign::Positive | Sign::Negative => {}
                    Sign::Uncertain => return Ok(Decision::Uncertain),
                    _ => return Ok(Decision::No),
                }
                let mut lower: Option<T> = None;
                for c in d.coeffs() {
                    let a = c.abs_lower();
                    lower = Some(match lower {
                        None => a,
                        Some(l) => l.min_lower(&a),
                    });
                }
                diag = lower;
            } else {
                let mut upper = T::zero();
                for c in d.coeffs() {
                    upper = upper.max_upper(&c.abs_upper());
                }
                off = off.add(&upper);
            }
        }
        let Some(diag) = diag else {
            return Ok(Decision::No);
        };
        match diag.sub(&off).sign() {
            Sign::Positive => {}
            Sign::Uncertain => uncertain = true,
            _ => return Ok(Decision::No),
        }
    }
    Ok(if uncertain {
        Decision::Uncertain
    } else {
        Decision::Yes
    })
}

/// The margin by which every projected range is widened: far above the few units of
/// rounding in [`hull_crossing`].
const PROJECTION_MARGIN: f64 = 1e-9;

/// Where on `[0, 1]` the convex hull of `points` `(x, y)` meets `y = 0`, or `None` when all
/// lie strictly on one side. Every crossing of the hull with the axis lies on a segment
/// between a point with `y ≥ 0` and one with `y ≤ 0`, so the extremes over those segments
/// are the hull's. `Some((0, 1))` when a value is not finite or a segment's rise overflows.
fn hull_crossing(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    if points.iter().any(|p| !p.1.is_finite()) {
        return Some((0.0, 1.0));
    }
    for p in points {
        if p.1 == 0.0 {
            lo = lo.min(p.0);
            hi = hi.max(p.0);
        }
    }
    for p in points.iter().filter(|p| p.1 > 0.0) {
        for q in points.iter().filter(|q| q.1 < 0.0) {
            let rise = p.1 - q.1;
            if !rise.is_finite() {
                return Some((0.0, 1.0));
            }
            let x = p.0 + (q.0 - p.0) * (p.1 / rise);
            lo = lo.min(x);
            hi = hi.max(x);
        }
    }
    (lo <= hi).then_some((lo, hi))
}

/// Projection of a box's equations on each unknown (the projection lemma of Mourrain &
/// Pavone, *Subdivision methods for solving polynomial equations*, J. Symbolic Comput. 44
/// (2009), with convex hulls as in the projected polyhedron of Sherbrooke & Patrikalakis):
/// per unknown `k` and equation `g_i`, the least and greatest coefficient of each index
/// along `k` bound `g_i` on every line along `k` by two 1-D control polygons, and every
/// root's `t_k` lies where their convex hull meets zero. True when, on some unknown, the
/// intersection over the equations of those ranges (each widened by [`PROJECTION_MARGIN`],
/// inside `[0, 1]`) is empty: the box is root-free. (Only emptiness is used: cutting the box
/// down to the ranges was measured and left out; see the module docs.)
fn projection_excludes_roots<T: Coefficient>(g: &[Bernstein<T>]) -> bool {
    let n = g.first().map_or(0, Bernstein::dim);
    let mut out = vec![(0.0f64, 1.0f64); n];
    let mut points = Vec::new();
    let (mut lower, mut upper) = (Vec::new(), Vec::new());
    let (mut least, mut greatest) = (Vec::new(), Vec::new());
    for gi in g {
        lower.clear();
        upper.clear();
        for c in gi.coeffs() {
            let (lo, hi) = c.bounds_f64();
            lower.push(lo);
            upper.push(hi);
        }
        // A bound that is not a number bounds nothing: this equation excludes nothing.
        if lower.iter().chain(&upper).any(|x| x.is_nan()) {
            continue;
        }
        let degrees = gi.degrees();
        // Coefficients with index `j` along axis `k` form slab `j` (of `stride` consecutive
        // values) of every block of `(d_k + 1)·stride`.
        let mut stride = 1;
        for k in 0..n {
            let (d, len) = (degrees[k], degrees[k] + 1);
            if d == 0 {
                stride *= len;
                continue;
            }
            least.clear();
            least.resize(len, f64::INFINITY);
            greatest.clear();
            greatest.resize(len, f64::NEG_INFINITY);
            let blocks = lower
                .chunks_exact(len * stride)
                .zip(upper.chunks_exact(len * stride));
            for (lo_block, hi_block) in blocks {
                for j in 0..len {
                    let slab = j * stride..(j + 1) * stride;
                    least[j] = least_of(&lo_block[slab.clone()], least[j], |x| x);
                    greatest[j] = -least_of(&hi_block[slab], -greatest[j], |x| -x);
                }
            }
            stride *= len;
            points.clear();
            for j in 0..=d {
                let x = j as f64 / d as f64;
                points.push((x, least[j]));
                points.push((x, greatest[j]));
            }
            let Some((lo, hi)) = hull_crossing(&points) else {
                return true;
            };
            let (lo, hi) = (
                (lo - PROJECTION_MARGIN).max(0.0),
                (hi + PROJECTION_MARGIN).min(1.0),
            );
            out[k] = (out[k].0.max(lo), out[k].1.min(hi));
            if out[k].0 > out[k].1 {
                return true;
            }
        }
    }
    false
}

/// `min(init, min map(xs))` of numbers (no NaN), with four running minima (they vectorise).
fn least_of(xs: &[f64], init: f64, map: impl Fn(f64) -> f64) -> f64 {
    let mut acc = [init; 4];
    let quads = xs.chunks_exact(4);
    let rest = quads.remainder();
    for quad in quads {
        for (a, &x) in acc.iter_mut().zip(quad) {
            let y = map(x);
            if y < *a {
                *a = y;
            }
        }
    }
    for &x in rest {
        let y = map(x);
        if y < acc[0] {
            acc[0] = y;
        }
    }
    acc.into_iter().fold(f64::INFINITY, f64::min)
}

/// Existence and uniqueness on a box: the certificate, `No`, or `Uncertain`.
fn certify<T: Coefficient>(
    polys: &[Bernstein<T>],
) -> Result<(Decision, Option<RootCertificate>), SolveError> {
    certify_or_cull(polys).map(|c| (c.decision, c.certificate))
}

/// What [`certify_or_cull`] decided on a box.
struct Certified<T> {
    /// Existence and uniqueness.
    decision: Decision,
    /// The certificate when both hold.
    certificate: Option<RootCertificate>,
    /// The preconditioned system culls the box.
    culled: bool,
    /// When neither culled nor certified (several unknowns): the preconditioner `A` and the
    /// preconditioned system `g = A f`.
    preconditioned: Option<(Preconditioner, Vec<Bernstein<T>>)>,
}

/// A preconditioning matrix `A`, row by row, exact.
type Preconditioner = Vec<Vec<Rational>>;

/// [`certify`], and whether the preconditioned system culls the box: a `g_i = Σ_j A_ij f_j`
/// of one strict sign on it (any matrix `A` keeps every root of `f` a root of `g`). Where the
/// equations' zero sets cross obliquely this culls far more than the equations themselves:
/// each `f_i` alone changes sign on boxes near the others' zero sets, `g ≈ J⁻¹ f` does not.
fn certify_or_cull<T: Coefficient>(polys: &[Bernstein<T>]) -> Result<Certified<T>, SolveError> {
    let a = preconditioner(polys)?;
    // One unknown: the preconditioner is the identity, `g = f`.
    if polys.len() == 1 {
        let (decision, certificate) = certify_with(polys, a)?;
        return Ok(Certified {
            decision,
            certificate,
            culled: false,
            preconditioned: None,
        });
    }
    let strict = |gi: &Bernstein<T>| matches!(strict_sign(gi), Sign::Positive | Sign::Negative);
    let Some(g) = precondition_until(&a, polys, strict)? else {
        return Ok(Certified {
            decision: Decision::No,
            certificate: None,
            culled: true,
            preconditioned: None,
        });
    };
    let (decision, certificate) = certify_with(&g, a.clone())?;
    let preconditioned = certificate.is_none().then_some((a, g));
    Ok(Certified {
        decision,
        certificate,
        culled: false,
        preconditioned,
    })
}

/// Miranda and diagonal dominance on `g = A f`.
fn certify_with<T: Coefficient>(
    g: &[Bernstein<T>],
    a: Vec<Vec<Rational>>,
) -> Result<(Decision, Option<RootCertificate>), SolveError> {
    let (exists, signs) = miranda(g)?;
    if exists == Decision::No {
        return Ok((Decision::No, None));
    }
    let unique = diagonally_dominant(g)?;
    Ok(match (exists, unique) {
        (Decision::Yes, Decision::Yes) => (
            Decision::Yes,
            Some(RootCertificate {
                preconditioner: a,
                lower_face_signs: signs,
                point: None,
            }),
        ),
        (_, Decision::No) => (Decision::No, None),
        _ => (Decision::Uncertain, None),
    })
}

/// `p` (on the unit box) restricted to the sub-box `[lo, hi]` of it, in integers: per axis a
/// de Casteljau split at `lo_k`, then at `(hi_k − lo_k)/(1 − lo_k)`.
fn restrict_scaled(
    p: &ScaledBernstein,
    lo: &[Rational],
    hi: &[Rational],
) -> Result<ScaledBernstein, SolveError> {
    let mut p = p.clone();
    for (k, (a, b)) in lo.iter().zip(hi).enumerate() {
        if !a.is_zero() {
            p = p.split(k, a.numer(), a.denom())?.1;
        }
        let t = (b - a) / (<Rational as One>::one() - a);
        if !t.is_one() {
            p = p.split(k, t.numer(), t.denom())?.0;
        }
        p.normalise_twos();
    }
    Ok(p)
}

/// The certificate of [`certify`] on the box `[lo, hi]` (unit coordinates) decided in exact
/// integers with the preconditioner `a` ([`certify_restricted`]).
fn certify_scaled(
    exact: &[ScaledBernstein],
    lo: &[Rational],
    hi: &[Rational],
    a: Vec<Vec<Rational>>,
) -> Result<Option<RootCertificate>, SolveError> {
    let f: Vec<ScaledBernstein> = exact
        .iter()
        .map(|p| restrict_scaled(p, lo, hi))
        .collect::<Result<_, _>>()?;
    Ok(match certify_restricted(&f, a)? {
        ScaledDecision::Certified(c) => Some(c),
        ScaledDecision::Culled | ScaledDecision::Open => None,
    })
}

/// What [`certify_restricted`] decided.
enum ScaledDecision {
    /// Some `g_i = Σ_j A_ij f_j` is of one strict sign: no root.
    Culled,
    /// Exactly one root.
    Certified(RootCertificate),
    /// Neither.
    Open,
}

/// The strict sign all of `nums` share (`1` or `-1`), if they do.
fn strict(nums: &mut dyn Iterator<Item = &num_bigint::BigInt>) -> Option<i8> {
    let mut sign = None;
    for x in nums {
        let s = match x.sign() {
            num_bigint::Sign::Plus => 1,
            num_bigint::Sign::Minus => -1,
            num_bigint::Sign::NoSign => return None,
        };
        if sign.is_some_and(|o| o != s) {
            return None;
        }
        sign = Some(s);
    }
    sign
}

/// The numerators of `p`'s coefficients on its face `axis = 0` (or `1` when `upper`); the
/// first axis runs fastest.
fn face_numerators(
    p: &ScaledBernstein,
    axis: usize,
    upper: bool,
) -> impl Iterator<Item = &num_bigint::BigInt> {
    let degrees = p.degrees();
    let stride: usize = degrees[..axis].iter().map(|d| d + 1).product();
    let len = degrees[axis] + 1;
    let at = if upper { len - 1 } else { 0 };
    p.numerators()
        .iter()
        .enumerate()
        .filter(move |(c, _)| (c / stride) % len == at)
        .map(|(_, x)| x)
}

/// [`certify_or_cull`] on the equations `f` already restricted to a box, in exact integers
/// with the preconditioner `a`: the equations brought to one denominator `D`, `A` scaled to
/// integers by `2^E`; every sign and every comparison of the culling, of Miranda's test and
/// of diagonal dominance is then one of integers (`D·2^E > 0`). No gcd is taken.
fn certify_restricted(
    f: &[ScaledBernstein],
    a: Vec<Vec<Rational>>,
) -> Result<ScaledDecision, SolveError> {
    use num_bigint::BigInt;
    let n = f.len();
    // One denominator for all: numerators of f_j times Π_{k≠j} D_k.
    let scale: Vec<BigInt> = (0..n)
        .map(|j| {
            (0..n)
                .filter(|&k| k != j)
                .fold(BigInt::one(), |acc, k| acc * f[k].denominator())
        })
        .collect();
    // A times the lcm of its denominators (powers of two: the entries are dyadic).
    let lcm = a.iter().flatten().fold(BigInt::one(), |l, x| {
        num_integer::Integer::lcm(&l, x.denom())
    });
    let m: Vec<Vec<BigInt>> = a
        .iter()
        .map(|row| row.iter().map(|x| x.numer() * (&lcm / x.denom())).collect())
        .collect();
    let degrees = f[0].degrees().to_vec();
    let size = f[0].numerators().len();
    let g: Vec<ScaledBernstein> = m
        .iter()
        .map(|row| {
            let num = (0..size)
                .map(|c| {
                    row.iter()
                        .enumerate()
                        .filter(|(_, mij)| !mij.is_zero())
                        .fold(BigInt::zero(), |acc, (j, mij)| {
                            acc + mij * &scale[j] * &f[j].numerators()[c]
                        })
                })
                .collect();
            ScaledBernstein::from_integers(degrees.clone(), num)
        })
        .collect::<Result<_, _>>()?;
    if g.iter()
        .any(|gi| strict(&mut gi.numerators().iter()).is_some())
    {
        return Ok(ScaledDecision::Culled);
    }
    let mut signs = Vec::with_capacity(n);
    for (i, gi) in g.iter().enumerate() {
        match (
            strict(&mut face_numerators(gi, i, false)),
            strict(&mut face_numerators(gi, i, true)),
        ) {
            (Some(l), Some(u)) if l == -u => signs.push(l),
            _ => return Ok(ScaledDecision::Open),
        }
    }
    for (i, gi) in g.iter().enumerate() {
        let mut off = BigInt::zero();
        let mut diag = None;
        for (k, &d) in degrees.iter().enumerate() {
            if d == 0 {
                if k == i {
                    return Ok(ScaledDecision::Open);
                }
                continue;
            }
            let dk = gi.derivative(k)?;
            if k == i {
                if strict(&mut dk.numerators().iter()).is_none() {
                    return Ok(ScaledDecision::Open);
                }
                diag = dk.numerators().iter().map(|x| x.abs()).min();
            } else {
                off += dk
                    .numerators()
                    .iter()
                    .map(|x| x.abs())
                    .max()
                    .unwrap_or_default();
            }
        }
        if diag.is_none_or(|m| m <= off) {
            return Ok(ScaledDecision::Open);
        }
    }
    Ok(ScaledDecision::Certified(RootCertificate {
        preconditioner: a,
        lower_face_signs: signs,
        point: None,
    }))
}

/// An `f64` near `num / den` (`den > 0`): both cut to about 64 significant bits of `den`.
fn approx_ratio(num: &num_bigint::BigInt, den: &num_bigint::BigInt) -> f64 {
    use num_traits::ToPrimitive;
    let shift = den.bits().saturating_sub(64);
    let (n, d) = (num >> shift, den >> shift);
    n.to_f64().unwrap_or(f64::NAN) / d.to_f64().unwrap_or(f64::NAN)
}

/// What the exact check of one box at the depth limit decided ([`decide_leaf`]).
enum Leaf {
    /// No root.
    Culled,
    /// One root, certified on the box (the rational path certifies it again and refines it).
    Certified,
    /// Neither: a cluster, with whether the box touches a face of the domain on which the
    /// system may vanish, and per equation a certified bound on `|f_i|`.
    Open {
        on_boundary: bool,
        max_abs_f: Vec<f64>,
    },
}

/// The filtered path's exact redo of one of the interval path's undecided boxes at the depth
/// limit, in integers over one denominator per equation (no gcd, no normalised rational):
/// the culling, the preconditioned culling, Miranda's test, diagonal dominance and the
/// domain-boundary test of [`subdivide`] at that depth, decided exactly.
fn decide_leaf(ctx: &Context<'_>, lo: &[Rational], hi: &[Rational]) -> Result<Leaf, SolveError> {
    let f: Vec<ScaledBernstein> = ctx
        .scaled()?
        .iter()
        .map(|p| restrict_scaled(p, lo, hi))
        .collect::<Result<_, _>>()?;
    if f.iter()
        .any(|p| strict(&mut p.numerators().iter()).is_some())
    {
        return Ok(Leaf::Culled);
    }
    let n = f.len();
    let a = if n == 1 {
        vec![vec![<Rational as One>::one()]]
    } else {
        let j = f
            .iter()
            .map(|p| {
                let approx = p
                    .numerators()
                    .iter()
                    .map(|x| approx_ratio(x, p.denominator()))
                    .collect();
                gradient_at_centre(approx, p.degrees())
            })
            .collect();
        rounded_inverse(j)
    };
    match certify_restricted(&f, a)? {
        ScaledDecision::Culled => return Ok(Leaf::Culled),
        ScaledDecision::Certified(_) => return Ok(Leaf::Certified),
        ScaledDecision::Open => {}
    }
    let face_free = |axis: usize, upper: bool| {
        f.iter()
            .any(|p| strict(&mut face_numerators(p, axis, upper)).is_some())
    };
    let on_boundary = (0..n).any(|axis| {
        (lo[axis].is_zero() && !face_free(axis, false))
            || (hi[axis].is_one() && !face_free(axis, true))
    });
    let max_abs_f = f
        .iter()
        .map(|p| {
            let top = p
                .numerators()
                .iter()
                .map(|x| x.magnitude())
                .max()
                .cloned()
                .unwrap_or_default();
            let bound = Rational::new_raw(top.into(), p.denominator().clone());
            Interval::from_rational(&bound).hi
        })
        .collect();
    Ok(Leaf::Open {
        on_boundary,
        max_abs_f,
    })
}

/// Shrinks a certified box around its root: Newton's method in `f64` from the box centre,
/// then the certificate on boxes of half-width `ρ` around the result, from `ρ` giving the
/// requested relative width upwards by factors of 16. Every box tried lies inside the
/// certified one, which holds exactly one root, so a certified small box holds that root.
/// With `exact` (the filtered path's equations on the whole domain, as integers over a
/// shared denominator), the smallest box that rounding cannot certify is tried once more in
/// exact integer arithmetic ([`certify_scaled`]), so the filtered path reaches the requested
/// width where interval rounding stops short of it.
#[allow(clippy::type_complexity)]
fn refine<T: Coefficient>(
    node: &Node<T>,
    certificate: RootCertificate,
    tolerance: f64,
    finish: Option<&Context<'_>>,
) -> Result<(Vec<Rational>, Vec<Rational>, RootCertificate), SolveError> {
    let keep = || (node.lo.clone(), node.hi.clone(), certificate.clone());
    let n = node.lo.len();
    let width = (0..n)
        .map(|k| rational_to_f64(&(&node.hi[k] - &node.lo[k])))
        .fold(0.0, f64::max);
    if tolerance.is_nan() || tolerance <= 0.0 || width <= tolerance {
        return Ok(keep());
    }
    let f: Vec<Bernstein<f64>> = node.polys.iter().map(|p| p.map(|c| c.approx())).collect();
    let mut jac = Vec::with_capacity(n);
    for p in &f {
        let mut row = Vec::with_capacity(n);
        for k in 0..n {
            row.push(if p.degrees()[k] == 0 {
                None
            } else {
                Some(p.derivative(k)?)
            });
        }
        jac.push(row);
    }
    let mut t = vec![0.5f64; n];
    for _ in 0..40 {
        let fx: Vec<f64> = f.iter().map(|p| p.eval(&t)).collect::<Result<_, _>>()?;
        let Some(step) = newton_step(&jac, &t, &fx)? else {
            break;
        };
        let mut moved = 0.0f64;
        for (x, s) in t.iter_mut().zip(&step) {
            let next = (*x - s).clamp(0.0, 1.0);
            moved = moved.max((next - *x).abs());
            *x = next;
        }
        if !moved.is_finite() || moved <= 1e-17 {
            break;
        }
    }
    if t.iter().any(|x| !x.is_finite()) {
        return Ok(keep());
    }
    let rho0 = (0.5 * tolerance / width).max(4.0 * f64::EPSILON);
    let mut rho = rho0;
    let mut first = true;
    let mut polished = false;
    // Interval path: the small box's ends are `f64` numbers in the domain's unit coordinates
    // (inside the certified box), so that the exact finish restricts the equations to short
    // dyadic ends, however long the certified box's own ends have grown; the equations on it
    // are enclosed from the node's by restricting with enclosures of the relative ends. The
    // exact path keeps dyadic ends relative to the node (exact relative ends).
    let widths: Vec<f64> = (0..n)
        .map(|k| rational_to_f64(&(&node.hi[k] - &node.lo[k])))
        .collect();
    let lows: Vec<f64> = node.lo.iter().map(rational_to_f64).collect();
    while rho < 0.25 {
        let mut lo = Vec::with_capacity(n);
        let mut hi = Vec::with_capacity(n);
        let mut tsub: Vec<(T, T)> = Vec::with_capacity(n);
        for (k, &x) in t.iter().enumerate() {
            let w = &node.hi[k] - &node.lo[k];
            let (a, b) = if T::EXACT {
                let (a, b) = ((x - rho).max(0.0), (x + rho).min(1.0));
                let (Ok(a), Ok(b)) = (rational_from_f64(a, "box"), rational_from_f64(b, "box"))
                else {
                    return Ok(keep());
                };
                (&node.lo[k] + &w * a, &node.lo[k] + &w * b)
            } else {
                let (centre, half) = (lows[k] + widths[k] * x, widths[k] * rho);
                let (Ok(a), Ok(b)) = (
                    rational_from_f64(centre - half, "box"),
                    rational_from_f64(centre + half, "box"),
                ) else {
                    return Ok(keep());
                };
                (a.max(node.lo[k].clone()), b.min(node.hi[k].clone()))
            };
            if a >= b {
                break;
            }
            let (ra, rb) = ((&a - &node.lo[k]) / &w, (&b - &node.lo[k]) / &w);
            tsub.push((T::from_rational(&ra), T::from_rational(&rb)));
            lo.push(a);
            hi.push(b);
        }
        // (Interval ends too close for rounding to order them refuse the restriction: that
        // box is skipped, as a collapsed one is.)
        let small: Option<Vec<Bernstein<T>>> = (tsub.len() == n)
            .then(|| node.polys.iter().map(|p| p.restrict(&tsub).ok()).collect())
            .flatten();
        if let Some(small) = small {
            if let (Decision::Yes, Some(c)) = certify(&small)? {
                return Ok((lo, hi, c));
            }
            if let Some(ctx) = finish.filter(|_| !T::EXACT && first) {
                let a = preconditioner(&small)?;
                if let Some(c) = certify_scaled(ctx.scaled()?, &lo, &hi, a)? {
                    return Ok((lo, hi, c));
                }
            }
        }
        // Boxes up to `POLISH_AFTER` times the smallest missed: where the equations are flat,
        // `f64` rounding in their values leaves Newton's point that far off. Newton's method
        // on exact values then puts it within rounding of the root, and the boxes are tried
        // again from the smallest, exactly.
        if let Some(ctx) = finish.filter(|_| !T::EXACT && !polished && rho >= POLISH_AFTER * rho0) {
            polished = true;
            if let Some(better) = polish(ctx, node, &jac, &t)? {
                t = better;
                rho = rho0;
                first = true;
                continue;
            }
        }
        first = false;
        rho *= 16.0;
    }
    Ok(keep())
}

/// Newton's method at most [`POLISH_STEPS`] times from `t` (unit coordinates of `node`'s
/// box) with the equations' values computed exactly at each point (rounded to `f64` only
/// afterwards) and the Jacobian `jac` in `f64`: `None` when it does not settle inside the box.
fn polish<T: Coefficient>(
    ctx: &Context<'_>,
    node: &Node<T>,
    jac: &[Vec<Option<Bernstein<f64>>>],
    t: &[f64],
) -> Result<Option<Vec<f64>>, SolveError> {
    // The equations as given (their own degrees: the cheapest exact values).
    let exact = &ctx.system.equations;
    let n = t.len();
    let mut t = t.to_vec();
    for _ in 0..POLISH_STEPS {
        let mut u = Vec::with_capacity(n);
        for (k, &x) in t.iter().enumerate() {
            let Ok(x) = rational_from_f64(x, "point") else {
                return Ok(None);
            };
            u.push(crate::num::rational::lerp(&node.lo[k], &node.hi[k], &x));
        }
        let values: Vec<f64> = exact
            .iter()
            .map(|p| p.eval(&u).map(|v| rational_to_f64(&v)))
            .collect::<Result<_, _>>()?;
        let Some(step) = newton_step(jac, &t, &values)? else {
            return Ok(None);
        };
        let mut moved = 0.0f64;
        for (x, step) in t.iter_mut().zip(&step) {
            let next = *x - step;
            if !(0.0..=1.0).contains(&next) {
                return Ok(None);
            }
            moved = moved.max((next - *x).abs());
            *x = next;
        }
        if moved <= f64::EPSILON {
            break;
        }
    }
    Ok(Some(t))
}

/// Newton's step `J(t)⁻¹ f` at `t` from the Jacobian's entries `jac` (`None` entries are
/// zero) and the values `f`, in `f64`; `None` when `J(t)` is singular or not finite.
fn newton_step(
    jac: &[Vec<Option<Bernstein<f64>>>],
    t: &[f64],
    f: &[f64],
) -> Result<Option<Vec<f64>>, SolveError> {
    let n = t.len();
    let mut m = vec![vec![0.0; n]; n];
    for (i, row) in jac.iter().enumerate() {
        for (k, d) in row.iter().enumerate() {
            if let Some(d) = d {
                m[i][k] = d.eval(t)?;
            }
        }
    }
    Ok(invert(m).map(|inv| {
        inv.iter()
            .map(|row| row.iter().zip(f).map(|(a, b)| a * b).sum())
            .collect()
    }))
}

/// The most exact Newton steps [`polish`] takes.
const POLISH_STEPS: usize = 6;

/// How much wider than the smallest refined box the interval path may go before Newton's
/// point is polished on exact values ([`polish`]): a root that `f64` locates to within a few
/// hundred units of rounding keeps the box it certifies there.
const POLISH_AFTER: f64 = 256.0;

/// The axis of the box's widest side (the lowest such axis on ties).
pub(super) fn widest_axis(lo: &[Rational], hi: &[Rational]) -> usize {
    (0..lo.len())
        .max_by(|&a, &b| (&hi[a] - &lo[a]).cmp(&(&hi[b] - &lo[b])).then(b.cmp(&a)))
        .unwrap_or(0)
}

/// The depth from which splits are always at ½.
pub(super) const MOVED_SPLITS_DEPTH: u32 = 24;

/// Split parameters tried in order: ½ first, then points off it, so that the plane can be
/// proved root-free.
pub(super) const SPLITS: [(i64, i64); 5] = [(1, 2), (7, 16), (9, 16), (3, 8), (5, 8)];

/// Splits every polynomial along `axis` at the first of [`SPLITS`] whose plane some equation
/// is of one strict sign on, else at ½; returns the parameter and the two halves. Below depth
/// [`MOVED_SPLITS_DEPTH`] only ½ is used: a root on such a plane (a dyadic coordinate with a
/// long expansion) leaves two touching clusters rather than a certified root, and the exact
/// path's coefficients stay short. ½'s plane is read off its split; the other planes are
/// tested on [`Bernstein::section_enclosure`] (Horner's rule in intervals, `d + 1` steps per
/// value) and split at only when root-free.
#[allow(clippy::type_complexity)]
fn split_polys<T: Field>(
    polys: &[Bernstein<T>],
    axis: usize,
    depth: u32,
    a: Option<&[Vec<Rational>]>,
) -> Result<(Rational, Vec<Bernstein<T>>, Vec<Bernstein<T>>), SolveError> {
    let tried = if depth < MOVED_SPLITS_DEPTH {
        SPLITS.len()
    } else {
        1
    };
    let plane_free = |faces: &[Bernstein<T>]| -> Result<bool, SolveError> {
        Ok(root_free(faces) == Decision::Yes
            || match a {
                Some(a) => root_free(&precondition(a, faces)?) == Decision::Yes,
                None => false,
            })
    };
    let split_at = |s: &T| -> Result<(Vec<Bernstein<T>>, Vec<Bernstein<T>>), SolveError> {
        let mut left = Vec::with_capacity(polys.len());
        let mut right = Vec::with_capacity(polys.len());
        for f in polys {
            let (l, r) = f.split(axis, s)?;
            left.push(l);
            right.push(r);
        }
        Ok((left, right))
    };
    // ½ first: its plane's coefficients are read off the split itself (the left halves'
    // upper faces), so the common case costs one split and no evaluation.
    let half = Rational::new(1.into(), 2.into());
    let (left, right) = split_at(&T::from_ratio(1, 2))?;
    let faces = left
        .iter()
        .map(|l| l.face(axis, true))
        .collect::<Result<Vec<_>, _>>()?;
    if tried == 1 || plane_free(&faces)? {
        return Ok((half, left, right));
    }
    // The other planes are tested on a cheap enclosure of their cross-sections and split
    // at only when proved root-free.
    for &(p, q) in &SPLITS[1..tried] {
        let s = T::from_ratio(p, q);
        let faces = polys
            .iter()
            .map(|f| f.section_enclosure(axis, &s))
            .collect::<Result<Vec<_>, _>>()?;
        if plane_free(&faces)? {
            let (l, r) = split_at(&s)?;
            return Ok((Rational::new(p.into(), q.into()), l, r));
        }
    }
    Ok((half, left, right))
}

/// Whether the box touches a face of the domain on which the system may vanish.
fn on_domain_boundary<T: Field>(node: &Node<T>) -> Result<bool, SolveError> {
    for axis in 0..node.lo.len() {
        for (at_face, upper) in [
            (node.lo[axis].is_zero(), false),
            (node.hi[axis].is_one(), true),
        ] {
            if at_face {
                let faces: Result<Vec<_>, _> =
                    node.polys.iter().map(|p| p.face(axis, upper)).collect();
                if root_free(&faces?) != Decision::Yes {
                    return Ok(true);
                }
            }
        }
    }
    Ok(false)
}

/// Everything one pass found.
struct Found<T> {
    roots: Vec<Root>,
    clusters: Vec<(Cluster, Vec<Rational>, Vec<Rational>, u32)>,
    visited: usize,
    /// Boxes left undecided at a deferring pass's depth limit.
    deferred: Vec<Node<T>>,
    /// Whether the pass stopped at its own box budget (what it found is then incomplete).
    exhausted: bool,
}

impl<T> Default for Found<T> {
    fn default() -> Self {
        Found {
            roots: Vec::new(),
            clusters: Vec::new(),
            visited: 0,
            deferred: Vec::new(),
            exhausted: false,
        }
    }
}

impl<T> Found<T> {
    /// The roots, clusters and visits (without the deferred nodes).
    fn erased(self) -> Found<()> {
        Found {
            roots: self.roots,
            clusters: self.clusters,
            visited: self.visited,
            deferred: Vec::new(),
            exhausted: self.exhausted,
        }
    }

    /// Takes in the roots, clusters and visits of a later pass.
    fn absorb<U>(&mut self, other: Found<U>) {
        self.roots.extend(other.roots);
        self.clusters.extend(other.clusters);
        self.visited += other.visited;
    }
}

/// The common degrees of all equations (each axis: the highest), for preconditioning (in
/// any field: exactly in rationals, enclosed in intervals).
pub(super) fn elevated<T: Field>(
    equations: &[Bernstein<T>],
) -> Result<Vec<Bernstein<T>>, SolveError> {
    let n = equations[0].dim();
    let top: Vec<usize> = (0..n)
        .map(|k| equations.iter().map(|e| e.degrees()[k]).max().unwrap_or(0))
        .collect();
    equations
        .iter()
        .map(|e| {
            let mut p = e.clone();
            for (k, &t) in top.iter().enumerate() {
                if p.degrees()[k] < t {
                    p = p.elevate(k, t - p.degrees()[k])?;
                }
            }
            Ok(p)
        })
        .collect()
}

/// What every run of one solve shares: the system, the options and the clock, and, made
/// when first needed, its equations at common degrees in exact rationals and as integers
/// over a shared denominator (the filtered path's last refinement). The interval path
/// elevates its own enclosures, so a filtered solve that every interval decision settles
/// never elevates in rationals.
struct Context<'a> {
    system: &'a System,
    opts: &'a SolveOptions,
    clock: Instant,
    /// Whether certified roots' last refinement may be decided in exact integers.
    exact_finish: bool,
    exact: std::cell::OnceCell<Vec<Bernstein<Rational>>>,
    scaled: std::cell::OnceCell<Vec<ScaledBernstein>>,
}

impl Context<'_> {
    /// The equations at common degrees, exactly.
    fn exact(&self) -> Result<&[Bernstein<Rational>], SolveError> {
        if let Some(e) = self.exact.get() {
            return Ok(e);
        }
        let e = elevated(&self.system.equations)?;
        Ok(self.exact.get_or_init(|| e))
    }

    /// [`Context::exact`] as integers over a shared denominator.
    fn scaled(&self) -> Result<&[ScaledBernstein], SolveError> {
        if let Some(s) = self.scaled.get() {
            return Ok(s);
        }
        let s = self
            .exact()?
            .iter()
            .map(ScaledBernstein::from_rational)
            .collect();
        Ok(self.scaled.get_or_init(|| s))
    }
}

/// The levels (halvings of each side) the first pass of a solve subdivides to before the
/// boxes still undecided are grouped: a regular root is certified well above it.
const COARSE_LEVELS: u32 = 5;

/// The boxes one group of touching undecided boxes may visit below the coarse levels before
/// it is given up as one [`ClusterReason::Singular`] cluster, in one or two unknowns; twice
/// as many with each unknown more ([`group_budget`]). A root on a split plane or a domain
/// face needs a few boxes per level (at most `2ⁿ`); around a multiple or tangential root the
/// undecided boxes multiply at every level (about `2^(k/2)` at level `k` for a double root)
/// and would otherwise take every box of the solve.
const GROUP_BOXES: usize = 2048;

/// The boxes a group may visit in `n` unknowns ([`GROUP_BOXES`] doubled for each unknown
/// past two): a point touches up to `2ⁿ` boxes of a level. With 2,048 in five unknowns,
/// Katsura-4 on `[−1, 1]⁵` left four simple roots about 0.06 apart and the root
/// `(1, 0, 0, 0, 0)` in two singular clusters; with 16,384 all twelve of msolve's real roots
/// are certified.
fn group_budget(n: u32) -> usize {
    GROUP_BOXES << n.saturating_sub(2).min(16)
}

/// The boxes the exact redo of a group ([`staged`]'s `filtered`) may visit.
const GROUP_EXACT_BOXES: usize = 256;

/// The boxes a group's budget grows by with each root it certifies (a group of several
/// regular roots close together is resolved, however many).
const GROUP_BOXES_PER_ROOT: usize = 512;

/// A group of the fast path's uncertain leaves larger than this is not redone exactly, box
/// by box, but reported as one [`ClusterReason::Singular`] cluster.
const GROUP_EXACT_REDO: usize = 32;

/// Where one subdivision pass stops.
struct Pass {
    /// Splits (all axes together) after which a box is not split further.
    depth_limit: u32,
    /// Boxes this pass may visit, and [`GROUP_BOXES_PER_ROOT`] more for each root it
    /// certifies (the solve's `max_boxes` bounds all passes together).
    budget: usize,
    /// Whether boxes left undecided at `depth_limit` are handed back in
    /// [`Found::deferred`] rather than reported as clusters.
    defer: bool,
}

/// The nodes of the given start boxes (unit coordinates) of the context's equations, in the
/// coefficient field `T`; start boxes past the time limit go to `found` as budget clusters.
fn start_nodes<T: Coefficient>(
    ctx: &Context<'_>,
    starts: Vec<(Vec<Rational>, Vec<Rational>, u32)>,
    found: &mut Found<T>,
) -> Result<Vec<Node<T>>, SolveError> {
    let (system, clock) = (ctx.system, ctx.clock);
    let limits = ctx.opts.limits;
    let mut stack = Vec::new();
    for (lo, hi, depth) in starts.into_iter().rev() {
        let whole = lo.iter().zip(&hi).all(|(a, b)| a.is_zero() && b.is_one());
        let polys = if whole && !T::EXACT {
            let mapped: Vec<Bernstein<T>> = system
                .equations
                .iter()
                .map(|e| e.map(T::from_rational))
                .collect();
            elevated(&mapped)?
        } else if whole {
            ctx.exact()?
                .iter()
                .map(|e| e.map(T::from_rational))
                .collect()
        } else if limits.time_limit.is_some_and(|t| clock.elapsed() > t) {
            // Out of time before this start box (the filtered path's exact redo of the fast
            // path's uncertain boxes): it goes back as a budget cluster, bounded by rigorous
            // interval enclosures rather than restricted exactly.
            found.clusters.push(enclosed_cluster(
                system,
                lo,
                hi,
                depth,
                ClusterReason::Budget,
            ));
            continue;
        } else {
            // In integers over one denominator (no gcd per de Casteljau step), normalised to
            // rationals once.
            ctx.scaled()?
                .iter()
                .map(|e| {
                    Ok(restrict_scaled(e, &lo, &hi)?
                        .to_rational()
                        .map(T::from_rational))
                })
                .collect::<Result<_, SolveError>>()?
        };
        stack.push(Node {
            lo,
            hi,
            polys,
            depth,
        });
    }
    Ok(stack)
}

/// The context's equations at the root of the unit box, in the coefficient field `T`.
fn whole_node<T: Coefficient>(ctx: &Context<'_>) -> Result<Vec<Node<T>>, SolveError> {
    let n = ctx.system.unknowns();
    let mut found = Found::default();
    let whole = vec![(
        vec![<Rational as Zero>::zero(); n],
        vec![<Rational as One>::one(); n],
        0,
    )];
    start_nodes(ctx, whole, &mut found)
}

/// One subdivision pass over `stack` (each node's box with the equations restricted to it).
fn subdivide<T: Coefficient>(
    ctx: &Context<'_>,
    mut stack: Vec<Node<T>>,
    visited_before: usize,
    pass: &Pass,
) -> Result<Found<T>, SolveError> {
    let (system, opts, clock) = (ctx.system, ctx.opts, ctx.clock);
    let limits = opts.limits;
    let mut found = Found::default();
    let cluster = |node: &Node<T>, reason| leaf_cluster(system, node, reason);
    while let Some(node) = stack.pop() {
        let over_time = limits.time_limit.is_some_and(|t| clock.elapsed() > t);
        if visited_before + found.visited >= limits.max_boxes || over_time {
            found.clusters.push(cluster(&node, ClusterReason::Budget));
            continue;
        }
        if found.visited
            >= pass
                .budget
                .saturating_add(found.roots.len() * GROUP_BOXES_PER_ROOT)
        {
            // What is left unvisited goes back with the pass, for the hull of what it left.
            found.exhausted = true;
            found.deferred.push(node);
            found.deferred.append(&mut stack);
            break;
        }
        found.visited += 1;
        let culled = root_free(&node.polys);
        if culled == Decision::Yes {
            continue;
        }
        let Certified {
            decision: certified,
            certificate,
            culled: empty,
            preconditioned,
        } = certify_or_cull(&node.polys)?;
        if empty {
            continue;
        }
        if let (Decision::Yes, Some(certificate)) = (certified, certificate) {
            let finish = ctx.exact_finish.then_some(ctx);
            let (lo, hi, certificate) = refine(&node, certificate, opts.tolerance, finish)?;
            found.roots.push(root_of(system, &lo, &hi, certificate));
            continue;
        }
        // Rounding may leave a decision open (fast path only): splitting is always sound, so
        // the box is split on; at the depth limit it goes back as uncertain (the filtered
        // path redoes it exactly from there).
        let uncertain = culled == Decision::Uncertain || certified == Decision::Uncertain;
        // The depth limit counts halvings of each side: `n` splits make one level.
        if node.depth >= pass.depth_limit {
            if pass.defer {
                found.deferred.push(node);
                continue;
            }
            let reason = if uncertain {
                ClusterReason::Uncertain
            } else if on_domain_boundary(&node)? {
                ClusterReason::DomainBoundary
            } else {
                ClusterReason::DepthLimit
            };
            found.clusters.push(cluster(&node, reason));
            continue;
        }
        // The equations' control polygons, projected on each unknown, may leave no room for a
        // root: the box is then dropped.
        let g = preconditioned
            .as_ref()
            .map_or(node.polys.as_slice(), |(_, g)| g.as_slice());
        if projection_excludes_roots(g) {
            continue;
        }
        // Split the widest side (in unit coordinates) at a root-free plane if one is found.
        let axis = widest_axis(&node.lo, &node.hi);
        let a = preconditioned.as_ref().map(|(a, _)| a.as_slice());
        let (s, left, right) = split_polys(&node.polys, axis, node.depth, a)?;
        let mid = crate::num::rational::lerp(&node.lo[axis], &node.hi[axis], &s);
        let mut hi_left = node.hi.clone();
        hi_left[axis] = mid.clone();
        let mut lo_right = node.lo.clone();
        lo_right[axis] = mid;
        stack.push(Node {
            lo: lo_right,
            hi: node.hi,
            polys: right,
            depth: node.depth + 1,
        });
        stack.push(Node {
            lo: node.lo,
            hi: hi_left,
            polys: left,
            depth: node.depth + 1,
        });
    }
    Ok(found)
}

/// A cluster tuple (cluster, unit box, depth) of one node.
type ClusterLeaf = (Cluster, Vec<Rational>, Vec<Rational>, u32);

/// The cluster of one node's box.
fn leaf_cluster<T: Coefficient>(
    system: &System,
    node: &Node<T>,
    reason: ClusterReason,
) -> ClusterLeaf {
    (
        Cluster {
            bounds: system.domain_box(&node.lo, &node.hi),
            reason,
            max_abs_f: max_abs(&node.polys),
        },
        node.lo.clone(),
        node.hi.clone(),
        node.depth,
    )
}

/// The hull of boxes (unit coordinates) and their smallest depth; `None` for no boxes.
fn hull<'a>(
    members: impl IntoIterator<Item = &'a ClusterLeaf>,
) -> Option<(Vec<Rational>, Vec<Rational>, u32)> {
    let mut members = members.into_iter();
    let first = members.next()?;
    let (mut lo, mut hi, mut depth) = (first.1.clone(), first.2.clone(), first.3);
    for (_, mlo, mhi, d) in members {
        for k in 0..lo.len() {
            if mlo[k] < lo[k] {
                lo[k] = mlo[k].clone();
            }
            if mhi[k] > hi[k] {
                hi[k] = mhi[k].clone();
            }
        }
        depth = depth.min(*d);
    }
    Some((lo, hi, depth))
}

/// One [`ClusterReason::Singular`] cluster for a group of boxes: their [`hull`], with bounds
/// on each `|f_i|` over the whole hull (interval enclosures of the equations restricted to
/// it); `None` for no boxes.
fn merged_cluster(system: &System, members: &[ClusterLeaf]) -> Option<ClusterLeaf> {
    hull(members).map(|(lo, hi, depth)| singular_cluster(system, lo, hi, depth))
}

/// The [`ClusterReason::Singular`] cluster of one box (unit coordinates).
fn singular_cluster(
    system: &System,
    lo: Vec<Rational>,
    hi: Vec<Rational>,
    depth: u32,
) -> ClusterLeaf {
    enclosed_cluster(system, lo, hi, depth, ClusterReason::Singular)
}

/// The cluster of one box (unit coordinates) for `reason`, its bounds on each `|f_i|` from
/// interval enclosures of the equations restricted to the box (no exact restriction).
fn enclosed_cluster(
    system: &System,
    lo: Vec<Rational>,
    hi: Vec<Rational>,
    depth: u32,
    reason: ClusterReason,
) -> ClusterLeaf {
    let sub: Vec<(Rational, Rational)> = lo.iter().cloned().zip(hi.iter().cloned()).collect();
    let max_abs_f = system
        .equations
        .iter()
        .map(|e| {
            super::enclose_on(e, &sub).map_or(f64::INFINITY, |p| {
                p.coeffs()
                    .iter()
                    .map(Coefficient::abs_upper_f64)
                    .fold(0.0, f64::max)
            })
        })
        .collect();
    (
        Cluster {
            bounds: system.domain_box(&lo, &hi),
            reason,
            max_abs_f,
        },
        lo,
        hi,
        depth,
    )
}

/// The boxes an exhausted pass left: unvisited, clusters and certified roots (unit
/// coordinates); every root of the pass's start boxes lies in one of them.
fn left_by<T: Coefficient>(system: &System, pass: Found<T>) -> Vec<ClusterLeaf> {
    let n = system.unknowns();
    let mut left: Vec<ClusterLeaf> = pass
        .deferred
        .iter()
        .map(|node| leaf_cluster(system, node, ClusterReason::Singular))
        .collect();
    left.extend(pass.clusters);
    for r in pass.roots {
        let lo = (0..n).map(|k| system.to_unit(k, &r.bounds[k].0)).collect();
        let hi = (0..n).map(|k| system.to_unit(k, &r.bounds[k].1)).collect();
        let cluster = Cluster {
            bounds: r.bounds,
            reason: ClusterReason::Singular,
            max_abs_f: Vec::new(),
        };
        left.push((cluster, lo, hi, 0));
    }
    left
}

/// The groups of touching boxes among `leaves` (indices).
fn leaf_groups<'a>(
    leaves: impl Iterator<Item = (&'a [Rational], &'a [Rational])>,
) -> Vec<Vec<usize>> {
    let boxes: Vec<(&[Rational], &[Rational])> = leaves.collect();
    super::touching_groups(&boxes)
}

/// A solve's subdivision of `nodes` in two stages: every box to [`COARSE_LEVELS`], then each
/// group of touching boxes still undecided there on its own, down to the depth limit within
/// [`group_budget`]; a group that needs more is one [`ClusterReason::Singular`] cluster: the
/// hull of the boxes the pass left (unvisited, clusters and roots), which hold every root of
/// the group.
///
/// `filtered` (the interval path of [`Path::Filtered`]): a group of at most
/// [`GROUP_EXACT_REDO`] coarse boxes that the intervals leave unresolved (out of budget, or
/// with more undecided leaves than that) is subdivided again in exact rationals from its
/// coarse boxes, within [`GROUP_EXACT_BOXES`], before it is given up: rounding, not the
/// geometry, may be what stopped it (two roots `2⁻²⁷` apart).
fn staged<T: Coefficient>(
    ctx: &Context<'_>,
    nodes: Vec<Node<T>>,
    filtered: bool,
) -> Result<Found<()>, SolveError> {
    let system = ctx.system;
    let n = system.unknowns() as u32;
    let levels = ctx.opts.limits.max_depth;
    let full = Pass {
        depth_limit: levels.saturating_mul(n),
        budget: usize::MAX,
        defer: false,
    };
    if levels <= COARSE_LEVELS {
        return Ok(subdivide(ctx, nodes, 0, &full)?.erased());
    }
    let coarse = Pass {
        depth_limit: COARSE_LEVELS * n,
        budget: usize::MAX,
        defer: true,
    };
    let mut first = subdivide(ctx, nodes, 0, &coarse)?;
    let deferred = std::mem::take(&mut first.deferred);
    let mut found = first.erased();
    let groups = leaf_groups(deferred.iter().map(|d| (d.lo.as_slice(), d.hi.as_slice())));
    let mut slots: Vec<Option<Node<T>>> = deferred.into_iter().map(Some).collect();
    let group_pass = Pass {
        budget: group_budget(n),
        ..full
    };
    for group in groups {
        let members: Vec<Node<T>> = group.iter().filter_map(|&i| slots[i].take()).collect();
        let starts: Vec<(Vec<Rational>, Vec<Rational>, u32)> = members
            .iter()
            .map(|m| (m.lo.clone(), m.hi.clone(), m.depth))
            .collect();
        let mut pass = subdivide(ctx, members, found.visited, &group_pass)?;
        let undecided = pass
            .clusters
            .iter()
            .filter(|c| c.0.reason == ClusterReason::Uncertain)
            .count();
        if !pass.exhausted && (!filtered || undecided <= GROUP_EXACT_REDO) {
            found.absorb(pass);
            continue;
        }
        found.visited += pass.visited;
        pass.visited = 0;
        let left = left_by(system, pass);
        if filtered && starts.len() <= GROUP_EXACT_REDO {
            let mut again = Found::<Rational>::default();
            let nodes = start_nodes(ctx, starts, &mut again)?;
            let exact_pass = Pass {
                budget: GROUP_EXACT_BOXES,
                ..full
            };
            let pass = subdivide(ctx, nodes, found.visited, &exact_pass)?;
            if !pass.exhausted {
                again.absorb(pass);
                found.absorb(again);
                continue;
            }
            found.visited += pass.visited;
            let mut exact_left = left_by(system, pass);
            exact_left.extend(again.clusters);
            // Both passes cover every root of the group: so does the meet of their hulls.
            if let (Some(a), Some(b)) = (hull(&left), hull(&exact_left)) {
                let lo: Vec<Rational> = a.0.into_iter().zip(b.0).map(|(x, y)| x.max(y)).collect();
                let hi: Vec<Rational> = a.1.into_iter().zip(b.1).map(|(x, y)| x.min(y)).collect();
                if lo.iter().zip(&hi).all(|(l, h)| l <= h) {
                    let depth = a.2.min(b.2);
                    found.clusters.push(singular_cluster(system, lo, hi, depth));
                    continue;
                }
            }
        }
        found.clusters.extend(merged_cluster(system, &left));
    }
    Ok(found)
}

/// A certified root from its unit box.
fn root_of(
    system: &System,
    lo: &[Rational],
    hi: &[Rational],
    certificate: RootCertificate,
) -> Root {
    root_in(system.domain_box(lo, hi), certificate)
}

/// A certified root from its box in domain coordinates: the centre rounded to `f64` and the
/// bound on the distance from it to any point of the box.
pub(super) fn root_in(bounds: RationalBox, certificate: RootCertificate) -> Root {
    let two = Rational::from_integer(2.into());
    let approx: Vec<f64> = bounds
        .iter()
        .map(|(a, b)| rational_to_f64(&((a + b) / &two)))
        .collect();
    let error_bound = bounds
        .iter()
        .zip(&approx)
        .map(|((a, b), &c)| {
            let c = rational_from_f64(c, "centre").unwrap_or_default();
            let far = (&c - a).abs().max((b - &c).abs());
            let i = Interval::from_rational(&far);
            i.hi
        })
        .fold(0.0, f64::max);
    Root {
        bounds,
        approx,
        error_bound,
        certificate,
    }
}

/// A root on a split plane leaves touching depth-limit clusters on both sides, none of which
/// can certify it. Each group of touching depth-limit clusters is tried once more as one box:
/// their hull, inflated by a quarter of its width on every side (inside the domain), and
/// certified exactly. A certified box replaces the group only when it meets no other root's
/// or cluster's box, so nothing is counted twice.
fn certify_across_planes(ctx: &Context<'_>, found: Found<()>) -> Result<Found<()>, SolveError> {
    let quarter = Rational::new(1.into(), 4.into());
    retry_groups(
        ctx,
        found,
        |c| c.0.reason == ClusterReason::DepthLimit,
        |_, members| members.len() >= 2,
        |lo, hi| {
            for k in 0..lo.len() {
                let w = (&hi[k] - &lo[k]) * &quarter;
                lo[k] = (&lo[k] - &w).max(<Rational as Zero>::zero());
                hi[k] = (&hi[k] + &w).min(<Rational as One>::one());
            }
        },
        |_, _, c| Ok(Some(c)),
    )
}

/// The retry both [`certify_across_planes`] and [`certify_on_boundary`] make: the clusters
/// `eligible` admits are grouped by touching; each group `wanted` is tried as one box (its
/// hull, `widen`ed, in unit coordinates), certified exactly on the equations there
/// ([`Bernstein::on_box`]) and refined; when the box meets no other root's or cluster's box
/// and `accept` keeps the refined box and its certificate, the root replaces the group.
fn retry_groups(
    ctx: &Context<'_>,
    mut found: Found<()>,
    eligible: impl Fn(&ClusterLeaf) -> bool,
    wanted: impl Fn(&[ClusterLeaf], &[usize]) -> bool,
    widen: impl Fn(&mut [Rational], &mut [Rational]),
    accept: impl Fn(
        &[Rational],
        &[Rational],
        RootCertificate,
    ) -> Result<Option<RootCertificate>, SolveError>,
) -> Result<Found<()>, SolveError> {
    let (system, opts) = (ctx.system, ctx.opts);
    let clusters = std::mem::take(&mut found.clusters);
    let (groups, group_of) = touching_clusters(&clusters, eligible);
    let mut replaced = vec![false; clusters.len()];
    for (gi, members) in groups.iter().enumerate() {
        if !wanted(&clusters, members) {
            continue;
        }
        let Some((mut lo, mut hi, _)) = hull(members.iter().map(|&m| &clusters[m])) else {
            continue;
        };
        widen(&mut lo, &mut hi);
        if !clear_of_others(system, &found.roots, &clusters, &group_of, gi, &lo, &hi) {
            continue;
        }
        let sub: Vec<(Rational, Rational)> = lo.iter().cloned().zip(hi.iter().cloned()).collect();
        let polys: Vec<Bernstein<Rational>> = ctx
            .exact()?
            .iter()
            .map(|e| e.on_box(&sub))
            .collect::<Result<_, _>>()?;
        let Some((rlo, rhi, c)) = certify_and_refine(lo, hi, polys, opts.tolerance)? else {
            continue;
        };
        let Some(c) = accept(&rlo, &rhi, c)? else {
            continue;
        };
        found.roots.push(root_of(system, &rlo, &rhi, c));
        for &m in members {
            replaced[m] = true;
        }
    }
    found.clusters = clusters
        .into_iter()
        .zip(replaced)
        .filter(|(_, r)| !r)
        .map(|(c, _)| c)
        .collect();
    Ok(found)
}

/// A refined root box (lower and upper corners) and its certificate.
pub(super) type RefinedRoot = (Vec<Rational>, Vec<Rational>, RootCertificate);

/// Certifies exactly that the equations `polys` (Bernstein form on the box `lo..hi`, in unit
/// coordinates of the domain, common degrees) have exactly one root on it, and refines the
/// box to `tolerance` ([`refine`]): the refined box and its certificate, or `None`.
pub(super) fn certify_and_refine(
    lo: Vec<Rational>,
    hi: Vec<Rational>,
    polys: Vec<Bernstein<Rational>>,
    tolerance: f64,
) -> Result<Option<RefinedRoot>, SolveError> {
    let (Decision::Yes, Some(c)) = certify(&polys)? else {
        return Ok(None);
    };
    let node = Node {
        lo,
        hi,
        polys,
        depth: 0,
    };
    refine(&node, c, tolerance, None).map(Some)
}

/// Groups of touching clusters among those `eligible` admits (indices into `clusters`), and
/// each cluster's group (`usize::MAX` for none).
fn touching_clusters(
    clusters: &[ClusterLeaf],
    eligible: impl Fn(&ClusterLeaf) -> bool,
) -> (Vec<Vec<usize>>, Vec<usize>) {
    let candidates: Vec<usize> = (0..clusters.len())
        .filter(|&i| eligible(&clusters[i]))
        .collect();
    let boxes: Vec<(&[Rational], &[Rational])> = candidates
        .iter()
        .map(|&i| (clusters[i].1.as_slice(), clusters[i].2.as_slice()))
        .collect();
    let groups: Vec<Vec<usize>> = super::touching_groups(&boxes)
        .into_iter()
        .map(|g| g.into_iter().map(|i| candidates[i]).collect())
        .collect();
    let mut group_of = vec![usize::MAX; clusters.len()];
    for (g, members) in groups.iter().enumerate() {
        for &m in members {
            group_of[m] = g;
        }
    }
    (groups, group_of)
}

/// Whether the box `lo..hi` (unit coordinates) meets no root's box and no cluster outside
/// group `gi` (so that what it certifies is counted once).
fn clear_of_others(
    system: &System,
    roots: &[Root],
    clusters: &[ClusterLeaf],
    group_of: &[usize],
    gi: usize,
    lo: &[Rational],
    hi: &[Rational],
) -> bool {
    let n = lo.len();
    let meets =
        |olo: &[Rational], ohi: &[Rational]| (0..n).all(|k| lo[k] <= ohi[k] && olo[k] <= hi[k]);
    let root_met = roots.iter().any(|r| {
        let ulo: Vec<Rational> = (0..n).map(|k| system.to_unit(k, &r.bounds[k].0)).collect();
        let uhi: Vec<Rational> = (0..n).map(|k| system.to_unit(k, &r.bounds[k].1)).collect();
        meets(&ulo, &uhi)
    });
    let cluster_met = clusters
        .iter()
        .zip(group_of)
        .any(|(c, &g)| g != gi && meets(&c.1, &c.2));
    !root_met && !cluster_met
}

/// A simple root on the domain's boundary leaves clusters there that no box inside the
/// domain certifies: Miranda's test needs strict signs on opposite faces, and the root lies
/// on one. Each group of touching depth-limit and boundary clusters with one on the boundary
/// ([`ClusterReason::DomainBoundary`]) is tried once more as one box reaching across the
/// boundary: their hull, mirrored across each boundary face it touches (the root, on the
/// face, then sits mid-box) and inflated by a quarter of its width on every other side; the
/// equations extend beyond the domain as polynomials ([`Bernstein::on_box`]). A box
/// certified exactly and refined replaces the group when it meets no other root's or
/// cluster's box and its one root is
/// - inside the domain (the refined box inside it): an ordinary root;
/// - on the boundary: the point of the refined box with the crossed faces' coordinates and,
///   on the other axes, the simplest rationals of its sides
///   ([`simplest_between`](crate::num::rational::simplest_between)) is tried as the root,
///   and kept ([`RootCertificate::point`]) when every equation vanishes there exactly.
///
/// Otherwise (an irrational root on a face, a singular one, or one outside the domain,
/// which culling nearly always removes first) the group stays.
fn certify_on_boundary(ctx: &Context<'_>, found: Found<()>) -> Result<Found<()>, SolveError> {
    let system = ctx.system;
    let n = system.unknowns();
    let unit = vec![(<Rational as Zero>::zero(), <Rational as One>::one()); n];
    let on_boundary = |c: &ClusterLeaf| c.0.reason == ClusterReason::DomainBoundary;
    retry_groups(
        ctx,
        found,
        |c| on_boundary(c) || c.0.reason == ClusterReason::DepthLimit,
        |clusters, members| members.iter().any(|&m| on_boundary(&clusters[m])),
        |lo, hi| super::reach_across(lo, hi, &unit),
        |rlo, rhi, mut c| {
            let refined = system.domain_box(rlo, rhi);
            let Some(candidate) = super::boundary_candidate(&system.domain, &refined) else {
                // Outside the domain.
                return Ok(None);
            };
            let Some(point) = candidate else {
                return Ok(Some(c));
            };
            // On the boundary: is the candidate the root?
            let u: Vec<Rational> = (0..n).map(|k| system.to_unit(k, &point[k])).collect();
            for e in &system.equations {
                if !e.eval(&u)?.is_zero() {
                    return Ok(None);
                }
            }
            c.point = Some(point);
            Ok(Some(c))
        },
    )
}

/// Solves `system` (as many equations as unknowns) on its domain on the path `opts.path`.
///
/// Every root of the system in the domain lies in exactly one reported root box (which holds
/// no other root) or in a cluster box; a multiple or tangential root, roots closer together
/// than the depth limit resolves, and a root on the domain's boundary that is not at a
/// rational point found as the simplest in its box ([`SolveOptions::boundary`]) come back as
/// clusters.
pub fn solve(system: &System, opts: &SolveOptions) -> Result<Solution, SolveError> {
    let n = system.unknowns();
    super::check_square(system.equations.len(), n)?;
    let ctx = Context {
        system,
        opts,
        clock: Instant::now(),
        exact_finish: opts.path == Path::Filtered,
        exact: Default::default(),
        scaled: Default::default(),
    };
    let found: Found<()> = match opts.path {
        Path::Exact => staged::<Rational>(&ctx, whole_node(&ctx)?, false)?,
        Path::Fast => staged::<Interval>(&ctx, whole_node(&ctx)?, false)?,
        Path::Filtered => {
            let mut fast = staged::<Interval>(&ctx, whole_node(&ctx)?, true)?;
            let (open, mut kept): (Vec<_>, Vec<_>) = fast
                .clusters
                .drain(..)
                .partition(|c| c.0.reason == ClusterReason::Uncertain);
            // The interval path's undecided leaves are redone exactly, box by box, unless
            // they crowd around one point (then they are one cluster).
            let mut starts = Vec::new();
            let mut slots: Vec<Option<ClusterLeaf>> = Vec::new();
            let groups = leaf_groups(open.iter().map(|c| (c.1.as_slice(), c.2.as_slice())));
            slots.extend(open.into_iter().map(Some));
            for group in groups {
                let members: Vec<ClusterLeaf> =
                    group.iter().filter_map(|&i| slots[i].take()).collect();
                if members.len() > GROUP_EXACT_REDO {
                    kept.extend(merged_cluster(system, &members));
                } else {
                    starts.extend(members.into_iter().map(|(_, lo, hi, d)| (lo, hi, d)));
                }
            }
            let full = Pass {
                depth_limit: opts.limits.max_depth.saturating_mul(n as u32),
                budget: usize::MAX,
                defer: false,
            };
            // A box at the depth limit is decided once, in integers; what it certifies (or a
            // box above the limit) is subdivided in rationals, with its root refined.
            let mut rational = Vec::new();
            for (lo, hi, depth) in starts {
                let over_time = opts
                    .limits
                    .time_limit
                    .is_some_and(|t| ctx.clock.elapsed() > t);
                if depth < full.depth_limit || over_time {
                    rational.push((lo, hi, depth));
                    continue;
                }
                fast.visited += 1;
                match decide_leaf(&ctx, &lo, &hi)? {
                    Leaf::Culled => {}
                    Leaf::Certified => rational.push((lo, hi, depth)),
                    Leaf::Open {
                        on_boundary,
                        max_abs_f,
                    } => {
                        let reason = if on_boundary {
                            ClusterReason::DomainBoundary
                        } else {
                            ClusterReason::DepthLimit
                        };
                        let cluster = Cluster {
                            bounds: system.domain_box(&lo, &hi),
                            reason,
                            max_abs_f,
                        };
                        kept.push((cluster, lo, hi, depth));
                    }
                }
            }
            let starts = rational;
            if !starts.is_empty() {
                let mut more = Found::<Rational>::default();
                let nodes = start_nodes(&ctx, starts, &mut more)?;
                let pass = subdivide(&ctx, nodes, fast.visited, &full)?;
                more.absorb(pass);
                fast.roots.extend(more.roots);
                kept.extend(more.clusters);
                fast.visited += more.visited;
            }
            fast.clusters = kept;
            fast
        }
    };
    let mut found = certify_across_planes(&ctx, found)?;
    if opts.boundary {
        found = certify_on_boundary(&ctx, found)?;
    }
    Ok(Solution {
        roots: found.roots,
        clusters: found.clusters.into_iter().map(|c| c.0).collect(),
        boxes_visited: found.visited,
        path: opts.path,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The preconditioner's gradient at the centre agrees with the partial derivatives'
    /// values there (Bernstein `derivative`, then `eval`) on random polynomials of 1–4
    /// unknowns, to rounding.
    #[test]
    fn gradient_at_centre_matches_derivatives() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next =
            move || (crate::num::xorshift(&mut seed) >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        let mut checked = 0;
        for k in 0..300 {
            let n = 1 + k % 4;
            let degrees: Vec<usize> = (0..n).map(|_| ((next() + 0.5) * 5.0) as usize).collect();
            let count: usize = degrees.iter().map(|d| d + 1).product();
            let p = Bernstein::new(degrees.clone(), (0..count).map(|_| next()).collect()).unwrap();
            let g = gradient_at_centre(p.coeffs().to_vec(), &degrees);
            let half = vec![0.5; n];
            for axis in 0..n {
                let want = if degrees[axis] == 0 {
                    0.0
                } else {
                    p.derivative(axis).unwrap().eval(&half).unwrap()
                };
                assert!(
                    (g[axis] - want).abs() <= 1e-12 * (1.0 + want.abs()),
                    "{g:?} {want}"
                );
                checked += 1;
            }
        }
        assert!(checked >= 700, "{checked}");
    }

    /// The filtered path's integer decision on one box ([`decide_leaf`]) is the rational
    /// path's ([`subdivide`]'s tests at the depth limit), on boxes around the roots of random
    /// systems of 2 and 3 unknowns: the roots' own boxes, boxes widened around them, boxes
    /// beside them, and boxes at the domain's corners.
    #[test]
    fn the_integer_leaf_decision_is_the_rational_one() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next =
            move || (crate::num::xorshift(&mut seed) >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        let q = |x: f64| rational_from_f64(x, "x").unwrap();
        let mut counts = [0usize; 4];
        for k in 0..24 {
            let n = 2 + k % 2;
            let degrees = vec![2; n];
            let count: usize = degrees.iter().map(|d| d + 1).product();
            let equations: Vec<Bernstein<Rational>> = (0..n)
                .map(|_| {
                    let c = (0..count).map(|_| q(next())).collect();
                    Bernstein::new(degrees.clone(), c).unwrap()
                })
                .collect();
            let zero = <Rational as Zero>::zero();
            let one = <Rational as One>::one();
            let system = System::new(vec![(zero.clone(), one.clone()); n], equations).unwrap();
            let opts = SolveOptions::default();
            let ctx = Context {
                system: &system,
                opts: &opts,
                clock: Instant::now(),
                exact_finish: true,
                exact: Default::default(),
                scaled: Default::default(),
            };
            let solution = solve(&system, &opts).unwrap();
            let mut boxes: Vec<(Vec<Rational>, Vec<Rational>)> = Vec::new();
            for r in &solution.roots {
                let c: Vec<f64> = r.approx.clone();
                for w in [1e-9, 1e-6, 1e-3, 0.05] {
                    for shift in [0.0, 3.0] {
                        let lo = c.iter().map(|&x| q((x - w + shift * w).clamp(0.0, 1.0)));
                        let hi = c.iter().map(|&x| q((x + w + shift * w).clamp(0.0, 1.0)));
                        boxes.push((lo.collect(), hi.collect()));
                    }
                }
            }
            for corner in [0.0, 1.0] {
                let lo = vec![q(if corner == 0.0 { 0.0 } else { 0.75 }); n];
                let hi = vec![q(if corner == 0.0 { 0.25 } else { 1.0 }); n];
                boxes.push((lo, hi));
            }
            for (lo, hi) in boxes {
                if lo.iter().zip(&hi).any(|(a, b)| a >= b) {
                    continue;
                }
                let sub: Vec<(Rational, Rational)> =
                    lo.iter().cloned().zip(hi.iter().cloned()).collect();
                let polys: Vec<Bernstein<Rational>> = ctx
                    .exact()
                    .unwrap()
                    .iter()
                    .map(|e| e.restrict(&sub).unwrap())
                    .collect();
                let node = Node {
                    lo: lo.clone(),
                    hi: hi.clone(),
                    polys,
                    depth: 0,
                };
                let rational = if root_free(&node.polys) == Decision::Yes {
                    0
                } else {
                    let c = certify_or_cull(&node.polys).unwrap();
                    if c.culled {
                        0
                    } else if c.certificate.is_some() {
                        1
                    } else if on_domain_boundary(&node).unwrap() {
                        2
                    } else {
                        3
                    }
                };
                let integer = match decide_leaf(&ctx, &lo, &hi).unwrap() {
                    Leaf::Culled => 0,
                    Leaf::Certified => 1,
                    Leaf::Open {
                        on_boundary: true, ..
                    } => 2,
                    Leaf::Open { .. } => 3,
                };
                assert_eq!(integer, rational, "system {k}, box {lo:?} – {hi:?}");
                counts[integer] += 1;
            }
        }
        println!(
            "culled {}, certified {}, open on the boundary {}, open inside {}: all agree",
            counts[0], counts[1], counts[2], counts[3]
        );
        assert!(
            counts[0] > 0 && counts[1] > 0 && counts[3] > 0,
            "{counts:?}"
        );
    }
}
