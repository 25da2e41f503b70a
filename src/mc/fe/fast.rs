//! The fast path: Section 3.3's algorithm in `f64`, certified where it decides.
//!
//! Every sampled value carries a rounding bound: the lattice is sampled by sum factorisation
//! ([`tensor`](super::tensor), which derives `|fl(u(ξ)) − u(ξ)| ≤ 2⁻⁴⁵ · Σ|uᵢᵏ|` over the
//! element's dofs), and world points by the same contractions within `2⁻⁴⁴ Σ max|x dof|`. A
//! sign within the bound of the isovalue is recomputed exactly; face decisions use interval
//! arithmetic on the bounded values and fall back to the exact decider; and two vertices are
//! merged as Figure 7 asks only after their exact world positions compare equal (candidates
//! come from a hash grid whose cells are 32 times the largest certified position error).
//! Exact values come from [`integer`](super::integer) (integers over a shared denominator).
//! So the triangle index structure equals the exact path's.
//!
//! Signs are kept as one bitset per lattice row and cut cells found 64 at a time, as on
//! grids. Cut edges inside an element use per-element arrays; edges on the element boundary
//! use slot blocks of the face or element edge they lie in ([`slots`](super::slots): the
//! entity is named once per element by its global nodes, Section 3.2, and its lattice edges
//! are indexed in its canonical frame). Element ranges run in parallel and are welded by
//! those names ([`polygonise_fast`]).

use super::exact::jacobian_determinant;
use super::integer::IntegerElement;
use super::slots::{BoundaryName, BoundarySlots};
use super::tensor::{slot_table, ElementTensor};
use super::{
    cell_corner, cell_edge, classify, face_abcd, prepare, tube_mesh, tube_triangles, weld,
    CellRule, FeError, FeModel, FeOptions, FeStats, NormalSource,
};
use crate::hashing::FastMap;
use crate::mc::decider::decide_exact;
use crate::mc::table::{table, CENTRE};
use crate::mc::trilinear::cell_topology_exact;
use crate::mc::trilinear::polygonise::{
    cell_mesh, interior_position, tunnel_possible, CellMesh, InteriorVertex,
};
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

/// Where a vertex came from, to recompute it exactly (small and without heap data: one is
/// kept per vertex).
#[derive(Clone, Copy, Debug)]
enum Origin {
    /// The cut point of the lattice edge from `lo` along `axis`.
    Edge {
        element: u32,
        lo: [u32; 3],
        axis: u8,
    },
    /// The centre of polygon `polygon` of table entry `entry` in cell `cell`.
    Centre {
        element: u32,
        cell: [u32; 3],
        entry: u16,
        polygon: u8,
    },
    /// Interior vertex `index` of the tube in cell `cell` ([`CellRule::Trilinear`]).
    Interior {
        element: u32,
        cell: [u32; 3],
        index: u8,
    },
}

/// A sampled lattice value: the `f64`, its error bound, its exact sign (`v ≥ iso`).
#[derive(Clone, Copy, Debug)]
struct Sample {
    v: f64,
    err: f64,
    positive: bool,
}

/// Lazily converted exact model and exact lattice values (the fallbacks).
struct ExactOracle<'a> {
    model: &'a FeModel<f64>,
    exact: Option<FeModel<Rational>>,
    iso: Rational,
    values: HashMap<(usize, [usize; 3]), Rational>,
    /// Elements met so far, in integer form (exact evaluation without a gcd per product).
    integer: FastMap<usize, IntegerElement>,
    n: [usize; 3],
}

