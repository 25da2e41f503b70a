//! Triangle-mesh node decimation and exact undecimation in linear time (Krivograd, Hren, Žalik
//! and Jezernik, "A fast triangular-mesh decimation-and-undecimation algorithm for transferring
//! FEM results via the Web", Strojniški vestnik – Journal of Mechanical Engineering, 2003).
//!
//! The algorithm of Section 1: evaluate every node ([`Criterion`]), file the nodes in the
//! bucket queue of eqs. (1)–(3) (module `bucket`), repeatedly take the first node of the lowest
//! non-empty interval, delete it with its fan of triangles, re-triangulate the hole by ear
//! cutting (module `earcut`) and re-evaluate the neighbours. Section 2: every removal is recorded
//! (the removed triangles, the added triangles, the triangle slots they occupy) so that any
//! number of steps can be undone in reverse order and redone ([`history`]).
//!
//! Two engines run the same driver (module `driver`), chosen by [`Options::path`]:
//! * `exact` — the reference path: rational coordinates and scalars, adjacency as per-node
//!   sets of incident triangles, orientation by exact rational determinants, criteria in
//!   exact arithmetic (rounded once to `f64` to file the node);
//! * `fast` — `f64` coordinates, per-node fan lists in cache-line blocks (module `fans`, the
//!   paper's Figure 4) naming triangles that live in reusable slots, adaptive robust
//!   orientation predicates (Shewchuk's, from the `robust` crate); while the loop removes,
//!   the nodes it takes next are evaluated ahead on a second thread (module `ahead`), which
//!   changes the speed, not the removals.
//!
//! Both use exact signs for every validity decision, so they take the same decisions; the
//! heuristics (which ear to cut first, which axis plane to project a fan into, the angle
//! criterion, which is transcendental) are the same `f64` functions of the input coordinates
//! in both. They remove the same nodes in the same order whenever their evaluation values
//! file nodes into the same intervals, and both undecimate to the original bit for bit.
//! [`check`] re-verifies every step independently.
//!
//! # Example
//!
//! Decimate a height grid to 10 % of its nodes, re-verify every step, and undo it exactly:
//!
//! ```
//! use geocert::decimate::{check, data, decimate, history, Options, Stage, Target};
//!
//! let grid = data::height_grid(30);
//! let out = decimate(&grid, &Options::new().with_target(Target::Keep(0.1)))?;
//! assert!(out.mesh.vertices.len() <= grid.vertices.len() / 10 + 1);
//! // An independent exact replay of every step (projection: the global xy plane).
//! let verified = check::verify(&grid, &out.history, out.stats.projection_xy, 10)?;
//! assert!(verified.undecimated_exactly);
//! // Undo every step from the decimated mesh and its history alone.
//! let mut stage = Stage::decimated(&out.mesh, &out.history)?;
//! while stage.applied > 0 {
//!     stage.undo(&out.history)?;
//! }
//! let back = stage.to_mesh();
//! assert_eq!(back, grid);
//! assert_eq!(history::fingerprint(&back), out.history.original_fingerprint);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub(crate) mod ahead;
pub(crate) mod bucket;
pub mod check;
pub mod data;
pub(crate) mod driver;
pub(crate) mod earcut;
pub(crate) mod exact;
pub(crate) mod fans;
pub(crate) mod fast;
pub mod fit;
pub mod history;
pub(crate) mod origin;
pub mod quadric;
pub mod quality;

use crate::mesh::{Mesh, MeshError};
use crate::Path;
use thiserror::Error;

pub use history::{History, HistoryError, Stage};
pub use quadric::{
    crossing_deviation, faces_against_original, flip_toward_fan, folds, initial_quadrics, landing,
    quadric_removal, quadric_value, removal_bound, vertex_normals, Carried, Quadric,
    QuadricRemoval,
};

