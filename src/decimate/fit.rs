//! Re-placement of the kept nodes after a decimation (an extension for surfaces in 3-D, after
//! the distance energy of Hoppe, DeRose, Duchamp, McDonald and Stuetzle, "Mesh optimization",
//! SIGGRAPH 1993, eq. 2, with their fixed-connectivity step): node decimation keeps a subset
//! of the original vertices, so every kept triangle is a chord of the original surface and
//! the whole result lies on one side of it where the surface curves. Moving the kept nodes
//! to the least-squares fit of the original vertices lets the result straddle the surface.
//!
//! One round: every vertex `oᵢ` of the original surface (one some triangle uses) is
//! attached to its closest point on the current result, with barycentric coordinates `bᵢ`
//! in triangle `tᵢ`, and a few points of every result triangle are attached to their closest
//! points on the original (`BackSamples`, weight `wᵢ`; the other direction of the distance,
//! which decides the Hausdorff distance where a triangle spans a groove or a bump; the
//! vertices' pulls weigh 1); then Gauss–Seidel sweeps over the kept nodes minimise
//! `Σᵢ wᵢ |Σₖ bᵢₖ x_{tᵢₖ} − oᵢ|² + Σ_v μ (1 + d_v) |x_v − x_v⁰|²` (the regulariser holds a
//! node near its start `x_v⁰` along directions its points do not constrain;
//! `d_v = Σᵢ wᵢ bᵢᵥ²`). A border node moves along its normal only by that fit (the surface's
//! points would pull it in along the surface) and across the border by the least-squares
//! fit of the original border arcs its border edges stand for (`BorderArcs`; a share
//! [`ACROSS_SHARE`] of it, none at a corner, [`CORNER_COS`]). A move is taken only when
//! every triangle around the node keeps a normal within about 72° of its normal before the
//! fit ([`MIN_COS`]) and, if it faced along its corners' original vertex normals, still
//! does, and (when the decimation ran the facing test,
//! [`Options::facing`](super::Options::facing)) no triangle around it faces against the
//! original surface nearest it; the first is decided with `f64` only where it provably gets
//! the sign right ([`normals_agree`]), so the fit flips no triangle and
//! [`check`](super::check) re-verifies that exactly.
//!
//! Everything is `f64` and runs alike after either engine (the closest points on all cores,
//! each a function of its point alone; the sweeps in node order), so both paths move the
//! same nodes to the same places. The history records every move (from, to) bit for bit, so
//! undecimation still restores the original exactly.

use super::origin::Origin;
use super::quality::{ClosestPoints, OriginalSurface};
use crate::mesh::{area_vector, Mesh};
use crate::num::rational::f64s_over_shared_power;
use num_bigint::BigInt;
use num_traits::Signed;

/// One node moved by the fit: its id in the original mesh and its position before and after.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Moved {
    /// The node (its index in the original mesh).
    pub node: u32,
    /// Where it was (its original coordinates).
    pub from: [f64; 3],
    /// Where the fit put it (its coordinates in the decimated mesh).
    pub to: [f64; 3],
}

/// The regulariser weight `μ` of a node's start position (relative to `1 + d_v`).
pub const REGULARISER: f64 = 0.01;

/// Gauss–Seidel sweeps per round.
pub const SWEEPS: usize = 3;

/// The longest move the fit does not take, as a share of the original's bounding-box
/// diagonal: the pulls on a node of a flat region cancel but for rounding.
pub const NEGLIGIBLE_MOVE: f64 = 1e-9;

/// The share of its least-squares move across the border a border node takes: a chord of
/// an arc of constant curvature with sagitta `h` fits it in least squares `2h/3` outside
/// its ends, leaving its ends `2h/3` from the arc and its middle `h/3`; three quarters of
/// that, `h/2`, balances the two (the smallest largest distance).
pub const ACROSS_SHARE: f64 = 0.75;

/// The smallest cosine of the angle between a border node's two border edges for which it
/// moves across the border (45°): beyond, it is a corner of the border, with no direction
/// across it.
pub const CORNER_COS: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// The smallest cosine between a triangle's normal after a move and before the fit that the
/// fit accepts (about 72°).
pub const MIN_COS: f64 = 0.3;

/// Fits the nodes of `decimated` (whose vertex `k` is node `kept[k]` of `original`) to the
/// original vertices in `rounds` rounds (module docs) and returns the moves, in node order;
/// `decimated`'s vertices are updated. Nothing moves when `rounds` is 0 or either mesh has
/// no triangles. Non-finite results are never taken. With `surface` (the original's, as the
/// decimation checked its removals against it), a move is also refused when a triangle
/// around the node would face against it
/// ([`OriginalSurface::faces_against`]).
pub fn fit(
    original: &Mesh,
    decimated: &mut Mesh,
    kept: &[u32],
    rounds: usize,
    surface: Option<&OriginalSurface>,
) -> Vec<Moved> {
    fit_in(
        original,
        decimated,
        kept,
        rounds,
        surface,
        Origin::default(),
    )
}

