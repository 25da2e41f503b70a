//! Marching cubes on regular grids with the 656-entry table: every ambiguous face decided by
//! the face decider, so neighbouring cells always agree and the surface is watertight.
//!
//! Two paths with the same traversal order (cells `x` fastest, then `y`, then `z`; within a
//! cell, the entry's triangles in order), so they number vertices identically and produce the
//! same triangle index structure:
//! * [`extract_exact`] — rational values and isovalue, exact decisions and exact vertex
//!   positions (reads like the method: one map from grid edges to vertices);
//! * [`extract_fast`] — `f64`, vertex ids of the grid edges kept for two `z`-layers only, face
//!   decisions by the certified `f64` decider with an exact fallback when it is uncertain.
//!
//! Positions are in grid coordinates (corner `(i, j, k)` at `(i, j, k)`).

use super::decider::{decide_exact, decide_fast};
use super::table::{ambiguous_faces, is_positive, table, CENTRE, CORNERS, EDGES, FACES};
use crate::mesh::Mesh;
use crate::num::{rational_from_f64, rational_to_f64, Rational};
use crate::Path;
use std::collections::HashMap;
use thiserror::Error;

/// A scalar volume on a regular grid, `x` fastest.
#[derive(Clone, Debug, PartialEq)]
pub struct Volume<T> {
    /// Samples per axis (`x, y, z`).
    pub dims: [usize; 3],
    /// The samples, `x` fastest.
    pub values: Vec<T>,
}

/// Bad volume input.
#[derive(Debug, Error, PartialEq)]
pub enum VolumeError {
    #[error("volume of {dims:?} needs {expected} values, found {found}")]
    /// The value count does not match the dimensions.
    Size {
        /// The dimensions.
        dims: [usize; 3],
        /// Their product.
        expected: usize,
        /// Values given.
        found: usize,
    },
    #[error("every dimension must be at least 2, found {0:?}")]
    /// A dimension is below 2.
    TooSmall([usize; 3]),
    #[error("value {index} is not finite")]
    /// A sample is NaN or infinite.
    NonFinite {
        /// Its index.
        index: usize,
    },
    #[error("the isovalue is not finite")]
    /// The isovalue is NaN or infinite.
    Isovalue,
    #[error("the isovalue {0} is not an f64: the fast path takes f64 isovalues (use the exact path for rational ones)")]
    /// The fast path was given an isovalue that is not an `f64`.
    IsovalueNotF64(String),
    #[error("NIfTI: {0}")]
    /// The NIfTI file is malformed (the reader's message).
    Nifti(String),
}

impl<T> Volume<T> {
    /// Checks the dimensions against the value count.
    pub fn new(dims: [usize; 3], values: Vec<T>) -> Result<Volume<T>, VolumeError> {
        if dims.iter().any(|&d| d < 2) {
            return Err(VolumeError::TooSmall(dims));
        }
        let expected = dims
            .iter()
            .try_fold(1usize, |acc, &d| acc.checked_mul(d))
            .unwrap_or(usize::MAX);
        if values.len() != expected {
            return Err(VolumeError::Size {
                dims,
                expected,
                found: values.len(),
            });
        }
        Ok(Volume { dims, values })
    }
    pub(crate) fn at(&self, i: usize, j: usize, k: usize) -> &T {
        &self.values[i + self.dims[0] * (j + self.dims[1] * k)]
    }
}

/// Counts of an extraction.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ExtractStats {
    /// Cells examined.
    pub cells: usize,
    /// Cells with at least one ambiguous face.
    pub ambiguous_cells: usize,
    /// Ambiguous faces decided (each shared face counted once per cell).
    pub ambiguous_faces: usize,
    /// Faces where the `f64` decider was uncertain and the exact one decided.
    pub exact_fallbacks: usize,
}

/// An exact extraction: rational vertices and triangles.
#[derive(Clone, Debug, PartialEq)]
pub struct ExactSurface {
    /// Vertices, exactly.
    pub vertices: Vec<[Rational; 3]>,
    /// Triangles, indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
    /// Counts.
    pub stats: ExtractStats,
}