impl<'a> ExactOracle<'a> {
    fn new(model: &'a FeModel<f64>, iso: Rational, n: [usize; 3]) -> ExactOracle<'a> {
        ExactOracle {
            model,
            exact: None,
            iso,
            values: HashMap::new(),
            integer: FastMap::default(),
            n,
        }
    }
    fn integer(&mut self, element: usize) -> &IntegerElement {
        let m = self.model;
        self.integer
            .entry(element)
            .or_insert_with(|| IntegerElement::new(m, &m.elements[element]))
    }
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
        let [v] = self.integer(element).eval([0], &xi);
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
        self.integer(element).eval([1, 2, 3], &xi)
    }
    fn vertex(&mut self, o: &Origin) -> [Rational; 3] {
        let widen = |p: [u32; 3]| p.map(|x| x as usize);
        match *o {
            Origin::Edge { element, lo, axis } => {
                let p = self.cut(element as usize, widen(lo), axis as usize);
                self.world_at_lattice_units(element as usize, &p)
            }
            Origin::Centre {
                element,
                cell,
                entry,
                polygon,
            } => {
                let edges = &table().entries[entry as usize].polygons[polygon as usize];
                let mut c = [Rational::zero(), Rational::zero(), Rational::zero()];
                for &e in edges {
                    let (axis, lo) = cell_edge(widen(cell), e);
                    let q = self.cut(element as usize, lo, axis);
                    for d in 0..3 {
                        c[d] += &q[d];
                    }
                }
                let len = Rational::from_integer((edges.len() as i64).into());
                let c = c.map(|s| s / &len);
                self.world_at_lattice_units(element as usize, &c)
            }
            Origin::Interior {
                element,
                cell,
                index,
            } => {
                let (e, cell) = (element as usize, widen(cell));
                let corners = std::array::from_fn(|c| self.value(e, cell_corner(cell, c)));
                let topo = cell_topology_exact(&corners, &self.iso);
                let mesh = cell_mesh(&topo, || corners.clone().map(|v| v - &self.iso))
                    .expect("the fast path drew this tube");
                let v = &mesh.interior[index as usize];
                let cuts: Vec<(u8, [Rational; 3])> =
                    v.of.iter()
                        .chain(&v.toward)
                        .map(|&x| {
                            let (axis, lo) = cell_edge(cell, x);
                            (x, self.cut(e, lo, axis))
                        })
                        .collect();
                let point = |x: u8| {
                    cuts.iter()
                        .find(|c| c.0 == x)
                        .map(|c| c.1.clone())
                        .expect("a cut point of the vertex")
                };
                let p = interior_position(
                    v,
                    point,
                    |a, b| [0, 1, 2].map(|d| &a[d] + &b[d]),
                    |a, k| {
                        let k = Rational::from_integer((k as i64).into());
                        [0, 1, 2].map(|d| &a[d] / &k)
                    },
                );
                self.world_at_lattice_units(e, &p)
            }
        }
    }
}

/// What a range of elements produced: vertices numbered in creation order, and the names of
/// the vertices it made on element boundaries (to weld it to the ranges before it).
#[derive(Default)]
struct Part {
    vertices: Vec<[f64; 3]>,
    normals: Vec<[f64; 3]>,
    radius: Vec<f64>,
    origin: Vec<Origin>,
    triangles: Vec<[u32; 3]>,
    keys: Vec<(u32, BoundaryName)>,
    stats: FeStats,
}

