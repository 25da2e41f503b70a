//! Ear cutting of the hole a removed node leaves (Section 1.3; the classical algorithm the
//! paper cites as ElGindy, Everett and Toussaint): `O(l²)` in the hole's `l` vertices.
//!
//! The polygon is given counter-clockwise by its vertices `0..l` in a projection plane. An ear
//! `(a, b, c)` of consecutive vertices is cut when `orient(a, b, c) > 0` and no other polygon
//! vertex lies in the closed triangle: every triangle made has positive area and the
//! triangles tile the polygon. A vertex on a straight angle is never an ear tip, and a vertex
//! on the diagonal `a–c` blocks the ear, so collinear runs (common on grids) are handled.
//! Every simple polygon has such an ear (Meisters' two-ears theorem, which holds with
//! straight angles for diagonals strictly inside); when none is found the polygon is not
//! simple in this projection and the cut fails.
//!
//! The validity tests take their signs from an [`Orient`] predicate (exact in both paths).
//! Among the valid ears the one of best shape is cut first (largest `2·area / Σ edge²` in
//! `f64`, the lowest position on ties): a heuristic, computed from the same `f64` coordinates
//! by both paths so that they cut the same ears. Ear status is cached and recomputed for the
//! two neighbours of each cut ear; when no cached ear is valid all are recomputed.
//!
//! Convex holes (every vertex turning left, or some straight between their neighbours,
//! common on grids) are cut by masks and cached sides alone, without orientation tests after
//! the first pass: the same ears, as the unit tests check against the general loop.

use std::cmp::Ordering;

/// The sign of the orientation of three polygon vertices (by position in the polygon).
pub trait Orient {
    /// `Greater` when `a, b, c` turn counter-clockwise, `Equal` when collinear.
    fn orient(&self, a: usize, b: usize, c: usize) -> Ordering;
    /// True only when `p` lies outside the bounding box of `t` (so outside the closed
    /// triangle): a cheap exact pre-test; `false` decides nothing.
    fn outside_box(&self, _t: [usize; 3], _p: usize) -> bool {
        false
    }
}

/// The shape heuristic of an ear: `2·area / (|ab|² + |bc|² + |ca|²)` in `f64`.
pub fn ear_quality(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    quality_of(a, b, c, dist2(a, b) + dist2(b, c) + dist2(c, a))
}

/// [`ear_quality`] given the sum `s` of its squared sides.
#[inline]
fn quality_of(a: [f64; 2], b: [f64; 2], c: [f64; 2], s: f64) -> f64 {
    let area2 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    if s > 0.0 {
        area2 / s
    } else {
        0.0
    }
}

/// `|p − q|²` in `f64` (the same value for `(p, q)` and `(q, p)`: a square does not see
/// the sign).
#[inline]
fn dist2(p: [f64; 2], q: [f64; 2]) -> f64 {
    (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)
}

/// The ear cutter, with buffers reused between holes. The polygon still to cut is a circular
/// doubly linked list over vertex indices, kept in increasing index order from `head` (the
/// lowest remaining index), so "lowest position" and "lowest index" coincide.
#[derive(Clone, Debug)]
pub struct EarCutter {
    next: [u8; 256],
    prev: [u8; 256],
    /// `orient(prev, v, next) > 0` at vertex `v`.
    convex: [bool; 256],
    valid: [bool; 256],
    quality: [f64; 256],
    /// In [`cut_convex`](Self::cut_convex): `|v next(v)|²`, and `|next(v) prev(v)|²` (the
    /// diagonal that cutting `v` makes an edge).
    edge: [f64; 256],
    diagonal: [f64; 256],
}

impl Default for EarCutter {
    fn default() -> Self {
        EarCutter {
            next: [0; 256],
            prev: [0; 256],
            convex: [false; 256],
            valid: [false; 256],
            quality: [0.0; 256],
            edge: [0.0; 256],
            diagonal: [0.0; 256],
        }
    }
}

impl EarCutter {
    /// Triangulates the counter-clockwise polygon `0..l` (`points` are its projected `f64`
    /// coordinates, exactly: the heuristic reads them, and so do the exact comparisons that
    /// recognise a convex polygon). Writes `l − 2` triangles of polygon positions to `out`
    /// and returns true, or returns false when no valid ear exists at some stage.
    /// `l` must be at most 255.
    pub fn cut(
        &mut self,
        points: &[[f64; 2]],
        orient: &impl Orient,
        out: &mut Vec<[u8; 3]>,
    ) -> bool {
        let l = points.len();
        out.clear();
        if !(3..=255).contains(&l) {
            return false;
        }
        self.link(l);
        if l <= 64 {
            self.cut_small(points, orient, out)
        } else {
            self.cut_list(points, orient, out)
        }
    }

