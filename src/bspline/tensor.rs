//! Tensor-product B-splines (trivariate is the FFD's case) and their Bézier cells.

use super::{morken::morken_product, morken::product_knots, BsplineError, Spline};
use crate::bernstein::poly::{coefficient_count, map_lines};
use crate::bernstein::{Bernstein, ScaledBernstein};
use crate::num::{Field, Rational};
use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::{One, Zero};
use std::sync::{Arc, Mutex, OnceLock};

/// `Σ c_{i₀…} Π_a N^{(a)}_{i_a, p_a}(x_a)`, coefficients with axis 0 fastest.
#[derive(Clone, Debug, PartialEq)]
pub struct TensorSpline<T> {
    degrees: Vec<usize>,
    knots: Vec<Vec<T>>,
    coeffs: Vec<T>,
}

/// One Bézier cell of a tensor spline: the span indices, the cell's box and its Bernstein form
/// on that box (reparametrised to the unit box).
#[derive(Clone, Debug, PartialEq)]
pub struct BezierCell<T> {
    /// Per axis, the index of the knot span the cell covers.
    pub spans: Vec<usize>,
    /// Per axis, the cell's parameter interval.
    pub bounds: Vec<(T, T)>,
    /// The spline on the cell, in Bernstein form over `bounds`.
    pub poly: Bernstein<T>,
}

impl<T: Field + PartialOrd> TensorSpline<T> {
    /// Checks each axis as a univariate spline would be checked.
    pub fn new(
        degrees: Vec<usize>,
        knots: Vec<Vec<T>>,
        coeffs: Vec<T>,
    ) -> Result<Self, BsplineError> {
        if degrees.len() != knots.len() {
            return Err(BsplineError::DimensionMismatch {
                expected: degrees.len(),
                found: knots.len(),
            });
        }
        let counts: Vec<usize> = degrees
            .iter()
            .zip(&knots)
            .map(|(p, k)| k.len().saturating_sub(p + 1))
            .collect();
        let expected: usize = counts.iter().product();
        if coeffs.len() != expected {
            return Err(BsplineError::CoefficientCount {
                degree: degrees[0],
                knots: knots[0].len(),
                expected,
                found: coeffs.len(),
            });
        }
        for (a, (&p, k)) in degrees.iter().zip(&knots).enumerate() {
            // Validate the axis with a dummy spline.
            Spline::new(p, k.clone(), vec![T::zero(); counts[a]])?;
        }
        Ok(TensorSpline {
            degrees,
            knots,
            coeffs,
        })
    }

    /// Degree per axis.
    pub fn degrees(&self) -> &[usize] {
        &self.degrees
    }
    /// Knot vector per axis.
    pub fn knots(&self) -> &[Vec<T>] {
        &self.knots
    }
    /// The coefficients, axis 0 fastest.
    pub fn coeffs(&self) -> &[T] {
        &self.coeffs
    }
    /// The number of variables.
    pub fn dim(&self) -> usize {
        self.degrees.len()
    }

    /// Coefficient counts per axis.
    pub fn counts(&self) -> Vec<usize> {
        self.degrees
            .iter()
            .zip(&self.knots)
            .map(|(p, k)| k.len() - p - 1)
            .collect()
    }

    fn axis_spline(&self, axis: usize, coeffs: Vec<T>) -> Spline<T> {
        Spline::new(self.degrees[axis], self.knots[axis].clone(), coeffs)
            .expect("validated at construction")
    }

    /// The value at a point, axis by axis with de Boor's algorithm.
    pub fn eval(&self, x: &[T]) -> Result<T, BsplineError> {
        if x.len() != self.dim() {
            return Err(BsplineError::DimensionMismatch {
                expected: self.dim(),
                found: x.len(),
            });
        }
        let mut counts = self.counts();
        let mut coeffs = self.coeffs.clone();
        for a in 0..self.dim() {
            let degs: Vec<usize> = counts.iter().map(|c| c - 1).collect();
            let mut err = None;
            coeffs = map_lines(&degs, &coeffs, a, 1, &T::zero(), |line, out| {
                match self.axis_spline(a, line.to_vec()).eval(&x[a]) {
                    Ok(v) => out[0] = v,
                    Err(e) => err = Some(e),
                }
            });
            if let Some(e) = err {
                return Err(e);
            }
            counts[a] = 1;
        }
        Ok(coeffs[0].clone())
    }

    /// Every Bézier cell (one per combination of non-empty spans), by blossoming per axis.
    pub fn bezier_cells(&self) -> Vec<BezierCell<T>> {
        self.cells_with(|s, spans| {
            Ok::<_, BsplineError>(
                spans
                    .iter()
                    .map(|(mu, lo, hi)| s.bezier_on(*mu, lo, hi))
                    .collect(),
            )
        })
        .expect("blossoming cannot fail")
    }

    /// Every Bézier cell by knot insertion (Oslo) along each axis: every interior breakpoint is
    /// raised to multiplicity `p` and the pieces are read off (Farin, ch. 8; the paper's
    /// Section 6, step 3). An independent route to [`bezier_cells`](Self::bezier_cells).
    pub fn bezier_cells_by_insertion(&self) -> Result<Vec<BezierCell<T>>, BsplineError> {
        self.cells_with(|s, _| {
            Ok(s.bezier_pieces_by_insertion()?
                .into_iter()
                .map(|(_, _, b)| b)
                .collect())
        })
    }

