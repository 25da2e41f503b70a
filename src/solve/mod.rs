//! A certified multivariate Bernstein subdivision solver: every root of `n` polynomial
//! equations in `n` unknowns on a box, each reported root with a certificate of existence and
//! uniqueness that [`verify_root`] re-checks independently, and everything that cannot be
//! certified within the limits reported as a [`Cluster`] — never dropped, never counted twice.
//!
//! The method is subdivision in Bernstein form (Sherbrooke and Patrikalakis, "Computation of
//! the solutions of nonlinear polynomial systems", Computer Aided Geometric Design 10(5),
//! 379–405, 1993, doi:10.1016/0167-8396(93)90019-Y; Elber and Kim, "Geometric constraint
//! solver using multivariate rational spline functions", ACM Solid Modeling 2001,
//! doi:10.1145/376957.376958), the solver the swept-volume silhouette paper (Seong, Kim, Kim
//! and Elber, The Visual Computer 22, 2006) runs in IRIT, here with certificates:
//!
//! * **culling** — a box is dropped when some equation's Bernstein coefficients on it are all
//!   of one strict sign (convex-hull property), or when some row of the preconditioned
//!   system `g = A f` below is (any `A` keeps every root of `f` a root of `g`; where the zero
//!   sets cross obliquely this culls what the equations alone cannot);
//! * **existence** — Miranda's theorem on the system preconditioned by an approximate inverse
//!   Jacobian `A` at the box centre (computed in `f64`, applied exactly: any matrix is
//!   allowed): `g = A f` with `g_i < 0` on the face `t_i = 0` and `g_i > 0` on `t_i = 1`
//!   (each decided from the face's Bernstein coefficients) has a zero in the box;
//! * **uniqueness** — the interval Jacobian of `g` on the box (each entry enclosed by the
//!   Bernstein coefficients of the partial derivative) is strictly diagonally dominant, so
//!   every matrix whose rows are gradients taken at any points of the box is non-singular and
//!   `g(x) − g(y) = M (x − y)` (mean value theorem, row by row) rules out a second zero.
//!   A Jacobian *determinant* of one sign on the box would not do: `(eˣ cos y, eˣ sin y)` has
//!   `det J = e²ˣ > 0` and is not injective on `[0,1] × [0, 3π]`;
//! * **projection** (the projection lemma of Mourrain and Pavone, "Subdivision methods for
//!   solving polynomial equations", J. Symbolic Comput. 44, 2009): per unknown, the least and
//!   greatest coefficients of each preconditioned equation along it bound the equation by two
//!   1-D control polygons, and every root lies where their convex hull meets zero; a box is
//!   dropped when those ranges, intersected over the equations, leave none. (Cutting boxes
//!   down to the ranges, as Mourrain and Pavone do, was measured here and left out: it
//!   halved the boxes of the moving-eye events but made the exact path's numbers longer and
//!   the interval path's curve tracing leave more clusters.)
//! * **splits** at rational points, moved off ½ when the split plane might hold a root (no
//!   equation and no row of `A f` of one strict sign on it), so that certified boxes meet
//!   only on root-free planes and no root is counted twice.
//! * **roots on split planes** — touching depth-limit clusters are tried once more as one
//!   box (their hull, inflated), certified exactly, and kept only when that box meets no
//!   other root's or cluster's box.
//! * **roots on the domain's boundary** ([`SolveOptions::boundary`]) — no box inside the
//!   domain passes Miranda's test around a root on one of its faces (the signs cannot be
//!   strict there). The clusters such a root leaves are tried once more as one box reaching
//!   across the face, the equations extended beyond the domain as the polynomials they are
//!   ([`Bernstein::on_box`]); once certified and refined, the simplest rational point of the
//!   refined box on the crossed faces is tried as the root, and when every equation
//!   vanishes there exactly, it is the box's one root and lies in the domain: the root is
//!   reported with that point ([`RootCertificate::point`]), which [`verify_root`] re-checks.
//! * **singular roots in bounded work** — every box is subdivided to 5 levels first; the
//!   boxes still undecided there are grouped by touching, and each group goes on alone, down
//!   to the depth limit, within its own budget (2,048 boxes and 512 more per root it
//!   certifies). Around a tangential root or along a curve of roots the undecided boxes
//!   multiply at every level; such a group is given up as one [`ClusterReason::Singular`]
//!   cluster (the hull of what it left undecided) instead of taking every box of the solve.
//!   The filtered path first redoes a small group (up to 32 boxes) exactly within 256 boxes,
//!   since rounding alone may be what stopped it, and decides each of the interval path's
//!   undecided boxes at the depth limit in integers over one denominator.
//!
//! Equations may be tensor B-spline fields ([`PiecewiseSystem`], [`solve_piecewise`]): their
//! knots cut the box into cells, and the subdivision's boxes cross the knot planes freely,
//! each cut into parts (one per cell) over which culling and both tests are taken, so a root
//! on a knot plane is found once like any other; [`verify_piecewise_root`] re-checks a root
//! part by part.
//!
//! One equation fewer than unknowns defines a curve: [`trace`] subdivides into boxes where a
//! component of the tangent has one strict sign, certifies the curve's crossings of every
//! split plane with the square solver above, and links the arcs into components (open or
//! closed, ending on the domain's faces or in clusters); [`verify_curves`] re-checks the
//! result. [`trace_piecewise`] and [`verify_piecewise_curves`] do the same for B-spline
//! equations, splitting exactly at knot planes where a field is only C⁰. Equations may be rational functions (the numerator, once the denominator is
//! certified to keep its sign on the box).
//!
//! Both paths run the same subdivision generically over the coefficient field: the
//! reference path in exact rationals ([`Path::Exact`]), the fast one in outward-rounded `f64`
//! intervals ([`Path::Fast`]: a decision the rounding cannot make is not made, and what is
//! left is reported as a cluster marked uncertain), and [`Path::Filtered`] runs the fast path
//! and redoes its uncertain clusters exactly.

