//! Whether a cell's triangles are embedded: an exact test for crossings between triangles of
//! one cell mesh ([`CellMesh`]), for cells with small integer corner values.
//!
//! Positions are exact: with shifted corner values `g` (isovalue at 0), the cut point of an
//! edge `a → b` sits at `t = g_a / (g_a − g_b)` along it, and interior vertices are averages
//! ([`interior_position`]). Every position is scaled by one common integer so that all
//! coordinates are integers, and orientations are signs of `i128` determinants.
//!
//! Every pair of triangles is tested (closed sets: touching counts; an edge in the other's
//! plane is tested in that plane). Two triangles with no vertex in common cross when an edge
//! of one meets the other; with one common vertex, when the edge opposite it in one meets
//! the other; with a common edge, when they are folded onto each other (coplanar, on the
//! same side of it). Pairs with a degenerate triangle in the coplanar case are counted apart.

use super::polygonise::{interior_position, CellMesh};
use crate::mc::table::{CORNERS, EDGES};

/// Crossings found in one cell mesh.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Crossings {
    /// Triangle pairs tested (every pair).
    pub pairs: usize,
    /// Pairs that meet.
    pub crossing: usize,
    /// Pairs with an edge in the plane of a degenerate other triangle (not decided).
    pub coplanar: usize,
}

/// The crossings of `mesh`, the triangulation of the cell with shifted integer corner values
/// `g` (table corner order; `|g| < 2¹⁵`, no corner on the level at an edge the mesh uses).
/// `None` when a value is out of range, a used edge has no sign change, or the common
/// denominator of the cut points reaches `2²⁴` (coordinates would overflow the determinants).
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
    // Scale: lcm of the used denominators, times the averaging counts (≤ 12, and 2), below
    // 2⁴⁰ so that the orientation determinants (cubes of coordinate differences) fit.
    let lcm = used.iter().try_fold(1i128, |l, &e| {
        let d = den[e as usize].abs();
        (l / gcd(l, d)).checked_mul(d).filter(|&x| x < 1 << 24)
    })?;
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
            let shared: Vec<usize> = (0..3).filter(|&k| b.contains(&a[k])).collect();
            // Corners of each triangle not in the other.
            let own = |t: &[u8; 3], other: &[u8; 3]| -> Vec<usize> {
                (0..3).filter(|&k| !other.contains(&t[k])).collect()
            };
            let (ta, tb) = (&tris[i], &tris[j]);
            let verdict = match shared.len() {
                0 => {
                    // Disjoint: no edge of one meets the other.
                    let mut v = Some(false);
                    for (s, t) in [(ta, tb), (tb, ta)] {
                        for k in 0..3 {
                            v = or(v, segment_meets_triangle(s[k], s[(k + 1) % 3], t));
                        }
                    }
                    v
                }
                1 => {
                    // One common vertex: they meet only there unless the edge opposite it
                    // in one meets the other (the intersection is a segment from the common
                    // vertex, which leaves one of them through that edge).
                    let (oa, ob) = (own(&a, &b), own(&b, &a));
                    or(
                        segment_meets_triangle(ta[oa[0]], ta[oa[1]], tb),
                        segment_meets_triangle(tb[ob[0]], tb[ob[1]], ta),
                    )
                }
                2 => {
                    // A common edge: they overlap only when folded onto each other (the
                    // other corners coplanar with it and on the same side).
                    let (u, v) = (
                        ta[shared[0]],
                        ta[(0..3)
                            .find(|&k| k != shared[0] && b.contains(&a[k]))
                            .expect("two shared")],
                    );
                    let (wa, wb) = (ta[own(&a, &b)[0]], tb[own(&b, &a)[0]]);
                    Some(orient(u, v, wa, wb) == 0 && same_side(u, v, wa, wb))
                }
                _ => Some(true),
            };
            out.pairs += 1;
            match verdict {
                Some(true) => out.crossing += 1,
                None => out.coplanar += 1,
                Some(false) => {}
            }
        }
    }
    Some(out)
}

/// Crossing if either says so; undecided if either is and none crosses.
fn or(a: Option<bool>, b: Option<bool>) -> Option<bool> {
    match (a, b) {
        (Some(true), _) | (_, Some(true)) => Some(true),
        (Some(false), Some(false)) => Some(false),
        _ => None,
    }
}

