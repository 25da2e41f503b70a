//! Verifies a marching-cubes mesh made by any program from a volume against the trilinear
//! interpolant's exact isosurface ([`super::trilinear`]).
//!
//! What is checked:
//! * **Placement.** Every vertex (after the grid transform `(p − origin) / spacing`) must lie
//!   on a grid edge the level cuts, at the linear interpolant's crossing, within
//!   `tolerance` cell units — or strictly inside a cell (programs that add interior vertices
//!   for tunnels). A vertex on an uncut edge or off the crossing is an error naming it: the
//!   mesh is from another isovalue or volume. A vertex on a cell face but on no edge, or on a
//!   grid point, cannot be placed; its cells are skipped and counted.
//! * **Globally.** Vertices on one grid edge are one point (meshes written without shared
//!   vertices, e.g. STL, are welded that way). The mesh must be watertight away from the
//!   volume's boundary (every edge in two triangles, except edges lying in a boundary
//!   plane); its Euler characteristic and number of components are compared with the truth.
//! * **Cell by cell.** Each triangle belongs to the one cell all three of its vertices can
//!   lie in. In each cell the triangles' boundary cycles (as cut-edge sequences) and their
//!   grouping into components are compared with the oracle's: different cycles mean a face
//!   decided unlike the trilinear interpolant (or a missing piece); the same cycles grouped
//!   differently mean a missing or extra tunnel; a component that is not a sphere with as
//!   many holes as cycles has the wrong shape. Each mismatch keeps the cell's corner values
//!   and the oracle's witnessed topology.

use std::collections::{BTreeSet, HashMap};

use serde::Serialize;
use thiserror::Error;

use super::grid::{grid_edge, Volume, VolumeError};
use super::trilinear::volume::corners_of;
use super::trilinear::{cell_topologies, CellTopology, VolumeTopology};
use crate::mesh::Mesh;

/// Where mesh coordinates sit on the grid, and how close counts as on it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VerifyOptions {
    /// The position of sample `(0, 0, 0)`.
    pub origin: [f64; 3],
    /// The distance between samples along each axis.
    pub spacing: [f64; 3],
    /// How far (in cell units) a vertex may be from a grid line or from the interpolated
    /// crossing: `1e-3` by default, which allows coordinates written as `f32`.
    pub tolerance: f64,
    /// Which side a sample equal to the isovalue counts on ([`Ties::Auto`] by default).
    pub ties: Ties,
}

impl Default for VerifyOptions {
    fn default() -> VerifyOptions {
        VerifyOptions {
            origin: [0.0; 3],
            spacing: [1.0; 3],
            tolerance: 1e-3,
            ties: Ties::Auto,
        }
    }
}

/// Which side of the level a sample exactly at the isovalue lies on. Programs differ, and on
/// integer volumes (medical images) at an integer isovalue such samples are common: a mesh
/// made under the other rule has vertices on grid points and crossings on edges that this
/// rule does not cut.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Ties {
    /// Inside (`value ≥ iso`): the level at the isovalue minus an infinitesimal, as
    /// geocert's table and VTK's marching cubes have it.
    Inside,
    /// Outside (`value > iso` is inside): the level at the isovalue plus an infinitesimal,
    /// as scikit-image's `marching_cubes` has it. Verified as the volume `−v` at `−iso`
    /// under [`Ties::Inside`] (the same surface; the sides swap, which no check depends on).
    Outside,
    /// [`Ties::Inside`], and where some sample equals the isovalue and that reading fails
    /// or differs, also [`Ties::Outside`]; the verdict is the reading that fits better (fewer
    /// open edges, then fewer differing or skipped cells, then the nearer Euler
    /// characteristic and components; inside on a tie) and says which it is.
    Auto,
}

crate::choice::named_enum!(Ties {
    Inside => "inside",
    Outside => "outside",
    Auto => "auto",
});

/// Why a mesh could not be verified against a volume.
#[derive(Debug, Error, PartialEq)]
pub enum VerifyError {
    /// The volume or isovalue is unusable.
    #[error("{0}")]
    Volume(#[from] VolumeError),
    /// The options are unusable.
    #[error("{0}")]
    Options(String),
    /// A triangle names a vertex that does not exist, or a coordinate is not finite.
    #[error("triangle {triangle}: {why}")]
    Triangle {
        /// Its index.
        triangle: usize,
        /// What is wrong.
        why: String,
    },
    /// A vertex lies outside the volume.
    #[error("vertex {vertex} at {position:?} lies outside the volume (grid coordinates {grid:?})")]
    Outside {
        /// Its index in the file.
        vertex: usize,
        /// Its position as written.
        position: [f64; 3],
        /// Its grid coordinates.
        grid: [f64; 3],
    },
    /// A vertex lies on a grid point: a corner value equal to the isovalue, which the table's
    /// rule counts as positive, so no cut edge ends there.
    #[error("vertex {vertex} at {position:?} lies on a grid point: the level passes through no sample (a sample equal to the isovalue counts as inside)")]
    GridPoint {
        /// Its index in the file.
        vertex: usize,
        /// Its position as written.
        position: [f64; 3],
    },
    /// A vertex lies on a grid edge the level does not cut.
    #[error("vertex {vertex} at {position:?} lies on the grid edge from {lo:?} along axis {axis}, whose ends ({a}, {b}) do not straddle the isovalue: a mesh from another isovalue or volume?")]
    UncutEdge {
        /// Its index in the file.
        vertex: usize,
        /// Its position as written.
        position: [f64; 3],
        /// The edge's axis.
        axis: usize,
        /// The edge's lower grid point.
        lo: [usize; 3],
        /// The values at its ends.
        a: f64,
        /// See `a`.
        b: f64,
    },
    /// A vertex lies on a cut grid edge but away from the crossing.
    #[error("vertex {vertex} at {position:?} lies on the grid edge from {lo:?} along axis {axis} at t = {found}, but the level crosses it at t = {expected}: a mesh from another isovalue, or not linear interpolation?")]
    OffCrossing {
        /// Its index in the file.
        vertex: usize,
        /// Its position as written.
        position: [f64; 3],
        /// The edge's axis.
        axis: usize,
        /// The edge's lower grid point.
        lo: [usize; 3],
        /// The parameter found.
        found: f64,
        /// The crossing's parameter.
        expected: f64,
    },
}

/// How a cell's triangles differ from the trilinear surface in it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, PartialOrd, Ord)]
#[serde(rename_all = "snake_case")]
pub enum MismatchKind {
    /// The boundary cycles differ: a face decided unlike the interpolant, or a piece missing.
    FaceCycles,
    /// The same cycles, but the oracle joins some by a tube the mesh does not have.
    MissingTunnel,
    /// The same cycles, but the mesh joins some the oracle keeps apart.
    ExtraTunnel,
    /// The same grouping, but a component is not a sphere with as many holes as cycles.
    ComponentShape,
}

/// One cell whose triangles differ from the trilinear surface.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CellMismatch {
    /// The cell (its lowest grid point).
    pub cell: [usize; 3],
    /// How.
    pub kind: MismatchKind,
    /// The oracle's components, each a list of boundary cycles (cut edges, Lorensen–Cline
    /// numbering, canonical rotation and direction).
    pub expected: Vec<Vec<Vec<u8>>>,
    /// The mesh's, likewise.
    pub found: Vec<Vec<Vec<u8>>>,
    /// The corner values (exact as written), corners in Lorensen–Cline order.
    pub values: [f64; 8],
    /// The oracle's corner groups `[positive, negative]` (the witness; re-check with
    /// [`super::trilinear::verify_cell`]). Read under [`Ties::Outside`], the groups are
    /// those of the field above and below the isovalue; the witness re-checks on `−values`
    /// with the two groups swapped.
    pub groups: [[u8; 8]; 2],
}

