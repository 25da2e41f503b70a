//! The decimation loop of Section 1, steps 1–7, shared by both engines: evaluate every node
//! and file it in the bucket queue; take the first node of the lowest non-empty interval;
//! remove it (the engine deletes the fan, cuts ears and records the step) or, when its hole
//! cannot be re-triangulated validly, skip it; re-evaluate the removed node's neighbours and
//! file them at the tails of their intervals; stop at the target.
//!
//! Lazy re-evaluation ([`Options::lazy`], an extension): instead of re-evaluating the
//! neighbours at once, a queued neighbour is marked stale and stays where it is; when a stale
//! node reaches the front it is evaluated, and removed if its value still belongs to the
//! lowest non-empty interval, else re-filed at the tail of its new interval. Neighbours that
//! are not queued are evaluated at once, as in the paper. On the 810k-node grid this takes
//! 1.7 evaluations per removal instead of 5.9.

use super::bucket::{interval_count, BucketQueue, Scale};
use super::history::fingerprint;
use super::quality::OriginalSurface;
use super::{History, Options, Outcome, Stats, Target};
use crate::mesh::Mesh;

/// With re-binning on, the queue is rebuilt once more than `1/REBIN_FRACTION` of the queued
/// nodes were re-filed above its range (on the 810k grid 2 gave the lowest maximum error
/// among 1, 2, 4 and 16).
const REBIN_FRACTION: usize = 2;

/// What an engine provides to the loop.
pub(crate) trait Engine {
    /// The number of nodes (vertices) of the input.
    fn node_count(&self) -> usize;
    /// The evaluation value of `v` when it may be removed now (present, in a fan, allowed by
    /// the border policy and the valence limit; for the error criterion also a triangulable
    /// hole), else `None`.
    fn evaluate(&mut self, v: u32) -> Option<f64>;
    /// `(v, evaluate(v))` for every node in increasing order whose value `keep` accepts (the
    /// initial pass).
    fn evaluate_all(&mut self, keep: impl Fn(f64) -> bool + Sync) -> Vec<(u32, f64)> {
        (0..self.node_count() as u32)
            .filter_map(|v| self.evaluate(v).filter(|&ev| keep(ev)).map(|ev| (v, ev)))
            .collect()
    }
    /// How many nodes ahead of the loop the engine wants to hear of the nodes it will take
    /// ([`look_ahead`](Self::look_ahead)); 0 for none.
    fn look_ahead_lead(&self) -> usize {
        0
    }
    /// A node the loop expects to take later, after those it was told of before (tickets
    /// increase by one): the engine may evaluate it meanwhile, from its list as it is now.
    fn look_ahead(&mut self, _v: u32, _ticket: u32) {}
    /// Whether the engine kept the plan of its last evaluation of `v`: when `v` is taken
    /// unchanged since it was last filed, that plan holds and nothing need be evaluated ahead.
    fn remembers(&self, _v: u32) -> bool {
        false
    }
    /// `v` is taken next. `ticket` is the one it was handed over with when its list is
    /// unchanged since (the queue's promise), so what was evaluated from it then holds;
    /// `unchanged`: its list is unchanged since it was last filed, so what the evaluation it
    /// was filed after planned holds ([`remembers`](Self::remembers)).
    fn take(&mut self, _v: u32, _ticket: Option<u32>, _unchanged: bool) {}
    /// The queue's intervals are now `scale` (`version` counts its changes): an engine that
    /// looks ahead may compute the intervals of the values it evaluates ahead.
    fn set_scale(&mut self, _scale: Scale, _version: usize) {}
    /// The interval of the value [`evaluate`](Self::evaluate) just gave for `v`, when the
    /// engine computed it under the scale of `version`.
    fn interval_of(&self, _v: u32, _version: usize) -> Option<usize> {
        None
    }
    /// How many taken nodes used what was evaluated ahead.
    fn evaluated_ahead(&self) -> usize {
        0
    }
    /// How many taken nodes were removed by a remembered plan ([`remembers`](Self::remembers)).
    fn remembered(&self) -> usize {
        0
    }
    /// Why each node left cannot go, when the loop stopped above its target with no valid
    /// removal left ([`Blocked`](super::Blocked)); `None` when the engine does not tell.
    fn blocked(&mut self) -> Option<super::Blocked> {
        None
    }
    /// A hint that `v` comes soon: start fetching its own data.
    fn prefetch(&self, _v: u32) {}
    /// A hint that `v` comes next, its own data fetched already: start fetching its
    /// neighbours' data, and call `each` on every neighbour.
    fn prefetch_ring(&self, _v: u32, _each: impl FnMut(u32)) {}
    /// Removes `v` and records the step, or refuses (nothing changed) when its hole cannot
    /// be re-triangulated validly. Called right after `evaluate(v)`, an engine may reuse what
    /// that evaluation planned. When the planned fill fails a test only a removal makes (the
    /// facing test) and another fill passes at a higher value, the removal goes ahead if
    /// `fits` accepts that value (it files where `v` was taken from, or lower), and is
    /// otherwise deferred ([`Removal::Later`]).
    fn try_remove(&mut self, v: u32, history: &mut History, fits: &dyn Fn(f64) -> bool) -> Removal;
    /// How many removals took a fan fill instead of their planned cut
    /// ([`fan_fills`](super::quadric::fan_fills)).
    fn fan_filled(&self) -> usize;
    /// The criterion the engine evaluates nodes by (resolved: never `Auto`).
    fn criterion(&self) -> super::Criterion;
    /// The original surface the removals were checked against
    /// ([`faces_against_original`](super::quadric::faces_against_original)), when they were:
    /// the fit keeps its moves to the same rule.
    fn original_surface(&self) -> Option<std::sync::Arc<OriginalSurface>> {
        None
    }
}

