//! The closed-form route: corner groups of the trilinear interpolant from slices along one
//! axis, every decision a sign at a rational point of that axis (no square roots).
//!
//! Slice the cell by planes `t` across `axis`. A slice is bilinear: on each of its sides the
//! interpolant is linear, and it has no interior extremum, so every component of a slice's
//! region `s·g > 0` (`s = ±1`) contains a slice corner, i.e. a point of one of the four
//! *sweep edges* parallel to `axis` (slice corners `k = 0…3` in cyclic order). On sweep edge
//! `k` the value `e_k(t) = g_k + t δ_k` is linear, so its part of sign `s` is one interval
//! `J_k^s` that contains an end of the edge. Two sweep edges are therefore connected through
//! the region iff, at some `t`,
//!
//! * *(side)* they are adjacent and both have sign `s` — the slice side between them is
//!   linear, of sign `s` throughout: `J_k^s ∩ J_{k+1}^s ≠ ∅`; or
//! * *(diagonal)* they are opposite, both of sign `s`, the other two of sign `−s`, and the
//!   slice's saddle lies in the region: with `P_k(t) = e_k e_{k+2} − e_{k+1} e_{k+3}` (the
//!   asymptotic decider: the saddle value is `P_k / (e_k + e_{k+2} − e_{k+1} − e_{k+3})`, and
//!   that denominator has sign `s` in this pattern), `P_k(t) > 0` for some `t` of the pattern
//!   interval `I = J_k^s ∩ J_{k+2}^s ∩ J_{k+1}^{−s} ∩ J_{k+3}^{−s}`.
//!
//! `I` is an interval with ends at `0`, `1` or edge roots `t_k = g_k / (g_k − g_k')`;
//! `P_k` is a quadratic, positive somewhere on `I` iff positive at an end of `Ī` or at its
//! vertex `−B / 2A` when `A < 0` and the vertex lies inside (`P_k` is continuous and `I` is
//! relatively open in `[0, 1]`). The union of these joins over all slices, with each sweep
//! edge's interval joining its two corners when both have sign `s`, is the region's
//! component structure: the same one every slicing axis must give
//! ([`super::verify_cell`] checks the witnesses and re-derives the groups across another
//! axis).

use std::cmp::Ordering;

use super::ring::{Frac, OrderedRing};
use super::{Groups, Join, JoinKind, Mark, Witness};
use crate::mc::table::CORNERS;

/// The cube corners `[at t = 0, at t = 1]` of sweep edge `k` for slices across `axis`; slice
/// corners in cyclic order `(0,0), (1,0), (1,1), (0,1)` over the other two axes in
/// increasing order.
pub(crate) fn sweep_edges(axis: usize) -> [[usize; 2]; 4] {
    let (u, w) = match axis {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    };
    [(0u8, 0u8), (1, 0), (1, 1), (0, 1)].map(|(a, b)| {
        [0u8, 1].map(|t| {
            let mut p = [0u8; 3];
            p[u] = a;
            p[w] = b;
            p[axis] = t;
            CORNERS.iter().position(|c| *c == p).unwrap_or(0)
        })
    })
}

/// One sweep edge: its values at both ends and their signs.
struct SweepEdge<S> {
    g0: S,
    g1: S,
    delta: S,
    pos: [bool; 2],
    corners: [usize; 2],
}

/// The data every decision of one cell along one axis reads.
pub(crate) struct Slices<S> {
    edges: [SweepEdge<S>; 4],
}

impl<S: OrderedRing> Slices<S> {
    /// The slices of a cell whose shifted corner values `g` (signs never zero) are given.
    /// `None` when a corner's sign is uncertain or zero.
    pub(crate) fn new(g: &[S; 8], axis: usize) -> Option<Slices<S>> {
        let mut pos = [false; 8];
        for (c, v) in g.iter().enumerate() {
            pos[c] = match v.sign()? {
                Ordering::Greater => true,
                Ordering::Less => false,
                Ordering::Equal => return None,
            };
        }
        let edges = sweep_edges(axis).map(|[a, b]| SweepEdge {
            g0: g[a].clone(),
            g1: g[b].clone(),
            delta: g[b].sub(&g[a]),
            pos: [pos[a], pos[b]],
            corners: [a, b],
        });
        Some(Slices { edges })
    }

