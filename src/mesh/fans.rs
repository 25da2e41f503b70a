//! The fan of every vertex of an oriented 2-manifold triangle mesh, in counter-clockwise
//! order, found vertex by vertex from the triangles' corners (no global edge table).
//!
//! Corner `h` is corner `h % 3` of triangle `h / 3`. At vertex `v` a corner's triangle is
//! `(v, a, b)` — `a` the next corner's vertex, `b` the one after — and the triangle that
//! follows it counter-clockwise is the one at `v` whose `a` is this one's `b`. The checks:
//! no edge `v → a` is used by two triangles (a repeated edge, or inconsistent orientation);
//! at most one triangle at `v` has no predecessor (its edge `v → a` has no twin `a → v`: the
//! border edge; two mean a bow-tie); and following the successors from there (or from any
//! triangle at an interior vertex) visits every triangle at `v` (else the vertex is pinched).

use super::{Mesh, MeshError};
use crate::par::prelude::*;

/// Every vertex's corners in counter-clockwise order, and which vertices are on the border.
#[derive(Clone, Debug)]
pub(crate) struct Fans {
    start: Vec<u32>,
    corners: Vec<u32>,
    border: Vec<bool>,
}

impl Fans {
    /// The fans of `mesh`, or the first topology error met (vertices in increasing order).
    /// Validates the mesh first ([`Mesh::validate`]).
    pub(crate) fn of(mesh: &Mesh) -> Result<Fans, MeshError> {
        mesh.validate()?;
        let n = mesh.vertices.len();
        let tris = &mesh.triangles;
        if 3 * tris.len() >= u32::MAX as usize {
            return Err(MeshError::BadTriangle {
                triangle: tris.len() - 1,
                why: "more than 1,431,655,764 triangles".into(),
            });
        }
        let mut start = crate::memory::huge_vec(0u32, n + 1);
        for tri in tris {
            for &a in tri {
                start[a as usize + 1] += 1;
            }
        }
        for v in 0..n {
            start[v + 1] += start[v];
        }
        let mut corners = crate::memory::huge_vec(0u32, 3 * tris.len());
        {
            let mut fill = start[..n].to_vec();
            for (t, tri) in tris.iter().enumerate() {
                for (c, &a) in tri.iter().enumerate() {
                    corners[fill[a as usize] as usize] = (3 * t + c) as u32;
                    fill[a as usize] += 1;
                }
            }
        }
        // Vertices are ordered independently: in parallel, in runs of vertices whose corners
        // are contiguous; the first error in vertex order is reported.
        let mut border = vec![false; n];
        let mut runs = Vec::with_capacity(n.div_ceil(RUN));
        let (mut rest, mut border_rest) = (&mut corners[..], &mut border[..]);
        for v0 in (0..n).step_by(RUN) {
            let v1 = (v0 + RUN).min(n);
            let (cs, tail) = rest.split_at_mut((start[v1] - start[v0]) as usize);
            let (bs, border_tail) = border_rest.split_at_mut(v1 - v0);
            (rest, border_rest) = (tail, border_tail);
            runs.push((v0, cs, bs));
        }
        let outcomes: Vec<Result<(), MeshError>> = runs
            .into_par_iter()
            .map_init(Order::default, |order, (v0, cs, bs)| {
                let base = start[v0] as usize;
                for (k, is_border) in bs.iter_mut().enumerate() {
                    let v = v0 + k;
                    let range = start[v] as usize - base..start[v + 1] as usize - base;
                    if !range.is_empty() {
                        *is_border = order.sort(v as u32, &mut cs[range], tris)?;
                    }
                }
                Ok(())
            })
            .collect();
        outcomes.into_iter().collect::<Result<(), MeshError>>()?;
        Ok(Fans {
            start,
            corners,
            border,
        })
    }

    /// The corners at `v`, counter-clockwise; for a border vertex the first is the triangle
    /// whose edge `v → a` is on the border.
    pub(crate) fn corners(&self, v: u32) -> &[u32] {
        &self.corners[self.start[v as usize] as usize..self.start[v as usize + 1] as usize]
    }

    /// True when `v`'s fan is open (a half-disc).
    pub(crate) fn is_border(&self, v: u32) -> bool {
        self.border[v as usize]
    }

    /// The number of border edges (each leaves exactly one border vertex).
    pub(crate) fn border_edges(&self) -> usize {
        self.border.iter().filter(|&&b| b).count()
    }
}

/// Scratch for ordering one vertex's corners.
#[derive(Default)]
struct Order {
    /// `(a, corner)` (sorted by `a` for large fans).
    by_a: Vec<(u32, u32)>,
    /// The `b` of every corner (sorted for large fans).
    bs: Vec<u32>,
    out: Vec<u32>,
}

