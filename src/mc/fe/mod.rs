//! Marching cubes in the material space of curvilinear finite elements (Wünsche & Lin,
//! Section 3).
//!
//! Each element's parent cube `ξ ∈ [0, 1]³` is divided into `n₁ × n₂ × n₃` cells; the field is
//! sampled at the cell corners by the element's own interpolation (eq. 1), every cell is
//! polygonised with the 656-entry table ([`table`](mod@super::table)), intersections are placed
//! by linear interpolation in `ξ`, and the vertices are mapped to world coordinates by the
//! isoparametric map (eq. 2). Lattice points and cut edges on element faces, edges and nodes
//! are identified by the global node numbers of the entity they lie on (Section 3.2), so a
//! surface crossing from one element into the next shares its vertices: the output is
//! welded. Vertices that the map sends to the same world point (degenerate elements, the
//! Figure 7 case) are merged and the triangles that collapse are removed.
//!
//! Two paths, side by side:
//! * [`exact::polygonise_exact`] — rationals throughout, faces decided by Mackerras' sort of
//!   the cut points' `ξ` coordinates (Section 3.1) with the tie rule of
//!   [`decide_exact`](super::decide_exact);
//! * [`fast::polygonise_fast`] — `f64` with a rounding bound on every sampled value: a sign
//!   or face decision the bound cannot certify is recomputed exactly, and so is every
//!   world-coincidence test, so both paths produce the same triangle index structure.
//!
//! Elements are tensor products of a 1-D basis per direction: linear Lagrange or cubic
//! Hermite (Section 2). A node carries the value and, for each subset of its Hermite
//! directions, the mixed `ξ`-derivative: dof `k` of a node differentiates along the Hermite
//! directions whose bit is set in `k` (the first Hermite direction is bit 0). For tricubic
//! Hermite that is `u, u₁, u₂, u₁₂, u₃, u₁₃, u₂₃, u₁₂₃`; for the heart model's cubic Hermite ×
//! cubic Hermite × linear Lagrange it is `u, u₁, u₂, u₁₂`. Derivatives are with respect to
//! `ξ` and shared by the elements meeting at a node.

pub(crate) mod basis;
pub(crate) mod exact;
pub(crate) mod fast;
pub(crate) mod integer;

pub use exact::{polygonise_exact, ExactFeSurface};
pub use fast::{polygonise_fast, FeSurface};
pub mod heart;
pub(crate) mod lattice;
pub mod models;
pub(crate) mod slots;
pub(crate) mod tensor;

use crate::mc::trilinear::polygonise::{CellMesh, TooManyCycles};
use crate::num::Rational;
use crate::Path;
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// The one-dimensional interpolation along one `ξ` direction (Section 2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Basis {
    /// `L₁ = 1 − ξ`, `L₂ = ξ`.
    LinearLagrange,
    /// `H₁⁰, H₁¹, H₂⁰, H₂¹`: values and first derivatives at both ends.
    CubicHermite,
}

/// An element type: one basis per `ξ` direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct ElementKind {
    /// The basis along `ξ₁, ξ₂, ξ₃`.
    pub bases: [Basis; 3],
}

impl ElementKind {
    /// Trilinear Lagrange (the 8-node hexahedron).
    pub const TRILINEAR_LAGRANGE: ElementKind = ElementKind {
        bases: [Basis::LinearLagrange; 3],
    };
    /// Tricubic Hermite.
    pub const TRICUBIC_HERMITE: ElementKind = ElementKind {
        bases: [Basis::CubicHermite; 3],
    };
    /// Cubic Hermite in `ξ₁`, `ξ₂` and linear Lagrange in `ξ₃` (the heart model, Section 4).
    pub const HERMITE_HERMITE_LAGRANGE: ElementKind = ElementKind {
        bases: [
            Basis::CubicHermite,
            Basis::CubicHermite,
            Basis::LinearLagrange,
        ],
    };

    /// Number of dofs per node: `2^h` for `h` Hermite directions.
    pub fn dofs_per_node(self) -> usize {
        1 << self
            .bases
            .iter()
            .filter(|&&b| b == Basis::CubicHermite)
            .count()
    }

