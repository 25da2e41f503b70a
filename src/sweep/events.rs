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
//! Faces and edges at `u, v ∈ {0, 1}` are the patch's borders: on a closed surface made of
//! several patches, events there mark where a component crosses into the neighbouring patch
//! at a tangency, not a change of the whole silhouette's topology; they are kept and labelled.

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
    /// Systems solved.
    pub systems: usize,
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
    let g = g.at_exact_degrees();
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
    let (f, g) = (&f_hat, &me.g);
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
            let m = minor(&ff, &gf, 0, 1)?;
            push(
                EventKind::Face { axis, upper },
                &free,
                vec![ff.clone(), gf.clone(), m],
            )?;
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
    let to_f64 = |x: &Rational| crate::num::rational::rational_to_f64(x);
    // The systems are independent: solved on all cores, read in order.
    let solutions: Vec<_> = systems
        .par_iter()
        .map(|es| solve(&es.system, opts))
        .collect();
    // Roots and clusters of the widened eye interval that meet the path's own.
    let (_, path_r) = eye_path(scene)?;
    let meets_path = |b: &crate::solve::RationalBox| {
        b.last()
            .is_some_and(|(lo, hi)| lo <= &path_r.1 && hi >= &path_r.0)
    };
    for (es, sol) in systems.iter().zip(solutions) {
        let sol = sol?;
        let n = es.system.unknowns();
        for root in sol.roots.into_iter().filter(|x| meets_path(&x.bounds)) {
            let free: Vec<usize> = match es.kind {
                EventKind::Interior => vec![0, 1, 2],
                EventKind::Face { axis, .. } => (0..3).filter(|&k| k != axis).collect(),
                EventKind::Edge { fixed } => (0..3)
                    .filter(|&k| k != fixed[0].0 && k != fixed[1].0)
                    .collect(),
                EventKind::AlongEdge { edge, fixed } => (0..3)
                    .filter(|&k| k != edge.0 && fixed.iter().flatten().all(|f| f.0 != k))
                    .collect(),
            };
            let mut uvt = [0.0; 3];
            for (j, &k) in free.iter().enumerate() {
                uvt[k] = root.approx[j];
            }
            let ends = |axis: usize, upper: bool| {
                if axis == 2 {
                    to_f64(if upper { &scene.t.1 } else { &scene.t.0 })
                } else if upper {
                    1.0
                } else {
                    0.0
                }
            };
            match es.kind {
                EventKind::Face { axis, upper } => uvt[axis] = ends(axis, upper),
                EventKind::Edge { fixed } => {
                    for (axis, upper) in fixed {
                        uvt[axis] = ends(axis, upper);
                    }
                }
                EventKind::AlongEdge { edge, fixed } => {
                    for (axis, upper) in fixed.iter().flatten().copied().chain([edge]) {
                        uvt[axis] = ends(axis, upper);
                    }
                }
                EventKind::Interior => {}
            }
            let pivot = match es.kind {
                EventKind::Interior => {
                    Some(pivot_certified(&es.system, &unit_box(&es.system, &root))?)
                }
                _ => None,
            };
            events.push(Event {
                surface: es.surface,
                patch: es.patch,
                kind: es.kind,
                r: root.approx[n - 1],
                uvt,
                root,
                pivot,
            });
        }
        for c in sol.clusters.into_iter().filter(|c| meets_path(&c.bounds)) {
            clusters.push((es.surface, es.patch, es.kind, c));
        }
    }
    events.sort_by(|a, b| a.r.total_cmp(&b.r));
    Ok(Events {
        events,
        clusters,
        systems: systems.len(),
    })
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
