//! The [`Field`] trait: write an algorithm once, run it exactly or in `f64`.
//!
//! `BigRational` is not `Copy`, so every operation takes references and returns
//! a new value. Implemented for [`Rational`] (exact), [`Interval`] (certified
//! `f64`) and plain `f64` (fast, uncertified: use only where no sign is decided).

use super::{interval::Interval, rational::rational_sign, Rational, Sign};
use num_bigint::BigInt;
use num_traits::{One, Zero};

/// Field operations, sign and conversion for a scalar type.
pub trait Field: Clone + std::fmt::Debug + Send + Sync {
    /// The additive identity.
    fn zero() -> Self;
    /// The multiplicative identity.
    fn one() -> Self;
    /// The exact value `n / d` (`d ≠ 0`), or the tightest enclosure the type has.
    fn from_ratio(n: i64, d: i64) -> Self;
    /// The rational `r`, exactly or enclosed.
    fn from_rational(r: &Rational) -> Self;
    /// `self + o`.
    fn add(&self, o: &Self) -> Self;
    /// `self − o`.
    fn sub(&self, o: &Self) -> Self;
    /// `self · o`.
    fn mul(&self, o: &Self) -> Self;
    /// Division; the caller guarantees a nonzero divisor in exact types.
    fn div(&self, o: &Self) -> Self;
    /// `−self`.
    fn neg(&self) -> Self;
    /// The sign: exact types never say `Uncertain`.
    fn sign(&self) -> Sign;
    /// A nearby `f64` (the nearest for exact types, the midpoint for intervals).
    fn approx(&self) -> f64;
    /// True when the value is exactly zero.
    fn is_exact_zero(&self) -> bool {
        self.sign() == Sign::Zero
    }
    /// `self · n` for a small integer `n`.
    fn mul_int(&self, n: i64) -> Self {
        self.mul(&Self::from_ratio(n, 1))
    }
    /// De Casteljau subdivision of one line of Bernstein coefficients at `t`: the pieces on
    /// `[0, t]` and `[t, 1]`. A type may do it faster than the generic recurrence.
    fn split_line(line: &[Self], t: &Self) -> (Vec<Self>, Vec<Self>) {
        crate::bernstein::poly::de_casteljau_split(line, t)
    }
    /// The value of one line of Bernstein coefficients at `t` (de Casteljau).
    fn eval_line(line: &[Self], t: &Self) -> Self {
        crate::bernstein::poly::de_casteljau_eval(line, t)
    }
    /// De Casteljau subdivision at `t` of every line along one axis of a tensor: `coeffs` is
    /// blocks of `len` slabs of `inner` values (slab `k` of a block holds the `k`-th
    /// coefficient of `inner` lines). Appends the pieces on `[0, t]` and `[t, 1]` to `left`
    /// and `right`, in the same layout. A type may do it without gathering each line.
    fn split_lines(
        coeffs: &[Self],
        len: usize,
        inner: usize,
        t: &Self,
        left: &mut Vec<Self>,
        right: &mut Vec<Self>,
    ) {
        split_lines_linewise(coeffs, len, inner, t, left, right);
    }
    /// The value at `t` of every line along one axis of a tensor laid out as in
    /// [`Field::split_lines`]: appends one slab of `inner` values per block to `out`.
    fn eval_lines(coeffs: &[Self], len: usize, inner: usize, t: &Self, out: &mut Vec<Self>) {
        let mut line = Vec::with_capacity(len);
        for block in coeffs.chunks_exact(len * inner) {
            for i in 0..inner {
                line.clear();
                line.extend((0..len).map(|k| block[i + inner * k].clone()));
                out.push(Self::eval_line(&line, t));
            }
        }
    }
    /// [`Field::eval_lines`] where any enclosure of the values will do (the cheap test of a
    /// split plane): the same values unless a type has a cheaper, possibly wider, enclosure.
    fn enclose_lines(coeffs: &[Self], len: usize, inner: usize, t: &Self, out: &mut Vec<Self>) {
        Self::eval_lines(coeffs, len, inner, t, out);
    }
    /// The coefficient-wise combination `Σ_j w_j v_j[c]` of equally long vectors `v_j`
    /// (the shorter of `weights` and `vectors` counts): [`Field::dot`] per coefficient unless
    /// a type does it faster.
    fn combine(weights: &[Self], vectors: &[&[Self]]) -> Vec<Self> {
        let count = vectors.first().map_or(0, |v| v.len());
        (0..count)
            .map(|c| Self::dot(weights, vectors.iter().map(|v| &v[c])))
            .collect()
    }
    /// The linear combination `Σ_j w_j v_j` (the shorter of `weights` and `values` counts). A type
    /// may do it faster than one rounding or reduction per operation.
    fn dot<'v>(weights: &[Self], values: impl IntoIterator<Item = &'v Self>) -> Self
    where
        Self: 'v,
    {
        weights
            .iter()
            .zip(values)
            .fold(Self::zero(), |s, (w, v)| s.add(&w.mul(v)))
    }
}

