//! The reference path: rational coordinates and scalars, adjacency as each node's set of
//! incident triangle slots, every sign from an exact rational determinant, the criteria in
//! exact arithmetic (rounded once to `f64` to file the node in the queue).

use super::driver::{self, Engine, Removal};
use super::earcut::{ear_order, simple_ccw, EarCutter, Orient};
use super::history::History;
use super::quadric::fan_fills;
use super::quality::OriginalSurface;
use super::{
    canonical_start, check_options, edge_angle, fallback_planes, fan_normal, flip_toward_fan,
    global_plane, initial_quadrics, quadric_removal, BorderPolicy, Carried, Criterion,
    DecimateError, Options, Outcome, Plane, Quadric, QuadricRemoval,
};
use crate::mesh::{Mesh, Scalars};
use crate::num::{rational_from_f64, rational_to_f64, Rational};
use num_traits::{Signed, Zero};
use std::cmp::Ordering;
use std::collections::{BTreeMap, BTreeSet};
use std::sync::Arc;

/// `det[b − a, c − a]`, exactly.
fn orient(a: &[Rational; 2], b: &[Rational; 2], c: &[Rational; 2]) -> Ordering {
    let d = (&b[0] - &a[0]) * (&c[1] - &a[1]) - (&b[1] - &a[1]) * (&c[0] - &a[0]);
    d.cmp(&Rational::zero())
}

struct ExactOrient<'a>(&'a [[Rational; 2]]);

impl Orient for ExactOrient<'_> {
    fn orient(&self, a: usize, b: usize, c: usize) -> Ordering {
        orient(&self.0[a], &self.0[b], &self.0[c])
    }
}

/// A node's fan: its neighbours counter-clockwise and the slots of `(v, ring[i], ring[i+1])`.
struct Fan {
    ring: Vec<u32>,
    slots: Vec<u32>,
    border: bool,
}

/// A hole ready to be filled.
struct Hole {
    fan: Fan,
    plane: Plane,
    projected: Vec<[Rational; 2]>,
    triangles: Vec<[u8; 3]>,
    /// The cut's crossing deviation ([`flip_toward_fan`]; the quadric criterion only).
    crossing: f64,
}

pub(crate) struct ExactEngine {
    /// The input coordinates as given (the heuristics read these).
    float: Vec<[f64; 3]>,
    /// Removals by a fan fill ([`Engine::fan_filled`]).
    filled: usize,
    /// The original surface's vertex normals ([`vertex_normals`](super::vertex_normals);
    /// [`Criterion::Quadric`] without the facing test only, else empty: the fold test's
    /// corner normals, [`folds`](super::folds)).
    normals: Vec<[f64; 3]>,
    /// The original surface for the facing test at removals
    /// ([`faces_against_original`](super::quadric::faces_against_original);
    /// [`Criterion::Quadric`] only).
    original: Option<Arc<OriginalSurface>>,
    coords: Vec<[Rational; 3]>,
    values: Option<Vec<Rational>>,
    slots: Vec<Option<[u32; 3]>>,
    incident: Vec<BTreeSet<u32>>,
    removed: Vec<bool>,
    global: Option<Plane>,
    criterion: Criterion,
    border_policy: BorderPolicy,
    max_valence: usize,
    cutter: EarCutter,
    /// Per node, its accumulated quadric ([`Criterion::Quadric`]; empty otherwise), in `f64`
    /// exactly as the fast path keeps them.
    quadrics: Vec<Quadric>,
    /// Per triangle slot, the bound on how far the original points it covers lie from it
    /// ([`Criterion::Quadric`]; empty otherwise).
    slot_error: Vec<f64>,
}