/// [`fit`] in local coordinates `origin`: every target is first rounded to a point that
/// translates back to the original frame exactly ([`Origin::snap`]; a target that cannot be
/// is not taken), and the checks run on the rounded point.
pub(crate) fn fit_in(
    original: &Mesh,
    decimated: &mut Mesh,
    kept: &[u32],
    rounds: usize,
    surface: Option<&OriginalSurface>,
    origin: Origin,
) -> Vec<Moved> {
    let n = decimated.vertices.len();
    if rounds == 0 || decimated.triangles.is_empty() || original.triangles.is_empty() {
        return Vec::new();
    }
    let start = decimated.vertices.clone();
    let around = crate::mesh::incident_triangles(n, &decimated.triangles);
    // Triangles whose normal `f64` cannot trust keep their corners where they are.
    let before: Vec<Option<[f64; 3]>> = decimated
        .triangles
        .iter()
        .map(|t| trusted_normal(t.map(|i| start[i as usize])))
        .collect();
    let normals = border_normals(decimated);
    let arcs = BorderArcs::new(original, decimated, kept);
    // The original surface's normals at the kept nodes: a triangle that faces along its
    // corners' normals before the fit must still after it (the decimation's fold test).
    let original_normals = super::vertex_normals(original);
    let corner_normal = |tri: [u32; 3]| -> [f64; 3] {
        let [a, b, c] = tri.map(|i| original_normals[kept[i as usize] as usize]);
        std::array::from_fn(|k| a[k] + b[k] + c[k])
    };
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let facing: Vec<bool> = decimated
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| start[i as usize]);
            dot(area_vector(a, b, c), corner_normal(*t)) > 0.0
        })
        .collect();
    // Every vertex of the original surface (a strided subset was tried: every 4th cost the
    // dragon scan 0.03 of RMS and 30 more flipped triangles for 0.33 s, and the bunny a
    // quarter of its gain); vertices no triangle uses are not on it and pull nothing.
    let samples = &original.vertices;
    let on_surface = original.used_vertices();
    let surface_points = on_surface.iter().filter(|&&u| u).count();
    // Moves within rounding of where a node is (a flat region's pulls cancel but for it)
    // are not taken.
    let negligible2 = (NEGLIGIBLE_MOVE * super::quality::bounding_diagonal(original)).powi(2);
    // The original's closest points for the pulls back (the facing test's when it ran).
    let own = match surface {
        Some(_) => None,
        None => ClosestPoints::new(original),
    };
    let Some(closest) = surface.map(|s| &s.closest).or(own.as_ref()) else {
        return Vec::new();
    };
    for _ in 0..rounds {
        let attached = attach(samples, decimated);
        let back = BackSamples::new(decimated, closest, surface_points);
        // Per triangle, the original vertex attached nearest its middle (the largest
        // smallest barycentric coordinate): where the facing test's search starts.
        let mut seeds: Vec<(f64, u32)> =
            vec![(f64::NEG_INFINITY, u32::MAX); decimated.triangles.len()];
        if surface.is_some() {
            for (i, &(t, b)) in attached.iter().enumerate() {
                if !on_surface[i] {
                    continue;
                }
                let depth = b[0].min(b[1]).min(b[2]);
                if depth > seeds[t as usize].0 {
                    seeds[t as usize] = (depth, i as u32);
                }
            }
        }
        // Per node, the attached points whose triangle it is a corner of (CSR, in point order).
        let mut first = vec![0u32; n + 1];
        for (&(t, _), _) in attached.iter().zip(&on_surface).filter(|(_, &u)| u) {
            for &v in &decimated.triangles[t as usize] {
                first[v as usize + 1] += 1;
            }
        }
        for v in 0..n {
            first[v + 1] += first[v];
        }
        let mut fill = first.clone();
        let mut points = vec![0u32; first[n] as usize];
        for (i, &(t, _)) in attached.iter().enumerate() {
            if !on_surface[i] {
                continue;
            }
            for &v in &decimated.triangles[t as usize] {
                points[fill[v as usize] as usize] = i as u32;
                fill[v as usize] += 1;
            }
        }
        for _ in 0..SWEEPS {
            for v in 0..n {
                let mine = &points[first[v] as usize..first[v + 1] as usize];
                let triangles = &around.1[around.0[v] as usize..around.0[v + 1] as usize];
                let forward = mine.iter().map(|&i| {
                    let (t, b) = attached[i as usize];
                    (t, b, samples[i as usize], 1.0)
                });
                let backward = triangles.iter().flat_map(|&t| back.of(t));
                let surface_target =
                    node_target(forward.chain(backward), decimated, v, start[v], normals[v]);
                let across =
                    normals[v].and_then(|n| arcs.shift(samples, decimated, v, start[v], n));
                let target = match (surface_target, across) {
                    (Some(x), Some(d)) => Some(std::array::from_fn(|c| x[c] + d[c])),
                    (Some(x), None) => Some(x),
                    (None, Some(d)) => Some(std::array::from_fn(|c| start[v][c] + d[c])),
                    (None, None) => None,
                };
                let Some(target) = target
                    .filter(|x: &[f64; 3]| x.iter().all(|c| c.is_finite()))
                    .and_then(|x| origin.snap(x))
                else {
                    continue;
                };
                let x = decimated.vertices[v];
                let step2: f64 = (0..3).map(|c| (target[c] - x[c]).powi(2)).sum();
                if step2 <= negligible2 {
                    continue;
                }
                // Triangle `t`'s corners with `v` at its target.
                let moved = |t: u32| {
                    decimated.triangles[t as usize].map(|i| {
                        if i as usize == v {
                            target
                        } else {
                            decimated.vertices[i as usize]
                        }
                    })
                };
                let ok = triangles.iter().all(|&t| {
                    let c = moved(t);
                    before[t as usize].is_some_and(|n| normals_agree(n, c))
                        && (!facing[t as usize]
                            || dot(
                                area_vector(c[0], c[1], c[2]),
                                corner_normal(decimated.triangles[t as usize]),
                            ) > 0.0)
                }) && surface.is_none_or(|s| {
                    triangles.iter().all(|&t| {
                        let c = moved(t);
                        let seed = match seeds[t as usize].1 {
                            u32::MAX => kept[v],
                            i => i,
                        };
                        !s.faces_against(c, &[seed])
                    })
                });
                if ok {
                    decimated.vertices[v] = target;
                }
            }
        }
    }
    (0..n)
        .filter(|&v| decimated.vertices[v] != start[v])
        .map(|v| Moved {
            node: kept[v],
            from: start[v],
            to: decimated.vertices[v],
        })
        .collect()
}