    /// Links the polygon `0..l` into the circular list.
    fn link(&mut self, l: usize) {
        for i in 0..l {
            self.next[i] = if i + 1 == l { 0 } else { i as u8 + 1 };
            self.prev[i] = if i == 0 { (l - 1) as u8 } else { i as u8 - 1 };
        }
    }

    /// [`cut`](Self::cut) on a linked list, for any size (after [`link`](Self::link)).
    fn cut_list(
        &mut self,
        points: &[[f64; 2]],
        orient: &impl Orient,
        out: &mut Vec<[u8; 3]>,
    ) -> bool {
        let l = points.len();
        for i in 0..l {
            self.convex[i] = self.turns_left(i, orient);
        }
        let mut head = 0usize;
        let mut n = l;
        for i in 0..l {
            self.refresh(i, n, points, orient);
        }
        while n > 3 {
            let mut best = self.best(head, n);
            if best.is_none() {
                let mut v = head;
                for _ in 0..n {
                    self.refresh(v, n, points, orient);
                    v = self.next[v] as usize;
                }
                best = self.best(head, n);
            }
            let Some(b) = best else {
                return false;
            };
            let (a, c) = self.cut_ear(b, out);
            if b == head {
                head = c;
            }
            n -= 1;
            self.convex[a] = self.turns_left(a, orient);
            self.convex[c] = self.turns_left(c, orient);
            self.refresh(a, n, points, orient);
            self.refresh(c, n, points, orient);
        }
        self.last_triangle(head, orient, out)
    }

    /// [`cut`](Self::cut) for polygons of at most 64 vertices (after [`link`](Self::link)), with the remaining, convex and
    /// valid vertices as bit masks: the same ears, in the same order (the unit tests compare
    /// the two), without walking the list to find blockers or the best ear.
    fn cut_small(
        &mut self,
        points: &[[f64; 2]],
        orient: &impl Orient,
        out: &mut Vec<[u8; 3]>,
    ) -> bool {
        let l = points.len();
        let mut masks = Masks {
            alive: if l == 64 { !0 } else { (1u64 << l) - 1 },
            convex: 0,
            valid: 0,
        };
        let (mut straight, mut reflex) = (0u64, false);
        for i in 0..l {
            match orient.orient(self.prev[i] as usize, i, self.next[i] as usize) {
                Ordering::Greater => masks.convex |= 1 << i,
                Ordering::Equal => straight |= 1 << i,
                Ordering::Less => reflex = true,
            }
        }
        if !reflex && self.straight_between(points, straight) && winds_once(points) {
            return self.cut_convex(points, masks.alive, masks.convex, out);
        }
        let mut n = l;
        for i in 0..l {
            self.refresh_small(i, n, &mut masks, points, orient);
        }
        while n > 3 {
            let mut best = self.best_small(masks.alive & masks.valid);
            if best.is_none() {
                let mut left = masks.alive;
                while left != 0 {
                    let v = left.trailing_zeros() as usize;
                    left &= left - 1;
                    self.refresh_small(v, n, &mut masks, points, orient);
                }
                best = self.best_small(masks.alive & masks.valid);
            }
            let Some(b) = best else {
                return false;
            };
            let (a, c) = self.cut_ear(b, out);
            masks.alive &= !(1 << b);
            n -= 1;
            for v in [a, c] {
                masks.convex =
                    (masks.convex & !(1 << v)) | (self.turns_left(v, orient) as u64) << v;
            }
            self.refresh_small(a, n, &mut masks, points, orient);
            self.refresh_small(c, n, &mut masks, points, orient);
        }
        self.last_triangle(masks.alive.trailing_zeros() as usize, orient, out)
    }

    /// Cuts the ear at `b`: records `(prev, b, next)` and unlinks `b`; returns its neighbours.
    #[inline]
    fn cut_ear(&mut self, b: usize, out: &mut Vec<[u8; 3]>) -> (usize, usize) {
        let (a, c) = (self.prev[b] as usize, self.next[b] as usize);
        out.push([a as u8, b as u8, c as u8]);
        self.next[a] = c as u8;
        self.prev[c] = a as u8;
        (a, c)
    }

    /// The triangle left from `head`, kept when it turns counter-clockwise.
    fn last_triangle(&self, head: usize, orient: &impl Orient, out: &mut Vec<[u8; 3]>) -> bool {
        let b = self.next[head] as usize;
        let c = self.next[b] as usize;
        if orient.orient(head, b, c) != Ordering::Greater {
            return false;
        }
        out.push([head as u8, b as u8, c as u8]);
        true
    }

