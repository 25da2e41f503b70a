//! Exact rationals and lossless conversions.

use super::NumError;
use num_bigint::{BigInt, Sign as BigSign};
use num_integer::Integer;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};

/// The exact scalar of every reference path.
pub type Rational = BigRational;

/// Converts a finite `f64` to the rational it denotes, exactly.
///
/// Every finite `f64` is `m · 2^e` with an integer `m` (IEEE 754 binary64), so
/// the conversion is lossless. NaN and infinities are a typed error naming `what`.
pub fn rational_from_f64(x: f64, what: &str) -> Result<Rational, NumError> {
    if !x.is_finite() {
        return Err(NumError::NonFinite {
            what: what.to_string(),
            value: x,
        });
    }
    if x == 0.0 {
        return Ok(Rational::zero());
    }
    let (m, e) = f64_dyadic(x);
    Ok(dyadic_rational(BigInt::from(m), e))
}

/// A finite `x` as `m · 2^e` exactly, with `m` odd (`(0, 0)` for zero). Not meaningful for
/// infinities and NaN.
pub(crate) fn f64_dyadic(x: f64) -> (i64, i64) {
    if x == 0.0 {
        return (0, 0);
    }
    let bits = x.to_bits();
    let negative = bits >> 63 == 1;
    let exp_bits = ((bits >> 52) & 0x7ff) as i64;
    let frac = bits & ((1u64 << 52) - 1);
    // Subnormals have exponent field 0 and no hidden bit.
    let (mant, exp) = if exp_bits == 0 {
        (frac, -1074)
    } else {
        (frac | (1u64 << 52), exp_bits - 1075)
    };
    let tz = mant.trailing_zeros() as i64;
    let m = (mant >> tz) as i64;
    (if negative { -m } else { m }, exp + tz)
}

/// Finite `xs` as integers over one shared power of two: `xs[i] = ints[i] · 2^e` exactly,
/// `e` the smallest exponent among the non-zero values (0 when all are zero), so that sign
/// and polynomial work on them needs no gcd.
pub(crate) fn f64s_over_shared_power(xs: &[f64]) -> (Vec<BigInt>, i64) {
    let parts: Vec<(i64, i64)> = xs.iter().map(|&x| f64_dyadic(x)).collect();
    let e = parts
        .iter()
        .filter(|(m, _)| *m != 0)
        .map(|&(_, k)| k)
        .min()
        .unwrap_or(0);
    let ints = parts
        .iter()
        .map(|&(m, k)| {
            if m == 0 {
                BigInt::zero()
            } else {
                BigInt::from(m) << ((k - e) as usize)
            }
        })
        .collect();
    (ints, e)
}

/// `n / d` in lowest terms (`d ≠ 0`). A power-of-two denominator needs no gcd; operands
/// that fit in `i128` (the common case: short coefficients, knots and split points) are
/// reduced with a machine-word binary gcd instead of `BigUint`'s; others through
/// `num-rational`.
pub(crate) fn reduced(n: BigInt, d: BigInt) -> Rational {
    if let Some(k) = power_of_two(&d).filter(|_| d.is_positive()) {
        return dyadic_rational(n, -(k as i64));
    }
    match (n.to_i128(), d.to_i128()) {
        (Some(a), Some(b)) if a != i128::MIN && b != i128::MIN => small_ratio(a, b),
        _ => Rational::new(n, d),
    }
}

/// `a / b` in lowest terms with a positive denominator (`b ≠ 0`, neither is `i128::MIN`).
fn small_ratio(a: i128, b: i128) -> Rational {
    let g = gcd_u128(a.unsigned_abs(), b.unsigned_abs()) as i128;
    let (a, b) = if b < 0 {
        (-a / g, -b / g)
    } else {
        (a / g, b / g)
    };
    Rational::new_raw(BigInt::from(a), BigInt::from(b))
}

/// Stein's binary gcd on machine words (`gcd(0, b) = b`), in `u64` when both fit.
fn gcd_u128(mut a: u128, mut b: u128) -> u128 {
    if a == 0 || b == 0 {
        return a | b;
    }
    let shift = (a | b).trailing_zeros();
    a >>= a.trailing_zeros();
    if let (Ok(mut x), Ok(mut y)) = (u64::try_from(a), u64::try_from(b)) {
        while y != 0 {
            y >>= y.trailing_zeros();
            if x > y {
                std::mem::swap(&mut x, &mut y);
            }
            y -= x;
        }
        return u128::from(x) << shift;
    }
    while b != 0 {
        b >>= b.trailing_zeros();
        if a > b {
            std::mem::swap(&mut a, &mut b);
        }
        b -= a;
    }
    a << shift
}