impl ExactEngine {
    pub(crate) fn new(mesh: &Mesh, options: &Options) -> Result<ExactEngine, DecimateError> {
        mesh.validate()?;
        mesh.check_manifold()?;
        check_options(mesh, options)?;
        let exact = |x: f64| rational_from_f64(x, "coordinate").expect("validated finite");
        let coords: Vec<[Rational; 3]> = mesh
            .vertices
            .iter()
            .map(|p| [exact(p[0]), exact(p[1]), exact(p[2])])
            .collect();
        let mut incident = vec![BTreeSet::new(); mesh.vertices.len()];
        for (s, t) in mesh.triangles.iter().enumerate() {
            for &v in t {
                incident[v as usize].insert(s as u32);
            }
        }
        let global = global_plane(mesh, options.projection, |t| {
            let p = t.map(|i| xy(&coords[i as usize]));
            orient(&p[0], &p[1], &p[2]) != Ordering::Greater
        })?;
        let criterion = options.criterion.resolve(global.is_some());
        let original = if global.is_none() && options.facing {
            OriginalSurface::new(mesh).map(Arc::new)
        } else {
            None
        };
        Ok(ExactEngine {
            float: mesh.vertices.clone(),
            filled: 0,
            // The corner-normal fold test stands in for the facing test ([`super::folds`]).
            normals: if criterion == Criterion::Quadric && original.is_none() {
                super::vertex_normals(mesh)
            } else {
                Vec::new()
            },
            original,
            coords,
            values: mesh
                .scalars
                .as_ref()
                .map(|s| s.values.iter().map(|&x| exact(x)).collect()),
            slots: mesh.triangles.iter().map(|&t| Some(t)).collect(),
            incident,
            removed: vec![false; mesh.vertices.len()],
            global,
            criterion,
            border_policy: options.border.resolve(global.is_some()),
            max_valence: options.max_valence,
            cutter: EarCutter::default(),
            quadrics: if criterion == Criterion::Quadric {
                initial_quadrics(mesh)
            } else {
                Vec::new()
            },
            slot_error: if criterion == Criterion::Quadric {
                vec![0.0; mesh.triangles.len()]
            } else {
                Vec::new()
            },
        })
    }

    /// The fan of `v` from its incident triangles: each `(v, a, b)` links `a` to `b`; a border
    /// fan starts at the neighbour no triangle links to, an interior fan at its lowest id.
    fn fan(&self, v: u32) -> Option<Fan> {
        self.fan_within(v, self.max_valence)
    }

    /// [`fan`](Self::fan) with the valence limit `limit`.
    fn fan_within(&self, v: u32, limit: usize) -> Option<Fan> {
        let mut link: BTreeMap<u32, (u32, u32)> = BTreeMap::new();
        for &s in &self.incident[v as usize] {
            let t = self.slots[s as usize].expect("incident slots are live");
            let k = t.iter().position(|&x| x == v).expect("incident");
            link.insert(t[(k + 1) % 3], (t[(k + 2) % 3], s));
        }
        if link.is_empty() || link.len() > limit {
            return None;
        }
        let targets: BTreeSet<u32> = link.values().map(|&(b, _)| b).collect();
        let start = link.keys().copied().find(|a| !targets.contains(a));
        let border = start.is_some();
        let first = match start {
            Some(a) => a,
            None => *link.keys().next().expect("non-empty"),
        };
        let mut fan = Fan {
            ring: vec![first],
            slots: vec![],
            border,
        };
        let mut a = first;
        while let Some(&(b, s)) = link.get(&a) {
            fan.slots.push(s);
            if b == first {
                break;
            }
            fan.ring.push(b);
            a = b;
        }
        debug_assert_eq!(fan.slots.len(), link.len());
        if fan.ring.len() > limit {
            return None;
        }
        if !border {
            let k = canonical_start(&fan.ring, false);
            fan.ring.rotate_left(k);
            fan.slots.rotate_left(k);
        }
        Some(fan)
    }

    fn plane_of(&self, v: u32, fan: &Fan) -> Plane {
        match self.global {
            Some(p) => p,
            None => {
                let ring: Vec<[f64; 3]> =
                    fan.ring.iter().map(|&w| self.float[w as usize]).collect();
                Plane::most_aligned(fan_normal(self.float[v as usize], &ring, !fan.border))
            }
        }
    }

