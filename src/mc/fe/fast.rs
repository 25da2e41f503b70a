//! The fast path: Section 3.3's algorithm in `f64`, certified where it decides.
//!
//! Every sampled value carries a rounding bound. From the Section 2 basis in `f64` at a
//! rounded `ξ`, each 1-D basis value is within `12u` of the true one (`|φ'| ≤ 1.5`, a few
//! roundings), so each tensor weight is within `40u`; summing at most 64 weighted dofs adds
//! `γ₆₅`. Hence `|fl(u(ξ)) − u(ξ)| ≤ 2⁻⁴⁵ · Σ|uᵢᵏ|` over the element's dofs (a factor 2 to
//! spare). A sign within that bound of the isovalue is recomputed exactly; face decisions
//! use interval arithmetic on the bounded values and fall back to the exact decider; and two
//! vertices are merged as Figure 7 asks only after their exact world positions compare equal
//! (candidates come from a spatial hash whose cells exceed twice the largest certified
//! position error). So the triangle index structure equals the exact path's.
//!
//! Cut edges inside an element use per-element arrays; only edges on the element boundary go
//! through the hash table of edge names (Section 3.2).

use super::basis::{basis_f64, terms_f64};
use super::exact::{interpolate_field, interpolate_world, jacobian_determinant};
use super::lattice::{edge_key, edge_on_boundary, EdgeKey};
use super::{
    cell_corner, cell_edge, classify, face_abcd, prepare, weld, FeError, FeModel, FeOptions,
    FeStats, NormalSource,
};
use crate::mc::decider::decide_exact;
use crate::mc::table::{table, CENTRE};
use crate::mesh::Mesh;
use crate::num::{rational_to_f64, Interval, Rational, Sign};
use glam::DMat3;
use num_traits::{Signed, Zero};
use std::collections::HashMap;

/// A fast isosurface: the mesh (with unit normals) and counts.
#[derive(Clone, Debug, PartialEq)]
pub struct FeSurface {
    /// The mesh, with unit normals.
    pub mesh: Mesh,
    /// Counts.
    pub stats: FeStats,
}

const NONE: u32 = u32::MAX;
/// `2⁻⁴⁵`: the value bound's factor (module docs).
const VALUE_BOUND: f64 = 1.0 / 35_184_372_088_832.0;
const EPS: f64 = f64::EPSILON;

/// Where a vertex came from, to recompute it exactly.
#[derive(Clone, Debug)]
enum Origin {
    Edge {
        element: usize,
        lo: [usize; 3],
        axis: usize,
    },
    Centre {
        element: usize,
        cell: [usize; 3],
        edges: Vec<u8>,
    },
}

/// A sampled lattice value: the `f64`, its error bound, its exact sign (`v ≥ iso`).
#[derive(Clone, Copy, Debug)]
struct Sample {
    v: f64,
    err: f64,
    positive: bool,
}

/// What one element needs while it is polygonised.
struct ElementData {
    dofs_u: Vec<f64>,
    dofs_x: Vec<[f64; 3]>,
    /// Bound on `|∂x/∂ξ_d|` (max-norm): `1.5 Σ max|x dof|`.
    lip: f64,
    /// Bound on the world evaluation error: `2⁻⁴⁴ Σ max|x dof|`.
    x_err: f64,
}

impl ElementData {
    fn new(m: &FeModel<f64>, nodes: &[u32; 8]) -> ElementData {
        let ndof = m.kind.dofs_per_node();
        let mut dofs_u = Vec::with_capacity(8 * ndof);
        let mut dofs_x = Vec::with_capacity(8 * ndof);
        for &nd in nodes {
            for k in 0..ndof {
                dofs_u.push(m.field[nd as usize * ndof + k]);
                dofs_x.push(m.coordinates[nd as usize * ndof + k]);
            }
        }
        let sx: f64 = dofs_x
            .iter()
            .map(|p| p.iter().fold(0.0f64, |a, x| a.max(x.abs())))
            .sum();
        ElementData {
            dofs_u,
            dofs_x,
            lip: 1.5 * sx * (1.0 + 8.0 * EPS),
            x_err: 2.0 * VALUE_BOUND * sx,
        }
    }

    fn world(&self, kind: super::ElementKind, xi: [f64; 3], derivative: Option<usize>) -> [f64; 3] {
        let mut terms = [(0usize, 0usize, 0.0f64); 64];
        let count = terms_f64(kind, xi, derivative, &mut terms);
        let ndof = kind.dofs_per_node();
        let mut x = [0.0; 3];
        for &(node, k, w) in &terms[..count] {
            let c = self.dofs_x[node * ndof + k];
            for a in 0..3 {
                x[a] += w * c[a];
            }
        }
        x
    }

