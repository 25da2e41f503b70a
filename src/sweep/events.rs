//! The moving eye of Section 4: the eye follows a polynomial path `P(r)`, `r ∈ [r₀, r₁]`, and
//! the silhouette `{F = 0, G(·, r) = 0}` changes with `r`. Its topology changes only at
//! critical events, found once by the certified solver.
//!
//! `F` does not depend on `r` (eq. 4), and `G` is affine in the eye:
//! `G̃(u, v, s, r) = G̃₀(u, v, s) − Σᵢ Pᵢ(r) Kᵢ(u, v, s)` with `G̃₀` the contour equation for
//! the eye at the origin and `Kᵢ = δ w (cof(M̂) N_h)ᵢ` (module `equations`). The silhouettes of
//! all eye positions form the 2-manifold `M = {F = 0, G = 0}` in `(u, v, t, r)`.
//!
//! **Correctness beyond the paper.** Section 4.1 takes the `r`-extreme points of `M` from
//! `G = G_u = G_v = G_t = 0` (eqs. 6–9), kept where `F = 0` too. That asks `G`'s own gradient to
//! point along `r`; but `M` is cut by two equations, and `r` restricted to `M` is critical
//! where `e_r` lies in the span of `∇F` and `∇G` (Lagrange): `α ∇F + β ∇G = e_r`, so the
//! `(u, v, t)` parts of the two gradients are parallel — the silhouette curve of that eye
//! position is singular (its tangent `∇F × ∇G` vanishes). The paper's condition is the case
//! `α = 0` only; generically its solutions do not lie on `F = 0` at all. So the events here are:
//!
//! * **interior** ([`EventKind::Interior`]): `F = G = 0` and the minors
//!   `F_u G_v − F_v G_u = F_u G_t − F_t G_u = 0`, four equations in `(u, v, t, r)`; where
//!   `(F_u, G_u) ≠ (0, 0)` (certified on the root's box, [`Event::pivot`]) the third minor
//!   vanishes too, so the root is a true event;
//! * **on a face** of the patch's `(u, v, t)` box ([`EventKind::Face`]; `t` faces are the
//!   start and end positions): the curve `M ∩ face` has an `r`-extreme — `F = G = 0` and the
//!   minor in the face's two free parameters, three equations;
//! * **on an edge** ([`EventKind::Edge`]): `M` meets the edge, where a component's end runs
//!   over a corner of the domain — `F = G = 0` in the edge's parameter and `r`.
//!
//! * **along a characteristic patch edge** ([`EventKind::AlongEdge`]; module `edges`): where
//!   the silhouette runs along a patch edge, `F̃` has that face's factor (divided out for the
//!   systems above) and the silhouettes of all eye positions there form the surface
//!   `{G̃(w, t, r) = 0}` over the face; its `r`-critical points are `G̃ = G̃_w = G̃_t = 0`
//!   inside the face, `G̃ = G̃_t = 0` or `G̃ = G̃_w = 0` on its ends in `w` or `t`, and `G̃ = 0`
//!   at its corners (one equation: the paper's condition is right for a single equation).
//!
//! **Sweeps invariant in `t`** (`t_invariant`): the characteristic curve is the same curve
//! `F̂(u, v) = 0` of the patch at every time (`F̃ = φ(t)·F̂`), and so is the contour on it from
//! any eye (`G̃/λ(t)` does not change along it). A translation along a fixed direction (the
//! cylinder) and a similarity with a fixed rotation moving along a line (the cone) are such
//! sweeps. Every system with `t` among its unknowns then has whole `t`-segments of roots: the
//! silhouette is made of rulings, and an event moves a whole ruling at once (the cylinder's
//! two contour lines merge along their length when the eye enters it). Those systems are not
//! solved (their subdivision would run to its limits along the segments); each segment's ends
//! are the isolated roots of the systems on the faces and edges at `t = a` and `t = b`, which
//! are.
//!
//! **Factors without a zero.** Rational parametrisations give `F̃` and `G̃` factors in one
//! parameter that keep one strict sign on its interval — a quarter circle's weight `1 + u²`,
//! a Cayley rotation's denominator `(1 + t²)ᵏ`. They change no zero set on the box and are
//! divided out before the systems are built
//! ([`Bernstein::without_signed_contents`](crate::bernstein::Bernstein::without_signed_contents)):
//! where `F̃ = a·F̂` and `G̃ = b·Ĝ` with `a, b ≠ 0`, the minors of `F̃, G̃` are `a·b` times
//! those of `F̂, Ĝ` wherever `F̂ = Ĝ = 0`, so every system keeps its roots. The turning
//! ellipsoid's interior systems drop from degrees `[9, 12, 14, 1]` to `[5, 6, 4, 1]`.
//!
//! Faces and edges at `u, v ∈ {0, 1}` are the patch's borders: on a closed surface made of
//! several patches, events there mark where a component crosses into the neighbouring patch
//! at a tangency, not a change of the whole silhouette's topology; they are kept and labelled.
//!
//! **Poles.** On a collapsed edge (a sphere's pole, its factor divided out of the normal) the
//! surface point and the normal's direction are the same for every value `w` of the other
//! parameter, so on that face `F̃ = λ(w)·φ(t)` and `G̃ = μ(w)·γ(t, r)`: the face system has
//! whole `w`-segments of roots over `φ = γ = 0` (the eye's silhouette passing the pole), and
//! is left out when that separation is proved exactly; the edge systems at the face's ends
//! solve `φ = γ = 0` in `(t, r)`. A root of the interior system on the pole is matched with
//! those events ([`BorderRoot`]).

use super::equations::{equations_with, motion_forms, on_interval, Equations, MotionForms};
use super::{Eye, Scene, SweepError};
use crate::bernstein::{Bernstein, ScaledBernstein};
use crate::num::Rational;
use crate::solve::{
    solve, verify_root, Cluster, Root, RootCheck, RootRefusal, SolveOptions, System,
};
use num_traits::{One, Signed, Zero};

type B = Bernstein<Rational>;

/// The root-box tolerance the CLI and the report solve events to (relative to each unknown's
/// interval, so `r` to about `1e-10` of the eye path's): enough to order events and frames,
/// and boxes that size are re-checked in rigorous `f64` intervals
/// ([`verify_root`](crate::solve::verify_root)'s filter). At the solver's default `1e-15`
/// the re-check of a 4-unknown interior event falls back to exact rationals (about 8 s for
/// the turning ellipsoid's instead of 0.02 s).
pub const EVENT_TOLERANCE: f64 = 1e-10;

/// Where on its patch's `(u, v, t)` box an event lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EventKind {
    /// Inside the box: the silhouette of one eye position has a singular point there.
    Interior,
    /// On the face `axis = 0` or `1` (`axis` 0 = u, 1 = v, 2 = t): the silhouette's end on
    /// that face turns back in `r`.
    Face {
        /// The fixed parameter.
        axis: usize,
        /// At its upper end.
        upper: bool,
    },
    /// On the edge where parameters `fixed[0]` and `fixed[1]` are at their ends (`upper`).
    Edge {
        /// The two fixed parameters, each with whether it is at its upper end.
        fixed: [(usize, bool); 2],
    },
    /// On a silhouette that runs along the patch edge `edge` (`(axis, upper)`, `axis` 0 = u,
    /// 1 = v; module `edges`): a critical point of the face curve's surface
    /// `{G̃(w, t, r) = 0}` — inside the face (`fixed` empty), on its ends in `w` or `t`
    /// (one fixed parameter), or at its corners (two).
    AlongEdge {
        /// The characteristic face.
        edge: (usize, bool),
        /// Further parameters at their ends (numbered as u, v, t).
        fixed: [Option<(usize, bool)>; 2],
    },
}