    /// The polynomial piece on `bounds` (a box inside one non-empty knot span per axis), in
    /// Bernstein form over `bounds`: per axis the blossom `b_i = F(lo^{p−i}, hi^i)` on every
    /// line. Fails when the box leaves the domain or crosses a knot strictly inside it.
    pub fn bezier_on_box(&self, bounds: &[(T, T)]) -> Result<Bernstein<T>, BsplineError> {
        let n = self.dim();
        if bounds.len() != n {
            return Err(BsplineError::DimensionMismatch {
                expected: n,
                found: bounds.len(),
            });
        }
        let mut counts = self.counts();
        let mut coeffs = self.coeffs.clone();
        for (a, (lo, hi)) in bounds.iter().enumerate() {
            let probe = self.axis_spline(a, vec![T::zero(); counts[a]]);
            let mu = probe
                .spans()
                .into_iter()
                .find(|&mu| &self.knots[a][mu] <= lo && hi <= &self.knots[a][mu + 1])
                .filter(|_| lo <= hi)
                .ok_or(BsplineError::CrossesKnot { axis: a })?;
            let p = self.degrees[a];
            let degs: Vec<usize> = counts.iter().map(|c| c - 1).collect();
            let m = probe.bezier_matrix(mu, lo, hi);
            coeffs = map_lines(&degs, &coeffs, a, p + 1, &T::zero(), |line, out| {
                let line = &line[mu - p..=mu];
                for (o, row) in out.iter_mut().zip(&m) {
                    *o = T::dot(row, line);
                }
            });
            counts[a] = p + 1;
        }
        Ok(Bernstein::new(self.degrees.clone(), coeffs)?)
    }

    /// `axis` names one of the variables.
    fn check_axis(&self, axis: usize) -> Result<(), BsplineError> {
        if axis >= self.dim() {
            return Err(BsplineError::DimensionMismatch {
                expected: self.dim(),
                found: axis + 1,
            });
        }
        Ok(())
    }

    /// The field on the plane `x_axis = x`: a tensor spline in the other `dim − 1` variables
    /// (same degrees and knots there), each line along `axis` contracted with the basis
    /// values `N_{i,p}(x)` — the blossom's weights on the diagonal `(x, …, x)`, the same for
    /// every line. Needs at least two variables and `x` in the axis' domain.
    pub fn restrict_axis(&self, axis: usize, x: &T) -> Result<TensorSpline<T>, BsplineError> {
        self.check_axis(axis)?;
        if self.dim() < 2 {
            return Err(BsplineError::DimensionMismatch {
                expected: 2,
                found: self.dim(),
            });
        }
        let counts = self.counts();
        let line = self.axis_spline(axis, vec![T::zero(); counts[axis]]);
        let mu = line.find_span(x)?;
        let p = self.degrees[axis];
        let weights = line.blossom_weights(mu, &vec![x.clone(); p]);
        let degs: Vec<usize> = counts.iter().map(|c| c - 1).collect();
        let coeffs = map_lines(&degs, &self.coeffs, axis, 1, &T::zero(), |l, out| {
            out[0] = T::dot(&weights, l[mu - p..=mu].iter());
        });
        let mut degrees = self.degrees.clone();
        degrees.remove(axis);
        let mut knots = self.knots.clone();
        knots.remove(axis);
        TensorSpline::new(degrees, knots, coeffs)
    }

    /// The same field with the knots `xs` (strictly inside the domain) inserted along `axis`
    /// on every line (the Oslo algorithm in blossom form).
    pub fn insert_knots(&self, axis: usize, xs: &[T]) -> Result<TensorSpline<T>, BsplineError> {
        self.check_axis(axis)?;
        let counts = self.counts();
        let degs: Vec<usize> = counts.iter().map(|c| c - 1).collect();
        let refined = self
            .axis_spline(axis, vec![T::zero(); counts[axis]])
            .insert_knots(xs)?;
        let mut err = None;
        let coeffs = map_lines(
            &degs,
            &self.coeffs,
            axis,
            refined.coeffs().len(),
            &T::zero(),
            |line, out| match self.axis_spline(axis, line.to_vec()).insert_knots(xs) {
                Ok(s) => out.clone_from_slice(s.coeffs()),
                Err(e) => err = Some(e),
            },
        );
        if let Some(e) = err {
            return Err(e);
        }
        let mut knots = self.knots.clone();
        knots[axis] = refined.knots().to_vec();
        TensorSpline::new(self.degrees.clone(), knots, coeffs)
    }

    /// Converts every line along every axis into its Bézier pieces with `pieces`
    /// (`(spline, spans) → one coefficient vector per span`), then cuts the net into cells.
    fn cells_with<F>(&self, pieces: F) -> Result<Vec<BezierCell<T>>, BsplineError>
    where
        F: Fn(&Spline<T>, &[(usize, T, T)]) -> Result<Vec<Vec<T>>, BsplineError>,
    {
        let n = self.dim();
        // Per axis: the spans, and for each the Bézier pieces of every line.
        let mut counts = self.counts();
        let mut coeffs = self.coeffs.clone();
        let mut axis_spans: Vec<Vec<(usize, T, T)>> = Vec::new();
        for a in 0..n {
            let probe = self.axis_spline(a, vec![T::zero(); counts[a]]);
            let spans: Vec<(usize, T, T)> = probe
                .spans()
                .into_iter()
                .map(|mu| (mu, self.knots[a][mu].clone(), self.knots[a][mu + 1].clone()))
                .collect();
            let p = self.degrees[a];
            let new_len = spans.len() * (p + 1);
            let degs: Vec<usize> = counts.iter().map(|c| c - 1).collect();
            let mut err = None;
            coeffs = map_lines(&degs, &coeffs, a, new_len, &T::zero(), |line, out| {
                let s = self.axis_spline(a, line.to_vec());
                match pieces(&s, &spans) {
                    Ok(ps) => {
                        for (k, piece) in ps.into_iter().enumerate() {
                            for (i, v) in piece.into_iter().enumerate() {
                                out[k * (p + 1) + i] = v;
                            }
                        }
                    }
                    Err(e) => err = Some(e),
                }
            });
            if let Some(e) = err {
                return Err(e);
            }
            counts[a] = new_len;
            axis_spans.push(spans);
        }
        Ok(cut_cells(&self.degrees, &counts, &coeffs, &axis_spans))
    }

    /// `self + other` (same degrees and knots), coefficient by coefficient.
    pub fn add(&self, other: &TensorSpline<T>) -> Result<TensorSpline<T>, BsplineError> {
        self.combine(other, |a, b| a.add(b))
    }

