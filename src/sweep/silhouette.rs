//! Algorithm 1: the silhouette components of a swept volume, their types, and the certified
//! `t`-extreme points `Z₀`.
//!
//! Per patch, `Z₁ = {F̃ = G̃ = 0}` is traced on `[0,1]² × [a, b]` by the certified tracer with
//! `t` as the extreme axis, so `Z₀ = {F = G = H = 0}` (eq. 3: `H` is the tangent minor without
//! the `t` column) comes out of the same run as certified roots on the traced components. The
//! pieces of a surface's patches are then joined where one ends on a patch edge and another
//! begins: at the same time `t` and the same 3-D point (within [`JOIN_TOLERANCE`] of the
//! scene's size; both ends are certified curve points refined to the tracer's tolerance).
//!
//! Types (Fig. 3): a closed loop is type 1; an open component with a `t`-extreme point on it
//! is type 2; a `t`-monotone open component is type 3 (on a closed surface it ends on
//! `t = a` and `t = b`; on a surface with a border it may end there).
//!
//! A patch edge that is a characteristic curve at every time makes `F̃` vanish on that face:
//! its factor is divided out and the silhouette on the face is traced on its own (module
//! `edges`). A component through a patch corner leaves the tracer a cluster there, which is
//! certified as a passage through the corner when it is one (module `corners`).
//!
//! The contours of the end positions `A(a)[S]` and `A(b)[S]` — `G̃(u, v, a) = 0`, one equation
//! in `(u, v)` — are traced the same way and reported as caps.

use super::corners::{
    certify_cap_border_box, certify_cap_corner_box, certify_corner_box, check_corner_lines,
    corner_times, resolve_cap_borders, resolve_cap_corners, resolve_corners, CapBorderTouch,
    CapCornerPassage, CornerCrossing,
};
use super::edges::{characteristic_faces, edge_system, same_edge, EdgeKey};
use super::equations::{equations, equations_with, motion_forms, Equations};
use super::rulings::{
    meets_square, overlap, ruling_chord_bound, ruling_margin, ruling_steps, ruling_systems,
    solve_rulings, widen, Ruling, RulingEvidence, RulingSystems,
};
use super::scene::Patch;
use super::{Eye, Scene, SweepError};
use crate::bernstein::{prove_positive, Bernstein, Limits, PositivityOptions, PositivityVerdict};
use crate::num::{rational_to_f64, Interval, Rational};
use crate::solve::{
    extreme_system, trace, verify_root, Cluster, CurveEnd, CurveOptions, Curves, Root, RootCheck,
    RootRefusal, System,
};
use crate::Path;
use num_traits::Zero;
use std::time::Instant;

/// Ends of pieces on patch edges are joined when their 3-D points are this close (relative to
/// `1 + ` the largest coordinate) at times this close.
pub const JOIN_TOLERANCE: f64 = 1e-7;

/// Options of [`silhouette`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct SilhouetteOptions {
    /// The arithmetic of the tracer ([`Path::Filtered`] by default).
    pub path: Path,
    /// The tracer's limits per patch.
    pub limits: Limits,
    /// The widest arc box relative to the parameter domain: the polylines follow the curve
    /// this closely in parameter space.
    pub resolution: f64,
    /// Trace the contours of the end positions too.
    pub caps: bool,
    /// Use eq. 2 as printed (`⟨A(t)S − P, M(t)N⟩`) instead of the cofactor normal; only to
    /// measure how far that is from the contour.
    pub printed_eq2: bool,
    /// When set, a patch whose polylines' certified 3-D chord bound
    /// ([`SilhouetteComponent::chord_bound`]) exceeds this distance is traced again with half
    /// the resolution, down to [`MIN_RESOLUTION`].
    pub tolerance: Option<f64>,
}

/// The finest resolution [`SilhouetteOptions::tolerance`] refines to.
pub const MIN_RESOLUTION: f64 = 1.0 / 1024.0;

impl Default for SilhouetteOptions {
    fn default() -> Self {
        SilhouetteOptions {
            path: Path::Filtered,
            limits: Limits::new().with_max_depth(14).with_max_boxes(100_000),
            resolution: 1.0 / 16.0,
            caps: true,
            printed_eq2: false,
            tolerance: None,
        }
    }
}

crate::choice::setters!(SilhouetteOptions {
    with_path => path: Path,
    with_limits => limits: Limits,
    with_resolution => resolution: f64,
    with_caps => caps: bool,
    with_printed_eq2 => printed_eq2: bool,
    with_tolerance => tolerance: Option<f64>,
});

/// What a component is a silhouette of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ComponentKind {
    /// The envelope (`F = G = 0`).
    Envelope,
    /// The contour of the start position `A(a)[S]`.
    CapA,
    /// The contour of the end position `A(b)[S]`.
    CapB,
}

impl ComponentKind {
    /// `envelope`, `cap_a` or `cap_b`.
    pub fn name(self) -> &'static str {
        match self {
            ComponentKind::Envelope => "envelope",
            ComponentKind::CapA => "cap_a",
            ComponentKind::CapB => "cap_b",
        }
    }
}

/// Fig. 3's types of an envelope component.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ComponentType {
    /// Type 1: a closed loop.
    Loop = 1,
    /// Type 2: open, with local `t`-extreme points.
    Extremes = 2,
    /// Type 3: open and `t`-monotone.
    Monotone = 3,
}

/// How an open component ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ComponentEnd {
    /// On `t = a` (`upper = false`) or `t = b`.
    Time {
        /// Whether on `t = b`.
        upper: bool,
    },
    /// On a patch edge that no other patch continues (the surface's border).
    Border,
    /// In a box the tracer could not resolve (see [`Silhouettes::clusters`]).
    Cluster,
}

