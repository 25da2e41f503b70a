//! Proving `p > 0` on the unit box by subdivision, with certificates.
//!
//! Each box is subdivided at ½ along every axis (an octree for trivariate polynomials,
//! as in Gain & Dodgson §6, step 4) until its coefficients decide: all positive proves the
//! box (convex-hull property), a vertex coefficient `≤ 0` is the value of `p` at that vertex
//! and refutes positivity with a rational witness point. Zero counts as failure.
//!
//! Three routes: [`prove_positive_exact`] (sign-only integers, no `f64` anywhere),
//! [`prove_positive_fast`] (`f64` with certified bounds; says `Uncertain` when they do not
//! decide) and [`prove_positive_filtered`] (fast first, exact on the uncertain boxes only).
//! [`verify_positive_certificate`] and [`verify_witness`] re-check the evidence with code of
//! their own, independent of the engines: the certificate by a division-free integer walk
//! down the box tree written in the checker, the witness by exact rational evaluation.

use super::fast::FastBernstein;
use super::poly::Bernstein;
use super::scaled::ScaledBernstein;
use super::BernsteinError;
use crate::num::{rational_to_f64, Field, Rational, Sign};
use crate::Path;
use num_bigint::BigInt;
use num_traits::{One, Zero};
use serde::{Deserialize, Serialize};
use std::collections::{HashMap, HashSet};
use std::time::{Duration, Instant};
use thiserror::Error;

/// A dyadic box `Π [index_a / 2^level, (index_a + 1) / 2^level]` of the unit box.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, PartialOrd, Ord)]
pub struct DyadicBox {
    /// Subdivision level: the box has side `2^-level`.
    pub level: u32,
    /// Per axis, the box's index at that level.
    pub index: Vec<u64>,
}

impl DyadicBox {
    /// The whole unit box in `dim` dimensions.
    pub fn root(dim: usize) -> DyadicBox {
        DyadicBox {
            level: 0,
            index: vec![0; dim],
        }
    }

    /// Child `c` (bit a set: upper half along axis a).
    pub fn child(&self, c: usize) -> DyadicBox {
        DyadicBox {
            level: self.level + 1,
            index: self
                .index
                .iter()
                .enumerate()
                .map(|(a, &i)| 2 * i + (c >> a & 1) as u64)
                .collect(),
        }
    }

    /// The parent box (None for the root).
    pub fn parent(&self) -> Option<DyadicBox> {
        (self.level > 0).then(|| DyadicBox {
            level: self.level - 1,
            index: self.index.iter().map(|i| i / 2).collect(),
        })
    }

    /// True when the box is well formed (indices inside the unit box).
    pub fn is_valid(&self) -> bool {
        self.level < 63 && self.index.iter().all(|&i| i < (1u64 << self.level))
    }

    /// The interval `[lo, hi]` on each axis, exactly.
    pub fn bounds(&self) -> Vec<(Rational, Rational)> {
        let den = BigInt::one() << self.level as usize;
        self.index
            .iter()
            .map(|&i| {
                (
                    Rational::new(BigInt::from(i), den.clone()),
                    Rational::new(BigInt::from(i + 1), den.clone()),
                )
            })
            .collect()
    }

    /// The vertex `corner` (bit a set: upper end on axis a), exactly.
    pub fn vertex(&self, corner: usize) -> Vec<Rational> {
        self.bounds()
            .into_iter()
            .enumerate()
            .map(|(a, (lo, hi))| if corner >> a & 1 == 1 { hi } else { lo })
            .collect()
    }
}

/// Explicit limits for the subdivision (exact arithmetic can explode).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct Limits {
    /// Deepest subdivision level (the root is level 0).
    pub max_depth: u32,
    /// Most boxes examined in one run.
    pub max_boxes: usize,
    /// Wall-clock budget.
    pub time_limit: Option<Duration>,
}

crate::choice::setters!(Limits {
    with_max_depth => max_depth: u32,
    with_max_boxes => max_boxes: usize,
    with_time_limit => time_limit: Option<Duration>,
});

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_depth: 12,
            max_boxes: 1_000_000,
            time_limit: None,
        }
    }
}