/// The verdict on a mesh.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeshVerdict {
    /// The tie rule the mesh was read under ([`Ties::Inside`] or [`Ties::Outside`]).
    pub ties: Ties,
    /// Distinct vertices after welding.
    pub vertices: usize,
    /// Triangles read; `degenerate` of them collapse after welding and are dropped.
    pub triangles: usize,
    /// See `triangles`.
    pub degenerate: usize,
    /// Vertices on cut grid edges.
    pub edge_vertices: usize,
    /// Vertices off every grid line (inside cells or on faces).
    pub interior_vertices: usize,
    /// Vertices exactly on a grid point where several cut edges cross within the tolerance
    /// (a sample within rounding of the isovalue): their cells are skipped.
    pub ambiguous_vertices: usize,
    /// Edges in one triangle away from the volume's boundary.
    pub open_edges: usize,
    /// Edges in three or more triangles.
    pub nonmanifold_edges: usize,
    /// No open and no non-manifold edge.
    pub watertight: bool,
    /// The mesh's Euler characteristic.
    pub euler_characteristic: i64,
    /// The mesh's connected components.
    pub components: usize,
    /// The trilinear truth.
    pub truth_euler_characteristic: i64,
    /// See `truth_euler_characteristic`.
    pub truth_components: usize,
    /// Cells the truth has a tunnel in.
    pub truth_tunnel_cells: usize,
    /// Of those, the cells compared.
    pub tunnel_cells_compared: usize,
    /// Cells compared.
    pub cells_compared: usize,
    /// Cells skipped (an unplaced vertex, or a triangle that fits no single cell).
    pub cells_skipped: usize,
    /// Triangles whose vertices share no cell, or more than one (a triangle in a face).
    pub unassigned_triangles: usize,
    /// Cells that differ, by kind.
    pub mismatches: Vec<(MismatchKind, usize)>,
    /// The first mismatching cells (at most [`EXAMPLES`]), in cell order.
    pub examples: Vec<CellMismatch>,
}

impl MeshVerdict {
    /// All mismatching cells.
    pub fn mismatching_cells(&self) -> usize {
        self.mismatches.iter().map(|(_, n)| n).sum()
    }
    /// How badly the mesh fits the truth, for choosing between two readings (smaller is
    /// better): open or non-manifold edges, cells that differ or could not be compared, the
    /// difference in Euler characteristic and in components.
    fn misfit(&self) -> (usize, usize, u64) {
        (
            self.open_edges + self.nonmanifold_edges,
            self.mismatching_cells() + self.cells_skipped + self.unassigned_triangles,
            self.euler_characteristic
                .abs_diff(self.truth_euler_characteristic)
                + self.components.abs_diff(self.truth_components) as u64,
        )
    }

    /// The mesh has the trilinear surface's topology: watertight, the same characteristic
    /// and components, and no cell differs.
    pub fn agrees(&self) -> bool {
        self.watertight
            && self.euler_characteristic == self.truth_euler_characteristic
            && self.components == self.truth_components
            && self.mismatching_cells() == 0
    }
}

/// Mismatching cells kept as examples.
pub const EXAMPLES: usize = 10;

/// Where a vertex sits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Place {
    /// On the cut grid edge `(axis, lower grid point)`.
    Edge(usize, [usize; 3]),
    /// Off every grid line: in the cells `lo[i] ..= hi[i]` (one, or two per axis when
    /// within the tolerance of a grid plane).
    Free { lo: [usize; 3], hi: [usize; 3] },
    /// Exactly on a grid point where several cut edges cross within the tolerance: which
    /// one it stands for cannot be told (its cells are skipped).
    Ambiguous([usize; 3]),
}

