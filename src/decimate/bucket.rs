//! The interval "hash table" of Section 1.2: `m = ⌊n/k⌋` intervals of evaluation values with
//! exponential-law boundaries (eqs. 1–3), a FIFO queue per interval, the next node taken from
//! the front of the lowest non-empty interval.
//!
//! Eq. (2) as printed, `d_j = ev_sum − ev_ln · ln(1 + Δev − j·Δev/m)`, gives `d_0 = ev_min`
//! but `d_m = ev_min + ev_max`: it assumes `ev_min = 0`. We use it on `ev − ev_min`, so the
//! boundaries cover `[ev_min, ev_max]`:
//! `d_j = ev_min + Δ − (Δ / ln(1+Δ)) · ln(1 + Δ·(1 − j/m))`, `Δ = ev_max − ev_min`.
//! Eq. (3) is its inverse. We take the floor (interval `j` holds `d_j ≤ ev < d_{j+1}`) where
//! the paper writes a ceiling with a special case for `ev ≥ ev_max`; values outside the
//! initial range (re-evaluated nodes) go to the first or last interval. `ln_1p`/`exp_m1` keep
//! the formula accurate for small `Δ`, where it tends to equal-width intervals.
//!
//! The queues are intrusive doubly linked lists over node ids: push to the tail, pop from the
//! head, unlink any node in `O(1)` when it is re-evaluated. A node's links, interval, value,
//! mark (a flag the caller may set on a queued node, [`BucketQueue::mark`]) and ticket (see
//! [`BucketQueue::give_ticket`]) share one record, so that touching a node costs one cache miss,
//! not five.
//!
//! Re-binning (an extension; [`BucketQueue::rebinning`]): the paper fixes the boundaries from
//! the initial range, so once re-evaluated values outgrow `ev_max` they all land in the last
//! interval and leave in FIFO order, unsorted — late in a decimation, when errors are
//! largest, the queue stops ordering. With re-binning on, once the pushes above the range
//! since the last rebuild exceed a fraction `1/r` of the queued nodes, the queue is rebuilt
//! over the queued nodes' current range with `m = ⌊len/k⌋` intervals (eq. 1 on what is
//! queued) but at least [`MIN_REBUILT_INTERVALS`], keeping the FIFO order within equal
//! values. A rebuild costs `O(len + MIN_REBUILT_INTERVALS)` and is paid for by the `len/r`
//! pushes before it, so every operation stays `O(1)` amortised.
//!
//! Units (an extension; [`BucketQueue::in_units`]): eq. (2)'s law is not invariant under a
//! change of units, so the loop measures values that are lengths in diagonals of the input.

use crate::memory::huge_vec;
use crate::par::prelude::*;

const NONE: u32 = u32::MAX;

/// The fewest intervals a re-binned queue has. Late in a decimation few nodes are queued
/// (on Kuen's surface at 2 %, under 100 of the 800 left, the others blocked), and `⌊len/k⌋`
/// fell to one interval: the queue then took nodes in FIFO order, removals with ten times
/// the error of others still queued, and the result's Hausdorff distance rose from 1.2 % to
/// 12 % of the diagonal. The bitmaps keep finding the front cheap at any `m`.
const MIN_REBUILT_INTERVALS: usize = 1024;

/// Eq. (1): the number of intervals `m = ⌊n/k⌋`, at least 1.
pub(crate) fn interval_count(n: usize, k: usize) -> usize {
    (n / k.max(1)).max(1)
}

/// What the queue keeps per node (32 bytes, two to a cache line).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
struct Node {
    next: u32,
    prev: u32,
    /// The interval the node is filed in, or `NONE`.
    bucket: u32,
    /// The ticket [`BucketQueue::give_ticket`] gave it, or `NONE`.
    ticket: u32,
    /// The value it was filed with.
    ev: f64,
    marked: bool,
}