    /// The value of a mark on the axis.
    pub(crate) fn point(&self, m: Mark) -> Frac<S> {
        match m {
            Mark::Zero => Frac::int(0),
            Mark::One => Frac::int(1),
            Mark::Root(k) => {
                let e = &self.edges[k as usize];
                // g0 + t δ = 0 at t = g0 / (g0 − g1); g0 − g1 has g0's sign (they differ).
                let d = e.g0.sub(&e.g1);
                if e.pos[0] {
                    Frac { n: e.g0.clone(), d }
                } else {
                    Frac {
                        n: S::int(0).sub(&e.g0),
                        d: S::int(0).sub(&d),
                    }
                }
            }
        }
    }

    /// `J_k^s`: the marks `(lo, hi)` bounding the part of sweep edge `k` with sign `s`, or
    /// `None` when it has none.
    pub(crate) fn part(&self, k: usize, s: bool) -> Option<(Mark, Mark)> {
        let e = &self.edges[k];
        match (e.pos[0] == s, e.pos[1] == s) {
            (true, true) => Some((Mark::Zero, Mark::One)),
            (true, false) => Some((Mark::Zero, Mark::Root(k as u8))),
            (false, true) => Some((Mark::Root(k as u8), Mark::One)),
            (false, false) => None,
        }
    }

    /// `∩ J`: the bounds `(lo, hi)` of the intersection of the parts `(k, s)`, or
    /// `Some(None)` when it is empty, `None` when uncertain.
    pub(crate) fn common(&self, parts: &[(usize, bool)]) -> Option<Option<(Mark, Mark)>> {
        let mut lo = Mark::Zero;
        let mut hi = Mark::One;
        for &(k, s) in parts {
            let Some((l, h)) = self.part(k, s) else {
                return Some(None);
            };
            if self.cmp_marks(l, lo)? == Ordering::Greater {
                lo = l;
            }
            if self.cmp_marks(h, hi)? == Ordering::Less {
                hi = h;
            }
        }
        Some((self.cmp_marks(lo, hi)? == Ordering::Less).then_some((lo, hi)))
    }

    /// Two marks compared (a mark equals itself without arithmetic: intervals could not
    /// tell).
    pub(crate) fn cmp_marks(&self, a: Mark, b: Mark) -> Option<Ordering> {
        match (a, b) {
            _ if a == b => Some(Ordering::Equal),
            (Mark::Zero, _) | (_, Mark::One) => Some(Ordering::Less),
            (_, Mark::Zero) | (Mark::One, _) => Some(Ordering::Greater),
            _ => self.point(a).cmp(&self.point(b)),
        }
    }

    /// `d · e_k(n / d)`: the sign of sweep edge `k` at a point, scaled by its denominator.
    pub(crate) fn edge_at(&self, k: usize, t: &Frac<S>) -> S {
        let e = &self.edges[k];
        e.g0.mul(&t.d).add(&e.delta.mul(&t.n))
    }

    /// `d² · P_k(n / d)`, `P_k = e_k e_{k+2} − e_{k+1} e_{k+3}` (`k` = 0 or 1).
    pub(crate) fn diagonal_at(&self, k: usize, t: &Frac<S>) -> S {
        let e = |j: usize| self.edge_at((k + j) % 4, t);
        e(0).mul(&e(2)).sub(&e(1).mul(&e(3)))
    }

    /// The vertex `−B / 2A` of `P_k` when its leading coefficient `A` is negative (a maximum),
    /// `None` otherwise; `Err` when uncertain.
    pub(crate) fn diagonal_peak(&self, k: usize) -> Result<Option<Frac<S>>, ()> {
        let e = |j: usize| &self.edges[(k + j) % 4];
        let a = e(0)
            .delta
            .mul(&e(2).delta)
            .sub(&e(1).delta.mul(&e(3).delta));
        if a.sign().ok_or(())? != Ordering::Less {
            return Ok(None);
        }
        let b = e(0)
            .g0
            .mul(&e(2).delta)
            .add(&e(2).g0.mul(&e(0).delta))
            .sub(&e(1).g0.mul(&e(3).delta))
            .sub(&e(3).g0.mul(&e(1).delta));
        Ok(Some(Frac {
            n: b,
            d: S::int(-2).mul(&a),
        }))
    }

    /// The cube corner of sweep edge `k` nearest its part of sign `s` (one end has it).
    fn corner_of(&self, k: usize, s: bool) -> usize {
        let e = &self.edges[k];
        if e.pos[0] == s {
            e.corners[0]
        } else {
            e.corners[1]
        }
    }

