//! Exhaustive proofs: deterministic enumerations, each stating what it enumerated and how many
//! cases passed. Run by `cargo test --release` (the `proofs` test target) and `geocert prove`.

pub mod diamond;
pub mod ffd;
pub mod kernel;
pub mod mc;
pub mod mc_body;

use serde::Serialize;

/// The outcome of one exhaustive proof.
#[derive(Clone, Debug, Serialize)]
pub struct ProofOutcome {
    /// Short name, e.g. `kernel.morken-vs-bernstein`.
    pub name: String,
    /// What was enumerated, in words.
    pub enumerated: String,
    /// Cases examined.
    pub cases: usize,
    /// Cases that passed.
    pub passed: usize,
    /// The first few failures, described.
    pub failures: Vec<String>,
    /// Wall-clock seconds of the run.
    pub seconds: f64,
}

impl ProofOutcome {
    /// True when every case passed and at least one case ran.
    pub fn ok(&self) -> bool {
        self.cases > 0 && self.passed == self.cases
    }

    /// One line: name, counts, what.
    pub fn summary(&self) -> String {
        format!(
            "{}: {}/{} passed ({}) in {:.2}s{}",
            self.name,
            self.passed,
            self.cases,
            self.enumerated,
            self.seconds,
            if self.failures.is_empty() {
                String::new()
            } else {
                format!("; first failure: {}", self.failures[0])
            }
        )
    }
}

/// Collects pass/fail counts for a proof.
pub(crate) struct Tally {
    name: String,
    enumerated: String,
    cases: usize,
    passed: usize,
    failures: Vec<String>,
    start: std::time::Instant,
}

impl Tally {
    pub(crate) fn new(name: &str, enumerated: &str) -> Tally {
        Tally {
            name: name.into(),
            enumerated: enumerated.into(),
            cases: 0,
            passed: 0,
            failures: vec![],
            start: std::time::Instant::now(),
        }
    }
    pub(crate) fn check(&mut self, ok: bool, describe: impl FnOnce() -> String) {
        self.cases += 1;
        if ok {
            self.passed += 1;
        } else if self.failures.len() < 5 {
            self.failures.push(describe());
        }
    }
    /// Appends a measured remark to the description of what was enumerated.
    pub(crate) fn note(&mut self, remark: String) {
        self.enumerated = format!("{}; {remark}", self.enumerated);
    }
    pub(crate) fn finish(self) -> ProofOutcome {
        ProofOutcome {
            name: self.name,
            enumerated: self.enumerated,
            cases: self.cases,
            passed: self.passed,
            failures: self.failures,
            seconds: self.start.elapsed().as_secs_f64(),
        }
    }
}

/// A small deterministic generator (64-bit LCG, Knuth's MMIX constants) so proofs enumerate the
/// same cases on every machine.
pub(crate) struct Lcg(u64);

impl Lcg {
    pub(crate) fn new(seed: u64) -> Lcg {
        Lcg(seed)
    }
    pub(crate) fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 11
    }
    /// An integer in `[-m, m]`.
    pub(crate) fn int(&mut self, m: i64) -> i64 {
        (self.next() % (2 * m as u64 + 1)) as i64 - m
    }
    /// `n/d` with `|n| ≤ max_num`, `1 ≤ d ≤ max_den`.
    pub(crate) fn rational(&mut self, max_num: i64, max_den: i64) -> crate::num::Rational {
        let n = self.int(max_num);
        let d = 1 + (self.next() % max_den as u64) as i64;
        crate::num::Rational::new(n.into(), d.into())
    }
}

/// A proof: runs its enumeration and reports.
pub type Proof = fn() -> ProofOutcome;

/// Every proof that exists so far, in order.
pub fn all() -> Vec<(&'static str, Proof)> {
    vec![
        (
            "kernel.f64-rational-round-trip",
            kernel::f64_round_trip as fn() -> ProofOutcome,
        ),
        ("kernel.morken-vs-bernstein", kernel::morken_vs_bernstein),
        ("kernel.subdivision-signs", kernel::subdivision_signs),
        (
            "kernel.tensor-bezier-cells",
            kernel::bezier_extraction_routes,
        ),
        ("ffd.jacobian-routes", ffd::jacobian_routes),
        ("ffd.identity-unit-jacobian", ffd::identity_unit_jacobian),
        ("mc.table-coverage", mc::coverage),
        ("mc.table-edges", mc::edges),
        ("mc.table-faces", mc::faces),
        ("mc.table-orientation", mc::orientation),
        ("mc.table-watertight", mc::watertight),
        ("mc.table-symmetry", mc::symmetry),
        ("mc.table-trilinear-realisability", mc::trilinear),
        ("mc.table-body-ambiguity", mc_body::body),
        ("mc.face-deciders", mc::face_deciders),
        (
            "diamond.implicit-vs-explicit",
            diamond::implicit_vs_explicit,
        ),
        (
            "diamond.maubach-is-longest-edge",
            diamond::maubach_is_longest_edge,
        ),
        ("diamond.supercube", diamond::supercube),
    ]
}
