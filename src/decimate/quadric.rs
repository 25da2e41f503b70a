//! The accumulated error of the [`Criterion::Quadric`](super::Criterion::Quadric) (an
//! extension for surfaces in 3-D): per-node quadrics of the original planes (Garland and
//! Heckbert 1997), per-triangle error bounds, where a removed node lands on its hole, how far
//! its fan lies from the new triangles, and the fold guard. Everything here is `f64` and is
//! called alike by both engines, in the same order, so that they take the same decisions.

use super::fan_normal;
use crate::mesh::Mesh;

/// A symmetric 4×4 quadric `Q(p) = Σ wᵢ (nᵢ·p + dᵢ)²` over weighted planes (Garland and
/// Heckbert 1997, eq. 2), stored as its ten distinct entries `[aa, ab, ac, ad, bb, bc, bd,
/// cc, cd, dd]` of `Σ wᵢ (a, b, c, d)ᵢᵀ (a, b, c, d)ᵢ`. With unit normals the weight is
/// the trace of the 3×3 block ([`weight`](Quadric::weight)).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Quadric(pub [f64; 10]);

impl Quadric {
    /// The quadric of the plane `n·p + d = 0` (`n` a unit normal) with weight `w`.
    pub fn plane(n: [f64; 3], d: f64, w: f64) -> Quadric {
        let [a, b, c] = n;
        Quadric([
            w * a * a,
            w * a * b,
            w * a * c,
            w * a * d,
            w * b * b,
            w * b * c,
            w * b * d,
            w * c * c,
            w * c * d,
            w * d * d,
        ])
    }

    /// Adds `other` entry by entry.
    #[inline]
    pub fn add(&mut self, other: &Quadric) {
        for k in 0..10 {
            self.0[k] += other.0[k];
        }
    }

    /// `Q(p)`: the weighted sum of squared distances from `p` to the planes.
    #[inline]
    pub fn value(&self, p: [f64; 3]) -> f64 {
        let q = &self.0;
        let [x, y, z] = p;
        x * (q[0] * x + 2.0 * (q[1] * y + q[2] * z + q[3]))
            + y * (q[4] * y + 2.0 * (q[5] * z + q[6]))
            + z * (q[7] * z + 2.0 * q[8])
            + q[9]
    }

    /// The total weight of its planes (for unit normals).
    pub fn weight(&self) -> f64 {
        self.0[0] + self.0[4] + self.0[7]
    }

    /// The root mean square distance `√(Q(p)/W)` from `p` to the planes (0 without weight;
    /// rounding below zero reads as zero).
    pub fn rms_distance(&self, p: [f64; 3]) -> f64 {
        let w = self.weight();
        if w > 0.0 {
            (self.value(p).max(0.0) / w).sqrt()
        } else {
            0.0
        }
    }
}

/// What a node carries into its evaluation under the quadric criterion: its quadric, and the
/// largest error bound of its fan's triangles (each triangle's bound on how far the original
/// points it covers lie from it).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Carried {
    /// The node's accumulated quadric.
    pub quadric: Quadric,
    /// The largest error bound among the node's triangles.
    pub fan_error: f64,
}