    /// `self − other` (same degrees and knots), coefficient by coefficient.
    pub fn sub(&self, other: &TensorSpline<T>) -> Result<TensorSpline<T>, BsplineError> {
        self.combine(other, |a, b| a.sub(b))
    }

    fn combine(
        &self,
        other: &TensorSpline<T>,
        f: impl Fn(&T, &T) -> T,
    ) -> Result<TensorSpline<T>, BsplineError> {
        if self.degrees != other.degrees || self.knots != other.knots {
            return Err(BsplineError::DomainMismatch { factor: 1 });
        }
        Ok(TensorSpline {
            degrees: self.degrees.clone(),
            knots: self.knots.clone(),
            coeffs: self
                .coeffs
                .iter()
                .zip(&other.coeffs)
                .map(|(a, b)| f(a, b))
                .collect(),
        })
    }

    /// The partial derivative along `axis`: the univariate derivative
    /// `p (c_i − c_{i−1}) / (s_{i+p} − s_i)` on every line (de Boor, ch. X, eq. (12)).
    pub fn derivative(&self, axis: usize) -> Result<TensorSpline<T>, BsplineError> {
        self.check_axis(axis)?;
        let counts = self.counts();
        let degs: Vec<usize> = counts.iter().map(|c| c - 1).collect();
        let probe = self
            .axis_spline(axis, vec![T::zero(); counts[axis]])
            .derivative();
        let new_len = probe.coeffs().len();
        let coeffs = map_lines(
            &degs,
            &self.coeffs,
            axis,
            new_len,
            &T::zero(),
            |line, out| {
                let d = self.axis_spline(axis, line.to_vec()).derivative();
                out.clone_from_slice(d.coeffs());
            },
        );
        let mut degrees = self.degrees.clone();
        degrees[axis] = probe.degree();
        let mut knots = self.knots.clone();
        knots[axis] = probe.knots().to_vec();
        TensorSpline::new(degrees, knots, coeffs)
    }

    /// The Mørken product `self · other` as one tensor spline on the per-axis product knot
    /// vectors. Tensor-product basis functions multiply axis by axis, so
    /// `c_o = Σ_{i,j} a_i b_j Π_x M_x[i_x, j_x](o_x)` where `M_x[i, j]` holds the Mørken
    /// coefficients of `N_i · N_j` on axis `x` (see [`basis_product_table`]).
    pub fn product(&self, other: &TensorSpline<T>) -> Result<TensorSpline<T>, BsplineError> {
        let n = self.dim();
        if other.dim() != n {
            return Err(BsplineError::DimensionMismatch {
                expected: n,
                found: other.dim(),
            });
        }
        let tables: Vec<BasisProductTable<T>> = (0..n)
            .map(|x| {
                basis_product_table(
                    self.degrees[x],
                    &self.knots[x],
                    other.degrees[x],
                    &other.knots[x],
                )
            })
            .collect::<Result<_, _>>()?;
        let (ca, cb) = (self.counts(), other.counts());
        let cp: Vec<usize> = tables.iter().map(|t| t.count).collect();
        let sp = strides_of(&cp);
        let mut out = vec![T::zero(); cp.iter().product()];
        let mut ia = vec![0usize; n];
        for a in &self.coeffs {
            if !a.is_exact_zero() {
                let mut ib = vec![0usize; n];
                for b in &other.coeffs {
                    if !b.is_exact_zero() {
                        let lists: Vec<&[(usize, T)]> = (0..n)
                            .map(|x| tables[x].entries[ia[x] * cb[x] + ib[x]].as_slice())
                            .collect();
                        if lists.iter().all(|l| !l.is_empty()) {
                            distribute(&a.mul(b), &lists, &sp, 0, 0, &mut out);
                        }
                    }
                    step(&mut ib, &cb);
                }
            }
            step(&mut ia, &ca);
        }
        TensorSpline::new(
            tables.iter().map(|t| t.degree).collect(),
            tables.into_iter().map(|t| t.knots).collect(),
            out,
        )
    }
}

impl TensorSpline<Rational> {
    /// [`product`](TensorSpline::product) for exact rationals, in integer arithmetic: each
    /// axis table is brought to a common denominator `L_x`, each factor's coefficients to a
    /// common denominator, the contraction runs on integers and one rational per output
    /// coefficient is formed at the end (no gcd inside the loop). Same result, exactly.
    pub fn product_exact(&self, other: &TensorSpline<Rational>) -> Result<Self, BsplineError> {
        self.product_exact_cached(other, &mut TableCache::default())
    }

    /// [`bezier_cells_by_insertion`](TensorSpline::bezier_cells_by_insertion) in integer
    /// arithmetic, with the same result exactly. Along each axis the Oslo map (line → its
    /// Bézier pieces by knot insertion) is linear and depends on the knots only: it is formed
    /// once, from the unit lines, brought to a common denominator and applied to every line in
    /// integers; the coefficients stay over one shared denominator until the cells are cut.
    pub fn bezier_cells_by_insertion_exact(
        &self,
    ) -> Result<Vec<BezierCell<Rational>>, BsplineError> {
        let (nums, den) = common_denominator(&self.coeffs);
        let (nums, den, counts, axis_spans) =
            insert_to_bezier(&self.degrees, &self.knots, self.counts(), nums, den)?;
        let coeffs: Vec<Rational> = nums
            .into_iter()
            .map(|v| Rational::new(v, den.clone()))
            .collect();
        Ok(cut_cells(&self.degrees, &counts, &coeffs, &axis_spans))
    }

