//! The fast path: `f64` coordinates in a half-edge structure whose triangles live in slots
//! that removals reuse (Fig. 5), orientation signs from Shewchuk's adaptive predicates.
//!
//! Half-edge `h` is corner `h % 3` of slot `h / 3`, from that corner's vertex to the next;
//! `twin[h]` is the opposite half-edge or `NONE` on the border. `out[v]` is a half-edge leaving
//! `v` — for a border node the one with no twin, so that rotating counter-clockwise
//! (`h ← twin[prev(h)]`) from it walks the whole fan.

use super::driver::{self, Engine};
use super::earcut::{orient2d, EarCutter, RobustOrient};
use super::history::History;
use super::{
    canonical_start, check_options, edge_angle, fan_normal, global_plane, BorderPolicy, Criterion,
    DecimateError, Options, Outcome, Plane,
};
use crate::memory::{huge_copy, huge_vec};
use crate::mesh::{Mesh, MeshError, Scalars};
use std::cmp::Ordering;

const NONE: u32 = u32::MAX;

#[inline]
fn next(h: u32) -> u32 {
    if h % 3 == 2 {
        h - 2
    } else {
        h + 1
    }
}

#[inline]
fn prev(h: u32) -> u32 {
    if h.is_multiple_of(3) {
        h + 2
    } else {
        h - 1
    }
}

/// A hole ready to be filled: the fan, its projection and the ear cut.
#[derive(Clone, Copy)]
struct Plan {
    border: bool,
    plane: Plane,
}

pub(crate) struct FastEngine {
    pos: Vec<[f64; 3]>,
    values: Option<Vec<f64>>,
    tri: Vec<[u32; 3]>,
    live: Vec<bool>,
    twin: Vec<u32>,
    out: Vec<u32>,
    removed: Vec<bool>,
    global: Option<Plane>,
    criterion: Criterion,
    border_policy: BorderPolicy,
    max_valence: usize,
    // Scratch.
    ring: Vec<u32>,
    fan: Vec<u32>,
    pts: Vec<[f64; 2]>,
    ring3: Vec<[f64; 3]>,
    tris: Vec<[u8; 3]>,
    cutter: EarCutter,
    slots: Vec<u32>,
    positions: Vec<u8>,
    outer: Vec<u32>,
    pending: Vec<(u8, u8, u32)>,
    /// The node whose plan the scratch buffers hold, while nothing has changed since.
    planned: Option<(u32, Plan)>,
    /// Holes are cut in the global projection and every fan of the input is a simple star
    /// in it. Removals keep that true: the new triangles at a ring node tile exactly the
    /// angular sector its removed triangles covered. Then every fan passes the star test, and
    /// no diagonal of a hole can repeat an existing edge (that edge would leave its endpoint
    /// in a direction inside the hole's sector, which no remaining triangle covers), so
    /// both checks are skipped.
    embedded: bool,
}

