//! Per-node fan lists, the fast engine's adjacency (the paper's Figure 4: "a list of
//! neighbouring nodes at each node", so that the neighbours are reached without a search).
//!
//! Node `v`'s list holds its neighbours counter-clockwise, each with the triangle that follows
//! it around `v`: entry `i` is `(ring[i], t)` where `t` names the triangle
//! `(v, ring[i], ring[i + 1])` as `slot · 4 + corner`, the corner of `v` in that slot's
//! triangle. An interior node's list is cyclic (any rotation); a border node's list starts
//! at the neighbour across its outgoing border edge and its last entry has no triangle
//! ([`NO_TRIANGLE`]).
//!
//! Node `v` owns block `v`, one cache line: a header and up to [`INLINE`] entries. Longer
//! lists live in an overflow run of `8 · 2^c` entries (size class `c`, a free list per
//! class) named by the header. Loading a typical fan (six neighbours on a triangle mesh) thus
//! touches one line found without any lookup, and the ring nodes' lines can be fetched
//! independently of each other — unlike a half-edge walk, where every step waits for the
//! previous one.

use crate::memory::advise_huge_pages;
use crate::par::prelude::*;
use std::sync::Mutex;

/// The triangle field of a border node's last entry.
pub(crate) const NO_TRIANGLE: u32 = u32::MAX;

/// A neighbour and the triangle that follows it counter-clockwise (`slot · 4 + corner`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Entry {
    pub node: u32,
    pub triangle: u32,
}

impl Entry {
    /// The triangle slot, when there is a triangle.
    #[inline]
    pub(crate) fn slot(self) -> u32 {
        self.triangle >> 2
    }

    /// The corner of the list's node in that slot's triangle.
    #[inline]
    pub(crate) fn corner(self) -> u8 {
        (self.triangle & 3) as u8
    }
}

/// Read access to nodes' lists: the live [`FanLists`], or a copy of one list
/// ([`CopiedList`]) that a node can be evaluated from on another thread.
pub(crate) trait Lists {
    /// The number of entries of `v`'s list.
    fn len(&self, v: u32) -> usize;
    /// True when `v` is on the border (its list is open).
    fn is_border(&self, v: u32) -> bool;
    /// Calls `f` on every entry of `v`'s list, in order.
    fn for_each(&self, v: u32, f: impl FnMut(Entry));
    /// Appends `v`'s list to `out`.
    fn read(&self, v: u32, out: &mut Vec<Entry>) {
        self.for_each(v, |e| out.push(e));
    }
    /// True when `v`'s list is empty (an isolated or removed node).
    fn is_empty(&self, v: u32) -> bool {
        self.len(v) == 0
    }
}

/// One node's list, copied: the lists of all other nodes read as empty.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CopiedList<'a> {
    pub node: u32,
    pub entries: &'a [Entry],
    pub border: bool,
}

impl Lists for CopiedList<'_> {
    fn len(&self, v: u32) -> usize {
        if v == self.node {
            self.entries.len()
        } else {
            0
        }
    }

    fn is_border(&self, v: u32) -> bool {
        v == self.node && self.border
    }

    fn for_each(&self, v: u32, f: impl FnMut(Entry)) {
        if v == self.node {
            self.entries.iter().copied().for_each(f);
        }
    }

    fn read(&self, v: u32, out: &mut Vec<Entry>) {
        if v == self.node {
            out.extend_from_slice(self.entries);
        }
    }
}

impl Lists for FanLists {
    #[inline]
    fn len(&self, v: u32) -> usize {
        FanLists::len(self, v)
    }

    #[inline]
    fn is_border(&self, v: u32) -> bool {
        FanLists::is_border(self, v)
    }

    #[inline]
    fn for_each(&self, v: u32, f: impl FnMut(Entry)) {
        FanLists::for_each(self, v, f)
    }

    #[inline]
    fn read(&self, v: u32, out: &mut Vec<Entry>) {
        FanLists::read(self, v, out)
    }
}

