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

/// A diamond's points in the field's flat array: strides, the centre's and the spine start's
/// indices, the odd axes (with the spine's direction `s_k`) and the even axes, and the even
/// offsets' range clipped to the domain.
struct Layout<const D: usize> {
    h: i64,
    stride: [i64; D],
    c_idx: i64,
    a_idx: i64,
    /// `(axis, s_k)` for the `m` odd axes.
    oa: [(usize, i64); D],
    m: usize,
    /// The `ne` even axes.
    ea: [usize; D],
    ne: usize,
    wlo: [i64; D],
    whi: [i64; D],
}

impl<const D: usize> Layout<D> {
    fn new(side: u32, dia: &Diamond<D>) -> Layout<D> {
        let h = i64::from(dia.half_width());
        let side = i64::from(side);
        let mut stride = [0i64; D];
        let mut st = 1i64;
        for s in stride.iter_mut() {
            *s = st;
            st *= side + 1;
        }
        let c = dia.center().map(i64::from);
        let odd = dia.odd_axes();
        let [a, _] = dia.spine();
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
        Layout {
            h,
            stride,
            c_idx: (0..D).map(|k| c[k] * stride[k]).sum(),
            a_idx: (0..D).map(|k| i64::from(a[k]) * stride[k]).sum(),
            oa,
            m,
            ea,
            ne,
            wlo: std::array::from_fn(|j| if j < ne { (-h).max(-c[ea[j]]) } else { 0 }),
            whi: std::array::from_fn(|j| if j < ne { h.min(side - c[ea[j]]) } else { 0 }),
        }
    }

    /// `‖w‖∞`, the index offset of `w`, and the even chain's `(2h·weight, index)` pairs:
    /// `c + h·sign(w)` along the axes by decreasing `|w|`, weights `2(|w|_(t) − |w|_(t+1))`.
    fn even_chain(&self, w: &[i64; D]) -> (i64, i64, [(i64, i64); D], usize) {
        let ne = self.ne;
        let nw = w[..ne].iter().map(|x| x.abs()).max().unwrap_or(0);
        let w_idx: i64 = (0..ne).map(|j| w[j] * self.stride[self.ea[j]]).sum();
        let mut order = [(0i64, 0usize); D];
        for j in 0..ne {
            order[j] = (w[j].abs(), j);
        }
        order[..ne].sort_unstable_by_key(|&(x, _)| std::cmp::Reverse(x));
        let mut chain = [(0i64, 0i64); D];
        let mut len = 0;
        let mut q = self.c_idx;
        for t in 0..ne {
            let (wk, j) = order[t];
            if wk == 0 {
                break;
            }
            q += self.h * w[j].signum() * self.stride[self.ea[j]];
            let next = if t + 1 < ne { order[t + 1].0 } else { 0 };
            chain[len] = (2 * (wk - next), q);
            len += 1;
        }
        (nw, w_idx, chain, len)
    }

    /// Steps `offsets[from..to]` through `[lo, hi]` each, first index fastest; false after the
    /// last.
    fn next(
        offsets: &mut [i64; D],
        from: usize,
        to: usize,
        lo: impl Fn(usize) -> i64,
        hi: impl Fn(usize) -> i64,
    ) -> bool {
        let mut j = from;
        while j < to && offsets[j] == hi(j) {
            offsets[j] = lo(j);
            j += 1;
        }
        if j >= to {
            return false;
        }
        offsets[j] += 1;
        true
    }
}

