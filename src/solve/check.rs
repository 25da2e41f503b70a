//! The independent checker of root certificates. It does not call the subdivision: it
//! restricts the original equations to the root's box directly, forms `g = A f` and reads
//! the faces and the partial derivatives itself, all in exact rationals — after a filter in
//! `f64` interval arithmetic that accepts a certificate only when rigorous enclosures of the
//! same quantities decide every condition (and otherwise leaves the decision to the exact
//! check; it never refuses).

use super::input::{
    certificate_from_json, parse_box, piecewise_system_from_json, piecewise_system_to_json,
    system_to_json,
};
use super::{
    Equation, PiecewiseSystem, RationalBox, RootCertificate, Solution, SolveError, System,
};
use crate::bernstein::{Bernstein, BernsteinError};
use crate::bspline::BsplineError;
use crate::num::{rational_to_string, Interval, Rational};
use num_traits::{One, Signed, Zero};
use serde_json::{json, Value};

/// The kind string of a root-certificate file.
pub const CERTIFICATE_KIND: &str = "geocert/solve-roots";

/// What [`verify_root`] re-established.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RootCheck {
    /// The number of unknowns (and of Miranda sign conditions checked per face pair).
    pub unknowns: usize,
    /// Whether the box reaches across the domain's boundary and the certificate's point was
    /// checked to be the root ([`RootCertificate::point`]).
    pub on_boundary: bool,
}

impl std::fmt::Display for RootCheck {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "exactly one root in the box: A·f changes sign across all {} pairs of opposite faces \
             (Miranda) and its interval Jacobian is diagonally dominant (uniqueness)",
            self.unknowns
        )?;
        if self.on_boundary {
            write!(
                f,
                "; it is the certificate's point, in the domain and the box, where every \
                 equation vanishes exactly (the box reaches across the domain's boundary)"
            )?;
        }
        Ok(())
    }
}

/// Why [`verify_root`] refused a certificate.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RootRefusal {
    /// The box is empty, inverted or not inside the domain on this axis.
    #[error("box axis {axis}: empty, inverted or outside the domain")]
    Bounds {
        /// The axis.
        axis: usize,
    },
    /// The certificate's point ([`RootCertificate::point`]) is not in the domain and the
    /// box, or not an exact zero of every equation.
    #[error("the certificate's point {0}")]
    Point(String),
    /// The box or matrix does not have the system's dimension.
    #[error("the box or preconditioner does not have the system's {0} unknowns")]
    Shape(usize),
    /// `g_i` is not of the certified strict sign on a face.
    #[error("g_{equation} is not strictly {} on the face t_{equation} = {}", if *negative { "negative" } else { "positive" }, if *upper { 1 } else { 0 })]
    Miranda {
        /// The row `i` of `g = A f` (and the axis of the face pair).
        equation: usize,
        /// Whether the upper face failed.
        upper: bool,
        /// The sign it should have had.
        negative: bool,
    },
    /// Row `i` of the interval Jacobian of `g` is not strictly diagonally dominant.
    #[error("row {row} of the interval Jacobian of A·f is not strictly diagonally dominant")]
    Uniqueness {
        /// The row.
        row: usize,
    },
    /// The Bernstein kernel refused an operation.
    #[error("Bernstein kernel: {0}")]
    Kernel(#[from] BernsteinError),
    /// The B-spline kernel refused an operation.
    #[error("B-spline kernel: {0}")]
    Spline(BsplineError),
}

/// Re-checks that `bounds` (domain coordinates) holds exactly one root of `system`, from the
/// certificate's preconditioner and face signs. The conditions are first read from rigorous
/// `f64` interval enclosures (accepted only when those decide every one of them); otherwise,
/// and for every refusal, exactly as [`verify_root_exactly`].
pub fn verify_root(
    system: &System,
    bounds: &RationalBox,
    certificate: &RootCertificate,
) -> Result<RootCheck, RootRefusal> {
    let sub = checked_box(system, bounds, certificate)?;
    if certificate.point.is_none() {
        if let Some(check) = check_interval(system, &sub, certificate) {
            return Ok(check);
        }
    }
    check_exactly(system, bounds, &sub, certificate)
}

