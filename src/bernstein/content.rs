//! Univariate contents of tensor Bernstein polynomials over the rationals: the factors that
//! depend on one variable only.
//!
//! In the tensor basis `p = Σ_j c_j(x_k) Π_{a≠k} B_{j_a}(x_a)`, and the products of the other
//! axes' Bernstein polynomials are linearly independent over `ℚ(x_k)`, so a polynomial
//! `c(x_k)` divides `p` exactly when it divides every *line* `c_j` along axis `k`. The
//! content along `k` is therefore the greatest common divisor of the lines (Euclid over `ℚ`,
//! in the power basis of the unit variable), and `p / c` is taken line by line.
//!
//! Rational parametrisations put such factors everywhere: a quarter circle's weight
//! `1 + u²`, a Cayley rotation's denominator `1 + t²` raised to a power, a patch's weights.
//! Where such a factor keeps one strict sign on `[0, 1]` it has no zero on the unit box,
//! and dividing it out changes no zero set there while lowering the degrees.

use super::poly::map_lines;
use super::univariate::{div_rem, gcd, monic, trimmed};
use super::{
    prove_positive_exact, Bernstein, BernsteinError, Limits, PositivityVerdict, ScaledBernstein,
};
use crate::num::Rational;
use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::{One, Signed, Zero};

/// Power-basis coefficients `a_0, a_1, …` of a univariate polynomial, lowest first.
type Power = Vec<Rational>;

/// A factor divided out: its axis and its monic power-basis coefficients (lowest first).
pub type UnivariateFactor = (usize, Vec<Rational>);

/// The lines of a coefficient tensor along `axis` (axis 0 fastest): `(start, stride, len)`.
fn lines(degrees: &[usize], axis: usize) -> impl Iterator<Item = (usize, usize, usize)> {
    let stride: usize = degrees[..axis].iter().map(|d| d + 1).product();
    let len = degrees[axis] + 1;
    let outer: usize = degrees[axis + 1..].iter().map(|d| d + 1).product();
    (0..outer).flat_map(move |o| (0..stride).map(move |i| (o * stride * len + i, stride, len)))
}

/// `c` with its factors `x` and `x − 1` divided out (as often as they divide).
fn without_end_roots(mut c: Power) -> Power {
    let x = [Rational::zero(), Rational::one()];
    let x_minus_1 = [-Rational::one(), Rational::one()];
    while c.len() >= 2 && c[0].is_zero() {
        c = div_rem(&c, &x).0;
    }
    while c.len() >= 2 && c.iter().sum::<Rational>().is_zero() {
        c = div_rem(&c, &x_minus_1).0;
    }
    c
}

/// Whether the univariate polynomial (power form in the unit variable) keeps one strict sign
/// on `[0, 1]`, proved exactly by Bernstein subdivision within small limits (`false` when
/// not proved).
fn one_strict_sign(c: &[Rational]) -> Result<bool, BernsteinError> {
    let b = Bernstein::from_power(vec![c.len() - 1], c.to_vec())?;
    let limits = Limits::default().with_max_depth(16).with_max_boxes(512);
    let positive = |p: &Bernstein<Rational>| {
        matches!(
            prove_positive_exact(p, limits),
            PositivityVerdict::Positive { .. }
        )
    };
    Ok(positive(&b) || positive(&b.scale(&-Rational::one())))
}

/// Pascal's triangle up to row `n`, as integers.
struct Binomials(Vec<Vec<BigInt>>);

impl Binomials {
    fn new(n: usize) -> Self {
        let mut rows: Vec<Vec<BigInt>> = vec![vec![BigInt::one()]];
        for k in 1..=n {
            let prev = &rows[k - 1];
            let row = (0..=k)
                .map(
                    |j| match (j.checked_sub(1).map(|i| &prev[i]), prev.get(j)) {
                        (Some(a), Some(b)) => a + b,
                        (Some(a), None) | (None, Some(a)) => a.clone(),
                        (None, None) => BigInt::zero(),
                    },
                )
                .collect();
            rows.push(row);
        }
        Binomials(rows)
    }

