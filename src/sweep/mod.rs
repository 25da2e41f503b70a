//! Perspective silhouettes of general swept volumes (Seong, Kim, Kim and Elber, "Perspective
//! silhouette of a general swept volume", The Visual Computer 22, 2006).
//!
//! An object bounded by rational patches `S(u,v)` moves under an affine map `A(t)`,
//! `t ∈ [a, b]`; its swept volume `∪ A(t)[O]` is seen from an eye `P`. The silhouette of the
//! sweep's envelope is the curve `Z₁ = {F = G = 0}` in `(u, v, t)` (Section 2):
//!
//! * `F = det[A′(t)S, M(t)S_u, M(t)S_v]` (eq. 1, `M` the linear part of `A`): the point is on
//!   the characteristic curve, where the envelope touches the moving object;
//! * `G = ⟨A(t)S − P, cof(M(t)) N⟩` with `N = S_u × S_v`: the point is on the moving
//!   object's contour seen from `P`.
//!
//! Eq. 2 of the paper writes `G = ⟨A(t)S − P, A(t)N⟩`, which is the contour only when `M(t)`
//! is a similarity: a normal transforms by the cofactor matrix `cof(M) = det(M)·M⁻ᵀ`
//! (`(Ma) × (Mb) = cof(M)(a × b)`). [`Equations::g_printed`] keeps the printed form so that
//! the difference can be measured.
//!
//! Both are built as exact tensor Bernstein polynomials in `(u, v, t)` through homogeneous
//! coordinates, so that no denominator is ever divided ([`equations`]). Their common zeros are
//! traced with the certified solver's curve tracer ([`crate::solve::trace`]) and the
//! `t`-extreme points `Z₀ = {F = G = H = 0}`, `H = F_u G_v − F_v G_u` (eq. 3), are its
//! certified extreme points along `t`; Algorithm 1's three component types follow from them
//! ([`silhouette`]). The degrees are bounded by the solver's (eq. 3's `H` has the sum of
//! `F`'s and `G`'s degrees; up to [`crate::solve::MAX_DEGREE`] per variable): bicubic patches
//! under low-degree motions fit, higher degrees are refused with the degrees named.
//!
//! The moving eye of Section 4: the critical events where the silhouette's topology can
//! change ([`events`], with the Lagrange condition in place of eqs. 6–9, module docs there).
//! Between events, frames are continued from the previous frame ([`frames`]); a traced
//! silhouette of a scene with an eye path is seen from `P(r₀)`.

mod corners;
mod edges;
mod equations;
mod events;
mod frames;
mod rulings;
mod scene;
mod silhouette;

pub use corners::{CapBorderTouch, CapCornerPassage, CornerCrossing};
pub use equations::{equations, patch_normal, Equations, Normal};
pub use events::{
    event_groups, event_systems, events, group_of_each, verify_border_root, verify_event,
    verify_events, BorderRoot, Event, EventKind, EventSystem, Events, EVENT_TOLERANCE,
};
pub use frames::{frames, Frame, FrameCurve, Frames, CONTINUATION_TOLERANCE, OVERSHOOT};
pub use rulings::{ruling_margin, Ruling, RulingEvidence, RULING_DEPTH, RULING_MARGIN};
pub use scene::{builtin_scene, builtin_scene_json, scene_from_json, Patch, BUILTIN_SCENES};
// What the report measures with (feature `reports`).
#[cfg(feature = "reports")]
pub(crate) use silhouette::{apply_motion, eye_point};
pub use silhouette::{
    silhouette, t_extreme_systems, verify_cap_border_touch, verify_cap_corner_passage,
    verify_corner_crossing, verify_ruling, verify_t_extreme, ComponentEnd, ComponentKind,
    ComponentType, SilhouetteComponent, SilhouetteOptions, Silhouettes, TExtreme, JOIN_TOLERANCE,
    MIN_RESOLUTION,
};

use crate::bernstein::BernsteinError;
use crate::num::Rational;
use crate::solve::SolveError;
use thiserror::Error;

/// The highest patch degree per parameter.
pub const MAX_PATCH_DEGREE: usize = 6;
/// The highest degree in `t` of a motion entry (and of an eye path in `r`).
pub const MAX_MOTION_DEGREE: usize = 6;

/// A polynomial in one variable by its power-basis coefficients `[c0, c1, …]`.
pub type Poly = Vec<Rational>;

/// The motion `A(t) p = (M̂(t) p + T̂(t)) / δ(t)`: a polynomial linear part, a polynomial
/// translation and a common denominator `δ > 0` on `[a, b]` (1 unless a rotation is given in
/// quaternion form, Section 2's "continuous affine transformation").
#[derive(Clone, Debug, PartialEq)]
pub struct Motion {
    /// `M̂`, row by row.
    pub linear: [[Poly; 3]; 3],
    /// `T̂`.
    pub translation: [Poly; 3],
    /// `δ`.
    pub denominator: Poly,
}

/// Where the eye is.
#[derive(Clone, Debug, PartialEq)]
pub enum Eye {
    /// A fixed point.
    Point([Rational; 3]),
    /// A polynomial path `P(r)`, `r ∈ [r0, r1]` (Section 4).
    Path {
        /// `P(r)` per coordinate.
        path: [Poly; 3],
        /// The parameter interval.
        r: (Rational, Rational),
    },
}

