//! FFD lattices: a trivariate tensor-product hyperpatch (paper eq. 1) with a uniform B-spline
//! basis of orders `(l, m, n)` over `a × b × c` cells, or a single Bézier cell.
//!
//! Parameter domain: `[0,a] × [0,b] × [0,c]` for B-splines (uniform knots `−(l−1), …, a+l−1`,
//! unit spacing), `[0,1]³` for a Bézier cell. Control points are stored `u` fastest, then `v`,
//! then `w`, as exact rationals (an `f64` input is taken exactly).

use super::FfdError;
use crate::bernstein::io::parse_number;
use crate::bernstein::{Bernstein, ScaledBernstein};
use crate::bspline::TensorSpline;
use crate::num::{rational_to_string, Rational};
use num_bigint::BigInt;
use num_traits::{One, ToPrimitive, Zero};
use serde_json::{json, Value};

/// The basis of a lattice.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Basis {
    /// Uniform B-splines (the paper's choice, Section 3).
    Bspline,
    /// One Bernstein (Bézier) cell.
    Bezier,
}

impl Basis {
    /// `bspline` or `bezier`, as in the JSON format.
    pub fn name(self) -> &'static str {
        match self {
            Basis::Bspline => "bspline",
            Basis::Bezier => "bezier",
        }
    }
}

/// A control point.
pub type Point = [Rational; 3];

/// Largest order accepted per axis (the Jacobian has degree `3(order−1)−1` per axis).
pub const MAX_ORDER: usize = 8;
/// Largest number of cells accepted per axis.
pub const MAX_CELLS: usize = 64;

/// A trivariate FFD lattice.
#[derive(Clone, Debug, PartialEq)]
pub struct Lattice {
    basis: Basis,
    order: [usize; 3],
    cells: [usize; 3],
    points: Vec<Point>,
    /// The points as `f64` when every coordinate is exactly an `f64`.
    exact_f64: Option<Vec<[f64; 3]>>,
}

impl Lattice {
    /// Checks orders (2…[`MAX_ORDER`]), cells (1…[`MAX_CELLS`], exactly one per axis for
    /// Bézier) and the point count.
    pub fn new(
        basis: Basis,
        order: [usize; 3],
        cells: [usize; 3],
        points: Vec<Point>,
    ) -> Result<Lattice, FfdError> {
        Self::check_shape(basis, order, cells, points.len())?;
        let approx: Vec<[f64; 3]> = points
            .iter()
            .map(|p| [0, 1, 2].map(|a| crate::num::rational_to_f64(&p[a])))
            .collect();
        let exact = points.iter().zip(&approx).all(|(p, f)| {
            (0..3).all(|a| {
                crate::num::rational_from_f64(f[a], "c")
                    .map(|r| r == p[a])
                    .unwrap_or(false)
            })
        });
        Ok(Lattice {
            basis,
            order,
            cells,
            points,
            exact_f64: exact.then_some(approx),
        })
    }

    fn counts_for(basis: Basis, order: [usize; 3], cells: [usize; 3]) -> [usize; 3] {
        match basis {
            Basis::Bspline => [0, 1, 2].map(|a| cells[a] + order[a] - 1),
            Basis::Bezier => order,
        }
    }

    /// Checks the orders (2…[`MAX_ORDER`]) and cell counts (1…[`MAX_CELLS`], one for Bézier).
    fn check_orders_cells(
        basis: Basis,
        order: [usize; 3],
        cells: [usize; 3],
    ) -> Result<(), FfdError> {
        let bad = |field: &str, why: String| FfdError::Input {
            lattice: 0,
            field: field.into(),
            why,
        };
        if let Some(o) = order.iter().find(|&&o| !(2..=MAX_ORDER).contains(&o)) {
            return Err(bad(
                "order",
                format!("each order must be 2…{MAX_ORDER}, found {o}"),
            ));
        }
        if let Some(c) = cells.iter().find(|&&c| !(1..=MAX_CELLS).contains(&c)) {
            return Err(bad(
                "cells",
                format!("each cell count must be 1…{MAX_CELLS}, found {c}"),
            ));
        }
        if basis == Basis::Bezier && cells != [1, 1, 1] {
            return Err(bad(
                "cells",
                "a bezier lattice is one cell: cells must be [1,1,1]".into(),
            ));
        }
        Ok(())
    }

