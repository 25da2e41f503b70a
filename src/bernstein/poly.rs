//! Tensor-product Bernstein polynomials over the unit box, generic in the scalar.
//!
//! `p(t₀,…,t_{n−1}) = Σ c_{i₀…i_{n−1}} Π_a B_{i_a, d_a}(t_a)` with
//! `B_{i,d}(t) = C(d,i) tⁱ (1−t)^{d−i}` (Farin, *Curves and Surfaces for CAGD*, ch. 5).
//! Coefficients are stored with axis 0 varying fastest (the FFD's `u` index).

use super::{binomial, BernsteinError};
use crate::num::{Field, Rational, Sign};
use num_bigint::BigInt;

/// A tensor-product polynomial in Bernstein form on `[0,1]ⁿ`.
#[derive(Clone, Debug, PartialEq)]
pub struct Bernstein<T> {
    degrees: Vec<usize>,
    coeffs: Vec<T>,
}

/// Strides of the coefficient array for the given degrees (axis 0 fastest).
pub(crate) fn strides(degrees: &[usize]) -> Vec<usize> {
    let mut s = Vec::with_capacity(degrees.len());
    let mut acc = 1;
    for &d in degrees {
        s.push(acc);
        acc *= d + 1;
    }
    s
}

/// Number of coefficients for the given degrees.
pub(crate) fn coefficient_count(degrees: &[usize]) -> usize {
    degrees.iter().map(|d| d + 1).product()
}

/// Multi-index of the flat position `flat` (axis 0 fastest).
pub(crate) fn multi_index(degrees: &[usize], mut flat: usize) -> Vec<usize> {
    degrees
        .iter()
        .map(|&d| {
            let i = flat % (d + 1);
            flat /= d + 1;
            i
        })
        .collect()
}

/// Applies `f` to every line of `coeffs` along `axis`: `f(input_line, output_line)`,
/// where output lines have length `new_len`. Returns the new coefficient array.
pub(crate) fn map_lines<T: Clone, F>(
    degrees: &[usize],
    coeffs: &[T],
    axis: usize,
    new_len: usize,
    fill: &T,
    mut f: F,
) -> Vec<T>
where
    F: FnMut(&[T], &mut [T]),
{
    let len = degrees[axis] + 1;
    let inner: usize = degrees[..axis].iter().map(|d| d + 1).product();
    let outer: usize = degrees[axis + 1..].iter().map(|d| d + 1).product();
    let mut out = vec![fill.clone(); inner * new_len * outer];
    let mut line_in: Vec<T> = Vec::with_capacity(if inner == 1 { 0 } else { len });
    let mut line_out: Vec<T> = vec![fill.clone(); new_len];
    for o in 0..outer {
        for i in 0..inner {
            // Along axis 0 a line is contiguous: no copy.
            let line = if inner == 1 {
                &coeffs[len * o..len * (o + 1)]
            } else {
                line_in.clear();
                line_in.extend((0..len).map(|k| coeffs[i + inner * (k + len * o)].clone()));
                &line_in[..]
            };
            f(line, &mut line_out);
            // Swapped out, not cloned: `out` held `fill`, so `line_out` is back to `fill`.
            for (k, v) in line_out.iter_mut().enumerate() {
                std::mem::swap(&mut out[i + inner * (k + new_len * o)], v);
            }
        }
    }
    out
}

/// One-dimensional de Casteljau subdivision of `b` at `t`: returns the control
/// values of the pieces on `[0,t]` and `[t,1]` (Farin, eq. 4.x "subdivision").
pub(crate) fn de_casteljau_split<T: Field>(b: &[T], t: &T) -> (Vec<T>, Vec<T>) {
    let n = b.len();
    let one_minus_t = T::one().sub(t);
    let mut work = b.to_vec();
    let mut left = Vec::with_capacity(n);
    let mut right = vec![T::zero(); n];
    left.push(work[0].clone());
    right[n - 1] = work[n - 1].clone();
    for r in 1..n {
        for i in 0..n - r {
            work[i] = one_minus_t.mul(&work[i]).add(&t.mul(&work[i + 1]));
        }
        left.push(work[0].clone());
        right[n - 1 - r] = work[n - 1 - r].clone();
    }
    (left, right)
}