/// How a node is evaluated (Section 1.1); the node with the lowest value goes first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Criterion {
    /// (a) The mean angle between the node's edges and the projection plane (Fig. 2a).
    Angle,
    /// (b) The mean absolute difference between the node's scalar and its neighbours' (Fig. 2b).
    Scalar,
    /// The deviation the removal would cause: the node's scalar (or, without a scalar field,
    /// its height above the projection plane) minus the value the re-triangulated hole
    /// interpolates at the node's projection.
    Error,
    /// Accumulated error (an extension for surfaces in 3-D, after Garland and Heckbert's
    /// quadrics and error-bounded simplification): every node carries the area-weighted
    /// squared-distance quadric of the original planes it stands for ([`Quadric`],
    /// [`initial_quadrics`]), passed on to the three corners of the triangle it lands on
    /// when it goes ([`landing`]); every triangle carries a bound on how far the original
    /// points it covers lie from it, which a removal's new triangles take as the largest
    /// bound of the fan plus how far the fan lies from them ([`removal_bound`],
    /// [`crossing_deviation`]). The value ([`quadric_value`]) is a length: the larger of the
    /// quadric's root mean square distance `√(Q(p)/W)` at the landing point and that bound.
    /// In per-fan projection a node whose fan is a simple star in no axis plane may still go
    /// when its ring is a simple polygon in one (the hole is then a disc on the ring; the
    /// bound becomes an estimate there). The ear-cut hole is retriangulated towards the fan
    /// by diagonal flips ([`flip_toward_fan`]).
    Quadric,
    /// [`Quadric`](Criterion::Quadric) when holes are cut in per-fan planes (surfaces in
    /// 3-D), [`Error`](Criterion::Error) when in the global xy plane (height fields, planar
    /// FEM meshes).
    Auto,
}

crate::choice::named_enum!(Criterion {
    Angle => "angle",
    Scalar => "scalar",
    Error => "error",
    Quadric => "quadric",
    Auto => "auto",
});

impl Criterion {
    /// The criterion that runs: [`Criterion::Auto`] resolved by whether holes are cut in the
    /// global xy plane.
    pub fn resolve(self, global_xy: bool) -> Criterion {
        match (self, global_xy) {
            (Criterion::Auto, true) => Criterion::Error,
            (Criterion::Auto, false) => Criterion::Quadric,
            (c, _) => c,
        }
    }

    /// Whether the value comes from the planned re-triangulation (so evaluating plans it).
    pub(crate) fn plans(self) -> bool {
        matches!(self, Criterion::Error | Criterion::Quadric)
    }

    /// Whether the queue measures its values in diagonals of the input
    /// ([`BucketQueue::in_units`]), so that the input's units do not change the order: the
    /// quadric criterion's values are always lengths. The paper's criteria keep eq. (2) on
    /// their values as printed (the error criterion reads a scalar field when there is one,
    /// and on the height grids of Table 1 measuring heights in diagonals changed the errors
    /// both ways, by up to 15 %).
    ///
    /// [`BucketQueue::in_units`]: bucket::BucketQueue::in_units
    pub(crate) fn in_diagonals(self) -> bool {
        self == Criterion::Quadric
    }
}

/// What happens to nodes on the mesh border.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BorderPolicy {
    /// Border nodes are never put in the queue (the paper's option).
    Exclude,
    /// A border node is queued only while removing it leaves the border intact: it lies
    /// exactly on the segment between its two border neighbours — in the xy plane when the
    /// mesh is decimated in the global xy projection (the domain's outline stays; heights
    /// along it may be simplified), in 3-D otherwise. Checked exactly. (`outline`.)
    Intact,
    /// Border nodes are removed like interior ones (an extension for meshes with holes): the
    /// hole of a border node is its ring closed by the new border edge from its last to its
    /// first neighbour, valid when every inner ring node lies strictly left of that edge in
    /// the projection (exact signs; under the quadric criterion, when the ring closed by it
    /// is a simple polygon) and the edge is new (so no border loop closes up). The
    /// quadric criterion measures the border's error through border-edge planes
    /// ([`initial_quadrics`]); a border node lands on its new border edge ([`landing`]).
    Simplify,
    /// [`Intact`](BorderPolicy::Intact) when holes are cut in the global xy plane (an FE
    /// domain's outline stays exact), [`Simplify`](BorderPolicy::Simplify) otherwise.
    Auto,
}

crate::choice::named_enum!(BorderPolicy {
    Exclude => "keep",
    Intact => "outline",
    Simplify => "simplify",
    Auto => "auto",
});