impl Order {
    /// Orders the corners at `v` counter-clockwise in place; returns whether `v` is on the
    /// border.
    fn sort(&mut self, v: u32, corners: &mut [u32], tris: &[[u32; 3]]) -> Result<bool, MeshError> {
        let a_of = |h: u32| tris[h as usize / 3][(h as usize % 3 + 1) % 3];
        let b_of = |h: u32| tris[h as usize / 3][(h as usize % 3 + 2) % 3];
        self.by_a.clear();
        self.by_a.extend(corners.iter().map(|&h| (a_of(h), h)));
        self.bs.clear();
        self.bs.extend(corners.iter().map(|&h| b_of(h)));
        // Small fans (nearly all) are searched linearly, large ones through sorted copies.
        let small = corners.len() <= SMALL;
        if !small {
            self.by_a.sort_unstable();
            self.bs.sort_unstable();
        }
        let (by_a, bs) = (&self.by_a, &self.bs);
        let find_a = |a: u32| -> Option<usize> {
            if small {
                by_a.iter().position(|&(x, _)| x == a)
            } else {
                by_a.binary_search_by_key(&a, |&(x, _)| x).ok()
            }
        };
        let has_b = |b: u32| -> bool {
            if small {
                bs.contains(&b)
            } else {
                bs.binary_search(&b).is_ok()
            }
        };
        // A repeated edge v → a.
        let repeated = if small {
            (1..by_a.len()).find_map(|j| {
                (0..j)
                    .find(|&i| by_a[i].0 == by_a[j].0)
                    .map(|i| (by_a[i], by_a[j]))
            })
        } else {
            by_a.windows(2)
                .find(|w| w[0].0 == w[1].0)
                .map(|w| (w[0], w[1]))
        };
        if let Some(((a, g), (_, h))) = repeated {
            return Err(MeshError::NonManifold {
                a: v,
                b: a,
                why: format!(
                    "traversed in the same direction by triangles {} and {} (inconsistent orientation or more than two triangles)",
                    g.min(h) / 3,
                    g.max(h) / 3
                ),
            });
        }
        // The triangle whose edge v → a has no twin a → v opens a border fan.
        let mut first = None;
        for &(a, h) in by_a {
            if !has_b(a) {
                if first.is_some() {
                    return Err(MeshError::PinchedVertex {
                        a: v,
                        b: a,
                        why: format!("vertex {v} has two boundary fans (a bow-tie vertex)"),
                    });
                }
                first = Some(h);
            }
        }
        let is_border = first.is_some();
        let h0 = first.unwrap_or(corners[0]);
        self.out.clear();
        let mut h = h0;
        loop {
            self.out.push(h);
            let Some(k) = find_a(b_of(h)) else {
                break;
            };
            h = by_a[k].1;
            if h == h0 || self.out.len() > corners.len() {
                break;
            }
        }
        if self.out.len() != corners.len() {
            return Err(MeshError::PinchedVertex {
                a: v,
                b: a_of(h0),
                why: format!(
                    "the {} triangles at vertex {v} form more than one fan (a pinched vertex)",
                    corners.len()
                ),
            });
        }
        corners.copy_from_slice(&self.out);
        Ok(is_border)
    }
}

/// Fans up to this many triangles are searched linearly.
const SMALL: usize = 16;

/// Vertices per parallel run.
const RUN: usize = 4096;

#[cfg(test)]
mod tests {
    use super::*;

    fn mesh(triangles: Vec<[u32; 3]>) -> Mesh {
        Mesh {
            normals: None,
            vertices: vec![[0.0; 3]; 8],
            triangles,
            scalars: None,
        }
    }

    #[test]
    fn fans_are_counter_clockwise_and_borders_start_at_the_border_edge() {
        // A square 0-1-2-3 around centre 4, plus a flap 1-5-2 outside it.
        let m = mesh(vec![[4, 0, 1], [4, 1, 2], [4, 2, 3], [4, 3, 0], [1, 5, 2]]);
        let f = Fans::of(&m).unwrap();
        assert!(!f.is_border(4));
        let ring: Vec<u32> = f.corners(4).iter().map(|&h| h / 3).collect();
        // Some rotation of triangles 0, 1, 2, 3.
        let r = ring.iter().position(|&t| t == 0).unwrap();
        let rotated: Vec<u32> = (0..4).map(|k| ring[(r + k) % 4]).collect();
        assert_eq!(rotated, vec![0, 1, 2, 3]);
        // Vertex 1: triangles (1, 4, 0)... its border edge 1 → 5 opens the fan.
        assert!(f.is_border(1));
        let at1: Vec<u32> = f.corners(1).iter().map(|&h| h / 3).collect();
        assert_eq!(at1, vec![4, 1, 0]);
        assert_eq!(f.border_edges(), 5);
    }

    #[test]
    fn topology_errors() {
        let e = Fans::of(&mesh(vec![[0, 1, 2], [0, 1, 3]])).unwrap_err();
        assert!(
            matches!(e, MeshError::NonManifold { a: 0, b: 1, .. }),
            "{e}"
        );
        let e = Fans::of(&mesh(vec![[0, 1, 2], [0, 3, 4]])).unwrap_err();
        assert!(e.to_string().contains("bow-tie"), "{e}");
        assert!(matches!(e, MeshError::PinchedVertex { a: 0, .. }), "{e}");
        // Two closed fans at vertex 0 (two tetrahedra sharing a vertex).
        let e = Fans::of(&mesh(vec![
            [0, 1, 2],
            [0, 2, 3],
            [0, 3, 1],
            [1, 3, 2],
            [0, 4, 5],
            [0, 5, 6],
            [0, 6, 4],
            [4, 6, 5],
        ]))
        .unwrap_err();
        assert!(e.to_string().contains("pinched"), "{e}");
        assert!(matches!(e, MeshError::PinchedVertex { a: 0, .. }), "{e}");
        assert!(Fans::of(&mesh(vec![[0, 1, 9]])).is_err());
    }
}