/// The value of a 1-D Bernstein polynomial at `t` by de Casteljau's algorithm.
pub(crate) fn de_casteljau_eval<T: Field>(b: &[T], t: &T) -> T {
    let one_minus_t = T::one().sub(t);
    let mut work = b.to_vec();
    let n = b.len();
    for r in 1..n {
        for i in 0..n - r {
            work[i] = one_minus_t.mul(&work[i]).add(&t.mul(&work[i + 1]));
        }
    }
    work[0].clone()
}

/// The degrees and coefficients of `(degrees, coeffs)` evaluated at `t` along `axis`.
fn eval_axis_of<T: Field>(
    degrees: &[usize],
    coeffs: &[T],
    axis: usize,
    t: &T,
) -> (Vec<usize>, Vec<T>) {
    let len = degrees[axis] + 1;
    let inner: usize = degrees[..axis].iter().map(|d| d + 1).product();
    let mut out = Vec::with_capacity(coeffs.len() / len);
    T::eval_lines(coeffs, len, inner, t, &mut out);
    let mut degrees = degrees.to_vec();
    degrees[axis] = 0;
    (degrees, out)
}

fn ratio<T: Field>(n: BigInt, d: BigInt) -> T {
    T::from_rational(&Rational::new(n, d))
}

impl<T: Field> Bernstein<T> {
    /// A polynomial from degrees and coefficients (axis 0 fastest).
    pub fn new(degrees: Vec<usize>, coeffs: Vec<T>) -> Result<Self, BernsteinError> {
        if degrees.is_empty() {
            return Err(BernsteinError::NoAxes);
        }
        let expected = coefficient_count(&degrees);
        if coeffs.len() != expected {
            return Err(BernsteinError::CoefficientCount {
                expected,
                found: coeffs.len(),
            });
        }
        Ok(Bernstein { degrees, coeffs })
    }

    /// The constant polynomial `c` with the given degrees (all coefficients `c`).
    pub fn constant(degrees: Vec<usize>, c: T) -> Self {
        let n = coefficient_count(&degrees);
        Bernstein {
            degrees,
            coeffs: vec![c; n],
        }
    }

    /// Degree per axis.
    pub fn degrees(&self) -> &[usize] {
        &self.degrees
    }

    /// The coefficients, axis 0 fastest.
    pub fn coeffs(&self) -> &[T] {
        &self.coeffs
    }

    /// The number of variables.
    pub fn dim(&self) -> usize {
        self.degrees.len()
    }

    /// The coefficient at a multi-index.
    pub fn coeff(&self, index: &[usize]) -> &T {
        let s = strides(&self.degrees);
        &self.coeffs[index.iter().zip(&s).map(|(i, s)| i * s).sum::<usize>()]
    }

    /// Converts every coefficient with `f` (e.g. exact to interval).
    pub fn map<U: Field>(&self, f: impl Fn(&T) -> U) -> Bernstein<U> {
        Bernstein {
            degrees: self.degrees.clone(),
            coeffs: self.coeffs.iter().map(f).collect(),
        }
    }

    pub(super) fn check_axis(&self, axis: usize) -> Result<(), BernsteinError> {
        if axis >= self.dim() {
            Err(BernsteinError::Axis {
                axis,
                dim: self.dim(),
            })
        } else {
            Ok(())
        }
    }

    /// Evaluates along one axis at `t`, leaving degree 0 on that axis.
    pub fn eval_axis(&self, axis: usize, t: &T) -> Result<Self, BernsteinError> {
        self.check_axis(axis)?;
        let (degrees, coeffs) = eval_axis_of(&self.degrees, &self.coeffs, axis, t);
        Ok(Bernstein { degrees, coeffs })
    }

