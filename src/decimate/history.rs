//! Undecimation (Section 2, Figs. 5–6): per removed node, the triangles removed with it and
//! the triangles added in the hole, in the triangle slots they occupy; any number of steps
//! undone in reverse order and redone. The versioned, checksummed binary history file.
//!
//! A step removing node `v` with neighbour ring `w_0 … w_{l−1}` (counter-clockwise) removed
//! the fan triangles `(v, w_i, w_{i+1})` — `l` of them around an interior node, `l − 1` at a
//! border node — each stored by its slot and the position of `v` in it (so the original
//! vertex order comes back, not only the orientation), as Fig. 6 stores two indices per
//! removed triangle. It added `l − 2` triangles, stored as ring positions, in the first
//! `l − 2` of those slots (Fig. 5: there are always fewer new triangles); the remaining
//! slots fall free.
//!
//! File layout (little-endian): `b"GCDHIST\n"`, version `u32` = 1, vertex count `u32`, slot
//! count `u32`, scalar flag `u8`, the scalar field's name (`u16` length, UTF-8), step count `u32`, the original and decimated meshes'
//! fingerprints (`u64` each); per step: node `u32`, border flag `u8`, ring length `u8`, ring
//! (`u32` each), removed slots (`u32` each), the node's position in each (`u8` each), added
//! triangles (three `u8` ring positions each), the node's coordinates (`f64` ×3) and, with
//! a scalar field, its value (`f64`); since version 2 the fit's moves ([`super::fit`]):
//! count `u32`, per move the node `u32` and its coordinates before and after (`f64` ×3
//! each); then an FNV-1a 64 checksum of everything before it. Version 1 files (no moves)
//! are read too.
//!
//! The fit is the last stage: [`Stage::decimated`] starts fitted, its first
//! [`undo`](Stage::undo) puts the moved nodes back, and [`redo`](Stage::redo) after the last
//! step moves them again.

use super::fit::Moved;
use crate::mesh::{Mesh, Scalars};
use thiserror::Error;

const MAGIC: &[u8; 8] = b"GCDHIST\n";
const VERSION: u32 = 2;

/// What is wrong with a history, or with a history against a mesh.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum HistoryError {
    #[error("history file: not a geocert decimation history (bad magic bytes)")]
    /// The file does not start with the history's magic bytes.
    BadMagic,
    #[error(
        "history file: version {0} is not supported (this build reads versions 1 to {VERSION})"
    )]
    /// The file's format version is not this build's.
    Version(u32),
    #[error("history file: truncated at byte {0}")]
    /// The file ends early, at this byte.
    Truncated(usize),
    #[error("history file: checksum mismatch (the file is corrupted)")]
    /// The checksum does not match.
    Checksum,
    #[error("history file: {0} trailing bytes after the checksum")]
    /// Bytes follow the checksum.
    Trailing(usize),
    #[error("history step {step}: {why}")]
    /// A step is inconsistent.
    Step {
        /// The step.
        step: usize,
        /// What is inconsistent.
        why: String,
    },
    #[error("the history does not belong to this mesh: {0}")]
    /// The history does not fit the mesh given (counts or fingerprint).
    Mismatch(String),
}

/// One node removal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StepRef<'a> {
    /// The removed node.
    pub node: u32,
    /// Whether it was a border node.
    pub border: bool,
    /// Its ring of neighbours in order (counter-clockwise).
    pub ring: &'a [u32],
    /// The triangle slots its fan occupied, the added triangles reuse the first `l − 2`.
    pub slots: &'a [u32],
    /// Per removed triangle, the rotation of its corners as stored.
    pub positions: &'a [u8],
    /// The added triangles, as positions in `ring`.
    pub added: &'a [[u8; 3]],
}