/// The numerator and denominator as `i64`, when both fit.
fn small_parts(r: &Rational) -> Option<(i64, i64)> {
    Some((r.numer().to_i64()?, r.denom().to_i64()?))
}

/// `a + b` (`minus`: `a − b`) in `i128` when all four parts fit in `i64` (`None` otherwise):
/// products of two `i64` and their sum fit, and one machine gcd reduces the result.
pub(crate) fn small_add(a: &Rational, b: &Rational, minus: bool) -> Option<Rational> {
    let ((p, q), (r, s)) = (small_parts(a)?, small_parts(b)?);
    let (x, y) = (i128::from(p) * i128::from(s), i128::from(r) * i128::from(q));
    let n = if minus { x - y } else { x + y };
    Some(small_ratio(n, i128::from(q) * i128::from(s)))
}

/// `a · b` (`inverse`: `a / b`, `b ≠ 0`) in `i128` when all four parts fit in `i64`.
pub(crate) fn small_mul(a: &Rational, b: &Rational, inverse: bool) -> Option<Rational> {
    let ((p, q), (r, s)) = (small_parts(a)?, small_parts(b)?);
    let (r, s) = if inverse { (s, r) } else { (r, s) };
    Some(small_ratio(
        i128::from(p) * i128::from(r),
        i128::from(q) * i128::from(s),
    ))
}

/// `2^k` when `d` is that power of two.
pub(crate) fn power_of_two(d: &BigInt) -> Option<u64> {
    let k = d.trailing_zeros()?;
    (d.bits() == k + 1).then_some(k)
}

/// De Casteljau subdivision of a line of dyadic rationals at a dyadic `t = a / 2^k`, in
/// integers and without a gcd, or `None` when some value is not dyadic. Every value is brought
/// over the largest power of two `2^E`; level `r` of the recurrence holds `2^{k·r}` times
/// `(1 − t) w_i + t w_{i+1}` as the integer `(2^k − a) w_i + a w_{i+1}`, and each output is
/// read off over `2^{E + k·r}`. Same values as the generic recurrence, exactly.
pub(crate) fn dyadic_split_line(
    line: &[Rational],
    t: &Rational,
) -> Option<(Vec<Rational>, Vec<Rational>)> {
    let k = power_of_two(t.denom())?;
    let e: Vec<u64> = line
        .iter()
        .map(|v| power_of_two(v.denom()))
        .collect::<Option<_>>()?;
    let top = *e.iter().max()?;
    let a = t.numer();
    let b = (BigInt::one() << k) - a;
    let mut w: Vec<BigInt> = line
        .iter()
        .zip(&e)
        .map(|(v, &ei)| v.numer() << (top - ei))
        .collect();
    let n = line.len();
    let out = |w: &BigInt, r: usize| dyadic_rational(w.clone(), -((top + k * r as u64) as i64));
    let mut left = Vec::with_capacity(n);
    let mut right = vec![Rational::zero(); n];
    left.push(out(&w[0], 0));
    right[n - 1] = out(&w[n - 1], 0);
    for r in 1..n {
        for i in 0..n - r {
            w[i] = &b * &w[i] + a * &w[i + 1];
        }
        left.push(out(&w[0], r));
        right[n - 1 - r] = out(&w[n - 1 - r], r);
    }
    Some((left, right))
}

/// The value at `t` of a line of Bernstein coefficients (the last value of the left piece of
/// [`common_split_line`]): the same integer recurrence, one gcd in all.
pub(crate) fn common_eval_line(line: &[Rational], t: &Rational) -> Rational {
    let (w, scale) = integer_levels(line, t, |_, _, _| {});
    reduced(w, scale)
}