    /// The value at a point of the unit box, by de Casteljau along each axis.
    pub fn eval(&self, point: &[T]) -> Result<T, BernsteinError> {
        if point.len() != self.dim() {
            return Err(BernsteinError::DimensionMismatch {
                expected: self.dim(),
                found: point.len(),
            });
        }
        // Axis by axis from axis 0 (its lines contiguous), the first step reading `self`.
        // (Every polynomial has an axis: `new` refuses none.)
        let (mut degrees, mut coeffs) = eval_axis_of(&self.degrees, &self.coeffs, 0, &point[0]);
        for (axis, t) in point.iter().enumerate().skip(1) {
            (degrees, coeffs) = eval_axis_of(&degrees, &coeffs, axis, t);
        }
        Ok(coeffs.swap_remove(0))
    }

    /// de Casteljau subdivision at `t` along `axis`: the pieces on `[0,t]` and `[t,1]`,
    /// each reparametrised to `[0,1]`.
    pub fn split(&self, axis: usize, t: &T) -> Result<(Self, Self), BernsteinError> {
        self.check_axis(axis)?;
        let len = self.degrees[axis] + 1;
        let inner: usize = self.degrees[..axis].iter().map(|d| d + 1).product();
        let total = self.coeffs.len();
        let (mut left, mut right) = (Vec::with_capacity(total), Vec::with_capacity(total));
        T::split_lines(&self.coeffs, len, inner, t, &mut left, &mut right);
        Ok((
            Bernstein {
                degrees: self.degrees.clone(),
                coeffs: left,
            },
            Bernstein {
                degrees: self.degrees.clone(),
                coeffs: right,
            },
        ))
    }

    /// The polynomial restricted to the sub-box `Π [a_k, b_k] ⊂ [0,1]ⁿ`, reparametrised to `[0,1]ⁿ`.
    pub fn restrict(&self, sub_box: &[(T, T)]) -> Result<Self, BernsteinError> {
        self.check_box(sub_box)?;
        let mut p = self.clone();
        for (axis, (a, b)) in sub_box.iter().enumerate() {
            let a_ok = a.sign() != Sign::Negative;
            let ba = b.sub(a).sign();
            let b_le_1 = T::one().sub(b).sign() != Sign::Negative;
            if !(a_ok && ba == Sign::Positive && b_le_1) {
                return Err(BernsteinError::BadBox { axis });
            }
            // Keep [0, b], then [a/b, 1] of that.
            if T::one().sub(b).sign() != Sign::Zero {
                p = p.split(axis, b)?.0;
            }
            if a.sign() != Sign::Zero {
                let t = a.div(b);
                p = p.split(axis, &t)?.1;
            }
        }
        Ok(p)
    }

    /// The polynomial on any box `Π [a_k, b_k]` (`a_k < b_k`, inside `[0,1]ⁿ` or not),
    /// reparametrised to `[0,1]ⁿ`: de Casteljau's recurrence at a point outside `[0, 1]`
    /// still gives the Bernstein coefficients of the polynomial on `[0, t]` and `[t, 1]` (an
    /// identity of polynomials), so the pieces extend it beyond the unit box. Exact over
    /// rationals; [`restrict`](Self::restrict) is the same inside the unit box.
    pub fn on_box(&self, sub_box: &[(T, T)]) -> Result<Self, BernsteinError> {
        self.check_box(sub_box)?;
        let mut p = self.clone();
        for (axis, (a, b)) in sub_box.iter().enumerate() {
            if b.sub(a).sign() != Sign::Positive {
                return Err(BernsteinError::BadBox { axis });
            }
            if T::one().sub(a).sign() != Sign::Zero {
                // [a, 1], then [0, (b − a)/(1 − a)] of that.
                if a.sign() != Sign::Zero {
                    p = p.split(axis, a)?.1;
                }
                let s = b.sub(a).div(&T::one().sub(a));
                if T::one().sub(&s).sign() != Sign::Zero {
                    p = p.split(axis, &s)?.0;
                }
            } else {
                // a = 1 < b: [0, b], then [1/b, 1] of that.
                p = p.split(axis, b)?.0;
                p = p.split(axis, &T::one().div(b))?.1;
            }
        }
        Ok(p)
    }