mod check;
mod curve;
mod curve_check;
mod input;
mod piecewise;
mod subdivision;

pub(crate) use check::enclose_on;
pub use check::{
    piecewise_solution_certificate, solution_certificate, verify_piecewise_root, verify_root,
    verify_root_exactly, verify_solution_certificate, RootCheck, RootRefusal, CERTIFICATE_KIND,
};
pub use curve::{
    extreme_system, plane_system, trace, trace_piecewise, Arc, Component, CurveEnd, CurveOptions,
    CurvePoint, Curves, Extreme,
};
pub use curve_check::{
    curve_certificate, piecewise_curve_certificate, verify_curve_certificate, verify_curves,
    verify_piecewise_curves, CurveCheck, CurveRefusal, CURVE_CERTIFICATE_KIND,
};
pub use input::{
    piecewise_system_from_json, piecewise_system_to_json, system_from_json, system_to_json,
};
pub use piecewise::{solve_piecewise, Equation, PiecewiseSystem, MAX_CELLS};
pub use subdivision::solve;

use crate::bernstein::{Bernstein, BernsteinError, Limits};
use crate::num::Rational;
use crate::Path;
use serde::Serialize;
use thiserror::Error;

/// The most unknowns a system may have.
pub const MAX_UNKNOWNS: usize = 6;
/// The highest degree per axis of an equation.
pub const MAX_DEGREE: usize = 24;

/// A polynomial system on a box: `equations[i]` in tensor Bernstein form on `domain`
/// (coordinate `x_k = a_k + (b_k − a_k) t_k`, `t ∈ [0,1]ⁿ`).
#[derive(Clone, Debug, PartialEq)]
pub struct System {
    /// Per unknown, `(a_k, b_k)` with `a_k < b_k`.
    pub domain: Vec<(Rational, Rational)>,
    /// The equations `f_i = 0`, each with `domain.len()` variables.
    pub equations: Vec<Bernstein<Rational>>,
}

impl System {
    /// Checks the shape: 1…[`MAX_UNKNOWNS`] unknowns, non-empty intervals, every equation in
    /// all the unknowns with degrees up to [`MAX_DEGREE`].
    pub fn new(
        domain: Vec<(Rational, Rational)>,
        equations: Vec<Bernstein<Rational>>,
    ) -> Result<System, SolveError> {
        let n = domain.len();
        check_domain(&domain)?;
        for (i, e) in equations.iter().enumerate() {
            if e.dim() != n {
                return Err(SolveError::Equation {
                    equation: i,
                    why: format!("has {} variables, the box {n}", e.dim()),
                });
            }
            if let Some(&d) = e.degrees().iter().find(|&&d| d > MAX_DEGREE) {
                return Err(SolveError::Equation {
                    equation: i,
                    why: format!("degree {d} exceeds the limit of {MAX_DEGREE}"),
                });
            }
        }
        Ok(System { domain, equations })
    }

    /// The number of unknowns.
    pub fn unknowns(&self) -> usize {
        self.domain.len()
    }