const UNQUEUED: Node = Node {
    next: NONE,
    prev: NONE,
    bucket: NONE,
    ticket: NONE,
    ev: 0.0,
    marked: false,
};

/// A node taken from the queue ([`BucketQueue::pop`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Taken {
    pub node: u32,
    /// The interval it was taken from.
    pub interval: usize,
    /// Whether it was marked.
    pub marked: bool,
    /// Its ticket, when it was handed over and neither marked nor moved since; else `None`.
    pub ticket: Option<u32>,
}

/// The bucket queue.
#[derive(Clone, Debug)]
pub(crate) struct BucketQueue {
    m: usize,
    ev_min: f64,
    delta: f64,
    /// `ln(1 + Δ)`.
    ln1p_delta: f64,
    /// The unit values are measured in for eqs. (2)–(3) ([`BucketQueue::in_units`]).
    unit: f64,
    head: Vec<u32>,
    tail: Vec<u32>,
    nodes: Vec<Node>,
    /// Bit `j` set when interval `j` is non-empty, and a summary bit per word of it: finding
    /// the lowest non-empty interval costs two word scans, not a walk over empty intervals.
    occupied: Vec<u64>,
    summary: Vec<u64>,
    len: usize,
    /// `Some((k, r))` when re-binning is on.
    rebin: Option<(usize, usize)>,
    /// Pushes above the range since the last rebuild.
    overflow: usize,
    rebuilds: usize,
    order: Vec<u32>,
    /// No interval below this one is non-empty: a bound that filing lowers and
    /// [`pop`](Self::pop) raises, so that the front is found without scanning from 0.
    lowest: usize,
}

/// The boundaries of a queue's intervals (eq. 3): enough to map a value to its interval away
/// from the queue (the lookahead thread does, for the nodes it evaluates).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Scale {
    m: usize,
    ev_min: f64,
    delta: f64,
    /// `ln(1 + Δ)`.
    ln1p_delta: f64,
    /// Values are divided by this before eq. (3) (`ev_min` and `Δ` are in it).
    unit: f64,
}

impl Scale {
    /// Eq. (3), normalised: the interval of evaluation value `ev`.
    pub(crate) fn interval(&self, ev: f64) -> usize {
        let ev = ev / self.unit;
        if self.delta == 0.0 || ev.is_nan() || ev <= self.ev_min {
            return 0;
        }
        let t = (self.ev_min + self.delta - ev) / self.delta;
        if t <= 0.0 {
            return self.m - 1;
        }
        // d_j = ev  ⇔  1 + Δ(1 − j/m) = (1+Δ)^t  ⇔  j/m = 1 − ((1+Δ)^t − 1)/Δ.
        let frac = 1.0 - (t * self.ln1p_delta).exp_m1() / self.delta;
        // ⌊j⌋ by truncation (no libm call): the same for positive j, NaN maps to 0.
        let j = frac * self.m as f64;
        if j <= 0.0 {
            0
        } else {
            (j as usize).min(self.m - 1)
        }
    }
}

impl BucketQueue {
    /// A queue for node ids `0..nodes`, with `m` intervals over `[ev_min, ev_max]`.
    #[cfg(test)]
    pub(crate) fn new(nodes: usize, m: usize, ev_min: f64, ev_max: f64) -> BucketQueue {
        BucketQueue::in_units(nodes, m, ev_min, ev_max, 1.0)
    }

