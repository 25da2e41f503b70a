//! Diamond-based multiresolution volumes (Section 6): the full DMV `Δf`, partial DMVs `Δp`
//! (closed under ancestors) selected by error or by isovalues, and their two indexed encodings:
//! diamond-based `Δd` (a hash from central vertex to data) and supercube-based `Δs` (per scale a
//! hash from supercube origin to a bit-flag internal map and a packed data array, Section 5.2–5.3).

use super::error::{diamond_stats_fast, diamond_stats_integer, integer_samples};
use super::table::{pack_point, HashTable, PointMap};
use super::{Diamond, Field, Hierarchy, Point};
use crate::par::prelude::*;

/// The data a DMV keeps per diamond (Section 6): `F(v_c)`, the error `ε(δ)` (an upper bound,
/// rounded up to `f32`) and the range of `F` over δ's domain (rounded outwards to `f32`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DiamondData {
    /// `F` at the central vertex.
    pub value: f64,
    /// `ε(δ)`, rounded up.
    pub error: f32,
    /// The least sample in δ's domain, rounded down.
    pub min: f32,
    /// The largest sample in δ's domain, rounded up.
    pub max: f32,
}

/// `x` rounded up to an `f32`.
pub(crate) fn f32_up(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) < x {
        f.next_up()
    } else {
        f
    }
}

/// `x` rounded down to an `f32`.
pub(crate) fn f32_down(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) > x {
        f.next_down()
    } else {
        f
    }
}

/// Read access to a DMV's diamonds, whatever the encoding.
pub trait DmvAccess<const D: usize> {
    /// The hierarchy.
    fn hierarchy(&self) -> Hierarchy<D>;
    /// The data of `dia`, or `None` when the DMV does not hold it.
    fn data(&self, dia: &Diamond<D>) -> Option<DiamondData>;
    /// `F` at a grid point that is a held diamond's central vertex or a domain corner.
    fn value(&self, p: &Point<D>) -> Option<f64>;
    /// Starts loading what [`DmvAccess::data`] of `dia` will read (a hint for the cache; it
    /// changes nothing else).
    #[inline]
    fn prefetch(&self, dia: &Diamond<D>) {
        let _ = dia;
    }
}

pub use crate::hashing::PointHasher;

/// The full DMV `Δf`: every diamond's data, indexed like the field (row-major, axis 0
/// fastest), the corners included with zero error.
#[derive(Clone, Debug)]
pub struct FullDmv<const D: usize> {
    field: Field<D>,
    /// Per grid point `[ε, min, max]`, interleaved so that refinement's one look-up per
    /// diamond touches one cache line.
    stats: Vec<[f32; 3]>,
}

impl<const D: usize> FullDmv<D> {
    /// Computes `ε` and the range of every diamond (the fast path's certified upper bound,
    /// rounded up), in parallel over the grid.
    pub fn build(field: Field<D>) -> FullDmv<D> {
        let hier = field.hierarchy();
        let n = field.values().len();
        // Integer samples take the exact integer route, others the certified f64 one.
        let ints = integer_samples(&field);
        let mut stats: Vec<[f32; 3]> = Vec::with_capacity(n);
        // Refinement reads it at scattered places: huge pages spare most TLB misses.
        crate::memory::advise_huge_pages(&mut stats);
        stats.par_extend(
            (0..n)
                .into_par_iter()
                .map(|i| match hier.diamond(field.point(i)) {
                    Ok(dia) => {
                        let s = match &ints {
                            Some(v) => diamond_stats_integer(v, hier.side(), &dia),
                            None => diamond_stats_fast(&field, &dia),
                        };
                        [f32_up(s.error_hi), f32_down(s.min), f32_up(s.max)]
                    }
                    Err(_) => {
                        let v = field.values()[i];
                        [0.0, f32_down(v), f32_up(v)]
                    }
                }),
        );
        FullDmv { field, stats }
    }