    /// The Hermite directions in order (bit `b` of a dof index refers to the `b`-th).
    pub fn hermite_directions(self) -> Vec<usize> {
        (0..3)
            .filter(|&d| self.bases[d] == Basis::CubicHermite)
            .collect()
    }

    /// Which directions dof `k` differentiates along.
    pub fn derivative_of_dof(self, k: usize) -> [bool; 3] {
        let mut out = [false; 3];
        let mut bit = 0;
        for (o, b) in out.iter_mut().zip(self.bases) {
            if b == Basis::CubicHermite {
                *o = k >> bit & 1 == 1;
                bit += 1;
            }
        }
        out
    }

    /// A short name: `trilinear-lagrange`, `tricubic-hermite`, `hermite-hermite-lagrange`, or
    /// the three bases.
    pub fn name(self) -> String {
        match self {
            ElementKind::TRILINEAR_LAGRANGE => "trilinear-lagrange".into(),
            ElementKind::TRICUBIC_HERMITE => "tricubic-hermite".into(),
            ElementKind::HERMITE_HERMITE_LAGRANGE => "hermite-hermite-lagrange".into(),
            _ => self
                .bases
                .map(|b| match b {
                    Basis::LinearLagrange => "L",
                    Basis::CubicHermite => "H",
                })
                .join(""),
        }
    }
}

/// A finite element model with one interpolated scalar field.
///
/// `coordinates` and `field` are node-major: node `i`'s dof `k` is at `i · dofs_per_node + k`
/// (see the module docs for the dof order). Element nodes are listed in tensor order: local
/// node `(a, b, c) ∈ {0, 1}³` (at `ξ = (a, b, c)`) is entry `a + 2b + 4c`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FeModel<T> {
    /// The element kind (every element has it).
    pub kind: ElementKind,
    /// World coordinates and their `ξ`-derivatives (eq. 2).
    pub coordinates: Vec<[T; 3]>,
    /// Field values and their `ξ`-derivatives (eq. 1).
    pub field: Vec<T>,
    /// Per element, its 8 corner nodes (`ξ₁` fastest).
    pub elements: Vec<[u32; 8]>,
}

impl FeModel<f64> {
    /// The same model in exact rationals (every finite `f64` converts losslessly).
    pub fn to_exact(&self) -> Result<FeModel<Rational>, FeError> {
        self.validate()?;
        let q = |x: f64| crate::num::rational_from_f64(x, "fe").expect("validated finite");
        Ok(FeModel {
            kind: self.kind,
            coordinates: self.coordinates.iter().map(|p| p.map(q)).collect(),
            field: self.field.iter().map(|&x| q(x)).collect(),
            elements: self.elements.clone(),
        })
    }

    /// Checks layout, node indices and finiteness.
    pub fn validate(&self) -> Result<(), FeError> {
        check_layout(self)?;
        let ndof = self.kind.dofs_per_node();
        for (i, p) in self.coordinates.iter().enumerate() {
            if let Some(a) = p.iter().position(|x| !x.is_finite()) {
                return Err(FeError::NonFinite {
                    what: "coordinate",
                    node: i / ndof,
                    dof: i % ndof,
                    component: Some(a),
                });
            }
        }
        if let Some(i) = self.field.iter().position(|x| !x.is_finite()) {
            return Err(FeError::NonFinite {
                what: "field",
                node: i / ndof,
                dof: i % ndof,
                component: None,
            });
        }
        Ok(())
    }
}

/// Checks the array sizes and node indices of a model.
fn check_layout<T>(m: &FeModel<T>) -> Result<usize, FeError> {
    if m.elements.is_empty() {
        return Err(FeError::NoElements);
    }
    let ndof = m.kind.dofs_per_node();
    if !m.field.len().is_multiple_of(ndof) || m.field.is_empty() {
        return Err(FeError::Layout {
            what: "field",
            why: format!(
                "{} values is not a positive multiple of {ndof} dofs per node",
                m.field.len()
            ),
        });
    }
    if m.coordinates.len() != m.field.len() {
        return Err(FeError::Layout {
            what: "coordinates",
            why: format!(
                "{} coordinate dofs for {} field dofs (one per field dof expected)",
                m.coordinates.len(),
                m.field.len()
            ),
        });
    }
    let nodes = m.field.len() / ndof;
    for (e, el) in m.elements.iter().enumerate() {
        if let Some(l) = el.iter().position(|&n| n as usize >= nodes) {
            return Err(FeError::NodeIndex {
                element: e,
                local: l,
                node: el[l],
                nodes,
            });
        }
    }
    Ok(nodes)
}