    /// A queue for node ids `0..nodes`, with `m` intervals over `[ev_min, ev_max]` and the
    /// values measured in `unit` for eqs. (2)–(3): the intervals of `ev` are those of
    /// `ev / unit` (`unit` is taken as one unless positive and finite). Eq. (2)'s law
    /// depends on the size of `Δ` itself (equal widths when `Δ ≪ 1`, crowded towards
    /// `ev_min` when `Δ ≫ 1`), so values in a unit of their own (a length in diagonals of
    /// the input) give the same order whatever units the input is in.
    pub(crate) fn in_units(
        nodes: usize,
        m: usize,
        ev_min: f64,
        ev_max: f64,
        unit: f64,
    ) -> BucketQueue {
        let unit = if unit > 0.0 && unit.is_finite() {
            unit
        } else {
            1.0
        };
        let (ev_min, ev_max) = (ev_min / unit, ev_max / unit);
        let m = m.max(1);
        let delta = if ev_max > ev_min && (ev_max - ev_min).is_finite() {
            ev_max - ev_min
        } else {
            0.0
        };
        BucketQueue {
            m,
            ev_min,
            delta,
            ln1p_delta: delta.ln_1p(),
            unit,
            head: vec![NONE; m],
            tail: vec![NONE; m],
            nodes: huge_vec(UNQUEUED, nodes),
            occupied: vec![0; m.div_ceil(64)],
            summary: vec![0; m.div_ceil(64).div_ceil(64)],
            len: 0,
            rebin: None,
            overflow: 0,
            rebuilds: 0,
            order: Vec::new(),
            lowest: 0,
        }
    }

    /// Turns re-binning on (see the module docs): rebuild with `⌊len/k⌋` intervals (at least
    /// [`MIN_REBUILT_INTERVALS`]) once more
    /// than `len/r` pushes since the last rebuild were above the range.
    pub(crate) fn rebinning(mut self, k: usize, r: usize) -> BucketQueue {
        self.rebin = Some((k.max(1), r.max(1)));
        self
    }

    /// How many times the queue was re-binned.
    pub(crate) fn rebuilds(&self) -> usize {
        self.rebuilds
    }

    /// The queued nodes in pop order.
    fn queued_in_order(&self, out: &mut Vec<u32>) {
        out.clear();
        for (w, &word) in self.occupied.iter().enumerate() {
            let mut bits = word;
            while bits != 0 {
                let j = 64 * w + bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let mut v = self.head[j];
                while v != NONE {
                    out.push(v);
                    v = self.nodes[v as usize].next;
                }
            }
        }
    }

