//! The hash table behind the diamond-based encodings (`Δd`, `Σd`) and the supercube indices
//! (`Δs`, `Σs`): open addressing with linear probing on grid-point keys, each key stored next to
//! its value so that a look-up touches one cache line, and a [`PointMap::prefetch`] that starts
//! loading a key's slot before it is needed.
//!
//! Refinement visits millions of diamonds in an order the hash scatters over memory; its cost
//! is the latency of those scattered loads. A prefetch issued when a diamond is queued (its
//! children, say) overlaps the loads of siblings that a general-purpose map, whose slot
//! address is private, cannot expose.

use super::Point;

/// The coordinate of an empty slot's key: no grid coordinate reaches it (the doubled grid's
/// coordinates are at most `2^31`).
const EMPTY: u32 = u32::MAX;

/// The table grows when more than `LOAD_NUM / LOAD_DEN` of its slots are taken (linear probing
/// stays short below about 0.7).
const LOAD_NUM: usize = 5;
const LOAD_DEN: usize = 8;

/// The fewest slots of an allocated table.
const MIN_SLOTS: usize = 16;

/// A hash map from grid points to `V` (open addressing, linear probing, backward-shift
/// deletion: no tombstones, so look-ups stay short after many removals).
#[derive(Clone, Debug)]
pub(crate) struct PointMap<V, const D: usize> {
    slots: Vec<(Point<D>, V)>,
    len: usize,
    /// `64 − log2(slots.len())`: the home slot is the hash's top bits.
    shift: u32,
}

impl<V: Copy + Default + Send + Sync, const D: usize> Default for PointMap<V, D> {
    fn default() -> Self {
        PointMap {
            slots: Vec::new(),
            len: 0,
            shift: 64,
        }
    }
}

/// A multiply–xor hash of the coordinates; its top bits choose the home slot.
#[inline(always)]
fn hash<const D: usize>(p: &Point<D>) -> u64 {
    let mut h = 0u64;
    for &x in p {
        h = (h ^ u64::from(x)).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    }
    h ^ (h >> 32)
}

impl<V: Copy + Default + Send + Sync, const D: usize> PointMap<V, D> {
    /// An empty map with room for `n` keys without growing.
    pub(crate) fn with_capacity(n: usize) -> Self {
        let mut m = PointMap::default();
        m.reserve(n);
        m
    }

    /// The number of keys.
    pub(crate) fn len(&self) -> usize {
        self.len
    }

    /// True when no key is held.
    pub(crate) fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The number of slots (the load factor is `len / capacity`).
    pub(crate) fn capacity(&self) -> usize {
        self.slots.len()
    }

    /// Makes room for `additional` more keys without growing.
    pub(crate) fn reserve(&mut self, additional: usize) {
        let need = self.len + additional;
        if need * LOAD_DEN > self.slots.len() * LOAD_NUM {
            let mut slots = MIN_SLOTS.max(self.slots.len());
            while need * LOAD_DEN > slots * LOAD_NUM {
                slots *= 2;
            }
            self.rebuild(slots);
        }
    }

    #[inline(always)]
    fn home(&self, p: &Point<D>) -> usize {
        // `shift` is 64 only for the unallocated table, whose callers return early.
        (hash(p) >> self.shift) as usize
    }

    #[inline(always)]
    fn mask(&self) -> usize {
        self.slots.len() - 1
    }

    /// The slot holding `p`, or the empty slot where it would go.
    #[inline(always)]
    fn probe(&self, p: &Point<D>) -> (usize, bool) {
        let mask = self.mask();
        let mut i = self.home(p);
        loop {
            let k = &self.slots[i].0;
            // Branch-free comparison of the coordinates.
            if k.iter().zip(p).fold(0, |d, (a, b)| d | (a ^ b)) == 0 {
                return (i, true);
            }
            if k[0] == EMPTY {
                return (i, false);
            }
            i = (i + 1) & mask;
        }
    }

    /// Starts loading `p`'s home slot into the cache (a hint; it changes nothing else).
    #[inline(always)]
    pub(crate) fn prefetch(&self, p: &Point<D>) {
        if !self.slots.is_empty() {
            crate::memory::prefetch(&self.slots[self.home(p)]);
        }
    }

    /// The value of `p`.
    #[inline]
    pub(crate) fn get(&self, p: &Point<D>) -> Option<&V> {
        if self.slots.is_empty() {
            return None;
        }
        match self.probe(p) {
            (i, true) => Some(&self.slots[i].1),
            _ => None,
        }
    }

    /// The value of `p`, inserting `make()` first when `p` is absent.
    #[inline]
    pub(crate) fn get_or_insert_with(&mut self, p: Point<D>, make: impl FnOnce() -> V) -> &mut V {
        debug_assert!(p[0] != EMPTY);
        if self.slots.is_empty() {
            self.reserve(1);
        }
        let (mut i, found) = self.probe(&p);
        if !found {
            if (self.len + 1) * LOAD_DEN > self.slots.len() * LOAD_NUM {
                self.rebuild(self.slots.len() * 2);
                i = self.probe(&p).0;
            }
            self.slots[i] = (p, make());
            self.len += 1;
        }
        &mut self.slots[i].1
    }