    /// The field.
    pub fn field(&self) -> &Field<D> {
        &self.field
    }

    /// `n_f`: the number of grid points (the paper counts every sample).
    pub fn len(&self) -> usize {
        self.field.values().len()
    }

    /// Never empty (a grid has at least `3^d` points).
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The data at array index `i`.
    pub fn data_at(&self, i: usize) -> DiamondData {
        let [error, min, max] = self.stats[i];
        DiamondData {
            value: self.field.values()[i],
            error,
            min,
            max,
        }
    }

    /// The partial DMV of the diamonds that `keep` selects, closed under ancestors (Section 6's
    /// transitive closure): a bit per grid point.
    pub fn select(&self, keep: impl Fn(&DiamondData) -> bool + Sync) -> Selection<D> {
        let hier = self.field.hierarchy();
        let n = self.len();
        let mut bits = vec![0u64; n.div_ceil(64)];
        let side = hier.side();
        // Children before parents: scales from the finest, and within a scale the classes
        // from d − 1 down to 0 (a class-i parent is class i − 1 at the same scale, a class-0
        // diamond's parents are class d − 1 one scale up).
        for scale in 0..hier.levels() {
            let step = 1u32 << scale;
            for class in (0..D).rev() {
                let mut p = [0u32; D];
                loop {
                    let odd = (0..D).fold(0u32, |m, k| m | ((p[k] >> scale) & 1) << k);
                    if odd != 0 && D - odd.count_ones() as usize == class {
                        let i = self.field.index(&p);
                        let kept = bits[i / 64] >> (i % 64) & 1 == 1 || keep(&self.data_at(i));
                        if kept {
                            bits[i / 64] |= 1 << (i % 64);
                            let dia = hier.diamond_unchecked(p);
                            for slot in 0..dia.parent_slots() {
                                if let Some(parent) = dia.parent_in_slot(slot) {
                                    let j = self.field.index(&parent.center());
                                    bits[j / 64] |= 1 << (j % 64);
                                }
                            }
                        }
                    }
                    let mut k = 0;
                    while k < D && p[k] + step > side {
                        p[k] = 0;
                        k += 1;
                    }
                    if k == D {
                        break;
                    }
                    p[k] += step;
                }
            }
        }
        Selection { bits, hier }
    }

    /// Δp for `ε(δ) > threshold`.
    pub fn select_by_error(&self, threshold: f64) -> Selection<D> {
        self.select(|d| f64::from(d.error) > threshold)
    }

    /// Δp for the diamonds whose range holds one of `isovalues`.
    pub fn select_by_isovalues(&self, isovalues: &[f64]) -> Selection<D> {
        self.select(|d| {
            isovalues
                .iter()
                .any(|&k| f64::from(d.min) <= k && k <= f64::from(d.max))
        })
    }

    /// The diamond-based encoding `Δd` of a selection.
    pub fn diamond_encoding(&self, sel: &Selection<D>) -> DiamondDmv<D> {
        let mut map = DataTable::new(self.field.hierarchy().side(), sel.count());
        for i in sel.indices() {
            map.insert(self.field.point(i), self.data_at(i));
        }
        DiamondDmv {
            hier: self.field.hierarchy(),
            map,
            corners: corner_values(&self.field),
        }
    }

