//! Rulings: the envelope's silhouette from a fixed eye when the sweep is invariant in `t`
//! (module `events`: `F̃ = φ(t)·F̂(u, v)` and `(G̃/λ)_t` vanishes wherever `F̂` does).
//!
//! Then `Z₁ = {F̃ = G̃ = 0}` is the union of the rulings `{(u₀, v₀)} × [a, b]` over the points
//! of `{F̂ = Ĝ = 0}` in the patch's square, `Ĝ = G̃(·, ·, a)`: on `F̂ = 0`,
//! `G̃(u, v, t) = G̃(u, v, a)·λ(t)/λ(a)` with `λ` of one strict sign. Those points are solved in
//! `(u, v)` by the certified solver, each ruling's point a certified root
//! ([`RulingEvidence::Root`]); every ruling is a type-3 component from `t = a` to `t = b`
//! with no `t`-extreme point (`H` is the Jacobian of `(F̂, Ĝ)`, not zero at a simple root).
//!
//! Tracing `Z₁` in `(u, v, t)` would find the same lines more slowly, and where the contour
//! touches the characteristic curve — the eye on the extension of the envelope, where the
//! cylinder's two contour lines merge into one — `Z₁` is singular along a whole ruling and
//! the tracer subdivides along it until its time limit. Here such a point is a tangential
//! root of `F̂ = Ĝ = 0`: the solve stops at [`RULING_DEPTH`] with a small cluster, and inside
//! it the critical point of `Ĝ` along `F̂ = 0` (a certified simple root of `F̂ = H = 0`,
//! `H = F̂_u Ĝ_v − F̂_v Ĝ_u`) with a certified bound on `|Ĝ|` there is reported as a
//! tangential ruling ([`RulingEvidence::Tangent`]); the cluster stays listed, since within
//! its box the merged line may also be two lines or none.
//!
//! The square is widened by [`RULING_MARGIN`] on every side (the polynomials extend beyond
//! it), so that a ruling exactly on a patch border or corner — common for eyes in a plane of
//! symmetry — is an inner root; the roots and clusters whose boxes meet the square are
//! kept, and a ruling found by two neighbouring patches is reported once.

use super::corners::reframed;
use super::equations::MotionForms;
use super::events::{cofactor_scales, minor, t_invariant};
use super::silhouette::unit_intervals;
use super::SweepError;
use crate::bernstein::Bernstein;
use crate::num::{Interval, Rational};
use crate::solve::{solve, Cluster, Root, SolveOptions, System};
use crate::Path;
use num_traits::{One, Signed, Zero};

type B = Bernstein<Rational>;

/// The depth per side at which the ruling solve stops subdividing (boxes of about `1e-9` of
/// the square): a tangential root leaves a cluster this small instead of a subdivision that
/// doubles its box count every two levels.
pub const RULING_DEPTH: u32 = 30;

/// The margin by which the patch's square is widened for the ruling solve (`2⁻²⁰`).
pub fn ruling_margin() -> Rational {
    Rational::new(1.into(), (1i64 << 20).into())
}

/// [`ruling_margin`] as a number (documentation and reports).
pub const RULING_MARGIN: f64 = 1.0 / (1u64 << 20) as f64;

/// Why a ruling is on the silhouette.
#[derive(Clone, Debug, PartialEq)]
pub enum RulingEvidence {
    /// A certified simple root of `F̂ = Ĝ = 0` in `(u, v)` (domain the widened square).
    Root(Root),
    /// A tangency: the solve of `F̂ = Ĝ = 0` left the cluster `cluster`, which holds the
    /// certified simple root `critical` of `F̂ = H = 0` (the one point of its box where `Ĝ`
    /// is critical along `F̂ = 0`), and `|Ĝ| ≤ g_bound` on `critical`'s box (`Ĝ` scaled to
    /// its largest coefficient on the widened square being 1). Within the cluster the silhouette is
    /// the merged line, or two lines, or none.
    Tangent {
        /// The root of `F̂ = H = 0`.
        critical: Root,
        /// A certified bound on `|Ĝ|` over `critical`'s box, relative to `Ĝ`'s largest
        /// coefficient.
        g_bound: f64,
        /// The unresolved box of the solve of `F̂ = Ĝ = 0`.
        cluster: Cluster,
    },
}

