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
use crate::bspline::{tensor::TableCache, TensorSpline};
use crate::num::Rational;
use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::One;

/// `[axis][coord]`: `∂F̃_coord / ∂u_axis` as tensor splines (coefficients: eq. 7's differences).
pub fn partial_derivatives(l: &Lattice) -> Result<[[TensorSpline<Rational>; 3]; 3], FfdError> {
    let coords = [0, 1, 2].map(|c| l.coordinate_spline(c));
    let d = |axis: usize, c: usize| {
        coords[c]
            .derivative(axis)
            .map_err(|e| FfdError::Kernel(e.to_string()))
    };
    Ok([
        [d(0, 0)?, d(0, 1)?, d(0, 2)?],
        [d(1, 0)?, d(1, 1)?, d(1, 2)?],
        [d(2, 0)?, d(2, 1)?, d(2, 2)?],
    ])
}

fn kernel<T>(r: Result<T, crate::bspline::BsplineError>) -> Result<T, FfdError> {
    r.map_err(|e| FfdError::Kernel(e.to_string()))
}

/// `det J` as one trivariate tensor B-spline through Mørken products (eq. 8).
pub fn jacobian_spline(l: &Lattice) -> Result<TensorSpline<Rational>, FfdError> {
    let [fu, fv, fw] = partial_derivatives(l)?;
    let mut cache = TableCache::default();
    let mut det: Option<TensorSpline<Rational>> = None;
    for c in 0..3 {
        let (a, b) = ((c + 1) % 3, (c + 2) % 3);
        // (∂_v F̃ × ∂_w F̃)_c = ∂_v F̃_a ∂_w F̃_b − ∂_v F̃_b ∂_w F̃_a.
        let cross = kernel(
            kernel(fv[a].product_exact(&fw[b]))?.sub(&kernel(fv[b].product_exact(&fw[a]))?),
        )?;
        let term = kernel(fu[c].product_exact_cached(&cross, &mut cache))?;
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
    let det = jacobian_spline(l)?;
    Ok(kernel(det.bezier_cells_by_insertion())?
        .into_iter()
        .map(|c| c.poly)
        .collect())
}

/// The Bézier form of `det J` on one cell from the cell's Bézier control net (one Bernstein
/// polynomial per coordinate), by exact Bernstein products.
pub fn jacobian_cell_bezier(
    net: &[Bernstein<Rational>; 3],
) -> Result<Bernstein<Rational>, FfdError> {
    let k = |r: Result<Bernstein<Rational>, crate::bernstein::BernsteinError>| {
        r.map_err(|e| FfdError::Kernel(e.to_string()))
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
    let k = |r: Result<ScaledBernstein, crate::bernstein::BernsteinError>| {
        r.map_err(|e| FfdError::Kernel(e.to_string()))
    };
    let mut den = BigInt::one();
    for c in net.iter().flat_map(|p| p.coeffs()) {
        den = den.lcm(c.denom());
    }
    let scaled: Vec<ScaledBernstein> = net
        .iter()
        .map(|p| {
            let num = p
                .coeffs()
                .iter()
                .map(|c| c.numer() * (&den / c.denom()))
                .collect();
            k(ScaledBernstein::with_denominator(
                p.degrees().to_vec(),
                num,
                den.clone(),
            ))
        })
        .collect::<Result<_, _>>()?;
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

/// The Jacobian matrix `J[coord][axis] = ∂F̃_coord/∂u_axis` at a parameter point, exactly.
pub fn jacobian_matrix_at(l: &Lattice, u: &[Rational; 3]) -> Result<[[Rational; 3]; 3], FfdError> {
    l.check_inside(u)?;
    let d = partial_derivatives(l)?;
    let mut j: [[Rational; 3]; 3] = Default::default();
    for (axis, per_coord) in d.iter().enumerate() {
        for (c, s) in per_coord.iter().enumerate() {
            j[c][axis] = kernel(s.eval(u))?;
        }
    }
    Ok(j)
}

/// `det J` at a parameter point, exactly (eq. 5), from the derivative splines directly —
/// independent of both Bézier routes.
pub fn jacobian_at(l: &Lattice, u: &[Rational; 3]) -> Result<Rational, FfdError> {
    Ok(det3(&jacobian_matrix_at(l, u)?))
}

/// The determinant of a 3×3 rational matrix.
pub fn det3(m: &[[Rational; 3]; 3]) -> Rational {
    let minor = |a: usize, b: usize| &m[1][a] * &m[2][b] - &m[1][b] * &m[2][a];
    &m[0][0] * minor(1, 2) - &m[0][1] * minor(0, 2) + &m[0][2] * minor(0, 1)
}

/// A parameter point of cell `cell` from local coordinates `t ∈ [0,1]³`.
pub fn cell_point(cell: [usize; 3], t: &[Rational]) -> [Rational; 3] {
    [0, 1, 2].map(|a| Rational::from_integer(BigInt::from(cell[a])) + &t[a])
}
