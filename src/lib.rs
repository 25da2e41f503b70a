//! # geocert
//!
//! An exact-arithmetic verification and reference engine for geometric algorithms.
//! Every algorithm exists twice: a **reference path** in exact rational arithmetic that reads
//! like the mathematics and is never wrong, and a **fast path** in `f64` whose decisions are
//! either certified by a rigorous error bound or say `Uncertain`. Every yes/no comes with a
//! certificate that an independent checker re-verifies. Use it as an oracle in property tests
//! and fuzz targets, and cite the reports `geocert prove` generates.
//!
//! ## Map
//!
//! * [`Path`] — the one way every family is told which arithmetic decides (`exact`, `fast`,
//!   `filtered`), as a field of its options.
//! * [`num`] — the scalar layer: [`num::Rational`], lossless `f64` conversion, parsing,
//!   certified [`num::Interval`]s, the four-valued [`num::Sign`], the [`num::Field`] trait.
//! * [`bernstein`] — tensor Bernstein polynomials (generic, sign-only integer, certified `f64`)
//!   and the subdivision positivity prover [`bernstein::prove_positive`] with checkable
//!   certificates.
//! * [`bspline`] — knot vectors, de Boor, Boehm and Oslo insertion, Bézier extraction, tensor
//!   splines, Mørken products.
//! * [`ffd`] — FFD injectivity (Gain & Dodgson 2001): the exact test with certificates, the
//!   sufficient tests, injective direct manipulation.
//! * [`mc`] — marching cubes on regular grids and curvilinear finite elements (Wünsche & Lin):
//!   the proved 656-entry [`table`](mod@mc::table), the face decider, [`mc::grid`], [`mc::fe`] and the
//!   auditor of other programs' tables [`mc::audit`].
//! * [`decimate`] — node decimation and exact undecimation (Krivograd et al. 2003): the bucket
//!   queue, ear cutting, exact and fast engines, the history file, an independent
//!   [`decimate::check`]er.
//! * [`sweep`] — perspective silhouettes of swept volumes (Seong, Kim, Kim & Elber 2006): exact
//!   `F`, `G` (with the cofactor normal) and Algorithm 1 on the certified curve tracer.
//! * [`mesh`] — indexed triangle meshes, PLY/OBJ/STL/VTK readers and writers, topology checks.
//! * `strategies` (feature `proptest`) — proptest strategies for other crates' property
//!   tests.
//!
//! Everything under `geocert::internals` (the report generator, the fuzz checks, the
//! exhaustive proofs) is unstable and hidden from these docs.
//!
//! ## Example
//!
//! Prove a polynomial positive on the unit square on the filtered path, then re-check the
//! certificate with the independent checker:
//!
//! ```
//! use geocert::bernstein::{
//!     certificate_for, poly_from_json, prove_positive, verify_certificate_file,
//!     PositivityOptions, PositivityVerdict,
//! };
//! use geocert::Path;
//!
//! // p(s, t) = (s − ½)² + t + 1/10 in Bernstein form, degrees (2, 1), axis 0 fastest.
//! let p = poly_from_json(&serde_json::json!({
//!     "degrees": [2, 1],
//!     "coeffs": ["7/20", "-3/20", "7/20", "27/20", "17/20", "27/20"],
//! }))?;
//! let verdict = prove_positive(&p, &PositivityOptions::new().with_path(Path::Filtered))?;
//! assert!(matches!(verdict, PositivityVerdict::Positive { .. }));
//! let certificate = certificate_for(&p, &verdict).expect("decided verdicts have one");
//! let check = verify_certificate_file(&certificate)?;
//! println!("{check}");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ## Feature flags
//!
//! * `cli` (default) — the `geocert` binary: argument parsing, progress bars, and `reports`.
//! * `reports` — the report generator behind `geocert prove` and the peers it times
//!   in-process (meshoptimizer); implies `parallel` and `nifti`.
//! * `nifti` — NIfTI-1 volumes (`.nii`, `.nii.gz`) for [`mc::grid`].
//! * `parallel` — parallel passes on all cores (rayon); without it the same passes run on one
//!   thread with identical results.
//! * `proptest` — `geocert::strategies`.
//!
//! A test suite that needs only the algorithms, certificates and strategies depends on
//! `geocert = { version = "0.1", default-features = false, features = ["proptest"] }`.

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
pub mod diamond;
pub mod ffd;
pub mod mc;
pub mod mesh;
pub mod num;
pub mod solve;
#[cfg(feature = "proptest")]
pub mod strategies;
pub mod sweep;

mod fuzzing;
mod hashing;
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