    fn project(&self, plane: Plane, v: u32) -> [Rational; 2] {
        let (a, b) = plane.axes();
        let c = &self.coords[v as usize];
        [c[a].clone(), c[b].clone()]
    }

    /// Whether the border policy lets `v` (with `fan`) go: always an interior node; a border
    /// node under [`BorderPolicy::Simplify`], or under [`BorderPolicy::Intact`] when the
    /// border stays intact without it.
    fn border_allows(&self, v: u32, fan: &Fan) -> bool {
        !fan.border
            || match self.border_policy {
                BorderPolicy::Simplify => true,
                BorderPolicy::Intact | BorderPolicy::Auto => self.border_intact(v, fan),
                BorderPolicy::Exclude => false,
            }
    }

    /// The `f64` input coordinates of `hole`'s ring, as the fast path reads them.
    fn ring_points(&self, hole: &Hole) -> Vec<[f64; 3]> {
        hole.fan
            .ring
            .iter()
            .map(|&w| self.float[w as usize])
            .collect()
    }

    /// The quadric criterion on `v`'s `hole` ([`quadric_removal`]), from the `f64` input
    /// coordinates as the fast path computes it, with the bounds kept per triangle slot;
    /// `None` when the new triangles would fold the surface over.
    fn quadric_cost(&self, v: u32, hole: &Hole) -> Option<QuadricRemoval> {
        let ring3 = self.ring_points(hole);
        let pts: Vec<[f64; 2]> = ring3.iter().map(|&q| hole.plane.project(q)).collect();
        let ring_normals: Vec<[f64; 3]> = if self.normals.is_empty() {
            Vec::new()
        } else {
            hole.fan
                .ring
                .iter()
                .map(|&w| self.normals[w as usize])
                .collect()
        };
        let p = self.float[v as usize];
        let pv = hole.plane.project(p);
        let fan_error = hole
            .fan
            .slots
            .iter()
            .map(|&s| self.slot_error[s as usize])
            .fold(0.0, f64::max);
        let carried = Carried {
            quadric: self.quadrics[v as usize],
            fan_error,
        };
        quadric_removal(
            &carried,
            p,
            pv,
            &ring3,
            &pts,
            &hole.triangles,
            hole.crossing,
            hole.fan.border,
            &ring_normals,
        )
    }

    /// The border node `v` lies strictly inside the segment between its border neighbours.
    fn border_intact(&self, v: u32, fan: &Fan) -> bool {
        let flat = |w: u32| -> [Rational; 3] {
            let c = &self.coords[w as usize];
            match self.global {
                // The domain's outline in the global projection stays the same.
                Some(plane) => {
                    let [x, y] = self.project(plane, w);
                    [x, y, Rational::zero()]
                }
                None => c.clone(),
            }
        };
        let (a, b, p) = (
            &flat(*fan.ring.last().unwrap()),
            &flat(fan.ring[0]),
            &flat(v),
        );
        // p = a + t (b − a) with 0 < t < 1: the cross product vanishes and t is strictly between.
        let d: Vec<Rational> = (0..3).map(|k| &b[k] - &a[k]).collect();
        let e: Vec<Rational> = (0..3).map(|k| &p[k] - &a[k]).collect();
        let cross_zero = (0..3).all(|k| {
            let (i, j) = ((k + 1) % 3, (k + 2) % 3);
            &d[i] * &e[j] - &d[j] * &e[i] == Rational::zero()
        });
        let dot_de: Rational = (0..3).map(|k| &d[k] * &e[k]).sum();
        let dot_dd: Rational = (0..3).map(|k| &d[k] * &d[k]).sum();
        cross_zero && dot_de.is_positive() && dot_de < dot_dd
    }

