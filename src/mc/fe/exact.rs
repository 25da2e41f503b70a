//! The reference path: Section 3.3's algorithm in rational arithmetic.
//!
//! Three hash tables as in Section 3.2: sampled values by lattice point name, cut-edge
//! vertices by edge name, and (for the Figure 7 merge) vertices by exact world position.
//! Ambiguous faces are decided as the paper does, by sorting the cut points' `ξ`
//! coordinates (Mackerras' rule), with the decider's tie rule: equal positions count as
//! joined.

use super::basis::terms_scaled;
use super::lattice::{edge_key, point_key, EdgeKey, PointKey};
use super::{
    cell_corner, cell_edge, classify, face_abcd, prepare, tube_mesh, tube_triangles, weld,
    CellRule, FeError, FeModel, FeOptions, FeStats,
};
use crate::mc::table::{is_positive, table, CENTRE};
use crate::mc::trilinear::polygonise::interior_position;
use crate::num::Rational;
use num_traits::{Signed, Zero};
use std::collections::HashMap;

/// An exact isosurface: rational world positions and triangles wound so that their normal
/// points into the positive region (`v ≥ iso`).
#[derive(Clone, Debug, PartialEq)]
pub struct ExactFeSurface {
    /// Vertices, exactly.
    pub vertices: Vec<[Rational; 3]>,
    /// Triangles, indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
    /// Counts.
    pub stats: FeStats,
}

impl ExactFeSurface {
    /// The mesh with every vertex rounded to the nearest `f64` (no normals).
    pub fn to_mesh(&self) -> crate::mesh::Mesh {
        crate::mesh::Mesh {
            vertices: self
                .vertices
                .iter()
                .map(|v| v.each_ref().map(crate::num::rational_to_f64))
                .collect(),
            triangles: self.triangles.clone(),
            ..Default::default()
        }
    }
}

/// Eq. (1) for one element: `Σ φᵢᵏ(ξ) uᵢᵏ` (or its `∂/∂ξ_d`).
pub(crate) fn interpolate_field(
    m: &FeModel<Rational>,
    nodes: &[u32; 8],
    xi: &[Rational; 3],
    derivative: Option<usize>,
) -> Rational {
    let ndof = m.kind.dofs_per_node();
    let (terms, denominator) = terms_scaled(m.kind, xi, derivative);
    let sum = terms
        .into_iter()
        .fold(Rational::zero(), |acc, (node, k, w)| {
            crate::num::Field::add(
                &acc,
                &crate::num::Field::mul(
                    &Rational::from_integer(w),
                    &m.field[nodes[node] as usize * ndof + k],
                ),
            )
        });
    sum / Rational::from_integer(denominator)
}

/// Eq. (2) for one element: the world point `x(ξ)` (or its `∂x/∂ξ_d`).
pub(crate) fn interpolate_world(
    m: &FeModel<Rational>,
    nodes: &[u32; 8],
    xi: &[Rational; 3],
    derivative: Option<usize>,
) -> [Rational; 3] {
    let ndof = m.kind.dofs_per_node();
    let mut x = [Rational::zero(), Rational::zero(), Rational::zero()];
    let (terms, denominator) = terms_scaled(m.kind, xi, derivative);
    for (node, k, w) in terms {
        let c = &m.coordinates[nodes[node] as usize * ndof + k];
        let w = Rational::from_integer(w);
        for a in 0..3 {
            x[a] = crate::num::Field::add(&x[a], &crate::num::Field::mul(&w, &c[a]));
        }
    }
    let denominator = Rational::from_integer(denominator);
    x.map(|v| v / &denominator)
}

/// `det J` of the isoparametric map at `ξ`, `J = ∂x/∂ξ`.
pub(crate) fn jacobian_determinant(
    m: &FeModel<Rational>,
    nodes: &[u32; 8],
    xi: &[Rational; 3],
) -> Rational {
    let c: [[Rational; 3]; 3] = std::array::from_fn(|d| interpolate_world(m, nodes, xi, Some(d)));
    // Columns c[d] = ∂x/∂ξ_d: det = c₀ · (c₁ × c₂).
    let cross = [
        &c[1][1] * &c[2][2] - &c[1][2] * &c[2][1],
        &c[1][2] * &c[2][0] - &c[1][0] * &c[2][2],
        &c[1][0] * &c[2][1] - &c[1][1] * &c[2][0],
    ];
    &c[0][0] * &cross[0] + &c[0][1] * &cross[1] + &c[0][2] * &cross[2]
}