/// [`verify_root`] in exact rationals only (no interval filter): the equations restricted to
/// the box exactly, every sign and the dominance read from exact coefficients.
pub fn verify_root_exactly(
    system: &System,
    bounds: &RationalBox,
    certificate: &RootCertificate,
) -> Result<RootCheck, RootRefusal> {
    let sub = checked_box(system, bounds, certificate)?;
    check_exactly(system, bounds, &sub, certificate)
}

/// The box in the domain's unit coordinates, after checking the shapes; inside the domain
/// unless the certificate has a point (which [`check_exactly`] checks).
fn checked_box(
    system: &System,
    bounds: &RationalBox,
    certificate: &RootCertificate,
) -> Result<Vec<(Rational, Rational)>, RootRefusal> {
    shape(
        system.unknowns(),
        system.equations.len(),
        bounds,
        certificate,
    )?;
    if certificate.point.is_none() {
        return unit_box(&system.domain, bounds);
    }
    // A root on the boundary: the box may reach beyond the domain (the point is checked with
    // the equations on it, [`check_exactly`]).
    let mut sub = Vec::with_capacity(bounds.len());
    for (axis, (lo, hi)) in bounds.iter().enumerate() {
        if lo >= hi {
            return Err(RootRefusal::Bounds { axis });
        }
        sub.push((system.to_unit(axis, lo), system.to_unit(axis, hi)));
    }
    Ok(sub)
}

/// The exact check on the box `bounds` (`sub` in the unit coordinates of the domain).
fn check_exactly(
    system: &System,
    bounds: &RationalBox,
    sub: &[(Rational, Rational)],
    certificate: &RootCertificate,
) -> Result<RootCheck, RootRefusal> {
    // (`on_box` is `restrict` inside the domain and extends the equations beyond it.)
    let f = system
        .equations
        .iter()
        .map(|e| e.on_box(sub))
        .collect::<Result<Vec<_>, _>>()?;
    whole_box(&system.domain, f, bounds, certificate)
}

/// Miranda and dominance on the whole box with the equations `f` on it ([`check_parts`] on
/// one part), after checking the certificate's point against them if it has one.
fn whole_box(
    domain: &[(Rational, Rational)],
    f: Vec<Bernstein<Rational>>,
    bounds: &RationalBox,
    certificate: &RootCertificate,
) -> Result<RootCheck, RootRefusal> {
    let n = bounds.len();
    if let Some(point) = &certificate.point {
        point_is_the_root(domain, &f, bounds, point)?;
    }
    let whole = Part {
        f: common_degrees(f)?,
        lower: vec![true; n],
        upper: vec![true; n],
        ratio: vec![Rational::one(); n],
    };
    let check = check_parts(&[whole], certificate)?;
    Ok(RootCheck {
        on_boundary: certificate.point.is_some(),
        ..check
    })
}

/// [`verify_root`] for a system with B-spline equations. The box is cut by the equations'
/// knots strictly inside it into parts; each equation is taken on each part directly (a
/// B-spline by blossoming, a polynomial by restriction); Miranda's conditions are checked on
/// every part of every face, and the interval Jacobian over all parts (which is what the mean
/// value theorem along a segment crossing parts needs; the field is continuous). With a
/// [`RootCertificate::point`] the box may reach beyond the domain: its part inside must lie
/// in one knot span of every B-spline, the equations are taken on the whole box as those
/// spans' polynomials, and the point must be an exact zero of them
/// in the domain and the box.
pub fn verify_piecewise_root(
    system: &PiecewiseSystem,
    bounds: &RationalBox,
    certificate: &RootCertificate,
) -> Result<RootCheck, RootRefusal> {
    let n = system.unknowns();
    shape(n, system.equations().len(), bounds, certificate)?;
    if certificate.point.is_some() {
        // A root on the domain's boundary: the box reaches across it, and the equations are
        // taken there as the polynomials they are on the box's part inside the domain.
        let f = extended_equations(system, bounds)?;
        return whole_box(system.domain(), f, bounds, certificate);
    }
    unit_box(system.domain(), bounds)?;
    let mut parts = Vec::new();
    for part in knot_parts(system, bounds) {
        parts.push(Part {
            f: common_degrees(part_equations(system, &part)?)?,
            lower: (0..n).map(|k| part[k].0 == bounds[k].0).collect(),
            upper: (0..n).map(|k| part[k].1 == bounds[k].1).collect(),
            ratio: (0..n)
                .map(|k| (&bounds[k].1 - &bounds[k].0) / (&part[k].1 - &part[k].0))
                .collect(),
        });
    }
    check_parts(&parts, certificate)
}

