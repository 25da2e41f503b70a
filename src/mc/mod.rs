//! Marching cubes on finite elements (B. Wünsche and J. Z. Lin, "An efficient and topological
//! correct polygonisation algorithm for finite element data sets", University of Auckland,
//! 2003): the generated table of all topologically different cell triangulations
//! ([`mod@table`]) and the face decider ([`decide_exact`], [`decide_fast`]), regular-grid
//! extraction ([`grid`]), polygonisation of curvilinear finite elements ([`fe`]) and the
//! auditor of other programs' tables ([`audit`]); the exact topology of the trilinear
//! interpolant's isosurface in a cell and in a volume ([`trilinear`]).
//!
//! # Examples
//!
//! Extract an isosurface on the filtered path and check that it is closed:
//!
//! ```
//! use geocert::mc::grid::{extract, ExtractOptions, Volume};
//! use geocert::num::Rational;
//!
//! // |x|² − 7² sampled on a 16³ grid centred at (7.5, 7.5, 7.5): a sphere inside the box.
//! let n = 16;
//! let values: Vec<f64> = (0..n * n * n)
//!     .map(|i| {
//!         let [x, y, z] = [i % n, i / n % n, i / (n * n)].map(|c| c as f64 - 7.5);
//!         x * x + y * y + z * z - 49.0
//!     })
//!     .collect();
//! let volume = Volume::new([n, n, n], values)?;
//! let (mesh, stats) = extract(&volume, &Rational::from_integer(0.into()), &ExtractOptions::new())?;
//! assert_eq!(mesh.check_manifold()?, 0, "no boundary edges: watertight");
//! assert_eq!(mesh.euler_characteristic(), 2);
//! assert_eq!(stats.cells, 15 * 15 * 15);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Audit a 256-case table (here geocert's own export, one rule on every ambiguous face):
//!
//! ```
//! use geocert::mc::audit::{audit, export, parse_table, Numbering};
//!
//! let text = export(Numbering::Bourke, |_| false);
//! let report = audit(&parse_table(&text)?, Numbering::Bourke);
//! assert_eq!((report.cracks, report.winding_errors, report.edge_errors), (0, 0, 0));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod audit;
pub(crate) mod decider;
pub mod fe;
pub mod grid;
#[cfg(feature = "nifti")]
pub mod nifti;
pub mod table;
pub mod trilinear;
pub mod verify;

pub use decider::{decide_exact, decide_fast, is_ambiguous_face};
pub use table::{table, Entry, Table};