impl Field for Rational {
    fn zero() -> Self {
        Zero::zero()
    }
    fn one() -> Self {
        One::one()
    }
    fn from_ratio(n: i64, d: i64) -> Self {
        Rational::new(BigInt::from(n), BigInt::from(d))
    }
    fn from_rational(r: &Rational) -> Self {
        r.clone()
    }
    // Dyadic values (power-of-two denominators: every f64, every dyadic split) are added,
    // subtracted and multiplied without a gcd; others through `num-rational`.
    // Values whose parts fit in `i64` go through `i128` with a machine-word gcd.
    fn add(&self, o: &Self) -> Self {
        super::rational::dyadic_add(self, o, false)
            .or_else(|| super::rational::small_add(self, o, false))
            .unwrap_or_else(|| self + o)
    }
    fn sub(&self, o: &Self) -> Self {
        super::rational::dyadic_add(self, o, true)
            .or_else(|| super::rational::small_add(self, o, true))
            .unwrap_or_else(|| self - o)
    }
    fn mul(&self, o: &Self) -> Self {
        super::rational::dyadic_mul(self, o)
            .or_else(|| super::rational::small_mul(self, o, false))
            .unwrap_or_else(|| self * o)
    }
    fn div(&self, o: &Self) -> Self {
        super::rational::small_mul(self, o, true).unwrap_or_else(|| self / o)
    }
    fn neg(&self) -> Self {
        -self
    }
    fn sign(&self) -> Sign {
        rational_sign(self)
    }
    fn approx(&self) -> f64 {
        super::rational_to_f64(self)
    }
    fn mul_int(&self, n: i64) -> Self {
        Rational::new(self.numer() * BigInt::from(n), self.denom().clone())
    }
    fn split_line(line: &[Self], t: &Self) -> (Vec<Self>, Vec<Self>) {
        super::rational::dyadic_split_line(line, t)
            .unwrap_or_else(|| super::rational::common_split_line(line, t))
    }
    fn eval_line(line: &[Self], t: &Self) -> Self {
        match super::rational::dyadic_split_line(line, t) {
            Some((mut left, _)) => left.pop().expect("a line has a coefficient"),
            None => super::rational::common_eval_line(line, t),
        }
    }
    fn dot<'v>(weights: &[Self], values: impl IntoIterator<Item = &'v Self>) -> Self {
        super::rational::common_dot(weights, values)
    }
}

/// Evaluates `$body` with `$step` bound to the interval de Casteljau step
/// `(a, b) ↦ (1 − t)·a + t·b`, chosen once for `t`: at `t = ½` a midpoint
/// ([`Interval::midpoint_of`], one outward-rounded addition); at a point `t` whose complement
/// is exact a non-negative blend ([`Interval::blend`]); otherwise the generic interval
/// products. Each choice monomorphises `$body`, so the step inlines.
macro_rules! with_interval_step {
    ($t:expr, $step:ident => $body:expr) => {{
        let t: &Interval = $t;
        if t.is_half() {
            let $step = Interval::midpoint_of;
            $body
        } else if let Some((s, w)) = t.exact_weights() {
            let $step = |a: Interval, b: Interval| Interval::blend(a, b, s, w);
            $body
        } else {
            let s = <Interval as Field>::one().sub(t);
            let $step = |a: Interval, b: Interval| s * a + *t * b;
            $body
        }
    }};
}

