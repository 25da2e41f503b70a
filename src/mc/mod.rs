//! Marching cubes on finite elements (Wünsche & Lin): the generated table of all
//! topologically different cell triangulations ([`mod@table`]) and the face decider
//! ([`decider`]), regular-grid extraction ([`grid`]), polygonisation of curvilinear finite
//! elements ([`fe`]) and the auditor of other tables ([`audit`]).

pub mod audit;
pub(crate) mod decider;
pub mod fe;
pub mod grid;
#[cfg(feature = "nifti")]
pub mod nifti;
pub mod table;

pub use decider::{decide_exact, decide_fast, is_ambiguous_face};
pub use table::{table, Entry, Table};