impl ExactSurface {
    /// The mesh with every vertex rounded to the nearest `f64`.
    pub fn to_mesh(&self) -> Mesh {
        Mesh {
            normals: None,
            vertices: self
                .vertices
                .iter()
                .map(|v| [0, 1, 2].map(|a| rational_to_f64(&v[a])))
                .collect(),
            triangles: self.triangles.clone(),
            scalars: None,
        }
    }
}

/// The cell's corner offsets.
fn corner_offset(c: usize) -> [usize; 3] {
    CORNERS[c].map(|x| x as usize)
}

/// Face corners in the decider's `A, B, C, D` order: cyclic `c0 c1 c2 c3` ↦ `A = c0`,
/// `B = c1`, `C = c3`, `D = c2` (`A, D` the diagonal `c0, c2`).
fn face_abcd(f: usize) -> [usize; 4] {
    let c = FACES[f].corners;
    [c[0] as usize, c[1] as usize, c[3] as usize, c[2] as usize]
}

/// The grid edge (axis, lower corner) of a cell's local edge.
pub(crate) fn grid_edge(cell: [usize; 3], e: usize) -> (usize, [usize; 3]) {
    let [a, b] = EDGES[e];
    let (pa, pb) = (corner_offset(a as usize), corner_offset(b as usize));
    let axis = (0..3)
        .find(|&x| pa[x] != pb[x])
        .expect("an edge spans one axis");
    let lo = [0, 1, 2].map(|x| cell[x] + pa[x].min(pb[x]));
    (axis, lo)
}

/// The vertex on a cell's cut edge `e`, created at the linear interpolant's zero on first use.
fn exact_edge_vertex(
    vol: &Volume<Rational>,
    iso: &Rational,
    cell: [usize; 3],
    e: u8,
    vertex_of: &mut HashMap<(usize, [usize; 3]), u32>,
    vertices: &mut Vec<[Rational; 3]>,
) -> u32 {
    let key = grid_edge(cell, e as usize);
    *vertex_of.entry(key).or_insert_with(|| {
        let (axis, lo) = key;
        let mut hi = lo;
        hi[axis] += 1;
        let (v0, v1) = (vol.at(lo[0], lo[1], lo[2]), vol.at(hi[0], hi[1], hi[2]));
        let t = (iso - v0) / (v1 - v0);
        let mut p: [Rational; 3] = lo.map(|x| Rational::from_integer((x as i64).into()));
        p[axis] += t;
        vertices.push(p);
        (vertices.len() - 1) as u32
    })
}

