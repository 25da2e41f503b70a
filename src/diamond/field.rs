//! A scalar field sampled on the `(2^N + 1)^d` grid of a diamond hierarchy (Section 6).

use super::{DiamondError, Hierarchy, Point};

/// Samples on `[0, 2^N]^d`, axis 0 fastest; volumes whose sides are not `2^N + 1` are padded by
/// edge replication, and the samples of the original volume are remembered as *real*.
#[derive(Clone, Debug, PartialEq)]
pub struct Field<const D: usize> {
    hierarchy: Hierarchy<D>,
    values: Vec<f64>,
    real: [usize; D],
}

impl<const D: usize> Field<D> {
    /// The field of a volume of `dims` samples (axis 0 fastest), padded to the smallest
    /// `2^N + 1 ≥ max(dims)` per side by repeating the last sample along each axis.
    pub fn pad(dims: [usize; D], values: &[f64]) -> Result<Field<D>, DiamondError> {
        if dims.iter().any(|&n| n < 2) {
            return Err(DiamondError::Volume(format!(
                "every side needs at least 2 samples, found {dims:?}"
            )));
        }
        let count = dims.iter().try_fold(1usize, |a, &n| a.checked_mul(n));
        if count != Some(values.len()) {
            return Err(DiamondError::Volume(format!(
                "a volume of {dims:?} needs {} samples, found {}",
                count.map_or("more than usize".into(), |c| c.to_string()),
                values.len()
            )));
        }
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(DiamondError::Volume(format!("sample {i} is not finite")));
        }
        let largest = *dims.iter().max().expect("d >= 2");
        // The smallest N with 2^N + 1 >= largest.
        let levels = (usize::BITS - (largest - 2).leading_zeros()).max(1);
        let hierarchy = Hierarchy::<D>::new(levels)?;
        let n = hierarchy.side() as usize + 1;
        let total = n
            .checked_pow(D as u32)
            .filter(|&t| t <= 1 << 31)
            .ok_or_else(|| {
                DiamondError::Volume(format!("a padded grid of {n}^{D} is too large"))
            })?;
        let mut out = Vec::with_capacity(total);
        for i in 0..total {
            let mut r = i;
            let mut src = 0usize;
            let mut stride = 1usize;
            for &side in &dims {
                let x = (r % n).min(side - 1);
                r /= n;
                src += x * stride;
                stride *= side;
            }
            out.push(values[src]);
        }
        Ok(Field {
            hierarchy,
            values: out,
            real: dims,
        })
    }

    /// The hierarchy of the grid.
    pub fn hierarchy(&self) -> Hierarchy<D> {
        self.hierarchy
    }

    /// All samples, axis 0 fastest.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// The original volume's sides (before padding).
    pub fn real_dims(&self) -> [usize; D] {
        self.real
    }

    /// The number of original (unpadded) samples.
    pub fn real_count(&self) -> usize {
        self.real.iter().product()
    }

    /// True when `p` is an original sample, not padding.
    pub fn is_real(&self, p: &Point<D>) -> bool {
        (0..D).all(|k| (p[k] as usize) < self.real[k])
    }

    /// The array index of grid point `p`.
    #[inline]
    pub fn index(&self, p: &Point<D>) -> usize {
        let n = self.hierarchy.side() as usize + 1;
        p.iter().rev().fold(0, |acc, &x| acc * n + x as usize)
    }

    /// The grid point of array index `i`.
    pub fn point(&self, mut i: usize) -> Point<D> {
        let n = self.hierarchy.side() as usize + 1;
        std::array::from_fn(|_| {
            let x = (i % n) as u32;
            i /= n;
            x
        })
    }

    /// `F(p)`.
    #[inline]
    pub fn at(&self, p: &Point<D>) -> f64 {
        self.values[self.index(p)]
    }
}
