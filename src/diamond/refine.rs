//! Selective refinement (Section 7): top-down from the base diamond or incrementally from an
//! existing front, for a level-of-detail criterion; the current mesh, an exact conformity
//! check, and marching tetrahedra on the current mesh.

use super::front::{absent_parent_flags, full_flags, Front};
use super::{Diamond, DiamondData, DmvAccess, Hierarchy, Point, PointMap, Simplex};
use crate::mesh::Mesh;
use num_bigint::BigUint;
use std::collections::HashMap;

/// A level-of-detail criterion: a diamond is refined when every condition given holds (the
/// paper's Table 4 query is `error > e` and an isovalue in the range).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Lod<const D: usize> {
    /// Refine when `ε(δ) > e`.
    pub error: Option<f64>,
    /// Refine when δ's range holds one of these.
    pub isovalues: Vec<f64>,
    /// Refine when δ's bounding box meets this box `[lo, hi]` (grid coordinates).
    pub roi: Option<([f64; D], [f64; D])>,
}

impl<const D: usize> Lod<D> {
    /// True when `dia` with `data` is to be refined.
    pub fn wants(&self, dia: &Diamond<D>, data: &DiamondData) -> bool {
        if let Some(e) = self.error {
            if f64::from(data.error) <= e {
                return false;
            }
        }
        if !self.isovalues.is_empty()
            && !self
                .isovalues
                .iter()
                .any(|&k| f64::from(data.min) <= k && k <= f64::from(data.max))
        {
            return false;
        }
        if let Some((lo, hi)) = &self.roi {
            let c = dia.center();
            let h = f64::from(dia.half_width());
            if (0..D).any(|k| f64::from(c[k]) + h < lo[k] || f64::from(c[k]) - h > hi[k]) {
                return false;
            }
        }
        true
    }
}

/// Why refinement stopped short.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum RefineError {
    /// A diamond had to be refined (a descendant needs it) but the DMV does not hold it: the
    /// partial DMV is not closed under ancestors.
    #[error("diamond {center:?} must be refined but the DMV does not hold it (not closed under ancestors)")]
    Missing {
        /// Its central vertex.
        center: Vec<u64>,
    },
}

/// Selective refinement on a DMV with a front.
///
/// The front lives on the grid of doubled coordinates (`N + 1` levels): subdividing a diamond of
/// scale 0 whose spine is a grid edge inserts its central vertex and leaves the Kuhn simplices
/// of the unit cubes, which belong to diamonds of scale −1 (centres at half-integers). Doubled,
/// those are the scale-0 diamonds, never subdivided; every other diamond is `2·v_c` of a DMV
/// diamond. [`Refiner::mesh`] returns the simplices in the DMV's coordinates.
pub struct Refiner<'a, const D: usize, A: DmvAccess<D>, F: Front<D>> {
    dmv: &'a A,
    /// The doubled grid's hierarchy.
    hier: Hierarchy<D>,
    /// The active front.
    pub front: F,
    /// Diamonds examined (the paper's "diamonds visited").
    pub visited: u64,
    /// Wanted diamonds waiting to be refined (depth first).
    queue: Vec<Diamond<D>>,
}

impl<'a, const D: usize, A: DmvAccess<D>, F: Front<D>> Refiner<'a, D, A, F> {
    /// The front of the base mesh: the root diamond with all its simplices.
    ///
    /// # Panics
    /// When the DMV's `N` is [`crate::diamond::MAX_LEVELS`] (the doubled grid would not fit
    /// `u32`); fields and `.dmv` files never have such an `N`.
    pub fn new(dmv: &'a A) -> Self {
        let hier =
            Hierarchy::new(dmv.hierarchy().levels() + 1).expect("a DMV's N is below MAX_LEVELS");
        let mut front = F::empty(hier);
        let root = hier.root();
        front.set_flags(&root, full_flags(&root));
        Refiner {
            dmv,
            hier,
            front,
            visited: 0,
            queue: Vec::new(),
        }
    }