/// The error and range of `dia` on `field` by the join formula, with a certified interval.
///
/// The points are visited without a bounding-box scan: for each offset `w` along the even axes
/// (clipped to the domain), the odd offsets run over `‖u‖∞ ≤ h − ‖w‖∞`; the even chain's part
/// of the interpolant depends on `w` only and is summed once per `w`.
pub fn diamond_stats_fast<const D: usize>(field: &Field<D>, dia: &Diamond<D>) -> DiamondStats {
    let l = Layout::new(field.hierarchy().side(), dia);
    let (h, m) = (l.h, l.m);
    let values = field.values();
    let g = gamma(D + 4) * 2.0;
    let two_h = (2 * h) as f64;
    let (mut error_lo, mut error_hi) = (0.0f64, 0.0f64);
    let (mut min, mut max) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut w = l.wlo;
    loop {
        let (nw, w_idx, chain, len) = l.even_chain(&w);
        let (mut acc_e, mut abs_e) = (0.0f64, 0.0f64);
        for &(weight, q) in &chain[..len] {
            let term = weight as f64 * values[q as usize];
            acc_e += term;
            abs_e += term.abs();
        }
        let r = h - nw;
        let lambda = 2 * r;
        // Odd offsets u ∈ [−r, r]^m.
        let mut u = [-r; D];
        loop {
            let mut idx = l.c_idx + w_idx;
            let mut t = [(0i64, 0usize); D];
            for j in 0..m {
                let (k, s) = l.oa[j];
                idx += u[j] * l.stride[k];
                t[j] = (s * u[j] + r, j);
            }
            let fp = values[idx as usize];
            min = min.min(fp);
            max = max.max(fp);
            t[..m].sort_unstable_by_key(|&(x, _)| std::cmp::Reverse(x));
            let (mut acc, mut abs) = (acc_e, abs_e);
            let mut v = l.a_idx;
            let mut prev = lambda;
            for &(tk, j) in &t[..m] {
                if prev != tk {
                    let term = (prev - tk) as f64 * values[v as usize];
                    acc += term;
                    abs += term.abs();
                }
                let (k, s) = l.oa[j];
                v += 2 * h * s * l.stride[k];
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
            if !Layout::<D>::next(&mut u, 0, m, |_| -r, |_| r) {
                break;
            }
        }
        if !Layout::<D>::next(&mut w, 0, l.ne, |j| l.wlo[j], |j| l.whi[j]) {
            break;
        }
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

/// The largest `|v|` of [`diamond_stats_integer`]'s samples: `2h·|F| ≤ 2^54` and the sums of
/// at most six such terms stay inside `i64`.
pub const MAX_INTEGER_SAMPLE: i32 = 1 << 24;

/// The samples as integers when every one is an integer of magnitude at most
/// [`MAX_INTEGER_SAMPLE`] (byte, short and integral float volumes), else `None`.
pub fn integer_samples<const D: usize>(field: &Field<D>) -> Option<Vec<i32>> {
    field
        .values()
        .iter()
        .map(|&v| {
            (v.fract() == 0.0 && v.abs() <= f64::from(MAX_INTEGER_SAMPLE)).then_some(v as i32)
        })
        .collect()
}

/// The error and range of `dia` for integer samples (`values` from [`integer_samples`]),
/// exactly: `2h·F̂` is an integer, so `2h·|F − F̂|` is computed in `i64` and the error is that
/// over `2h` (`error_lo == error_hi`).
///
/// Rows along the first odd axis `R` are walked without sorting per point: with the other
/// `T_k` of the row fixed, `2h·F̂_Q = C_p + T_R·G_p` where `p` is `T_R`'s rank among them, and
/// `C_p`, `G_p` come from one Kuhn-chain walk per rank.
pub fn diamond_stats_integer<const D: usize>(
    values: &[i32],
    side: u32,
    dia: &Diamond<D>,
) -> DiamondStats {
    let l = Layout::new(side, dia);
    let (h, m) = (l.h, l.m);
    let at = |i: i64| i64::from(values[i as usize]);
    let (row_axis, row_sign) = l.oa[0];
    let mut worst = 0i64;
    let (mut min, mut max) = (i64::MAX, i64::MIN);
    let mut w = l.wlo;
    loop {
        let (nw, w_idx, chain, len) = l.even_chain(&w);
        let acc_e: i64 = chain[..len].iter().map(|&(weight, q)| weight * at(q)).sum();
        let r = h - nw;
        let lambda = 2 * r;
        // The other odd offsets u[1..m] ∈ [−r, r]^(m−1); the row runs along oa[0].
        let mut u = [-r; D];
        loop {
            // The other odd axes' T, sorted descending.
            let mut others = [(0i64, 0usize); D];
            let mut row_idx = l.c_idx + w_idx;
            for j in 1..m {
                let (k, s) = l.oa[j];
                row_idx += u[j] * l.stride[k];
                others[j - 1] = (s * u[j] + r, j);
            }
            let no = m - 1;
            others[..no].sort_unstable_by_key(|&(x, _)| std::cmp::Reverse(x));
            // Per rank p of T_R: C_p and G_p by one walk of the Kuhn chain.
            let mut cs = [0i64; D];
            let mut gs = [0i64; D];
            for p in 0..m {
                let mut v = l.a_idx;
                let mut fv = at(v);
                let mut cp = lambda * fv;
                let mut gp = 0;
                for step in 0..m {
                    let j = match step.cmp(&p) {
                        std::cmp::Ordering::Less => others[step].1,
                        std::cmp::Ordering::Equal => 0,
                        std::cmp::Ordering::Greater => others[step - 1].1,
                    };
                    let (k, s) = l.oa[j];
                    v += 2 * h * s * l.stride[k];
                    let fnext = at(v);
                    let df = fnext - fv;
                    if j == 0 {
                        gp = df;
                    } else {
                        cp += (s * u[j] + r) * df;
                    }
                    fv = fnext;
                }
                cs[p] = cp;
                gs[p] = gp;
            }
            // The row's samples, in order; `|2h·F| ≤ 2^54` and each term below is a sum of at
            // most six such (see `MAX_INTEGER_SAMPLE`), so the wrapping operations never wrap.
            let stride = l.stride[row_axis];
            let first = (row_idx - r * stride) as usize;
            let row = values[first..]
                .iter()
                .step_by(stride as usize)
                .take((2 * r + 1) as usize);
            let two_h = 2 * h;
            for (ur, &f) in (-r..=r).zip(row) {
                let t_r = row_sign * ur + r;
                let p = others[..no].iter().take_while(|o| o.0 > t_r).count();
                let fp = i64::from(f);
                min = min.min(fp);
                max = max.max(fp);
                let e = two_h
                    .wrapping_mul(fp)
                    .wrapping_sub(cs[p])
                    .wrapping_sub(t_r.wrapping_mul(gs[p]))
                    .wrapping_sub(acc_e)
                    .wrapping_abs();
                worst = worst.max(e);
            }
            if !Layout::<D>::next(&mut u, 1, m, |_| -r, |_| r) {
                break;
            }
        }
        if !Layout::<D>::next(&mut w, 0, l.ne, |j| l.wlo[j], |j| l.whi[j]) {
            break;
        }
    }
    let error = worst as f64 / (2 * h) as f64;
    DiamondStats {
        error_lo: error,
        error_hi: error,
        min: min as f64,
        max: max as f64,
    }
}
