//! The sign-only exact form: integer numerators over one shared positive denominator.
//!
//! `p = (1/den) Σ num_i B_i`. Subdividing at ½ with de Casteljau and multiplying every
//! coefficient by `2^d` keeps the numerators integers and leaves every sign unchanged,
//! so no gcd is ever computed (NOTES.md, "Exact arithmetic"). The denominator is
//! tracked exactly, so values (witnesses) can still be recovered as rationals.

use super::poly::{coefficient_count, strides, Bernstein};
use super::{binomial, poly::map_lines, BernsteinError};
use crate::num::wide::I256;
use crate::num::{Rational, Sign};
use num_bigint::{BigInt, Sign as BigSign};
use num_integer::Integer;
use num_traits::{One, Zero};

/// A tensor Bernstein polynomial as integer numerators over a shared denominator.
#[derive(Clone, Debug, PartialEq)]
pub struct ScaledBernstein {
    degrees: Vec<usize>,
    num: Vec<BigInt>,
    den: BigInt,
}

/// Trial divisors of a denominator's odd part in [`ScaledBernstein::to_rational`].
const SMALL_FACTOR_LIMIT: u64 = 1000;

/// The odd positive `m` as a product of pairwise coprime moduli below `2⁶³`, each a product
/// of whole prime powers `pᵉ` (trial division by odd `p < SMALL_FACTOR_LIMIT`, in increasing
/// order, so each `p` found is prime), or `None` when a larger prime factor remains or one
/// prime power is too large.
fn coprime_moduli(m: &BigInt) -> Option<Vec<u64>> {
    const CAP: u64 = 1 << 63;
    let mut rest = m.clone();
    let mut moduli: Vec<u64> = Vec::new();
    let mut p = 3u64;
    while !rest.is_one() {
        if p >= SMALL_FACTOR_LIMIT || rest.is_zero() {
            return None;
        }
        let mut power = 1u64;
        while residue(&rest, p) == 0 {
            rest /= p;
            power = power.checked_mul(p).filter(|&x| x < CAP)?;
        }
        if power > 1 {
            match moduli.last_mut() {
                Some(last) if last.checked_mul(power).is_some_and(|x| x < CAP) => *last *= power,
                _ => moduli.push(power),
            }
        }
        p += 2;
    }
    Some(moduli)
}

/// `gcd(a, b)` of machine words (Euclid).
fn gcd_u64(mut a: u64, mut b: u64) -> u64 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// `|n| mod p` for `0 < p < 2⁶⁴`, limb by limb from the most significant.
fn residue(n: &BigInt, p: u64) -> u64 {
    n.iter_u64_digits().rev().fold(0u64, |r, digit| {
        (((u128::from(r) << 64) | u128::from(digit)) % u128::from(p)) as u64
    })
}

fn sign_of(b: &BigInt) -> Sign {
    match b.sign() {
        BigSign::Minus => Sign::Negative,
        BigSign::NoSign => Sign::Zero,
        BigSign::Plus => Sign::Positive,
    }
}

impl ScaledBernstein {
    /// Brings a rational polynomial to the common denominator (the lcm of its denominators).
    pub fn from_rational(p: &Bernstein<Rational>) -> Self {
        let mut den = BigInt::one();
        for c in p.coeffs() {
            den = den.lcm(c.denom());
        }
        let num = p
            .coeffs()
            .iter()
            .map(|c| c.numer() * (&den / c.denom()))
            .collect();
        ScaledBernstein {
            degrees: p.degrees().to_vec(),
            num,
            den,
        }
    }

    /// Integer numerators with denominator 1.
    pub fn from_integers(degrees: Vec<usize>, num: Vec<BigInt>) -> Result<Self, BernsteinError> {
        let expected = coefficient_count(&degrees);
        if num.len() != expected {
            return Err(BernsteinError::CoefficientCount {
                expected,
                found: num.len(),
            });
        }
        Ok(ScaledBernstein {
            degrees,
            num,
            den: BigInt::one(),
        })
    }