/// The equations of `system` on a box that may reach beyond the domain (Bernstein form on
/// the box): each one is a polynomial on the box's part inside the domain (a B-spline there
/// lies in one knot span on every axis), extended beyond it as that polynomial
/// ([`Bernstein::on_box`]). Refused when the part inside crosses a knot of some B-spline.
pub(super) fn extended_equations(
    system: &PiecewiseSystem,
    bounds: &RationalBox,
) -> Result<Vec<Bernstein<Rational>>, RootRefusal> {
    let domain = system.domain();
    let mut inside = Vec::with_capacity(bounds.len());
    for (axis, ((lo, hi), (a, b))) in bounds.iter().zip(domain).enumerate() {
        let (l, h) = (lo.max(a).clone(), hi.min(b).clone());
        if l >= h {
            return Err(RootRefusal::Bounds { axis });
        }
        inside.push((l, h));
    }
    // The box in the unit coordinates of the part inside.
    let relative: Vec<(Rational, Rational)> = bounds
        .iter()
        .zip(&inside)
        .map(|((lo, hi), (l, h))| {
            let w = h - l;
            ((lo - l) / &w, (hi - l) / &w)
        })
        .collect();
    system
        .equations()
        .iter()
        .map(|e| {
            let on_inside = match e {
                Equation::Polynomial(p) => p.restrict(&unit_box(domain, &inside)?)?,
                Equation::Spline(s) => s
                    .bezier_on_box_exact(&inside)
                    .map_err(RootRefusal::Spline)?,
            };
            Ok(on_inside.on_box(&relative)?)
        })
        .collect()
}

/// Checks that `point` lies in `domain` and in `bounds` and that every equation of `f` (on
/// `bounds`, [`extended_equations`]) vanishes there exactly.
pub(super) fn point_is_the_root(
    domain: &[(Rational, Rational)],
    f: &[Bernstein<Rational>],
    bounds: &RationalBox,
    point: &[Rational],
) -> Result<(), RootRefusal> {
    let n = bounds.len();
    if point.len() != n {
        return Err(RootRefusal::Shape(n));
    }
    let mut u = Vec::with_capacity(n);
    for (k, x) in point.iter().enumerate() {
        let (a, b) = &domain[k];
        if x < a || x > b {
            return Err(RootRefusal::Point(format!(
                "is outside the domain on axis {k}"
            )));
        }
        let (lo, hi) = &bounds[k];
        if x < lo || x > hi || lo >= hi {
            return Err(RootRefusal::Point(format!(
                "is outside the box on axis {k}"
            )));
        }
        u.push((x - lo) / (hi - lo));
    }
    for (i, e) in f.iter().enumerate() {
        if !e.eval(&u)?.is_zero() {
            return Err(RootRefusal::Point(format!("is not a zero of equation {i}")));
        }
    }
    Ok(())
}

/// The parts the equations' knots strictly inside `bounds` cut it into (every part a box
/// inside one knot span of every equation; `bounds` itself when no knot is inside).
pub(super) fn knot_parts(system: &PiecewiseSystem, bounds: &RationalBox) -> Vec<RationalBox> {
    let n = bounds.len();
    let mut cuts: Vec<Vec<Rational>> = bounds
        .iter()
        .map(|(a, b)| vec![a.clone(), b.clone()])
        .collect();
    for e in system.equations() {
        if let Equation::Spline(s) = e {
            for (k, knots) in s.knots().iter().enumerate().take(n) {
                let (a, b) = &bounds[k];
                cuts[k].extend(knots.iter().filter(|x| a < *x && *x < b).cloned());
            }
        }
    }
    for c in &mut cuts {
        c.sort();
        c.dedup();
    }
    let counts: Vec<usize> = cuts.iter().map(|c| c.len() - 1).collect();
    let total: usize = counts.iter().product();
    (0..total)
        .map(|mut flat| {
            (0..n)
                .map(|k| {
                    let j = flat % counts[k];
                    flat /= counts[k];
                    (cuts[k][j].clone(), cuts[k][j + 1].clone())
                })
                .collect()
        })
        .collect()
}

