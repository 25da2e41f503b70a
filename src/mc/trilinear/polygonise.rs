//! Triangles with the trilinear topology: one cell's triangulation built from the oracle's
//! components, and grid extraction with it (`mc extract --topology trilinear`).
//!
//! A component with one boundary cycle is a disc: the table's own triangulation of that
//! polygon (on its cut points, or fanned around its centre where a chord would lie in a
//! face). A component with two cycles `A`, `B` is a tube, built as an annulus through the
//! cell's interior: each cycle gets an inner ring (its points moved halfway towards the
//! centroid of both cycles), a strip joins each cycle to its ring, and the two rings are
//! stitched to each other. Every new edge has an interior end, so no chord lies in a cube
//! face and the faces carry exactly the table's segments: neighbouring cells stay watertight.
//! Both cycles keep the table's winding (counter-clockwise about the normal into the
//! positive region), which for the two boundaries of one oriented annulus means they turn
//! opposite ways around it: the stitch pairs one ring forward with the other backward.
//! Components with more cycles do not occur in trilinear cells (the proof
//! `mc.trilinear-topology` counts them: none); they are refused.
//!
//! The stitch interleaves the two rings' steps by index ratio, and its alignment is
//! geometric: of all pairs of start vertices, the one whose zip's diagonals have the least
//! sum of squared lengths, compared exactly from the cut points (so both paths choose alike).
//! Zipping from the cycles' first vertices instead crossed itself in about half the tube
//! cells of `[−3, 3]⁸`; the aligned zip is embedded in every tube cell of `[−3, 3]⁸` and
//! `[−4, 4]⁸` at the isovalue 1/2 (proofs `mc.tube-embedding` and `mc.tube-embedding-wide`,
//! with the exact crossing test of [`embedding`](super::embedding)).

use std::collections::HashMap;

use super::CellTopology;
use crate::mc::table::{table, triangulate};
use crate::num::Rational;

/// A vertex of a cell's triangulation that is not a cut point: `(centroid(of) + p) / 2` for
/// `toward = Some(p)` (a cut point), `centroid(of)` for `None`. All ids are cut edges.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct InteriorVertex {
    /// The cut points averaged.
    pub of: Vec<u8>,
    /// The cut point it lies halfway towards the centroid from, if any.
    pub toward: Option<u8>,
}

/// One cell's triangles: ids below 12 are cut edges, id `12 + k` is `interior[k]`.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct CellMesh {
    /// Triangles, wound counter-clockwise about the normal into the positive region.
    pub triangles: Vec<[u8; 3]>,
    /// The interior vertices.
    pub interior: Vec<InteriorVertex>,
}

/// A component with three or more boundary cycles (never produced by a trilinear cell).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("a component with {0} boundary cycles: no construction (trilinear cells have at most two)")]
pub struct TooManyCycles(pub usize);

/// The triangulation of a cell with the oracle's topology. `shifted` gives the cell's corner
/// values minus the isovalue (any common positive scale; table corner order): it is called
/// only for a cell with a tube, whose stitch is chosen from the cut points' positions.
pub fn cell_mesh(
    topo: &CellTopology,
    shifted: impl FnOnce() -> [Rational; 8],
) -> Result<CellMesh, TooManyCycles> {
    let mut out = CellMesh {
        triangles: Vec::new(),
        interior: Vec::new(),
    };
    let mut shifted = Some(shifted);
    let mut g: Option<[Rational; 8]> = None;
    for comp in &topo.components {
        match comp.cycles.as_slice() {
            [p] => disc(p, &mut out),
            [a, b] => {
                let g = g.get_or_insert_with(|| (shifted.take().expect("called once"))());
                tube(a, b, g, &mut out)
            }
            other => return Err(TooManyCycles(other.len())),
        }
    }
    Ok(out)
}

/// The cut point of table edge `e` in the unit cell, for shifted corner values `g` (the edge
/// must change sign; its point is where the linear interpolant along it is 0).
pub fn cut_point(g: &[Rational; 8], e: u8) -> [Rational; 3] {
    let [a, b] = crate::mc::table::EDGES[e as usize];
    let (ga, gb) = (&g[a as usize], &g[b as usize]);
    let t = ga / (ga - gb);
    let (pa, pb) = (
        crate::mc::table::CORNERS[a as usize],
        crate::mc::table::CORNERS[b as usize],
    );
    [0, 1, 2].map(|k| {
        Rational::from_integer(pa[k].into())
            + &t * Rational::from_integer((i64::from(pb[k]) - i64::from(pa[k])).into())
    })
}

