//! The hash tables behind the diamond-based encodings (`Δd`, `Σd`) and the supercube indices
//! (`Δs`, `Σs`): open addressing with linear probing on grid-point keys (as coordinates, or
//! packed into one word), each key stored next to its value so that a look-up touches one
//! cache line, and a [`HashTable::prefetch`] that starts loading a key's slot before it is
//! needed.
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

/// A key of [`HashTable`]: a value no key takes marks an empty slot.
pub(crate) trait TableKey: Copy + Send + Sync {
    /// The empty slot's key.
    const EMPTY: Self;
    /// True for [`TableKey::EMPTY`] (cheaper than a full comparison).
    fn is_empty_key(&self) -> bool;
    /// Equality, without branches.
    fn same(&self, other: &Self) -> bool;
    /// The hash whose top bits choose the home slot.
    fn table_hash(&self) -> u64;
}

impl<const D: usize> TableKey for Point<D> {
    const EMPTY: Self = [EMPTY; D];
    #[inline(always)]
    fn is_empty_key(&self) -> bool {
        self[0] == EMPTY
    }
    #[inline(always)]
    fn same(&self, other: &Self) -> bool {
        self.iter().zip(other).fold(0, |d, (a, b)| d | (a ^ b)) == 0
    }
    #[inline(always)]
    fn table_hash(&self) -> u64 {
        hash(self)
    }
}

/// A grid point packed into one word (see [`pack_point`]); never all ones.
impl TableKey for u64 {
    const EMPTY: Self = u64::MAX;
    #[inline(always)]
    fn is_empty_key(&self) -> bool {
        *self == u64::MAX
    }
    #[inline(always)]
    fn same(&self, other: &Self) -> bool {
        self == other
    }
    #[inline(always)]
    fn table_hash(&self) -> u64 {
        mix(*self)
    }
}

/// `p` in one word, `bits` bits per coordinate (every coordinate below `2^bits`, `d·bits ≤
/// 63`, so the word is never all ones).
#[inline(always)]
pub(crate) fn pack_point<const D: usize>(p: &Point<D>, bits: u32) -> u64 {
    let mut key = 0u64;
    for (k, &x) in p.iter().enumerate() {
        debug_assert!(u64::from(x) < 1 << bits);
        key |= u64::from(x) << (k as u32 * bits);
    }
    key
}

/// The point [`pack_point`] packed.
#[inline(always)]
pub(crate) fn unpack_point<const D: usize>(key: u64, bits: u32) -> Point<D> {
    let mask = (1u64 << bits) - 1;
    std::array::from_fn(|k| ((key >> (k as u32 * bits)) & mask) as u32)
}

/// A hash map from keys to `V` (open addressing, linear probing, backward-shift deletion: no
/// tombstones, so look-ups stay short after many removals).
#[derive(Clone, Debug)]
pub(crate) struct HashTable<K, V> {
    slots: Vec<(K, V)>,
    len: usize,
    /// `64 − log2(slots.len())`: the home slot is the hash's top bits.
    shift: u32,
}

/// A hash map from grid points to `V`.
pub(crate) type PointMap<V, const D: usize> = HashTable<Point<D>, V>;

