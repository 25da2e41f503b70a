//! The accumulated error of the [`Criterion::Quadric`](super::Criterion::Quadric) (an
//! extension for surfaces in 3-D): per-node quadrics of the original planes (Garland and
//! Heckbert 1997), per-triangle error bounds, where a removed node lands on its hole, how far
//! its fan lies from the new triangles, and the fold guard. Everything here is `f64` and is
//! called alike by both engines, in the same order, so that they take the same decisions.

use super::fan_normal;
use crate::mesh::Mesh;
use std::cmp::Ordering;

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
    Spokes {
        p,
        pv,
        ring3,
        pts,
        drop,
        border,
    }
    .crossing(tris)
}

/// A node's fan seen from its projection `pv` (the quadric criterion's gaps between the fan
/// and a cut of its hole, both engines, `f64`), through the spoke products
/// `(qᵢ − pv) × (qⱼ − pv)` of its projected ring. Every crossing test below is a sum of
/// these: `det[c − a, v − a]` is `(a − v) × (c − v)`, `det[c − a, q − a]` is
/// `(a × c) + (c × q) + (q × a)` with each product taken about `v`, and `det[q − v, a − v]`
/// is `q × a`.
struct Spokes<'a> {
    p: [f64; 3],
    pv: [f64; 2],
    ring3: &'a [[f64; 3]],
    pts: &'a [[f64; 2]],
    drop: usize,
    border: bool,
}

impl Spokes<'_> {
    /// `(qᵢ − pv) × (qⱼ − pv)`.
    #[inline]
    fn m(&self, i: usize, j: usize) -> f64 {
        let (a, b, v) = (self.pts[i], self.pts[j], self.pv);
        (a[0] - v[0]) * (b[1] - v[1]) - (a[1] - v[1]) * (b[0] - v[0])
    }

    /// How far the fan lies from the new diagonal `a–c` (ring positions) along `drop`: the
    /// largest difference at a point where a spoke `(v, qᵢ)` properly crosses it in the
    /// projection (0 when none does).
    fn gap(&self, a: usize, c: usize) -> f64 {
        let l = self.pts.len();
        let (ha, hc, hv) = (
            self.ring3[a][self.drop],
            self.ring3[c][self.drop],
            self.p[self.drop],
        );
        let d1 = self.m(a, c);
        let mut worst = 0.0f64;
        for i in 0..l {
            if i == a || i == c || (self.border && (i == 0 || i == l - 1)) {
                continue;
            }
            // v and qᵢ on opposite sides of a–c, and a, c on opposite sides of v–qᵢ.
            let (d3, d4) = (self.m(i, a), self.m(i, c));
            let d2 = d1 - d4 + d3;
            if d1 == d2 || (d1 > 0.0) == (d2 > 0.0) || d3 == d4 || (d3 > 0.0) == (d4 > 0.0) {
                continue;
            }
            let (u, s) = (d1 / (d1 - d2), d3 / (d3 - d4));
            let h_new = ha + s * (hc - ha);
            let h_fan = hv + u * (self.ring3[i][self.drop] - hv);
            worst = worst.max((h_new - h_fan).abs());
        }
        worst
    }

    /// The largest [`gap`](Self::gap) over the interior diagonals of the cut `tris`.
    fn crossing(&self, tris: &[[u8; 3]]) -> f64 {
        let l = self.pts.len();
        let mut worst = 0.0f64;
        for t in tris {
            for e in 0..3 {
                let (a, c) = (t[e] as usize, t[(e + 1) % 3] as usize);
                // Each diagonal once (a < c); link edges and a border node's closing edge
                // have no spoke crossing them inside.
                if a < c && is_diagonal(l, a, c) {
                    worst = worst.max(self.gap(a, c));
                }
            }
        }
        worst
    }

    /// The barycentric weights of the node's projection in triangle `t` (twice the areas of
    /// `(v, b, c)`, `(v, c, a)`, `(v, a, b)`) and their sum.
    #[inline]
    fn weights(&self, t: [u8; 3]) -> ([f64; 3], f64) {
        let [a, b, c] = t.map(usize::from);
        let w = [self.m(b, c), self.m(c, a), self.m(a, b)];
        (w, w[0] + w[1] + w[2])
    }

    /// Whether the node's projection lies in `t`'s closed projection (by [`weights`](Self::weights)).
    #[inline]
    fn holds(&self, t: [u8; 3]) -> bool {
        let (w, area) = self.weights(t);
        area > 0.0 && w.iter().all(|&x| x >= 0.0)
    }

    /// How far the node lies from the new triangle `t` along `drop` when its projection lies
    /// in it ([`holds`](Self::holds)), else 0.
    fn point(&self, t: [u8; 3]) -> f64 {
        if !self.holds(t) {
            return 0.0;
        }
        let (w, area) = self.weights(t);
        let [ha, hb, hc] = t.map(|k| self.ring3[k as usize][self.drop]);
        (self.p[self.drop] - (w[0] * ha + w[1] * hb + w[2] * hc) / area).abs()
    }
}

