//! Applying an FFD to points and meshes (paper eq. 1, with `X ≡ U`: Section 3's linear
//! precision): the exact image of each point, and a fast `f64` evaluator that allocates
//! nothing per point.
//!
//! An object is embedded either directly (its coordinates are parameters in the lattice's
//! domain `[0,a]×[0,b]×[0,c]`) or through a [`Fit`]: the affine map that sends its bounding
//! box, grown by a margin, onto the domain, so any mesh can be deformed by any lattice.

use super::lattice::{Lattice, Point};
use super::FfdError;
use crate::num::{rational_from_f64, rational_to_f64};
use glam::DVec3;

/// Largest order handled by [`FastDeformer`] (the lattice's own limit).
const MAX_ORDER: usize = super::lattice::MAX_ORDER;

/// The `f64` form of a lattice for evaluating `F(U)` at many points.
#[derive(Clone, Debug)]
pub struct FastDeformer {
    order: [usize; 3],
    counts: [usize; 3],
    knots: [Vec<f64>; 3],
    /// Upper end of the domain per axis.
    hi: [f64; 3],
    /// Control points rounded to the nearest `f64`.
    points: Vec<DVec3>,
}

impl FastDeformer {
    /// The `f64` form of `l` (control points rounded to nearest).
    pub fn new(l: &Lattice) -> FastDeformer {
        let knots = [0, 1, 2].map(|a| l.knots(a).iter().map(rational_to_f64).collect());
        let hi = [0, 1, 2].map(|a| l.cells()[a] as f64);
        let points = match l.points_f64() {
            Some(p) => p.iter().map(|&q| DVec3::from(q)).collect(),
            None => l
                .points()
                .iter()
                .map(|p| DVec3::from([0, 1, 2].map(|a| rational_to_f64(&p[a]))))
                .collect(),
        };
        FastDeformer {
            order: l.order(),
            counts: l.counts(),
            knots,
            hi,
            points,
        }
    }

    fn basis(&self, a: usize, x: f64, out: &mut [f64; MAX_ORDER]) -> usize {
        basis_f64(&self.knots[a], self.order[a] - 1, self.counts[a], x, out)
    }

    #[allow(clippy::needless_range_loop)] // i, j, k index basis values and control points
    /// `F(U)` in `f64`; `None` outside the domain or for a non-finite input.
    pub fn deform(&self, u: [f64; 3]) -> Option<[f64; 3]> {
        if (0..3).any(|a| !(u[a] >= 0.0 && u[a] <= self.hi[a])) {
            return None;
        }
        let mut b = [[0.0f64; MAX_ORDER]; 3];
        let first = [0, 1, 2].map(|a| self.basis(a, u[a], &mut b[a]));
        let mut out = DVec3::ZERO;
        for k in 0..self.order[2] {
            for j in 0..self.order[1] {
                let wjk = b[1][j] * b[2][k];
                let row =
                    first[0] + self.counts[0] * (first[1] + j + self.counts[1] * (first[2] + k));
                for i in 0..self.order[0] {
                    out += b[0][i] * wjk * self.points[row + i];
                }
            }
        }
        Some(out.to_array())
    }
}

/// The `p+1` nonzero basis values at `x` (Cox–de Boor, NURBS Book A2.2) of a spline with `n`
/// coefficients on `knots`, and the index of the first; the span is the one with
/// `t_μ ≤ x < t_{μ+1}` (the last span at the right end of the domain).
pub(crate) fn basis_f64(
    knots: &[f64],
    p: usize,
    n: usize,
    x: f64,
    out: &mut [f64; MAX_ORDER],
) -> usize {
    let t = knots;
    let mut mu = p;
    while mu + 1 < n && t[mu + 1] <= x {
        mu += 1;
    }
    out[0] = 1.0;
    let mut left = [0.0f64; MAX_ORDER];
    let mut right = [0.0f64; MAX_ORDER];
    for j in 1..=p {
        left[j] = x - t[mu + 1 - j];
        right[j] = t[mu + j] - x;
        let mut saved = 0.0;
        for r in 0..j {
            let temp = out[r] / (right[r + 1] + left[j - r]);
            out[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        out[j] = saved;
    }
    mu - p
}

/// The affine embedding of an object into a lattice's domain: `U = (X − origin) · scale`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fit {
    /// The corner of the grown bounding box that maps to the domain's origin.
    pub origin: [f64; 3],
    /// Per axis, domain length over box length.
    pub scale: [f64; 3],
}

impl Fit {
    /// Sends the bounding box of `points`, grown by `margin` (a fraction of each side, at least
    /// a small absolute amount on flat axes), onto the domain of `l`.
    pub fn bounding_box(points: &[[f64; 3]], l: &Lattice, margin: f64) -> Result<Fit, FfdError> {
        if points.is_empty() {
            return Err(FfdError::Input {
                lattice: 0,
                field: "mesh".into(),
                why: "no vertices to embed".into(),
            });
        }
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in points {
            for a in 0..3 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        let longest = (0..3)
            .map(|a| hi[a] - lo[a])
            .fold(0.0f64, f64::max)
            .max(1.0);
        let mut origin = [0.0; 3];
        let mut scale = [0.0; 3];
        for a in 0..3 {
            let pad = ((hi[a] - lo[a]) * margin).max(longest * 1e-3);
            origin[a] = lo[a] - pad;
            scale[a] = l.cells()[a] as f64 / (hi[a] - lo[a] + 2.0 * pad);
        }
        Ok(Fit { origin, scale })
    }
    /// World point to parameter point.
    pub fn to_domain(&self, x: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|a| (x[a] - self.origin[a]) * self.scale[a])
    }
    /// Parameter point back to world.
    pub fn from_domain(&self, u: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|a| u[a] / self.scale[a] + self.origin[a])
    }
}