    /// Checks orders, cells and the point count.
    fn check_shape(
        basis: Basis,
        order: [usize; 3],
        cells: [usize; 3],
        count: usize,
    ) -> Result<(), FfdError> {
        Self::check_orders_cells(basis, order, cells)?;
        let bad = |field: &str, why: String| FfdError::Input {
            lattice: 0,
            field: field.into(),
            why,
        };
        let counts = Self::counts_for(basis, order, cells);
        let expected = counts.iter().product::<usize>();
        if count != expected {
            return Err(bad(
                "points",
                format!(
                    "expected {expected} points ({}×{}×{}), found {}",
                    counts[0], counts[1], counts[2], count
                ),
            ));
        }
        Ok(())
    }

    /// A lattice with `f64` control points, taken exactly (no round trip needed).
    pub fn from_f64(
        basis: Basis,
        order: [usize; 3],
        cells: [usize; 3],
        points: Vec<[f64; 3]>,
    ) -> Result<Self, FfdError> {
        let mut exact = Vec::with_capacity(points.len());
        for (i, p) in points.iter().enumerate() {
            let mut q: Point = Default::default();
            for a in 0..3 {
                q[a] = crate::num::rational_from_f64(p[a], "coordinate").map_err(|e| {
                    FfdError::Input {
                        lattice: 0,
                        field: format!("points[{i}][{a}]"),
                        why: e.to_string(),
                    }
                })?;
            }
            exact.push(q);
        }
        Self::check_shape(basis, order, cells, exact.len())?;
        Ok(Lattice {
            basis,
            order,
            cells,
            points: exact,
            exact_f64: Some(points),
        })
    }

    /// The undeformed lattice: points at the Greville abscissae, so `F(U) = U` (linear
    /// precision, paper Section 3).
    pub fn identity(basis: Basis, order: [usize; 3], cells: [usize; 3]) -> Result<Self, FfdError> {
        Self::check_orders_cells(basis, order, cells)?;
        let counts = Self::counts_for(basis, order, cells);
        let greville: Vec<Vec<Rational>> = (0..3)
            .map(|a| {
                let p = order[a] - 1;
                let knots = axis_knots(basis, order[a], cells[a]);
                (0..counts[a])
                    .map(|i| {
                        let s = knots[i + 1..=i + p]
                            .iter()
                            .fold(Rational::zero(), |acc, k| acc + k);
                        s / Rational::from_integer(BigInt::from(p))
                    })
                    .collect()
            })
            .collect();
        let mut points = Vec::with_capacity(counts.iter().product());
        for k in 0..counts[2] {
            for j in 0..counts[1] {
                for i in 0..counts[0] {
                    points.push([
                        greville[0][i].clone(),
                        greville[1][j].clone(),
                        greville[2][k].clone(),
                    ]);
                }
            }
        }
        Lattice::new(basis, order, cells, points)
    }

    /// B-spline or Bézier.
    pub fn basis(&self) -> Basis {
        self.basis
    }
    /// Order (degree + 1) per axis.
    pub fn order(&self) -> [usize; 3] {
        self.order
    }
    /// Cells per axis.
    pub fn cells(&self) -> [usize; 3] {
        self.cells
    }
    /// The control points, `u` fastest.
    pub fn points(&self) -> &[Point] {
        &self.points
    }
    /// Control points per axis.
    pub fn counts(&self) -> [usize; 3] {
        Self::counts_for(self.basis, self.order, self.cells)
    }
    /// Flat index of control point `(i, j, k)`.
    pub fn index(&self, i: usize, j: usize, k: usize) -> usize {
        let c = self.counts();
        i + c[0] * (j + c[1] * k)
    }
    /// The parameter domain per axis.
    pub fn domain(&self) -> [(Rational, Rational); 3] {
        [0, 1, 2].map(|a| {
            (
                Rational::zero(),
                Rational::from_integer(BigInt::from(self.cells[a])),
            )
        })
    }
    /// Number of cells.
    pub fn cell_count(&self) -> usize {
        self.cells.iter().product()
    }
    /// Cell multi-index of flat cell number `c` (`u` fastest).
    pub fn cell_index(&self, c: usize) -> [usize; 3] {
        [
            c % self.cells[0],
            (c / self.cells[0]) % self.cells[1],
            c / (self.cells[0] * self.cells[1]),
        ]
    }