/// Exact extraction (reference path).
pub fn extract_exact(vol: &Volume<Rational>, iso: &Rational) -> ExactSurface {
    let tab = table();
    let mut vertex_of: HashMap<(usize, [usize; 3]), u32> = HashMap::new();
    let mut vertices: Vec<[Rational; 3]> = Vec::new();
    let mut triangles = Vec::new();
    let mut stats = ExtractStats::default();
    let [nx, ny, nz] = vol.dims;
    for k in 0..nz - 1 {
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                stats.cells += 1;
                let v: [&Rational; 8] = std::array::from_fn(|c| {
                    let o = corner_offset(c);
                    vol.at(i + o[0], j + o[1], k + o[2])
                });
                let config =
                    (0..8).fold(0u8, |acc, c| acc | (u8::from(is_positive(v[c], iso)) << c));
                let amb = ambiguous_faces(config);
                if !amb.is_empty() {
                    stats.ambiguous_cells += 1;
                    stats.ambiguous_faces += amb.len();
                }
                let sub = amb.iter().enumerate().fold(0u8, |acc, (bit, &f)| {
                    let [a, b, c, d] = face_abcd(f as usize);
                    let joined = decide_exact([v[a], v[b], v[c], v[d]], iso).unwrap_or(false);
                    acc | (u8::from(joined) << bit)
                });
                let entry = tab.entry(config, sub);
                let mut centre = [u32::MAX; 4];
                for tri in entry.triangles_with_centres() {
                    let mut t = [0u32; 3];
                    for (slot, e) in t.iter_mut().zip(tri) {
                        if e < CENTRE {
                            *slot = exact_edge_vertex(
                                vol,
                                iso,
                                [i, j, k],
                                e,
                                &mut vertex_of,
                                &mut vertices,
                            );
                            continue;
                        }
                        let p = (e - CENTRE) as usize;
                        if centre[p] == u32::MAX {
                            // The average of the polygon's cut points.
                            let ids: Vec<u32> = entry.polygons[p]
                                .iter()
                                .map(|&x| {
                                    exact_edge_vertex(
                                        vol,
                                        iso,
                                        [i, j, k],
                                        x,
                                        &mut vertex_of,
                                        &mut vertices,
                                    )
                                })
                                .collect();
                            let n = Rational::from_integer((ids.len() as i64).into());
                            let c = [0, 1, 2].map(|a| {
                                ids.iter()
                                    .fold(Rational::default(), |s, &q| s + &vertices[q as usize][a])
                                    / &n
                            });
                            vertices.push(c);
                            centre[p] = (vertices.len() - 1) as u32;
                        }
                        *slot = centre[p];
                    }
                    triangles.push(t);
                }
            }
        }
    }
    ExactSurface {
        vertices,
        triangles,
        stats,
    }
}

/// Vertex ids of the grid edges of one `z`-layer: `x`-edges, `y`-edges, and the `z`-edges up
/// to the next layer.
struct Layer {
    /// Per grid point of the layer, the ids of its x-, y- and z-edge (interleaved, so a
    /// cell's lookups touch few cache lines).
    ids: Vec<[u32; 3]>,
}

const NONE: u32 = u32::MAX;

impl Layer {
    fn new(n: usize) -> Layer {
        Layer {
            ids: vec![[NONE; 3]; n],
        }
    }
}

/// The samples' signs (`v ≥ iso`), one bitset per grid row along `x`.
struct SignRows {
    words: usize,
    bits: Vec<u64>,
}

impl SignRows {
    /// Also checks every sample is finite (in the same pass over memory).
    fn of(vals: &[f64], nx: usize, iso: f64) -> Result<SignRows, VolumeError> {
        let words = nx.div_ceil(64);
        let rows = vals.len() / nx;
        let mut bits = vec![0u64; rows * words];
        let mut finite = true;
        for (r, row) in vals.chunks_exact(nx).enumerate() {
            for (w, chunk) in row.chunks(64).enumerate() {
                let mut word = 0u64;
                for (b, &x) in chunk.iter().enumerate() {
                    word |= u64::from(x >= iso) << b;
                    finite &= x.is_finite();
                }
                bits[r * words + w] = word;
            }
        }
        if !finite {
            let index = vals.iter().position(|v| !v.is_finite()).unwrap_or(0);
            return Err(VolumeError::NonFinite { index });
        }
        Ok(SignRows { words, bits })
    }
    fn row(&self, r: usize) -> &[u64] {
        &self.bits[r * self.words..(r + 1) * self.words]
    }
}

/// The cut cells of one cell row as a bitset (bit `i`: cell `i` has corners of both signs),
/// from the sign bitsets of its four grid rows; `cells` cells in the row.
pub(crate) fn cut_cells(rows: [&[u64]; 4], cells: usize, out: &mut [u64]) {
    let words = out.len();
    let all = |w: usize| rows[0][w] & rows[1][w] & rows[2][w] & rows[3][w];
    let any = |w: usize| rows[0][w] | rows[1][w] | rows[2][w] | rows[3][w];
    for (w, slot) in out.iter_mut().enumerate() {
        // Samples i and i + 1 of every row: shift the next word's low bit in.
        let (a, o) = (all(w), any(w));
        let (a_next, o_next) = if w + 1 < words {
            (all(w + 1) & 1, any(w + 1) & 1)
        } else {
            (0, 0)
        };
        let a1 = (a >> 1) | (a_next << 63);
        let o1 = (o >> 1) | (o_next << 63);
        let uniform = (a & a1) | !(o | o1);
        let mut cut = !uniform;
        let first = 64 * w;
        if first + 64 > cells {
            let keep = cells.saturating_sub(first);
            cut &= if keep >= 64 {
                u64::MAX
            } else {
                (1u64 << keep) - 1
            };
        }
        *slot = cut;
    }
}

