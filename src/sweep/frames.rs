//! Frames of a moving eye (Section 4.2, "Extraction"): the silhouette at a sequence of eye
//! parameters `r`. Between two critical events ([`super::events`]) the silhouette's topology
//! does not change, so a frame is the previous frame's polylines moved onto the new
//! silhouette by Newton's method in `(u, v, t)` (the minimum-norm step for the two equations
//! `F = 0`, `G(·, r) = 0`; a component's end on a time face keeps its `t`). A frame is traced
//! afresh by the certified tracer ([`super::silhouette`]) when it is the first, when an event
//! off the patch borders lies between it and the previous frame, or when continuing fails
//! (a point does not converge even in substeps of `r`, or a component meets a time face where
//! it did not). Events on patch borders do not change the silhouette's topology, only how it
//! is cut into patches: a point that converges across a border moves to the neighbouring
//! patch (located there by its surface point), a point joining two patches' pieces whose
//! crossing is gone is dropped, one whose crossing moved past a neighbour moves to where the
//! component now passes between the patches, and gaps wider than the last traced frame's are
//! refilled by points moved onto the silhouette (from the surface point nearest to the
//! chord's midpoint when the chord crosses patches). An inner point that slides a little past
//! the time face its component ends on is dropped; a point past a time face the component
//! does not end on (it meets the face anew) makes the frame traced.
//!
//! Continued frames are drawings, not certificates: the topology between events is what the
//! events certify, and every continued point is checked to satisfy both equations to within
//! [`CONTINUATION_TOLERANCE`] of their coefficient scale.

use super::equations::{motion_forms, MotionForms};
use super::events::{events, moving_eye, Events};
use super::silhouette::{apply_motion, eye_at, silhouette, SilhouetteComponent, SilhouetteOptions};
use super::{Eye, Scene, SweepError};
use crate::bernstein::Bernstein;
use crate::num::rational::rational_to_f64;
use crate::num::Rational;
use crate::solve::SolveOptions;

type B = Bernstein<Rational>;

/// The largest residual `|F|`, `|G|` a continued point may keep, relative to the largest
/// coefficient of each equation.
pub const CONTINUATION_TOLERANCE: f64 = 1e-9;

/// How far (in parameter units) a continued point may leave its patch's box: a silhouette
/// running along a patch border crosses it back and forth; the patch's polynomials extend
/// past it (for the primitives, onto the same quadric).
pub const OVERSHOOT: f64 = 0.02;

/// How far past the time interval's ends (in its unit parameter) a continued point may
/// converge: rounding only (a point on a time face is held on it).
const TIME_SLACK: f64 = 1e-9;

/// How far (in parameter units) Newton's iterates may wander outside the patch's box before
/// the point counts as lost; a converged point beyond [`OVERSHOOT`] has crossed into the
/// neighbouring patch.
const WANDER: f64 = 0.25;

/// Inner points a continued component may lose across patch borders per frame (or an eighth
/// of its points, if more).
const MAX_DROPPED: usize = 2;

/// A polynomial in the power basis in up to four variables (axis 0 fastest), in `f64`.
#[derive(Clone, Debug)]
struct Power {
    degrees: Vec<usize>,
    coeffs: Vec<f64>,
    scale: f64,
}

impl Power {
    fn of(b: &B) -> Power {
        let coeffs: Vec<f64> = b.to_power().iter().map(rational_to_f64).collect();
        let scale = b
            .coeffs()
            .iter()
            .map(|c| rational_to_f64(c).abs())
            .fold(0.0, f64::max);
        Power {
            degrees: b.degrees().to_vec(),
            coeffs,
            scale,
        }
    }

    /// The last axis fixed at `x` (Horner along it).
    fn fix_last(&self, x: f64) -> Power {
        let last = *self.degrees.last().expect("at least one axis");
        let inner: usize = self.coeffs.len() / (last + 1);
        let mut coeffs = vec![0.0; inner];
        for k in (0..=last).rev() {
            for (i, c) in coeffs.iter_mut().enumerate() {
                *c = *c * x + self.coeffs[k * inner + i];
            }
        }
        Power {
            degrees: self.degrees[..self.degrees.len() - 1].to_vec(),
            coeffs,
            scale: self.scale,
        }
    }