/// The initial quadrics of the quadric criterion (both engines use these): every triangle's
/// plane weighted by its area goes to its three corners; every border edge `a → b` (its twin
/// `b → a` absent) adds the plane through it perpendicular to its triangle, weighted by
/// `|ab|²`, to `a` and `b` (so that a border node's removal is charged its distance from the
/// original border). Each node sums its incident triangles in increasing
/// order (face plane, then the border edge leaving it, then the one entering it), in `f64`,
/// on all cores: the same values however many. Degenerate triangles add nothing. The mesh
/// must be valid (indices in range).
pub fn initial_quadrics(mesh: &Mesh) -> Vec<Quadric> {
    use crate::par::prelude::*;
    let n = mesh.vertices.len();
    let (pos, tris) = (&mesh.vertices, &mesh.triangles);
    // Incident triangles by node, in increasing order.
    let (start, incident) = crate::mesh::incident_triangles(n, tris);
    let around = |a: u32| &incident[start[a as usize] as usize..start[a as usize + 1] as usize];
    let unit = |v: [f64; 3]| {
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        (l > 0.0 && l.is_finite()).then(|| ([v[0] / l, v[1] / l, v[2] / l], l))
    };
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    // The plane through the edge p → r perpendicular to the unit normal nn, weight |pr|².
    let edge_plane = |p: [f64; 3], r: [f64; 3], nn: [f64; 3]| {
        let d = sub(r, p);
        unit(crate::mesh::cross(d, nn)).map(|(m, _)| Quadric::plane(m, -dot(m, p), dot(d, d)))
    };
    let at = |i: u32| pos[i as usize];
    (0..n as u32)
        .into_par_iter()
        .map_init(Vec::new, |links: &mut Vec<(u32, u32)>, a| {
            // Around a, each triangle (a, next, prev): the edge a → next is a border edge
            // when no triangle around a enters a from next, prev → a when none leaves a to
            // prev.
            links.clear();
            links.extend(around(a).iter().map(|&k| {
                let t = tris[k as usize];
                let e = t.iter().position(|&x| x == a).unwrap_or(0);
                (t[(e + 1) % 3], t[(e + 2) % 3])
            }));
            let mut q = Quadric::default();
            for (&k, &(next, prev)) in around(a).iter().zip(links.iter()) {
                let [pa, pb, pc] = tris[k as usize].map(at);
                let Some((nn, twice_area)) = unit(crate::mesh::cross(sub(pb, pa), sub(pc, pa)))
                else {
                    continue;
                };
                q.add(&Quadric::plane(nn, -dot(nn, pa), 0.5 * twice_area));
                if !links.iter().any(|&(_, p)| p == next) {
                    if let Some(k) = edge_plane(at(a), at(next), nn) {
                        q.add(&k);
                    }
                }
                if !links.iter().any(|&(x, _)| x == prev) {
                    if let Some(k) = edge_plane(at(prev), at(a), nn) {
                        q.add(&k);
                    }
                }
            }
            q
        })
        .collect()
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// The largest deviation between a node's fan and the triangles that replace it, away from
/// the node itself (both engines, in `f64`): along the projection axis `drop`, at every point
/// where a new diagonal `(a, c)` crosses a spoke `(v, w)` in the projection (both surfaces
/// are linear along those segments, so between the node and these points the difference is
/// piecewise linear and peaks at one of them or at the node). `p` is the node, `ring3` its
/// ring, `pts`/`pv` their projections, `tris` the cut.
pub fn crossing_deviation(
    p: [f64; 3],
    pv: [f64; 2],
    ring3: &[[f64; 3]],
    pts: &[[f64; 2]],
    tris: &[[u8; 3]],
    drop: usize,
    border: bool,
) -> f64 {
    let l = pts.len();
    let cross2 = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut worst = 0.0f64;
    for t in tris {
        for e in 0..3 {
            let (a, c) = (t[e] as usize, t[(e + 1) % 3] as usize);
            // Each diagonal once (a < c); link edges and a border node's closing edge have
            // no spoke crossing them inside.
            if a > c || c == a + 1 || (a == 0 && c == l - 1) {
                continue;
            }
            let (pa, pc) = (pts[a], pts[c]);
            let (ha, hc) = (ring3[a][drop], ring3[c][drop]);
            for (i, &q) in pts.iter().enumerate() {
                if i == a || i == c || (border && (i == 0 || i == l - 1)) {
                    continue;
                }
                // Proper crossing of a–c with v–q: parameters s on a–c, u on v–q.
                let d1 = cross2(pa, pc, pv);
                let d2 = cross2(pa, pc, q);
                if d1 == d2 || (d1 > 0.0) == (d2 > 0.0) {
                    continue;
                }
                let u = d1 / (d1 - d2);
                let d3 = cross2(pv, q, pa);
                let d4 = cross2(pv, q, pc);
                if d3 == d4 || (d3 > 0.0) == (d4 > 0.0) {
                    continue;
                }
                let s = d3 / (d3 - d4);
                let h_new = ha + s * (hc - ha);
                let h_fan = p[drop] + u * (ring3[i][drop] - p[drop]);
                worst = worst.max((h_new - h_fan).abs());
            }
        }
    }
    worst
}

/// The bound on how far the original points a removal's new triangles cover lie from them:
/// the largest bound of the removed fan's triangles plus how far the fan lies from the new
/// triangles (the node's distance to its landing point `landed`, and the `crossing`
/// deviation, [`crossing_deviation`]).
pub fn removal_bound(c: &Carried, p: [f64; 3], landed: [f64; 3], crossing: f64) -> f64 {
    let d = ((p[0] - landed[0]).powi(2) + (p[1] - landed[1]).powi(2) + (p[2] - landed[2]).powi(2))
        .sqrt();
    c.fan_error + d.max(crossing)
}

/// The evaluation value of the quadric criterion for a node carrying `c`, landing at
/// `landed`, with the removal's error bound `bound` ([`removal_bound`]): the larger of the
/// quadric's root mean square distance at the landing point and the bound. The bound keeps
/// the largest deviation in check (it halved the quadric alone's Hausdorff distance on the
/// dragon scan and cut it by a quarter on the MNI152 isosurface), the quadric the accumulated
/// planes' average (the two alone, their sum and this were compared on both).
pub fn quadric_value(c: &Carried, landed: [f64; 3], bound: f64) -> f64 {
    c.quadric.rms_distance(landed).max(bound)
}

/// The original surface's normal at every vertex: the sum of its triangles' area vectors (in
/// triangle order, `f64`; both engines use these). The mesh must be valid.
pub fn vertex_normals(mesh: &Mesh) -> Vec<[f64; 3]> {
    let mut n = vec![[0.0; 3]; mesh.vertices.len()];
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
        let m = crate::mesh::area_vector(a, b, c);
        for &i in t {
            for k in 0..3 {
                n[i as usize][k] += m[k];
            }
        }
    }
    n
}