/// A ruling of the envelope: the silhouette line `{(u₀, v₀)} × [a, b]` of a sweep invariant
/// in `t` (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Ruling {
    /// The surface.
    pub surface: usize,
    /// The patch.
    pub patch: usize,
    /// The evidence for `(u₀, v₀)`.
    pub evidence: RulingEvidence,
    /// The component drawn along it ([`Silhouettes::components`](super::Silhouettes)).
    pub component: usize,
}

impl Ruling {
    /// The `(u, v)` point the component is drawn through: the centre of the root's box,
    /// clamped to the patch's square (the box meets it; a root on a patch border may lie a
    /// rounding outside).
    pub fn uv(&self) -> [f64; 2] {
        let root = match &self.evidence {
            RulingEvidence::Root(r) => r,
            RulingEvidence::Tangent { critical, .. } => critical,
        };
        [0, 1].map(|k| root.approx[k].clamp(0.0, 1.0))
    }

    /// The box of `(u, v)` the ruling passes through (the root's, domain coordinates).
    pub fn bounds(&self) -> &[(Rational, Rational)] {
        match &self.evidence {
            RulingEvidence::Root(r) => &r.bounds,
            RulingEvidence::Tangent { critical, .. } => &critical.bounds,
        }
    }
}

/// The polynomials of the ruling solve of one patch, on the widened square.
pub(super) struct RulingSystems {
    /// `(F̂, Ĝ)`.
    pub(super) points: System,
    /// `(F̂, H)`, `H = F̂_u Ĝ_v − F̂_v Ĝ_u`.
    pub(super) critical: System,
    /// `Ĝ` in intervals, scaled to its largest coefficient being 1.
    g_unit: Bernstein<Interval>,
}

/// `p` on `[−m, 1 + m]` along every axis in `axes`, reparametrised to `[0, 1]` (de Casteljau
/// extrapolates exactly).
pub(super) fn widen(p: &B, axes: &[usize], m: &Rational) -> Result<B, SweepError> {
    let (lo, hi) = (-m, Rational::one() + m);
    let mut q = p.clone();
    for &axis in axes {
        q = reframed(&q, axis, &lo, &hi)?;
    }
    Ok(q)
}

/// The ruling systems of a patch whose sweep is invariant in `t`, or `None` when it is not:
/// decided on `F̃` itself (`f_full`) and `g` (the `G̃` in use), solved with `f`, `F̃` with the
/// characteristic faces' factors divided out (the silhouettes along those edges are traced
/// on their own, module `edges`).
pub(super) fn ruling_systems(
    forms: &MotionForms,
    f_full: &B,
    f: &B,
    g: &B,
) -> Result<Option<RulingSystems>, SweepError> {
    let (f4, g4) = (f_full.embed(&[0, 1, 2], 4)?, g.embed(&[0, 1, 2], 4)?);
    if !t_invariant(&f4, &g4, &cofactor_scales(forms)?)? {
        return Ok(None);
    }
    let m = ruling_margin();
    // `F̃(·, ·, a) = φ(a)·F̂` with `φ(a) ≠ 0`, and `Ĝ = G̃(·, ·, a)`.
    let f_hat = widen(&f.face(2, false)?, &[0, 1], &m)?;
    let g_hat = widen(&g.face(2, false)?, &[0, 1], &m)?;
    let h = minor(&f_hat, &g_hat, 0, 1)?;
    let domain = vec![(-&m, Rational::one() + &m); 2];
    let largest = g_hat
        .coeffs()
        .iter()
        .map(|c| c.abs())
        .max()
        .unwrap_or_else(Rational::zero);
    let g_unit = if largest.is_zero() {
        g_hat.map(Interval::from_rational)
    } else {
        g_hat.map(|c| Interval::from_rational(&(c / &largest)))
    };
    Ok(Some(RulingSystems {
        points: System::new(domain.clone(), vec![f_hat.clone(), g_hat])?,
        critical: System::new(domain, vec![f_hat, h])?,
        g_unit,
    }))
}