/// Runs the integer de Casteljau recurrence of [`common_split_line`], calling
/// `each(r, w, scale)` on the integer values of level `r` over their denominator `scale`;
/// returns the last level's single value and its denominator.
fn integer_levels(
    line: &[Rational],
    t: &Rational,
    mut each: impl FnMut(usize, &[BigInt], &BigInt),
) -> (BigInt, BigInt) {
    let n = line.len();
    // Powers of two (every dyadic value) share the largest without a gcd.
    let twos: Option<u64> = line
        .iter()
        .map(|v| power_of_two(v.denom()))
        .try_fold(0, |m, k| k.map(|k| m.max(k)));
    let d = match twos {
        Some(k) => BigInt::one() << k,
        None => {
            let mut d = line[0].denom().clone();
            for v in &line[1..] {
                if v.denom() != &d {
                    d = d.lcm(v.denom());
                }
            }
            d
        }
    };
    let (a, b) = (t.numer(), t.denom());
    let c = b - a;
    let mut w: Vec<BigInt> = line
        .iter()
        .map(|v| {
            if v.denom() == &d {
                v.numer().clone()
            } else {
                v.numer() * (&d / v.denom())
            }
        })
        .collect();
    let mut scale = d;
    each(0, &w, &scale);
    for r in 1..n {
        for i in 0..n - r {
            w[i] = &c * &w[i] + a * &w[i + 1];
        }
        scale *= b;
        each(r, &w[..n - r], &scale);
    }
    (w.swap_remove(0), scale)
}

/// De Casteljau subdivision of a line of rationals at any rational `t = a/b`, in integers:
/// the values over their common denominator `D`, level `r` of the recurrence holding
/// `b^r` times its values as the integers `(b − a) w_i + a w_{i+1}`; each output is reduced
/// once, over `D·b^r`. Same values as the generic recurrence, with one gcd per output instead
/// of three per step.
pub(crate) fn common_split_line(line: &[Rational], t: &Rational) -> (Vec<Rational>, Vec<Rational>) {
    let n = line.len();
    let mut left = Vec::with_capacity(n);
    let mut right = vec![Rational::zero(); n];
    integer_levels(line, t, |r, w, scale| {
        left.push(reduced(w[0].clone(), scale.clone()));
        right[n - 1 - r] = reduced(w[n - 1 - r].clone(), scale.clone());
    });
    (left, right)
}

/// `Σ_j w_j v_j` in integers: the products' numerators summed over the running product of
/// the distinct denominators met (equal denominators, the common case, share one), reduced
/// once at the end. Same value as the term-by-term sum, with one gcd instead of two per term.
pub(crate) fn common_dot<'v>(
    weights: &[Rational],
    values: impl IntoIterator<Item = &'v Rational>,
) -> Rational {
    let mut num = BigInt::zero();
    let mut den = BigInt::one();
    for (w, v) in weights.iter().zip(values) {
        if w.is_zero() || v.is_zero() {
            continue;
        }
        let n = w.numer() * v.numer();
        let d = w.denom() * v.denom();
        if d == den {
            num += n;
        } else {
            num = num * &d + n * &den;
            den *= d;
        }
    }
    reduced(num, den)
}

/// `a ± b` when both are dyadic (`None` otherwise): over the larger power of two, then the
/// powers of two are taken out of the numerator, so no gcd is needed.
pub(crate) fn dyadic_add(a: &Rational, b: &Rational, minus: bool) -> Option<Rational> {
    let (ka, kb) = (power_of_two(a.denom())?, power_of_two(b.denom())?);
    let k = ka.max(kb);
    let (na, nb) = (a.numer() << (k - ka), b.numer() << (k - kb));
    let n = if minus { na - nb } else { na + nb };
    Some(dyadic_rational(n, -(k as i64)))
}

/// `a · b` when both are dyadic (`None` otherwise): odd numerators (of lowest terms) multiply
/// to an odd one, so the product over the product of the powers of two is in lowest terms.
pub(crate) fn dyadic_mul(a: &Rational, b: &Rational) -> Option<Rational> {
    let (ka, kb) = (power_of_two(a.denom())?, power_of_two(b.denom())?);
    let n = a.numer() * b.numer();
    if n.is_zero() {
        return Some(Rational::zero());
    }
    // A numerator may be even only over the denominator 1 (an integer): normalise then.
    if ka == 0 || kb == 0 {
        return Some(dyadic_rational(n, -((ka + kb) as i64)));
    }
    Some(Rational::new_raw(n, BigInt::one() << ((ka + kb) as usize)))
}