/// Per node on a border, its unit normal (the sum of its triangles' area vectors,
/// normalised; `None` inside or when that sum vanishes): border nodes move only along it,
/// so that the fit does not pull borders in along the surface.
fn border_normals(mesh: &Mesh) -> Vec<Option<[f64; 3]>> {
    let n = mesh.vertices.len();
    let on_border = mesh.border_vertices();
    let mut sum = vec![[0.0; 3]; n];
    for tri in &mesh.triangles {
        let [a, b, c] = tri.map(|i| mesh.vertices[i as usize]);
        let m = area_vector(a, b, c);
        for &i in tri {
            for k in 0..3 {
                sum[i as usize][k] += m[k];
            }
        }
    }
    (0..n)
        .map(|v| {
            let m = sum[v];
            let l = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
            (on_border[v] && l > 0.0 && l.is_finite()).then(|| [m[0] / l, m[1] / l, m[2] / l])
        })
        .collect()
}

/// Points of the result pulled back to the original (module docs): [`BACK_SAMPLES`] per
/// triangle, each pulled to its closest point on the original surface and weighted by
/// [`BACK_WEIGHT`] times the original vertices' density on the result (their count over its
/// area) times its share of the triangle's area, so that a unit of area pulls back half as
/// much as its original vertices pull forward. The forward pulls alone leave the inside of a
/// triangle free to lie far from the surface (across a groove, over a bump between its
/// corners).
struct BackSamples {
    /// Per triangle `t`, its samples `pulls[t · BACK_SAMPLES..][..BACK_SAMPLES]`.
    pulls: Vec<(u32, [f64; 3], [f64; 3], f64)>,
}

/// The barycentric coordinates of the points of a triangle pulled back to the original.
const BACK_POINTS: [[f64; 3]; 4] = [
    [1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0],
    [2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0],
    [1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0],
    [1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0],
];

/// Points per triangle pulled back to the original (module docs).
pub const BACK_SAMPLES: usize = BACK_POINTS.len();

/// How much the pulls back weigh against the original vertices' pulls forward, per unit of
/// area: half (at the same triangle count, on pymeshlab's cow, the bunny, Kuen's and
/// Henneberg's surfaces and the airplane, a weight of 1 or 2 cost forward RMS for little
/// more Hausdorff gain, and 0.25 lost most of that gain).
pub const BACK_WEIGHT: f64 = 0.5;

impl BackSamples {
    /// The pulls of `decimated`'s triangles where they are now, towards their closest points
    /// on the original (`closest`), which has `points` vertices on its surface (on all cores,
    /// each a function of its point alone).
    fn new(decimated: &Mesh, closest: &ClosestPoints, points: usize) -> Self {
        use crate::par::prelude::*;
        let corners = |t: &[u32; 3]| t.map(|i| decimated.vertices[i as usize]);
        let area = |c: [[f64; 3]; 3]| {
            let m = area_vector(c[0], c[1], c[2]);
            0.5 * (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt()
        };
        let total: f64 = decimated.triangles.iter().map(|t| area(corners(t))).sum();
        let density = if total > 0.0 && total.is_finite() {
            points as f64 / total
        } else {
            0.0
        };
        let pulls = decimated
            .triangles
            .par_iter()
            .enumerate()
            .map(|(t, tri)| {
                let c = corners(tri);
                let w = BACK_WEIGHT * density * area(c) / BACK_SAMPLES as f64;
                BACK_POINTS.map(|b| {
                    let p =
                        std::array::from_fn(|k| b[0] * c[0][k] + b[1] * c[1][k] + b[2] * c[2][k]);
                    let to = closest.query(p).point;
                    let ok = w.is_finite() && to.iter().all(|x| x.is_finite());
                    (
                        t as u32,
                        b,
                        if ok { to } else { p },
                        if ok { w } else { 0.0 },
                    )
                })
            })
            .flatten_iter()
            .collect();
        BackSamples { pulls }
    }

    /// The pulls on triangle `t`.
    fn of(&self, t: u32) -> impl Iterator<Item = (u32, [f64; 3], [f64; 3], f64)> + '_ {
        self.pulls[t as usize * BACK_SAMPLES..][..BACK_SAMPLES]
            .iter()
            .copied()
    }
}

/// The border of the result against the border of the original (module docs): node
/// removal keeps a subset of the original vertices and never closes or joins a border loop,
/// so each border edge `a → b` of the result (as its triangle traverses it) stands for the
/// arc of the original border from `a` up to `b`. A border node moves across its border
/// (in the surface, perpendicular to the border) to the least-squares fit of the arcs of its
/// two border edges, each arc vertex attached to its closest point on its edge; that lets
/// the border chords straddle a curved original border instead of cutting inside it.
struct BorderArcs {
    /// The result's border edges `[a, b]` (decimated vertex ids).
    edges: Vec<[u32; 2]>,
    /// The original vertices edge `e` stands for, `points[first[e]..first[e + 1]]`: `a` and
    /// the arc's vertices after it, before `b` (each original border vertex of a kept arc
    /// once, so every arc's start counts once).
    first: Vec<u32>,
    points: Vec<u32>,
    /// Per decimated vertex, the border edge arriving at it and the one leaving it
    /// (`u32::MAX` for none, or where more than one does).
    into: Vec<u32>,
    out: Vec<u32>,
}