    /// Whether corner `c` is positive.
    pub(crate) fn positive(&self, c: usize) -> bool {
        self.edges
            .iter()
            .find_map(|e| e.corners.iter().position(|&x| x == c).map(|i| e.pos[i]))
            .unwrap_or(false)
    }

    /// The joins of sign class `s` along this axis, with their witnesses; `None` when a sign
    /// is uncertain.
    pub(crate) fn joins(&self, s: bool, axis: u8) -> Option<Vec<Join>> {
        let mut out = Vec::new();
        for k in 0..4 {
            let e = &self.edges[k];
            if e.pos == [s, s] {
                out.push(Join {
                    positive: s,
                    axis,
                    kind: JoinKind::Edge(k as u8),
                    corners: [e.corners[0] as u8, e.corners[1] as u8],
                    witness: Witness {
                        lo: Mark::Zero,
                        hi: Mark::One,
                        at: Mark::Zero.into(),
                    },
                });
            }
            let next = (k + 1) % 4;
            if let Some((lo, hi)) = self.common(&[(k, s), (next, s)])? {
                out.push(Join {
                    positive: s,
                    axis,
                    kind: JoinKind::Side(k as u8),
                    corners: [self.corner_of(k, s) as u8, self.corner_of(next, s) as u8],
                    witness: Witness {
                        lo,
                        hi,
                        at: lo.into(),
                    },
                });
            }
        }
        for k in 0..2 {
            let pattern = [(k, s), (k + 2, s), (k + 1, !s), ((k + 3) % 4, !s)];
            let Some((lo, hi)) = self.common(&pattern)? else {
                continue;
            };
            let at = self.diagonal_witness(k, lo, hi)?;
            if let Some(at) = at {
                out.push(Join {
                    positive: s,
                    axis,
                    kind: JoinKind::Diagonal(k as u8),
                    corners: [self.corner_of(k, s) as u8, self.corner_of(k + 2, s) as u8],
                    witness: Witness { lo, hi, at },
                });
            }
        }
        Some(out)
    }

    /// Where `P_k > 0` on the closure of `(lo, hi)`: an end or the peak; `Some(None)` when
    /// nowhere.
    fn diagonal_witness(
        &self,
        k: usize,
        lo: Mark,
        hi: Mark,
    ) -> Option<Option<super::WitnessPoint>> {
        use super::WitnessPoint;
        let positive_at = |t: &Frac<S>| -> Option<bool> {
            Some(self.diagonal_at(k, t).sign()? == Ordering::Greater)
        };
        if positive_at(&self.point(lo))? {
            return Some(Some(WitnessPoint::Mark(lo)));
        }
        if positive_at(&self.point(hi))? {
            return Some(Some(WitnessPoint::Mark(hi)));
        }
        if let Some(v) = self.diagonal_peak(k).ok()? {
            let inside = self.point(lo).cmp(&v)? == Ordering::Less
                && v.cmp(&self.point(hi))? == Ordering::Less;
            if inside && positive_at(&v)? {
                return Some(Some(WitnessPoint::Peak));
            }
        }
        Some(None)
    }
}

/// The corner groups of both sign classes from the joins (labels: the smallest corner of a
/// group; `u8::MAX` for corners of the other class).
pub(crate) fn groups_from_joins(positive: &[bool; 8], joins: &[Join]) -> [Groups; 2] {
    [true, false].map(|s| {
        let mut parent: [usize; 8] = std::array::from_fn(|i| i);
        fn find(p: &mut [usize; 8], mut a: usize) -> usize {
            while p[a] != a {
                p[a] = p[p[a]];
                a = p[a];
            }
            a
        }
        for j in joins.iter().filter(|j| j.positive == s) {
            let (a, b) = (
                find(&mut parent, j.corners[0] as usize),
                find(&mut parent, j.corners[1] as usize),
            );
            if a != b {
                parent[a.max(b)] = a.min(b);
            }
        }
        let mut label = [u8::MAX; 8];
        for c in 0..8 {
            if positive[c] == s {
                let r = find(&mut parent, c);
                label[c] = (0..8)
                    .find(|&d| positive[d] == s && find(&mut parent, d) == r)
                    .unwrap_or(c) as u8;
            }
        }
        label
    })
}