    /// The fan projected, checked to be a simple star around `v`, and its hole ear-cut.
    fn hole(&mut self, v: u32) -> Option<Hole> {
        if self.removed[v as usize] {
            return None;
        }
        let fan = self.fan(v)?;
        let l = fan.ring.len();
        if l < 3 {
            return None;
        }
        if !self.border_allows(v, &fan) {
            return None;
        }
        // The most aligned axis plane, else (per-fan projection) the others in order.
        let first = self.plane_of(v, &fan);
        let others: Vec<Plane> = match self.global {
            Some(_) => Vec::new(),
            None => {
                let ring: Vec<[f64; 3]> =
                    fan.ring.iter().map(|&w| self.float[w as usize]).collect();
                fallback_planes(fan_normal(self.float[v as usize], &ring, !fan.border)).collect()
            }
        };
        let planes: Vec<Plane> = std::iter::once(first).chain(others).collect();
        let projected_in = |plane: Plane| -> Vec<[Rational; 2]> {
            fan.ring.iter().map(|&w| self.project(plane, w)).collect()
        };
        let star = planes.iter().find_map(|&plane| {
            let projected = projected_in(plane);
            let centre = self.project(plane, v);
            simple_star(&centre, &projected, fan.border).then_some((plane, projected))
        });
        // The quadric criterion also accepts a ring that is a simple counter-clockwise
        // polygon in some axis plane, in the same order (per-fan projection only).
        let relaxed = || {
            if self.criterion != Criterion::Quadric || self.global.is_some() {
                return None;
            }
            planes.iter().find_map(|&plane| {
                let projected = projected_in(plane);
                let lower = |i: usize, j: usize| {
                    (&projected[i][0], &projected[i][1]) < (&projected[j][0], &projected[j][1])
                };
                simple_ccw(projected.len(), &ExactOrient(&projected), lower)
                    .then_some((plane, projected))
            })
        };
        let (plane, projected) = star.or_else(relaxed)?;
        let float: Vec<[f64; 2]> = fan
            .ring
            .iter()
            .map(|&w| plane.project(self.float[w as usize]))
            .collect();
        let mut triangles = Vec::new();
        let mut crossing = 0.0;
        let orient = ExactOrient(&projected);
        if !self.cutter.cut(&float, &orient, &mut triangles) {
            return None;
        }
        if self.criterion == Criterion::Quadric {
            let ring3: Vec<[f64; 3]> = fan.ring.iter().map(|&w| self.float[w as usize]).collect();
            let p = self.float[v as usize];
            let f = flip_toward_fan(
                p,
                plane.project(p),
                &ring3,
                &float,
                &mut triangles,
                plane.drop,
                fan.border,
                &orient,
            );
            if f.flipped && !ear_order(fan.ring.len(), &mut triangles) {
                return None;
            }
            crossing = f.crossing;
        }
        Some(Hole {
            fan,
            plane,
            projected,
            triangles,
            crossing,
        })
    }

    fn adjacent(&self, a: u32, b: u32) -> bool {
        self.incident[a as usize]
            .iter()
            .any(|&s| self.slots[s as usize].expect("live").contains(&b))
    }

    /// No new edge exists already, and no new triangle repeats one outside the hole.
    fn topology_ok(&self, hole: &Hole) -> bool {
        self.new_edges_ok(&hole.fan, &hole.triangles)
    }

    /// [`topology_ok`](Self::topology_ok) for the fill `tris` of `fan`'s hole.
    fn new_edges_ok(&self, fan: &Fan, tris: &[[u8; 3]]) -> bool {
        let ring = &fan.ring;
        let l = ring.len();
        for t in tris {
            let tri = t.map(|p| ring[p as usize]);
            for e in 0..3 {
                let (pa, pb) = (t[e] as usize, t[(e + 1) % 3] as usize);
                let link_edge = pb == (pa + 1) % l && !(fan.border && pa == l - 1);
                if !link_edge && self.adjacent(tri[e], tri[(e + 1) % 3]) {
                    return false;
                }
            }
            let mut key = tri;
            key.sort_unstable();
            let repeated = self.incident[tri[0] as usize].iter().any(|&s| {
                let mut other = self.slots[s as usize].expect("live");
                other.sort_unstable();
                other == key
            });
            if repeated {
                return false;
            }
        }
        true
    }

