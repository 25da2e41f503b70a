//! Vertex slots for cut lattice edges on element boundaries (Section 3.2), for the fast path.
//!
//! [`edge_key`](super::lattice::edge_key) names a boundary edge by its two lattice points'
//! global names: 56 bytes, built and hashed per edge. Here the entity the edge lies in is
//! named once per element (an element face by its canonical corners, an element edge by its
//! two nodes) and gets a block of slots, one per lattice edge of the entity in the entity's
//! own canonical frame; an edge's slot is then an index into that block. Two lattice edges
//! get the same slot exactly when they get the same [`EdgeKey`]:
//! * on a face with four distinct corners, a point's key is its canonical-frame position
//!   (or, on the face's border, its element-edge or node name), so two edges of the face
//!   are equal by key exactly when they are equal in the frame; an edge whose key has a
//!   face point cannot lie on a face with other corners, and one whose two points lie on
//!   two opposite element edges of the face names four distinct nodes, so no edge of a
//!   degenerate face shares its key;
//! * on an element edge with two distinct nodes, likewise with the position from the
//!   smaller node;
//! * on an entity with a repeated node the edge keeps its [`EdgeKey`] (a plain map).

use super::lattice::{
    canonical_face, edge_key, face_corners, face_counts, face_position, free_axes, node_at, EdgeKey,
};
use crate::hashing::FastMap;

/// No vertex in a slot yet.
pub(crate) const EMPTY: u32 = u32::MAX;
/// A per-element cache entry not looked up yet.
const UNSET: u32 = u32::MAX;
/// An entity with a repeated node: its edges keep their [`EdgeKey`].
const DEGENERATE: u32 = u32::MAX - 1;

/// The name of a cut lattice edge on an element boundary, as recorded for welding ranges.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum BoundaryName {
    /// Lattice edge `index` of the face with these canonical corners.
    Face { corners: [u32; 4], index: u32 },
    /// Lattice edge `index` (counted from `ends[0]`) of the element edge `ends[0] < ends[1]`.
    Edge { ends: [u32; 2], index: u32 },
    /// An edge of an entity with a repeated node.
    Other(EdgeKey),
}

/// Where a boundary edge's vertex id is kept.
pub(crate) enum Slot {
    /// Slot `at` of the block of the current element's face `entity` (below 6) or element
    /// edge `entity − 6`.
    Dense { at: usize, entity: u8 },
    /// An edge of an entity with a repeated node.
    Other(EdgeKey),
}

/// The current element's view of one of its faces.
#[derive(Clone, Copy)]
struct FaceFrame {
    block: u32,
    corners: [u32; 4],
    start: u8,
    forward: bool,
    counts: [u32; 2],
}

/// Slots of one range of elements.
pub(crate) struct BoundarySlots {
    faces: FastMap<[u32; 4], u32>,
    edges: FastMap<[u32; 2], u32>,
    slots: Vec<u32>,
    other: FastMap<EdgeKey, u32>,
    n: [usize; 3],
    /// The current element and its nodes.
    element: usize,
    nodes: [u32; 8],
    /// Per face `2d + side`: its frame, looked up on first use in the element.
    face: [FaceFrame; 6],
    /// Per element edge `4·axis + side_u + 2·side_v`: its block start and its nodes, ordered.
    edge: [u32; 12],
    edge_ends: [[u32; 2]; 12],
}

impl BoundarySlots {
    /// Slots for lattices of `n` cells per element.
    pub(crate) fn new(n: [usize; 3]) -> BoundarySlots {
        let unset = FaceFrame {
            block: UNSET,
            corners: [0; 4],
            start: 0,
            forward: true,
            counts: [0; 2],
        };
        BoundarySlots {
            faces: FastMap::default(),
            edges: FastMap::default(),
            slots: Vec::new(),
            other: FastMap::default(),
            n,
            element: 0,
            nodes: [0; 8],
            face: [unset; 6],
            edge: [UNSET; 12],
            edge_ends: [[0; 2]; 12],
        }
    }

    /// Starts element `element` with these nodes.
    pub(crate) fn begin(&mut self, element: usize, nodes: [u32; 8]) {
        self.element = element;
        self.nodes = nodes;
        for f in &mut self.face {
            f.block = UNSET;
        }
        self.edge = [UNSET; 12];
    }