fn push_interior(out: &mut CellMesh, v: InteriorVertex) -> u8 {
    out.interior.push(v);
    (12 + out.interior.len() - 1) as u8
}

/// The table's triangulation of one polygon.
fn disc(p: &[u8], out: &mut CellMesh) {
    match triangulate(p) {
        Some(t) => out.triangles.extend(t),
        None => {
            let c = push_interior(
                out,
                InteriorVertex {
                    of: p.to_vec(),
                    toward: None,
                },
            );
            out.triangles
                .extend((0..p.len()).map(|k| [c, p[k], p[(k + 1) % p.len()]]));
        }
    }
}

/// An annulus between cycles `a` and `b` (see the module docs), for shifted corner values
/// `g`.
fn tube(a: &[u8], b: &[u8], g: &[Rational; 8], out: &mut CellMesh) {
    let of: Vec<u8> = a.iter().chain(b).copied().collect();
    let ring = |cycle: &[u8], out: &mut CellMesh| -> Vec<u8> {
        let inner: Vec<u8> = cycle
            .iter()
            .map(|&e| {
                push_interior(
                    out,
                    InteriorVertex {
                        of: of.clone(),
                        toward: Some(e),
                    },
                )
            })
            .collect();
        // Strip: the cycle's edges forward, the ring's backward.
        let n = cycle.len();
        for i in 0..n {
            let j = (i + 1) % n;
            out.triangles.push([cycle[i], cycle[j], inner[j]]);
            out.triangles.push([cycle[i], inner[j], inner[i]]);
        }
        inner
    };
    let ra = ring(a, out);
    let rb = ring(b, out);
    // Ring b reversed, so that both rings' edges run forward in the stitch.
    let (m, n) = (ra.len(), rb.len());
    let rev = |j: usize| (n - j) % n;
    // The rings are the cycles scaled by 1/2 about one centre, so squared distances between
    // ring vertices are a quarter of those between the cut points: compare those.
    let pa: Vec<[Rational; 3]> = a.iter().map(|&e| cut_point(g, e)).collect();
    let pb: Vec<[Rational; 3]> = b.iter().map(|&e| cut_point(g, e)).collect();
    let dist: Vec<Vec<Rational>> = pa
        .iter()
        .map(|p| {
            (0..n)
                .map(|j| {
                    let q = &pb[rev(j)];
                    (0..3).map(|k| (&p[k] - &q[k]) * (&p[k] - &q[k])).sum()
                })
                .collect()
        })
        .collect();
    let d = |i: usize, j: usize| &dist[i % m][j % n];
    // The zip: steps along ring a or ring b interleaved by index ratio (never a whole ring at
    // one vertex of the other), from the pair of start vertices whose zip's diagonals have
    // the least sum of squared lengths (the first such pair on ties).
    let mut steps = Vec::with_capacity(m + n);
    let (mut i, mut j) = (0usize, 0usize);
    while i < m || j < n {
        let along_a = j == n || (i < m && (i + 1) * n <= (j + 1) * m);
        i += usize::from(along_a);
        j += usize::from(!along_a);
        steps.push(along_a);
    }
    let mut best: Option<(Rational, usize, usize)> = None;
    for i0 in 0..m {
        for j0 in 0..n {
            let mut total = d(i0, j0).clone();
            let (mut i, mut j) = (i0, j0);
            for &along_a in &steps {
                i += usize::from(along_a);
                j += usize::from(!along_a);
                total += d(i, j);
            }
            if best.as_ref().is_none_or(|b| total < b.0) {
                best = Some((total, i0, j0));
            }
        }
    }
    let (_, i0, j0) = best.expect("cycles are not empty");
    let q = |j: usize| rb[rev((j0 + j) % n)];
    let p = |i: usize| ra[(i0 + i) % m];
    let (mut i, mut j) = (0usize, 0usize);
    for along_a in steps {
        if along_a {
            out.triangles.push([p(i), p(i + 1), q(j)]);
            i += 1;
        } else {
            out.triangles.push([p(i), q(j + 1), q(j)]);
            j += 1;
        }
    }
}