    /// The cheapest fan fill of `hole` ([`fan_fills`]) that passes the topology and facing
    /// tests and does not fold (the first on ties), with its value, as the fast engine takes
    /// it when the planned cut faces against `original`; `None` when no fill passes.
    fn fan_fill(&self, v: u32, hole: Hole, original: &OriginalSurface) -> Option<(f64, Hole)> {
        let ring3 = self.ring_points(&hole);
        let pts: Vec<[f64; 2]> = ring3.iter().map(|&q| hole.plane.project(q)).collect();
        let p = self.float[v as usize];
        let fills: Vec<Vec<[u8; 3]>> =
            fan_fills(hole.fan.ring.len(), &ExactOrient(&hole.projected)).collect();
        let mut trial = hole;
        let mut best: Option<(f64, Vec<[u8; 3]>, f64)> = None;
        for tris in fills {
            if !self.new_edges_ok(&trial.fan, &tris)
                || super::quadric::faces_against_original(original, &trial.fan.ring, &ring3, &tris)
            {
                continue;
            }
            trial.crossing = super::crossing_deviation(
                p,
                trial.plane.project(p),
                &ring3,
                &pts,
                &tris,
                trial.plane.drop,
                trial.fan.border,
            );
            trial.triangles = tris;
            if let Some(q) = self.quadric_cost(v, &trial) {
                if best.as_ref().is_none_or(|b| q.value < b.0) {
                    best = Some((q.value, trial.triangles.clone(), trial.crossing));
                }
            }
        }
        let (value, triangles, crossing) = best?;
        trial.triangles = triangles;
        trial.crossing = crossing;
        Some((value, trial))
    }

    /// The value the criterion reads at `w`: the scalar, or the height along the normal.
    fn height(&self, w: u32, plane: Plane) -> &Rational {
        match &self.values {
            Some(f) => &f[w as usize],
            None => &self.coords[w as usize][plane.drop],
        }
    }

    /// The error criterion: `h(v)` minus the interpolant of the first new triangle (in ear
    /// order) that contains `v`'s projection, exactly.
    fn removal_error(&self, v: u32, hole: &Hole) -> Rational {
        let p = self.project(hole.plane, v);
        let h = |w: u32| self.height(w, hole.plane).clone();
        for t in &hole.triangles {
            let [a, b, c] = t.map(|i| &hole.projected[i as usize]);
            let area = det(a, b, c);
            let l0 = det(&p, b, c) / &area;
            let l1 = det(a, &p, c) / &area;
            let l2 = Rational::from_integer(1.into()) - &l0 - &l1;
            if !l0.is_negative() && !l1.is_negative() && !l2.is_negative() {
                let [wa, wb, wc] = t.map(|i| hole.fan.ring[i as usize]);
                let interp = l0 * h(wa) + l1 * h(wb) + l2 * h(wc);
                return (h(v) - interp).abs();
            }
        }
        unreachable!("a simple star's hole contains its centre")
    }
}

fn det(a: &[Rational; 2], b: &[Rational; 2], c: &[Rational; 2]) -> Rational {
    (&b[0] - &a[0]) * (&c[1] - &a[1]) - (&b[1] - &a[1]) * (&c[0] - &a[0])
}

fn xy(c: &[Rational; 3]) -> [Rational; 2] {
    [c[0].clone(), c[1].clone()]
}

