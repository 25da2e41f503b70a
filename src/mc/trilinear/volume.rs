//! The trilinear isosurface of a whole volume: its Euler characteristic, its connected
//! components and whether each is closed, assembled exactly from the cells' topologies.
//!
//! Compactly supported Euler characteristics add over the disjoint pieces of the surface in
//! open cells, open faces and open edges (no corner lies on the perturbed level). A cell
//! component with `k` boundary cycles (a sphere with `k` holes) is an open surface of
//! `χ = 2 − k`; an open arc on a face has `χ_c = −1`; a cut point on an edge `+1`. So
//! `χ = Σ_cells Σ (2 − k) − #arcs + #cut edges`, where a face arc is counted once although
//! both cells sharing its face list it. Components are glued through cut edges: every piece
//! through one cut point belongs to one component. A component is closed iff none of its cut
//! edges lies on the volume's boundary (there the surface meets the boundary along an arc).

use std::collections::HashMap;

use super::{cell_topology_exact, cell_topology_fast, CellTopology};
use crate::mc::grid::{grid_edge, Volume, VolumeError};
use crate::mc::table::{face_edges, is_positive, CORNERS, FACES};
use crate::num::{rational_from_f64, Rational};

/// One connected component of a volume's trilinear isosurface.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct SurfaceComponent {
    /// Its Euler characteristic (2 for a sphere, 0 for a torus, 1 for a disc).
    pub euler_characteristic: i64,
    /// No boundary on the volume's faces.
    pub closed: bool,
    /// Cells it passes through.
    pub cells: usize,
    /// Cut grid edges on it (its vertices in a marching-cubes mesh).
    pub cut_edges: usize,
    /// Cells where it forms a tube (a tunnel the 656-entry table does not draw).
    pub tunnels: usize,
}

/// The topology of a volume's trilinear isosurface.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct VolumeTopology {
    /// The whole surface's Euler characteristic.
    pub euler_characteristic: i64,
    /// Its components, largest (most cut edges) first.
    pub components: Vec<SurfaceComponent>,
    /// Cells the surface crosses.
    pub cells: usize,
    /// Cells with a tunnel.
    pub tunnel_cells: usize,
    /// Cells the certified `f64` path could not decide (decided exactly instead).
    pub exact_fallbacks: usize,
}

/// A cell (its lowest grid point) and its topology.
pub type CellAt = ([usize; 3], CellTopology);

/// The face (index into `FACES`) that two edges of a cube share, if any.
fn shared_face(a: u8, b: u8) -> Option<usize> {
    FACES.iter().position(|f| {
        let e = face_edges(f);
        e.contains(&a) && e.contains(&b)
    })
}

/// Assembles cell topologies (`(cell, topology)`, every crossed cell once) into the volume's.
pub(crate) fn assemble<T: std::borrow::Borrow<CellTopology>>(
    dims: [usize; 3],
    cells: impl Iterator<Item = ([usize; 3], T)>,
    exact_fallbacks: usize,
) -> VolumeTopology {
    let mut edge_node: HashMap<(usize, [usize; 3]), usize> = HashMap::new();
    let mut parent: Vec<usize> = Vec::new();
    fn find(p: &mut [usize], mut a: usize) -> usize {
        while p[a] != a {
            p[a] = p[p[a]];
            a = p[a];
        }
        a
    }
    // Per cell component: (first cut edge node, 2·(2 − k) − Σ arc weights, tunnel).
    let mut pieces: Vec<(usize, i64, bool)> = Vec::new();
    let mut crossed = 0usize;
    let mut tunnel_cells = 0usize;
    for (cell, topo) in cells {
        let topo = topo.borrow();
        crossed += 1;
        if topo.tunnels() > 0 {
            tunnel_cells += 1;
        }
        let on_boundary = |f: usize| {
            let face = FACES[f];
            if face.side == 0 {
                cell[face.axis] == 0
            } else {
                cell[face.axis] + 2 == dims[face.axis]
            }
        };
        for comp in &topo.components {
            let mut first = None;
            let mut chi2 = 2 * (2 - comp.cycles.len() as i64);
            for cycle in &comp.cycles {
                for (i, &e) in cycle.iter().enumerate() {
                    let key = grid_edge(cell, e as usize);
                    let next = parent.len();
                    let node = *edge_node.entry(key).or_insert(next);
                    if node == next {
                        parent.push(next);
                    }
                    match first {
                        None => first = Some(node),
                        Some(f) => {
                            let (x, y) = (find(&mut parent, f), find(&mut parent, node));
                            if x != y {
                                parent[x.max(y)] = x.min(y);
                            }
                        }
                    }
                    let succ = cycle[(i + 1) % cycle.len()];
                    let weight = match shared_face(e, succ) {
                        Some(f) if on_boundary(f) => 2,
                        _ => 1,
                    };
                    chi2 -= weight;
                }
            }
            if let Some(f) = first {
                pieces.push((f, chi2, comp.cycles.len() >= 2));
            }
        }
    }
    let mut by_root: HashMap<usize, (i64, bool, usize, usize, usize)> = HashMap::new();
    for (&(axis, lo), &node) in &edge_node {
        let root = find(&mut parent, node);
        let boundary = (0..3).any(|b| b != axis && (lo[b] == 0 || lo[b] + 1 == dims[b]));
        let s = by_root.entry(root).or_insert((0, true, 0, 0, 0));
        s.0 += 2;
        s.1 &= !boundary;
        s.3 += 1;
    }
    for &(first, chi2, tunnel) in &pieces {
        let root = find(&mut parent, first);
        let s = by_root.entry(root).or_insert((0, true, 0, 0, 0));
        s.0 += chi2;
        s.2 += 1;
        s.4 += usize::from(tunnel);
    }
    let mut components: Vec<SurfaceComponent> = by_root
        .into_values()
        .map(
            |(chi2, closed, cells, cut_edges, tunnels)| SurfaceComponent {
                euler_characteristic: chi2 / 2,
                closed,
                cells,
                cut_edges,
                tunnels,
            },
        )
        .collect();
    components.sort_by(|a, b| {
        b.cut_edges
            .cmp(&a.cut_edges)
            .then(a.euler_characteristic.cmp(&b.euler_characteristic))
            .then(b.closed.cmp(&a.closed))
            .then(b.cells.cmp(&a.cells))
    });
    VolumeTopology {
        euler_characteristic: components.iter().map(|c| c.euler_characteristic).sum(),
        components,
        cells: crossed,
        tunnel_cells,
        exact_fallbacks,
    }
}