    /// A box has one interval per variable.
    fn check_box(&self, sub_box: &[(T, T)]) -> Result<(), BernsteinError> {
        if sub_box.len() != self.dim() {
            return Err(BernsteinError::DimensionMismatch {
                expected: self.dim(),
                found: sub_box.len(),
            });
        }
        Ok(())
    }

    /// Degree elevation by `by` along `axis`: the same polynomial with degree `d + by`
    /// (Farin, "degree elevation": `b'_i = Σ_j b_j C(d,j) C(by,i−j) / C(d+by,i)`).
    pub fn elevate(&self, axis: usize, by: usize) -> Result<Self, BernsteinError> {
        self.check_axis(axis)?;
        let d = self.degrees[axis];
        let e = d + by;
        // Row i: the weights of b_j for j = i − by … i (clamped to 0 … d), once per call; each
        // output is one `Field::dot` (for rationals: one reduction instead of one per term).
        let rows: Vec<(usize, Vec<T>)> = (0..=e)
            .map(|i| {
                let j0 = i.saturating_sub(by);
                let weights = (j0..=i.min(d))
                    .map(|j| ratio(binomial(d, j) * binomial(by, i - j), binomial(e, i)))
                    .collect();
                (j0, weights)
            })
            .collect();
        let coeffs = map_lines(
            &self.degrees,
            &self.coeffs,
            axis,
            e + 1,
            &T::zero(),
            |line, out| {
                for (o, (j0, w)) in out.iter_mut().zip(&rows) {
                    *o = T::dot(w, &line[*j0..]);
                }
            },
        );
        let mut degrees = self.degrees.clone();
        degrees[axis] = e;
        Ok(Bernstein { degrees, coeffs })
    }

    /// The partial derivative along `axis` on the unit box: `d Σ (b_{i+1} − b_i) B_{i,d−1}`.
    /// A degree-0 axis gives the zero polynomial of degree 0 there.
    pub fn derivative(&self, axis: usize) -> Result<Self, BernsteinError> {
        self.check_axis(axis)?;
        let d = self.degrees[axis];
        let new_len = d.max(1);
        let coeffs = map_lines(
            &self.degrees,
            &self.coeffs,
            axis,
            new_len,
            &T::zero(),
            |line, out| {
                if d == 0 {
                    out[0] = T::zero();
                } else {
                    for i in 0..d {
                        out[i] = line[i + 1].sub(&line[i]).mul_int(d as i64);
                    }
                }
            },
        );
        let mut degrees = self.degrees.clone();
        degrees[axis] = d.saturating_sub(1);
        Ok(Bernstein { degrees, coeffs })
    }

