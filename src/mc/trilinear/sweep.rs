//! The independent route: corner groups of the trilinear interpolant by an event sweep of
//! plane slices, exact on small integer cells.
//!
//! Sweep planes `t` along one axis. Each slice is bilinear; every component of a slice's
//! positive set `f ≥ 0` contains a slice corner (a bilinear function is linear on the square's
//! sides and has no interior extremum), so components are tracked through the four edges
//! parallel to the sweep. A slice's topology changes only where such an edge crosses 0
//! (rational `t`) or where its saddle crosses 0: `q(t) = e₀e₂ − e₁e₃` (products along the
//! diagonals, a quadratic in `t`) changes sign. All sign questions are answered in integers:
//! rational roots become events, irrational roots are located against the rational events by
//! the sign of `q` at the ends, at the vertex and of `q'`. Adjacent slice corners of one sign
//! are joined (the side between them has that sign); diagonal corners are joined by the
//! saddle rule (positive: `S ≥ 0`, negative: `S < 0`).
//!
//! The classes are the closed set `{f ≥ 0}` and the open set `{f < 0}`: for a compact
//! semi-algebraic set these have the components of `{f > −ε}` and `{f < −ε}` for small
//! `ε > 0`, so the groups are those of the perturbed level the oracle decides at
//! (the oracle's `ring` module). The route shares only the map of sweep edges with the
//! oracle's closed form: it walks events in order instead of asking one question per pair of
//! sweep edges.

use super::closed::sweep_edges;
use super::Groups;
use std::cmp::Ordering;

/// The largest corner magnitude the sweep takes: every product it forms stays inside
/// `i128` (events have numerators and denominators below `2²⁸`, their midpoints below `2⁵⁷`,
/// and `q` at a midpoint below `2¹²¹`).
pub const SWEEP_LIMIT: i64 = 1 << 10;

/// A rational `n / d` with `d > 0`, small integers.
#[derive(Clone, Copy, Debug)]
struct Q {
    n: i128,
    d: i128,
}

impl Q {
    fn new(n: i128, d: i128) -> Q {
        if d < 0 {
            Q { n: -n, d: -d }
        } else {
            Q { n, d }
        }
    }
    fn cmp(self, o: Q) -> Ordering {
        (self.n * o.d).cmp(&(o.n * self.d))
    }
    fn mid(self, o: Q) -> Q {
        Q::new(self.n * o.d + o.n * self.d, 2 * self.d * o.d)
    }
}

/// A quadratic `a t² + b t + c` with integer coefficients.
#[derive(Clone, Copy)]
struct Quad {
    a: i128,
    b: i128,
    c: i128,
}

impl Quad {
    /// `sign(q(t))` at rational `t` (`d² q(n/d) = a n² + b n d + c d²`).
    fn sign_at(&self, t: Q) -> i32 {
        let (n, d) = (t.n, t.d);
        (self.a * n * n + self.b * n * d + self.c * d * d).signum() as i32
    }
    /// `sign(q'(t))`.
    fn slope_at(&self, t: Q) -> i32 {
        let (n, d) = (t.n, t.d);
        (2 * self.a * n + self.b * d).signum() as i32
    }
    /// The sign just right of `t` (`towards = 1`) or just left (`-1`).
    fn sign_near(&self, t: Q, towards: i32) -> i32 {
        let s = self.sign_at(t);
        if s != 0 {
            return s;
        }
        let s1 = self.slope_at(t) * towards;
        if s1 != 0 {
            return s1;
        }
        self.a.signum() as i32
    }
    /// Rational roots in `(0, 1)` (all roots when the discriminant is a perfect square).
    fn rational_roots(&self) -> Vec<Q> {
        let mut out = Vec::new();
        if self.a == 0 {
            if self.b != 0 {
                out.push(Q::new(-self.c, self.b));
            }
        } else {
            let disc = self.b * self.b - 4 * self.a * self.c;
            if disc >= 0 {
                let r = isqrt(disc);
                if r * r == disc {
                    for s in [-1, 1] {
                        out.push(Q::new(-self.b + s * r, 2 * self.a));
                    }
                }
            }
        }
        out.retain(|t| {
            t.cmp(Q::new(0, 1)) == Ordering::Greater && t.cmp(Q::new(1, 1)) == Ordering::Less
        });
        out
    }
    /// Signs of `q` along the open interval `(l, r)` in which it has no rational root: one
    /// entry per maximal sub-interval of constant sign, zeros between them.
    fn signs_between(&self, l: Q, r: Q) -> Vec<i32> {
        let (sl, sr) = (self.sign_near(l, 1), self.sign_near(r, -1));
        if sl != sr {
            return vec![sl, 0, sr];
        }
        if self.a != 0 {
            // Two roots inside iff the vertex −b/2a lies inside and q there has the other sign
            // (q(vertex) = −disc / 4a).
            let v = Q::new(-self.b, 2 * self.a);
            let disc = self.b * self.b - 4 * self.a * self.c;
            let sv = (-(disc.signum()) * self.a.signum()) as i32;
            if v.cmp(l) == Ordering::Greater && v.cmp(r) == Ordering::Less && sv != 0 && sv != sl {
                return vec![sl, 0, sv, 0, sl];
            }
        }
        vec![sl]
    }
}