impl FastEngine {
    /// Builds the half-edge structure, checking that the mesh is an oriented 2-manifold.
    pub(crate) fn new(mesh: &Mesh, options: &Options) -> Result<FastEngine, DecimateError> {
        mesh.validate()?;
        check_options(mesh, options)?;
        let n = mesh.vertices.len();
        let t = mesh.triangles.len();
        if 3 * t >= NONE as usize {
            return Err(DecimateError::BadOption(format!(
                "{t} triangles are too many"
            )));
        }
        // Outgoing half-edges by source vertex (CSR).
        let mut start = huge_vec(0u32, n + 1);
        for tri in &mesh.triangles {
            for &a in tri {
                start[a as usize + 1] += 1;
            }
        }
        for v in 0..n {
            start[v + 1] += start[v];
        }
        let mut fill = start.clone();
        let mut outgoing = huge_vec(0u32, 3 * t);
        for (s, tri) in mesh.triangles.iter().enumerate() {
            for (c, &a) in tri.iter().enumerate() {
                outgoing[fill[a as usize] as usize] = (3 * s + c) as u32;
                fill[a as usize] += 1;
            }
        }
        let target = |h: u32| mesh.triangles[h as usize / 3][(h as usize % 3 + 1) % 3];
        let mut twin = huge_vec(NONE, 3 * t);
        for h in 0..3 * t as u32 {
            let a = mesh.triangles[h as usize / 3][h as usize % 3];
            let b = target(h);
            let of = |v: u32| &outgoing[start[v as usize] as usize..start[v as usize + 1] as usize];
            for &g in of(a) {
                if g != h && target(g) == b {
                    return Err(MeshError::NonManifold {
                        a,
                        b,
                        why: format!(
                            "traversed in the same direction by triangles {} and {} (inconsistent orientation or more than two triangles)",
                            g / 3,
                            h / 3
                        ),
                    }
                    .into());
                }
            }
            for &g in of(b) {
                if target(g) == a {
                    twin[h as usize] = g;
                }
            }
        }
        let mut out = huge_vec(NONE, n);
        for v in 0..n {
            let list = &outgoing[start[v] as usize..start[v + 1] as usize];
            let Some(&first) = list.first() else {
                continue;
            };
            let mut chosen = first;
            let mut borders = 0;
            for &h in list {
                if twin[h as usize] == NONE {
                    borders += 1;
                    chosen = h;
                }
            }
            if borders > 1 {
                return Err(MeshError::NonManifold {
                    a: v as u32,
                    b: target(chosen),
                    why: format!("vertex {v} has two boundary fans (a bow-tie vertex)"),
                }
                .into());
            }
            out[v] = chosen;
            // One fan must visit every outgoing half-edge.
            let mut h = chosen;
            let mut visited = 0;
            loop {
                visited += 1;
                let p = twin[prev(h) as usize];
                if p == NONE || p == chosen || visited > list.len() {
                    break;
                }
                h = p;
            }
            if visited != list.len() {
                return Err(MeshError::NonManifold {
                    a: v as u32,
                    b: target(chosen),
                    why: format!(
                        "the {} triangles at vertex {v} form more than one fan (a pinched vertex)",
                        list.len()
                    ),
                }
                .into());
            }
        }
        let global = global_plane(mesh, options.projection, |tri| {
            let p = tri.map(|i| Plane::XY.project(mesh.vertices[i as usize]));
            orient2d(p[0], p[1], p[2]) != Ordering::Greater
        })?;
        let mut engine = FastEngine {
            pos: huge_copy(&mesh.vertices),
            values: mesh.scalars.as_ref().map(|s| s.values.clone()),
            tri: huge_copy(&mesh.triangles),
            live: huge_vec(true, t),
            twin,
            out,
            removed: huge_vec(false, n),
            global,
            criterion: options.criterion,
            border_policy: options.border,
            max_valence: options.max_valence,
            ring: Vec::new(),
            fan: Vec::new(),
            pts: Vec::new(),
            ring3: Vec::new(),
            tris: Vec::new(),
            cutter: EarCutter::default(),
            slots: Vec::new(),
            positions: Vec::new(),
            outer: Vec::new(),
            pending: Vec::new(),
            planned: None,
            embedded: false,
        };
        engine.embedded = engine.global.is_some() && (0..n as u32).all(|v| engine.fan_embedded(v));
        Ok(engine)
    }

    /// True when `v`'s fan, whatever its valence, is a simple star in the global projection.
    fn fan_embedded(&mut self, v: u32) -> bool {
        if self.out[v as usize] == NONE {
            return true;
        }
        let limit = std::mem::replace(&mut self.max_valence, usize::MAX);
        let border = self.load_fan(v).expect("no valence limit");
        self.max_valence = limit;
        let pv = self.project_fan(v, self.global.unwrap_or(Plane::XY));
        star_is_simple(pv, &self.pts, border)
    }

    /// Projects the loaded ring into `pts` and returns the projection of `v`.
    fn project_fan(&mut self, v: u32, plane: Plane) -> [f64; 2] {
        self.pts.clear();
        self.pts.extend(
            self.ring
                .iter()
                .map(|&w| plane.project(self.pos[w as usize])),
        );
        plane.project(self.pos[v as usize])
    }

    #[inline]
    fn source(&self, h: u32) -> u32 {
        self.tri[h as usize / 3][h as usize % 3]
    }

    #[inline]
    fn target(&self, h: u32) -> u32 {
        self.tri[h as usize / 3][(h as usize % 3 + 1) % 3]
    }