/// Every fan triangle turns counter-clockwise and the ring winds once around `centre`.
/// Interior: with the points classified into the upper half-plane (angles `[0, π)` about
/// `centre`) and the lower (`[π, 2π)`), counter-clockwise steps of less than `π` pass angle 0
/// exactly when they go from lower to upper; one such step is one winding. Border: every
/// inner ring point lies strictly left of the line from the last ring point to the first.
pub(crate) fn simple_star(centre: &[Rational; 2], ring: &[[Rational; 2]], border: bool) -> bool {
    let l = ring.len();
    let count = if border { l - 1 } else { l };
    if (0..count).any(|i| orient(centre, &ring[i], &ring[(i + 1) % l]) != Ordering::Greater) {
        return false;
    }
    if border {
        return (1..l - 1).all(|i| orient(&ring[l - 1], &ring[0], &ring[i]) == Ordering::Greater);
    }
    let upper = |p: &[Rational; 2]| p[1] > centre[1] || (p[1] == centre[1] && p[0] > centre[0]);
    let crossings = (0..l)
        .filter(|&i| !upper(&ring[i]) && upper(&ring[(i + 1) % l]))
        .count();
    crossings == 1
}

impl Engine for ExactEngine {
    fn node_count(&self) -> usize {
        self.coords.len()
    }

    fn evaluate(&mut self, v: u32) -> Option<f64> {
        match self.criterion {
            Criterion::Angle | Criterion::Scalar => {
                if self.removed[v as usize] {
                    return None;
                }
                let fan = self.fan(v)?;
                if !self.border_allows(v, &fan) {
                    return None;
                }
                let l = fan.ring.len();
                if self.criterion == Criterion::Angle {
                    // Transcendental: each edge's angle in f64 from the exact difference rounded
                    // once, summed in ring order (as the fast path does).
                    let plane = self.plane_of(v, &fan);
                    let p = &self.coords[v as usize];
                    let mut sum = 0.0;
                    for &w in &fan.ring {
                        let q = &self.coords[w as usize];
                        let d = [0, 1, 2].map(|k| rational_to_f64(&(&q[k] - &p[k])));
                        sum += edge_angle(d, plane);
                    }
                    Some(sum / l as f64)
                } else {
                    let f = self.values.as_ref()?;
                    let total: Rational = fan
                        .ring
                        .iter()
                        .map(|&w| (&f[w as usize] - &f[v as usize]).abs())
                        .sum();
                    Some(rational_to_f64(
                        &(total / Rational::from_integer((l as i64).into())),
                    ))
                }
            }
            Criterion::Error => {
                let hole = self.hole(v)?;
                Some(rational_to_f64(&self.removal_error(v, &hole)))
            }
            Criterion::Quadric => {
                let hole = self.hole(v)?;
                self.quadric_cost(v, &hole).map(|r| r.value)
            }
            Criterion::Auto => unreachable!("resolved when the engine is built"),
        }
    }

    fn criterion(&self) -> Criterion {
        self.criterion
    }

    fn fan_filled(&self) -> usize {
        self.filled
    }

    fn original_surface(&self) -> Option<Arc<OriginalSurface>> {
        self.original.clone()
    }

    fn blocked(&mut self) -> Option<super::Blocked> {
        let mut b = super::Blocked::default();
        for v in 0..self.coords.len() as u32 {
            if self.removed[v as usize] {
                continue;
            }
            let Some(fan) = self.fan_within(v, usize::MAX) else {
                continue;
            };
            // The checks of an evaluation and a removal, in their order.
            let count = if fan.ring.len() > self.max_valence {
                &mut b.valence
            } else if !self.border_allows(v, &fan) {
                &mut b.border
            } else {
                match self.hole(v) {
                    None => &mut b.no_plane,
                    Some(hole) => {
                        if self.criterion == Criterion::Quadric
                            && self.quadric_cost(v, &hole).is_none()
                        {
                            &mut b.fold
                        } else if !self.topology_ok(&hole) {
                            &mut b.topology
                        } else if self.original.as_deref().is_some_and(|original| {
                            super::quadric::faces_against_original(
                                original,
                                &hole.fan.ring,
                                &self.ring_points(&hole),
                                &hole.triangles,
                            )
                        }) {
                            &mut b.facing
                        } else {
                            &mut b.removable
                        }
                    }
                }
            };
            *count += 1;
        }
        Some(b)
    }

