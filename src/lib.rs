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

#![warn(unused_crate_dependencies)]

// The binary's own dependencies, declared by the library's `cli` feature.
#[cfg(feature = "cli")]
use {clap as _, indicatif as _};
// The dev-dependencies the integration tests and benchmarks use, seen by the unit tests too.
#[cfg(test)]
use {approx as _, criterion as _, geocert as _};

mod choice;
pub use choice::{Path, UnknownName};

pub mod bernstein;
pub mod bspline;
pub mod decimate;
pub mod ffd;
pub mod mc;
pub mod mesh;
pub mod num;
#[cfg(feature = "proptest")]
pub mod strategies;

mod fuzzing;
mod memory;
mod par;
#[path = "../proofs/mod.rs"]
mod proofs;
// The report generator is unstable (`internals`) and documented by its module docs only.
#[cfg(feature = "reports")]
#[allow(missing_docs)]
mod report;

/// Unstable internals: the report generator, the fuzz checks, the exhaustive proofs and the
/// memory helpers, public only so that geocert's own binary, fuzz crate, tests and benchmarks
/// can reach them. They change without notice between any two versions; do not depend on
/// them.
#[doc(hidden)]
pub mod internals {
    /// The fuzz targets' checks (each target is a call to one of them).
    pub mod fuzzing {
        pub use crate::fuzzing::*;
    }
    /// The decimation's ear cutter (exposed for its property tests).
    pub mod earcut {
        pub use crate::decimate::earcut::*;
    }
    /// Large working arrays on huge pages; cache prefetch.
    pub mod memory {
        pub use crate::memory::*;
    }
    /// The exhaustive proofs run by `cargo test` and `geocert prove`.
    pub mod proofs {
        pub use crate::proofs::*;
    }
    /// The report generator behind `geocert prove`.
    #[cfg(feature = "reports")]
    pub mod report {
        pub use crate::report::*;
    }
}