impl Field for Interval {
    fn zero() -> Self {
        Interval::point(0.0)
    }
    fn one() -> Self {
        Interval::point(1.0)
    }
    fn from_ratio(n: i64, d: i64) -> Self {
        Interval::from_ratio(n, d)
    }
    fn from_rational(r: &Rational) -> Self {
        Interval::from_rational(r)
    }
    fn add(&self, o: &Self) -> Self {
        *self + *o
    }
    fn sub(&self, o: &Self) -> Self {
        *self - *o
    }
    fn mul(&self, o: &Self) -> Self {
        *self * *o
    }
    fn div(&self, o: &Self) -> Self {
        *self / *o
    }
    fn neg(&self) -> Self {
        -*self
    }
    fn sign(&self) -> Sign {
        Interval::sign(self)
    }
    fn approx(&self) -> f64 {
        self.mid()
    }
    /// With the step `with_interval_step!` chooses for `t` (a midpoint at ½, a blend
    /// where `1 − t` is exact, the generic recurrence otherwise).
    fn split_line(line: &[Self], t: &Self) -> (Vec<Self>, Vec<Self>) {
        if t.is_half() && !line.is_empty() {
            let (mut left, mut right) = (Vec::with_capacity(line.len()), Vec::new());
            split_slabs_half(line, line.len(), 1, &mut left, &mut right);
            return (left, right);
        }
        with_interval_step!(t, step => split_with(line, step))
    }
    /// With point weights (every `f64`, every dyadic preconditioner entry) each end is one
    /// sum of `n` products rounded to nearest, widened once by the classical bound
    /// `γₙ·Σ|pⱼ|` of its rounding error (Higham, *Accuracy and Stability of Numerical
    /// Algorithms*, §3.1) plus `n` subnormal units for underflow, taken with a factor two to
    /// spare: no rounding mode and no per-term widening. A zero weight adds nothing (it times
    /// any real is 0). Other weights take the generic interval products.
    fn dot<'v>(weights: &[Self], values: impl IntoIterator<Item = &'v Self>) -> Self {
        let values = values.into_iter();
        if weights.iter().any(|w| w.lo != w.hi) {
            return weights
                .iter()
                .zip(values)
                .fold(Interval::point(0.0), |s, (w, v)| s + *w * *v);
        }
        let (mut lo, mut hi, mut magnitude, mut n) = (0.0f64, 0.0f64, 0.0f64, 0u32);
        for (w, v) in weights.iter().zip(values) {
            if w.lo == 0.0 {
                continue;
            }
            let (a, b) = scaled_ends(w.lo, v);
            lo += a;
            hi += b;
            magnitude += a.abs().max(b.abs());
            n += 1;
        }
        widened_sum(lo, hi, magnitude, n)
    }
    /// With point weights, vector by vector over all coefficients in round-to-nearest (the
    /// loops run over contiguous memory and vectorise), each end then moved outward by one
    /// rounding bound for the whole row (`row_bound`: Higham's bound of [`Field::dot`]
    /// with the largest coefficient magnitude of each vector). Vectors with an unbounded
    /// coefficient go coefficient by coefficient.
    fn combine(weights: &[Self], vectors: &[&[Self]]) -> Vec<Self> {
        let count = vectors.first().map_or(0, |v| v.len());
        if weights.iter().any(|w| w.lo != w.hi) {
            return (0..count)
                .map(|c| Self::dot(weights, vectors.iter().map(|v| &v[c])))
                .collect();
        }
        let (mut lo, mut hi) = (vec![0.0f64; count], vec![0.0f64; count]);
        let (mut magnitude, mut n) = (0.0f64, 0u32);
        for (w, v) in weights.iter().zip(vectors) {
            let x = w.lo;
            if x == 0.0 {
                continue;
            }
            n += 1;
            magnitude += x.abs() * largest_end(&v[..count]);
            let v = &v[..count];
            if x > 0.0 {
                for ((l, h), c) in lo.iter_mut().zip(hi.iter_mut()).zip(v) {
                    *l += x * c.lo;
                    *h += x * c.hi;
                }
            } else {
                for ((l, h), c) in lo.iter_mut().zip(hi.iter_mut()).zip(v) {
                    *l += x * c.hi;
                    *h += x * c.lo;
                }
            }
        }
        let Some(bound) = row_bound(magnitude, n) else {
            return (0..count)
                .map(|c| Self::dot(weights, vectors.iter().map(|v| &v[c])))
                .collect();
        };
        // A NaN end (an input end NaN: [`largest_end`] passes over it) is the whole line.
        lo.iter()
            .zip(&hi)
            .map(|(&l, &h)| {
                if l.is_nan() || h.is_nan() {
                    Interval::new(f64::NEG_INFINITY, f64::INFINITY)
                } else {
                    Interval {
                        lo: l - bound,
                        hi: h + bound,
                    }
                }
            })
            .collect()
    }
    fn eval_line(line: &[Self], t: &Self) -> Self {
        with_interval_step!(t, step => eval_with(line, step))
    }
    /// Slab by slab, with the steps of [`Field::split_line`] (the same operations on each
    /// line, so the same enclosures).
    fn split_lines(
        coeffs: &[Self],
        len: usize,
        inner: usize,
        t: &Self,
        left: &mut Vec<Self>,
        right: &mut Vec<Self>,
    ) {
        if t.is_half() {
            return split_slabs_half(coeffs, len, inner, left, right);
        }
        with_interval_step!(t, step => split_slabs(coeffs, len, inner, step, left, right));
    }
    fn eval_lines(coeffs: &[Self], len: usize, inner: usize, t: &Self, out: &mut Vec<Self>) {
        with_interval_step!(t, step => eval_slabs(coeffs, len, inner, step, out));
    }
    /// Horner's rule in `q = t/(1 − t)`, slab by slab: `(1 − t)^d Σₖ C(d, k) qᵏ bₖ`, `d + 1`
    /// interval steps per value instead of de Casteljau's `d(d + 1)/2` (every operation
    /// rounded outward, so the result encloses the exact value). For `t` outside `(0, 1)`
    /// (no such `q`), de Casteljau.
    fn enclose_lines(coeffs: &[Self], len: usize, inner: usize, t: &Self, out: &mut Vec<Self>) {
        let s = <Interval as Field>::one() - *t;
        if !(t.lo > 0.0 && s.lo > 0.0) {
            return Self::eval_lines(coeffs, len, inner, t, out);
        }
        let d = len - 1;
        // C(d, k) exactly in integers (below 2^53 up to d = 56, so exact in f64 too).
        if d > 56 {
            return Self::eval_lines(coeffs, len, inner, t, out);
        }
        let q = *t / s;
        let scale = (0..d).fold(<Interval as Field>::one(), |acc, _| acc * s);
        let mut binom = vec![1u64; len];
        for k in 1..len {
            binom[k] = binom[k - 1] * (d + 1 - k) as u64 / k as u64;
        }
        // A point `t` with an exact complement: `q` to nearest, one rounding.
        if let Some((complement, point)) = t.exact_weights() {
            if horner_to_nearest(coeffs, len, inner, point / complement, &binom, scale, out) {
                return;
            }
        }
        let weight = |k: usize| Interval::point(binom[k] as f64);
        let mut acc = vec![Interval::point(0.0); inner];
        for block in coeffs.chunks_exact(len * inner) {
            for (i, a) in acc.iter_mut().enumerate() {
                *a = weight(d) * block[i + inner * d];
            }
            for k in (0..d).rev() {
                let w = weight(k);
                for (i, a) in acc.iter_mut().enumerate() {
                    *a = *a * q + w * block[i + inner * k];
                }
            }
            out.extend(acc.iter().map(|a| *a * scale));
        }
    }
}