impl EventKind {
    /// The parameters among `u, v, t` (0, 1, 2) fixed at an end, each with whether it is the
    /// upper one.
    pub fn fixed(&self) -> Vec<(usize, bool)> {
        match *self {
            EventKind::Interior => Vec::new(),
            EventKind::Face { axis, upper } => vec![(axis, upper)],
            EventKind::Edge { fixed } => fixed.to_vec(),
            EventKind::AlongEdge { edge, fixed } => std::iter::once(edge)
                .chain(fixed.iter().flatten().copied())
                .collect(),
        }
    }

    /// The free parameters among `u, v, t`, in order: the system's unknowns before `r`.
    pub fn free(&self) -> Vec<usize> {
        let fixed = self.fixed();
        (0..3).filter(|k| fixed.iter().all(|f| f.0 != *k)).collect()
    }

    /// Whether the event lies on a border of the patch in `u` or `v` (module docs).
    pub fn on_patch_border(&self) -> bool {
        match self {
            EventKind::Interior => false,
            EventKind::Face { axis, .. } => *axis < 2,
            EventKind::Edge { fixed } => fixed.iter().any(|&(a, _)| a < 2),
            EventKind::AlongEdge { fixed, .. } => fixed.iter().flatten().any(|&(a, _)| a < 2),
        }
    }
}

/// One event system: the patch, where on it, and the square system whose roots are the
/// events (unknowns: the free parameters among `u, v, t` in that order, then `r`).
#[derive(Clone, Debug, PartialEq)]
pub struct EventSystem {
    /// The surface.
    pub surface: usize,
    /// The patch on it.
    pub patch: usize,
    /// Where.
    pub kind: EventKind,
    /// The system.
    pub system: System,
    /// The patch's collapsed edges (poles: `(axis, upper)` of the faces whose factor was
    /// divided out of the normal), where every value of the other parameter is one point.
    pub collapsed: Vec<(usize, bool)>,
}

/// A certified event.
#[derive(Clone, Debug, PartialEq)]
pub struct Event {
    /// The surface.
    pub surface: usize,
    /// The patch on it.
    pub patch: usize,
    /// Where on the patch.
    pub kind: EventKind,
    /// The eye parameter (the root box's centre).
    pub r: f64,
    /// `(u, v, t)` (the box's centre; fixed parameters at their ends).
    pub uvt: [f64; 3],
    /// The root of its [`EventSystem`] (box and certificate, [`verify_event`]).
    pub root: Root,
    /// For an interior event, whether `F_u` or `G_u` has one strict sign on the root's box
    /// (then the third minor vanishes too and the event is a true one); `None` elsewhere.
    pub pivot: Option<bool>,
}

impl Event {
    /// The event's point on its patch, `S(u, v)` in `f64`, before the motion (`None` when
    /// the scene has no such patch).
    pub fn patch_point(&self, scene: &Scene) -> Option<[f64; 3]> {
        let [u, v, _] = self.uvt;
        scene
            .surfaces
            .get(self.surface)
            .and_then(|s| s.patches.get(self.patch))
            .and_then(|p| p.point(u, v))
    }
}

/// The events of a scene with a moving eye, sorted by `r`.
#[derive(Clone, Debug, PartialEq)]
pub struct Events {
    /// Certified events in increasing `r`.
    pub events: Vec<Event>,
    /// Boxes the solver could not certify, with their system's surface, patch and kind.
    pub clusters: Vec<(usize, usize, EventKind, Cluster)>,
    /// Roots on a system's domain boundary, resolved across the patch's border
    /// ([`BorderRoot`]): each was a cluster of the solve, and is an event of the border's
    /// own system.
    pub border_roots: Vec<BorderRoot>,
    /// Systems solved.
    pub systems: usize,
}

/// A root of an event system exactly on (or within its box's width of) the boundary of the
/// system's domain, where the subdivision can only leave a domain-boundary cluster: for a
/// start position's contour, two of its border points merging on the border between two
/// patches (the t-face system's root on `u = 0`, say). The system's equations are
/// polynomials, defined beyond the patch, so the cluster's box is widened across each
/// boundary face it touches (by its own width on that axis) and the system solved there
/// again: `root` is its one certified root, and its box crosses the boundary. The event is
/// then one of the border's own system (the edge `u = 0, t = a`): `event` is that event, the
/// certified root of the lower-dimensional system, whose box meets `root`'s. On a pole (a
/// collapsed edge, one point for every value of the other parameter) the interior system's
/// root there is the pole's event, certified by the edge systems at the pole's ends in
/// `(t, r)`: the other parameter is not compared. Re-checked by [`verify_border_root`].
#[derive(Clone, Debug, PartialEq)]
pub struct BorderRoot {
    /// The surface.
    pub surface: usize,
    /// The patch on it.
    pub patch: usize,
    /// The system whose domain boundary holds the root.
    pub kind: EventKind,
    /// The cluster the solve left (domain coordinates).
    pub cluster: Cluster,
    /// The box the system was solved on again (domain coordinates): the cluster's widened
    /// across the boundary faces it touches.
    pub extended: crate::solve::RationalBox,
    /// The certified root of the system on `extended`, whose box crosses the domain's
    /// boundary.
    pub root: Root,
    /// The index in [`Events::events`] of the border system's event at the same point.
    pub event: usize,
}

/// The product, in integers over a common denominator.
fn mul(a: &B, b: &B) -> Result<B, SweepError> {
    Ok(ScaledBernstein::from_rational(a)
        .product(&ScaledBernstein::from_rational(b))?
        .to_rational())
}

fn sub(a: &B, b: &B) -> Result<B, SweepError> {
    Ok(a.add_elevated(&b.scale(&-Rational::one()))?)
}

/// `f_i g_j − f_j g_i` (derivatives along axes `i`, `j`).
/// Both products have the degrees `deg f + deg g − e_i − e_j` (where `f` and `g` have
/// positive degrees along `i` and `j`), so the difference is taken in integers over one
/// denominator and brought to rationals once.
pub(super) fn minor(f: &B, g: &B, i: usize, j: usize) -> Result<B, SweepError> {
    let (f, g) = (
        ScaledBernstein::from_rational(f),
        ScaledBernstein::from_rational(g),
    );
    let (fi, fj, gi, gj) = (
        f.derivative(i)?,
        f.derivative(j)?,
        g.derivative(i)?,
        g.derivative(j)?,
    );
    let (p, q) = (fi.product(&gj)?, fj.product(&gi)?);
    if p.degrees() != q.degrees() {
        // A derivative along an axis of degree 0 keeps that degree (it is the zero
        // polynomial): the products' degrees then differ, and the difference is elevated.
        return Ok(sub(&p.to_rational(), &q.to_rational())?.at_exact_degrees());
    }
    // At exact degrees in integers, then brought to rationals once.
    Ok(p.sub(&q)?.at_exact_degrees().to_rational())
}

