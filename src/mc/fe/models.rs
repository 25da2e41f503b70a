//! Small analytic models for tests and reports.

use super::{ElementKind, FeModel};

/// `f = x² + y² + z²` on an `e × e × e` block of tricubic Hermite elements covering
/// `[−1, 1]³`. Quadratics are cubics, so the interpolant is exactly `f`: nodal values,
/// `f_ξd = 2 x_d h` (element size `h = 2/e`) and zero mixed derivatives; the geometry is the
/// affine map with `x_ξd = h e_d`. The level set `f = r²` (`r < 1`) is a closed sphere.
pub fn hermite_ball(e: usize) -> FeModel<f64> {
    let h = 2.0 / e as f64;
    let world = |p: [f64; 3]| p.map(|a| -1.0 + h * a);
    let value = |p: [f64; 3]| world(p).iter().map(|x| x * x).sum();
    let derivative = |p: [f64; 3], der: [bool; 3]| match der.iter().filter(|&&b| b).count() {
        1 => 2.0 * world(p)[der.iter().position(|&b| b).expect("one direction")] * h,
        _ => 0.0,
    };
    let mut m = block(
        ElementKind::TRICUBIC_HERMITE,
        [e; 3],
        &value,
        &derivative,
        &world,
    );
    // The block's coordinate tangents are unit vectors; the map scales them by h.
    let ndof = m.kind.dofs_per_node();
    for (i, c) in m.coordinates.iter_mut().enumerate() {
        if i % ndof != 0 {
            *c = c.map(|x| x * h);
        }
    }
    m
}

/// One period of the gyroid `sin x cos y + sin y cos z + sin z cos x` across a block of `e³`
/// trilinear Lagrange elements, sampled at nodes that a smooth warp moves off the grid (the
/// same surface at every `e`; its level sets cross many element faces). The report's and the
/// benchmark's trilinear model.
pub fn gyroid_block(e: usize) -> FeModel<f64> {
    let k = std::f64::consts::TAU / e as f64;
    let f = move |p: [f64; 3]| {
        (k * p[0]).sin() * (k * p[1]).cos()
            + (k * p[1]).sin() * (k * p[2]).cos()
            + (k * p[2]).sin() * (k * p[0]).cos()
    };
    block(
        ElementKind::TRILINEAR_LAGRANGE,
        [e; 3],
        &f,
        &|_, _| 0.0,
        &|p| {
            [
                p[0] + 0.1 * (0.3 * p[1]).sin(),
                p[1] + 0.1 * (0.3 * p[2]).sin(),
                p[2],
            ]
        },
    )
}

/// A block of `e[0] × e[1] × e[2]` elements of `kind` over unit cells: node `(i, j, k)` at
/// `warp((i, j, k))` with field value `value((i, j, k))`; a single ξ-derivative of the
/// coordinates is the unit vector along its direction, mixed ones are zero (straight
/// coordinate lines before the warp, which moves nodes only); field derivatives come from
/// `derivative(point, directions)`. Nodes are numbered `i` fastest; elements likewise, each
/// in tensor order.
pub fn block(
    kind: ElementKind,
    e: [usize; 3],
    value: &dyn Fn([f64; 3]) -> f64,
    derivative: &dyn Fn([f64; 3], [bool; 3]) -> f64,
    warp: &dyn Fn([f64; 3]) -> [f64; 3],
) -> FeModel<f64> {
    let id = |i: usize, j: usize, k: usize| (i + (e[0] + 1) * (j + (e[1] + 1) * k)) as u32;
    let mut coordinates = Vec::new();
    let mut field = Vec::new();
    for k in 0..=e[2] {
        for j in 0..=e[1] {
            for i in 0..=e[0] {
                let p = [i as f64, j as f64, k as f64];
                for dof in 0..kind.dofs_per_node() {
                    let der = kind.derivative_of_dof(dof);
                    if dof == 0 {
                        coordinates.push(warp(p));
                        field.push(value(p));
                        continue;
                    }
                    let mut c = [0.0; 3];
                    if der.iter().filter(|&&b| b).count() == 1 {
                        c[der.iter().position(|&b| b).expect("one direction")] = 1.0;
                    }
                    coordinates.push(c);
                    field.push(derivative(p, der));
                }
            }
        }
    }
    let mut elements = Vec::new();
    for k in 0..e[2] {
        for j in 0..e[1] {
            for i in 0..e[0] {
                elements.push(std::array::from_fn(|l| {
                    id(i + (l & 1), j + (l >> 1 & 1), k + (l >> 2 & 1))
                }));
            }
        }
    }
    FeModel {
        kind,
        coordinates,
        field,
        elements,
    }
}