/// Whether `a < c` are the ends of a diagonal of the hole `0..l` (not a side).
#[inline]
fn is_diagonal(l: usize, a: usize, c: usize) -> bool {
    c != a + 1 && !(a == 0 && c == l - 1)
}

/// Diagonal flips of a cut hole towards its fan (the quadric criterion's retriangulation,
/// both engines; Lawson-style flips with the fan's deviation as the measure). An interior
/// diagonal `x–y` of two new triangles is replaced by the other diagonal of their
/// quadrilateral when
/// - the fan lies closer to the new pair: the diagonal's gap (how far the fan lies from it
///   along `drop` where spokes cross it, as in [`crossing_deviation`]), plus, for the
///   quadrilateral the node's projection `pv` lies in, the node's gap to the triangle it
///   falls in, strictly decreases; and
/// - both new triangles turn counter-clockwise (signs from `orient`, exact in both engines).
///
/// The quadrilateral is then strictly convex, so the new triangles are positive and hold no
/// other polygon vertex: the cut stays valid. Sweeps repeat until nothing flips (at most
/// `l²` flips). The ear cutter chooses by shape alone, blind to heights; on the dragon scan
/// about 1.5 flips per hole follow. Returns whether anything flipped (the order of `tris` is
/// then not an ear order: [`ear_order`](super::earcut::ear_order) restores one) and the
/// cut's crossing deviation.
#[allow(clippy::too_many_arguments)]
pub fn flip_toward_fan(
    p: [f64; 3],
    pv: [f64; 2],
    ring3: &[[f64; 3]],
    pts: &[[f64; 2]],
    tris: &mut [[u8; 3]],
    drop: usize,
    border: bool,
    orient: &impl super::earcut::Orient,
) -> Flipped {
    let l = pts.len();
    let spokes = Spokes {
        p,
        pv,
        ring3,
        pts,
        drop,
        border,
    };
    let (mut flipped, mut crossing) = (false, 0.0f64);
    if l >= 4 {
        // Gaps by diagonal, each computed once for holes of up to 8 vertices.
        let (mut known, mut cache) = (0u64, [0.0f64; 64]);
        let mut gap = |x: u8, y: u8| {
            let (x, y) = (x.min(y) as usize, x.max(y) as usize);
            if y >= 8 {
                return spokes.gap(x, y);
            }
            let k = 8 * x + y;
            if known & 1 << k == 0 {
                cache[k] = spokes.gap(x, y);
                known |= 1 << k;
            }
            cache[k]
        };
        // The triangle the node's projection lies in: only its quadrilaterals see the
        // node's own gap.
        let mut holder = tris.iter().position(|&t| spokes.holds(t));
        let mut flips = 0;
        'sweep: loop {
            let mut changed = false;
            for i in 0..tris.len() {
                for e in 0..3 {
                    let (x, y, z1) = (tris[i][e], tris[i][(e + 1) % 3], tris[i][(e + 2) % 3]);
                    // Each diagonal once, from its triangle with x < y.
                    if x > y || !is_diagonal(l, x as usize, y as usize) {
                        continue;
                    }
                    let Some((j, z2)) = tris.iter().enumerate().find_map(|(j, t)| {
                        (0..3)
                            .find(|&f| t[f] == y && t[(f + 1) % 3] == x)
                            .map(|f| (j, t[(f + 2) % 3]))
                    }) else {
                        continue;
                    };
                    let (n1, n2) = ([z2, y, z1], [z1, x, z2]);
                    let held = holder == Some(i) || holder == Some(j);
                    let (mut before, mut after) = (gap(x, y), gap(z1, z2));
                    if held {
                        before += spokes.point(tris[i]) + spokes.point(tris[j]);
                        after += spokes.point(n1) + spokes.point(n2);
                    }
                    if after.partial_cmp(&before) != Some(Ordering::Less)
                        || orient.orient(z2 as usize, y as usize, z1 as usize) != Ordering::Greater
                        || orient.orient(z1 as usize, x as usize, z2 as usize) != Ordering::Greater
                    {
                        continue;
                    }
                    (tris[i], tris[j]) = (n1, n2);
                    if held {
                        holder = [(i, n1), (j, n2)]
                            .into_iter()
                            .find_map(|(k, t)| spokes.holds(t).then_some(k));
                    }
                    (flipped, changed) = (true, true);
                    flips += 1;
                    if flips >= l * l {
                        break 'sweep;
                    }
                    // Triangle i changed: on to the next one.
                    break;
                }
            }
            if !changed {
                break;
            }
        }
        for t in tris.iter() {
            for e in 0..3 {
                let (a, c) = (t[e], t[(e + 1) % 3]);
                if a < c && is_diagonal(l, a as usize, c as usize) {
                    crossing = crossing.max(gap(a, c));
                }
            }
        }
    }
    Flipped { flipped, crossing }
}