/// What [`Engine::try_remove`] did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Removal {
    Removed,
    /// No valid fill: nothing changed.
    Refused,
    /// Only a fill of this value passes, and `fits` did not accept it: nothing changed, and
    /// the node is filed again at that value.
    Later(f64),
}

/// The loop's counts.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct LoopCounts {
    pub removed: usize,
    pub refused: usize,
    /// Removals put off to a later interval ([`Removal::Later`]).
    pub deferred: usize,
    /// Removals by a fan fill ([`Engine::fan_filled`]).
    pub filled: usize,
    pub intervals: usize,
    pub rebuilds: usize,
    /// Evaluations after the initial pass.
    pub evaluations: usize,
    pub taken: usize,
    pub evaluated_ahead: usize,
    pub remembered: usize,
    /// Seconds on `clock` when the first node was taken.
    pub setup_seconds: f64,
    /// Why the nodes left cannot go, when the queue ran dry above the target.
    pub blocked: Option<super::Blocked>,
}

/// The node count `target` asks for on `n` nodes of which `unused` are in no triangle (they
/// are counted on top); `None` for an error bound.
pub(crate) fn node_target(target: Target, n: usize, unused: usize) -> Option<usize> {
    let surface = n.saturating_sub(unused);
    match target {
        Target::Keep(f) => Some(unused + (f * surface as f64).round() as usize),
        Target::Nodes(k) => Some(unused + k),
        Target::ErrorBound(_) => None,
    }
}