/// How vertex normals are computed (Section 3, step 7).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum NormalSource {
    /// The gradient of the interpolated field at the vertex, mapped to world with `J⁻¹`.
    Interpolant,
    /// Central differences of the sampled values at the lattice points, interpolated
    /// linearly along the cut edge, mapped to world with `J⁻¹`.
    FiniteDifference,
}

crate::choice::named_enum!(NormalSource {
    Interpolant => "interpolant",
    FiniteDifference => "finite-difference",
});

/// The surface drawn in each cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CellRule {
    /// The 656-entry table: one disc per polygon.
    Table,
    /// The trilinear interpolant's topology (trilinear Lagrange elements only: inside a cell
    /// their field is exactly the trilinear interpolant of the cell's corner values). Cells
    /// where it has a tube get the tube of
    /// [`cell_mesh`](crate::mc::trilinear::polygonise::cell_mesh); every other cell is drawn
    /// as by the table.
    Trilinear,
}

crate::choice::named_enum!(CellRule {
    Table => "table",
    Trilinear => "trilinear",
});

/// Options of a polygonisation.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct FeOptions {
    /// Cells per element along `ξ₁, ξ₂, ξ₃` (each at least 1).
    pub cells: [usize; 3],
    /// How vertex normals are computed.
    pub normals: NormalSource,
    /// Refuse models with more cells than this (elements × cells per element).
    pub max_cells: u64,
    /// The arithmetic ([`Path::Filtered`] by default; see [`polygonise`]).
    pub path: Path,
    /// Contiguous element ranges the fast path polygonises independently (in parallel with
    /// the `parallel` feature) and then welds; `0` (the default) picks two per thread. The
    /// mesh is the same for every value.
    pub parts: usize,
    /// The surface drawn in each cell ([`CellRule::Table`] by default).
    pub topology: CellRule,
}

crate::choice::setters!(FeOptions {
    with_cells => cells: [usize; 3],
    with_normals => normals: NormalSource,
    with_max_cells => max_cells: u64,
    with_path => path: Path,
    with_parts => parts: usize,
    with_topology => topology: CellRule,
});

impl FeOptions {
    /// The number of element ranges [`FeOptions::parts`] asks for, `0` resolved.
    pub fn parts(&self) -> usize {
        match self.parts {
            0 => 2 * crate::par::threads(),
            p => p,
        }
    }
}

impl Default for FeOptions {
    fn default() -> Self {
        FeOptions {
            cells: [8, 8, 8],
            normals: NormalSource::Interpolant,
            max_cells: 1 << 30,
            path: Path::Filtered,
            parts: 0,
            topology: CellRule::Table,
        }
    }
}

/// Polygonises `m` at `iso` on the path `opts.path` names: [`exact::polygonise_exact`] on the
/// model taken exactly (vertices rounded to the nearest `f64` in the returned mesh), or
/// [`fast::polygonise_fast`] (certified `f64`, exact fallback) for [`Path::Fast`] and
/// [`Path::Filtered`], which needs `iso` to be an `f64` ([`FeError::IsovalueNotF64`]).
pub fn polygonise(
    m: &FeModel<f64>,
    iso: &Rational,
    opts: &FeOptions,
) -> Result<fast::FeSurface, FeError> {
    match opts.path {
        Path::Fast | Path::Filtered => {
            let f = crate::num::rational_to_f64(iso);
            match crate::num::rational_from_f64(f, "iso") {
                Ok(back) if &back == iso => fast::polygonise_fast(m, f, opts),
                _ => Err(FeError::IsovalueNotF64(crate::num::rational_to_string(iso))),
            }
        }
        Path::Exact => {
            let s = exact::polygonise_exact(&m.to_exact()?, iso, opts)?;
            Ok(fast::FeSurface {
                mesh: s.to_mesh(),
                stats: s.stats,
            })
        }
    }
}