/// Each equation on `part` (a box inside one knot span of every equation), in Bernstein form
/// on it, taken directly: a B-spline by blossoming, a polynomial by restriction.
pub(super) fn part_equations(
    system: &PiecewiseSystem,
    part: &RationalBox,
) -> Result<Vec<Bernstein<Rational>>, RootRefusal> {
    let sub = unit_box(system.domain(), part)?;
    system
        .equations()
        .iter()
        .map(|e| match e {
            Equation::Polynomial(p) => Ok(p.restrict(&sub)?),
            Equation::Spline(s) => s.bezier_on_box_exact(part).map_err(RootRefusal::Spline),
        })
        .collect()
}

/// The box, the matrix and the signs have the system's dimension, and it is square.
fn shape(
    n: usize,
    equations: usize,
    bounds: &RationalBox,
    certificate: &RootCertificate,
) -> Result<(), RootRefusal> {
    let a = &certificate.preconditioner;
    if bounds.len() != n
        || a.len() != n
        || a.iter().any(|r| r.len() != n)
        || certificate.lower_face_signs.len() != n
        || equations != n
    {
        return Err(RootRefusal::Shape(n));
    }
    Ok(())
}

/// `bounds` in the unit coordinates of `domain`; refused when empty or not inside.
fn unit_box(
    domain: &[(Rational, Rational)],
    bounds: &RationalBox,
) -> Result<Vec<(Rational, Rational)>, RootRefusal> {
    let mut sub = Vec::with_capacity(bounds.len());
    for (axis, ((lo, hi), (a0, b0))) in bounds.iter().zip(domain).enumerate() {
        let w = b0 - a0;
        let (u, v) = ((lo - a0) / &w, (hi - a0) / &w);
        if u.is_negative() || v > Rational::one() || u >= v {
            return Err(RootRefusal::Bounds { axis });
        }
        sub.push((u, v));
    }
    Ok(sub)
}

/// The polynomials elevated to the highest degree each axis has among them.
fn common_degrees(f: Vec<Bernstein<Rational>>) -> Result<Vec<Bernstein<Rational>>, RootRefusal> {
    let n = f.first().map_or(0, Bernstein::dim);
    let top: Vec<usize> = (0..n)
        .map(|k| f.iter().map(|e| e.degrees()[k]).max().unwrap_or(0))
        .collect();
    f.into_iter()
        .map(|mut p| {
            for (k, &t) in top.iter().enumerate() {
                let d = p.degrees()[k];
                if d < t {
                    p = p.elevate(k, t - d)?;
                }
            }
            Ok(p)
        })
        .collect()
}

/// One part of the box under check: the equations on it (Bernstein form on the part, common
/// degrees), whether it lies on the box's lower / upper face per axis, and per axis the box's
/// width over the part's (a derivative in the part's unit coordinates times this is one in
/// the box's).
struct Part {
    f: Vec<Bernstein<Rational>>,
    lower: Vec<bool>,
    upper: Vec<bool>,
    ratio: Vec<Rational>,
}