    /// The product: degrees add per axis and
    /// `c_k = Σ_{i+j=k} a_i b_j C(m,i) C(n,j) / C(m+n,k)` per axis (Farin, "products").
    pub fn product(&self, other: &Self) -> Result<Self, BernsteinError> {
        if other.dim() != self.dim() {
            return Err(BernsteinError::DimensionMismatch {
                expected: self.dim(),
                found: other.dim(),
            });
        }
        let degrees: Vec<usize> = self
            .degrees
            .iter()
            .zip(&other.degrees)
            .map(|(a, b)| a + b)
            .collect();
        // In the scaled basis C(n,i) tⁱ(1−t)ⁿ⁻ⁱ a product is a plain convolution: scale the
        // factors by Π C(m,i), convolve, divide each result by Π C(m+n,k) once (identical to
        // the weights C(m,i)C(n,j)/C(m+n,i+j), with one division per coefficient).
        let scale = |p: &Self, fi: usize| -> T {
            let idx = multi_index(&p.degrees, fi);
            let mut w = BigInt::from(1);
            for (ax, &i) in idx.iter().enumerate() {
                w *= binomial(p.degrees[ax], i);
            }
            p.coeffs[fi].mul(&ratio(w, BigInt::from(1)))
        };
        let a_scaled: Vec<T> = (0..self.coeffs.len()).map(|i| scale(self, i)).collect();
        let b_scaled: Vec<T> = (0..other.coeffs.len()).map(|j| scale(other, j)).collect();
        let out_strides = strides(&degrees);
        let offset = |p: &Self, fi: usize| -> usize {
            multi_index(&p.degrees, fi)
                .iter()
                .zip(&out_strides)
                .map(|(i, s)| i * s)
                .sum()
        };
        let off_b: Vec<usize> = (0..other.coeffs.len()).map(|j| offset(other, j)).collect();
        let mut out = vec![T::zero(); coefficient_count(&degrees)];
        for (fi, a) in a_scaled.iter().enumerate() {
            if a.is_exact_zero() {
                continue;
            }
            let oa = offset(self, fi);
            for (b, ob) in b_scaled.iter().zip(&off_b) {
                out[oa + ob] = out[oa + ob].add(&a.mul(b));
            }
        }
        for (fk, c) in out.iter_mut().enumerate() {
            let mut w = BigInt::from(1);
            for (ax, &k) in multi_index(&degrees, fk).iter().enumerate() {
                w *= binomial(degrees[ax], k);
            }
            *c = c.mul(&ratio(BigInt::from(1), w));
        }
        Ok(Bernstein {
            degrees,
            coeffs: out,
        })
    }

    /// Sum of two polynomials of equal degrees.
    pub fn add(&self, other: &Self) -> Result<Self, BernsteinError> {
        if self.degrees != other.degrees {
            return Err(BernsteinError::DegreeMismatch);
        }
        Ok(Bernstein {
            degrees: self.degrees.clone(),
            coeffs: self
                .coeffs
                .iter()
                .zip(&other.coeffs)
                .map(|(a, b)| a.add(b))
                .collect(),
        })
    }

    /// The sum of two polynomials of any degrees: each is first elevated to the larger
    /// degree per axis.
    pub fn add_elevated(&self, other: &Self) -> Result<Self, BernsteinError> {
        if other.dim() != self.dim() {
            return Err(BernsteinError::DimensionMismatch {
                expected: self.dim(),
                found: other.dim(),
            });
        }
        let mut a = self.clone();
        let mut b = other.clone();
        for axis in 0..self.dim() {
            let (da, db) = (a.degrees[axis], b.degrees[axis]);
            if da < db {
                a = a.elevate(axis, db - da)?;
            } else if db < da {
                b = b.elevate(axis, da - db)?;
            }
        }
        a.add(&b)
    }

    /// The same polynomial as an `n`-variate one, constant along the other axes: axis `k` of
    /// `self` becomes axis `axes[k]` (strictly increasing, below `n`). The coefficient order is
    /// unchanged: degree-0 axes hold one coefficient.
    pub fn embed(&self, axes: &[usize], n: usize) -> Result<Self, BernsteinError> {
        if axes.len() != self.dim() || axes.windows(2).any(|w| w[0] >= w[1]) {
            return Err(BernsteinError::DimensionMismatch {
                expected: self.dim(),
                found: axes.len(),
            });
        }
        if let Some(&a) = axes.iter().find(|&&a| a >= n) {
            return Err(BernsteinError::Axis { axis: a, dim: n });
        }
        let mut degrees = vec![0; n];
        for (k, &a) in axes.iter().enumerate() {
            degrees[a] = self.degrees[k];
        }
        Ok(Bernstein {
            degrees,
            coeffs: self.coeffs.clone(),
        })
    }