impl BorderPolicy {
    /// The policy that runs: [`BorderPolicy::Auto`] resolved by whether holes are cut in the
    /// global xy plane.
    pub fn resolve(self, global_xy: bool) -> BorderPolicy {
        match (self, global_xy) {
            (BorderPolicy::Auto, true) => BorderPolicy::Intact,
            (BorderPolicy::Auto, false) => BorderPolicy::Simplify,
            (b, _) => b,
        }
    }
}

/// How many rounds the kept nodes are fitted to the original vertices after the last
/// removal ([`fit`]: least squares, flipping no triangle, recorded in the history so that
/// undecimation stays exact).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fit {
    /// [`Fit::DEFAULT_ROUNDS`] on surfaces in 3-D (holes cut in per-fan planes); none in the
    /// global xy plane (height fields and FE meshes keep their nodes, as the paper does).
    Auto,
    /// This many rounds (0: the kept nodes stay where they are).
    Rounds(usize),
}

impl Fit {
    /// The rounds [`Fit::Auto`] runs on surfaces in 3-D: on the dragon scan at 1 % of the
    /// nodes two rounds take the RMS distance from 0.130 % to 0.078 % of the diagonal
    /// (`reports/decimate.md`); in trials one round gave about 0.081 %, three about 0.073 %
    /// with more triangles flipped against the original.
    pub const DEFAULT_ROUNDS: usize = 2;

    /// The rounds that run: [`Fit::Auto`] resolved by whether holes are cut in the global xy
    /// plane.
    pub fn resolve(self, global_xy: bool) -> usize {
        match (self, global_xy) {
            (Fit::Auto, true) => 0,
            (Fit::Auto, false) => Fit::DEFAULT_ROUNDS,
            (Fit::Rounds(n), _) => n,
        }
    }
}

impl std::str::FromStr for Fit {
    type Err = crate::UnknownName;

    /// `auto` or a number of rounds.
    fn from_str(s: &str) -> Result<Fit, crate::UnknownName> {
        if s == "auto" {
            return Ok(Fit::Auto);
        }
        s.parse().map(Fit::Rounds).map_err(|_| crate::UnknownName {
            what: "Fit",
            got: s.to_string(),
            expected: &["auto", "a number of rounds"],
        })
    }
}

impl std::fmt::Display for Fit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Fit::Auto => f.write_str("auto"),
            Fit::Rounds(n) => write!(f, "{n}"),
        }
    }
}

/// Which plane the holes are triangulated in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProjectionChoice {
    /// `Xy` when every triangle of the input has positive area in the xy plane (height
    /// fields, planar FEM meshes), otherwise `PerFan`.
    Auto,
    /// The xy plane for every fan; the input must be positively oriented in it.
    Xy,
    /// For each fan the axis plane most aligned with its area-weighted normal.
    PerFan,
}

crate::choice::named_enum!(ProjectionChoice {
    Auto => "auto",
    Xy => "xy",
    PerFan => "per-fan",
});

/// A projection onto an axis plane: drop axis `drop`, keep the other two in the right-handed
/// order, swapped when the plane's normal points to the negative side.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Plane {
    /// The axis dropped (0 = x, 1 = y, 2 = z).
    pub drop: usize,
    /// Whether the kept two are swapped (the normal points to the negative side).
    pub flip: bool,
}

impl Plane {
    /// The xy plane seen from +z.
    pub const XY: Plane = Plane {
        drop: 2,
        flip: false,
    };

    /// The two kept coordinate axes, in the order that makes the projection orientation
    /// preserving for a normal pointing along +drop (or −drop when flipped): the projection
    /// of the point whose coordinates are their own indices.
    pub fn axes(self) -> (usize, usize) {
        let [a, b] = self.project([0.0, 1.0, 2.0]);
        (a as usize, b as usize)
    }

    /// The projection of `p` (exact: it only selects coordinates). The axes are constants
    /// per arm, so a projection is two loads (no division, no bounds check).
    #[inline]
    pub fn project(self, p: [f64; 3]) -> [f64; 2] {
        match (self.drop, self.flip) {
            (0, false) => [p[1], p[2]],
            (0, true) => [p[2], p[1]],
            (1, false) => [p[2], p[0]],
            (1, true) => [p[0], p[2]],
            (_, false) => [p[0], p[1]],
            (_, true) => [p[1], p[0]],
        }
    }

