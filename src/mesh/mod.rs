//! Indexed triangle meshes shared by the families: vertices in `f64` (exact as dyadic
//! rationals when the exact paths need them), triangles as vertex-index triples, an optional
//! nodal scalar field; readers and writers for PLY (ascii and binary), OBJ, STL and legacy VTK;
//! topology checks.
//!
//! Every reader validates what it returns: finite coordinates, indices in range, no triangle
//! repeating a vertex. Errors name the file's element (line, face or vertex number) at fault.

pub(crate) mod fans;
pub mod obj;
pub mod ply;
pub(crate) mod polygon;
pub(crate) mod shapes;
pub mod split;

pub use shapes::squashed_hemisphere;
pub mod stl;
pub mod vtk;

use glam::DVec3;
use std::path::Path;
use thiserror::Error;

/// A nodal scalar field: one value per vertex.
#[derive(Clone, Debug, PartialEq)]
pub struct Scalars {
    /// The field's name (a PLY property or VTK array).
    pub name: String,
    /// One value per vertex.
    pub values: Vec<f64>,
}

/// An indexed triangle mesh.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Mesh {
    /// Vertex positions.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles, counter-clockwise about their outward normal.
    pub triangles: Vec<[u32; 3]>,
    /// The nodal scalar field, if any.
    pub scalars: Option<Scalars>,
    /// Optional unit vertex normals (written as PLY `nx ny nz`, OBJ `vn`, VTK `NORMALS`).
    pub normals: Option<Vec<[f64; 3]>>,
}

/// What went wrong reading, writing or checking a mesh, and where.
#[derive(Debug, Error, PartialEq)]
pub enum MeshError {
    #[error("{path}: {why}")]
    /// A file could not be read or written.
    Io {
        /// The file.
        path: String,
        /// The system's reason.
        why: String,
    },
    #[error("{format} {place}: {why}")]
    /// A file is malformed.
    Parse {
        /// `PLY`, `OBJ`, `STL` or `VTK`.
        format: &'static str,
        /// Where (line, element or byte).
        place: String,
        /// What is wrong.
        why: String,
    },
    #[error("vertex {vertex}: coordinate {value} is not finite")]
    /// A vertex coordinate is NaN or infinite.
    NonFinite {
        /// The vertex.
        vertex: usize,
        /// The coordinate.
        value: f64,
    },
    #[error("triangle {triangle}: {why}")]
    /// A triangle is invalid (an index out of range, a repeated vertex).
    BadTriangle {
        /// The triangle.
        triangle: usize,
        /// What is wrong.
        why: String,
    },
    #[error("edge ({a}, {b}): {why}")]
    /// An edge is not manifold (more than two triangles, or two with the same direction).
    NonManifold {
        /// One end.
        a: u32,
        /// The other end.
        b: u32,
        /// What is wrong.
        why: String,
    },
    #[error("edge ({a}, {b}): {why}")]
    /// More than one fan of triangles meets at vertex `a` (a bow-tie or a pinched vertex;
    /// [`split::split_pinched`] gives each fan its own vertex).
    PinchedVertex {
        /// The vertex.
        a: u32,
        /// The other end of an edge at it.
        b: u32,
        /// What is wrong.
        why: String,
    },
    #[error("{0}")]
    /// A format or option this reader does not take.
    Unsupported(String),
}

/// File formats geocert reads and writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// PLY, ASCII.
    PlyAscii,
    /// PLY, binary little-endian.
    PlyBinary,
    /// Wavefront OBJ.
    Obj,
    /// STL (binary).
    Stl,
    /// Legacy VTK ASCII polydata.
    Vtk,
}

impl Format {
    /// From a file extension (`.ply` writes binary).
    pub fn from_path(path: &Path) -> Result<Format, MeshError> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .as_deref()
        {
            Some("ply") => Ok(Format::PlyBinary),
            Some("obj") => Ok(Format::Obj),
            Some("stl") => Ok(Format::Stl),
            Some("vtk") => Ok(Format::Vtk),
            _ => Err(MeshError::Unsupported(format!(
                "{}: unknown mesh format (expected .ply, .obj, .stl or .vtk)",
                path.display()
            ))),
        }
    }
}

/// `a × b` (each component one rounding of a difference of two rounded products).
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    DVec3::from(a).cross(DVec3::from(b)).to_array()
}

/// Twice the area vector of triangle `abc`: `(b − a) × (c − a)` (right-hand rule).
pub fn area_vector(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    let a = DVec3::from(a);
    (DVec3::from(b) - a).cross(DVec3::from(c) - a).to_array()
}

/// Per vertex of `n`, its incident triangles in increasing order, by counting sort: offsets
/// (`n + 1`, vertex `v`'s run is `ids[offsets[v]..offsets[v + 1]]`) and triangle ids. The
/// indices must be in range.
pub(crate) fn incident_triangles(n: usize, triangles: &[[u32; 3]]) -> (Vec<u32>, Vec<u32>) {
    let mut first = vec![0u32; n + 1];
    for t in triangles {
        for &i in t {
            first[i as usize + 1] += 1;
        }
    }
    for v in 0..n {
        first[v + 1] += first[v];
    }
    let mut fill = first.clone();
    let mut ids = vec![0u32; first[n] as usize];
    for (k, t) in triangles.iter().enumerate() {
        for &i in t {
            ids[fill[i as usize] as usize] = k as u32;
            fill[i as usize] += 1;
        }
    }
    (first, ids)
}

impl Mesh {
    /// Per vertex, whether some triangle uses it (the surface's vertices; the others are
    /// loose points that no surface measure or decimation target counts). Indices out of
    /// range are skipped.
    pub fn used_vertices(&self) -> Vec<bool> {
        let mut used = vec![false; self.vertices.len()];
        for &i in self.triangles.iter().flatten() {
            if let Some(u) = used.get_mut(i as usize) {
                *u = true;
            }
        }
        used
    }