impl<K: TableKey, V: Copy + Default + Send + Sync> Default for HashTable<K, V> {
    fn default() -> Self {
        HashTable {
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

impl<K: TableKey, V: Copy + Default + Send + Sync> HashTable<K, V> {
    /// An empty map with room for `n` keys without growing.
    pub(crate) fn with_capacity(n: usize) -> Self {
        let mut m = HashTable::default();
        m.reserve(n);
        m
    }

    /// The number of keys.
    pub(crate) fn len(&self) -> usize {
        self.len
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
    fn home(&self, p: &K) -> usize {
        // `shift` is 64 only for the unallocated table, whose callers return early.
        (p.table_hash() >> self.shift) as usize
    }

    #[inline(always)]
    fn mask(&self) -> usize {
        self.slots.len() - 1
    }

    /// The slot holding `p`, or the empty slot where it would go.
    #[inline(always)]
    fn probe(&self, p: &K) -> (usize, bool) {
        let mask = self.mask();
        let mut i = self.home(p);
        loop {
            let k = &self.slots[i].0;
            if k.same(p) {
                return (i, true);
            }
            if k.is_empty_key() {
                return (i, false);
            }
            i = (i + 1) & mask;
        }
    }

    /// Starts loading `p`'s home slot into the cache (a hint; it changes nothing else).
    #[inline(always)]
    pub(crate) fn prefetch(&self, p: &K) {
        if !self.slots.is_empty() {
            crate::memory::prefetch(&self.slots[self.home(p)]);
        }
    }

    /// The value of `p`.
    #[inline]
    pub(crate) fn get(&self, p: &K) -> Option<&V> {
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
    pub(crate) fn get_or_insert_with(&mut self, p: K, make: impl FnOnce() -> V) -> &mut V {
        debug_assert!(!p.is_empty_key());
        if self.slots.is_empty() {
            self.reserve(1);
        }
        let (mut i, found) = self.probe(&p);
        if !found {
            if (self.len + 1) * LOAD_DEN > self.slots.len() * LOAD_NUM {
                let grow = if self.slots.len() >= 1 << 16 { 4 } else { 2 };
                self.rebuild(self.slots.len() * grow);
                i = self.probe(&p).0;
            }
            self.slots[i] = (p, make());
            self.len += 1;
        }
        &mut self.slots[i].1
    }

    /// Keeps only the entries for which `keep` holds, in a table sized for them.
    pub(crate) fn retain(&mut self, keep: impl Fn(&K, &V) -> bool) {
        let kept: Vec<(K, V)> = self
            .slots
            .iter()
            .filter(|(k, v)| !k.is_empty_key() && keep(k, v))
            .copied()
            .collect();
        *self = HashTable::with_capacity(kept.len());
        for (k, v) in kept {
            self.insert(k, v);
        }
    }

    /// Sets the value of `p`; the old value, if any.
    #[inline]
    pub(crate) fn insert(&mut self, p: K, v: V) -> Option<V> {
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
    pub(crate) fn remove(&mut self, p: &K) -> Option<V> {
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
            if self.slots[j].0.is_empty_key() {
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
        self.slots[hole] = (K::EMPTY, V::default());
        self.len -= 1;
        Some(value)
    }

    /// Every key with its value, in slot order.
    pub(crate) fn iter(&self) -> impl Iterator<Item = (&K, &V)> + '_ {
        self.slots
            .iter()
            .filter(|(k, _)| !k.is_empty_key())
            .map(|(k, v)| (k, v))
    }

    /// Moves every entry into a table of `slots` slots (a power of two).
    fn rebuild(&mut self, slots: usize) {
        debug_assert!(slots.is_power_of_two() && slots >= MIN_SLOTS);
        // Large tables on huge pages: refinement's look-ups are scattered, and on 4 KiB pages
        // nearly every one would also miss the TLB.
        let fresh = crate::memory::huge_vec((K::EMPTY, V::default()), slots);
        let old = std::mem::replace(&mut self.slots, fresh);
        self.shift = 64 - slots.trailing_zeros();
        for (k, v) in old {
            if !k.is_empty_key() {
                let (i, _) = self.probe(&k);
                self.slots[i] = (k, v);
            }
        }
    }
}

/// A set of grid points with a few flag bits each, one `u64` per slot: the coordinates
/// packed `B = ⌊(64 − F)/d⌋` bits each and the `F` flag bits above them — the diamond front
/// `Σd` in 8 bytes per slot where [`PointMap`] takes 16. Open addressing with linear probing;
/// entries are never removed one by one (a cleared entry keeps its key with flags `0`), only
/// all at once by [`FlagTable::retain_flagged`].
#[derive(Clone, Debug)]
pub(crate) struct FlagTable<const D: usize> {
    slots: Vec<u64>,
    len: usize,
    shift: u32,
}

/// A 64-bit finaliser (MurmurHash3's `fmix64`): every input bit reaches every output bit,
/// so packed lattice keys — coordinates in bit fields, low bits zero — spread evenly over
/// the top bits that choose the home slot (one multiply leaves them clustered).
#[inline(always)]
fn mix(mut h: u64) -> u64 {
    h ^= h >> 33;
    h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
    h ^= h >> 33;
    h = h.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
    h ^ (h >> 33)
}

/// An empty slot: all ones, which no packed entry is (a coordinate's field is never all
/// ones, see [`FlagTable::fits`]).
const EMPTY_WORD: u64 = u64::MAX;

impl<const D: usize> Default for FlagTable<D> {
    fn default() -> Self {
        FlagTable {
            slots: Vec::new(),
            len: 0,
            shift: 64,
        }
    }
}

impl<const D: usize> FlagTable<D> {
    /// Flag bits: the most parent slots of a `d`-D diamond, `max(d, 2(d − 1))`.
    pub(crate) const FLAG_BITS: u32 = if 2 * (D as u32).saturating_sub(1) > D as u32 {
        2 * (D as u32 - 1)
    } else {
        D as u32
    };
    /// Bits per coordinate.
    const COORD_BITS: u32 = (64 - Self::FLAG_BITS) / D as u32;
    const KEY_BITS: u32 = Self::COORD_BITS * D as u32;
    const KEY_MASK: u64 = (1 << Self::KEY_BITS) - 1;

    /// True when every coordinate up to `max` packs (below the field's all-ones value).
    pub(crate) fn fits(max: u32) -> bool {
        u64::from(max) < (1u64 << Self::COORD_BITS) - 1
    }

    #[inline(always)]
    fn pack(p: &Point<D>) -> u64 {
        pack_point(p, Self::COORD_BITS)
    }

    #[inline(always)]
    fn unpack(word: u64) -> (Point<D>, u32) {
        (
            unpack_point(word & Self::KEY_MASK, Self::COORD_BITS),
            (word >> Self::KEY_BITS) as u32,
        )
    }

    #[inline(always)]
    fn home(&self, key: u64) -> usize {
        (mix(key) >> self.shift) as usize
    }

    /// The slot holding `key`, or the empty slot where it would go.
    #[inline(always)]
    fn probe(&self, key: u64) -> (usize, bool) {
        let mask = self.slots.len() - 1;
        let mut i = self.home(key);
        loop {
            let w = self.slots[i];
            // A packed key is never all ones, so a match is no empty slot.
            if w & Self::KEY_MASK == key {
                return (i, true);
            }
            if w == EMPTY_WORD {
                return (i, false);
            }
            i = (i + 1) & mask;
        }
    }

    /// Entries, flagged or not.
    pub(crate) fn len(&self) -> usize {
        self.len
    }

    /// The flags of `p` (`0` when absent).
    #[inline]
    pub(crate) fn get(&self, p: &Point<D>) -> u32 {
        if self.slots.is_empty() {
            return 0;
        }
        match self.probe(Self::pack(p)) {
            (i, true) => (self.slots[i] >> Self::KEY_BITS) as u32,
            _ => 0,
        }
    }

    /// Sets the flags of `p` to `f(old)` (`old` is `0` when `p` is absent; an absent `p`
    /// whose new flags are `0` is not inserted); returns `(old, new)`.
    #[inline]
    pub(crate) fn update(&mut self, p: &Point<D>, f: impl FnOnce(u32) -> u32) -> (u32, u32) {
        let key = Self::pack(p);
        if self.slots.is_empty() {
            self.rebuild(MIN_SLOTS);
        }
        let (mut i, found) = self.probe(key);
        let old = if found {
            (self.slots[i] >> Self::KEY_BITS) as u32
        } else {
            0
        };
        let new = f(old);
        debug_assert!(new < 1 << Self::FLAG_BITS);
        if !found {
            if new == 0 {
                return (0, 0);
            }
            if (self.len + 1) * LOAD_DEN > self.slots.len() * LOAD_NUM {
                let grow = if self.slots.len() >= 1 << 16 { 4 } else { 2 };
                self.rebuild(self.slots.len() * grow);
                i = self.probe(key).0;
            }
            self.len += 1;
        }
        self.slots[i] = key | (u64::from(new) << Self::KEY_BITS);
        (old, new)
    }

    /// Starts loading `p`'s home slot into the cache (a hint; it changes nothing else).
    #[inline(always)]
    pub(crate) fn prefetch(&self, p: &Point<D>) {
        if !self.slots.is_empty() {
            crate::memory::prefetch(&self.slots[self.home(Self::pack(p))]);
        }
    }

    /// Every entry with non-zero flags, in slot order.
    pub(crate) fn flagged(&self) -> impl Iterator<Item = (Point<D>, u32)> + '_ {
        self.slots
            .iter()
            .filter(|&&w| w != EMPTY_WORD && w >> Self::KEY_BITS != 0)
            .map(|&w| Self::unpack(w))
    }

    /// Drops the entries whose flags are `0`, in a table sized for the rest.
    pub(crate) fn retain_flagged(&mut self) {
        let kept: Vec<u64> = self
            .slots
            .iter()
            .copied()
            .filter(|&w| w != EMPTY_WORD && w >> Self::KEY_BITS != 0)
            .collect();
        let mut slots = MIN_SLOTS;
        while kept.len() * LOAD_DEN > slots * LOAD_NUM {
            slots *= 2;
        }
        self.slots = Vec::new();
        self.len = 0;
        self.rebuild(slots);
        for w in kept {
            let (i, _) = self.probe(w & Self::KEY_MASK);
            self.slots[i] = w;
            self.len += 1;
        }
    }

    /// Moves every entry into a table of `slots` slots (a power of two).
    fn rebuild(&mut self, slots: usize) {
        let fresh = crate::memory::huge_vec(EMPTY_WORD, slots);
        let old = std::mem::replace(&mut self.slots, fresh);
        self.shift = 64 - slots.trailing_zeros();
        for w in old {
            if w != EMPTY_WORD {
                let (i, _) = self.probe(w & Self::KEY_MASK);
                self.slots[i] = w;
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

    /// Random flag updates against `std`'s map, in 2-D, 3-D and 5-D, on keys from a small box
    /// (long probe runs) and up to the largest coordinate that packs; entries cleared and
    /// compacted away.
    #[test]
    fn flag_table_agrees_with_std_hash_map() {
        fn run<const D: usize>(range: u32, ops: usize) {
            assert!(FlagTable::<D>::fits(range));
            assert!(!FlagTable::<D>::fits((1 << FlagTable::<D>::COORD_BITS) - 1));
            let mut ours: FlagTable<D> = FlagTable::default();
            let mut reference: HashMap<[u32; D], u32> = HashMap::new();
            let mut x = 0x9e37_79b9_7f4a_7c15u64 ^ D as u64;
            let mut next = || {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                x
            };
            let flag_mask = (1u32 << FlagTable::<D>::FLAG_BITS) - 1;
            for _ in 0..ops {
                let r = next();
                let p: [u32; D] =
                    std::array::from_fn(|k| ((next() >> (k * 7)) as u32) % (range + 1));
                let bits = (r >> 8) as u32 & flag_mask;
                if r & 3 == 0 {
                    assert_eq!(ours.get(&p), reference.get(&p).copied().unwrap_or(0));
                } else {
                    let set = r & 3 == 1;
                    let (old, new) = ours.update(&p, |f| if set { bits } else { f | bits });
                    let want_old = reference.get(&p).copied().unwrap_or(0);
                    let want_new = if set { bits } else { want_old | bits };
                    assert_eq!((old, new), (want_old, want_new));
                    if want_new != 0 || reference.contains_key(&p) {
                        reference.insert(p, want_new);
                    }
                }
                ours.prefetch(&p);
            }
            let mut a: Vec<_> = ours.flagged().collect();
            let mut b: Vec<_> = reference
                .iter()
                .filter(|(_, &f)| f != 0)
                .map(|(k, &f)| (*k, f))
                .collect();
            a.sort_unstable();
            b.sort_unstable();
            assert_eq!(a, b);
            assert_eq!(ours.len(), reference.len());
            ours.retain_flagged();
            assert_eq!(ours.len(), b.len());
            for (k, f) in &b {
                assert_eq!(ours.get(k), *f);
            }
        }
        run::<2>(9, 50_000);
        run::<2>((1 << FlagTable::<2>::COORD_BITS) - 2, 50_000);
        run::<3>(6, 100_000);
        run::<3>((1 << FlagTable::<3>::COORD_BITS) - 2, 100_000);
        run::<5>(4, 50_000);
        run::<5>((1 << FlagTable::<5>::COORD_BITS) - 2, 50_000);
    }
}
