//! Univariate B-splines.

use super::BsplineError;
use crate::num::{Field, Sign};

/// A univariate spline `Σ c_i N_{i,p}` on a non-decreasing knot vector.
#[derive(Clone, Debug, PartialEq)]
pub struct Spline<T> {
    degree: usize,
    knots: Vec<T>,
    coeffs: Vec<T>,
}

pub(crate) fn lt<T: Field>(a: &T, b: &T) -> bool {
    b.sub(a).sign() == Sign::Positive
}

impl<T: Field + PartialOrd> Spline<T> {
    /// A spline of degree `degree`; needs `knots.len() = coeffs.len() + degree + 1`, sorted
    /// knots and a non-empty domain `[s_p, s_n]`.
    pub fn new(degree: usize, knots: Vec<T>, coeffs: Vec<T>) -> Result<Self, BsplineError> {
        if let Some(index) = knots.windows(2).position(|w| w[1] < w[0]) {
            return Err(BsplineError::KnotsNotSorted { index: index + 1 });
        }
        if knots.len() != coeffs.len() + degree + 1 {
            return Err(BsplineError::CoefficientCount {
                degree,
                knots: knots.len(),
                expected: knots.len().saturating_sub(degree + 1),
                found: coeffs.len(),
            });
        }
        if coeffs.is_empty()
            || knots[degree].partial_cmp(&knots[coeffs.len()]) != Some(std::cmp::Ordering::Less)
        {
            return Err(BsplineError::EmptyDomain);
        }
        Ok(Spline {
            degree,
            knots,
            coeffs,
        })
    }

    /// Uniform knots `0, 1, …, n+p` (the FFD paper's uniform basis), domain `[p, n]`.
    pub fn uniform(degree: usize, coeffs: Vec<T>) -> Result<Self, BsplineError> {
        let knots = (0..coeffs.len() + degree + 1)
            .map(|i| T::from_ratio(i as i64, 1))
            .collect();
        Spline::new(degree, knots, coeffs)
    }

    /// The degree `p`.
    pub fn degree(&self) -> usize {
        self.degree
    }
    /// The knot vector.
    pub fn knots(&self) -> &[T] {
        &self.knots
    }
    /// The B-spline coefficients.
    pub fn coeffs(&self) -> &[T] {
        &self.coeffs
    }

    /// The domain `[s_p, s_n]`.
    pub fn domain(&self) -> (T, T) {
        (
            self.knots[self.degree].clone(),
            self.knots[self.coeffs.len()].clone(),
        )
    }

    /// The non-empty knot spans inside the domain, as indices `μ` with `s_μ < s_{μ+1}`.
    pub fn spans(&self) -> Vec<usize> {
        (self.degree..self.coeffs.len())
            .filter(|&mu| self.knots[mu] < self.knots[mu + 1])
            .collect()
    }

    /// The span `μ` with `s_μ ≤ x < s_{μ+1}` (the last span for `x = s_n`).
    pub fn find_span(&self, x: &T) -> Result<usize, BsplineError> {
        let (a, b) = self.domain();
        if x < &a || x > &b {
            return Err(BsplineError::OutsideDomain);
        }
        let spans = self.spans();
        for &mu in spans.iter().rev() {
            if &self.knots[mu] <= x {
                return Ok(mu);
            }
        }
        Ok(spans[0])
    }

    /// The blossom (polar form) of the polynomial piece on span `mu` at `args` (`p` values):
    /// de Boor's algorithm with argument `y_r` at level `r`:
    /// `c_i^[r] = ((s_{i+p+1−r} − y_r) c_{i−1}^[r−1] + (y_r − s_i) c_i^[r−1]) / (s_{i+p+1−r} − s_i)`
    /// (Ramshaw; de Boor's algorithm, NOTES.md "Coefficients through blossoms").
    pub fn blossom(&self, mu: usize, args: &[T]) -> T {
        let p = self.degree;
        debug_assert_eq!(args.len(), p);
        let mut c: Vec<T> = self.coeffs[mu - p..=mu].to_vec();
        for (r, y) in args.iter().enumerate().map(|(r, y)| (r + 1, y)) {
            // entries k = r..=p correspond to i = mu - p + k
            for k in (r..=p).rev() {
                let i = mu - p + k;
                let lo = &self.knots[i];
                let hi = &self.knots[i + p + 1 - r];
                let den = hi.sub(lo);
                c[k] = hi
                    .sub(y)
                    .mul(&c[k - 1])
                    .add(&y.sub(lo).mul(&c[k]))
                    .div(&den);
            }
        }
        c[p].clone()
    }