    /// Integer numerators over the positive denominator `den`.
    pub fn with_denominator(
        degrees: Vec<usize>,
        num: Vec<BigInt>,
        den: BigInt,
    ) -> Result<Self, BernsteinError> {
        let mut p = Self::from_integers(degrees, num)?;
        if den.sign() != BigSign::Plus {
            return Err(BernsteinError::BadParameter);
        }
        p.den = den;
        Ok(p)
    }

    /// The partial derivative along `axis` on the unit box: `d (b_{i+1} − b_i)` (Farin, eq. 4.9
    /// per axis), same denominator.
    pub fn derivative(&self, axis: usize) -> Result<Self, BernsteinError> {
        if axis >= self.degrees.len() {
            return Err(BernsteinError::Axis {
                axis,
                dim: self.degrees.len(),
            });
        }
        let d = self.degrees[axis];
        if d == 0 {
            let mut z = self.clone();
            z.num.iter_mut().for_each(|n| *n = BigInt::zero());
            return Ok(z);
        }
        let factor = BigInt::from(d);
        let (degrees, num) = self.lines_one_lower(axis, |line, out| {
            for i in 0..d {
                out[i] = &factor * (&line[i + 1] - &line[i]);
            }
        });
        Ok(ScaledBernstein {
            degrees,
            num,
            den: self.den.clone(),
        })
    }

    /// The exact product in integers. With `ã_i = C(m,i) a_i`, `b̃_j = C(n,j) b_j` (per axis
    /// products of binomials), the product's coefficient is `Σ_{i+j=k} ã_i b̃_j / C(m+n,k)`
    /// (NOTES: Bernstein product); multiplying by `L = Π_x lcm_k C(m_x+n_x, k)` keeps every
    /// numerator an integer: `num_k = (L / Π C(·,k)) Σ ã_i b̃_j`, `den = den_a den_b L`.
    pub fn product(&self, other: &Self) -> Result<Self, BernsteinError> {
        let n = self.degrees.len();
        if other.degrees.len() != n {
            return Err(BernsteinError::DimensionMismatch {
                expected: n,
                found: other.degrees.len(),
            });
        }
        let degrees: Vec<usize> = (0..n).map(|x| self.degrees[x] + other.degrees[x]).collect();
        let (wa, wb, wp) = (
            weights(&self.degrees),
            weights(&other.degrees),
            weights(&degrees),
        );
        let binomial_scaled = |p: &Self, w: &Weights| -> Vec<BigInt> {
            p.num.iter().zip(&w.binomial).map(|(a, w)| a * w).collect()
        };
        let (at, bt) = (binomial_scaled(self, &wa), binomial_scaled(other, &wb));
        let so = strides(&degrees);
        // Flat offset of each multi-index of `self` / `other` in the product's layout.
        let off_a = offsets(&self.degrees, &so);
        let off_b = offsets(&other.degrees, &so);
        let mut out = convolve_i128(&at, &off_a, &bt, &off_b, coefficient_count(&degrees))
            .unwrap_or_else(|| {
                let mut out = vec![BigInt::zero(); coefficient_count(&degrees)];
                for (a, oa) in at.iter().zip(&off_a) {
                    if a.is_zero() {
                        continue;
                    }
                    for (b, ob) in bt.iter().zip(&off_b) {
                        if !b.is_zero() {
                            out[oa + ob] += a * b;
                        }
                    }
                }
                out
            });
        // Coefficient k gets Π_x L_x / C(N_x, k_x), L_x = lcm_k C(N_x, k).
        for (v, w) in out.iter_mut().zip(&wp.to_common) {
            if !v.is_zero() && !w.is_one() {
                *v *= w;
            }
        }
        let big_l = wp.common.clone();
        Ok(ScaledBernstein {
            degrees,
            num: out,
            den: &self.den * &other.den * big_l,
        })
    }

