//! Built-in meshes.

use super::Mesh;
use std::collections::HashMap;

/// The upper half of an octahedron with each face cut into `n²` triangles, pushed onto the unit
/// sphere and squashed to height `squash`: an open dome with `2n² + 2n + 1` vertices and `4n²`
/// triangles, outward oriented (n = 8, 16, 32 give the 145, 545 and 2113 vertices of the FFD
/// paper's Fig. 6 meshes).
pub fn squashed_hemisphere(n: u32, squash: f64) -> Mesh {
    let n = n.max(1) as i64;
    let mut index: HashMap<(i64, i64), u32> = HashMap::new();
    let mut mesh = Mesh::default();
    let mut vertex = |i: i64, j: i64, mesh: &mut Mesh| -> u32 {
        *index.entry((i, j)).or_insert_with(|| {
            let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
            let z = 1.0 - x.abs() - y.abs();
            let r = (x * x + y * y + z * z).sqrt();
            mesh.vertices.push([x / r, y / r, squash * z / r]);
            (mesh.vertices.len() - 1) as u32
        })
    };
    for (sx, sy) in [(1, 1), (-1, 1), (-1, -1), (1, -1)] {
        let mut tri = |a: (i64, i64), b: (i64, i64), c: (i64, i64), mesh: &mut Mesh| {
            let mut t = [a, b, c].map(|(i, j)| vertex(sx * i, sy * j, mesh));
            if sx * sy < 0 {
                t.swap(1, 2);
            }
            mesh.triangles.push(t);
        };
        for i in 0..n {
            for j in 0..n - i {
                // Lower triangle of the cell, then the upper one where the cell is inside.
                tri((i, j), (i + 1, j), (i, j + 1), &mut mesh);
                if i + j + 2 <= n {
                    tri((i + 1, j), (i + 1, j + 1), (i, j + 1), &mut mesh);
                }
            }
        }
    }
    mesh
}