    /// `C(n, k)` (`k ≤ n` within the table).
    fn get(&self, n: usize, k: usize) -> &BigInt {
        &self.0[n][k]
    }
}

/// Bernstein coefficients of one line (degree `d`) to power-basis coefficients, in integers:
/// `a_j = C(d,j) Σ_{i≤j} (−1)^{j−i} C(j,i) b_i`.
fn line_to_power(b: &[BigInt], c: &Binomials) -> Vec<BigInt> {
    let d = b.len() - 1;
    (0..=d)
        .map(|j| {
            let mut acc = BigInt::zero();
            for (i, bi) in b.iter().enumerate().take(j + 1) {
                let term = bi * c.get(j, i);
                if (j - i) % 2 == 0 {
                    acc += term;
                } else {
                    acc -= term;
                }
            }
            acc * c.get(d, j)
        })
        .collect()
}

/// Power-basis coefficients of one line (degree `d`) to Bernstein coefficients times
/// `scale = lcm_j C(d, j)`: `scale·b_i = Σ_{j≤i} C(i,j) (scale / C(d,j)) a_j`; `weights` are
/// the `scale / C(d, j)`.
fn line_from_power(a: &[BigInt], weights: &[BigInt], c: &Binomials) -> Vec<BigInt> {
    let d = a.len() - 1;
    (0..=d)
        .map(|i| {
            (0..=i)
                .map(|j| &a[j] * &weights[j] * c.get(i, j))
                .sum::<BigInt>()
        })
        .collect()
}

/// `a / c` for an integer `c` dividing `a` over `ℚ` (`c` primitive, so the quotient is an
/// integer polynomial by Gauss's lemma); `None` when some step leaves a remainder.
fn integer_quotient(a: &[BigInt], c: &[BigInt]) -> Option<Vec<BigInt>> {
    let (n, m) = (a.len(), c.len());
    if n < m {
        return None;
    }
    let lead = c.last()?;
    let mut rest = a.to_vec();
    let mut q = vec![BigInt::zero(); n - m + 1];
    for k in (0..q.len()).rev() {
        let top = &rest[k + m - 1];
        if !top.is_zero() {
            let (quot, rem) = top.div_rem(lead);
            if !rem.is_zero() {
                return None;
            }
            for (i, ci) in c.iter().enumerate() {
                rest[k + i] -= &quot * ci;
            }
            q[k] = quot;
        }
    }
    rest.iter().all(Zero::is_zero).then_some(q)
}

/// The primitive part of an integer polynomial (trimmed; empty for zero).
fn primitive_part(mut a: Vec<BigInt>) -> Vec<BigInt> {
    while a.last().is_some_and(Zero::is_zero) {
        a.pop();
    }
    let g = a.iter().fold(BigInt::zero(), |acc, x| acc.gcd(x));
    if !g.is_zero() && !g.is_one() {
        a.iter_mut().for_each(|x| *x /= &g);
    }
    a
}

/// A greatest common divisor over `ℚ` of two integer polynomials, as a primitive integer
/// polynomial: Euclid with pseudo-remainders, each reduced to its primitive part (empty when
/// both are zero).
fn integer_gcd(a: Vec<BigInt>, b: Vec<BigInt>) -> Vec<BigInt> {
    let (mut a, mut b) = (primitive_part(a), primitive_part(b));
    if a.len() < b.len() {
        std::mem::swap(&mut a, &mut b);
    }
    while !b.is_empty() {
        // lead(b)^(deg a − deg b + 1)·a mod b, in integers.
        let lead = b.last().expect("non-empty").clone();
        let mut r = a;
        while r.len() >= b.len() {
            let top = r.pop().expect("non-empty");
            let shift = r.len() + 1 - b.len();
            r.iter_mut().for_each(|x| *x *= &lead);
            for (i, bi) in b[..b.len() - 1].iter().enumerate() {
                r[shift + i] -= &top * bi;
            }
            while r.last().is_some_and(Zero::is_zero) {
                r.pop();
            }
        }
        (a, b) = (b, primitive_part(r));
    }
    a
}