    /// True when every vertex in `straight` (collinear with its neighbours) lies strictly
    /// between them: no spike turning back and no repeated point (exact comparisons).
    fn straight_between(&self, points: &[[f64; 2]], mut straight: u64) -> bool {
        while straight != 0 {
            let v = straight.trailing_zeros() as usize;
            straight &= straight - 1;
            let (a, p, b) = (
                points[self.prev[v] as usize],
                points[v],
                points[self.next[v] as usize],
            );
            let inside =
                (0..2).all(|k| (a[k] <= p[k] && p[k] <= b[k]) || (b[k] <= p[k] && p[k] <= a[k]));
            if p == a || p == b || !inside {
                return false;
            }
        }
        true
    }

    /// [`cut_small`](Self::cut_small) on a simple polygon without reflex vertices, its
    /// straight vertices (`alive & !convex`, each strictly between its neighbours) not all of
    /// them: a convex polygon, perhaps with points on its sides. The same ears as the general
    /// loop, from masks alone and without orientation tests, because in such a polygon
    /// (it stays one after every cut, with positive area):
    /// - cutting the ear at a strictly convex `b` leaves its neighbours `a`, `c` strictly
    ///   convex (a straight `a` had `c` strictly left of its line; a strictly convex `a`
    ///   turning straight would put `b` outside the supporting line of the side before `a`);
    /// - a vertex in the closed ear triangle `(a, b, c)` lies on the polygon's boundary, so
    ///   on the open diagonal `a c`, so all of the chain from `c` round to `a` does: the ear
    ///   at `b` is blocked exactly when every remaining vertex but `a`, `b`, `c` is straight;
    /// - so no cut changes the validity of an ear other than its neighbours' (the general
    ///   loop's cache is exact), and a valid ear always exists.
    ///
    /// Strictly convex polygons (`convex == alive`) are the plain case: every ear stays valid
    /// and only the cut ear's neighbours change quality. Each squared side is computed once
    /// and cached (the same qualities bit for bit).
    fn cut_convex(
        &mut self,
        points: &[[f64; 2]],
        mut alive: u64,
        mut convex: u64,
        out: &mut Vec<[u8; 3]>,
    ) -> bool {
        for v in 0..points.len() {
            self.edge[v] = dist2(points[v], points[self.next[v] as usize]);
        }
        let mut left = convex;
        while left != 0 {
            let v = left.trailing_zeros() as usize;
            left &= left - 1;
            self.convex_quality(points, v);
        }
        let mut n = points.len();
        while n > 3 {
            let tips = alive & convex;
            // An ear is valid unless every other remaining vertex is straight: with more
            // than three strictly convex vertices none is blocked.
            let valid = if tips.count_ones() > 3 {
                tips
            } else {
                let mut valid = 0;
                let mut left = tips;
                while left != 0 {
                    let v = left.trailing_zeros() as usize;
                    left &= left - 1;
                    let own = 1 << v | 1 << self.prev[v] | 1 << self.next[v];
                    if tips & !own != 0 {
                        valid |= 1 << v;
                    }
                }
                valid
            };
            let Some(b) = self.best_small(valid) else {
                return false;
            };
            let (a, c) = self.cut_ear(b, out);
            alive &= !(1 << b);
            convex |= 1 << a | 1 << c;
            n -= 1;
            self.edge[a] = self.diagonal[b];
            self.convex_quality(points, a);
            self.convex_quality(points, c);
        }
        let a = alive.trailing_zeros() as usize;
        let b = self.next[a] as usize;
        out.push([a as u8, b as u8, self.next[b]]);
        true
    }

    /// The quality of the ear at `v` from the cached sides ([`cut_convex`](Self::cut_convex)).
    #[inline]
    fn convex_quality(&mut self, points: &[[f64; 2]], v: usize) {
        let (a, c) = (self.prev[v] as usize, self.next[v] as usize);
        let diagonal = dist2(points[c], points[a]);
        self.diagonal[v] = diagonal;
        let s = self.edge[a] + self.edge[v] + diagonal;
        self.quality[v] = quality_of(points[a], points[v], points[c], s);
    }

    /// The ear of best quality among `candidates`, the lowest index on ties.
    #[inline]
    fn best_small(&self, mut candidates: u64) -> Option<usize> {
        if candidates == 0 {
            return None;
        }
        let mut best = candidates.trailing_zeros() as usize;
        let mut best_quality = self.quality[best];
        candidates &= candidates - 1;
        // Selects rather than branches: which ear wins is data, not a pattern to predict.
        while candidates != 0 {
            let v = candidates.trailing_zeros() as usize;
            candidates &= candidates - 1;
            let q = self.quality[v];
            let better = q > best_quality;
            best = if better { v } else { best };
            best_quality = if better { q } else { best_quality };
        }
        Some(best)
    }

