//! Tensor-product B-splines (trivariate is the FFD's case) and their Bézier cells.

use super::{BsplineError, Spline};
use crate::bernstein::poly::{coefficient_count, map_lines};
use crate::bernstein::Bernstein;
use crate::num::Field;

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
    pub spans: Vec<usize>,
    pub bounds: Vec<(T, T)>,
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

    pub fn degrees(&self) -> &[usize] {
        &self.degrees
    }
    pub fn knots(&self) -> &[Vec<T>] {
        &self.knots
    }
    pub fn coeffs(&self) -> &[T] {
        &self.coeffs
    }
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
            coeffs = map_lines(&degs, &coeffs, a, new_len, &T::zero(), |line, out| {
                let s = self.axis_spline(a, line.to_vec());
                for (k, (mu, lo, hi)) in spans.iter().enumerate() {
                    for (i, v) in s.bezier_on(*mu, lo, hi).into_iter().enumerate() {
                        out[k * (p + 1) + i] = v;
                    }
                }
            });
            counts[a] = new_len;
            axis_spans.push(spans);
        }
        // Cut the concatenated Bézier nets into cells.
        let cell_counts: Vec<usize> = axis_spans.iter().map(|s| s.len()).collect();
        let total: usize = cell_counts.iter().product();
        let mut cells = Vec::with_capacity(total);
        for flat in 0..total {
            let mut rem = flat;
            let cell: Vec<usize> = cell_counts
                .iter()
                .map(|&c| {
                    let i = rem % c;
                    rem /= c;
                    i
                })
                .collect();
            let degs = self.degrees.clone();
            let m = coefficient_count(&degs);
            let mut local = Vec::with_capacity(m);
            for lf in 0..m {
                let mut r = lf;
                let mut g = 0;
                let mut stride = 1;
                for a in 0..n {
                    let i = r % (degs[a] + 1);
                    r /= degs[a] + 1;
                    g += (cell[a] * (degs[a] + 1) + i) * stride;
                    stride *= counts[a];
                }
                local.push(coeffs[g].clone());
            }
            cells.push(BezierCell {
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
                poly: Bernstein::new(degs, local).expect("count matches"),
            });
        }
        cells
    }
}
