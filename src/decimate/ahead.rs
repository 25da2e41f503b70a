//! Evaluation ahead: the fast engine's second core (an extension; the removal sequence is the
//! same with it or without it).
//!
//! The loop takes nodes from the bucket queue one at a time, and most of what it does with a
//! taken node is evaluating it: loading its fan, cutting the ears of its hole, measuring the
//! removal error. That work reads only the node's own fan list and data that never change
//! (positions, values, settings), and the queue knows long in advance which nodes come next.
//! So the loop hands the coming nodes over, in pop order, a lead of four batches ahead of
//! itself, with copies of their lists ([`Lookahead::add`]); a worker thread evaluates them a
//! batch at a time meanwhile and sends back each node's value and plan (its hole's cut,
//! packed in a word). When the loop takes a node it uses what was evaluated ahead if the
//! queue vouches that the node's list is unchanged since it was handed over (the node still
//! holds its ticket, [`BucketQueue::give_ticket`]), and evaluates it itself otherwise, or
//! when the result has not come back yet. A node not marked since it was filed is not handed
//! over at all: the engine remembers the plan of the evaluation it was filed after, and that
//! plan still holds.
//!
//! Both threads run the same code on the same `f64` inputs, so a result evaluated ahead is
//! bit for bit what the loop would have computed: the removal sequence cannot depend on
//! timing. On the 810k-node grid a list changes within a thousand removals of being handed
//! over almost never, so nearly every evaluation moves to the worker.
//!
//! [`BucketQueue::give_ticket`]: super::bucket::BucketQueue::give_ticket

use super::bucket::Scale;
use super::fans::{Entry, FanLists};
use super::{Carried, Plane};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::mpsc::{channel, Receiver, Sender, TryRecvError};
use std::sync::Arc;
use std::thread::JoinHandle;

/// Nodes per batch. Small batches come back soon and keep the lead short, so fewer nodes
/// are re-filed behind it: on the 810k-node grid, while the worker kept up, 32 left 2 % of
/// the taken nodes to the loop and 256 left 20 %. (When the loop outruns the worker, the
/// loop evaluates what has not come back; the report gives the share measured.)
pub(crate) const BATCH: usize = 32;
/// The lead the loop keeps, in batches. On the dragon scan (quadric criterion), with a lead
/// of two batches the loop found 21 % of the stale nodes it took not yet evaluated (the
/// worker's batch still out) and evaluated them itself; with four, 7 %, and the run took
/// about 7 % less time (3.85 s against 4.15 s). The 810k-node grid is unchanged.
const LEAD: usize = 4;
/// Batches whose results have not come back, at most; beyond that a batch is dropped (the
/// worker is behind, and the loop evaluates those nodes itself).
const IN_FLIGHT: usize = 8;
/// How long the worker polls for the next batch before it sleeps: the loop sends one every
/// few tens of microseconds, and waking a sleeping thread costs the sender a system call.
const POLL: std::time::Duration = std::time::Duration::from_micros(200);
/// The loop publishes its progress to the worker at every this many tickets (the worker
/// then skips up to this many nodes later than it could).
const PROGRESS_EVERY: u32 = 16;
/// Results are kept by ticket modulo this (a power of two).
const KEPT: usize = 64 * BATCH;

/// A node's plan as evaluated ahead.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Planned {
    /// Its hole cannot be filled: it may not go.
    Refused,
    /// Its hole is filled by the packed cut (`earcut::pack_cut`) in `plane`.
    Cut {
        border: bool,
        plane: Plane,
        cut: u64,
    },
    /// Not kept (a hole too large to pack): the loop plans it itself.
    NotKept,
}

/// What was evaluated ahead for one node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Evaluated {
    pub node: u32,
    pub ticket: u32,
    /// The evaluation value, `None` when the node may not be removed now.
    pub ev: Option<f64>,
    pub plan: Planned,
    /// `(version, interval)`: the queue interval of `ev` under the job's [`Scale`] of that
    /// version (so that the loop need not compute it while the queue keeps that scale).
    pub interval: Option<(u32, u32)>,
    /// Under the quadric criterion, the planned removal's error bound and the ring
    /// positions of the triangle the node lands in (what the removal needs besides the cut).
    pub landing: Option<(f64, [u8; 3])>,
}