    /// The slot of the lattice edge from `lo` along `axis` of the current element, or `None`
    /// when the edge is inside the element.
    #[inline]
    pub(crate) fn locate(&mut self, lo: [usize; 3], axis: usize) -> Option<Slot> {
        let n = self.n;
        let (u, v) = free_axes(axis);
        let side = |d: usize| -> Option<usize> {
            if lo[d] == 0 {
                Some(0)
            } else if lo[d] == n[d] {
                Some(1)
            } else {
                None
            }
        };
        match (side(u), side(v)) {
            (None, None) => None,
            (Some(su), Some(sv)) => Some(self.edge_slot(lo, axis, su, sv)),
            (Some(s), None) => Some(self.face_slot(lo, axis, u, s)),
            (None, Some(s)) => Some(self.face_slot(lo, axis, v, s)),
        }
    }

    /// An edge on the element edge along `axis` at sides `su, sv` of its free axes.
    fn edge_slot(&mut self, lo: [usize; 3], axis: usize, su: usize, sv: usize) -> Slot {
        let at = 4 * axis + su + 2 * sv;
        let (u, v) = free_axes(axis);
        let mut s = [0; 3];
        s[u] = su;
        s[v] = sv;
        let a = node_at(&self.nodes, s);
        s[axis] = 1;
        let b = node_at(&self.nodes, s);
        if self.edge[at] == UNSET {
            self.edge[at] = if a == b {
                DEGENERATE
            } else {
                let len = self.n[axis];
                let slots = &mut self.slots;
                self.edge_ends[at] = [a.min(b), a.max(b)];
                *self.edges.entry([a.min(b), a.max(b)]).or_insert_with(|| {
                    let start = slots.len() as u32;
                    slots.resize(slots.len() + len, EMPTY);
                    start
                })
            };
        }
        match self.edge[at] {
            DEGENERATE => Slot::Other(self.key(lo, axis)),
            block => {
                let i = if a < b {
                    lo[axis]
                } else {
                    self.n[axis] - 1 - lo[axis]
                };
                Slot::Dense {
                    at: block as usize + i,
                    entity: 6 + at as u8,
                }
            }
        }
    }

    /// An edge inside the face normal to `d` on side `side`.
    fn face_slot(&mut self, lo: [usize; 3], axis: usize, d: usize, side: usize) -> Slot {
        let f = 2 * d + side;
        if self.face[f].block == UNSET {
            self.face[f] = self.frame(d, side);
        }
        let frame = self.face[f];
        if frame.block == DEGENERATE {
            return Slot::Other(self.key(lo, axis));
        }
        let (u, v) = free_axes(d);
        let (nu, nv) = (self.n[u], self.n[v]);
        let mut hi = lo;
        hi[axis] += 1;
        let (start, fwd) = (frame.start as usize, frame.forward);
        let a = face_position([lo[u], lo[v]], [nu, nv], start, fwd);
        let b = face_position([hi[u], hi[v]], [nu, nv], start, fwd);
        let [cu, cv] = frame.counts.map(|c| c as usize);
        let i = if a[1] == b[1] {
            a[0].min(b[0]) + cu * a[1]
        } else {
            cu * (cv + 1) + a[0] + (cu + 1) * a[1].min(b[1])
        };
        Slot::Dense {
            at: frame.block as usize + i,
            entity: f as u8,
        }
    }

    /// Looks up (or makes) the block of the face normal to `d` on side `side`.
    fn frame(&mut self, d: usize, side: usize) -> FaceFrame {
        let (u, v) = free_axes(d);
        match canonical_face(face_corners(&self.nodes, d, side)) {
            None => FaceFrame {
                block: DEGENERATE,
                corners: [0; 4],
                start: 0,
                forward: true,
                counts: [0; 2],
            },
            Some((corners, start, forward)) => {
                let [cu, cv] = face_counts([self.n[u], self.n[v]], start, forward);
                let len = cu * (cv + 1) + (cu + 1) * cv;
                let slots = &mut self.slots;
                let block = *self.faces.entry(corners).or_insert_with(|| {
                    let start = slots.len() as u32;
                    slots.resize(slots.len() + len, EMPTY);
                    start
                });
                FaceFrame {
                    block,
                    corners,
                    start: start as u8,
                    forward,
                    counts: [cu as u32, cv as u32],
                }
            }
        }
    }

    fn key(&self, lo: [usize; 3], axis: usize) -> EdgeKey {
        edge_key(self.element, &self.nodes, self.n, lo, axis).0
    }