    /// The value of `p`, mutably.
    #[inline]
    pub(crate) fn get_mut(&mut self, p: &Point<D>) -> Option<&mut V> {
        if self.slots.is_empty() {
            return None;
        }
        match self.probe(p) {
            (i, true) => Some(&mut self.slots[i].1),
            _ => None,
        }
    }

    /// Keeps only the entries for which `keep` holds, in a table sized for them.
    pub(crate) fn retain(&mut self, keep: impl Fn(&Point<D>, &V) -> bool) {
        let kept: Vec<(Point<D>, V)> = self
            .slots
            .iter()
            .filter(|(k, v)| k[0] != EMPTY && keep(k, v))
            .copied()
            .collect();
        *self = PointMap::with_capacity(kept.len());
        for (k, v) in kept {
            self.insert(k, v);
        }
    }

    /// Sets the value of `p`; the old value, if any.
    #[inline]
    pub(crate) fn insert(&mut self, p: Point<D>, v: V) -> Option<V> {
        let mut inserted = false;
        let slot = self.get_or_insert_with(p, || {
            inserted = true;
            v
        });
        if inserted {
            None
        } else {
            Some(std::mem::replace(slot, v))
        }
    }

    /// Removes `p`; its value, if it was held.
    #[inline]
    pub(crate) fn remove(&mut self, p: &Point<D>) -> Option<V> {
        if self.slots.is_empty() {
            return None;
        }
        let (mut hole, found) = self.probe(p);
        if !found {
            return None;
        }
        let value = self.slots[hole].1;
        let mask = self.mask();
        // Backward shift: move later entries of the run into the hole when their home slot
        // does not lie cyclically in (hole, j].
        let mut j = hole;
        loop {
            j = (j + 1) & mask;
            if self.slots[j].0[0] == EMPTY {
                break;
            }
            let home = self.home(&self.slots[j].0);
            let between = if hole <= j {
                hole < home && home <= j
            } else {
                hole < home || home <= j
            };
            if !between {
                self.slots[hole] = self.slots[j];
                hole = j;
            }
        }
        self.slots[hole] = ([EMPTY; D], V::default());
        self.len -= 1;
        Some(value)
    }

    /// Every key with its value, in slot order.
    pub(crate) fn iter(&self) -> impl Iterator<Item = (&Point<D>, &V)> + '_ {
        self.slots
            .iter()
            .filter(|(k, _)| k[0] != EMPTY)
            .map(|(k, v)| (k, v))
    }

    /// Moves every entry into a table of `slots` slots (a power of two).
    fn rebuild(&mut self, slots: usize) {
        debug_assert!(slots.is_power_of_two() && slots >= MIN_SLOTS);
        // Large tables on huge pages: refinement's look-ups are scattered, and on 4 KiB pages
        // nearly every one would also miss the TLB.
        let fresh = crate::memory::huge_vec(([EMPTY; D], V::default()), slots);
        let old = std::mem::replace(&mut self.slots, fresh);
        self.shift = 64 - slots.trailing_zeros();
        for (k, v) in old {
            if k[0] != EMPTY {
                let (i, _) = self.probe(&k);
                self.slots[i] = (k, v);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    /// Random inserts, updates, removals and look-ups against `std`'s map, on keys from a small
    /// box (long probe runs, wrapping runs, removals in the middle of runs) and a large one.
    #[test]
    fn agrees_with_std_hash_map() {
        for (range, ops) in [(6u32, 200_000usize), (1 << 20, 100_000)] {
            let mut ours: PointMap<u32, 3> = PointMap::default();
            let mut std_map: HashMap<[u32; 3], u32> = HashMap::new();
            let mut x = 0x2545_f491_4f6c_dd1du64;
            let mut next = || {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                x
            };
            for step in 0..ops {
                let r = next();
                let p = [0, 1, 2].map(|k| ((r >> (20 * k)) as u32) % range);
                match r >> 62 {
                    0 => assert_eq!(ours.insert(p, step as u32), std_map.insert(p, step as u32)),
                    1 => assert_eq!(ours.remove(&p), std_map.remove(&p)),
                    2 => {
                        *ours.get_or_insert_with(p, || 7) += 1;
                        *std_map.entry(p).or_insert(7) += 1;
                    }
                    _ => assert_eq!(ours.get(&p), std_map.get(&p)),
                }
                assert_eq!(ours.len(), std_map.len());
                ours.prefetch(&p);
            }
            let mut a: Vec<_> = ours.iter().map(|(k, v)| (*k, *v)).collect();
            let mut b: Vec<_> = std_map.iter().map(|(k, v)| (*k, *v)).collect();
            a.sort_unstable();
            b.sort_unstable();
            assert_eq!(a, b);
            assert!(ours.len() * LOAD_DEN <= ours.capacity() * LOAD_NUM);
            ours.retain(|k, _| k[0] % 2 == 0);
            std_map.retain(|k, _| k[0] % 2 == 0);
            assert_eq!(ours.len(), std_map.len());
            for (k, v) in &std_map {
                assert_eq!(ours.get(k), Some(v));
            }
        }
        let empty: PointMap<u32, 2> = PointMap::default();
        assert_eq!(
            (empty.get(&[1, 2]), empty.len(), empty.capacity()),
            (None, 0, 0)
        );
    }
}
