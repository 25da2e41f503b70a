//! Splitting the vertices at which more than one fan of triangles meets: a *bow-tie* (two
//! border fans touching at a point) or a *pinched* vertex (closed fans sharing a point), the
//! common defect of range maps. Each extra fan gets its own copy of the vertex, at the same
//! place, so that every vertex has one fan and the mesh is a 2-manifold wherever its edges
//! are.

use super::Mesh;

/// A mesh whose pinched vertices were split ([`split_pinched`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Split {
    /// The mesh: the input's vertices, then one copy per extra fan; the triangles in the
    /// input's order, their corners at a pinched vertex renamed to their fan's copy.
    pub mesh: Mesh,
    /// Per copy (vertex `n + i` of [`mesh`](Self::mesh), `n` the input's vertex count), the
    /// input vertex it copies (scalars and normals copied with it).
    pub copied_from: Vec<u32>,
}

/// Splits every vertex at which the triangles form more than one fan. Two triangles at `v`
/// are in one fan when they share an edge at `v` (another common vertex); the fan holding
/// `v`'s first triangle (lowest index) keeps `v`, and the others, in the order of their first
/// triangles, get copies appended after the input's vertices (pinched vertices in increasing
/// order). Edges used by more than two triangles are left as they are (the fan checks
/// report them). The indices must be in range.
pub fn split_pinched(mesh: &Mesh) -> Split {
    let n = mesh.vertices.len();
    let (first, ids) = super::incident_triangles(n, &mesh.triangles);
    let mut triangles = mesh.triangles.clone();
    let mut copied_from = Vec::new();
    // Per corner at the current vertex: its fan (union-find over the corners).
    let mut parent: Vec<usize> = Vec::new();
    let mut fan_copy: Vec<Option<u32>> = Vec::new();
    for v in 0..n {
        let around = &ids[first[v] as usize..first[v + 1] as usize];
        if around.len() < 2 {
            continue;
        }
        let others = |t: u32| {
            let tri = mesh.triangles[t as usize];
            let at = tri.iter().position(|&x| x as usize == v).unwrap_or(0);
            [tri[(at + 1) % 3], tri[(at + 2) % 3]]
        };
        parent.clear();
        parent.extend(0..around.len());
        fn root(parent: &mut [usize], mut x: usize) -> usize {
            while parent[x] != x {
                parent[x] = parent[parent[x]];
                x = parent[x];
            }
            x
        }
        // Corners sharing a neighbour share an edge at `v`: one fan.
        let mut seen: Vec<(u32, usize)> = around
            .iter()
            .enumerate()
            .flat_map(|(i, &t)| others(t).map(|w| (w, i)))
            .collect();
        seen.sort_unstable();
        for pair in seen.windows(2) {
            if pair[0].0 == pair[1].0 {
                let (a, b) = (root(&mut parent, pair[0].1), root(&mut parent, pair[1].1));
                // The lower corner (earlier triangle) stays the root.
                parent[a.max(b)] = a.min(b);
            }
        }
        let fans = (0..around.len())
            .filter(|&i| root(&mut parent, i) == i)
            .count();
        if fans < 2 {
            continue;
        }
        fan_copy.clear();
        fan_copy.resize(around.len(), None);
        for (i, &t) in around.iter().enumerate() {
            let r = root(&mut parent, i);
            if r == 0 {
                continue;
            }
            let copy = *fan_copy[r].get_or_insert_with(|| {
                copied_from.push(v as u32);
                (n + copied_from.len() - 1) as u32
            });
            for x in &mut triangles[t as usize] {
                if *x as usize == v {
                    *x = copy;
                }
            }
        }
    }
    let copy_of = |values: &[[f64; 3]]| -> Vec<[f64; 3]> {
        values
            .iter()
            .copied()
            .chain(copied_from.iter().map(|&v| values[v as usize]))
            .collect()
    };
    let split = Mesh {
        vertices: copy_of(&mesh.vertices),
        triangles,
        scalars: mesh.scalars.as_ref().map(|s| super::Scalars {
            name: s.name.clone(),
            values: s
                .values
                .iter()
                .copied()
                .chain(copied_from.iter().map(|&v| s.values[v as usize]))
                .collect(),
        }),
        normals: mesh.normals.as_deref().map(copy_of),
    };
    Split {
        mesh: split,
        copied_from,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::fans::Fans;

    fn mesh(vertices: usize, triangles: Vec<[u32; 3]>) -> Mesh {
        Mesh {
            vertices: (0..vertices)
                .map(|i| [i as f64, (i * i) as f64, 0.0])
                .collect(),
            triangles,
            scalars: None,
            normals: None,
        }
    }

    #[test]
    fn a_bow_tie_and_a_pinched_vertex_split_into_one_vertex_per_fan() {
        // Two triangles touching at vertex 0: a bow-tie.
        let bow = mesh(5, vec![[0, 1, 2], [0, 3, 4]]);
        assert!(Fans::of(&bow).is_err());
        let s = split_pinched(&bow);
        assert_eq!(s.copied_from, vec![0]);
        assert_eq!(s.mesh.triangles, vec![[0, 1, 2], [5, 3, 4]]);
        assert_eq!(s.mesh.vertices[5], bow.vertices[0]);
        Fans::of(&s.mesh).expect("a 2-manifold after the split");
        // Two closed tetrahedra sharing vertex 0 (pinched), and three fans at vertex 0.
        let tet = |a: u32, b: u32, c: u32| vec![[0, a, b], [0, b, c], [0, c, a], [a, c, b]];
        let mut tris = tet(1, 2, 3);
        tris.extend(tet(4, 5, 6));
        tris.push([0, 7, 8]);
        let pinched = mesh(9, tris);
        assert!(Fans::of(&pinched).is_err());
        let s = split_pinched(&pinched);
        assert_eq!(s.copied_from, vec![0, 0]);
        assert!(s.mesh.triangles[4..7].iter().all(|t| t[0] == 9));
        assert_eq!(s.mesh.triangles[8], [10, 7, 8]);
        Fans::of(&s.mesh).expect("a 2-manifold after the split");
        // A manifold mesh is unchanged.
        let fan = mesh(4, vec![[0, 1, 2], [0, 2, 3]]);
        let s = split_pinched(&fan);
        assert!(s.copied_from.is_empty());
        assert_eq!(s.mesh, fan);
    }
}