/// What [`flip_toward_fan`] did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flipped {
    /// Whether any diagonal was flipped (the cut is then not in ear order).
    pub flipped: bool,
    /// The cut's [`crossing_deviation`] after the flips.
    pub crossing: f64,
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
///
/// The corner normals are a cheap stand-in for the facing test
/// ([`faces_against_original`]), which asks the same question of the original surface
/// itself: the engines pass them only when that test is off. With both, on strongly curved
/// coarse meshes the corner normals refused most of what was left (on Kuen's surface at 2 %,
/// 708 of the 1,397 nodes the run stopped at; on pymeshlab's cow at 3 %, 57 of 88), where
/// the facing test accepts the removals and no result triangle faces against the original.
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

/// Whether some triangle of a planned hole faces against the original surface nearest its
/// centroid ([`OriginalSurface::faces_against`](super::quality::OriginalSurface::faces_against);
/// both engines, in `f64`, when a removal is taken): the quadric criterion refuses such
/// removals, so that no triangle of the result faces against the original surface where it
/// lies (the count [`deviation`](super::quality::deviation) reports). `ring` is the ring
/// (node ids, where the searches start), `ring3` its points, `tris` the cut.
pub fn faces_against_original(
    original: &super::quality::OriginalSurface,
    ring: &[u32],
    ring3: &[[f64; 3]],
    tris: &[[u8; 3]],
) -> bool {
    tris.iter().any(|t| {
        let seeds = t.map(|k| ring[k as usize]);
        original.faces_against(t.map(|k| ring3[k as usize]), &seeds)
    })
}