    /// [`bezier_on_box`](TensorSpline::bezier_on_box) for exact rationals, with the same
    /// result exactly. Per axis the span's rows of the memoised integer Oslo map (the Bézier
    /// piece on the whole knot span, a linear map of the line that depends on the knots only)
    /// are applied to every line in integers over one shared denominator; the piece is then
    /// cut to `bounds` by de Casteljau subdivision where the box is smaller than the span.
    pub fn bezier_on_box_exact(
        &self,
        bounds: &[(Rational, Rational)],
    ) -> Result<Bernstein<Rational>, BsplineError> {
        let n = self.dim();
        if bounds.len() != n || bounds.iter().any(|(lo, hi)| lo >= hi) {
            // Mismatched or flat boxes (a Bernstein form on a point): the blossom route.
            return self.bezier_on_box(bounds);
        }
        let mut counts = self.counts();
        let (mut nums, mut den) = common_denominator(&self.coeffs);
        let mut sub = Vec::with_capacity(n);
        for (a, (lo, hi)) in bounds.iter().enumerate() {
            let p = self.degrees[a];
            let map = oslo_map(p, &self.knots[a])?;
            let j = map
                .spans
                .iter()
                .position(|(_, k0, k1)| k0 <= lo && hi <= k1)
                .ok_or(BsplineError::CrossesKnot { axis: a })?;
            let (_, k0, k1) = &map.spans[j];
            let rows = &map.rows[j * (p + 1)..(j + 1) * (p + 1)];
            let degs: Vec<usize> = counts.iter().map(|c| c - 1).collect();
            nums = map_lines(&degs, &nums, a, p + 1, &BigInt::zero(), |line, out| {
                apply_rows(rows, line, out)
            });
            den *= &map.scale;
            counts[a] = p + 1;
            let width = k1 - k0;
            sub.push(((lo - k0) / &width, (hi - k0) / &width));
        }
        let coeffs = nums
            .into_iter()
            .map(|v| Rational::new(v, den.clone()))
            .collect();
        let cell = Bernstein::new(self.degrees.clone(), coeffs)?;
        let whole = sub.iter().all(|(a, b)| a.is_zero() && b.is_one());
        if whole {
            Ok(cell)
        } else {
            Ok(cell.restrict(&sub)?)
        }
    }

    /// [`product_exact`](Self::product_exact) reusing per-axis tables from `cache` (products
    /// of factors with the same degrees and knots share them).
    pub fn product_exact_cached(
        &self,
        other: &TensorSpline<Rational>,
        cache: &mut TableCache,
    ) -> Result<Self, BsplineError> {
        let [a, b] = ScaledSpline::common(&[self, other])
            .try_into()
            .expect("two splines");
        a.product(&b, cache)?.to_rational()
    }
}

/// A tensor spline with integer coefficients over one denominator, `c_i = nums_i / den`:
/// Mørken products, sums and differences of such splines need no gcd per coefficient, so a
/// polynomial expression of splines (a Jacobian determinant) reduces once, at the end.
#[derive(Clone, Debug, PartialEq)]
pub struct ScaledSpline {
    degrees: Vec<usize>,
    knots: Vec<Vec<Rational>>,
    nums: Vec<BigInt>,
    den: BigInt,
}

impl ScaledSpline {
    /// The splines over one shared denominator (the lcm of all their coefficients').
    pub fn common(splines: &[&TensorSpline<Rational>]) -> Vec<ScaledSpline> {
        let den = lcm_of_denominators(splines.iter().flat_map(|s| s.coeffs.iter()));
        splines
            .iter()
            .map(|s| ScaledSpline {
                degrees: s.degrees.clone(),
                knots: s.knots.clone(),
                nums: s.coeffs.iter().map(|c| scaled_by(c, &den)).collect(),
                den: den.clone(),
            })
            .collect()
    }

    /// The Mørken product `self · other` over `den_a · den_b · Π_x scale_x` (the tables'
    /// common denominators), contracted in `i128` when every factor fits, else in `BigInt`.
    pub fn product(
        &self,
        other: &ScaledSpline,
        cache: &mut TableCache,
    ) -> Result<ScaledSpline, BsplineError> {
        let n = self.degrees.len();
        if other.degrees.len() != n {
            return Err(BsplineError::DimensionMismatch {
                expected: n,
                found: other.degrees.len(),
            });
        }
        let mut tables: Vec<Arc<IntTable>> = Vec::with_capacity(n);
        for x in 0..n {
            tables.push(cache.table(
                self.degrees[x],
                &self.knots[x],
                other.degrees[x],
                &other.knots[x],
            )?);
        }
        let den = tables
            .iter()
            .fold(&self.den * &other.den, |d, t| d * &t.scale);
        let (ca, cb) = (
            counts_of(&self.degrees, &self.knots),
            counts_of(&other.degrees, &other.knots),
        );
        let cp: Vec<usize> = tables.iter().map(|t| t.table.count).collect();
        let sp = strides_of(&cp);
        let counts = (ca.as_slice(), cb.as_slice());
        let nums = contract_small(&self.nums, &other.nums, &tables, counts, &sp)
            .unwrap_or_else(|| contract_big(&self.nums, &other.nums, &tables, counts, &sp));
        Ok(ScaledSpline {
            degrees: tables.iter().map(|t| t.table.degree).collect(),
            knots: tables.iter().map(|t| t.table.knots.clone()).collect(),
            nums,
            den,
        })
    }

    /// `self + other` (same degrees and knots).
    pub fn add(&self, other: &ScaledSpline) -> Result<ScaledSpline, BsplineError> {
        self.combine(other, |a, b| a + b)
    }

    /// `self − other` (same degrees and knots).
    pub fn sub(&self, other: &ScaledSpline) -> Result<ScaledSpline, BsplineError> {
        self.combine(other, |a, b| a - b)
    }

    /// Coefficient by coefficient over the common denominator (the product of the two when
    /// they differ).
    fn combine(
        &self,
        other: &ScaledSpline,
        f: impl Fn(BigInt, BigInt) -> BigInt,
    ) -> Result<ScaledSpline, BsplineError> {
        if self.degrees != other.degrees || self.knots != other.knots {
            return Err(BsplineError::DomainMismatch { factor: 1 });
        }
        let same = self.den == other.den;
        let nums = self
            .nums
            .iter()
            .zip(&other.nums)
            .map(|(a, b)| {
                if same {
                    f(a.clone(), b.clone())
                } else {
                    f(a * &other.den, b * &self.den)
                }
            })
            .collect();
        let den = if same {
            self.den.clone()
        } else {
            &self.den * &other.den
        };
        Ok(ScaledSpline {
            degrees: self.degrees.clone(),
            knots: self.knots.clone(),
            nums,
            den,
        })
    }