    /// [`refresh`](Self::refresh) on masks: the candidate blockers are the remaining vertices
    /// that do not turn strictly left, other than the ear's own three.
    #[inline(always)]
    fn refresh_small(
        &mut self,
        b: usize,
        n: usize,
        masks: &mut Masks,
        points: &[[f64; 2]],
        orient: &impl Orient,
    ) {
        let (a, c) = (self.prev[b] as usize, self.next[b] as usize);
        let mut valid = masks.convex & (1 << b) != 0;
        if valid && n > 3 {
            let mut blockers = masks.alive & !masks.convex & !(1 << a | 1 << b | 1 << c);
            while blockers != 0 {
                let p = blockers.trailing_zeros() as usize;
                blockers &= blockers - 1;
                if in_closed_triangle(orient, [a, b, c], p) {
                    valid = false;
                    break;
                }
            }
        }
        masks.valid = (masks.valid & !(1 << b)) | (valid as u64) << b;
        self.quality[b] = if valid {
            ear_quality(points[a], points[b], points[c])
        } else {
            0.0
        };
    }

    /// The valid ear of best quality, the lowest index on ties.
    fn best(&self, head: usize, n: usize) -> Option<usize> {
        let mut best: Option<usize> = None;
        let mut v = head;
        for _ in 0..n {
            if self.valid[v] && best.is_none_or(|b| self.quality[v] > self.quality[b]) {
                best = Some(v);
            }
            v = self.next[v] as usize;
        }
        best
    }

    /// `orient(prev, v, next) > 0` at vertex `v`.
    #[inline]
    fn turns_left(&self, v: usize, orient: &impl Orient) -> bool {
        orient.orient(self.prev[v] as usize, v, self.next[v] as usize) == Ordering::Greater
    }

    /// Recomputes whether vertex `b` (of the `n` remaining) is an ear tip. Only vertices
    /// that do not turn strictly left can lie in an ear's triangle (if any polygon vertex
    /// does, the one farthest from the diagonal is reflex or straight towards the tip), so
    /// only those are tested.
    fn refresh(&mut self, b: usize, n: usize, points: &[[f64; 2]], orient: &impl Orient) {
        let (a, c) = (self.prev[b] as usize, self.next[b] as usize);
        let mut valid = self.convex[b];
        if valid && n > 3 {
            // The other vertices: from after c round to before a.
            let mut p = self.next[c] as usize;
            while p != a {
                if !self.convex[p] && in_closed_triangle(orient, [a, b, c], p) {
                    valid = false;
                    break;
                }
                p = self.next[p] as usize;
            }
        }
        self.valid[b] = valid;
        self.quality[b] = if valid {
            ear_quality(points[a], points[b], points[c])
        } else {
            0.0
        };
    }
}

/// Polygons of up to this many vertices have packed cuts ([`pack_cut`]).
pub const PACKED_MAX: usize = 16;

/// A cut of a polygon of `l ≤ PACKED_MAX` vertices packed into the low 56 bits of a word:
/// `l − 3` in bits 0–3, then the ear tips in cut order, four bits each. The cutter writes
/// `(prev, tip, next)` per ear and ends with the lowest remaining vertex and its two
/// successors, so the tips alone determine every triangle ([`unpack_cut`]). `None` for larger
/// polygons or a list that is not a cut of `l` vertices.
pub fn pack_cut(l: usize, tris: &[[u8; 3]]) -> Option<u64> {
    if !(3..=PACKED_MAX).contains(&l) || tris.len() != l - 2 {
        return None;
    }
    let mut bits = (l - 3) as u64;
    for (k, t) in tris[..l - 3].iter().enumerate() {
        bits |= u64::from(t[1]) << (4 + 4 * k);
    }
    Some(bits)
}

/// The triangles of a cut packed by [`pack_cut`] (bits above 56 ignored), written to `out`;
/// returns the polygon's vertex count.
pub fn unpack_cut(bits: u64, out: &mut Vec<[u8; 3]>) -> usize {
    let l = (bits & 15) as usize + 3;
    let (mut next, mut prev) = ([0u8; PACKED_MAX], [0u8; PACKED_MAX]);
    for i in 0..l {
        next[i] = i as u8 + 1;
        prev[i] = (i as u8).wrapping_sub(1);
    }
    next[l - 1] = 0;
    prev[0] = (l - 1) as u8;
    let mut alive = (1u32 << l) - 1;
    out.clear();
    for k in 0..l - 3 {
        let b = ((bits >> (4 + 4 * k)) & 15) as u8;
        let (a, c) = (prev[b as usize], next[b as usize]);
        out.push([a, b, c]);
        next[a as usize] = c;
        prev[c as usize] = a;
        alive &= !(1 << b);
    }
    let a = alive.trailing_zeros() as u8;
    let b = next[a as usize];
    out.push([a, b, next[b as usize]]);
    l
}