/// Whether a patch's sweep is invariant in `t` (module docs): `F̃ = φ(t)·F̂(u, v)` with `φ`
/// of one strict sign, and for one of the `scales` `λ(t)` (of one strict sign; the constant
/// `1` is always tried) `λ G̃_t − λ′ G̃ = c(t, r)·F̂`. Then `(G̃/λ)_t` vanishes wherever `F̃`
/// does, so on `F̃ = 0` each equation of the event systems is its value at `t = a` times a
/// power of `λ(t)/λ(a)` (the minors are products of the two), and every system with `t`
/// among its unknowns has whole `t`-segments of roots. A translation along a fixed direction
/// (`λ = 1`: `G̃_t = ⟨d, N⟩ = F̃`) and a similarity `s(t)R` with a fixed rotation moving along
/// a line (`λ = s²`, an entry of `cof(M̂)`: the cone) are such sweeps. Decided exactly on
/// Bernstein coefficients: the slices of `F̃` at one `t` index are multiples of one slice `F̂`
/// (their factors are `φ`'s coefficients, all of one strict sign), and each slice of the
/// difference at one `(t, r)` index is a multiple of `F̂`.
pub(super) fn t_invariant(f: &B, g: &B, scales: &[B]) -> Result<bool, SweepError> {
    let f = f.at_exact_degrees();
    if f.degrees()[3] != 0 {
        return Ok(false);
    }
    let m = (f.degrees()[0] + 1) * (f.degrees()[1] + 1);
    // F̂: the slice with the first non-zero coefficient.
    let Some(first) = f.coeffs().iter().position(|c| !c.is_zero()) else {
        // `F̃ ≡ 0`: the patch moves within itself, refused elsewhere.
        return Ok(false);
    };
    let f_hat = &f.coeffs()[first / m * m..(first / m + 1) * m];
    let j0 = first % m;
    // Every slice of `coeffs` (length `m`) as `c·F̂`: the factors, or `None`.
    let factors = |coeffs: &[Rational]| -> Option<Vec<Rational>> {
        coeffs
            .chunks(m)
            .map(|slice| {
                let c = &slice[j0] / &f_hat[j0];
                slice
                    .iter()
                    .zip(f_hat)
                    .all(|(x, y)| *x == &c * y)
                    .then_some(c)
            })
            .collect()
    };
    let one_sign =
        |c: &[Rational]| c.iter().all(Signed::is_positive) || c.iter().all(Signed::is_negative);
    match factors(f.coeffs()) {
        Some(phi) if one_sign(&phi) => {}
        _ => return Ok(false),
    }
    let one = B::constant(vec![0], Rational::one());
    for lambda in std::iter::once(&one).chain(scales) {
        let lambda = lambda.at_exact_degrees();
        if !one_sign(lambda.coeffs()) {
            continue;
        }
        let l4 = lambda.embed(&[2], 4)?;
        let dl4 = lambda.derivative(0)?.embed(&[2], 4)?;
        let e = sub(&mul(&l4, &g.derivative(2)?)?, &mul(&dl4, g)?)?.at_exact_degrees();
        if e.coeffs().iter().all(Zero::is_zero) {
            return Ok(true);
        }
        if e.degrees()[..2] == f.degrees()[..2] && factors(e.coeffs()).is_some() {
            return Ok(true);
        }
    }
    Ok(false)
}

/// The entries of `cof(M̂)` that are not identically zero, as candidate scales `λ(t)` of
/// [`t_invariant`] (in `s`).
pub(super) fn cofactor_scales(forms: &MotionForms) -> Result<Vec<B>, SweepError> {
    let m = &forms.m;
    let mut out: Vec<B> = Vec::new();
    for i in 0..3 {
        for j in 0..3 {
            let (i1, i2, j1, j2) = ((i + 1) % 3, (i + 2) % 3, (j + 1) % 3, (j + 2) % 3);
            let c = sub(&mul(&m[i1][j1], &m[i2][j2])?, &mul(&m[i1][j2], &m[i2][j1])?)?
                .at_exact_degrees();
            if c.coeffs().iter().any(|x| !x.is_zero()) && !out.contains(&c) {
                out.push(c);
            }
        }
    }
    Ok(out)
}

/// The eye interval the event systems are solved on: the path's `[r₀, r₁]` widened at both
/// ends by `2⁻²⁰` of its length, so that an event at an end of the path (where the
/// silhouette changes exactly at the first or last eye position) is an inner root the solver
/// certifies, not a root on its domain's boundary; [`events`] keeps the roots and clusters
/// whose `r` box meets `[r₀, r₁]`.
pub(super) fn solved_interval(r: &(Rational, Rational)) -> (Rational, Rational) {
    let margin = (&r.1 - &r.0) / Rational::from_integer((1i64 << 20).into());
    (&r.0 - &margin, &r.1 + &margin)
}

/// One patch under a moving eye: its equations for the eye at the origin, and `F̃`, `G̃` in
/// `(u, v, s, ρ)` (`t = a + (b − a)s`, `r = r̂₀ + (r̂₁ − r̂₀)ρ` over the widened interval
/// [`solved_interval`]).
pub(super) struct MovingEye {
    /// The patch's equations with the eye at the origin (`G̃₀`, `Kᵢ`'s parts, the image).
    pub(super) eq0: Equations,
    /// `F̃`, constant in `ρ`.
    pub(super) f: B,
    /// `G̃ = G̃₀ − Σᵢ Pᵢ(r) Kᵢ`.
    pub(super) g: B,
    /// Whether the sweep is invariant in `t` ([`t_invariant`]).
    pub(super) invariant: bool,
    /// The eye interval `ρ` spans ([`solved_interval`]).
    pub(super) r: (Rational, Rational),
}

/// [`MovingEye`] of patch `p` of surface `s` (the eye must move along a path).
pub(super) fn moving_eye(
    scene: &Scene,
    forms: &MotionForms,
    s: usize,
    p: usize,
) -> Result<MovingEye, SweepError> {
    let (path, path_r) = eye_path(scene)?;
    let r = solved_interval(path_r);
    let patch = scene
        .surfaces
        .get(s)
        .and_then(|x| x.patches.get(p))
        .ok_or_else(|| SweepError::field("event", format!("no patch {p} on surface {s}")))?;
    let origin = [Rational::zero(), Rational::zero(), Rational::zero()];
    let eq0 = equations_with(forms, patch, &origin)?;
    let f = eq0.f.embed(&[0, 1, 2], 4)?;
    let mut g = eq0.g.embed(&[0, 1, 2], 4)?;
    for (i, poly) in path.iter().enumerate() {
        let k = mul(&eq0.image[3], &eq0.cof_normal[i])?.embed(&[0, 1, 2], 4)?;
        let pi = on_interval(poly, &r.0, &r.1).embed(&[3], 4)?;
        g = sub(&g, &mul(&k, &pi)?)?;
    }
    let g = super::equations::exact_degrees(&g);
    let invariant = t_invariant(&f, &g, &cofactor_scales(forms)?)?;
    Ok(MovingEye {
        eq0,
        f,
        g,
        invariant,
        r,
    })
}