/// Per local edge: (axis, lower-corner offset) and (lower corner, upper corner).
type EdgeTables<'t> = (&'t [(usize, [usize; 3]); 12], &'t [(usize, usize); 12]);

/// A cut cell of the fast path, with what its edge vertices need.
struct CellAt<'a> {
    i: usize,
    j: usize,
    k: usize,
    nx: usize,
    /// The slab's first layer in the whole volume (vertex positions are global).
    z0: usize,
    /// Record the grid edge of each vertex on an x- or y-edge of the slab's first or last
    /// plane (slabs weld by it); `last_plane` is that plane's local index.
    record: bool,
    last_plane: usize,
    v: &'a [f64; 8],
    iso: f64,
    /// Vertex ids below these are left over from older layers (see `extract_fast`).
    previous_start: u32,
    current_start: u32,
}

impl CellAt<'_> {
    /// The id of the vertex on local edge `e`, made (interpolated in the grid frame) on first
    /// use and remembered in the layer that owns the edge.
    #[inline(always)]
    fn edge_vertex(
        &self,
        (edge_info, edge_ends): EdgeTables,
        e: u8,
        lower: &mut Layer,
        upper: &mut Layer,
        mesh: &mut Mesh,
        keys: &mut Vec<(u32, (usize, [usize; 3]))>,
    ) -> u32 {
        let (axis, off) = edge_info[e as usize];
        let (x, y) = (self.i + off[0], self.j + off[1]);
        let (layer, oldest) = match (off[2], axis) {
            (0, 0 | 1) => (lower, self.previous_start),
            (0, _) => (lower, self.current_start),
            _ => (upper, self.current_start),
        };
        let id = &mut layer.ids[x + self.nx * y][axis];
        if *id == NONE || *id < oldest {
            let (c0, c1) = edge_ends[e as usize];
            let (v0, v1) = (self.v[c0], self.v[c1]);
            let mut p = [x as f64, y as f64, (self.z0 + self.k + off[2]) as f64];
            p[axis] += (self.iso - v0) / (v1 - v0);
            mesh.vertices.push(p);
            *id = (mesh.vertices.len() - 1) as u32;
            let z = self.k + off[2];
            if self.record && axis < 2 && (z == 0 || z == self.last_plane) {
                keys.push((*id, (axis, [x, y, self.z0 + z])));
            }
        }
        *id
    }
}

/// Fast extraction. Errors on non-finite values or isovalue.
pub fn extract_fast(vol: &Volume<f64>, iso: f64) -> Result<(Mesh, ExtractStats), VolumeError> {
    extract_fast_slab(&vol.values, vol.dims, iso, 0, false).map(|(m, s, _)| (m, s))
}

/// Edge vertices by grid edge `(axis, lower grid point)`, for welding slabs.
type EdgeKeys = Vec<(u32, (usize, [usize; 3]))>;