/// The position of a cell vertex from the cut points' positions (`point(e)` for a cut edge
/// `e`), in any field: `add`, `half` and `scale(1/k)` given as closures.
pub fn interior_position<P: Clone>(
    v: &InteriorVertex,
    point: impl Fn(u8) -> P,
    add: impl Fn(&P, &P) -> P,
    div: impl Fn(&P, usize) -> P,
) -> P {
    let mut sum = point(v.of[0]);
    for &e in &v.of[1..] {
        sum = add(&sum, &point(e));
    }
    let centroid = div(&sum, v.of.len());
    match v.toward {
        Some(e) => div(&add(&centroid, &point(e)), 2),
        None => centroid,
    }
}

/// Checks a cell triangulation against its topology: an oriented surface (every edge in at
/// most two triangles, in opposite directions when in two), whose boundary is exactly the
/// topology's cycles, grouped into the same components, each a sphere with as many holes as
/// cycles, and with no edge between two cut points of one face other than a polygon side.
pub fn check_cell_mesh(topo: &CellTopology, mesh: &CellMesh) -> Result<(), String> {
    let mut directed: HashMap<(u8, u8), u32> = HashMap::new();
    for t in &mesh.triangles {
        if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
            return Err(format!("degenerate triangle {t:?}"));
        }
        for i in 0..3 {
            *directed.entry((t[i], t[(i + 1) % 3])).or_default() += 1;
        }
    }
    if directed.values().any(|&n| n > 1) {
        return Err("an edge is used twice in one direction (orientation)".into());
    }
    let polygon_side = |a: u8, b: u8| {
        topo.entry().polygons.iter().any(|p| {
            (0..p.len()).any(|k| {
                let (x, y) = (p[k], p[(k + 1) % p.len()]);
                (x, y) == (a, b) || (x, y) == (b, a)
            })
        })
    };
    for &(a, b) in directed.keys() {
        if a < 12 && b < 12 && !polygon_side(a, b) && crate::mc::table::share_face(a, b) {
            return Err(format!("chord {a}–{b} lies in a cube face"));
        }
    }
    let found = super::super::verify::local_components(&mesh.triangles)
        .ok_or("the boundary does not close into cycles through cut points")?;
    let expected: Vec<(Vec<Vec<u8>>, i64)> = topo
        .components
        .iter()
        .map(|c| (c.cycles.clone(), 2 - c.cycles.len() as i64))
        .collect();
    let expected = super::super::verify::canonical_components(&expected);
    if found != expected {
        return Err(format!("components {found:?}, the oracle's {expected:?}"));
    }
    // The table's polygons keep their direction: each polygon side appears forward.
    for p in &topo.entry().polygons {
        for k in 0..p.len() {
            if !directed.contains_key(&(p[k], p[(k + 1) % p.len()])) {
                return Err(format!(
                    "polygon side {}→{} not forward",
                    p[k],
                    p[(k + 1) % p.len()]
                ));
            }
        }
    }
    Ok(())
}

/// Whether a table entry can have a tube at all (two corner groups of one sign).
pub fn tunnel_possible(config: u8, sub: u8) -> bool {
    let e = table().entry(config, sub);
    // A tube joins two polygons; with one polygon there is nothing to join.
    e.polygons.len() >= 2
}

/// Counts of a trilinear-topology extraction.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct TrilinearStats {
    /// Cells the level crosses.
    pub cells: usize,
    /// Cells with a tube.
    pub tunnel_cells: usize,
    /// Cells the certified `f64` path could not decide (decided exactly).
    pub exact_fallbacks: usize,
}