/// The eye path and its interval, or an error for a fixed eye.
fn eye_path(scene: &Scene) -> Result<(&[super::Poly; 3], &(Rational, Rational)), SweepError> {
    match &scene.eye {
        Eye::Path { path, r } => Ok((path, r)),
        Eye::Point(_) => Err(SweepError::field(
            "eye",
            "events need an eye path {\"path\": …, \"r\": [r0, r1]}",
        )),
    }
}

/// Every event system of a scene whose eye moves along a path (module docs): per patch, the
/// interior system, the six faces' and the twelve edges' systems. Refused when the eye is a
/// fixed point.
pub fn event_systems(scene: &Scene) -> Result<Vec<EventSystem>, SweepError> {
    let forms = motion_forms(&scene.motion, &scene.t.0, &scene.t.1)?;
    let mut out = Vec::new();
    for (s, surface) in scene.surfaces.iter().enumerate() {
        for p in 0..surface.patches.len() {
            let me = moving_eye(scene, &forms, s, p)?;
            out.extend(patch_event_systems(scene, &me, s, p)?);
        }
    }
    Ok(out)
}

/// The event systems of one patch ([`event_systems`]).
fn patch_event_systems(
    scene: &Scene,
    me: &MovingEye,
    s: usize,
    p: usize,
) -> Result<Vec<EventSystem>, SweepError> {
    let r = &me.r;
    let unit = (Rational::zero(), Rational::one());
    let params = [unit.clone(), unit, scene.t.clone()];
    // Characteristic patch edges (module `edges`): their factors divided out of F̃, and the
    // face curve's surface {G̃(w, t, r) = 0} given its own critical points below.
    let (f_hat, faces) = super::edges::characteristic_faces(&me.f, s, p)?;
    // Factors in one parameter without a zero on its interval (a quarter circle's weight
    // `1 + u²`, a Cayley rotation's `(1 + t²)ᵏ`) change no zero set on the box: divided out,
    // the equations and their minors are of far lower degrees.
    let (f_hat, _) = f_hat.without_signed_contents()?;
    let (g_hat, _) = me.g.without_signed_contents()?;
    let (f, g) = (&f_hat, &g_hat);
    // A sweep invariant in t: systems with t free have t-segments of roots, whose ends are
    // the roots of the systems on the faces t = a, b (module docs).
    let invariant = me.invariant;
    let mut out = Vec::new();
    let mut push = |kind: EventKind, free: &[usize], eqs: Vec<B>| -> Result<(), SweepError> {
        if invariant && free.contains(&2) {
            return Ok(());
        }
        let mut domain: Vec<(Rational, Rational)> =
            free.iter().map(|&k| params[k].clone()).collect();
        domain.push(r.clone());
        out.push(EventSystem {
            surface: s,
            patch: p,
            kind,
            system: System::new(domain, eqs)?,
            collapsed: me.eq0.divided.clone(),
        });
        Ok(())
    };
    let mut along: Vec<(usize, bool)> = Vec::new();
    for &face in &faces {
        if along.contains(&face) || me.eq0.divided.contains(&face) {
            continue;
        }
        along.push(face);
        let (axis, upper) = face;
        let gf = g.face(axis, upper)?;
        if gf.coeffs().iter().all(Zero::is_zero) {
            return Err(SweepError::SilhouetteCoversEdge {
                surface: s,
                patch: p,
                axis,
                upper,
            });
        }
        // The face's parameters: w (the other of u, v), t, then r.
        let w_axis = 1 - axis;
        push(
            EventKind::AlongEdge {
                edge: face,
                fixed: [None, None],
            },
            &[w_axis, 2],
            vec![gf.clone(), gf.derivative(0)?, gf.derivative(1)?],
        )?;
        for end in [false, true] {
            // w at an end (a patch corner line): the curve's end there turns back in r.
            let gw = gf.face(0, end)?;
            push(
                EventKind::AlongEdge {
                    edge: face,
                    fixed: [Some((w_axis, end)), None],
                },
                &[2],
                vec![gw.clone(), gw.derivative(0)?],
            )?;
            // t at an end (the start or end position).
            let gt = gf.face(1, end)?;
            push(
                EventKind::AlongEdge {
                    edge: face,
                    fixed: [Some((2, end)), None],
                },
                &[w_axis],
                vec![gt.clone(), gt.derivative(0)?],
            )?;
            for t_end in [false, true] {
                push(
                    EventKind::AlongEdge {
                        edge: face,
                        fixed: [Some((w_axis, end)), Some((2, t_end))],
                    },
                    &[],
                    vec![gw.face(0, t_end)?],
                )?;
            }
        }
    }
    // Interior: F, G and the two minors with the u column.
    push(
        EventKind::Interior,
        &[0, 1, 2],
        vec![f.clone(), g.clone(), minor(f, g, 0, 1)?, minor(f, g, 0, 2)?],
    )?;
    for axis in 0..3 {
        for upper in [false, true] {
            let (ff, gf) = (f.face(axis, upper)?, g.face(axis, upper)?);
            let free: Vec<usize> = (0..3).filter(|&k| k != axis).collect();
            // A collapsed edge (a pole, its factor divided out of the normal) where both
            // equations separate as `λ(w)·φ(t)` and `μ(w)·γ(t, r)` (the surface point and the
            // normal's direction the same all along it): the face system's roots are whole
            // segments in `w` over the roots `φ = γ = 0` of the edge systems at the face's
            // ends, which are solved below; the face system is left out (its subdivision
            // would run to its limits along the segments).
            let pole = me.eq0.divided.contains(&(axis, upper))
                && separable_along_first(&ff)
                && separable_along_first(&gf);
            if !pole {
                let m = minor(&ff, &gf, 0, 1)?;
                push(
                    EventKind::Face { axis, upper },
                    &free,
                    vec![ff.clone(), gf.clone(), m],
                )?;
            }
            // Each edge once: the second fixed axis above the first.
            for axis2 in axis + 1..3 {
                for upper2 in [false, true] {
                    // In the face polynomial, axis2 sits one lower.
                    let (fe, ge) = (ff.face(axis2 - 1, upper2)?, gf.face(axis2 - 1, upper2)?);
                    let free: Vec<usize> = (0..3).filter(|&k| k != axis && k != axis2).collect();
                    push(
                        EventKind::Edge {
                            fixed: [(axis, upper), (axis2, upper2)],
                        },
                        &free,
                        vec![fe, ge],
                    )?;
                }
            }
        }
    }
    Ok(out)
}