/// Fast extraction in `slabs` slabs of cell layers along z, run in parallel (feature
/// `parallel`; one after the other without it) and welded where they meet: the vertices on a
/// shared plane lie on x- and y-edges of that plane; each slab records the grid edge of those
/// (not their positions: where a sample equals the isovalue, vertices of different edges
/// coincide), and the upper slab's are replaced by the lower slab's. The mesh equals the
/// serial one, vertex for vertex and triangle for triangle (the lower slab creates a shared
/// vertex first, as the serial pass does). The output is copied once into one mesh, so on
/// few cores and surfaces with many triangles the gain is small (reports/mc.md measures it).
pub fn extract_fast_parallel(
    vol: &Volume<f64>,
    iso: f64,
    slabs: usize,
) -> Result<(Mesh, ExtractStats), VolumeError> {
    use crate::par::prelude::*;
    let [nx, ny, nz] = vol.dims;
    let layers = nz - 1;
    let slabs = slabs.clamp(1, layers);
    if slabs == 1 {
        return extract_fast(vol, iso);
    }
    if let Some(index) = vol.values.iter().position(|v| !v.is_finite()) {
        return Err(VolumeError::NonFinite { index });
    }
    let plane = nx * ny;
    let bounds: Vec<(usize, usize)> = (0..slabs)
        .map(|s| (s * layers / slabs, (s + 1) * layers / slabs))
        .collect();
    let parts: Vec<Result<(Mesh, ExtractStats, EdgeKeys), VolumeError>> = bounds
        .clone()
        .into_par_iter()
        .map(|(k0, k1)| {
            let vals = &vol.values[k0 * plane..(k1 + 1) * plane];
            extract_fast_slab(vals, [nx, ny, k1 - k0 + 1], iso, k0, true)
        })
        .collect();
    let mut parts = parts.into_iter().collect::<Result<Vec<_>, _>>()?;
    let total_v: usize = parts.iter().map(|p| p.0.vertices.len()).sum();
    let total_t: usize = parts.iter().map(|p| p.0.triangles.len()).sum();
    // The first slab's mesh is the start (moved, not copied).
    let (first, first_stats, first_keys) = parts.remove(0);
    let mut mesh = first;
    mesh.vertices.reserve(total_v - mesh.vertices.len());
    mesh.triangles.reserve(total_t - mesh.triangles.len());
    let mut stats = first_stats;
    let mut top: HashMap<(usize, [usize; 3]), u32> = first_keys
        .iter()
        .filter(|(_, key)| key.1[2] == bounds[0].1)
        .map(|&(id, key)| (key, id))
        .collect();
    // Vertices of the previous slab on x- and y-edges of its top plane, by grid edge.
    for ((m, st, keys), &(k0, k1)) in parts.into_iter().zip(&bounds[1..]) {
        stats.cells += st.cells;
        stats.ambiguous_cells += st.ambiguous_cells;
        stats.ambiguous_faces += st.ambiguous_faces;
        stats.exact_fallbacks += st.exact_fallbacks;
        // New ids: in order, skipping the bottom-plane vertices the previous slab made.
        let mut remap: Vec<u32> = vec![u32::MAX; m.vertices.len()];
        let mut next_top = HashMap::new();
        for &(id, key) in &keys {
            if key.1[2] == k0 {
                if let Some(&old) = top.get(&key) {
                    remap[id as usize] = old;
                }
            }
        }
        let mut next = mesh.vertices.len() as u32;
        for (slot, p) in remap.iter_mut().zip(&m.vertices) {
            if *slot == u32::MAX {
                mesh.vertices.push(*p);
                *slot = next;
                next += 1;
            }
        }
        for &(id, key) in &keys {
            if key.1[2] == k1 {
                next_top.insert(key, remap[id as usize]);
            }
        }
        mesh.triangles
            .extend(m.triangles.iter().map(|t| t.map(|v| remap[v as usize])));
        top = next_top;
    }
    Ok((mesh, stats))
}

