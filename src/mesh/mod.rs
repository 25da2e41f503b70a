//! Indexed triangle meshes shared by the families: vertices in `f64` (exact as dyadic
//! rationals when the exact paths need them), triangles as vertex-index triples, an optional
//! nodal scalar field; readers and writers for PLY (ascii and binary), OBJ, STL and legacy VTK;
//! topology checks.
//!
//! Every reader validates what it returns: finite coordinates, indices in range, no triangle
//! repeating a vertex. Errors name the file's element (line, face or vertex number) at fault.

pub mod obj;
pub mod ply;
pub mod shapes;
pub mod stl;
pub mod vtk;

use std::path::Path;
use thiserror::Error;

/// A nodal scalar field: one value per vertex.
#[derive(Clone, Debug, PartialEq)]
pub struct Scalars {
    pub name: String,
    pub values: Vec<f64>,
}

/// An indexed triangle mesh.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Mesh {
    pub vertices: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
    pub scalars: Option<Scalars>,
    /// Optional unit vertex normals (written as PLY `nx ny nz`, OBJ `vn`, VTK `NORMALS`).
    pub normals: Option<Vec<[f64; 3]>>,
}

/// What went wrong reading, writing or checking a mesh, and where.
#[derive(Debug, Error, PartialEq)]
pub enum MeshError {
    #[error("{path}: {why}")]
    Io { path: String, why: String },
    #[error("{format} {place}: {why}")]
    Parse {
        format: &'static str,
        place: String,
        why: String,
    },
    #[error("vertex {vertex}: coordinate {value} is not finite")]
    NonFinite { vertex: usize, value: f64 },
    #[error("triangle {triangle}: {why}")]
    BadTriangle { triangle: usize, why: String },
    #[error("edge ({a}, {b}): {why}")]
    NonManifold { a: u32, b: u32, why: String },
    #[error("{0}")]
    Unsupported(String),
}

/// File formats geocert reads and writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    PlyAscii,
    PlyBinary,
    Obj,
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

/// `a × b`.
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Twice the area vector of triangle `abc`: `(b − a) × (c − a)` (right-hand rule).
pub fn area_vector(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    let d = |u: [f64; 3], v: [f64; 3]| [u[0] - v[0], u[1] - v[1], u[2] - v[2]];
    cross(d(b, a), d(c, a))
}

impl Mesh {
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
        self.validate()?;
        let n = self.vertices.len();
        let tris = &self.triangles;
        // Half-edge `h` runs from corner `h % 3` of triangle `h / 3` to the next corner; the
        // half-edges leaving each vertex are listed together (counting sort by source).
        let source = |h: usize| tris[h / 3][h % 3];
        let target = |h: usize| tris[h / 3][(h % 3 + 1) % 3];
        let mut first = vec![0usize; n + 1];
        for tri in tris {
            for &a in tri {
                first[a as usize + 1] += 1;
            }
        }
        for v in 0..n {
            first[v + 1] += first[v];
        }
        let mut fill = first.clone();
        let mut leaving = vec![0usize; 3 * tris.len()];
        for h in 0..3 * tris.len() {
            let a = source(h) as usize;
            leaving[fill[a]] = h;
            fill[a] += 1;
        }
        let out = |a: u32| &leaving[first[a as usize]..first[a as usize + 1]];
        // The half-edge a→b, if any (the lowest when repeated).
        let find = |a: u32, b: u32| out(a).iter().copied().find(|&g| target(g) == b);
        let mut boundary_start: Vec<Option<u32>> = vec![None; n];
        let mut boundary = 0usize;
        for h in 0..3 * tris.len() {
            let (a, b) = (source(h), target(h));
            let g = find(a, b).expect("h itself");
            if g != h {
                return Err(MeshError::NonManifold {
                    a,
                    b,
                    why: format!(
                        "traversed in the same direction by triangles {} and {} (inconsistent orientation or more than two triangles)",
                        g / 3,
                        h / 3
                    ),
                });
            }
            if find(b, a).is_none() {
                boundary += 1;
                if boundary_start[a as usize].replace(b).is_some() {
                    return Err(MeshError::NonManifold {
                        a,
                        b,
                        why: format!("vertex {a} has two boundary fans (a bow-tie vertex)"),
                    });
                }
            }
        }
        // Each vertex's fan: start at its outgoing boundary edge (an edge with no twin), or at
        // any outgoing edge for an interior vertex, and rotate through the triangles
        // (`(v, b, c)` leads from edge `v→b` to edge `v→c`); a single fan visits them all.
        let third = |a: u32, b: u32| {
            find(a, b).map(|h| {
                let tri = tris[h / 3];
                tri[0] ^ tri[1] ^ tri[2] ^ a ^ b
            })
        };
        for v in 0..n as u32 {
            let degree = out(v).len();
            let Some(start) = boundary_start[v as usize].or(out(v).first().map(|&h| target(h)))
            else {
                continue;
            };
            let mut b = start;
            let mut visited = 0usize;
            while let Some(c) = third(v, b) {
                visited += 1;
                if c == start || visited > degree {
                    break;
                }
                b = c;
            }
            if visited != degree {
                return Err(MeshError::NonManifold {
                    a: v,
                    b: start,
                    why: format!(
                        "the {degree} triangles at vertex {v} form more than one fan (a pinched vertex)"
                    ),
                });
            }
        }
        Ok(boundary)
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