    /// The axis plane most aligned with `normal` (largest absolute component, the lowest
    /// axis on ties).
    pub fn most_aligned(normal: [f64; 3]) -> Plane {
        let mut drop = 0;
        for axis in [1, 2] {
            if normal[axis].abs() > normal[drop].abs() {
                drop = axis;
            }
        }
        Plane {
            drop,
            flip: normal[drop] < 0.0,
        }
    }
}

/// The axis planes other than [`Plane::most_aligned`] in which a fan whose area-weighted
/// normal is `normal` may still be a simple star: the other two axes in decreasing order of
/// `|normal|` component (the lower axis on ties), each seen from the side its component points
/// to.
pub fn fallback_planes(normal: [f64; 3]) -> impl Iterator<Item = Plane> {
    let first = Plane::most_aligned(normal).drop;
    let mut rest: Vec<usize> = (0..3).filter(|&k| k != first).collect();
    if normal[rest[1]].abs() > normal[rest[0]].abs() {
        rest.swap(0, 1);
    }
    rest.into_iter()
        .filter(move |&k| normal[k] != 0.0)
        .map(move |drop| Plane {
            drop,
            flip: normal[drop] < 0.0,
        })
}

/// The area-weighted normal of a fan around `centre` with `ring` in order (`closed` for an
/// interior node), in `f64`: the heuristic that picks the projection plane in both paths.
pub fn fan_normal(centre: [f64; 3], ring: &[[f64; 3]], closed: bool) -> [f64; 3] {
    let mut n = [0.0; 3];
    let count = if closed { ring.len() } else { ring.len() - 1 };
    for i in 0..count {
        let a = crate::mesh::area_vector(centre, ring[i], ring[(i + 1) % ring.len()]);
        for k in 0..3 {
            n[k] += a[k];
        }
    }
    n
}

/// The projection both engines use for the whole mesh: `None` for per-fan planes; the xy
/// plane when every triangle is positive there (`nonpositive_in_xy` finds none); otherwise
/// per-fan planes under `Auto` and an error naming the first bad triangle under `Xy`.
pub(crate) fn global_plane(
    mesh: &Mesh,
    choice: ProjectionChoice,
    nonpositive_in_xy: impl Fn(&[u32; 3]) -> bool + Sync + Send,
) -> Result<Option<Plane>, DecimateError> {
    use crate::par::prelude::*;
    if choice == ProjectionChoice::PerFan {
        return Ok(None);
    }
    // On all cores, in chunks (a plain loop each); the first offending triangle in order is
    // reported.
    const CHUNK: usize = 1 << 16;
    let first = mesh
        .triangles
        .par_chunks(CHUNK)
        .enumerate()
        .filter_map(|(i, tris)| {
            tris.iter()
                .position(&nonpositive_in_xy)
                .map(|k| i * CHUNK + k)
        })
        .min();
    match (choice, first) {
        (_, None) => Ok(Some(Plane::XY)),
        (ProjectionChoice::Xy, Some(t)) => Err(DecimateError::NotProjectable {
            triangle: t,
            tri: mesh.triangles[t],
        }),
        _ => Ok(None),
    }
}

/// When the decimation stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Target {
    /// Keep this fraction of the surface's nodes (0 < f ≤ 1), rounded to the nearest count.
    /// Both targets count only the nodes of some triangle: vertices no triangle uses have
    /// no fan to remove and are carried through unchanged ([`Stats::unused`]).
    Keep(f64),
    /// Keep this many of the surface's nodes (as [`Target::Keep`] counts them).
    Nodes(usize),
    /// Remove nodes while their evaluation value is at most this bound.
    ErrorBound(f64),
}