/// The fast kernel on a slab: `vals` holds `dims[2]` planes starting at layer `z0`.
fn extract_fast_slab(
    vals: &[f64],
    dims: [usize; 3],
    iso: f64,
    z0: usize,
    record: bool,
) -> Result<(Mesh, ExtractStats, EdgeKeys), VolumeError> {
    if !iso.is_finite() {
        return Err(VolumeError::Isovalue);
    }
    let mut keys: EdgeKeys = Vec::new();
    let tab = table();
    let [nx, ny, nz] = dims;
    let plane = nx * ny;
    // Layers k and k+1 (x/y-edges at their z; z-edges of layer k go from k to k+1).
    let mut lower = Layer::new(plane);
    let mut upper = Layer::new(plane);
    let mut mesh = Mesh::default();
    let mut stats = ExtractStats::default();
    // Per local edge: its axis and the offset of its lower corner.
    let edge_info: [(usize, [usize; 3]); 12] = std::array::from_fn(|e| grid_edge([0, 0, 0], e));
    // Per local edge: its lower and upper corner (cell corner ids).
    let edge_ends: [(usize, usize); 12] = std::array::from_fn(|e| {
        let [a, b] = EDGES[e];
        let (a, b) = (a as usize, b as usize);
        if corner_offset(a) < corner_offset(b) {
            (a, b)
        } else {
            (b, a)
        }
    });
    // Per corner: its offset in the value array from the cell's lower corner.
    let corner_off: [usize; 8] = std::array::from_fn(|c| {
        let o = corner_offset(c);
        o[0] + nx * (o[1] + ny * o[2])
    });
    let amb_of = &tab.ambiguous;
    // As flying edges' first pass (Schroeder et al. 2015) classifies edges, one pass records
    // every sample's sign as a bit; a cell row's cut cells are then found 64 at a time from
    // the bitsets of its four grid rows, and only those cells are visited (in order, so the
    // output is as if every cell were).
    let signs = SignRows::of(vals, nx, iso)?;
    // The cut-cell bitsets of every cell row, computed once: they size the output (about one
    // vertex and two triangles per cut cell, so it does not grow by doubling) and drive the
    // traversal.
    let words = signs.words;
    let mut cut_rows = vec![0u64; (ny - 1) * (nz - 1) * words];
    for (r, cut) in cut_rows.chunks_exact_mut(words).enumerate() {
        let (j, k) = (r % (ny - 1), r / (ny - 1));
        cut_cells(
            [
                signs.row(j + ny * k),
                signs.row(j + 1 + ny * k),
                signs.row(j + ny * (k + 1)),
                signs.row(j + 1 + ny * (k + 1)),
            ],
            nx - 1,
            cut,
        );
    }
    let cut_total: usize = cut_rows.iter().map(|w| w.count_ones() as usize).sum();
    mesh.vertices.reserve(cut_total + cut_total / 4);
    mesh.triangles.reserve(2 * cut_total + cut_total / 4);
    crate::memory::advise_huge_pages(&mut mesh.vertices);
    crate::memory::advise_huge_pages(&mut mesh.triangles);
    // The layers are reused without clearing: vertex ids only grow, so an id is current when
    // it was made during this cell layer (the upper layer, and z-edges of the lower one) or
    // the previous one (x- and y-edges of the lower layer, made as the previous upper layer);
    // anything older is left over from two layers back.
    let mut current_start = 0u32;
    for k in 0..nz - 1 {
        let previous_start = std::mem::replace(&mut current_start, mesh.vertices.len() as u32);
        for j in 0..ny - 1 {
            let r = j + (ny - 1) * k;
            for (w, &word) in cut_rows[r * words..(r + 1) * words].iter().enumerate() {
                let mut bits = word;
                while bits != 0 {
                    let i = 64 * w + bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    let base = i + nx * (j + ny * k);
                    let c = &vals[base..];
                    let v: [f64; 8] = [
                        c[corner_off[0]],
                        c[corner_off[1]],
                        c[corner_off[2]],
                        c[corner_off[3]],
                        c[corner_off[4]],
                        c[corner_off[5]],
                        c[corner_off[6]],
                        c[corner_off[7]],
                    ];
                    let mut config = 0u8;
                    for (c, x) in v.iter().enumerate() {
                        config |= u8::from(*x >= iso) << c;
                    }
                    debug_assert!(config != 0 && config != 255, "a cut cell");
                    let amb = &amb_of[config as usize];
                    let mut sub = 0u8;
                    if !amb.is_empty() {
                        stats.ambiguous_cells += 1;
                        stats.ambiguous_faces += amb.len();
                        for (bit, &f) in amb.iter().enumerate() {
                            let [a, b, c, d] = face_abcd(f as usize);
                            let joined = match decide_fast([v[a], v[b], v[c], v[d]], iso) {
                                Some(Some(j)) => j,
                                _ => {
                                    stats.exact_fallbacks += 1;
                                    let q = |x: f64| rational_from_f64(x, "value").expect("finite");
                                    let (qa, qb, qc, qd, qi) =
                                        (q(v[a]), q(v[b]), q(v[c]), q(v[d]), q(iso));
                                    decide_exact([&qa, &qb, &qc, &qd], &qi).unwrap_or(false)
                                }
                            };
                            sub |= u8::from(joined) << bit;
                        }
                    }
                    let entry = tab.offsets[config as usize] as usize + sub as usize;
                    let mut centre = [u32::MAX; 4];
                    let cell = CellAt {
                        i,
                        j,
                        k,
                        nx,
                        z0,
                        record,
                        last_plane: nz - 1,
                        v: &v,
                        iso,
                        previous_start,
                        current_start,
                    };
                    let edge_vertex = |e: u8,
                                       lower: &mut Layer,
                                       upper: &mut Layer,
                                       mesh: &mut Mesh,
                                       keys: &mut Vec<_>| {
                        cell.edge_vertex((&edge_info, &edge_ends), e, lower, upper, mesh, keys)
                    };
                    for tri in tab.extraction_triangles(entry) {
                        let mut t = [0u32; 3];
                        for (slot, &e) in t.iter_mut().zip(tri) {
                            if e < CENTRE {
                                *slot =
                                    edge_vertex(e, &mut lower, &mut upper, &mut mesh, &mut keys);
                                continue;
                            }
                            let p = (e - CENTRE) as usize;
                            if centre[p] == u32::MAX {
                                let poly = &tab.entries[entry].polygons[p];
                                let mut c = [0.0f64; 3];
                                for &x in poly {
                                    let id = edge_vertex(
                                        x, &mut lower, &mut upper, &mut mesh, &mut keys,
                                    );
                                    let q = mesh.vertices[id as usize];
                                    for a in 0..3 {
                                        c[a] += q[a];
                                    }
                                }
                                mesh.vertices.push(c.map(|x| x / poly.len() as f64));
                                centre[p] = (mesh.vertices.len() - 1) as u32;
                            }
                            *slot = centre[p];
                        }
                        mesh.triangles.push(t);
                    }
                }
            }
        }
        stats.cells += (nx - 1) * (ny - 1);
        std::mem::swap(&mut lower, &mut upper);
    }
    Ok((mesh, stats, keys))
}