/// The ends of `x·v` for a point weight `x ≠ 0`, each rounded to nearest: `(lower, upper)`.
#[inline]
fn scaled_ends(x: f64, v: &Interval) -> (f64, f64) {
    if x > 0.0 {
        (x * v.lo, x * v.hi)
    } else {
        (x * v.hi, x * v.lo)
    }
}

/// The enclosure of a sum of `n` products whose lower and upper ends were summed to nearest
/// as `lo` and `hi`, with `magnitude` the computed sum of the larger end magnitudes: each end
/// widened by `|error| ≤ γₙ/(1 − γₙ)·magnitude + n·2⁻¹⁰⁷⁴ < 2(n + 1)u·magnitude + n·2⁻¹⁰⁷⁴`
/// (Higham, *Accuracy and Stability of Numerical Algorithms*, §3.1; the last term for
/// underflow), rounded outward; the whole line when a sum is not a number.
fn widened_sum(lo: f64, hi: f64, magnitude: f64, n: u32) -> Interval {
    let bound = sum_error(magnitude, n);
    let out = Interval {
        lo: (lo - bound).next_down(),
        hi: (hi + bound).next_up(),
    };
    if out.lo.is_nan() || out.hi.is_nan() {
        Interval {
            lo: f64::NEG_INFINITY,
            hi: f64::INFINITY,
        }
    } else {
        out
    }
}

