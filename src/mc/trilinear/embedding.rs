//! Whether a cell's triangles are embedded: an exact test for crossings between triangles of
//! one cell mesh ([`CellMesh`]), for cells with small integer corner values.
//!
//! Positions are exact: with shifted corner values `g` (isovalue at 0), the cut point of an
//! edge `a → b` sits at `t = g_a / (g_a − g_b)` along it, and interior vertices are averages
//! ([`interior_position`]). Every position is scaled by one common integer so that all
//! coordinates are integers, and orientations are signs of `i128` determinants.
//!
//! Two triangles with no vertex in common cross when an edge of one meets the other (closed
//! sets: touching counts). Pairs that share a vertex or an edge are not tested, nor pairs
//! where an edge lies in the other triangle's plane (counted apart): the count is a lower
//! bound on the crossings.

use super::polygonise::{interior_position, CellMesh};
use crate::mc::table::{CORNERS, EDGES};

/// Crossings found in one cell mesh.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Crossings {
    /// Vertex-disjoint triangle pairs tested.
    pub pairs: usize,
    /// Pairs that meet.
    pub crossing: usize,
    /// Pairs with an edge in the other's plane (not decided).
    pub coplanar: usize,
}

/// The crossings of `mesh`, the triangulation of the cell with shifted integer corner values
/// `g` (table corner order; `|g| < 2¹⁵`, no corner on the level at an edge the mesh uses).
/// `None` when a value is out of range or a used edge has no sign change.
pub fn crossings(g: &[i64; 8], mesh: &CellMesh) -> Option<Crossings> {
    if g.iter().any(|v| v.abs() >= 1 << 15) {
        return None;
    }
    // Every edge's crossing as a rational point num / den with den = g_a − g_b.
    let mut den = [0i128; 12];
    for (e, [a, b]) in EDGES.iter().enumerate() {
        den[e] = (g[*a as usize] - g[*b as usize]) as i128;
    }
    let used: Vec<u8> = {
        let mut u: Vec<u8> = mesh
            .triangles
            .iter()
            .flatten()
            .copied()
            .filter(|&v| v < 12)
            .chain(
                mesh.interior
                    .iter()
                    .flat_map(|v| v.of.iter().chain(&v.toward).copied()),
            )
            .collect();
        u.sort_unstable();
        u.dedup();
        u
    };
    if used.iter().any(|&e| den[e as usize] == 0) {
        return None;
    }
    // Scale: lcm of the used denominators, times the averaging counts (≤ 12, and 2).
    let lcm = used.iter().fold(1i128, |l, &e| {
        let d = den[e as usize].abs();
        l / gcd(l, d) * d
    });
    let scale = lcm * 27720 * 2;
    let cut = |e: u8| -> [i128; 3] {
        let [a, b] = EDGES[e as usize];
        let (pa, pb) = (CORNERS[a as usize], CORNERS[b as usize]);
        let t_num = g[a as usize] as i128 * (scale / den[e as usize]);
        [0, 1, 2].map(|k| pa[k] as i128 * scale + t_num * (pb[k] as i128 - pa[k] as i128))
    };
    let position = |v: u8| -> [i128; 3] {
        if v < 12 {
            return cut(v);
        }
        interior_position(
            &mesh.interior[(v - 12) as usize],
            cut,
            |a, b| [a[0] + b[0], a[1] + b[1], a[2] + b[2]],
            |a, k| a.map(|x| x / k as i128),
        )
    };
    let tris: Vec<[[i128; 3]; 3]> = mesh.triangles.iter().map(|t| t.map(position)).collect();
    let mut out = Crossings::default();
    for i in 0..tris.len() {
        for j in i + 1..tris.len() {
            let (a, b) = (mesh.triangles[i], mesh.triangles[j]);
            if a.iter().any(|v| b.contains(v)) {
                continue;
            }
            out.pairs += 1;
            let (mut meet, mut flat) = (false, false);
            for (s, t) in [(&tris[i], &tris[j]), (&tris[j], &tris[i])] {
                for k in 0..3 {
                    match segment_meets_triangle(s[k], s[(k + 1) % 3], t) {
                        Some(true) => meet = true,
                        None => flat = true,
                        Some(false) => {}
                    }
                }
            }
            if meet {
                out.crossing += 1;
            } else if flat {
                out.coplanar += 1;
            }
        }
    }
    Some(out)
}