/// Puts a cut of the polygon `0..l` (any triangulation into `l − 2` counter-clockwise
/// triangles, e.g. after diagonal flips) back into the cutter's ear order, which
/// [`pack_cut`] relies on: repeatedly the ear with the lowest tip, written `(prev, tip,
/// next)`, then the last triangle from its lowest vertex. Every triangulation of a polygon
/// with more than three vertices has an ear, so this always succeeds on a valid cut; returns
/// false (leaving `tris` in some order) when `tris` is not one.
pub fn ear_order(l: usize, tris: &mut [[u8; 3]]) -> bool {
    if !(3..=255).contains(&l) || tris.len() != l - 2 {
        return false;
    }
    let (mut next, mut prev) = ([0u8; 256], [0u8; 256]);
    for i in 0..l {
        next[i] = if i + 1 == l { 0 } else { i as u8 + 1 };
        prev[i] = if i == 0 { (l - 1) as u8 } else { i as u8 - 1 };
    }
    for k in 0..tris.len() {
        let last = k + 1 == tris.len();
        let rest = &tris[k..];
        // The lowest tip among the remaining triangles that are ears now (for the last
        // triangle, its lowest vertex).
        let best = rest
            .iter()
            .enumerate()
            .flat_map(|(j, t)| (0..3).map(move |f| (j, t, f)))
            .filter(|&(_, t, f)| {
                let (a, b, c) = (t[(f + 2) % 3], t[f], t[(f + 1) % 3]);
                next[a as usize] == b && next[b as usize] == c
            })
            .map(|(j, t, f)| {
                let tip = if last {
                    *t.iter().min().expect("three")
                } else {
                    t[f]
                };
                (tip, j)
            })
            .min();
        let Some((tip, j)) = best else {
            return false;
        };
        tris.swap(k, k + j);
        let (a, c) = (prev[tip as usize], next[tip as usize]);
        if last {
            let b = next[tip as usize];
            tris[k] = [tip, b, next[b as usize]];
        } else {
            tris[k] = [a, tip, c];
            next[a as usize] = c;
            prev[c as usize] = a;
        }
    }
    true
}

/// True when vertex `p` lies in the closed counter-clockwise triangle `t`.
#[inline(always)]
fn in_closed_triangle(orient: &impl Orient, [a, b, c]: [usize; 3], p: usize) -> bool {
    !orient.outside_box([a, b, c], p)
        && orient.orient(a, b, p) != Ordering::Less
        && orient.orient(b, c, p) != Ordering::Less
        && orient.orient(c, a, p) != Ordering::Less
}

/// True when the closed polygon's edge directions pass angle 0 exactly once going round
/// (lower half-plane to upper, with the positive x axis upper). For a polygon whose every
/// vertex turns strictly left each step turns by less than π, so this counts its windings: one
/// means it is simple and convex. Exact: the signs of `f64` differences are exact.
fn winds_once(points: &[[f64; 2]]) -> bool {
    let l = points.len();
    if l == 0 {
        return false;
    }
    let upper = |p: [f64; 2], q: [f64; 2]| {
        let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
        dy > 0.0 || (dy == 0.0 && dx > 0.0)
    };
    // Cyclically over the edges (p_i, p_i+1), from the closing edge on.
    let mut was = upper(points[l - 1], points[0]);
    let mut wraps = 0;
    for i in 0..l {
        let now = upper(points[i], points[if i + 1 == l { 0 } else { i + 1 }]);
        wraps += (!was && now) as usize;
        was = now;
    }
    wraps == 1
}

/// The small cutter's state: bit `v` of each mask for polygon vertex `v`.
struct Masks {
    alive: u64,
    convex: u64,
    valid: u64,
}

/// Exact orientation of `f64` points by Shewchuk's adaptive predicate.
pub struct RobustOrient<'a>(pub &'a [[f64; 2]]);

impl Orient for RobustOrient<'_> {
    #[inline(always)]
    fn orient(&self, a: usize, b: usize, c: usize) -> Ordering {
        orient2d(self.0[a], self.0[b], self.0[c])
    }

    /// Comparisons of `f64` coordinates: exact.
    #[inline(always)]
    fn outside_box(&self, [a, b, c]: [usize; 3], p: usize) -> bool {
        let (a, b, c, p) = (self.0[a], self.0[b], self.0[c], self.0[p]);
        (0..2).any(|k| {
            (p[k] < a[k] && p[k] < b[k] && p[k] < c[k])
                || (p[k] > a[k] && p[k] > b[k] && p[k] > c[k])
        })
    }
}