/// Assembles a mesh from per-cell triangulations: cut points shared through their grid edge,
/// interior vertices per cell. `edge_point(cell, e)` and `interior(cell, v, edge_point)`
/// give positions; cells are visited in order (x fastest), so both paths number alike.
fn assemble<P: Clone>(
    cells: impl Iterator<Item = ([usize; 3], CellMesh)>,
    edge_point: impl Fn([usize; 3], u8) -> P,
    interior: impl Fn(&InteriorVertex, &dyn Fn(u8) -> P) -> P,
) -> (Vec<P>, Vec<[u32; 3]>) {
    use crate::mc::grid::grid_edge;
    let mut vertices: Vec<P> = Vec::new();
    let mut triangles = Vec::new();
    let mut by_edge: HashMap<(usize, [usize; 3]), u32> = HashMap::new();
    for (cell, m) in cells {
        let mut ids = [u32::MAX; 12];
        let mut id_of = |e: u8, vertices: &mut Vec<P>| -> u32 {
            if ids[e as usize] == u32::MAX {
                let key = grid_edge(cell, e as usize);
                ids[e as usize] = *by_edge.entry(key).or_insert_with(|| {
                    vertices.push(edge_point(cell, e));
                    (vertices.len() - 1) as u32
                });
            }
            ids[e as usize]
        };
        let mut inner = Vec::with_capacity(m.interior.len());
        for v in &m.interior {
            let p = interior(v, &|e| edge_point(cell, e));
            vertices.push(p);
            inner.push((vertices.len() - 1) as u32);
        }
        for t in &m.triangles {
            let mut out = [0u32; 3];
            for (slot, &x) in out.iter_mut().zip(t) {
                *slot = if x < 12 {
                    id_of(x, &mut vertices)
                } else {
                    inner[(x - 12) as usize]
                };
            }
            triangles.push(out);
        }
    }
    (vertices, triangles)
}

/// Why a trilinear extraction failed.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum TrilinearError {
    /// The volume or isovalue is unusable.
    #[error("{0}")]
    Volume(#[from] crate::mc::grid::VolumeError),
    /// A cell has a component with no construction (never seen in a trilinear cell).
    #[error("cell {cell:?}: {why}")]
    Construction {
        /// The cell.
        cell: [usize; 3],
        /// What.
        why: TooManyCycles,
    },
}

/// Grid extraction with the trilinear topology on the certified `f64` path (each cell's
/// topology exact where the interval path is uncertain). Disc components are triangulated
/// as the table does; tubes as in the module docs.
pub fn extract_trilinear(
    vol: &crate::mc::grid::Volume<f64>,
    iso: f64,
) -> Result<(crate::mesh::Mesh, TrilinearStats), TrilinearError> {
    let (cells, fallbacks) = super::cell_topologies(vol, iso)?;
    let mut stats = TrilinearStats {
        cells: cells.len(),
        exact_fallbacks: fallbacks,
        ..TrilinearStats::default()
    };
    let mut meshes = Vec::with_capacity(cells.len());
    for (cell, topo) in &cells {
        stats.tunnel_cells += usize::from(topo.tunnels() > 0);
        let shifted = || {
            let iso = crate::num::rational_from_f64(iso, "isovalue").expect("finite");
            super::volume::corners_of(vol, *cell)
                .map(|v| crate::num::rational_from_f64(v, "sample").expect("finite") - &iso)
        };
        let m = cell_mesh(topo, shifted)
            .map_err(|why| TrilinearError::Construction { cell: *cell, why })?;
        meshes.push((*cell, m));
    }
    let point = |cell: [usize; 3], e: u8| -> [f64; 3] {
        let [a, b] = crate::mc::table::EDGES[e as usize];
        let (pa, pb) = (
            crate::mc::table::CORNERS[a as usize],
            crate::mc::table::CORNERS[b as usize],
        );
        let at = |p: [u8; 3]| {
            *vol.at(
                cell[0] + p[0] as usize,
                cell[1] + p[1] as usize,
                cell[2] + p[2] as usize,
            )
        };
        let (va, vb) = (at(pa), at(pb));
        let t = (iso - va) / (vb - va);
        [0, 1, 2].map(|i| cell[i] as f64 + pa[i] as f64 + t * (pb[i] as f64 - pa[i] as f64))
    };
    let (vertices, triangles) = assemble(meshes.into_iter(), point, |v, pt| {
        interior_position(
            v,
            pt,
            |a, b| [a[0] + b[0], a[1] + b[1], a[2] + b[2]],
            |a, k| a.map(|x| x / k as f64),
        )
    });
    Ok((
        crate::mesh::Mesh {
            vertices,
            triangles,
            scalars: None,
            normals: None,
        },
        stats,
    ))
}