fn gcd(mut a: i128, mut b: i128) -> i128 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a.abs()
}

/// The sign of the orientation of `d` against the plane through `a, b, c`.
fn orient(a: [i128; 3], b: [i128; 3], c: [i128; 3], d: [i128; 3]) -> i32 {
    let u = [0, 1, 2].map(|k| b[k] - a[k]);
    let v = [0, 1, 2].map(|k| c[k] - a[k]);
    let w = [0, 1, 2].map(|k| d[k] - a[k]);
    let det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
        + u[2] * (v[0] * w[1] - v[1] * w[0]);
    det.signum() as i32
}

/// Whether the closed segment `pq` meets the closed triangle `t`; `None` when the segment
/// lies in the triangle's plane.
fn segment_meets_triangle(p: [i128; 3], q: [i128; 3], t: &[[i128; 3]; 3]) -> Option<bool> {
    let (sp, sq) = (orient(t[0], t[1], t[2], p), orient(t[0], t[1], t[2], q));
    if sp == 0 && sq == 0 {
        return None;
    }
    if sp * sq > 0 {
        return Some(false);
    }
    let s = [
        orient(p, q, t[0], t[1]),
        orient(p, q, t[1], t[2]),
        orient(p, q, t[2], t[0]),
    ];
    Some(!(s.contains(&1) && s.contains(&-1)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mc::trilinear::polygonise::cell_mesh;
    use crate::mc::trilinear::topology_of_small;

    /// The predicates on hand-made points, a disc cell (embedded), and a tube cell where the
    /// current construction crosses itself.
    #[test]
    fn crossings_are_exact() {
        let (o, x, y, z) = ([0; 3], [4, 0, 0], [0, 4, 0], [0, 0, 4]);
        assert_eq!(orient(o, x, y, z), 1);
        assert_eq!(orient(o, y, x, z), -1);
        assert_eq!(orient(o, x, y, [1, 1, 0]), 0);
        let t = [o, x, y];
        // Through the triangle, beside it, touching its edge, and in its plane.
        assert_eq!(
            segment_meets_triangle([1, 1, -1], [1, 1, 1], &t),
            Some(true)
        );
        assert_eq!(
            segment_meets_triangle([5, 5, -1], [5, 5, 1], &t),
            Some(false)
        );
        assert_eq!(
            segment_meets_triangle([2, 0, -1], [2, 0, 1], &t),
            Some(true)
        );
        assert_eq!(segment_meets_triangle([1, 1, 0], [9, 9, 0], &t), None);
        // One positive corner: a single triangle, no pair.
        let g = [5, -1, -1, -1, -1, -1, -1, -1];
        let m = cell_mesh(&topology_of_small(&g).unwrap()).unwrap();
        assert_eq!(crossings(&g, &m), Some(Crossings::default()));
        // Corner values 1 −1 2 1 1 2 −1 −2 at isovalue 1/2: a tube whose stitched rings cross
        // (reports/mc.md counts such cells; a construction that removes them flips this).
        let g = [1, -1, 2, 1, 1, 2, -1, -2].map(|v: i64| 2 * v - 1);
        let t = topology_of_small(&g).unwrap();
        assert_eq!(t.tunnels(), 1);
        let c = crossings(&g, &cell_mesh(&t).unwrap()).unwrap();
        assert!(c.crossing > 0, "{c:?}");
        // Out of range: no answer.
        assert_eq!(crossings(&[1 << 15, 0, 0, 0, 0, 0, 0, -1], &m), None);
    }
}