/// Which limit stopped a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum LimitHit {
    /// [`Limits::max_depth`].
    Depth,
    /// [`Limits::max_boxes`].
    Boxes,
    /// [`Limits::time_limit`].
    Time,
}

/// The value of `p` at a witness point.
#[derive(Clone, Debug, PartialEq)]
pub enum WitnessValue {
    /// Known exactly.
    Exact(Rational),
    /// Certified `≤` this (non-positive) `f64`; the fast path does not know it exactly.
    AtMost(f64),
}

/// The outcome of a positivity proof, with its evidence.
#[derive(Clone, Debug, PartialEq)]
pub enum PositivityVerdict {
    /// `p > 0` on the whole box: every leaf box has all coefficients positive.
    /// `lower_bound` is a certified lower bound of `p` on the box: the smallest leaf
    /// coefficient, rounded down to an `f64` (convex-hull property).
    Positive {
        /// Leaf boxes tiling the unit box, each with all coefficients positive.
        leaves: Vec<DyadicBox>,
        /// Certified lower bound of `p` on the box.
        lower_bound: f64,
    },
    /// `p(witness) ≤ 0`.
    NotPositive {
        /// A rational point of the unit box.
        witness: Vec<Rational>,
        /// `p` there: exact, or a certified upper bound `≤ 0` on the fast path.
        value: WitnessValue,
    },
    /// A limit was hit before a decision: `at` is the undecided box, `lower_bound` a certified
    /// lower bound of `p` there (its smallest coefficient, rounded down).
    Undecided {
        /// Which limit.
        limit: LimitHit,
        /// The undecided box.
        at: DyadicBox,
        /// Certified lower bound of `p` on `at`.
        lower_bound: f64,
    },
    /// Fast path only: rounding error left these boxes undecided; `proven` are the leaves it
    /// did prove positive. Hand `boxes` to the exact path.
    Uncertain {
        /// Boxes the fast path could not decide.
        boxes: Vec<DyadicBox>,
        /// Leaves it proved positive.
        proven: Vec<DyadicBox>,
        /// Certified lower bound of `p` on the `proven` leaves.
        proven_lower_bound: f64,
    },
}

struct Budget {
    limits: Limits,
    start: Instant,
    boxes: usize,
}

impl Budget {
    fn new(limits: Limits) -> Budget {
        Budget {
            limits,
            start: Instant::now(),
            boxes: 0,
        }
    }
    /// Counts a box; returns the limit that is now exceeded, if any.
    fn tick(&mut self) -> Option<LimitHit> {
        self.boxes += 1;
        if self.boxes > self.limits.max_boxes {
            return Some(LimitHit::Boxes);
        }
        if let Some(t) = self.limits.time_limit {
            if self.boxes.is_multiple_of(64) && self.start.elapsed() > t {
                return Some(LimitHit::Time);
            }
        }
        None
    }
}

pub(crate) fn round_down(r: &Rational) -> f64 {
    let x = rational_to_f64(r);
    if &crate::num::rational_from_f64(x, "bound").unwrap_or_else(|_| r.clone()) > r {
        x.next_down()
    } else {
        x
    }
}

/// Splits along every axis at ½: the 2^n children, child c in position c.
fn split_all_scaled(p: &ScaledBernstein) -> Vec<ScaledBernstein> {
    let mut parts = vec![p.clone()];
    for axis in 0..p.degrees().len() {
        let mut next = Vec::with_capacity(parts.len() * 2);
        for q in &parts {
            let (l, r) = q.split_half(axis).expect("axis in range");
            next.push(l);
            next.push(r);
        }
        parts = next;
    }
    // parts is ordered with the last axis as the lowest bit; reorder so bit a = axis a.
    let n = p.degrees().len();
    let mut out = vec![None; parts.len()];
    for (pos, mut q) in parts.into_iter().enumerate() {
        let mut c = 0;
        for a in 0..n {
            if pos >> (n - 1 - a) & 1 == 1 {
                c |= 1 << a;
            }
        }
        q.normalise_twos();
        out[c] = Some(q);
    }
    out.into_iter()
        .map(|q| q.expect("every child filled"))
        .collect()
}

