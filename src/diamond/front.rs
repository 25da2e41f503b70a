//! Active fronts (Section 7): the current mesh `Σ` as diamonds with parent flags. A diamond with
//! `k` parents has its simplices in `k` groups, one per parent; the group of parent `p` is in
//! `Σ` once `p` has been subdivided, so a flag per parent slot tracks both (3/2/4 bits in 3-D).
//! Slots whose parent lies outside the domain (and all of the root's) are set from the start.
//!
//! Two representations give the identical mesh:
//! * [`DiamondFront`] (`Σd`): a hash from central vertex to the flags;
//! * [`SupercubeFront`] (`Σs`): per scale a hash from supercube origin to one bit per
//!   (type, parent slot) pair — `Σ_τ slots(τ)` bits, 168 in 3-D (the paper's 336/2).

use super::table::{FlagTable, PointMap};
use super::{Diamond, DiamondType, Hierarchy, Point};

/// An active front: parent flags per diamond in `Σ` (a diamond is in `Σ` when it has flags).
pub trait Front<const D: usize> {
    /// An empty front on `hier`.
    fn empty(hier: Hierarchy<D>) -> Self;
    /// The flags of `dia` (`0` when it is not in the front).
    fn flags(&self, dia: &Diamond<D>) -> u32;
    /// Sets the flags of `dia`; `0` removes it.
    fn set_flags(&mut self, dia: &Diamond<D>, flags: u32);
    /// Adds `bits` to the flags of `dia`, starting from `absent` when it is not in the front.
    fn add_flags(&mut self, dia: &Diamond<D>, absent: impl FnOnce() -> u32, bits: u32) {
        let mut f = self.flags(dia);
        if f == 0 {
            f = absent();
        }
        self.set_flags(dia, f | bits);
    }
    /// Starts loading what [`Front::flags`] of `dia` will read (a hint for the cache; it
    /// changes nothing else).
    #[inline]
    fn prefetch(&self, dia: &Diamond<D>) {
        let _ = dia;
    }
    /// Every diamond in the front with its flags (in no particular order).
    fn for_each(&self, f: impl FnMut(Diamond<D>, u32));
    /// Diamonds in the front.
    fn diamonds(&self) -> usize;
    /// Bookkeeping bytes by the paper's model: `Σd` 7 bytes per diamond in 3-D (coordinates and
    /// a flag byte), `Σs` 27 per supercube (origin and 168 bits); in `d`-D, `b_v + 1` and
    /// `b_v + ⌈slots/8⌉`.
    fn bookkeeping_bytes(&self) -> u64;
}

/// The flag bits of the slots whose parent does not exist (outside the domain, or above the
/// root): always set.
pub fn absent_parent_flags<const D: usize>(dia: &Diamond<D>) -> u32 {
    dia.absent_parent_flags()
}

/// All slots of `dia`.
pub fn full_flags<const D: usize>(dia: &Diamond<D>) -> u32 {
    (1u32 << dia.parent_slots()) - 1
}

/// The diamond-based front `Σd`.
///
/// A diamond that leaves the front keeps its entry with flags `0` (a removal would shift the
/// entries after it in the table); such entries are dropped when they outnumber the live
/// ones. Where the doubled grid's coordinates pack into a `u64` with the flags (3-D grids up
/// to `2^18 + 1` points a side), an entry takes 8 bytes; elsewhere 16.
#[derive(Clone, Debug)]
pub struct DiamondFront<const D: usize> {
    hier: Hierarchy<D>,
    map: FrontMap<D>,
    /// Entries with flags.
    live: usize,
}

/// `Σd`'s table: packed where the coordinates fit.
#[derive(Clone, Debug)]
enum FrontMap<const D: usize> {
    Packed(FlagTable<D>),
    Wide(PointMap<u32, D>),
}

impl<const D: usize> DiamondFront<D> {
    /// Sets the flags of `dia` to `f(old)`; returns `(old, new)`.
    #[inline(always)]
    fn update(&mut self, dia: &Diamond<D>, f: impl FnOnce(u32) -> u32) -> (u32, u32) {
        let c = dia.center();
        match &mut self.map {
            FrontMap::Packed(t) => t.update(&c, f),
            FrontMap::Wide(m) => {
                let slot = m.get_or_insert_with(c, || 0);
                let old = *slot;
                *slot = f(old);
                (old, *slot)
            }
        }
    }