    /// The DMV's diamond and data for the doubled-grid diamond `dia`, when `dia` can be
    /// subdivided at all (not a unit cube's, and held by the DMV).
    #[inline]
    fn refinable(&self, dia: &Diamond<D>) -> Option<(Diamond<D>, DiamondData)> {
        if dia.scale() == 0 {
            return None;
        }
        let orig = self.original(dia);
        self.dmv.data(&orig).map(|d| (orig, d))
    }

    /// The DMV's diamond for a doubled-grid diamond of scale at least 1 (centre `2·v_c`).
    #[inline]
    fn original(&self, dia: &Diamond<D>) -> Diamond<D> {
        // A doubled-grid centre of scale ≥ 1 is even and no domain corner, so half of it is
        // a central vertex of the DMV's grid.
        let orig = dia.halved();
        debug_assert_eq!(
            orig,
            self.dmv
                .hierarchy()
                .diamond_unchecked(dia.center().map(|x| x / 2))
        );
        orig
    }

    /// Examines `dia` (counted as visited) and queues it when the criterion wants it.
    #[inline]
    fn examine(&mut self, dia: Diamond<D>, lod: &Lod<D>) {
        self.visited += 1;
        if self
            .refinable(&dia)
            .is_some_and(|(orig, data)| lod.wants(&orig, &data))
        {
            self.queue.push(dia);
        }
    }

    /// Refines every front diamond the criterion wants, and the ones their refinement needs,
    /// until no front diamond is wanted (top-down when called on a fresh refiner).
    ///
    /// Every diamond is examined once when it enters the front (or, for the starting front,
    /// here): only wanted diamonds are queued. A queued diamond no longer in the front when it
    /// is taken (subdivided meanwhile, as a parent of another) is skipped. The refined set is
    /// the same in any order: a diamond is refined exactly when it, or a descendant that
    /// enters the front, is wanted.
    pub fn refine(&mut self, lod: &Lod<D>) -> Result<(), RefineError> {
        let mut start = Vec::new();
        self.front.for_each(|d, _| start.push(d));
        for d in start {
            self.examine(d, lod);
        }
        while let Some(dia) = self.queue.pop() {
            // The next diamond's slot loads while this one is refined.
            if let Some(next) = self.queue.last() {
                self.front.prefetch(next);
            }
            let flags = self.front.flags(&dia);
            if flags != 0 {
                self.force(&dia, true, flags, lod)?;
            }
        }
        Ok(())
    }

    /// Refines `dia`, whose front flags are `flags` (`0` when it is not in the front), after
    /// refining, recursively, every parent not yet refined.
    fn force(
        &mut self,
        dia: &Diamond<D>,
        held: bool,
        mut flags: u32,
        lod: &Lod<D>,
    ) -> Result<(), RefineError> {
        if flags == 0 {
            flags = absent_parent_flags(dia);
        }
        // The parents still to refine are scattered in the front: load them all at once.
        let mut parents = [*dia; 2 * super::MAX_DIM];
        let mut n = 0;
        for slot in 0..dia.parent_slots() {
            if flags >> slot & 1 == 0 {
                let parent = dia
                    .parent_in_slot(slot)
                    .expect("slots without a parent are always set");
                self.front.prefetch(&parent);
                parents[n] = parent;
                n += 1;
            }
        }
        for parent in &parents[..n] {
            self.visited += 1;
            let parent_flags = self.front.flags(parent);
            self.force(parent, false, parent_flags, lod)?;
        }
        if !held && self.refinable(dia).is_none() {
            return Err(RefineError::Missing {
                center: dia.center().iter().map(|&x| u64::from(x)).collect(),
            });
        }
        self.split(dia, lod);
        Ok(())
    }

    /// Subdivides `dia` (all its parents refined): it leaves the front, and each child gains
    /// the simplices `dia` contributes and is examined.
    fn split(&mut self, dia: &Diamond<D>, lod: &Lod<D>) {
        self.front.set_flags(dia, 0);
        // The children's front slots and DMV data are scattered in memory: start loading them
        // all before the first is needed.
        let mut children = [(*dia, 0); 1 << super::MAX_DIM];
        let mut n = 0;
        dia.for_each_child_slot(|child, slot| {
            self.front.prefetch(&child);
            if child.scale() > 0 {
                self.dmv.prefetch(&self.original(&child));
            }
            debug_assert_eq!(child.slot_of_parent(dia), Some(slot));
            children[n] = (child, slot);
            n += 1;
        });
        for &(child, slot) in &children[..n] {
            self.front
                .add_flags(&child, || absent_parent_flags(&child), 1 << slot);
            self.examine(child, lod);
        }
    }