/// Bad model or options.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FeError {
    #[error("the model has no elements")]
    /// The model has no elements.
    NoElements,
    #[error("{what}: {why}")]
    /// A model array has the wrong shape.
    Layout {
        /// Which array.
        what: &'static str,
        /// What is wrong.
        why: String,
    },
    #[error(
        "element {element}: local node {local} is node {node}, but the model has {nodes} nodes"
    )]
    /// An element names a node that does not exist.
    NodeIndex {
        /// The element.
        element: usize,
        /// Its local node (0–7).
        local: usize,
        /// The node named.
        node: u32,
        /// Nodes in the model.
        nodes: usize,
    },
    #[error("{what} of node {node}, dof {dof}{}: not finite", component.map(|c| format!(", component {c}")).unwrap_or_default())]
    /// A coordinate, derivative or field value is NaN or infinite.
    NonFinite {
        /// Coordinates or field.
        what: &'static str,
        /// The node.
        node: usize,
        /// The degree of freedom.
        dof: usize,
        /// The coordinate's component, for coordinates.
        component: Option<usize>,
    },
    #[error("the isovalue is not finite")]
    /// The isovalue is NaN or infinite.
    Isovalue,
    #[error("the isovalue {0} is not an f64: the fast path takes f64 isovalues (use the exact path for rational ones)")]
    /// The fast path was given an isovalue that is not an `f64`.
    IsovalueNotF64(String),
    #[error("the trilinear topology needs trilinear Lagrange elements; {0} elements are not trilinear inside a cell (use the table topology)")]
    /// [`CellRule::Trilinear`] was asked for elements that are not trilinear Lagrange.
    TopologyNeedsTrilinear(String),
    #[error("element {element}, cell {cell:?}: {why}")]
    /// A cell's trilinear topology has no construction (never met in a trilinear cell).
    Construction {
        /// The element.
        element: usize,
        /// The cell in the element's lattice.
        cell: [usize; 3],
        /// What.
        why: crate::mc::trilinear::polygonise::TooManyCycles,
    },
    #[error("cells per element must be at least 1 in every direction, found {0:?}")]
    /// A cell count per element is 0.
    Cells([usize; 3]),
    #[error("{cells} cells exceed the limit of {limit}")]
    /// The model has more cells than the limit.
    TooManyCells {
        /// Cells asked for.
        cells: u64,
        /// [`FeOptions::max_cells`].
        limit: u64,
    },
    #[error("element {element} and element {other} share {entity} but subdivide it into different cell counts ({mine:?} against {theirs:?}); give the same count in every direction or orient the elements alike")]
    /// Two elements subdivide a shared face or edge differently.
    NonConforming {
        /// One element.
        element: usize,
        /// The other.
        other: usize,
        /// The shared face or edge.
        entity: String,
        /// The first element's cell counts along it.
        mine: Vec<usize>,
        /// The other's.
        theirs: Vec<usize>,
    },
}

/// Counts of a polygonisation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct FeStats {
    /// Elements polygonised.
    pub elements: usize,
    /// Cells examined.
    pub cells: usize,
    /// Cells with corners of both signs.
    pub cut_cells: usize,
    /// Cells with at least one ambiguous face.
    pub ambiguous_cells: usize,
    /// Ambiguous faces decided (a face shared by two cells counts twice).
    pub ambiguous_faces: usize,
    /// Lattice values whose sign the `f64` bound could not certify, recomputed exactly.
    pub exact_values: usize,
    /// Face decisions the `f64` bound could not certify, recomputed exactly.
    pub exact_faces: usize,
    /// Vertices merged into another at the same world point (Figure 7).
    pub welded_vertices: usize,
    /// Triangles removed because two of their vertices coincide in world space.
    pub degenerate_triangles: usize,
    /// Elements whose Jacobian determinant is negative at the centre: their triangles are
    /// flipped so that every normal points into the positive region.
    pub flipped_elements: usize,
    /// Cells drawn with a tube ([`CellRule::Trilinear`]: the interpolant has a tunnel there).
    pub tunnel_cells: usize,
}