    fn try_remove(&mut self, v: u32, history: &mut History, fits: &dyn Fn(f64) -> bool) -> Removal {
        let Some(mut hole) = self.hole(v) else {
            return Removal::Refused;
        };
        if !self.topology_ok(&hole) {
            return Removal::Refused;
        }
        if let Some(original) = &self.original {
            let ring3 = self.ring_points(&hole);
            if super::quadric::faces_against_original(
                original,
                &hole.fan.ring,
                &ring3,
                &hole.triangles,
            ) {
                // Under the quadric criterion, the cheapest fan fill that passes instead.
                if self.criterion != Criterion::Quadric {
                    return Removal::Refused;
                }
                match self.fan_fill(v, hole, original) {
                    None => return Removal::Refused,
                    Some((value, _)) if !fits(value) => return Removal::Later(value),
                    Some((_, filled)) => {
                        hole = filled;
                        self.filled += 1;
                    }
                }
            }
        }
        if !self.quadrics.is_empty() {
            // The removed node's quadric passes to the corners of the triangle it lands in;
            // the new triangles (in the fan's first slots) take the removal's bound.
            let Some(QuadricRemoval { bound, corners, .. }) = self.quadric_cost(v, &hole) else {
                return Removal::Refused;
            };
            let q = self.quadrics[v as usize];
            for k in corners {
                self.quadrics[hole.fan.ring[k as usize] as usize].add(&q);
            }
            for &s in &hole.fan.slots[..hole.triangles.len()] {
                self.slot_error[s as usize] = bound;
            }
        }
        let ring = &hole.fan.ring;
        let l = ring.len();
        let positions: Vec<u8> = hole
            .fan
            .slots
            .iter()
            .map(|&s| {
                let t = self.slots[s as usize].expect("live");
                t.iter().position(|&x| x == v).expect("incident") as u8
            })
            .collect();
        history.push(
            v,
            hole.fan.border,
            ring,
            hole.fan.slots.iter().copied().zip(positions),
            &hole.triangles,
            self.float[v as usize],
            self.values
                .as_ref()
                .map(|f| rational_to_f64(&f[v as usize])),
        );
        // Delete the fan, then fill the hole: the first l − 2 slots take the new triangles.
        for &s in &hole.fan.slots {
            let t = self.slots[s as usize].take().expect("live");
            for x in t {
                self.incident[x as usize].remove(&s);
            }
        }
        for (k, t) in hole.triangles.iter().enumerate() {
            let s = hole.fan.slots[k];
            let tri = t.map(|p| ring[p as usize]);
            for x in tri {
                self.incident[x as usize].insert(s);
            }
            self.slots[s as usize] = Some(tri);
        }
        debug_assert!(l >= 3);
        self.removed[v as usize] = true;
        Removal::Removed
    }
}

/// Decimates with the exact engine.
pub(crate) fn decimate(mesh: &Mesh, options: &Options) -> Result<Outcome, DecimateError> {
    driver::decimate_with(
        mesh,
        options,
        || ExactEngine::new(mesh, options),
        |e| (to_mesh(e, mesh), e.global.is_some()),
    )
}

fn to_mesh(engine: &ExactEngine, mesh: &Mesh) -> Mesh {
    let mut new_id = vec![u32::MAX; mesh.vertices.len()];
    let mut out = Mesh::default();
    let mut values = Vec::new();
    for (v, p) in mesh.vertices.iter().enumerate() {
        if !engine.removed[v] {
            new_id[v] = out.vertices.len() as u32;
            out.vertices.push(*p);
            if let Some(s) = &mesh.scalars {
                values.push(s.values[v]);
            }
        }
    }
    out.triangles = engine
        .slots
        .iter()
        .flatten()
        .map(|t| t.map(|i| new_id[i as usize]))
        .collect();
    out.scalars = mesh.scalars.as_ref().map(|s| Scalars {
        name: s.name.clone(),
        values,
    });
    out
}
