//! Body (interior) ambiguity: which table entries a trilinear interpolant may connect
//! differently inside the cell (tunnels), measured exactly on enumerated trilinear cells.
//!
//! The table fills every boundary loop with a disc, so its positive region's components are
//! the groups of positive corners joined along cube edges and across joined ambiguous faces
//! (likewise the negative region, across faces that are not joined). A trilinear interpolant
//! has no interior extrema, so its regions can only be coarser: a tunnel joins two groups.
//!
//! The interpolant's groups are found by sweeping planes `t` along one axis. Each slice is
//! bilinear; every component of a slice's positive set `f ≥ 0` contains a slice corner (a
//! bilinear function is linear on the square's sides and has no interior extremum), so
//! components are tracked through the four edges parallel to the sweep. A slice's topology
//! changes only where such an edge crosses 0 (rational `t`) or where its saddle crosses 0:
//! `q(t) = e₀e₂ − e₁e₃` (products along the diagonals, a quadratic in `t`) changes sign. All
//! sign questions are answered in integers: rational roots become events, irrational roots are
//! located against the rational events by the sign of `q` at the ends, at the vertex and of
//! `q'`. Adjacent slice corners of one sign are joined (the side between them has that sign);
//! diagonal corners are joined by the saddle rule (positive: `S ≥ 0`, negative: `S < 0`).

use super::{ProofOutcome, Shard, Tally};
use crate::mc::table::{ambiguous_faces, table, CORNERS, EDGES, FACES};
use std::cmp::Ordering;

/// A rational `n / d` with `d > 0`, small integers.
#[derive(Clone, Copy, Debug)]
struct Q {
    n: i64,
    d: i64,
}