    /// The supercube-based encoding `Δs` of a selection: the supercubes of every scale are
    /// visited in (scale, origin) order and their types looked up in the selection, so no
    /// sorting or per-supercube allocation is needed.
    pub fn supercube_encoding(&self, sel: &Selection<D>) -> SupercubeDmv<D> {
        let hier = self.field.hierarchy();
        let side = hier.side();
        let types: Vec<super::DiamondType<D>> = super::DiamondType::all().collect();
        let mut out = SupercubeDmv::empty(hier, self.field.real_dims(), corner_values(&self.field));
        let mut items: Vec<(usize, DiamondData)> = Vec::with_capacity(types.len());
        for scale in 0..hier.levels() {
            let step = 4u32 << scale;
            // Origins in lexicographic order: the last coordinate fastest.
            let mut origin = [0u32; D];
            loop {
                items.clear();
                for (t, tau) in types.iter().enumerate() {
                    let off = tau.offset();
                    let mut c = [0u32; D];
                    let mut inside = true;
                    for k in 0..D {
                        let x = u64::from(origin[k]) + (u64::from(off[k]) << scale);
                        inside &= x <= u64::from(side);
                        c[k] = x as u32;
                    }
                    if inside && !hier.is_corner(&c) {
                        let i = self.field.index(&c);
                        if sel.contains_index(i) {
                            items.push((t, self.data_at(i)));
                        }
                    }
                }
                if !items.is_empty() {
                    out.push_cube(scale, origin, &items);
                }
                let mut k = D;
                let done = loop {
                    if k == 0 {
                        break true;
                    }
                    k -= 1;
                    if origin[k] + step <= side {
                        origin[k] += step;
                        break false;
                    }
                    origin[k] = 0;
                };
                if done {
                    break;
                }
            }
        }
        out
    }
}

/// The values at the `2^d` domain corners, corner `j` having `x_k = 2^N` when bit `k` of `j`
/// is set.
pub(crate) fn corner_values<const D: usize>(field: &Field<D>) -> Vec<f64> {
    let side = field.hierarchy().side();
    (0..1usize << D)
        .map(|j| {
            field.at(&std::array::from_fn(
                |k| if j >> k & 1 == 1 { side } else { 0 },
            ))
        })
        .collect()
}

/// The corner index of `p`, when `p` is a domain corner.
pub(crate) fn corner_index<const D: usize>(p: &Point<D>, side: u32) -> Option<usize> {
    let mut j = 0;
    for (k, &x) in p.iter().enumerate() {
        if x == side {
            j |= 1 << k;
        } else if x != 0 {
            return None;
        }
    }
    Some(j)
}

impl<const D: usize> DmvAccess<D> for FullDmv<D> {
    fn hierarchy(&self) -> Hierarchy<D> {
        self.field.hierarchy()
    }
    #[inline]
    fn data(&self, dia: &Diamond<D>) -> Option<DiamondData> {
        Some(self.data_at(self.field.index(&dia.center())))
    }
    #[inline]
    fn prefetch(&self, dia: &Diamond<D>) {
        // `data` reads the statistics and the sample: two arrays, two lines.
        let i = self.field.index(&dia.center());
        if let (Some(s), Some(v)) = (self.stats.get(i), self.field.values().get(i)) {
            crate::memory::prefetch(s);
            crate::memory::prefetch(v);
        }
    }
    #[inline]
    fn value(&self, p: &Point<D>) -> Option<f64> {
        Some(self.field.at(p))
    }
}

/// A partial DMV `Δp`: which grid points' diamonds are kept (closed under ancestors).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Selection<const D: usize> {
    bits: Vec<u64>,
    hier: Hierarchy<D>,
}

impl<const D: usize> Selection<D> {
    /// `n_p`: the number of diamonds kept.
    pub fn count(&self) -> usize {
        self.bits.iter().map(|w| w.count_ones() as usize).sum()
    }

    /// True when the diamond at array index `i` is kept.
    pub fn contains_index(&self, i: usize) -> bool {
        self.bits
            .get(i / 64)
            .is_some_and(|w| w >> (i % 64) & 1 == 1)
    }

    /// The kept array indices, increasing.
    pub fn indices(&self) -> impl Iterator<Item = usize> + '_ {
        self.bits.iter().enumerate().flat_map(|(w, &bits)| {
            (0..64)
                .filter(move |b| bits >> b & 1 == 1)
                .map(move |b| w * 64 + b)
        })
    }

    /// The hierarchy.
    pub fn hierarchy(&self) -> Hierarchy<D> {
        self.hier
    }
}