/// The decimation's settings.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct Options {
    /// How nodes are evaluated ([`Criterion::Auto`] by default: the error criterion on height
    /// fields and planar meshes, the quadric one on surfaces in 3-D).
    pub criterion: Criterion,
    /// When to stop (keep 1 % of the nodes by default).
    pub target: Target,
    /// What may happen to border nodes ([`BorderPolicy::Auto`] by default: the outline stays
    /// on height fields and planar meshes, borders are simplified on surfaces in 3-D).
    pub border: BorderPolicy,
    /// The plane holes are triangulated in ([`ProjectionChoice::Auto`] by default).
    pub projection: ProjectionChoice,
    /// Rounds of fitting the kept nodes to the original after the last removal
    /// ([`Fit::Auto`] by default: two on surfaces in 3-D, none on height fields and planar
    /// meshes).
    pub fit: Fit,
    /// On surfaces in 3-D (holes cut in per-fan planes), under every criterion, refuse every
    /// removal (and fit move) that would leave a triangle facing against the original surface
    /// nearest its centroid ([`faces_against_original`]; the count [`quality::deviation`]
    /// reports as flipped), so that the result has none. In the global xy plane (height
    /// fields, planar meshes) the test is not run: every triangle stays counter-clockwise in
    /// that plane, facing the same side of it as the original. Costs a closest-point search
    /// per new triangle; `true` by default.
    pub facing: bool,
    /// The constant `k` of eq. (1): `m = ⌊n/k⌋` intervals.
    pub k: usize,
    /// Nodes with more neighbours than this are not removed (the history stores ring
    /// positions in one byte; ear cutting is `O(l²)` in the valence `l`).
    pub max_valence: usize,
    /// Re-bin the bucket queue when re-evaluated values outgrow its range (an extension of
    /// the paper); `false` keeps the paper's boundaries fixed from the initial range.
    pub rebin: bool,
    /// Re-evaluate a removed node's queued neighbours when they reach the front of the queue
    /// rather than at once (an extension of the paper); `false` is the paper's step.
    pub lazy: bool,
    /// Let the fast path evaluate the nodes the queue gives next on a second thread while
    /// the loop removes (when the machine has more than one core and the mesh at least
    /// 10,000 nodes). The result is the same either way.
    pub look_ahead: bool,
    /// The engine: [`Path::Exact`], or the fast one for [`Path::Fast`] / [`Path::Filtered`]
    /// (the default).
    pub path: Path,
    /// The translation [`decimate`] ran the engine in (none unless the mesh is far from the
    /// origin): the fit rounds its moves so that they translate back exactly.
    pub(crate) origin: origin::Origin,
}

crate::choice::setters!(Options {
    with_criterion => criterion: Criterion,
    with_target => target: Target,
    with_border => border: BorderPolicy,
    with_projection => projection: ProjectionChoice,
    with_fit => fit: Fit,
    with_facing => facing: bool,
    with_k => k: usize,
    with_max_valence => max_valence: usize,
    with_rebin => rebin: bool,
    with_lazy => lazy: bool,
    with_look_ahead => look_ahead: bool,
    with_path => path: Path,
});

impl Default for Options {
    fn default() -> Self {
        Options {
            criterion: Criterion::Auto,
            target: Target::Keep(0.01),
            border: BorderPolicy::Auto,
            projection: ProjectionChoice::Auto,
            fit: Fit::Auto,
            facing: true,
            k: 10,
            max_valence: 64,
            rebin: true,
            lazy: true,
            look_ahead: true,
            path: Path::Filtered,
            origin: origin::Origin::default(),
        }
    }
}

