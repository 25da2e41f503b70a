//! # geocert
//!
//! An exact-arithmetic verification and reference engine for geometric algorithms.
//! Every algorithm exists twice: a **reference path** in exact rational arithmetic that reads
//! like the mathematics and is never wrong, and a **fast path** in `f64` whose decisions are
//! either certified by a rigorous error bound or say `Uncertain`. The two are compared by
//! property tests, differential fuzzing and exhaustive proofs, and `geocert prove` publishes
//! the results as reports.
//!
//! ## Map
//!
//! * [`num`] — the scalar layer: [`num::Rational`], lossless `f64` conversion, parsing,
//!   certified [`num::Interval`]s, the four-valued [`num::Sign`], the [`num::Field`] trait.
//! * [`bernstein`] — tensor Bernstein polynomials (generic, sign-only integer, certified `f64`)
//!   and the subdivision positivity prover with checkable certificates.
//! * [`bspline`] — knot vectors, de Boor, Boehm and Oslo insertion, Bézier extraction, tensor
//!   splines, Mørken products.
//! * [`decimate`] — node decimation with the exponential-interval bucket queue, ear cutting,
//!   exact undecimation (Krivograd et al.), exact and fast engines, an independent checker.
//! * [`memory`] — large working arrays on transparent huge pages (Linux).
//! * [`proofs`] — the exhaustive proofs (source in `proofs/`), run by `cargo test` and
//!   `geocert prove`.
//! * [`report`] — writes the Markdown reports in `reports/` from measured runs.
//! * `strategies` (feature `proptest`) — proptest strategies for other crates' property tests.

pub mod bernstein;
pub mod bspline;
pub mod decimate;
pub mod ffd;
pub mod fuzzing;
pub mod mc;
pub mod memory;
pub mod mesh;
pub mod num;
#[path = "../proofs/mod.rs"]
pub mod proofs;
pub mod report;
#[cfg(feature = "proptest")]
pub mod strategies;