    /// `p / t_axis` (`upper = false`) or `p / (1 − t_axis)` when `p` vanishes identically on
    /// that face (every face coefficient exactly zero), else `None`. Exact in Bernstein form:
    /// `b'_j = b_{j+1}·d/(j+1)`, resp. `b'_j = b_j·d/(d−j)`, `j < d`.
    pub fn divide_by_face(&self, axis: usize, upper: bool) -> Result<Option<Self>, BernsteinError> {
        self.check_axis(axis)?;
        let d = self.degrees[axis];
        let face = self.face(axis, upper)?;
        if d == 0 || !face.coeffs.iter().all(Field::is_exact_zero) {
            return Ok(None);
        }
        let coeffs = map_lines(
            &self.degrees,
            &self.coeffs,
            axis,
            d,
            &T::zero(),
            |line, out| {
                for (j, o) in out.iter_mut().enumerate() {
                    *o = if upper {
                        line[j].mul(&T::from_ratio(d as i64, (d - j) as i64))
                    } else {
                        line[j + 1].mul(&T::from_ratio(d as i64, (j + 1) as i64))
                    };
                }
            },
        );
        let mut degrees = self.degrees.clone();
        degrees[axis] = d - 1;
        Ok(Some(Bernstein { degrees, coeffs }))
    }

    /// The same polynomial at its exact degree per axis (the highest power actually present);
    /// never higher than the current degrees. Per axis, while the leading power coefficient
    /// (the top forward difference `Δ^d b` of every line along it) vanishes, the degree is
    /// reduced by inverting degree elevation, `c₀ = b₀`, `cᵢ = (d·bᵢ − i·cᵢ₋₁)/(d − i)`
    /// (exact then); the Bernstein form at given degrees is unique, so this is the power
    /// basis's answer without converting to it.
    pub fn at_exact_degrees(&self) -> Self {
        let mut p = self.clone();
        for axis in 0..p.dim() {
            while p.degrees[axis] > 0 && p.top_difference_vanishes(axis) {
                p = p.reduced(axis);
            }
        }
        p
    }

    /// Whether `Δ^d b` vanishes on every line along `axis` (`d ≥ 1` its degree there): the
    /// coefficient of `t_axis^d` in the power basis is `Δ^d b` times other variables' terms.
    fn top_difference_vanishes(&self, axis: usize) -> bool {
        let d = self.degrees[axis];
        let weights: Vec<T> = (0..=d)
            .map(|k| {
                let w = ratio::<T>(binomial(d, k), BigInt::from(1));
                if (d - k).is_multiple_of(2) {
                    w
                } else {
                    w.neg()
                }
            })
            .collect();
        map_lines(
            &self.degrees,
            &self.coeffs,
            axis,
            1,
            &T::zero(),
            |line, out| {
                out[0] = line
                    .iter()
                    .zip(&weights)
                    .fold(T::zero(), |acc, (b, w)| acc.add(&b.mul(w)));
            },
        )
        .iter()
        .all(Field::is_exact_zero)
    }

    /// Degree `d − 1` along `axis` by inverting elevation; exact when
    /// [`top_difference_vanishes`](Self::top_difference_vanishes).
    fn reduced(&self, axis: usize) -> Self {
        let d = self.degrees[axis];
        let coeffs = map_lines(
            &self.degrees,
            &self.coeffs,
            axis,
            d,
            &T::zero(),
            |line, out| {
                out[0] = line[0].clone();
                for i in 1..d {
                    let c = line[i]
                        .mul_int(d as i64)
                        .sub(&out[i - 1].mul_int(i as i64))
                        .mul(&T::from_ratio(1, (d - i) as i64));
                    out[i] = c;
                }
            },
        );
        let mut degrees = self.degrees.clone();
        degrees[axis] = d - 1;
        Bernstein { degrees, coeffs }
    }

    /// Every coefficient times `k`.
    pub fn scale(&self, k: &T) -> Self {
        self.map(|c| c.mul(k))
    }

