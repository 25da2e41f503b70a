//! The FFD Jacobian `det J` (paper eq. 5), exactly, by two independent routes.
//!
//! * **Mørken route** (the reference, paper Section 6 steps 1–3): the partial derivatives of
//!   eq. 1 are tensor B-splines whose coefficients are the difference vectors `P̃^(u)`, `P̃^(v)`,
//!   `P̃^(w)` of eq. 7; `det J = Σ_c ∂_u F̃_c · (∂_v F̃ × ∂_w F̃)_c` (eq. 9) is formed with Mørken
//!   products into one tensor B-spline of degree `3(l−1)−1` per axis (eq. 8; interior knots of
//!   multiplicity `2l−1`), and every cell is then brought to Bézier form by knot insertion.
//!   Pairwise products give the same knot vector as the three-factor product of eq. 6: the
//!   multiplicity `Σd_i − min_i(d_i − m_i)` is associative.
//! * **Per-cell Bézier route**: each cell's control net in Bézier form, its partial derivatives
//!   (`d (b_{i+1} − b_i)` per axis) and Bernstein products. Exact in rationals
//!   ([`jacobian_cell_bezier`]) or in sign-only integers ([`jacobian_cell_scaled`]).
//!
//! Both give identical Bézier coefficients (proof `ffd-jacobian-routes`).

use super::lattice::Lattice;
use super::FfdError;
use crate::bernstein::{Bernstein, ScaledBernstein};
use crate::bspline::{tensor::TableCache, ScaledSpline, TensorSpline};
use crate::num::Rational;
use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::{One, Zero};

/// `[axis][coord]`: `∂F̃_coord / ∂u_axis` as tensor splines (coefficients: eq. 7's differences).
pub(crate) fn partial_derivatives(
    l: &Lattice,
) -> Result<[[TensorSpline<Rational>; 3]; 3], FfdError> {
    let coords = [0, 1, 2].map(|c| l.coordinate_spline(c));
    let d = |axis: usize, c: usize| coords[c].derivative(axis).map_err(FfdError::from);
    Ok([
        [d(0, 0)?, d(0, 1)?, d(0, 2)?],
        [d(1, 0)?, d(1, 1)?, d(1, 2)?],
        [d(2, 0)?, d(2, 1)?, d(2, 2)?],
    ])
}

fn kernel<T>(r: Result<T, crate::bspline::BsplineError>) -> Result<T, FfdError> {
    r.map_err(FfdError::from)
}

/// `det J` as one trivariate tensor B-spline through Mørken products (eq. 8), in integer
/// numerators over one denominator per factor set, reduced once at the end.
pub fn jacobian_spline(l: &Lattice) -> Result<TensorSpline<Rational>, FfdError> {
    kernel(jacobian_spline_scaled(l)?.to_rational())
}

/// [`jacobian_spline`] left as integer numerators over one denominator (no reduction).
#[allow(clippy::needless_range_loop)] // the index also picks partner rows/columns
pub fn jacobian_spline_scaled(l: &Lattice) -> Result<ScaledSpline, FfdError> {
    let [fu, fv, fw] = partial_derivatives(l)?;
    let scaled = |f: &[TensorSpline<Rational>; 3]| ScaledSpline::common(&[&f[0], &f[1], &f[2]]);
    let (fu, fv, fw) = (scaled(&fu), scaled(&fv), scaled(&fw));
    let mut cache = TableCache::default();
    let mut det: Option<ScaledSpline> = None;
    for c in 0..3 {
        let (a, b) = ((c + 1) % 3, (c + 2) % 3);
        // (∂_v F̃ × ∂_w F̃)_c = ∂_v F̃_a ∂_w F̃_b − ∂_v F̃_b ∂_w F̃_a.
        let cross = kernel(
            kernel(fv[a].product(&fw[b], &mut cache))?
                .sub(&kernel(fv[b].product(&fw[a], &mut cache))?),
        )?;
        let term = kernel(fu[c].product(&cross, &mut cache))?;
        det = Some(match det {
            None => term,
            Some(d) => kernel(d.add(&term))?,
        });
    }
    Ok(det.expect("three terms"))
}

