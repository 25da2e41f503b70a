//! Marching cubes on finite elements (Wünsche & Lin): the generated table of all
//! topologically different cell triangulations ([`mod@table`]) and the face decider
//! ([`decider`]).

pub mod audit;
pub mod decider;
pub mod grid;
pub mod table;

pub use table::{table, Entry, Table};