/// Whether `p` is `λ(x₀)·q(x₁, …)` with `λ` of one strict sign on `[0, 1]`, decided exactly on
/// Bernstein coefficients (the tensor basis makes a product's coefficients the outer
/// product of its factors'): every slice at one index along axis 0 is `c_j` times one
/// non-zero slice, and the `c_j` (`λ`'s coefficients up to a constant) are all of one strict
/// sign. False for `p ≡ 0`.
fn separable_along_first(p: &B) -> bool {
    let len = p.degrees()[0] + 1;
    let c = p.coeffs();
    let Some(first) = c.iter().position(|x| !x.is_zero()) else {
        return false;
    };
    let (j0, k0) = (first % len, first / len);
    let mut factors = Vec::with_capacity(len);
    for j in 0..len {
        let f = &c[j + k0 * len] / &c[first];
        if !c.chunks(len).all(|line| line[j] == &f * &line[j0]) {
            return false;
        }
        factors.push(f);
    }
    factors.iter().all(Signed::is_positive) || factors.iter().all(Signed::is_negative)
}

/// Certifies that the eye path stays off the moving patch: `|M̂X + (T̂ − δP(r))w|² > 0` on
/// `[0,1]² × [a, b] × [r₀, r₁]` by the positivity prover (as for a fixed eye, module
/// `silhouette`); a witness where it vanishes, or no verdict within the limits, is refused.
fn eye_path_off_patch(scene: &Scene, me: &MovingEye, s: usize, p: usize) -> Result<(), SweepError> {
    use crate::bernstein::{prove_positive, Limits, PositivityOptions, PositivityVerdict};
    let (path, r) = eye_path(scene)?;
    let eq0 = &me.eq0;
    let weight = eq0.image[3].embed(&[0, 1, 2], 4)?;
    let mut sum: Option<B> = None;
    for (i, poly) in path.iter().enumerate() {
        let pi = on_interval(poly, &r.0, &r.1).embed(&[3], 4)?;
        let c = sub(&eq0.image[i].embed(&[0, 1, 2], 4)?, &mul(&weight, &pi)?)?;
        let sq = mul(&c, &c)?;
        sum = Some(match sum {
            None => sq,
            Some(acc) => acc.add_elevated(&sq)?,
        });
    }
    let sum = sum.expect("three components");
    let verdict = prove_positive(
        &sum,
        &PositivityOptions::new()
            .with_path(crate::Path::Filtered)
            .with_limits(Limits::new().with_max_depth(30).with_max_boxes(100_000)),
    )?;
    let to_f64 = crate::num::rational::rational_to_f64;
    let lerp = |lo: &Rational, hi: &Rational, x: &Rational| to_f64(&(lo + (hi - lo) * x));
    match verdict {
        PositivityVerdict::Positive { .. } => Ok(()),
        PositivityVerdict::NotPositive { witness, .. } => Err(SweepError::EyePathOnSurface {
            surface: s,
            patch: p,
            r: lerp(&r.0, &r.1, &witness[3]),
            t: lerp(&scene.t.0, &scene.t.1, &witness[2]),
        }),
        _ => Err(SweepError::EyePathOnSurface {
            surface: s,
            patch: p,
            r: f64::NAN,
            t: f64::NAN,
        }),
    }
}

/// Whether `F_u` or `G_u` (the interior system's first two equations, derivative along the
/// first unknown) has one strict sign on the unit-parameter box `sub` of `system`.
fn pivot_certified(system: &System, sub: &[(Rational, Rational)]) -> Result<bool, SweepError> {
    let derivatives = [
        system.equations[0].derivative(0)?,
        system.equations[1].derivative(0)?,
    ];
    // Rigorous interval enclosures decide it almost always; exactly otherwise.
    for d in &derivatives {
        if let Some(d) = crate::solve::enclose_on(d, sub) {
            let c = d.coeffs();
            if c.iter().all(|x| x.lo > 0.0) || c.iter().all(|x| x.hi < 0.0) {
                return Ok(true);
            }
        }
    }
    for d in &derivatives {
        let d = d.restrict(sub)?;
        let c = d.coeffs();
        if c.iter().all(|x| x.is_positive()) || c.iter().all(|x| x.is_negative()) {
            return Ok(true);
        }
    }
    Ok(false)
}

/// The unit-box parameters of a root's box in `system`.
fn unit_box(system: &System, root: &Root) -> Vec<(Rational, Rational)> {
    system
        .domain
        .iter()
        .zip(&root.bounds)
        .map(|((a, b), (lo, hi))| {
            let h = b - a;
            ((lo - a) / &h, (hi - a) / &h)
        })
        .collect()
}

/// Solves every event system ([`event_systems`], on all cores) and returns the certified
/// events sorted by `r`, with what could not be certified. First certifies that the eye path
/// never meets the moving surface ([`SweepError::EyePathOnSurface`] otherwise): there the
/// silhouette degenerates and `∇G` vanishes with `G`. The systems are solved with `r` over
/// the path's interval widened by `2⁻²⁰` of its length at both ends, so that an event exactly
/// at an end is an inner, certified root; the events and clusters kept are those whose `r`
/// box meets the path's interval (an event at an end may have a box reaching past it).
pub fn events(scene: &Scene, opts: &SolveOptions) -> Result<Events, SweepError> {
    use crate::par::prelude::*;
    // Roots on a patch's border are settled here, across it ([`across_border`]), not by
    // the solver's own boundary stage ([`SolveOptions::boundary`]).
    let opts = &opts.with_boundary(false);
    let forms = motion_forms(&scene.motion, &scene.t.0, &scene.t.1)?;
    // Per patch (on all cores): the eye path certified off it, then its systems.
    let patches: Vec<(usize, usize)> = scene
        .surfaces
        .iter()
        .enumerate()
        .flat_map(|(s, surface)| (0..surface.patches.len()).map(move |p| (s, p)))
        .collect();
    let per_patch: Vec<Result<Vec<EventSystem>, SweepError>> = patches
        .par_iter()
        .map(|&(s, p)| {
            let me = moving_eye(scene, &forms, s, p)?;
            eye_path_off_patch(scene, &me, s, p)?;
            patch_event_systems(scene, &me, s, p)
        })
        .collect();
    let mut systems = Vec::new();
    for r in per_patch {
        systems.extend(r?);
    }
    let mut events = Vec::new();
    let mut clusters = Vec::new();
    // The systems are independent: solved on all cores, read in order.
    // The largest systems (by coefficients) are started first, one at a time by whichever
    // core is free, so that no core is left alone with a large one at the end.
    let size =
        |es: &EventSystem| -> usize { es.system.equations.iter().map(|e| e.coeffs().len()).sum() };
    let mut order: Vec<usize> = (0..systems.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(size(&systems[i])));
    let solved = crate::par::map_in_turn(&order, |&i| solve(&systems[i].system, opts));
    let mut solutions: Vec<_> = (0..systems.len()).map(|_| None).collect();
    for (i, sol) in order.into_iter().zip(solved) {
        solutions[i] = Some(sol);
    }
    let solutions = solutions.into_iter().flatten();
    // Roots and clusters of the widened eye interval that meet the path's own.
    let (_, path_r) = eye_path(scene)?;
    let meets_path = |b: &crate::solve::RationalBox| {
        b.last()
            .is_some_and(|(lo, hi)| lo <= &path_r.1 && hi >= &path_r.0)
    };
    let mut boundary = Vec::new();
    for (es, sol) in systems.iter().zip(solutions) {
        let sol = sol?;
        for root in sol.roots.into_iter().filter(|x| meets_path(&x.bounds)) {
            events.push(event_of(scene, es, root)?);
        }
        for c in sol.clusters.into_iter().filter(|c| meets_path(&c.bounds)) {
            if c.reason == crate::solve::ClusterReason::DomainBoundary {
                boundary.push((es, c));
            } else {
                clusters.push((es.surface, es.patch, es.kind, c));
            }
        }
    }
    // Domain-boundary clusters solved again across the patch's border (on all cores).
    let across: Vec<_> = boundary
        .par_iter()
        .map(|(es, c)| across_border(es, c, opts))
        .collect();
    let mut pending = Vec::new();
    for ((es, c), found) in boundary.into_iter().zip(across) {
        match found? {
            None => clusters.push((es.surface, es.patch, es.kind, c)),
            Some((extended, roots)) => {
                for root in roots.into_iter().filter(|x| meets_path(&x.bounds)) {
                    match crossed_axes(es, &root.bounds) {
                        None => {}
                        Some(crossed) if crossed.is_empty() => {
                            events.push(event_of(scene, es, root)?)
                        }
                        Some(crossed) => {
                            pending.push((es, c.clone(), extended.clone(), root, crossed))
                        }
                    }
                }
            }
        }
    }
    events.sort_by(|a, b| a.r.total_cmp(&b.r));
    // Each root across the border is matched with the border system's event there; one
    // that matches none stays a cluster.
    let mut border_roots = Vec::new();
    for (es, c, extended, root, crossed) in pending {
        let matched = events
            .iter()
            .position(|e| border_match(scene, es, &root.bounds, &crossed, e));
        match matched {
            Some(event) => border_roots.push(BorderRoot {
                surface: es.surface,
                patch: es.patch,
                kind: es.kind,
                cluster: c,
                extended,
                root,
                event,
            }),
            None => clusters.push((es.surface, es.patch, es.kind, c)),
        }
    }
    Ok(Events {
        events,
        clusters,
        border_roots,
        systems: systems.len(),
    })
}