/// The lattice point `p` as `ξ` (`ξ_d = p_d / n_d`).
fn lattice_xi(p: [usize; 3], n: [usize; 3]) -> [Rational; 3] {
    std::array::from_fn(|d| Rational::new((p[d] as i64).into(), (n[d] as i64).into()))
}

/// The zero of the linear interpolant from `v0` (at 0) to `v1` (at 1) (Section 3).
fn cut_parameter(v0: &Rational, v1: &Rational, iso: &Rational) -> Rational {
    (iso - v0) / (v1 - v0)
}

/// Exact polygonisation (reference path).
pub fn polygonise_exact(
    m: &FeModel<Rational>,
    iso: &Rational,
    opts: &FeOptions,
) -> Result<ExactFeSurface, FeError> {
    prepare(m, opts)?;
    let n = opts.cells;
    let tab = table();
    let mut stats = FeStats {
        elements: m.elements.len(),
        ..FeStats::default()
    };
    let mut value_of: HashMap<PointKey, Rational> = HashMap::new();
    let mut vertex_of: HashMap<EdgeKey, u32> = HashMap::new();
    let mut vertices: Vec<[Rational; 3]> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let half = Rational::new(1.into(), 2.into());
    let index = |p: [usize; 3]| p[0] + (n[0] + 1) * (p[1] + (n[1] + 1) * p[2]);
    for (e, nodes) in m.elements.iter().enumerate() {
        // Step 2: sample the element's lattice (shared points once, by name).
        let mut v = Vec::with_capacity((n[0] + 1) * (n[1] + 1) * (n[2] + 1));
        for k in 0..=n[2] {
            for j in 0..=n[1] {
                for i in 0..=n[0] {
                    let key = point_key(e, nodes, n, [i, j, k]);
                    let val = value_of.entry(key).or_insert_with(|| {
                        interpolate_field(m, nodes, &lattice_xi([i, j, k], n), None)
                    });
                    v.push(val.clone());
                }
            }
        }
        let value = |p: [usize; 3]| &v[index(p)];
        let flip = jacobian_determinant(m, nodes, &[half.clone(), half.clone(), half.clone()])
            .is_negative();
        stats.flipped_elements += usize::from(flip);
        // The cut point of a cell edge, in this element's ξ (lattice units).
        let cut_xi = |cell: [usize; 3], edge: u8| -> [Rational; 3] {
            let (axis, lo) = cell_edge(cell, edge);
            let mut hi = lo;
            hi[axis] += 1;
            let t = cut_parameter(value(lo), value(hi), iso);
            let mut p = lo.map(|x| Rational::from_integer((x as i64).into()));
            p[axis] += t;
            p
        };
        let to_xi = |p: &[Rational; 3]| -> [Rational; 3] {
            std::array::from_fn(|d| &p[d] / Rational::from_integer((n[d] as i64).into()))
        };
        // The vertex on a cell edge: made once per edge name (Section 3.2).
        let edge_vertex = |cell: [usize; 3],
                           edge: u8,
                           vertex_of: &mut HashMap<EdgeKey, u32>,
                           vertices: &mut Vec<[Rational; 3]>|
         -> u32 {
            let (axis, lo) = cell_edge(cell, edge);
            let (key, _) = edge_key(e, nodes, n, lo, axis);
            *vertex_of.entry(key).or_insert_with(|| {
                let xi = to_xi(&cut_xi(cell, edge));
                vertices.push(interpolate_world(m, nodes, &xi, None));
                (vertices.len() - 1) as u32
            })
        };
        for ck in 0..n[2] {
            for cj in 0..n[1] {
                for ci in 0..n[0] {
                    let cell = [ci, cj, ck];
                    stats.cells += 1;
                    // Step 3: the 8-bit configuration.
                    let corner: [&Rational; 8] =
                        std::array::from_fn(|c| value(cell_corner(cell, c)));
                    let Some((config, amb)) = classify(|c| is_positive(corner[c], iso), &mut stats)
                    else {
                        continue;
                    };
                    // Step 4: the subconfiguration, by sorting cut points along ξ.
                    let mut sub = 0u8;
                    for (bit, &f) in amb.iter().enumerate() {
                        let joined = mackerras(cell, f as usize, &corner, iso, &cut_xi);
                        sub |= u8::from(joined) << bit;
                    }
                    // The trilinear topology's tube, where it has one.
                    let tube = match opts.topology {
                        CellRule::Table => None,
                        CellRule::Trilinear => {
                            tube_mesh(config, sub, &corner.map(|v| v.clone()), iso)
                        }
                    };
                    if let Some(mesh) = tube {
                        let mesh = mesh.map_err(|why| FeError::Construction {
                            element: e,
                            cell,
                            why,
                        })?;
                        stats.tunnel_cells += 1;
                        let tris = tube_triangles(&mesh, flip, |x| {
                            if x < 12 {
                                return edge_vertex(cell, x, &mut vertex_of, &mut vertices);
                            }
                            let p = interior_position(
                                &mesh.interior[(x - 12) as usize],
                                |x| cut_xi(cell, x),
                                |a, b| [0, 1, 2].map(|d| &a[d] + &b[d]),
                                |a, k| {
                                    let k = Rational::from_integer((k as i64).into());
                                    [0, 1, 2].map(|d| &a[d] / &k)
                                },
                            );
                            vertices.push(interpolate_world(m, nodes, &to_xi(&p), None));
                            (vertices.len() - 1) as u32
                        });
                        triangles.extend(tris);
                        continue;
                    }
                    // Steps 5–6: the entry's triangles, vertices by linear interpolation.
                    let entry = tab.entry(config, sub);
                    let mut centre = [u32::MAX; 4];
                    for tri in entry.triangles_with_centres() {
                        let mut t = [0u32; 3];
                        for (slot, edge) in t.iter_mut().zip(tri) {
                            if edge < CENTRE {
                                *slot = edge_vertex(cell, edge, &mut vertex_of, &mut vertices);
                                continue;
                            }
                            let p = (edge - CENTRE) as usize;
                            if centre[p] == u32::MAX {
                                // The polygon's centre: the average of its cut points in ξ
                                // (numbered after them).
                                let poly = &entry.polygons[p];
                                let mut c = [Rational::zero(), Rational::zero(), Rational::zero()];
                                for &x in poly {
                                    edge_vertex(cell, x, &mut vertex_of, &mut vertices);
                                    let q = cut_xi(cell, x);
                                    for d in 0..3 {
                                        c[d] += &q[d];
                                    }
                                }
                                let len = Rational::from_integer((poly.len() as i64).into());
                                let xi = to_xi(&c.map(|s| s / &len));
                                vertices.push(interpolate_world(m, nodes, &xi, None));
                                centre[p] = (vertices.len() - 1) as u32;
                            }
                            *slot = centre[p];
                        }
                        if flip {
                            t.swap(1, 2);
                        }
                        triangles.push(t);
                    }
                }
            }
        }
    }
    // Figure 7: vertices at one world point become one; collapsed triangles go.
    let mut first_at: HashMap<&[Rational; 3], u32> = HashMap::new();
    let rep: Vec<u32> = vertices
        .iter()
        .enumerate()
        .map(|(i, x)| *first_at.entry(x).or_insert(i as u32))
        .collect();
    let kept = weld(&rep, &mut triangles, &mut stats);
    let vertices = kept.iter().map(|&i| vertices[i as usize].clone()).collect();
    Ok(ExactFeSurface {
        vertices,
        triangles,
        stats,
    })
}