    fn field_gradient(&self, kind: super::ElementKind, xi: [f64; 3]) -> [f64; 3] {
        let mut terms = [(0usize, 0usize, 0.0f64); 64];
        let ndof = kind.dofs_per_node();
        std::array::from_fn(|d| {
            let count = terms_f64(kind, xi, Some(d), &mut terms);
            terms[..count]
                .iter()
                .map(|&(node, k, w)| w * self.dofs_u[node * ndof + k])
                .sum()
        })
    }
}

/// Lazily converted exact model and exact lattice values (the fallbacks).
struct ExactOracle<'a> {
    model: &'a FeModel<f64>,
    exact: Option<FeModel<Rational>>,
    iso: Rational,
    values: HashMap<(usize, [usize; 3]), Rational>,
    n: [usize; 3],
}

impl ExactOracle<'_> {
    fn model(&mut self) -> &FeModel<Rational> {
        if self.exact.is_none() {
            self.exact = Some(self.model.to_exact().expect("validated"));
        }
        self.exact.as_ref().expect("just set")
    }
    fn xi(&self, p: [usize; 3]) -> [Rational; 3] {
        std::array::from_fn(|d| Rational::new((p[d] as i64).into(), (self.n[d] as i64).into()))
    }
    fn value(&mut self, element: usize, p: [usize; 3]) -> Rational {
        if let Some(v) = self.values.get(&(element, p)) {
            return v.clone();
        }
        let xi = self.xi(p);
        let nodes = self.model.elements[element];
        let v = interpolate_field(self.model(), &nodes, &xi, None);
        self.values.insert((element, p), v.clone());
        v
    }
    /// The exact cut point of the lattice edge `lo → lo + e_axis`, in lattice units.
    fn cut(&mut self, element: usize, lo: [usize; 3], axis: usize) -> [Rational; 3] {
        let mut hi = lo;
        hi[axis] += 1;
        let (v0, v1) = (self.value(element, lo), self.value(element, hi));
        let t = (&self.iso - &v0) / (v1 - v0);
        let mut p = lo.map(|x| Rational::from_integer((x as i64).into()));
        p[axis] += t;
        p
    }
    fn world_at_lattice_units(&mut self, element: usize, p: &[Rational; 3]) -> [Rational; 3] {
        let n = self.n;
        let xi: [Rational; 3] =
            std::array::from_fn(|d| &p[d] / Rational::from_integer((n[d] as i64).into()));
        let nodes = self.model.elements[element];
        interpolate_world(self.model(), &nodes, &xi, None)
    }
    fn vertex(&mut self, o: &Origin) -> [Rational; 3] {
        match o {
            Origin::Edge { element, lo, axis } => {
                let p = self.cut(*element, *lo, *axis);
                self.world_at_lattice_units(*element, &p)
            }
            Origin::Centre {
                element,
                cell,
                edges,
            } => {
                let mut c = [Rational::zero(), Rational::zero(), Rational::zero()];
                for &e in edges {
                    let (axis, lo) = cell_edge(*cell, e);
                    let q = self.cut(*element, lo, axis);
                    for d in 0..3 {
                        c[d] += &q[d];
                    }
                }
                let len = Rational::from_integer((edges.len() as i64).into());
                let c = c.map(|s| s / &len);
                self.world_at_lattice_units(*element, &c)
            }
        }
    }
}