/// Whether a box of the widened square meets the patch's square `[0, 1]²`.
pub(super) fn meets_square(bounds: &[(Rational, Rational)]) -> bool {
    bounds
        .iter()
        .all(|(lo, hi)| *lo <= Rational::one() && !hi.is_negative())
}

/// Whether two boxes intersect.
pub(super) fn overlap(a: &[(Rational, Rational)], b: &[(Rational, Rational)]) -> bool {
    a.iter().zip(b).all(|(x, y)| x.0 <= y.1 && y.0 <= x.1)
}

impl RulingSystems {
    /// The certified bound of `|Ĝ|` (relative) over `bounds` (domain coordinates).
    pub(super) fn g_bound(&self, bounds: &[(Rational, Rational)]) -> f64 {
        match self.g_unit.restrict(&unit_intervals(&self.points, bounds)) {
            Ok(part) => part
                .coeffs()
                .iter()
                .map(|c| c.lo.abs().max(c.hi.abs()))
                .fold(0.0, f64::max),
            Err(_) => f64::INFINITY,
        }
    }
}

/// The rulings' points of one patch: certified roots, tangencies, and the clusters left
/// (both meeting the square). `limits` are the patch's box and time limits (the depth is
/// [`RULING_DEPTH`]).
pub(super) fn solve_rulings(
    sys: &RulingSystems,
    path: Path,
    limits: crate::bernstein::Limits,
) -> Result<(Vec<RulingEvidence>, Vec<Cluster>), SweepError> {
    let opts = SolveOptions::new()
        .with_path(path)
        .with_limits(limits.with_max_depth(RULING_DEPTH))
        .with_boundary(false);
    let found = solve(&sys.points, &opts)?;
    let mut out: Vec<RulingEvidence> = found
        .roots
        .into_iter()
        .filter(|r| meets_square(&r.bounds))
        .map(RulingEvidence::Root)
        .collect();
    let clusters: Vec<Cluster> = found
        .clusters
        .into_iter()
        .filter(|c| meets_square(&c.bounds))
        .collect();
    if !clusters.is_empty() {
        let critical = solve(&sys.critical, &opts)?;
        for c in &clusters {
            let inside: Vec<&Root> = critical
                .roots
                .iter()
                .filter(|r| overlap(&r.bounds, &c.bounds))
                .collect();
            if let [root] = inside[..] {
                out.push(RulingEvidence::Tangent {
                    critical: root.clone(),
                    g_bound: sys.g_bound(&root.bounds),
                    cluster: c.clone(),
                });
            }
        }
    }
    Ok((out, clusters))
}

/// The `t` samples of a ruling: `n` equal steps of `[a, b]` (as unit parameters `s`).
pub(super) fn ruling_steps(n: usize) -> Vec<f64> {
    (0..=n).map(|k| k as f64 / n as f64).collect()
}

/// A certified bound on the 3-D distance between a ruling's chords and the ruling: per step
/// `[s_k, s_{k+1}]`, the diagonal of the bounding box of the moved patch's control points
/// over the ruling's `(u, v)` box (in unit coordinates of the widened square) times that step
/// (`image` the moved patch on the widened square); the largest.
pub(super) fn ruling_chord_bound(
    image: &[Bernstein<Interval>],
    points: &System,
    bounds: &[(Rational, Rational)],
    s: &[f64],
) -> f64 {
    let uv = unit_intervals(points, bounds);
    s.windows(2)
        .map(|w| {
            let mut sub = uv.clone();
            sub.push((Interval::point(w[0]), Interval::point(w[1])));
            super::silhouette::image_box_diagonal(image, &sub)
        })
        .fold(0.0, f64::max)
}