/// What went wrong.
#[derive(Debug, Error)]
pub enum DecimateError {
    #[error(transparent)]
    /// The mesh is invalid (its error names the element).
    Mesh(#[from] MeshError),
    #[error("criterion {0:?} needs a nodal scalar field and the mesh has none")]
    /// The criterion needs a nodal scalar field and the mesh has none.
    NoScalars(Criterion),
    #[error("bad option: {0}")]
    /// An option is out of range for this mesh (the message names it).
    BadOption(String),
    #[error("triangle {triangle} ({tri:?}) has non-positive area in the xy plane: the mesh is not projectable onto xy (use the per-fan projection)")]
    /// The xy projection was asked for and a triangle is not positive in it.
    NotProjectable {
        /// The triangle's index.
        triangle: usize,
        /// Its nodes.
        tri: [u32; 3],
    },
    #[error(transparent)]
    /// The history could not be built or applied.
    History(#[from] HistoryError),
}

/// The counts and time of one decimation run.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct Stats {
    /// Nodes of the input.
    pub nodes_in: usize,
    /// Nodes kept (with the [`unused`](Self::unused) vertices).
    pub nodes_out: usize,
    /// Vertices of the input that no triangle uses: carried through unchanged and not
    /// counted by the [`Target`]s.
    pub unused: usize,
    /// The node count the [`Target`] asked for (with the unused vertices); `None` for an
    /// error bound. More nodes are left when no further removal was valid.
    pub target_nodes: Option<usize>,
    /// Triangles of the input.
    pub triangles_in: usize,
    /// Triangles of the output.
    pub triangles_out: usize,
    /// Nodes removed (history steps).
    pub removed: usize,
    /// Queue pops whose removal was refused (hole not triangulable validly, border not
    /// intact, valence over the limit); such a node re-enters when a neighbour goes.
    pub refused: usize,
    /// Queue pops whose planned fill faced against the original surface and whose cheapest
    /// fan fill that does not costs more than the interval they were taken from: filed again
    /// at that cost rather than removed now.
    pub deferred: usize,
    /// Removals whose planned fill faced against the original surface and that took the
    /// cheapest fan fill that does not instead.
    pub fan_filled: usize,
    /// Intervals `m` of eq. (1).
    pub intervals: usize,
    /// Times the bucket queue was re-binned ([`Options::rebin`]).
    pub rebuilds: usize,
    /// Node evaluations after the initial pass (neighbours, and stale nodes with
    /// [`Options::lazy`]).
    pub evaluations: usize,
    /// Nodes taken from the queue.
    pub taken: usize,
    /// Taken nodes whose evaluation and plan came from the lookahead thread
    /// ([`Options::look_ahead`]).
    pub evaluated_ahead: usize,
    /// Taken nodes removed by the plan of the evaluation they were filed after, their fans
    /// unchanged since (neither evaluated ahead nor again).
    pub remembered: usize,
    /// Whether holes were triangulated in the xy plane (else per fan).
    pub projection_xy: bool,
    /// The criterion that ran ([`Criterion::Auto`] resolved).
    pub criterion: String,
    /// The border policy that ran ([`BorderPolicy::Auto`] resolved).
    pub border: String,
    /// Nodes the fit moved ([`Options::fit`]).
    pub moved: usize,
    /// Rounds of the fit that ran.
    pub fit_rounds: usize,
    /// Seconds of the decimation itself (adjacency, evaluation, queue, removals, fit).
    pub seconds: f64,
    /// Of `seconds`, those of the fit.
    pub fit_seconds: f64,
    /// Of `seconds`, those before the first removal: the adjacency, the initial evaluation
    /// and the queue fill.
    pub setup_seconds: f64,
    /// When the decimation stopped above its target because no further removal was valid:
    /// why each node left cannot go (both engines give the same counts; `None` otherwise).
    pub blocked: Option<Blocked>,
}

/// Why the nodes left by a decimation that stopped above its target cannot go, each counted
/// once, under the first rule that holds it (in this order). The counts add up to the nodes
/// left that some triangle uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct Blocked {
    /// Border nodes the border policy keeps ([`BorderPolicy`]).
    pub border: usize,
    /// Nodes over the valence limit ([`Options::max_valence`]).
    pub valence: usize,
    /// Nodes whose hole no allowed plane can hold: the fan is a simple star in no axis plane
    /// (nor, under the quadric criterion, the ring a simple polygon), or the ears cannot be
    /// cut.
    pub no_plane: usize,
    /// Nodes whose new triangles would fold the surface over (the quadric criterion,
    /// [`folds`]).
    pub fold: usize,
    /// Nodes whose new triangles would repeat an edge or a triangle of the mesh.
    pub topology: usize,
    /// Nodes whose new triangles would face against the original surface
    /// ([`faces_against_original`], the facing test).
    pub facing: usize,
    /// Nodes that could go (none when the queue ran dry; kept so that the counts add up).
    pub removable: usize,
}