/// Fast polygonisation. Errors on bad models or a non-finite isovalue.
///
/// The elements are cut into [`FeOptions::parts`] contiguous ranges, polygonised in parallel
/// (feature `parallel`) and welded by the names of the cut edges on shared element faces;
/// a vertex is numbered where the one-pass order would create it, so the mesh is the same
/// for every number of parts.
pub fn polygonise_fast(m: &FeModel<f64>, iso: f64, opts: &FeOptions) -> Result<FeSurface, FeError> {
    use crate::par::prelude::*;
    m.validate()?;
    if !iso.is_finite() {
        return Err(FeError::Isovalue);
    }
    prepare(m, opts)?;
    let iso_exact = crate::num::rational_from_f64(iso, "isovalue").expect("finite");
    let elements = m.elements.len();
    let parts = opts.parts().clamp(1, elements);
    let ranges: Vec<(usize, usize)> = (0..parts)
        .map(|p| (p * elements / parts, (p + 1) * elements / parts))
        .collect();
    let lattice = ElementTensor::lattice_bases(m.kind, opts.cells);
    let pieces: Vec<(Part, BoundarySlots)> = ranges
        .into_par_iter()
        .map(|range| {
            let mut k = Kernel::new(m, iso, &iso_exact, opts, &lattice);
            k.record_keys = range.0 > 0;
            for e in range.0..range.1 {
                if k.error.is_some() {
                    break;
                }
                k.element(e);
            }
            match k.error {
                Some(err) => Err(err),
                None => Ok((k.out, k.slots)),
            }
        })
        .collect::<Vec<_>>()
        .into_iter()
        .collect::<Result<_, _>>()?;
    let mut stats = FeStats {
        elements,
        ..FeStats::default()
    };
    // Each later range's boundary vertices, looked up (in parallel) in the names of the
    // ranges before it: the first range that has the name, and its vertex there.
    let (parts, maps): (Vec<Part>, Vec<BoundarySlots>) = pieces.into_iter().unzip();
    let found: Vec<Vec<(u32, usize, u32)>> = parts
        .par_iter()
        .enumerate()
        .map(|(p, part)| {
            part.keys
                .iter()
                .filter_map(|(id, key)| {
                    maps[..p]
                        .iter()
                        .enumerate()
                        .find_map(|(q, map)| map.find(key).map(|old| (*id, q, old)))
                })
                .collect()
        })
        .collect();
    drop(maps);
    let mut parts = parts.into_iter();
    // The first range's vertices keep their ids; the others are appended in order.
    let mut all = parts.next().expect("at least one range");
    stats.add(&all.stats);
    let mut remaps: Vec<Vec<u32>> = vec![(0..all.vertices.len() as u32).collect()];
    for (piece, found) in parts.zip(&found[1..]) {
        stats.add(&piece.stats);
        let remap = append(&mut all, piece, found, &remaps);
        remaps.push(remap);
    }
    let rep = coincident_representatives(
        m,
        &iso_exact,
        opts.cells,
        &all.vertices,
        &all.radius,
        &all.origin,
    );
    let mut triangles = std::mem::take(&mut all.triangles);
    let kept = weld(&rep, &mut triangles, &mut stats);
    // `kept` is increasing: as long as the vertices, it keeps them all.
    let (vertices, normals) = if kept.len() == all.vertices.len() {
        (all.vertices, all.normals)
    } else {
        (
            kept.iter().map(|&i| all.vertices[i as usize]).collect(),
            kept.iter().map(|&i| all.normals[i as usize]).collect(),
        )
    };
    let normals = finish_normals(normals, &vertices, &triangles);
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

/// Appends `piece` to `all`: its vertices that an earlier range made (`found`: local id,
/// that range, its local id there; `remaps` turn those into ids of `all`) take that
/// vertex's id, the others are numbered after `all`'s in creation order. Returns the
/// piece's remap.
fn append(
    all: &mut Part,
    piece: Part,
    found: &[(u32, usize, u32)],
    remaps: &[Vec<u32>],
) -> Vec<u32> {
    let mut remap = vec![NONE; piece.vertices.len()];
    for &(id, q, old) in found {
        remap[id as usize] = remaps[q][old as usize];
    }
    let Part {
        vertices,
        normals,
        radius,
        origin,
        triangles,
        ..
    } = piece;
    for (((slot, x), (nrm, r)), o) in remap
        .iter_mut()
        .zip(vertices)
        .zip(normals.into_iter().zip(radius))
        .zip(origin)
    {
        if *slot == NONE {
            *slot = all.vertices.len() as u32;
            all.vertices.push(x);
            all.normals.push(nrm);
            all.radius.push(r);
            all.origin.push(o);
        }
    }
    all.triangles
        .extend(triangles.iter().map(|t| t.map(|v| remap[v as usize])));
    remap
}

/// The per-range state of the fast path: lattice samples and sign rows of the current
/// element, cut-edge vertex ids, and the output.
struct Kernel<'a> {
    m: &'a FeModel<f64>,
    iso: f64,
    normals: NormalSource,
    topology: CellRule,
    /// The first error met (a construction the trilinear topology does not have).
    error: Option<FeError>,
    n: [usize; 3],
    lattice: &'a [Vec<[f64; 4]>; 3],
    oracle: ExactOracle<'a>,
    /// The element tensor, reloaded for each element (taken out while one is polygonised).
    tensor: Option<Box<ElementTensor>>,
    /// [`slot_table`] of the model's kind.
    slot_table: Vec<(u8, u8, u8)>,
    /// The current element's samples, `i` fastest.
    vals: Vec<f64>,
    scratch: Vec<f64>,
    /// Certified signs (`v ≥ iso`): one bitset of `words` words per lattice row along `ξ₁`.
    signs: Vec<u64>,
    words: usize,
    cut: Vec<u64>,
    gradients: Vec<[f64; 3]>,
    /// Per lattice point, the vertex ids of its edges along `ξ₁, ξ₂, ξ₃`; ids below the
    /// current element's first vertex are left over from earlier elements.
    ids: Vec<[u32; 3]>,
    /// Vertices on element boundaries made in this range, by the entity they lie in.
    slots: BoundarySlots,
    /// Whether to list the boundary vertices' names in the output, for looking them up in
    /// the earlier ranges' maps (every range but the first).
    record_keys: bool,
    out: Part,
}

/// The current element inside [`Kernel::element`].
struct Current<'t> {
    e: usize,
    nodes: [u32; 8],
    tensor: &'t ElementTensor,
    /// The samples' error bound.
    err: f64,
    /// Bound on `|∂x/∂ξ_d|` (max-norm): `1.5 Σ max|x dof|`.
    lip: f64,
    /// Bound on the world evaluation error: `2⁻⁴⁴ Σ max|x dof|`.
    x_err: f64,
    /// Vertex ids from here on were made by this element.
    start: u32,
}

