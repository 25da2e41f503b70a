//! FFD injectivity (J. E. Gain and N. A. Dodgson, "Preventing self-intersection under
//! free-form deformation", IEEE Transactions on Visualization and Computer Graphics 7(4),
//! 289–298, 2001, doi:10.1109/2945.965344).
//!
//! A trivariate FFD is injective on its hyperpatch iff it is C¹ and `det J > 0` everywhere
//! (Theorem 1). geocert decides this exactly, with certificates:
//!
//! * [`Lattice`] — lattices (uniform B-spline or one Bézier cell) and their JSON format
//!   ([`lattices_from_json`]);
//! * [`jacobian_cells_morken`] — `det J` exactly by the Mørken route (eqs. 6–8);
//!   [`jacobian_cell_bezier`] / [`jacobian_cell_scaled`] per cell by Bernstein products
//!   (rational and sign-only integer); [`jacobian_cell_fast`] in `f64` with a certified
//!   error bound;
//! * [`check_injectivity`] — the necessary-and-sufficient test (Section 6) on the path
//!   [`CheckOptions::path`] names, its [`InjectivityCertificate`] and the independent checker
//!   [`verify_injectivity_certificate`];
//! * [`phi_test_exact`], [`bezier_coefficient_test_exact`], [`conic_test_exact`] and their
//!   `_fast` twins — the sufficient tests of Section 7;
//! * [`solve_exact`] / [`solve_fast`] — direct manipulation (Section 4, eq. 4) and
//!   [`injective_drag`] — injective DMFFD (Section 8);
//! * [`deform_points_exact`] / [`deform_points_fast`] — applying a lattice to points.
//!
//! # Example
//!
//! ```
//! use geocert::ffd::{
//!     check_injectivity, lattices_from_json, verify_injectivity_certificate, CheckOptions,
//!     InjectivityCertificate, InjectivityVerdict,
//! };
//! // The undeformed tricubic lattice: F(U) = U, det J = 1 everywhere.
//! let lattice = &lattices_from_json(
//!     r#"{"basis": "bspline", "order": [4, 4, 4], "cells": [1, 1, 1], "points": "identity"}"#,
//! )?[0];
//! let report = check_injectivity(lattice, CheckOptions::new())?;
//! assert!(matches!(report.verdict, InjectivityVerdict::Injective { .. }));
//! // The certificate is re-checked through the other Jacobian route.
//! let certificate = InjectivityCertificate::from_report(lattice, &report).unwrap();
//! println!("{}", verify_injectivity_certificate(&certificate)?);
//! # Ok::<(), geocert::ffd::FfdError>(())
//! ```

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
    jacobian_at, jacobian_cell_bezier, jacobian_cell_scaled, jacobian_cell_scaled_net,
    jacobian_cells_morken, jacobian_cells_morken_scaled, jacobian_in_cell, jacobian_matrix_at,
    jacobian_spline, jacobian_spline_scaled,
};
pub use lattice::{
    lattice_from_value, lattices_from_json, Basis, Lattice, Point, MAX_CELLS, MAX_ORDER,
};
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
