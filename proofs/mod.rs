//! Exhaustive proofs: deterministic enumerations, each stating what it enumerated and how many
//! cases passed. Run by `cargo test --release` (the `proofs` test target) and `geocert prove`.

pub mod diamond;
pub mod ffd;
pub mod kernel;
pub mod mc;
pub mod mc_body;
pub mod mc_topology;

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A slice of every proof: the parts whose index `≡ index (mod count)`. Proofs number their
/// parts deterministically (a configuration, a shape, a grid), so the `count` slices are
/// disjoint and together enumerate exactly what the whole proof does; [`merge`] puts them
/// back together.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// Which slice, `0..count`.
    pub index: usize,
    /// How many slices.
    pub count: usize,
}

impl Shard {
    /// The whole proof.
    pub const WHOLE: Shard = Shard { index: 0, count: 1 };

    /// `K/N` with `1 ≤ K ≤ N` (one-based, as array jobs number their tasks).
    pub fn parse(s: &str) -> Result<Shard, String> {
        let bad = || format!("shard '{s}': expected K/N with 1 ≤ K ≤ N, e.g. 3/8");
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let (k, n): (usize, usize) = (
            k.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        if k == 0 || n == 0 || k > n {
            return Err(bad());
        }
        Ok(Shard {
            index: k - 1,
            count: n,
        })
    }

    /// Whether this slice runs part `part`.
    pub fn owns(&self, part: u64) -> bool {
        part % self.count as u64 == self.index as u64
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index + 1, self.count)
    }
}

/// The outcome of one exhaustive proof (or of one slice of it).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ProofOutcome {
    /// Short name, e.g. `kernel.morken-vs-bernstein`.
    pub name: String,
    /// What was enumerated, in words (with the measured remarks).
    pub enumerated: String,
    /// Cases examined.
    pub cases: usize,
    /// Cases that passed.
    pub passed: usize,
    /// The first few failures, described.
    pub failures: Vec<String>,
    /// Wall-clock seconds of the run (summed over merged slices).
    pub seconds: f64,
    /// The slices this outcome covers: `None` for a whole run (or a complete merge).
    #[serde(default)]
    pub shard: Option<Shard>,
    /// What [`merge`] needs to put slices back together.
    #[serde(default)]
    pub detail: Detail,
}

/// The mergeable parts of an outcome: failures with the part they came from, counters (summed
/// by [`merge`]), flag sets (united), remarks per part, and the template the counters are
/// written into.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Detail {
    /// The description without remarks.
    pub what: String,
    /// `(part, failure)`, at most [`MAX_FAILURES`], in part order.
    pub failures: Vec<(u64, String)>,
    /// Named counts.
    pub counters: BTreeMap<String, u64>,
    /// Named flag sets.
    pub flags: BTreeMap<String, Vec<bool>>,
    /// `(part, remark)`, in part order.
    pub remarks: Vec<(u64, String)>,
    /// A remark written from the counters: `{name}` is a counter, `{#name}` the number of
    /// flags set in a set.
    pub template: String,
}

/// Failures kept per outcome.
pub const MAX_FAILURES: usize = 5;

impl Detail {
    /// The full description: what, then the remarks, then the template filled in.
    fn render(&self) -> String {
        let mut out = self.what.clone();
        for (_, r) in &self.remarks {
            out.push_str("; ");
            out.push_str(r);
        }
        if !self.template.is_empty() {
            let mut t = self.template.clone();
            for (k, v) in &self.counters {
                t = t.replace(&format!("{{{k}}}"), &v.to_string());
            }
            for (k, v) in &self.flags {
                t = t.replace(
                    &format!("{{#{k}}}"),
                    &v.iter().filter(|&&b| b).count().to_string(),
                );
            }
            out.push_str("; ");
            out.push_str(&t);
        }
        out
    }

    /// A counter's value (0 when never counted).
    pub fn counter(&self, name: &str) -> u64 {
        self.counters.get(name).copied().unwrap_or(0)
    }