/// The Bézier form of `det J` on every cell (order as [`Lattice::cell_index`]) by the
/// Mørken route: [`jacobian_spline`], then knot insertion (Section 6, step 3).
pub fn jacobian_cells_morken(l: &Lattice) -> Result<Vec<Bernstein<Rational>>, FfdError> {
    Ok(jacobian_cells_morken_scaled(l)?
        .iter()
        .map(ScaledBernstein::to_rational)
        .collect())
}

/// [`jacobian_cells_morken`] in integers over one shared denominator: the Mørken products
/// and the knot insertion take no gcd, so a positivity certificate reads signs directly.
pub fn jacobian_cells_morken_scaled(l: &Lattice) -> Result<Vec<ScaledBernstein>, FfdError> {
    kernel(jacobian_spline_scaled(l)?.bezier_cells())
}

/// The Bézier form of `det J` on one cell from the cell's Bézier control net (one Bernstein
/// polynomial per coordinate), by exact Bernstein products.
#[allow(clippy::needless_range_loop)] // the index also picks partner rows/columns
pub fn jacobian_cell_bezier(
    net: &[Bernstein<Rational>; 3],
) -> Result<Bernstein<Rational>, FfdError> {
    let k = |r: Result<Bernstein<Rational>, crate::bernstein::BernsteinError>| {
        r.map_err(FfdError::from)
    };
    let d = |axis: usize, c: usize| k(net[c].derivative(axis));
    let fu = [d(0, 0)?, d(0, 1)?, d(0, 2)?];
    let fv = [d(1, 0)?, d(1, 1)?, d(1, 2)?];
    let fw = [d(2, 0)?, d(2, 1)?, d(2, 2)?];
    let minus_one = -Rational::one();
    let mut det: Option<Bernstein<Rational>> = None;
    for c in 0..3 {
        let (a, b) = ((c + 1) % 3, (c + 2) % 3);
        let cross = k(k(fv[a].product(&fw[b]))?.add(&k(fv[b].product(&fw[a]))?.scale(&minus_one)))?;
        let term = k(fu[c].product(&cross))?;
        det = Some(match det {
            None => term,
            Some(s) => k(s.add(&term))?,
        });
    }
    Ok(det.expect("three terms"))
}

/// The same in sign-only integers: the net is brought to one common denominator, so every
/// derivative, product and sum stays over a shared denominator (no gcd anywhere).
pub fn jacobian_cell_scaled(net: &[Bernstein<Rational>; 3]) -> Result<ScaledBernstein, FfdError> {
    jacobian_cell_scaled_net(&scaled_net(net)?)
}

/// [`jacobian_cell_scaled`] from a net already in integers (best over one shared denominator,
/// as [`Lattice::bezier_nets_scaled`] gives it).
#[allow(clippy::needless_range_loop)] // the index also picks partner rows/columns
pub fn jacobian_cell_scaled_net(
    scaled: &[ScaledBernstein; 3],
) -> Result<ScaledBernstein, FfdError> {
    let k =
        |r: Result<ScaledBernstein, crate::bernstein::BernsteinError>| r.map_err(FfdError::from);
    let d = |axis: usize, c: usize| k(scaled[c].derivative(axis));
    let fu = [d(0, 0)?, d(0, 1)?, d(0, 2)?];
    let fv = [d(1, 0)?, d(1, 1)?, d(1, 2)?];
    let fw = [d(2, 0)?, d(2, 1)?, d(2, 2)?];
    let mut det: Option<ScaledBernstein> = None;
    for c in 0..3 {
        let (a, b) = ((c + 1) % 3, (c + 2) % 3);
        let cross = k(k(fv[a].product(&fw[b]))?.sub(&k(fv[b].product(&fw[a]))?))?;
        let term = k(fu[c].product(&cross))?;
        det = Some(match det {
            None => term,
            Some(s) => k(s.add(&term))?,
        });
    }
    Ok(det.expect("three terms"))
}

