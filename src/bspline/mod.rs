//! B-splines: knot vectors, Cox–de Boor evaluation, derivatives, Boehm knot insertion, the
//! Oslo algorithm, conversion to Bézier pieces, blossoms, tensor-product splines, and Mørken
//! products (the exact B-spline coefficients of a product of splines).
//!
//! Conventions (de Boor, *A Practical Guide to Splines*): a spline of degree `p` on knots
//! `s_0 ≤ … ≤ s_{n+p}` with coefficients `c_0 … c_{n−1}` is `Σ c_i N_{i,p}`, `N_{i,p}` supported
//! on `[s_i, s_{i+p+1}]`; its domain is `[s_p, s_n]`.

pub(crate) mod morken;
pub(crate) mod spline;
pub(crate) mod tensor;

pub use morken::{morken_product, product_knots};
pub use spline::Spline;
pub use tensor::{
    basis_product_table, BasisProductTable, BezierCell, ScaledSpline, TableCache, TensorSpline,
};

use thiserror::Error;

/// Errors of the B-spline kernel.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum BsplineError {
    #[error("knot vector is not non-decreasing at position {index}")]
    /// The knot vector decreases somewhere.
    KnotsNotSorted {
        /// The first position where it does.
        index: usize,
    },
    #[error("degree {degree} with {knots} knots needs {expected} coefficients, found {found}")]
    /// The coefficient count does not fit the degree and knots (`knots − degree − 1`).
    CoefficientCount {
        /// The degree.
        degree: usize,
        /// Knots given.
        knots: usize,
        /// Coefficients needed.
        expected: usize,
        /// Coefficients given.
        found: usize,
    },
    #[error("the spline's domain [s_p, s_n] is empty")]
    /// The domain `[s_p, s_n]` is empty.
    EmptyDomain,
    #[error("parameter outside the domain")]
    /// A parameter lies outside the domain.
    OutsideDomain,
    #[error("knot {what} must lie strictly inside the domain")]
    /// A knot to insert is not strictly inside the domain.
    KnotOutsideDomain {
        /// Which knot.
        what: String,
    },
    #[error("the box crosses a knot or leaves the domain on axis {axis}")]
    /// A box asked to lie inside one knot span does not.
    CrossesKnot {
        /// The axis.
        axis: usize,
    },
    #[error("factors live on different domains (factor {factor})")]
    /// Product factors live on different domains.
    DomainMismatch {
        /// The first factor that differs.
        factor: usize,
    },
    #[error("no factors given")]
    /// A product of no factors was asked for.
    NoFactors,
    #[error("dimension mismatch: expected {expected}, found {found}")]
    /// Operands have different numbers of variables.
    DimensionMismatch {
        /// Expected.
        expected: usize,
        /// Found.
        found: usize,
    },
    #[error("Bernstein kernel: {0}")]
    /// The Bernstein kernel refused an operation.
    Bernstein(#[from] crate::bernstein::BernsteinError),
}