impl FeStats {
    /// Adds the counts of `other` (a polygonisation of other elements) to these, except
    /// [`FeStats::elements`] and the welding counts, which belong to the whole model.
    pub(crate) fn add(&mut self, other: &FeStats) {
        self.cells += other.cells;
        self.cut_cells += other.cut_cells;
        self.ambiguous_cells += other.ambiguous_cells;
        self.ambiguous_faces += other.ambiguous_faces;
        self.exact_values += other.exact_values;
        self.exact_faces += other.exact_faces;
        self.flipped_elements += other.flipped_elements;
        self.tunnel_cells += other.tunnel_cells;
    }
}

impl<T> FeModel<T> {
    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.field.len() / self.kind.dofs_per_node().max(1)
    }
}

/// Checks the options and the conformity of shared element entities; returns the lattice
/// keys' context.
pub(crate) fn prepare<T>(m: &FeModel<T>, opts: &FeOptions) -> Result<(), FeError> {
    check_layout(m)?;
    if opts.topology == CellRule::Trilinear && m.kind != ElementKind::TRILINEAR_LAGRANGE {
        return Err(FeError::TopologyNeedsTrilinear(m.kind.name()));
    }
    if opts.cells.contains(&0) {
        return Err(FeError::Cells(opts.cells));
    }
    let per: u64 = opts.cells.iter().map(|&n| n as u64).product();
    let cells = per.saturating_mul(m.elements.len() as u64);
    if cells > opts.max_cells {
        return Err(FeError::TooManyCells {
            cells,
            limit: opts.max_cells,
        });
    }
    lattice::check_conforming(&m.elements, opts.cells)
}

/// The triangles of a polygonisation after welding: `rep[v]` is the smallest vertex id at
/// the same world point as `v`. Drops triangles that repeat a representative (Figure 7),
/// keeps the representatives some triangle uses in increasing id order, and renumbers the
/// triangles in place. Returns the kept old ids (all of them, in order, when nothing
/// merged and every vertex is used); counts the merged vertices and the dropped triangles
/// in `stats`.
pub(crate) fn weld(rep: &[u32], triangles: &mut Vec<[u32; 3]>, stats: &mut FeStats) -> Vec<u32> {
    stats.welded_vertices = rep
        .iter()
        .enumerate()
        .filter(|(i, r)| **r != *i as u32)
        .count();
    let before = triangles.len();
    let mut used = vec![false; rep.len()];
    triangles.retain_mut(|t| {
        let r = t.map(|v| rep[v as usize]);
        if r[0] == r[1] || r[1] == r[2] || r[0] == r[2] {
            return false;
        }
        for v in r {
            used[v as usize] = true;
        }
        *t = r;
        true
    });
    stats.degenerate_triangles = before - triangles.len();
    let mut new_id = vec![u32::MAX; rep.len()];
    let mut kept = Vec::with_capacity(rep.len());
    for (v, u) in used.iter().enumerate() {
        if *u {
            new_id[v] = kept.len() as u32;
            kept.push(v as u32);
        }
    }
    if kept.len() < rep.len() {
        for t in triangles.iter_mut() {
            *t = t.map(|v| new_id[v as usize]);
        }
    }
    kept
}

/// Step 3 of Section 3.3: the cell's 8-bit configuration from its corner signs, or `None`
/// for a cell the surface does not cross; counts cut and ambiguous cells. Returns the
/// configuration and its ambiguous faces.
pub(crate) fn classify(
    positive: impl Fn(usize) -> bool,
    stats: &mut FeStats,
) -> Option<(u8, &'static [u8])> {
    let config = (0..8).fold(0u8, |acc, c| acc | (u8::from(positive(c)) << c));
    if config == 0 || config == 255 {
        return None;
    }
    stats.cut_cells += 1;
    let amb = &super::table::table().ambiguous[config as usize];
    if !amb.is_empty() {
        stats.ambiguous_cells += 1;
        stats.ambiguous_faces += amb.len();
    }
    Some((config, amb))
}