    /// Drops the entries of diamonds that left the front when they outnumber the live ones.
    fn compact(&mut self) {
        let entries = match &self.map {
            FrontMap::Packed(t) => t.len(),
            FrontMap::Wide(m) => m.len(),
        };
        if entries > 2 * self.live + 1024 {
            match &mut self.map {
                FrontMap::Packed(t) => t.retain_flagged(),
                FrontMap::Wide(m) => m.retain(|_, &f| f != 0),
            }
        }
    }
}

impl<const D: usize> Front<D> for DiamondFront<D> {
    fn empty(hier: Hierarchy<D>) -> Self {
        let map = if FlagTable::<D>::fits(hier.side()) {
            FrontMap::Packed(FlagTable::default())
        } else {
            FrontMap::Wide(PointMap::default())
        };
        DiamondFront { hier, map, live: 0 }
    }
    #[inline]
    fn flags(&self, dia: &Diamond<D>) -> u32 {
        match &self.map {
            FrontMap::Packed(t) => t.get(&dia.center()),
            FrontMap::Wide(m) => m.get(&dia.center()).copied().unwrap_or(0),
        }
    }
    #[inline]
    fn set_flags(&mut self, dia: &Diamond<D>, flags: u32) {
        let (old, _) = self.update(dia, |_| flags);
        match (old != 0, flags != 0) {
            (false, true) => self.live += 1,
            (true, false) => {
                self.live -= 1;
                self.compact();
            }
            _ => {}
        }
    }
    #[inline]
    fn add_flags(&mut self, dia: &Diamond<D>, absent: impl FnOnce() -> u32, bits: u32) {
        let (old, new) = self.update(dia, |f| if f == 0 { absent() | bits } else { f | bits });
        if old == 0 && new != 0 {
            self.live += 1;
        }
    }
    #[inline]
    fn prefetch(&self, dia: &Diamond<D>) {
        match &self.map {
            FrontMap::Packed(t) => t.prefetch(&dia.center()),
            FrontMap::Wide(m) => m.prefetch(&dia.center()),
        }
    }
    fn for_each(&self, mut f: impl FnMut(Diamond<D>, u32)) {
        let mut call = |p: Point<D>, flags: u32| {
            f(
                self.hier.diamond(p).expect("front points are diamonds"),
                flags,
            )
        };
        match &self.map {
            FrontMap::Packed(t) => t.flagged().for_each(|(p, flags)| call(p, flags)),
            FrontMap::Wide(m) => m
                .iter()
                .filter(|(_, &flags)| flags != 0)
                .for_each(|(p, &flags)| call(*p, flags)),
        }
    }
    fn diamonds(&self) -> usize {
        self.live
    }
    fn bookkeeping_bytes(&self) -> u64 {
        let (bv, _) = super::index_bytes(D, self.hier.levels());
        self.live as u64 * (bv + 1)
    }
}

/// Per type index: the first bit of its slots within a supercube's flags, and the total.
fn slot_offsets<const D: usize>() -> (Vec<u16>, usize) {
    let mut offsets = Vec::new();
    let mut total = 0usize;
    for tau in DiamondType::<D>::all() {
        offsets.push(total as u16);
        total += match tau.class() {
            0 => D,
            i => 2 * i,
        };
    }
    (offsets, total)
}

/// The `n ≤ 32` bits of `bits` from bit `start` on (bit `start` lowest).
#[inline(always)]
fn get_bits(bits: &[u64], start: usize, n: usize) -> u32 {
    let (w, o) = (start / 64, start % 64);
    let mut v = bits[w] >> o;
    if o + n > 64 {
        v |= bits[w + 1] << (64 - o);
    }
    (v & ((1u64 << n) - 1)) as u32
}