/// The diamond-based partial DMV `Δd`: a hash from central vertex to data.
#[derive(Clone, Debug)]
pub struct DiamondDmv<const D: usize> {
    hier: Hierarchy<D>,
    map: DataTable<D>,
    corners: Vec<f64>,
}

/// `Δd`'s table: the central vertex packed into one word where its coordinates fit
/// (`⌊63/d⌋` bits each: 3-D grids up to `2^20 + 1` a side), 32-byte entries in 3-D that never
/// straddle a cache line; else the coordinates as they are (40 bytes).
#[derive(Clone, Debug)]
enum DataTable<const D: usize> {
    Packed(HashTable<u64, DiamondData>),
    Wide(PointMap<DiamondData, D>),
}

impl<const D: usize> DataTable<D> {
    const BITS: u32 = 63 / D as u32;

    /// An empty table for a grid of side `side`, with room for `n` entries.
    ///
    /// `Δd` is built once and then only read, mostly for diamonds it does not hold (the
    /// children refinement examines outside the selection), so the table is sized for a load
    /// of at most ½ (the growth rule's ⅝ of room for `5n/4`): a miss under linear probing
    /// scans `(1 + 1/(1−α)²)/2` slots, 3.2 at ⅝ and at most 2.5 here. Table 1's `Δd` bytes are
    /// the model's `n_p (b_δ + b_v)`, not this table's.
    fn new(side: u32, n: usize) -> Self {
        let room = n + n.div_ceil(4);
        if u64::from(side) < 1 << Self::BITS {
            DataTable::Packed(HashTable::with_capacity(room))
        } else {
            DataTable::Wide(HashTable::with_capacity(room))
        }
    }

    fn insert(&mut self, p: Point<D>, data: DiamondData) {
        match self {
            DataTable::Packed(t) => t.insert(pack_point(&p, Self::BITS), data),
            DataTable::Wide(t) => t.insert(p, data),
        };
    }

    #[inline]
    fn get(&self, p: &Point<D>) -> Option<DiamondData> {
        match self {
            DataTable::Packed(t) => t.get(&pack_point(p, Self::BITS)).copied(),
            DataTable::Wide(t) => t.get(p).copied(),
        }
    }

    #[inline]
    fn prefetch(&self, p: &Point<D>) {
        match self {
            DataTable::Packed(t) => t.prefetch(&pack_point(p, Self::BITS)),
            DataTable::Wide(t) => t.prefetch(p),
        }
    }

    fn len(&self) -> usize {
        match self {
            DataTable::Packed(t) => t.len(),
            DataTable::Wide(t) => t.len(),
        }
    }

    fn capacity(&self) -> usize {
        match self {
            DataTable::Packed(t) => t.capacity(),
            DataTable::Wide(t) => t.capacity(),
        }
    }
}

impl<const D: usize> DiamondDmv<D> {
    /// `n_p`.
    pub fn len(&self) -> usize {
        self.map.len()
    }
    /// True when no diamond is held.
    pub fn is_empty(&self) -> bool {
        self.map.len() == 0
    }
    /// The hash table's buckets (for the load factor).
    pub fn capacity(&self) -> usize {
        self.map.capacity()
    }
}

impl<const D: usize> DmvAccess<D> for DiamondDmv<D> {
    fn hierarchy(&self) -> Hierarchy<D> {
        self.hier
    }
    #[inline]
    fn data(&self, dia: &Diamond<D>) -> Option<DiamondData> {
        self.map.get(&dia.center())
    }
    #[inline]
    fn prefetch(&self, dia: &Diamond<D>) {
        self.map.prefetch(&dia.center());
    }
    fn value(&self, p: &Point<D>) -> Option<f64> {
        match corner_index(p, self.hier.side()) {
            Some(j) => self.corners.get(j).copied(),
            None => self.map.get(p).map(|d| d.value),
        }
    }
}

/// The number of 64-bit words of a supercube's internal map: `⌈(4^d − 2^d) / 64⌉`.
pub const fn flag_words(d: usize) -> usize {
    ((1usize << (2 * d)) - (1usize << d)).div_ceil(64)
}