    /// Maps unit-box parameters to the domain: `a + (b − a) t` per axis.
    pub fn to_domain(&self, t: &[Rational]) -> Vec<Rational> {
        self.domain
            .iter()
            .zip(t)
            .map(|((a, b), t)| crate::num::rational::lerp(a, b, t))
            .collect()
    }

    /// The unit-box parameter of the domain coordinate `x` on `axis` ([`unit_coordinate`]).
    pub(crate) fn to_unit(&self, axis: usize, x: &Rational) -> Rational {
        unit_coordinate(&self.domain, axis, x)
    }

    /// A box of the domain in unit-box coordinates ([`unit_bounds`]).
    pub(crate) fn unit_bounds(&self, bounds: &RationalBox) -> RationalBox {
        unit_bounds(&self.domain, bounds)
    }

    /// The domain box of the unit-box bounds `lo`, `hi` ([`domain_bounds`]).
    pub(crate) fn domain_box(&self, lo: &[Rational], hi: &[Rational]) -> RationalBox {
        domain_bounds(&self.domain, lo, hi)
    }
}

/// The unit-box parameter of the coordinate `x` on `axis` of `domain`: `(x − a)/(b − a)`.
pub(crate) fn unit_coordinate(
    domain: &[(Rational, Rational)],
    axis: usize,
    x: &Rational,
) -> Rational {
    let (a, b) = &domain[axis];
    if num_traits::Zero::is_zero(a) && num_traits::One::is_one(b) {
        return x.clone();
    }
    (x - a) / (b - a)
}

/// A box of `domain` (per axis `(lo, hi)`) in unit-box coordinates.
pub(crate) fn unit_bounds(domain: &[(Rational, Rational)], bounds: &RationalBox) -> RationalBox {
    bounds
        .iter()
        .enumerate()
        .map(|(k, (lo, hi))| {
            (
                unit_coordinate(domain, k, lo),
                unit_coordinate(domain, k, hi),
            )
        })
        .collect()
}

/// The box of `domain` whose unit-box bounds are `lo`, `hi`: `a + (b − a) t` per axis.
pub(crate) fn domain_bounds(
    domain: &[(Rational, Rational)],
    lo: &[Rational],
    hi: &[Rational],
) -> RationalBox {
    domain
        .iter()
        .zip(lo.iter().zip(hi))
        .map(|((a, b), (l, h))| {
            (
                crate::num::rational::lerp(a, b, l),
                crate::num::rational::lerp(a, b, h),
            )
        })
        .collect()
}

/// 1…[`MAX_UNKNOWNS`] unknowns, each interval non-empty.
fn check_domain(domain: &[(Rational, Rational)]) -> Result<(), SolveError> {
    let n = domain.len();
    if n == 0 || n > MAX_UNKNOWNS {
        return Err(SolveError::Unknowns(n));
    }
    match domain.iter().position(|(a, b)| a >= b) {
        Some(axis) => Err(SolveError::EmptyBox { axis }),
        None => Ok(()),
    }
}

/// As many equations as unknowns.
fn check_square(equations: usize, unknowns: usize) -> Result<(), SolveError> {
    if equations == unknowns {
        Ok(())
    } else {
        Err(SolveError::NotSquare {
            equations,
            unknowns,
        })
    }
}

/// Options of [`solve`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct SolveOptions {
    /// The arithmetic ([`Path::Filtered`] by default).
    pub path: Path,
    /// Depth, box-count and time limits; the depth counts levels per side (a box at depth
    /// `k` has been split `k` times along each of its `n` axes, `k·n` splits in all).
    pub limits: Limits,
    /// Certified roots are refined to boxes of at most this width relative to the domain's
    /// side on every axis (Newton's method in `f64`, then the same certificate on the small
    /// box around its result; a box that cannot be certified that small keeps the smallest
    /// width that could). `0` keeps the first certified box. The fast path stops where
    /// interval rounding does (about `1e-13`); the filtered path decides that last box in
    /// exact integers and reaches `1e-15`.
    pub tolerance: f64,
    /// Certify simple roots on the domain's boundary (`true` by default): the clusters a
    /// boundary root leaves are tried once more as one box reaching across the boundary, and
    /// a root certified there replaces them when it lies inside the domain, or when a
    /// rational point of the box and the domain is an exact zero of every equation (that
    /// point is the root, on the boundary: [`RootCertificate::point`]). With B-spline
    /// equations ([`solve_piecewise`]) the box's part inside the domain must lie in one knot
    /// span of every B-spline (each is extended as that span's polynomial). Otherwise the
    /// clusters stay.
    pub boundary: bool,
}

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            path: Path::Filtered,
            limits: Limits::new().with_max_depth(40).with_max_boxes(200_000),
            tolerance: 1e-15,
            boundary: true,
        }
    }
}