/// Sets the `n ≤ 32` bits of `bits` from bit `start` on to the low bits of `value`.
#[inline(always)]
fn set_bits(bits: &mut [u64], start: usize, n: usize, value: u32) {
    let (w, o) = (start / 64, start % 64);
    let mask = (1u64 << n) - 1;
    let v = u64::from(value) & mask;
    bits[w] = (bits[w] & !(mask << o)) | (v << o);
    if o + n > 64 {
        let spill = 64 - o;
        bits[w + 1] = (bits[w + 1] & !(mask >> spill)) | (v >> spill);
    }
}

/// The supercube-based front `Σs`.
#[derive(Clone, Debug)]
pub struct SupercubeFront<const D: usize> {
    hier: Hierarchy<D>,
    /// Per scale: origin → supercube number.
    levels: Vec<PointMap<u32, D>>,
    /// `words` per supercube.
    bits: Vec<u64>,
    /// Per supercube: scale and origin (`None` once freed).
    keys: Vec<Option<(u32, Point<D>)>>,
    /// Freed supercube numbers, for reuse.
    free: Vec<u32>,
    /// Per supercube: diamonds with flags.
    counts: Vec<u16>,
    offsets: Vec<u16>,
    words: usize,
    slots: usize,
    diamonds: usize,
}

impl<const D: usize> SupercubeFront<D> {
    /// Supercubes holding at least one diamond of the front.
    pub fn supercubes(&self) -> usize {
        self.keys.len() - self.free.len()
    }

    #[inline]
    fn locate(&self, dia: &Diamond<D>) -> (Option<u32>, usize, usize) {
        let t = dia.diamond_type().index();
        let cube = self.levels[dia.scale() as usize]
            .get(&dia.supercube_origin())
            .copied();
        (cube, self.offsets[t] as usize, dia.parent_slots())
    }
}