    /// Undoes the subdivision of `dia`, whose children are all in the front and unrefined.
    fn merge(&mut self, dia: &Diamond<D>) {
        for c in dia.children().iter() {
            let child = self.hier.diamond(*c).expect("children are diamonds");
            let slot = slot_of_parent(&child, dia);
            let flags = self.front.flags(&child) & !(1 << slot);
            let left = if flags == absent_parent_flags(&child) {
                0
            } else {
                flags
            };
            self.front.set_flags(&child, left);
        }
        self.front.set_flags(dia, full_flags(dia));
    }

    /// Moves the front to a new criterion incrementally, coarsening and refining; the result is
    /// exactly the top-down front of `lod`, whatever the criteria (a moving region of interest,
    /// a raised or lowered threshold, other isovalues).
    ///
    /// Top-down refinement yields the least set `R` of refined diamonds with: the root in `R`
    /// when wanted; a wanted child of a member in `R`; the parents of a member in `R`. The
    /// refined set `R₀` of the current front is closed under parents, so the same rules run
    /// on `R₀` alone (top-down from the root, never leaving `R₀`) give the part `S ⊆ R₀` that
    /// `R` keeps: `S ⊆ R`, and refining from `S` gives `R`. Every diamond of `R₀ ∖ S` is
    /// merged, children before parents; then the front is refined. The work is proportional
    /// to `|R₀|` plus the refinement's.
    pub fn update(&mut self, lod: &Lod<D>) -> Result<(), RefineError> {
        // R₀: every parent named by a set flag is refined, and so are its parents.
        let mut refined: PointMap<bool, D> = PointMap::default();
        let mut stack: Vec<Diamond<D>> = Vec::new();
        self.front.for_each(|d, flags| {
            for slot in 0..d.parent_slots() {
                if flags >> slot & 1 == 1 {
                    stack.extend(d.parent_in_slot(slot));
                }
            }
        });
        while let Some(p) = stack.pop() {
            if refined.insert(p.center(), false).is_none() {
                for slot in 0..p.parent_slots() {
                    stack.extend(p.parent_in_slot(slot));
                }
            }
        }
        // S: top-down inside R₀ (the value `true` marks a member of S).
        let root = self.hier.root();
        if refined.get(&root.center()).is_some() && self.wanted(&root, lod) {
            stack.push(root);
        }
        while let Some(x) = stack.pop() {
            self.keep(x, lod, &mut refined, &mut stack);
        }
        // Merge R₀ ∖ S, children first: finer scales first, and within a scale the classes
        // from d − 1 down (a class-i diamond's parents are class i − 1 at its scale, a class-0
        // diamond's are class d − 1 one scale up).
        let mut dropped: Vec<Diamond<D>> = refined
            .iter()
            .filter(|(_, &kept)| !kept)
            .map(|(c, _)| self.hier.diamond_unchecked(*c))
            .collect();
        dropped.sort_unstable_by_key(|d| (d.scale(), D - d.class(), d.center()));
        for d in &dropped {
            self.merge(d);
        }
        self.refine(lod)
    }

    /// True when the criterion wants `dia` (counted as visited).
    fn wanted(&mut self, dia: &Diamond<D>, lod: &Lod<D>) -> bool {
        self.visited += 1;
        self.refinable(dia)
            .is_some_and(|(orig, data)| lod.wants(&orig, &data))
    }