/// Deforms `points` in place by the composition of `lattices` (each applied to the previous
/// image, as the steps of an injective drag are), through `fit` when given. Errors name the
/// first point that leaves the domain; on error `points` is unchanged.
pub fn deform_points_fast(
    lattices: &[Lattice],
    fit: Option<&Fit>,
    points: &mut [[f64; 3]],
) -> Result<(), FfdError> {
    let deformers: Vec<FastDeformer> = lattices.iter().map(FastDeformer::new).collect();
    let mut out = Vec::with_capacity(points.len());
    for (i, x) in points.iter().enumerate() {
        let mut u = fit.map_or(*x, |f| f.to_domain(*x));
        for (s, d) in deformers.iter().enumerate() {
            u = d.deform(u).ok_or_else(|| FfdError::Input {
                lattice: s,
                field: format!("vertex {i}"),
                why: format!(
                    "parameter point ({}, {}, {}) lies outside the lattice domain",
                    u[0], u[1], u[2]
                ),
            })?;
        }
        out.push(fit.map_or(u, |f| f.from_domain(u)));
    }
    points.copy_from_slice(&out);
    Ok(())
}

/// The exact image of each `f64` point (taken exactly) under the composition of `lattices`,
/// with no embedding: the reference for [`deform_points_fast`].
pub fn deform_points_exact(
    lattices: &[Lattice],
    points: &[[f64; 3]],
) -> Result<Vec<Point>, FfdError> {
    points
        .iter()
        .enumerate()
        .map(|(i, x)| {
            let mut u: Point = Default::default();
            for a in 0..3 {
                u[a] =
                    rational_from_f64(x[a], "vertex coordinate").map_err(|e| FfdError::Input {
                        lattice: 0,
                        field: format!("vertex {i}"),
                        why: e.to_string(),
                    })?;
            }
            for l in lattices {
                u = l.deform(&u)?;
            }
            Ok(u)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ffd::Basis;

    fn wavy(basis: Basis, order: [usize; 3], cells: [usize; 3]) -> Lattice {
        let id = Lattice::identity(basis, order, cells).unwrap();
        let delta: Vec<Point> = (0..id.points().len())
            .map(|i| {
                [0, 1, 2].map(|a| {
                    let k = ((7 * i + 3 * a) % 11) as f64 / 64.0 - 0.08;
                    rational_from_f64(k, "t").unwrap()
                })
            })
            .collect();
        id.displaced(&delta).unwrap()
    }

    #[test]
    fn fast_deform_matches_the_exact_image() {
        for (basis, order, cells) in [
            (Basis::Bspline, [4, 4, 4], [3, 2, 2]),
            (Basis::Bspline, [3, 2, 5], [2, 3, 1]),
            (Basis::Bezier, [4, 3, 2], [1, 1, 1]),
        ] {
            let l = wavy(basis, order, cells);
            let fast = FastDeformer::new(&l);
            let pts: Vec<[f64; 3]> = (0..50)
                .map(|i| {
                    let f = |k: usize, c: usize| ((i * k) % 97) as f64 / 96.0 * cells[c] as f64;
                    [f(13, 0), f(29, 1), f(41, 2)]
                })
                .collect();
            let exact = deform_points_exact(std::slice::from_ref(&l), &pts).unwrap();
            for (p, e) in pts.iter().zip(&exact) {
                let f = fast.deform(*p).unwrap();
                for a in 0..3 {
                    assert!((f[a] - rational_to_f64(&e[a])).abs() < 1e-13, "{p:?}");
                }
            }
        }
    }

    #[test]
    fn identity_lattice_fixes_points_and_fit_round_trips() {
        let id = Lattice::identity(Basis::Bspline, [4, 4, 4], [4, 4, 4]).unwrap();
        let mut pts = vec![[1.0, -2.0, 3.5], [4.0, 0.25, -1.0], [2.0, 2.0, 2.0]];
        let fit = Fit::bounding_box(&pts, &id, 0.1).unwrap();
        let before = pts.clone();
        deform_points_fast(std::slice::from_ref(&id), Some(&fit), &mut pts).unwrap();
        for (a, b) in pts.iter().zip(&before) {
            for c in 0..3 {
                assert!((a[c] - b[c]).abs() < 1e-12);
            }
        }
        // Without a fit the points lie outside [0,4]³: a clear error, nothing changed.
        let mut outside = vec![[1.0, 1.0, 1.0], [5.0, 1.0, 1.0]];
        let e = deform_points_fast(std::slice::from_ref(&id), None, &mut outside).unwrap_err();
        assert!(e.to_string().contains("vertex 1"), "{e}");
        assert_eq!(outside[0], [1.0, 1.0, 1.0]);
    }
}