/// The exact sign of `det[b − a, c − a]` for `f64` points, adaptively: Shewchuk's
/// first-stage filter inline, his exact adaptive stages (the `robust` crate) only when it
/// cannot decide. The filter is written without branches on the products' signs (which
/// mispredict on mixed input): with `detleft`, `detright` the two rounded products,
/// `|detleft − detright| > (3 + 16ε)ε · (|detleft| + |detright|)` certifies the sign when they
/// have the same sign (Shewchuk's bound `ccwerrboundA`), and holds trivially when they have
/// opposite signs, where the subtraction cannot cancel. When both are zero the exact stages
/// decide (a product can underflow to zero).
#[inline(always)]
pub fn orient2d(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Ordering {
    const EPS: f64 = f64::EPSILON / 2.0;
    const ERRBOUND_A: f64 = (3.0 + 16.0 * EPS) * EPS;
    let left = (a[0] - c[0]) * (b[1] - c[1]);
    let right = (a[1] - c[1]) * (b[0] - c[0]);
    let det = left - right;
    if det.abs() > ERRBOUND_A * (left.abs() + right.abs()) {
        return if det > 0.0 {
            Ordering::Greater
        } else {
            Ordering::Less
        };
    }
    orient2d_adaptive(a, b, c)
}

/// The exact stages of [`orient2d`], out of line: the filter decides almost every call.
#[cold]
#[inline(never)]
fn orient2d_adaptive(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Ordering {
    let d = robust::orient2d(
        robust::Coord { x: a[0], y: a[1] },
        robust::Coord { x: b[0], y: b[1] },
        robust::Coord { x: c[0], y: c[1] },
    );
    d.partial_cmp(&0.0).unwrap_or(Ordering::Equal)
}

/// Whether the closed polygon `0..l` is simple and counter-clockwise, from orientation signs
/// and the exact lexicographic order `lower(i, j)` of its vertices ((x, y) of `i` before
/// `j`'s): no two non-adjacent edges meet (closed segments, so no repeated point), no two
/// adjacent edges fold back onto each other, and the turn at the lexicographically lowest
/// vertex is counter-clockwise. `O(l²)`; the relaxed validity of a hole whose fan is not a
/// simple star in any axis plane (the quadric criterion), and the checker's test of a hole.
pub fn simple_ccw(l: usize, orient: &impl Orient, lower: impl Fn(usize, usize) -> bool) -> bool {
    if l < 3 {
        return false;
    }
    // Collinear with a–b: c strictly outside the segment on neither side.
    let on_segment =
        |a: usize, b: usize, c: usize| !(lower(c, a) && lower(c, b) || lower(a, c) && lower(b, c));
    let strictly_between =
        |a: usize, b: usize, c: usize| (lower(a, b) && lower(b, c)) || (lower(c, b) && lower(b, a));
    for i in 0..l {
        let (prev, next) = ((i + l - 1) % l, (i + 1) % l);
        if orient.orient(prev, i, next) == Ordering::Equal && !strictly_between(prev, i, next) {
            return false;
        }
    }
    for i in 0..l {
        let (a, b) = (i, (i + 1) % l);
        for j in i + 2..l {
            let (c, d) = (j, (j + 1) % l);
            if d == a {
                continue;
            }
            let (o1, o2) = (orient.orient(a, b, c), orient.orient(a, b, d));
            let (o3, o4) = (orient.orient(c, d, a), orient.orient(c, d, b));
            let meet = (o1 != o2
                && o3 != o4
                && o1 != Ordering::Equal
                && o2 != Ordering::Equal
                && o3 != Ordering::Equal
                && o4 != Ordering::Equal)
                || (o1 == Ordering::Equal && on_segment(a, b, c))
                || (o2 == Ordering::Equal && on_segment(a, b, d))
                || (o3 == Ordering::Equal && on_segment(c, d, a))
                || (o4 == Ordering::Equal && on_segment(c, d, b));
            if meet {
                return false;
            }
        }
    }
    let m = (1..l).fold(0, |m, i| if lower(i, m) { i } else { m });
    orient.orient((m + l - 1) % l, m, (m + 1) % l) == Ordering::Greater
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cut(points: &[[f64; 2]]) -> Option<Vec<[u8; 3]>> {
        let mut out = Vec::new();
        EarCutter::default()
            .cut(points, &RobustOrient(points), &mut out)
            .then_some(out)
    }

    fn area2(p: &[[f64; 2]], t: [u8; 3]) -> f64 {
        let (a, b, c) = (p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]);
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    }

    #[test]
    fn grid_ring_with_collinear_runs() {
        // The 8-ring of a grid node: four straight angles.
        let p = [
            [1.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [2.0, 2.0],
            [1.0, 2.0],
            [0.0, 2.0],
            [0.0, 1.0],
            [0.0, 0.0],
        ];
        let t = cut(&p).expect("a square with midpoints is triangulable");
        assert_eq!(t.len(), 6);
        let total: f64 = t.iter().map(|&t| area2(&p, t)).sum();
        assert!(t.iter().all(|&t| area2(&p, t) > 0.0));
        assert_eq!(total, 8.0);
    }

    #[test]
    fn small_and_list_cutters_cut_the_same_ears() {
        // Star-shaped polygons around the origin on a coarse grid of radii and angles, so
        // that collinear runs, reflex vertices, ties in quality and failures all occur.
        let mut rng = crate::decimate::TestRng(0x2545_f491_4f6c_dd1d);
        let mut rand = |k: u64| rng.below(k);
        let (mut agreed, mut failed, mut convex, mut packed) = (0, 0, 0, 0);
        for _ in 0..3000 {
            let l = 3 + rand(62) as usize;
            let mut angles: Vec<u64> = (0..l).map(|_| rand(720)).collect();
            angles.sort_unstable();
            angles.dedup();
            // A third on one circle: mostly convex (the convex path), some collinear runs.
            let on_circle = rand(3) == 0;
            let points: Vec<[f64; 2]> = angles
                .iter()
                .map(|&a| {
                    let r = if on_circle { 3.0 } else { 1.0 + rand(3) as f64 };
                    let t = a as f64 * std::f64::consts::PI / 360.0;
                    [(r * t.cos() * 64.0).round(), (r * t.sin() * 64.0).round()]
                })
                .collect();
            if points.len() < 3 {
                continue;
            }
            let all_left = (0..points.len()).all(|i| {
                let l = points.len();
                orient2d(points[(i + l - 1) % l], points[i], points[(i + 1) % l])
                    == Ordering::Greater
            });
            convex += (all_left && winds_once(&points)) as usize;
            let (mut small, mut list) = (Vec::new(), Vec::new());
            let mut cutter = EarCutter::default();
            cutter.link(points.len());
            let a = cutter.cut_small(&points, &RobustOrient(&points), &mut small);
            cutter.link(points.len());
            let b = cutter.cut_list(&points, &RobustOrient(&points), &mut list);
            assert_eq!(a, b, "{points:?}");
            if a {
                assert_eq!(small, list, "{points:?}");
                if let Some(bits) = pack_cut(points.len(), &small) {
                    let mut back = Vec::new();
                    assert_eq!(unpack_cut(bits, &mut back), points.len());
                    assert_eq!(back, small, "the packed cut unpacks to the same triangles");
                    packed += 1;
                }
                agreed += 1;
            } else {
                failed += 1;
            }
        }
        println!(
            "small = list cutter: {agreed} triangulated ({convex} strictly convex, {packed} packed and unpacked alike), {failed} refused alike"
        );
        assert!(
            agreed > 1000 && failed > 0 && convex > 200 && packed > 100,
            "{agreed} {failed} {convex} {packed}"
        );
    }

    /// The counter-clockwise convex hull of lattice points with the points on its sides
    /// kept (monotone chain popping only right turns).
    fn hull_with_sides(mut pts: Vec<[i64; 2]>) -> Vec<[i64; 2]> {
        pts.sort_unstable();
        pts.dedup();
        let turn = |o: [i64; 2], a: [i64; 2], b: [i64; 2]| {
            (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
        };
        let chain = |points: &mut dyn Iterator<Item = [i64; 2]>| {
            let mut h: Vec<[i64; 2]> = Vec::new();
            for p in points {
                while h.len() >= 2 && turn(h[h.len() - 2], h[h.len() - 1], p) < 0 {
                    h.pop();
                }
                h.push(p);
            }
            h.pop();
            h
        };
        let mut hull = chain(&mut pts.iter().copied());
        hull.extend(chain(&mut pts.iter().rev().copied()));
        hull
    }

    #[test]
    fn weakly_convex_polygons_cut_as_the_general_loop_does() {
        // Convex lattice polygons with lattice points on their sides (straight vertices),
        // some of them dropped, from every starting vertex: the masks-only path must cut
        // the ears the general loop cuts (which `cut_list` runs on every polygon).
        let mut rng = crate::decimate::TestRng(0x9e37_79b9_7f4a_7c15);
        let (mut weakly, mut degenerate, mut checked) = (0, 0, 0);
        for _ in 0..8000 {
            let span = 2 + rng.below(6) as i64;
            let k = 3 + rng.below(8);
            let pts: Vec<[i64; 2]> = (0..k)
                .map(|_| {
                    [
                        rng.below(span as u64 + 1) as i64,
                        rng.below(span as u64 + 1) as i64,
                    ]
                })
                .collect();
            let mut hull = hull_with_sides(pts);
            // Drop some points, then start anywhere.
            hull.retain(|_| rng.below(5) != 0);
            if hull.len() < 3 || hull.len() > 64 {
                continue;
            }
            let start = rng.below(hull.len() as u64) as usize;
            hull.rotate_left(start);
            let points: Vec<[f64; 2]> = hull.iter().map(|p| [p[0] as f64, p[1] as f64]).collect();
            let l = points.len();
            let turns: Vec<Ordering> = (0..l)
                .map(|i| orient2d(points[(i + l - 1) % l], points[i], points[(i + 1) % l]))
                .collect();
            let straight = turns.iter().filter(|&&t| t == Ordering::Equal).count();
            let strict = turns.iter().filter(|&&t| t == Ordering::Greater).count();
            if turns.contains(&Ordering::Less) || straight == 0 {
                continue;
            }
            if strict < 3 {
                degenerate += 1;
            } else {
                weakly += 1;
            }
            let (mut small, mut list) = (Vec::new(), Vec::new());
            let mut cutter = EarCutter::default();
            cutter.link(l);
            let a = cutter.cut_small(&points, &RobustOrient(&points), &mut small);
            cutter.link(l);
            let b = cutter.cut_list(&points, &RobustOrient(&points), &mut list);
            assert_eq!((a, &small), (b, &list), "{points:?}");
            if a {
                assert!(small.iter().all(|&t| area2(&points, t) > 0.0), "{points:?}");
            }
            checked += 1;
        }
        println!(
            "weakly convex polygons: {checked} cut alike by masks and by the general loop ({weakly} with three or more strictly convex vertices, {degenerate} flat: all points on one line)"
        );
        assert!(weakly > 1500 && degenerate > 50, "{weakly} {degenerate}");
    }

    #[test]
    fn winding_count() {
        let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert!(winds_once(&square));
        // A pentagram: every vertex turns left, twice round.
        let star: Vec<[f64; 2]> = (0..5)
            .map(|k| {
                let t = (2 * k) as f64 * 2.0 * std::f64::consts::PI / 5.0;
                [t.cos(), t.sin()]
            })
            .collect();
        assert!(!winds_once(&star));
        let mut out = Vec::new();
        let cut = EarCutter::default().cut(&star, &RobustOrient(&star), &mut out);
        let mut list = Vec::new();
        let mut cutter = EarCutter::default();
        cutter.link(star.len());
        let by_list = cutter.cut_list(&star, &RobustOrient(&star), &mut list);
        assert_eq!((cut, &out), (by_list, &list));
    }

    #[test]
    fn reflex_polygon_and_failure() {
        // An arrow (one reflex vertex).
        let p = [[0.0, 0.0], [4.0, 0.0], [2.0, 1.0], [4.0, 4.0], [0.0, 4.0]];
        let t = cut(&p).unwrap();
        let total: f64 = t.iter().map(|&t| area2(&p, t)).sum();
        assert!(t.iter().all(|&t| area2(&p, t) > 0.0));
        assert_eq!(total, 2.0 * (16.0 - 4.0));
        // Clockwise: no ear.
        let mut q = p;
        q.reverse();
        assert!(cut(&q).is_none());
        // All collinear: no ear.
        assert!(cut(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]]).is_none());
    }

    #[test]
    fn simple_ccw_polygons() {
        let run = |pts: &[[f64; 2]]| {
            let lower = |i: usize, j: usize| {
                (pts[i][0], pts[i][1]).partial_cmp(&(pts[j][0], pts[j][1])) == Some(Ordering::Less)
            };
            simple_ccw(pts.len(), &RobustOrient(pts), lower)
        };
        let square = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
        assert!(run(&square));
        let mut cw = square;
        cw.reverse();
        assert!(!run(&cw), "clockwise");
        assert!(
            !run(&[[0.0, 0.0], [2.0, 2.0], [2.0, 0.0], [0.0, 2.0]]),
            "bow tie"
        );
        // A straight angle is fine, a fold back is not, nor a repeated point.
        assert!(run(&[
            [0.0, 0.0],
            [1.0, 0.0],
            [2.0, 0.0],
            [2.0, 2.0],
            [0.0, 2.0]
        ]));
        assert!(!run(&[
            [0.0, 0.0],
            [2.0, 0.0],
            [1.0, 0.0],
            [2.0, 2.0],
            [0.0, 2.0]
        ]));
        assert!(!run(&[
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 2.0],
            [0.0, 0.0],
            [0.0, 2.0]
        ]));
        // A non-convex simple polygon, and a vertex touching a non-adjacent edge.
        assert!(run(&[
            [0.0, 0.0],
            [4.0, 0.0],
            [4.0, 4.0],
            [2.0, 1.0],
            [0.0, 4.0]
        ]));
        assert!(!run(&[
            [0.0, 0.0],
            [4.0, 0.0],
            [4.0, 4.0],
            [2.0, 0.0],
            [0.0, 4.0]
        ]));
        assert!(!run(&[[0.0, 0.0], [1.0, 1.0]]));
    }
}