/// `c` (rational, non-zero) times the positive rational that makes it a primitive integer
/// polynomial.
fn primitive(c: &[Rational]) -> Vec<BigInt> {
    let den = c.iter().fold(BigInt::one(), |acc, x| acc.lcm(x.denom()));
    primitive_part(c.iter().map(|x| x.numer() * (&den / x.denom())).collect())
}

/// The content along `axis` of integer Bernstein coefficients (see
/// [`Bernstein::univariate_content`]), monic, or `None` when constant. With `candidate`, only
/// two fixed pseudo-random combinations of the lines are taken: their gcd is a multiple of
/// the content (equal to it but for a coincidence), to be confirmed by dividing every line.
fn content_along(num: &[BigInt], degrees: &[usize], axis: usize, candidate: bool) -> Option<Power> {
    let to_rational =
        |a: Vec<BigInt>| -> Power { a.into_iter().map(Rational::from_integer).collect() };
    let binomials = Binomials::new(degrees[axis]);
    let line = |start: usize, stride: usize, len: usize| -> Vec<BigInt> {
        (0..len).map(|j| num[start + j * stride].clone()).collect()
    };
    if candidate {
        let len = degrees[axis] + 1;
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut combos = [vec![BigInt::zero(); len], vec![BigInt::zero(); len]];
        for (start, stride, len) in lines(degrees, axis) {
            for combo in &mut combos {
                let w = BigInt::from((crate::num::xorshift(&mut seed) >> 60) as i64 + 1);
                for (j, x) in combo.iter_mut().enumerate().take(len) {
                    *x += &num[start + j * stride] * &w;
                }
            }
        }
        let [a, b] = combos.map(|c| line_to_power(&c, &binomials));
        let g = integer_gcd(a, b);
        return (g.len() >= 2).then(|| monic(to_rational(g)));
    }
    let mut g: Option<Power> = None;
    for (start, stride, len) in lines(degrees, axis) {
        let p = trimmed(to_rational(line_to_power(
            &line(start, stride, len),
            &binomials,
        )));
        if p.is_empty() {
            continue;
        }
        let next = match g {
            None => monic(p),
            Some(acc) => gcd(&acc, &p),
        };
        if next.len() < 2 {
            return None;
        }
        g = Some(next);
    }
    g.filter(|c| c.len() >= 2)
}

/// Every line along `axis` divided by `c` (integers, primitive): the numerators along
/// `axis` of degree `d − deg c`, scaled by `lcm_j C(d − deg c, j)` (returned), or `None`
/// when some line leaves a remainder.
fn divide_lines(
    num: &[BigInt],
    degrees: &[usize],
    axis: usize,
    c: &[BigInt],
) -> Option<(Vec<usize>, Vec<BigInt>, BigInt)> {
    let mut out_degrees = degrees.to_vec();
    out_degrees[axis] = degrees[axis] + 1 - c.len();
    let d = out_degrees[axis];
    let binomials = Binomials::new(degrees[axis]);
    let scale = (0..=d).fold(BigInt::one(), |acc, j| acc.lcm(binomials.get(d, j)));
    let weights: Vec<BigInt> = (0..=d).map(|j| &scale / binomials.get(d, j)).collect();
    let mut exact = true;
    let out =
        map_lines(
            degrees,
            num,
            axis,
            d + 1,
            &BigInt::zero(),
            |line, out| match integer_quotient(&line_to_power(line, &binomials), c) {
                Some(q) => out.clone_from_slice(&line_from_power(&q, &weights, &binomials)),
                None => exact = false,
            },
        );
    exact.then_some((out_degrees, out, scale))
}