    /// The value of a two-variable polynomial at `(u, v)`.
    fn eval2(&self, u: f64, v: f64) -> f64 {
        let d0 = self.degrees[0];
        let mut acc = 0.0;
        for line in self.coeffs.chunks(d0 + 1).rev() {
            let p = line.iter().rev().fold(0.0, |p, &c| p * u + c);
            acc = acc * v + p;
        }
        acc
    }

    /// Value and gradient of a three-variable polynomial at `x`.
    fn eval_grad(&self, x: [f64; 3]) -> (f64, [f64; 3]) {
        let [d0, d1, d2] = [self.degrees[0], self.degrees[1], self.degrees[2]];
        let (mut v, mut g) = (0.0, [0.0; 3]);
        for k in (0..=d2).rev() {
            let (mut q, mut q0, mut q1) = (0.0, 0.0, 0.0);
            for j in (0..=d1).rev() {
                let line = &self.coeffs[(k * (d1 + 1) + j) * (d0 + 1)..][..d0 + 1];
                let (mut p, mut p0) = (0.0, 0.0);
                for &c in line.iter().rev() {
                    p0 = p0 * x[0] + p;
                    p = p * x[0] + c;
                }
                q1 = q1 * x[1] + q;
                q = q * x[1] + p;
                q0 = q0 * x[1] + p0;
            }
            g[2] = g[2] * x[2] + v;
            v = v * x[2] + q;
            g[0] = g[0] * x[2] + q0;
            g[1] = g[1] * x[2] + q1;
        }
        (v, g)
    }
}

/// One patch's equations for continuation: `F̃(u, v, s)` and `G̃(u, v, s, ρ)`, and its
/// homogeneous coordinates.
struct PatchForms {
    /// The faces on which `F ≡ 0` (characteristic patch edges, module `edges`).
    characteristic: Vec<(usize, bool)>,
    /// `F` with those faces' factors divided out.
    f_hat: Power,
    f: Power,
    g: Power,
    hom: [Power; 4],
}

impl PatchForms {
    /// `S(u, v)` (also a little past the patch's square); `None` where the weight is not
    /// positive.
    fn point(&self, u: f64, v: f64) -> Option<[f64; 3]> {
        let w = self.hom[3].eval2(u, v);
        (w > 0.0).then(|| std::array::from_fn(|k| self.hom[k].eval2(u, v) / w))
    }
}

fn patch_forms(
    scene: &Scene,
    forms: &MotionForms,
    s: usize,
    p: usize,
) -> Result<PatchForms, SweepError> {
    let me = moving_eye(scene, forms, s, p)?;
    let hom = &scene.surfaces[s].patches[p].hom;
    let (f_hat, characteristic) = super::edges::characteristic_faces(&me.eq0.f, s, p)?;
    Ok(PatchForms {
        characteristic,
        f_hat: Power::of(&f_hat),
        f: Power::of(&me.eq0.f),
        g: Power::of(&me.g),
        hom: std::array::from_fn(|k| Power::of(&hom[k])),
    })
}

/// One frame: the eye parameter, the envelope's silhouette components as 3-D polylines, and
/// how the frame was made.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// The eye parameter.
    pub r: f64,
    /// The eye `P(r)` (rounded to `f64`).
    pub eye: [f64; 3],
    /// Per envelope component, its points in `(u, v, t)` and in 3-D.
    pub components: Vec<FrameCurve>,
    /// Traced afresh by the certified tracer (else continued from the previous frame).
    pub traced: bool,
    /// The boxes the tracer could not resolve in a traced frame (its components may then be
    /// incomplete; an eye at an event's `r` makes the silhouette singular); 0 when continued.
    pub clusters: usize,
}

/// One component of a frame.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameCurve {
    /// The surface.
    pub surface: usize,
    /// Per point, its patch.
    pub patches: Vec<usize>,
    /// Points in `(u, v, t)`.
    pub uvt: Vec<[f64; 3]>,
    /// Points in 3-D (`A(t)S(u, v)`).
    pub points: Vec<[f64; 3]>,
    /// Whether it is closed.
    pub closed: bool,
}

/// The frames at `rs` (increasing, inside the eye path's interval) and the events that
/// decided where the tracer had to run again, with the seconds spent continuing.
#[derive(Clone, Debug)]
pub struct Frames {
    /// One per requested `r`.
    pub frames: Vec<Frame>,
    /// The certified events ([`events`]).
    pub events: Events,
    /// Seconds spent in continued frames (not in traced ones or the events).
    pub continued_seconds: f64,
}