/// `m · 2^e` as a rational, without a gcd: the powers of two are taken out of `m`, and an odd
/// numerator over a power of two is in lowest terms.
pub(crate) fn dyadic_rational(m: BigInt, e: i64) -> Rational {
    let Some(tz) = m.trailing_zeros() else {
        return Rational::zero();
    };
    let (m, e) = (m >> tz, e + tz as i64);
    if e >= 0 {
        Rational::from_integer(m << (e as usize))
    } else {
        Rational::new_raw(m, BigInt::one() << ((-e) as usize))
    }
}

/// Rounds a rational to the nearest `f64` (ties to even); overflows go to ±infinity.
///
/// Correctly rounded: the quotient is computed with 2 guard bits beyond the
/// 53-bit significand and a sticky bit from the remainder.
pub fn rational_to_f64(r: &Rational) -> f64 {
    if r.is_zero() {
        return 0.0;
    }
    if let Some(x) = exact_f64(r) {
        return x;
    }
    ratio_to_f64(r.numer(), r.denom())
}

/// `n / d` (`d ≠ 0`, not necessarily in lowest terms) rounded to the nearest `f64` (ties to
/// even), as [`rational_to_f64`] without a gcd: the rounding reads only the quotient's
/// leading bits and whether a remainder is left, which do not depend on common factors.
pub(crate) fn ratio_to_f64(n: &BigInt, d: &BigInt) -> f64 {
    if n.is_zero() {
        return 0.0;
    }
    let negative = n.is_negative() != d.is_negative();
    let n = n.abs();
    let d = d.abs();
    // Choose a shift s so that q = floor(n·2^s / d) has exactly 55 bits.
    let nb = n.bits() as i64;
    let db = d.bits() as i64;
    let mut s = 55 - (nb - db);
    let (mut q, mut rem) = shifted_div(&n, &d, s);
    while q.bits() > 55 {
        s -= 1;
        let qr = shifted_div(&n, &d, s);
        q = qr.0;
        rem = qr.1;
    }
    while q.bits() < 55 {
        s += 1;
        let qr = shifted_div(&n, &d, s);
        q = qr.0;
        rem = qr.1;
    }
    // value = (q + rem/d) · 2^-s with q in [2^54, 2^55).
    let sticky = !rem.is_zero();
    let q = q.to_u64().expect("55-bit quotient fits in u64");
    // Unbiased exponent of the leading bit: 54 - s.
    let lead_exp = 54 - s;
    let value = if lead_exp < -1022 {
        // Subnormal range: keep fewer significand bits.
        let keep = 53 - (-1022 - lead_exp); // bits of precision left
        if keep <= 0 {
            // Below half the smallest subnormal (or exactly at it): round to 0 or min subnormal.
            let half_min = -1075i64; // 2^-1075 is half of the smallest subnormal
            if lead_exp < half_min || (lead_exp == half_min && !sticky && q == 1u64 << 54) {
                0.0
            } else {
                f64::from_bits(1)
            }
        } else {
            round_bits(q, sticky, (55 - keep) as u32, -1074)
        }
    } else if lead_exp > 1023 {
        f64::INFINITY
    } else {
        round_bits(q, sticky, 2, lead_exp - 52)
    };
    if negative {
        -value
    } else {
        value
    }
}

/// `r` as the `f64` it equals, when that is seen cheaply: a numerator of at most 53 bits over
/// `2^k`, `k ≤ 1022` (so the value is a normal `f64` or zero). `None` says nothing about
/// whether `r` is an `f64`.
pub(crate) fn exact_f64(r: &Rational) -> Option<f64> {
    let n = r.numer();
    if n.bits() > 53 {
        return None;
    }
    let k = power_of_two(r.denom())?;
    if k > 1022 {
        return None;
    }
    // |n| < 2^53 converts exactly; 2^−k is a normal power of two; their product is exact.
    let m = n.to_i64()? as f64;
    Some(m * f64::from_bits((1023 - k) << 52))
}