/// Miranda on every part of every face and diagonal dominance over all parts, for
/// `g = A f`.
fn check_parts(parts: &[Part], certificate: &RootCertificate) -> Result<RootCheck, RootRefusal> {
    let a = &certificate.preconditioner;
    let n = a.len();
    let mut gs: Vec<Vec<Bernstein<Rational>>> = Vec::with_capacity(parts.len());
    for part in parts {
        let top = part.f[0].degrees().to_vec();
        // g = A f, coefficient by coefficient (one integer dot product each).
        let size = part.f[0].coeffs().len();
        let g: Vec<Bernstein<Rational>> = a
            .iter()
            .map(|row| {
                let coeffs = (0..size)
                    .map(|c| {
                        <Rational as crate::num::Field>::dot(
                            row,
                            part.f.iter().map(|fj| &fj.coeffs()[c]),
                        )
                    })
                    .collect();
                Bernstein::new(top.clone(), coeffs)
            })
            .collect::<Result<_, _>>()?;
        // Miranda: every coefficient on the face t_i = 0 has the certified sign, on t_i = 1
        // the other.
        let strides: Vec<usize> = (0..n)
            .scan(1, |s, k| {
                let here = *s;
                *s *= top[k] + 1;
                Some(here)
            })
            .collect();
        for (i, gi) in g.iter().enumerate() {
            let negative_below = certificate.lower_face_signs[i] < 0;
            for upper in [false, true] {
                if !(if upper { part.upper[i] } else { part.lower[i] }) {
                    continue;
                }
                let want_negative = negative_below != upper;
                let on_face =
                    |c: usize| (c / strides[i]) % (top[i] + 1) == if upper { top[i] } else { 0 };
                let ok = gi
                    .coeffs()
                    .iter()
                    .enumerate()
                    .filter(|(c, _)| on_face(*c))
                    .all(|(_, x)| {
                        if want_negative {
                            x.is_negative()
                        } else {
                            x.is_positive()
                        }
                    });
                if !ok {
                    return Err(RootRefusal::Miranda {
                        equation: i,
                        upper,
                        negative: want_negative,
                    });
                }
            }
        }
        gs.push(g);
    }
    // Uniqueness: min |∂g_i/∂t_i| > Σ_{k≠i} max |∂g_i/∂t_k| over the coefficients of all
    // parts (in the box's coordinates), the diagonal of one strict sign everywhere.
    for i in 0..n {
        let mut off = vec![Rational::zero(); n];
        let mut diag: Option<Rational> = None;
        let mut diag_sign = 0i8;
        for (part, g) in parts.iter().zip(&gs) {
            let top = part.f[0].degrees();
            let gi = g.get(i).ok_or(RootRefusal::Shape(n))?;
            for (k, &degree) in top.iter().enumerate() {
                if degree == 0 {
                    if k == i {
                        return Err(RootRefusal::Uniqueness { row: i });
                    }
                    continue;
                }
                let d = gi.derivative(k)?;
                if k == i {
                    let sign = if d.coeffs().iter().all(|c| c.is_positive()) {
                        1
                    } else if d.coeffs().iter().all(|c| c.is_negative()) {
                        -1
                    } else {
                        0
                    };
                    if sign == 0 || (diag_sign != 0 && sign != diag_sign) {
                        return Err(RootRefusal::Uniqueness { row: i });
                    }
                    diag_sign = sign;
                    let least = d.coeffs().iter().map(|c| c.abs()).min().unwrap_or_default()
                        * &part.ratio[k];
                    diag = Some(diag.map_or(least.clone(), |m| m.min(least)));
                } else {
                    let most = d.coeffs().iter().map(|c| c.abs()).max().unwrap_or_default()
                        * &part.ratio[k];
                    off[k] = off[k].clone().max(most);
                }
            }
        }
        let off: Rational = off.into_iter().sum();
        if diag.is_none_or(|m| m <= off) {
            return Err(RootRefusal::Uniqueness { row: i });
        }
    }
    Ok(RootCheck {
        unknowns: n,
        on_boundary: false,
    })
}

/// Rigorous `f64` interval enclosures of the Bernstein coefficients of `e` restricted to
/// `sub` (unit coordinates): the coefficients and the box's ends enclosed, de Casteljau's
/// recurrence in outward-rounded intervals (which, by inclusion monotonicity, encloses the
/// exact split at the exact point). `None` when the box is not certainly inside `[0, 1]ⁿ`.
pub(crate) fn enclose_on(
    e: &Bernstein<Rational>,
    sub: &[(Rational, Rational)],
) -> Option<Bernstein<Interval>> {
    let sub: Vec<(Interval, Interval)> = sub
        .iter()
        .map(|(a, b)| (Interval::from_rational(a), Interval::from_rational(b)))
        .collect();
    e.map(Interval::from_rational).restrict(&sub).ok()
}