    /// A flag set (empty when never set).
    pub fn flag_set(&self, name: &str) -> &[bool] {
        self.flags.get(name).map_or(&[], Vec::as_slice)
    }
}

/// Puts the slices of one proof back together: the same cases, counts, first failures,
/// counters, flags and remarks as the whole run (the seconds are summed). Fails unless the
/// outcomes name one proof and are the slices `1..=N` of one `N`, each exactly once.
pub fn merge(mut slices: Vec<ProofOutcome>) -> Result<ProofOutcome, String> {
    let first = slices.first().ok_or("no slices to merge")?;
    let name = first.name.clone();
    let count = first.shard.map_or(1, |s| s.count);
    let mut seen = vec![false; count];
    for o in &slices {
        if o.name != name {
            return Err(format!("cannot merge '{}' into '{name}'", o.name));
        }
        let s = o.shard.unwrap_or(Shard::WHOLE);
        if s.count != count {
            return Err(format!(
                "{name}: slices of {count} and of {} mixed",
                s.count
            ));
        }
        if std::mem::replace(&mut seen[s.index], true) {
            return Err(format!("{name}: slice {s} given twice"));
        }
    }
    if let Some(k) = seen.iter().position(|&b| !b) {
        return Err(format!("{name}: slice {}/{count} missing", k + 1));
    }
    slices.sort_by_key(|o| o.shard.map_or(0, |s| s.index));
    let mut d = Detail {
        what: slices[0].detail.what.clone(),
        template: slices[0].detail.template.clone(),
        ..Detail::default()
    };
    let (mut cases, mut passed, mut seconds) = (0, 0, 0.0);
    for o in &slices {
        cases += o.cases;
        passed += o.passed;
        seconds += o.seconds;
        d.failures.extend(o.detail.failures.iter().cloned());
        d.remarks.extend(o.detail.remarks.iter().cloned());
        for (k, v) in &o.detail.counters {
            *d.counters.entry(k.clone()).or_default() += v;
        }
        for (k, v) in &o.detail.flags {
            let set = d.flags.entry(k.clone()).or_default();
            if set.len() < v.len() {
                set.resize(v.len(), false);
            }
            for (a, b) in set.iter_mut().zip(v) {
                *a |= b;
            }
        }
    }
    // Stable sorts: within a part, the order each slice saw.
    d.failures.sort_by_key(|(p, _)| *p);
    d.failures.truncate(MAX_FAILURES);
    d.remarks.sort_by_key(|(p, _)| *p);
    Ok(ProofOutcome {
        name,
        enumerated: d.render(),
        cases,
        passed,
        failures: d.failures.iter().map(|(_, f)| f.clone()).collect(),
        seconds,
        shard: None,
        detail: d,
    })
}

/// [`merge`] for whole runs of [`all`] (and of [`long`], when present): groups the outcomes
/// by proof (in the order of [`everything`]) and merges each; fails when a proof of [`all`]
/// is missing or a proof is unknown.
pub fn merge_runs(outcomes: Vec<ProofOutcome>) -> Result<Vec<ProofOutcome>, String> {
    let mut by_name: BTreeMap<String, Vec<ProofOutcome>> = BTreeMap::new();
    for o in outcomes {
        by_name.entry(o.name.clone()).or_default().push(o);
    }
    let mut merged = Vec::new();
    for (name, _) in all() {
        let slices = by_name
            .remove(name)
            .ok_or_else(|| format!("no slices of proof '{name}'"))?;
        merged.push(merge(slices)?);
    }
    // The long proofs are merged when their slices are there (`geocert prove --shard` runs
    // them), and may be absent as a whole.
    for (name, _) in long() {
        if let Some(slices) = by_name.remove(name) {
            merged.push(merge(slices)?);
        }
    }
    if let Some(name) = by_name.keys().next() {
        return Err(format!("unknown proof '{name}' among the slices"));
    }
    Ok(merged)
}