/// The simplest rational in the closed interval `[lo, hi]` (`lo ≤ hi`): the one with the
/// least denominator, and among those the least in magnitude (0 when the interval holds it),
/// by continued fractions (the Stern–Brocot descent): an integer when the interval holds
/// one, else `n + 1/s` with `n = ⌊lo⌋` and `s` the simplest in `[1/(hi − n), 1/(lo − n)]`.
/// The descent takes one step per partial quotient of the ends (at most about as many as
/// their bits).
pub(crate) fn simplest_between(lo: &Rational, hi: &Rational) -> Rational {
    if !lo.is_positive() && !hi.is_negative() {
        return Rational::zero();
    }
    if hi.is_negative() {
        return -simplest_between(&-hi, &-lo);
    }
    // 0 < lo ≤ hi.
    let n = lo.floor();
    if &n == lo {
        return n;
    }
    let up = &n + Rational::one();
    if &up <= hi {
        return up;
    }
    // lo, hi in (n, n + 1).
    let s = simplest_between(&(hi - &n).recip(), &(lo - &n).recip());
    n + s.recip()
}

/// `a + (b − a)·t`, through the gcd-free dyadic operations when all three are dyadic.
pub(crate) fn lerp(a: &Rational, b: &Rational, t: &Rational) -> Rational {
    if t.is_zero() {
        return a.clone();
    }
    if t.is_one() {
        return b.clone();
    }
    dyadic_add(b, a, true)
        .and_then(|w| dyadic_mul(&w, t))
        .and_then(|wt| dyadic_add(a, &wt, false))
        .unwrap_or_else(|| a + (b - a) * t)
}

/// Rounds the 55-bit `q` (plus `sticky`) by dropping `drop` low bits, ties to even,
/// and scales by `2^unit_exp` per unit of the kept part.
fn round_bits(q: u64, sticky: bool, drop: u32, unit_exp: i64) -> f64 {
    let kept = q >> drop;
    let rest = q & ((1u64 << drop) - 1);
    let half = 1u64 << (drop - 1);
    let round_up = rest > half || (rest == half && (sticky || kept & 1 == 1));
    let kept = if round_up { kept + 1 } else { kept };
    // kept < 2^54, exactly representable; ldexp via powi is exact for powers of two in range.
    ldexp(kept as f64, unit_exp)
}

/// `m · 2^e` computed exactly when the result is representable.
fn ldexp(m: f64, e: i64) -> f64 {
    let mut v = m;
    let mut e = e;
    while e > 1000 {
        v *= 2f64.powi(1000);
        e -= 1000;
    }
    while e < -1000 {
        // Multiply in two steps to avoid double rounding: m has at most 54 bits
        // and the final result is the correctly rounded kept value, so while
        // intermediate values stay normal these steps are exact.
        v *= 2f64.powi(-1000);
        e += 1000;
    }
    v * 2f64.powi(e as i32)
}

fn shifted_div(n: &BigInt, d: &BigInt, s: i64) -> (BigInt, BigInt) {
    if s >= 0 {
        (n << (s as usize)).div_rem(d)
    } else {
        n.div_rem(&(d << ((-s) as usize)))
    }
}

/// Parses `"p/q"`, an integer, or a decimal with optional exponent (`"-1.25e-3"`), exactly.
pub fn parse_rational(text: &str) -> Result<Rational, NumError> {
    let t = text.trim();
    let err = |why: &str| NumError::Parse {
        text: text.to_string(),
        why: why.to_string(),
    };
    if t.is_empty() {
        return Err(err("empty"));
    }
    if let Some((p, q)) = t.split_once('/') {
        let p = parse_integer(p.trim()).ok_or_else(|| err("numerator is not an integer"))?;
        let q = parse_integer(q.trim()).ok_or_else(|| err("denominator is not an integer"))?;
        if q.is_zero() {
            return Err(NumError::ZeroDenominator {
                text: text.to_string(),
            });
        }
        return Ok(Rational::new(p, q));
    }
    let lower = t.to_ascii_lowercase();
    if lower.contains("nan") || lower.contains("inf") {
        return Err(err("non-finite values are not accepted"));
    }
    let (mantissa, exponent) = match lower.split_once('e') {
        Some((m, e)) => (m, e.parse::<i64>().map_err(|_| err("bad exponent"))?),
        None => (lower.as_str(), 0),
    };
    if exponent.abs() > 100_000 {
        return Err(err("exponent out of range (|e| > 100000)"));
    }
    let (negative, digits) = match mantissa.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, mantissa.strip_prefix('+').unwrap_or(mantissa)),
    };
    let (int_part, frac_part) = digits.split_once('.').unwrap_or((digits, ""));
    if int_part.is_empty() && frac_part.is_empty() {
        return Err(err("no digits"));
    }
    if !int_part
        .chars()
        .chain(frac_part.chars())
        .all(|c| c.is_ascii_digit())
    {
        return Err(err("unexpected character"));
    }
    let all: String = format!("{int_part}{frac_part}");
    let mut m: BigInt = if all.is_empty() {
        BigInt::zero()
    } else {
        all.parse().map_err(|_| err("bad digits"))?
    };
    if negative {
        m = -m;
    }
    let scale = exponent - frac_part.len() as i64;
    let ten = BigInt::from(10);
    Ok(if scale >= 0 {
        Rational::from_integer(m * num_traits::pow(ten, scale as usize))
    } else {
        Rational::new(m, num_traits::pow(ten, (-scale) as usize))
    })
}