/// Restricts a scaled polynomial to a dyadic box by halving along its index bits.
fn restrict_scaled(p: &ScaledBernstein, b: &DyadicBox) -> ScaledBernstein {
    let mut q = p.clone();
    for bit in (0..b.level).rev() {
        for (axis, &i) in b.index.iter().enumerate() {
            let (l, r) = q.split_half(axis).expect("axis in range");
            q = if i >> bit & 1 == 1 { r } else { l };
        }
        q.normalise_twos();
    }
    q
}

/// Exact necessary-and-sufficient positivity test on `start` (use [`DyadicBox::root`] for the
/// whole box), in sign-only integer arithmetic; never touches `f64` for a decision.
pub fn prove_positive_exact(p: &Bernstein<Rational>, limits: Limits) -> PositivityVerdict {
    prove_positive_scaled(&ScaledBernstein::from_rational(p), limits)
}

/// [`prove_positive_exact`] on a polynomial already in the sign-only integer form.
pub fn prove_positive_scaled(p: &ScaledBernstein, limits: Limits) -> PositivityVerdict {
    let root = DyadicBox::root(p.degrees().len());
    let mut budget = Budget::new(limits);
    exact_from(p, root, &mut budget)
}

fn exact_from(p: &ScaledBernstein, start: DyadicBox, budget: &mut Budget) -> PositivityVerdict {
    let n = start.index.len();
    let mut leaves = Vec::new();
    let mut lowest: Option<Rational> = None;
    let mut stack = vec![(start, p.clone())];
    while let Some((b, q)) = stack.pop() {
        for corner in 0..1usize << n {
            let k = q.vertex_index(corner);
            if q.coeff_sign(k) != Sign::Positive {
                return PositivityVerdict::NotPositive {
                    witness: b.vertex(corner),
                    value: WitnessValue::Exact(q.coeff_value(k)),
                };
            }
        }
        if q.all_positive() {
            let m = q.coeff_value(q.argmin());
            if lowest.as_ref().is_none_or(|l| &m < l) {
                lowest = Some(m);
            }
            leaves.push(b);
            continue;
        }
        let limit = if b.level >= budget.limits.max_depth {
            Some(LimitHit::Depth)
        } else {
            budget.tick()
        };
        if let Some(limit) = limit {
            let lower_bound = round_down(&q.coeff_value(q.argmin()));
            return PositivityVerdict::Undecided {
                limit,
                at: b,
                lower_bound,
            };
        }
        let children = split_all_scaled(&q);
        // Push the child with the smallest coefficient last so it is explored first.
        let mut order: Vec<usize> = (0..children.len()).collect();
        let mins: Vec<Rational> = children.iter().map(|c| c.coeff_value(c.argmin())).collect();
        order.sort_by(|&x, &y| mins[y].cmp(&mins[x]));
        let mut children: Vec<Option<ScaledBernstein>> = children.into_iter().map(Some).collect();
        for c in order {
            stack.push((b.child(c), children[c].take().expect("each child once")));
        }
    }
    PositivityVerdict::Positive {
        leaves,
        lower_bound: lowest.map_or(f64::INFINITY, |l| round_down(&l)),
    }
}