/// The largest end magnitude of `v`, passing over NaN ends (four running maxima by plain
/// comparison, which vectorise; `f64::max`'s NaN rule does not). Infinite ends count.
fn largest_end(v: &[Interval]) -> f64 {
    let mut acc = [0.0f64; 4];
    let pairs = v.chunks_exact(2);
    let rest = pairs.remainder();
    for pair in pairs {
        let ends = [
            pair[0].lo.abs(),
            pair[0].hi.abs(),
            pair[1].lo.abs(),
            pair[1].hi.abs(),
        ];
        for (a, e) in acc.iter_mut().zip(ends) {
            if e > *a {
                *a = e;
            }
        }
    }
    for c in rest {
        for e in [c.lo.abs(), c.hi.abs()] {
            if e > acc[0] {
                acc[0] = e;
            }
        }
    }
    acc.into_iter().fold(0.0, f64::max)
}

/// The amount by which to move each end of `n`-term sums computed to nearest, whose terms'
/// magnitudes sum to at most `magnitude` (each term's computed product counted), so that one
/// subtraction (or addition) rounded to nearest lands outside the exact value: Higham's
/// `γₙ/(1 − γₙ)·magnitude < 2(n + 1)u·magnitude` plus `n·2⁻¹⁰⁷⁴` for underflow, plus
/// `4u·(magnitude + bound)` for the rounding of that last subtraction itself (`|end| ≤
/// (1 + γₙ)·magnitude`). `None` when `magnitude` is not finite.
fn row_bound(magnitude: f64, n: u32) -> Option<f64> {
    if !magnitude.is_finite() {
        return None;
    }
    let moved = past_last_rounding(sum_error(magnitude, n), magnitude);
    moved.is_finite().then_some(moved)
}

/// `2(n + 1)u·magnitude + n·2⁻¹⁰⁷⁴`, rounded up: above Higham's `γₙ/(1 − γₙ)·magnitude`
/// bound of an `n`-term sum to nearest whose terms' magnitudes sum to `magnitude`, with the
/// underflow term ([`widened_sum`], [`row_bound`]).
fn sum_error(magnitude: f64, n: u32) -> f64 {
    let n = f64::from(n);
    (magnitude * ((n + 1.0) * f64::EPSILON) + n * f64::from_bits(1)).next_up()
}

/// `bound + 4u·(magnitude + bound)`, rounded up: moving an end of magnitude at most about
/// `magnitude` by this, in one subtraction (or addition) to nearest, lands at least `bound`
/// outside it ([`row_bound`], [`split_slabs_half`]).
fn past_last_rounding(bound: f64, magnitude: f64) -> f64 {
    (bound + 2.0 * f64::EPSILON * (magnitude + bound)).next_up()
}