impl<'a> Kernel<'a> {
    fn new(
        m: &'a FeModel<f64>,
        iso: f64,
        iso_exact: &Rational,
        opts: &FeOptions,
        lattice: &'a [Vec<[f64; 4]>; 3],
    ) -> Kernel<'a> {
        let n = opts.cells;
        let points = (n[0] + 1) * (n[1] + 1) * (n[2] + 1);
        let words = (n[0] + 1).div_ceil(64);
        Kernel {
            m,
            iso,
            normals: opts.normals,
            topology: opts.topology,
            error: None,
            n,
            lattice,
            oracle: ExactOracle::new(m, iso_exact.clone(), n),
            tensor: Some(Box::new(ElementTensor::empty(m.kind))),
            slot_table: slot_table(m.kind),
            vals: Vec::with_capacity(points),
            scratch: Vec::new(),
            signs: vec![0; (n[1] + 1) * (n[2] + 1) * words],
            words,
            cut: vec![0; n[0].div_ceil(64)],
            gradients: Vec::new(),
            ids: vec![[NONE; 3]; points],
            slots: BoundarySlots::new(n),
            record_keys: true,
            out: Part::default(),
        }
    }

    fn index(&self, p: [usize; 3]) -> usize {
        p[0] + (self.n[0] + 1) * (p[1] + (self.n[1] + 1) * p[2])
    }

    /// Whether lattice point `p`'s sample is at least the isovalue (certified).
    fn positive(&self, p: [usize; 3]) -> bool {
        let row = p[1] + (self.n[1] + 1) * p[2];
        self.signs[row * self.words + p[0] / 64] >> (p[0] % 64) & 1 == 1
    }

    /// Polygonises element `e` (Section 3.3, steps 2–6).
    fn element(&mut self, e: usize) {
        let nodes = self.m.elements[e];
        self.slots.begin(e, nodes);
        let mut tensor = std::mem::take(&mut self.tensor).expect("a tensor between elements");
        let (s_u, s_x) = tensor.load(self.m, &nodes, &self.slot_table);
        let cur = Current {
            e,
            nodes,
            tensor: &tensor,
            err: (VALUE_BOUND * s_u).max(f64::MIN_POSITIVE),
            lip: 1.5 * s_x * (1.0 + 8.0 * EPS),
            x_err: 2.0 * VALUE_BOUND * s_x,
            start: self.out.vertices.len() as u32,
        };
        // Step 2: sample the lattice, and certify each sign.
        tensor.sample_field(self.lattice, &mut self.scratch, &mut self.vals);
        self.classify_samples(&cur);
        if self.normals == NormalSource::FiniteDifference {
            self.gradients = finite_difference_gradients(&self.vals, self.n);
        }
        let flip = element_flip(&cur, &mut self.oracle, &mut self.out.stats);
        let n = self.n;
        self.out.stats.cells += n[0] * n[1] * n[2];
        let words = self.words;
        let row = |j: usize, k: usize| (j + (n[1] + 1) * k) * words;
        let mut cut = std::mem::take(&mut self.cut);
        for ck in 0..n[2] {
            for cj in 0..n[1] {
                let r = [
                    row(cj, ck),
                    row(cj + 1, ck),
                    row(cj, ck + 1),
                    row(cj + 1, ck + 1),
                ];
                if words == 1 {
                    // One word per row (up to 63 cells along ξ₁): the grid's rule inline.
                    let s = &self.signs;
                    let (a, o) = (
                        s[r[0]] & s[r[1]] & s[r[2]] & s[r[3]],
                        s[r[0]] | s[r[1]] | s[r[2]] | s[r[3]],
                    );
                    let uniform = (a & (a >> 1)) | !(o | (o >> 1));
                    cut[0] = !uniform & ((1u64 << n[0]) - 1);
                } else {
                    let rows = [0, 1, 2, 3].map(|q| &self.signs[r[q]..r[q] + words]);
                    crate::mc::grid::cut_cells(rows, n[0], &mut cut);
                }
                for (w, &word) in cut.iter().enumerate() {
                    let mut bits = word;
                    while bits != 0 {
                        let ci = 64 * w + bits.trailing_zeros() as usize;
                        bits &= bits - 1;
                        self.cell(&cur, [ci, cj, ck], flip);
                    }
                }
            }
        }
        self.cut = cut;
        self.tensor = Some(tensor);
    }

    /// Sets the sign rows from the samples: certified in `f64` where the value is farther
    /// from the isovalue than its bound, exactly otherwise.
    fn classify_samples(&mut self, cur: &Current) {
        let (iso, err, words) = (self.iso, cur.err, self.words);
        let p0 = self.n[0] + 1;
        for r in 0..self.vals.len() / p0 {
            for w in 0..words {
                let (mut word, mut unsure) = (0u64, 0u64);
                let chunk = &self.vals[r * p0 + 64 * w..(r * p0 + 64 * (w + 1)).min((r + 1) * p0)];
                for (b, &v) in chunk.iter().enumerate() {
                    let d = v - iso;
                    let margin = err + EPS * d.abs();
                    let (above, below) = (d > margin, d < -margin);
                    word |= u64::from(above) << b;
                    // NaN (an overflowed sum) is neither: decided exactly.
                    unsure |= u64::from(!(above || below)) << b;
                }
                while unsure != 0 {
                    let b = unsure.trailing_zeros() as usize;
                    unsure &= unsure - 1;
                    let i = 64 * w + b;
                    let p = [i, r % (self.n[1] + 1), r / (self.n[1] + 1)];
                    self.out.stats.exact_values += 1;
                    let exact = self.oracle.value(cur.e, p);
                    word |= u64::from(exact >= self.oracle.iso) << b;
                }
                self.signs[r * words + w] = word;
            }
        }
    }

    fn sample(&self, cur: &Current, p: [usize; 3]) -> Sample {
        Sample {
            v: self.vals[self.index(p)],
            err: cur.err,
            positive: self.positive(p),
        }
    }

    /// Steps 3–6 for one cut cell.
    fn cell(&mut self, cur: &Current, cell: [usize; 3], flip: bool) {
        let tab = table();
        let corner: [bool; 8] = std::array::from_fn(|c| self.positive(cell_corner(cell, c)));
        let Some((config, amb)) = classify(|c| corner[c], &mut self.out.stats) else {
            return;
        };
        let mut sub = 0u8;
        for (bit, &f) in amb.iter().enumerate() {
            let abcd = face_abcd(f as usize);
            let s = abcd.map(|c| self.sample(cur, cell_corner(cell, c)));
            let joined = match decide_bounded(s, self.iso) {
                Some(j) => j,
                None => {
                    self.out.stats.exact_faces += 1;
                    let v = abcd.map(|c| self.oracle.value(cur.e, cell_corner(cell, c)));
                    decide_exact([&v[0], &v[1], &v[2], &v[3]], &self.oracle.iso).unwrap_or(false)
                }
            };
            sub |= u8::from(joined) << bit;
        }
        if self.topology == CellRule::Trilinear && tunnel_possible(config, sub) {
            let corners = std::array::from_fn(|c| self.oracle.value(cur.e, cell_corner(cell, c)));
            match tube_mesh(config, sub, &corners, &self.oracle.iso) {
                Some(Ok(mesh)) => return self.tube(cur, cell, &mesh, flip),
                Some(Err(why)) => {
                    self.error.get_or_insert(FeError::Construction {
                        element: cur.e,
                        cell,
                        why,
                    });
                    return;
                }
                None => {}
            }
        }
        let entry = tab.offsets[config as usize] as usize + sub as usize;
        let mut centre = [NONE; 4];
        for tri in tab.extraction_triangles(entry) {
            let mut t = [0u32; 3];
            for (slot, &edge) in t.iter_mut().zip(tri) {
                if edge < CENTRE {
                    *slot = self.edge_vertex(cur, cell, edge);
                    continue;
                }
                let pi = (edge - CENTRE) as usize;
                if centre[pi] == NONE {
                    centre[pi] = self.centre_vertex(cur, cell, entry, pi);
                }
                *slot = centre[pi];
            }
            if flip {
                t.swap(1, 2);
            }
            self.out.triangles.push(t);
        }
    }

    /// A cell drawn with its trilinear tube: cut points shared as everywhere, interior
    /// vertices made on first use (the exact path's order).
    fn tube(&mut self, cur: &Current, cell: [usize; 3], mesh: &CellMesh, flip: bool) {
        self.out.stats.tunnel_cells += 1;
        let triangles = tube_triangles(mesh, flip, |x| match x {
            0..12 => self.edge_vertex(cur, cell, x),
            _ => {
                let k = (x - 12) as usize;
                self.interior_vertex(cur, cell, &mesh.interior[k], k)
            }
        });
        self.out.triangles.extend(triangles);
    }

    /// An interior vertex of a tube: [`interior_position`] of the cut points in lattice
    /// units, mapped by eq. (2).
    fn interior_vertex(
        &mut self,
        cur: &Current,
        cell: [usize; 3],
        v: &InteriorVertex,
        index: usize,
    ) -> u32 {
        let mut dxi = 0.0f64;
        let mut cuts: Vec<(u8, [f64; 3])> = Vec::with_capacity(v.of.len() + 1);
        for &x in v.of.iter().chain(&v.toward) {
            let (axis, lo) = cell_edge(cell, x);
            let (p, dt) = self.cut_point(cur, lo, axis);
            dxi = dxi.max(dt / self.n[axis] as f64);
            cuts.push((x, p));
        }
        let point = |x: u8| {
            cuts.iter()
                .find(|c| c.0 == x)
                .map(|c| c.1)
                .unwrap_or([0.0; 3])
        };
        let p = interior_position(
            v,
            point,
            |a, b| [a[0] + b[0], a[1] + b[1], a[2] + b[2]],
            |a, k| a.map(|x| x / k as f64),
        );
        let xi = [0, 1, 2].map(|d| p[d] / self.n[d] as f64);
        let g = (self.normals == NormalSource::FiniteDifference).then(|| {
            let (axis, lo) = cell_edge(cell, v.of[0]);
            self.fd_gradient(lo, axis, point(v.of[0])[axis] - lo[axis] as f64)
        });
        let radius = cur.lip * (dxi + 8.0 * EPS) + cur.x_err;
        let origin = Origin::Interior {
            element: cur.e as u32,
            cell: cell.map(|x| x as u32),
            index: index as u8,
        };
        self.push_vertex(cur, xi, g, radius, origin)
    }

    /// The cut point of the lattice edge `lo → lo + e_axis` in lattice units, and a bound on
    /// the error of its coordinate along `axis`.
    fn cut_point(&mut self, cur: &Current, lo: [usize; 3], axis: usize) -> ([f64; 3], f64) {
        let mut hi = lo;
        hi[axis] += 1;
        let (a, b) = (self.vals[self.index(lo)], self.vals[self.index(hi)]);
        let den = (b - a).abs();
        let e_sum = 2.0 * cur.err;
        let (t, dt) = if e_sum <= 0.25 * den {
            ((self.iso - a) / (b - a), 3.0 * e_sum / den + 4.0 * EPS)
        } else {
            let p = self.oracle.cut(cur.e, lo, axis);
            (
                rational_to_f64(&(&p[axis] - Rational::from_integer((lo[axis] as i64).into()))),
                EPS,
            )
        };
        let mut p = lo.map(|x| x as f64);
        p[axis] += t.clamp(0.0, 1.0);
        (p, dt)
    }

    /// The gradient of the field in `ξ` at lattice point `lo` moved `s` along `axis`, for
    /// finite-difference normals.
    fn fd_gradient(&self, lo: [usize; 3], axis: usize, s: f64) -> [f64; 3] {
        let mut hi = lo;
        hi[axis] += 1;
        let (g0, g1) = (
            self.gradients[self.index(lo)],
            self.gradients[self.index(hi)],
        );
        [0, 1, 2].map(|d| g0[d] + s * (g1[d] - g0[d]))
    }

    /// Pushes a vertex at `ξ` with its normal (from `g`, or from the interpolant) and bound.
    fn push_vertex(
        &mut self,
        cur: &Current,
        xi: [f64; 3],
        g: Option<[f64; 3]>,
        radius: f64,
        origin: Origin,
    ) -> u32 {
        let jet = cur.tensor.jet(xi);
        let g = g.unwrap_or([jet.d[0][0], jet.d[1][0], jet.d[2][0]]);
        let columns = [0, 1, 2].map(|d| [jet.d[d][1], jet.d[d][2], jet.d[d][3]]);
        self.out
            .vertices
            .push([jet.value[1], jet.value[2], jet.value[3]]);
        self.out.normals.push(world_normal(columns, g));
        self.out.radius.push(radius);
        self.out.origin.push(origin);
        (self.out.vertices.len() - 1) as u32
    }

    /// The vertex on cell edge `edge`: made on first use, shared within the element through
    /// the id arrays and across elements through the boundary slots.
    fn edge_vertex(&mut self, cur: &Current, cell: [usize; 3], edge: u8) -> u32 {
        let (axis, lo) = cell_edge(cell, edge);
        let at = self.index(lo);
        let id = self.ids[at][axis];
        if id != NONE && id >= cur.start {
            return id;
        }
        let slot = self.slots.locate(lo, axis);
        if let Some(v) = slot.as_ref().and_then(|s| self.slots.get(s)) {
            self.ids[at][axis] = v;
            return v;
        }
        let (p, dt) = self.cut_point(cur, lo, axis);
        let xi = [0, 1, 2].map(|d| p[d] / self.n[d] as f64);
        let g = (self.normals == NormalSource::FiniteDifference)
            .then(|| self.fd_gradient(lo, axis, p[axis] - lo[axis] as f64));
        let radius = cur.lip * (dt / self.n[axis] as f64 + 4.0 * EPS) + cur.x_err;
        let origin = Origin::Edge {
            element: cur.e as u32,
            lo: lo.map(|x| x as u32),
            axis: axis as u8,
        };
        let v = self.push_vertex(cur, xi, g, radius, origin);
        self.ids[at][axis] = v;
        if let Some(s) = slot {
            if self.record_keys {
                self.out.keys.push((v, self.slots.name(&s)));
            }
            self.slots.set(s, v);
        }
        v
    }

    /// The centre vertex of a polygon (numbered after its polygon's cut points): the mean of
    /// their lattice positions, mapped by eq. (2).
    fn centre_vertex(&mut self, cur: &Current, cell: [usize; 3], entry: usize, pi: usize) -> u32 {
        let poly = &table().entries[entry].polygons[pi];
        for &x in poly {
            self.edge_vertex(cur, cell, x);
        }
        let mut c = [0.0; 3];
        let mut dxi = 0.0f64;
        let mut g = [0.0; 3];
        for &x in poly {
            let (axis, lo) = cell_edge(cell, x);
            let (p, dt) = self.cut_point(cur, lo, axis);
            for d in 0..3 {
                c[d] += p[d];
            }
            dxi = dxi.max(dt / self.n[axis] as f64);
            if self.normals == NormalSource::FiniteDifference {
                let gx = self.fd_gradient(lo, axis, p[axis] - lo[axis] as f64);
                for d in 0..3 {
                    g[d] += gx[d];
                }
            }
        }
        let xi = [0, 1, 2].map(|d| c[d] / poly.len() as f64 / self.n[d] as f64);
        let g = (self.normals == NormalSource::FiniteDifference).then_some(g);
        let radius = cur.lip * (dxi + 8.0 * EPS) + cur.x_err;
        let origin = Origin::Centre {
            element: cur.e as u32,
            cell: cell.map(|x| x as u32),
            entry: entry as u16,
            polygon: pi as u8,
        };
        self.push_vertex(cur, xi, g, radius, origin)
    }
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
fn element_flip(cur: &Current, oracle: &mut ExactOracle, stats: &mut FeStats) -> bool {
    let jet = cur.tensor.jet([0.5; 3]);
    let c: [[f64; 3]; 3] = std::array::from_fn(|d| [jet.d[d][1], jet.d[d][2], jet.d[d][3]]);
    let det = c[0][0] * (c[1][1] * c[2][2] - c[1][2] * c[2][1])
        + c[0][1] * (c[1][2] * c[2][0] - c[1][0] * c[2][2])
        + c[0][2] * (c[1][0] * c[2][1] - c[1][1] * c[2][0]);
    let flip = if det.abs() > 1e-8 * cur.lip.powi(3) {
        det < 0.0
    } else {
        let half = Rational::new(1.into(), 2.into());
        jacobian_determinant(
            oracle.model(),
            &cur.nodes,
            &[half.clone(), half.clone(), half],
        )
        .is_negative()
    };
    stats.flipped_elements += usize::from(flip);
    flip
}