/// The supercube-based partial DMV `Δs` (Sections 5.2–5.3): per scale, a hash from supercube
/// origin to the supercube's number; per supercube, `4^d − 2^d` bit flags (the internal map)
/// and the start of its packed data, indexed by the prefix popcount of the flags.
#[derive(Clone, Debug)]
pub struct SupercubeDmv<const D: usize> {
    pub(crate) hier: Hierarchy<D>,
    /// The original volume's sides (before padding).
    pub(crate) real: [usize; D],
    pub(crate) corners: Vec<f64>,
    /// Per scale `γ`: origin → the supercube's number, first datum and first flag word.
    pub(crate) levels: Vec<PointMap<CubeRef, D>>,
    /// Per supercube: its scale and origin (in file order).
    pub(crate) keys: Vec<(u32, Point<D>)>,
    /// `flag_words(d)` words per supercube.
    pub(crate) flags: Vec<u64>,
    /// Per supercube: the index of its first datum.
    pub(crate) start: Vec<u32>,
    /// Packed data, supercube after supercube, each in type order.
    pub(crate) data: Vec<DiamondData>,
}

/// A supercube as its origin's hash entry holds it: one look-up gives the flags of the first 64
/// types (all of them in 2-D and 3-D) and where its data start.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct CubeRef {
    /// The internal map's first word.
    flags0: u64,
    /// The supercube's number (file order).
    number: u32,
    /// The index of its first datum.
    start: u32,
}

impl<const D: usize> SupercubeDmv<D> {
    /// An empty `Δs`, to be filled by [`SupercubeDmv::push_cube`] in (scale, origin) order.
    pub(crate) fn empty(
        hier: Hierarchy<D>,
        real: [usize; D],
        corners: Vec<f64>,
    ) -> SupercubeDmv<D> {
        SupercubeDmv {
            hier,
            real,
            corners,
            levels: vec![PointMap::default(); hier.levels() as usize],
            keys: Vec::new(),
            flags: Vec::new(),
            start: Vec::new(),
            data: Vec::new(),
        }
    }

    /// Appends a supercube after every one already held, with its `(type index, data)` pairs
    /// in increasing type order.
    pub(crate) fn push_cube(
        &mut self,
        scale: u32,
        origin: Point<D>,
        items: &[(usize, DiamondData)],
    ) {
        let w = flag_words(D);
        let number = self.keys.len() as u32;
        let start = self.data.len() as u32;
        self.keys.push((scale, origin));
        self.start.push(start);
        let base = self.flags.len();
        self.flags.extend(std::iter::repeat_n(0, w));
        for &(t, d) in items {
            self.flags[base + t / 64] |= 1 << (t % 64);
            self.data.push(d);
        }
        let cube = CubeRef {
            flags0: self.flags[base],
            number,
            start,
        };
        self.levels[scale as usize].insert(origin, cube);
    }

    /// `n_s`: the number of supercubes.
    pub fn supercubes(&self) -> usize {
        self.keys.len()
    }

    /// `n_p`: the number of diamonds.
    pub fn len(&self) -> usize {
        self.data.len()
    }

    /// True when no diamond is held.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    /// The hash tables' buckets, all scales together.
    pub fn capacity(&self) -> usize {
        self.levels.iter().map(|m| m.capacity()).sum()
    }

    /// The original volume's sides (before padding).
    pub fn real_dims(&self) -> [usize; D] {
        self.real
    }