/// Entries per cache line (a node's block: its header and [`INLINE`] entries).
pub(crate) const BLOCK: usize = 8;
/// Entries held in a node's own block, after its header.
pub(crate) const INLINE: usize = BLOCK - 1;

/// One cache line of entries.
#[derive(Clone, Copy, Default)]
#[repr(C, align(64))]
struct Block([Entry; BLOCK]);

// The header, entry 0 of a node's block: `node` packs the length (bits 0–23), the overflow
// size class (24–29), the removed mark (30) and the border flag (31); `triangle` is the
// overflow run's first block.
const LEN_MASK: u32 = (1 << 24) - 1;
const CLASS_SHIFT: u32 = 24;
const CLASS_MASK: u32 = (1 << 6) - 1;
/// Set in the header of a node that was removed ([`FanLists::retire`]).
const RETIRED: u32 = 1 << 30;
const BORDER: u32 = 1 << 31;
const NO_RUN: u32 = u32::MAX;

/// The lists of all nodes.
pub(crate) struct FanLists {
    /// Blocks `0..nodes` are the nodes' own; overflow runs follow.
    blocks: Vec<Block>,
    /// Free overflow runs per size class.
    free: Vec<Vec<u32>>,
}

/// The smallest size class whose run holds `len` entries.
fn class_for(len: usize) -> u32 {
    let blocks = len.div_ceil(BLOCK).max(1);
    blocks.next_power_of_two().trailing_zeros()
}

impl FanLists {
    /// Lists for `nodes` nodes, all empty.
    #[cfg(test)]
    pub(crate) fn new(nodes: usize) -> FanLists {
        FanLists::build(nodes, |_, _| false)
    }

    /// Lists for `nodes` nodes, node `v`'s written by `fill(v, list)` (which returns whether
    /// it is a border list), in one parallel pass over the blocks (lists too long for their
    /// block then move to overflow runs, in node order).
    pub(crate) fn build(
        nodes: usize,
        fill: impl Fn(u32, &mut Vec<Entry>) -> bool + Sync,
    ) -> FanLists {
        // Room for some overflow runs before the blocks move.
        let mut blocks = Vec::with_capacity(nodes + nodes / 8);
        advise_huge_pages(&mut blocks);
        let long = Mutex::new(Vec::new());
        blocks.par_extend(
            (0..nodes as u32)
                .into_par_iter()
                .map_init(Vec::new, |list, v| {
                    list.clear();
                    let border = fill(v, list);
                    let mut block = Block::default();
                    block.0[0] = Entry {
                        node: if border { BORDER } else { 0 },
                        triangle: NO_RUN,
                    };
                    if list.len() <= INLINE {
                        block.0[0].node |= list.len() as u32;
                        block.0[1..=list.len()].copy_from_slice(list);
                    } else {
                        long.lock().unwrap_or_else(|e| e.into_inner()).push((
                            v,
                            border,
                            list.clone(),
                        ));
                    }
                    block
                }),
        );
        let mut lists = FanLists {
            blocks,
            free: Vec::new(),
        };
        let mut long = long.into_inner().unwrap_or_else(|e| e.into_inner());
        long.sort_unstable_by_key(|&(v, _, _)| v);
        for (v, border, list) in long {
            lists.store(v, &list, border);
        }
        lists
    }

    #[inline]
    fn header(&self, v: u32) -> Entry {
        self.blocks[v as usize].0[0]
    }

    /// The number of entries of `v`'s list.
    #[inline]
    pub(crate) fn len(&self, v: u32) -> usize {
        (self.header(v).node & LEN_MASK) as usize
    }

    /// True when `v`'s list is empty (an isolated or removed node).
    #[inline]
    pub(crate) fn is_empty(&self, v: u32) -> bool {
        self.len(v) == 0
    }

    /// True when `v` is on the border (its list is open).
    #[inline]
    pub(crate) fn is_border(&self, v: u32) -> bool {
        self.header(v).node & BORDER != 0
    }

