//! The exact-vs-fast campaign and subdivision timings run by `geocert prove`.

use crate::bernstein::positivity::{verify_witness, WitnessValue};
use crate::bernstein::{
    prove_positive_exact, prove_positive_fast, prove_positive_filtered,
    verify_positive_certificate, Bernstein, FastBernstein, Limits, PositivityVerdict,
    ScaledBernstein,
};
use crate::num::{Rational, Sign};
use num_bigint::BigInt;
use serde::Serialize;
use std::time::Instant;

/// A small deterministic generator (64-bit LCG).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 11
    }
    fn int(&mut self, m: i64) -> i64 {
        (self.next() % (2 * m as u64 + 1)) as i64 - m
    }
}

/// Counts of the exact-vs-fast positivity campaign.
#[derive(Clone, Debug, Default, Serialize)]
pub struct KernelCampaign {
    pub seed: u64,
    pub degrees: Vec<usize>,
    pub max_depth: u32,
    pub cases: usize,
    pub exact_positive: usize,
    pub exact_not_positive: usize,
    pub exact_undecided: usize,
    pub fast_positive: usize,
    pub fast_not_positive: usize,
    pub fast_uncertain: usize,
    pub fast_undecided: usize,
    pub filtered_agrees: usize,
    pub contradictions: usize,
    pub certificates_refused: usize,
    pub exact_ms_median: f64,
    pub fast_ms_median: f64,
    pub filtered_ms_median: f64,
}

fn class(v: &PositivityVerdict) -> Sign {
    match v {
        PositivityVerdict::Positive { .. } => Sign::Positive,
        PositivityVerdict::NotPositive { .. } => Sign::Negative,
        _ => Sign::Uncertain,
    }
}

/// Median of a sample (0 for an empty one).
pub fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(|a, b| a.total_cmp(b));
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// A random trivariate polynomial: offset + noise; a quarter have near-zero coefficients.
fn random_poly(rng: &mut Rng, degrees: &[usize]) -> Bernstein<Rational> {
    let n: usize = degrees.iter().map(|d| d + 1).product();
    let offset = rng.int(6) + 3;
    let near = rng.next().is_multiple_of(4);
    let coeffs = (0..n)
        .map(|_| {
            if near && rng.next().is_multiple_of(3) {
                let e = 40 + (rng.next() % 11) as usize;
                Rational::new(BigInt::from(rng.int(3)), BigInt::from(1) << e)
            } else {
                Rational::new(BigInt::from(offset * 4 + rng.int(16)), BigInt::from(4))
            }
        })
        .collect();
    Bernstein::new(degrees.to_vec(), coeffs).expect("count matches")
}

/// Runs exact, fast and filtered positivity on `cases` random polynomials and re-verifies every
/// certificate the exact and filtered routes produce.
pub fn kernel_campaign(
    seed: u64,
    cases: usize,
    degrees: &[usize],
    max_depth: u32,
) -> KernelCampaign {
    let mut rng = Rng(seed);
    let limits = Limits {
        max_depth,
        max_boxes: 200_000,
        time_limit: None,
    };
    let mut c = KernelCampaign {
        seed,
        degrees: degrees.to_vec(),
        max_depth,
        cases,
        ..Default::default()
    };
    let (mut te, mut tf, mut tx) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..cases {
        let p = random_poly(&mut rng, degrees);
        let t0 = Instant::now();
        let exact = prove_positive_exact(&p, limits);
        te.push(t0.elapsed().as_secs_f64() * 1e3);
        let t0 = Instant::now();
        let fast = FastBernstein::from_rational(&p).map(|f| prove_positive_fast(&f, limits));
        tf.push(t0.elapsed().as_secs_f64() * 1e3);
        let t0 = Instant::now();
        let filtered = prove_positive_filtered(&p, limits);
        tx.push(t0.elapsed().as_secs_f64() * 1e3);
        match &exact {
            PositivityVerdict::Positive { .. } => c.exact_positive += 1,
            PositivityVerdict::NotPositive { .. } => c.exact_not_positive += 1,
            _ => c.exact_undecided += 1,
        }
        match &fast {
            Ok(PositivityVerdict::Positive { .. }) => c.fast_positive += 1,
            Ok(PositivityVerdict::NotPositive { .. }) => c.fast_not_positive += 1,
            Ok(PositivityVerdict::Uncertain { .. }) | Err(_) => c.fast_uncertain += 1,
            Ok(PositivityVerdict::Undecided { .. }) => c.fast_undecided += 1,
        }
        if let Ok(f) = &fast {
            if class(f) != Sign::Uncertain
                && class(&exact) != Sign::Uncertain
                && class(f) != class(&exact)
            {
                c.contradictions += 1;
            }
        }
        if class(&filtered) == class(&exact) {
            c.filtered_agrees += 1;
        }
        for v in [&exact, &filtered] {
            let ok = match v {
                PositivityVerdict::Positive { leaves, .. } => {
                    verify_positive_certificate(&p, leaves).is_ok()
                }
                PositivityVerdict::NotPositive { witness, value } => {
                    let claimed = match value {
                        WitnessValue::Exact(r) => Some(r),
                        WitnessValue::AtMost(_) => None,
                    };
                    verify_witness(&p, witness, claimed).is_ok()
                }
                _ => true,
            };
            if !ok {
                c.certificates_refused += 1;
            }
        }
    }
    c.exact_ms_median = median(te);
    c.fast_ms_median = median(tf);
    c.filtered_ms_median = median(tx);
    c
}