/// [`check_parts`] on the whole box (one part) in `f64` interval arithmetic. Every
/// enclosure is rigorous: the coefficients and the box's ends are enclosed, arithmetic rounds
/// outward, and de Casteljau's recurrence with an enclosed split point encloses the exact
/// split (inclusion monotonicity). So when every Miranda coefficient's enclosure has the
/// certified strict sign, and the diagonal derivative's least enclosed magnitude exceeds the
/// enclosed sum of the others' largest, the exact check would pass as well. `None` when the
/// enclosures do not decide (wide, or not finite): then the exact check runs.
fn check_interval(
    system: &System,
    sub: &[(Rational, Rational)],
    certificate: &RootCertificate,
) -> Option<RootCheck> {
    use crate::num::Field;
    let n = sub.len();
    let f: Vec<Bernstein<Interval>> = system
        .equations
        .iter()
        .map(|e| enclose_on(e, sub))
        .collect::<Option<_>>()?;
    let top: Vec<usize> = (0..n)
        .map(|k| f.iter().map(|e| e.degrees()[k]).max().unwrap_or(0))
        .collect();
    let f: Vec<Bernstein<Interval>> = f
        .into_iter()
        .map(|mut p| {
            for (k, &t) in top.iter().enumerate() {
                let d = p.degrees()[k];
                if d < t {
                    p = p.elevate(k, t - d).ok()?;
                }
            }
            Some(p)
        })
        .collect::<Option<_>>()?;
    let size = f.first()?.coeffs().len();
    let g: Vec<Bernstein<Interval>> = certificate
        .preconditioner
        .iter()
        .map(|row| {
            let row: Vec<Interval> = row.iter().map(Interval::from_rational).collect();
            let coeffs = (0..size)
                .map(|c| <Interval as Field>::dot(&row, f.iter().map(|fj| &fj.coeffs()[c])))
                .collect();
            Bernstein::new(top.clone(), coeffs).ok()
        })
        .collect::<Option<_>>()?;
    if g.len() != n || certificate.lower_face_signs.len() != n {
        return None;
    }
    let strides: Vec<usize> = (0..n)
        .scan(1, |s, k| {
            let here = *s;
            *s *= top[k] + 1;
            Some(here)
        })
        .collect();
    let negative = |x: &Interval| x.hi < 0.0;
    let positive = |x: &Interval| x.lo > 0.0;
    for (i, gi) in g.iter().enumerate() {
        let negative_below = certificate.lower_face_signs[i] < 0;
        for upper in [false, true] {
            let want_negative = negative_below != upper;
            let face = if upper { top[i] } else { 0 };
            let decided = gi
                .coeffs()
                .iter()
                .enumerate()
                .filter(|(c, _)| (c / strides[i]) % (top[i] + 1) == face)
                .all(|(_, x)| {
                    if want_negative {
                        negative(x)
                    } else {
                        positive(x)
                    }
                });
            if !decided {
                return None;
            }
        }
    }
    for (i, gi) in g.iter().enumerate() {
        let mut diag = f64::INFINITY;
        let mut off = Interval::point(0.0);
        for (k, &degree) in top.iter().enumerate() {
            if degree == 0 {
                if k == i {
                    return None;
                }
                continue;
            }
            let d = gi.derivative(k).ok()?;
            if k == i {
                diag = if d.coeffs().iter().all(positive) {
                    d.coeffs()
                        .iter()
                        .map(|x| x.lo)
                        .fold(f64::INFINITY, f64::min)
                } else if d.coeffs().iter().all(negative) {
                    d.coeffs()
                        .iter()
                        .map(|x| -x.hi)
                        .fold(f64::INFINITY, f64::min)
                } else {
                    return None;
                };
            } else {
                let most = d
                    .coeffs()
                    .iter()
                    .map(|x| x.lo.abs().max(x.hi.abs()))
                    .fold(0.0, f64::max);
                off = <Interval as Field>::add(&off, &Interval::point(most));
            }
        }
        // Decided only when `diag > off.hi` (false for NaN too).
        if diag.partial_cmp(&off.hi) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
    }
    Some(RootCheck {
        unknowns: n,
        on_boundary: false,
    })
}

/// The certificate file of a solution: the system (exactly) and each root's box,
/// preconditioner and face signs.
pub fn solution_certificate(system: &System, solution: &Solution) -> Value {
    certificate_with(system_to_json(system), solution)
}

/// [`solution_certificate`] for a system with B-spline equations (written as given).
pub fn piecewise_solution_certificate(system: &PiecewiseSystem, solution: &Solution) -> Value {
    certificate_with(piecewise_system_to_json(system), solution)
}

fn certificate_with(system: Value, solution: &Solution) -> Value {
    json!({
        "kind": CERTIFICATE_KIND,
        "system": system,
        "roots": solution.roots.iter().map(|r| {
            let mut root = json!({
                "box": r.bounds.iter()
                    .map(|(a, b)| json!([rational_to_string(a), rational_to_string(b)]))
                    .collect::<Vec<_>>(),
                "preconditioner": serde_json::to_value(&r.certificate).unwrap_or_default()["preconditioner"],
                "lower_face_signs": r.certificate.lower_face_signs,
            });
            if let Some(p) = &r.certificate.point {
                root["point"] = json!(p.iter().map(rational_to_string).collect::<Vec<_>>());
            }
            root
        }).collect::<Vec<_>>(),
    })
}