    /// The Bézier form of every cell (knot span product, axis 0 fastest, as
    /// [`TensorSpline::bezier_cells_by_insertion_exact`]) by knot insertion in integers: the
    /// cells share one denominator and no gcd is taken, so signs (positivity certificates)
    /// are read off directly.
    pub fn bezier_cells(&self) -> Result<Vec<ScaledBernstein>, BsplineError> {
        let counts = counts_of(&self.degrees, &self.knots);
        let (nums, den, counts, axis_spans) = insert_to_bezier(
            &self.degrees,
            &self.knots,
            counts,
            self.nums.clone(),
            self.den.clone(),
        )?;
        let cell_counts: Vec<usize> = axis_spans.iter().map(Vec::len).collect();
        let total: usize = cell_counts.iter().product();
        (0..total)
            .map(|flat| {
                let (_, local) = gather_cell(&self.degrees, &counts, &cell_counts, &nums, flat);
                Ok(ScaledBernstein::with_denominator(
                    self.degrees.clone(),
                    local,
                    den.clone(),
                )?)
            })
            .collect()
    }

    /// The spline with rational coefficients in lowest terms.
    pub fn to_rational(&self) -> Result<TensorSpline<Rational>, BsplineError> {
        TensorSpline::new(
            self.degrees.clone(),
            self.knots.clone(),
            self.nums
                .iter()
                .map(|v| Rational::new(v.clone(), self.den.clone()))
                .collect(),
        )
    }
}

/// Coefficients per axis of a spline with these degrees and knot vectors.
fn counts_of(degrees: &[usize], knots: &[Vec<Rational>]) -> Vec<usize> {
    degrees
        .iter()
        .zip(knots)
        .map(|(p, k)| k.len().saturating_sub(p + 1))
        .collect()
}

/// Cuts a net of concatenated Bézier pieces (per axis `spans.len() · (p + 1)` coefficients,
/// `counts` per axis) into one Bézier cell per combination of spans.
fn cut_cells<T: Field>(
    degrees: &[usize],
    counts: &[usize],
    coeffs: &[T],
    axis_spans: &[Vec<(usize, T, T)>],
) -> Vec<BezierCell<T>> {
    let cell_counts: Vec<usize> = axis_spans.iter().map(|s| s.len()).collect();
    let total: usize = cell_counts.iter().product();
    (0..total)
        .map(|flat| {
            let (cell, local) = gather_cell(degrees, counts, &cell_counts, coeffs, flat);
            BezierCell {
                spans: cell
                    .iter()
                    .enumerate()
                    .map(|(a, &k)| axis_spans[a][k].0)
                    .collect(),
                bounds: cell
                    .iter()
                    .enumerate()
                    .map(|(a, &k)| (axis_spans[a][k].1.clone(), axis_spans[a][k].2.clone()))
                    .collect(),
                poly: Bernstein::new(degrees.to_vec(), local).expect("count matches"),
            }
        })
        .collect()
}

/// The integer core of Bézier extraction by knot insertion: along each axis the memoised
/// integer Oslo map is applied to every line of `nums / den` (`counts` per axis); returns the
/// concatenated Bézier pieces' numerators, their denominator, counts per axis and every
/// axis's non-empty spans `(μ, lo, hi)`.
#[allow(clippy::type_complexity)] // one private helper's tuple, unpacked at both call sites
fn insert_to_bezier(
    degrees: &[usize],
    knots: &[Vec<Rational>],
    mut counts: Vec<usize>,
    mut nums: Vec<BigInt>,
    mut den: BigInt,
) -> Result<
    (
        Vec<BigInt>,
        BigInt,
        Vec<usize>,
        Vec<Vec<(usize, Rational, Rational)>>,
    ),
    BsplineError,
> {
    let n = degrees.len();
    let mut axis_spans = Vec::with_capacity(n);
    for a in 0..n {
        let map = oslo_map(degrees[a], &knots[a])?;
        let (rows, l, spans) = (&map.rows, &map.scale, map.spans.clone());
        let new_len = rows.len();
        den *= l;
        let degs: Vec<usize> = counts.iter().map(|c| c - 1).collect();
        nums = map_lines(&degs, &nums, a, new_len, &BigInt::zero(), |line, out| {
            apply_rows(rows, line, out)
        });
        counts[a] = new_len;
        axis_spans.push(spans);
    }
    Ok((nums, den, counts, axis_spans))
}

/// The cell of flat index `flat` (axis 0 fastest) among `cell_counts` cells per axis, and its
/// Bézier coefficients gathered from the concatenated pieces (`counts` per axis).
fn gather_cell<T: Clone>(
    degrees: &[usize],
    counts: &[usize],
    cell_counts: &[usize],
    coeffs: &[T],
    flat: usize,
) -> (Vec<usize>, Vec<T>) {
    let mut rem = flat;
    let cell: Vec<usize> = cell_counts
        .iter()
        .map(|&c| {
            let i = rem % c;
            rem /= c;
            i
        })
        .collect();
    let m = coefficient_count(degrees);
    let mut local = Vec::with_capacity(m);
    for lf in 0..m {
        let mut r = lf;
        let mut g = 0;
        let mut stride = 1;
        for (a, &d) in degrees.iter().enumerate() {
            let i = r % (d + 1);
            r /= d + 1;
            g += (cell[a] * (d + 1) + i) * stride;
            stride *= counts[a];
        }
        local.push(coeffs[g].clone());
    }
    (cell, local)
}

/// `out_i = Σ_k w · line_k` over the sparse integer `rows` (`(k, w)` pairs) of a linear map.
fn apply_rows(rows: &[Vec<(usize, BigInt)>], line: &[BigInt], out: &mut [BigInt]) {
    for (o, row) in out.iter_mut().zip(rows) {
        let mut acc = BigInt::zero();
        for (k, w) in row {
            if !line[*k].is_zero() {
                acc += &line[*k] * w;
            }
        }
        *o = acc;
    }
}