    /// Converts power-basis coefficients `a` (`p = Σ a_j Π t_a^{j_a}`, same layout and
    /// degrees) to Bernstein form: per axis `b_i = Σ_{j≤i} C(i,j)/C(d,j) a_j`.
    pub fn from_power(degrees: Vec<usize>, power: Vec<T>) -> Result<Self, BernsteinError> {
        let mut p = Bernstein::new(degrees, power)?;
        for axis in 0..p.dim() {
            let d = p.degrees[axis];
            p.coeffs = map_lines(
                &p.degrees,
                &p.coeffs,
                axis,
                d + 1,
                &T::zero(),
                |line, out| {
                    for (i, o) in out.iter_mut().enumerate() {
                        let mut acc = T::zero();
                        for (j, aj) in line.iter().enumerate().take(i + 1) {
                            acc = acc.add(&aj.mul(&ratio(binomial(i, j), binomial(d, j))));
                        }
                        *o = acc;
                    }
                },
            );
        }
        Ok(p)
    }

    /// The power-basis coefficients: per axis `a_j = C(d,j) Σ_{i≤j} (−1)^{j−i} C(j,i) b_i`.
    pub fn to_power(&self) -> Vec<T> {
        let mut coeffs = self.coeffs.clone();
        for axis in 0..self.dim() {
            let d = self.degrees[axis];
            coeffs = map_lines(
                &self.degrees,
                &coeffs,
                axis,
                d + 1,
                &T::zero(),
                |line, out| {
                    for (j, o) in out.iter_mut().enumerate() {
                        let mut acc = T::zero();
                        for (i, bi) in line.iter().enumerate().take(j + 1) {
                            let w = ratio::<T>(binomial(d, j) * binomial(j, i), BigInt::from(1));
                            let term = bi.mul(&w);
                            acc = if (j - i) % 2 == 0 {
                                acc.add(&term)
                            } else {
                                acc.sub(&term)
                            };
                        }
                        *o = acc;
                    }
                },
            );
        }
        coeffs
    }

    /// An enclosure of the cross-section `x_axis = t` (the axis removed, as in
    /// [`Bernstein::face`]): exact for exact types, [`Field::enclose_lines`] otherwise (a
    /// cheap test of a split plane before splitting there).
    pub fn section_enclosure(&self, axis: usize, t: &T) -> Result<Self, BernsteinError> {
        self.check_axis(axis)?;
        let len = self.degrees[axis] + 1;
        let inner: usize = self.degrees[..axis].iter().map(|d| d + 1).product();
        let mut coeffs = Vec::with_capacity(self.coeffs.len() / len);
        T::enclose_lines(&self.coeffs, len, inner, t, &mut coeffs);
        Ok(self.without_axis(axis, coeffs))
    }

    /// A polynomial of `coeffs` over this one's degrees with `axis` removed (a 1-D
    /// polynomial becomes the constant of degree 0): a face's or a cross-section's.
    fn without_axis(&self, axis: usize, coeffs: Vec<T>) -> Self {
        let mut degrees = self.degrees.clone();
        if self.dim() == 1 {
            degrees[0] = 0;
        } else {
            degrees.remove(axis);
        }
        Bernstein { degrees, coeffs }
    }

    /// The boundary slice `t_axis = 0` (`upper = false`) or `t_axis = 1`: an (n−1)-variate
    /// polynomial whose coefficients are the face's coefficients. For a 1-D polynomial the
    /// result is the 1-D constant at that end (degree 0).
    pub fn face(&self, axis: usize, upper: bool) -> Result<Self, BernsteinError> {
        self.check_axis(axis)?;
        let d = self.degrees[axis];
        let coeffs = map_lines(
            &self.degrees,
            &self.coeffs,
            axis,
            1,
            &T::zero(),
            |line, out| {
                out[0] = if upper {
                    line[d].clone()
                } else {
                    line[0].clone()
                };
            },
        );
        Ok(self.without_axis(axis, coeffs))
    }

    /// The coefficient at a vertex of the box: it equals the polynomial's value there.
    /// `corner` holds one bit per axis (bit a set: `t_a = 1`).
    pub fn vertex_coeff(&self, corner: usize) -> &T {
        let s = strides(&self.degrees);
        let mut k = 0;
        for (a, &d) in self.degrees.iter().enumerate() {
            if corner >> a & 1 == 1 {
                k += d * s[a];
            }
        }
        &self.coeffs[k]
    }
}