    /// `self + sign · other` exactly (same degrees); equal denominators add numerators.
    fn combine(&self, other: &Self, negate: bool) -> Result<Self, BernsteinError> {
        if self.degrees != other.degrees {
            return Err(BernsteinError::DegreeMismatch);
        }
        let (num, den) = if self.den == other.den {
            let num = self
                .num
                .iter()
                .zip(&other.num)
                .map(|(a, b)| if negate { a - b } else { a + b })
                .collect();
            (num, self.den.clone())
        } else {
            let num = self
                .num
                .iter()
                .zip(&other.num)
                .map(|(a, b)| {
                    let (x, y) = (a * &other.den, b * &self.den);
                    if negate {
                        x - y
                    } else {
                        x + y
                    }
                })
                .collect();
            (num, &self.den * &other.den)
        };
        Ok(ScaledBernstein {
            degrees: self.degrees.clone(),
            num,
            den,
        })
    }

    /// `self + other` exactly.
    pub fn add(&self, other: &Self) -> Result<Self, BernsteinError> {
        self.combine(other, false)
    }

    /// `self − other` exactly.
    pub fn sub(&self, other: &Self) -> Result<Self, BernsteinError> {
        self.combine(other, true)
    }

    /// Whether the polynomial's degree along `axis` can drop: the top forward difference
    /// `Δ^d b = Σ_k (−1)^{d−k} C(d, k) b_k` (`d ≥ 1` the degree there) vanishes on every line
    /// along `axis`, decided on the integer numerators. `false` at degree 0 or a bad axis.
    pub fn top_difference_vanishes(&self, axis: usize) -> bool {
        let Some(&d) = self.degrees.get(axis) else {
            return false;
        };
        if d == 0 {
            return false;
        }
        let weights: Vec<BigInt> = (0..=d)
            .map(|k| {
                let w = binomial(d, k);
                if (d - k).is_multiple_of(2) {
                    w
                } else {
                    -w
                }
            })
            .collect();
        let len = d + 1;
        let inner: usize = self.degrees[..axis].iter().map(|x| x + 1).product();
        self.num.chunks_exact(len * inner).all(|block| {
            (0..inner).all(|i| {
                (0..len)
                    .fold(BigInt::zero(), |acc, k| {
                        acc + &weights[k] * &block[i + inner * k]
                    })
                    .is_zero()
            })
        })
    }

    /// The same polynomial at its exact degrees (as [`Bernstein::at_exact_degrees`]), in
    /// integers: per axis, while the top difference vanishes, degree elevation is inverted,
    /// `c₀ = b₀`, `cᵢ = (d·bᵢ − i·cᵢ₋₁)/(d − i)`, with the numerators and the denominator
    /// first scaled by `(d − 1)!`: each `cᵢ` has a denominator dividing
    /// `(d − 1)⋯(d − i)`, so the scaled ones are integers and every division is exact.
    pub fn at_exact_degrees(&self) -> ScaledBernstein {
        let mut p = self.clone();
        for axis in 0..p.degrees.len() {
            while p.degrees[axis] > 0 && p.top_difference_vanishes(axis) {
                p = p.reduced(axis);
            }
        }
        p
    }

    /// One degree less along `axis` (`d ≥ 1` there), exact when the top difference vanishes
    /// ([`ScaledBernstein::at_exact_degrees`]).
    fn reduced(&self, axis: usize) -> ScaledBernstein {
        let d = self.degrees[axis];
        let scale: BigInt = (1..d).fold(BigInt::one(), |acc, j| acc * j);
        let (degrees, num) = self.lines_one_lower(axis, |line, out| {
            out[0] = &line[0] * &scale;
            for i in 1..d {
                let n = &line[i] * &scale * BigInt::from(d) - &out[i - 1] * BigInt::from(i);
                out[i] = n / BigInt::from(d - i);
            }
        });
        ScaledBernstein {
            degrees,
            num,
            den: &self.den * &scale,
        }
    }