impl<const D: usize> Front<D> for SupercubeFront<D> {
    fn empty(hier: Hierarchy<D>) -> Self {
        let (offsets, slots) = slot_offsets::<D>();
        SupercubeFront {
            hier,
            levels: vec![PointMap::default(); hier.levels() as usize],
            bits: Vec::new(),
            keys: Vec::new(),
            free: Vec::new(),
            counts: Vec::new(),
            offsets,
            words: slots.div_ceil(64),
            slots,
            diamonds: 0,
        }
    }
    #[inline]
    fn flags(&self, dia: &Diamond<D>) -> u32 {
        let (cube, off, n) = self.locate(dia);
        let Some(cube) = cube else { return 0 };
        get_bits(&self.bits, cube as usize * self.words * 64 + off, n)
    }
    fn set_flags(&mut self, dia: &Diamond<D>, flags: u32) {
        let (cube, off, n) = self.locate(dia);
        let cube = match cube {
            Some(c) => c,
            None if flags == 0 => return,
            None => {
                let key = (dia.scale(), dia.supercube_origin());
                let c = match self.free.pop() {
                    Some(c) => {
                        self.keys[c as usize] = Some(key);
                        c
                    }
                    None => {
                        self.keys.push(Some(key));
                        self.counts.push(0);
                        self.bits.extend(std::iter::repeat_n(0, self.words));
                        (self.keys.len() - 1) as u32
                    }
                };
                self.levels[key.0 as usize].insert(key.1, c);
                c
            }
        };
        let base = cube as usize * self.words * 64 + off;
        let had = get_bits(&self.bits, base, n) != 0;
        set_bits(&mut self.bits, base, n, flags);
        let c = cube as usize;
        match (had, flags != 0) {
            (false, true) => {
                self.counts[c] += 1;
                self.diamonds += 1;
            }
            (true, false) => {
                self.counts[c] -= 1;
                self.diamonds -= 1;
                if self.counts[c] == 0 {
                    if let Some((scale, origin)) = self.keys[c].take() {
                        self.levels[scale as usize].remove(&origin);
                    }
                    self.free.push(cube);
                }
            }
            _ => {}
        }
    }
    /// One look-up of the supercube where the default takes two (`flags`, then `set_flags`).
    #[inline]
    fn add_flags(&mut self, dia: &Diamond<D>, absent: impl FnOnce() -> u32, bits: u32) {
        let (cube, off, n) = self.locate(dia);
        let Some(cube) = cube else {
            // A new supercube: `set_flags` creates it.
            self.set_flags(dia, absent() | bits);
            return;
        };
        let base = cube as usize * self.words * 64 + off;
        let old = get_bits(&self.bits, base, n);
        let new = if old == 0 {
            absent() | bits
        } else {
            old | bits
        };
        set_bits(&mut self.bits, base, n, new);
        // Flags are only added: a diamond in the front stays there.
        if old == 0 && new != 0 {
            self.counts[cube as usize] += 1;
            self.diamonds += 1;
        }
    }
    #[inline]
    fn prefetch(&self, dia: &Diamond<D>) {
        self.levels[dia.scale() as usize].prefetch(&dia.supercube_origin());
    }
    fn for_each(&self, mut f: impl FnMut(Diamond<D>, u32)) {
        let types: Vec<DiamondType<D>> = DiamondType::all().collect();
        for (c, key) in self.keys.iter().enumerate() {
            let Some((scale, origin)) = key else { continue };
            let cube = super::Supercube {
                origin: *origin,
                scale: *scale,
            };
            for (t, tau) in types.iter().enumerate() {
                let Ok(dia) = cube.diamond(&self.hier, *tau) else {
                    continue;
                };
                let base = c * self.words * 64 + self.offsets[t] as usize;
                let flags = get_bits(&self.bits, base, dia.parent_slots());
                if flags != 0 {
                    f(dia, flags);
                }
            }
        }
    }
    fn diamonds(&self) -> usize {
        self.diamonds
    }
    fn bookkeeping_bytes(&self) -> u64 {
        let (bv, _) = super::index_bytes(D, self.hier.levels());
        self.supercubes() as u64 * (bv + (self.slots as u64).div_ceil(8))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The packed `Σd` table (8-byte entries) and the wide one (the fallback for grids whose
    /// coordinates do not pack) hold the same front through random flag changes on every
    /// diamond of a small 3-D grid, compactions included.
    #[test]
    fn packed_and_wide_diamond_fronts_agree() {
        let hier = Hierarchy::<3>::new(5).unwrap();
        let side = hier.side();
        let diamonds: Vec<Diamond<3>> = (0..(side + 1).pow(3))
            .filter_map(|i| {
                let p = [
                    i % (side + 1),
                    i / (side + 1) % (side + 1),
                    i / (side + 1).pow(2),
                ];
                hier.diamond(p).ok()
            })
            .collect();
        let mut packed = DiamondFront::empty(hier);
        assert!(matches!(packed.map, FrontMap::Packed(_)));
        let mut wide = DiamondFront {
            hier,
            map: FrontMap::Wide(PointMap::default()),
            live: 0,
        };
        let mut x = 0x2545_f491_4f6c_dd1du64;
        let (mut compacted, mut entries) = (false, 0);
        for step in 0..400_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let dia = &diamonds[(x >> 16) as usize % diamonds.len()];
            let bits = (x >> 8) as u32 & full_flags(dia);
            // Mostly clearing, so that cleared entries come to outnumber the live ones.
            match x & 7 {
                0 => assert_eq!(packed.flags(dia), wide.flags(dia), "step {step}"),
                1 => {
                    packed.set_flags(dia, bits);
                    wide.set_flags(dia, bits);
                }
                2 => {
                    packed.add_flags(dia, || absent_parent_flags(dia), bits);
                    wide.add_flags(dia, || absent_parent_flags(dia), bits);
                }
                _ => {
                    packed.set_flags(dia, 0);
                    wide.set_flags(dia, 0);
                }
            }
            assert_eq!(packed.diamonds(), wide.diamonds());
            if let FrontMap::Packed(t) = &packed.map {
                compacted |= t.len() < entries;
                entries = t.len();
            }
        }
        assert!(compacted, "the test reaches a compaction");
        let collect = |f: &DiamondFront<3>| {
            let mut v = Vec::new();
            f.for_each(|d, flags| v.push((d.center(), flags)));
            v.sort_unstable();
            v
        };
        assert_eq!(collect(&packed), collect(&wide));
        // Adding no bits to an absent diamond without absent parents adds nothing.
        assert_eq!(collect(&packed).len(), packed.diamonds());
        assert!(packed.diamonds() > 0);
    }
}