    /// Adds `x` (a member of `R₀`) and its parents to `S`, and queues its wanted children in
    /// `R₀` — [`Refiner::update`]'s top-down pass.
    fn keep(
        &mut self,
        x: Diamond<D>,
        lod: &Lod<D>,
        refined: &mut PointMap<bool, D>,
        queue: &mut Vec<Diamond<D>>,
    ) {
        if refined.get(&x.center()) != Some(&false) {
            return;
        }
        for slot in 0..x.parent_slots() {
            if let Some(p) = x.parent_in_slot(slot) {
                // R₀ is closed under parents, so `p` is in it.
                self.keep(p, lod, refined, queue);
            }
        }
        refined.insert(x.center(), true);
        for &c in x.children().iter() {
            let child = self.hier.diamond_unchecked(c);
            if refined.get(&c) == Some(&false) && self.wanted(&child, lod) {
                queue.push(child);
            }
        }
    }

    /// The simplices of the current mesh, in the DMV's grid coordinates.
    pub fn mesh(&self) -> Vec<Simplex<D>> {
        let mut out = Vec::new();
        self.front
            .for_each(|d, flags| push_simplices(&d, flags, &mut out));
        out
    }

    /// The simplices of the current mesh that the isosurface at `iso` can cross, in the DMV's
    /// grid coordinates: those of the front diamonds whose value range holds `iso` (a simplex's
    /// vertices are samples of its diamond's domain, so outside the range none of them
    /// straddles `iso`), and the unit cubes' simplices, which carry no range. Marching
    /// tetrahedra on these gives the same surface as on [`Refiner::mesh`].
    pub fn mesh_near(&self, iso: f64) -> Vec<Simplex<D>> {
        let mut out = Vec::new();
        self.front.for_each(|d, flags| {
            let holds = d.scale() == 0
                || self
                    .refinable(&d)
                    .is_none_or(|(_, r)| f64::from(r.min) <= iso && iso <= f64::from(r.max));
            if holds {
                push_simplices(&d, flags, &mut out);
            }
        });
        out
    }
}

/// The simplices of the doubled-grid front diamond `d` whose parent flag is set, halved to the
/// DMV's grid.
fn push_simplices<const D: usize>(d: &Diamond<D>, flags: u32, out: &mut Vec<Simplex<D>>) {
    d.for_each_simplex(|s, slot| {
        if flags >> slot & 1 == 1 {
            let mut v = [[0u32; D]; super::MAX_DIM + 1];
            for (w, p) in v.iter_mut().zip(s.vertices()) {
                *w = p.map(|x| x / 2);
            }
            out.push(Simplex::new(&v[..=D]).expect("d + 1 vertices"));
        }
    })
}

/// The slot of `child` whose parent is `parent`.
#[inline]
fn slot_of_parent<const D: usize>(child: &Diamond<D>, parent: &Diamond<D>) -> usize {
    let slot = child.slot_of_parent_unchecked(parent);
    debug_assert_eq!(slot, child.slot_of_parent(parent));
    slot.expect("a child names its parent in one slot")
}

/// The simplices of a front's current mesh: each front diamond's simplices whose parent flag
/// is set.
pub fn current_mesh<const D: usize, F: Front<D>>(front: &F) -> Vec<Simplex<D>> {
    let mut out = Vec::new();
    front.for_each(|d, flags| {
        d.for_each_simplex(|s, slot| {
            if flags >> slot & 1 == 1 {
                out.push(s);
            }
        })
    });
    out
}

/// The exact conformity certificate of a simplicial mesh of the domain.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Conformity {
    /// Simplices checked.
    pub simplices: usize,
    /// `(d−1)`-faces shared by exactly two simplices.
    pub interior_faces: usize,
    /// `(d−1)`-faces on the domain boundary, in exactly one simplex.
    pub boundary_faces: usize,
    /// Faces in one simplex but not on the boundary, or in more than two (the first few).
    pub bad_faces: Vec<Vec<Vec<u32>>>,
    /// Their number.
    pub bad_face_count: usize,
    /// `Σ d!·vol(simplex)`, exactly, as a decimal string.
    pub volume_sum: String,
    /// `d!·(2^N)^d`, the domain's.
    pub domain_volume: String,
    /// Every face matched and the volumes sum to the domain's.
    pub conforming: bool,
}