/// Options of [`extract`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[non_exhaustive]
pub struct ExtractOptions {
    /// [`Path::Exact`]: [`extract_exact`] on the samples taken exactly as rationals;
    /// [`Path::Fast`] / [`Path::Filtered`] (the default): [`extract_fast`], whose face
    /// decisions are certified `f64` with an exact fallback. Both give the same triangles.
    pub path: Path,
}

crate::choice::setters!(ExtractOptions {
    with_path => path: Path,
});

/// Polygonises `vol` at `iso` on the path `opts.path` names. The exact path rounds its
/// rational vertices to the nearest `f64` in the returned mesh; the fast path needs `iso` to
/// be an `f64` ([`VolumeError::IsovalueNotF64`] otherwise).
pub fn extract(
    vol: &Volume<f64>,
    iso: &Rational,
    opts: &ExtractOptions,
) -> Result<(Mesh, ExtractStats), VolumeError> {
    match opts.path {
        Path::Fast | Path::Filtered => extract_fast(vol, rational_as_f64(iso)?),
        Path::Exact => {
            let exact: Result<Vec<Rational>, _> = vol
                .values
                .iter()
                .enumerate()
                .map(|(index, &v)| {
                    crate::num::rational_from_f64(v, "sample")
                        .map_err(|_| VolumeError::NonFinite { index })
                })
                .collect();
            let s = extract_exact(&Volume::new(vol.dims, exact?)?, iso);
            Ok((s.to_mesh(), s.stats))
        }
    }
}