/// The event of the root `root` of the system `es`.
fn event_of(scene: &Scene, es: &EventSystem, root: Root) -> Result<Event, SweepError> {
    let n = es.system.unknowns();
    let mut uvt = [0.0; 3];
    for (j, k) in es.kind.free().into_iter().enumerate() {
        uvt[k] = root.approx[j];
    }
    for (axis, upper) in es.kind.fixed() {
        uvt[axis] = crate::num::rational::rational_to_f64(&parameter_end(scene, axis, upper));
    }
    let pivot = match es.kind {
        EventKind::Interior => Some(pivot_certified(&es.system, &unit_box(&es.system, &root))?),
        _ => None,
    };
    Ok(Event {
        surface: es.surface,
        patch: es.patch,
        kind: es.kind,
        r: root.approx[n - 1],
        uvt,
        root,
        pivot,
    })
}

/// The end of parameter `axis` (0 = u, 1 = v, 2 = t): `0` or `1` for `u`, `v`, the scene's
/// `t` interval's for `t`.
fn parameter_end(scene: &Scene, axis: usize, upper: bool) -> Rational {
    match (axis, upper) {
        (2, false) => scene.t.0.clone(),
        (2, true) => scene.t.1.clone(),
        (_, false) => Rational::zero(),
        (_, true) => Rational::one(),
    }
}

/// A box of a system of kind `kind` (its unknowns' bounds) in all of `(u, v, t, r)`: the
/// fixed parameters at their ends.
fn full_box(
    scene: &Scene,
    kind: EventKind,
    bounds: &crate::solve::RationalBox,
) -> Vec<(Rational, Rational)> {
    let mut out = vec![(Rational::zero(), Rational::zero()); 4];
    for (j, k) in kind.free().into_iter().enumerate() {
        out[k] = bounds[j].clone();
    }
    for (axis, upper) in kind.fixed() {
        let x = parameter_end(scene, axis, upper);
        out[axis] = (x.clone(), x);
    }
    out[3] = bounds[bounds.len() - 1].clone();
    out
}

/// Whether the event `e` is the border system's event at the root (of `es`, box `bounds`)
/// that crosses the faces `crossed`: the same patch, every crossed face fixed in `e`'s
/// kind, and the boxes meet in `(u, v, t, r)` — where a crossed face is a collapsed edge
/// (a pole, one point for every value of the other parameter), that parameter is not
/// compared.
fn border_match(
    scene: &Scene,
    es: &EventSystem,
    bounds: &crate::solve::RationalBox,
    crossed: &[(usize, bool)],
    e: &Event,
) -> bool {
    if e.surface != es.surface
        || e.patch != es.patch
        || !crossed.iter().all(|f| e.kind.fixed().contains(f))
    {
        return false;
    }
    let (mut a, mut b) = (
        full_box(scene, es.kind, bounds),
        full_box(scene, e.kind, &e.root.bounds),
    );
    for &(axis, upper) in crossed {
        if axis < 2 && es.collapsed.contains(&(axis, upper)) {
            let unit = (Rational::zero(), Rational::one());
            a[1 - axis] = unit.clone();
            b[1 - axis] = unit;
        }
    }
    boxes_meet(&a, &b)
}

/// Whether two closed boxes meet.
fn boxes_meet(a: &[(Rational, Rational)], b: &[(Rational, Rational)]) -> bool {
    a.iter().zip(b).all(|(x, y)| x.0 <= y.1 && y.0 <= x.1)
}

/// Where a root box of the system `es` lies against its domain: `None` when it misses the
/// domain, else the boundary faces (`(parameter among u, v, t, upper)`) it reaches past,
/// none when it lies inside.
fn crossed_axes(
    es: &EventSystem,
    bounds: &crate::solve::RationalBox,
) -> Option<Vec<(usize, bool)>> {
    let mut crossed = Vec::new();
    for (j, k) in es.kind.free().into_iter().enumerate() {
        let ((a, b), (lo, hi)) = (&es.system.domain[j], &bounds[j]);
        if hi < a || lo > b {
            return None;
        }
        if lo < a {
            crossed.push((k, false));
        }
        if hi > b {
            crossed.push((k, true));
        }
    }
    Some(crossed)
}

/// The polynomial `p` (on the unit box) re-expressed on the box `sub` of unit coordinates,
/// which may reach past `[0, 1]` (de Casteljau's steps are polynomial identities, so
/// splitting at a parameter outside `[0, 1]` extrapolates exactly): per axis the piece on
/// `[0, e]`, then of that the piece on `[s/e, 1]`. Needs `e > 0`. In integers over one
/// denominator ([`ScaledBernstein::split_anywhere`]), normalised to rationals once.
fn on_box(p: &B, sub: &[(Rational, Rational)]) -> Result<B, SweepError> {
    let mut p = ScaledBernstein::from_rational(p);
    for (axis, (s, e)) in sub.iter().enumerate() {
        if !e.is_one() {
            p = p.split_anywhere(axis, e.numer(), e.denom())?.0;
        }
        if !s.is_zero() {
            let t = s / e;
            p = p.split_anywhere(axis, t.numer(), t.denom())?.1;
        }
        p.normalise_twos();
    }
    Ok(p.to_rational())
}