    /// The lattice with `delta[i]` added to point `i`.
    pub fn displaced(&self, delta: &[Point]) -> Result<Lattice, FfdError> {
        if delta.len() != self.points.len() {
            return Err(FfdError::Input {
                lattice: 0,
                field: "points".into(),
                why: format!(
                    "displacement has {} points, lattice {}",
                    delta.len(),
                    self.points.len()
                ),
            });
        }
        let points = self
            .points
            .iter()
            .zip(delta)
            .map(|(p, d)| [0, 1, 2].map(|a| &p[a] + &d[a]))
            .collect();
        Lattice::new(self.basis, self.order, self.cells, points)
    }

    /// The knot vector of axis `a`.
    pub fn knots(&self, a: usize) -> Vec<Rational> {
        axis_knots(self.basis, self.order[a], self.cells[a])
    }

    /// Coordinate `coord` of the deformation as a tensor spline (paper eq. 1).
    pub fn coordinate_spline(&self, coord: usize) -> TensorSpline<Rational> {
        TensorSpline::new(
            self.order.iter().map(|o| o - 1).collect(),
            (0..3).map(|a| self.knots(a)).collect(),
            self.points.iter().map(|p| p[coord].clone()).collect(),
        )
        .expect("a validated lattice is a valid tensor spline")
    }

    /// The deformed position `F̃(U)` of a parameter point, exactly.
    pub fn deform(&self, u: &[Rational; 3]) -> Result<[Rational; 3], FfdError> {
        self.check_inside(u)?;
        let mut out = [Rational::zero(), Rational::zero(), Rational::zero()];
        for (c, o) in out.iter_mut().enumerate() {
            *o = self.coordinate_spline(c).eval(u)?;
        }
        Ok(out)
    }

    /// Errors unless `u` lies in the parameter domain.
    pub fn check_inside(&self, u: &[Rational; 3]) -> Result<(), FfdError> {
        for (a, (lo, hi)) in self.domain().iter().enumerate() {
            if &u[a] < lo || &u[a] > hi {
                return Err(FfdError::OutsideDomain {
                    axis: a,
                    value: rational_to_string(&u[a]),
                });
            }
        }
        Ok(())
    }

    /// The Bézier control net of every cell, per coordinate (exact; B-spline cells by the
    /// uniform span map in integers, checked against blossoming). Cell order as [`cell_index`](Self::cell_index).
    pub fn bezier_nets(&self) -> Vec<[Bernstein<Rational>; 3]> {
        if self.basis == Basis::Bezier {
            let degs: Vec<usize> = self.order.iter().map(|o| o - 1).collect();
            let coord = |c: usize| {
                Bernstein::new(
                    degs.clone(),
                    self.points.iter().map(|p| p[c].clone()).collect(),
                )
                .expect("counts match")
            };
            return vec![[coord(0), coord(1), coord(2)]];
        }
        self.bezier_nets_scaled()
            .iter()
            .map(|net| net.clone().map(|p| p.to_rational()))
            .collect()
    }