/// One connected silhouette component.
#[derive(Clone, Debug, PartialEq)]
pub struct SilhouetteComponent {
    /// Envelope or cap.
    pub kind: ComponentKind,
    /// Its type (envelope components only).
    pub component_type: Option<ComponentType>,
    /// The surface (index in [`Scene::surfaces`]).
    pub surface: usize,
    /// Per polyline vertex, the patch it was traced on.
    pub patches: Vec<usize>,
    /// The polyline in `(u, v, t)` (certified curve points, box centres).
    pub uvt: Vec<[f64; 3]>,
    /// The same in 3-D, `A(t) S(u, v)`.
    pub points: Vec<[f64; 3]>,
    /// Whether it is a closed loop.
    pub closed: bool,
    /// The two ends of an open component.
    pub ends: Vec<ComponentEnd>,
    /// Indices in [`Silhouettes::t_extreme`] of the `t`-extreme points on it.
    pub extremes: Vec<usize>,
    /// A bound on the parameter-space distance between the polyline and the curve (the
    /// largest arc box diagonal over its pieces).
    pub hausdorff_bound: f64,
    /// A certified bound on the 3-D distance between the polyline and the silhouette curve:
    /// each segment and its arc lie in one arc box, whose image under `A(t)S` lies in the
    /// bounding box of its rational Bernstein control points (positive weights); the largest
    /// diagonal of those boxes (infinite where a weight coefficient is not certified positive).
    pub chord_bound: f64,
    /// When the component is a ruling of a sweep invariant in `t` (module `rulings`), its
    /// index in [`Silhouettes::rulings`].
    pub ruling: Option<usize>,
}

/// A certified `t`-extreme point (a root of eq. 3's system `F = G = H = 0`).
#[derive(Clone, Debug, PartialEq)]
pub struct TExtreme {
    /// The surface.
    pub surface: usize,
    /// The patch.
    pub patch: usize,
    /// The certified root in `(u, v, t)`, with its certificate; on a characteristic patch
    /// edge (`edge`), in the face's free parameter and `t`.
    pub root: Root,
    /// The component it lies on, when the tracer could attribute it.
    pub component: Option<usize>,
    /// The face `(axis, upper)` (`axis` 0 = u, 1 = v) when the point lies on a silhouette
    /// that runs along a patch edge (module `edges`): the root is then one of the face curve
    /// `G̃|face = 0`'s `t`-extremes.
    pub edge: Option<(usize, bool)>,
}

/// The result of [`silhouette`].
#[derive(Clone, Debug, PartialEq)]
pub struct Silhouettes {
    /// The components.
    pub components: Vec<SilhouetteComponent>,
    /// `Z₀`.
    pub t_extreme: Vec<TExtreme>,
    /// Certified passages through patch corners, where the pieces of neighbouring patches
    /// are joined (module `corners`; re-checked by [`verify_corner_crossing`]).
    pub corner_crossings: Vec<CornerCrossing>,
    /// Certified passages of the end positions' contours through patch corners (module
    /// `corners`; re-checked by [`verify_cap_corner_passage`]).
    pub cap_corner_passages: Vec<CapCornerPassage>,
    /// The contours of the start and end positions touching a patch border away from the
    /// corners, certified where the tracer left clusters on the border (module `corners`;
    /// re-checked by [`verify_cap_border_touch`]).
    pub cap_border_touches: Vec<CapBorderTouch>,
    /// Boxes the tracer could not resolve: `(surface, patch, kind, cluster)`.
    pub clusters: Vec<(usize, usize, ComponentKind, Cluster)>,
    /// `t`-extreme candidates the solver could not certify (singular points of `Z₁` among
    /// them): `(surface, patch, cluster)`.
    pub extreme_clusters: Vec<(usize, usize, Cluster)>,
    /// The rulings of the patches whose sweep is invariant in `t` (module `rulings`; their
    /// components are straight lines in `(u, v, t)` from `t = a` to `t = b`, re-checked by
    /// [`verify_ruling`]).
    pub rulings: Vec<Ruling>,
    /// Patches traced.
    pub patches: usize,
    /// The path that ran.
    pub path: Path,
    /// Wall time.
    pub seconds: f64,
}

fn horner(p: &[Rational], t: f64) -> f64 {
    p.iter()
        .rev()
        .fold(0.0, |acc, c| acc * t + rational_to_f64(c))
}

/// `A(t) x` in `f64`.
pub(crate) fn apply_motion(scene: &Scene, t: f64, x: [f64; 3]) -> [f64; 3] {
    let m = &scene.motion;
    let d = horner(&m.denominator, t);
    let mut out = [0.0; 3];
    for (i, o) in out.iter_mut().enumerate() {
        let mut acc = horner(&m.translation[i], t);
        for (j, xj) in x.iter().enumerate() {
            acc += horner(&m.linear[i][j], t) * xj;
        }
        *o = acc / d;
    }
    out
}

/// The eye the static silhouette is seen from (`P(r₀)` for a path).
pub(crate) fn eye_point(scene: &Scene) -> [Rational; 3] {
    match &scene.eye {
        Eye::Point(p) => p.clone(),
        Eye::Path { path, r } => eye_at(path, &r.0),
    }
}