impl Q {
    fn new(n: i64, d: i64) -> Q {
        if d < 0 {
            Q { n: -n, d: -d }
        } else {
            Q { n, d }
        }
    }
    fn cmp(self, o: Q) -> Ordering {
        ((self.n as i128) * (o.d as i128)).cmp(&((o.n as i128) * (self.d as i128)))
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
        let (n, d) = (t.n as i128, t.d as i128);
        (self.a * n * n + self.b * n * d + self.c * d * d).signum() as i32
    }
    /// `sign(q'(t))`.
    fn slope_at(&self, t: Q) -> i32 {
        let (n, d) = (t.n as i128, t.d as i128);
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
                out.push(Q::new(-self.c as i64, self.b as i64));
            }
        } else {
            let disc = self.b * self.b - 4 * self.a * self.c;
            if disc >= 0 {
                let r = isqrt(disc);
                if r * r == disc {
                    for s in [-1, 1] {
                        out.push(Q::new((-self.b + s * r) as i64, (2 * self.a) as i64));
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
            let v = Q::new(-self.b as i64, (2 * self.a) as i64);
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
struct Dsu(Vec<usize>);

impl Dsu {
    fn new(n: usize) -> Dsu {
        Dsu((0..n).collect())
    }
    fn find(&mut self, a: usize) -> usize {
        let mut a = a;
        while self.0[a] != a {
            self.0[a] = self.0[self.0[a]];
            a = self.0[a];
        }
        a
    }
    fn union(&mut self, a: usize, b: usize) {
        let (x, y) = (self.find(a), self.find(b));
        if x != y {
            self.0[x.max(y)] = x.min(y);
        }
    }
}

/// One slice state: the four edge signs (`true` = `f ≥ 0`) and, when the slice is ambiguous,
/// the sign of `q` (`None` otherwise).
type Slice = ([bool; 4], Option<i32>);

/// Corner groups of a sign class: `label[c]` is the smallest corner of `c`'s group (corners
/// of the other sign get `u8::MAX`).
type Groups = [u8; 8];

/// The corners `(cube corner at t = 0, cube corner at t = 1)` of sweep edge `k` when sweeping
/// along `axis`; slice corners in cyclic order `(0,0), (1,0), (1,1), (0,1)` over the other two
/// axes in increasing order.
fn sweep_edges(axis: usize) -> [[usize; 2]; 4] {
    let (u, w) = match axis {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    };
    [(0, 0), (1, 0), (1, 1), (0, 1)].map(|(a, b)| {
        [0, 1].map(|t| {
            let mut p = [0u8; 3];
            p[u] = a;
            p[w] = b;
            p[axis] = t;
            CORNERS.iter().position(|c| *c == p).expect("a corner")
        })
    })
}

/// The trilinear interpolant's corner groups (positive, negative) for corner values `v`
/// (nonzero integers), sweeping along `axis`.
fn trilinear_groups(v: &[i64; 8], axis: usize) -> (Groups, Groups) {
    let edges = sweep_edges(axis);
    let e: [(i64, i64); 4] = edges.map(|[a, b]| (v[a], v[b] - v[a])); // e_k(t) = v + t δ
    let q = Quad {
        a: (e[0].1 * e[2].1 - e[1].1 * e[3].1) as i128,
        b: (e[0].0 * e[2].1 + e[2].0 * e[0].1 - e[1].0 * e[3].1 - e[3].0 * e[1].1) as i128,
        c: (e[0].0 * e[2].0 - e[1].0 * e[3].0) as i128,
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
            let k = edges
                .iter()
                .position(|ed| ed.contains(&c))
                .expect("on a sweep edge");
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
                .expect("itself") as u8;
        }
        label
    };
    (groups(true), groups(false))
}

/// The table entry's corner groups (positive, negative): along cube edges, and across
/// ambiguous faces by the entry's decision.
fn table_groups(config: u8, sub: u8) -> (Groups, Groups) {
    let e = table().entry(config, sub);
    let pos = |c: usize| config >> c & 1 == 1;
    let groups = |positive: bool| -> Groups {
        let mut dsu = Dsu::new(8);
        for [a, b] in EDGES {
            let (a, b) = (a as usize, b as usize);
            if pos(a) == positive && pos(b) == positive {
                dsu.union(a, b);
            }
        }
        for &f in &e.ambiguous {
            let c = FACES[f as usize].corners.map(|x| x as usize);
            if e.joined(f) == positive {
                let (a, b) = if pos(c[0]) == positive {
                    (c[0], c[2])
                } else {
                    (c[1], c[3])
                };
                dsu.union(a, b);
            }
        }
        let mut label = [u8::MAX; 8];
        for (c, l) in label.iter_mut().enumerate() {
            if pos(c) == positive {
                let r = dsu.find(c);
                *l = (0..8)
                    .find(|&d| pos(d) == positive && dsu.find(d) == r)
                    .expect("itself") as u8;
            }
        }
        label
    };
    (groups(true), groups(false))
}

/// Whether `fine` refines into `coarse`: every group of `fine` lies inside one of `coarse`.
fn coarsens(coarse: &Groups, fine: &Groups) -> bool {
    (0..8)
        .all(|c| (0..8).all(|d| fine[c] == u8::MAX || fine[c] != fine[d] || coarse[c] == coarse[d]))
}

/// The face decisions of a trilinear cell by the product rule, `None` on a tie.
fn decisions(config: u8, v: &[i64; 8]) -> Option<u8> {
    let mut sub = 0u8;
    for (j, &f) in ambiguous_faces(config).iter().enumerate() {
        let c = FACES[f as usize].corners.map(|x| x as usize);
        let (d0, d1) = (v[c[0]] * v[c[2]], v[c[1]] * v[c[3]]);
        let (p, n) = if v[c[0]] >= 0 { (d0, d1) } else { (d1, d0) };
        match p.cmp(&n) {
            Ordering::Equal => return None,
            Ordering::Greater => sub |= 1 << j,
            Ordering::Less => {}
        }
    }
    Some(sub)
}

/// The body-ambiguity measurement, with corner magnitudes from `mags`. Every enumerated
/// trilinear cell (ties on faces skipped) must group its corners as the table entry of its
/// decisions does or coarser, and the sweeps along `x` and `z` must agree. Returns the proof
/// and the number of entries some cell connects differently (a tunnel).
pub fn body_ambiguity(mags: &[i64]) -> (ProofOutcome, usize) {
    let (p, tunnel) = body_witnesses(mags);
    (p, tunnel.iter().filter(|&&b| b).count())
}

/// [`body_ambiguity`] with the per-entry witness flags (table order).
pub fn body_witnesses(mags: &[i64]) -> (ProofOutcome, Vec<bool>) {
    let p = body_slice(mags, Shard::WHOLE);
    let mut tunnel = p.detail.flag_set("tunnel").to_vec();
    tunnel.resize(table().entries.len(), false);
    (p, tunnel)
}

/// One slice of the measurement (one part per configuration); the entries with a tunnel
/// witness are the flag set `tunnel`.
pub fn body_slice(mags: &[i64], shard: Shard) -> ProofOutcome {
    let mut t = Tally::new(
        "mc.table-body-ambiguity",
        &format!(
            "trilinear cells with corner magnitudes in {mags:?} ({}⁸ per configuration, face ties skipped): interior corner groups from plane sweeps along z and x agree, and coarsen the table entry's groups",
            mags.len()
        ),
        shard,
    );
    let tab = table();
    let entries = tab.entries.len();
    let mut tunnel = vec![false; entries];
    for config in 0..=255u8 {
        if !t.owns(config as u64) {
            continue;
        }
        let mut idx = [0usize; 8];
        loop {
            let v: [i64; 8] = std::array::from_fn(|c| {
                if config >> c & 1 == 1 {
                    mags[idx[c]]
                } else {
                    -mags[idx[c]]
                }
            });
            if let Some(sub) = decisions(config, &v) {
                let (tp, tn) = table_groups(config, sub);
                let (zp, zn) = trilinear_groups(&v, 2);
                let (xp, xn) = trilinear_groups(&v, 0);
                let ok = zp == xp && zn == xn && coarsens(&zp, &tp) && coarsens(&zn, &tn);
                t.check(ok, || {
                    format!("config {config} sub {sub} values {v:?}: table {tp:?}/{tn:?}, sweep z {zp:?}/{zn:?}, x {xp:?}/{xn:?}")
                });
                if zp != tp || zn != tn {
                    tunnel[tab.offsets[config as usize] as usize + sub as usize] = true;
                }
            }
            let mut i = 0;
            while i < 8 {
                idx[i] += 1;
                if idx[i] < mags.len() {
                    break;
                }
                idx[i] = 0;
                i += 1;
            }
            if i == 8 {
                break;
            }
        }
    }
    for (i, _) in tunnel.iter().enumerate().filter(|(_, &b)| b) {
        t.flag("tunnel", entries, i);
    }
    t.finish()
}

/// Entries that could have a tunnel at all: two or more corner groups of one sign in the
/// table (a tunnel joins two groups). An upper bound for [`body_ambiguity`]'s count among
/// the entries a trilinear cell realises.
pub fn tunnel_candidates() -> Vec<bool> {
    let tab = table();
    tab.entries
        .iter()
        .map(|e| {
            let (p, n) = table_groups(e.config, e.sub);
            let count = |g: &Groups| {
                (0..8)
                    .filter(|&c| g[c] != u8::MAX && g[c] as usize == c)
                    .count()
            };
            count(&p) >= 2 || count(&n) >= 2
        })
        .collect()
}

/// The corner magnitudes of the published measurement. Geometric sets (1, 3, 9, 27;
/// 1, 2, 5, 25) and 1, 2, 3, 5, 8 witness no entry beyond these.
pub const MAGNITUDES: [i64; 4] = [1, 2, 3, 4];

/// The measurement with [`MAGNITUDES`], computed once per process: the proof and the number
/// of entries with a tunnel witness.
pub fn measured() -> &'static (ProofOutcome, usize) {
    measured_cell().get_or_init(|| body_ambiguity(&MAGNITUDES))
}

/// Takes the measurement from a merged run of slices ([`super::merge`]) instead of running it
/// here, when it has not run in this process yet.
pub fn preset(merged: ProofOutcome) {
    let tunnels = merged
        .detail
        .flag_set("tunnel")
        .iter()
        .filter(|&&b| b)
        .count();
    let _ = measured_cell().set((merged, tunnels));
}

fn measured_cell() -> &'static std::sync::OnceLock<(ProofOutcome, usize)> {
    static M: std::sync::OnceLock<(ProofOutcome, usize)> = std::sync::OnceLock::new();
    &M
}

/// The proof alone: the measurement of [`MAGNITUDES`] (computed once per process when whole).
pub fn body(shard: Shard) -> ProofOutcome {
    if shard == Shard::WHOLE {
        measured().0.clone()
    } else {
        body_slice(&MAGNITUDES, shard)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_body_diagonal_tunnel() {
        // Corners 0 and 6 strongly positive, the rest weakly negative: a tube joins them.
        let mut v = [-1i64; 8];
        v[0] = 8;
        v[6] = 8;
        let (p, _) = trilinear_groups(&v, 2);
        assert_eq!(p[0], p[6], "joined through the interior");
        let (tp, _) = table_groups(0b0100_0001, 0);
        assert_ne!(tp[0], tp[6], "the table keeps them apart");
        // Weakly positive corners stay apart.
        let mut w = [-8i64; 8];
        w[0] = 1;
        w[6] = 1;
        let (p, _) = trilinear_groups(&w, 2);
        assert_ne!(p[0], p[6]);
    }
}
