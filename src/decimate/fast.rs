//! The fast path: `f64` coordinates, per-node fan lists ([`fans`](super::fans), the paper's
//! Figure 4) naming the triangle slots that removals reuse (Fig. 5), orientation signs from
//! Shewchuk's adaptive predicates.
//!
//! The input's fans are ordered once ([`Fans`], which checks that the mesh is an oriented
//! 2-manifold); the decimation then works on the lists alone. The triangles are read off the
//! lists at the end (every live slot is named by its three corners).
//!
//! The engine is the geometry (what never changes), the mesh state and scratch buffers for
//! planning a removal. The initial evaluation of every node and the embedding check run on
//! all cores (rayon), each thread with its own scratch. The decimation loop is sequential,
//! but the nodes it will take next are evaluated ahead on a second thread
//! ([`ahead`]) from copies of their lists, except those whose last plan still holds (the
//! engine remembers it). The loop prefetches: a node's list, queue record and remembered plan
//! a step before it is handed over, its ring's lists and queue records (and positions when
//! nothing is evaluated ahead) when it reaches the front of the queue (and again after a
//! removal, which may change its ring).

use super::ahead::{self, Evaluated, Job, Lookahead, Planned};
use super::bucket::Scale;
use super::driver::{self, Engine, Removal};
use super::earcut::{
    ear_order, orient2d, pack_cut, simple_ccw, unpack_cut, EarCutter, RobustOrient,
};
use super::fans::{CopiedList, Entry, FanLists, Lists, NO_TRIANGLE};
use super::history::History;
use super::quality::OriginalSurface;
use super::{
    check_options, edge_angle, fallback_planes, fan_normal, global_plane, initial_quadrics,
    BorderPolicy, Carried, Criterion, DecimateError, Options, Outcome, Plane, Quadric,
};
use crate::memory::{huge_copy, huge_vec};
use crate::mesh::fans::Fans;
use crate::mesh::{Mesh, Scalars};
use crate::par::prelude::*;
use std::cmp::Ordering;
use std::sync::atomic::{AtomicBool, Ordering as AtomicOrdering};
use std::sync::Arc;

const NONE: u32 = u32::MAX;

/// No plan remembered ([`FastEngine::memo`]).
const NO_MEMO: u64 = u64::MAX;

/// A plan to remember ([`FastEngine::memo`]) in one word: the packed cut ([`pack_cut`]) in
/// bits 0–55, the border flag in bit 56, the plane's dropped axis in bits 57–58 and its flip
/// in bit 59 (so never [`NO_MEMO`]).
fn memo(border: bool, plane: Plane, cut: u64) -> u64 {
    cut & ((1 << 56) - 1)
        | u64::from(border) << 56
        | (plane.drop as u64) << 57
        | u64::from(plane.flip) << 59
}

/// The plan a [`memo`] word holds, `None` for [`NO_MEMO`].
fn recall(m: u64) -> Option<Planned> {
    (m != NO_MEMO).then_some(Planned::Cut {
        border: m >> 56 & 1 == 1,
        plane: Plane {
            drop: (m >> 57 & 3) as usize,
            flip: m >> 59 & 1 == 1,
        },
        cut: m,
    })
}

/// Smaller meshes are decimated without the lookahead thread: starting and joining it
/// would cost more than it saves.
pub(crate) const LOOK_AHEAD_NODES: usize = 10_000;

/// A hole ready to be filled: the fan, its projection and the ear cut.
#[derive(Clone, Copy)]
struct Plan {
    border: bool,
    plane: Plane,
}

/// What never changes during a decimation: the nodes' data and the settings (shared with the
/// lookahead thread).
struct Geometry {
    pos: Vec<[f64; 3]>,
    /// The original surface's vertex normals ([`vertex_normals`](super::vertex_normals);
    /// [`Criterion::Quadric`] without the facing test only, else empty: the fold test's
    /// corner normals, [`folds`](super::folds)).
    normals: Vec<[f64; 3]>,
    values: Option<Vec<f64>>,
    /// The original surface for the facing test at removals
    /// ([`faces_against_original`](super::quadric::faces_against_original);
    /// [`Criterion::Quadric`] only).
    original: Option<Arc<OriginalSurface>>,
    global: Option<Plane>,
    criterion: Criterion,
    border_policy: BorderPolicy,
    max_valence: usize,
    /// Holes are cut in the global projection and every fan of the input is a simple star
    /// in it. Removals keep that true: the new triangles at a ring node tile exactly the
    /// angular sector its removed triangles covered. Then every fan passes the star test, and
    /// no diagonal of a hole can repeat an existing edge (that edge would leave its endpoint
    /// in a direction inside the hole's sector, which no remaining triangle covers), so
    /// both checks are skipped.
    embedded: bool,
}

/// The mesh as the decimation leaves it.
struct State {
    geo: Arc<Geometry>,
    lists: FanLists,
    /// Per node, its accumulated quadric ([`Criterion::Quadric`]; empty otherwise).
    quadrics: Vec<Quadric>,
    /// Per node, the largest error bound among its triangles ([`Criterion::Quadric`]; empty
    /// otherwise). Kept without reading the triangles: a removal's new triangles take a bound
    /// at least the largest of the removed fan's, and every ring node gets one of them, so a
    /// ring node's largest bound becomes the larger of its old one and the new bound (the
    /// exact engine keeps the bounds per triangle slot; the histories agree).
    node_error: Vec<f64>,
}

impl State {
    /// What `v` carries into its evaluation (zero when the criterion keeps nothing).
    fn carried(&self, v: u32) -> Carried {
        match self.quadrics.get(v as usize) {
            Some(&quadric) => Carried {
                quadric,
                fan_error: self.node_error[v as usize],
            },
            None => Carried::default(),
        }
    }
}

/// Buffers for planning one removal; one per thread when nodes are evaluated in parallel.
#[derive(Default)]
struct Scratch {
    ring: Vec<u32>,
    /// The triangles of the loaded fan (`slot · 4 + corner`), `(v, ring[i], ring[i + 1])`.
    fan: Vec<u32>,
    pts: Vec<[f64; 2]>,
    ring3: Vec<[f64; 3]>,
    /// The ring's original vertex normals (the quadric criterion's fold test).
    ring_normals: Vec<[f64; 3]>,
    tris: Vec<[u8; 3]>,
    /// The node whose cut `tris` holds, cut here, and the cut's crossing deviation (the
    /// quadric criterion, [`flip_toward_fan`](super::flip_toward_fan)); `None` after a cut
    /// was unpacked from a plan (the deviation is then computed again).
    crossing: Option<(u32, f64)>,
    cutter: EarCutter,
    /// The new triangles' corners by ring positions, `succ[at · l + from] = (to, triangle)`
    /// ([`State::apply`]).
    succ: Vec<u64>,
    list: Vec<Entry>,
    chain: Vec<Entry>,
    /// The node whose plan the buffers hold, while nothing has changed since.
    planned: Option<(u32, Plan)>,
    /// The ring positions of the triangle the last node valued under the quadric criterion
    /// lands in ([`landing`](super::landing)).
    corners: [u8; 3],
    /// The error bound of the last removal evaluated under the quadric criterion
    /// ([`removal_bound`](super::removal_bound)).
    bound: f64,
    /// The node `corners` and `bound` were computed for, while its plan holds.
    valued: Option<u32>,
}