impl Bernstein<Rational> {
    /// The content along `axis`: the monic greatest common divisor over `ℚ` of the
    /// polynomial's lines along it, as power-basis coefficients in the unit variable
    /// (lowest first), or `None` when it is a constant (or the polynomial is zero).
    pub fn univariate_content(&self, axis: usize) -> Result<Option<Vec<Rational>>, BernsteinError> {
        self.check_axis(axis)?;
        if self.degrees()[axis] == 0 {
            return Ok(None);
        }
        let s = ScaledBernstein::from_rational(self);
        Ok(content_along(s.numerators(), self.degrees(), axis, false))
    }

    /// The polynomial with its univariate contents of one strict sign on `[0, 1]` divided
    /// out along every axis (each content without its factors `x` and `x − 1`, when that is
    /// proved to keep one strict sign; one with another zero on `[0, 1]` stays), up to a
    /// positive constant factor, and the factors divided out as `(axis, power coefficients)`,
    /// each monic up to its sign and positive on `[0, 1]`: the product of the result and the
    /// factors is the polynomial times a positive constant. The zero set and the signs on the
    /// unit box are unchanged. (Computed in integers: each axis's content is the gcd
    /// of two fixed combinations of its lines, confirmed by dividing every line exactly.)
    pub fn without_signed_contents(&self) -> Result<(Self, Vec<UnivariateFactor>), BernsteinError> {
        let s = ScaledBernstein::from_rational(self);
        let mut degrees = self.degrees().to_vec();
        let mut num = s.numerators().to_vec();
        let mut den = s.denominator().clone();
        let mut divided = Vec::new();
        for axis in 0..degrees.len() {
            if degrees[axis] == 0 {
                continue;
            }
            let Some(c) = content_along(&num, &degrees, axis, true) else {
                continue;
            };
            // The factors `x` and `x − 1` vanish on the box's faces and stay.
            let c = without_end_roots(c);
            if c.len() < 2 || !one_strict_sign(&c)? {
                continue;
            }
            // Divided as the multiple positive on [0, 1] (`c(0) = a₀` has the sign of all of
            // it), so the quotient keeps the polynomial's signs.
            let c: Power = if c[0].is_negative() {
                c.into_iter().map(|x| -x).collect()
            } else {
                c
            };
            let ints = primitive(&c);
            if let Some((d, n, scale)) = divide_lines(&num, &degrees, axis, &ints) {
                (degrees, num) = (d, n);
                den *= scale;
                divided.push((axis, c));
            }
        }
        if divided.is_empty() {
            return Ok((self.clone(), divided));
        }
        Ok((
            ScaledBernstein::with_denominator(degrees, num, den)?.to_rational(),
            divided,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn r(n: i64) -> Rational {
        Rational::from_integer(n.into())
    }

    /// A product `(1 + u²)·(2 + t)·q(u, v, t)` loses exactly its two signed univariate
    /// factors; `u·q` keeps `u` (a zero at `u = 0`), and values agree at sample points.
    #[test]
    fn signed_univariate_factors_are_divided_out() {
        let q = Bernstein::from_power(
            vec![2, 1, 2],
            (0..18).map(|k| r((k * 7 % 11) as i64 - 5)).collect(),
        )
        .unwrap();
        let a = Bernstein::from_power(vec![2, 0, 0], vec![r(1), r(0), r(1)]).unwrap();
        let b = Bernstein::from_power(vec![0, 0, 1], vec![r(2), r(1)]).unwrap();
        let p = a.product(&b).unwrap().product(&q).unwrap();
        let (reduced, divided) = p.without_signed_contents().unwrap();
        assert_eq!(reduced.degrees(), q.degrees());
        assert_eq!(divided.len(), 2);
        for point in [[1, 3, 5], [2, 7, 1], [4, 4, 4]] {
            let x: Vec<Rational> = point
                .iter()
                .map(|&k| Rational::new(k.into(), 8.into()))
                .collect();
            let (pv, qv, av, bv) = (
                p.eval(&x).unwrap(),
                reduced.eval(&x).unwrap(),
                a.eval(&x).unwrap(),
                b.eval(&x).unwrap(),
            );
            // Monic factors: the reduced polynomial is q up to a constant.
            assert_eq!(pv, qv * av * bv * r(1));
        }
        let u = Bernstein::from_power(vec![1, 0, 0], vec![r(0), r(1)]).unwrap();
        let (kept, none) = u.product(&q).unwrap().without_signed_contents().unwrap();
        assert!(none.is_empty());
        assert_eq!(kept.degrees(), &[3, 1, 2]);
        assert_eq!(
            u.product(&q).unwrap().univariate_content(0).unwrap(),
            Some(vec![r(0), r(1)])
        );
    }

    /// On 60 random products `a(x_k)·q(u, v, t)`: a factor of one strict sign on `[0, 1]` is
    /// divided out (`x − 2`, negative there, as `2 − x`; and `x(1 + x²)` loses `1 + x²` but
    /// keeps `x`), one with a zero inside (`(2x − 1)²`) stays; the reduced polynomial times the factors divided is the
    /// original times one positive constant at every sample point.
    #[test]
    fn random_products_lose_exactly_their_signed_factors() {
        // (power coefficients, degree dropped when divided out)
        let factors: [(&[i64], usize); 6] = [
            (&[1, 0, 1], 2),
            (&[-2, 1], 1),
            (&[2, 1], 1),
            (&[3, -1, 1], 2),
            (&[0, 1, 0, 1], 2),
            (&[1, -4, 4], 0),
        ];
        let mut seed = 0x1234_5678_9abc_def1u64;
        let mut next = |m: u64| crate::num::xorshift(&mut seed) % m;
        let mut checked = 0;
        for case in 0..60 {
            let degrees: Vec<usize> = (0..3).map(|_| 1 + next(3) as usize).collect();
            let count: usize = degrees.iter().map(|d| d + 1).product();
            let q = Bernstein::from_power(
                degrees.clone(),
                (0..count).map(|_| r(next(19) as i64 - 9)).collect(),
            )
            .unwrap();
            // A q with a univariate content of its own is rare; skip it.
            if (0..3).any(|k| q.univariate_content(k).unwrap().is_some()) {
                continue;
            }
            let axis = case % 3;
            let (coeffs, drop) = factors[case % factors.len()];
            let mut fd = vec![0; 3];
            fd[axis] = coeffs.len() - 1;
            let mut fp = vec![r(0); coeffs.len()];
            for (j, &c) in coeffs.iter().enumerate() {
                fp[j] = r(c);
            }
            // Embed the univariate power coefficients along `axis`.
            let a = Bernstein::from_power(fd, fp).unwrap();
            let p = a.product(&q).unwrap();
            let (reduced, divided) = p.without_signed_contents().unwrap();
            let mut expected = p.degrees().to_vec();
            expected[axis] -= drop;
            assert_eq!(reduced.degrees(), expected.as_slice(), "case {case}");
            assert_eq!(divided.len(), usize::from(drop > 0), "case {case}");
            let mut ratio: Option<Rational> = None;
            for point in [[1, 3, 5], [2, 7, 1], [4, 4, 4], [7, 1, 6]] {
                let x: Vec<Rational> = point
                    .iter()
                    .map(|&k| Rational::new(k.into(), 8.into()))
                    .collect();
                let mut value = reduced.eval(&x).unwrap();
                for (k, c) in &divided {
                    let xk = &x[*k];
                    value *= c.iter().rev().fold(r(0), |acc, ci| acc * xk + ci);
                }
                let pv = p.eval(&x).unwrap();
                if pv.is_zero() {
                    assert!(value.is_zero());
                    continue;
                }
                let k = value / pv;
                assert!(k.is_positive(), "case {case}");
                assert!(ratio.as_ref().is_none_or(|x| *x == k), "case {case}");
                ratio = Some(k);
            }
            checked += 1;
        }
        println!("random products checked: {checked} of 60");
        assert!(checked >= 50);
    }
}