/// A cell's Bézier net as three integer polynomials over one shared denominator.
pub(crate) fn scaled_net(net: &[Bernstein<Rational>; 3]) -> Result<[ScaledBernstein; 3], FfdError> {
    let mut den = BigInt::one();
    for c in net.iter().flat_map(|p| p.coeffs()) {
        den = den.lcm(c.denom());
    }
    let one = |p: &Bernstein<Rational>| {
        let num = p
            .coeffs()
            .iter()
            .map(|c| c.numer() * (&den / c.denom()))
            .collect();
        ScaledBernstein::with_denominator(p.degrees().to_vec(), num, den.clone())
            .map_err(FfdError::from)
    };
    Ok([one(&net[0])?, one(&net[1])?, one(&net[2])?])
}

/// The `p+1` basis functions `N_{μ−p..μ, p}` nonzero at `x` and their derivatives, exactly:
/// Cox–de Boor's triangular scheme (Piegl & Tiller, *The NURBS Book*, A2.2) and
/// `N'_{i,p} = p N_{i,p−1}/(t_{i+p} − t_i) − p N_{i+1,p−1}/(t_{i+p+1} − t_{i+1})` (eq. 2.7).
/// Returns `(μ − p, values, derivatives)`. The span `μ` is `span` when given (one-sided values
/// at a knot, from inside `[t_μ, t_{μ+1}]`), else the one with `t_μ ≤ x < t_{μ+1}` (the last
/// span at the right end). The caller keeps `x` inside the domain `[t_p, t_n]`.
pub(crate) fn basis_at(
    knots: &[Rational],
    p: usize,
    x: &Rational,
    span: Option<usize>,
) -> (usize, Vec<Rational>, Vec<Rational>) {
    let n = knots.len() - p - 1;
    let mut mu = p;
    match span {
        Some(s) => mu = s,
        None => {
            while mu + 1 < n && &knots[mu + 1] <= x {
                mu += 1;
            }
        }
    }
    let zero = Rational::default();
    let mut below: Vec<Rational> = Vec::new();
    let mut level = vec![Rational::one()];
    for j in 1..=p {
        below = level.clone();
        let mut next = vec![zero.clone(); j + 1];
        let mut saved = zero.clone();
        for r in 0..j {
            let right = &knots[mu + r + 1] - x;
            let left = x - &knots[mu + 1 + r - j];
            let temp = &level[r] / (&knots[mu + r + 1] - &knots[mu + 1 + r - j]);
            next[r] = &saved + &right * &temp;
            saved = left * temp;
        }
        next[j] = saved;
        level = next;
    }
    let mut deriv = vec![zero.clone(); p + 1];
    if p > 0 {
        let pr = Rational::from_integer(BigInt::from(p));
        for (r, d) in deriv.iter_mut().enumerate() {
            let i = mu - p + r;
            if r >= 1 {
                let den = &knots[i + p] - &knots[i];
                if den != zero {
                    *d += &pr * &below[r - 1] / den;
                }
            }
            if r < p {
                let den = &knots[i + p + 1] - &knots[i + 1];
                if den != zero {
                    *d -= &pr * &below[r] / den;
                }
            }
        }
    }
    (mu - p, level, deriv)
}

/// Per axis: the first nonzero basis index, the values and the derivatives (each as integer
/// numerators over a common denominator).
type AxisBasis = (usize, (Vec<BigInt>, BigInt), (Vec<BigInt>, BigInt));

/// Integer numerators over one common denominator.
fn common(values: &[Rational]) -> (Vec<BigInt>, BigInt) {
    let den = values
        .iter()
        .fold(BigInt::one(), |acc, v| acc.lcm(v.denom()));
    (
        values
            .iter()
            .map(|v| v.numer() * (&den / v.denom()))
            .collect(),
        den,
    )
}