    /// The vertex in `slot`, if any.
    #[inline]
    pub(crate) fn get(&self, slot: &Slot) -> Option<u32> {
        match slot {
            Slot::Dense { at, .. } => Some(self.slots[*at]).filter(|&v| v != EMPTY),
            Slot::Other(k) => self.other.get(k).copied(),
        }
    }

    /// Puts vertex `v` in `slot`.
    pub(crate) fn set(&mut self, slot: Slot, v: u32) {
        match slot {
            Slot::Dense { at, .. } => self.slots[at] = v,
            Slot::Other(k) => {
                self.other.insert(k, v);
            }
        }
    }

    /// The name of `slot` (made by [`locate`](Self::locate) in the current element), to look
    /// it up in another range's slots.
    pub(crate) fn name(&self, slot: &Slot) -> BoundaryName {
        match *slot {
            Slot::Dense { at, entity } if entity < 6 => {
                let f = &self.face[entity as usize];
                BoundaryName::Face {
                    corners: f.corners,
                    index: at as u32 - f.block,
                }
            }
            Slot::Dense { at, entity } => {
                let e = (entity - 6) as usize;
                BoundaryName::Edge {
                    ends: self.edge_ends[e],
                    index: at as u32 - self.edge[e],
                }
            }
            Slot::Other(k) => BoundaryName::Other(k),
        }
    }

    /// The vertex this range made for the edge named `name`, if any.
    pub(crate) fn find(&self, name: &BoundaryName) -> Option<u32> {
        let v = match name {
            BoundaryName::Face { corners, index } => {
                self.slots[(*self.faces.get(corners)? + index) as usize]
            }
            BoundaryName::Edge { ends, index } => {
                self.slots[(*self.edges.get(ends)? + index) as usize]
            }
            BoundaryName::Other(k) => *self.other.get(k)?,
        };
        (v != EMPTY).then_some(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mc::fe::heart;
    use std::collections::HashMap;

    /// Slot equality is edge-key equality, over every boundary lattice edge of the heart, of a
    /// block glued to a quarter-turned copy, and of a wedge (collapsed edge) beside them.
    #[test]
    fn slots_name_edges_as_edge_keys_do() {
        let [e0, e1, wedge] = crate::mc::fe::lattice::glued_pair_and_wedge();
        let heart = heart::left_ventricle().elements;
        let cases: [(&[[u32; 8]], [usize; 3]); 6] = [
            (&[wedge, e0, e1], [3, 3, 3]),
            (&[wedge, e1], [2, 2, 2]),
            (&heart, [3, 3, 2]),
            (&heart, [1, 2, 1]),
            (&[e0, e1], [3, 3, 3]),
            (&[e0, e1], [1, 1, 1]),
        ];
        for (elements, n) in cases {
            let mut slots = BoundarySlots::new(n);
            // Slot identity → key, and key → slot identity: both must be functions.
            let mut by_slot: HashMap<String, EdgeKey> = HashMap::new();
            let mut by_key: HashMap<EdgeKey, String> = HashMap::new();
            let (mut edges, mut others) = (0, 0);
            for (e, nodes) in elements.iter().enumerate() {
                slots.begin(e, *nodes);
                for axis in 0..3 {
                    let mut len = [n[0] + 1, n[1] + 1, n[2] + 1];
                    len[axis] -= 1;
                    for k in 0..len[2] {
                        for j in 0..len[1] {
                            for i in 0..len[0] {
                                let lo = [i, j, k];
                                let Some(slot) = slots.locate(lo, axis) else {
                                    continue;
                                };
                                edges += 1;
                                others += usize::from(matches!(slot, Slot::Other(_)));
                                let key = edge_key(e, nodes, n, lo, axis).0;
                                let name = format!("{:?}", slots.name(&slot));
                                // A slot's name finds what was put in it.
                                if slots.get(&slot).is_none() {
                                    let name = slots.name(&slot);
                                    slots.set(slot, edges);
                                    assert_eq!(slots.find(&name), Some(edges));
                                }
                                assert_eq!(*by_slot.entry(name.clone()).or_insert(key), key);
                                assert_eq!(*by_key.entry(key).or_insert(name.clone()), name);
                            }
                        }
                    }
                }
            }
            println!(
                "{} elements at {n:?}: {edges} boundary edges ({others} on collapsed entities), \
                 {} names, all equal to keys",
                elements.len(),
                by_key.len()
            );
            assert!(by_key.len() < edges as usize, "some edges are shared");
            if elements[0] == wedge {
                assert!(others > 0, "collapsed entities keep their keys");
            }
        }
    }
}