fn isqrt(x: i128) -> i128 {
    if x < 2 {
        return x;
    }
    let mut r = (x as f64).sqrt() as i128;
    while r * r > x {
        r -= 1;
    }
    while (r + 1) * (r + 1) <= x {
        r += 1;
    }
    r
}

/// Union-find over a few nodes.
pub(crate) struct Dsu(Vec<usize>);

impl Dsu {
    pub(crate) fn new(n: usize) -> Dsu {
        Dsu((0..n).collect())
    }
    pub(crate) fn find(&mut self, a: usize) -> usize {
        let mut a = a;
        while self.0[a] != a {
            self.0[a] = self.0[self.0[a]];
            a = self.0[a];
        }
        a
    }
    pub(crate) fn union(&mut self, a: usize, b: usize) {
        let (x, y) = (self.find(a), self.find(b));
        if x != y {
            self.0[x.max(y)] = x.min(y);
        }
    }
}

/// One slice state: the four edge signs (`true` = `f ≥ 0`) and, when the slice is ambiguous,
/// the sign of `q` (`None` otherwise).
type Slice = ([bool; 4], Option<i32>);

/// The trilinear interpolant's corner groups `[positive, negative]` for integer corner values
/// `v` (shifted by the isovalue; `v ≥ 0` is positive), sweeping along `axis`; `None` when a
/// magnitude reaches [`SWEEP_LIMIT`].
pub fn sweep_groups(v: &[i64; 8], axis: usize) -> Option<[Groups; 2]> {
    if v.iter().any(|x| x.abs() >= SWEEP_LIMIT) || axis > 2 {
        return None;
    }
    let edges = sweep_edges(axis);
    let e: [(i128, i128); 4] = edges.map(|[a, b]| (v[a] as i128, (v[b] - v[a]) as i128)); // e_k(t) = v + t δ
    let q = Quad {
        a: e[0].1 * e[2].1 - e[1].1 * e[3].1,
        b: e[0].0 * e[2].1 + e[2].0 * e[0].1 - e[1].0 * e[3].1 - e[3].0 * e[1].1,
        c: e[0].0 * e[2].0 - e[1].0 * e[3].0,
    };
    // Rational events: edge crossings and rational roots of q.
    let mut events = vec![Q::new(0, 1), Q::new(1, 1)];
    for &(v0, dv) in &e {
        let v1 = v0 + dv;
        if (v0 >= 0) != (v1 >= 0) {
            events.push(Q::new(-v0, dv));
        }
    }
    events.extend(q.rational_roots());
    events.sort_by(|a, b| a.cmp(*b));
    events.dedup_by(|a, b| a.cmp(*b) == Ordering::Equal);
    let signs_at = |t: Q| -> [bool; 4] { e.map(|(v0, dv)| v0 * t.d + dv * t.n >= 0) };
    let ambiguous = |s: &[bool; 4]| s[0] == s[2] && s[1] == s[3] && s[0] != s[1];
    let mut slices: Vec<Slice> = Vec::new();
    for (i, &t) in events.iter().enumerate() {
        let s = signs_at(t);
        slices.push((s, ambiguous(&s).then(|| q.sign_at(t))));
        if let Some(&r) = events.get(i + 1) {
            let s = signs_at(t.mid(r));
            if ambiguous(&s) {
                for qs in q.signs_between(t, r) {
                    slices.push((s, Some(qs)));
                }
            } else {
                slices.push((s, None));
            }
        }
    }
    let groups = |positive: bool| -> Groups {
        let mut dsu = Dsu::new(4 * slices.len());
        for (p, (s, qs)) in slices.iter().enumerate() {
            let mine = |k: usize| s[k] == positive;
            for k in 0..4 {
                if mine(k) && mine((k + 1) % 4) {
                    dsu.union(4 * p + k, 4 * p + (k + 1) % 4);
                }
                if p + 1 < slices.len() && mine(k) && slices[p + 1].0[k] == positive {
                    dsu.union(4 * p + k, 4 * (p + 1) + k);
                }
            }
            if let Some(qs) = *qs {
                // The diagonal of this sign: (0, 2) if corner 0 has it, else (1, 3). Positive
                // joined iff S ≥ 0, i.e. its diagonal product ≥ the other's.
                let (a, b) = if mine(0) { (0, 2) } else { (1, 3) };
                let own = if a == 0 { qs } else { -qs }; // sign of (own product − other)
                let joined = if positive { own >= 0 } else { own > 0 };
                if joined {
                    dsu.union(4 * p + a, 4 * p + b);
                }
            }
        }
        let last = slices.len() - 1;
        let mut label = [u8::MAX; 8];
        let node_of = |c: usize| -> usize {
            let k = edges.iter().position(|ed| ed.contains(&c)).unwrap_or(0);
            if edges[k][0] == c {
                k
            } else {
                4 * last + k
            }
        };
        for c in 0..8 {
            if (v[c] >= 0) != positive {
                continue;
            }
            let root = dsu.find(node_of(c));
            label[c] = (0..8)
                .find(|&d| (v[d] >= 0) == positive && dsu.find(node_of(d)) == root)
                .unwrap_or(c) as u8;
        }
        label
    };
    Some([groups(true), groups(false)])
}