impl StepRef<'_> {
    /// The `i`-th removed triangle as it was stored in the mesh.
    pub fn removed_triangle(&self, i: usize) -> [u32; 3] {
        let l = self.ring.len();
        let canonical = [self.node, self.ring[i], self.ring[(i + 1) % l]];
        let p = self.positions[i] as usize;
        let mut t = [0; 3];
        for (k, &c) in canonical.iter().enumerate() {
            t[(p + k) % 3] = c;
        }
        t
    }

    /// The `i`-th added triangle.
    pub fn added_triangle(&self, i: usize) -> [u32; 3] {
        self.added[i].map(|p| self.ring[p as usize])
    }
}

/// The record of a decimation: every step, and the removed nodes' data.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct History {
    /// Vertices of the original mesh.
    pub vertex_count: u32,
    /// Triangle slots (the original's triangle count).
    pub slot_count: u32,
    /// Whether the mesh carries a scalar field.
    pub has_scalars: bool,
    /// The scalar field's name (empty without one).
    pub scalar_name: String,
    /// Fingerprint of the original mesh (vertices, scalars, triangles in order).
    pub original_fingerprint: u64,
    /// Fingerprint of the decimated mesh.
    pub decimated_fingerprint: u64,
    /// The fit's moves after the last step, in node order ([`super::fit`]; empty when the
    /// kept nodes stay where they were).
    pub fit: Vec<Moved>,
    nodes: Vec<u32>,
    border: Vec<bool>,
    /// Step `s` owns `rings[ring_start[s]..ring_start[s+1]]`; its slots and positions use the
    /// same start (a border step leaves one entry unused), its added triangles start at
    /// `ring_start[s] − 2s`.
    ring_start: Vec<u32>,
    rings: Vec<u32>,
    slots: Vec<u32>,
    positions: Vec<u8>,
    added: Vec<[u8; 3]>,
    coordinates: Vec<[f64; 3]>,
    values: Vec<f64>,
}

impl History {
    /// An empty history for a mesh with these counts.
    pub fn new(vertex_count: usize, slot_count: usize, has_scalars: bool) -> History {
        History {
            vertex_count: vertex_count as u32,
            slot_count: slot_count as u32,
            has_scalars,
            ring_start: vec![0],
            ..History::default()
        }
    }

    /// Reserves room for `steps` more steps of about `valence` ring nodes each (on huge
    /// pages when large), so that a long decimation does not copy its history as it grows.
    pub fn reserve(&mut self, steps: usize, valence: usize) {
        use crate::memory::{advise_huge_pages, prefault};
        let entries = steps * valence;
        self.nodes.reserve(steps);
        self.border.reserve(steps);
        self.ring_start.reserve(steps);
        self.coordinates.reserve(steps);
        self.rings.reserve(entries);
        self.slots.reserve(entries);
        self.positions.reserve(entries);
        self.added.reserve(entries);
        advise_huge_pages(&mut self.nodes);
        advise_huge_pages(&mut self.ring_start);
        advise_huge_pages(&mut self.coordinates);
        advise_huge_pages(&mut self.rings);
        advise_huge_pages(&mut self.slots);
        advise_huge_pages(&mut self.positions);
        advise_huge_pages(&mut self.added);
        if self.has_scalars {
            self.values.reserve(steps);
            advise_huge_pages(&mut self.values);
        }
        // Present before the loop appends (its pages cleared on all cores now, not on the
        // loop's at first touch).
        prefault(&mut self.nodes, 0);
        prefault(&mut self.ring_start, 0);
        prefault(&mut self.coordinates, [0.0; 3]);
        prefault(&mut self.rings, 0);
        prefault(&mut self.slots, Default::default());
        prefault(&mut self.positions, Default::default());
        prefault(&mut self.added, Default::default());
        prefault(&mut self.values, 0.0);
    }