/// The eye path's point `P(r)`, exactly.
pub(crate) fn eye_at(path: &[super::Poly; 3], r: &Rational) -> [Rational; 3] {
    path.clone()
        .map(|p| p.iter().rev().fold(Rational::zero(), |acc, c| acc * r + c))
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum End {
    Time(bool),
    Edge,
    Cluster,
}

/// One traced component of one patch.
struct Piece {
    surface: usize,
    patch: usize,
    kind: ComponentKind,
    uvt: Vec<[f64; 3]>,
    world: Vec<[f64; 3]>,
    closed: bool,
    ends: [End; 2],
    extremes: Vec<usize>,
    hausdorff: f64,
    chord: f64,
    /// Index in [`Collected::rulings`] when the piece is a ruling (module `rulings`).
    ruling: Option<usize>,
}

fn centre(root: &Root) -> Vec<f64> {
    root.bounds
        .iter()
        .map(|(lo, hi)| rational_to_f64(&((lo + hi) / Rational::from_integer(2.into()))))
        .collect()
}

fn world(scene: &Scene, patch: &Patch, uvt: [f64; 3]) -> [f64; 3] {
    let x = patch.point(uvt[0], uvt[1]).unwrap_or([f64::NAN; 3]);
    apply_motion(scene, uvt[2], x)
}

/// Where a traced system lives in `(u, v, t)`.
#[derive(Clone, Copy)]
enum Domain {
    /// `(u, v, t)` itself.
    Box,
    /// `(u, v)` at a fixed time (a cap).
    Cap(f64),
    /// `(w, t)` on the face `(axis, upper)` (a characteristic patch edge).
    Edge((usize, bool)),
}

impl Domain {
    /// `(u, v, t)` of a point of the traced system.
    fn uvt(self, c: &[f64]) -> [f64; 3] {
        match self {
            Domain::Box => [c[0], c[1], c[2]],
            Domain::Cap(t) => [c[0], c[1], t],
            Domain::Edge(face) => super::edges::face_point(face, c[0], c[1]),
        }
    }
    /// The traced system's axis that is `t`, if any.
    fn time_axis(self) -> Option<usize> {
        match self {
            Domain::Box => Some(2),
            Domain::Cap(_) => None,
            Domain::Edge(_) => Some(1),
        }
    }
}

/// Pieces of one trace on `domain`.
#[allow(clippy::too_many_arguments)]
fn pieces_of(
    scene: &Scene,
    patch: &Patch,
    surface: usize,
    patch_index: usize,
    kind: ComponentKind,
    curves: &Curves,
    chords: &[f64],
    domain: Domain,
    extreme_offset: usize,
    corners: &[(usize, [f64; 3])],
) -> Vec<Piece> {
    let uvt_of = |p: usize| -> [f64; 3] { domain.uvt(&centre(&curves.points[p].root)) };
    // The corner point `(u, v, t)` a piece continues to when it ends in a cluster group
    // certified as a passage through a patch corner (module `corners`).
    let corner_of = |e: &CurveEnd| match e {
        CurveEnd::Cluster { group, .. } => corners.iter().find(|(g, _)| g == group).map(|c| c.1),
        CurveEnd::Face { .. } => None,
    };
    let end = |e: &CurveEnd| match *e {
        CurveEnd::Face { axis, upper, .. } if Some(axis) == domain.time_axis() => End::Time(upper),
        CurveEnd::Face { .. } => End::Edge,
        CurveEnd::Cluster { .. } => End::Cluster,
    };
    curves
        .components
        .iter()
        .enumerate()
        .map(|(c, comp)| {
            let mut uvt: Vec<[f64; 3]> = comp.points.iter().map(|&p| uvt_of(p)).collect();
            // Each end by its point (an end the tracer could not place counts as a cluster);
            // an end in a certified corner passage continues to the corner, on the edge.
            let end_at = |p: Option<&usize>| {
                comp.ends
                    .iter()
                    .find(|e| match e {
                        CurveEnd::Face { point, .. } | CurveEnd::Cluster { point, .. } => {
                            Some(point) == p
                        }
                    })
                    .map_or((End::Cluster, None), |e| match corner_of(e) {
                        Some(x) => (End::Edge, Some(x)),
                        None => (end(e), None),
                    })
            };
            let ends = if comp.closed {
                [End::Edge, End::Edge]
            } else {
                let (first, to_first) = end_at(comp.points.first());
                let (last, to_last) = end_at(comp.points.last());
                if let Some(x) = to_first {
                    uvt.insert(0, x);
                }
                if let Some(x) = to_last {
                    uvt.push(x);
                }
                [first, last]
            };
            let world = uvt.iter().map(|&q| world(scene, patch, q)).collect();
            Piece {
                surface,
                patch: patch_index,
                kind,
                uvt,
                world,
                closed: comp.closed,
                ends,
                extremes: curves
                    .extremes
                    .iter()
                    .enumerate()
                    .filter(|(_, x)| x.component == Some(c))
                    .map(|(i, _)| extreme_offset + i)
                    .collect(),
                hausdorff: comp.hausdorff_bound,
                chord: chords[c],
                ruling: None,
            }
        })
        .collect()
}

/// The certified 3-D bound of every component of `curves`: per arc box, the diagonal of the
/// bounding box of the moved patch's control points on it (`image` in unit coordinates of
/// the traced system's domain).
fn chord_bounds(curves: &Curves, system: &System, image: &[Bernstein<Interval>]) -> Vec<f64> {
    let arc_bound = |bounds: &[(Rational, Rational)]| -> f64 {
        image_box_diagonal(image, &unit_intervals(system, bounds))
    };
    let per_arc: Vec<f64> = curves.arcs.iter().map(|a| arc_bound(&a.bounds)).collect();
    curves
        .components
        .iter()
        .map(|c| c.arcs.iter().map(|&a| per_arc[a]).fold(0.0, f64::max))
        .collect()
}

/// A box of `system`'s domain in its unit coordinates, as intervals.
pub(super) fn unit_intervals(
    system: &System,
    bounds: &[(Rational, Rational)],
) -> Vec<(Interval, Interval)> {
    bounds
        .iter()
        .enumerate()
        .map(|(k, (lo, hi))| {
            (
                Interval::from_rational(&system.to_unit(k, lo)),
                Interval::from_rational(&system.to_unit(k, hi)),
            )
        })
        .collect()
}

/// The diagonal of the bounding box of the rational control points of `image` (homogeneous,
/// `x/w`) restricted to `sub` (unit coordinates), rounded up: a certified bound on the
/// diameter of the image of that box when every weight coefficient is certified positive,
/// infinite otherwise.
pub(super) fn image_box_diagonal(
    image: &[Bernstein<Interval>],
    sub: &[(Interval, Interval)],
) -> f64 {
    let Ok(parts) = image
        .iter()
        .map(|p| p.restrict(sub))
        .collect::<Result<Vec<_>, _>>()
    else {
        return f64::INFINITY;
    };
    let w = parts[3].coeffs();
    if w.iter().any(|c| c.lo <= 0.0) {
        return f64::INFINITY;
    }
    let mut diag2 = 0.0;
    for part in &parts[..3] {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for (x, wk) in part.coeffs().iter().zip(w) {
            let q = crate::num::Field::div(x, wk);
            lo = lo.min(q.lo);
            hi = hi.max(q.hi);
        }
        diag2 += (hi - lo) * (hi - lo);
    }
    // Rounded up: the sum of squares and the root each add at most an ulp.
    diag2.sqrt() * (1.0 + 4.0 * f64::EPSILON)
}

/// Traces `system`, halving the resolution while a component's certified chord bound
/// exceeds the tolerance (down to [`MIN_RESOLUTION`]); returns the curves and their bounds.
fn trace_to_tolerance(
    system: &System,
    curve_opts: &CurveOptions,
    image: &[Bernstein<Interval>],
    tolerance: Option<f64>,
) -> Result<(Curves, Vec<f64>), SweepError> {
    let mut opts = *curve_opts;
    loop {
        let curves = trace(system, &opts)?;
        let chords = chord_bounds(&curves, system, image);
        let worst = chords.iter().copied().fold(0.0, f64::max);
        match tolerance {
            Some(tol) if worst > tol && opts.resolution / 2.0 >= MIN_RESOLUTION => {
                opts = opts.with_resolution(opts.resolution / 2.0);
            }
            _ => return Ok((curves, chords)),
        }
    }
}

fn unit_domain(n: usize) -> Vec<(Rational, Rational)> {
    vec![(Rational::zero(), Rational::from_integer(1.into())); n]
}

fn close(a: &[f64; 3], b: &[f64; 3], scale: f64) -> bool {
    (0..3).all(|k| (a[k] - b[k]).abs() <= JOIN_TOLERANCE * scale)
}

/// Joins pieces that meet on patch edges into components.
fn join(pieces: Vec<Piece>, t_extreme: &mut [TExtreme]) -> Vec<SilhouetteComponent> {
    let scale = 1.0
        + pieces
            .iter()
            .flat_map(|p| p.world.iter().flatten())
            .fold(0.0f64, |m, x| m.max(x.abs()));
    // End slots: (piece, 0 = first vertex / 1 = last vertex).
    let endpoint = |p: &Piece, e: usize| -> ([f64; 3], f64) {
        let k = if e == 0 { 0 } else { p.uvt.len() - 1 };
        (p.world[k], p.uvt[k][2])
    };
    let mut partner: Vec<[Option<(usize, usize)>; 2]> = vec![[None, None]; pieces.len()];
    for i in 0..pieces.len() {
        if pieces[i].closed {
            continue;
        }
        for ei in 0..2 {
            if pieces[i].ends[ei] != End::Edge || partner[i][ei].is_some() {
                continue;
            }
            let (pi, ti) = endpoint(&pieces[i], ei);
            let mut best: Option<(f64, usize, usize)> = None;
            for (j, pj) in pieces.iter().enumerate() {
                if pj.closed || pj.surface != pieces[i].surface || pj.kind != pieces[i].kind {
                    continue;
                }
                for (ej, end) in pj.ends.iter().enumerate() {
                    if (j, ej) == (i, ei) || *end != End::Edge || partner[j][ej].is_some() {
                        continue;
                    }
                    let (q, tq) = endpoint(pj, ej);
                    if close(&pi, &q, scale) && (ti - tq).abs() <= JOIN_TOLERANCE * scale {
                        let d: f64 = (0..3).map(|k| (pi[k] - q[k]).abs()).sum();
                        if best.is_none_or(|b| d < b.0) {
                            best = Some((d, j, ej));
                        }
                    }
                }
            }
            if let Some((_, j, ej)) = best {
                partner[i][ei] = Some((j, ej));
                partner[j][ej] = Some((i, ei));
            }
        }
    }
    let mut used = vec![false; pieces.len()];
    let mut out = Vec::new();
    let emit = |chain: Vec<(usize, bool)>, closed: bool, out: &mut Vec<SilhouetteComponent>| {
        let first = &pieces[chain[0].0];
        let mut comp = SilhouetteComponent {
            kind: first.kind,
            component_type: None,
            surface: first.surface,
            patches: Vec::new(),
            uvt: Vec::new(),
            points: Vec::new(),
            closed,
            ends: Vec::new(),
            extremes: Vec::new(),
            hausdorff_bound: 0.0,
            chord_bound: 0.0,
            ruling: None,
        };
        for (n, &(p, reversed)) in chain.iter().enumerate() {
            let piece = &pieces[p];
            let mut idx: Vec<usize> = (0..piece.uvt.len()).collect();
            if reversed {
                idx.reverse();
            }
            // Consecutive pieces share their joint point: keep it once.
            let skip = usize::from(n > 0);
            for &k in idx.iter().skip(skip) {
                comp.patches.push(piece.patch);
                comp.uvt.push(piece.uvt[k]);
                comp.points.push(piece.world[k]);
            }
            comp.extremes.extend(&piece.extremes);
            comp.hausdorff_bound = comp.hausdorff_bound.max(piece.hausdorff);
            comp.chord_bound = comp.chord_bound.max(piece.chord);
            comp.ruling = comp.ruling.or(piece.ruling);
        }
        if !closed {
            let (p0, r0) = chain[0];
            let (p1, r1) = *chain.last().expect("non-empty chain");
            let to_end = |e: End| match e {
                End::Time(upper) => ComponentEnd::Time { upper },
                End::Edge => ComponentEnd::Border,
                End::Cluster => ComponentEnd::Cluster,
            };
            comp.ends = vec![
                to_end(pieces[p0].ends[usize::from(r0)]),
                to_end(pieces[p1].ends[usize::from(!r1)]),
            ];
        }
        if comp.kind == ComponentKind::Envelope {
            comp.component_type = Some(if closed {
                ComponentType::Loop
            } else if comp.extremes.is_empty() {
                ComponentType::Monotone
            } else {
                ComponentType::Extremes
            });
        }
        out.push(comp);
    };
    // Open chains start at an end that has no partner.
    for start in 0..pieces.len() {
        if used[start] || pieces[start].closed {
            continue;
        }
        let free = (0..2).find(|&e| partner[start][e].is_none());
        let Some(e0) = free else { continue };
        let mut chain = Vec::new();
        let (mut p, mut entry) = (start, e0);
        loop {
            used[p] = true;
            chain.push((p, entry == 1));
            match partner[p][1 - entry] {
                Some((q, eq)) if !used[q] => {
                    p = q;
                    entry = eq;
                }
                _ => break,
            }
        }
        emit(chain, false, &mut out);
    }
    // What is left is closed: single closed pieces and cycles of joined pieces.
    for start in 0..pieces.len() {
        if used[start] {
            continue;
        }
        let mut chain = Vec::new();
        let (mut p, mut entry) = (start, 0);
        loop {
            used[p] = true;
            chain.push((p, entry == 1));
            if pieces[p].closed {
                break;
            }
            match partner[p][1 - entry] {
                Some((q, eq)) if !used[q] => {
                    p = q;
                    entry = eq;
                }
                _ => break,
            }
        }
        emit(chain, true, &mut out);
    }
    for (c, comp) in out.iter().enumerate() {
        for &x in &comp.extremes {
            t_extreme[x].component = Some(c);
        }
    }
    out
}

/// The traced systems of one patch.
fn patch_system(scene: &Scene, eq: &Equations, printed: bool) -> Result<System, SweepError> {
    let mut domain = unit_domain(2);
    domain.push(scene.t.clone());
    let g = if printed { &eq.g_printed } else { &eq.g };
    Ok(System::new(domain, vec![eq.f.clone(), g.clone()])?)
}

/// The contour of an end position, `G̃(u, v, a or b) = 0`. On a collapsed patch edge (a pole,
/// `divided`) the contour passes through that one 3-D point exactly when `G̃` vanishes on the
/// whole edge; its factor is divided out (as often as it divides), so that the curve crosses
/// the edge where it leaves the point instead of running along it.
fn cap_system(
    g: &Bernstein<Rational>,
    upper: bool,
    divided: &[(usize, bool)],
) -> Result<System, SweepError> {
    let mut cap = g.face(2, upper)?;
    for &(axis, end) in divided {
        while let Some(q) = cap.divide_by_face(axis, end)? {
            cap = q;
        }
    }
    Ok(System::new(unit_domain(2), vec![cap])?)
}

/// Certifies that the eye is not on the moving patch: `|M̂X + (T̂ − δP)w|² > 0` on
/// `[0,1]² × [a, b]` by the positivity prover (a sum of squares is bounded away from zero
/// wherever one term is, so this ends where a solve of the three components would follow the
/// curves where two of them vanish). A witness where it is zero — the eye on the surface — or
/// a box the prover could not decide within its limits is refused.
fn eye_off_surface(
    eq: &Equations,
    scene: &Scene,
    surface: usize,
    patch: usize,
    path: Path,
) -> Result<(), SweepError> {
    let mut sum = eq.sight[0].product(&eq.sight[0])?;
    for s in &eq.sight[1..] {
        sum = sum.add_elevated(&s.product(s)?)?;
    }
    let verdict = prove_positive(
        &sum,
        &PositivityOptions::new()
            .with_path(path)
            .with_limits(Limits::new().with_max_depth(30).with_max_boxes(50_000)),
    )?;
    let (a, b) = (rational_to_f64(&scene.t.0), rational_to_f64(&scene.t.1));
    let at = |s: f64| a + (b - a) * s;
    match verdict {
        PositivityVerdict::Positive { .. } => Ok(()),
        PositivityVerdict::NotPositive { witness, .. } => {
            let t = at(rational_to_f64(&witness[2]));
            Err(SweepError::EyeOnSurface {
                surface,
                patch,
                t_lo: t,
                t_hi: t,
            })
        }
        _ => Err(SweepError::EyeOnSurface {
            surface,
            patch,
            t_lo: a,
            t_hi: b,
        }),
    }
}

/// The equations of patch `p` of surface `s` from the scene's eye, or an error naming `what`
/// was being re-checked when there is no such patch.
fn patch_equations(scene: &Scene, s: usize, p: usize, what: &str) -> Result<Equations, SweepError> {
    let patch = scene
        .surfaces
        .get(s)
        .and_then(|x| x.patches.get(p))
        .ok_or_else(|| SweepError::field(what, format!("no patch {p} on surface {s}")))?;
    equations(scene, patch, &eye_point(scene))
}

/// Re-checks a `t`-extreme point's certificate: rebuilds `F̃`, `G̃` of its patch from the scene
/// (with the factors of characteristic patch edges divided out of `F̃`, module `edges`) and
/// checks Miranda's test and the Jacobian's dominance on its box for `F = G = H = 0` with
/// [`crate::solve::verify_root`], which does not call the solver. A point on a
/// characteristic edge ([`TExtreme::edge`]) is checked on the face curve's system
/// `G̃|face = ∂G̃|face/∂w = 0`, after checking exactly that `F̃` vanishes on that face.
pub fn verify_t_extreme(
    scene: &Scene,
    extreme: &TExtreme,
    printed_eq2: bool,
) -> Result<Result<RootCheck, RootRefusal>, SweepError> {
    let eq = patch_equations(scene, extreme.surface, extreme.patch, "t_extreme")?;
    let (f_hat, faces) = characteristic_faces(&eq.f, extreme.surface, extreme.patch)?;
    let system = match extreme.edge {
        None => extreme_system(
            &patch_system(scene, &Equations { f: f_hat, ..eq }, printed_eq2)?,
            2,
        )?,
        Some(face) => {
            if !faces.contains(&face) {
                return Err(SweepError::field(
                    "t_extreme.edge",
                    format!(
                        "F does not vanish on the face {face:?} of surface {} patch {}",
                        extreme.surface, extreme.patch
                    ),
                ));
            }
            let g = if printed_eq2 { &eq.g_printed } else { &eq.g };
            extreme_system(
                &edge_system(g, face, &scene.t, extreme.surface, extreme.patch)?,
                1,
            )?
        }
    };
    Ok(verify_root(
        &system,
        &extreme.root.bounds,
        &extreme.root.certificate,
    ))
}

/// Re-checks a ruling ([`Silhouettes::rulings`]) from the scene, without the solver: rebuilds
/// `F̃` (characteristic edges divided out) and `G̃` of its patch, decides again exactly that the
/// sweep is invariant in `t` (module `rulings`), checks that the root's box meets the patch's
/// square, and certifies the root again with [`crate::solve::verify_root`] — on `F̂ = Ĝ = 0`
/// for a root, on `F̂ = H = 0` for a tangency, whose bound on `|Ĝ|` is recomputed and must not
/// exceed the one reported, and whose root box must meet its cluster's.
pub fn verify_ruling(
    scene: &Scene,
    ruling: &Ruling,
    printed_eq2: bool,
) -> Result<Result<RootCheck, RootRefusal>, SweepError> {
    let bad = |why: String| SweepError::field("ruling", why);
    let eq = patch_equations(scene, ruling.surface, ruling.patch, "ruling")?;
    let (f_hat, _) = characteristic_faces(&eq.f, ruling.surface, ruling.patch)?;
    let forms = motion_forms(&scene.motion, &scene.t.0, &scene.t.1)?;
    let g = if printed_eq2 { &eq.g_printed } else { &eq.g };
    let Some(rs) = ruling_systems(&forms, &eq.f, &f_hat, g)? else {
        return Err(bad(format!(
            "the sweep of surface {} patch {} is not invariant in t",
            ruling.surface, ruling.patch
        )));
    };
    if !meets_square(ruling.bounds()) {
        return Err(bad("the root's box does not meet the patch's square".into()));
    }
    Ok(match &ruling.evidence {
        RulingEvidence::Root(root) => verify_root(&rs.points, &root.bounds, &root.certificate),
        RulingEvidence::Tangent {
            critical,
            g_bound,
            cluster,
        } => {
            let bound = rs.g_bound(&critical.bounds);
            // A NaN bound fails too.
            if !matches!(
                bound.partial_cmp(g_bound),
                Some(std::cmp::Ordering::Less | std::cmp::Ordering::Equal)
            ) {
                return Err(bad(format!(
                    "|Ĝ| on the critical point's box is bounded by {bound:e}, above the {g_bound:e} reported"
                )));
            }
            if !overlap(&critical.bounds, &cluster.bounds) {
                return Err(bad(
                    "the critical point's box does not meet its cluster".into()
                ));
            }
            verify_root(&rs.critical, &critical.bounds, &critical.certificate)
        }
    })
}

/// Re-checks a passage through a patch corner ([`Silhouettes::corner_crossings`]) from the
/// scene, without the tracer: rebuilds `F̂` (characteristic edges divided out) and `G̃` of its
/// patch, checks that its time interval holds one of the corner line's crossing times (the
/// roots of `gcd(F̂(c, t), G̃(c, t))`), and certifies its box again (regular along its axis,
/// the crossings on the inner faces counted, the corner point alone on the border faces).
/// `Ok(true)` when everything holds and gives the same arc count.
pub fn verify_corner_crossing(
    scene: &Scene,
    crossing: &CornerCrossing,
    printed_eq2: bool,
) -> Result<bool, SweepError> {
    let (s, p) = (crossing.surface, crossing.patch);
    let eq = patch_equations(scene, s, p, "corner_crossing")?;
    let (f_hat, _) = characteristic_faces(&eq.f, s, p)?;
    let system = patch_system(scene, &Equations { f: f_hat, ..eq }, printed_eq2)?;
    if crossing.bounds.len() != 3 {
        return Ok(false);
    }
    let unit = system.unit_bounds(&crossing.bounds);
    let t = (
        system.to_unit(2, &crossing.t.0),
        system.to_unit(2, &crossing.t.1),
    );
    let (f, g) = (&system.equations[0], &system.equations[1]);
    let times = corner_times(f, g, crossing.corner, s, p)?;
    if !times.iter().any(|(lo, hi)| t.0 <= *lo && *hi <= t.1) {
        return Ok(false);
    }
    Ok(certify_corner_box(f, g, crossing.corner, &t, &unit)?
        == Some((crossing.monotone_axis, crossing.arcs)))
}

/// Re-checks a cap's passage through a patch corner ([`Silhouettes::cap_corner_passages`])
/// from the scene, without the tracer: rebuilds the end position's contour equation of its
/// patch (a pole's factor divided out as in [`silhouette`]) and certifies the box again
/// (the corner on the contour exactly, a partial derivative of one strict sign, the inner
/// crossings counted, the corner the only zero on the border edges).
pub fn verify_cap_corner_passage(
    scene: &Scene,
    passage: &CapCornerPassage,
    printed_eq2: bool,
) -> Result<bool, SweepError> {
    let (s, p) = (passage.surface, passage.patch);
    let eq = patch_equations(scene, s, p, "cap_corner_passage")?;
    let g = if printed_eq2 { &eq.g_printed } else { &eq.g };
    let system = cap_system(g, passage.upper, &eq.divided)?;
    Ok(
        certify_cap_corner_box(&system.equations[0], passage.corner, &passage.bounds)?
            == Some((passage.monotone_axis, passage.arcs)),
    )
}

/// Re-checks a cap's touch on a patch border ([`Silhouettes::cap_border_touches`]) from the
/// scene, without the tracer: rebuilds the end position's contour equation of its patch (a
/// pole's factor divided out as in [`silhouette`]) and certifies the box again (one strict
/// sign across the border, none on the inner edge, one distinct zero on the border by an
/// exact gcd, the arcs counted from the signs at the box's corners).
pub fn verify_cap_border_touch(
    scene: &Scene,
    touch: &CapBorderTouch,
    printed_eq2: bool,
) -> Result<bool, SweepError> {
    let (s, p) = (touch.surface, touch.patch);
    let eq = patch_equations(scene, s, p, "cap_border_touch")?;
    let g = if printed_eq2 { &eq.g_printed } else { &eq.g };
    let system = cap_system(g, touch.upper, &eq.divided)?;
    let Some((along, arcs)) =
        certify_cap_border_box(&system.equations[0], touch.border, &touch.bounds)?
    else {
        return Ok(false);
    };
    // The same root: the recorded interval and the one found now overlap (each holds the
    // only distinct root in the box's span).
    Ok(arcs == touch.arcs && along.0 <= touch.along.1 && touch.along.0 <= along.1)
}

/// Per patch of every surface (in order), the square system `Z₀ = {F̃ = G̃ = H = 0}` of
/// eq. 3 on `[0,1]² × [a, b]` (`H` the Jacobian minor `F_u G_v − F_v G_u`): its roots are the
/// silhouette's `t`-extreme points. These are the solver's silhouette systems;
/// [`silhouette`] solves them only on the boxes the trace leaves non-monotone in `t`.
pub fn t_extreme_systems(scene: &Scene) -> Result<Vec<System>, SweepError> {
    let eye = eye_point(scene);
    let forms = motion_forms(&scene.motion, &scene.t.0, &scene.t.1)?;
    let mut out = Vec::new();
    for (s, surface) in scene.surfaces.iter().enumerate() {
        for (p, patch) in surface.patches.iter().enumerate() {
            let eq = equations_with(&forms, patch, &eye)?.without_signed_factors()?;
            let (f, _) = characteristic_faces(&eq.f, s, p)?;
            let eq = Equations { f, ..eq };
            out.push(extreme_system(&patch_system(scene, &eq, false)?, 2)?);
        }
    }
    Ok(out)
}

/// What the traces of a scene add up to, before the pieces are joined.
#[derive(Default)]
struct Collected {
    pieces: Vec<Piece>,
    rulings: Vec<Ruling>,
    t_extreme: Vec<TExtreme>,
    clusters: Vec<(usize, usize, ComponentKind, Cluster)>,
    extreme_clusters: Vec<(usize, usize, Cluster)>,
}

impl Collected {
    /// Adds the rulings of patch `p` of surface `s`, a sweep invariant in `t` (module
    /// `rulings`): one type-3 piece per ruling point not already found on a neighbouring
    /// patch (same 3-D ends), sampled in `t` at the resolution (halved while its certified
    /// chord bound exceeds the tolerance), and the solve's clusters.
    fn add_rulings(
        &mut self,
        scene: &Scene,
        patch: &Patch,
        (s, p): (usize, usize),
        eq: &Equations,
        rs: &RulingSystems,
        opts: &SilhouetteOptions,
    ) -> Result<(), SweepError> {
        let (found, clusters) = solve_rulings(rs, opts.path, opts.limits)?;
        self.clusters.extend(
            clusters
                .into_iter()
                .map(|c| (s, p, ComponentKind::Envelope, c)),
        );
        let margin = ruling_margin();
        let image: Vec<Bernstein<Interval>> = eq
            .image
            .iter()
            .map(|b| widen(b, &[0, 1], &margin).map(|w| w.map(Interval::from_rational)))
            .collect::<Result<_, _>>()?;
        let (a, b) = (rational_to_f64(&scene.t.0), rational_to_f64(&scene.t.1));
        for evidence in found {
            let ruling = Ruling {
                surface: s,
                patch: p,
                evidence,
                component: 0,
            };
            let bounds = ruling.bounds().to_vec();
            let [u, v] = ruling.uv();
            let mut n = (1.0 / opts.resolution).ceil().max(1.0) as usize;
            let (steps, chord) = loop {
                let steps = ruling_steps(n);
                let chord = ruling_chord_bound(&image, &rs.points, &bounds, &steps);
                match opts.tolerance {
                    Some(tol) if chord > tol && (n as f64) * 2.0 <= 1.0 / MIN_RESOLUTION => {
                        n *= 2;
                    }
                    _ => break (steps, chord),
                }
            };
            let uvt: Vec<[f64; 3]> = steps
                .iter()
                .map(|&x| [u, v, if x == 1.0 { b } else { a + (b - a) * x }])
                .collect();
            let world: Vec<[f64; 3]> = uvt.iter().map(|&q| world(scene, patch, q)).collect();
            let ends = [world[0], world[world.len() - 1]];
            let scale = 1.0 + ends.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
            let seen = self.pieces.iter().any(|q| {
                q.ruling.is_some()
                    && q.surface == s
                    && close(&q.world[0], &ends[0], scale)
                    && close(&q.world[q.world.len() - 1], &ends[1], scale)
            });
            if seen {
                continue;
            }
            let diag = bounds
                .iter()
                .map(|(lo, hi)| rational_to_f64(&(hi - lo)).powi(2))
                .sum::<f64>()
                .sqrt();
            self.pieces.push(Piece {
                surface: s,
                patch: p,
                kind: ComponentKind::Envelope,
                uvt,
                world,
                closed: false,
                ends: [End::Time(false), End::Time(true)],
                extremes: Vec::new(),
                hausdorff: diag,
                chord,
                ruling: Some(self.rulings.len()),
            });
            self.rulings.push(ruling);
        }
        Ok(())
    }

    /// Adds one envelope trace of patch `p` of surface `s` on `domain`: its pieces (ends in
    /// the cluster groups of `corners` continued to their corner points), its `t`-extreme
    /// points, and its clusters (those of the groups in `corners` left out).
    #[allow(clippy::too_many_arguments)]
    fn add_envelope(
        &mut self,
        scene: &Scene,
        patch: &Patch,
        (s, p): (usize, usize),
        curves: &Curves,
        chords: &[f64],
        domain: Domain,
        corners: &[(usize, [f64; 3])],
    ) {
        let offset = self.t_extreme.len();
        self.pieces.extend(pieces_of(
            scene,
            patch,
            s,
            p,
            ComponentKind::Envelope,
            curves,
            chords,
            domain,
            offset,
            corners,
        ));
        let edge = match domain {
            Domain::Edge(face) => Some(face),
            _ => None,
        };
        self.t_extreme
            .extend(curves.extremes.iter().map(|x| TExtreme {
                surface: s,
                patch: p,
                root: x.root.clone(),
                component: None,
                edge,
            }));
        let resolved: Vec<usize> = corners
            .iter()
            .flat_map(|(group, _)| curves.cluster_groups[*group].iter().copied())
            .collect();
        self.clusters.extend(
            curves
                .clusters
                .iter()
                .enumerate()
                .filter(|(i, _)| !resolved.contains(i))
                .map(|(_, c)| (s, p, ComponentKind::Envelope, c.clone())),
        );
        self.extreme_clusters
            .extend(curves.extreme_clusters.iter().map(|c| (s, p, c.clone())));
    }
}

/// Algorithm 1 on every patch of every surface: the envelope's silhouette components with
/// their types, the certified `t`-extreme points, and (optionally) the end positions'
/// contours.
pub fn silhouette(scene: &Scene, opts: &SilhouetteOptions) -> Result<Silhouettes, SweepError> {
    let clock = Instant::now();
    let eye = eye_point(scene);
    let (a, b) = (rational_to_f64(&scene.t.0), rational_to_f64(&scene.t.1));
    let curve_opts = CurveOptions::default()
        .with_path(opts.path)
        .with_limits(opts.limits)
        .with_resolution(opts.resolution);
    let mut acc = Collected::default();
    let mut patches = 0;
    let mut edge_keys = Vec::new();
    let mut corner_crossings = Vec::new();
    let mut cap_passages = Vec::new();
    let mut cap_touches = Vec::new();
    // The motion's Bernstein forms and their certified checks, once for every patch.
    let forms = motion_forms(&scene.motion, &scene.t.0, &scene.t.1)?;
    for (s, surface) in scene.surfaces.iter().enumerate() {
        for (p, patch) in surface.patches.iter().enumerate() {
            patches += 1;
            let eq = equations_with(&forms, patch, &eye)
                .and_then(Equations::without_signed_factors)
                .map_err(|e| match e {
                    SweepError::DegeneratePatch { .. } => SweepError::DegeneratePatch {
                        surface: s,
                        patch: p,
                    },
                    other => other,
                })?;
            // H = F_u G_v − F_v G_u has at most the sum of F's and G's degrees per variable.
            let h: Vec<usize> =
                eq.f.degrees()
                    .iter()
                    .zip(eq.g.degrees())
                    .map(|(a, b)| a + b)
                    .collect();
            if h.iter().any(|&d| d > crate::solve::MAX_DEGREE) {
                return Err(SweepError::field(
                    format!("surfaces[{s}] patch {p}"),
                    format!(
                        "F and G have degrees {:?} and {:?} in (u, v, t), so eq. 3's H up to {h:?}; the solver takes up to {} per variable (lower the patch or motion degree)",
                        eq.f.degrees(),
                        eq.g.degrees(),
                        crate::solve::MAX_DEGREE
                    ),
                ));
            }
            eye_off_surface(&eq, scene, s, p, opts.path)?;
            // Patch edges that are characteristic at every time: F̃'s factors divided out,
            // the silhouette on each such face traced on its own (module `edges`).
            let (f_hat, faces) = characteristic_faces(&eq.f, s, p)?;
            let g = if opts.printed_eq2 {
                &eq.g_printed
            } else {
                &eq.g
            };
            let mut seen_faces: Vec<(usize, bool)> = Vec::new();
            for &face in &faces {
                // A collapsed edge (a pole: `N_h`'s factor was divided there) is one point in
                // 3-D; the curves through it are the neighbouring edges' and interiors'.
                if seen_faces.contains(&face) || eq.divided.contains(&face) {
                    continue;
                }
                seen_faces.push(face);
                let key = EdgeKey::new(s, patch, &eq.normal, face)?;
                if edge_keys.iter().any(|k| same_edge(k, &key)) {
                    continue;
                }
                edge_keys.push(key);
                let system = edge_system(g, face, &scene.t, s, p)?;
                let image: Vec<Bernstein<Interval>> = eq
                    .image
                    .iter()
                    .map(|b| {
                        b.face(face.0, face.1)
                            .map(|f| f.map(Interval::from_rational))
                    })
                    .collect::<Result<_, _>>()?;
                let (curves, chords) = trace_to_tolerance(
                    &system,
                    &curve_opts.with_extreme_axis(Some(1)),
                    &image,
                    opts.tolerance,
                )?;
                acc.add_envelope(
                    scene,
                    patch,
                    (s, p),
                    &curves,
                    &chords,
                    Domain::Edge(face),
                    &[],
                );
            }
            let f_full = eq.f.clone();
            let eq = Equations { f: f_hat, ..eq };
            let g_used = if opts.printed_eq2 {
                &eq.g_printed
            } else {
                &eq.g
            };
            // A sweep invariant in t: the silhouette is made of rulings over the points of
            // F̂ = Ĝ = 0, solved in (u, v) (module `rulings`).
            if let Some(rs) = ruling_systems(&forms, &f_full, &eq.f, g_used)? {
                acc.add_rulings(scene, patch, (s, p), &eq, &rs, opts)?;
            } else {
                let system = patch_system(scene, &eq, opts.printed_eq2)?;
                check_corner_lines(&system.equations[0], &system.equations[1], s, p)?;
                let image: Vec<Bernstein<Interval>> = eq
                    .image
                    .iter()
                    .map(|b| b.map(Interval::from_rational))
                    .collect();
                let (curves, chords) = trace_to_tolerance(
                    &system,
                    &curve_opts.with_extreme_axis(Some(2)),
                    &image,
                    opts.tolerance,
                )?;
                // Cluster groups on patch corners certified as passages through the corner.
                let passages = resolve_corners(&system, &curves, s, p)?;
                let corner_points: Vec<(usize, [f64; 3])> = passages
                    .iter()
                    .map(|(group, cc)| {
                        let t = rational_to_f64(
                            &((&cc.t.0 + &cc.t.1) / Rational::from_integer(2.into())),
                        );
                        let at = |upper: bool| if upper { 1.0 } else { 0.0 };
                        (*group, [at(cc.corner[0]), at(cc.corner[1]), t])
                    })
                    .collect();
                acc.add_envelope(
                    scene,
                    patch,
                    (s, p),
                    &curves,
                    &chords,
                    Domain::Box,
                    &corner_points,
                );
                corner_crossings.extend(passages.into_iter().map(|(_, cc)| cc));
            }
            if opts.caps {
                let g = if opts.printed_eq2 {
                    &eq.g_printed
                } else {
                    &eq.g
                };
                for (upper, kind, t) in [
                    (false, ComponentKind::CapA, a),
                    (true, ComponentKind::CapB, b),
                ] {
                    let system = cap_system(g, upper, &eq.divided)?;
                    let face: Vec<Bernstein<Interval>> = eq
                        .image
                        .iter()
                        .map(|b| b.face(2, upper).map(|f| f.map(Interval::from_rational)))
                        .collect::<Result<_, _>>()?;
                    let (cap, chords) =
                        trace_to_tolerance(&system, &curve_opts, &face, opts.tolerance)?;
                    // Cluster groups on patch corners certified as the contour's passages.
                    let passages = resolve_cap_corners(&system, &cap, s, p, upper)?;
                    // And those on a border away from the corners, certified as touches.
                    let touches = resolve_cap_borders(&system, &cap, s, p, upper)?;
                    let at = |upper: bool| if upper { 1.0 } else { 0.0 };
                    let corner_points: Vec<(usize, [f64; 3])> = passages
                        .iter()
                        .map(|(group, cp)| (*group, [at(cp.corner[0]), at(cp.corner[1]), t]))
                        .chain(touches.iter().map(|(group, x)| {
                            let (axis, upper) = x.border;
                            let mut point = [0.0, 0.0, t];
                            point[axis] = at(upper);
                            point[1 - axis] = rational_to_f64(
                                &((&x.along.0 + &x.along.1) / Rational::from_integer(2.into())),
                            );
                            (*group, point)
                        }))
                        .collect();
                    acc.pieces.extend(pieces_of(
                        scene,
                        patch,
                        s,
                        p,
                        kind,
                        &cap,
                        &chords,
                        Domain::Cap(t),
                        0,
                        &corner_points,
                    ));
                    let resolved: Vec<usize> = corner_points
                        .iter()
                        .flat_map(|(group, _)| cap.cluster_groups[*group].iter().copied())
                        .collect();
                    acc.clusters.extend(
                        cap.clusters
                            .iter()
                            .enumerate()
                            .filter(|(i, _)| !resolved.contains(i))
                            .map(|(_, c)| (s, p, kind, c.clone())),
                    );
                    cap_passages.extend(passages.into_iter().map(|(_, cp)| cp));
                    cap_touches.extend(touches.into_iter().map(|(_, x)| x));
                }
            }
        }
    }
    let Collected {
        pieces,
        mut rulings,
        mut t_extreme,
        clusters,
        extreme_clusters,
    } = acc;
    let components = join(pieces, &mut t_extreme);
    for (c, comp) in components.iter().enumerate() {
        if let Some(i) = comp.ruling {
            rulings[i].component = c;
        }
    }
    Ok(Silhouettes {
        components,
        t_extreme,
        corner_crossings,
        clusters,
        extreme_clusters,
        rulings,
        cap_corner_passages: cap_passages,
        cap_border_touches: cap_touches,
        patches,
        path: opts.path,
        seconds: clock.elapsed().as_secs_f64(),
    })
}