/// One hand-over: nodes with copies of their lists.
#[derive(Default)]
pub(crate) struct Job {
    /// The first node's ticket; the others follow in order.
    pub first_ticket: u32,
    /// `(node, start, len, border)`: the node's list is `entries[start..start + len]`.
    pub nodes: Vec<(u32, u32, u32, bool)>,
    pub entries: Vec<Entry>,
    /// What the nodes carried when handed over (the quadric criterion, else empty; a node's
    /// quadric and its triangles' bounds change only when a neighbour goes, which changes its
    /// list too).
    pub carried: Vec<Carried>,
    /// Filled by the worker, which sends the job back (its buffers are reused).
    pub results: Vec<Evaluated>,
    /// The queue's scale and its version when the nodes were handed over.
    pub scale: Option<(Scale, u32)>,
}

/// The worker thread and the results that came back.
pub(crate) struct Lookahead {
    jobs: Option<Sender<Job>>,
    done: Receiver<Job>,
    /// Emptied jobs, for their buffers.
    spare: Vec<Job>,
    worker: Option<JoinHandle<()>>,
    /// The ticket of the last node the loop took with one: the worker skips nodes the loop
    /// has passed (when it falls behind, it catches up instead of computing what nobody
    /// will read).
    progress: Arc<AtomicU32>,
    /// The last ticket stored in `progress`.
    published: u32,
    batch: usize,
    /// The batch being filled.
    pending: Job,
    in_flight: usize,
    /// Wait for results instead of evaluating in the loop (tests: every taken node then
    /// uses what was evaluated ahead, unless its hand-over was dropped).
    wait: bool,
    kept: Vec<Evaluated>,
    /// How many taken nodes used a result evaluated ahead.
    pub used: usize,
}

impl Lookahead {
    /// Starts the worker: `evaluate` appends an [`Evaluated`] for every node of a job, in
    /// order, except those whose ticket `passed` says the loop has gone by; jobs have
    /// `batch` nodes. `None` when no thread can be started (the loop then evaluates
    /// everything itself).
    pub(crate) fn spawn(
        mut evaluate: impl FnMut(&Job, &mut Vec<Evaluated>, &dyn Fn(u32) -> bool) + Send + 'static,
        batch: usize,
        wait: bool,
    ) -> Option<Lookahead> {
        let (jobs, inbox) = channel::<Job>();
        let (outbox, done) = channel();
        let progress = Arc::new(AtomicU32::new(0));
        let seen = Arc::clone(&progress);
        // Tickets increase along the queue (wrapping), so "passed" is a signed distance.
        let passed =
            move |ticket: u32| (seen.load(Ordering::Relaxed).wrapping_sub(ticket) as i32) > 0;
        let worker = std::thread::Builder::new()
            .name("geocert-lookahead".into())
            .spawn(move || {
                while let Some(mut job) = next_job(&inbox) {
                    let mut out = std::mem::take(&mut job.results);
                    evaluate(&job, &mut out, &passed);
                    job.results = out;
                    if outbox.send(job).is_err() {
                        break;
                    }
                }
            })
            .ok()?;
        Some(Lookahead {
            jobs: Some(jobs),
            done,
            spare: Vec::new(),
            worker: Some(worker),
            progress,
            published: 0,
            batch: batch.max(1),
            pending: Job::default(),
            in_flight: 0,
            wait,
            kept: vec![
                Evaluated {
                    node: u32::MAX,
                    ticket: u32::MAX,
                    ev: None,
                    plan: Planned::NotKept,
                    interval: None,
                    landing: None,
                };
                KEPT
            ],
            used: 0,
        })
    }

    /// The lead the loop should keep.
    pub(crate) fn lead(&self) -> usize {
        LEAD * self.batch
    }