/// The Oslo map of one axis in integers: `rows[i]` holds the nonzero `(k, w)` with
/// `piece_i = Σ_k w · c_k / scale`, the Bézier pieces (concatenated, `p + 1` per span) of a
/// line `c` by knot insertion; `spans` are `(μ, lo, hi)` of the non-empty spans.
pub(crate) struct OsloMap {
    rows: Vec<Vec<(usize, BigInt)>>,
    scale: BigInt,
    spans: Vec<(usize, Rational, Rational)>,
}

/// [`OsloMap`] of degree `p` on `knots`: each column is the insertion route
/// ([`Spline::bezier_pieces_by_insertion`]) applied to a unit line. Memoised per process
/// (bounded like the product tables): the map depends on the knots only.
fn oslo_map(p: usize, knots: &[Rational]) -> Result<Arc<OsloMap>, BsplineError> {
    static MEMO: OnceLock<Memo<(usize, Vec<Rational>), OsloMap>> = OnceLock::new();
    memoised(&MEMO, (p, knots.to_vec()), || compute_oslo_map(p, knots))
}

fn compute_oslo_map(p: usize, knots: &[Rational]) -> Result<OsloMap, BsplineError> {
    let m = knots.len().saturating_sub(p + 1);
    let unit = |k: usize| {
        let mut c = vec![<Rational as Zero>::zero(); m];
        c[k] = <Rational as One>::one();
        Spline::new(p, knots.to_vec(), c)
    };
    let mut spans = Vec::new();
    let mut columns = Vec::with_capacity(m);
    for k in 0..m {
        let line = unit(k)?;
        let pieces = line.bezier_pieces_by_insertion()?;
        if k == 0 {
            spans = line
                .spans()
                .into_iter()
                .zip(&pieces)
                .map(|(mu, (lo, hi, _))| (mu, lo.clone(), hi.clone()))
                .collect();
        }
        columns.push(
            pieces
                .into_iter()
                .flat_map(|(_, _, b)| b)
                .collect::<Vec<_>>(),
        );
    }
    let new_len = columns.first().map_or(0, Vec::len);
    let scale = lcm_of_denominators(columns.iter().flatten());
    let rows = (0..new_len)
        .map(|i| {
            columns
                .iter()
                .enumerate()
                .filter(|(_, c)| !c[i].is_zero())
                .map(|(k, c)| (k, scaled_by(&c[i], &scale)))
                .collect()
        })
        .collect();
    Ok(OsloMap { rows, scale, spans })
}

/// A process-wide memo of values that are pure functions of their keys.
type Memo<K, V> = Mutex<std::collections::HashMap<K, Arc<V>>>;

/// The memoised value of `key`, computed (outside the lock) when absent. The memo holds at
/// most [`TABLE_MEMO_CAPACITY`] values and is emptied when full (the working set of one
/// program is a handful of knot vectors). A poisoned lock only means another thread panicked
/// while holding it; the map is still valid (values are inserted whole), so it is used.
fn memoised<K: std::hash::Hash + Eq, V, E>(
    memo: &'static OnceLock<Memo<K, V>>,
    key: K,
    compute: impl FnOnce() -> Result<V, E>,
) -> Result<Arc<V>, E> {
    let memo = memo.get_or_init(Default::default);
    if let Some(v) = memo.lock().unwrap_or_else(|e| e.into_inner()).get(&key) {
        return Ok(v.clone());
    }
    let v = Arc::new(compute()?);
    let mut m = memo.lock().unwrap_or_else(|e| e.into_inner());
    if m.len() >= TABLE_MEMO_CAPACITY {
        m.clear();
    }
    m.insert(key, v.clone());
    Ok(v)
}

/// Per-axis basis product tables keyed by `(p, knots, q, knots)`: a local map in front of a
/// bounded process-wide memo. A table is a pure function of
/// its key, and computing one (Mørken products of every basis pair by blossoming) costs far
/// more than the tensor contraction that uses it; callers that check many lattices of the
/// same shape (certificate checkers, fuzzing, campaigns) compute each table once.
#[derive(Default)]
pub struct TableCache(std::collections::HashMap<TableKey, Arc<IntTable>>);

/// A basis product table with its weights over one common denominator `scale`: `ints` in
/// `BigInt`, `small` the same in `i128` when every weight fits.
pub struct IntTable {
    /// The rational table.
    pub table: BasisProductTable<Rational>,
    /// The common denominator of the weights.
    pub scale: BigInt,
    /// `entries` with each weight times `scale`.
    pub ints: Vec<Vec<(usize, BigInt)>>,
    /// `ints` in `i128`, when they fit.
    pub small: Option<Vec<Vec<(usize, i128)>>>,
}

impl IntTable {
    fn new(table: BasisProductTable<Rational>) -> IntTable {
        let scale = lcm_of_denominators(table.entries.iter().flatten().map(|(_, w)| w));
        let ints: Vec<Vec<(usize, BigInt)>> = table
            .entries
            .iter()
            .map(|e| e.iter().map(|(o, w)| (*o, scaled_by(w, &scale))).collect())
            .collect();
        let small = ints
            .iter()
            .map(|e| {
                e.iter()
                    .map(|(o, w)| i128::try_from(w).ok().map(|w| (*o, w)))
                    .collect::<Option<Vec<_>>>()
            })
            .collect::<Option<Vec<_>>>();
        IntTable {
            table,
            scale,
            ints,
            small,
        }
    }
}

/// `(p, knots of the first factor, q, knots of the second)`.
type TableKey = (usize, Vec<Rational>, usize, Vec<Rational>);

/// Most tables the process-wide memo holds; it is emptied when full (tables are small, and
/// the working set of one program is a handful of knot vectors).
pub(crate) const TABLE_MEMO_CAPACITY: usize = 512;