    /// Every line along `axis` (degree `d ≥ 1` there) mapped by `f` to `d` numerators: the
    /// degrees and numerators of a polynomial one degree lower along `axis`.
    fn lines_one_lower(
        &self,
        axis: usize,
        f: impl FnMut(&[BigInt], &mut [BigInt]),
    ) -> (Vec<usize>, Vec<BigInt>) {
        let d = self.degrees[axis];
        let num = map_lines(&self.degrees, &self.num, axis, d, &BigInt::zero(), f);
        let mut degrees = self.degrees.clone();
        degrees[axis] = d - 1;
        (degrees, num)
    }

    /// The same polynomial with rational coefficients, each in lowest terms. The shared
    /// denominator is factored once into a power of two and powers of small odd primes
    /// (trial division below 1000; Bernstein forms' denominators are products of binomial
    /// coefficients and of the inputs' denominators): each coefficient is then reduced by a
    /// shift and by machine-word gcds with those prime powers, not by a gcd of big integers.
    /// A denominator with a larger prime factor takes a gcd per coefficient.
    pub fn to_rational(&self) -> Bernstein<Rational> {
        let twos = self.den.trailing_zeros().unwrap_or(0);
        let moduli = coprime_moduli(&(&self.den >> twos));
        let coeffs = self
            .num
            .iter()
            .map(|n| {
                let Some(moduli) = &moduli else {
                    return Rational::new(n.clone(), self.den.clone());
                };
                let Some(zeros) = n.trailing_zeros() else {
                    return Rational::from_integer(BigInt::zero());
                };
                // The odd part of the denominator is the product of the pairwise coprime
                // moduli, so dividing out the common twos and each `gcd(num mod m, m)`
                // leaves no common factor: the ratio is in lowest terms.
                let k = zeros.min(twos);
                let (mut num, mut den) = (n >> k, &self.den >> k);
                for &m in moduli {
                    let g = gcd_u64(residue(&num, m), m);
                    if g > 1 {
                        num /= g;
                        den /= g;
                    }
                }
                Rational::new_raw(num, den)
            })
            .collect();
        Bernstein::new(self.degrees.clone(), coeffs).expect("counts match by construction")
    }

    /// Degree per axis.
    pub fn degrees(&self) -> &[usize] {
        &self.degrees
    }

    /// The integer numerators, axis 0 fastest.
    pub fn numerators(&self) -> &[BigInt] {
        &self.num
    }

    /// The shared positive denominator.
    pub fn denominator(&self) -> &BigInt {
        &self.den
    }

    /// The exact value of coefficient `k`.
    pub fn coeff_value(&self, k: usize) -> Rational {
        Rational::new(self.num[k].clone(), self.den.clone())
    }

    /// The exact sign of coefficient `k` (the denominator is positive).
    pub fn coeff_sign(&self, k: usize) -> Sign {
        sign_of(&self.num[k])
    }

    /// Flat index of the vertex coefficient at `corner` (bit a set: `t_a = 1`).
    pub fn vertex_index(&self, corner: usize) -> usize {
        let s = strides(&self.degrees);
        self.degrees
            .iter()
            .enumerate()
            .filter(|(a, _)| corner >> a & 1 == 1)
            .map(|(a, &d)| d * s[a])
            .sum()
    }

    /// True when every numerator is positive (so `p > 0` on the box).
    pub fn all_positive(&self) -> bool {
        self.num.iter().all(|n| n.sign() == BigSign::Plus)
    }

    /// Index of the smallest coefficient.
    pub fn argmin(&self) -> usize {
        let mut best = 0;
        for (k, n) in self.num.iter().enumerate() {
            if n < &self.num[best] {
                best = k;
            }
        }
        best
    }