/// The fast path: `f64` subdivision with certified error bounds. Certified verdicts are
/// `Positive`, `NotPositive` (with `WitnessValue::AtMost`) and `Undecided`; otherwise
/// `Uncertain` with the boxes the exact path must finish.
pub fn prove_positive_fast(p: &FastBernstein, limits: Limits) -> PositivityVerdict {
    let n = p.degrees().len();
    let mut budget = Budget::new(limits);
    let mut leaves = Vec::new();
    let mut uncertain = Vec::new();
    let mut lowest = f64::INFINITY;
    let mut pool: Vec<FastBernstein> = Vec::new();
    let mut stack = vec![(DyadicBox::root(n), p.clone())];
    while let Some((b, q)) = stack.pop() {
        let mut vertex_uncertain = false;
        for corner in 0..1usize << n {
            let k = q.vertex_index(corner);
            match q.coeff_sign(k) {
                Sign::Negative | Sign::Zero => {
                    let bound = (q.coeffs()[k] + q.err()).next_up();
                    return PositivityVerdict::NotPositive {
                        witness: b.vertex(corner),
                        value: WitnessValue::AtMost(bound.min(0.0)),
                    };
                }
                Sign::Uncertain => vertex_uncertain = true,
                Sign::Positive => {}
            }
        }
        if !vertex_uncertain && (0..q.coeffs().len()).all(|k| q.coeff_sign(k) == Sign::Positive) {
            let min = q.coeffs().iter().fold(f64::INFINITY, |m, &c| m.min(c));
            lowest = lowest.min((min - q.err()).next_down());
            leaves.push(b);
            pool.push(q);
            continue;
        }
        let any_uncertain =
            vertex_uncertain || (0..q.coeffs().len()).any(|k| q.coeff_sign(k) == Sign::Uncertain);
        if vertex_uncertain {
            uncertain.push(b);
            pool.push(q);
            continue;
        }
        let limit = if b.level >= budget.limits.max_depth {
            Some(LimitHit::Depth)
        } else {
            budget.tick()
        };
        if let Some(limit) = limit {
            if any_uncertain {
                uncertain.push(b);
                pool.push(q);
                continue;
            }
            let min = q.coeffs().iter().fold(f64::INFINITY, |m, &c| m.min(c));
            return PositivityVerdict::Undecided {
                limit,
                at: b,
                lower_bound: (min - q.err()).next_down(),
            };
        }
        // Split along every axis into 2^n children without allocating in steady state.
        let mut parts: Vec<(usize, FastBernstein)> = vec![(0, q)];
        for axis in 0..n {
            let mut next = Vec::with_capacity(parts.len() * 2);
            for (c, part) in parts {
                let mut l = pool.pop().unwrap_or_else(|| part.buffer_like());
                let mut r = pool.pop().unwrap_or_else(|| part.buffer_like());
                part.split_half_into(axis, &mut l, &mut r);
                pool.push(part);
                next.push((c, l));
                next.push((c | 1 << axis, r));
            }
            parts = next;
        }
        for (c, part) in parts {
            stack.push((b.child(c), part));
        }
    }
    if uncertain.is_empty() {
        PositivityVerdict::Positive {
            leaves,
            lower_bound: lowest,
        }
    } else {
        PositivityVerdict::Uncertain {
            boxes: uncertain,
            proven: leaves,
            proven_lower_bound: lowest,
        }
    }
}

/// Options of [`prove_positive`]: the arithmetic and the limits of the subdivision.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[non_exhaustive]
pub struct PositivityOptions {
    /// [`Path::Filtered`] by default; [`Path::Fast`] may answer
    /// [`PositivityVerdict::Uncertain`].
    pub path: Path,
    /// Depth, box and time limits.
    pub limits: Limits,
}

crate::choice::setters!(PositivityOptions {
    with_path => path: Path,
    with_limits => limits: Limits,
});

/// Decides `p > 0` on the unit box on the path `opts.path` names: [`prove_positive_exact`],
/// [`prove_positive_fast`] (on the certified `f64` form of `p`) or [`prove_positive_filtered`].
///
/// Fails only on the fast path, when a coefficient of `p` overflows `f64`.
pub fn prove_positive(
    p: &Bernstein<Rational>,
    opts: &PositivityOptions,
) -> Result<PositivityVerdict, BernsteinError> {
    Ok(match opts.path {
        Path::Exact => prove_positive_exact(p, opts.limits),
        Path::Fast => prove_positive_fast(&FastBernstein::from_rational(p)?, opts.limits),
        Path::Filtered => prove_positive_filtered(p, opts.limits),
    })
}

/// Fast first, then the exact path on each box the fast path left uncertain. The verdict is
/// exact: it never depends on an uncertified `f64` decision.
pub fn prove_positive_filtered(p: &Bernstein<Rational>, limits: Limits) -> PositivityVerdict {
    let fast = FastBernstein::from_rational(p).ok();
    prove_positive_filtered_with(
        fast.as_ref(),
        || ScaledBernstein::from_rational(p),
        |w| p.eval(w).expect("witness has the polynomial's dimension"),
        limits,
    )
}