/// Checks exactly that `simplices` form a conforming mesh of `[0, 2^N]^d`: every `(d−1)`-face is
/// shared by exactly two simplices or lies on the domain boundary in exactly one, and the
/// simplices' volumes sum to the domain's (no overlap, no gap).
pub fn check_conforming<const D: usize>(
    hier: &Hierarchy<D>,
    simplices: &[Simplex<D>],
) -> Conformity {
    let side = hier.side();
    // Face multiplicities: packed sorted keys when D² coordinates fit a u128, else a map.
    let counts = match FaceCodec::<D>::new(side) {
        Some(codec) => codec.face_counts(simplices),
        None => face_counts_hashed(simplices),
    };
    let mut volume = BigUint::from(0u8);
    let mut small: u128 = 0;
    for s in simplices {
        match s.scaled_volume_u128().and_then(|x| small.checked_add(x)) {
            Some(sum) => small = sum,
            None => {
                volume += BigUint::from(small) + s.scaled_volume();
                small = 0;
            }
        }
    }
    volume += BigUint::from(small);
    let on_boundary = |f: &[Point<D>]| {
        (0..D).any(|k| {
            let x = f[0][k];
            (x == 0 || x == side) && f.iter().all(|p| p[k] == x)
        })
    };
    let (mut interior, mut boundary, mut bad) = (0, 0, Vec::new());
    let mut bad_count = 0;
    for (f, n) in &counts {
        match (*n, on_boundary(f)) {
            (2, false) => interior += 1,
            (1, true) => boundary += 1,
            _ => {
                bad_count += 1;
                if bad.len() < 5 {
                    bad.push(f.iter().map(|p| p.to_vec()).collect());
                }
            }
        }
    }
    let factorial: u64 = (1..=D as u64).product();
    let domain = BigUint::from(factorial) * BigUint::from(side).pow(D as u32);
    Conformity {
        simplices: simplices.len(),
        interior_faces: interior,
        boundary_faces: boundary,
        bad_faces: bad,
        bad_face_count: bad_count,
        conforming: bad_count == 0 && volume == domain,
        volume_sum: volume.to_string(),
        domain_volume: domain.to_string(),
    }
}

/// Each distinct `(d−1)`-face (its `d` vertices, sorted) with the number of simplices using it.
type FaceCounts<const D: usize> = Vec<([Point<D>; D], u32)>;

/// [`check_conforming`]'s face count through a hash map keyed by the sorted vertices.
fn face_counts_hashed<const D: usize>(simplices: &[Simplex<D>]) -> FaceCounts<D> {
    let mut faces: HashMap<[Point<D>; D], u32, std::hash::BuildHasherDefault<super::PointHasher>> =
        HashMap::default();
    faces.reserve(simplices.len() * 2);
    for s in simplices {
        let v = s.sorted();
        let v = v.vertices();
        for skip in 0..=D {
            let face: [Point<D>; D] = std::array::from_fn(|j| v[if j < skip { j } else { j + 1 }]);
            *faces.entry(face).or_insert(0) += 1;
        }
    }
    faces.into_iter().collect()
}

/// Grid points packed into `bits`-bit fields, and faces into one `u128` of `d` packed points:
/// the lossless key [`check_conforming`] sorts when `d²·bits ≤ 128` (in 3-D, `2^N < 2^14`).
struct FaceCodec<const D: usize> {
    bits: u32,
}

impl<const D: usize> FaceCodec<D> {
    /// The codec for coordinates in `0..=side`, when a face fits a `u128`.
    fn new(side: u32) -> Option<Self> {
        let bits = u32::BITS - side.leading_zeros();
        ((D * D) as u32 * bits <= u128::BITS).then_some(FaceCodec { bits })
    }

    fn point(&self, p: &Point<D>) -> u128 {
        p.iter()
            .rev()
            .fold(0u128, |acc, &x| acc << self.bits | u128::from(x))
    }

    fn unpoint(&self, mut code: u128) -> Point<D> {
        let mask = (1u128 << self.bits) - 1;
        std::array::from_fn(|_| {
            let x = (code & mask) as u32;
            code >>= self.bits;
            x
        })
    }