    /// Adds `v` (with `ticket`, one more than the node added before, or else a new batch
    /// starts) to the batch being filled, with a copy of its list; a full batch goes to the
    /// worker, unless too many batches are still out (then it is dropped). `scale`: the
    /// queue's, with its version (a batch holds nodes handed over under one version).
    pub(crate) fn add(
        &mut self,
        v: u32,
        ticket: u32,
        lists: &FanLists,
        carried: Option<Carried>,
        scale: Option<(Scale, u32)>,
    ) {
        let job = &self.pending;
        if !job.nodes.is_empty()
            && (job.first_ticket.wrapping_add(job.nodes.len() as u32) != ticket
                || job.scale.map(|s| s.1) != scale.map(|s| s.1))
        {
            self.flush();
        }
        let job = &mut self.pending;
        if job.nodes.is_empty() {
            job.first_ticket = ticket;
            job.scale = scale;
        }
        let start = job.entries.len() as u32;
        // An inline list goes over as its whole line (header first): one fixed-size copy.
        let (start, len, border) = match lists.inline_line(v) {
            Some((line, len, border)) => {
                job.entries.extend_from_slice(&line);
                (start + 1, len as u32, border)
            }
            None => {
                lists.read(v, &mut job.entries);
                let len = job.entries.len() as u32 - start;
                (start, len, lists.is_border(v))
            }
        };
        job.nodes.push((v, start, len, border));
        if let Some(c) = carried {
            job.carried.push(c);
        }
        if job.nodes.len() >= self.batch {
            self.flush();
        }
    }

    /// Sends the batch being filled to the worker (or drops it when the worker is behind).
    fn flush(&mut self) {
        if self.pending.nodes.is_empty() {
            return;
        }
        let fresh = self.spare.pop().unwrap_or_default();
        let job = std::mem::replace(&mut self.pending, fresh);
        self.collect();
        if self.in_flight >= IN_FLIGHT && !self.wait {
            self.recycle(job);
            return;
        }
        if let Some(jobs) = &self.jobs {
            if jobs.send(job).is_ok() {
                self.in_flight += 1;
            }
        }
    }

    /// Keeps an emptied job's buffers for a later batch.
    fn recycle(&mut self, mut job: Job) {
        job.nodes.clear();
        job.entries.clear();
        job.carried.clear();
        job.results.clear();
        self.spare.push(job);
    }

    /// Files the results that came back.
    fn collect(&mut self) {
        loop {
            match self.done.try_recv() {
                Ok(job) => self.file(job),
                Err(TryRecvError::Empty) => return,
                Err(TryRecvError::Disconnected) => {
                    // The worker is gone: hand nothing over any more.
                    self.jobs = None;
                    self.in_flight = 0;
                    return;
                }
            }
        }
    }

    fn file(&mut self, job: Job) {
        self.in_flight -= 1;
        for &r in &job.results {
            self.kept[r.ticket as usize % KEPT] = r;
        }
        self.recycle(job);
    }

    /// What was evaluated ahead for `node` under `ticket`, if it has come back; the loop is
    /// taking it now.
    pub(crate) fn result(&mut self, node: u32, ticket: u32) -> Option<Evaluated> {
        // Every PROGRESS_EVERY tickets: each store takes the line from the worker's core.
        if !self.wait && ticket.wrapping_sub(self.published) >= PROGRESS_EVERY {
            self.progress.store(ticket, Ordering::Relaxed);
            self.published = ticket;
        }
        let slot = ticket as usize % KEPT;
        let hit = |r: &Evaluated| r.ticket == ticket && r.node == node;
        if !hit(&self.kept[slot]) {
            if self.wait {
                self.flush();
            }
            self.collect();
            while self.wait && self.in_flight > 0 && !hit(&self.kept[slot]) {
                match self.done.recv() {
                    Ok(job) => self.file(job),
                    Err(_) => break,
                }
            }
        }
        let r = self.kept[slot];
        if hit(&r) {
            self.used += 1;
            Some(r)
        } else {
            None
        }
    }
}

/// The next job: polled for [`POLL`], then waited for; `None` once the loop has hung up.
fn next_job(inbox: &Receiver<Job>) -> Option<Job> {
    let start = std::time::Instant::now();
    loop {
        match inbox.try_recv() {
            Ok(job) => return Some(job),
            Err(TryRecvError::Disconnected) => return None,
            Err(TryRecvError::Empty) if start.elapsed() < POLL => std::hint::spin_loop(),
            Err(TryRecvError::Empty) => return inbox.recv().ok(),
        }
    }
}

impl Drop for Lookahead {
    fn drop(&mut self) {
        // Closing the job channel ends the worker's loop.
        self.jobs = None;
        if let Some(worker) = self.worker.take() {
            // A worker that panicked only means results that never came back; the loop
            // evaluated those nodes itself.
            let _ = worker.join();
        }
    }
}