/// Median times of a full subdivision tree in the three representations.
#[derive(Clone, Debug, Serialize)]
pub struct SubdivisionTiming {
    pub degree: usize,
    pub depth: u32,
    pub runs: usize,
    pub rational_ms: f64,
    pub scaled_ms: f64,
    pub fast_ms: f64,
    /// The BigRational and integer trees counted the same positive leaf coefficients.
    pub leaf_signs_agree: bool,
}

/// The degree-`degree` polynomial used by the timing (deterministic random rationals).
pub fn timing_poly(degree: usize) -> Bernstein<Rational> {
    let mut rng = Rng(12345);
    let coeffs = (0..=degree)
        .map(|_| {
            Rational::new(
                BigInt::from(rng.int(1000)),
                BigInt::from(1 + rng.next() % 97),
            )
        })
        .collect();
    Bernstein::new(vec![degree], coeffs).expect("count")
}

/// Full binary tree of `depth` levels of splits at ½; returns a checksum (sum of leaf signs) so
/// the work cannot be optimised away.
pub fn tree_rational(p: &Bernstein<Rational>, depth: u32) -> i64 {
    if depth == 0 {
        return p
            .coeffs()
            .iter()
            .filter(|c| c > &&Rational::from_integer(0.into()))
            .count() as i64;
    }
    let half = Rational::new(1.into(), 2.into());
    let (l, r) = p.split(0, &half).expect("axis 0");
    tree_rational(&l, depth - 1) + tree_rational(&r, depth - 1)
}

/// The same tree in the sign-only integer form.
pub fn tree_scaled(p: &ScaledBernstein, depth: u32) -> i64 {
    if depth == 0 {
        return (0..p.numerators().len())
            .filter(|&k| p.coeff_sign(k) == Sign::Positive)
            .count() as i64;
    }
    let (l, r) = p.split_half(0).expect("axis 0");
    tree_scaled(&l, depth - 1) + tree_scaled(&r, depth - 1)
}

/// The same tree in certified `f64` with preallocated buffers per level.
pub fn tree_fast(
    p: &FastBernstein,
    depth: u32,
    bufs: &mut Vec<(FastBernstein, FastBernstein)>,
) -> i64 {
    if depth == 0 {
        return (0..p.coeffs().len())
            .filter(|&k| p.coeff_sign(k) == Sign::Positive)
            .count() as i64;
    }
    let (mut l, mut r) = bufs
        .pop()
        .unwrap_or_else(|| (p.buffer_like(), p.buffer_like()));
    p.split_half_into(0, &mut l, &mut r);
    let s = tree_fast(&l, depth - 1, bufs) + tree_fast(&r, depth - 1, bufs);
    bufs.push((l, r));
    s
}

/// Times the three trees (median of `runs`); checks that their leaf sign counts agree where the
/// fast path is certain.
pub fn subdivision_timing(degree: usize, depth: u32, runs: usize) -> SubdivisionTiming {
    let p = timing_poly(degree);
    let scaled = ScaledBernstein::from_rational(&p);
    let fast = FastBernstein::from_rational(&p).expect("finite");
    let time = |f: &mut dyn FnMut() -> i64| -> (f64, i64) {
        let mut ts = Vec::new();
        let mut out = 0;
        for _ in 0..runs {
            let t0 = Instant::now();
            out = std::hint::black_box(f());
            ts.push(t0.elapsed().as_secs_f64() * 1e3);
        }
        (median(ts), out)
    };
    let (rational_ms, a) = time(&mut || tree_rational(&p, depth));
    let (scaled_ms, b) = time(&mut || tree_scaled(&scaled, depth));
    let mut bufs = Vec::new();
    let (fast_ms, _) = time(&mut || tree_fast(&fast, depth, &mut bufs));
    SubdivisionTiming {
        degree,
        depth,
        runs,
        rational_ms,
        scaled_ms,
        fast_ms,
        leaf_signs_agree: a == b,
    }
}