impl BorderArcs {
    /// The arcs of `decimated`'s border edges in `original` (vertex `k` of `decimated` is
    /// node `kept[k]`). An edge whose arc cannot be followed (a vertex where more than one
    /// border edge leaves, as at a bow-tie, or a walk that does not reach its end) has none.
    fn new(original: &Mesh, decimated: &Mesh, kept: &[u32]) -> Self {
        const NONE: u32 = u32::MAX;
        let n = decimated.vertices.len();
        let mut arcs = BorderArcs {
            edges: Vec::new(),
            first: vec![0],
            points: Vec::new(),
            into: vec![NONE; n],
            out: vec![NONE; n],
        };
        let result_edges = decimated.border_edges();
        if result_edges.is_empty() {
            return arcs;
        }
        let next = border_successors(original);
        let mut leaving = vec![0u8; n];
        for &[a, _] in &result_edges {
            leaving[a as usize] = leaving[a as usize].saturating_add(1);
        }
        for [a, b] in result_edges {
            let (u, w) = (kept[a as usize], kept[b as usize]);
            let mark = arcs.points.len();
            arcs.points.push(u);
            let mut o = next[u as usize];
            while o != w
                && o != NONE
                && o != u
                && arcs.points.len() - mark <= original.vertices.len()
            {
                arcs.points.push(o);
                o = next[o as usize];
            }
            if o != w || leaving[a as usize] != 1 {
                arcs.points.truncate(mark);
                continue;
            }
            let e = arcs.edges.len() as u32;
            arcs.edges.push([a, b]);
            arcs.first.push(arcs.points.len() as u32);
            for (end, v) in [(&mut arcs.out, a), (&mut arcs.into, b)] {
                end[v as usize] = if end[v as usize] == NONE { e } else { NONE - 1 };
            }
        }
        for end in [&mut arcs.out, &mut arcs.into] {
            for x in end.iter_mut().filter(|x| **x == NONE - 1) {
                *x = NONE;
            }
        }
        arcs
    }

    /// The move of border node `v` from `start` (its place before the fit) across its border
    /// (perpendicular to its unit `normal` and to the border's direction at it) that fits
    /// its edges' arcs best, the other nodes where they are (the isotropic least squares with
    /// the regulariser, projected on that line); `None` when `v` has no arc or the direction
    /// is not defined.
    fn shift(
        &self,
        samples: &[[f64; 3]],
        decimated: &Mesh,
        v: usize,
        start: [f64; 3],
        normal: [f64; 3],
    ) -> Option<[f64; 3]> {
        let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let edges = [self.into[v], self.out[v]];
        let pos = |i: u32| decimated.vertices[i as usize];
        let x = pos(v as u32);
        // The border's direction at v: from the start of the edge in to the end of the edge
        // out (either alone when the other has no arc).
        let (from, to) = match edges.map(|e| self.edges.get(e as usize)) {
            [Some(&[p, _]), Some(&[_, q])] => (pos(p), pos(q)),
            [Some(&[p, _]), None] => (pos(p), x),
            [None, Some(&[_, q])] => (x, pos(q)),
            [None, None] => return None,
        };
        if let [Some(&[p, _]), Some(&[_, q])] = edges.map(|e| self.edges.get(e as usize)) {
            // A corner of the border: no direction across it.
            let (a, b) = (sub(x, pos(p)), sub(pos(q), x));
            let (la, lb) = (dot(a, a).sqrt(), dot(b, b).sqrt());
            let gentle = dot(a, b) >= CORNER_COS * la * lb;
            if !gentle {
                return None;
            }
        }
        let e = sub(to, from);
        let m = [
            normal[1] * e[2] - normal[2] * e[1],
            normal[2] * e[0] - normal[0] * e[2],
            normal[0] * e[1] - normal[1] * e[0],
        ];
        let lm = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
        if !(lm > 0.0 && lm.is_finite()) {
            return None;
        }
        let m = m.map(|c| c / lm);
        let (mut num, mut den) = ([0.0; 3], 0.0);
        for e in edges
            .into_iter()
            .filter(|&e| (e as usize) < self.edges.len())
        {
            let [a, b] = self.edges[e as usize];
            let (xa, xb) = (pos(a), pos(b));
            let ab = [xb[0] - xa[0], xb[1] - xa[1], xb[2] - xa[2]];
            let l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
            if l2.is_nan() || l2 <= 0.0 {
                continue;
            }
            let (other, xo) = if a as usize == v { (b, xb) } else { (a, xa) };
            let range = self.first[e as usize] as usize..self.first[e as usize + 1] as usize;
            for &i in &self.points[range] {
                let o = samples[i as usize];
                let t =
                    (((o[0] - xa[0]) * ab[0] + (o[1] - xa[1]) * ab[1] + (o[2] - xa[2]) * ab[2])
                        / l2)
                        .clamp(0.0, 1.0);
                // v's weight in the attached point, and the other end's.
                let (bv, bo) = if other == b {
                    (1.0 - t, t)
                } else {
                    (t, 1.0 - t)
                };
                for c in 0..3 {
                    num[c] += bv * (o[c] - bo * xo[c]);
                }
                den += bv * bv;
            }
        }
        if den.is_nan() || den <= 0.0 {
            return None;
        }
        // The regulariser holds v near its start, as the surface fit does.
        let reg = REGULARISER * (1.0 + den);
        let fit: [f64; 3] = std::array::from_fn(|c| (num[c] + reg * start[c]) / (den + reg));
        let r = ACROSS_SHARE * dot(sub(fit, start), m);
        r.is_finite().then(|| m.map(|c| r * c))
    }
}