/// The lattice point of cell `cell` at its table corner `c` (Bourke numbering).
#[inline]
pub(crate) fn cell_corner(cell: [usize; 3], c: usize) -> [usize; 3] {
    let o = super::table::CORNERS[c];
    [
        cell[0] + o[0] as usize,
        cell[1] + o[1] as usize,
        cell[2] + o[2] as usize,
    ]
}

/// Per table edge: the axis it runs along and its lower corner's offset in the cell.
const EDGE_AXIS_LOW: [(usize, [usize; 3]); 12] = {
    let mut out = [(0, [0; 3]); 12];
    let mut e = 0;
    while e < 12 {
        let [a, b] = super::table::EDGES[e];
        let (pa, pb) = (
            super::table::CORNERS[a as usize],
            super::table::CORNERS[b as usize],
        );
        let mut axis = 0;
        let mut low = [0usize; 3];
        let mut x = 0;
        while x < 3 {
            if pa[x] != pb[x] {
                axis = x;
            }
            low[x] = if pa[x] < pb[x] { pa[x] } else { pb[x] } as usize;
            x += 1;
        }
        out[e] = (axis, low);
        e += 1;
    }
    out
};

/// A cell edge `e` as (axis, lower lattice point).
#[inline]
pub(crate) fn cell_edge(cell: [usize; 3], e: u8) -> (usize, [usize; 3]) {
    let (axis, o) = EDGE_AXIS_LOW[e as usize];
    (axis, [cell[0] + o[0], cell[1] + o[1], cell[2] + o[2]])
}

/// The decider's `A, B, C, D` corners of table face `f` (see [`decider`](super::decider)).
pub(crate) fn face_abcd(f: usize) -> [usize; 4] {
    let c = super::table::FACES[f].corners;
    [c[0] as usize, c[1] as usize, c[3] as usize, c[2] as usize]
}

/// A tube cell's triangles with vertex ids from `vertex`: cut edge `x < 12` as often as it
/// appears, interior vertex `12 + k` once, on first use (so both paths number alike); wound
/// backwards when `flip`.
pub(crate) fn tube_triangles(
    mesh: &CellMesh,
    flip: bool,
    mut vertex: impl FnMut(u8) -> u32,
) -> Vec<[u32; 3]> {
    let mut inner = vec![u32::MAX; mesh.interior.len()];
    mesh.triangles
        .iter()
        .map(|tri| {
            let mut t = tri.map(|x| {
                if x < 12 {
                    return vertex(x);
                }
                let k = (x - 12) as usize;
                if inner[k] == u32::MAX {
                    inner[k] = vertex(x);
                }
                inner[k]
            });
            if flip {
                t.swap(1, 2);
            }
            t
        })
        .collect()
}

/// The trilinear cell surface for [`CellRule::Trilinear`]: `Some` when the table entry can
/// hold a tube (two or more polygons) and the interpolant has one there, computed exactly
/// from the cell's corner values (table numbering).
pub(crate) fn tube_mesh(
    config: u8,
    sub: u8,
    corners: &[Rational; 8],
    iso: &Rational,
) -> Option<Result<CellMesh, TooManyCycles>> {
    use crate::mc::trilinear::polygonise::{cell_mesh, tunnel_possible};
    if !tunnel_possible(config, sub) {
        return None;
    }
    let topo = crate::mc::trilinear::cell_topology_exact(corners, iso);
    debug_assert_eq!(
        (topo.config, topo.sub),
        (config, sub),
        "Mackerras = asymptotic decider"
    );
    (topo.tunnels() > 0).then(|| cell_mesh(&topo, || corners.clone().map(|v| v - iso)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cell_edges_join_their_table_corners() {
        let cell = [3, 5, 7];
        for (e, [a, b]) in crate::mc::table::EDGES.iter().enumerate() {
            let (axis, lo) = cell_edge(cell, e as u8);
            let (pa, pb) = (
                cell_corner(cell, *a as usize),
                cell_corner(cell, *b as usize),
            );
            let mut hi = lo;
            hi[axis] += 1;
            assert!((pa, pb) == (lo, hi) || (pa, pb) == (hi, lo), "edge {e}");
        }
    }
}