/// The Jacobian matrix `J[coord][axis] = ∂F̃_coord/∂u_axis` at a parameter point, exactly:
/// eq. 1 differentiated, `Σ P_{ijk} N'_i(u) N_j(v) N_k(w)` etc., with the basis values from
/// [`basis_at`] and the sums in integers over common denominators. Independent of both Bézier
/// routes, so it re-checks their witnesses.
///
/// With `cell`, the point must lie in that closed cell and the derivatives are the cell's
/// one-sided ones (order-2 lattices are only C⁰ across cell faces); without, the cell
/// containing the point on the right is used.
#[allow(clippy::needless_range_loop)] // the index also picks partner rows/columns
pub(crate) fn jacobian_matrix_in_cell(
    l: &Lattice,
    cell: Option<[usize; 3]>,
    u: &[Rational; 3],
) -> Result<[[Rational; 3]; 3], FfdError> {
    l.check_inside(u)?;
    let order = l.order();
    if let Some(c) = cell {
        let dims = l.cells();
        for a in 0..3 {
            let lo = Rational::from_integer(BigInt::from(c[a]));
            let hi = &lo + Rational::one();
            if c[a] >= dims[a] || u[a] < lo || u[a] > hi {
                return Err(FfdError::OutsideDomain {
                    axis: a,
                    value: format!(
                        "{} (not in cell {c:?})",
                        crate::num::rational_to_string(&u[a])
                    ),
                });
            }
        }
    }
    let per_axis: Vec<AxisBasis> = (0..3)
        .map(|a| {
            let p = order[a] - 1;
            let (first, vals, ders) = basis_at(&l.knots(a), p, &u[a], cell.map(|c| c[a] + p));
            (first, common(&vals), common(&ders))
        })
        .collect();
    // Control points of the influencing block, over one denominator.
    let mut block: Vec<Rational> = Vec::with_capacity(3 * order[0] * order[1] * order[2]);
    for k in 0..order[2] {
        for j in 0..order[1] {
            for i in 0..order[0] {
                let p =
                    &l.points()[l.index(per_axis[0].0 + i, per_axis[1].0 + j, per_axis[2].0 + k)];
                block.extend(p.iter().cloned());
            }
        }
    }
    let (pts, pden) = common(&block);
    let mut out: [[Rational; 3]; 3] = Default::default();
    for axis in 0..3 {
        // Factor per axis: derivative along `axis`, values elsewhere.
        let f = |a: usize| {
            if a == axis {
                &per_axis[a].2
            } else {
                &per_axis[a].1
            }
        };
        let (fu, fv, fw) = (f(0), f(1), f(2));
        let mut sums = [BigInt::zero(), BigInt::zero(), BigInt::zero()];
        let mut at = 0;
        for k in 0..order[2] {
            for j in 0..order[1] {
                let vw = &fv.0[j] * &fw.0[k];
                for i in 0..order[0] {
                    let w = &fu.0[i] * &vw;
                    for (c, sum) in sums.iter_mut().enumerate() {
                        *sum += &w * &pts[at + c];
                    }
                    at += 3;
                }
            }
        }
        let den = &pden * &fu.1 * &fv.1 * &fw.1;
        for c in 0..3 {
            out[c][axis] = Rational::new(sums[c].clone(), den.clone());
        }
    }
    Ok(out)
}

/// `jacobian_matrix_in_cell` in the cell containing `u` on the right.
pub fn jacobian_matrix_at(l: &Lattice, u: &[Rational; 3]) -> Result<[[Rational; 3]; 3], FfdError> {
    jacobian_matrix_in_cell(l, None, u)
}

/// `det J` at a parameter point, exactly (eq. 5), from [`jacobian_matrix_at`].
pub fn jacobian_at(l: &Lattice, u: &[Rational; 3]) -> Result<Rational, FfdError> {
    Ok(det3(&jacobian_matrix_at(l, u)?))
}

/// `det J` at a point of the closed cell `cell`, with that cell's one-sided derivatives.
pub fn jacobian_in_cell(
    l: &Lattice,
    cell: [usize; 3],
    u: &[Rational; 3],
) -> Result<Rational, FfdError> {
    Ok(det3(&jacobian_matrix_in_cell(l, Some(cell), u)?))
}

/// The determinant of a 3×3 rational matrix.
pub(crate) fn det3(m: &[[Rational; 3]; 3]) -> Rational {
    let minor = |a: usize, b: usize| &m[1][a] * &m[2][b] - &m[1][b] * &m[2][a];
    &m[0][0] * minor(1, 2) - &m[0][1] * minor(0, 2) + &m[0][2] * minor(0, 1)
}

/// A parameter point of cell `cell` from local coordinates `t ∈ [0,1]³`.
pub(crate) fn cell_point(cell: [usize; 3], t: &[Rational]) -> [Rational; 3] {
    [0, 1, 2].map(|a| Rational::from_integer(BigInt::from(cell[a])) + &t[a])
}