/// Mackerras' rule on table face `f` of `cell` (Section 3.1): the cut points on the face's
/// edges `A–B` and `C–D` (both along the same `ξ` axis, in its positive direction) sorted
/// along that axis; the first pair and the last pair are joined. `A–B`'s point first cuts
/// off `A` and `D`, so the positive corners are joined exactly when `A` is negative;
/// otherwise `B` and `C` are cut off. Equal positions (the saddle on the level set) count as
/// joined.
fn mackerras(
    cell: [usize; 3],
    f: usize,
    corner: &[&Rational; 8],
    iso: &Rational,
    cut_xi: &dyn Fn([usize; 3], u8) -> [Rational; 3],
) -> bool {
    let [a, b, c, d] = face_abcd(f);
    let edge = |x: usize, y: usize| {
        crate::mc::table::edge_between(x as u8, y as u8).expect("face corners are adjacent")
    };
    let (axis, _) = cell_edge(cell, edge(a, b));
    let s_ab = &cut_xi(cell, edge(a, b))[axis];
    let s_cd = &cut_xi(cell, edge(c, d))[axis];
    match s_ab.cmp(s_cd) {
        std::cmp::Ordering::Less => !is_positive(corner[a], iso),
        std::cmp::Ordering::Greater => !is_positive(corner[b], iso),
        std::cmp::Ordering::Equal => true,
    }
}
