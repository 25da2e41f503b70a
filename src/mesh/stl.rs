//! STL, binary (80-byte header, count, 50 bytes per facet) or ascii (`solid … facet … vertex`).
//! STL stores each facet's corners by value; vertices with identical coordinates (bit for
//! bit) are merged, so the result is an indexed mesh.

use super::{Mesh, MeshError};
use std::collections::HashMap;

fn err(place: impl Into<String>, why: impl Into<String>) -> MeshError {
    MeshError::Parse {
        format: "STL",
        place: place.into(),
        why: why.into(),
    }
}

struct Welder {
    mesh: Mesh,
    index: HashMap<[u64; 3], u32>,
    /// Skip (and count) facets with two equal corners instead of refusing them.
    drop_slivers: bool,
    dropped: usize,
}

/// The welding key of a point: its coordinates' bits, with -0.0 and 0.0 the same.
fn key(v: [f64; 3]) -> [u64; 3] {
    v.map(|x| if x == 0.0 { 0 } else { x.to_bits() })
}

impl Welder {
    /// The vertex at `v` (welding key `key`), added when new.
    fn vertex(&mut self, v: [f64; 3], key: [u64; 3]) -> u32 {
        let n = self.mesh.vertices.len() as u32;
        *self.index.entry(key).or_insert_with(|| {
            self.mesh.vertices.push(v);
            n
        })
    }
    fn facet(&mut self, corners: [[f64; 3]; 3], place: String) -> Result<(), MeshError> {
        if let Some(x) = corners.iter().flatten().find(|x| !x.is_finite()) {
            return Err(err(place, format!("coordinate {x} is not finite")));
        }
        let k = corners.map(key);
        if k[0] == k[1] || k[1] == k[2] || k[0] == k[2] {
            if self.drop_slivers {
                self.dropped += 1;
                return Ok(());
            }
            return Err(err(place, "a facet with two equal corners"));
        }
        let tri = [0, 1, 2].map(|c| self.vertex(corners[c], k[c]));
        self.mesh.triangles.push(tri);
        Ok(())
    }
}

/// Reads an STL mesh (binary when the size matches the facet count, else ascii). A facet
/// with two equal corners is an error naming it.
pub fn read(bytes: &[u8]) -> Result<Mesh, MeshError> {
    read_with(bytes, false).map(|(mesh, _)| mesh)
}

/// [`read`], but facets with two equal corners (slivers without area, as CAD tessellations
/// rounded to `f32` carry) are skipped and counted rather than refused; none of their
/// corners becomes a vertex unless another facet uses it.
pub fn read_dropping_slivers(bytes: &[u8]) -> Result<(Mesh, usize), MeshError> {
    read_with(bytes, true)
}

fn read_with(bytes: &[u8], drop_slivers: bool) -> Result<(Mesh, usize), MeshError> {
    let mut w = Welder {
        mesh: Mesh::default(),
        index: HashMap::new(),
        drop_slivers,
        dropped: 0,
    };
    let binary_len = bytes
        .get(80..84)
        .map(|c| 84 + 50 * u32::from_le_bytes([c[0], c[1], c[2], c[3]]) as usize);
    if binary_len == Some(bytes.len()) {
        for (f, rec) in bytes[84..].chunks_exact(50).enumerate() {
            let val = |k: usize| {
                let o = 12 + 4 * k;
                f32::from_le_bytes([rec[o], rec[o + 1], rec[o + 2], rec[o + 3]]) as f64
            };
            let corners = [0, 1, 2].map(|c| [val(3 * c), val(3 * c + 1), val(3 * c + 2)]);
            w.facet(corners, format!("facet {f}"))?;
        }
    } else {
        let text = std::str::from_utf8(bytes)
            .map_err(|_| err("file", "neither binary STL (size mismatch) nor ascii text"))?;
        if !text.trim_start().starts_with("solid") {
            return Err(err("line 1", "ascii STL must start with \"solid\""));
        }
        let mut corners: Vec<[f64; 3]> = Vec::with_capacity(3);
        let mut facet = 0usize;
        for (i, raw) in text.lines().enumerate() {
            let mut words = raw.split_whitespace();
            match words.next() {
                Some("vertex") => {
                    let mut v = [0.0f64; 3];
                    for slot in v.iter_mut() {
                        let tok = words.next().unwrap_or("");
                        *slot = tok.parse().map_err(|_| {
                            err(format!("line {}", i + 1), format!("not a number: {tok:?}"))
                        })?;
                    }
                    if corners.len() == 3 {
                        return Err(err(
                            format!("line {}", i + 1),
                            "a facet with more than 3 vertices",
                        ));
                    }
                    corners.push(v);
                }
                Some("endloop") => {
                    if corners.len() != 3 {
                        return Err(err(
                            format!("line {}", i + 1),
                            format!("a facet with {} vertices", corners.len()),
                        ));
                    }
                    w.facet(
                        [corners[0], corners[1], corners[2]],
                        format!("facet {facet}"),
                    )?;
                    corners.clear();
                    facet += 1;
                }
                _ => {}
            }
        }
    }
    w.mesh.validate()?;
    Ok((w.mesh, w.dropped))
}

/// Writes binary STL (coordinates rounded to `f32`, as the format requires; normals from the
/// rounded corners).
pub fn write(mesh: &Mesh) -> Vec<u8> {
    let mut out = vec![0u8; 80];
    out[..18].copy_from_slice(b"written by geocert");
    out.extend_from_slice(&(mesh.triangles.len() as u32).to_le_bytes());
    for t in &mesh.triangles {
        let p = t.map(|i| mesh.vertices[i as usize].map(|x| x as f32));
        let e1 = [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]];
        let e2 = [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]];
        let n = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        let n = if len > 0.0 {
            n.map(|x| x / len)
        } else {
            [0.0; 3]
        };
        for x in n.iter().chain(p.iter().flatten()) {
            out.extend_from_slice(&x.to_le_bytes());
        }
        out.extend_from_slice(&[0, 0]);
    }
    out
}