    /// de Casteljau at ½ along `axis` in integers: returns the halves on `[0,½]` and `[½,1]`,
    /// each with denominator `den · 2^d`.
    ///
    /// Dedicated route: in-place additions (`a += &b` reuses the limb buffer) and shifts, one
    /// pass over the lines, no multiplication and no gcd.
    pub fn split_half(&self, axis: usize) -> Result<(Self, Self), BernsteinError> {
        if axis >= self.degrees.len() {
            return Err(BernsteinError::Axis {
                axis,
                dim: self.degrees.len(),
            });
        }
        let d = self.degrees[axis];
        let len = d + 1;
        let stride = strides(&self.degrees)[axis];
        let total = self.num.len();
        let block = stride * len;
        let mut left = self.num.clone();
        let mut right = self.num.clone();
        let mut work: Vec<BigInt> = vec![BigInt::zero(); len];
        for base in (0..total).step_by(block) {
            for off in 0..stride {
                let at = |i: usize| base + off + i * stride;
                for (i, w) in work.iter_mut().enumerate() {
                    w.clone_from(&self.num[at(i)]);
                }
                // Level r: w_i ← w_i + w_{i+1} (= 2^r × true de Casteljau value).
                // left[r] = w_0 and right[d−r] = w_{d−r} at level r, both scaled by 2^(d−r)
                // to the common denominator den·2^d.
                left[at(0)] <<= d;
                right[at(d)] <<= d;
                for r in 1..len {
                    for i in 0..len - r {
                        let (lo, hi) = work.split_at_mut(i + 1);
                        lo[i] += &hi[0];
                    }
                    left[at(r)].clone_from(&work[0]);
                    left[at(r)] <<= d - r;
                    right[at(d - r)].clone_from(&work[d - r]);
                    right[at(d - r)] <<= d - r;
                }
            }
        }
        let den = &self.den << d;
        Ok((
            ScaledBernstein {
                degrees: self.degrees.clone(),
                num: left,
                den: den.clone(),
            },
            ScaledBernstein {
                degrees: self.degrees.clone(),
                num: right,
                den,
            },
        ))
    }

    /// de Casteljau at `t = p/q` (`0 < p < q`) along `axis` in integers: every level computes
    /// `(q−p)·b_i + p·b_{i+1}` and the halves are rescaled by powers of `q`.
    pub fn split(
        &self,
        axis: usize,
        p: &BigInt,
        q: &BigInt,
    ) -> Result<(Self, Self), BernsteinError> {
        if !(p.sign() == BigSign::Plus && p < q) {
            return Err(BernsteinError::BadParameter);
        }
        self.split_generic(axis, p, q)
    }

    /// de Casteljau at any `t = p/q` (`q > 0`) along `axis`, as [`split`](Self::split): the
    /// steps are polynomial identities, so at `t > 1` the first part is the polynomial on
    /// `[0, t]` and at `t < 0` the second is the one on `[t, 1]` (extrapolation, exact).
    pub fn split_anywhere(
        &self,
        axis: usize,
        p: &BigInt,
        q: &BigInt,
    ) -> Result<(Self, Self), BernsteinError> {
        if q.sign() != BigSign::Plus {
            return Err(BernsteinError::BadParameter);
        }
        self.split_generic(axis, p, q)
    }