/// The filtered test with the representations supplied by the caller: `fast` (if the
/// polynomial fits the fast path), `exact()` (built only when some box is uncertain) and
/// `value_at(witness)` (the exact value at a witness the fast path found).
pub fn prove_positive_filtered_with(
    fast: Option<&FastBernstein>,
    exact: impl FnOnce() -> ScaledBernstein,
    value_at: impl FnOnce(&[Rational]) -> Rational,
    limits: Limits,
) -> PositivityVerdict {
    let fast = match fast {
        Some(f) => prove_positive_fast(f, limits),
        None => PositivityVerdict::Uncertain {
            boxes: vec![],
            proven: vec![],
            proven_lower_bound: f64::INFINITY,
        },
    };
    match fast {
        PositivityVerdict::Uncertain {
            boxes,
            mut proven,
            proven_lower_bound,
        } => {
            let mut lowest = proven_lower_bound;
            let scaled = exact();
            let boxes = if boxes.is_empty() && proven.is_empty() {
                vec![DyadicBox::root(scaled.degrees().len())]
            } else {
                boxes
            };
            let mut budget = Budget::new(limits);
            for b in boxes {
                let sub = restrict_scaled(&scaled, &b);
                match exact_from(&sub, b.clone(), &mut budget) {
                    // `exact_from` labels boxes and witnesses globally (children of `b`).
                    PositivityVerdict::Positive {
                        leaves,
                        lower_bound,
                    } => {
                        proven.extend(leaves);
                        lowest = lowest.min(lower_bound);
                    }
                    verdict @ (PositivityVerdict::NotPositive { .. }
                    | PositivityVerdict::Undecided { .. }) => {
                        return verdict;
                    }
                    PositivityVerdict::Uncertain { .. } => {
                        unreachable!("the exact path is never uncertain")
                    }
                }
            }
            PositivityVerdict::Positive {
                leaves: proven,
                lower_bound: lowest,
            }
        }
        PositivityVerdict::NotPositive { witness, .. } => {
            // Recover the exact value at the witness (one exact evaluation).
            let value = value_at(&witness);
            PositivityVerdict::NotPositive {
                witness,
                value: WitnessValue::Exact(value),
            }
        }
        other => other,
    }
}

/// Why a certificate was refused.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum CertificateError {
    #[error("leaf {index} is not a valid box of the unit {dim}-cube")]
    /// A leaf is not a valid dyadic box of the unit cube.
    BadLeaf {
        /// The leaf's index.
        index: usize,
        /// The cube's dimension.
        dim: usize,
    },
    #[error("leaves {a} and {b} overlap")]
    /// Two leaves overlap.
    Overlap {
        /// One leaf's index.
        a: usize,
        /// The other's.
        b: usize,
    },
    #[error("the leaves cover {covered} of the unit box, not all of it")]
    /// The leaves' volumes do not sum to 1.
    NotCovering {
        /// Their total volume, exactly.
        covered: String,
    },
    #[error("leaf {index} has a coefficient that is not positive: {coeff}")]
    /// A leaf has a coefficient `≤ 0`.
    NotPositiveLeaf {
        /// The leaf's index.
        index: usize,
        /// The coefficient, exactly.
        coeff: String,
    },
    #[error("the witness point lies outside the unit box or has the wrong dimension")]
    /// The witness point lies outside the unit box or has the wrong dimension.
    BadWitness,
    #[error("the polynomial's value at the witness is {value}, which is positive")]
    /// The polynomial is positive at the witness.
    WitnessPositive {
        /// Its value there, exactly.
        value: String,
    },
    #[error("the claimed witness value {claimed} differs from the exact value {exact}")]
    /// The claimed value is not the exact value.
    WitnessValueMismatch {
        /// The certificate's value.
        claimed: String,
        /// The exact value.
        exact: String,
    },
}