/// [`Field::split_lines`] line by line through [`Field::split_line`] (the trait's default; for
/// intervals, outward rounding at every step).
pub(crate) fn split_lines_linewise<T: Field>(
    coeffs: &[T],
    len: usize,
    inner: usize,
    t: &T,
    left: &mut Vec<T>,
    right: &mut Vec<T>,
) {
    let mut line = Vec::with_capacity(len);
    for block in coeffs.chunks_exact(len * inner) {
        let (l0, r0) = (left.len(), right.len());
        left.resize(l0 + block.len(), T::zero());
        right.resize(r0 + block.len(), T::zero());
        for i in 0..inner {
            line.clear();
            line.extend((0..len).map(|k| block[i + inner * k].clone()));
            let (l, r) = T::split_line(&line, t);
            for (k, (l, r)) in l.into_iter().zip(r).enumerate() {
                left[l0 + i + inner * k] = l;
                right[r0 + i + inner * k] = r;
            }
        }
    }
}

/// De Casteljau subdivision of every line of a tensor along one axis at once (layout of
/// [`Field::split_lines`]) with the step `(a, b) ↦ (1 − t)·a + t·b`: each level updates whole
/// slabs, and the work is done in place in `right`, whose slab `k` is final after level
/// `len − 1 − k`; `left` takes slab 0 after every level.
pub(crate) fn split_slabs<T: Copy>(
    coeffs: &[T],
    len: usize,
    inner: usize,
    step: impl Fn(T, T) -> T,
    left: &mut Vec<T>,
    right: &mut Vec<T>,
) {
    for block in coeffs.chunks_exact(len * inner) {
        left.extend_from_slice(&block[..inner]);
        let r0 = right.len();
        right.extend_from_slice(block);
        let work = &mut right[r0..];
        for r in 1..len {
            reduce_level(work, len - r, inner, &step);
            left.extend_from_slice(&work[..inner]);
        }
    }
}

/// [`Field::enclose_lines`]' Horner sums `Σₖ C(d, k) qᵏ bₖ` in round-to-nearest on both ends
/// and on the ends' magnitudes (plain `f64`, which vectorises), each moved outward once by
/// the rounding bound and then multiplied by `scale ∋ (1 − t)^d`. `q` is `t/(1 − t)` rounded
/// once (`q > 0`, so each end's sum bounds the line's values on its side). Every term passes
/// through at most `2d + 1` roundings and `q`'s own error `(1 + u)^k`, so each sum is within
/// `γ₃d₊₁` of the magnitudes' sum `M` (computed within the same factor), plus underflow:
/// at most `2d + 1` units of `2⁻¹⁰⁷⁴`, each grown by at most `max(1, q)^d` (Higham,
/// *Accuracy and Stability of Numerical Algorithms*, §5.1). A value from a NaN end is the
/// whole line. Returns `false` (appending nothing) when a magnitude is not finite.
fn horner_to_nearest(
    coeffs: &[Interval],
    len: usize,
    inner: usize,
    q: f64,
    binom: &[u64],
    scale: Interval,
    out: &mut Vec<Interval>,
) -> bool {
    let d = len - 1;
    if !(q > 0.0 && q.is_finite()) {
        return false;
    }
    let weights: Vec<f64> = binom.iter().map(|&c| c as f64).collect();
    let roundings = (3 * d + 3) as f64 * f64::EPSILON;
    let underflow = (2 * d + 2) as f64 * f64::from_bits(1) * q.max(1.0).powi(d as i32) * 2.0;
    let start = out.len();
    let (mut lo, mut hi, mut mag) = (vec![0.0; inner], vec![0.0; inner], vec![0.0; inner]);
    for block in coeffs.chunks_exact(len * inner) {
        let top = &block[inner * d..inner * (d + 1)];
        for (((l, h), m), c) in lo.iter_mut().zip(&mut hi).zip(&mut mag).zip(top) {
            *l = weights[d] * c.lo;
            *h = weights[d] * c.hi;
            *m = weights[d] * c.lo.abs().max(c.hi.abs());
        }
        for k in (0..d).rev() {
            let w = weights[k];
            let slab = &block[inner * k..inner * (k + 1)];
            for (((l, h), m), c) in lo.iter_mut().zip(&mut hi).zip(&mut mag).zip(slab) {
                *l = *l * q + w * c.lo;
                *h = *h * q + w * c.hi;
                *m = *m * q + w * c.lo.abs().max(c.hi.abs());
            }
        }
        for ((&l, &h), &m) in lo.iter().zip(&hi).zip(&mag) {
            let bound = (m * roundings + underflow).next_up();
            if !bound.is_finite() {
                out.truncate(start);
                return false;
            }
            if l.is_nan() || h.is_nan() {
                out.push(Interval::new(f64::NEG_INFINITY, f64::INFINITY));
                continue;
            }
            let (a, b) = ((l - bound).next_down(), (h + bound).next_up());
            let lower = if a >= 0.0 { a * scale.lo } else { a * scale.hi };
            let upper = if b >= 0.0 { b * scale.hi } else { b * scale.lo };
            out.push(Interval {
                lo: lower.next_down(),
                hi: upper.next_up(),
            });
        }
    }
    true
}