/// Fast polygonisation. Errors on bad models or a non-finite isovalue.
pub fn polygonise_fast(m: &FeModel<f64>, iso: f64, opts: &FeOptions) -> Result<FeSurface, FeError> {
    m.validate()?;
    if !iso.is_finite() {
        return Err(FeError::Isovalue);
    }
    prepare(m, opts)?;
    let n = opts.cells;
    let kind = m.kind;
    let ndof = kind.dofs_per_node();
    let tab = table();
    let mut stats = FeStats {
        elements: m.elements.len(),
        ..FeStats::default()
    };
    let mut oracle = ExactOracle {
        model: m,
        exact: None,
        iso: crate::num::rational_from_f64(iso, "isovalue").expect("finite"),
        values: HashMap::new(),
        n,
    };
    // The 1-D bases at the lattice positions, per direction.
    let lattice_basis: [Vec<[f64; 4]>; 3] = std::array::from_fn(|d| {
        (0..=n[d])
            .map(|i| basis_f64(kind.bases[d], i as f64 / n[d] as f64))
            .collect()
    });
    let side_of = |node: usize| [node & 1, node >> 1 & 1, node >> 2 & 1];
    let dof_der: Vec<[usize; 3]> = (0..ndof)
        .map(|k| kind.derivative_of_dof(k).map(usize::from))
        .collect();
    let stride = [1, n[0] + 1, (n[0] + 1) * (n[1] + 1)];
    let points = stride[2] * (n[2] + 1);
    let index = |p: [usize; 3]| p[0] + stride[1] * p[1] + stride[2] * p[2];

    let mut boundary_vertex: HashMap<EdgeKey, u32> = HashMap::new();
    let mut vertices: Vec<[f64; 3]> = Vec::new();
    let mut normals: Vec<[f64; 3]> = Vec::new();
    let mut radius: Vec<f64> = Vec::new();
    let mut origin: Vec<Origin> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let mut samples = vec![
        Sample {
            v: 0.0,
            err: 0.0,
            positive: false
        };
        points
    ];
    let mut local_ids: [Vec<u32>; 3] = std::array::from_fn(|_| vec![NONE; points]);
    let mut gradients: Vec<[f64; 3]> = Vec::new();

    for (e, nodes) in m.elements.iter().enumerate() {
        let data = ElementData::new(m, nodes);
        let s_u: f64 = data.dofs_u.iter().map(|x| x.abs()).sum();
        let err = (VALUE_BOUND * s_u).max(f64::MIN_POSITIVE);
        // Step 2: sample the lattice.
        for k in 0..=n[2] {
            for j in 0..=n[1] {
                for i in 0..=n[0] {
                    let mut v = 0.0;
                    for node in 0..8 {
                        let s = side_of(node);
                        for (dof, der) in dof_der.iter().enumerate() {
                            let w = lattice_basis[0][i][2 * s[0] + der[0]]
                                * lattice_basis[1][j][2 * s[1] + der[1]]
                                * lattice_basis[2][k][2 * s[2] + der[2]];
                            v += w * data.dofs_u[node * ndof + dof];
                        }
                    }
                    let d = v - iso;
                    let margin = err + EPS * d.abs();
                    let sample = if d > margin {
                        Sample {
                            v,
                            err,
                            positive: true,
                        }
                    } else if d < -margin {
                        Sample {
                            v,
                            err,
                            positive: false,
                        }
                    } else {
                        stats.exact_values += 1;
                        let exact = oracle.value(e, [i, j, k]);
                        let v = rational_to_f64(&exact);
                        Sample {
                            v,
                            err: (v.abs() * EPS).max(f64::MIN_POSITIVE),
                            positive: exact >= oracle.iso,
                        }
                    };
                    samples[index([i, j, k])] = sample;
                }
            }
        }
        if opts.normals == NormalSource::FiniteDifference {
            gradients = finite_difference_gradients(&samples, n, &index);
        }
        let flip = element_flip(&data, kind, &mut oracle, e, &mut stats);
        for ids in &mut local_ids {
            ids.fill(NONE);
        }
        // The cut point of a lattice edge in lattice units, and its bound.
        let cut = |lo: [usize; 3], axis: usize, oracle: &mut ExactOracle| -> ([f64; 3], f64) {
            let mut hi = lo;
            hi[axis] += 1;
            let (a, b) = (samples[index(lo)], samples[index(hi)]);
            let den = (b.v - a.v).abs();
            let e_sum = a.err + b.err;
            let (t, dt) = if e_sum <= 0.25 * den {
                ((iso - a.v) / (b.v - a.v), 3.0 * e_sum / den + 4.0 * EPS)
            } else {
                let p = oracle.cut(e, lo, axis);
                (
                    rational_to_f64(&(&p[axis] - Rational::from_integer((lo[axis] as i64).into()))),
                    EPS,
                )
            };
            let mut p = lo.map(|x| x as f64);
            p[axis] += t.clamp(0.0, 1.0);
            (p, dt)
        };
        for ck in 0..n[2] {
            for cj in 0..n[1] {
                for ci in 0..n[0] {
                    let cell = [ci, cj, ck];
                    stats.cells += 1;
                    let corner: [Sample; 8] =
                        std::array::from_fn(|c| samples[index(cell_corner(cell, c))]);
                    let Some((config, amb)) = classify(|c| corner[c].positive, &mut stats) else {
                        continue;
                    };
                    let mut sub = 0u8;
                    for (bit, &f) in amb.iter().enumerate() {
                        let abcd = face_abcd(f as usize);
                        let joined = match decide_bounded(abcd.map(|c| corner[c]), iso) {
                            Some(j) => j,
                            None => {
                                stats.exact_faces += 1;
                                let v = abcd.map(|c| oracle.value(e, cell_corner(cell, c)));
                                decide_exact([&v[0], &v[1], &v[2], &v[3]], &oracle.iso)
                                    .unwrap_or(false)
                            }
                        };
                        sub |= u8::from(joined) << bit;
                    }
                    let entry = tab.offsets[config as usize] as usize + sub as usize;
                    let mut centre = [NONE; 4];
                    for tri in tab.extraction_triangles(entry) {
                        let mut t = [0u32; 3];
                        for (slot, &edge) in t.iter_mut().zip(tri) {
                            let mut edge_vertex = |edge: u8| -> u32 {
                                let (axis, lo) = cell_edge(cell, edge);
                                let id = &mut local_ids[axis][index(lo)];
                                if *id != NONE {
                                    return *id;
                                }
                                let key = edge_on_boundary(n, lo, axis)
                                    .then(|| edge_key(e, nodes, n, lo, axis).0);
                                if let Some(v) = key.as_ref().and_then(|k| boundary_vertex.get(k)) {
                                    *id = *v;
                                    return *id;
                                }
                                let (p, dt) = cut(lo, axis, &mut oracle);
                                let xi = [0, 1, 2].map(|d| p[d] / n[d] as f64);
                                vertices.push(data.world(kind, xi, None));
                                let g = match opts.normals {
                                    NormalSource::Interpolant => data.field_gradient(kind, xi),
                                    NormalSource::FiniteDifference => {
                                        let mut hi = lo;
                                        hi[axis] += 1;
                                        let s = p[axis] - lo[axis] as f64;
                                        let (g0, g1) = (gradients[index(lo)], gradients[index(hi)]);
                                        [0, 1, 2].map(|d| g0[d] + s * (g1[d] - g0[d]))
                                    }
                                };
                                normals.push(world_normal(&data, kind, xi, g));
                                radius.push(
                                    data.lip * (dt / n[axis] as f64 + 4.0 * EPS) + data.x_err,
                                );
                                origin.push(Origin::Edge {
                                    element: e,
                                    lo,
                                    axis,
                                });
                                *id = (vertices.len() - 1) as u32;
                                if let Some(k) = key {
                                    boundary_vertex.insert(k, *id);
                                }
                                *id
                            };
                            if edge < CENTRE {
                                *slot = edge_vertex(edge);
                                continue;
                            }
                            let pi = (edge - CENTRE) as usize;
                            let poly = &tab.entries[entry].polygons[pi];
                            if centre[pi] == NONE {
                                // The centre is numbered after its polygon's cut points.
                                for &x in poly {
                                    edge_vertex(x);
                                }
                                let mut c = [0.0; 3];
                                let mut dxi = 0.0f64;
                                let mut g = [0.0; 3];
                                for &x in poly {
                                    let (axis, lo) = cell_edge(cell, x);
                                    let (p, dt) = cut(lo, axis, &mut oracle);
                                    for d in 0..3 {
                                        c[d] += p[d];
                                    }
                                    dxi = dxi.max(dt / n[axis] as f64);
                                    if opts.normals == NormalSource::FiniteDifference {
                                        let mut hi = lo;
                                        hi[axis] += 1;
                                        let s = p[axis] - lo[axis] as f64;
                                        let (g0, g1) = (gradients[index(lo)], gradients[index(hi)]);
                                        for d in 0..3 {
                                            g[d] += g0[d] + s * (g1[d] - g0[d]);
                                        }
                                    }
                                }
                                let xi = [0, 1, 2].map(|d| c[d] / poly.len() as f64 / n[d] as f64);
                                vertices.push(data.world(kind, xi, None));
                                if opts.normals == NormalSource::Interpolant {
                                    g = data.field_gradient(kind, xi);
                                }
                                normals.push(world_normal(&data, kind, xi, g));
                                radius.push(data.lip * (dxi + 8.0 * EPS) + data.x_err);
                                origin.push(Origin::Centre {
                                    element: e,
                                    cell,
                                    edges: poly.clone(),
                                });
                                centre[pi] = (vertices.len() - 1) as u32;
                            }
                            *slot = centre[pi];
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
    let rep = coincident_representatives(&vertices, &radius, &origin, &mut oracle);
    let (kept, triangles) = weld(&rep, &triangles, &mut stats);
    let vertices: Vec<[f64; 3]> = kept.iter().map(|&i| vertices[i as usize]).collect();
    let normals = finish_normals(
        kept.iter().map(|&i| normals[i as usize]).collect(),
        &vertices,
        &triangles,
    );
    Ok(FeSurface {
        mesh: Mesh {
            vertices,
            triangles,
            scalars: None,
            normals: Some(normals),
        },
        stats,
    })
}

/// The face decision from bounded values, or `None` when the bounds do not settle it. Signs
/// are the samples' exact ones; `A, D` and `B, C` are the diagonals.
fn decide_bounded(s: [Sample; 4], iso: f64) -> Option<bool> {
    if s[0].positive != s[3].positive
        || s[1].positive != s[2].positive
        || s[0].positive == s[1].positive
    {
        return None; // not ambiguous: never asked
    }
    // [v − err, v + err] rounded outward, then shifted by the isovalue (interval subtraction
    // rounds outward itself).
    let iv = |x: Sample| {
        Interval::new((x.v - x.err).next_down(), (x.v + x.err).next_up()) - Interval::point(iso)
    };
    let [a, b, c, d] = s.map(iv);
    let diff = if s[0].positive {
        a * d - b * c
    } else {
        b * c - a * d
    };
    match diff.sign() {
        Sign::Positive => Some(true),
        Sign::Negative => Some(false),
        _ => None,
    }
}

/// Whether an element's triangles must be flipped: `det J < 0` at its centre, decided in
/// `f64` when far from zero and exactly otherwise.
fn element_flip(
    data: &ElementData,
    kind: super::ElementKind,
    oracle: &mut ExactOracle,
    e: usize,
    stats: &mut FeStats,
) -> bool {
    let c: [[f64; 3]; 3] = std::array::from_fn(|d| data.world(kind, [0.5; 3], Some(d)));
    let det = c[0][0] * (c[1][1] * c[2][2] - c[1][2] * c[2][1])
        + c[0][1] * (c[1][2] * c[2][0] - c[1][0] * c[2][2])
        + c[0][2] * (c[1][0] * c[2][1] - c[1][1] * c[2][0]);
    let flip = if det.abs() > 1e-8 * data.lip.powi(3) {
        det < 0.0
    } else {
        let half = Rational::new(1.into(), 2.into());
        let nodes = oracle.model.elements[e];
        jacobian_determinant(oracle.model(), &nodes, &[half.clone(), half.clone(), half])
            .is_negative()
    };
    stats.flipped_elements += usize::from(flip);
    flip
}

/// `∇s = J⁻ᵀ ∇_ξ s` (Section 3's normal formula), unit length, or zero where `J` is singular.
fn world_normal(
    data: &ElementData,
    kind: super::ElementKind,
    xi: [f64; 3],
    g: [f64; 3],
) -> [f64; 3] {
    // Columns c[d] = ∂x/∂ξ_d. J⁻ᵀ g = (c₁ × c₂ g₀ + c₂ × c₀ g₁ + c₀ × c₁ g₂) / det: the rows of
    // the adjugate, scaled by the sign of det only (the length is normalised away).
    let j = DMat3::from_cols_array_2d(&std::array::from_fn(|d| data.world(kind, xi, Some(d))));
    let adjugate_rows = [
        j.y_axis.cross(j.z_axis),
        j.z_axis.cross(j.x_axis),
        j.x_axis.cross(j.y_axis),
    ];
    let det = j.x_axis.dot(adjugate_rows[0]);
    if det == 0.0 || !det.is_finite() {
        return [0.0; 3];
    }
    let v = (adjugate_rows[0] * g[0] + adjugate_rows[1] * g[1] + adjugate_rows[2] * g[2])
        * det.signum();
    let len = v.length();
    if len > 0.0 && len.is_finite() {
        (v / len).to_array()
    } else {
        [0.0; 3]
    }
}

/// Central differences of the samples in `ξ` (one-sided on the element boundary).
fn finite_difference_gradients(
    samples: &[Sample],
    n: [usize; 3],
    index: &dyn Fn([usize; 3]) -> usize,
) -> Vec<[f64; 3]> {
    let mut out = vec![[0.0; 3]; samples.len()];
    for k in 0..=n[2] {
        for j in 0..=n[1] {
            for i in 0..=n[0] {
                let p = [i, j, k];
                out[index(p)] = std::array::from_fn(|d| {
                    let (mut lo, mut hi) = (p, p);
                    lo[d] = p[d].saturating_sub(1);
                    hi[d] = (p[d] + 1).min(n[d]);
                    let h = (hi[d] - lo[d]) as f64 / n[d] as f64;
                    (samples[index(hi)].v - samples[index(lo)].v) / h
                });
            }
        }
    }
    out
}

/// For every vertex the smallest id at the same exact world point. Candidates are pairs whose
/// `f64` positions lie within the sum of their certified radii; each is confirmed exactly.
fn coincident_representatives(
    x: &[[f64; 3]],
    radius: &[f64],
    origin: &[Origin],
    oracle: &mut ExactOracle,
) -> Vec<u32> {
    let mut parent: Vec<u32> = (0..x.len() as u32).collect();
    if x.is_empty() {
        return parent;
    }
    let r_max = radius.iter().fold(0.0f64, |a, &r| a.max(r));
    let scale = x
        .iter()
        .flat_map(|p| p.iter())
        .fold(0.0f64, |a, v| a.max(v.abs()));
    // Cells at least twice (with margin) the largest pair distance 2·r_max, and coarse enough
    // that cell coordinates fit an i64.
    let cell = (4.1 * r_max)
        .max(scale * 2f64.powi(-50))
        .max(f64::MIN_POSITIVE);
    let bucket = |p: [f64; 3]| p.map(|v| (v / cell).floor() as i64);
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::with_capacity(x.len());
    for (i, p) in x.iter().enumerate() {
        grid.entry(bucket(*p)).or_default().push(i as u32);
    }
    let mut exact: HashMap<u32, [Rational; 3]> = HashMap::new();
    fn find(parent: &mut [u32], mut a: u32) -> u32 {
        while parent[a as usize] != a {
            parent[a as usize] = parent[parent[a as usize] as usize];
            a = parent[a as usize];
        }
        a
    }
    for (i, p) in x.iter().enumerate() {
        let b = bucket(*p);
        let near: [i64; 3] = std::array::from_fn(|a| {
            let f = p[a] / cell - b[a] as f64;
            if f < 0.5 {
                b[a] - 1
            } else {
                b[a] + 1
            }
        });
        for mask in 0..8 {
            let key: [i64; 3] =
                std::array::from_fn(|a| if mask >> a & 1 == 1 { near[a] } else { b[a] });
            let Some(list) = grid.get(&key) else { continue };
            for &j in list {
                if j as usize >= i {
                    continue;
                }
                let q = x[j as usize];
                let dist = (0..3).fold(0.0f64, |m, a| m.max((p[a] - q[a]).abs()));
                if dist > radius[i] + radius[j as usize] {
                    continue;
                }
                let (ri, rj) = (find(&mut parent, i as u32), find(&mut parent, j));
                if ri == rj {
                    continue;
                }
                for v in [i as u32, j] {
                    exact
                        .entry(v)
                        .or_insert_with(|| oracle.vertex(&origin[v as usize]));
                }
                if exact[&(i as u32)] == exact[&j] {
                    let (lo, hi) = (ri.min(rj), ri.max(rj));
                    parent[hi as usize] = lo;
                }
            }
        }
    }
    (0..x.len() as u32).map(|i| find(&mut parent, i)).collect()
}

/// Unit normals; where the Jacobian was singular (zero normal), the normalised sum of the
/// incident triangles' area vectors.
fn finish_normals(
    mut normals: Vec<[f64; 3]>,
    x: &[[f64; 3]],
    triangles: &[[u32; 3]],
) -> Vec<[f64; 3]> {
    if normals.iter().all(|v| *v != [0.0; 3]) {
        return normals;
    }
    let mut acc = vec![[0.0; 3]; x.len()];
    for t in triangles {
        let [a, b, c] = t.map(|v| x[v as usize]);
        let nrm = crate::mesh::area_vector(a, b, c);
        for &v in t {
            for a in 0..3 {
                acc[v as usize][a] += nrm[a];
            }
        }
    }
    for (n, s) in normals.iter_mut().zip(acc) {
        if *n == [0.0; 3] {
            let len = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
            if len > 0.0 && len.is_finite() {
                *n = s.map(|v| v / len);
            }
        }
    }
    normals
}