/// Per vertex of `mesh`, the end `b` of the one border edge `v → b` leaving it
/// ([`Mesh::border_edges`]); `u32::MAX` for a vertex with none or with more than one. Read off the
/// triangles around each vertex (an edge `v → b` is on the border when no triangle around
/// `v` has `b` just before it).
fn border_successors(mesh: &Mesh) -> Vec<u32> {
    use crate::par::prelude::*;
    let n = mesh.vertices.len();
    let (first, around) = crate::mesh::incident_triangles(n, &mesh.triangles);
    (0..n)
        .into_par_iter()
        .map(|v| {
            let ts = &around[first[v] as usize..first[v + 1] as usize];
            let corner = |t: u32, step: usize| {
                let tri = mesh.triangles[t as usize];
                let k = tri.iter().position(|&i| i as usize == v).unwrap_or(0);
                tri[(k + step) % 3]
            };
            let mut found = u32::MAX;
            for &t in ts {
                let b = corner(t, 1);
                if ts.iter().all(|&s| corner(s, 2) != b) {
                    if found != u32::MAX {
                        return u32::MAX;
                    }
                    found = b;
                }
            }
            found
        })
        .collect()
}

/// Every sample's closest point on `decimated`: its triangle and barycentric coordinates
/// there (on all cores; each a function of its point alone). Searching only near the
/// previous round's triangle was tried: starting the search there saved 8 %, searching only
/// the triangles around its corners cost 25 % more than the hierarchy.
fn attach(samples: &[[f64; 3]], decimated: &Mesh) -> Vec<(u32, [f64; 3])> {
    use crate::par::prelude::*;
    let Some(cp) = ClosestPoints::new(decimated) else {
        return Vec::new();
    };
    samples
        .par_iter()
        .map(|&o| {
            let c = cp.query(o);
            let t =
                decimated.triangles[c.triangle as usize].map(|i| decimated.vertices[i as usize]);
            (c.triangle, barycentric(c.point, t))
        })
        .collect()
}

/// The barycentric coordinates of `p` (a point of the triangle's plane) in triangle `t`
/// (least squares in the plane; `(1, 0, 0)` for a degenerate triangle).
fn barycentric(p: [f64; 3], t: [[f64; 3]; 3]) -> [f64; 3] {
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let (e0, e1, d) = (sub(t[1], t[0]), sub(t[2], t[0]), sub(p, t[0]));
    let (a00, a01, a11) = (dot(e0, e0), dot(e0, e1), dot(e1, e1));
    let (b0, b1) = (dot(d, e0), dot(d, e1));
    let den = a00 * a11 - a01 * a01;
    if den.is_nan() || den <= 0.0 {
        return [1.0, 0.0, 0.0];
    }
    let s = (a11 * b0 - a01 * b1) / den;
    let u = (a00 * b1 - a01 * b0) / den;
    [1.0 - s - u, s, u]
}

/// The Gauss–Seidel update of node `v` (module docs) from the points pulling on its
/// triangles, each `(triangle, barycentric coordinates, where it is pulled to, weight)`, the
/// other corners where they are now; `None` when no point constrains it or the result is not
/// finite. With a `normal` (a border node) the move is projected onto it (the isotropic least
/// squares' minimum on that line).
fn node_target(
    pulls: impl Iterator<Item = (u32, [f64; 3], [f64; 3], f64)>,
    decimated: &Mesh,
    v: usize,
    start: [f64; 3],
    normal: Option<[f64; 3]>,
) -> Option<[f64; 3]> {
    let mut num = [0.0; 3];
    let mut den = 0.0;
    for (t, b, to, w) in pulls {
        let tri = decimated.triangles[t as usize];
        let mut rest = to;
        let mut bv = 0.0;
        for k in 0..3 {
            if tri[k] as usize == v {
                bv += b[k];
            } else {
                let x = decimated.vertices[tri[k] as usize];
                for c in 0..3 {
                    rest[c] -= b[k] * x[c];
                }
            }
        }
        for c in 0..3 {
            num[c] += w * bv * rest[c];
        }
        den += w * bv * bv;
    }
    if den.is_nan() || den <= 0.0 {
        return None;
    }
    let m = REGULARISER * (1.0 + den);
    let mut x: [f64; 3] = std::array::from_fn(|c| (num[c] + m * start[c]) / (den + m));
    if let Some(n) = normal {
        let s = (x[0] - start[0]) * n[0] + (x[1] - start[1]) * n[1] + (x[2] - start[2]) * n[2];
        x = std::array::from_fn(|c| start[c] + s * n[c]);
    }
    x.iter().all(|c| c.is_finite()).then_some(x)
}

/// The area vector of triangle `t` when `f64` gets its direction right to within 1e-8 (its
/// length at least 1e-6 of `|b − a||c − a|`, finite), else `None`: each computed component
/// of `(b − a) × (c − a)` is within `8ε|b − a||c − a|` of the true one (ε = 2⁻⁵³), so the
/// computed vector is within `14ε` of that product, a relative error below 3.2·10⁻⁹.
pub fn trusted_normal(t: [[f64; 3]; 3]) -> Option<[f64; 3]> {
    let [a, b, c] = t;
    let m = area_vector(a, b, c);
    let len = |u: [f64; 3], w: [f64; 3]| {
        ((u[0] - w[0]).powi(2) + (u[1] - w[1]).powi(2) + (u[2] - w[2]).powi(2)).sqrt()
    };
    let lm = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
    // `area_vector` is the cross product itself.
    (lm.is_finite() && lm > 0.0 && lm >= 1e-6 * len(b, a) * len(c, a)).then_some(m)
}

/// Whether the triangle `after` keeps a normal within the fit's angle ([`MIN_COS`]) of
/// `before` (a [`trusted_normal`]), in `f64`; `false` when `after`'s normal is not trusted.
/// Both directions being right to 3.2·10⁻⁹, an accepted cosine of at least 0.3 is truly
/// above 0.3 − 10⁻⁸: the exact dot product ([`normals_agree_exactly`]) is positive.
pub fn normals_agree(before: [f64; 3], after: [[f64; 3]; 3]) -> bool {
    let Some(m) = trusted_normal(after) else {
        return false;
    };
    let dot = before[0] * m[0] + before[1] * m[1] + before[2] * m[2];
    let lb = (before[0] * before[0] + before[1] * before[1] + before[2] * before[2]).sqrt();
    let lm = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
    dot >= MIN_COS * lb * lm
}