/// [`split_slabs`] of intervals at ½ in round-to-nearest on both ends (plain `f64` additions
/// and halvings, which vectorise), each line's results then moved outward once by the bound
/// of all its levels' rounding: a value of level `r` is the mean of two of level `r − 1` and
/// one rounding more, so its error is at most `r·(u·m + 2⁻¹⁰⁷⁵)` with `m` the line's largest
/// end magnitude (every value is a mean, so none exceeds `m` by more than rounding; a halving
/// is exact unless subnormal). A line with an unbounded end, or one within a factor four of
/// overflow, keeps the outward rounding of every step ([`Interval::midpoint_of`]); a NaN end
/// stays NaN, as it does there.
pub(crate) fn split_slabs_half(
    coeffs: &[Interval],
    len: usize,
    inner: usize,
    left: &mut Vec<Interval>,
    right: &mut Vec<Interval>,
) {
    let mean = |a: Interval, b: Interval| Interval {
        lo: 0.5 * (a.lo + b.lo),
        hi: 0.5 * (a.hi + b.hi),
    };
    let levels = (len - 1) as f64;
    let mut bounds = vec![0.0f64; inner];
    for block in coeffs.chunks_exact(len * inner) {
        bounds.iter_mut().for_each(|b| *b = 0.0);
        for slab in block.chunks_exact(inner) {
            for (b, c) in bounds.iter_mut().zip(slab) {
                *b = b.max(c.lo.abs()).max(c.hi.abs());
            }
        }
        // `levels·(2u·m + 2⁻¹⁰⁷⁴)` covers `(1 + u)^r` growth of `m`; the final move adds
        // `4u·(m + bound)` for its own rounding ([`row_bound`]'s argument).
        // Ends within a factor four of overflow keep the outward rounding too: a sum of two
        // of them may overflow before it is halved.
        let mut finite = true;
        for b in bounds.iter_mut() {
            let m = *b;
            let bound = (levels * (m * f64::EPSILON + f64::from_bits(1))).next_up();
            *b = past_last_rounding(bound, m);
            finite &= m < f64::MAX / 4.0 && b.is_finite();
        }
        if !finite {
            split_slabs(block, len, inner, Interval::midpoint_of, left, right);
            continue;
        }
        let (l0, r0) = (left.len(), right.len());
        left.extend_from_slice(&block[..inner]);
        right.extend_from_slice(block);
        let work = &mut right[r0..];
        for r in 1..len {
            reduce_level(work, len - r, inner, &mean);
            left.extend_from_slice(&work[..inner]);
        }
        // Slab 0 of the left half and the last of the right are the inputs themselves.
        let (fresh_left, fresh_right) = (
            &mut left[l0 + inner..],
            &mut right[r0..r0 + (len - 1) * inner],
        );
        for slab in fresh_left
            .chunks_exact_mut(inner)
            .chain(fresh_right.chunks_exact_mut(inner))
        {
            for (c, b) in slab.iter_mut().zip(&bounds) {
                c.lo -= b;
                c.hi += b;
            }
        }
    }
}

