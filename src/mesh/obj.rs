//! Wavefront OBJ: `v x y z [w]` and `f` records (`i`, `i/t`, `i/t/n`, `i//n`, negative
//! indices counted from the end; faces of more than three vertices are triangulated,
//! module `polygon`); other records (`vt`, `vn`, `o`, `g`, `usemtl`, …) are ignored.

use super::{Mesh, MeshError};

fn err(line: usize, why: impl Into<String>) -> MeshError {
    MeshError::Parse {
        format: "OBJ",
        place: format!("line {line}"),
        why: why.into(),
    }
}

/// Reads an OBJ mesh.
pub fn read(bytes: &[u8]) -> Result<Mesh, MeshError> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let line = bytes[..e.valid_up_to()]
            .iter()
            .filter(|b| **b == b'\n')
            .count()
            + 1;
        err(line, "not UTF-8 text")
    })?;
    let mut mesh = Mesh::default();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let mut words = raw.split_whitespace();
        match words.next() {
            Some("v") => {
                let mut v = [0.0f64; 3];
                for (a, slot) in v.iter_mut().enumerate() {
                    let w = words.next().ok_or_else(|| {
                        err(line, format!("vertex needs 3 coordinates, found {a}"))
                    })?;
                    *slot = w
                        .parse()
                        .map_err(|_| err(line, format!("not a number: {w:?}")))?;
                }
                mesh.vertices.push(v);
            }
            Some("f") => {
                let n = mesh.vertices.len() as i64;
                let mut face = Vec::with_capacity(4);
                for r in words {
                    let head = r.split('/').next().unwrap_or("");
                    let k: i64 = head
                        .parse()
                        .map_err(|_| err(line, format!("bad vertex reference {r:?}")))?;
                    let idx = if k > 0 { k - 1 } else { n + k };
                    if k == 0 || idx < 0 || idx >= n {
                        return Err(err(
                            line,
                            format!("vertex reference {k} out of range ({n} vertices so far)"),
                        ));
                    }
                    face.push(idx as u32);
                }
                super::polygon::triangulate(&mesh.vertices, &face, &mut mesh.triangles)
                    .map_err(|why| err(line, why))?;
            }
            _ => {}
        }
    }
    mesh.validate()?;
    Ok(mesh)
}

/// Writes `v` (and `vn`, one per vertex, when the mesh has normals) and `f` records (shortest round-trip decimals, 1-based indices).
pub fn write(mesh: &Mesh) -> Vec<u8> {
    use std::fmt::Write;
    let mut s = String::from("# written by geocert\n");
    for v in &mesh.vertices {
        let _ = writeln!(s, "v {:?} {:?} {:?}", v[0], v[1], v[2]);
    }
    if let Some(normals) = &mesh.normals {
        for v in normals {
            let _ = writeln!(s, "vn {:?} {:?} {:?}", v[0], v[1], v[2]);
        }
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| i + 1);
            let _ = writeln!(s, "f {a}//{a} {b}//{b} {c}//{c}");
        }
    } else {
        for t in &mesh.triangles {
            let _ = writeln!(s, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
        }
    }
    s.into_bytes()
}