/// A finished decimation: its history (from which the decimated mesh and every stage back to
/// the original follow) and its statistics.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// The history that undecimates the output.
    pub history: History,
    /// Counts and times.
    pub stats: Stats,
    /// The decimated mesh (kept nodes in original order, live triangle slots in order).
    pub mesh: crate::mesh::Mesh,
}

/// Decimates `mesh` with the engine [`Options::path`] names: the exact engine for
/// [`Path::Exact`], the fast one (adaptive predicates: certified `f64` with an exact fallback,
/// never uncertain) for [`Path::Fast`] and [`Path::Filtered`].
///
/// A mesh far from the origin is decimated in local coordinates, translated exactly to near
/// its bounding box's centre on each axis whose coordinates all have one sign and lie within
/// a factor two of each other (so that the translation is exact both ways), and the outcome
/// is translated back: the result does not depend on where the mesh sits, to within the
/// last bits of its coordinates.
pub fn decimate(mesh: &crate::mesh::Mesh, options: &Options) -> Result<Outcome, DecimateError> {
    let engine = |mesh: &crate::mesh::Mesh, options: &Options| match options.path {
        Path::Exact => exact::decimate(mesh, options),
        Path::Fast | Path::Filtered => fast::decimate(mesh, options),
    };
    let origin = origin::Origin::for_vertices(&mesh.vertices);
    if origin.is_none() {
        return engine(mesh, options);
    }
    let local = origin.local_mesh(mesh);
    let mut options = options.clone();
    options.origin = origin;
    let mut outcome = engine(&local, &options)?;
    for v in &mut outcome.mesh.vertices {
        *v = origin.to_global(*v);
    }
    let history = &mut outcome.history;
    history.map_coordinates(|p| origin.to_global(p));
    history.original_fingerprint = history::fingerprint(mesh);
    history.decimated_fingerprint = history::fingerprint(&outcome.mesh);
    Ok(outcome)
}

/// Validates options against a mesh (shared by both engines).
pub(crate) fn check_options(
    mesh: &crate::mesh::Mesh,
    options: &Options,
) -> Result<(), DecimateError> {
    if options.criterion == Criterion::Scalar && mesh.scalars.is_none() {
        return Err(DecimateError::NoScalars(options.criterion));
    }
    if options.k == 0 {
        return Err(DecimateError::BadOption(
            "k (eq. 1) must be positive".into(),
        ));
    }
    if !(3..=255).contains(&options.max_valence) {
        return Err(DecimateError::BadOption(format!(
            "max valence {} outside 3..=255",
            options.max_valence
        )));
    }
    match options.target {
        Target::Keep(f) if !(f > 0.0 && f <= 1.0) => Err(DecimateError::BadOption(format!(
            "keep fraction {f} outside (0, 1]"
        ))),
        Target::ErrorBound(e) if !(e >= 0.0 && e.is_finite()) => Err(DecimateError::BadOption(
            format!("error bound {e} must be finite and non-negative"),
        )),
        _ => Ok(()),
    }
}

/// Criterion (a) for one edge (Fig. 2a): the angle between the edge vector `d` and the
/// projection plane, `atan2(|d_normal|, √(d_a² + d_b²))`, in `f64`.
pub fn edge_angle(d: [f64; 3], plane: Plane) -> f64 {
    let (a, b) = plane.axes();
    d[plane.drop]
        .abs()
        .atan2((d[a] * d[a] + d[b] * d[b]).sqrt())
}

/// Where both paths start a node's counter-clockwise ring (so that ear-cutting ties, `f64`
/// sums over neighbours and the history agree): the border neighbour that starts the ring,
/// or for an interior node the neighbour of lowest id.
pub fn canonical_start(ring: &[u32], border: bool) -> usize {
    if border {
        return 0;
    }
    let mut best = 0;
    for (i, &w) in ring.iter().enumerate() {
        if w < ring[best] {
            best = i;
        }
    }
    best
}

/// A small deterministic generator for the unit tests (xorshift64).
#[cfg(test)]
pub(crate) struct TestRng(pub u64);

#[cfg(test)]
impl TestRng {
    /// The next 64-bit word.
    pub(crate) fn word(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// The next word modulo `m`.
    pub(crate) fn below(&mut self, m: u64) -> u64 {
        self.word() % m
    }
}