pub(crate) struct FastEngine {
    st: State,
    sc: Scratch,
    ahead: Option<Lookahead>,
    /// The lookahead thread to start once the initial pass has set [`Geometry::embedded`]:
    /// `Some(wait)` ([`FastEngine::build`]).
    start_ahead: Option<bool>,
    /// What was evaluated ahead for the node being taken.
    ready: Option<Evaluated>,
    /// The queue's scale and its version ([`Engine::set_scale`]), handed over with the nodes.
    scale: Option<(Scale, u32)>,
    /// Per node, the plan its last evaluation made ([`memo`]), or [`NO_MEMO`] (none made:
    /// the angle and scalar criteria plan only ahead, and a hole too large to pack). A node
    /// taken unchanged since it was filed is removed by it, with nothing evaluated again
    /// ([`Engine::remembers`]). Filled by the initial pass.
    memo: Vec<u64>,
    /// The remembered plan of the node being taken, when it holds.
    recalled: Option<(u32, Planned)>,
    /// How many taken nodes were removed by a remembered plan.
    remembered: usize,
    /// Removals by a fan fill ([`Engine::fan_filled`]).
    filled: usize,
}

impl FastEngine {
    /// Builds the fan lists, checking that the mesh is an oriented 2-manifold; starts the
    /// lookahead thread when [`Options::look_ahead`] asks for it, the machine has more than
    /// one core and the mesh has at least [`LOOK_AHEAD_NODES`] nodes.
    pub(crate) fn new(mesh: &Mesh, options: &Options) -> Result<FastEngine, DecimateError> {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        let look_ahead =
            (options.look_ahead && cores > 1 && mesh.vertices.len() >= LOOK_AHEAD_NODES)
                .then_some(false);
        FastEngine::build(mesh, options, look_ahead)
    }

    /// [`new`](Self::new) with the lookahead thread chosen: `None` for none, `Some(wait)`
    /// for one (`wait`: the loop waits for its results rather than evaluating itself). The
    /// thread starts after the initial pass ([`Engine::evaluate_all`]), which also decides
    /// [`Geometry::embedded`].
    fn build(
        mesh: &Mesh,
        options: &Options,
        look_ahead: Option<bool>,
    ) -> Result<FastEngine, DecimateError> {
        let t = mesh.triangles.len();
        if 3 * t >= NONE as usize / 2 {
            return Err(DecimateError::BadOption(format!(
                "{t} triangles are too many"
            )));
        }
        // The projection decides whether the facing test's original surface is needed; it
        // reads every triangle, so the indices are checked first (as the fan lists do).
        mesh.validate()?;
        let global = global_plane(mesh, options.projection, |tri| {
            let p = tri.map(|i| Plane::XY.project(mesh.vertices[i as usize]));
            orient2d(p[0], p[1], p[2]) != Ordering::Greater
        });
        let wants_surface = options.facing && matches!(global, Ok(None));
        // The original surface's hierarchy is built side by side with the fan lists and
        // quadrics (its build has long one-core stretches, and so do they); errors are
        // reported in the order the steps had one after the other.
        let (original, built) = crate::par::join(
            || {
                wants_surface
                    .then(|| OriginalSurface::new(mesh).map(Arc::new))
                    .flatten()
            },
            || -> Result<_, DecimateError> {
                let lists = fan_lists(mesh)?;
                check_options(mesh, options)?;
                let global = global?;
                let criterion = options.criterion.resolve(global.is_some());
                let quadrics = if criterion == Criterion::Quadric {
                    initial_quadrics(mesh)
                } else {
                    Vec::new()
                };
                Ok((lists, global, criterion, quadrics))
            },
        );
        let (lists, global, criterion, quadrics) = built?;
        // The corner-normal fold test stands in for the facing test ([`super::folds`]).
        let normals = if criterion == Criterion::Quadric && original.is_none() {
            super::vertex_normals(mesh)
        } else {
            Vec::new()
        };
        let geo = Geometry {
            pos: huge_copy(&mesh.vertices),
            normals,
            values: mesh.scalars.as_ref().map(|s| s.values.clone()),
            original,
            global,
            criterion,
            border_policy: options.border.resolve(global.is_some()),
            max_valence: options.max_valence,
            embedded: false,
        };
        Ok(FastEngine {
            st: State {
                geo: Arc::new(geo),
                lists,
                node_error: if quadrics.is_empty() {
                    Vec::new()
                } else {
                    vec![0.0; mesh.vertices.len()]
                },
                quadrics,
            },
            sc: Scratch::default(),
            ahead: None,
            start_ahead: look_ahead,
            ready: None,
            scale: None,
            memo: Vec::new(),
            recalled: None,
            remembered: 0,
            filled: 0,
        })
    }

    /// Starts the lookahead thread if one was asked for and none runs.
    fn start_lookahead(&mut self) {
        let Some(wait) = self.start_ahead.take() else {
            return;
        };
        let geo = Arc::clone(&self.st.geo);
        let mut sc = Scratch::default();
        let batch = if wait { 8 } else { ahead::BATCH };
        self.ahead = Lookahead::spawn(
            move |job, out, passed| sc.evaluate_job(&geo, job, out, passed),
            batch,
            wait,
        );
    }
}

impl Scratch {
    /// The initial pass at `v` when holes are cut in the `global` plane: `v`'s evaluation
    /// value ([`evaluate`](Self::evaluate) with [`Geometry::embedded`] not yet known, so
    /// false) and whether `v`'s fan, whatever its valence, is a simple star in that plane
    /// (all of them: `embedded`). One fan load and projection serve both.
    fn evaluate_initial(
        &mut self,
        geo: &Geometry,
        lists: &FanLists,
        v: u32,
        global: Plane,
        carried: &Carried,
    ) -> (Option<f64>, bool) {
        if lists.is_empty(v) {
            return (None, true);
        }
        let border = self
            .load_fan(lists, v, usize::MAX)
            .expect("no valence limit");
        let pv = self.project_fan(geo, v, global);
        // The fan's triangles are the input's, all counter-clockwise in the global plane.
        let simple = star_winds_once(pv, &self.pts, border);
        if self.ring.len() > geo.max_valence {
            return (None, simple);
        }
        let Some((border, plane)) = self.admit(geo, v, border) else {
            return (None, simple);
        };
        let ev = if geo.criterion.plans() {
            self.cut_projected(geo, v, border, plane, simple)
                .and_then(|plan| self.removal_value(geo, v, plan, carried))
        } else {
            self.mean_value(geo, v, plane)
        };
        (ev, simple)
    }