    /// Fills `ring` (counter-clockwise) and `fan` (the half-edges `v → ring[i]`) of `v`;
    /// returns whether `v` is on the border, or `None` when the valence is over the limit.
    fn load_fan(&mut self, v: u32) -> Option<bool> {
        self.planned = None;
        self.ring.clear();
        self.fan.clear();
        let h0 = self.out[v as usize];
        let mut h = h0;
        loop {
            self.ring.push(self.target(h));
            self.fan.push(h);
            let p = prev(h);
            let t = self.twin[p as usize];
            if t == NONE {
                self.ring.push(self.source(p));
                return (self.ring.len() <= self.max_valence).then_some(true);
            }
            if t == h0 {
                if self.ring.len() > self.max_valence {
                    return None;
                }
                // Interior rings start at the lowest id, as in the exact path.
                let start = canonical_start(&self.ring, false);
                self.ring.rotate_left(start);
                self.fan.rotate_left(start);
                return Some(false);
            }
            if self.ring.len() > self.max_valence {
                return None;
            }
            h = t;
        }
    }

    /// True when the border node `v` lies exactly on the segment between its two border
    /// neighbours (the border stays intact without it).
    fn border_intact(&self, v: u32) -> bool {
        let a = self.pos[*self.ring.last().unwrap() as usize];
        let b = self.pos[self.ring[0] as usize];
        let p = self.pos[v as usize];
        match self.global {
            // The domain's outline in the global projection stays the same.
            Some(plane) => {
                let flat = |q: [f64; 3]| {
                    let [x, y] = plane.project(q);
                    [x, y, 0.0]
                };
                collinear_between(flat(a), flat(p), flat(b))
            }
            None => collinear_between(a, p, b),
        }
    }

    /// Checks that `v` may go and its hole can be filled: loads the fan, applies the border
    /// policy, projects, checks the fan is a simple star in the projection, cuts the ears.
    fn plan(&mut self, v: u32) -> Option<Plan> {
        if self.removed[v as usize] || self.out[v as usize] == NONE {
            return None;
        }
        let border = self.load_fan(v)?;
        let l = self.ring.len();
        if l < 3 {
            return None;
        }
        if border && (self.border_policy == BorderPolicy::Exclude || !self.border_intact(v)) {
            return None;
        }
        let plane = match self.global {
            Some(p) => p,
            None => {
                self.ring3.clear();
                self.ring3
                    .extend(self.ring.iter().map(|&w| self.pos[w as usize]));
                Plane::most_aligned(fan_normal(self.pos[v as usize], &self.ring3, !border))
            }
        };
        let pv = self.project_fan(v, plane);
        if !self.embedded && !star_is_simple(pv, &self.pts, border) {
            return None;
        }
        if !self
            .cutter
            .cut(&self.pts, &RobustOrient(&self.pts), &mut self.tris)
        {
            return None;
        }
        let plan = Plan { border, plane };
        self.planned = Some((v, plan));
        Some(plan)
    }

    /// True when `a` and `b` share an edge.
    fn adjacent(&self, a: u32, b: u32) -> bool {
        let h0 = self.out[a as usize];
        let mut h = h0;
        loop {
            if self.target(h) == b {
                return true;
            }
            let p = prev(h);
            let t = self.twin[p as usize];
            if t == NONE {
                return self.source(p) == b;
            }
            if t == h0 {
                return false;
            }
            h = t;
        }
    }

    /// The new triangles must not repeat an edge or a triangle the mesh has outside the hole
    /// (a closed surface seen in a per-fan projection can offer such holes).
    fn topology_ok(&self, border: bool) -> bool {
        let l = self.ring.len();
        for t in &self.tris {
            for e in 0..3 {
                let (pa, pb, pc) = (t[e] as usize, t[(e + 1) % 3] as usize, t[(e + 2) % 3]);
                if border && pa == l - 1 && pb == 0 {
                    // The closing edge at a border node is new: it must not exist already.
                    if self.adjacent(self.ring[pa], self.ring[pb]) {
                        return false;
                    }
                } else if pb == (pa + 1) % l {
                    // Link edge: the triangle across it must not be this one reversed.
                    let o = self.twin[next(self.fan[pa]) as usize];
                    if o != NONE && self.target(next(o)) == self.ring[pc as usize] {
                        return false;
                    }
                } else if pa < pb && self.adjacent(self.ring[pa], self.ring[pb]) {
                    return false;
                }
            }
        }
        true
    }