/// Whether a planned hole would fold the surface over (both engines, in `f64`; the quadric
/// criterion refuses such removals): some new triangle's normal points against the removed
/// fan's area-weighted normal ([`fan_normal`]) — a projection only proves the new triangles
/// positive along its axis, not along the surface — or against the sum of its corners'
/// original normals (`normals`, per ring node, [`vertex_normals`]; empty to skip): the
/// current fan may already lean away from the original surface somewhere, and a new
/// triangle that agrees with the fan can still face against the surface its corners sit on.
pub fn folds(
    p: [f64; 3],
    ring3: &[[f64; 3]],
    tris: &[[u8; 3]],
    border: bool,
    normals: &[[f64; 3]],
) -> bool {
    let n = fan_normal(p, ring3, !border);
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    tris.iter().any(|t| {
        let [a, b, c] = t.map(|k| ring3[k as usize]);
        let m = crate::mesh::area_vector(a, b, c);
        if dot(m, n) <= 0.0 {
            return true;
        }
        if normals.is_empty() {
            return false;
        }
        let [na, nb, nc] = t.map(|k| normals[k as usize]);
        let corners = std::array::from_fn(|k| na[k] + nb[k] + nc[k]);
        dot(m, corners) <= 0.0
    })
}

/// Where a removed node lands on its re-triangulated hole (both engines, in `f64`): for an
/// interior node, in the new triangle whose smallest barycentric coordinate at the node's
/// projection `pv` is largest (`pts` the ring's projection, `tris` the cut), the 3-D point
/// with those coordinates; for a border node, the closest point of the new border edge
/// (`ring3[l − 1]` to `ring3[0]`) to `p`. Returns the point and the ring positions of the
/// triangle it lands in (for a border node the new triangle holding that edge).
pub fn landing(
    p: [f64; 3],
    pv: [f64; 2],
    ring3: &[[f64; 3]],
    pts: &[[f64; 2]],
    tris: &[[u8; 3]],
    border: bool,
) -> ([f64; 3], [u8; 3]) {
    let l = ring3.len();
    if border {
        let (a, b) = (ring3[l - 1], ring3[0]);
        let d = sub(b, a);
        let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        let t = if dd > 0.0 {
            let e = sub(p, a);
            ((e[0] * d[0] + e[1] * d[1] + e[2] * d[2]) / dd).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let point = [a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]];
        let last = (l - 1) as u8;
        let corners = tris
            .iter()
            .copied()
            .find(|t| (0..3).any(|e| t[e] == last && t[(e + 1) % 3] == 0))
            .unwrap_or([last, 0, 1]);
        return (point, corners);
    }
    let best = deepest_triangle(pv, pts, tris);
    match best {
        Some((w, t)) => {
            let [a, b, c] = t.map(|k| ring3[k as usize]);
            (
                std::array::from_fn(|k| w[0] * a[k] + w[1] * b[k] + w[2] * c[k]),
                t,
            )
        }
        None => (p, tris.first().copied().unwrap_or([0, 1, 2])),
    }
}