    /// The position of `dia`'s datum in the packed array, if held: scale → origin → prefix
    /// popcount of the flags below its type (Section 5.3's three steps).
    #[inline(always)]
    fn slot(&self, dia: &Diamond<D>) -> Option<usize> {
        let cube = *self
            .levels
            .get(dia.scale() as usize)?
            .get(&dia.supercube_origin())?;
        let t = dia.diamond_type().index();
        if t < 64 {
            // The common case, and every case in 2-D and 3-D: the first word is in the entry.
            if cube.flags0 >> t & 1 == 0 {
                return None;
            }
            let below = (cube.flags0 & ((1u64 << t) - 1)).count_ones();
            return Some(cube.start as usize + below as usize);
        }
        let w = flag_words(D);
        let n = cube.number as usize;
        let words = &self.flags[n * w..(n + 1) * w];
        if words[t / 64] >> (t % 64) & 1 == 0 {
            return None;
        }
        let below: u32 = words[..t / 64].iter().map(|x| x.count_ones()).sum::<u32>()
            + (words[t / 64] & ((1u64 << (t % 64)) - 1)).count_ones();
        Some(cube.start as usize + below as usize)
    }
}

impl<const D: usize> DmvAccess<D> for SupercubeDmv<D> {
    fn hierarchy(&self) -> Hierarchy<D> {
        self.hier
    }
    #[inline(always)]
    fn data(&self, dia: &Diamond<D>) -> Option<DiamondData> {
        self.slot(dia).map(|i| self.data[i])
    }
    #[inline]
    fn prefetch(&self, dia: &Diamond<D>) {
        if let Some(level) = self.levels.get(dia.scale() as usize) {
            level.prefetch(&dia.supercube_origin());
        }
    }
    fn value(&self, p: &Point<D>) -> Option<f64> {
        match corner_index(p, self.hier.side()) {
            Some(j) => self.corners.get(j).copied(),
            None => {
                let dia = self.hier.diamond(*p).ok()?;
                self.slot(&dia).map(|i| self.data[i].value)
            }
        }
    }
}

/// Table 1's storage model, in bytes.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct StorageSizes {
    /// `n_f · b_δ`.
    pub full: u64,
    /// `n_p · (b_δ + b_v)`.
    pub diamond: u64,
    /// `n_p · b_δ + n_s · b_σ`.
    pub supercube: u64,
    /// `n_p · b_δ`.
    pub ideal: u64,
}

/// Table 1 for `n_f`, `n_p`, `n_s` with `b_δ` bytes per diamond, `b_v` per central vertex and
/// `b_σ` per supercube.
pub fn storage(nf: u64, np: u64, ns: u64, b_delta: u64, b_v: u64, b_sigma: u64) -> StorageSizes {
    StorageSizes {
        full: nf * b_delta,
        diamond: np * (b_delta + b_v),
        supercube: np * b_delta + ns * b_sigma,
        ideal: np * b_delta,
    }
}

/// geocert's byte counts for a `d`-D grid of side `2^N`: `(b_v, b_σ)` — a central vertex in
/// `d` coordinates of `⌈(N+1)/8⌉` bytes; a supercube: its origin, `⌈(4^d − 2^d)/8⌉` flag
/// bytes and a 4-byte data offset (17 bytes in 3-D with 16-bit coordinates, as in the paper).
pub fn index_bytes(d: usize, levels: u32) -> (u64, u64) {
    let coord = u64::from(levels + 1).div_ceil(8);
    let bv = d as u64 * coord;
    let flags = ((1u64 << (2 * d)) - (1u64 << d)).div_ceil(8);
    (bv, bv + flags + 4)
}

/// What a partial DMV holds and costs (Tables 1–3).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct DmvSummary {
    /// `n_p`: diamonds kept.
    pub diamonds: usize,
    /// `n_s`: supercubes holding them.
    pub supercubes: usize,
    /// `n_f`: grid points of the padded grid.
    pub grid_points: usize,
    /// Samples of the original volume.
    pub real_samples: usize,
    /// `ρ = n_p / n_f`, both counted over the original (unpadded) samples only.
    pub density: f64,
    /// `κ = n_p / n_s`.
    pub concentration: f64,
    /// Table 1's sizes with geocert's byte counts.
    pub bytes: StorageSizes,
    /// `b_δ`, `b_v`, `b_σ`.
    pub bytes_per: [u64; 3],
}