    fn split_generic(
        &self,
        axis: usize,
        p: &BigInt,
        q: &BigInt,
    ) -> Result<(Self, Self), BernsteinError> {
        if axis >= self.degrees.len() {
            return Err(BernsteinError::Axis {
                axis,
                dim: self.degrees.len(),
            });
        }
        let d = self.degrees[axis];
        let len = d + 1;
        let half = p == &BigInt::one() && q == &BigInt::from(2);
        let qmp = q - p;
        // q^k for k = 0..=d
        let mut qpow = vec![BigInt::one()];
        for k in 1..=d {
            let next = &qpow[k - 1] * q;
            qpow.push(next);
        }
        let mut rights: Vec<Vec<BigInt>> = Vec::new();
        let left = map_lines(
            &self.degrees,
            &self.num,
            axis,
            len,
            &BigInt::zero(),
            |line, out| {
                // w_i^(r) = q^r · (true level-r value) · den
                let mut work = line.to_vec();
                let mut right = vec![BigInt::zero(); len];
                out[0] = work[0].clone();
                right[d] = work[d].clone();
                for r in 1..len {
                    for i in 0..len - r {
                        work[i] = if half {
                            &work[i] + &work[i + 1]
                        } else {
                            &qmp * &work[i] + p * &work[i + 1]
                        };
                    }
                    out[r] = work[0].clone();
                    right[d - r] = work[d - r].clone();
                }
                // Scale to the common denominator q^d.
                for (r, o) in out.iter_mut().enumerate() {
                    *o = scale_pow(o, half, &qpow, d - r);
                }
                for (j, v) in right.iter_mut().enumerate() {
                    // right[j] is at level d − j.
                    *v = scale_pow(v, half, &qpow, j);
                }
                rights.push(right);
            },
        );
        let mut it = rights.into_iter();
        let right = map_lines(
            &self.degrees,
            &self.num,
            axis,
            len,
            &BigInt::zero(),
            |_, out| {
                out.clone_from_slice(&it.next().expect("one right line per left line"));
            },
        );
        let den = &self.den * &qpow[d];
        Ok((
            ScaledBernstein {
                degrees: self.degrees.clone(),
                num: left,
                den: den.clone(),
            },
            ScaledBernstein {
                degrees: self.degrees.clone(),
                num: right,
                den,
            },
        ))
    }

    /// Divides numerators and denominator by their common power of two (keeps sizes down;
    /// optional, signs are unaffected).
    pub fn normalise_twos(&mut self) {
        let mut tz = self.den.trailing_zeros().unwrap_or(0);
        for n in &self.num {
            if let Some(z) = n.trailing_zeros() {
                tz = tz.min(z);
            }
        }
        if tz > 0 {
            for n in &mut self.num {
                *n = &*n >> tz as usize;
            }
            self.den = &self.den >> tz as usize;
        }
    }
}

fn scale_pow(v: &BigInt, half: bool, qpow: &[BigInt], k: usize) -> BigInt {
    if k == 0 {
        v.clone()
    } else if half {
        v << k
    } else {
        v * &qpow[k]
    }
}

/// The integer weights of a Bernstein product's operands and result, per degree vector.
struct Weights {
    /// `Π_x C(d_x, i_x)` for every multi-index (axis 0 fastest).
    binomial: Vec<BigInt>,
    /// `Π_x L_x / C(d_x, i_x)` with `L_x = lcm_k C(d_x, k)`: brings `1 / Π C(d_x, i_x)` to the
    /// common denominator [`common`](Self::common).
    to_common: Vec<BigInt>,
    /// `Π_x L_x`.
    common: BigInt,
}

