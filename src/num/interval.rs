//! Certified `f64`: outward-rounded intervals and forward error constants.
//!
//! Every operation computes in the default round-to-nearest mode and then widens
//! the result by one ulp in each direction (`f64::next_down` / `f64::next_up`).
//! Round-to-nearest is within half an ulp of the exact result, so the widened
//! interval contains it. The FPU rounding mode is never changed.

use super::{rational_from_f64, Rational, Sign};

/// The unit roundoff of binary64, `u = 2⁻⁵³`.
pub const UNIT_ROUNDOFF: f64 = 1.0 / 9_007_199_254_740_992.0;

/// `γₙ = n·u / (1 − n·u)` (Higham, *Accuracy and Stability of Numerical Algorithms*, §3.1),
/// rounded up; bounds the relative error of `n` chained roundings.
pub fn gamma(n: u32) -> f64 {
    let nu = n as f64 * UNIT_ROUNDOFF;
    (nu / (1.0 - nu)).next_up()
}

/// A closed interval `[lo, hi]` of reals, guaranteed to contain the exact value
/// it stands for. Empty and NaN intervals are never produced from finite inputs;
/// overflow yields infinite bounds, which stay sound (and make signs `Uncertain`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    /// Lower end.
    pub lo: f64,
    /// Upper end.
    pub hi: f64,
}

impl Interval {
    /// The point interval `[x, x]` (exact: `x` is the value).
    pub fn point(x: f64) -> Interval {
        Interval { lo: x, hi: x }
    }

    /// `[lo, hi]`; the caller asserts `lo ≤ hi`.
    pub fn new(lo: f64, hi: f64) -> Interval {
        debug_assert!(lo <= hi || lo.is_nan() || hi.is_nan());
        Interval { lo, hi }
    }

    /// The tightest interval of `f64` that contains the rational `r`.
    pub fn from_rational(r: &Rational) -> Interval {
        if let Some(x) = super::rational::exact_f64(r) {
            return Interval::point(x);
        }
        let x = super::rational_to_f64(r);
        // Every finite f64 is dyadic: a rational whose (lowest-terms) denominator is no power
        // of two is never one, and the rounded quotient lies strictly inside the widening.
        if super::rational::power_of_two(r.denom()).is_none() {
            return Interval {
                lo: x.next_down(),
                hi: x.next_up(),
            };
        }
        let exact = rational_from_f64(x, "interval").ok();
        match exact {
            Some(e) if &e == r => Interval::point(x),
            _ => Interval {
                lo: x.next_down(),
                hi: x.next_up(),
            },
        }
    }

    /// The tightest interval around `n / d` (`d ≠ 0`): a point when the quotient is an `f64`.
    /// Small operands are divided in `f64` (correctly rounded, so the quotient lies within one
    /// ulp); others go through [`Interval::from_rational`].
    pub fn from_ratio(n: i64, d: i64) -> Interval {
        const SMALL: i64 = 1 << 53;
        if d != 0 && (-SMALL..=SMALL).contains(&n) && (-SMALL..=SMALL).contains(&d) {
            let g = num_integer::gcd(n, d);
            let (n, d) = if g == 0 { (n, d) } else { (n / g, d / g) };
            let q = n as f64 / d as f64;
            // In lowest terms, n/d is dyadic exactly when |d| is a power of two, and then
            // (|d| ≤ 2^53, |n| ≤ 2^53) the quotient is exact.
            return if d.unsigned_abs().is_power_of_two() {
                Interval::point(q)
            } else {
                Interval {
                    lo: q.next_down(),
                    hi: q.next_up(),
                }
            };
        }
        Interval::from_rational(&Rational::new(n.into(), d.into()))
    }

    fn widen(lo: f64, hi: f64) -> Interval {
        Interval {
            lo: lo.next_down(),
            hi: hi.next_up(),
        }
    }

    fn add_(self, o: Interval) -> Interval {
        let lo = self.lo + o.lo;
        let hi = self.hi + o.hi;
        Interval::widen(lo, hi)
    }

    fn sub_(self, o: Interval) -> Interval {
        Interval::widen(self.lo - o.hi, self.hi - o.lo)
    }

    fn neg_(self) -> Interval {
        Interval {
            lo: -self.hi,
            hi: -self.lo,
        }
    }