impl TableCache {
    /// The table for `N_{i,p}` (knots `s`) times `N_{j,q}` (knots `t`), from this cache, the
    /// process-wide memo, or [`basis_product_table`].
    pub fn table(
        &mut self,
        p: usize,
        s: &[Rational],
        q: usize,
        t: &[Rational],
    ) -> Result<Arc<IntTable>, BsplineError> {
        let key = (p, s.to_vec(), q, t.to_vec());
        if let Some(t) = self.0.get(&key) {
            return Ok(t.clone());
        }
        static MEMO: OnceLock<Memo<TableKey, IntTable>> = OnceLock::new();
        let table = memoised(&MEMO, key.clone(), || {
            basis_product_table(p, s, q, t).map(IntTable::new)
        })?;
        self.0.insert(key, table.clone());
        Ok(table)
    }
}

/// The lcm of the denominators.
fn lcm_of_denominators<'a>(cs: impl IntoIterator<Item = &'a Rational>) -> BigInt {
    cs.into_iter()
        .fold(BigInt::one(), |acc, c| acc.lcm(c.denom()))
}

/// `c · den` as an integer (`den` a multiple of `c`'s denominator).
fn scaled_by(c: &Rational, den: &BigInt) -> BigInt {
    c.numer() * (den / c.denom())
}

/// Integer numerators over the lcm of the denominators.
fn common_denominator(cs: &[Rational]) -> (Vec<BigInt>, BigInt) {
    let den = lcm_of_denominators(cs);
    (cs.iter().map(|c| scaled_by(c, &den)).collect(), den)
}