/// Verifies `mesh` against the trilinear isosurface of `vol` at `iso`, with samples equal to
/// `iso` on the side [`VerifyOptions::ties`] says.
pub fn verify_mesh(
    vol: &Volume<f64>,
    iso: f64,
    mesh: &Mesh,
    opts: &VerifyOptions,
) -> Result<MeshVerdict, VerifyError> {
    let outside = || {
        let negated = Volume {
            dims: vol.dims,
            values: vol.values.iter().map(|v| -v).collect(),
        };
        let verdict = verify_inside(&negated, -iso, mesh, opts).map_err(|e| match e {
            // In the volume's own values.
            VerifyError::UncutEdge {
                vertex,
                position,
                axis,
                lo,
                a,
                b,
            } => VerifyError::UncutEdge {
                vertex,
                position,
                axis,
                lo,
                a: -a,
                b: -b,
            },
            e => e,
        });
        verdict.map(|mut v| {
            // The examples in the volume's own values: the corners above the isovalue are
            // the negated field's below it.
            for m in &mut v.examples {
                m.values = m.values.map(|x| -x);
                m.groups.swap(0, 1);
            }
            MeshVerdict {
                ties: Ties::Outside,
                ..v
            }
        })
    };
    match opts.ties {
        Ties::Inside => verify_inside(vol, iso, mesh, opts),
        Ties::Outside => outside(),
        Ties::Auto => {
            let inside = verify_inside(vol, iso, mesh, opts);
            if inside.as_ref().is_ok_and(MeshVerdict::agrees) || !vol.values.contains(&iso) {
                return inside;
            }
            match (inside, outside()) {
                (Ok(i), Ok(o)) => Ok(if o.misfit() < i.misfit() { o } else { i }),
                (Ok(i), Err(_)) => Ok(i),
                (Err(_), Ok(o)) => Ok(o),
                (Err(e), Err(_)) => Err(e),
            }
        }
    }
}