/// Runs the loop to the target; the removal sequence is in `history`.
/// `clock` started with the decimation (for [`LoopCounts::setup_seconds`]); `unused` of the
/// nodes are in no triangle (never removed, not counted by the target); `unit`: the unit the
/// queue measures values in ([`BucketQueue::in_units`]).
pub(crate) fn run(
    engine: &mut impl Engine,
    options: &Options,
    history: &mut History,
    clock: std::time::Instant,
    unused: usize,
    unit: f64,
) -> LoopCounts {
    let n = engine.node_count();
    let bound = match options.target {
        Target::ErrorBound(e) => Some(e),
        _ => None,
    };
    let target_nodes = node_target(options.target, n, unused).unwrap_or(0);
    let admissible = |ev: f64| bound.is_none_or(|b| ev <= b);
    let initial = engine.evaluate_all(admissible);
    let (lo, hi) = initial
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &(_, ev)| {
            (lo.min(ev), hi.max(ev))
        });
    let m = interval_count(n, options.k);
    let mut queue = BucketQueue::in_units(n, m, lo, hi, unit);
    if options.rebin {
        queue = queue.rebinning(options.k, REBIN_FRACTION);
    }
    queue.push_all(&initial);
    drop(initial);
    let mut counts = LoopCounts {
        intervals: m,
        setup_seconds: clock.elapsed().as_secs_f64(),
        ..LoopCounts::default()
    };
    let mut present = n;
    // Removals to come (at most); rings average six nodes on triangle meshes (Euler).
    history.reserve(n.saturating_sub(target_nodes).min(queue.len()), 7);
    let lead = engine.look_ahead_lead();
    let mut ahead = LookAheadState::default();
    let mut scale_version = None;
    while present > target_nodes {
        if lead > 0 {
            if scale_version != Some(queue.rebuilds()) {
                scale_version = Some(queue.rebuilds());
                engine.set_scale(queue.scale(), queue.rebuilds());
            }
            ahead.step(&mut queue, engine, lead);
        }
        let Some(taken) = queue.pop() else {
            break;
        };
        let (v, j, stale) = (taken.node, taken.interval, taken.marked);
        counts.taken += 1;
        engine.take(v, taken.ticket, !stale);
        // The next node's list arrived a step ago (or when it was handed over): fetch its
        // ring's data ([`Engine::prefetch_ring`]) and queue records, and its own record.
        let next = queue.peek();
        if let Some(u) = next {
            engine.prefetch_ring(u, |w| queue.prefetch(w));
            queue.prefetch(u);
        }
        if stale {
            counts.evaluations += 1;
            match engine.evaluate(v) {
                Some(ev) if admissible(ev) => {
                    let to = engine
                        .interval_of(v, queue.rebuilds())
                        .unwrap_or_else(|| queue.interval(ev));
                    if to > j {
                        queue.push_to(v, ev, to);
                        continue;
                    }
                }
                _ => continue,
            }
        }
        match engine.try_remove(v, history, &|ev| queue.interval(ev) <= j) {
            Removal::Removed => {}
            Removal::Refused => {
                counts.refused += 1;
                continue;
            }
            Removal::Later(ev) => {
                if admissible(ev) {
                    counts.deferred += 1;
                    queue.push(v, ev);
                } else {
                    counts.refused += 1;
                }
                continue;
            }
        }
        present -= 1;
        counts.removed += 1;
        let ring = history.last_ring();
        if options.lazy {
            for &w in ring {
                queue.prefetch(w);
            }
        }
        for &w in ring {
            // Lazy: a queued neighbour is marked stale (the queue's mark).
            if options.lazy && queue.mark(w) {
                continue;
            }
            counts.evaluations += 1;
            match engine.evaluate(w) {
                Some(ev) if admissible(ev) => queue.push(w, ev),
                _ => queue.remove(w),
            }
        }
        // Unless the removal changed the next node (a neighbour filed in front).
        if let Some(u) = queue.peek().filter(|&u| Some(u) != next) {
            engine.prefetch_ring(u, |w| queue.prefetch(w));
        }
    }
    if bound.is_none() && present > target_nodes && queue.is_empty() {
        counts.blocked = engine.blocked();
    }
    counts.rebuilds = queue.rebuilds();
    counts.evaluated_ahead = engine.evaluated_ahead();
    counts.remembered = engine.remembered();
    counts.filled = engine.fan_filled();
    counts
}

/// The hand-over to an engine that looks ahead: a cursor walking the queue in pop order,
/// `lead` nodes ahead of the loop.
#[derive(Default)]
struct LookAheadState {
    /// The last node handed over.
    cursor: Option<u32>,
    /// The node after the cursor, found at the step before: its record and list were
    /// fetched then, it gets its ticket and is told to the engine now.
    found: Option<u32>,
    next_ticket: u32,
}

impl LookAheadState {
    /// Called before each take: hands one more node over, so that the cursor keeps its
    /// lead (each take removes one node ahead of it). When the cursor starts from the front
    /// (at the beginning, or when the loop caught up with it) it walks the whole lead at
    /// once; otherwise one node per step, whose record and list are fetched a step before
    /// they are read.
    fn step(&mut self, queue: &mut BucketQueue, engine: &mut impl Engine, lead: usize) {
        if let Some(v) = self.found.take() {
            self.hand(queue, engine, v);
        }
        let Some((v, front)) = queue.next_after(self.cursor) else {
            return;
        };
        if !front {
            queue.prefetch(v);
            engine.prefetch(v);
            self.found = Some(v);
            return;
        }
        self.hand(queue, engine, v);
        for _ in 1..lead {
            match queue.next_after(self.cursor) {
                Some((w, false)) => self.hand(queue, engine, w),
                _ => return,
            }
        }
    }