crate::choice::setters!(SolveOptions {
    with_path => path: Path,
    with_limits => limits: Limits,
    with_tolerance => tolerance: f64,
    with_boundary => boundary: bool,
});

/// A box of the domain with rational bounds.
pub type RationalBox = Vec<(Rational, Rational)>;

/// The evidence that a box holds exactly one root: everything [`verify_root`] needs.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RootCertificate {
    /// The preconditioner `A` (row-major, `n × n`, exact): the Miranda test is on `g = A f`.
    #[serde(serialize_with = "input::serialize_matrix")]
    pub preconditioner: Vec<Vec<Rational>>,
    /// Per `i`, the sign of `g_i` on the face `t_i = 0` (`-1` or `1`; the face `t_i = 1` has
    /// the other sign).
    pub lower_face_signs: Vec<i8>,
    /// For a root on the domain's boundary: the root itself (domain coordinates), a point of
    /// the domain and of the box where every equation vanishes exactly. The box then reaches
    /// across the boundary (the equations extend beyond the domain as polynomials; a
    /// B-spline as the polynomial of the one knot span holding the box's part inside the
    /// domain), and the root it holds is this point, so it lies in the domain. `None` for a
    /// box inside it.
    #[serde(skip)]
    pub point: Option<Vec<Rational>>,
}

/// A certified root: exactly one zero of the system lies in `bounds` (in its interior).
/// A root on the domain's boundary has a box that reaches across it, and its certificate
/// names the root exactly ([`RootCertificate::point`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Root {
    /// The box, in domain coordinates (inside the domain unless the certificate has a point).
    pub bounds: RationalBox,
    /// Its centre, rounded to `f64`.
    pub approx: Vec<f64>,
    /// A bound on `|x_k − approx_k|` for the root `x` (the half-width plus the centre's
    /// rounding).
    pub error_bound: f64,
    /// The evidence.
    pub certificate: RootCertificate,
}

/// Why a box could not be certified.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ClusterReason {
    /// The depth limit was reached with neither culling nor a certificate (a tangential or
    /// multiple root, roots closer than the box width, or a root on a box face).
    DepthLimit,
    /// The box touches the domain's boundary and cannot be split further without leaving it
    /// (a root on the domain's boundary that [`SolveOptions::boundary`] did not certify: not
    /// at a rational point found as the simplest in its box, singular, also on an interior
    /// knot plane of a B-spline equation, or the stage off).
    DomainBoundary,
    /// The box or time limit stopped the subdivision here.
    Budget,
    /// Fast path only: rounding left a decision open in this box down to the depth limit.
    Uncertain,
    /// The hull of a group of touching boxes that stayed undecided below the coarse levels
    /// and did not resolve within the group's box budget (or, on the filtered path, too many
    /// of the interval path's undecided leaves to redo exactly): around a multiple or
    /// tangential root the undecided boxes multiply at every level. One such root is one
    /// cluster, quickly, rather than thousands of depth-limit boxes.
    Singular,
}

/// A box that may hold roots (any number) but was not certified.
#[derive(Clone, Debug, PartialEq)]
pub struct Cluster {
    /// The box, in domain coordinates.
    pub bounds: RationalBox,
    /// Why it was not certified.
    pub reason: ClusterReason,
    /// Per equation, a certified upper bound of `|f_i|` on the box.
    pub max_abs_f: Vec<f64>,
}

/// The result of [`solve`]: every root of the system in the domain lies in exactly one
/// root's box or in one or more clusters' boxes.
#[derive(Clone, Debug, PartialEq)]
pub struct Solution {
    /// Certified roots, each with exactly one zero.
    pub roots: Vec<Root>,
    /// What could not be certified.
    pub clusters: Vec<Cluster>,
    /// Boxes examined.
    pub boxes_visited: usize,
    /// The path that ran.
    pub path: Path,
}