    /// Sorts the faces' keys and counts each key's run, in `u64` keys when they fit.
    fn face_counts(&self, simplices: &[Simplex<D>]) -> FaceCounts<D> {
        if (D * D) as u32 * self.bits <= u64::BITS {
            self.face_counts_in::<u64>(simplices)
        } else {
            self.face_counts_in::<u128>(simplices)
        }
    }

    fn face_counts_in<K>(&self, simplices: &[Simplex<D>]) -> FaceCounts<D>
    where
        K: Ord + Copy + TryFrom<u128> + Into<u128>,
    {
        let width = D as u32 * self.bits;
        let mut keys: Vec<K> = Vec::with_capacity(simplices.len() * (D + 1));
        let mut codes = [0u128; super::MAX_DIM + 1];
        for s in simplices {
            let codes = &mut codes[..=D];
            for (c, p) in codes.iter_mut().zip(s.vertices()) {
                *c = self.point(p);
            }
            // Packed points order as their reversed coordinate tuples; any total order works.
            codes.sort_unstable();
            for skip in 0..=D {
                let key = codes
                    .iter()
                    .enumerate()
                    .filter(|&(j, _)| j != skip)
                    .fold(0u128, |acc, (_, &c)| acc << width | c);
                // `new` admitted only codecs whose faces fit `K`.
                keys.extend(K::try_from(key).ok());
            }
        }
        keys.sort_unstable();
        let mask = (1u128 << width) - 1;
        let mut out = Vec::with_capacity(keys.len() / 2 + 1);
        for run in keys.chunk_by(|a, b| a == b) {
            let mut key: u128 = run[0].into();
            let mut face = [[0u32; D]; D];
            for f in face.iter_mut().rev() {
                *f = self.unpoint(key & mask);
                key = key.checked_shr(width).unwrap_or(0);
            }
            out.push((face, run.len() as u32));
        }
        out
    }
}

/// An isosurface by marching tetrahedra on a 3-D current mesh, and whether it is closed.
#[derive(Clone, Debug)]
pub struct TetSurface {
    /// The triangles (grid coordinates), one vertex per cut mesh edge.
    pub mesh: Mesh,
    /// Surface edges used by one triangle that do not lie on the domain boundary, or by more
    /// than two: zero when the surface is closed away from the boundary.
    pub open_edges: usize,
}