fn from_components(comps: &[SilhouetteComponent]) -> Vec<FrameCurve> {
    comps
        .iter()
        .filter(|c| c.kind == super::ComponentKind::Envelope)
        .map(|c| FrameCurve {
            surface: c.surface,
            patches: c.patches.clone(),
            uvt: c.uvt.clone(),
            points: c.points.clone(),
            closed: c.closed,
        })
        .filter(|c| !c.uvt.is_empty() && c.patches.len() == c.uvt.len())
        .collect()
}

/// The silhouette frames at the eye parameters `rs` (module docs). Traced frames use
/// `opts`; the events are solved with `solve_opts`.
pub fn frames(
    scene: &Scene,
    rs: &[f64],
    opts: &SilhouetteOptions,
    solve_opts: &SolveOptions,
) -> Result<Frames, SweepError> {
    let Eye::Path { path, r } = &scene.eye else {
        return Err(SweepError::field("eye", "frames need an eye path"));
    };
    let (r0, r1) = (rational_to_f64(&r.0), rational_to_f64(&r.1));
    let solved = super::events::solved_interval(r);
    let solved = (rational_to_f64(&solved.0), rational_to_f64(&solved.1));
    let increasing = rs.windows(2).all(|w| w[0] < w[1]);
    if !increasing || rs.iter().any(|x| !(r0..=r1).contains(x)) {
        return Err(SweepError::field(
            "frames",
            format!("eye parameters must increase inside [{r0}, {r1}]"),
        ));
    }
    let ev = events(scene, solve_opts)?;
    let forms = motion_forms(&scene.motion, &scene.t.0, &scene.t.1)?;
    let mut patch: Vec<Vec<PatchForms>> = Vec::new();
    for (s, surface) in scene.surfaces.iter().enumerate() {
        let mut v = Vec::new();
        for p in 0..surface.patches.len() {
            v.push(patch_forms(scene, &forms, s, p)?);
        }
        patch.push(v);
    }
    let (a, b) = (rational_to_f64(&scene.t.0), rational_to_f64(&scene.t.1));
    let mut out: Vec<Frame> = Vec::with_capacity(rs.len());
    let mut continued_seconds = 0.0;
    // The largest gap between consecutive points of the last traced frame: continued frames
    // are refined to keep theirs within it.
    let mut spacing = f64::INFINITY;
    for (k, &rk) in rs.iter().enumerate() {
        let crosses = k > 0
            && ev
                .events
                .iter()
                .any(|e| !e.kind.on_patch_border() && e.r > rs[k - 1] && e.r <= rk);
        // The patches' G is in the unit parameter of the widened eye interval the events
        // are solved on.
        let rho = (rk - solved.0) / (solved.1 - solved.0);
        let continued = if k == 0 || crosses {
            None
        } else {
            let clock = std::time::Instant::now();
            let rho_prev = (rs[k - 1] - solved.0) / (solved.1 - solved.0);
            let c = continue_in_steps(scene, &patch, &out[k - 1], (rho_prev, rho), (a, b))
                .map(|comps| refine(scene, &patch, comps, rho, spacing, (a, b)));
            continued_seconds += clock.elapsed().as_secs_f64();
            c
        };
        let rq = crate::num::rational_from_f64(rk, "r")
            .map_err(|e| SweepError::field("frames", e.to_string()))?;
        let eye_rq = eye_at(path, &rq);
        let eye = std::array::from_fn(|k| rational_to_f64(&eye_rq[k]));
        let frame = match continued {
            Some(components) => Frame {
                r: rk,
                eye,
                components,
                traced: false,
                clusters: 0,
            },
            None => {
                let mut fixed = scene.clone();
                fixed.eye = Eye::Point(eye_rq);
                let s = silhouette(&fixed, opts)?;
                let components = from_components(&s.components);
                spacing = largest_gap(&components);
                Frame {
                    r: rk,
                    eye,
                    components,
                    traced: true,
                    clusters: s.clusters.len(),
                }
            }
        };
        out.push(frame);
    }
    Ok(Frames {
        frames: out,
        events: ev,
        continued_seconds,
    })
}