/// [`verify_mesh`] with samples equal to `iso` inside.
fn verify_inside(
    vol: &Volume<f64>,
    iso: f64,
    mesh: &Mesh,
    opts: &VerifyOptions,
) -> Result<MeshVerdict, VerifyError> {
    if !(opts.tolerance > 0.0 && opts.tolerance < 0.25)
        || opts.spacing.iter().any(|s| !(s.is_finite() && *s > 0.0))
        || opts.origin.iter().any(|o| !o.is_finite())
    {
        return Err(VerifyError::Options(
            "tolerance must lie in (0, 0.25), spacings be positive and the origin finite".into(),
        ));
    }
    let (cells, fallbacks) = cell_topologies(vol, iso)?;
    let truth: VolumeTopology =
        super::trilinear::volume::assemble(vol.dims, cells.iter().map(|(c, t)| (*c, t)), fallbacks);
    let dims = vol.dims;
    // Place and weld the vertices.
    let mut key_of: HashMap<Place, u32> = HashMap::new();
    let mut welded: Vec<u32> = Vec::with_capacity(mesh.vertices.len());
    let mut places: Vec<Place> = Vec::new();
    let mut exact_key: HashMap<[u64; 3], u32> = HashMap::new();
    let mut referenced = vec![0u32; mesh.vertices.len()];
    for (ti, t) in mesh.triangles.iter().enumerate() {
        for &v in t {
            *referenced
                .get_mut(v as usize)
                .ok_or_else(|| VerifyError::Triangle {
                    triangle: ti,
                    why: format!(
                        "vertex {v} does not exist ({} vertices)",
                        mesh.vertices.len()
                    ),
                })? += 1;
        }
    }
    // A triangle soup (no vertex shared, as STL writes meshes) is welded: vertices on one
    // grid edge are one point, others by exact position. An indexed mesh keeps its own
    // vertices (two at one position stay two, as the writer meant).
    let soup = referenced.iter().all(|&n| n <= 1);
    for (vi, p) in mesh.vertices.iter().enumerate() {
        if referenced[vi] == 0 {
            welded.push(u32::MAX);
            continue;
        }
        if p.iter().any(|x| !x.is_finite()) {
            return Err(VerifyError::Options(format!(
                "vertex {vi} has a coordinate that is not finite: {p:?}"
            )));
        }
        let place = place_vertex(vol, iso, vi, *p, opts)?;
        let id = match place {
            _ if !soup => {
                places.push(place);
                (places.len() - 1) as u32
            }
            Place::Edge(..) => *key_of.entry(place).or_insert_with(|| {
                places.push(place);
                (places.len() - 1) as u32
            }),
            _ => *exact_key.entry(p.map(f64::to_bits)).or_insert_with(|| {
                places.push(place);
                (places.len() - 1) as u32
            }),
        };
        welded.push(id);
    }
    let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(mesh.triangles.len());
    let mut degenerate = 0;
    for (ti, t) in mesh.triangles.iter().enumerate() {
        let mut w = [0u32; 3];
        for (slot, &v) in w.iter_mut().zip(t) {
            *slot = *welded
                .get(v as usize)
                .ok_or_else(|| VerifyError::Triangle {
                    triangle: ti,
                    why: format!("vertex {v} does not exist ({} vertices)", welded.len()),
                })?;
        }
        if w[0] == w[1] || w[1] == w[2] || w[0] == w[2] {
            degenerate += 1;
        } else {
            triangles.push(w);
        }
    }
    // Global: edges, characteristic, components.
    let mut edge_uses: HashMap<(u32, u32), u32> = HashMap::new();
    for t in &triangles {
        for i in 0..3 {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            *edge_uses.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let on_boundary_plane = |a: u32, b: u32| {
        let planes = |p: &Place| -> [(bool, bool); 3] {
            let lo_hi = |c: usize, axis: usize, along: bool| {
                if along {
                    (false, false)
                } else {
                    (c == 0, c + 1 == dims[axis])
                }
            };
            match p {
                Place::Edge(ax, lo) => std::array::from_fn(|i| lo_hi(lo[i], i, i == *ax)),
                Place::Ambiguous(point) => std::array::from_fn(|i| lo_hi(point[i], i, false)),
                // Vertices off the grid lines (polygon centres, tunnel vertices) are not on
                // the volume's boundary in a marching-cubes mesh.
                Place::Free { .. } => [(false, false); 3],
            }
        };
        let (pa, pb) = (planes(&places[a as usize]), planes(&places[b as usize]));
        (0..3).any(|i| (pa[i].0 && pb[i].0) || (pa[i].1 && pb[i].1))
    };
    let mut open_edges = 0;
    let mut nonmanifold_edges = 0;
    for (&(a, b), &n) in &edge_uses {
        if n == 1 && !on_boundary_plane(a, b) {
            open_edges += 1;
        } else if n > 2 {
            nonmanifold_edges += 1;
        }
    }
    let mut used = vec![false; places.len()];
    let mut parent: Vec<u32> = (0..places.len() as u32).collect();
    fn find(p: &mut [u32], mut a: u32) -> u32 {
        while p[a as usize] != a {
            p[a as usize] = p[p[a as usize] as usize];
            a = p[a as usize];
        }
        a
    }
    for t in &triangles {
        for &v in t {
            used[v as usize] = true;
        }
        for i in 1..3 {
            let (x, y) = (find(&mut parent, t[0]), find(&mut parent, t[i]));
            if x != y {
                parent[x.max(y) as usize] = x.min(y);
            }
        }
    }
    let used_count = used.iter().filter(|u| **u).count();
    let components = (0..places.len() as u32)
        .filter(|&v| used[v as usize] && find(&mut parent, v) == v)
        .count();
    let euler = used_count as i64 - edge_uses.len() as i64 + triangles.len() as i64;
    // Cell by cell.
    let candidates = |p: &Place| -> Vec<[usize; 3]> {
        match *p {
            Place::Ambiguous(point) => {
                let mut out = Vec::new();
                for z in point[2].saturating_sub(1)..=point[2].min(dims[2] - 2) {
                    for y in point[1].saturating_sub(1)..=point[1].min(dims[1] - 2) {
                        for x in point[0].saturating_sub(1)..=point[0].min(dims[0] - 2) {
                            out.push([x, y, z]);
                        }
                    }
                }
                out
            }
            Place::Free { lo, hi } => {
                let mut out = Vec::new();
                for z in lo[2]..=hi[2] {
                    for y in lo[1]..=hi[1] {
                        for x in lo[0]..=hi[0] {
                            out.push([x, y, z]);
                        }
                    }
                }
                out
            }
            Place::Edge(axis, lo) => {
                let mut out = Vec::with_capacity(4);
                let others: Vec<usize> = (0..3).filter(|&i| i != axis).collect();
                for du in 0..2usize {
                    for dw in 0..2usize {
                        let mut c = lo;
                        let (u, w) = (others[0], others[1]);
                        if lo[u] < du || lo[w] < dw {
                            continue;
                        }
                        c[u] -= du;
                        c[w] -= dw;
                        if c[u] + 1 < dims[u] && c[w] + 1 < dims[w] && c[axis] + 1 < dims[axis] {
                            out.push(c);
                        }
                    }
                }
                out
            }
        }
    };
    let mut per_cell: HashMap<[usize; 3], Vec<[u32; 3]>> = HashMap::new();
    let mut skipped: BTreeSet<[usize; 3]> = BTreeSet::new();
    let mut unassigned = 0;
    for t in &triangles {
        let sets: Vec<Vec<[usize; 3]>> =
            t.iter().map(|&v| candidates(&places[v as usize])).collect();
        let common: Vec<[usize; 3]> = sets[0]
            .iter()
            .filter(|c| sets[1].contains(c) && sets[2].contains(c))
            .copied()
            .collect();
        let ambiguous = t
            .iter()
            .any(|&v| matches!(places[v as usize], Place::Ambiguous(_)));
        match common.as_slice() {
            [c] if ambiguous => {
                skipped.insert(*c);
            }
            [c] => per_cell.entry(*c).or_default().push(*t),
            _ => {
                unassigned += 1;
                skipped.extend(common.iter().copied());
                for s in &sets {
                    if s.len() == 1 {
                        skipped.insert(s[0]);
                    }
                }
            }
        }
    }
    let truth_of: HashMap<[usize; 3], &CellTopology> = cells.iter().map(|(c, t)| (*c, t)).collect();
    let mut compare: BTreeSet<[usize; 3]> = per_cell.keys().copied().collect();
    compare.extend(truth_of.keys().copied());
    let mut counts: HashMap<MismatchKind, usize> = HashMap::new();
    let mut examples = Vec::new();
    let mut compared = 0;
    let mut tunnels_compared = 0;
    for cell in compare {
        if skipped.contains(&cell) {
            continue;
        }
        compared += 1;
        if truth_of.get(&cell).is_some_and(|t| t.tunnels() > 0) {
            tunnels_compared += 1;
        }
        let expected = truth_of
            .get(&cell)
            .map(|t| {
                canonical_components(
                    &t.components
                        .iter()
                        .map(|c| (c.cycles.clone(), 2 - c.cycles.len() as i64))
                        .collect::<Vec<_>>(),
                )
            })
            .unwrap_or_default();
        let tris = per_cell.get(&cell).map(Vec::as_slice).unwrap_or(&[]);
        // `None`: the boundary does not close into cycles through cut edges.
        let found_or = found_components(cell, tris, &places);
        let found = found_or.clone().unwrap_or_default();
        let exp_cycles: BTreeSet<&Vec<u8>> = expected.iter().flat_map(|c| &c.0).collect();
        let found_cycles: BTreeSet<&Vec<u8>> = found.iter().flat_map(|c| &c.0).collect();
        let kind = if found_or.is_none() {
            Some(MismatchKind::ComponentShape)
        } else if exp_cycles != found_cycles {
            Some(MismatchKind::FaceCycles)
        } else {
            let groups = |v: &[(Vec<Vec<u8>>, i64)]| -> BTreeSet<Vec<Vec<u8>>> {
                v.iter().map(|c| c.0.clone()).collect()
            };
            let (eg, fg) = (groups(&expected), groups(&found));
            if eg != fg {
                let exp_max = expected.iter().map(|c| c.0.len()).max().unwrap_or(0);
                let found_max = found.iter().map(|c| c.0.len()).max().unwrap_or(0);
                Some(if found_max < exp_max {
                    MismatchKind::MissingTunnel
                } else {
                    MismatchKind::ExtraTunnel
                })
            } else if found.iter().any(|(cy, chi)| *chi != 2 - cy.len() as i64) {
                Some(MismatchKind::ComponentShape)
            } else {
                None
            }
        };
        if let Some(kind) = kind {
            *counts.entry(kind).or_default() += 1;
            if examples.len() < EXAMPLES {
                examples.push(CellMismatch {
                    cell,
                    kind,
                    expected: expected.iter().map(|c| c.0.clone()).collect(),
                    found: found.iter().map(|c| c.0.clone()).collect(),
                    values: corners_of(vol, cell),
                    groups: truth_of.get(&cell).map_or([[u8::MAX; 8]; 2], |t| t.groups),
                });
            }
        }
    }
    let mut mismatches: Vec<(MismatchKind, usize)> = counts.into_iter().collect();
    mismatches.sort();
    let count_places = |f: fn(&Place) -> bool| places.iter().filter(|p| f(p)).count();
    Ok(MeshVerdict {
        ties: Ties::Inside,
        vertices: used_count,
        triangles: mesh.triangles.len(),
        degenerate,
        edge_vertices: count_places(|p| matches!(p, Place::Edge(..))),
        interior_vertices: count_places(|p| matches!(p, Place::Free { .. })),
        ambiguous_vertices: count_places(|p| matches!(p, Place::Ambiguous(_))),
        open_edges,
        nonmanifold_edges,
        watertight: open_edges == 0 && nonmanifold_edges == 0,
        euler_characteristic: euler,
        components,
        truth_euler_characteristic: truth.euler_characteristic,
        truth_components: truth.components.len(),
        truth_tunnel_cells: truth.tunnel_cells,
        tunnel_cells_compared: tunnels_compared,
        cells_compared: compared,
        cells_skipped: skipped.len(),
        unassigned_triangles: unassigned,
        mismatches,
        examples,
    })
}

/// Places vertex `vi` on the grid.
fn place_vertex(
    vol: &Volume<f64>,
    iso: f64,
    vi: usize,
    p: [f64; 3],
    opts: &VerifyOptions,
) -> Result<Place, VerifyError> {
    let tol = opts.tolerance;
    let g: [f64; 3] = std::array::from_fn(|i| (p[i] - opts.origin[i]) / opts.spacing[i]);
    let dims = vol.dims;
    if (0..3).any(|i| !(g[i] >= -tol && g[i] <= (dims[i] - 1) as f64 + tol)) {
        return Err(VerifyError::Outside {
            vertex: vi,
            position: p,
            grid: g,
        });
    }
    let near: [Option<usize>; 3] = std::array::from_fn(|i| {
        let r = g[i].round();
        ((g[i] - r).abs() <= tol).then_some(r.clamp(0.0, (dims[i] - 1) as f64) as usize)
    });
    let cell_of = |x: f64, i: usize| (x.floor().max(0.0) as usize).min(dims[i] - 2);
    let on = (0..3).filter(|&i| near[i].is_some()).count();
    if on < 2 {
        return Ok(Place::Free {
            lo: [0, 1, 2].map(|i| cell_of(g[i] - tol, i)),
            hi: [0, 1, 2].map(|i| cell_of(g[i] + tol, i)),
        });
    }
    // The grid edges the vertex may lie on: along each axis whose two others are on grid
    // lines (near a grid point, the edges on both sides of it along every axis).
    let mut candidates: Vec<(usize, [usize; 3])> = Vec::new();
    for axis in 0..3 {
        if (0..3).any(|i| i != axis && near[i].is_none()) {
            continue;
        }
        let mut lo: [usize; 3] = std::array::from_fn(|i| near[i].unwrap_or(0));
        let base = g[axis].floor().max(0.0) as usize;
        for l in [base.saturating_sub(1), base, base + 1] {
            if l + 1 < dims[axis]
                && (g[axis] - l as f64) >= -tol
                && (g[axis] - l as f64) <= 1.0 + tol
            {
                lo[axis] = l;
                if !candidates.contains(&(axis, lo)) {
                    candidates.push((axis, lo));
                }
            }
        }
    }
    let mut best: Option<(f64, usize, [usize; 3])> = None;
    let mut qualifying = 0;
    let mut first_uncut = None;
    let mut first_off = None;
    let mut on_level = false;
    for &(axis, lo) in &candidates {
        let mut hi = lo;
        hi[axis] += 1;
        let (a, b) = (*vol.at(lo[0], lo[1], lo[2]), *vol.at(hi[0], hi[1], hi[2]));
        if a == iso && b == iso {
            // The whole edge lies on the level (the interpolant is `iso` all along it): a
            // point of it is a point of the surface, though no crossing (an interior vertex
            // some programs put at the mean of a cell's crossings can land there).
            on_level = true;
            continue;
        }
        if (a >= iso) == (b >= iso) {
            first_uncut.get_or_insert(VerifyError::UncutEdge {
                vertex: vi,
                position: p,
                axis,
                lo,
                a,
                b,
            });
            continue;
        }
        let expected = (iso - a) / (b - a);
        let found = g[axis] - lo[axis] as f64;
        let off = (found - expected).abs();
        if off > tol {
            first_off.get_or_insert(VerifyError::OffCrossing {
                vertex: vi,
                position: p,
                axis,
                lo,
                found,
                expected,
            });
            continue;
        }
        // Near a grid point several edges qualify; the vertex's own edge is the one it is
        // closest to across (writers compute the other coordinates exactly) and along.
        let across: f64 = (0..3)
            .filter(|&i| i != axis)
            .map(|i| (g[i] - lo[i] as f64).abs())
            .sum();
        let score = off + across;
        qualifying += 1;
        if best.is_none_or(|(d, _, _)| score < d) {
            best = Some((score, axis, lo));
        }
    }
    let exactly_on_point = (0..3).all(|i| near[i].is_some_and(|n| g[i] == n as f64));
    match (best, first_off, first_uncut) {
        (Some(_), _, _) if exactly_on_point && qualifying > 1 => {
            Ok(Place::Ambiguous(near.map(|n| n.unwrap_or(0))))
        }
        (Some((_, axis, lo)), _, _) => Ok(Place::Edge(axis, lo)),
        (None, _, _) if on_level => Ok(Place::Free {
            lo: [0, 1, 2].map(|i| cell_of(g[i] - tol, i)),
            hi: [0, 1, 2].map(|i| cell_of(g[i] + tol, i)),
        }),
        (None, Some(e), _) | (None, None, Some(e)) => Err(e),
        (None, None, None) => Err(VerifyError::GridPoint {
            vertex: vi,
            position: p,
        }),
    }
}

/// Canonical cycle: rotated to start at its smallest edge, in the direction whose second
/// element is smaller.
fn canonical_cycle(c: &[u8]) -> Vec<u8> {
    let n = c.len();
    let start = (0..n).min_by_key(|&i| c[i]).unwrap_or(0);
    let fwd: Vec<u8> = (0..n).map(|k| c[(start + k) % n]).collect();
    let bwd: Vec<u8> = (0..n).map(|k| c[(start + n - k) % n]).collect();
    fwd.min(bwd)
}

/// Components as sorted lists of canonical cycles, with their Euler characteristics, sorted.
pub(crate) fn canonical_components(comps: &[(Vec<Vec<u8>>, i64)]) -> Vec<(Vec<Vec<u8>>, i64)> {
    let mut out: Vec<(Vec<Vec<u8>>, i64)> = comps
        .iter()
        .map(|(cycles, chi)| {
            let mut cs: Vec<Vec<u8>> = cycles.iter().map(|c| canonical_cycle(c)).collect();
            cs.sort();
            (cs, *chi)
        })
        .collect();
    out.sort();
    out
}

/// The components of a cell's triangles: their boundary cycles (local cut-edge ids) and
/// Euler characteristics; `None` when the boundary does not close into cycles through
/// cut-edge vertices.
fn found_components(
    cell: [usize; 3],
    tris: &[[u32; 3]],
    places: &[Place],
) -> Option<Vec<(Vec<Vec<u8>>, i64)>> {
    if tris.is_empty() {
        return Some(Vec::new());
    }
    // Local ids: cut edges 0–11, interior vertices 12 and up.
    let local_edge: HashMap<(usize, [usize; 3]), u8> = (0..12u8)
        .map(|e| (grid_edge(cell, e as usize), e))
        .collect();
    let mut interior: HashMap<u32, u32> = HashMap::new();
    let local = |v: u32, interior: &mut HashMap<u32, u32>| -> u32 {
        match places[v as usize] {
            Place::Edge(axis, lo) => local_edge.get(&(axis, lo)).map_or(u32::MAX, |&e| e as u32),
            _ => {
                let n = interior.len() as u32;
                12 + *interior.entry(v).or_insert(n)
            }
        }
    };
    let lt: Vec<[u32; 3]> = tris
        .iter()
        .map(|t| t.map(|v| local(v, &mut interior)))
        .collect();
    if lt
        .iter()
        .flatten()
        .any(|&v| v == u32::MAX || v > u8::MAX as u32)
    {
        return None;
    }
    let lt: Vec<[u8; 3]> = lt.iter().map(|t| t.map(|v| v as u8)).collect();
    local_components(&lt)
}

/// The components of triangles on a cell's local ids (cut edges 0–11, interior vertices 12
/// and up): their boundary cycles and Euler characteristics, canonical; `None` when the
/// boundary does not close into cycles through cut points.
pub(crate) fn local_components(lt: &[[u8; 3]]) -> Option<Vec<(Vec<Vec<u8>>, i64)>> {
    if lt.is_empty() {
        return Some(Vec::new());
    }
    let nv = 1 + lt.iter().flatten().copied().max().unwrap_or(0) as usize;
    let lt: Vec<[u32; 3]> = lt.iter().map(|t| t.map(u32::from)).collect();
    let mut parent: Vec<usize> = (0..nv).collect();
    fn find(p: &mut [usize], mut a: usize) -> usize {
        while p[a] != a {
            p[a] = p[p[a]];
            a = p[a];
        }
        a
    }
    let mut uses: HashMap<(u32, u32), u32> = HashMap::new();
    for t in &lt {
        for i in 0..3 {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            *uses.entry((a.min(b), a.max(b))).or_default() += 1;
            let (x, y) = (find(&mut parent, a as usize), find(&mut parent, b as usize));
            if x != y {
                parent[x.max(y)] = x.min(y);
            }
        }
    }
    let mut next: HashMap<u32, Vec<u32>> = HashMap::new();
    for (&(a, b), &n) in &uses {
        if n == 1 {
            next.entry(a).or_default().push(b);
            next.entry(b).or_default().push(a);
        }
    }
    if next.values().any(|v| v.len() != 2) || next.keys().any(|&v| v >= 12) {
        return None;
    }
    // Walk the cycles.
    let mut seen: BTreeSet<u32> = BTreeSet::new();
    /// Per component: cycles, vertices, edges, triangles.
    type Parts = (Vec<Vec<u8>>, BTreeSet<u32>, usize, usize);
    let mut by_root: HashMap<usize, Parts> = HashMap::new();
    let mut starts: Vec<u32> = next.keys().copied().collect();
    starts.sort();
    for s in starts {
        if seen.contains(&s) {
            continue;
        }
        let mut cycle = vec![s as u8];
        seen.insert(s);
        let (mut prev, mut cur) = (s, next[&s][0]);
        while cur != s {
            if !seen.insert(cur) {
                return None;
            }
            cycle.push(cur as u8);
            let n = &next[&cur];
            let nxt = if n[0] != prev { n[0] } else { n[1] };
            prev = cur;
            cur = nxt;
        }
        let root = find(&mut parent, s as usize);
        by_root.entry(root).or_default().0.push(cycle);
    }
    for t in &lt {
        let root = find(&mut parent, t[0] as usize);
        let e = by_root.entry(root).or_default();
        e.1.extend(t.iter().copied());
        e.3 += 1;
    }
    for (&(a, _), _) in uses.iter() {
        let root = find(&mut parent, a as usize);
        by_root.entry(root).or_default().2 += 1;
    }
    let comps: Vec<(Vec<Vec<u8>>, i64)> = by_root
        .into_values()
        .map(|(cycles, verts, edges, faces)| {
            (cycles, verts.len() as i64 - edges as i64 + faces as i64)
        })
        .collect();
    Some(canonical_components(&comps))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mc::grid::{extract, ExtractOptions};
    use crate::mc::table::{table, CORNERS, EDGES};
    use crate::num::rational_from_f64;

    fn noise(n: usize, seed: u64) -> Volume<f64> {
        let mut s = seed;
        let values = (0..n * n * n)
            .map(|_| {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                ((s >> 33) % 2001) as f64 / 1000.0 - 1.0
            })
            .collect();
        Volume::new([n, n, n], values).unwrap()
    }

    fn table_mesh(vol: &Volume<f64>, iso: f64) -> Mesh {
        let iso = rational_from_f64(iso, "iso").unwrap();
        extract(vol, &iso, &ExtractOptions::new()).unwrap().0
    }

    #[test]
    fn the_table_mesh_differs_exactly_in_the_tunnel_cells() {
        let mut tunnels = 0;
        for seed in 0..6 {
            let vol = noise(9, seed);
            let mesh = table_mesh(&vol, 0.1);
            let v = verify_mesh(&vol, 0.1, &mesh, &VerifyOptions::default()).unwrap();
            assert!(v.watertight, "{v:?}");
            if v.ambiguous_vertices == 0 {
                assert_eq!((v.unassigned_triangles, v.cells_skipped), (0, 0));
            }
            // Only tunnels are missing, and every tunnel cell is found.
            assert!(
                v.mismatches
                    .iter()
                    .all(|(k, _)| *k == MismatchKind::MissingTunnel),
                "{v:?}"
            );
            assert_eq!(v.mismatching_cells(), v.tunnel_cells_compared);
            // Each missing tube is two discs: +2 to χ per tunnel (the tube's χ is 0).
            assert_eq!(
                v.euler_characteristic,
                v.truth_euler_characteristic + 2 * v.truth_tunnel_cells as i64
            );
            tunnels += v.truth_tunnel_cells;
            for m in &v.examples {
                assert_eq!(m.expected.len() + 1, m.found.len());
            }
        }
        assert!(tunnels > 0, "noise has tunnels");
    }

    /// Integer samples at an integer isovalue, as medical images have them: about a fifth of
    /// the samples equal the isovalue. A mesh made with ties inside (geocert, VTK) and one
    /// made with ties outside (scikit-image; here the table on `−v` at `−iso`) are each read
    /// under their own rule by `auto` and verify, up to the table's missing tunnels; a
    /// vertex on an edge lying wholly on the level is a point of the surface.
    #[test]
    fn ties_are_read_under_the_rule_the_mesh_was_made_with() {
        let mut grid_point_vertices = 0;
        for seed in 0..4 {
            let noisy = noise(9, seed);
            let values = noisy.values.iter().map(|v| (2.0 * v).round()).collect();
            let vol = Volume::new(noisy.dims, values).unwrap();
            assert!(vol.values.iter().filter(|&&v| v == 0.0).count() > 100);
            let negated = Volume::new(vol.dims, vol.values.iter().map(|v| -v).collect()).unwrap();
            for (mesh, rule) in [
                (table_mesh(&vol, 0.0), Ties::Inside),
                (table_mesh(&negated, 0.0), Ties::Outside),
            ] {
                let v = verify_mesh(&vol, 0.0, &mesh, &VerifyOptions::default()).unwrap();
                assert_eq!(v.ties, rule);
                assert!(v.watertight, "{rule:?}: {v:?}");
                assert!(
                    v.mismatches
                        .iter()
                        .all(|(k, _)| *k == MismatchKind::MissingTunnel),
                    "{rule:?}: {v:?}"
                );
                let forced = VerifyOptions {
                    ties: rule,
                    ..VerifyOptions::default()
                };
                assert_eq!(verify_mesh(&vol, 0.0, &mesh, &forced).unwrap(), v);
                grid_point_vertices += v.ambiguous_vertices;
            }
        }
        assert!(grid_point_vertices > 0);
        // A vertex in the middle of an edge whose two samples equal the isovalue is on the
        // surface (placed off the grid lines); on a cut edge crossed at t = 1/4 it is off the
        // crossing.
        let opts = VerifyOptions::default();
        let mut values = vec![1.0; 8];
        values[0] = 0.0;
        values[1] = 0.0;
        let level = Volume::new([2, 2, 2], values).unwrap();
        let place = place_vertex(&level, 0.0, 0, [0.5, 0.0, 0.0], &opts);
        assert!(matches!(place, Ok(Place::Free { .. })), "{place:?}");
        let mut values = vec![3.0; 8];
        values[0] = -1.0;
        let crossing = Volume::new([2, 2, 2], values).unwrap();
        let place = place_vertex(&crossing, 0.0, 0, [0.5, 0.0, 0.0], &opts);
        assert!(
            matches!(place, Err(VerifyError::OffCrossing { .. })),
            "{place:?}"
        );
    }

    #[test]
    fn a_smooth_surface_agrees() {
        let n = 12;
        let values = (0..n * n * n)
            .map(|i| {
                let p = [i % n, i / n % n, i / (n * n)].map(|c| c as f64 - 5.5);
                p[0] * p[0] + 2.0 * p[1] * p[1] + p[2] * p[2] - 16.0
            })
            .collect();
        let vol = Volume::new([n, n, n], values).unwrap();
        let mesh = table_mesh(&vol, 0.0);
        let v = verify_mesh(&vol, 0.0, &mesh, &VerifyOptions::default()).unwrap();
        assert!(v.agrees(), "{v:?}");
        assert_eq!(v.euler_characteristic, 2);
        // Unwelded (as STL writes it) and scaled: the same verdict.
        let mut soup = Mesh::default();
        for t in &mesh.triangles {
            let base = soup.vertices.len() as u32;
            for &i in t {
                let p = mesh.vertices[i as usize];
                soup.vertices
                    .push([2.0 * p[0] + 1.0, 0.5 * p[1], p[2] - 3.0]);
            }
            soup.triangles.push([base, base + 1, base + 2]);
        }
        let opts = VerifyOptions {
            origin: [1.0, 0.0, -3.0],
            spacing: [2.0, 0.5, 1.0],
            ..VerifyOptions::default()
        };
        let w = verify_mesh(&vol, 0.0, &soup, &opts).unwrap();
        assert!(w.agrees(), "{w:?}");
        assert_eq!(w.vertices, v.vertices);
    }

    /// One cell's mesh from a table entry, vertices at the edge crossings.
    fn cell_mesh(values: &[f64; 8], iso: f64, config: u8, sub: u8) -> Mesh {
        let e = table().entry(config, sub);
        let mut mesh = Mesh::default();
        for [a, b] in EDGES {
            let (va, vb) = (values[a as usize], values[b as usize]);
            let t = if (va >= iso) != (vb >= iso) {
                (iso - va) / (vb - va)
            } else {
                0.5
            };
            let (pa, pb) = (CORNERS[a as usize], CORNERS[b as usize]);
            mesh.vertices
                .push([0, 1, 2].map(|i| pa[i] as f64 + t * (pb[i] as f64 - pa[i] as f64)));
        }
        mesh.triangles = e.triangles().iter().map(|t| t.map(|x| x as u32)).collect();
        mesh
    }

    #[test]
    fn a_face_decided_the_other_way_is_found() {
        // Face z = 0 ambiguous (corners 0, 2 positive), decided joined by the interpolant
        // (2·2 > 1·1).
        let values = [2.0, -1.0, 2.0, -1.0, -3.0, -3.0, -3.0, -3.0];
        let mut grid = vec![0.0; 8];
        for (c, p) in CORNERS.iter().enumerate() {
            grid[p[0] as usize + 2 * p[1] as usize + 4 * p[2] as usize] = values[c];
        }
        let vol = Volume::new([2, 2, 2], grid).unwrap();
        let truth = crate::mc::trilinear::cell_topology_exact(
            &values.map(|x| rational_from_f64(x, "v").unwrap()),
            &rational_from_f64(0.0, "iso").unwrap(),
        );
        let right = cell_mesh(&values, 0.0, truth.config, truth.sub);
        let v = verify_mesh(&vol, 0.0, &right, &VerifyOptions::default()).unwrap();
        assert_eq!(v.mismatching_cells(), 0, "{v:?}");
        let wrong = cell_mesh(&values, 0.0, truth.config, truth.sub ^ 1);
        let v = verify_mesh(&vol, 0.0, &wrong, &VerifyOptions::default()).unwrap();
        assert_eq!(v.mismatches, vec![(MismatchKind::FaceCycles, 1)]);
        assert_eq!(v.examples[0].cell, [0, 0, 0]);
        assert_eq!(v.examples[0].values, values);
    }

    #[test]
    fn bad_meshes_get_clear_errors() {
        let vol = noise(6, 9);
        let mesh = table_mesh(&vol, 0.1);
        // Another isovalue: vertices on uncut edges or off the crossing.
        let err = verify_mesh(&vol, 0.3, &mesh, &VerifyOptions::default()).unwrap_err();
        assert!(
            matches!(
                err,
                VerifyError::UncutEdge { .. } | VerifyError::OffCrossing { .. }
            ),
            "{err}"
        );
        let mut outside = mesh.clone();
        outside.vertices[0] = [-5.0, 0.0, 0.0];
        assert!(matches!(
            verify_mesh(&vol, 0.1, &outside, &VerifyOptions::default()),
            Err(VerifyError::Outside { vertex: 0, .. })
        ));
        let mut dangling = mesh.clone();
        dangling.triangles.push([0, 1, 999_999]);
        assert!(matches!(
            verify_mesh(&vol, 0.1, &dangling, &VerifyOptions::default()),
            Err(VerifyError::Triangle { .. })
        ));
        let mut holed = mesh;
        holed.triangles.pop();
        let v = verify_mesh(&vol, 0.1, &holed, &VerifyOptions::default()).unwrap();
        assert!(!v.watertight);
        assert!(v.open_edges > 0);
        let bad = VerifyOptions {
            tolerance: 0.0,
            ..VerifyOptions::default()
        };
        assert!(matches!(
            verify_mesh(&vol, 0.1, &holed, &bad),
            Err(VerifyError::Options(_))
        ));
    }
}