    /// Rebuilds over the queued nodes' range with `⌊len/k⌋` intervals, keeping pop order
    /// among nodes that land in the same interval.
    fn rebuild(&mut self, k: usize) {
        let mut order = std::mem::take(&mut self.order);
        self.queued_in_order(&mut order);
        let (lo, hi) = order
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                let e = self.nodes[v as usize].ev;
                (lo.min(e), hi.max(e))
            });
        let m = interval_count(order.len(), k).max(MIN_REBUILT_INTERVALS);
        let fresh = BucketQueue::in_units(0, m, lo, hi, self.unit);
        self.m = fresh.m;
        self.ev_min = fresh.ev_min;
        self.delta = fresh.delta;
        self.ln1p_delta = fresh.ln1p_delta;
        self.head = fresh.head;
        self.tail = fresh.tail;
        self.occupied = fresh.occupied;
        self.summary = fresh.summary;
        self.len = 0;
        self.lowest = 0;
        for &v in &order {
            let node = &mut self.nodes[v as usize];
            let marked = node.marked;
            let ev = node.ev;
            *node = UNQUEUED;
            self.file(v, ev);
            self.nodes[v as usize].marked = marked;
        }
        self.overflow = 0;
        self.rebuilds += 1;
        self.order = order;
    }

    /// The number of queued nodes.
    pub(crate) fn len(&self) -> usize {
        self.len
    }

    /// True when no node is queued.
    pub(crate) fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Eq. (2), normalised: the lower boundary `d_j` of interval `j` (`0 ≤ j ≤ m`).
    #[cfg(test)]
    pub(crate) fn boundary(&self, j: usize) -> f64 {
        if self.delta == 0.0 {
            return self.ev_min * self.unit;
        }
        let j = j.min(self.m) as f64;
        let m = self.m as f64;
        (self.ev_min + self.delta
            - (self.delta / self.ln1p_delta) * (self.delta * (1.0 - j / m)).ln_1p())
            * self.unit
    }

    /// Eq. (3), normalised: the interval of evaluation value `ev`.
    #[inline]
    pub(crate) fn interval(&self, ev: f64) -> usize {
        self.scale().interval(ev)
    }

    /// The intervals' boundaries as they are now; they change only when the queue is re-binned
    /// (then [`rebuilds`](Self::rebuilds) counts one more).
    #[inline]
    pub(crate) fn scale(&self) -> Scale {
        Scale {
            m: self.m,
            ev_min: self.ev_min,
            delta: self.delta,
            ln1p_delta: self.ln1p_delta,
            unit: self.unit,
        }
    }

    /// Asks the processor to start fetching `node`'s record.
    #[inline]
    pub(crate) fn prefetch(&self, node: u32) {
        crate::memory::prefetch(&self.nodes[node as usize]);
    }

    /// True when `node` is queued.
    pub(crate) fn contains(&self, node: u32) -> bool {
        self.nodes[node as usize].bucket != NONE
    }

    /// Marks `node` if it is queued, and returns whether it is. Filing or unlinking a node
    /// clears its mark; [`pop`](Self::pop) reports it. Marking voids the node's ticket.
    pub(crate) fn mark(&mut self, node: u32) -> bool {
        let n = &mut self.nodes[node as usize];
        n.marked |= n.bucket != NONE;
        n.ticket = NONE;
        n.bucket != NONE
    }

    /// True when `node` is queued and marked.
    #[inline]
    pub(crate) fn is_marked(&self, node: u32) -> bool {
        self.nodes[node as usize].marked
    }

    /// The queued node that pops right after `from`, or the front node when `from` is
    /// `None` or no longer queued; and whether it is the front node.
    pub(crate) fn next_after(&self, from: Option<u32>) -> Option<(u32, bool)> {
        match from {
            Some(h) if self.contains(h) => Some((self.after(h)?, false)),
            _ => Some((self.peek()?, true)),
        }
    }

    /// Gives the queued `node` a ticket (and returns true; false when it is not queued). A
    /// ticket stays with its node until the node is marked, filed again or unlinked, so a
    /// popped node's ticket says that it has neither been marked nor moved since it got it:
    /// what a caller computed for it then, from data that only changes when it is marked,
    /// still holds.
    pub(crate) fn give_ticket(&mut self, node: u32, ticket: u32) -> bool {
        let n = &mut self.nodes[node as usize];
        if n.bucket == NONE {
            return false;
        }
        n.ticket = ticket;
        true
    }

    /// The queued node that pops right after the queued `node`.
    fn after(&self, node: u32) -> Option<u32> {
        let n = &self.nodes[node as usize];
        if n.next != NONE {
            return Some(n.next);
        }
        self.first_from(n.bucket as usize + 1).map(|j| self.head[j])
    }

    /// Pushes `items` (distinct nodes) in order, as [`push`](Self::push) one by one would.
    /// Into an empty queue, when no value lies above the range (no push would count towards
    /// re-binning), the intervals are computed in parallel, a counting sort gives the pop
    /// order, and every record is written once, from its neighbours in that order (in
    /// parallel and in node order when the ids increase), without chasing tails.
    pub(crate) fn push_all(&mut self, items: &[(u32, f64)]) {
        let top = self.ev_min + self.delta;
        let overflows = self.rebin.is_some() && items.iter().any(|&(_, ev)| ev / self.unit > top);
        if !self.is_empty() || overflows {
            for &(v, ev) in items {
                self.push(v, ev);
            }
            return;
        }
        let intervals: Vec<u32> = items
            .par_iter()
            .map(|&(_, ev)| self.interval(ev) as u32)
            .collect();
        // A stable counting sort by interval keeps the push order within each interval.
        let mut start = vec![0u32; self.m + 1];
        for &j in &intervals {
            start[j as usize + 1] += 1;
        }
        for j in 0..self.m {
            start[j + 1] += start[j];
        }
        // The nodes in pop order, and each item's place in it.
        let mut sorted = vec![0u32; items.len()];
        let mut rank = vec![0u32; items.len()];
        let mut fill = start.clone();
        for (k, &j) in intervals.iter().enumerate() {
            let at = fill[j as usize];
            sorted[at as usize] = items[k].0;
            rank[k] = at;
            fill[j as usize] += 1;
        }
        for j in 0..self.m {
            let (first, end) = (start[j] as usize, start[j + 1] as usize);
            if first == end {
                continue;
            }
            self.head[j] = sorted[first];
            self.tail[j] = sorted[end - 1];
            self.occupied[j / 64] |= 1 << (j % 64);
            self.summary[j / 4096] |= 1 << ((j / 64) % 64);
        }
        // Item k's record: its neighbours in pop order, within its interval.
        let record = |k: usize| {
            let (j, r) = (intervals[k] as usize, rank[k] as usize);
            Node {
                next: if r + 1 < start[j + 1] as usize {
                    sorted[r + 1]
                } else {
                    NONE
                },
                prev: if r > start[j] as usize {
                    sorted[r - 1]
                } else {
                    NONE
                },
                bucket: j as u32,
                ticket: NONE,
                ev: items[k].1,
                marked: false,
            }
        };
        if items.par_windows(2).all(|w| w[0].0 < w[1].0) {
            // Increasing ids (the initial pass): the records are written in order, in
            // parallel runs of nodes.
            const RUN: usize = 1 << 14;
            self.nodes
                .par_chunks_mut(RUN)
                .enumerate()
                .for_each(|(c, run)| {
                    let v0 = c * RUN;
                    let mut k = items.partition_point(|&(v, _)| (v as usize) < v0);
                    while k < items.len() && (items[k].0 as usize) < v0 + run.len() {
                        run[items[k].0 as usize - v0] = record(k);
                        k += 1;
                    }
                });
        } else {
            for (k, &(v, _)) in items.iter().enumerate() {
                self.nodes[v as usize] = record(k);
            }
        }
        self.len = items.len();
        self.lowest = 0;
    }

    /// Files `node` at the tail of the interval of `ev` (unlinking it first if queued).
    pub(crate) fn push(&mut self, node: u32, ev: f64) {
        self.push_to(node, ev, self.interval(ev));
    }

    /// [`push`](Self::push) when the caller has `interval(ev)` already.
    pub(crate) fn push_to(&mut self, node: u32, ev: f64, interval: usize) {
        debug_assert_eq!(interval, self.interval(ev));
        self.remove(node);
        self.file_in(node, ev, interval);
        if let Some((k, r)) = self.rebin {
            if ev / self.unit > self.ev_min + self.delta {
                self.overflow += 1;
                if self.overflow * r > self.len {
                    self.rebuild(k);
                }
            }
        }
    }

    /// Links the unqueued `node` at the tail of the interval of `ev`.
    fn file(&mut self, node: u32, ev: f64) {
        self.file_in(node, ev, self.interval(ev));
    }

    /// Links the unqueued `node` at the tail of interval `j`, filed with `ev`.
    fn file_in(&mut self, node: u32, ev: f64, j: usize) {
        self.lowest = self.lowest.min(j);
        self.nodes[node as usize] = Node {
            next: NONE,
            prev: self.tail[j],
            bucket: j as u32,
            ticket: NONE,
            ev,
            marked: false,
        };
        if self.tail[j] == NONE {
            self.head[j] = node;
        } else {
            self.nodes[self.tail[j] as usize].next = node;
        }
        self.tail[j] = node;
        self.occupied[j / 64] |= 1 << (j % 64);
        self.summary[j / 4096] |= 1 << ((j / 64) % 64);
        self.len += 1;
    }

    /// Unlinks `node` if it is queued.
    pub(crate) fn remove(&mut self, node: u32) {
        let n = self.nodes[node as usize];
        if n.bucket == NONE {
            return;
        }
        let j = n.bucket as usize;
        let (p, q) = (n.prev, n.next);
        if p == NONE {
            self.head[j] = q;
        } else {
            self.nodes[p as usize].next = q;
        }
        if q == NONE {
            self.tail[j] = p;
        } else {
            self.nodes[q as usize].prev = p;
        }
        if self.head[j] == NONE {
            self.occupied[j / 64] &= !(1 << (j % 64));
            if self.occupied[j / 64] == 0 {
                self.summary[j / 4096] &= !(1 << ((j / 64) % 64));
            }
        }
        self.nodes[node as usize] = UNQUEUED;
        self.len -= 1;
    }

    /// The lowest non-empty interval.
    fn front(&self) -> Option<usize> {
        if self.len == 0 {
            return None;
        }
        self.first_from(self.lowest)
    }

    /// The lowest non-empty interval from `j` on.
    fn first_from(&self, j: usize) -> Option<usize> {
        if j >= self.m {
            return None;
        }
        let word = j / 64;
        let bits = self.occupied[word] & (!0u64 << (j % 64));
        if bits != 0 {
            return Some(64 * word + bits.trailing_zeros() as usize);
        }
        // The next non-empty word, by the summary.
        let after = word + 1;
        let mut s = after / 64;
        let mut bits = self.summary.get(s)? & (!0u64 << (after % 64));
        loop {
            if bits != 0 {
                let word = 64 * s + bits.trailing_zeros() as usize;
                return Some(64 * word + self.occupied[word].trailing_zeros() as usize);
            }
            s += 1;
            bits = *self.summary.get(s)?;
        }
    }

    /// The node [`pop`](Self::pop) would take now.
    pub(crate) fn peek(&self) -> Option<u32> {
        self.front().map(|j| self.head[j])
    }

    /// Takes the node at the front of the lowest non-empty interval.
    pub(crate) fn pop(&mut self) -> Option<Taken> {
        let j = self.front()?;
        self.lowest = j;
        let node = self.head[j];
        let n = self.nodes[node as usize];
        self.remove(node);
        Some(Taken {
            node,
            interval: j,
            marked: n.marked,
            ticket: (n.ticket != NONE).then_some(n.ticket),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn boundaries_cover_the_range_and_invert() {
        for (lo, hi) in [(0.0, 1.0), (2.0, 50.0), (1e-9, 3e-9), (0.0, 1e6)] {
            let q = BucketQueue::new(1, 100, lo, hi);
            assert!((q.boundary(0) - lo).abs() <= 1e-12 * hi.abs().max(1.0));
            assert!((q.boundary(100) - hi).abs() <= 1e-9 * hi.abs().max(1.0));
            for j in 0..100 {
                assert!(q.boundary(j) < q.boundary(j + 1), "{lo} {hi} {j}");
                // A value just inside interval j maps to j.
                let mid = 0.5 * (q.boundary(j) + q.boundary(j + 1));
                assert_eq!(q.interval(mid), j, "{lo} {hi} {j}");
            }
            assert_eq!(q.interval(hi * 2.0 + 1.0), 99);
            assert_eq!(q.interval(lo - 1.0), 0);
        }
    }

    #[test]
    fn intervals_widen_exponentially() {
        let q = BucketQueue::new(1, 10, 0.0, 100.0);
        let first = q.boundary(1) - q.boundary(0);
        let last = q.boundary(10) - q.boundary(9);
        assert!(last > 10.0 * first, "{first} {last}");
    }

    #[test]
    fn fifo_within_interval_lowest_first() {
        let mut q = BucketQueue::new(6, 4, 0.0, 1.0);
        q.push(0, 0.9);
        q.push(1, 0.0);
        q.push(2, 0.9);
        q.push(3, 0.0);
        q.push(4, 0.5);
        q.push(1, 0.95); // re-evaluated: moves to the tail of the last interval
        assert_eq!(q.len(), 5);
        assert_eq!(q.peek(), Some(3));
        assert!(q.mark(3) && !q.mark(5));
        let order: Vec<(u32, bool)> =
            std::iter::from_fn(|| q.pop().map(|p| (p.node, p.marked))).collect();
        let lo4 = q.interval(0.5);
        assert!(lo4 < q.interval(0.9));
        assert_eq!(
            order,
            vec![(3, true), (4, false), (0, false), (2, false), (1, false)]
        );
        assert_eq!(q.peek(), None);
        assert!(q.is_empty());
    }

    #[test]
    fn pushing_all_at_once_is_pushing_one_by_one() {
        let mut rng = crate::decimate::TestRng(0x9e37_79b9_7f4a_7c15);
        let mut rand = || rng.word();
        for round in 0..20 {
            let n = 1 + (rand() % 40_000) as usize;
            // Rounds 0, 1 mod 4: every node, shuffled; 2, 3: increasing ids with gaps (as the
            // initial pass gives them; push_all then writes records in parallel runs).
            let mut nodes: Vec<u32> = (0..n as u32).collect();
            if round % 4 < 2 {
                for i in (1..n).rev() {
                    nodes.swap(i, (rand() % (i as u64 + 1)) as usize);
                }
            } else {
                nodes.retain(|_| rand() % 7 != 0);
            }
            // Values with ties, and (odd rounds) a few above the range given.
            let items: Vec<(u32, f64)> = nodes
                .iter()
                .map(|&v| {
                    let above = round % 2 == 1 && rand() % 50 == 0;
                    (
                        v,
                        if above {
                            9.0
                        } else {
                            (rand() % 40) as f64 / 8.0
                        },
                    )
                })
                .collect();
            let popped = |bulk: bool| {
                let mut q = BucketQueue::new(n, 1 + n / 10, 0.0, 5.0).rebinning(10, 2);
                if bulk {
                    q.push_all(&items);
                } else {
                    items.iter().for_each(|&(v, ev)| q.push(v, ev));
                }
                // Unlinking uses the back links too.
                for v in (0..n as u32).step_by(5) {
                    q.remove(v);
                }
                let order: Vec<(u32, usize)> =
                    std::iter::from_fn(|| q.pop().map(|t| (t.node, t.interval))).collect();
                (order, q.rebuilds())
            };
            assert_eq!(popped(true), popped(false), "round {round}");
        }
    }

    /// Late in a decimation few nodes are queued and their values have outgrown the range:
    /// the rebuilt queue still takes them in order of value, not in the FIFO order one
    /// interval (`⌊len/k⌋` of 24 nodes at k = 10 is 2) would give.
    #[test]
    fn a_small_rebuilt_queue_still_orders_by_value() {
        // Values small against the unit, as lengths in diagonals are: eq. (2)'s intervals
        // then have nearly equal widths.
        let value = |v: u32| {
            if v < 6 {
                0.001 * v as f64
            } else {
                0.5 - 0.01 * v as f64
            }
        };
        let mut q = BucketQueue::new(64, 6, 0.0, 0.005).rebinning(10, 2);
        // Six nodes in range, then eighteen above it in decreasing order of value: the
        // thirteenth push above the range rebuilds the queue.
        for v in 0..24u32 {
            q.push(v, value(v));
        }
        assert!(q.rebuilds() >= 1);
        let values: Vec<f64> = std::iter::from_fn(|| q.pop())
            .map(|t| value(t.node))
            .collect();
        assert_eq!(values.len(), 24);
        let sorted = values.windows(2).all(|w| w[0] <= w[1]);
        println!(
            "24 nodes through {} rebuild(s): taken in order of value: {sorted}",
            q.rebuilds()
        );
        assert!(sorted, "{values:?}");
    }

    /// Values in another unit: the same intervals as the values divided by it.
    #[test]
    fn values_in_units_file_like_the_values_divided() {
        let (lo, hi) = (0.003, 7.5);
        for unit in [1e-6, 0.25, 1.0, 3.0, 1e6] {
            let q = BucketQueue::in_units(1, 100, lo * unit, hi * unit, unit);
            let p = BucketQueue::new(1, 100, lo, hi);
            for i in 0..=1000 {
                let ev = lo + (hi - lo) * i as f64 / 1000.0;
                // Powers of two scale exactly; the others to within rounding at a boundary.
                if unit == 0.25 || unit == 1.0 {
                    assert_eq!(q.interval(ev * unit), p.interval(ev), "{unit} {ev}");
                } else {
                    assert!(
                        q.interval(ev * unit).abs_diff(p.interval(ev)) <= 1,
                        "{unit} {ev}"
                    );
                }
            }
        }
    }

    #[test]
    fn tickets_survive_until_marked_or_moved() {
        let mut q = BucketQueue::new(8, 4, 0.0, 1.0);
        for (v, ev) in [(0, 0.9), (1, 0.0), (2, 0.5), (3, 0.0), (4, 0.9)] {
            q.push(v, ev);
        }
        // Pop order 1, 3, 2, 0, 4: the walk crosses intervals.
        let mut walked = Vec::new();
        let mut from = None;
        while let Some((v, front)) = q.next_after(from) {
            assert_eq!(front, from.is_none());
            assert!(q.give_ticket(v, 10 + walked.len() as u32));
            walked.push(v);
            from = Some(v);
        }
        assert_eq!(walked, vec![1, 3, 2, 0, 4]);
        q.mark(2);
        q.push(0, 0.95);
        let taken: Vec<(u32, Option<u32>)> =
            std::iter::from_fn(|| q.pop().map(|t| (t.node, t.ticket))).collect();
        assert_eq!(
            taken,
            vec![
                (1, Some(10)),
                (3, Some(11)),
                (2, None),
                (4, Some(14)),
                (0, None)
            ]
        );
        // A cursor that is no longer queued restarts from the front.
        q.push(5, 0.3);
        assert_eq!(q.next_after(Some(1)), Some((5, true)));
        assert_eq!(q.next_after(Some(5)), None);
        assert!(!q.give_ticket(1, 20), "an unqueued node gets no ticket");
    }

    #[test]
    fn rebinning_orders_values_above_the_range() {
        // Ten nodes in [0, 1], then six re-filed far above in descending order.
        let above = [
            (0u32, 60.0),
            (1, 50.0),
            (2, 40.0),
            (3, 30.0),
            (4, 20.0),
            (5, 10.0),
        ];
        let run = |rebin: bool| {
            let mut q = BucketQueue::new(10, 10, 0.0, 1.0);
            if rebin {
                q = q.rebinning(1, 2);
            }
            for v in 0..10 {
                q.push(v, v as f64 / 10.0);
            }
            for (v, ev) in above {
                q.push(v, ev);
            }
            let order: Vec<u32> = std::iter::from_fn(|| q.pop().map(|p| p.node)).collect();
            (order, q.rebuilds())
        };
        // The paper's fixed boundaries: the last interval is FIFO.
        let (fixed, none) = run(false);
        assert_eq!(none, 0);
        assert_eq!(fixed, vec![6, 7, 8, 9, 0, 1, 2, 3, 4, 5]);
        // Re-binned once more than half the queue overflowed: ascending again (1024
        // intervals: even the widest, exponential-law one at the top holds only 60).
        let (rebinned, rebuilds) = run(true);
        assert_eq!(rebuilds, 1);
        assert_eq!(rebinned, vec![6, 7, 8, 9, 5, 4, 3, 2, 1, 0]);
    }
}