    /// The blossom's weights: `F(args) = Σ_k w_k c_{mu−p+k}` (the blossom is linear in the
    /// coefficients). De Boor's recurrence of [`blossom`](Self::blossom) run on the weight
    /// vectors, one division per step.
    pub fn blossom_weights(&self, mu: usize, args: &[T]) -> Vec<T> {
        let p = self.degree;
        debug_assert_eq!(args.len(), p);
        // w[k]: the weights of c_k^[r] on c_{mu−p}, …, c_mu (non-zero only at k−r..=k).
        let mut w: Vec<Vec<T>> = (0..=p)
            .map(|k| {
                let mut e = vec![T::zero(); p + 1];
                e[k] = T::one();
                e
            })
            .collect();
        for (r, y) in args.iter().enumerate().map(|(r, y)| (r + 1, y)) {
            for k in (r..=p).rev() {
                let i = mu - p + k;
                let lo = &self.knots[i];
                let hi = &self.knots[i + p + 1 - r];
                let den = hi.sub(lo);
                let (a, b) = (hi.sub(y).div(&den), y.sub(lo).div(&den));
                let (below, this) = w.split_at_mut(k);
                for (j, t) in this[0].iter_mut().enumerate().take(k + 1).skip(k - r) {
                    *t = a.mul(&below[k - 1][j]).add(&b.mul(t));
                }
            }
        }
        w.swap_remove(p)
    }

    /// The Bézier coefficients of [`bezier_on`](Self::bezier_on) as a matrix: row `i` holds
    /// the weights of `b_i = F(lo^{p−i}, hi^i)` on `c_{mu−p}, …, c_mu`. The same for every
    /// coefficient vector on these knots, so a tensor field computes it once per axis.
    pub fn bezier_matrix(&self, mu: usize, lo: &T, hi: &T) -> Vec<Vec<T>> {
        let p = self.degree;
        (0..=p)
            .map(|i| {
                let mut args = vec![lo.clone(); p - i];
                args.extend(std::iter::repeat_n(hi.clone(), i));
                self.blossom_weights(mu, &args)
            })
            .collect()
    }

    /// The value at `x` by de Boor's algorithm (the blossom on the diagonal).
    pub fn eval(&self, x: &T) -> Result<T, BsplineError> {
        let mu = self.find_span(x)?;
        Ok(self.blossom(mu, &vec![x.clone(); self.degree]))
    }

    /// The derivative: degree `p−1` on the knots without their ends, coefficients
    /// `p (c_i − c_{i−1}) / (s_{i+p} − s_i)` (de Boor, ch. X, eq. (12)). A degree-0 spline
    /// has the zero derivative (returned as degree 0).
    pub fn derivative(&self) -> Spline<T> {
        let p = self.degree;
        if p == 0 {
            return Spline {
                degree: 0,
                knots: self.knots.clone(),
                coeffs: vec![T::zero(); self.coeffs.len()],
            };
        }
        let n = self.coeffs.len();
        let coeffs = (1..n)
            .map(|i| {
                let den = self.knots[i + p].sub(&self.knots[i]);
                if den.sign() == Sign::Zero {
                    T::zero()
                } else {
                    self.coeffs[i]
                        .sub(&self.coeffs[i - 1])
                        .mul_int(p as i64)
                        .div(&den)
                }
            })
            .collect();
        Spline {
            degree: p - 1,
            knots: self.knots[1..self.knots.len() - 1].to_vec(),
            coeffs,
        }
    }

    /// Boehm's algorithm: inserts `x` once (strictly inside the domain). The function is unchanged;
    /// `c'_i = α_i c_i + (1 − α_i) c_{i−1}` with `α_i = (x − s_i)/(s_{i+p} − s_i)` for `μ−p < i ≤ μ`.
    pub fn insert_knot(&self, x: &T) -> Result<Spline<T>, BsplineError> {
        let (a, b) = self.domain();
        if !(&a < x && x < &b) {
            return Err(BsplineError::KnotOutsideDomain {
                what: format!("{:?}", x),
            });
        }
        let p = self.degree;
        let mu = self.find_span(x)?;
        let mut coeffs = Vec::with_capacity(self.coeffs.len() + 1);
        for i in 0..=self.coeffs.len() {
            let c = if i + p <= mu {
                self.coeffs[i].clone()
            } else if i > mu {
                self.coeffs[i - 1].clone()
            } else {
                let alpha = x
                    .sub(&self.knots[i])
                    .div(&self.knots[i + p].sub(&self.knots[i]));
                alpha
                    .mul(&self.coeffs[i])
                    .add(&T::one().sub(&alpha).mul(&self.coeffs[i - 1]))
            };
            coeffs.push(c);
        }
        let mut knots = self.knots.clone();
        knots.insert(mu + 1, x.clone());
        Ok(Spline {
            degree: p,
            knots,
            coeffs,
        })
    }