    /// [`bezier_nets`](Self::bezier_nets) as integer numerators over one denominator shared
    /// by every coordinate of every cell (no gcd anywhere): the input of the sign-only exact
    /// Jacobian ([`jacobian_cell_scaled_net`](super::jacobian::jacobian_cell_scaled_net)).
    pub fn bezier_nets_scaled(&self) -> Vec<[ScaledBernstein; 3]> {
        let [l, m, n] = self.order;
        let degs = vec![l - 1, m - 1, n - 1];
        let (nums, den) = common_denominator(self.points.iter().flatten());
        let coord = |c: usize| nums.iter().skip(c).step_by(3);
        if self.basis == Basis::Bezier {
            let one = |c: usize| {
                ScaledBernstein::with_denominator(
                    degs.clone(),
                    coord(c).cloned().collect(),
                    den.clone(),
                )
                .expect("counts match, den > 0")
            };
            return vec![[one(0), one(1), one(2)]];
        }
        // Uniform knots: every span's B-spline-to-Bézier map is the same matrix `K / d`
        // (integers over one denominator), applied along u, v, w in integers.
        let maps: Vec<(Vec<Vec<BigInt>>, BigInt)> =
            (0..3).map(|a| uniform_bezier_map(self.order[a])).collect();
        let total = &den * &maps[0].1 * &maps[1].1 * &maps[2].1;
        let small_maps: Option<Vec<Vec<Vec<i64>>>> = maps
            .iter()
            .map(|(k, _)| {
                k.iter()
                    .map(|row| row.iter().map(|x| x.to_i64()).collect())
                    .collect()
            })
            .collect();
        (0..self.cell_count())
            .map(|k| {
                let [ci, cj, ck] = self.cell_index(k);
                [0, 1, 2].map(|c| {
                    // The order-sized block of control numerators of this cell.
                    let mut block: Vec<BigInt> = Vec::with_capacity(l * m * n);
                    for w in 0..n {
                        for v in 0..m {
                            for u in 0..l {
                                block
                                    .push(nums[3 * self.index(ci + u, cj + v, ck + w) + c].clone());
                            }
                        }
                    }
                    let block =
                        apply_all_small(&block, [l, m, n], &small_maps).unwrap_or_else(|| {
                            for (axis, (kmat, _)) in maps.iter().enumerate() {
                                block = apply_along(&block, [l, m, n], axis, kmat);
                            }
                            block
                        });
                    ScaledBernstein::with_denominator(degs.clone(), block, total.clone())
                        .expect("counts match, den > 0")
                })
            })
            .collect()
    }

    /// The Bézier nets by blossoming each coordinate spline (the general B-spline route of
    /// `src/bspline/`): the reference [`bezier_nets`](Self::bezier_nets) is checked against.
    pub fn bezier_nets_by_blossoming(&self) -> Vec<[Bernstein<Rational>; 3]> {
        if self.basis == Basis::Bezier {
            return self.bezier_nets();
        }
        let per: Vec<Vec<Bernstein<Rational>>> = (0..3)
            .map(|c| {
                self.coordinate_spline(c)
                    .bezier_cells()
                    .into_iter()
                    .map(|cell| cell.poly)
                    .collect()
            })
            .collect();
        (0..self.cell_count())
            .map(|k| [per[0][k].clone(), per[1][k].clone(), per[2][k].clone()])
            .collect()
    }

    /// The JSON form (coordinates as exact `"p/q"` strings).
    pub fn to_json(&self) -> Value {
        json!({
            "basis": self.basis.name(),
            "order": self.order,
            "cells": self.cells,
            "points": self.points.iter().map(|p| p.iter().map(rational_to_string).collect::<Vec<_>>()).collect::<Vec<_>>(),
        })
    }

    /// The control points as `f64`, when every coordinate is exactly an `f64`.
    pub fn points_f64(&self) -> Option<&[[f64; 3]]> {
        self.exact_f64.as_deref()
    }
}

/// The uniform B-spline-to-Bézier map of one span for order `order`: Bézier coefficient `i`
/// is `Σ_j K[i][j] P_j / d` over the span's `order` control points (blossoms at the span's
/// ends, Ramshaw; computed once by converting unit coefficient vectors).
fn uniform_bezier_map(order: usize) -> (Vec<Vec<BigInt>>, BigInt) {
    let p = order - 1;
    let knots = axis_knots(Basis::Bspline, order, 1);
    let cols: Vec<Vec<Rational>> = (0..order)
        .map(|j| {
            let unit = (0..order)
                .map(|i| {
                    if i == j {
                        Rational::one()
                    } else {
                        Rational::zero()
                    }
                })
                .collect();
            crate::bspline::Spline::new(p, knots.clone(), unit)
                .expect("uniform knots")
                .bezier_on(p, &knots[p], &knots[p + 1])
        })
        .collect();
    let (_, d) = common_denominator(cols.iter().flatten());
    let k = (0..order)
        .map(|i| {
            (0..order)
                .map(|j| (&cols[j][i] * Rational::from_integer(d.clone())).to_integer())
                .collect()
        })
        .collect();
    (k, d)
}