/// For `w1, w2` coplanar with the line `uv`: whether they lie strictly on the same side of
/// it (the cross products `(v − u) × (w − u)` point the same way).
fn same_side(u: [i128; 3], v: [i128; 3], w1: [i128; 3], w2: [i128; 3]) -> bool {
    let d = [0, 1, 2].map(|k| v[k] - u[k]);
    let cross = |w: [i128; 3]| {
        let e = [0, 1, 2].map(|k| w[k] - u[k]);
        [
            d[1] * e[2] - d[2] * e[1],
            d[2] * e[0] - d[0] * e[2],
            d[0] * e[1] - d[1] * e[0],
        ]
    };
    // The two cross products are parallel (normal to the common plane): compare signs, not
    // magnitudes (their products could overflow).
    let (c1, c2) = (cross(w1), cross(w2));
    (0..3)
        .map(|k| c1[k].signum() * c2[k].signum())
        .sum::<i128>()
        > 0
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
/// lies in the plane of a degenerate triangle.
fn segment_meets_triangle(p: [i128; 3], q: [i128; 3], t: &[[i128; 3]; 3]) -> Option<bool> {
    let (sp, sq) = (orient(t[0], t[1], t[2], p), orient(t[0], t[1], t[2], q));
    if sp == 0 && sq == 0 {
        return coplanar_meets(p, q, t);
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

/// Small integer shifted values as rationals (for [`cell_mesh`](super::polygonise::cell_mesh)).
pub fn shifted(g: &[i64; 8]) -> [crate::num::Rational; 8] {
    g.map(|x| crate::num::Rational::from_integer(x.into()))
}

/// The coplanar case: the segment and the triangle projected along the axis where the
/// triangle's normal is largest (a projection that keeps incidence in their plane). `None`
/// for a degenerate triangle.
fn coplanar_meets(p: [i128; 3], q: [i128; 3], t: &[[i128; 3]; 3]) -> Option<bool> {
    let u = [0, 1, 2].map(|k| t[1][k] - t[0][k]);
    let v = [0, 1, 2].map(|k| t[2][k] - t[0][k]);
    let n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let drop = (0..3).max_by_key(|&k| n[k].abs())?;
    if n[drop] == 0 {
        return None;
    }
    let (a, b) = ((drop + 1) % 3, (drop + 2) % 3);
    let flat = |x: [i128; 3]| [x[a], x[b]];
    let (p, q, t) = (flat(p), flat(q), t.map(flat));
    let o2 = |a: [i128; 2], b: [i128; 2], c: [i128; 2]| {
        ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).signum()
    };
    let turn = o2(t[0], t[1], t[2]);
    let inside = |x: [i128; 2]| (0..3).all(|k| o2(t[k], t[(k + 1) % 3], x) * turn >= 0);
    let on = |a: [i128; 2], b: [i128; 2], x: [i128; 2]| {
        o2(a, b, x) == 0
            && (a[0].min(b[0])..=a[0].max(b[0])).contains(&x[0])
            && (a[1].min(b[1])..=a[1].max(b[1])).contains(&x[1])
    };
    let cross = |a: [i128; 2], b: [i128; 2], c: [i128; 2], d: [i128; 2]| {
        let (d1, d2, d3, d4) = (o2(a, b, c), o2(a, b, d), o2(c, d, a), o2(c, d, b));
        (d1 * d2 < 0 && d3 * d4 < 0) || on(a, b, c) || on(a, b, d) || on(c, d, a) || on(c, d, b)
    };
    Some(inside(p) || inside(q) || (0..3).any(|k| cross(p, q, t[k], t[(k + 1) % 3])))
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
        assert_eq!(segment_meets_triangle([1, 1, 0], [9, 9, 0], &t), Some(true));
        assert_eq!(
            segment_meets_triangle([5, 5, 0], [9, 9, 0], &t),
            Some(false)
        );
        assert_eq!(
            segment_meets_triangle([-1, 2, 0], [2, -1, 0], &t),
            Some(true)
        );
        assert_eq!(
            segment_meets_triangle([-1, -1, 0], [-1, 9, 0], &t),
            Some(false)
        );
        // One positive corner: a single triangle, no pair.
        let g = [5, -1, -1, -1, -1, -1, -1, -1];
        let m = cell_mesh(&topology_of_small(&g).unwrap(), || shifted(&g)).unwrap();
        assert_eq!(crossings(&g, &m), Some(Crossings::default()));
        // Corner values 1 −1 2 1 1 2 −1 −2 at isovalue 1/2: a tube whose rings crossed when
        // they were zipped from fixed start vertices; the shortest zip does not cross.
        let g = [1, -1, 2, 1, 1, 2, -1, -2].map(|v: i64| 2 * v - 1);
        let t = topology_of_small(&g).unwrap();
        assert_eq!(t.tunnels(), 1);
        let c = crossings(&g, &cell_mesh(&t, || shifted(&g)).unwrap()).unwrap();
        assert_eq!((c.crossing, c.coplanar), (0, 0), "{c:?}");
        // Out of range: no answer.
        assert_eq!(crossings(&[1 << 15, 0, 0, 0, 0, 0, 0, -1], &m), None);
    }
}