    fn apply(&mut self, v: u32, border: bool, history: &mut History) {
        self.planned = None;
        let l = self.ring.len();
        let old = self.fan.len();
        self.slots.clear();
        self.positions.clear();
        self.outer.clear();
        for &h in &self.fan {
            self.slots.push(h / 3);
            self.positions.push((h % 3) as u8);
            self.outer.push(self.twin[next(h) as usize]);
        }
        history.push(
            v,
            border,
            &self.ring,
            &self.slots,
            &self.positions,
            &self.tris,
            self.pos[v as usize],
            self.values.as_ref().map(|f| f[v as usize]),
        );
        for k in l - 2..old {
            let s = self.slots[k] as usize;
            self.live[s] = false;
            for e in 0..3 {
                self.twin[3 * s + e] = NONE;
            }
        }
        self.pending.clear();
        for k in 0..l - 2 {
            let s = self.slots[k];
            let t = self.tris[k];
            self.tri[s as usize] = t.map(|p| self.ring[p as usize]);
            for e in 0..3 {
                let h = 3 * s + e as u32;
                let (pa, pb) = (t[e], t[(e + 1) % 3]);
                if pb as usize == (pa as usize + 1) % l && !(border && pa as usize == l - 1) {
                    let o = self.outer[pa as usize];
                    self.twin[h as usize] = o;
                    if o != NONE {
                        self.twin[o as usize] = h;
                    }
                } else if border && pa as usize == l - 1 && pb == 0 {
                    self.twin[h as usize] = NONE;
                } else if let Some(i) = self
                    .pending
                    .iter()
                    .position(|&(x, y, _)| x == pb && y == pa)
                {
                    let g = self.pending.swap_remove(i).2;
                    self.twin[h as usize] = g;
                    self.twin[g as usize] = h;
                } else {
                    self.pending.push((pa, pb, h));
                }
            }
        }
        debug_assert!(self.pending.is_empty());
        // Re-anchor ring nodes whose out half-edge was in the rebuilt or freed slots.
        for i in 0..l {
            let w = self.ring[i] as usize;
            let s = self.out[w] / 3;
            if !self.slots.contains(&s) {
                continue;
            }
            let mut any = NONE;
            let mut boundary = NONE;
            for k in 0..l - 2 {
                let s = self.slots[k];
                for e in 0..3 {
                    if self.tris[k][e] as usize == i {
                        let h = 3 * s + e as u32;
                        any = h;
                        if self.twin[h as usize] == NONE {
                            boundary = h;
                        }
                    }
                }
            }
            self.out[w] = if boundary != NONE { boundary } else { any };
        }
        self.removed[v as usize] = true;
        self.out[v as usize] = NONE;
    }

    /// The decimated mesh and the stage's fingerprint inputs.
    fn to_mesh(&self, name: Option<&str>) -> Mesh {
        let mut new_id = vec![NONE; self.pos.len()];
        let mut vertices = Vec::new();
        let mut values = Vec::new();
        for v in 0..self.pos.len() {
            if !self.removed[v] {
                new_id[v] = vertices.len() as u32;
                vertices.push(self.pos[v]);
                if let Some(f) = &self.values {
                    values.push(f[v]);
                }
            }
        }
        let triangles = (0..self.tri.len())
            .filter(|&s| self.live[s])
            .map(|s| self.tri[s].map(|i| new_id[i as usize]))
            .collect();
        Mesh {
            normals: None,
            vertices,
            triangles,
            scalars: name.map(|n| Scalars {
                name: n.to_string(),
                values,
            }),
        }
    }
}

impl Engine for FastEngine {
    fn node_count(&self) -> usize {
        self.pos.len()
    }

    fn evaluate(&mut self, v: u32) -> Option<f64> {
        match self.criterion {
            Criterion::Angle | Criterion::Scalar => {
                if self.removed[v as usize] || self.out[v as usize] == NONE {
                    return None;
                }
                let border = self.load_fan(v)?;
                if border && (self.border_policy == BorderPolicy::Exclude || !self.border_intact(v))
                {
                    return None;
                }
                let p = self.pos[v as usize];
                let plane = match self.global {
                    Some(plane) => plane,
                    None => {
                        self.ring3.clear();
                        self.ring3
                            .extend(self.ring.iter().map(|&w| self.pos[w as usize]));
                        Plane::most_aligned(fan_normal(p, &self.ring3, !border))
                    }
                };
                let l = self.ring.len();
                let mut sum = 0.0;
                for i in 0..l {
                    let w = self.ring[i] as usize;
                    sum += if self.criterion == Criterion::Angle {
                        let q = self.pos[w];
                        edge_angle([q[0] - p[0], q[1] - p[1], q[2] - p[2]], plane)
                    } else {
                        let f = self.values.as_ref()?;
                        (f[w] - f[v as usize]).abs()
                    };
                }
                Some(sum / l as f64)
            }
            Criterion::Error => {
                let plan = self.plan(v)?;
                Some(self.removal_error(v, plan.plane))
            }
        }
    }

