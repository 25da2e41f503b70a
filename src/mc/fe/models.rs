//! Small analytic models for tests and reports.

use super::{ElementKind, FeModel};

/// `f = x² + y² + z²` on an `e × e × e` block of tricubic Hermite elements covering
/// `[−1, 1]³`. Quadratics are cubics, so the interpolant is exactly `f`: nodal values,
/// `f_ξd = 2 x_d h` (element size `h = 2/e`) and zero mixed derivatives; the geometry is the
/// affine map with `x_ξd = h e_d`. The level set `f = r²` (`r < 1`) is a closed sphere.
pub fn hermite_ball(e: usize) -> FeModel<f64> {
    let kind = ElementKind::TRICUBIC_HERMITE;
    let h = 2.0 / e as f64;
    let id = |i: usize, j: usize, k: usize| (i + (e + 1) * (j + (e + 1) * k)) as u32;
    let mut coordinates = Vec::new();
    let mut field = Vec::new();
    for k in 0..=e {
        for j in 0..=e {
            for i in 0..=e {
                let p = [i, j, k].map(|a| -1.0 + h * a as f64);
                for dof in 0..kind.dofs_per_node() {
                    let der = kind.derivative_of_dof(dof);
                    match der.iter().filter(|&&b| b).count() {
                        0 => {
                            coordinates.push(p);
                            field.push(p.iter().map(|x| x * x).sum());
                        }
                        1 => {
                            let d = der.iter().position(|&b| b).expect("one direction");
                            let mut c = [0.0; 3];
                            c[d] = h;
                            coordinates.push(c);
                            field.push(2.0 * p[d] * h);
                        }
                        _ => {
                            coordinates.push([0.0; 3]);
                            field.push(0.0);
                        }
                    }
                }
            }
        }
    }
    let mut elements = Vec::new();
    for k in 0..e {
        for j in 0..e {
            for i in 0..e {
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