/// Errors of the solver and its input.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SolveError {
    /// The system file is not JSON.
    #[error("not valid JSON: {0}")]
    Json(String),
    /// A field of the system file is missing or malformed.
    #[error("field `{field}`: {why}")]
    Field {
        /// The field, e.g. `equations[1].terms[3]`.
        field: String,
        /// What is wrong with it.
        why: String,
    },
    /// Too few or too many unknowns.
    #[error("{0} unknowns: the solver takes 1 to {MAX_UNKNOWNS}")]
    Unknowns(usize),
    /// A box interval is empty or inverted.
    #[error("box interval {axis} is empty or inverted (a ≥ b)")]
    EmptyBox {
        /// The axis.
        axis: usize,
    },
    /// An equation does not fit the system.
    #[error("equation {equation}: {why}")]
    Equation {
        /// The equation.
        equation: usize,
        /// What is wrong.
        why: String,
    },
    /// The number of equations is not the number of unknowns.
    #[error("{equations} equations in {unknowns} unknowns: a zero-dimensional system needs as many equations as unknowns (n − 1 equations are traced as a curve: `solve --curves`, `solve::trace`)")]
    NotSquare {
        /// Equations given.
        equations: usize,
        /// Unknowns.
        unknowns: usize,
    },
    /// A curve needs one equation fewer than unknowns (and at least two unknowns).
    #[error("{equations} equations in {unknowns} unknowns: a curve needs n − 1 equations in n ≥ 2 unknowns")]
    NotCurve {
        /// Equations given.
        equations: usize,
        /// Unknowns.
        unknowns: usize,
    },
    /// The Bernstein kernel refused an operation.
    #[error("Bernstein kernel: {0}")]
    Bernstein(#[from] BernsteinError),
}

/// Widens the hull `lo..hi` of clusters at the boundary of the box `bounds` (the same
/// coordinates) into a box reaching across it: mirrored across each face of `bounds` it
/// touches (a root on that face then sits mid-box), grown by a quarter of its width on the
/// other sides.
pub(crate) fn reach_across(
    lo: &mut [Rational],
    hi: &mut [Rational],
    bounds: &[(Rational, Rational)],
) {
    let quarter = Rational::new(1.into(), 4.into());
    for (k, (a, b)) in bounds.iter().enumerate() {
        let w = (&hi[k] - &lo[k]) * &quarter;
        (lo[k], hi[k]) = if &lo[k] == a {
            (a - (&hi[k] - a) - &w, &hi[k] + &w)
        } else if &hi[k] == b {
            (&lo[k] - &w, b + (b - &lo[k]) + &w)
        } else {
            (&lo[k] - &w, &hi[k] + &w)
        };
    }
}

/// Where the one root of a certified, refined box near the domain's boundary lies (`refined`
/// and `domain` in domain coordinates): `None` when the box lies beyond a face (outside the
/// domain), `Some(None)` when it lies inside the domain, else `Some(Some(point))` with the
/// candidate for the root, on the boundary: the crossed faces' coordinates and, on the other
/// axes, the simplest rationals of the box's sides
/// ([`simplest_between`](crate::num::rational::simplest_between)).
pub(crate) fn boundary_candidate(
    domain: &[(Rational, Rational)],
    refined: &RationalBox,
) -> Option<Option<Vec<Rational>>> {
    let pairs = || refined.iter().zip(domain);
    if pairs().any(|((lo, hi), (a, b))| hi <= a || lo >= b) {
        return None;
    }
    if pairs().all(|((lo, hi), (a, b))| lo >= a && hi <= b) {
        return Some(None);
    }
    Some(Some(
        pairs()
            .map(|((lo, hi), (a, b))| {
                if lo < a {
                    a.clone()
                } else if hi > b {
                    b.clone()
                } else {
                    crate::num::rational::simplest_between(lo, hi)
                }
            })
            .collect(),
    ))
}

/// Connected groups of touching closed boxes (each `(lo, hi)` per axis), by a sweep along
/// axis 0 and union–find: `O(m log m)` plus the pairs whose axis-0 extents overlap.
pub(crate) fn touching_groups(boxes: &[(&[Rational], &[Rational])]) -> Vec<Vec<usize>> {
    fn find(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let m = boxes.len();
    let mut parent: Vec<usize> = (0..m).collect();
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&a, &b| boxes[a].0[0].cmp(&boxes[b].0[0]));
    let mut active: Vec<usize> = Vec::new();
    for &i in &order {
        let (lo, hi) = boxes[i];
        active.retain(|&j| boxes[j].1[0] >= lo[0]);
        for &j in &active {
            let (olo, ohi) = boxes[j];
            if lo.iter().zip(ohi).all(|(a, b)| a <= b) && olo.iter().zip(hi).all(|(a, b)| a <= b) {
                let (ri, rj) = (find(&mut parent, i), find(&mut parent, j));
                parent[ri] = rj;
            }
        }
        active.push(i);
    }
    let mut index = vec![usize::MAX; m];
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for i in 0..m {
        let r = find(&mut parent, i);
        if index[r] == usize::MAX {
            index[r] = groups.len();
            groups.push(Vec::new());
        }
        groups[index[r]].push(i);
    }
    groups
}