    /// The number of steps.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// True when nothing was removed.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Step `s`.
    pub fn step(&self, s: usize) -> StepRef<'_> {
        let (a, b) = (self.ring_start[s] as usize, self.ring_start[s + 1] as usize);
        let old = b - a - self.border[s] as usize;
        let added_start = a - 2 * s;
        StepRef {
            node: self.nodes[s],
            border: self.border[s],
            ring: &self.rings[a..b],
            slots: &self.slots[a..a + old],
            positions: &self.positions[a..a + old],
            added: &self.added[added_start..added_start + (b - a - 2)],
        }
    }

    /// The ring of the last step (empty when there is none).
    pub fn last_ring(&self) -> &[u32] {
        let from = self.ring_start[self.len().saturating_sub(1)] as usize;
        &self.rings[from..]
    }

    /// The removed node of step `s`: its coordinates and scalar.
    pub fn node_data(&self, s: usize) -> ([f64; 3], Option<f64>) {
        (
            self.coordinates[s],
            self.has_scalars.then(|| self.values[s]),
        )
    }

    /// Maps every coordinate the history holds (removed nodes, the fit's moves) through `f`:
    /// how a decimation run in local coordinates returns to the original frame. The
    /// fingerprints are not touched.
    pub(crate) fn map_coordinates(&mut self, f: impl Fn([f64; 3]) -> [f64; 3]) {
        for c in &mut self.coordinates {
            *c = f(*c);
        }
        for m in &mut self.fit {
            m.from = f(m.from);
            m.to = f(m.to);
        }
    }

    /// Appends a step. `removed` gives `(slot, position)` per removed triangle (`l`, or
    /// `l − 1` at the border), `added` the `l − 2` new triangles as ring positions.
    #[allow(clippy::too_many_arguments)]
    pub fn push(
        &mut self,
        node: u32,
        border: bool,
        ring: &[u32],
        removed: impl IntoIterator<Item = (u32, u8)>,
        added: &[[u8; 3]],
        coordinates: [f64; 3],
        value: Option<f64>,
    ) {
        debug_assert_eq!(added.len(), ring.len() - 2);
        self.nodes.push(node);
        self.border.push(border);
        // Element-wise copies: these slices are a few entries long, too short for memcpy.
        self.rings.extend(ring.iter().copied());
        for (slot, position) in removed {
            self.slots.push(slot);
            self.positions.push(position);
        }
        debug_assert_eq!(
            self.slots.len(),
            self.rings.len() - border as usize,
            "one removed triangle per ring node, less one at the border"
        );
        if border {
            self.slots.push(u32::MAX);
            self.positions.push(0);
        }
        self.added.extend(added.iter().copied());
        self.ring_start.push(self.rings.len() as u32);
        self.coordinates.push(coordinates);
        if self.has_scalars {
            self.values.push(value.unwrap_or(0.0));
        }
    }

    /// Serialises to the versioned, checksummed file format.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(64 + self.rings.len() * 10 + self.len() * 40);
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&VERSION.to_le_bytes());
        out.extend_from_slice(&self.vertex_count.to_le_bytes());
        out.extend_from_slice(&self.slot_count.to_le_bytes());
        out.push(self.has_scalars as u8);
        let name = self.scalar_name.as_bytes();
        out.extend_from_slice(&(name.len().min(u16::MAX as usize) as u16).to_le_bytes());
        out.extend_from_slice(&name[..name.len().min(u16::MAX as usize)]);
        out.extend_from_slice(&(self.len() as u32).to_le_bytes());
        out.extend_from_slice(&self.original_fingerprint.to_le_bytes());
        out.extend_from_slice(&self.decimated_fingerprint.to_le_bytes());
        for s in 0..self.len() {
            let st = self.step(s);
            out.extend_from_slice(&st.node.to_le_bytes());
            out.push(st.border as u8);
            out.push(st.ring.len() as u8);
            for &w in st.ring {
                out.extend_from_slice(&w.to_le_bytes());
            }
            for &t in st.slots {
                out.extend_from_slice(&t.to_le_bytes());
            }
            out.extend_from_slice(st.positions);
            for t in st.added {
                out.extend_from_slice(t);
            }
            let (c, v) = self.node_data(s);
            for x in c {
                out.extend_from_slice(&x.to_le_bytes());
            }
            if let Some(v) = v {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
        out.extend_from_slice(&(self.fit.len() as u32).to_le_bytes());
        for m in &self.fit {
            out.extend_from_slice(&m.node.to_le_bytes());
            for x in m.from.iter().chain(&m.to) {
                out.extend_from_slice(&x.to_le_bytes());
            }
        }
        let sum = fnv1a(&out);
        out.extend_from_slice(&sum.to_le_bytes());
        out
    }

    /// Parses and checks a history file: magic, version, checksum, and every index in range.
    pub fn from_bytes(bytes: &[u8]) -> Result<History, HistoryError> {
        let mut r = Reader { bytes, at: 0 };
        if r.take(8)? != MAGIC {
            return Err(HistoryError::BadMagic);
        }
        let version = r.u32()?;
        if !(1..=VERSION).contains(&version) {
            return Err(HistoryError::Version(version));
        }
        let body = &bytes[..bytes.len() - 8];
        let stored = u64::from_le_bytes(bytes[bytes.len() - 8..].try_into().unwrap());
        let vertex_count = r.u32()?;
        let slot_count = r.u32()?;
        let has_scalars = match r.u8()? {
            0 => false,
            1 => true,
            f => {
                return Err(HistoryError::Step {
                    step: 0,
                    why: format!("scalar flag {f} is not 0 or 1"),
                })
            }
        };
        let name_len = u16::from_le_bytes([r.u8()?, r.u8()?]) as usize;
        let scalar_name =
            String::from_utf8(r.take(name_len)?.to_vec()).map_err(|_| HistoryError::Step {
                step: 0,
                why: "the scalar field's name is not UTF-8".into(),
            })?;
        let steps = r.u32()? as usize;
        let mut h = History::new(vertex_count as usize, slot_count as usize, has_scalars);
        h.scalar_name = scalar_name;
        h.original_fingerprint = r.u64()?;
        h.decimated_fingerprint = r.u64()?;
        let bad = |step: usize, why: String| HistoryError::Step { step, why };
        let (mut ring, mut slots, mut pos, mut added) = (vec![], vec![], vec![], vec![]);
        for s in 0..steps {
            let node = r.u32()?;
            let border = match r.u8()? {
                0 => false,
                1 => true,
                f => return Err(bad(s, format!("border flag {f} is not 0 or 1"))),
            };
            let l = r.u8()? as usize;
            if l < 3 {
                return Err(bad(s, format!("ring of {l} nodes (at least 3)")));
            }
            if node >= vertex_count {
                return Err(bad(s, format!("node {node} out of range")));
            }
            ring.clear();
            for _ in 0..l {
                let w = r.u32()?;
                if w >= vertex_count || w == node {
                    return Err(bad(
                        s,
                        format!("ring node {w} out of range or the node itself"),
                    ));
                }
                ring.push(w);
            }
            let old = l - border as usize;
            slots.clear();
            for _ in 0..old {
                let t = r.u32()?;
                if t >= slot_count {
                    return Err(bad(s, format!("slot {t} out of range")));
                }
                slots.push(t);
            }
            pos.clear();
            for _ in 0..old {
                let p = r.u8()?;
                if p > 2 {
                    return Err(bad(s, format!("position {p} in a triangle")));
                }
                pos.push(p);
            }
            added.clear();
            for _ in 0..l - 2 {
                let t = [r.u8()?, r.u8()?, r.u8()?];
                if t.iter().any(|&p| p as usize >= l) {
                    return Err(bad(s, format!("added triangle {t:?} outside the ring")));
                }
                added.push(t);
            }
            let c = [r.f64()?, r.f64()?, r.f64()?];
            let v = if has_scalars { Some(r.f64()?) } else { None };
            h.push(
                node,
                border,
                &ring,
                slots.iter().copied().zip(pos.iter().copied()),
                &added,
                c,
                v,
            );
        }
        if version >= 2 {
            let moves = r.u32()? as usize;
            let mut last = None;
            for k in 0..moves {
                let node = r.u32()?;
                let from = [r.f64()?, r.f64()?, r.f64()?];
                let to = [r.f64()?, r.f64()?, r.f64()?];
                let bad = |why: String| HistoryError::Step { step: steps, why };
                if node >= vertex_count || last.is_some_and(|l| l >= node) {
                    return Err(bad(format!(
                        "fit move {k}: node {node} out of range or out of order"
                    )));
                }
                if !to.iter().all(|x| x.is_finite()) {
                    return Err(bad(format!("fit move {k}: node {node} moves to {to:?}")));
                }
                last = Some(node);
                h.fit.push(Moved { node, from, to });
            }
        }
        if r.at + 8 > bytes.len() {
            return Err(HistoryError::Truncated(bytes.len()));
        }
        if r.at + 8 < bytes.len() {
            return Err(HistoryError::Trailing(bytes.len() - r.at - 8));
        }
        if fnv1a(body) != stored {
            return Err(HistoryError::Checksum);
        }
        Ok(h)
    }
}

struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], HistoryError> {
        // The last 8 bytes are the checksum, never data.
        if self.at + n > self.bytes.len().saturating_sub(8) {
            return Err(HistoryError::Truncated(self.bytes.len()));
        }
        let s = &self.bytes[self.at..self.at + n];
        self.at += n;
        Ok(s)
    }
    fn u8(&mut self) -> Result<u8, HistoryError> {
        Ok(self.take(1)?[0])
    }
    fn u32(&mut self) -> Result<u32, HistoryError> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into().unwrap()))
    }
    fn u64(&mut self) -> Result<u64, HistoryError> {
        Ok(u64::from_le_bytes(self.take(8)?.try_into().unwrap()))
    }
    fn f64(&mut self) -> Result<f64, HistoryError> {
        Ok(f64::from_le_bytes(self.take(8)?.try_into().unwrap()))
    }
}

/// FNV-1a, 64 bit.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf29ce484222325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x100000001b3);
    }
    h
}

/// A fingerprint of a mesh: its vertex coordinates' bits, triangles and scalar values' bits
/// in order (FNV-1a over their little-endian bytes).
pub fn fingerprint(mesh: &Mesh) -> u64 {
    let mut bytes = Vec::with_capacity(mesh.vertices.len() * 32 + mesh.triangles.len() * 12 + 16);
    bytes.extend_from_slice(&(mesh.vertices.len() as u64).to_le_bytes());
    for v in &mesh.vertices {
        for x in v {
            bytes.extend_from_slice(&x.to_bits().to_le_bytes());
        }
    }
    bytes.extend_from_slice(&(mesh.triangles.len() as u64).to_le_bytes());
    for t in &mesh.triangles {
        for i in t {
            bytes.extend_from_slice(&i.to_le_bytes());
        }
    }
    if let Some(s) = &mesh.scalars {
        for x in &s.values {
            bytes.extend_from_slice(&x.to_bits().to_le_bytes());
        }
    }
    fnv1a(&bytes)
}