    /// Per vertex, whether it lies on a border edge: one that no triangle traverses back.
    /// Indices must be in range.
    pub fn border_vertices(&self) -> Vec<bool> {
        let mut on_border = vec![false; self.vertices.len()];
        for [a, b] in self.border_edges() {
            on_border[a as usize] = true;
            on_border[b as usize] = true;
        }
        on_border
    }

    /// The border edges `[a, b]` as a triangle traverses them (no triangle traverses
    /// `b → a`), in triangle order.
    pub fn border_edges(&self) -> Vec<[u32; 2]> {
        let edges = |&t: &[u32; 3]| (0..3).map(move |e| [t[e], t[(e + 1) % 3]]);
        let mut directed: Vec<[u32; 2]> = self.triangles.iter().flat_map(edges).collect();
        directed.sort_unstable();
        self.triangles
            .iter()
            .flat_map(edges)
            .filter(|&[a, b]| directed.binary_search(&[b, a]).is_err())
            .collect()
    }

    /// Checks coordinates, scalar count and triangle indices.
    pub fn validate(&self) -> Result<(), MeshError> {
        for (i, v) in self.vertices.iter().enumerate() {
            if let Some(x) = v.iter().find(|x| !x.is_finite()) {
                return Err(MeshError::NonFinite {
                    vertex: i,
                    value: *x,
                });
            }
        }
        if let Some(s) = &self.scalars {
            if s.values.len() != self.vertices.len() {
                return Err(MeshError::Unsupported(format!(
                    "scalar field {} has {} values for {} vertices",
                    s.name,
                    s.values.len(),
                    self.vertices.len()
                )));
            }
            if let Some(i) = s.values.iter().position(|x| !x.is_finite()) {
                return Err(MeshError::NonFinite {
                    vertex: i,
                    value: s.values[i],
                });
            }
        }
        if let Some(nv) = &self.normals {
            if nv.len() != self.vertices.len() {
                return Err(MeshError::Unsupported(format!(
                    "{} normals for {} vertices",
                    nv.len(),
                    self.vertices.len()
                )));
            }
            if let Some(i) = nv.iter().position(|v| v.iter().any(|x| !x.is_finite())) {
                return Err(MeshError::NonFinite {
                    vertex: i,
                    value: nv[i]
                        .iter()
                        .copied()
                        .find(|x| !x.is_finite())
                        .unwrap_or(f64::NAN),
                });
            }
        }
        let n = self.vertices.len();
        for (t, tri) in self.triangles.iter().enumerate() {
            if let Some(i) = tri.iter().find(|&&i| i as usize >= n) {
                return Err(MeshError::BadTriangle {
                    triangle: t,
                    why: format!("vertex index {i} out of range (mesh has {n} vertices)"),
                });
            }
            if tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] {
                return Err(MeshError::BadTriangle {
                    triangle: t,
                    why: format!("repeats a vertex: {tri:?}"),
                });
            }
        }
        Ok(())
    }

    /// Checks that the triangles form an oriented 2-manifold with boundary: every edge in at
    /// most two triangles, traversed in opposite directions when shared, and every vertex's
    /// fan a single disc or half-disc. Returns the number of boundary edges.
    pub fn check_manifold(&self) -> Result<usize, MeshError> {
        Ok(fans::Fans::of(self)?.border_edges())
    }

    /// Euler characteristic `V − E + F` over the vertices the triangles use.
    pub fn euler_characteristic(&self) -> i64 {
        let mut used = vec![false; self.vertices.len()];
        let mut edges = std::collections::HashSet::new();
        for tri in &self.triangles {
            for e in 0..3 {
                used[tri[e] as usize] = true;
                let (a, b) = (tri[e], tri[(e + 1) % 3]);
                edges.insert((a.min(b), a.max(b)));
            }
        }
        used.iter().filter(|u| **u).count() as i64 - edges.len() as i64
            + self.triangles.len() as i64
    }

    /// Reads a mesh, the format chosen by the extension (PLY ascii or binary by its header);
    /// `scalar` names a PLY vertex property or a VTK `SCALARS` array to read as the nodal
    /// field.
    pub fn read(path: &Path, scalar: Option<&str>) -> Result<Mesh, MeshError> {
        let bytes = std::fs::read(path).map_err(|e| MeshError::Io {
            path: path.display().to_string(),
            why: e.to_string(),
        })?;
        let mesh = match Format::from_path(path)? {
            Format::PlyAscii | Format::PlyBinary => ply::read(&bytes, scalar)?,
            Format::Obj => obj::read(&bytes)?,
            Format::Stl => stl::read(&bytes)?,
            Format::Vtk => vtk::read(&bytes, scalar)?,
        };
        Ok(mesh)
    }

    /// Writes a mesh in `format`; the file is written whole or not at all (a temporary file
    /// renamed into place).
    pub fn write(&self, path: &Path, format: Format) -> Result<(), MeshError> {
        self.validate()?;
        let bytes = match format {
            Format::PlyAscii => ply::write(self, false),
            Format::PlyBinary => ply::write(self, true),
            Format::Obj => obj::write(self),
            Format::Stl => stl::write(self),
            Format::Vtk => vtk::write(self),
        };
        let io = |e: std::io::Error| MeshError::Io {
            path: path.display().to_string(),
            why: e.to_string(),
        };
        let tmp = path.with_extension("geocert-partial");
        std::fs::write(&tmp, bytes).map_err(io)?;
        std::fs::rename(&tmp, path).map_err(io)
    }
}