/// The largest distance between consecutive points of the components (closing segments
/// included).
fn largest_gap(comps: &[FrameCurve]) -> f64 {
    let d = |p: &[f64; 3], q: &[f64; 3]| (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>().sqrt();
    comps
        .iter()
        .flat_map(|c| {
            let closing = c
                .closed
                .then(|| d(&c.points[0], c.points.last().expect("non-empty")));
            c.points.windows(2).map(|w| d(&w[0], &w[1])).chain(closing)
        })
        .fold(0.0, f64::max)
}

/// Halvings [`refine`] applies to one gap at most.
const MAX_REFINE: usize = 4;

/// Continued components with points added where consecutive points lie more than `spacing`
/// apart (a piece that grew into another patch, points dropped at borders): a point midway
/// (in the patch's parameters, or between the two surface points located on either patch
/// when they differ) moved onto the silhouette at `rho` by Newton's method, halving up to
/// [`MAX_REFINE`] times; a gap that does not converge stays.
fn refine(
    scene: &Scene,
    patch: &[Vec<PatchForms>],
    comps: Vec<FrameCurve>,
    rho: f64,
    spacing: f64,
    (a, b): (f64, f64),
) -> Vec<FrameCurve> {
    if !spacing.is_finite() {
        return comps;
    }
    let dist =
        |p: &[f64; 3], q: &[f64; 3]| (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>().sqrt();
    comps
        .into_iter()
        .map(|c| {
            let forms = &patch[c.surface];
            let g: Vec<Power> = forms.iter().map(|p| p.g.fix_last(rho)).collect();
            // A point midway between points i and j, on the silhouette.
            let midway =
                |x: (usize, [f64; 3]), y: (usize, [f64; 3])| -> Option<(usize, [f64; 3])> {
                    let s = |t: f64| (t - a) / (b - a);
                    let s_mid = (s(x.1[2]) + s(y.1[2])) / 2.0;
                    let (p, u, v) = if x.0 == y.0 {
                        (x.0, (x.1[0] + y.1[0]) / 2.0, (x.1[1] + y.1[1]) / 2.0)
                    } else {
                        let (px, py) = (
                            forms[x.0].point(x.1[0], x.1[1])?,
                            forms[y.0].point(y.1[0], y.1[1])?,
                        );
                        // The chord's midpoint lies off a curved surface: Newton starts from
                        // the nearest point of either patch.
                        let m = std::array::from_fn(|k| (px[k] + py[k]) / 2.0);
                        [x.0, y.0]
                            .into_iter()
                            .find_map(|q| nearest(&forms[q], m, false).map(|[u, v]| (q, u, v)))?
                    };
                    let z = newton([u, v, s_mid], Some(&forms[p].f), &g[p], [false; 3])?;
                    let inside = |c: f64| (-OVERSHOOT..=1.0 + OVERSHOOT).contains(&c);
                    (inside(z[0]) && inside(z[1]) && (0.0..=1.0).contains(&z[2]))
                        .then_some((p, [z[0], z[1], a + (b - a) * z[2]]))
                };
            let n = c.uvt.len();
            let segments = if c.closed { n } else { n.saturating_sub(1) };
            let mut out = FrameCurve {
                surface: c.surface,
                patches: Vec::with_capacity(n),
                uvt: Vec::with_capacity(n),
                points: Vec::with_capacity(n),
                closed: c.closed,
            };
            let push = |out: &mut FrameCurve, (p, y): (usize, [f64; 3]), world: [f64; 3]| {
                out.patches.push(p);
                out.uvt.push(y);
                out.points.push(world);
            };
            for i in 0..n {
                push(&mut out, (c.patches[i], c.uvt[i]), c.points[i]);
                if i >= segments {
                    continue;
                }
                let j = (i + 1) % n;
                // Stack of (from, to, depth, whether `to` is point j) in order along the curve;
                // each piece's end is kept once it is short enough (point j by the next turn).
                let mut stack = vec![(
                    (c.patches[i], c.uvt[i], c.points[i]),
                    (c.patches[j], c.uvt[j], c.points[j]),
                    0,
                    true,
                )];
                while let Some((x, y, depth, last)) = stack.pop() {
                    let split = (depth < MAX_REFINE && dist(&x.2, &y.2) > spacing)
                        .then(|| midway((x.0, x.1), (y.0, y.1)))
                        .flatten()
                        .and_then(|(p, m)| {
                            let world = forms[p].point(m[0], m[1])?;
                            Some((p, m, apply_motion(scene, m[2], world)))
                        });
                    match split {
                        Some(mid) => {
                            // The second half after the first: pushed first.
                            stack.push((mid, y, depth + 1, last));
                            stack.push((x, mid, depth + 1, false));
                        }
                        None if !last => push(&mut out, (y.0, y.1), y.2),
                        None => {}
                    }
                }
            }
            out
        })
        .collect()
}

/// Substeps of the eye parameter [`continue_in_steps`] tries at most (powers of two).
const MAX_SUBSTEPS: usize = 8;

/// [`continue_frame`] from `prev` (at unit eye parameter `from`) to `to`, in one step or,
/// when a point does not converge, in 2, 4, … up to [`MAX_SUBSTEPS`] equal steps (a point
/// that moves fast, as a component's end on a time face near a border event, is followed
/// closely).
fn continue_in_steps(
    scene: &Scene,
    patch: &[Vec<PatchForms>],
    prev: &Frame,
    (from, to): (f64, f64),
    ab: (f64, f64),
) -> Option<Vec<FrameCurve>> {
    let mut steps = 1;
    while steps <= MAX_SUBSTEPS {
        let mut frame = prev.clone();
        let mut ok = true;
        for i in 1..=steps {
            let rho = from + (to - from) * i as f64 / steps as f64;
            match continue_frame(scene, patch, &frame, rho, ab) {
                Some(components) => frame.components = components,
                None => {
                    ok = false;
                    break;
                }
            }
        }
        if ok {
            return Some(frame.components);
        }
        steps *= 2;
    }
    None
}

/// The previous frame's components moved onto the silhouette at `rho` (unit eye
/// parameter); `None` when a point does not converge.
fn continue_frame(
    scene: &Scene,
    patch: &[Vec<PatchForms>],
    prev: &Frame,
    rho: f64,
    (a, b): (f64, f64),
) -> Option<Vec<FrameCurve>> {
    // G at this eye position, per patch.
    let g_here: Vec<Vec<Power>> = patch
        .iter()
        .map(|ps| ps.iter().map(|p| p.g.fix_last(rho)).collect())
        .collect();
    let mut comps = Vec::with_capacity(prev.components.len());
    for c in &prev.components {
        let mut uvt = Vec::with_capacity(c.uvt.len());
        let mut points = Vec::with_capacity(c.uvt.len());
        let mut kept = Vec::with_capacity(c.uvt.len());
        let mut dropped = 0;
        // Whether the component ends on the time face t = a (0) or t = b (1).
        let on_face =
            |x: &[f64; 3], end: f64| !c.closed && (x[2] - end).abs() <= 1e-12 * (1.0 + end.abs());
        let ends_on = [a, b].map(|end| {
            c.uvt.first().is_some_and(|x| on_face(x, end))
                || c.uvt.last().is_some_and(|x| on_face(x, end))
        });
        for (&x, &p) in c.uvt.iter().zip(&c.patches) {
            let forms = &patch[c.surface][p];
            let g = &g_here[c.surface][p];
            // Points on a face of the patch's box (a time face, or a patch border where the
            // component passes to the next patch) stay on it.
            let s0 = (x[2] - a) / (b - a);
            let y0 = [x[0], x[1], s0];
            // On a face: at 0 or 1 to rounding (a point a little outside, within
            // `OVERSHOOT`, crossed a border and is free).
            let fixed = y0.map(|c| c.abs() <= 1e-12 || (c - 1.0).abs() <= 1e-12);
            // On a characteristic patch edge F vanishes identically (module `edges`): a point
            // of the edge's own curve follows G alone along the edge, the end of another
            // characteristic curve there (F̂ = 0 at it) follows F̂ and G.
            let on_characteristic =
                (0..2).any(|k| fixed[k] && forms.characteristic.contains(&(k, y0[k] >= 0.5)));
            let f = if !on_characteristic {
                Some(&forms.f)
            } else if forms.f_hat.eval_grad(y0).0.abs()
                <= CONTINUATION_TOLERANCE * forms.f_hat.scale
            {
                Some(&forms.f_hat)
            } else {
                None
            };
            let y = match newton(y0, f, g, fixed) {
                Some(y) => y,
                // A point joining two patches' pieces on their border, where the component
                // no longer crosses it (the end of a piece on a face turned back in r, a
                // border event): the pieces on either side now meet elsewhere.
                None if fixed[0] || fixed[1] => {
                    dropped += 1;
                    continue;
                }
                None => return None,
            };
            let outside = |c: f64| !(-OVERSHOOT..=1.0 + OVERSHOOT).contains(&c);
            if !(-TIME_SLACK..=1.0 + TIME_SLACK).contains(&y[2]) {
                // The time interval's ends are the component's real ends. An inner point next
                // to the component's end on that time face may slide a little past it (along
                // a characteristic edge, where G alone holds it) and is dropped; a point past
                // a time face the component does not end on means that it meets the face
                // anew (traced afresh).
                let upper = y[2] > 1.0;
                if !ends_on[usize::from(upper)] || outside(y[2]) {
                    return None;
                }
                dropped += 1;
                continue;
            }
            let (p, y) = if outside(y[0]) || outside(y[1]) {
                // A point that crossed a patch border: the neighbouring patch holds it now.
                match relocate(&patch[c.surface], &g_here[c.surface], p, y, fixed[2]) {
                    Some(moved) => moved,
                    None => {
                        dropped += 1;
                        continue;
                    }
                }
            } else {
                (p, y)
            };
            let t = a + (b - a) * y[2];
            let world = patch[c.surface][p].point(y[0], y[1])?;
            uvt.push([y[0], y[1], t]);
            points.push(apply_motion(scene, t, world));
            kept.push(p);
        }
        // A point on a patch border between two points inside its own patch joined that
        // patch's piece to the next one's, and the crossing moved past a neighbour: Newton's
        // method kept it on the border, at the crossing, but out of order. It moves to where
        // the component passes from its patch to another, the nearer way along the curve
        // (dropped when there is none).
        let mut pts: Vec<([f64; 3], [f64; 3], usize)> = uvt
            .into_iter()
            .zip(points)
            .zip(kept)
            .map(|((y, w), p)| (y, w, p))
            .collect();
        for _ in 0..pts.len() {
            let Some(i) = (0..pts.len()).find(|&i| out_of_order(&pts, i, c.closed)) else {
                break;
            };
            let junction = pts.remove(i);
            let other = |k: &usize| pts[*k].2 != junction.2;
            let ahead = (i..pts.len()).find(other);
            let behind = (0..i).rev().find(other).map(|k| k + 1);
            let to = match (ahead, behind) {
                (Some(f), Some(b)) => Some(if f - i <= i - b { f } else { b }),
                (f, b) => f.or(b),
            };
            match to {
                Some(k) => pts.insert(k, junction),
                None => dropped += 1,
            }
        }
        let uvt: Vec<[f64; 3]> = pts.iter().map(|x| x.0).collect();
        let points: Vec<[f64; 3]> = pts.iter().map(|x| x.1).collect();
        let kept: Vec<usize> = pts.iter().map(|x| x.2).collect();
        // More than a few points across borders, or too few left: traced afresh instead.
        if uvt.len() < 2 || dropped > MAX_DROPPED.max(c.uvt.len() / 8) {
            return None;
        }
        comps.push(FrameCurve {
            surface: c.surface,
            patches: kept,
            uvt,
            points,
            closed: c.closed,
        });
    }
    Some(comps)
}

/// Whether point `i` of a continued component (`(u, v, t)`, 3-D point, patch) lies on a
/// border of its patch (`u` or `v` at 0 or 1) between two points inside that patch, off its
/// borders: a junction of two patches' pieces out of order ([`continue_frame`]).
fn out_of_order(pts: &[([f64; 3], [f64; 3], usize)], i: usize, closed: bool) -> bool {
    let n = pts.len();
    let on_border = |y: &[f64; 3]| {
        let s = |c: f64| c.abs() <= 1e-12 || (c - 1.0).abs() <= 1e-12;
        s(y[0]) || s(y[1])
    };
    if n < 3 || !on_border(&pts[i].0) || (!closed && (i == 0 || i + 1 == n)) {
        return false;
    }
    let (h, j) = ((i + n - 1) % n, (i + 1) % n);
    pts[h].2 == pts[i].2 && pts[j].2 == pts[i].2 && !on_border(&pts[h].0) && !on_border(&pts[j].0)
}

/// A continued point `y` of patch `p` that Newton's method took past the patch's border
/// (within [`WANDER`]) moved to the neighbouring patch of the same surface that holds it:
/// the point `S_p(y)` of the extended patch located on another patch (least squares from the
/// nearest of a few samples, inside its square to `1e-6`), then Newton's method on that
/// patch's `F = G = 0` from there (`t` kept when `t_fixed`). `None` when no patch takes it.
fn relocate(
    patches: &[PatchForms],
    g_here: &[Power],
    p: usize,
    y: [f64; 3],
    t_fixed: bool,
) -> Option<(usize, [f64; 3])> {
    let x = patches[p].point(y[0], y[1])?;
    let inside = |c: f64| (-OVERSHOOT..=1.0 + OVERSHOOT).contains(&c);
    for (q, forms) in patches.iter().enumerate() {
        if q == p {
            continue;
        }
        let Some([u, v]) = locate(forms, x) else {
            continue;
        };
        let z0 = [u.clamp(0.0, 1.0), v.clamp(0.0, 1.0), y[2]];
        let Some(z) = newton(z0, Some(&forms.f), &g_here[q], [false, false, t_fixed]) else {
            continue;
        };
        if inside(z[0]) && inside(z[1]) && (-TIME_SLACK..=1.0 + TIME_SLACK).contains(&z[2]) {
            return Some((q, z));
        }
    }
    None
}

/// The parameters `(u, v)` of the patch `forms` at the 3-D point `x`, when it lies on the
/// patch (inside its square to `1e-6`, `|S(u, v) − x|` within `1e-9` of the point's scale):
/// Gauss–Newton from the nearest sample of a 5 × 5 grid, with central differences.
fn locate(forms: &PatchForms, x: [f64; 3]) -> Option<[f64; 2]> {
    nearest(forms, x, true)
}

/// The parameters `(u, v)` of the point of the patch `forms` nearest to `x` (a local
/// minimum of `|S(u, v) − x|` by Gauss–Newton, as [`locate`]), when it lies inside the
/// patch's square to `1e-6`; with `on_surface`, only when `x` lies on the patch.
fn nearest(forms: &PatchForms, x: [f64; 3], on_surface: bool) -> Option<[f64; 2]> {
    let dist2 = |p: [f64; 3]| (0..3).map(|k| (p[k] - x[k]).powi(2)).sum::<f64>();
    let mut best: Option<(f64, [f64; 2])> = None;
    for i in 0..5 {
        for j in 0..5 {
            let uv = [i as f64 / 4.0, j as f64 / 4.0];
            if let Some(p) = forms.point(uv[0], uv[1]) {
                let d = dist2(p);
                if best.is_none_or(|b| d < b.0) {
                    best = Some((d, uv));
                }
            }
        }
    }
    let (_, mut uv) = best?;
    let scale = 1.0 + x.iter().fold(0.0f64, |m, c| m.max(c.abs()));
    let h = 1e-6;
    for _ in 0..12 {
        let p = forms.point(uv[0], uv[1])?;
        let r: [f64; 3] = std::array::from_fn(|k| p[k] - x[k]);
        if dist2(p).sqrt() <= 1e-9 * scale {
            let ok = |c: f64| (-1e-6..=1.0 + 1e-6).contains(&c);
            return (ok(uv[0]) && ok(uv[1])).then_some(uv);
        }
        let du = {
            let (a, b) = (
                forms.point(uv[0] + h, uv[1])?,
                forms.point(uv[0] - h, uv[1])?,
            );
            std::array::from_fn::<f64, 3, _>(|k| (a[k] - b[k]) / (2.0 * h))
        };
        let dv = {
            let (a, b) = (
                forms.point(uv[0], uv[1] + h)?,
                forms.point(uv[0], uv[1] - h)?,
            );
            std::array::from_fn::<f64, 3, _>(|k| (a[k] - b[k]) / (2.0 * h))
        };
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let (m00, m01, m11) = (dot(du, du), dot(du, dv), dot(dv, dv));
        let det = m00 * m11 - m01 * m01;
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let (b0, b1) = (dot(du, r), dot(dv, r));
        let step = [(m11 * b0 - m01 * b1) / det, (m00 * b1 - m01 * b0) / det];
        uv[0] -= step[0];
        uv[1] -= step[1];
        if !uv.iter().all(|c| c.is_finite() && (-1.0..=2.0).contains(c)) {
            return None;
        }
        if !on_surface && step[0].abs().max(step[1].abs()) <= 1e-10 {
            let ok = |c: f64| (-1e-6..=1.0 + 1e-6).contains(&c);
            return (ok(uv[0]) && ok(uv[1])).then_some(uv);
        }
    }
    None
}

/// Newton's method for `F = G = 0` from `x` (minimum-norm steps; the `fixed` coordinates do
/// not move), or for `G = 0` alone when `f` is `None` (on a face where `F ≡ 0`); `None` when
/// it does not reach [`CONTINUATION_TOLERANCE`] in eight steps, no coordinate is left for
/// each equation, or an iterate wanders more than [`WANDER`] outside the unit box.
fn newton(mut x: [f64; 3], f: Option<&Power>, g: &Power, fixed: [bool; 3]) -> Option<[f64; 3]> {
    let equations = if f.is_some() { 2 } else { 1 };
    if fixed.iter().filter(|&&b| b).count() > 3 - equations {
        return None;
    }
    for _ in 0..8 {
        let (fv, fg) = f.map_or((0.0, [0.0; 3]), |f| f.eval_grad(x));
        let (gv, gg) = g.eval_grad(x);
        if f.is_none_or(|f| fv.abs() <= CONTINUATION_TOLERANCE * f.scale)
            && gv.abs() <= CONTINUATION_TOLERANCE * g.scale
        {
            return Some(x);
        }
        let free = |v: [f64; 3]| std::array::from_fn(|k| if fixed[k] { 0.0 } else { v[k] });
        let (fg, gg): ([f64; 3], [f64; 3]) = (free(fg), free(gg));
        // dx = −Jᵀ (J Jᵀ)⁻¹ R with J = [∇F; ∇G] (J = ∇G alone without F).
        let dot = |p: [f64; 3], q: [f64; 3]| p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
        let (l0, l1) = if f.is_some() {
            let (m00, m01, m11) = (dot(fg, fg), dot(fg, gg), dot(gg, gg));
            let det = m00 * m11 - m01 * m01;
            if det == 0.0 || !det.is_finite() {
                return None;
            }
            ((m11 * fv - m01 * gv) / det, (m00 * gv - m01 * fv) / det)
        } else {
            let m11 = dot(gg, gg);
            if m11 == 0.0 || !m11.is_finite() {
                return None;
            }
            (0.0, gv / m11)
        };
        for k in 0..3 {
            x[k] -= l0 * fg[k] + l1 * gg[k];
        }
        if x.iter()
            .any(|c| !(c.is_finite() && (-WANDER..=1.0 + WANDER).contains(c)))
        {
            return None;
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_evaluation_and_gradient_match_the_bernstein_form() {
        // A random-ish 3-variable polynomial of degrees (2, 3, 1).
        let degrees = vec![2, 3, 1];
        let n = 3 * 4 * 2;
        let coeffs: Vec<Rational> = (0..n)
            .map(|i| Rational::new(((i * 37 % 11) as i64 - 5).into(), 3.into()))
            .collect();
        let b = Bernstein::new(degrees, coeffs).unwrap();
        let p = Power::of(&b);
        let x = [0.3, 0.7, 0.45];
        let q = |v: f64| crate::num::rational_from_f64(v, "x").unwrap();
        let exact = |poly: &B| rational_to_f64(&poly.eval(&x.map(q)).unwrap());
        let (v, g) = p.eval_grad(x);
        assert!((v - exact(&b)).abs() < 1e-12);
        for (axis, ga) in g.iter().enumerate() {
            let d = b.derivative(axis).unwrap();
            assert!((ga - exact(&d)).abs() < 1e-11, "axis {axis}");
        }
        // Fixing the last axis of a 4-variable form.
        let b4 = b.embed(&[0, 1, 2], 4).unwrap();
        let p3 = Power::of(&b4).fix_last(0.25);
        assert!((p3.eval_grad(x).0 - v).abs() < 1e-12);
    }
}