/// Numerators over the least common denominator of `values`.
fn common_denominator<'a>(
    values: impl Iterator<Item = &'a Rational> + Clone,
) -> (Vec<BigInt>, BigInt) {
    use num_integer::Integer;
    let d = values
        .clone()
        .fold(BigInt::one(), |acc, v| acc.lcm(v.denom()));
    let nums = values.map(|v| v.numer() * (&d / v.denom())).collect();
    (nums, d)
}

/// [`apply_along`] on every axis in `i128` with overflow checks: `None` when a matrix or
/// block entry does not fit `i64` or a sum overflows (the caller then uses `BigInt`).
fn apply_all_small(
    block: &[BigInt],
    ext: [usize; 3],
    maps: &Option<Vec<Vec<Vec<i64>>>>,
) -> Option<Vec<BigInt>> {
    let maps = maps.as_ref()?;
    let mut cur: Vec<i128> = block
        .iter()
        .map(|v| v.to_i64().map(i128::from))
        .collect::<Option<_>>()?;
    for (axis, k) in maps.iter().enumerate() {
        let stride = [1, ext[0], ext[0] * ext[1]][axis];
        let len = ext[axis];
        let mut out = vec![0i128; cur.len()];
        for (idx, slot) in out.iter_mut().enumerate() {
            let i = (idx / stride) % len;
            let base = idx - i * stride;
            let mut acc = 0i128;
            for (j, &kij) in k[i].iter().enumerate() {
                if kij != 0 {
                    acc = acc.checked_add(i128::from(kij).checked_mul(cur[base + j * stride])?)?;
                }
            }
            *slot = acc;
        }
        cur = out;
    }
    Some(cur.into_iter().map(BigInt::from).collect())
}

/// Applies the square integer matrix `k` along `axis` of a block with extents `ext`
/// (`u` fastest).
fn apply_along(block: &[BigInt], ext: [usize; 3], axis: usize, k: &[Vec<BigInt>]) -> Vec<BigInt> {
    let stride = [1, ext[0], ext[0] * ext[1]][axis];
    let len = ext[axis];
    let mut out = vec![BigInt::zero(); block.len()];
    for (idx, slot) in out.iter_mut().enumerate() {
        let i = (idx / stride) % len;
        let base = idx - i * stride;
        let mut acc = BigInt::zero();
        for (j, kij) in k[i].iter().enumerate() {
            if !kij.is_zero() {
                acc += kij * &block[base + j * stride];
            }
        }
        *slot = acc;
    }
    out
}

/// The knots of one axis: uniform `−(l−1), …, cells+l−1` (B-spline), `0^l 1^l` (Bézier).
fn axis_knots(basis: Basis, order: usize, cells: usize) -> Vec<Rational> {
    let int = |i: i64| Rational::from_integer(BigInt::from(i));
    match basis {
        Basis::Bspline => {
            let p = order as i64 - 1;
            (-p..=cells as i64 + p).map(int).collect()
        }
        Basis::Bezier => {
            let mut k = vec![Rational::zero(); order];
            k.extend(std::iter::repeat_n(Rational::one(), order));
            k
        }
    }
}

/// Parses one lattice or an array of lattices (`{"basis", "order", "cells", "points"}`).
/// Errors name the lattice (its position in the array, 0 for a single one) and the field.
pub fn lattices_from_json(text: &str) -> Result<Vec<Lattice>, FfdError> {
    let v: Value = serde_json::from_str(text)?;
    match v {
        Value::Array(items) => items
            .iter()
            .enumerate()
            .map(|(i, item)| lattice_from_value(item).map_err(|e| e.in_lattice(i)))
            .collect(),
        other => Ok(vec![lattice_from_value(&other)?]),
    }
}