    /// `v`'s whole line when its list is inline: the header, then the list's entries from
    /// index 1 (the rest of the line is unspecified); with the list's length and border
    /// flag. `None` for a list in an overflow run. One fixed-size copy of a cache line,
    /// cheaper than reading a few entries one by one.
    #[inline]
    pub(crate) fn inline_line(&self, v: u32) -> Option<([Entry; BLOCK], usize, bool)> {
        let line = self.blocks[v as usize].0;
        let len = (line[0].node & LEN_MASK) as usize;
        (len <= INLINE).then_some((line, len, line[0].node & BORDER != 0))
    }

    /// Asks the processor to start fetching `v`'s block.
    #[inline]
    pub(crate) fn prefetch(&self, v: u32) {
        crate::memory::prefetch(&self.blocks[v as usize]);
    }

    /// The entries of `v`'s list, in order, as up to two slices of whole blocks' entries.
    #[inline]
    fn slices(&self, v: u32) -> (usize, usize) {
        Self::slices_under(v, self.header(v))
    }

    /// [`slices`](Self::slices) with `v`'s header `h` read already.
    #[inline]
    fn slices_under(v: u32, h: Entry) -> (usize, usize) {
        let len = (h.node & LEN_MASK) as usize;
        if len <= INLINE {
            (v as usize * BLOCK + 1, len)
        } else {
            (h.triangle as usize * BLOCK, len)
        }
    }

    #[inline]
    fn at(&self, flat: usize) -> Entry {
        self.blocks[flat / BLOCK].0[flat % BLOCK]
    }

    #[inline]
    fn flat_mut(&mut self, flat: usize) -> &mut Entry {
        &mut self.blocks[flat / BLOCK].0[flat % BLOCK]
    }

    /// Entry `j` of `v`'s list.
    #[inline]
    pub(crate) fn get(&self, v: u32, j: usize) -> Entry {
        let (start, _) = self.slices(v);
        self.at(start + j)
    }

    /// Calls `f` on every run of consecutive entries of `v`'s list, in order: the inline
    /// entries, or an overflow run block by block.
    #[inline]
    fn for_each_chunk(&self, v: u32, mut f: impl FnMut(&[Entry])) {
        let (start, len) = self.slices(v);
        if len <= INLINE {
            f(&self.blocks[v as usize].0[1..=len]);
            return;
        }
        let (mut b, mut left) = (start / BLOCK, len);
        while left > 0 {
            let take = left.min(BLOCK);
            f(&self.blocks[b].0[..take]);
            left -= take;
            b += 1;
        }
    }

    /// Calls `f` on every entry of `v`'s list, in order.
    #[inline]
    pub(crate) fn for_each(&self, v: u32, mut f: impl FnMut(Entry)) {
        self.for_each_chunk(v, |chunk| chunk.iter().for_each(|&e| f(e)));
    }

    /// Appends `v`'s list to `out`.
    #[inline]
    pub(crate) fn read(&self, v: u32, out: &mut Vec<Entry>) {
        self.for_each_chunk(v, |chunk| out.extend_from_slice(chunk));
    }

    /// True when `b` is in `a`'s list.
    pub(crate) fn contains(&self, a: u32, b: u32) -> bool {
        let mut found = false;
        self.for_each(a, |e| found |= e.node == b);
        found
    }

    /// Replaces `v`'s list by `entries` (`border`: an open list), inline when it fits, else
    /// in an overflow run (moved to a larger one when it outgrows its own).
    pub(crate) fn store(&mut self, v: u32, entries: &[Entry], border: bool) {
        let h = self.header(v);
        let mut run = h.triangle;
        let mut class = (h.node >> CLASS_SHIFT) & CLASS_MASK;
        let start = if entries.len() <= INLINE {
            if run != NO_RUN {
                self.free_run(run, class);
                run = NO_RUN;
                class = 0;
            }
            v as usize * BLOCK + 1
        } else {
            let needed = class_for(entries.len());
            if run == NO_RUN || needed > class {
                if run != NO_RUN {
                    self.free_run(run, class);
                }
                run = self.alloc(needed);
                class = needed;
            }
            run as usize * BLOCK
        };
        if entries.len() <= INLINE {
            self.blocks[v as usize].0[1..=entries.len()].copy_from_slice(entries);
        } else {
            for (k, chunk) in entries.chunks(BLOCK).enumerate() {
                self.blocks[start / BLOCK + k].0[..chunk.len()].copy_from_slice(chunk);
            }
        }
        self.blocks[v as usize].0[0] = Entry {
            node: entries.len() as u32 | class << CLASS_SHIFT | if border { BORDER } else { 0 },
            triangle: run,
        };
    }

