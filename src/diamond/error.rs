//! The approximation error of a diamond (Section 6): `ε(δ) = max_{p ∈ δ} |F(p) − F̂_δ(p)|` over
//! the grid points `p` of δ's domain, `F̂_δ` the barycentric interpolation of `F` on δ's
//! simplices, and the range of `F` over the same points.
//!
//! * [`diamond_stats_exact`] (reference) reads like the definition: for every simplex of the
//!   diamond, every grid point of its bounding box, barycentric coordinates by Cramer's rule in
//!   integers, inside when all are `≥ 0`, the error in rationals.
//! * [`diamond_stats_fast`] never locates a simplex. A class-`i` diamond is the join of the
//!   odd axes' cube `Q` (its Kuhn simplices around the spine) and the boundary of the even axes'
//!   cube of side `2h` around `c`, so its domain is `‖u‖∞ + ‖w‖∞ ≤ h` (`u`, `w` the offsets
//!   from `c` along the odd and the even axes), and the barycentric coordinates of `p` times
//!   `2h` are integers read off sorted offsets (Freudenthal's rule on both factors):
//!   `T_k = s_k u_k + h − ‖w‖∞` on the odd axes (weights `2(h − ‖w‖∞) − T_(1)`,
//!   `T_(j) − T_(j+1)`, `T_(m)` along the Kuhn chain) and `2(|w|_(j) − |w|_(j+1))` along the
//!   even chain. The sum in `f64` carries a rigorous rounding bound, so the fast path returns an
//!   interval `[error_lo, error_hi]` that contains the exact error.

use super::{Diamond, Field, Point, Simplex};
use crate::num::{rational_from_f64, Rational};
use num_traits::{Signed, Zero};

/// A diamond's error and range, from the fast path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiamondStats {
    /// A lower bound of the exact error.
    pub error_lo: f64,
    /// An upper bound of the exact error.
    pub error_hi: f64,
    /// The least sample in the domain.
    pub min: f64,
    /// The largest sample in the domain.
    pub max: f64,
}

/// A diamond's error and range, exactly.
#[derive(Clone, Debug, PartialEq)]
pub struct ExactStats {
    /// `ε(δ)`.
    pub error: Rational,
    /// The least sample in the domain.
    pub min: f64,
    /// The largest sample in the domain.
    pub max: f64,
    /// Grid points examined (counted once per simplex that contains them).
    pub points: usize,
}

/// `γ_n = n·u / (1 − n·u)`, `u = 2^−53`: the relative bound of `n` rounded operations.
fn gamma(n: usize) -> f64 {
    let nu = n as f64 * f64::EPSILON / 2.0;
    nu / (1.0 - nu)
}

/// The error and range of `dia` on `field` by the join formula, with a certified interval.
///
/// The points are visited without a bounding-box scan: for each offset `w` along the even axes
/// (clipped to the domain), the odd offsets run over `‖u‖∞ ≤ h − ‖w‖∞`; the even chain's part
/// of the interpolant depends on `w` only and is summed once per `w`.
pub fn diamond_stats_fast<const D: usize>(field: &Field<D>, dia: &Diamond<D>) -> DiamondStats {
    let h = i64::from(dia.half_width());
    let side = i64::from(field.hierarchy().side());
    let values = field.values();
    let mut stride = [0i64; D];
    let mut st = 1i64;
    for s in stride.iter_mut() {
        *s = st;
        st *= side + 1;
    }
    let c = dia.center().map(i64::from);
    let c_idx: i64 = (0..D).map(|k| c[k] * stride[k]).sum();
    let odd = dia.odd_axes();
    let [a, _] = dia.spine();
    let a_idx: i64 = (0..D).map(|k| i64::from(a[k]) * stride[k]).sum();
    // Odd axes (with the spine's direction) and even axes.
    let mut oa = [(0usize, 0i64); D];
    let mut m = 0;
    let mut ea = [0usize; D];
    let mut ne = 0;
    for k in 0..D {
        if odd >> k & 1 == 1 {
            oa[m] = (k, if c[k] > i64::from(a[k]) { 1 } else { -1 });
            m += 1;
        } else {
            ea[ne] = k;
            ne += 1;
        }
    }
    let g = gamma(D + 4) * 2.0;
    let two_h = (2 * h) as f64;
    let (mut error_lo, mut error_hi) = (0.0f64, 0.0f64);
    let (mut min, mut max) = (f64::INFINITY, f64::NEG_INFINITY);
    // Even offsets, clipped to the domain.
    let wlo: [i64; D] = std::array::from_fn(|j| if j < ne { (-h).max(-c[ea[j]]) } else { 0 });
    let whi: [i64; D] = std::array::from_fn(|j| if j < ne { h.min(side - c[ea[j]]) } else { 0 });
    let mut w = wlo;
    loop {
        let nw = w[..ne].iter().map(|x| x.abs()).max().unwrap_or(0);
        let w_idx: i64 = (0..ne).map(|j| w[j] * stride[ea[j]]).sum();
        // The even chain: c + h·sign(w) along the axes by decreasing |w|.
        let mut order = [(0i64, 0usize); D];
        for j in 0..ne {
            order[j] = (w[j].abs(), j);
        }
        order[..ne].sort_unstable_by_key(|&(x, _)| std::cmp::Reverse(x));
        let (mut acc_e, mut abs_e) = (0.0f64, 0.0f64);
        let mut q = c_idx;
        for t in 0..ne {
            let (wk, j) = order[t];
            if wk == 0 {
                break;
            }
            q += h * w[j].signum() * stride[ea[j]];
            let next = if t + 1 < ne { order[t + 1].0 } else { 0 };
            let term = (2 * (wk - next)) as f64 * values[q as usize];
            acc_e += term;
            abs_e += term.abs();
        }
        let r = h - nw;
        let lambda = 2 * r;
        // Odd offsets u ∈ [−r, r]^m.
        let mut u = [0i64; D];
        for x in u[..m].iter_mut() {
            *x = -r;
        }
        loop {
            let mut idx = c_idx + w_idx;
            let mut t = [(0i64, 0usize); D];
            for j in 0..m {
                let (k, s) = oa[j];
                idx += u[j] * stride[k];
                t[j] = (s * u[j] + r, j);
            }
            let fp = values[idx as usize];
            min = min.min(fp);
            max = max.max(fp);
            t[..m].sort_unstable_by_key(|&(x, _)| std::cmp::Reverse(x));
            let (mut acc, mut abs) = (acc_e, abs_e);
            let mut v = a_idx;
            let mut prev = lambda;
            for &(tk, j) in &t[..m] {
                if prev != tk {
                    let term = (prev - tk) as f64 * values[v as usize];
                    acc += term;
                    abs += term.abs();
                }
                let (k, s) = oa[j];
                v += 2 * h * s * stride[k];
                prev = tk;
            }
            if prev != 0 {
                let term = prev as f64 * values[v as usize];
                acc += term;
                abs += term.abs();
            }
            let err = (fp - acc / two_h).abs();
            let bound = g * (abs / two_h + fp.abs());
            error_lo = error_lo.max(err - bound);
            error_hi = error_hi.max(err + bound);
            // Next u.
            let mut j = 0;
            while j < m && u[j] == r {
                u[j] = -r;
                j += 1;
            }
            if j == m {
                break;
            }
            u[j] += 1;
        }
        // Next w.
        let mut j = 0;
        while j < ne && w[j] == whi[j] {
            w[j] = wlo[j];
            j += 1;
        }
        if j == ne {
            break;
        }
        w[j] += 1;
    }
    DiamondStats {
        error_lo: error_lo.max(0.0),
        error_hi,
        min,
        max,
    }
}