/// Parses one lattice object; `"points": "identity"` gives the undeformed lattice.
pub fn lattice_from_value(v: &Value) -> Result<Lattice, FfdError> {
    let bad = |field: &str, why: String| FfdError::Input {
        lattice: 0,
        field: field.into(),
        why,
    };
    let obj = v
        .as_object()
        .ok_or_else(|| bad("lattice", "expected a JSON object".into()))?;
    let basis = match obj.get("basis").and_then(Value::as_str) {
        Some("bspline") => Basis::Bspline,
        Some("bezier") => Basis::Bezier,
        Some(other) => {
            return Err(bad(
                "basis",
                format!("expected \"bspline\" or \"bezier\", found \"{other}\""),
            ))
        }
        None => return Err(bad("basis", "missing or not a string".into())),
    };
    let triple = |field: &str| -> Result<[usize; 3], FfdError> {
        let arr = obj
            .get(field)
            .and_then(Value::as_array)
            .ok_or_else(|| bad(field, "missing or not an array".into()))?;
        if arr.len() != 3 {
            return Err(bad(
                field,
                format!("expected 3 integers, found {}", arr.len()),
            ));
        }
        let mut out = [0usize; 3];
        for (o, x) in out.iter_mut().zip(arr) {
            *o = x.as_u64().filter(|&n| n <= 1 << 20).ok_or_else(|| {
                bad(
                    field,
                    format!("expected a small non-negative integer, found {x}"),
                )
            })? as usize;
        }
        Ok(out)
    };
    let order = triple("order")?;
    let cells = match obj.get("cells") {
        None if basis == Basis::Bezier => [1, 1, 1],
        _ => triple("cells")?,
    };
    if obj.get("points").and_then(Value::as_str) == Some("identity") {
        return Lattice::identity(basis, order, cells);
    }
    let pts = obj
        .get("points")
        .and_then(Value::as_array)
        .ok_or_else(|| bad("points", "missing, not an array, nor \"identity\"".into()))?;
    let mut points = Vec::with_capacity(pts.len());
    for (i, p) in pts.iter().enumerate() {
        let field = format!("points[{i}]");
        let xyz = p
            .as_array()
            .filter(|a| a.len() == 3)
            .ok_or_else(|| bad(&field, "expected [x, y, z]".into()))?;
        let mut q = [Rational::zero(), Rational::zero(), Rational::zero()];
        for (a, (slot, x)) in q.iter_mut().zip(xyz).enumerate() {
            *slot =
                parse_number(x).map_err(|why| bad(&format!("{field}[{a}]"), why.to_string()))?;
        }
        points.push(q);
    }
    Lattice::new(basis, order, cells, points)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integer_span_map_equals_blossoming() {
        for (order, cells) in [
            ([4, 4, 4], [2, 3, 1]),
            ([2, 3, 5], [3, 1, 2]),
            ([6, 3, 2], [1, 2, 2]),
        ] {
            let id = Lattice::identity(Basis::Bspline, order, cells).unwrap();
            let delta: Vec<Point> = (0..id.points().len())
                .map(|i| {
                    [0, 1, 2].map(|a| {
                        Rational::new(
                            BigInt::from((i * 37 + a * 11) as i64 % 23 - 11),
                            BigInt::from(7 + (i % 5) as i64 * 3),
                        )
                    })
                })
                .collect();
            let l = id.displaced(&delta).unwrap();
            assert_eq!(
                l.bezier_nets(),
                l.bezier_nets_by_blossoming(),
                "{order:?} {cells:?}"
            );
        }
    }

    /// The integer nets share one denominator and equal the rational nets, Bézier and B-spline,
    /// with small numbers (the `i128` route) and 2^80-sized ones (the `BigInt` route).
    #[test]
    fn scaled_nets_equal_rational_nets() {
        for (basis, order, cells, shift) in [
            (Basis::Bezier, [3, 4, 2], [1, 1, 1], 0),
            (Basis::Bspline, [4, 3, 2], [2, 1, 3], 0),
            (Basis::Bspline, [4, 3, 2], [2, 1, 3], 80),
        ] {
            let id = Lattice::identity(basis, order, cells).unwrap();
            let delta: Vec<Point> = (0..id.points().len())
                .map(|i| {
                    [0, 1, 2].map(|a| {
                        Rational::new(
                            BigInt::from((i * 13 + a) as i64 % 9 - 4) << shift,
                            BigInt::from(5 + a as i64),
                        )
                    })
                })
                .collect();
            let l = id.displaced(&delta).unwrap();
            let scaled = l.bezier_nets_scaled();
            let den = scaled[0][0].denominator().clone();
            assert!(scaled.iter().flatten().all(|p| p.denominator() == &den));
            let back: Vec<[Bernstein<Rational>; 3]> = scaled
                .iter()
                .map(|net| net.clone().map(|p| p.to_rational()))
                .collect();
            assert_eq!(back, l.bezier_nets(), "{basis:?} {order:?} {cells:?}");
        }
    }
}