/// An exact trilinear extraction: rational vertices, triangles, counts.
pub type ExactTrilinear = (
    Vec<[crate::num::Rational; 3]>,
    Vec<[u32; 3]>,
    TrilinearStats,
);

/// The exact path: every cell's topology decided exactly, vertices rational.
pub fn extract_trilinear_exact(
    vol: &crate::mc::grid::Volume<crate::num::Rational>,
    iso: &crate::num::Rational,
) -> Result<ExactTrilinear, TrilinearError> {
    use crate::num::Rational;
    let mut meshes = Vec::new();
    let mut stats = TrilinearStats::default();
    let [nx, ny, nz] = vol.dims;
    for k in 0..nz - 1 {
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let cell = [i, j, k];
                let v: [Rational; 8] = super::volume::corners_of(vol, cell);
                let pos = v
                    .iter()
                    .filter(|x| crate::mc::table::is_positive(*x, iso))
                    .count();
                if pos == 0 || pos == 8 {
                    continue;
                }
                let topo = super::cell_topology_exact(&v, iso);
                stats.cells += 1;
                stats.tunnel_cells += usize::from(topo.tunnels() > 0);
                let m = cell_mesh(&topo, || v.clone().map(|x| x - iso))
                    .map_err(|why| TrilinearError::Construction { cell, why })?;
                meshes.push((cell, m));
            }
        }
    }
    let point = |cell: [usize; 3], e: u8| -> [Rational; 3] {
        let [a, b] = crate::mc::table::EDGES[e as usize];
        let (pa, pb) = (
            crate::mc::table::CORNERS[a as usize],
            crate::mc::table::CORNERS[b as usize],
        );
        let at = |p: [u8; 3]| {
            vol.at(
                cell[0] + p[0] as usize,
                cell[1] + p[1] as usize,
                cell[2] + p[2] as usize,
            )
        };
        let (va, vb) = (at(pa), at(pb));
        let t = (iso - va) / (vb - va);
        [0, 1, 2].map(|i| {
            Rational::from_integer((cell[i] + pa[i] as usize).into())
                + &t * Rational::from_integer((pb[i] as i64 - pa[i] as i64).into())
        })
    };
    let (vertices, triangles) = assemble(meshes.into_iter(), point, |v, pt| {
        interior_position(
            v,
            pt,
            |a, b| [0, 1, 2].map(|i| &a[i] + &b[i]),
            |a, k| {
                let k = Rational::from_integer((k as i64).into());
                [0, 1, 2].map(|i| &a[i] / &k)
            },
        )
    });
    Ok((vertices, triangles, stats))
}

/// Extraction with the trilinear topology on either path, as a mesh (exact vertices rounded
/// to the nearest `f64`): the fast path needs an isovalue that is an `f64`.
pub fn extract_trilinear_path(
    vol: &crate::mc::grid::Volume<f64>,
    iso: &crate::num::Rational,
    path: crate::Path,
) -> Result<(crate::mesh::Mesh, TrilinearStats), TrilinearError> {
    use crate::num::{rational_from_f64, rational_to_f64};
    match path {
        crate::Path::Fast | crate::Path::Filtered => {
            extract_trilinear(vol, crate::mc::grid::rational_as_f64(iso)?)
        }
        crate::Path::Exact => {
            let mut exact = Vec::with_capacity(vol.values.len());
            for (index, &x) in vol.values.iter().enumerate() {
                exact.push(
                    rational_from_f64(x, "value")
                        .map_err(|_| crate::mc::grid::VolumeError::NonFinite { index })?,
                );
            }
            let ev = crate::mc::grid::Volume::new(vol.dims, exact)?;
            let (vertices, triangles, stats) = extract_trilinear_exact(&ev, iso)?;
            let mesh = crate::mesh::Mesh {
                vertices: vertices
                    .iter()
                    .map(|p| [0, 1, 2].map(|i| rational_to_f64(&p[i])))
                    .collect(),
                triangles,
                scalars: None,
                normals: None,
            };
            Ok((mesh, stats))
        }
    }
}