    /// Replaces entry `q` of `v`'s list (`q` below its length) by the entries `with`; the
    /// border flag stays. In place when the list is inline and stays so (nearly always: the
    /// entries after `q` move within the node's own line), else through `spare` and
    /// [`store`](Self::store).
    #[cfg(test)]
    pub(crate) fn replace(&mut self, v: u32, q: usize, with: &[Entry], spare: &mut Vec<Entry>) {
        self.replace_under(v, self.header(v), q, with, spare);
    }

    /// [`replace`](Self::replace) with `v`'s header `h` read already.
    #[inline(always)]
    fn replace_under(
        &mut self,
        v: u32,
        h: Entry,
        q: usize,
        with: &[Entry],
        spare: &mut Vec<Entry>,
    ) {
        let len = (h.node & LEN_MASK) as usize;
        debug_assert!(q < len);
        let new_len = len - 1 + with.len();
        if len <= INLINE && new_len <= INLINE {
            // As `splice_within` does, on the node's own line (block[j + 1] holds entry j):
            // indices into the fixed-size line need fewer checks than into a slice (measured:
            // `splice_within` here costs ~3 % more instructions per removal).
            let block = &mut self.blocks[v as usize].0;
            if with.len() > 1 {
                for j in (q + 1..len).rev() {
                    block[j + with.len()] = block[j + 1];
                }
            } else if with.is_empty() {
                for j in q + 1..len {
                    block[j] = block[j + 1];
                }
            }
            for (k, &e) in with.iter().enumerate() {
                block[q + 1 + k] = e;
            }
            block[0].node = (h.node & !LEN_MASK) | new_len as u32;
            return;
        }
        spare.clear();
        self.read(v, spare);
        spare.resize(len.max(new_len), Entry::default());
        splice_within(spare, q, len, with);
        self.store(v, &spare[..new_len], h.node & BORDER != 0);
    }

    /// The edit at node `w` when its neighbour `v` is removed and the new triangles at `w`
    /// form the chain `chain[..k]`, `k = chain.len() − 1`: entries `(x_j, (w, x_j, x_j+1))`
    /// from `x_0`, the neighbour before `v` around `w`; `chain[k]` is the entry that closes
    /// `w`'s list when it is a border list that `v`'s entry closed. `v`'s entry gives way to
    /// the chain less `x_0`, which is listed already and now names the chain's first
    /// triangle; where `v`'s entry opened a border list, `x_0` is new (the border edge now
    /// leads to it) and the whole chain goes in. One header read; in place when the list
    /// stays inline ([`replace`](Self::replace)).
    #[inline]
    pub(crate) fn give_way(&mut self, w: u32, v: u32, chain: &[Entry], spare: &mut Vec<Entry>) {
        let k = chain.len() - 1;
        let h = self.header(w);
        let (start, len) = Self::slices_under(w, h);
        let border = h.node & BORDER != 0;
        let q = if len <= INLINE {
            self.blocks[w as usize].0[1..=len]
                .iter()
                .position(|e| e.node == v)
        } else {
            (0..len).find(|&j| self.at(start + j).node == v)
        }
        .expect("a ring node lists the removed node");
        let with = if border && q == 0 {
            &chain[..k]
        } else {
            let p = if q > 0 { q - 1 } else { len - 1 };
            debug_assert_eq!(self.at(start + p).node, chain[0].node);
            self.flat_mut(start + p).triangle = chain[0].triangle;
            let closes = border && q == len - 1;
            &chain[1..k + closes as usize]
        };
        self.replace_under(w, h, q, with, spare);
    }