/// Re-checks a `Positive` certificate: the leaves are valid, pairwise non-overlapping dyadic
/// boxes whose volumes sum to 1 (so they tile the box), and on each leaf every Bernstein
/// coefficient of `p` is positive. The coefficients on the leaves come from a walk down the
/// tree of boxes by integer midpoint subdivision written here (not the provers' splitting
/// code), so shared ancestors are subdivided once. Returns the number of leaves.
pub fn verify_positive_certificate(
    p: &Bernstein<Rational>,
    leaves: &[DyadicBox],
) -> Result<usize, CertificateError> {
    // The coefficients as integers over one positive denominator (signs are what counts).
    let den = p.coeffs().iter().fold(BigInt::one(), |acc, c| {
        num_integer::Integer::lcm(&acc, c.denom())
    });
    let nums: Vec<BigInt> = p
        .coeffs()
        .iter()
        .map(|c| c.numer() * (&den / c.denom()))
        .collect();
    verify_leaves(p.degrees(), nums, &den, leaves)
}

/// [`verify_positive_certificate`] for a polynomial given as integer numerators over one
/// positive denominator (no gcd is needed: only signs are checked, and the denominator only
/// names a failing coefficient's value).
pub fn verify_positive_certificate_scaled(
    p: &ScaledBernstein,
    leaves: &[DyadicBox],
) -> Result<usize, CertificateError> {
    verify_leaves(
        p.degrees(),
        p.numerators().to_vec(),
        p.denominator(),
        leaves,
    )
}

/// The common body: `nums / den` (`den > 0`) are the Bernstein coefficients on the unit box.
fn verify_leaves(
    degrees: &[usize],
    nums: Vec<BigInt>,
    den: &BigInt,
    leaves: &[DyadicBox],
) -> Result<usize, CertificateError> {
    let dim = degrees.len();
    let mut seen: HashSet<&DyadicBox> = HashSet::new();
    for (i, l) in leaves.iter().enumerate() {
        if l.index.len() != dim || !l.is_valid() {
            return Err(CertificateError::BadLeaf { index: i, dim });
        }
        if !seen.insert(l) {
            let a = leaves.iter().position(|x| x == l).unwrap_or(0);
            return Err(CertificateError::Overlap { a, b: i });
        }
    }
    // Dyadic boxes overlap iff one contains the other: check no ancestor of a leaf is a leaf.
    for (i, l) in leaves.iter().enumerate() {
        let mut cur = l.parent();
        while let Some(anc) = cur {
            if seen.contains(&anc) {
                let a = leaves.iter().position(|x| x == &anc).unwrap_or(0);
                return Err(CertificateError::Overlap { a, b: i });
            }
            cur = anc.parent();
        }
    }
    // Volumes in units of the finest leaf: Σ 2^{(L − l)·dim} = 2^{L·dim} exactly when they
    // tile the box (they do not overlap).
    let finest = leaves.iter().map(|l| l.level).max().unwrap_or(0) as usize;
    let volume = leaves.iter().fold(BigInt::zero(), |v, l| {
        v + (BigInt::one() << ((finest - l.level as usize) * dim))
    });
    let whole = BigInt::one() << (finest * dim);
    if volume != whole {
        return Err(CertificateError::NotCovering {
            covered: crate::num::rational_to_string(&Rational::new(volume, whole)),
        });
    }
    let index: HashMap<&DyadicBox, usize> =
        leaves.iter().enumerate().map(|(i, l)| (l, i)).collect();
    let check = LeafCheck {
        degrees,
        index: &index,
        den,
    };
    check.descend(&DyadicBox::root(dim), nums)?;
    Ok(leaves.len())
}

/// The tree walk of [`verify_positive_certificate`]: from the root down to the leaves, each
/// box's coefficients from its parent's by integer midpoint subdivision, so the work is shared
/// among leaves (no leaf is restricted from the root on its own).
struct LeafCheck<'a> {
    degrees: &'a [usize],
    index: &'a HashMap<&'a DyadicBox, usize>,
    den: &'a BigInt,
}