impl ProofOutcome {
    /// True when every case passed and at least one case ran (a slice may own no case).
    pub fn ok(&self) -> bool {
        self.passed == self.cases && (self.cases > 0 || self.shard.is_some_and(|s| s.count > 1))
    }

    /// One line: name, counts, what.
    pub fn summary(&self) -> String {
        format!(
            "{}{}: {}/{} passed ({}) in {:.2}s{}",
            self.name,
            self.shard
                .map(|s| format!(" [slice {s}]"))
                .unwrap_or_default(),
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

/// Collects pass/fail counts for a proof (or its slice).
pub(crate) struct Tally {
    name: String,
    shard: Shard,
    part: u64,
    cases: usize,
    passed: usize,
    detail: Detail,
    start: std::time::Instant,
}

impl Tally {
    pub(crate) fn new(name: &str, enumerated: &str, shard: Shard) -> Tally {
        Tally {
            name: name.into(),
            shard,
            part: 0,
            cases: 0,
            passed: 0,
            detail: Detail {
                what: enumerated.into(),
                ..Detail::default()
            },
            start: std::time::Instant::now(),
        }
    }
    /// Enters part `part` (parts must come in increasing order); true when this slice runs it.
    pub(crate) fn owns(&mut self, part: u64) -> bool {
        self.part = part;
        self.shard.owns(part)
    }
    pub(crate) fn check(&mut self, ok: bool, describe: impl FnOnce() -> String) {
        self.cases += 1;
        if ok {
            self.passed += 1;
        } else if self.detail.failures.len() < MAX_FAILURES {
            self.detail.failures.push((self.part, describe()));
        }
    }
    /// Appends a measured remark (of the current part) to the description.
    pub(crate) fn note(&mut self, remark: String) {
        self.detail.remarks.push((self.part, remark));
    }
    /// Adds to a named counter.
    pub(crate) fn count(&mut self, name: &str, by: u64) {
        *self.detail.counters.entry(name.into()).or_default() += by;
    }
    /// Sets flag `i` of the named set of `len` flags.
    pub(crate) fn flag(&mut self, name: &str, len: usize, i: usize) {
        let set = self
            .detail
            .flags
            .entry(name.into())
            .or_insert_with(|| vec![false; len]);
        set[i] = true;
    }
    /// The remark written from the counters and flag sets at the end (see [`Detail`]).
    pub(crate) fn template(&mut self, template: &str) {
        self.detail.template = template.into();
    }
    pub(crate) fn finish(self) -> ProofOutcome {
        ProofOutcome {
            name: self.name,
            enumerated: self.detail.render(),
            cases: self.cases,
            passed: self.passed,
            failures: self
                .detail
                .failures
                .iter()
                .map(|(_, f)| f.clone())
                .collect(),
            seconds: self.start.elapsed().as_secs_f64(),
            shard: (self.shard.count > 1).then_some(self.shard),
            detail: self.detail,
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

/// A proof: runs its enumeration (the parts of one slice) and reports.
pub type Proof = fn(Shard) -> ProofOutcome;

/// Proofs too long for `cargo test` (minutes each), run by `geocert prove` after [`all`].
pub fn long() -> Vec<(&'static str, Proof)> {
    vec![
        (
            "mc.trilinear-topology-wide",
            mc_topology::oracle_vs_sweep_wide as Proof,
        ),
        ("mc.tube-embedding-wide", mc_topology::tube_embedding_wide),
    ]
}

/// [`all`], then [`long`]: what `geocert prove` runs and publishes.
pub fn everything() -> Vec<(&'static str, Proof)> {
    let mut v = all();
    v.extend(long());
    v
}

/// Every proof `cargo test` runs, in order.
pub fn all() -> Vec<(&'static str, Proof)> {
    vec![
        (
            "kernel.f64-rational-round-trip",
            kernel::f64_round_trip as Proof,
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
        ("mc.trilinear-topology", mc_topology::oracle_vs_sweep),
        ("mc.tube-embedding", mc_topology::tube_embedding),
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