/// Marching tetrahedra at `iso` on `tets` with the DMV's values (`F > iso` is inside). Surface
/// vertices are keyed by the cut mesh edge — by its midpoint, which in a conforming mesh no
/// other edge passes through — so neighbouring tetrahedra share them exactly, and each is
/// interpolated from the edge's lesser end, whichever tetrahedron makes it.
pub fn marching_tetrahedra<A: DmvAccess<3>>(
    dmv: &A,
    tets: &[Simplex<3>],
    iso: f64,
) -> Result<TetSurface, RefineError> {
    let side = dmv.hierarchy().side();
    // Cut edge (by the sum of its ends) → surface vertex.
    let mut ids: PointMap<u32, 3> = PointMap::default();
    let mut vertices: Vec<[f64; 3]> = Vec::new();
    // Per surface vertex: its edge's ends.
    let mut edges: Vec<[Point<3>; 2]> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    for t in tets {
        let v = t.vertices();
        let mut f = [0.0f64; 4];
        let mut inside = 0u32;
        for j in 0..4 {
            f[j] = dmv.value(&v[j]).ok_or_else(|| RefineError::Missing {
                center: v[j].iter().map(|&x| u64::from(x)).collect(),
            })?;
            if f[j] > iso {
                inside |= 1 << j;
            }
        }
        if inside == 0 || inside == 15 {
            continue;
        }
        let mut cut = |a: usize, b: usize| -> u32 {
            // From the lesser end, so that the vertex does not depend on which tetrahedron
            // makes it.
            let (a, b) = if v[a] < v[b] { (a, b) } else { (b, a) };
            let key: Point<3> = std::array::from_fn(|k| v[a][k] + v[b][k]);
            *ids.get_or_insert_with(key, || {
                let s = (iso - f[a]) / (f[b] - f[a]);
                vertices.push(std::array::from_fn(|k| {
                    f64::from(v[a][k]) + s * (f64::from(v[b][k]) - f64::from(v[a][k]))
                }));
                edges.push([v[a], v[b]]);
                (vertices.len() - 1) as u32
            })
        };
        let (mut ins, mut outs) = ([0usize; 4], [0usize; 4]);
        let (mut ni, mut no) = (0, 0);
        for j in 0..4 {
            if inside >> j & 1 == 1 {
                ins[ni] = j;
                ni += 1;
            } else {
                outs[no] = j;
                no += 1;
            }
        }
        let (ins, outs) = (&ins[..ni], &outs[..no]);
        let (polygon, n) = match ins.len() {
            1 => (
                [
                    cut(ins[0], outs[0]),
                    cut(ins[0], outs[1]),
                    cut(ins[0], outs[2]),
                    0,
                ],
                3,
            ),
            3 => (
                [
                    cut(ins[0], outs[0]),
                    cut(ins[1], outs[0]),
                    cut(ins[2], outs[0]),
                    0,
                ],
                3,
            ),
            _ => (
                [
                    cut(ins[0], outs[0]),
                    cut(ins[0], outs[1]),
                    cut(ins[1], outs[1]),
                    cut(ins[1], outs[0]),
                ],
                4,
            ),
        };
        // Orient towards decreasing F: the normal points from inside to outside. The sign is
        // taken on the cut edges' midpoints, not on the interpolated vertices: sliding the
        // vertices along the open edges never makes three of them collinear, so the two agree
        // wherever the vertices are distinct, and the midpoints (exact in `f64`) still decide
        // where a sample equal to `iso` puts two vertices at its grid point.
        let gi: [f64; 3] = centroid(v, ins);
        let go: [f64; 3] = centroid(v, outs);
        let dir = [go[0] - gi[0], go[1] - gi[1], go[2] - gi[2]];
        let mut emit = |a: u32, b: u32, c: u32| {
            let mid = |i: u32| -> [f64; 3] {
                let [p, q] = edges[i as usize];
                std::array::from_fn(|k| 0.5 * (f64::from(p[k]) + f64::from(q[k])))
            };
            let (x, y, z) = (mid(a), mid(b), mid(c));
            let n = cross(sub(y, x), sub(z, x));
            triangles.push(if n[0] * dir[0] + n[1] * dir[1] + n[2] * dir[2] >= 0.0 {
                [a, b, c]
            } else {
                [a, c, b]
            });
        };
        emit(polygon[0], polygon[1], polygon[2]);
        if n == 4 {
            emit(polygon[0], polygon[2], polygon[3]);
        }
    }
    // Closedness: every surface edge in two triangles, unless it lies in a boundary face.
    let mut edge_use: PointMap<u32, 3> = PointMap::with_capacity(triangles.len() * 3 / 2);
    for tri in &triangles {
        for j in 0..3 {
            let (a, b) = (tri[j], tri[(j + 1) % 3]);
            *edge_use.get_or_insert_with([a.min(b), a.max(b), 0], || 0) += 1;
        }
    }
    let open_edges = edge_use
        .iter()
        .filter(|&(e, &n)| {
            let [ka, kb] = [edges[e[0] as usize], edges[e[1] as usize]];
            let pts = [ka[0], ka[1], kb[0], kb[1]];
            let boundary = (0..3).any(|k| {
                let x = pts[0][k];
                (x == 0 || x == side) && pts.iter().all(|p| p[k] == x)
            });
            !(n == 2 || (n == 1 && boundary))
        })
        .count();
    Ok(TetSurface {
        mesh: Mesh {
            vertices,
            triangles,
            scalars: None,
            normals: None,
        },
        open_edges,
    })
}

fn centroid(v: &[Point<3>], which: &[usize]) -> [f64; 3] {
    let n = which.len() as f64;
    std::array::from_fn(|k| which.iter().map(|&j| f64::from(v[j][k])).sum::<f64>() / n)
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