/// Re-checks every root of a certificate file with [`verify_piecewise_root`] (which is
/// [`verify_root`] when no equation has a knot inside the root's box). The outer error is a
/// malformed file; each root has its own outcome.
#[allow(clippy::type_complexity)]
pub fn verify_solution_certificate(
    text: &str,
) -> Result<Vec<Result<RootCheck, RootRefusal>>, SolveError> {
    let v: Value = serde_json::from_str(text).map_err(|e| SolveError::Json(e.to_string()))?;
    let field = |f: &str, why: &str| SolveError::Field {
        field: f.into(),
        why: why.into(),
    };
    if v.get("kind").and_then(Value::as_str) != Some(CERTIFICATE_KIND) {
        return Err(field("kind", &format!("expected {CERTIFICATE_KIND:?}")));
    }
    let system = piecewise_system_from_json(&v["system"].to_string())?;
    let n = system.unknowns();
    let roots = v
        .get("roots")
        .and_then(Value::as_array)
        .ok_or_else(|| field("roots", "missing or not an array"))?;
    let mut out = Vec::with_capacity(roots.len());
    for (r, root) in roots.iter().enumerate() {
        let bounds = parse_box(root.get("box"), &format!("roots[{r}].box"), Some(n))?;
        let certificate = certificate_from_json(root, n)?;
        out.push(verify_piecewise_root(&system, &bounds, &certificate));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(n: i64, d: i64) -> Rational {
        Rational::new(n.into(), d.into())
    }

    /// The filter decides a 2⁻²⁶-wide box around the root of `x² + y² = ½, x = y` (at
    /// `(½, ½)`) with a Newton preconditioner, declines the box moved off the root (where
    /// the exact check refuses), and declines a 2⁻⁵⁰-wide box (too small for `f64`) that the
    /// exact check accepts.
    #[test]
    fn interval_filter_decides_moderate_boxes() {
        // x² + y² − ½ and x − y on [0, 1]², in Bernstein form (degree 2 × 2 and 1 × 1
        // elevated to 2 × 2).
        let circle = Bernstein::new(
            vec![2, 2],
            vec![
                q(-1, 2),
                q(-1, 2),
                q(1, 2),
                q(-1, 2),
                q(-1, 2),
                q(1, 2),
                q(1, 2),
                q(1, 2),
                q(3, 2),
            ],
        )
        .unwrap();
        let diagonal = Bernstein::new(vec![1, 1], vec![q(0, 1), q(1, 1), q(-1, 1), q(0, 1)])
            .unwrap()
            .elevate(0, 1)
            .unwrap()
            .elevate(1, 1)
            .unwrap();
        let system = System::new(vec![(q(0, 1), q(1, 1)); 2], vec![circle, diagonal]).unwrap();
        // J = [[1, 1], [1, −1]] at (½, ½); in unit coordinates of a box of width w,
        // J·w, so A = (J w)⁻¹ = [[1, 1], [1, −1]] / (2w).
        let boxed = |k: u32, shift: i64| -> (RationalBox, RootCertificate) {
            let w = Rational::new(1.into(), num_bigint::BigInt::from(1u64) << k);
            let c = q(1, 2) + &w * q(shift, 1);
            let half = &w / q(2, 1);
            let bounds = vec![(&c - &half, &c + &half), (q(1, 2) - &half, q(1, 2) + &half)];
            let a = &w * q(2, 1);
            let cert = RootCertificate {
                preconditioner: vec![
                    vec![q(1, 1) / &a, q(1, 1) / &a],
                    vec![q(1, 1) / &a, q(-1, 1) / &a],
                ],
                lower_face_signs: vec![-1, -1],
                point: None,
            };
            (bounds, cert)
        };
        let (b, cert) = boxed(26, 0);
        let sub = unit_box(&system.domain, &b).unwrap();
        assert!(check_interval(&system, &sub, &cert).is_some());
        assert!(verify_root_exactly(&system, &b, &cert).is_ok());
        let (b, cert) = boxed(26, 3);
        let sub = unit_box(&system.domain, &b).unwrap();
        assert!(check_interval(&system, &sub, &cert).is_none());
        assert!(verify_root_exactly(&system, &b, &cert).is_err());
        assert!(verify_root(&system, &b, &cert).is_err());
        let (b, cert) = boxed(50, 0);
        let sub = unit_box(&system.domain, &b).unwrap();
        assert!(check_interval(&system, &sub, &cert).is_none());
        assert!(verify_root(&system, &b, &cert).is_ok());
    }
}