/// A mesh at some step of its history: every vertex of the original (with a present flag)
/// and every triangle slot (with a live flag). Undo and redo move between steps.
#[derive(Clone, Debug, PartialEq)]
pub struct Stage {
    /// Every vertex of the original.
    pub vertices: Vec<[f64; 3]>,
    /// The scalar field, if any.
    pub scalars: Option<Scalars>,
    /// Every triangle slot (live or not).
    pub slots: Vec<[u32; 3]>,
    /// Which slots hold a triangle at this stage.
    pub live: Vec<bool>,
    /// Which vertices are present at this stage.
    pub present: Vec<bool>,
    /// Steps of the history applied (the original is stage 0).
    pub applied: usize,
    /// Whether the fit's moves are applied (only after the last step).
    pub fitted: bool,
}

impl Stage {
    /// The original mesh, before any step.
    pub fn original(mesh: &Mesh) -> Stage {
        Stage {
            vertices: mesh.vertices.clone(),
            scalars: mesh.scalars.clone(),
            slots: mesh.triangles.clone(),
            live: vec![true; mesh.triangles.len()],
            present: vec![true; mesh.vertices.len()],
            applied: 0,
            fitted: false,
        }
    }

    /// The stage after every step, from the decimated mesh (as [`Stage::to_mesh`] wrote it)
    /// and its history. Refused when the mesh's counts or fingerprint are not the history's.
    pub fn decimated(mesh: &Mesh, history: &History) -> Result<Stage, HistoryError> {
        let n = history.vertex_count as usize;
        let mut present = vec![true; n];
        for s in 0..history.len() {
            let v = history.step(s).node as usize;
            if !present[v] {
                return Err(HistoryError::Step {
                    step: s,
                    why: format!("node {v} removed twice"),
                });
            }
            present[v] = false;
        }
        let kept = present.iter().filter(|p| **p).count();
        if mesh.vertices.len() != kept {
            return Err(HistoryError::Mismatch(format!(
                "the mesh has {} vertices, the history leaves {kept} of {n}",
                mesh.vertices.len()
            )));
        }
        let mut live = vec![true; history.slot_count as usize];
        for s in 0..history.len() {
            let st = history.step(s);
            let l = st.ring.len();
            for &t in &st.slots[l - 2..] {
                if !live[t as usize] {
                    return Err(HistoryError::Step {
                        step: s,
                        why: format!("slot {t} freed twice"),
                    });
                }
                live[t as usize] = false;
            }
        }
        let live_count = live.iter().filter(|l| **l).count();
        if mesh.triangles.len() != live_count {
            return Err(HistoryError::Mismatch(format!(
                "the mesh has {} triangles, the history leaves {live_count}",
                mesh.triangles.len()
            )));
        }
        if mesh.scalars.is_some() != history.has_scalars {
            return Err(HistoryError::Mismatch(format!(
                "the mesh {} a scalar field, the history {}",
                if mesh.scalars.is_some() {
                    "has"
                } else {
                    "has no"
                },
                if history.has_scalars {
                    "has"
                } else {
                    "has none"
                }
            )));
        }
        if fingerprint(mesh) != history.decimated_fingerprint {
            return Err(HistoryError::Mismatch(
                "its fingerprint differs from the decimated mesh the history was made from".into(),
            ));
        }
        // Kept vertices in original order; removed ones from the history.
        let mut vertices = vec![[0.0; 3]; n];
        let mut values = vec![0.0; n];
        let mut k = 0;
        let mesh_values = mesh.scalars.as_ref().map(|s| &s.values);
        for v in 0..n {
            if present[v] {
                vertices[v] = mesh.vertices[k];
                if let Some(mv) = mesh_values {
                    values[v] = mv[k];
                }
                k += 1;
            }
        }
        let old_id: Vec<u32> = (0..n as u32).filter(|&v| present[v as usize]).collect();
        for s in 0..history.len() {
            let (c, value) = history.node_data(s);
            let v = history.step(s).node as usize;
            vertices[v] = c;
            if let Some(x) = value {
                values[v] = x;
            }
        }
        for m in &history.fit {
            let v = m.node as usize;
            if !present[v] || vertices[v] != m.to {
                return Err(HistoryError::Mismatch(format!(
                    "node {v} is not where the history's fit moved it"
                )));
            }
        }
        let mut slots = vec![[0u32; 3]; history.slot_count as usize];
        let mut next = mesh.triangles.iter();
        for (t, slot) in slots.iter_mut().enumerate() {
            if live[t] {
                let tri = next.next().expect("counted above");
                *slot = tri.map(|i| old_id[i as usize]);
            }
        }
        Ok(Stage {
            vertices,
            scalars: mesh.scalars.as_ref().map(|s| Scalars {
                name: s.name.clone(),
                values,
            }),
            slots,
            live,
            present,
            applied: history.len(),
            fitted: !history.fit.is_empty(),
        })
    }