/// The system `es` on the cluster box `c` widened across each boundary face of the domain
/// it touches (by its own width on that axis; `r`, whose interval is widened already, is
/// left): the widened box and the system on it, or `None` when `c` touches no face of the
/// patch's parameters.
fn widened_system(
    es: &EventSystem,
    c: &crate::solve::RationalBox,
) -> Result<Option<(crate::solve::RationalBox, System)>, SweepError> {
    let n = es.system.unknowns();
    let mut extended = c.clone();
    let mut widened = false;
    for (k, ((a, b), (lo, hi))) in es.system.domain.iter().zip(c).enumerate().take(n - 1) {
        let w = hi - lo;
        if lo <= a {
            extended[k].0 = a - &w;
            widened = true;
        }
        if hi >= b {
            extended[k].1 = b + &w;
            widened = true;
        }
    }
    if !widened {
        return Ok(None);
    }
    let sub: Vec<(Rational, Rational)> = es
        .system
        .domain
        .iter()
        .zip(&extended)
        .map(|((a, b), (lo, hi))| {
            let h = b - a;
            ((lo - a) / &h, (hi - a) / &h)
        })
        .collect();
    let equations = es
        .system
        .equations
        .iter()
        .map(|e| on_box(e, &sub))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Some((extended.clone(), System::new(extended, equations)?)))
}

/// A domain-boundary cluster `c` of the system `es` solved again on its box widened across
/// the boundary ([`widened_system`]): the widened box and the certified roots there, or
/// `None` when the box touches no face of the patch's parameters or the solve leaves a
/// cluster.
fn across_border(
    es: &EventSystem,
    c: &Cluster,
    opts: &SolveOptions,
) -> Result<Option<(crate::solve::RationalBox, Vec<Root>)>, SweepError> {
    let Some((extended, system)) = widened_system(es, &c.bounds)? else {
        return Ok(None);
    };
    let sol = solve(&system, opts)?;
    Ok(sol.clusters.is_empty().then_some((extended, sol.roots)))
}