    /// Empties `v`'s list, frees its overflow run and marks `v` removed: its header, which
    /// is written anyway, carries the mark (no separate array to touch).
    pub(crate) fn retire(&mut self, v: u32) {
        if self.header(v).triangle != NO_RUN {
            self.clear(v);
        }
        self.blocks[v as usize].0[0] = Entry {
            node: RETIRED,
            triangle: NO_RUN,
        };
    }

    /// True when `v` was [`retire`](Self::retire)d.
    #[inline]
    pub(crate) fn is_retired(&self, v: u32) -> bool {
        self.header(v).node & RETIRED != 0
    }

    /// Empties `v`'s list and frees its overflow run.
    pub(crate) fn clear(&mut self, v: u32) {
        self.store(v, &[], false);
    }

    fn alloc(&mut self, class: u32) -> u32 {
        if let Some(b) = self.free.get_mut(class as usize).and_then(Vec::pop) {
            return b;
        }
        let b = self.blocks.len();
        self.blocks.resize(b + (1usize << class), Block::default());
        b as u32
    }

    fn free_run(&mut self, block: u32, class: u32) {
        let c = class as usize;
        if self.free.len() <= c {
            self.free.resize(c + 1, Vec::new());
        }
        self.free[c].push(block);
    }
}

/// In `entries[..len]`, entry `q` gives way to `with`: the entries after it move (one by
/// one: a few entries, too short for memmove) to make room or close the gap. `entries`
/// must hold `len − 1 + with.len()`.
#[inline]
fn splice_within(entries: &mut [Entry], q: usize, len: usize, with: &[Entry]) {
    if with.len() > 1 {
        for j in (q + 1..len).rev() {
            entries[j - 1 + with.len()] = entries[j];
        }
    } else if with.is_empty() {
        for j in q + 1..len {
            entries[j - 1] = entries[j];
        }
    }
    for (k, &e) in with.iter().enumerate() {
        entries[q + k] = e;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entries(n: u32) -> Vec<Entry> {
        (0..n)
            .map(|i| Entry {
                node: 100 + i,
                triangle: 4 * i + 1,
            })
            .collect()
    }

    #[test]
    fn built_lists_read_back() {
        let lists = FanLists::build(3, |v, list| {
            list.extend(entries([9, 3, 0][v as usize]));
            v == 1
        });
        let mut got = Vec::new();
        for (v, n) in [(0, 9), (1, 3), (2, 0)] {
            got.clear();
            lists.read(v, &mut got);
            assert_eq!(got, entries(n));
            assert_eq!(lists.is_border(v), v == 1);
        }
        assert!(lists.is_empty(2));
    }

    #[test]
    fn lists_grow_shrink_and_reuse_blocks() {
        let mut lists = FanLists::new(3);
        lists.store(0, &entries(6), false);
        lists.store(1, &entries(3), true);
        assert_eq!(lists.len(0), 6);
        assert!(lists.is_border(1) && !lists.is_border(0));
        // Growing past eight entries moves node 0 to a two-block run.
        lists.store(0, &entries(13), false);
        let mut got = Vec::new();
        lists.read(0, &mut got);
        assert_eq!(got, entries(13));
        assert_eq!(lists.get(0, 12).slot(), 12);
        assert_eq!(lists.get(0, 12).corner(), 1);
        assert!(lists.contains(0, 112) && !lists.contains(0, 113));
        // Shrinking moves it back inline; node 2 reuses the run node 0 left.
        let before = lists.blocks.len();
        lists.store(0, &entries(7), false);
        got.clear();
        lists.read(0, &mut got);
        assert_eq!(got, entries(7));
        lists.store(2, &entries(16), false);
        assert_eq!(
            lists.blocks.len(),
            before,
            "the freed two-block run is reused"
        );
        lists.store(2, &entries(9), true);
        assert!(lists.is_border(2));
        lists.clear(0);
        assert!(lists.is_empty(0) && !lists.is_border(0) && !lists.is_retired(0));
        lists.store(0, &entries(8), false);
        assert_eq!(
            lists.blocks.len(),
            before + 1,
            "a new one-block run when none is free"
        );
        got.clear();
        lists.read(2, &mut got);
        assert_eq!(
            got,
            entries(9),
            "shrinking within the overflow keeps the run"
        );
        got.clear();
        lists.read(0, &mut got);
        assert_eq!(got, entries(8));
        got.clear();
        lists.read(1, &mut got);
        assert_eq!(got, entries(3));
        // Retiring frees the run and marks the node; a later list elsewhere reuses the run.
        let blocks = lists.blocks.len();
        lists.retire(2);
        assert!(lists.is_retired(2) && lists.is_empty(2) && !lists.is_border(2));
        lists.store(1, &entries(12), true);
        assert_eq!(lists.blocks.len(), blocks, "node 2's run is reused");
        assert!(!lists.is_retired(1) && lists.is_border(1));
    }

    /// `give_way` at an interior node (the entry before v's wraps round), at a border node
    /// whose list v's entry opened, and at one whose list v's entry closed.
    #[test]
    fn give_way_splices_the_chain_for_the_removed_node() {
        let e = |node: u32, triangle: u32| Entry { node, triangle };
        let (v, x0, y1, z) = (9, 20, 21, 22);
        // The chain (x0, T0), (y1, T1) and the closing entry (z, none).
        let chain = [e(x0, 100), e(y1, 101), e(z, NO_TRIANGLE)];
        let cases: [(Vec<Entry>, bool, Vec<Entry>); 3] = [
            (
                vec![e(v, 1), e(5, 2), e(6, 3), e(x0, 4)],
                false,
                vec![e(y1, 101), e(5, 2), e(6, 3), e(x0, 100)],
            ),
            (
                vec![e(v, 1), e(5, 2), e(6, NO_TRIANGLE)],
                true,
                vec![e(x0, 100), e(y1, 101), e(5, 2), e(6, NO_TRIANGLE)],
            ),
            (
                vec![e(5, 1), e(x0, 2), e(v, NO_TRIANGLE)],
                true,
                vec![e(5, 1), e(x0, 100), e(y1, 101), e(z, NO_TRIANGLE)],
            ),
        ];
        let mut spare = Vec::new();
        for (before, border, after) in cases {
            let mut lists = FanLists::new(1);
            lists.store(0, &before, border);
            lists.give_way(0, v, &chain, &mut spare);
            let mut got = Vec::new();
            lists.read(0, &mut got);
            assert_eq!(got, after, "{before:?}");
            assert_eq!(lists.is_border(0), border);
        }
    }

    /// `replace` agrees with splicing a copy, in place and across the inline limit both ways.
    #[test]
    fn replace_splices_in_place_and_across_the_limit() {
        let mut lists = FanLists::new(2);
        let mut spare = Vec::new();
        let mut expected = entries(5);
        lists.store(0, &expected, true);
        lists.store(1, &entries(3), false);
        let new = |n: u32| Entry {
            node: 500 + n,
            triangle: 7 * n,
        };
        // (position, entries to put there): inline in place; out to a one-block run; within
        // it; out to a two-block run; within it across its blocks, growing and shrinking;
        // back inline.
        let steps: [(usize, Vec<Entry>); 10] = [
            (2, vec![new(1), new(2)]),
            (0, vec![]),
            (4, vec![new(3), new(4), new(5), new(6)]),
            (7, vec![new(7)]),
            (2, vec![new(8), new(9)]),
            (5, vec![new(10), new(11), new(12)]),
            (0, vec![]),
            (9, vec![]),
            (1, vec![]),
            (1, vec![]),
        ];
        let mut longest = 0;
        for (q, with) in steps {
            lists.replace(0, q, &with, &mut spare);
            expected.splice(q..=q, with);
            let mut got = Vec::new();
            lists.read(0, &mut got);
            assert_eq!(got, expected, "after replacing position {q}");
            assert!(lists.is_border(0));
            longest = longest.max(expected.len());
        }
        assert!(
            longest > INLINE && expected.len() <= INLINE,
            "out of the block and back"
        );
        let mut other = Vec::new();
        lists.read(1, &mut other);
        assert_eq!(other, entries(3), "the neighbouring block is untouched");
    }
}