    /// The memo of what the buffers planned for `v` ([`FastEngine::memo`]).
    fn memo_of(&self, v: u32) -> u64 {
        match self.planned {
            Some((u, plan)) if u == v => pack_cut(self.ring.len(), &self.tris)
                .map_or(NO_MEMO, |cut| memo(plan.border, plan.plane, cut)),
            _ => NO_MEMO,
        }
    }

    /// Projects the loaded ring into `pts` and returns the projection of `v`.
    fn project_fan(&mut self, geo: &Geometry, v: u32, plane: Plane) -> [f64; 2] {
        self.pts.clear();
        self.pts.extend(
            self.ring
                .iter()
                .map(|&w| plane.project(geo.pos[w as usize])),
        );
        plane.project(geo.pos[v as usize])
    }

    /// Evaluates a job's nodes from their copied lists (on the lookahead thread): the value,
    /// and the plan (for the error criterion the evaluation's own). Skips the nodes whose
    /// tickets the loop has `passed`.
    fn evaluate_job(
        &mut self,
        geo: &Geometry,
        job: &Job,
        out: &mut Vec<Evaluated>,
        passed: &dyn Fn(u32) -> bool,
    ) {
        // The positions of the node two ahead start coming now (the lists are in the job).
        let fetch = |k: usize| {
            if let Some(&(u, start, len, _)) = job.nodes.get(k) {
                crate::memory::prefetch(&geo.pos[u as usize]);
                for e in &job.entries[start as usize..(start + len) as usize] {
                    crate::memory::prefetch(&geo.pos[e.node as usize]);
                }
            }
        };
        fetch(0);
        fetch(1);
        for (k, &(v, start, len, border)) in job.nodes.iter().enumerate() {
            fetch(k + 2);
            let ticket = job.first_ticket.wrapping_add(k as u32);
            if passed(ticket) {
                continue;
            }
            let list = CopiedList {
                node: v,
                entries: &job.entries[start as usize..(start + len) as usize],
                border,
            };
            let carried = job.carried.get(k).copied().unwrap_or_default();
            let ev = self.evaluate(geo, &list, v, &carried);
            let planned = match self.planned {
                Some((u, plan)) if u == v => Some(plan),
                _ if !geo.criterion.plans() => self.plan(geo, &list, v),
                _ => None,
            };
            let plan = match planned {
                None => Planned::Refused,
                Some(p) => match pack_cut(self.ring.len(), &self.tris) {
                    Some(cut) => Planned::Cut {
                        border: p.border,
                        plane: p.plane,
                        cut,
                    },
                    None => Planned::NotKept,
                },
            };
            let interval = match (ev, job.scale) {
                (Some(ev), Some((scale, version))) => Some((version, scale.interval(ev) as u32)),
                _ => None,
            };
            let landing = (self.valued == Some(v)).then_some((self.bound, self.corners));
            out.push(Evaluated {
                node: v,
                ticket,
                ev,
                plan,
                interval,
                landing,
            });
        }
    }

    /// Fills `ring` (counter-clockwise) and `fan` (the triangles `(v, ring[i], ring[i + 1])`)
    /// of `v`; returns whether `v` is on the border, or `None` when the valence is over
    /// `limit`. Interior rings start at the lowest id, as in the exact path.
    fn load_fan(&mut self, lists: &impl Lists, v: u32, limit: usize) -> Option<bool> {
        self.planned = None;
        self.valued = None;
        self.ring.clear();
        self.fan.clear();
        if lists.len(v) > limit {
            return None;
        }
        self.list.clear();
        lists.read(v, &mut self.list);
        let border = lists.is_border(v);
        // Interior: from the lowest id on (the first lowest: ids in a fan are distinct).
        let mut start = 0;
        if !border {
            for (j, e) in self.list.iter().enumerate() {
                if e.node < self.list[start].node {
                    start = j;
                }
            }
        }
        let (rest, head) = (&self.list[start..], &self.list[..start]);
        self.ring.extend(rest.iter().map(|e| e.node));
        self.ring.extend(head.iter().map(|e| e.node));
        self.fan.extend(rest.iter().map(|e| e.triangle));
        self.fan.extend(head.iter().map(|e| e.triangle));
        if border {
            // The last entry has no triangle.
            self.fan.pop();
        }
        Some(border)
    }