    fn mul_(self, o: Interval) -> Interval {
        let p = [
            self.lo * o.lo,
            self.lo * o.hi,
            self.hi * o.lo,
            self.hi * o.hi,
        ];
        // 0·∞ gives NaN: treat it as the whole line, which is sound.
        if p.iter().any(|v| v.is_nan()) {
            return Interval {
                lo: f64::NEG_INFINITY,
                hi: f64::INFINITY,
            };
        }
        let lo = p.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = p.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Interval::widen(lo, hi)
    }

    /// Division; a divisor interval containing 0 gives the whole line.
    fn div_(self, o: Interval) -> Interval {
        if o.lo <= 0.0 && o.hi >= 0.0 {
            return Interval {
                lo: f64::NEG_INFINITY,
                hi: f64::INFINITY,
            };
        }
        let inv = Interval::widen(1.0 / o.hi, 1.0 / o.lo);
        self.mul_(inv)
    }

    /// `(a + b)/2`, enclosed: the outward-rounded sum halved. Halving is exact except below
    /// `2⁻¹⁰²¹` in magnitude (subnormal results), where each end is widened once more.
    #[inline]
    pub fn midpoint_of(a: Interval, b: Interval) -> Interval {
        let s = a.add_(b);
        let half = |x: f64, out: fn(f64) -> f64| {
            let h = 0.5 * x;
            if h != 0.0 && h.abs() < f64::MIN_POSITIVE {
                out(h)
            } else {
                h
            }
        };
        Interval {
            lo: half(s.lo, f64::next_down),
            hi: half(s.hi, f64::next_up),
        }
    }

    /// `(1 − t)·a + t·b` for weights `s = 1 − t` and `t`, both exact non-negative `f64`
    /// (`s + t = 1`): each end is a weighted sum of the ends, every product and the sum
    /// rounded to nearest and then moved one step outward, so each is on the right side of
    /// the exact value (no sign cases: the weights are non-negative).
    #[inline]
    pub fn blend(a: Interval, b: Interval, s: f64, t: f64) -> Interval {
        let lo = ((s * a.lo).next_down() + (t * b.lo).next_down()).next_down();
        let hi = ((s * a.hi).next_up() + (t * b.hi).next_up()).next_up();
        Interval { lo, hi }
    }

    /// The weights `(1 − t, t)` of a de Casteljau step when `t` is a point interval in
    /// `(0, 1)` whose complement `1 − t` is exact in `f64`, else `None` (the ends are left to
    /// the generic recurrence: a zero weight times an infinite bound would be NaN).
    pub fn exact_weights(&self) -> Option<(f64, f64)> {
        let t = self.lo;
        let s = 1.0 - t;
        (self.lo == self.hi && t > 0.0 && t < 1.0 && s + t == 1.0 && 1.0 - s == t).then_some((s, t))
    }

    /// True for the point interval `[½, ½]`, where de Casteljau's step is a midpoint.
    #[inline]
    pub fn is_half(&self) -> bool {
        self.lo == 0.5 && self.hi == 0.5
    }

    /// Multiplication by an exactly known scalar.
    pub fn scale(self, k: f64) -> Interval {
        self.mul_(Interval::point(k))
    }

    /// True when the interval contains the rational `r` (exact comparison).
    pub fn contains(&self, r: &Rational) -> bool {
        let lo = rational_from_f64(self.lo, "lo");
        let hi = rational_from_f64(self.hi, "hi");
        let above = match lo {
            Ok(l) => &l <= r,
            Err(_) => self.lo == f64::NEG_INFINITY,
        };
        let below = match hi {
            Ok(h) => r <= &h,
            Err(_) => self.hi == f64::INFINITY,
        };
        above && below
    }

    /// The certified sign: known only when the interval excludes zero, or is exactly `[0,0]`.
    pub fn sign(&self) -> Sign {
        if self.lo > 0.0 {
            Sign::Positive
        } else if self.hi < 0.0 {
            Sign::Negative
        } else if self.lo == 0.0 && self.hi == 0.0 {
            Sign::Zero
        } else {
            Sign::Uncertain
        }
    }

    /// The midpoint.
    pub fn mid(&self) -> f64 {
        0.5 * self.lo + 0.5 * self.hi
    }