impl<const D: usize> FullDmv<D> {
    /// The summary of `sel` encoded as `ds`; `value_bytes` is 4 when values are stored as
    /// `f32`, 8 for `f64` (`b_δ` adds the error and the range, 12 bytes).
    pub fn summary(
        &self,
        sel: &Selection<D>,
        ds: &SupercubeDmv<D>,
        value_bytes: u64,
    ) -> DmvSummary {
        let real_kept = sel
            .indices()
            .filter(|&i| self.field.is_real(&self.field.point(i)))
            .count();
        let real = self.field.real_count();
        let b_delta = value_bytes + 12;
        let (b_v, b_sigma) = index_bytes(D, self.field.hierarchy().levels());
        let np = sel.count();
        DmvSummary {
            diamonds: np,
            supercubes: ds.supercubes(),
            grid_points: self.len(),
            real_samples: real,
            density: real_kept as f64 / real as f64,
            concentration: np as f64 / ds.supercubes().max(1) as f64,
            bytes: storage(
                self.len() as u64,
                np as u64,
                ds.supercubes() as u64,
                b_delta,
                b_v,
                b_sigma,
            ),
            bytes_per: [b_delta, b_v, b_sigma],
        }
    }
}

impl<const D: usize> DiamondDmv<D> {
    /// `Δd` holding the same diamonds as `ds`.
    pub fn from_supercubes(ds: &SupercubeDmv<D>) -> DiamondDmv<D> {
        let types: Vec<super::DiamondType<D>> = super::DiamondType::all().collect();
        let w = flag_words(D);
        let mut map = DataTable::new(ds.hier.side(), ds.len());
        for (n, &(scale, origin)) in ds.keys.iter().enumerate() {
            let cube = super::Supercube { origin, scale };
            let mut next = ds.start[n] as usize;
            for (t, tau) in types.iter().enumerate() {
                if ds.flags[n * w + t / 64] >> (t % 64) & 1 == 1 {
                    let dia = cube
                        .diamond(&ds.hier, *tau)
                        .expect("a Δs holds diamonds of its grid");
                    map.insert(dia.center(), ds.data[next]);
                    next += 1;
                }
            }
        }
        DiamondDmv {
            hier: ds.hier,
            map,
            corners: ds.corners.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `Δd`'s packed table (one-word keys) and its wide fallback hold the same data, at the
    /// largest coordinates that pack.
    #[test]
    fn packed_and_wide_data_tables_agree() {
        let bits = DataTable::<3>::BITS;
        let side = (1u32 << bits) - 1;
        assert!(matches!(DataTable::<3>::new(side, 0), DataTable::Packed(_)));
        assert!(matches!(
            DataTable::<3>::new(side + 1, 0),
            DataTable::Wide(_)
        ));
        let mut packed = DataTable::<3>::Packed(HashTable::default());
        let mut wide = DataTable::<3>::Wide(HashTable::default());
        let mut x = 0x2545_f491_4f6c_dd1du64;
        let mut points = Vec::new();
        for i in 0..20_000u32 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            // Coordinates near 0 and near the top of the packed range.
            let p: Point<3> = std::array::from_fn(|k| {
                let c = (x >> (16 * k)) as u32 & 0xff;
                if x >> (60 - k) & 1 == 1 {
                    side - c
                } else {
                    c
                }
            });
            let data = DiamondData {
                value: f64::from(i),
                error: i as f32,
                min: -(i as f32),
                max: 2.0 * i as f32,
            };
            packed.insert(p, data);
            wide.insert(p, data);
            points.push(p);
        }
        assert_eq!(packed.len(), wide.len());
        for p in &points {
            assert_eq!(packed.get(p), wide.get(p));
            assert!(packed.get(p).is_some());
            let q = [p[0], p[1], p[2] ^ 1];
            assert_eq!(packed.get(&q), wide.get(&q));
        }
    }
}
