//! FFD injectivity (Gain & Dodgson, "Preventing self-intersection under free-form
//! deformation", IEEE TVCG 7(4), 2001; `../shared/papers/ffd-injectivity-gain-dodgson.txt`).
//!
//! A trivariate FFD is injective on its hyperpatch iff it is C¹ and `det J > 0` everywhere
//! (Theorem 1). geocert decides this exactly, with certificates:
//!
//! * [`lattice`] — lattices (uniform B-spline or one Bézier cell), their JSON format;
//! * [`jacobian`] — `det J` exactly by the Mørken route (eqs. 6–8) and per cell by Bernstein
//!   products (rational and sign-only integer);
//! * [`fast`] — the per-cell Jacobian in `f64` with a certified error bound;
//! * [`injectivity`] — the necessary-and-sufficient test (Section 6), three paths, its
//!   certificates and their independent checker;
//! * [`sufficient`] — the phi, Bézier-coefficient and conic-hull tests (Section 7);
//! * [`manipulation`] — direct manipulation (Section 4) and injective DMFFD (Section 8).

pub(crate) mod deform;
pub(crate) mod fast;
pub(crate) mod injectivity;
pub(crate) mod jacobian;
pub(crate) mod lattice;
pub(crate) mod manipulation;
pub(crate) mod sufficient;

pub use deform::{deform_points_exact, deform_points_fast, FastDeformer, Fit};
pub use fast::{jacobian_cell_fast, JacobianWorkspace};
pub use injectivity::{
    check_injectivity, verify_injectivity_certificate, CertificateRefusal, CheckOptions,
    InjectivityCertificate, InjectivityCheck, InjectivityReport, InjectivityVerdict,
};
pub use jacobian::{
    jacobian_at, jacobian_cell_bezier, jacobian_cell_scaled, jacobian_cells_morken,
    jacobian_in_cell, jacobian_matrix_at, jacobian_spline,
};
pub use lattice::{lattice_from_value, lattices_from_json, Basis, Lattice, Point};
pub use manipulation::{
    compose, constraints_from_json, injective_drag, solve_exact, solve_fast, steps_to_json,
    Constraint, DragOptions, DragStep, DragTest,
};
pub use sufficient::{
    bezier_coefficient_test_exact, bezier_coefficient_test_fast, conic_test_exact, conic_test_fast,
    phi_test_exact, phi_test_fast, ConicOptions, Scope, SufficientVerdict,
};

use thiserror::Error;

/// Errors of the FFD family.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FfdError {
    /// The text is not JSON.
    #[error("not valid JSON at line {line}, column {column}: {why}")]
    Json {
        /// 1-based line of the error.
        line: usize,
        /// 1-based column of the error.
        column: usize,
        /// The parser's message.
        why: String,
    },
    /// A lattice, constraint or certificate field is missing or malformed.
    #[error("lattice {lattice}, field `{field}`: {why}")]
    Input {
        /// The lattice's index in an array input (0 for a single lattice).
        lattice: usize,
        /// The field, e.g. `points[3][1]`.
        field: String,
        /// What is wrong with it.
        why: String,
    },
    /// A parameter point lies outside `[0,a]×[0,b]×[0,c]`.
    #[error("parameter {value} on axis {axis} lies outside the lattice's domain")]
    OutsideDomain {
        /// The axis (0, 1, 2).
        axis: usize,
        /// The coordinate, exactly.
        value: String,
    },
    /// The Bernstein kernel refused an operation (it names the shape mismatch).
    #[error("Bernstein kernel: {0}")]
    Bernstein(#[from] crate::bernstein::BernsteinError),
    /// The B-spline kernel refused an operation.
    #[error("B-spline kernel: {0}")]
    Bspline(#[from] crate::bspline::BsplineError),
    /// The `f64` path cannot carry this input with a certified bound (non-finite values,
    /// magnitudes outside its safe range, a degree-0 axis, an overflowing solve); the exact
    /// path takes it.
    #[error("f64 path: {0}")]
    FastUnfit(&'static str),
    /// [`verify_injectivity_certificate`] refused a certificate.
    #[error("certificate refused: {0}")]
    Certificate(#[from] CertificateRefusal),
    /// Two drag constraints are linearly dependent.
    #[error(
        "constraint {constraint} is dependent on the others (B Bᵀ is singular): drop or move it"
    )]
    RankDeficient {
        /// The first constraint found dependent on the earlier ones.
        constraint: usize,
    },
    /// `InjectSubdiv` reached its depth limit with a piece still not certified.
    #[error("the drag could not be made injective: a piece still fails at depth {depth} (first constraint point {first_point})")]
    DragNotInjective {
        /// The depth limit ([`DragOptions::max_depth`]).
        depth: u32,
        /// The first constraint point of the failing piece, exactly.
        first_point: String,
    },
}

impl From<serde_json::Error> for FfdError {
    fn from(e: serde_json::Error) -> FfdError {
        FfdError::Json {
            line: e.line(),
            column: e.column(),
            why: e.to_string(),
        }
    }
}

impl FfdError {
    /// The same error attributed to lattice `i` of an array.
    pub fn in_lattice(self, i: usize) -> FfdError {
        match self {
            FfdError::Input { field, why, .. } => FfdError::Input {
                lattice: i,
                field,
                why,
            },
            other => other,
        }
    }
}