fn cells_of(dims: [usize; 3]) -> impl Iterator<Item = [usize; 3]> {
    let [nx, ny, nz] = dims;
    (0..nz - 1)
        .flat_map(move |k| (0..ny - 1).flat_map(move |j| (0..nx - 1).map(move |i| [i, j, k])))
}

pub(crate) fn corners_of<T: Clone>(vol: &Volume<T>, cell: [usize; 3]) -> [T; 8] {
    std::array::from_fn(|c| {
        let o = CORNERS[c];
        vol.at(
            cell[0] + o[0] as usize,
            cell[1] + o[1] as usize,
            cell[2] + o[2] as usize,
        )
        .clone()
    })
}

/// The topology of every cell of `vol` the level crosses (at `iso − ε`, the table's tie
/// rules), each on the certified `f64` path and exactly where it is uncertain; and how many
/// needed the exact path.
pub fn cell_topologies(vol: &Volume<f64>, iso: f64) -> Result<(Vec<CellAt>, usize), VolumeError> {
    if !iso.is_finite() {
        return Err(VolumeError::Isovalue);
    }
    if let Some(index) = vol.values.iter().position(|v| !v.is_finite()) {
        return Err(VolumeError::NonFinite { index });
    }
    let iso_r = rational_from_f64(iso, "isovalue").map_err(|_| VolumeError::Isovalue)?;
    let mut fallbacks = 0usize;
    let cells = cells_of(vol.dims)
        .filter_map(|cell| {
            let v: [f64; 8] = corners_of(vol, cell);
            let pos = v.iter().filter(|x| is_positive(*x, &iso)).count();
            if pos == 0 || pos == 8 {
                return None;
            }
            let topo = cell_topology_fast(&v, iso).unwrap_or_else(|| {
                fallbacks += 1;
                // Finite f64s convert exactly.
                let q = v.map(|x| rational_from_f64(x, "value").unwrap_or_else(|_| iso_r.clone()));
                cell_topology_exact(&q, &iso_r)
            });
            Some((cell, topo))
        })
        .collect();
    Ok((cells, fallbacks))
}

/// The topology of the trilinear isosurface of `vol` at `iso` (at `iso − ε`, the table's tie
/// rules): each crossed cell on the certified `f64` path, exactly where it is uncertain.
pub fn volume_topology(vol: &Volume<f64>, iso: f64) -> Result<VolumeTopology, VolumeError> {
    let (cells, fallbacks) = cell_topologies(vol, iso)?;
    Ok(assemble(vol.dims, cells.into_iter(), fallbacks))
}

/// The reference path: every crossed cell decided exactly.
pub fn volume_topology_exact(vol: &Volume<Rational>, iso: &Rational) -> VolumeTopology {
    let cells = cells_of(vol.dims).filter_map(|cell| {
        let v: [Rational; 8] = corners_of(vol, cell);
        let pos = v.iter().filter(|x| is_positive(*x, iso)).count();
        (pos != 0 && pos != 8).then(|| (cell, cell_topology_exact(&v, iso)))
    });
    assemble(vol.dims, cells, 0)
}