    /// Gives `v` the next ticket and tells the engine, when `v` is still queued and the
    /// engine does not remember a plan that holds (`v` unmarked since it was filed).
    fn hand(&mut self, queue: &mut BucketQueue, engine: &mut impl Engine, v: u32) {
        if queue.contains(v) && !queue.is_marked(v) && engine.remembers(v) {
            self.cursor = Some(v);
        } else if queue.give_ticket(v, self.next_ticket) {
            engine.look_ahead(v, self.next_ticket);
            self.next_ticket = self.next_ticket.wrapping_add(1);
            self.cursor = Some(v);
        }
    }
}

/// Runs an engine built by `build` on `mesh` and packages the outcome: the decimated mesh
/// (`finish` reads it off the engine, with whether holes were cut in the global xy plane),
/// the history with both fingerprints, and the statistics. `seconds` covers building the
/// engine, the loop and reading off the mesh.
pub(crate) fn decimate_with<E: Engine>(
    mesh: &Mesh,
    options: &Options,
    build: impl FnOnce() -> Result<E, super::DecimateError>,
    finish: impl FnOnce(&E) -> (Mesh, bool),
) -> Result<Outcome, super::DecimateError> {
    let clock = std::time::Instant::now();
    let mut engine = build()?;
    let mut history = History::new(
        mesh.vertices.len(),
        mesh.triangles.len(),
        mesh.scalars.is_some(),
    );
    let unused = mesh.used_vertices().iter().filter(|&&u| !u).count();
    // Lengths in diagonals: the same order for the input in any units.
    let unit = if engine.criterion().in_diagonals() {
        super::quality::bounding_diagonal(mesh)
    } else {
        1.0
    };
    let counts = run(&mut engine, options, &mut history, clock, unused, unit);
    let (mut out, projection_xy) = finish(&engine);
    let original = engine.original_surface();
    drop(engine);
    let fit_clock = std::time::Instant::now();
    let fit_rounds = if history.is_empty() {
        0
    } else {
        options.fit.resolve(projection_xy)
    };
    if fit_rounds > 0 {
        // The kept nodes in original order are the decimated mesh's vertices.
        let mut removed = vec![false; mesh.vertices.len()];
        for s in 0..history.len() {
            removed[history.step(s).node as usize] = true;
        }
        let kept: Vec<u32> = (0..mesh.vertices.len() as u32)
            .filter(|&v| !removed[v as usize])
            .collect();
        history.fit = super::fit::fit_in(
            mesh,
            &mut out,
            &kept,
            fit_rounds,
            original.as_deref(),
            options.origin,
        );
    }
    let fit_seconds = fit_clock.elapsed().as_secs_f64();
    let seconds = clock.elapsed().as_secs_f64();
    history.original_fingerprint = fingerprint(mesh);
    history.scalar_name = mesh
        .scalars
        .as_ref()
        .map(|s| s.name.clone())
        .unwrap_or_default();
    history.decimated_fingerprint = fingerprint(&out);
    Ok(Outcome {
        stats: Stats {
            nodes_in: mesh.vertices.len(),
            nodes_out: out.vertices.len(),
            unused,
            target_nodes: node_target(options.target, mesh.vertices.len(), unused),
            triangles_in: mesh.triangles.len(),
            triangles_out: out.triangles.len(),
            removed: counts.removed,
            refused: counts.refused,
            deferred: counts.deferred,
            fan_filled: counts.filled,
            intervals: counts.intervals,
            rebuilds: counts.rebuilds,
            evaluations: counts.evaluations,
            taken: counts.taken,
            evaluated_ahead: counts.evaluated_ahead,
            remembered: counts.remembered,
            projection_xy,
            criterion: options.criterion.resolve(projection_xy).name().into(),
            border: options.border.resolve(projection_xy).name().into(),
            moved: history.fit.len(),
            fit_rounds,
            seconds,
            fit_seconds,
            setup_seconds: counts.setup_seconds,
            blocked: counts.blocked,
        },
        history,
        mesh: out,
    })
}