/// Calls `f(i, j, lists)` for every pair of coefficients `a_i`, `b_j` (both nonzero by
/// `nonzero`) whose basis functions have a nonzero product on every axis, `lists[x]` being that
/// product's `(output index, weight)` list on axis `x` (`entries[x]`, indexed `i_x · n_b + j_x`).
/// Stops at the first `None` from `f`.
fn for_each_product<'t, W>(
    nonzero: (&[bool], &[bool]),
    counts: (&[usize], &[usize]),
    entries: &[&'t [Vec<(usize, W)>]],
    mut f: impl FnMut(usize, usize, &[&'t [(usize, W)]]) -> Option<()>,
) -> Option<()> {
    let (ca, cb) = counts;
    let n = ca.len();
    let mut ia = vec![0usize; n];
    let mut lists: Vec<&[(usize, W)]> = Vec::with_capacity(n);
    for (i, &a) in nonzero.0.iter().enumerate() {
        if a {
            let mut ib = vec![0usize; n];
            for (j, &b) in nonzero.1.iter().enumerate() {
                if b {
                    lists.clear();
                    lists.extend((0..n).map(|x| entries[x][ia[x] * cb[x] + ib[x]].as_slice()));
                    if lists.iter().all(|l| !l.is_empty()) {
                        f(i, j, &lists)?;
                    }
                }
                step(&mut ib, cb);
            }
        }
        step(&mut ia, ca);
    }
    Some(())
}

/// The Mørken contraction `out_o = Σ_{i,j} a_i b_j Π_x w_x` in `i128`, or `None` when a
/// factor does not fit or a partial sum would overflow (then [`contract_big`] runs).
///
/// Axis by axis: `W₀[i, j] = a_i b_j`, and stage `x` replaces the index pair `(i_x, j_x)` by
/// `o_x` through axis `x`'s table, `W_{x+1}[…, o_x, …] = Σ_{i_x, j_x} w_x · W_x[…, i_x, j_x, …]`.
/// Each axis's weights multiply partial sums once, not once per leaf of every pair's product
/// of lists; in 3-D that is several times fewer multiplications than pair by pair.
fn contract_small(
    na: &[BigInt],
    nb: &[BigInt],
    tables: &[Arc<IntTable>],
    counts: (&[usize], &[usize]),
    sp: &[usize],
) -> Option<Vec<BigInt>> {
    let small: Vec<&[Vec<(usize, i128)>]> = tables
        .iter()
        .map(|t| t.small.as_deref())
        .collect::<Option<_>>()?;
    let fit = |v: &[BigInt]| {
        v.iter()
            .map(|x| i128::try_from(x).ok())
            .collect::<Option<Vec<_>>>()
    };
    let (na, nb) = (fit(na)?, fit(nb)?);
    let (ca, cb) = counts;
    let n = tables.len();
    let m: Vec<usize> = tables.iter().map(|t| t.table.count).collect();
    // Stage k's layout, fastest first: o_0 … o_{k−1}, i_k … i_{n−1}, j_k … j_{n−1}. Stage 0 is
    // `a`'s flat index plus `|a|` times `b`'s; stage n is the output's (`sp`).
    let layout = |k: usize| -> (Vec<usize>, Vec<usize>) {
        let sizes: Vec<usize> = m[..k]
            .iter()
            .chain(&ca[k..])
            .chain(&cb[k..])
            .copied()
            .collect();
        (strides_of(&sizes), sizes)
    };
    let mut w = Vec::with_capacity(na.len() * nb.len());
    for &y in &nb {
        for &x in &na {
            w.push(x.checked_mul(y)?);
        }
    }
    for (k, list) in small.iter().enumerate() {
        let (sin, size_in) = layout(k);
        let (sout, size_out) = layout(k + 1);
        // The dimensions kept through stage k: (size, stride in, stride out).
        let rest: Vec<(usize, usize, usize)> = (0..k)
            .map(|y| (size_in[y], sin[y], sout[y]))
            .chain((k + 1..n).map(|y| (size_in[y], sin[y], sout[y])))
            .chain((k + 1..n).map(|y| (size_in[n + y - k], sin[n + y - k], sout[n + y - k - 1])))
            .collect();
        let (si, sj, so) = (sin[k], sin[n], sout[k]);
        let mut next = vec![0i128; size_out.iter().product()];
        let mut digits = vec![0usize; rest.len()];
        let (mut at_in, mut at_out) = (0usize, 0usize);
        loop {
            for ik in 0..ca[k] {
                for jk in 0..cb[k] {
                    let v = w[at_in + ik * si + jk * sj];
                    if v == 0 {
                        continue;
                    }
                    for &(o, wt) in &list[ik * cb[k] + jk] {
                        let slot = &mut next[at_out + o * so];
                        *slot = slot.checked_add(v.checked_mul(wt)?)?;
                    }
                }
            }
            // Advance the kept dimensions' counter (and both flat offsets) by one.
            let mut d = 0;
            loop {
                if d == rest.len() {
                    break;
                }
                let (size, s_in, s_out) = rest[d];
                digits[d] += 1;
                at_in += s_in;
                at_out += s_out;
                if digits[d] < size {
                    break;
                }
                at_in -= size * s_in;
                at_out -= size * s_out;
                digits[d] = 0;
                d += 1;
            }
            if d == rest.len() {
                break;
            }
        }
        w = next;
    }
    debug_assert_eq!(strides_of(&m), sp);
    Some(w.into_iter().map(BigInt::from).collect())
}

/// [`contract_small`] in `BigInt`.
fn contract_big(
    na: &[BigInt],
    nb: &[BigInt],
    tables: &[Arc<IntTable>],
    counts: (&[usize], &[usize]),
    sp: &[usize],
) -> Vec<BigInt> {
    let ints: Vec<&[Vec<(usize, BigInt)>]> = tables.iter().map(|t| t.ints.as_slice()).collect();
    let nonzero = |v: &[BigInt]| v.iter().map(|x| !x.is_zero()).collect::<Vec<_>>();
    let mut out = vec![BigInt::zero(); tables.iter().map(|t| t.table.count).product()];
    for_each_product(
        (&nonzero(na), &nonzero(nb)),
        counts,
        &ints,
        |i, j, lists| {
            distribute_int(&(&na[i] * &nb[j]), lists, sp, 0, 0, &mut out);
            Some(())
        },
    );
    out
}

fn distribute_int(
    v: &BigInt,
    lists: &[&[(usize, BigInt)]],
    strides: &[usize],
    axis: usize,
    at: usize,
    out: &mut [BigInt],
) {
    if axis == lists.len() {
        out[at] += v;
        return;
    }
    for (o, w) in lists[axis] {
        distribute_int(
            &(v * w),
            lists,
            strides,
            axis + 1,
            at + o * strides[axis],
            out,
        );
    }
}

/// Adds `v · Π_x w_x` to `out[Σ o_x · stride_x]` for every choice of `(o_x, w_x)` in the lists.
fn distribute<T: Field>(
    v: &T,
    lists: &[&[(usize, T)]],
    strides: &[usize],
    axis: usize,
    at: usize,
    out: &mut [T],
) {
    if axis == lists.len() {
        out[at] = out[at].add(v);
        return;
    }
    for (o, w) in lists[axis] {
        distribute(
            &v.mul(w),
            lists,
            strides,
            axis + 1,
            at + o * strides[axis],
            out,
        );
    }
}

fn strides_of(counts: &[usize]) -> Vec<usize> {
    let mut s = Vec::with_capacity(counts.len());
    let mut acc = 1;
    for &c in counts {
        s.push(acc);
        acc *= c;
    }
    s
}

/// Advances a multi-index with the given per-axis counts (axis 0 fastest).
fn step(idx: &mut [usize], counts: &[usize]) {
    for (i, &c) in idx.iter_mut().zip(counts) {
        *i += 1;
        if *i < c {
            return;
        }
        *i = 0;
    }
}

/// The Mørken products of pairs of univariate basis functions on one axis.
#[derive(Clone, Debug)]
pub struct BasisProductTable<T> {
    /// Degree of the products.
    pub degree: usize,
    /// The product knot vector ([`product_knots`]).
    pub knots: Vec<T>,
    /// Number of product basis functions.
    pub count: usize,
    /// `entries[i · n_b + j]`: the nonzero coefficients `(o, M[i,j](o))` of `N_{i,p} · N_{j,q}`.
    pub entries: Vec<Vec<(usize, T)>>,
}

/// Products of every pair of basis functions `N_{i,p}` (knots `s`) and `N_{j,q}` (knots `t`) as
/// splines on the product knots, each through [`morken_product`] of unit-coefficient splines.
pub fn basis_product_table<T: Field + PartialOrd>(
    p: usize,
    s: &[T],
    q: usize,
    t: &[T],
) -> Result<BasisProductTable<T>, BsplineError> {
    let na = s.len().saturating_sub(p + 1);
    let nb = t.len().saturating_sub(q + 1);
    let unit = |n: usize, i: usize| -> Vec<T> {
        (0..n)
            .map(|k| if k == i { T::one() } else { T::zero() })
            .collect()
    };
    let probe_a = Spline::new(p, s.to_vec(), unit(na, 0))?;
    let probe_b = Spline::new(q, t.to_vec(), unit(nb, 0))?;
    let knots = product_knots(&[&probe_a, &probe_b])?;
    let count = knots.len() - (p + q) - 1;
    let mut entries = Vec::with_capacity(na * nb);
    for i in 0..na {
        let fi = Spline::new(p, s.to_vec(), unit(na, i))?;
        for j in 0..nb {
            // Supports [s_i, s_{i+p+1}] and [t_j, t_{j+q+1}] must overlap in an interval.
            let lo = if s[i] > t[j] { &s[i] } else { &t[j] };
            let hi = if s[i + p + 1] < t[j + q + 1] {
                &s[i + p + 1]
            } else {
                &t[j + q + 1]
            };
            if lo.partial_cmp(hi) != Some(std::cmp::Ordering::Less) {
                entries.push(Vec::new());
                continue;
            }
            let gj = Spline::new(q, t.to_vec(), unit(nb, j))?;
            let h = morken_product(&[&fi, &gj])?;
            entries.push(
                h.coeffs()
                    .iter()
                    .enumerate()
                    .filter(|(_, c)| !c.is_exact_zero())
                    .map(|(o, c)| (o, c.clone()))
                    .collect(),
            );
        }
    }
    Ok(BasisProductTable {
        degree: p + q,
        knots,
        count,
        entries,
    })
}