    fn try_remove(&mut self, v: u32, history: &mut History) -> bool {
        let plan = match self.planned {
            Some((u, plan)) if u == v => plan,
            _ => match self.plan(v) {
                Some(plan) => plan,
                None => return false,
            },
        };
        if !self.embedded && !self.topology_ok(plan.border) {
            return false;
        }
        self.apply(v, plan.border, history);
        true
    }
}

impl FastEngine {
    /// The error criterion: `|h(v) − h_interp|` over the planned triangles, `h` the scalar or
    /// the height along the projection normal; the triangle is the one whose smallest
    /// barycentric coordinate at `v` is largest.
    fn removal_error(&mut self, v: u32, plane: Plane) -> f64 {
        let pv = plane.project(self.pos[v as usize]);
        let height = |s: &Self, w: usize| match &s.values {
            Some(f) => f[w],
            None => s.pos[w][plane.drop],
        };
        let mut best = (f64::NEG_INFINITY, height(self, self.ring[0] as usize));
        for t in &self.tris {
            let [a, b, c] = t.map(|p| self.pts[p as usize]);
            let area = cross(a, b, c);
            if area.is_nan() || area <= 0.0 {
                continue;
            }
            let l0 = cross(pv, b, c) / area;
            let l1 = cross(a, pv, c) / area;
            let l2 = 1.0 - l0 - l1;
            let min = l0.min(l1).min(l2);
            if min > best.0 {
                let [wa, wb, wc] = t.map(|p| self.ring[p as usize] as usize);
                let h = l0 * height(self, wa) + l1 * height(self, wb) + l2 * height(self, wc);
                best = (min, h);
            }
        }
        (height(self, v as usize) - best.1).abs()
    }
}

fn cross(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// True when `p` lies exactly on the open segment `a b` in 3-D: the three coordinate-plane
/// orientations vanish and `p` is strictly between (exact: adaptive predicates, comparisons).
pub(crate) fn collinear_between(a: [f64; 3], p: [f64; 3], b: [f64; 3]) -> bool {
    for (i, j) in [(0, 1), (1, 2), (2, 0)] {
        if orient2d([a[i], a[j]], [p[i], p[j]], [b[i], b[j]]) != Ordering::Equal {
            return false;
        }
    }
    if p == a || p == b {
        return false;
    }
    (0..3).all(|k| (a[k] <= p[k] && p[k] <= b[k]) || (b[k] <= p[k] && p[k] <= a[k]))
}

/// The fan around `pv` with ring `pts` is a simple star: every fan triangle turns
/// counter-clockwise, and an interior fan winds exactly once around `pv` (a border fan stays
/// strictly left of the line from its last to its first ring point, through `pv`).
pub(crate) fn star_is_simple(pv: [f64; 2], pts: &[[f64; 2]], border: bool) -> bool {
    let l = pts.len();
    let count = if border { l - 1 } else { l };
    for i in 0..count {
        if orient2d(pv, pts[i], pts[(i + 1) % l]) != Ordering::Greater {
            return false;
        }
    }
    if border {
        return (1..l - 1).all(|i| orient2d(pts[l - 1], pts[0], pts[i]) == Ordering::Greater);
    }
    // Count the steps whose angle around pv decreases: exactly one for a single winding.
    let half = |p: [f64; 2]| !(p[1] > pv[1] || (p[1] == pv[1] && p[0] > pv[0]));
    let mut wraps = 0;
    for i in 0..l {
        let (a, b) = (pts[i], pts[(i + 1) % l]);
        let (ha, hb) = (half(a), half(b));
        let decreases = if ha != hb {
            ha && !hb
        } else {
            orient2d(pv, a, b) == Ordering::Less
        };
        wraps += decreases as usize;
    }
    wraps == 1
}

/// Decimates with the fast engine.
pub fn decimate(mesh: &Mesh, options: &Options) -> Result<Outcome, DecimateError> {
    driver::decimate_with(
        mesh,
        options,
        || FastEngine::new(mesh, options),
        |e| {
            let name = mesh.scalars.as_ref().map(|s| s.name.as_str());
            (e.to_mesh(name), e.global.is_some())
        },
    )
}