/// One object's boundary: rational Bézier patches on the unit square.
#[derive(Clone, Debug, PartialEq)]
pub struct Surface {
    /// What it was built from (`sphere`, `bezier`, …).
    pub name: String,
    /// Its patches.
    pub patches: Vec<Patch>,
}

/// A swept scene: surfaces, the time interval, the motion and the eye.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The moving surfaces.
    pub surfaces: Vec<Surface>,
    /// `[a, b]`, `a < b`.
    pub t: (Rational, Rational),
    /// `A(t)`.
    pub motion: Motion,
    /// `P` or `P(r)`.
    pub eye: Eye,
}

/// Why a scene was refused or could not be processed.
#[derive(Clone, Debug, Error)]
#[non_exhaustive]
pub enum SweepError {
    /// The scene file is not JSON.
    #[error("scene is not valid JSON at line {line}, column {column}: {why}")]
    Json {
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The parser's message.
        why: String,
    },
    /// A field is missing or malformed.
    #[error("field `{field}`: {why}")]
    Field {
        /// The field, e.g. `surfaces[1].bezier.points[3]`.
        field: String,
        /// What is wrong with it.
        why: String,
    },
    /// No built-in scene of that name.
    #[error("no built-in scene `{0}` (built-ins: {names})", names = BUILTIN_SCENES.join(", "))]
    UnknownBuiltin(String),
    /// `det M(t)` vanishes somewhere on `[a, b]`, or `δ(t)` does not stay positive.
    #[error("singular motion: {why}")]
    SingularMotion {
        /// Where or why.
        why: String,
    },
    /// A patch whose normal `S_u × S_v` vanishes identically.
    #[error(
        "surface {surface}, patch {patch}: degenerate (its normal S_u × S_v vanishes identically)"
    )]
    DegeneratePatch {
        /// The surface.
        surface: usize,
        /// The patch.
        patch: usize,
    },
    /// The eye lies on the swept surface (a certified root of `A(t)S(u,v) = P`), or the solver
    /// could not clear a box around where it may: the contour is not defined there.
    #[error("the eye lies on (or cannot be certified off) surface {surface}, patch {patch} at t ∈ [{t_lo}, {t_hi}]")]
    EyeOnSurface {
        /// The surface.
        surface: usize,
        /// The patch.
        patch: usize,
        /// The time's certified interval, lower end.
        t_lo: f64,
        /// Upper end.
        t_hi: f64,
    },
    /// The eye path meets the moving surface (a witness point), or that it does not could not
    /// be certified within the prover's limits (`r`, `t` NaN): the silhouette degenerates
    /// there, and so would the events.
    #[error("the eye path meets the moving surface {surface}, patch {patch}, near r = {r}, t = {t} (or this could not be ruled out)")]
    EyePathOnSurface {
        /// The surface.
        surface: usize,
        /// The patch.
        patch: usize,
        /// The eye parameter of the witness.
        r: f64,
        /// Its time.
        t: f64,
    },
    /// `F` vanishes on the whole patch: the patch moves within itself (a cylinder along its
    /// axis, a surface of revolution turning about its axis), so the envelope is the swept
    /// surface itself, not a family of characteristic curves.
    #[error("surface {surface}, patch {patch}: F vanishes identically (the patch moves within itself, so its characteristic set is the whole patch, not a curve)")]
    CharacteristicPatch {
        /// The surface.
        surface: usize,
        /// The patch.
        patch: usize,
    },
    /// A patch edge is characteristic at every time and the eye sees it edge-on at every
    /// time too (`F` and `G` both vanish on that face): the silhouette covers the swept edge,
    /// a surface rather than a curve.
    #[error("surface {surface}, patch {patch}: F and G vanish on the whole face {name} = {end} (the silhouette covers that swept edge)", name = ["u", "v"][*axis], end = u8::from(*upper))]
    SilhouetteCoversEdge {
        /// The surface.
        surface: usize,
        /// The patch.
        patch: usize,
        /// The face's parameter (0 = u, 1 = v).
        axis: usize,
        /// At its upper end.
        upper: bool,
    },
    /// `F` and `G` both vanish on a whole corner line `(u, v) = corner` of a patch: the
    /// silhouette stays on that patch corner at every time (a curve along an edge of the
    /// `(u, v, t)` box, which is not traced).
    #[error("surface {surface}, patch {patch}: the silhouette stays on the patch corner (u, v) = ({u}, {v}) at every time", u = u8::from(corner[0]), v = u8::from(corner[1]))]
    SilhouetteAlongCorner {
        /// The surface.
        surface: usize,
        /// The patch.
        patch: usize,
        /// The corner: whether `u = 1`, whether `v = 1`.
        corner: [bool; 2],
    },
    /// The Bernstein kernel refused an operation.
    #[error("Bernstein kernel: {0}")]
    Bernstein(#[from] BernsteinError),
    /// The solver refused a system.
    #[error("solver: {0}")]
    Solve(#[from] SolveError),
}

impl SweepError {
    pub(crate) fn field(field: impl Into<String>, why: impl Into<String>) -> SweepError {
        SweepError::Field {
            field: field.into(),
            why: why.into(),
        }
    }
}