/// The error and range of `dia` on `field`, exactly, from the definition.
pub fn diamond_stats_exact<const D: usize>(field: &Field<D>, dia: &Diamond<D>) -> ExactStats {
    simplices_stats_exact(field, &dia.simplices())
}

/// `max |F(p) − F̂(p)|` and the range over the grid points `p` of the given simplices, `F̂`
/// the linear interpolation on the simplex holding `p`, exactly (a mesh's error, or a
/// diamond's when the simplices are the diamond's).
pub fn simplices_stats_exact<const D: usize>(
    field: &Field<D>,
    simplices: &[Simplex<D>],
) -> ExactStats {
    let value = |p: &Point<D>| rational_from_f64(field.at(p), "sample").expect("finite samples");
    let mut error = Rational::zero();
    let (mut min, mut max) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut points = 0;
    for simplex in simplices {
        let v = simplex.vertices();
        let lo: Point<D> = std::array::from_fn(|k| v.iter().map(|x| x[k]).min().unwrap_or(0));
        let hi: Point<D> = std::array::from_fn(|k| v.iter().map(|x| x[k]).max().unwrap_or(0));
        let det = |replace: Option<(usize, &Point<D>)>| -> i128 {
            let mut m = [[0i128; super::MAX_DIM]; super::MAX_DIM];
            for r in 0..D {
                let row = match replace {
                    Some((j, p)) if j == r + 1 => p,
                    _ => &v[r + 1],
                };
                for k in 0..D {
                    m[r][k] = i128::from(row[k]) - i128::from(v[0][k]);
                }
            }
            super::bareiss_det_checked(&mut m, D).expect("grid simplices' determinants fit i128")
        };
        let total = det(None);
        let values: Vec<Rational> = v.iter().map(value).collect();
        let mut p = lo;
        'points: loop {
            // Barycentric coordinates times `total` (Cramer's rule).
            let mut lambdas = [0i128; super::MAX_DIM + 1];
            let mut rest = total;
            for (j, l) in lambdas.iter_mut().enumerate().take(D + 1).skip(1) {
                *l = det(Some((j, &p)));
                rest -= *l;
            }
            lambdas[0] = rest;
            let inside = lambdas[..=D]
                .iter()
                .all(|&l| l == 0 || (l > 0) == (total > 0));
            if inside {
                points += 1;
                let interp: Rational = (0..=D)
                    .map(|j| &values[j] * Rational::from_integer(lambdas[j].into()))
                    .sum::<Rational>()
                    / Rational::from_integer(total.into());
                let e = (value(&p) - interp).abs();
                if e > error {
                    error = e;
                }
                let fp = field.at(&p);
                min = min.min(fp);
                max = max.max(fp);
            }
            let mut k = 0;
            loop {
                if k == D {
                    break 'points;
                }
                if p[k] < hi[k] {
                    p[k] += 1;
                    break;
                }
                p[k] = lo[k];
                k += 1;
            }
        }
    }
    ExactStats {
        error,
        min,
        max,
        points,
    }
}