/// The fan fills of a hole whose planned cut would face against the original surface (both
/// engines, at removal, under the quadric criterion): the fan triangulation from each ring
/// position `i = 0, 1, …` in turn (triangles `(i, i+k, i+k+1)`, positions mod `l`), kept
/// when every triangle turns counter-clockwise by `orient` (exact signs): on the simple hole
/// polygon their signed areas then add up to its winding number, so they tile it without
/// overlap. Each comes in ear order ([`ear_order`](super::earcut::ear_order)). The engines
/// value those that pass their topology and facing tests and take the cheapest (the first
/// on ties).
pub fn fan_fills<'a>(
    l: usize,
    orient: &'a impl super::earcut::Orient,
) -> impl Iterator<Item = Vec<[u8; 3]>> + 'a {
    (0..if l >= 4 { l } else { 0 }).filter_map(move |i| {
        let mut tris: Vec<[u8; 3]> = (1..l - 1)
            .map(|k| [i, (i + k) % l, (i + k + 1) % l].map(|x| x as u8))
            .collect();
        let turning = tris.iter().all(|t| {
            orient.orient(t[0] as usize, t[1] as usize, t[2] as usize) == Ordering::Greater
        });
        (turning && super::earcut::ear_order(l, &mut tris)).then_some(tris)
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
/// with the ring's original `normals`), else the bound from the cut's `crossing` deviation
/// ([`crossing_deviation`], as [`flip_toward_fan`] returns it) and the value for a node
/// carrying `c`. `ring3`/`pts` are the ring and its projection, `tris` the cut.
#[allow(clippy::too_many_arguments)]
pub fn quadric_removal(
    c: &Carried,
    p: [f64; 3],
    pv: [f64; 2],
    ring3: &[[f64; 3]],
    pts: &[[f64; 2]],
    tris: &[[u8; 3]],
    crossing: f64,
    border: bool,
    normals: &[[f64; 3]],
) -> Option<QuadricRemoval> {
    let (landed, corners) = landing(p, pv, ring3, pts, tris, border);
    if folds(p, ring3, tris, border, normals) {
        return None;
    }
    let bound = removal_bound(c, p, landed, crossing);
    Some(QuadricRemoval {
        value: quadric_value(c, landed, bound),
        bound,
        corners,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::decimate::earcut::{ear_order, pack_cut, unpack_cut, EarCutter, RobustOrient};

    /// Fan fills tile the hole: on an L-shaped hexagon (one reflex corner, at position 3)
    /// only the fans from the corners that see the whole polygon come out, each with `l − 2`
    /// counter-clockwise triangles whose areas add up to the polygon's, every diagonal from
    /// its apex, in ear order; a square gives a fan from every corner.
    #[test]
    fn fan_fills_tile_the_hole_from_the_corners_that_see_it() {
        let area = |p: &[[f64; 2]], t: [u8; 3]| {
            let [a, b, c] = t.map(|i| p[i as usize]);
            0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
        };
        let ell = [
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 2.0],
            [0.0, 2.0],
        ];
        let fills: Vec<Vec<[u8; 3]>> = fan_fills(6, &RobustOrient(&ell)).collect();
        let apexes: Vec<u8> = fills
            .iter()
            .map(|f| {
                (0..6u8)
                    .find(|&a| f.iter().all(|t| t.contains(&a)))
                    .expect("a fan has an apex")
            })
            .collect();
        // From 0 the diagonals 0–2, 0–3, 0–4 stay inside; from 3 (the reflex corner) too;
        // from 1, 2, 4 and 5 a triangle turns clockwise or degenerates.
        assert_eq!(apexes, vec![0, 3]);
        for f in &fills {
            assert_eq!(f.len(), 4);
            assert!(f.iter().all(|&t| area(&ell, t) > 0.0));
            assert_eq!(f.iter().map(|&t| area(&ell, t)).sum::<f64>(), 3.0);
            let mut again = f.clone();
            assert!(ear_order(6, &mut again));
            assert_eq!(&again, f, "already in ear order");
        }
        let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert_eq!(fan_fills(4, &RobustOrient(&square)).count(), 4);
        assert_eq!(fan_fills(3, &RobustOrient(&square[..3])).count(), 0);
        println!("L-shaped hexagon: fan fills from corners {apexes:?}; square: 4");
    }

    /// A square hole around a node on a ridge: the ring's corners 0 and 2 lie on the ridge
    /// (height 1), 1 and 3 below it (height 0), the node near the centre on the ridge. The
    /// ear cutter sees a square (all ears alike) and cuts across the ridge; the flip puts the
    /// diagonal along it, where the fan stays close, and the crossing deviation it returns is
    /// the cut's.
    #[test]
    fn flips_turn_the_diagonal_along_a_ridge() {
        let ring3 = [
            [1.0, 0.0, 1.0],
            [0.0, 1.0, 0.0],
            [-1.0, 0.0, 1.0],
            [0.0, -1.0, 0.0],
        ];
        let pts: Vec<[f64; 2]> = ring3.iter().map(|q| [q[0], q[1]]).collect();
        let (p, pv) = ([0.1, 0.05, 1.0], [0.1, 0.05]);
        let mut tris = Vec::new();
        let orient = RobustOrient(&pts);
        assert!(EarCutter::default().cut(&pts, &orient, &mut tris));
        let diagonal = |tris: &[[u8; 3]]| {
            let mut d: Vec<(u8, u8)> = tris
                .iter()
                .flat_map(|t| (0..3).map(move |e| (t[e], t[(e + 1) % 3])))
                .filter(|&(a, c)| a < c && is_diagonal(4, a as usize, c as usize))
                .collect();
            d.dedup();
            d
        };
        assert_eq!(
            diagonal(&tris),
            vec![(1, 3)],
            "the cutter crosses the ridge"
        );
        let before = crossing_deviation(p, pv, &ring3, &pts, &tris, 2, false);
        let f = flip_toward_fan(p, pv, &ring3, &pts, &mut tris, 2, false, &orient);
        assert!(f.flipped);
        assert_eq!(diagonal(&tris), vec![(0, 2)], "the flip follows it");
        let after = crossing_deviation(p, pv, &ring3, &pts, &tris, 2, false);
        assert_eq!(f.crossing, after);
        assert!(after < 0.2 && before > 0.8, "{before} → {after}");
        // Back in ear order, the cut packs and unpacks to itself.
        assert!(ear_order(4, &mut tris));
        let mut back = Vec::new();
        unpack_cut(pack_cut(4, &tris).unwrap(), &mut back);
        assert_eq!(back, tris);
        // Flat: nothing to gain, nothing flips.
        let flat: Vec<[f64; 3]> = ring3.iter().map(|q| [q[0], q[1], 0.0]).collect();
        let mut tris = Vec::new();
        EarCutter::default().cut(&pts, &orient, &mut tris);
        let g = flip_toward_fan(
            [0.1, 0.05, 0.0],
            pv,
            &flat,
            &pts,
            &mut tris,
            2,
            false,
            &orient,
        );
        assert!(!g.flipped && g.crossing == 0.0);
    }
}