    /// Undoes the last applied step, checking that the mesh holds what the step added; when
    /// the fit is applied, puts its moved nodes back first (one call; `applied` stays).
    pub fn undo(&mut self, history: &History) -> Result<(), HistoryError> {
        if self.fitted {
            return self.move_fitted(history, false);
        }
        if self.applied == 0 {
            return Err(HistoryError::Mismatch("nothing left to undo".into()));
        }
        let s = self.applied - 1;
        let st = history.step(s);
        let l = st.ring.len();
        let bad = |why: String| HistoryError::Step { step: s, why };
        if self.present[st.node as usize] {
            return Err(bad(format!(
                "node {} is present; cannot restore it",
                st.node
            )));
        }
        for (i, &t) in st.slots.iter().enumerate() {
            let t = t as usize;
            if i < l - 2 {
                if !self.live[t] || self.slots[t] != st.added_triangle(i) {
                    return Err(bad(format!(
                        "slot {t} does not hold the added triangle {:?}",
                        st.added_triangle(i)
                    )));
                }
            } else if self.live[t] {
                return Err(bad(format!("slot {t} is live; the step freed it")));
            }
        }
        for (i, &t) in st.slots.iter().enumerate() {
            self.slots[t as usize] = st.removed_triangle(i);
            self.live[t as usize] = true;
        }
        self.present[st.node as usize] = true;
        self.applied -= 1;
        Ok(())
    }