fn parse_integer(s: &str) -> Option<BigInt> {
    let digits = s.strip_prefix(['-', '+']).unwrap_or(s);
    if digits.is_empty() || !digits.chars().all(|c| c.is_ascii_digit()) {
        return None;
    }
    s.parse().ok()
}

/// Formats a rational as `"p/q"`, or `"p"` when it is an integer.
pub fn rational_to_string(r: &Rational) -> String {
    if r.denom().is_one() {
        r.numer().to_string()
    } else {
        format!("{}/{}", r.numer(), r.denom())
    }
}

/// A point's coordinates, exactly, separated by `", "` (e.g. `1/3, 0, -5/2`).
pub fn point_to_string(point: &[Rational]) -> String {
    point
        .iter()
        .map(rational_to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

/// The exact sign of a rational.
pub(crate) fn rational_sign(r: &Rational) -> super::Sign {
    match r.numer().sign() {
        BigSign::Minus => super::Sign::Negative,
        BigSign::NoSign => super::Sign::Zero,
        BigSign::Plus => super::Sign::Positive,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::num::xorshift;

    /// Around every fraction `p/q` with `q ≤ 40` (and its negative), any interval narrower
    /// than `1/(2q²)`-ish that holds it gives it back (a closer fraction of denominator ≤ q
    /// is at least `1/q²` away); an interval holding an integer gives the integer nearest 0.
    #[test]
    fn the_simplest_rational_between_is_the_fraction_inside() {
        let r = |n: i64, d: i64| Rational::new(n.into(), d.into());
        let mut checked = 0;
        for q in 1..=40i64 {
            for p in -3 * q..=3 * q {
                let x = r(p, q);
                let eps = r(1, 4 * q * q + 1);
                for (lo, hi) in [
                    (&x - &eps, &x + &eps),
                    (x.clone(), x.clone()),
                    (x.clone(), &x + &eps),
                ] {
                    assert_eq!(simplest_between(&lo, &hi), x, "[{lo}, {hi}]");
                    checked += 1;
                }
            }
        }
        assert_eq!(simplest_between(&r(-5, 2), &r(7, 3)), r(0, 1));
        assert_eq!(simplest_between(&r(3, 2), &r(7, 3)), r(2, 1));
        assert_eq!(simplest_between(&r(-7, 3), &r(-3, 2)), r(-2, 1));
        assert_eq!(simplest_between(&r(1, 3), &r(1, 2)), r(1, 2));
        assert!(checked > 9000, "{checked}");
    }

    /// A cheap exact conversion is the `f64` the rational denotes (and happens on a good part
    /// of small dyadics); the gcd-free lerp equals the rational formula, dyadic or not.
    #[test]
    fn exact_f64_and_lerp_agree_with_the_general_routes() {
        let mut seed = 7u64;
        let mut next = || xorshift(&mut seed);
        let mut seen = 0;
        for _ in 0..2000 {
            let (m, k) = ((next() >> (next() % 64)) as i64, next() % 1100);
            let d = BigInt::one() << (k as usize);
            let r = Rational::new(BigInt::from(m) - BigInt::from(next() % 3), d);
            if let Some(x) = exact_f64(&r) {
                seen += 1;
                assert_eq!(rational_from_f64(x, "x").unwrap(), r);
            }
            let t = Rational::new(BigInt::from((next() % 33) as i64 - 8), BigInt::from(16));
            let a = Rational::new(BigInt::from(next() as i32), BigInt::from(1 + next() % 12));
            assert_eq!(lerp(&a, &r, &t), &a + (&r - &a) * &t);
        }
        assert!(seen > 100, "{seen} exact conversions");
    }

    /// The gcd-free rounding of `n / d` equals the rounding of the reduced rational, for
    /// common factors from 1 to large, both signs of `n` and `d`, and magnitudes from
    /// subnormal to overflow.
    #[test]
    fn unreduced_ratio_rounds_as_the_reduced_rational() {
        let mut seed = 5u64;
        let mut next = || xorshift(&mut seed);
        for i in 0..3000 {
            let n = BigInt::from((next() >> (next() % 64)) as i64 - (1 << 20))
                << (next() % 1100) as usize;
            let d: BigInt = (BigInt::from((next() >> (next() % 64)).max(1))
                << (next() % 1100) as usize)
                * if i % 2 == 0 { 1 } else { -1 };
            let k = BigInt::from(next() >> (next() % 64)).max(BigInt::one())
                * (BigInt::one() << (next() % 40) as usize);
            let want = rational_to_f64(&Rational::new(n.clone(), d.clone()));
            assert_eq!(
                ratio_to_f64(&(&n * &k), &(&d * &k)).to_bits(),
                want.to_bits(),
                "{n}/{d} x{k}"
            );
        }
    }

    /// The machine-word routes (`i128` products, binary gcd) give the same lowest terms as
    /// `num-rational`, on values from tiny to the edges of `i64` (both signs, zero), and
    /// decline what does not fit.
    #[test]
    fn small_routes_equal_num_rational() {
        let mut seed = 11u64;
        let mut next = || xorshift(&mut seed);
        let edges = [i64::MIN, i64::MIN + 1, i64::MAX, -1, 0, 1, 3, 1 << 62];
        let value = |next: &mut dyn FnMut() -> u64| -> Rational {
            let pick = |x: u64| edges[(x % edges.len() as u64) as usize];
            let n = match next() % 3 {
                0 => pick(next()),
                1 => (next() % 1000) as i64 - 500,
                _ => (next() >> (next() % 64)) as i64,
            };
            let d = match next() % 3 {
                0 => pick(next()).max(1),
                1 => 1 + (next() % 1000) as i64,
                _ => ((next() >> (next() % 64)) as i64).max(1),
            };
            Rational::new(n.into(), d.into())
        };
        let mut taken = 0;
        for _ in 0..20_000 {
            let (a, b) = (value(&mut next), value(&mut next));
            let same = |x: Option<Rational>, want: Rational| {
                if let Some(x) = x {
                    assert_eq!((x.numer(), x.denom()), (want.numer(), want.denom()));
                    true
                } else {
                    false
                }
            };
            taken += usize::from(same(small_add(&a, &b, false), &a + &b));
            same(small_add(&a, &b, true), &a - &b);
            same(small_mul(&a, &b, false), &a * &b);
            if !b.is_zero() {
                same(small_mul(&a, &b, true), &a / &b);
            }
            let (n, d) = (a.numer() * b.denom(), b.numer() * a.denom());
            if !d.is_zero() {
                let r = reduced(n.clone(), d.clone());
                let want = Rational::new(n, d);
                assert_eq!((r.numer(), r.denom()), (want.numer(), want.denom()));
            }
        }
        assert!(taken > 10_000, "{taken} sums on the machine-word route");
        let big = Rational::from_integer(BigInt::one() << 70usize);
        assert!(small_add(&big, &big, false).is_none());
        assert_eq!(gcd_u128(0, 0), 0);
        assert_eq!(gcd_u128(u128::MAX, 3), 3);
    }

    /// The integer dyadic subdivision gives exactly the generic recurrence's coefficients, at
    /// split points inside and outside [0, 1], on lines of mixed powers of two and signs; a
    /// non-dyadic value or split point falls back (`None`).
    #[test]
    fn dyadic_split_equals_de_casteljau() {
        let q = |n: i64, d: i64| Rational::new(n.into(), d.into());
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = |m: i64| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) as i64 % m
        };
        for _ in 0..2_000 {
            let len = 1 + next(5) as usize;
            let line: Vec<Rational> = (0..len).map(|_| q(next(41) - 20, 1 << next(12))).collect();
            let t = q(next(40) - 8, 1 << next(6));
            let fast = dyadic_split_line(&line, &t).expect("dyadic");
            assert_eq!(fast, crate::bernstein::poly::de_casteljau_split(&line, &t));
        }
        assert!(dyadic_split_line(&[q(1, 3), q(1, 2)], &q(1, 2)).is_none());
        for _ in 0..2_000 {
            let len = 1 + next(5) as usize;
            let line: Vec<Rational> = (0..len).map(|_| q(next(41) - 20, 1 + next(12))).collect();
            let t = q(next(40) - 8, 1 + next(13));
            let want = crate::bernstein::poly::de_casteljau_split(&line, &t);
            let got = common_split_line(&line, &t);
            for (g, w) in got.0.iter().chain(&got.1).zip(want.0.iter().chain(&want.1)) {
                assert_eq!((g.numer(), g.denom()), (w.numer(), w.denom()));
            }
            assert_eq!(&common_eval_line(&line, &t), want.0.last().expect("value"));
            assert_eq!(
                crate::bernstein::poly::de_casteljau_eval(&line, &t),
                common_eval_line(&line, &t)
            );
        }
        // Sums, differences and products of dyadics, integers and zeros: lowest terms, equal
        // to num-rational's; non-dyadic operands are declined.
        for _ in 0..5_000 {
            let a = q(next(61) - 30, 1 << next(62));
            let b = q(next(61) - 30, 1 << next(62));
            let (s, d, p) = (
                dyadic_add(&a, &b, false).expect("dyadic"),
                dyadic_add(&a, &b, true).expect("dyadic"),
                dyadic_mul(&a, &b).expect("dyadic"),
            );
            for (got, want) in [(s, &a + &b), (d, &a - &b), (p, &a * &b)] {
                // Field equality and the representation (lowest terms, positive denominator).
                assert_eq!((got.numer(), got.denom()), (want.numer(), want.denom()));
            }
        }
        assert!(dyadic_add(&q(1, 3), &q(1, 2), false).is_none());
        assert!(dyadic_mul(&q(1, 2), &q(2, 3)).is_none());
        assert!(dyadic_split_line(&[q(1, 4), q(1, 2)], &q(1, 3)).is_none());
    }

    #[test]
    fn f64_round_trip_exact() {
        for &x in &[
            0.1,
            -3.5,
            1e-300,
            5e-324,
            f64::MAX,
            f64::MIN_POSITIVE,
            2.0f64.powi(-1060),
            123456.789,
        ] {
            let r = rational_from_f64(x, "x").unwrap();
            assert_eq!(rational_to_f64(&r), x, "{x}");
        }
        assert!(rational_from_f64(f64::NAN, "x").is_err());
        assert!(rational_from_f64(f64::INFINITY, "x").is_err());
    }

    #[test]
    fn nearest_rounding() {
        let third = Rational::new(1.into(), 3.into());
        assert_eq!(rational_to_f64(&third), 1.0 / 3.0);
        let r = parse_rational("0.1").unwrap();
        assert_eq!(rational_to_f64(&r), 0.1);
        // 1 + 2^-53 is a tie between 1 and 1 + 2^-52: ties to even gives 1.
        let tie = Rational::one() + Rational::new(1.into(), BigInt::one() << 53usize);
        assert_eq!(rational_to_f64(&tie), 1.0);
        let above = tie + Rational::new(1.into(), BigInt::one() << 80usize);
        assert_eq!(rational_to_f64(&above), 1.0 + f64::EPSILON);
    }

    #[test]
    fn parsing() {
        assert_eq!(
            parse_rational("-3/6").unwrap(),
            Rational::new((-1).into(), 2.into())
        );
        assert_eq!(
            parse_rational("1.25e-1").unwrap(),
            Rational::new(1.into(), 8.into())
        );
        assert_eq!(
            parse_rational("-.5").unwrap(),
            Rational::new((-1).into(), 2.into())
        );
        assert_eq!(
            parse_rational("12E2").unwrap(),
            Rational::from_integer(1200.into())
        );
        for bad in ["", "1/0", "abc", "1.2.3", "nan", "inf", "1/x", "--1", "."] {
            assert!(parse_rational(bad).is_err(), "{bad}");
        }
    }
}