/// The new triangle whose smallest barycentric coordinate at `pv` is largest (the first on
/// ties; triangles without positive area in `f64` are passed over), with the barycentric
/// coordinates of `pv` in it: where a removed node's projection falls in its hole (both
/// engines, the error and the quadric criteria).
pub(crate) fn deepest_triangle(
    pv: [f64; 2],
    pts: &[[f64; 2]],
    tris: &[[u8; 3]],
) -> Option<([f64; 3], [u8; 3])> {
    let cross2 = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| {
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    };
    let mut best: Option<(f64, [f64; 3], [u8; 3])> = None;
    for &t in tris {
        let [a, b, c] = t.map(|k| pts[k as usize]);
        let area = cross2(a, b, c);
        if area.is_nan() || area <= 0.0 {
            continue;
        }
        let l0 = cross2(pv, b, c) / area;
        let l1 = cross2(a, pv, c) / area;
        let l2 = 1.0 - l0 - l1;
        let min = l0.min(l1).min(l2);
        if min > best.map_or(f64::NEG_INFINITY, |b| b.0) {
            best = Some((min, [l0, l1, l2], t));
        }
    }
    best.map(|(_, w, t)| (w, t))
}

/// What removing a node costs under the quadric criterion ([`quadric_removal`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadricRemoval {
    /// The evaluation value ([`quadric_value`]).
    pub value: f64,
    /// The new triangles' error bound ([`removal_bound`]).
    pub bound: f64,
    /// The ring positions of the triangle the node lands in ([`landing`]).
    pub corners: [u8; 3],
}

/// The quadric criterion on one planned hole, as both engines compute it: where the node `p`
/// (projected `pv`) lands, `None` when the new triangles fold the surface over ([`folds`],
/// with the ring's original `normals`), else the crossing deviation along axis `drop`, the
/// bound and the value for a node carrying `c`. `ring3`/`pts` are the ring and its
/// projection, `tris` the cut.
#[allow(clippy::too_many_arguments)]
pub fn quadric_removal(
    c: &Carried,
    p: [f64; 3],
    pv: [f64; 2],
    ring3: &[[f64; 3]],
    pts: &[[f64; 2]],
    tris: &[[u8; 3]],
    drop: usize,
    border: bool,
    normals: &[[f64; 3]],
) -> Option<QuadricRemoval> {
    let (landed, corners) = landing(p, pv, ring3, pts, tris, border);
    if folds(p, ring3, tris, border, normals) {
        return None;
    }
    let crossing = crossing_deviation(p, pv, ring3, pts, tris, drop, border);
    let bound = removal_bound(c, p, landed, crossing);
    Some(QuadricRemoval {
        value: quadric_value(c, landed, bound),
        bound,
        corners,
    })
}