impl LeafCheck<'_> {
    /// `nums` are the box's Bernstein coefficients times `den · 2^{level · Σ degrees}`.
    fn descend(&self, b: &DyadicBox, nums: Vec<BigInt>) -> Result<(), CertificateError> {
        if let Some(&i) = self.index.get(b) {
            if let Some(c) = nums.iter().find(|c| c.sign() != num_bigint::Sign::Plus) {
                let scale: usize = b.level as usize * self.degrees.iter().sum::<usize>();
                return Err(CertificateError::NotPositiveLeaf {
                    index: i,
                    coeff: crate::num::rational_to_string(&Rational::new(
                        c.clone(),
                        self.den << scale,
                    )),
                });
            }
            return Ok(());
        }
        // The leaves tile the box and none contains another, so a box that is not a leaf is
        // covered by leaves strictly inside it, at most 62 levels down. The 2^dim children
        // come from halving axis by axis (both halves of a line in one pass): child `c` is the
        // lower (bit `axis` of `c` clear) or upper half along every axis.
        let mut parts: Vec<Vec<BigInt>> = vec![nums];
        for axis in 0..self.degrees.len() {
            let mut next = Vec::with_capacity(2 * parts.len());
            for part in &parts {
                let (lower, upper) = midpoint_halves(self.degrees, part, axis);
                next.push(lower);
                next.push(upper);
            }
            parts = next;
        }
        // After axis a the parts are ordered with axis a's bit lowest; reverse the bit order
        // to index children by `c` (bit `axis` = upper along `axis`).
        let dim = self.degrees.len();
        let mut children: Vec<Option<Vec<BigInt>>> = parts.into_iter().map(Some).collect();
        for c in 0..1usize << dim {
            let at = (0..dim).fold(0, |k, axis| k | ((c >> axis & 1) << (dim - 1 - axis)));
            let child = children[at].take().expect("each part once");
            self.descend(&b.child(c), child)?;
        }
        Ok(())
    }
}

/// Both halves of every line along `axis`, split at ½ by de Casteljau without division: level
/// `r` holds `2^r` times the averages; output `i` of the lower half (the triangle's left side,
/// `c^{(i)}_0`) is brought to the common scale `2^d` by `2^{d−i}`, and the upper half is the
/// right side `c^{(d−i)}_i`, likewise.
fn midpoint_halves(degrees: &[usize], nums: &[BigInt], axis: usize) -> (Vec<BigInt>, Vec<BigInt>) {
    let d = degrees[axis];
    let stride: usize = degrees[..axis].iter().map(|e| e + 1).product();
    let block = stride * (d + 1);
    let mut lower = nums.to_vec();
    let mut upper = nums.to_vec();
    let mut tri: Vec<BigInt> = vec![BigInt::zero(); d + 1];
    for base in (0..nums.len()).step_by(block) {
        for off in 0..stride {
            let at = |k: usize| base + off + k * stride;
            for (k, t) in tri.iter_mut().enumerate() {
                t.clone_from(&nums[at(k)]);
            }
            lower[at(0)] <<= d;
            upper[at(d)] <<= d;
            for r in 1..=d {
                for k in 0..=d - r {
                    let (a, b) = tri.split_at_mut(k + 1);
                    a[k] += &b[0];
                }
                lower[at(r)].clone_from(&tri[0]);
                lower[at(r)] <<= d - r;
                upper[at(d - r)].clone_from(&tri[d - r]);
                upper[at(d - r)] <<= d - r;
            }
        }
    }
    (lower, upper)
}

/// Re-checks a `NotPositive` witness: the point lies in the unit box and `p(point) ≤ 0`,
/// evaluated exactly; a claimed exact value must match. Returns the exact value.
pub fn verify_witness(
    p: &Bernstein<Rational>,
    witness: &[Rational],
    claimed: Option<&Rational>,
) -> Result<Rational, CertificateError> {
    if witness.len() != p.dim()
        || witness
            .iter()
            .any(|t| t.sign() == Sign::Negative || t > &<Rational as One>::one())
    {
        return Err(CertificateError::BadWitness);
    }
    let value = p.eval(witness).map_err(|_| CertificateError::BadWitness)?;
    if value.sign() == Sign::Positive {
        return Err(CertificateError::WitnessPositive {
            value: crate::num::rational_to_string(&value),
        });
    }
    if let Some(c) = claimed {
        if c != &value {
            return Err(CertificateError::WitnessValueMismatch {
                claimed: crate::num::rational_to_string(c),
                exact: crate::num::rational_to_string(&value),
            });
        }
    }
    Ok(value)
}