    /// `hi − lo`.
    pub fn width(&self) -> f64 {
        self.hi - self.lo
    }
}

macro_rules! interval_op {
    ($tr:ident, $m:ident, $imp:ident) => {
        impl std::ops::$tr for Interval {
            type Output = Interval;
            fn $m(self, o: Interval) -> Interval {
                self.$imp(o)
            }
        }
    };
}
interval_op!(Add, add, add_);
interval_op!(Sub, sub, sub_);
interval_op!(Mul, mul, mul_);
interval_op!(Div, div, div_);

impl std::ops::Neg for Interval {
    type Output = Interval;
    fn neg(self) -> Interval {
        self.neg_()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contains_exact_results() {
        let a = Interval::point(0.1);
        let b = Interval::point(0.2);
        let s = a + b;
        let exact = rational_from_f64(0.1, "a").unwrap() + rational_from_f64(0.2, "b").unwrap();
        assert!(s.contains(&exact));
        let p = a * b;
        let exact = rational_from_f64(0.1, "a").unwrap() * rational_from_f64(0.2, "b").unwrap();
        assert!(p.contains(&exact));
        assert_eq!(Interval::new(-1e-300, 1.0).sign(), Sign::Uncertain);
        assert_eq!(Interval::new(1e-300, 1.0).sign(), Sign::Positive);
        assert_eq!(Interval::point(0.0).sign(), Sign::Zero);
    }

    /// The interval de Casteljau routes (midpoints at ½, non-negative blends at other exact
    /// splits, the generic recurrence otherwise) enclose the exact split and value of every
    /// line drawn from the intervals (their ends, taken exactly), across magnitudes from
    /// subnormals to the largest finite; 3,000 lines of 1–8 coefficients.
    #[test]
    fn interval_splits_enclose_exact_splits() {
        use crate::num::Field;
        let mut next = xorshift(0x9e37_79b9_7f4a_7c15);
        let mut checked = 0;
        for k in 0..3000 {
            // ½, the solver's other split fractions, an arbitrary dyadic, and a t whose
            // complement is not exact (the generic route).
            let (tn, td) = [
                (1i64, 2i64),
                (7, 16),
                (9, 16),
                (3, 8),
                (5, 8),
                (12345, 65536),
                (1, 3),
            ][k % 7];
            let half = Interval::from_ratio(tn, td);
            let n = 1 + (next() % 8) as usize;
            // Up to 0.995 of the largest finite magnitude (the last scale takes values of
            // either sign above half of it): sums of two ends overflow.
            let pick_scale = (next() % 5) as usize;
            let scale = [1.0, 1e-300, 1e-310, 1e300, 0.995 * f64::MAX][pick_scale];
            let line: Vec<Interval> = (0..n)
                .map(|_| {
                    let x = (next() >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                    let a = if pick_scale == 4 {
                        (0.5 + x.abs()).copysign(x) * scale
                    } else {
                        x * scale
                    };
                    let w = a.abs() * 1e-3 * (next() % 3) as f64;
                    Interval::new(a - w, a + w)
                })
                .collect();
            let (l, r) = <Interval as Field>::split_line(&line, &half);
            let e = <Interval as Field>::eval_line(&line, &half);
            for pick in [0, 1] {
                let exact: Vec<Rational> = line
                    .iter()
                    .map(|x| rational_from_f64(if pick == 0 { x.lo } else { x.hi }, "x").unwrap())
                    .collect();
                let t = Rational::new(tn.into(), td.into());
                let (el, er) = crate::bernstein::poly::de_casteljau_split(&exact, &t);
                for (i, x) in l.iter().zip(&el).chain(r.iter().zip(&er)) {
                    assert!(i.contains(x), "{i:?} misses {x}");
                    checked += 1;
                }
                assert!(e.contains(&el[n - 1]));
            }
        }
        assert!(checked > 20_000, "{checked}");
    }

    /// The tests' deterministic generator ([`crate::num::xorshift`]) from `seed`.
    fn xorshift(mut seed: u64) -> impl FnMut() -> u64 {
        move || crate::num::xorshift(&mut seed)
    }

    /// The slab-wise routines ([`Field::split_lines`], [`Field::eval_lines`]) give, for every
    /// line of a tensor along every axis, exactly the enclosures of the line-by-line routines
    /// (the same operations per line, whose enclosures the test above checks), at the three
    /// kinds of split point and magnitudes down to subnormals; and the `f64` versions the
    /// generic recurrence's values. 600 tensors of 1–3 axes.
    #[test]
    fn slab_splits_match_line_splits() {
        use crate::num::Field;
        let mut next = xorshift(0x2545_f491_4f6c_dd1d);
        let mut lines = 0;
        for k in 0..600 {
            let dims = 1 + (next() % 3) as usize;
            let lens: Vec<usize> = (0..dims).map(|_| 1 + (next() % 5) as usize).collect();
            let count: usize = lens.iter().product();
            // Magnitudes from subnormal (the per-step route) to huge.
            let scale = [1.0, 1e-300, 1e-310, 1e300][(k / 3) % 4];
            let values: Vec<Interval> = (0..count)
                .map(|_| {
                    let a = ((next() >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * scale;
                    Interval::new(a - 1e-9 * scale, a + 1e-9 * scale)
                })
                .collect();
            let points: Vec<f64> = values.iter().map(|x| x.lo).collect();
            let (tn, td) = [(1i64, 2i64), (7, 16), (1, 3)][k % 3];
            let t = Interval::from_ratio(tn, td);
            let tf = tn as f64 / td as f64;
            for axis in 0..dims {
                let len = lens[axis];
                let inner: usize = lens[..axis].iter().product();
                let (mut left, mut right, mut at) = (Vec::new(), Vec::new(), Vec::new());
                <Interval as Field>::split_lines(&values, len, inner, &t, &mut left, &mut right);
                <Interval as Field>::eval_lines(&values, len, inner, &t, &mut at);
                let (mut fl, mut fr, mut fa) = (Vec::new(), Vec::new(), Vec::new());
                <f64 as Field>::split_lines(&points, len, inner, &tf, &mut fl, &mut fr);
                <f64 as Field>::eval_lines(&points, len, inner, &tf, &mut fa);
                for (b, block) in values.chunks_exact(len * inner).enumerate() {
                    for i in 0..inner {
                        let at_k = |k: usize| b * len * inner + i + inner * k;
                        let line: Vec<Interval> = (0..len).map(|k| block[i + inner * k]).collect();
                        let (l, r) = <Interval as Field>::split_line(&line, &t);
                        let e = <Interval as Field>::eval_line(&line, &t);
                        let pline: Vec<f64> = line.iter().map(|x| x.lo).collect();
                        let (pl, pr) = crate::bernstein::poly::de_casteljau_split(&pline, &tf);
                        for kk in 0..len {
                            assert_eq!(left[at_k(kk)], l[kk]);
                            assert_eq!(right[at_k(kk)], r[kk]);
                            assert_eq!(fl[at_k(kk)], pl[kk]);
                            assert_eq!(fr[at_k(kk)], pr[kk]);
                        }
                        assert_eq!(at[b * inner + i], e);
                        assert_eq!(fa[b * inner + i], pl[len - 1]);
                        lines += 1;
                    }
                }
            }
        }
        assert!(lines > 3_000, "{lines}");
    }

    /// [`Field::enclose_lines`] (Horner's rule in `t/(1 − t)`, to nearest with one bound at
    /// the moved split points) encloses the exact value of every line at `t`, computed in
    /// rationals from the lines' lower ends and from their upper ends (point and proper
    /// intervals), at the moved split points and at a non-dyadic one, for degrees 0–16 and
    /// magnitudes from subnormals to the largest finite; ends outside `(0, 1)` take de
    /// Casteljau's enclosures.
    /// 1,500 tensors.
    #[test]
    fn horner_sections_enclose_exact_values() {
        use crate::num::{rational_from_f64, Field, Rational};
        let mut next = xorshift(0x5851_f42d_4c95_7f2d);
        let mut checked = 0;
        for k in 0..1500 {
            let dims = 1 + (next() % 3) as usize;
            let axis = (next() % dims as u64) as usize;
            let mut lens: Vec<usize> = (0..dims).map(|_| 1 + (next() % 4) as usize).collect();
            lens[axis] = 1 + (next() % 17) as usize;
            let count: usize = lens.iter().product();
            let scale = [1.0, 1e-300, 1e-310, 1e300, f64::MAX][(k / 5) % 5];
            let points: Vec<f64> = (0..count)
                .map(|_| ((next() >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * scale)
                .collect();
            // Every other case has proper intervals: their upper ends are `points`.
            let wide = (k / 2) % 2 == 1;
            let values: Vec<Interval> = points
                .iter()
                .map(|&x| Interval::new(if wide { x - x.abs() * 1e-3 } else { x }, x))
                .collect();
            let (tn, td) = [
                (7i64, 16i64),
                (9, 16),
                (3, 8),
                (5, 8),
                (1, 3),
                (0, 1),
                (1, 1),
            ][k % 7];
            let t = Interval::from_ratio(tn, td);
            let tq = Rational::new(tn.into(), td.into());
            let len = lens[axis];
            let inner: usize = lens[..axis].iter().product();
            let mut at = Vec::new();
            <Interval as Field>::enclose_lines(&values, len, inner, &t, &mut at);
            for end in [0, 1] {
                let exact: Vec<Rational> = values
                    .iter()
                    .map(|x| rational_from_f64(if end == 0 { x.lo } else { x.hi }, "x").unwrap())
                    .collect();
                let mut want = Vec::new();
                <Rational as Field>::eval_lines(&exact, len, inner, &tq, &mut want);
                assert_eq!(at.len(), want.len());
                for (e, w) in at.iter().zip(&want) {
                    assert!(e.contains(w), "{e:?} misses {w} (t = {tn}/{td}, len {len})");
                    checked += 1;
                }
            }
        }
        assert!(checked > 6_000, "{checked}");
    }

    /// [`Field::combine`] and [`Field::dot`] with point weights (the preconditioner's) enclose
    /// the exact combination of every choice of the values' ends, across magnitudes from
    /// subnormals to the largest finite and with cancellation; 4,000 combinations of 1–5
    /// terms.
    #[test]
    fn point_weight_combinations_enclose_exact_ones() {
        use crate::num::Field;
        use num_traits::Zero;
        let mut next = xorshift(0x9e37_79b9_7f4a_7c15);
        let unit = |x: u64| (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        let mut checked = 0;
        for _ in 0..4000 {
            let n = 1 + (next() % 5) as usize;
            let scale = [1.0, 1e-300, 1e-310, 1e300, f64::MAX][(next() % 5) as usize];
            let weights: Vec<Interval> = (0..n)
                .map(|_| match next() % 4 {
                    0 => Interval::point(0.0),
                    _ => Interval::point(f64::from(unit(next()) as f32) * 8.0),
                })
                .collect();
            let vectors: Vec<Vec<Interval>> = (0..n)
                .map(|_| {
                    (0..3)
                        .map(|_| {
                            let a = unit(next()) * scale;
                            Interval::new(a - a.abs() * 1e-3, a)
                        })
                        .collect()
                })
                .collect();
            let refs: Vec<&[Interval]> = vectors.iter().map(Vec::as_slice).collect();
            let combined = <Interval as Field>::combine(&weights, &refs);
            for c in 0..3 {
                let dot = <Interval as Field>::dot(&weights, refs.iter().map(|v| &v[c]));
                for pick in 0..4u32 {
                    let exact = weights.iter().zip(&refs).enumerate().fold(
                        <Rational as Zero>::zero(),
                        |acc, (j, (w, v))| {
                            let x = if (pick >> (j % 2)) & 1 == 0 {
                                v[c].lo
                            } else {
                                v[c].hi
                            };
                            acc + rational_from_f64(w.lo, "w").unwrap()
                                * rational_from_f64(x, "x").unwrap()
                        },
                    );
                    assert!(
                        combined[c].contains(&exact),
                        "{:?} misses {exact}",
                        combined[c]
                    );
                    assert!(dot.contains(&exact), "{dot:?} misses {exact}");
                    checked += 1;
                }
            }
        }
        assert!(checked >= 40_000, "{checked}");
    }

    #[test]
    fn negative_lower_bounds_stay_negative() {
        // The class of bug NOTES.md describes: a negative lower bound rounded upward.
        let a = Interval::point(-1e-310);
        let s = a + Interval::point(-1e-310);
        assert!(s.lo <= -2e-310);
    }
}