/// Events that are one geometric event seen from several patches, as groups of indices into
/// `events` (in order; every event in exactly one group). A silhouette crossing the border
/// between two patches of a surface at a tangency yields the same event on both patches (and
/// at a corner on up to four), and an event along a characteristic edge on both patches that
/// share it. Two such events (border events, [`EventKind::on_patch_border`], or
/// [`EventKind::AlongEdge`]) are joined
/// when they lie on the same surface and on different patches, their certified `r`
/// intervals overlap (each widened by `1e-9` of the eye path's interval), and their points
/// `A(t)S(u, v)` agree to `1e-6 · (1 + |x|)`. This groups by geometry to count distinct
/// events; each member keeps its own certificate.
pub fn event_groups(scene: &Scene, events: &[Event]) -> Vec<Vec<usize>> {
    // Border events, and every event along a characteristic edge (both patches of a shared
    // edge solve its face curve's systems).
    let seen_by_neighbours =
        |k: &EventKind| k.on_patch_border() || matches!(k, EventKind::AlongEdge { .. });
    let n = events.len();
    let widen = match &scene.eye {
        Eye::Path { r, .. } => 1e-9 * crate::num::rational_to_f64(&(&r.1 - &r.0)).abs(),
        Eye::Point(_) => 0.0,
    };
    let r_range = |e: &Event| {
        let (lo, hi) = e.root.bounds.last().map_or((e.r, e.r), |(a, b)| {
            (
                crate::num::rational_to_f64(a),
                crate::num::rational_to_f64(b),
            )
        });
        (lo - widen, hi + widen)
    };
    let point = |e: &Event| {
        e.patch_point(scene)
            .map(|x| super::silhouette::apply_motion(scene, e.uvt[2], x))
    };
    let points: Vec<Option<[f64; 3]>> = events.iter().map(point).collect();
    // Union-find over the joined pairs.
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for i in 0..n {
        let (ei, (lo_i, hi_i)) = (&events[i], r_range(&events[i]));
        if !seen_by_neighbours(&ei.kind) {
            continue;
        }
        for j in i + 1..n {
            // All pairs: event lists are short (tens to hundreds).
            let (ej, (lo_j, hi_j)) = (&events[j], r_range(&events[j]));
            if lo_j > hi_i
                || hi_j < lo_i
                || !seen_by_neighbours(&ej.kind)
                || ej.surface != ei.surface
                || ej.patch == ei.patch
            {
                continue;
            }
            let (Some(a), Some(b)) = (points[i], points[j]) else {
                continue;
            };
            let d = (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt();
            let size = (0..3).map(|k| a[k] * a[k]).sum::<f64>().sqrt();
            if d <= 1e-6 * (1.0 + size) {
                let (ri, rj) = (root(&mut parent, i), root(&mut parent, j));
                parent[ri.max(rj)] = ri.min(rj);
            }
        }
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut slot = vec![usize::MAX; n];
    for i in 0..n {
        let r = root(&mut parent, i);
        if slot[r] == usize::MAX {
            slot[r] = groups.len();
            groups.push(Vec::new());
        }
        groups[slot[r]].push(i);
    }
    groups
}

/// Per event, the index of its group in `groups` ([`event_groups`]).
pub fn group_of_each(groups: &[Vec<usize>]) -> Vec<usize> {
    let mut of = vec![0; groups.iter().map(Vec::len).sum()];
    for (g, members) in groups.iter().enumerate() {
        for &i in members {
            of[i] = g;
        }
    }
    of
}

/// Re-checks an event's certificate: rebuilds its system from the scene and checks the root
/// box with [`verify_root`] (which does not call the solver), and an interior event's pivot.
/// To re-check many events, [`verify_events`] builds each patch's systems once.
pub fn verify_event(
    scene: &Scene,
    event: &Event,
) -> Result<Result<RootCheck, RootRefusal>, SweepError> {
    verify_events(scene, std::slice::from_ref(event))
        .pop()
        .expect("one event, one check")
}

/// [`verify_event`] for each of `events`, in order; each patch's systems are rebuilt from
/// the scene once (what a single check costs is almost all in building them).
pub fn verify_events(
    scene: &Scene,
    events: &[Event],
) -> Vec<Result<Result<RootCheck, RootRefusal>, SweepError>> {
    use crate::par::prelude::*;
    let forms = match motion_forms(&scene.motion, &scene.t.0, &scene.t.1) {
        Ok(f) => f,
        Err(e) => return events.iter().map(|_| Err(e.clone())).collect(),
    };
    // The patches the events lie on, each one's systems built once (on all cores).
    let mut keys: Vec<(usize, usize)> = events.iter().map(|e| (e.surface, e.patch)).collect();
    keys.sort_unstable();
    keys.dedup();
    let built: Vec<Result<Vec<EventSystem>, SweepError>> = keys
        .par_iter()
        .map(|&(s, p)| {
            moving_eye(scene, &forms, s, p).and_then(|me| patch_event_systems(scene, &me, s, p))
        })
        .collect();
    events
        .par_iter()
        .map(|event| {
            let at = keys
                .binary_search(&(event.surface, event.patch))
                .expect("every event's patch was built");
            let systems = built[at].as_ref().map_err(Clone::clone)?;
            check_event(systems, event)
        })
        .collect()
}

/// Re-checks a [`BorderRoot`] of `events` (the list it was found with): rebuilds its system
/// from the scene, widens the cluster's box across the boundary again and re-expresses the
/// system there, which must give the recorded widened box; checks the root's certificate
/// on it with [`verify_root`] (not the solver); and checks that the root's box reaches past
/// the domain's boundary and meets the box of `events[event]`, an event of the same patch
/// with the crossed faces fixed (across a pole, not comparing the parameter along it; that
/// event's own certificate is re-checked by [`verify_events`]). False when a condition
/// fails.
pub fn verify_border_root(
    scene: &Scene,
    events: &[Event],
    border: &BorderRoot,
) -> Result<bool, SweepError> {
    let forms = motion_forms(&scene.motion, &scene.t.0, &scene.t.1)?;
    let me = moving_eye(scene, &forms, border.surface, border.patch)?;
    let systems = patch_event_systems(scene, &me, border.surface, border.patch)?;
    let Some(es) = systems.iter().find(|s| s.kind == border.kind) else {
        return Ok(false);
    };
    let Some((extended, system)) = widened_system(es, &border.cluster.bounds)? else {
        return Ok(false);
    };
    if extended != border.extended
        || verify_root(&system, &border.root.bounds, &border.root.certificate).is_err()
    {
        return Ok(false);
    }
    let crossed = match crossed_axes(es, &border.root.bounds) {
        Some(c) if !c.is_empty() => c,
        _ => return Ok(false),
    };
    let Some(event) = events.get(border.event) else {
        return Ok(false);
    };
    Ok(border_match(
        scene,
        es,
        &border.root.bounds,
        &crossed,
        event,
    ))
}

/// The check of [`verify_event`] against the event's patch's rebuilt systems.
fn check_event(
    systems: &[EventSystem],
    event: &Event,
) -> Result<Result<RootCheck, RootRefusal>, SweepError> {
    let system = &systems
        .iter()
        .find(|s| s.kind == event.kind)
        .ok_or_else(|| {
            SweepError::field(
                "event",
                format!(
                    "no system for surface {} patch {} {:?}",
                    event.surface, event.patch, event.kind
                ),
            )
        })?
        .system;
    if event.pivot == Some(true) && !pivot_certified(system, &unit_box(system, &event.root))? {
        return Err(SweepError::field(
            "event",
            "the pivot F_u or G_u has no strict sign on the box",
        ));
    }
    Ok(verify_root(
        system,
        &event.root.bounds,
        &event.root.certificate,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::scene_from_json;

    /// `on_box` re-expresses a polynomial exactly on a box reaching past the unit box: at
    /// random rational points of the box, the new form at the point's box coordinates has the
    /// old form's value there, on random polynomials of 2–4 unknowns and boxes that stick out
    /// on either side.
    #[test]
    fn on_box_extrapolates_exactly() {
        let mut seed = 0x5851_f42d_4c95_7f2du64;
        let mut next =
            move |m: i64| (crate::num::xorshift(&mut seed) % (2 * m as u64 + 1)) as i64 - m;
        let q = |n: i64, d: i64| Rational::new(n.into(), d.into());
        let mut checked = 0;
        for k in 0..40 {
            let n = 2 + k % 3;
            let degrees: Vec<usize> = (0..n)
                .map(|_| 1 + next(1).unsigned_abs() as usize + 1)
                .collect();
            let count: usize = degrees.iter().map(|d| d + 1).product();
            let p = B::new(
                degrees,
                (0..count).map(|_| q(next(9), 1 + next(4).abs())).collect(),
            )
            .unwrap();
            // Boxes [s, e] with e > 0: some below 0, some past 1.
            let sub: Vec<(Rational, Rational)> = (0..n)
                .map(|_| {
                    let s = q(next(6), 8);
                    (s.clone(), &s + q(1 + next(5).abs(), 4))
                })
                .filter(|(_, e)| e > &Rational::zero())
                .collect();
            if sub.len() != n {
                continue;
            }
            let moved = on_box(&p, &sub).unwrap();
            for _ in 0..4 {
                let y: Vec<Rational> = (0..n).map(|_| q(next(8).abs(), 8)).collect();
                let x: Vec<Rational> = y
                    .iter()
                    .zip(&sub)
                    .map(|(y, (s, e))| s + (e - s) * y)
                    .collect();
                assert_eq!(moved.eval(&y).unwrap(), p.eval(&x).unwrap());
                checked += 1;
            }
        }
        assert!(checked >= 100, "{checked}");
    }

    /// Whether every patch of the scene (`motion` JSON, `t` interval) is an invariant sweep.
    fn invariant(t: &str, motion: &str) -> Vec<bool> {
        let scene = scene_from_json(&format!(
            r#"{{"surfaces": [{{"sphere": {{"center": [0, 0, 0], "radius": 1}}}}],
                "t": {t}, "motion": {motion}, "eye": {{"path": [[9], [0, 1], [2]], "r": [0, 1]}}}}"#
        ))
        .unwrap();
        let forms = motion_forms(&scene.motion, &scene.t.0, &scene.t.1).unwrap();
        (0..scene.surfaces[0].patches.len())
            .map(|p| moving_eye(&scene, &forms, 0, p).unwrap().invariant)
            .collect()
    }

    #[test]
    fn invariant_sweeps_are_recognised_exactly() {
        let all = |v: Vec<bool>, want: bool| {
            assert_eq!(v.len(), 8);
            assert!(v.iter().all(|&x| x == want), "{v:?}, want {want}");
        };
        // A translation along a fixed direction (λ = 1), also at a varying speed where the
        // speed keeps its sign (x = 2t² on [1, 2]).
        all(
            invariant("[0, 1]", r#"{"translation": [[0, 2], [0, 1], [0]]}"#),
            true,
        );
        all(
            invariant("[1, 2]", r#"{"translation": [[0, 0, 2], [0], [0]]}"#),
            true,
        );
        // The same speed through zero (the sphere stops at t = 0: φ = 4t changes sign).
        all(
            invariant("[0, 1]", r#"{"translation": [[0, 0, 2], [0], [0]]}"#),
            false,
        );
        // A uniform scale along a line (the cone, λ = s²).
        all(
            invariant(
                "[0, 2]",
                r#"{"translation": [[0, 3], [0], [0]],
                    "linear": [[[1, "1/2"], [0], [0]], [[0], [1, "1/2"], [0]], [[0], [0], [1, "1/2"]]]}"#,
            ),
            true,
        );
        // A curved path, a non-uniform scale, a rotation: the characteristic curve moves.
        all(
            invariant("[0, 1]", r#"{"translation": [[0, 4], [0, 0, 1], [0]]}"#),
            false,
        );
        all(
            invariant(
                "[0, 1]",
                r#"{"translation": [[0, 4], [0, 1], [0]],
                    "linear": [[[1, 1], [0], [0]], [[0], [1], [0]], [[0], [0], [1, "1/2"]]]}"#,
            ),
            false,
        );
        all(
            invariant(
                "[0, 1]",
                r#"{"translation": [[0, 3], [0], [0]],
                    "rotation": {"quaternion": [[1], [0], [0], [0, "1/2"]]}}"#,
            ),
            false,
        );
    }
}