/// One de Casteljau level on slabs: slab `k ← step(slab k, slab k + 1)` for `k < count`.
#[inline]
pub(crate) fn reduce_level<T: Copy>(
    work: &mut [T],
    count: usize,
    inner: usize,
    step: &impl Fn(T, T) -> T,
) {
    for k in 0..count {
        let (this, next) = work[k * inner..(k + 2) * inner].split_at_mut(inner);
        for (x, y) in this.iter_mut().zip(next.iter()) {
            *x = step(*x, *y);
        }
    }
}

/// The values of every line of a tensor along one axis (layout of [`Field::split_lines`]),
/// slab by slab with the step of [`split_slabs`].
pub(crate) fn eval_slabs<T: Copy>(
    coeffs: &[T],
    len: usize,
    inner: usize,
    step: impl Fn(T, T) -> T,
    out: &mut Vec<T>,
) {
    let mut work = Vec::with_capacity(len * inner);
    for block in coeffs.chunks_exact(len * inner) {
        work.clear();
        work.extend_from_slice(block);
        for r in 1..len {
            reduce_level(&mut work, len - r, inner, &step);
        }
        out.extend_from_slice(&work[..inner]);
    }
}

/// De Casteljau's subdivision of an interval line with the step `(a, b) ↦ (1 − t)·a + t·b`
/// (each monomorphised, so the step inlines).
fn split_with(line: &[Interval], step: impl Fn(Interval, Interval) -> Interval) -> SplitLine {
    let n = line.len();
    let mut work = line.to_vec();
    let mut left = Vec::with_capacity(n);
    let mut right = vec![Interval::point(0.0); n];
    left.push(work[0]);
    right[n - 1] = work[n - 1];
    for r in 1..n {
        for i in 0..n - r {
            work[i] = step(work[i], work[i + 1]);
        }
        left.push(work[0]);
        right[n - 1 - r] = work[n - 1 - r];
    }
    (left, right)
}

/// The pieces of a split line on `[0, t]` and `[t, 1]`.
type SplitLine = (Vec<Interval>, Vec<Interval>);

/// De Casteljau's value of an interval line with the step of [`split_with`].
fn eval_with(line: &[Interval], step: impl Fn(Interval, Interval) -> Interval) -> Interval {
    let mut work = line.to_vec();
    for r in 1..work.len() {
        for i in 0..work.len() - r {
            work[i] = step(work[i], work[i + 1]);
        }
    }
    work[0]
}

/// Plain `f64`: fast and uncertified. Its `sign` is the sign of the rounded value,
/// so it must not be used for certified decisions.
impl Field for f64 {
    fn zero() -> Self {
        0.0
    }
    fn one() -> Self {
        1.0
    }
    fn from_ratio(n: i64, d: i64) -> Self {
        n as f64 / d as f64
    }
    fn from_rational(r: &Rational) -> Self {
        super::rational_to_f64(r)
    }
    fn add(&self, o: &Self) -> Self {
        self + o
    }
    fn sub(&self, o: &Self) -> Self {
        self - o
    }
    fn mul(&self, o: &Self) -> Self {
        self * o
    }
    fn div(&self, o: &Self) -> Self {
        self / o
    }
    fn neg(&self) -> Self {
        -self
    }
    fn sign(&self) -> Sign {
        if *self > 0.0 {
            Sign::Positive
        } else if *self < 0.0 {
            Sign::Negative
        } else if *self == 0.0 {
            Sign::Zero
        } else {
            Sign::Uncertain
        }
    }
    fn approx(&self) -> f64 {
        *self
    }
    fn split_lines(
        coeffs: &[Self],
        len: usize,
        inner: usize,
        t: &Self,
        left: &mut Vec<Self>,
        right: &mut Vec<Self>,
    ) {
        let s = 1.0 - t;
        split_slabs(coeffs, len, inner, |a, b| s * a + t * b, left, right);
    }
    fn eval_lines(coeffs: &[Self], len: usize, inner: usize, t: &Self, out: &mut Vec<Self>) {
        let s = 1.0 - t;
        eval_slabs(coeffs, len, inner, |a, b| s * a + t * b, out);
    }
}