/// `∇s = J⁻ᵀ ∇_ξ s` (Section 3's normal formula), unit length, or zero where `J` is singular.
fn world_normal(columns: [[f64; 3]; 3], g: [f64; 3]) -> [f64; 3] {
    // Columns c[d] = ∂x/∂ξ_d. J⁻ᵀ g = (c₁ × c₂ g₀ + c₂ × c₀ g₁ + c₀ × c₁ g₂) / det: the rows of
    // the adjugate, scaled by the sign of det only (the length is normalised away).
    let j = DMat3::from_cols_array_2d(&columns);
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
fn finite_difference_gradients(vals: &[f64], n: [usize; 3]) -> Vec<[f64; 3]> {
    let index = |p: [usize; 3]| p[0] + (n[0] + 1) * (p[1] + (n[1] + 1) * p[2]);
    let mut out = vec![[0.0; 3]; vals.len()];
    for k in 0..=n[2] {
        for j in 0..=n[1] {
            for i in 0..=n[0] {
                let p = [i, j, k];
                out[index(p)] = std::array::from_fn(|d| {
                    let (mut lo, mut hi) = (p, p);
                    lo[d] = p[d].saturating_sub(1);
                    hi[d] = (p[d] + 1).min(n[d]);
                    let h = (hi[d] - lo[d]) as f64 / n[d] as f64;
                    (vals[index(hi)] - vals[index(lo)]) / h
                });
            }
        }
    }
    out
}

/// For every vertex the smallest id at the same exact world point. Candidates are pairs whose
/// `f64` positions lie within the sum of their certified radii; each is confirmed exactly.
/// Candidates are found and the candidates' exact positions computed in parallel (one exact
/// oracle per thread); exact equality is transitive, so the classes do not depend on the
/// order in which confirmed pairs are joined.
fn coincident_representatives(
    m: &FeModel<f64>,
    iso: &Rational,
    n: [usize; 3],
    x: &[[f64; 3]],
    radius: &[f64],
    origin: &[Origin],
) -> Vec<u32> {
    use crate::par::prelude::*;
    let mut parent: Vec<u32> = (0..x.len() as u32).collect();
    if x.is_empty() {
        return parent;
    }
    let r_max = radius.iter().fold(0.0f64, |a, &r| a.max(r));
    let scale = x
        .iter()
        .flat_map(|p| p.iter())
        .fold(0.0f64, |a, v| a.max(v.abs()));
    // Cells of 32 r_max: two vertices within r_i + r_j ≤ 2 r_max of each other lie in the
    // same cell or, along an axis, in the neighbouring cell on the side where the first is
    // within 1/16 of a cell of the face. Neighbours are visited from 1/8 on (margin for the
    // rounding of p / cell, below 2⁻¹² of a cell as cells are at least 2⁻⁴⁰ of the largest
    // coordinate): about two look-ups per vertex instead of eight.
    let cell = (32.0 * r_max)
        .max(scale * 2f64.powi(-40))
        .max(f64::MIN_POSITIVE);
    let bucket = |p: [f64; 3]| p.map(|v| (v / cell).floor() as i64);
    // A hash grid without keys: cell coordinates hash to one of 2^k ≥ 2N slots, each the head
    // of a linked list through `next`. Cells that share a slot share a list, which only adds
    // candidates (every one is checked by distance), and the slot array stays small enough
    // for the cache.
    let bits = (2 * x.len()).next_power_of_two().trailing_zeros();
    let slot_of = |b: [i64; 3]| {
        let h = (b[0] as u64)
            .wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .rotate_left(21)
            ^ (b[1] as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
            ^ (b[2] as u64)
                .wrapping_mul(0x1656_67B1_9E37_79F9)
                .rotate_left(42);
        (h.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> (64 - bits)) as usize
    };
    // One pass in creation order: each vertex meets the earlier ones in its cells, then joins
    // its own cell's list. The slots are scattered over the array: each vertex's own slot is
    // prefetched `AHEAD` vertices early.
    const AHEAD: usize = 16;
    let home: Vec<u32> = x.iter().map(|p| slot_of(bucket(*p)) as u32).collect();
    let mut head = vec![NONE; 1 << bits];
    let mut next = vec![NONE; x.len()];
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    for (i, &p) in x.iter().enumerate() {
        if let Some(&s) = home.get(i + AHEAD) {
            crate::memory::prefetch(&head[s as usize]);
        }
        let b = bucket(p);
        // Per axis: the cells to visit, as offsets (0, and −1 or +1 near a face).
        let mut span = [[0i64; 2]; 3];
        let mut count = [1usize; 3];
        for a in 0..3 {
            let f = p[a] / cell - b[a] as f64;
            if f < 0.125 {
                span[a][1] = -1;
                count[a] = 2;
            } else if f > 0.875 {
                span[a][1] = 1;
                count[a] = 2;
            }
        }
        for o in 0..count[0] * count[1] * count[2] {
            let slot = if o == 0 {
                home[i] as usize
            } else {
                let pick = [
                    o % count[0],
                    o / count[0] % count[1],
                    o / (count[0] * count[1]),
                ];
                slot_of(std::array::from_fn(|a| b[a] + span[a][pick[a]]))
            };
            let mut walk = head[slot];
            while walk != NONE {
                let j = walk as usize;
                walk = next[j];
                let q = x[j];
                let dist = (0..3).fold(0.0f64, |m, a| m.max((p[a] - q[a]).abs()));
                if dist <= radius[i] + radius[j] {
                    pairs.push((j as u32, i as u32));
                }
            }
        }
        let own = &mut head[home[i] as usize];
        next[i] = *own;
        *own = i as u32;
    }
    if pairs.is_empty() {
        return parent;
    }
    let mut ids: Vec<u32> = pairs.iter().flat_map(|&(a, b)| [a, b]).collect();
    ids.sort_unstable();
    ids.dedup();
    let positions: Vec<[Rational; 3]> = ids
        .par_iter()
        .map_init(
            || ExactOracle::new(m, iso.clone(), n),
            |oracle, &v| oracle.vertex(&origin[v as usize]),
        )
        .collect();
    let exact = |v: u32| &positions[ids.binary_search(&v).expect("a candidate")];
    fn find(parent: &mut [u32], mut a: u32) -> u32 {
        while parent[a as usize] != a {
            parent[a as usize] = parent[parent[a as usize] as usize];
            a = parent[a as usize];
        }
        a
    }
    for (j, i) in pairs {
        if exact(i) == exact(j) {
            let (ri, rj) = (find(&mut parent, i), find(&mut parent, j));
            let (lo, hi) = (ri.min(rj), ri.max(rj));
            parent[hi as usize] = lo;
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