/// `iso` as the `f64` it equals, or [`VolumeError::IsovalueNotF64`].
pub(crate) fn rational_as_f64(iso: &Rational) -> Result<f64, VolumeError> {
    let f = crate::num::rational_to_f64(iso);
    match crate::num::rational_from_f64(f, "iso") {
        Ok(back) if &back == iso => Ok(f),
        _ => Err(VolumeError::IsovalueNotF64(crate::num::rational_to_string(
            iso,
        ))),
    }
}

/// Sample types of raw volumes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RawType {
    /// 32-bit IEEE floats.
    F32,
    /// Unsigned bytes.
    U8,
    /// 16-bit two's-complement integers.
    I16,
}

crate::choice::named_enum!(RawType {
    F32 => "f32",
    U8 => "u8",
    I16 => "i16",
});

/// Reads a raw little-endian volume of `dims` samples of `ty`, `x` fastest; every sample is
/// converted to `f64` exactly.
pub fn read_raw(bytes: &[u8], dims: [usize; 3], ty: RawType) -> Result<Volume<f64>, VolumeError> {
    let size = match ty {
        RawType::F32 => 4,
        RawType::U8 => 1,
        RawType::I16 => 2,
    };
    let n = dims
        .iter()
        .try_fold(1usize, |acc, &d| acc.checked_mul(d))
        .unwrap_or(usize::MAX);
    if bytes.len() != n.saturating_mul(size) {
        return Err(VolumeError::Size {
            dims,
            expected: n,
            found: bytes.len() / size,
        });
    }
    let values: Vec<f64> = match ty {
        RawType::F32 => bytes
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]) as f64)
            .collect(),
        RawType::U8 => bytes.iter().map(|&b| b as f64).collect(),
        RawType::I16 => bytes
            .chunks_exact(2)
            .map(|c| i16::from_le_bytes([c[0], c[1]]) as f64)
            .collect(),
    };
    if let Some(index) = values.iter().position(|v| !v.is_finite()) {
        return Err(VolumeError::NonFinite { index });
    }
    Volume::new(dims, values)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slabs_give_the_serial_mesh() {
        let mut s = 17u64;
        for (dims, slabs) in [
            ([9, 7, 12], 2),
            ([5, 6, 20], 3),
            ([8, 8, 9], 8),
            ([4, 4, 3], 5),
        ] {
            let n = dims[0] * dims[1] * dims[2];
            let values: Vec<f64> = (0..n)
                .map(|_| {
                    s = s
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    ((s >> 33) % 17) as f64 - 8.0
                })
                .collect();
            let vol = Volume::new(dims, values).unwrap();
            for iso in [0.0, 0.5] {
                let serial = extract_fast(&vol, iso).unwrap();
                let parallel = extract_fast_parallel(&vol, iso, slabs).unwrap();
                assert_eq!(serial, parallel, "{dims:?} in {slabs} slabs at {iso}");
            }
        }
        let mut v = vec![0.5; 4 * 3 * 70];
        v[201] = f64::NAN;
        let vol = Volume::new([70, 3, 4], v).unwrap();
        assert_eq!(
            extract_fast_parallel(&vol, 0.0, 2).unwrap_err(),
            VolumeError::NonFinite { index: 201 }
        );
    }

    #[test]
    fn bad_values_are_refused_with_their_index() {
        let mut v = vec![0.5; 4 * 3 * 70];
        v[201] = f64::NAN;
        let vol = Volume::new([70, 3, 4], v).unwrap();
        assert_eq!(
            extract_fast(&vol, 0.0).unwrap_err(),
            VolumeError::NonFinite { index: 201 }
        );
        let ok = Volume::new([70, 3, 4], vec![0.5; 4 * 3 * 70]).unwrap();
        assert_eq!(
            extract_fast(&ok, f64::NAN).unwrap_err(),
            VolumeError::Isovalue
        );
    }
}