/// The exact sign test behind the fit's guarantee: whether `(b − a) × (c − a)` of `after`
/// has a positive dot product with `(b − a) × (c − a)` of `before` (finite coordinates), in
/// integers over a shared power of two.
pub fn normals_agree_exactly(before: [[f64; 3]; 3], after: [[f64; 3]; 3]) -> bool {
    let coords: Vec<f64> = before
        .iter()
        .chain(after.iter())
        .flatten()
        .copied()
        .collect();
    let (ints, _) = f64s_over_shared_power(&coords);
    let normal = |p: &[BigInt]| {
        let d = |i: usize, k: usize| &p[3 * i + k] - &p[k];
        let (u, w) = ([d(1, 0), d(1, 1), d(1, 2)], [d(2, 0), d(2, 1), d(2, 2)]);
        [
            &u[1] * &w[2] - &u[2] * &w[1],
            &u[2] * &w[0] - &u[0] * &w[2],
            &u[0] * &w[1] - &u[1] * &w[0],
        ]
    };
    let (n0, n1) = (normal(&ints[..9]), normal(&ints[9..]));
    (&n0[0] * &n1[0] + &n0[1] * &n1[1] + &n0[2] * &n1[2]).is_positive()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_agreement_matches_the_rational_formula() {
        use crate::num::{rational_from_f64, Rational};
        let mut rng = crate::decimate::TestRng(0x05ee_df17);
        for _ in 0..2000 {
            let mut coord = || {
                let m = (rng.below(2001) as f64 - 1000.0) / 64.0;
                m * [1.0, 1e-9, 3.0e7][rng.below(3) as usize]
            };
            let tri = |c: &mut dyn FnMut() -> f64| -> [[f64; 3]; 3] {
                std::array::from_fn(|_| [c(), c(), c()])
            };
            let (x, y) = (tri(&mut coord), tri(&mut coord));
            let q = |t: [[f64; 3]; 3]| {
                t.map(|p| p.map(|c| rational_from_f64(c, "coordinate").unwrap()))
            };
            let normal = |t: [[Rational; 3]; 3]| {
                let d = |i: usize, k: usize| &t[i][k] - &t[0][k];
                let (u, w) = ([d(1, 0), d(1, 1), d(1, 2)], [d(2, 0), d(2, 1), d(2, 2)]);
                [
                    &u[1] * &w[2] - &u[2] * &w[1],
                    &u[2] * &w[0] - &u[0] * &w[2],
                    &u[0] * &w[1] - &u[1] * &w[0],
                ]
            };
            let (a, b) = (normal(q(x)), normal(q(y)));
            let dot = &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2];
            assert_eq!(
                normals_agree_exactly(x, y),
                dot.is_positive(),
                "{x:?} {y:?}"
            );
        }
    }

    #[test]
    fn the_filter_never_accepts_what_exact_signs_refuse() {
        let mut rng = crate::decimate::TestRng(0xf11e);
        let mut accepted = 0;
        for _ in 0..5000 {
            let s = (rng.below(1000) as f64) / 1000.0;
            let eps = [1e-3, 1e-9, 1e-15][rng.below(3) as usize];
            let mut c = || (rng.below(1 << 20) as f64 - (1 << 19) as f64) / 1024.0;
            let before: [[f64; 3]; 3] = std::array::from_fn(|_| [c(), c(), c()]);
            let mut after = before;
            // Nearly degenerate: the third corner close to the line of the first two.
            after[2] = std::array::from_fn(|k| {
                before[0][k] + s * (before[1][k] - before[0][k]) + eps * (c() - c())
            });
            let Some(n) = trusted_normal(before) else {
                continue;
            };
            if normals_agree(n, after) {
                accepted += 1;
                assert!(normals_agree_exactly(before, after), "{before:?} {after:?}");
            }
        }
        println!(
            "filter: {accepted} of 5000 near-degenerate moves accepted, all confirmed exactly"
        );
    }

    #[test]
    fn fitting_a_chord_moves_it_onto_the_arc_and_flips_nothing() {
        // A fine cylinder patch (radius 1) decimated to its outer columns: the chord lies
        // inside; the fit must move it outward toward the arc and reduce the RMS distance.
        let (cols, rows) = (33usize, 5usize);
        let mut original = Mesh::default();
        for r in 0..rows {
            for c in 0..cols {
                let a = -0.6 + 1.2 * c as f64 / (cols - 1) as f64;
                original.vertices.push([a.sin(), r as f64 * 0.25, a.cos()]);
            }
        }
        let id = |r: usize, c: usize| (r * cols + c) as u32;
        for r in 0..rows - 1 {
            for c in 0..cols - 1 {
                original
                    .triangles
                    .push([id(r, c), id(r + 1, c + 1), id(r, c + 1)]);
                original
                    .triangles
                    .push([id(r, c), id(r + 1, c), id(r + 1, c + 1)]);
            }
        }
        let kept: Vec<u32> = (0..rows)
            .flat_map(|r| [0, cols / 2, cols - 1].map(|c| id(r, c)))
            .collect();
        let mut coarse = Mesh {
            vertices: kept
                .iter()
                .map(|&k| original.vertices[k as usize])
                .collect(),
            ..Mesh::default()
        };
        for r in 0..rows - 1 {
            for c in 0..2 {
                let v = |r: usize, c: usize| (3 * r + c) as u32;
                coarse
                    .triangles
                    .push([v(r, c), v(r + 1, c + 1), v(r, c + 1)]);
                coarse
                    .triangles
                    .push([v(r, c), v(r + 1, c), v(r + 1, c + 1)]);
            }
        }
        let rms = |m: &Mesh| crate::decimate::quality::deviation(&original, m).forward_rms;
        let before_mesh = coarse.clone();
        let before = rms(&coarse);
        let moves = fit(&original, &mut coarse, &kept, 2, None);
        let after = rms(&coarse);
        println!(
            "chord fit: {} moves, RMS {before:.5} → {after:.5}",
            moves.len()
        );
        assert!(!moves.is_empty());
        assert!(after < 0.6 * before, "{before} → {after}");
        for m in &moves {
            let k = kept.iter().position(|&x| x == m.node).unwrap();
            assert_eq!(m.from, before_mesh.vertices[k]);
            assert_eq!(m.to, coarse.vertices[k]);
        }
        for (t, tri) in coarse.triangles.iter().enumerate() {
            let x = tri.map(|i| before_mesh.vertices[i as usize]);
            let y = tri.map(|i| coarse.vertices[i as usize]);
            assert!(normals_agree_exactly(x, y), "triangle {t} flipped");
        }
    }

    /// A flat disc of radius 1: its centre and `n` border points, fanned.
    fn disc(n: usize) -> Mesh {
        let mut m = Mesh::default();
        m.vertices.push([0.0, 0.0, 0.0]);
        for i in 0..n {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            m.vertices.push([a.cos(), a.sin(), 0.0]);
        }
        for i in 0..n {
            m.triangles
                .push([0, 1 + i as u32, 1 + ((i + 1) % n) as u32]);
        }
        m
    }

    /// A disc of `n` border points and its decimation to every `step`-th of them: (original,
    /// decimated, the decimated vertices' ids in the original).
    fn decimated_disc(n: usize, step: usize) -> (Mesh, Mesh, Vec<u32>) {
        let original = disc(n);
        let kept: Vec<u32> = std::iter::once(0)
            .chain((0..n / step).map(|k| 1 + (k * step) as u32))
            .collect();
        let mut coarse = disc(n / step);
        coarse.vertices = kept
            .iter()
            .map(|&k| original.vertices[k as usize])
            .collect();
        (original, coarse, kept)
    }

    /// The largest distance from the original's border vertices to the border of `m` (in
    /// the plane z = 0).
    fn border_gap(original: &Mesh, m: &Mesh) -> f64 {
        let edges = m.border_edges();
        let on = original.border_vertices();
        (0..original.vertices.len())
            .filter(|&i| on[i])
            .map(|i| {
                let o = original.vertices[i];
                edges
                    .iter()
                    .map(|&[a, b]| {
                        let (p, q) = (m.vertices[a as usize], m.vertices[b as usize]);
                        let d = [q[0] - p[0], q[1] - p[1]];
                        let t = (((o[0] - p[0]) * d[0] + (o[1] - p[1]) * d[1])
                            / (d[0] * d[0] + d[1] * d[1]))
                            .clamp(0.0, 1.0);
                        (o[0] - p[0] - t * d[0]).hypot(o[1] - p[1] - t * d[1])
                    })
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn border_arcs_partition_the_original_border() {
        let (n, step) = (96usize, 8usize);
        let (original, coarse, kept) = decimated_disc(n, step);
        let arcs = BorderArcs::new(&original, &coarse, &kept);
        assert_eq!(arcs.edges.len(), n / step);
        let mut seen = vec![0; original.vertices.len()];
        for (e, &[a, b]) in arcs.edges.iter().enumerate() {
            assert_eq!(arcs.out[a as usize], e as u32);
            assert_eq!(arcs.into[b as usize], e as u32);
            let points = &arcs.points[arcs.first[e] as usize..arcs.first[e + 1] as usize];
            assert_eq!(points.len(), step, "edge {e}");
            assert_eq!(points[0], kept[a as usize]);
            for &p in points {
                seen[p as usize] += 1;
            }
        }
        assert_eq!(seen[0], 0);
        assert!(seen[1..].iter().all(|&c| c == 1), "{seen:?}");
        assert_eq!(arcs.into[0], u32::MAX);
        assert_eq!(arcs.out[0], u32::MAX);
    }

    #[test]
    fn a_coarse_border_straddles_the_arc_it_stands_for() {
        // A flat disc with 96 border points decimated to 12: each border chord cuts inside
        // the circle by its sagitta h; moved across the border, the chords straddle it and
        // the border's largest gap falls to about h/2 (ACROSS_SHARE), nothing leaves the
        // plane and no triangle flips.
        let (n, step) = (96usize, 8usize);
        let (original, mut coarse, kept) = decimated_disc(n, step);
        let before_mesh = coarse.clone();
        let sagitta = 1.0 - (std::f64::consts::PI / (n / step) as f64).cos();
        let before = border_gap(&original, &coarse);
        assert!((before - sagitta).abs() < 1e-12, "{before} {sagitta}");
        let moves = fit(&original, &mut coarse, &kept, 2, None);
        let after = border_gap(&original, &coarse);
        println!(
            "disc border: {} moves, largest border gap {before:.5} → {after:.5} (sagitta {sagitta:.5})",
            moves.len()
        );
        assert!(
            after < 0.6 * before && after > 0.4 * before,
            "{before} → {after}"
        );
        // The centre, pulled alike from every side, stays near its place.
        let centre = coarse.vertices[0];
        assert!(centre[0].hypot(centre[1]) < 1e-2 * sagitta, "{centre:?}");
        let border: Vec<&Moved> = moves.iter().filter(|m| m.node != 0).collect();
        assert_eq!(border.len(), n / step, "every border node moves");
        for m in border {
            let r = m.to[0].hypot(m.to[1]);
            assert!(
                r > 1.0 && r < 1.0 + sagitta,
                "node {} to radius {r}",
                m.node
            );
            assert_eq!(m.to[2], 0.0);
        }
        for (t, tri) in coarse.triangles.iter().enumerate() {
            let x = tri.map(|i| before_mesh.vertices[i as usize]);
            let y = tri.map(|i| coarse.vertices[i as usize]);
            assert!(normals_agree_exactly(x, y), "triangle {t} flipped");
        }
    }

    #[test]
    fn straight_borders_and_corners_stay_where_they_are() {
        // A flat 9 × 9 grid decimated to its 3 × 3 subgrid: every original vertex lies on
        // the result already, so nothing moves (no spurious move across a straight border,
        // none at the corners).
        let side = 9usize;
        let grid = |s: usize, every: usize| {
            let mut m = Mesh::default();
            for r in (0..s).step_by(every) {
                for c in (0..s).step_by(every) {
                    m.vertices.push([c as f64, r as f64, 0.0]);
                }
            }
            let w = (s - 1) / every + 1;
            let id = |r: usize, c: usize| (r * w + c) as u32;
            for r in 0..w - 1 {
                for c in 0..w - 1 {
                    m.triangles.push([id(r, c), id(r, c + 1), id(r + 1, c + 1)]);
                    m.triangles.push([id(r, c), id(r + 1, c + 1), id(r + 1, c)]);
                }
            }
            m
        };
        let original = grid(side, 1);
        let mut coarse = grid(side, 4);
        let kept: Vec<u32> = (0..side)
            .step_by(4)
            .flat_map(|r| (0..side).step_by(4).map(move |c| (r * side + c) as u32))
            .collect();
        for (k, &o) in kept.iter().enumerate() {
            assert_eq!(coarse.vertices[k], original.vertices[o as usize]);
        }
        let arcs = BorderArcs::new(&original, &coarse, &kept);
        assert_eq!(arcs.edges.len(), 8);
        let moves = fit(&original, &mut coarse, &kept, 2, None);
        assert!(moves.is_empty(), "{moves:?}");
    }

    #[test]
    fn corners_of_a_border_do_not_move_across_it() {
        // A flat quarter disc fanned from its centre: its border is two radii and an arc
        // meeting at right angles. Decimated to every 8th arc point, the arc's inner nodes
        // move out across the border; its two ends are corners (90°) and stay, though the arc
        // beside each would pull it out.
        let (n, step) = (48usize, 8usize);
        let sector = |count: usize, every: usize| {
            let mut m = Mesh::default();
            m.vertices.push([0.0, 0.0, 0.0]);
            for i in (0..=count).step_by(every) {
                let a = std::f64::consts::FRAC_PI_2 * i as f64 / count as f64;
                m.vertices.push([a.cos(), a.sin(), 0.0]);
            }
            for i in 1..m.vertices.len() as u32 - 1 {
                m.triangles.push([0, i, i + 1]);
            }
            m
        };
        let original = sector(n, 1);
        let mut coarse = sector(n, step);
        let kept: Vec<u32> = std::iter::once(0)
            .chain((0..=n).step_by(step).map(|i| 1 + i as u32))
            .collect();
        for (k, &o) in kept.iter().enumerate() {
            assert_eq!(coarse.vertices[k], original.vertices[o as usize]);
        }
        let moves = fit(&original, &mut coarse, &kept, 2, None);
        let ends = [kept[1], kept[kept.len() - 1]];
        let arc: Vec<&Moved> = moves
            .iter()
            .filter(|m| m.node != 0 && !ends.contains(&m.node))
            .collect();
        assert_eq!(arc.len(), n / step - 1, "{moves:?}");
        for m in arc {
            assert!(m.to[0].hypot(m.to[1]) > 1.0, "{m:?}");
        }
        for m in moves.iter().filter(|m| ends.contains(&m.node)) {
            // Pulled along the surface by its triangle's points at most, never out.
            assert!(m.to[0].hypot(m.to[1]) <= 1.0, "corner {m:?}");
        }
    }

    #[test]
    fn pulls_back_land_on_the_original_and_weigh_half_its_vertices() {
        // A fine disc and its 12-gon: every pull back lands on the fine disc (within it, so
        // at the point itself) and the weights add up to BACK_WEIGHT per original vertex.
        let (original, mut coarse, _) = decimated_disc(96, 8);
        let closest = ClosestPoints::new(&original).unwrap();
        let back = BackSamples::new(&coarse, &closest, original.vertices.len());
        assert_eq!(back.pulls.len(), BACK_SAMPLES * coarse.triangles.len());
        let total: f64 = back.pulls.iter().map(|p| p.3).sum();
        let want = BACK_WEIGHT * original.vertices.len() as f64;
        assert!((total - want).abs() < 1e-9 * want, "{total} {want}");
        for t in 0..coarse.triangles.len() as u32 {
            for (tri, b, to, w) in back.of(t) {
                assert_eq!(tri, t);
                assert!(w > 0.0);
                let c = coarse.triangles[t as usize].map(|i| coarse.vertices[i as usize]);
                let p: [f64; 3] =
                    std::array::from_fn(|k| b[0] * c[0][k] + b[1] * c[1][k] + b[2] * c[2][k]);
                let d = (0..3).map(|k| (p[k] - to[k]).powi(2)).sum::<f64>().sqrt();
                assert!(d < 1e-12, "{p:?} → {to:?}");
            }
        }
        // Lifted off the plane, every pull lands back on it, straight below.
        for v in &mut coarse.vertices {
            v[2] = 0.25;
        }
        let back = BackSamples::new(&coarse, &closest, original.vertices.len());
        for &(_, _, to, _) in &back.pulls {
            assert_eq!(to[2], 0.0);
            assert!(to[0].hypot(to[1]) < 1.0);
        }
    }
}