/// The [`Weights`] of `degrees`, memoised per thread (a program multiplies a handful of
/// degree vectors; the memo is emptied past 64 of them).
fn weights(degrees: &[usize]) -> std::rc::Rc<Weights> {
    use std::cell::RefCell;
    use std::collections::HashMap;
    use std::rc::Rc;
    thread_local! {
        static MEMO: RefCell<HashMap<Vec<usize>, Rc<Weights>>> = RefCell::new(HashMap::new());
    }
    MEMO.with(|memo| {
        if let Some(w) = memo.borrow().get(degrees) {
            return w.clone();
        }
        let rows: Vec<Vec<BigInt>> = degrees
            .iter()
            .map(|&d| (0..=d).map(|k| binomial(d, k)).collect())
            .collect();
        let lcms: Vec<BigInt> = rows
            .iter()
            .map(|row| row.iter().fold(BigInt::one(), |acc, c| acc.lcm(c)))
            .collect();
        let per_index = |f: &dyn Fn(usize, usize) -> BigInt| -> Vec<BigInt> {
            (0..coefficient_count(degrees))
                .map(|flat| {
                    let mut rem = flat;
                    let mut w = BigInt::one();
                    for (x, &d) in degrees.iter().enumerate() {
                        w *= f(x, rem % (d + 1));
                        rem /= d + 1;
                    }
                    w
                })
                .collect()
        };
        let w = Rc::new(Weights {
            binomial: per_index(&|x, i| rows[x][i].clone()),
            to_common: per_index(&|x, i| &lcms[x] / &rows[x][i]),
            common: lcms.iter().product(),
        });
        let mut memo = memo.borrow_mut();
        if memo.len() >= 64 {
            memo.clear();
        }
        memo.insert(degrees.to_vec(), w.clone());
        w
    })
}

/// For every multi-index of `degrees`, its flat position under the strides `so`.
fn offsets(degrees: &[usize], so: &[usize]) -> Vec<usize> {
    (0..coefficient_count(degrees))
        .map(|flat| {
            let mut rem = flat;
            let mut at = 0;
            for (x, &d) in degrees.iter().enumerate() {
                at += (rem % (d + 1)) * so[x];
                rem /= d + 1;
            }
            at
        })
        .collect()
}

/// The convolution when both operands fit `i64`: every product is exact in `i128` and the
/// sums are overflow-checked; `None` when an operand is wider or a sum overflows.
fn convolve_i64(
    a: &[BigInt],
    off_a: &[usize],
    b: &[BigInt],
    off_b: &[usize],
    len: usize,
) -> Option<Vec<BigInt>> {
    let narrow = |v: &[BigInt]| -> Option<Vec<i64>> {
        v.iter().map(num_traits::ToPrimitive::to_i64).collect()
    };
    let (a, b) = (narrow(a)?, narrow(b)?);
    let mut out = vec![0i128; len];
    for (&x, &oa) in a.iter().zip(off_a) {
        if x == 0 {
            continue;
        }
        for (&y, &ob) in b.iter().zip(off_b) {
            let slot = &mut out[oa + ob];
            *slot = slot.checked_add(x as i128 * y as i128)?;
        }
    }
    Some(out.into_iter().map(BigInt::from).collect())
}