    /// The Oslo algorithm in blossom form: inserts all of `xs` at once. Each coefficient of the
    /// refined spline is the blossom `c'_j = F(τ_{j+1}, …, τ_{j+p})` of the piece on a non-empty
    /// interval of `N_j`'s support (Cohen–Lyche–Riesenfeld 1980; Ramshaw 1989).
    pub fn insert_knots(&self, xs: &[T]) -> Result<Spline<T>, BsplineError> {
        let (a, b) = self.domain();
        for x in xs {
            if !(&a < x && x < &b) {
                return Err(BsplineError::KnotOutsideDomain {
                    what: format!("{:?}", x),
                });
            }
        }
        let mut tau = self.knots.clone();
        tau.extend(xs.iter().cloned());
        tau.sort_by(|x, y| x.partial_cmp(y).expect("finite knots"));
        let p = self.degree;
        let m = tau.len() - p - 1;
        let coeffs = (0..m)
            .map(|j| {
                let mu = self.span_for_support(&tau, j);
                self.blossom(mu, &tau[j + 1..j + p + 1])
            })
            .collect();
        Ok(Spline {
            degree: p,
            knots: tau,
            coeffs,
        })
    }

    /// A span of `self` containing a non-empty interval `[τ_k, τ_{k+1})`, `j ≤ k ≤ j+p`, of the
    /// refined knots inside the domain; the nearest domain span when there is none.
    fn span_for_support(&self, tau: &[T], j: usize) -> usize {
        let (a, b) = self.domain();
        for k in j..=j + self.degree {
            if tau[k] < tau[k + 1] && tau[k] >= a && tau[k + 1] <= b {
                return self.find_span(&tau[k]).expect("inside the domain");
            }
        }
        let spans = self.spans();
        if tau[j] < a {
            spans[0]
        } else {
            *spans.last().expect("non-empty domain")
        }
    }

    /// The Bézier control values of the piece on `[lo, hi]` (inside span `mu`):
    /// `b_i = F(lo^{p−i}, hi^i)` (blossom form of the Bernstein coefficients).
    pub fn bezier_on(&self, mu: usize, lo: &T, hi: &T) -> Vec<T> {
        let p = self.degree;
        (0..=p)
            .map(|i| {
                let mut args = vec![lo.clone(); p - i];
                args.extend(std::iter::repeat_n(hi.clone(), i));
                self.blossom(mu, &args)
            })
            .collect()
    }

    /// All Bézier pieces on the domain: `(lo, hi, control values)` per non-empty span.
    pub fn bezier_pieces(&self) -> Vec<(T, T, Vec<T>)> {
        self.spans()
            .into_iter()
            .map(|mu| {
                let (lo, hi) = (self.knots[mu].clone(), self.knots[mu + 1].clone());
                let b = self.bezier_on(mu, &lo, &hi);
                (lo, hi, b)
            })
            .collect()
    }

    /// The Bézier pieces by knot insertion: raises every interior breakpoint to multiplicity
    /// `p` with the Oslo algorithm and reads the pieces off (an independent route to
    /// [`bezier_pieces`](Self::bezier_pieces); the ends are handled by the blossom at the ends).
    pub fn bezier_pieces_by_insertion(&self) -> Result<Vec<(T, T, Vec<T>)>, BsplineError> {
        let p = self.degree;
        let (a, b) = self.domain();
        let mut extra = Vec::new();
        let mut i = 0;
        while i < self.knots.len() {
            let mut j = i;
            while j + 1 < self.knots.len() && self.knots[j + 1] == self.knots[i] {
                j += 1;
            }
            let x = &self.knots[i];
            if &a < x && x < &b {
                for _ in (j - i + 1)..p {
                    extra.push(x.clone());
                }
            }
            i = j + 1;
        }
        let refined = if extra.is_empty() {
            self.clone()
        } else {
            self.insert_knots(&extra)?
        };
        // In the refined spline every interior breakpoint has multiplicity ≥ p, so the piece on
        // span μ has Bézier coefficients c_{μ−p..μ} once the ends are clamped too.
        let mut out = Vec::new();
        for mu in refined.spans() {
            let lo = refined.knots[mu].clone();
            let hi = refined.knots[mu + 1].clone();
            let clamped_left = refined.knots[mu + 1 - p..=mu].iter().all(|k| k == &lo);
            let clamped_right = refined.knots[mu + 1..=mu + p].iter().all(|k| k == &hi);
            let b = if clamped_left && clamped_right {
                refined.coeffs[mu - p..=mu].to_vec()
            } else {
                refined.bezier_on(mu, &lo, &hi)
            };
            out.push((lo, hi, b));
        }
        Ok(out)
    }

    /// Multiplicity of `x` among the knots.
    pub fn multiplicity(&self, x: &T) -> usize {
        self.knots.iter().filter(|k| *k == x).count()
    }
}
