//! Proofs about the numeric, Bernstein and B-spline kernel.
use super::{ProofOutcome, Tally};
pub fn f64_round_trip() -> ProofOutcome { Tally::new("x","y").finish() }
pub fn morken_vs_bernstein() -> ProofOutcome { Tally::new("x","y").finish() }
pub fn subdivision_signs() -> ProofOutcome { Tally::new("x","y").finish() }
pub fn bezier_extraction_routes() -> ProofOutcome { Tally::new("x","y").finish() }