/// The convolution `out[oa + ob] += a·b` in 256-bit arithmetic ([`I256`]): one operand must
/// fit `i128`, the other is split as `h·2⁶⁴ + l` with `h` in `i128`; products are exact and
/// sums overflow-checked. `None` when the operands are too wide or a sum overflows (the caller
/// then uses `BigInt`). Exact either way.
fn convolve_i128(
    a: &[BigInt],
    off_a: &[usize],
    b: &[BigInt],
    off_b: &[usize],
    len: usize,
) -> Option<Vec<BigInt>> {
    if let Some(out) = convolve_i64(a, off_a, b, off_b, len) {
        return Some(out);
    }
    let narrow = |v: &[BigInt]| -> Option<Vec<i128>> {
        v.iter().map(num_traits::ToPrimitive::to_i128).collect()
    };
    let split = |v: &[BigInt]| -> Option<Vec<(i128, u64)>> {
        v.iter()
            .map(|x| {
                let hi = num_traits::ToPrimitive::to_i128(&(x >> 64u32))?;
                let lo = num_traits::ToPrimitive::to_u64(&(x - (BigInt::from(hi) << 64u32)))?;
                Some((hi, lo))
            })
            .collect()
    };
    // The narrow operand is `y`; the other one is split.
    let (wide, off_w, y, off_y) = match (narrow(b), narrow(a)) {
        (Some(y), _) => (a, off_a, y, off_b),
        (None, Some(y)) => (b, off_b, y, off_a),
        (None, None) => return None,
    };
    let wide = split(wide)?;
    let mut out = vec![I256::ZERO; len];
    for (&(h, l), &ow) in wide.iter().zip(off_w) {
        if h == 0 && l == 0 {
            continue;
        }
        for (&y, &oy) in y.iter().zip(off_y) {
            let slot = &mut out[ow + oy];
            *slot = slot.checked_add(I256::split_product(h, l, y)?)?;
        }
    }
    Some(out.into_iter().map(I256::to_bigint).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `to_rational` gives each coefficient in lowest terms, by shifts and small moduli (or
    /// a gcd past them): the same rationals (the same numerator and denominator) as
    /// `Rational::new`, on 300 polynomials with dyadic denominators, small odd factors,
    /// prime powers spanning several machine words, a factor past the trial divisors, and
    /// zero, odd and even numerators.
    #[test]
    fn to_rational_is_in_lowest_terms() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || crate::num::xorshift(&mut seed);
        let mut checked = 0;
        for case in 0..300 {
            let den = match case % 5 {
                0 => BigInt::from(1u64) << (next() % 130),
                1 => BigInt::from(3u64 * (1 + next() % 1000)) << (next() % 70),
                // Powers of small factors past one machine word, and a factor past the
                // trial divisors (the gcd path).
                2 => (BigInt::from(3u64.pow(30) * 5) * BigInt::from(7u64.pow(20))) << (next() % 9),
                3 => BigInt::from(1009u64 * (1 + next() % 500)) << (next() % 9),
                _ => BigInt::from(1u64),
            };
            let num: Vec<BigInt> = (0..1 + next() % 9)
                .map(|_| {
                    let shift = next() % 140;
                    let a = BigInt::from((next() % 2001) as i64 - 1000);
                    let power = BigInt::from(3u64.pow((next() % 30) as u32));
                    (a * power) << shift
                })
                .collect();
            let p = ScaledBernstein {
                degrees: vec![num.len() - 1],
                num: num.clone(),
                den: den.clone(),
            };
            for (got, n) in p.to_rational().coeffs().iter().zip(&num) {
                let want = Rational::new(n.clone(), den.clone());
                assert_eq!(got.numer(), want.numer());
                assert_eq!(got.denom(), want.denom());
                checked += 1;
            }
        }
        assert!(checked > 1000, "{checked}");
    }

    /// Integer degree reduction agrees with the rational one on polynomials elevated along
    /// random axes (so that they reduce) and on ones that do not reduce.
    #[test]
    fn exact_degrees_in_integers_match_the_rational_reduction() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let mut reduced = 0;
        for case in 0..200 {
            let dims = 1 + (next() % 3) as usize;
            let degrees: Vec<usize> = (0..dims).map(|_| (next() % 4) as usize).collect();
            let n = coefficient_count(&degrees);
            let coeffs: Vec<Rational> = (0..n)
                .map(|_| {
                    let a = (next() % 41) as i64 - 20;
                    let b = 1 + (next() % 9) as i64;
                    Rational::new(a.into(), b.into())
                })
                .collect();
            let mut p = Bernstein::new(degrees, coeffs).unwrap();
            if case % 3 != 0 {
                for _ in 0..1 + next() % 3 {
                    let axis = (next() % dims as u64) as usize;
                    p = p.elevate(axis, 1 + (next() % 3) as usize).unwrap();
                }
            }
            let s = ScaledBernstein::from_rational(&p);
            let want = p.at_exact_degrees();
            let got = s.at_exact_degrees();
            if got.degrees() != p.degrees() {
                reduced += 1;
            }
            assert_eq!(got.to_rational(), want, "case {case}");
        }
        println!(
            "200 polynomials, {reduced} reduced in integers, all equal to the rational reduction"
        );
        assert!(reduced > 100);
    }
}