    /// True when the border node `v` lies exactly on the segment between its two border
    /// neighbours (the border stays intact without it).
    fn border_intact(&self, geo: &Geometry, v: u32) -> bool {
        let a = geo.pos[*self.ring.last().unwrap() as usize];
        let b = geo.pos[self.ring[0] as usize];
        let p = geo.pos[v as usize];
        match geo.global {
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

    /// Loads `v`'s fan and applies the border policy; returns whether `v` is on the border
    /// and the plane its hole is cut in, or `None` when `v` may not go.
    fn candidate(&mut self, geo: &Geometry, lists: &impl Lists, v: u32) -> Option<(bool, Plane)> {
        if lists.is_empty(v) {
            return None;
        }
        let border = self.load_fan(lists, v, geo.max_valence)?;
        self.admit(geo, v, border)
    }

    /// The border policy and the projection plane for `v`'s loaded fan
    /// ([`candidate`](Self::candidate) after the load).
    fn admit(&mut self, geo: &Geometry, v: u32, border: bool) -> Option<(bool, Plane)> {
        if border {
            match geo.border_policy {
                BorderPolicy::Simplify => {}
                BorderPolicy::Intact | BorderPolicy::Auto if self.border_intact(geo, v) => {}
                _ => return None,
            }
        }
        let plane = match geo.global {
            Some(p) => p,
            None => {
                self.ring3.clear();
                self.ring3
                    .extend(self.ring.iter().map(|&w| geo.pos[w as usize]));
                Plane::most_aligned(fan_normal(geo.pos[v as usize], &self.ring3, !border))
            }
        };
        Some((border, plane))
    }

    /// Checks that `v` may go and its hole can be filled: loads the fan, applies the border
    /// policy, projects, checks the fan is a simple star in the projection, cuts the ears.
    fn plan(&mut self, geo: &Geometry, lists: &impl Lists, v: u32) -> Option<Plan> {
        let (border, plane) = self.candidate(geo, lists, v)?;
        if self.ring.len() < 3 {
            return None;
        }
        let pv = self.project_fan(geo, v, plane);
        let simple = geo.embedded || star_is_simple(pv, &self.pts, border);
        if !simple && geo.global.is_none() {
            // Per-fan projection: the other axis planes, in order ([`fallback_planes`]).
            self.ring3.clear();
            self.ring3
                .extend(self.ring.iter().map(|&w| geo.pos[w as usize]));
            let n = fan_normal(geo.pos[v as usize], &self.ring3, !border);
            let planes: Vec<Plane> = std::iter::once(plane).chain(fallback_planes(n)).collect();
            for &other in &planes[1..] {
                let pv = self.project_fan(geo, v, other);
                if star_is_simple(pv, &self.pts, border) {
                    return self.cut_projected(geo, v, border, other, true);
                }
            }
            // The quadric criterion (an estimate anyway) accepts a ring that is a simple
            // counter-clockwise polygon in some axis plane, in the same order.
            if geo.criterion == Criterion::Quadric {
                for other in planes {
                    self.project_fan(geo, v, other);
                    let pts = &self.pts;
                    let lower = |i: usize, j: usize| {
                        (pts[i][0], pts[i][1]).partial_cmp(&(pts[j][0], pts[j][1]))
                            == Some(Ordering::Less)
                    };
                    if simple_ccw(pts.len(), &RobustOrient(pts), lower) {
                        return self.cut_projected(geo, v, border, other, true);
                    }
                }
            }
            return None;
        }
        self.cut_projected(geo, v, border, plane, simple)
    }

    /// Cuts the ears of `v`'s loaded and projected hole, unless its fan is not a `simple`
    /// star ([`plan`](Self::plan) after the projection); under the quadric criterion the cut
    /// is then flipped towards the fan ([`flip_toward_fan`](super::flip_toward_fan)) and put
    /// back in ear order.
    fn cut_projected(
        &mut self,
        geo: &Geometry,
        v: u32,
        border: bool,
        plane: Plane,
        simple: bool,
    ) -> Option<Plan> {
        if self.ring.len() < 3 || !simple {
            return None;
        }
        let orient = RobustOrient(&self.pts);
        if !self.cutter.cut(&self.pts, &orient, &mut self.tris) {
            return None;
        }
        if geo.criterion == Criterion::Quadric {
            self.ring3.clear();
            self.ring3
                .extend(self.ring.iter().map(|&w| geo.pos[w as usize]));
            let p = geo.pos[v as usize];
            let f = super::flip_toward_fan(
                p,
                plane.project(p),
                &self.ring3,
                &self.pts,
                &mut self.tris,
                plane.drop,
                border,
                &orient,
            );
            if f.flipped && !ear_order(self.ring.len(), &mut self.tris) {
                return None;
            }
            self.crossing = Some((v, f.crossing));
        }
        let plan = Plan { border, plane };
        self.planned = Some((v, plan));
        Some(plan)
    }

    /// The evaluation value of `v` ([`Engine::evaluate`]); `carried` is what `v` carries (read
    /// by the quadric criterion only).
    fn evaluate(
        &mut self,
        geo: &Geometry,
        lists: &impl Lists,
        v: u32,
        carried: &Carried,
    ) -> Option<f64> {
        if geo.criterion.plans() {
            let plan = self.plan(geo, lists, v)?;
            return self.removal_value(geo, v, plan, carried);
        }
        let (_, plane) = self.candidate(geo, lists, v)?;
        self.mean_value(geo, v, plane)
    }

    /// The angle or scalar criterion over `v`'s loaded ring.
    fn mean_value(&self, geo: &Geometry, v: u32, plane: Plane) -> Option<f64> {
        let p = geo.pos[v as usize];
        let mut sum = 0.0;
        for &w in &self.ring {
            let w = w as usize;
            sum += if geo.criterion == Criterion::Angle {
                let q = geo.pos[w];
                edge_angle([q[0] - p[0], q[1] - p[1], q[2] - p[2]], plane)
            } else {
                let f = geo.values.as_ref()?;
                (f[w] - f[v as usize]).abs()
            };
        }
        Some(sum / self.ring.len() as f64)
    }

    /// The value of removing `v` as planned (loaded, projected and cut): the error criterion
    /// ([`removal_error`](Self::removal_error)) or the quadric one
    /// ([`quadric_removal`](super::quadric_removal), its bound and landing corners kept in
    /// `bound` and `corners`); `None` when the new triangles would fold the surface over.
    fn removal_value(
        &mut self,
        geo: &Geometry,
        v: u32,
        plan: Plan,
        carried: &Carried,
    ) -> Option<f64> {
        if geo.criterion == Criterion::Quadric {
            self.ring3.clear();
            self.ring3
                .extend(self.ring.iter().map(|&w| geo.pos[w as usize]));
            self.ring_normals.clear();
            if !geo.normals.is_empty() {
                self.ring_normals
                    .extend(self.ring.iter().map(|&w| geo.normals[w as usize]));
            }
            let p = geo.pos[v as usize];
            let pv = plan.plane.project(p);
            let crossing = match self.crossing {
                Some((u, c)) if u == v => c,
                _ => super::crossing_deviation(
                    p,
                    pv,
                    &self.ring3,
                    &self.pts,
                    &self.tris,
                    plan.plane.drop,
                    plan.border,
                ),
            };
            let Some(r) = super::quadric_removal(
                carried,
                p,
                pv,
                &self.ring3,
                &self.pts,
                &self.tris,
                crossing,
                plan.border,
                &self.ring_normals,
            ) else {
                self.planned = None;
                return None;
            };
            (self.bound, self.corners, self.valued) = (r.bound, r.corners, Some(v));
            Some(r.value)
        } else {
            Some(self.removal_error(geo, v, plan.plane))
        }
    }

    /// Replaces `v`'s planned cut, which faces against `original`, by the cheapest fan fill
    /// of its hole ([`fan_fills`](super::quadric::fan_fills)) that passes the topology and
    /// facing tests and does not fold (the first on ties, as the exact engine takes it), and
    /// returns its value; `None`, with the cut kept, when no fill passes.
    fn fan_fill(
        &mut self,
        st: &State,
        original: &OriginalSurface,
        v: u32,
        plan: Plan,
    ) -> Option<f64> {
        self.project_fan(&st.geo, v, plan.plane);
        let fills: Vec<Vec<[u8; 3]>> =
            super::quadric::fan_fills(self.ring.len(), &RobustOrient(&self.pts)).collect();
        let planned = std::mem::take(&mut self.tris);
        // The buffers no longer hold `v`'s planned cut (a removal put off takes `v` again
        // from its plan, as the exact engine does).
        self.planned = None;
        let carried = st.carried(v);
        let mut best: Option<(f64, usize)> = None;
        for (k, fill) in fills.iter().enumerate() {
            self.tris.clone_from(fill);
            self.crossing = None;
            if (st.geo.embedded || self.topology_ok(st, plan.border))
                && !super::quadric::faces_against_original(
                    original,
                    &self.ring,
                    &self.ring3,
                    &self.tris,
                )
            {
                if let Some(value) = self.removal_value(&st.geo, v, plan, &carried) {
                    if best.is_none_or(|(b, _)| value < b) {
                        best = Some((value, k));
                    }
                }
            }
        }
        self.valued = None;
        match best {
            Some((value, k)) => {
                self.tris.clone_from(&fills[k]);
                Some(value)
            }
            None => {
                self.tris = planned;
                None
            }
        }
    }

    /// The error criterion: `|h(v) − h_interp|` over the planned triangles, `h` the scalar or
    /// the height along the projection normal; the triangle is the one whose smallest
    /// barycentric coordinate at `v` is largest.
    fn removal_error(&self, geo: &Geometry, v: u32, plane: Plane) -> f64 {
        let pv = plane.project(geo.pos[v as usize]);
        let height = |w: usize| match &geo.values {
            Some(f) => f[w],
            None => geo.pos[w][plane.drop],
        };
        let interpolated = match super::quadric::deepest_triangle(pv, &self.pts, &self.tris) {
            Some((l, t)) => {
                let [wa, wb, wc] = t.map(|p| self.ring[p as usize] as usize);
                l[0] * height(wa) + l[1] * height(wb) + l[2] * height(wc)
            }
            None => height(self.ring[0] as usize),
        };
        (height(v as usize) - interpolated).abs()
    }

    /// The new triangles must not repeat an edge or a triangle the mesh has outside the hole
    /// (a closed surface seen in a per-fan projection can offer such holes).
    fn topology_ok(&self, st: &State, border: bool) -> bool {
        let l = self.ring.len();
        for t in &self.tris {
            for e in 0..3 {
                let (pa, pb, pc) = (t[e] as usize, t[(e + 1) % 3] as usize, t[(e + 2) % 3]);
                if border && pa == l - 1 && pb == 0 {
                    // The closing edge at a border node is new: it must not exist already.
                    if st.lists.contains(self.ring[pa], self.ring[pb]) {
                        return false;
                    }
                } else if pb == (pa + 1) % l {
                    // Link edge: the triangle across it must not be this one reversed.
                    if st.outer_apex(self.ring[pa], self.ring[pb]) == Some(self.ring[pc as usize]) {
                        return false;
                    }
                } else if pa < pb && st.lists.contains(self.ring[pa], self.ring[pb]) {
                    return false;
                }
            }
        }
        true
    }
}

impl State {
    /// Starts fetching `v`'s list block and position, and what it carries.
    #[inline]
    fn prefetch(&self, v: u32) {
        self.lists.prefetch(v);
        crate::memory::prefetch(&self.geo.pos[v as usize]);
        self.prefetch_carried(v);
    }

    /// Starts fetching what `v` carries (its quadric, two lines, and its error bound).
    #[inline]
    fn prefetch_carried(&self, v: u32) {
        if let (Some(q), Some(e)) = (
            self.quadrics.get(v as usize),
            self.node_error.get(v as usize),
        ) {
            crate::memory::prefetch(&q.0[0]);
            crate::memory::prefetch(&q.0[9]);
            crate::memory::prefetch(e);
        }
    }

    /// The third node of the triangle `(b, a, y)` on the far side of the edge `a → b`, if
    /// any: around `a` it is `(a, y, b)`, so `y` is the entry before `b` in `a`'s list.
    fn outer_apex(&self, a: u32, b: u32) -> Option<u32> {
        let len = self.lists.len(a);
        let j = (0..len).find(|&j| self.lists.get(a, j).node == b)?;
        let before = if j > 0 {
            j - 1
        } else if self.lists.is_border(a) {
            return None;
        } else {
            len - 1
        };
        let e = self.lists.get(a, before);
        (e.triangle != NO_TRIANGLE).then_some(e.node)
    }

    /// Removes `v` as planned in `sc`: records the step, reuses the fan's slots for the new
    /// triangles and rewrites the ring nodes' lists.
    fn apply(&mut self, sc: &mut Scratch, v: u32, border: bool, history: &mut History) {
        sc.planned = None;
        let l = sc.ring.len();
        for &w in &sc.ring {
            self.lists.prefetch(w);
        }
        history.push(
            v,
            border,
            &sc.ring,
            sc.fan.iter().map(|&t| (t >> 2, (t & 3) as u8)),
            &sc.tris,
            self.geo.pos[v as usize],
            self.geo.values.as_ref().map(|f| f[v as usize]),
        );
        // New triangle k takes the fan's k-th slot; the slots after l − 2 fall free. Its
        // corner at ring position `at` leads from `from` to `to` around `at`:
        // succ[at · l + from] = (to, slot · 4 + corner).
        if sc.succ.len() < l * l {
            sc.succ.resize(l * l, 0);
        }
        // Room for the longest chain (l − 1 entries) and a closing entry.
        if sc.chain.len() < l + 1 {
            sc.chain.resize(l + 1, Entry::default());
        }
        for (k, t) in sc.tris.iter().enumerate() {
            let s = sc.fan[k] >> 2;
            for (e, (at, from, to)) in [(t[0], t[1], t[2]), (t[1], t[2], t[0]), (t[2], t[0], t[1])]
                .into_iter()
                .enumerate()
            {
                sc.succ[at as usize * l + from as usize] =
                    u64::from(4 * s + e as u32) | u64::from(to) << 32;
            }
        }
        for i in 0..l {
            self.relink(sc, v, i);
        }
        self.lists.retire(v);
    }

    /// Rewrites the list of ring node `w = ring[i]` after `v`'s removal. Around `w` the new
    /// triangles form a chain from `ring[i + 1]` to `ring[i − 1]` (a border node's ring does
    /// not wrap: its ends gain the closing edge) that replaces the sector `v` held
    /// ([`FanLists::give_way`]).
    fn relink(&mut self, sc: &mut Scratch, v: u32, i: usize) {
        let l = sc.ring.len();
        let w = sc.ring[i];
        let last = if i == 0 { l - 1 } else { i - 1 };
        // The chain: (x_j, the new triangle (w, x_j, x_j+1)) from x_0 = ring[i + 1] on, in
        // `chain[..k]` (sized by `apply`).
        let row = &sc.succ[i * l..(i + 1) * l];
        let mut from = if i + 1 == l { 0 } else { i + 1 };
        let mut k = 0;
        while from != last && k < l {
            let step = row[from];
            sc.chain[k] = Entry {
                node: sc.ring[from],
                triangle: step as u32,
            };
            k += 1;
            from = (step >> 32) as usize;
        }
        sc.chain[k] = Entry {
            node: sc.ring[last],
            triangle: NO_TRIANGLE,
        };
        self.lists.give_way(w, v, &sc.chain[..=k], &mut sc.list);
    }

    /// The decimated mesh.
    fn to_mesh(&self, name: Option<&str>) -> Mesh {
        let geo = &self.geo;
        // The nodes left, in order (one pass over the headers, on all cores).
        let kept: Vec<u32> = (0..geo.pos.len() as u32)
            .into_par_iter()
            .filter(|&v| !self.lists.is_retired(v))
            .collect();
        let vertices = kept.iter().map(|&v| geo.pos[v as usize]).collect();
        let values = match &geo.values {
            Some(f) => kept.iter().map(|&v| f[v as usize]).collect(),
            None => Vec::new(),
        };
        // Every live slot, from the list of its corner 0: entry (a, t) at v with v at corner 0
        // of t is the triangle (v, a, b), b the next entry's node; in slot order.
        let mut live: Vec<(u32, [u32; 3])> = Vec::new();
        let mut list = Vec::new();
        for &v in &kept {
            list.clear();
            self.lists.read(v, &mut list);
            for (i, e) in list.iter().enumerate() {
                if e.triangle != NO_TRIANGLE && e.corner() == 0 {
                    let b = list[if i + 1 == list.len() { 0 } else { i + 1 }].node;
                    live.push((e.slot(), [v, e.node, b]));
                }
            }
        }
        live.sort_unstable_by_key(|&(slot, _)| slot);
        let new_id = |v: u32| kept.binary_search(&v).map_or(NONE, |i| i as u32);
        let triangles = live.iter().map(|&(_, t)| t.map(new_id)).collect();
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
        self.st.geo.pos.len()
    }

    fn evaluate(&mut self, v: u32) -> Option<f64> {
        if let Some(r) = self.ready.filter(|r| r.node == v) {
            return r.ev;
        }
        let c = self.st.carried(v);
        let ev = self.sc.evaluate(&self.st.geo, &self.st.lists, v, &c);
        if let Some(m) = self.memo.get_mut(v as usize) {
            *m = self.sc.memo_of(v);
        }
        ev
    }

    /// In parallel (rayon), each thread with its own scratch buffers. With a global plane
    /// the same pass decides [`Geometry::embedded`]; then the lookahead thread starts.
    fn evaluate_all(&mut self, keep: impl Fn(f64) -> bool + Sync) -> Vec<(u32, f64)> {
        let (geo, lists, st) = (&*self.st.geo, &self.st.lists, &self.st);
        let all_simple = AtomicBool::new(geo.global.is_some());
        let mut memo = huge_vec(NO_MEMO, geo.pos.len());
        let initial = memo
            .par_iter_mut()
            .enumerate()
            .map_init(Scratch::default, |sc, (v, m)| {
                let v = v as u32;
                let c = st.carried(v);
                let ev = match geo.global {
                    Some(global) => {
                        let (ev, simple) = sc.evaluate_initial(geo, lists, v, global, &c);
                        if !simple {
                            all_simple.store(false, AtomicOrdering::Relaxed);
                        }
                        ev
                    }
                    None => sc.evaluate(geo, lists, v, &c),
                };
                *m = sc.memo_of(v);
                ev.filter(|&ev| keep(ev)).map(|ev| (v, ev))
            })
            .flatten_iter()
            .collect();
        self.memo = memo;
        if let Some(geo) = Arc::get_mut(&mut self.st.geo) {
            // Border removals change the domain: its fans need not stay simple stars.
            geo.embedded = all_simple.into_inner() && geo.border_policy != BorderPolicy::Simplify;
        }
        self.start_lookahead();
        initial
    }

    fn look_ahead_lead(&self) -> usize {
        self.ahead.as_ref().map_or(0, Lookahead::lead)
    }

    fn look_ahead(&mut self, v: u32, ticket: u32) {
        if let Some(ahead) = &mut self.ahead {
            let c = (!self.st.quadrics.is_empty()).then(|| self.st.carried(v));
            ahead.add(v, ticket, &self.st.lists, c, self.scale);
        }
    }

    fn set_scale(&mut self, scale: Scale, version: usize) {
        self.scale = Some((scale, version as u32));
    }

    fn interval_of(&self, v: u32, version: usize) -> Option<usize> {
        let (ver, j) = self.ready.filter(|r| r.node == v)?.interval?;
        (ver == version as u32).then_some(j as usize)
    }

    fn evaluated_ahead(&self) -> usize {
        self.ahead.as_ref().map_or(0, |a| a.used)
    }

    fn remembered(&self) -> usize {
        self.remembered
    }

    fn remembers(&self, v: u32) -> bool {
        self.memo.get(v as usize).is_some_and(|&m| m != NO_MEMO)
    }

    fn take(&mut self, v: u32, ticket: Option<u32>, unchanged: bool) {
        // An unchanged node is tried for removal now: the facing test reads its ring's seed
        // leaves (their indices fetched a step ago), the removal its ring's quadrics and
        // bounds.
        if let (true, Some(o)) = (unchanged, self.st.geo.original.as_deref()) {
            self.st.lists.for_each(v, |e| {
                o.closest.prefetch_seed(e.node);
                self.st.prefetch_carried(e.node);
            });
        }
        self.ready = match (&mut self.ahead, ticket) {
            (Some(ahead), Some(t)) => ahead.result(v, t),
            _ => None,
        };
        self.recalled = None;
        let Some(m) = self.memo.get_mut(v as usize) else {
            return;
        };
        match self.ready {
            // What was evaluated ahead is now the node's last evaluation.
            Some(r) => {
                *m = match r.plan {
                    Planned::Cut { border, plane, cut } => memo(border, plane, cut),
                    _ => NO_MEMO,
                }
            }
            None if unchanged => self.recalled = recall(*m).map(|plan| (v, plan)),
            None => {}
        }
    }

    fn prefetch(&self, v: u32) {
        self.st.prefetch(v);
        if let Some(m) = self.memo.get(v as usize) {
            crate::memory::prefetch(m);
        }
    }

    /// The ring's lists (for relinking), and their positions when there is no lookahead
    /// thread: with one, the loop seldom evaluates a node itself, and fewer prefetches in
    /// flight leave more room for those it needs (about 4 % faster on the 810k grid).
    fn prefetch_ring(&self, v: u32, mut each: impl FnMut(u32)) {
        let positions = self.ahead.is_none();
        let original = self.st.geo.original.as_deref();
        self.st.lists.for_each(v, |e| {
            self.st.lists.prefetch(e.node);
            if positions {
                crate::memory::prefetch(&self.st.geo.pos[e.node as usize]);
            }
            if let Some(o) = original {
                o.closest.prefetch_seed_index(e.node);
            }
            each(e.node);
        });
    }

    fn criterion(&self) -> Criterion {
        self.st.geo.criterion
    }

    fn fan_filled(&self) -> usize {
        self.filled
    }

    fn original_surface(&self) -> Option<Arc<OriginalSurface>> {
        self.st.geo.original.clone()
    }

    fn blocked(&mut self) -> Option<super::Blocked> {
        let (st, sc) = (&self.st, &mut self.sc);
        let geo = &*st.geo;
        let mut b = super::Blocked::default();
        for v in 0..geo.pos.len() as u32 {
            if st.lists.is_empty(v) {
                continue;
            }
            // The checks of an evaluation and a removal, in their order.
            let border = sc
                .load_fan(&st.lists, v, usize::MAX)
                .expect("no valence limit");
            let count = if sc.ring.len() > geo.max_valence {
                &mut b.valence
            } else if sc.admit(geo, v, border).is_none() {
                &mut b.border
            } else {
                match sc.plan(geo, &st.lists, v) {
                    None => &mut b.no_plane,
                    Some(plan) => {
                        let carried = st.carried(v);
                        if geo.criterion.plans()
                            && sc.removal_value(geo, v, plan, &carried).is_none()
                        {
                            &mut b.fold
                        } else if !geo.embedded && !sc.topology_ok(st, plan.border) {
                            &mut b.topology
                        } else if geo.original.as_deref().is_some_and(|original| {
                            sc.ring3.clear();
                            sc.ring3
                                .extend(sc.ring.iter().map(|&w| geo.pos[w as usize]));
                            super::quadric::faces_against_original(
                                original, &sc.ring, &sc.ring3, &sc.tris,
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
        let (st, sc) = (&mut self.st, &mut self.sc);
        let recalled = self
            .recalled
            .take()
            .filter(|&(u, _)| u == v)
            .map(|(_, p)| p);
        let ready = self.ready.take().filter(|r| r.node == v);
        let landing = ready.and_then(|r| r.landing);
        let ready = ready.map(|r| r.plan);
        let from_memo = ready.is_none() && recalled.is_some();
        let plan = match (sc.planned, ready.or(recalled)) {
            (Some((u, plan)), _) if u == v => plan,
            (_, Some(Planned::Refused)) => return Removal::Refused,
            (_, Some(Planned::Cut { border, plane, cut })) => {
                // The list is unchanged since it was handed over (or since the evaluation
                // remembered): the same fan, and the cut planned from it then.
                self.remembered += from_memo as usize;
                sc.load_fan(&st.lists, v, usize::MAX);
                unpack_cut(cut, &mut sc.tris);
                sc.crossing = None;
                Plan { border, plane }
            }
            _ => match sc.plan(&st.geo, &st.lists, v) {
                Some(plan) => plan,
                None => return Removal::Refused,
            },
        };
        if !st.geo.embedded && !sc.topology_ok(st, plan.border) {
            return Removal::Refused;
        }
        let mut refilled = false;
        if let Some(original) = &st.geo.original {
            sc.ring3.clear();
            sc.ring3
                .extend(sc.ring.iter().map(|&w| st.geo.pos[w as usize]));
            if super::quadric::faces_against_original(original, &sc.ring, &sc.ring3, &sc.tris) {
                // Under the quadric criterion, the cheapest fan fill that passes instead.
                if st.geo.criterion != Criterion::Quadric {
                    return Removal::Refused;
                }
                match sc.fan_fill(st, original, v, plan) {
                    None => return Removal::Refused,
                    Some(value) if !fits(value) => return Removal::Later(value),
                    Some(_) => {
                        refilled = true;
                        self.filled += 1;
                    }
                }
            }
        }
        if !st.quadrics.is_empty() {
            // The removed node's quadric passes to the corners of the triangle it lands in.
            // What its evaluation just computed, or what was evaluated ahead with the plan,
            // holds; a remembered plan is valued again (the same inputs, the same numbers),
            // and so is a fan fill.
            let fresh =
                !refilled && sc.valued == Some(v) && matches!(sc.planned, Some((u, _)) if u == v);
            if let (false, false, Some((bound, corners))) = (refilled, fresh, landing) {
                // Evaluated ahead from the same list and the same carried values.
                sc.bound = bound;
                sc.corners = corners;
            } else if !fresh {
                if !matches!(sc.planned, Some((u, _)) if u == v) {
                    sc.project_fan(&st.geo, v, plan.plane);
                }
                let carried = st.carried(v);
                if sc.removal_value(&st.geo, v, plan, &carried).is_none() {
                    return Removal::Refused;
                }
            }
            let q = st.quadrics[v as usize];
            for k in sc.corners {
                st.quadrics[sc.ring[k as usize] as usize].add(&q);
            }
            // Every ring node gets new triangles with the removal's bound.
            for &w in &sc.ring {
                let e = &mut st.node_error[w as usize];
                *e = e.max(sc.bound);
            }
        }
        st.apply(sc, v, plan.border, history);
        Removal::Removed
    }
}

/// Every vertex's fan list, from the mesh's fans ([`Fans`], which checks that the mesh is an
/// oriented 2-manifold).
fn fan_lists(mesh: &Mesh) -> Result<FanLists, DecimateError> {
    let fans = Fans::of(mesh)?;
    let n = mesh.vertices.len();
    let corner = |h: u32, k: usize| mesh.triangles[h as usize / 3][(h as usize % 3 + k) % 3];
    let lists = FanLists::build(n, |v, list| {
        let corners = fans.corners(v);
        let Some(&last) = corners.last() else {
            return false;
        };
        list.extend(corners.iter().map(|&h| Entry {
            node: corner(h, 1),
            triangle: 4 * (h / 3) + h % 3,
        }));
        let border = fans.is_border(v);
        if border {
            list.push(Entry {
                node: corner(last, 2),
                triangle: NO_TRIANGLE,
            });
        }
        border
    });
    Ok(lists)
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
    star_test(pv, pts, border, true)
}

/// [`star_is_simple`] for a fan whose every triangle is known to turn counter-clockwise (an
/// input fan in the global plane, which [`global_plane`](super::global_plane) checked): the
/// winding, or for a border fan the line test, alone.
fn star_winds_once(pv: [f64; 2], pts: &[[f64; 2]], border: bool) -> bool {
    star_test(pv, pts, border, false)
}

/// [`star_is_simple`], testing the triangles' turns only when `turns` is set.
#[inline(always)]
fn star_test(pv: [f64; 2], pts: &[[f64; 2]], border: bool, turns: bool) -> bool {
    let (Some(&first), Some(&last)) = (pts.first(), pts.last()) else {
        return false;
    };
    // The angle around pv, from the positive x direction: in [0, π) "upper", else "lower".
    let lower = |p: [f64; 2]| !(p[1] > pv[1] || (p[1] == pv[1] && p[0] > pv[0]));
    // Every step turns counter-clockwise, so it is less than π; an interior fan winds once
    // when exactly one step crosses from the lower half to the upper (angle 2π to 0).
    let mut wraps = 0;
    let closing = (!border).then_some((last, first));
    for (a, b) in pts.windows(2).map(|w| (w[0], w[1])).chain(closing) {
        if turns && orient2d(pv, a, b) != Ordering::Greater {
            return false;
        }
        wraps += (lower(a) && !lower(b)) as usize;
    }
    if border {
        let mut inner = pts.iter().skip(1).take(pts.len().saturating_sub(2));
        return inner.all(|&p| orient2d(last, first, p) == Ordering::Greater);
    }
    wraps == 1
}

/// Decimates with the fast engine.
pub(crate) fn decimate(mesh: &Mesh, options: &Options) -> Result<Outcome, DecimateError> {
    driver::decimate_with(
        mesh,
        options,
        || FastEngine::new(mesh, options),
        |e| {
            let name = mesh.scalars.as_ref().map(|s| s.name.as_str());
            (e.st.to_mesh(name), e.st.geo.global.is_some())
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::decimate::data::{height_grid, paper_plate, wheel};
    use crate::decimate::{ProjectionChoice, Stats, Target};

    /// The history (as bytes), how many taken nodes used a result evaluated ahead, and the
    /// statistics, with the lookahead thread chosen as in [`FastEngine::build`].
    fn run(mesh: &Mesh, options: &Options, look_ahead: Option<bool>) -> (Vec<u8>, usize, Stats) {
        let used = std::cell::Cell::new(0);
        let out = driver::decimate_with(
            mesh,
            options,
            || FastEngine::build(mesh, options, look_ahead),
            |e| {
                used.set(e.ahead.as_ref().map_or(0, |a| a.used));
                let name = mesh.scalars.as_ref().map(|s| s.name.as_str());
                (e.st.to_mesh(name), e.st.geo.global.is_some())
            },
        )
        .expect("decimates");
        (out.history.to_bytes(), used.get(), out.stats)
    }

    /// The fast star test agrees with the exact path's on small fans full of collinear and
    /// repeated points (integer coordinates in `-2..=2`), interior and border.
    #[test]
    fn star_test_agrees_with_the_exact_path() {
        use crate::num::rational_from_f64;
        let mut rng = crate::decimate::TestRng(0x2545_f491_4f6c_dd1d);
        let mut next = |m: u64| rng.below(m);
        let (mut simple, mut cases, mut turning_fans) = (0, 0, 0);
        for _ in 0..40_000 {
            let l = 1 + next(8) as usize;
            let border = next(2) == 1;
            let mut point = || [next(5) as f64 - 2.0, next(5) as f64 - 2.0];
            let pv = point();
            let pts: Vec<[f64; 2]> = (0..l).map(|_| point()).collect();
            let exact =
                |p: [f64; 2]| p.map(|x| rational_from_f64(x, "coordinate").expect("finite"));
            let ring: Vec<_> = pts.iter().map(|&p| exact(p)).collect();
            let want = super::super::exact::simple_star(&exact(pv), &ring, border);
            assert_eq!(
                star_is_simple(pv, &pts, border),
                want,
                "{pv:?} {pts:?} {border}"
            );
            // Where every fan triangle turns counter-clockwise, the winding test alone says
            // the same.
            let steps = pts.len() - border as usize;
            let turning = (0..steps)
                .all(|i| orient2d(pv, pts[i], pts[(i + 1) % pts.len()]) == Ordering::Greater);
            if turning {
                assert_eq!(star_winds_once(pv, &pts, border), want, "{pv:?} {pts:?}");
                turning_fans += 1;
            }
            simple += want as usize;
            cases += 1;
        }
        println!(
            "star test: {cases} fans, {simple} simple stars, fast = exact on all; \
             {turning_fans} turning left throughout, winding test alone = exact on those"
        );
        assert!(turning_fans > simple, "{turning_fans}");
        assert!(
            simple > 1000,
            "the cases exercise simple stars too: {simple}"
        );
    }

    #[test]
    fn evaluating_ahead_changes_nothing() {
        let grid = height_grid(60);
        let plate = paper_plate();
        let hub = wheel(40);
        use Criterion::{Angle, Error, Quadric, Scalar};
        use ProjectionChoice::{Auto, PerFan};
        let cases = [
            ("grid, error", &grid, Error, Auto, true, 0.05),
            ("grid, quadric per-fan", &grid, Quadric, PerFan, true, 0.05),
            ("plate, quadric", &plate, Quadric, Auto, true, 0.05),
            ("grid, angle", &grid, Angle, Auto, true, 0.05),
            ("grid, per-fan", &grid, Error, PerFan, true, 0.05),
            ("grid, eager", &grid, Error, Auto, false, 0.05),
            ("plate, scalar", &plate, Scalar, Auto, true, 0.05),
            ("plate, error", &plate, Error, Auto, true, 0.05),
            ("wheel of 40 spokes, scalar", &hub, Scalar, Auto, true, 0.5),
        ];
        for (name, mesh, criterion, projection, lazy, keep) in cases {
            let options = Options {
                criterion,
                projection,
                lazy,
                target: Target::Keep(keep),
                ..Options::default()
            };
            let (alone, none, stats) = run(mesh, &options, None);
            let (helped, _, _) = run(mesh, &options, Some(false));
            let (waited, used, waited_stats) = run(mesh, &options, Some(true));
            let (removed, remembered) = (stats.removed, waited_stats.remembered);
            assert_eq!(none, 0);
            assert!(
                alone == helped && alone == waited,
                "{name}: histories differ"
            );
            println!("{name}: {removed} removals, {used} taken nodes used what was evaluated ahead, {remembered} were removed by a remembered plan; the same history alone, helped and waited for");
            // (Few with the angle criterion: its ties keep neighbours adjacent in the queue,
            // and a node marked after it was handed over is evaluated by the loop. None when
            // re-evaluation is eager: every taken node then has its remembered plan.)
            assert!(used + remembered > 0, "{name}: {used} of {removed}");
            // Plans are remembered wherever the evaluation plans (the error criterion).
            if criterion == Error || criterion == Quadric {
                assert!(remembered > 0, "{name}: {remembered}");
                assert!(stats.remembered > 0, "{name}: {}", stats.remembered);
            }
        }
    }
}