    /// Re-applies the next step, checking that the mesh holds what the step removed; after
    /// the last step, applies the fit's moves (one call).
    pub fn redo(&mut self, history: &History) -> Result<(), HistoryError> {
        if self.applied == history.len() && !self.fitted && !history.fit.is_empty() {
            return self.move_fitted(history, true);
        }
        if self.applied == history.len() {
            return Err(HistoryError::Mismatch("nothing left to redo".into()));
        }
        let s = self.applied;
        let st = history.step(s);
        let l = st.ring.len();
        let bad = |why: String| HistoryError::Step { step: s, why };
        if !self.present[st.node as usize] {
            return Err(bad(format!("node {} is already removed", st.node)));
        }
        for (i, &t) in st.slots.iter().enumerate() {
            let t = t as usize;
            if !self.live[t] || self.slots[t] != st.removed_triangle(i) {
                return Err(bad(format!(
                    "slot {t} does not hold the removed triangle {:?}",
                    st.removed_triangle(i)
                )));
            }
        }
        for (i, &t) in st.slots.iter().enumerate() {
            if i < l - 2 {
                self.slots[t as usize] = st.added_triangle(i);
            } else {
                self.live[t as usize] = false;
            }
        }
        self.present[st.node as usize] = false;
        self.applied += 1;
        Ok(())
    }

    /// Moves the fit's nodes `from → to` (`forward`) or back, checking each is present and
    /// where the move starts.
    fn move_fitted(&mut self, history: &History, forward: bool) -> Result<(), HistoryError> {
        if self.applied != history.len() {
            return Err(HistoryError::Mismatch(
                "the fit applies only after the last step".into(),
            ));
        }
        for m in &history.fit {
            let (at, to) = if forward {
                (m.from, m.to)
            } else {
                (m.to, m.from)
            };
            let v = m.node as usize;
            if !self.present.get(v).copied().unwrap_or(false) || self.vertices[v] != at {
                return Err(HistoryError::Step {
                    step: history.len(),
                    why: format!("fit: node {v} is not at {at:?}"),
                });
            }
            self.vertices[v] = to;
        }
        self.fitted = forward;
        Ok(())
    }

    /// The mesh at this stage: present vertices in original order, live slots in order.
    pub fn to_mesh(&self) -> Mesh {
        let mut new_id = vec![u32::MAX; self.vertices.len()];
        let mut vertices = Vec::new();
        let mut values = Vec::new();
        for (v, &p) in self.present.iter().enumerate() {
            if p {
                new_id[v] = vertices.len() as u32;
                vertices.push(self.vertices[v]);
                if let Some(s) = &self.scalars {
                    values.push(s.values[v]);
                }
            }
        }
        let triangles = self
            .slots
            .iter()
            .zip(&self.live)
            .filter(|(_, &l)| l)
            .map(|(t, _)| t.map(|i| new_id[i as usize]))
            .collect();
        Mesh {
            normals: None,
            vertices,
            triangles,
            scalars: self.scalars.as_ref().map(|s| Scalars {
                name: s.name.clone(),
                values,
            }),
        }
    }
}
