//! Proofs of the marching-cubes table (Wünsche & Lin): coverage, edges, face pairings against
//! Mackerras' sorting rule on exact witness values, local winding at random rational edge
//! points, watertightness across every face of every pair of entries that can meet, and
//! symmetry under the 48 cube symmetries and sign inversion.

use super::{Lcg, ProofOutcome, Shard, Tally};
use crate::mc::table::{
    ambiguous_faces, corner_across, edge_across, face_edges, face_on, face_segments, is_cut, table,
    Entry, CORNERS, EDGES, FACES,
};
use crate::num::Rational;
use num_traits::{One, Zero};
use std::collections::BTreeSet;

/// (1) One entry per (configuration, subconfiguration); 656 in all; per ambiguous-face count
/// 136, 72, 30, 16 and 2 configurations.
pub fn coverage(shard: Shard) -> ProofOutcome {
    let mut t = Tally::new(
        "mc.table-coverage",
        "256 configurations × 2^k subconfigurations; total 656; configurations with 0/1/2/3/6 ambiguous faces = 136/72/30/16/2",
        shard,
    );
    if !t.owns(0) {
        return t.finish();
    }
    let tab = table();
    let mut by_k = [0usize; 7];
    for config in 0..=255u8 {
        let k = ambiguous_faces(config).len();
        by_k[k] += 1;
        for sub in 0..(1u16 << k) {
            let e = tab.entry(config, sub as u8);
            t.check(e.config == config && e.sub == sub as u8, || {
                format!("entry ({config}, {sub}) holds ({}, {})", e.config, e.sub)
            });
        }
    }
    t.check(tab.entries.len() == 656, || {
        format!("{} entries", tab.entries.len())
    });
    t.check(by_k == [136, 72, 30, 16, 0, 0, 2], || {
        format!("configurations per ambiguous-face count {by_k:?}")
    });
    t.finish()
}

/// (2) Every cut edge is used exactly once, no uncut edge is used, every polygon has ≥ 3
/// vertices.
pub fn edges(shard: Shard) -> ProofOutcome {
    let mut t = Tally::new(
        "mc.table-edges",
        "656 entries: each cut edge in exactly one polygon once, no uncut edge, polygons of ≥ 3 vertices, triangulated for extraction without a chord inside a cube face",
        shard,
    );
    if !t.owns(0) {
        return t.finish();
    }
    for e in &table().entries {
        let mut count = [0usize; 12];
        for p in &e.polygons {
            for &x in p {
                count[x as usize] += 1;
            }
        }
        let ok = (0..12u8).all(|x| count[x as usize] == usize::from(is_cut(e.config, x)))
            && e.polygons.iter().all(|p| p.len() >= 3)
            && e.triangles_with_centres().iter().all(|t| {
                (0..3).all(|k| {
                    let (a, b) = (t[k], t[(k + 1) % 3]);
                    // Every side is a polygon side, touches a centre, or shares no face.
                    a >= crate::mc::table::CENTRE
                        || b >= crate::mc::table::CENTRE
                        || e.polygons.iter().any(|p| {
                            (0..p.len()).any(|i| {
                                let (x, y) = (p[i], p[(i + 1) % p.len()]);
                                (x, y) == (a, b) || (y, x) == (a, b)
                            })
                        })
                        || !crate::mc::table::share_face(a, b)
                })
            });
        t.check(ok, || {
            format!("config {} sub {}: edge use {count:?}", e.config, e.sub)
        });
    }
    t.finish()
}

/// Face coordinates `(ξ₁, ξ₂)` of face corner `k` (cyclic order).
const FACE_UV: [[i64; 2]; 4] = [[0, 0], [1, 0], [1, 1], [0, 1]];

/// Mackerras' rule on exact values: the cut points of the face's edges, sorted along ξ₁; the
/// first two and the last two are joined. Returns the pairs as sets of edge ids.
fn mackerras_pairs(face: usize, values: [Rational; 4]) -> BTreeSet<BTreeSet<u8>> {
    let edges = face_edges(&FACES[face]);
    let mut pts: Vec<(Rational, u8)> = Vec::new();
    for k in 0..4 {
        let (a, b) = (&values[k], &values[(k + 1) % 4]);
        if (a >= &Rational::zero()) == (b >= &Rational::zero()) {
            continue;
        }
        let t = -a / (b - a);
        let (u0, u1) = (FACE_UV[k][0], FACE_UV[(k + 1) % 4][0]);
        let xi1 = Rational::from_integer(u0.into()) + &t * Rational::from_integer((u1 - u0).into());
        pts.push((xi1, edges[k]));
    }
    pts.sort();
    pts.chunks(2)
        .map(|p| p.iter().map(|(_, e)| *e).collect())
        .collect()
}

/// The table's pairing on a face (undirected).
fn table_pairs(e: &Entry, face: u8) -> BTreeSet<BTreeSet<u8>> {
    face_segments(e.config, face, e.joined(face))
        .iter()
        .map(|s| [s.from, s.to].into_iter().collect())
        .collect()
}

/// (3) Consecutive polygon vertices share a face; on every face the segments pair the cut
/// points exactly as the bilinear interpolant does, checked by Mackerras' rule on exact
/// witness values that realise the entry's decision (positive corners `3`, negative `−1`:
/// joined, since `3·3 > (−1)(−1)`; or `1` and `−3`: separated).
pub fn faces(shard: Shard) -> ProofOutcome {
    let mut t = Tally::new(
        "mc.table-faces",
        "656 entries × 6 faces: polygon steps stay on one face; pairing = Mackerras' sort on exact witness values",
        shard,
    );
    if !t.owns(0) {
        return t.finish();
    }
    for e in &table().entries {
        let steps_on_faces = e.polygons.iter().all(|p| {
            (0..p.len()).all(|i| {
                let (a, b) = (p[i], p[(i + 1) % p.len()]);
                FACES.iter().any(|f| {
                    let fe = face_edges(f);
                    fe.contains(&a) && fe.contains(&b)
                })
            })
        });
        t.check(steps_on_faces, || {
            format!("config {} sub {}: a step leaves its face", e.config, e.sub)
        });
        for (fi, f) in FACES.iter().enumerate() {
            let joined = e.joined(fi as u8);
            let (pos, neg) = if joined { (3, -1) } else { (1, -3) };
            let values = f.corners.map(|c| {
                Rational::from_integer(if e.config >> c & 1 == 1 { pos } else { neg }.into())
            });
            let expect = mackerras_pairs(fi, values);
            let got = table_pairs(e, fi as u8);
            t.check(expect == got, || {
                format!(
                    "config {} sub {} face {fi}: table {got:?}, Mackerras {expect:?}",
                    e.config, e.sub
                )
            });
        }
    }
    t.finish()
}

fn point_on_edge(e: u8, t: &Rational) -> [Rational; 3] {
    let [a, b] = EDGES[e as usize];
    [0, 1, 2].map(|i| {
        let pa = Rational::from_integer((CORNERS[a as usize][i] as i64).into());
        let pb = Rational::from_integer((CORNERS[b as usize][i] as i64).into());
        &pa + t * (pb - &pa)
    })
}

fn sub3(a: &[Rational; 3], b: &[Rational; 3]) -> [Rational; 3] {
    [0, 1, 2].map(|i| &a[i] - &b[i])
}

/// (4) Winding: each segment, with its end points at random rational positions on their edges
/// (exact), has the face's positive corners on its right and negative ones on its left as
/// seen from outside; on an ambiguous face, the single corner a segment cuts off is on its
/// right exactly when positive. Each polygon is a closed directed cycle (checked by 2).
pub fn orientation(shard: Shard) -> ProofOutcome {
    let mut t = Tally::new(
        "mc.table-orientation",
        "656 entries × every segment × 4 random rational placements of the cut points: exact side tests",
        shard,
    );
    if !t.owns(0) {
        return t.finish();
    }
    let mut rng = Lcg::new(656);
    for e in &table().entries {
        for round in 0..4 {
            let ts: Vec<Rational> = (0..12)
                .map(|_| {
                    let d = 2 + (rng.next() % 97) as i64;
                    let n = 1 + (rng.next() % (d as u64 - 1)) as i64;
                    Rational::new(n.into(), d.into())
                })
                .collect();
            for s in e.segments() {
                let f = &FACES[s.face as usize];
                let p = point_on_edge(s.from, &ts[s.from as usize]);
                let q = point_on_edge(s.to, &ts[s.to as usize]);
                let d = sub3(&q, &p);
                let mut n: [Rational; 3] = Default::default();
                n[f.axis] = if f.side == 1 {
                    Rational::one()
                } else {
                    -Rational::one()
                };
                let dn = [
                    &d[1] * &n[2] - &d[2] * &n[1],
                    &d[2] * &n[0] - &d[0] * &n[2],
                    &d[0] * &n[1] - &d[1] * &n[0],
                ];
                // Right of the segment (seen from outside): (d × n)·(x − p) < 0.
                let right = |c: u8| {
                    let x = CORNERS[c as usize].map(|v| Rational::from_integer((v as i64).into()));
                    let r = sub3(&x, &p);
                    (&dn[0] * &r[0] + &dn[1] * &r[1] + &dn[2] * &r[2]) < Rational::zero()
                };
                let pos = |c: u8| e.config >> c & 1 == 1;
                let (rs, ls): (Vec<u8>, Vec<u8>) = f.corners.iter().partition(|&&c| right(c));
                let ok = if ambiguous_faces(e.config).contains(&s.face) {
                    let single = if rs.len() == 1 {
                        Some((rs[0], true))
                    } else if ls.len() == 1 {
                        Some((ls[0], false))
                    } else {
                        None
                    };
                    single.is_some_and(|(w, on_right)| on_right == pos(w))
                } else {
                    rs.iter().all(|&c| pos(c)) && ls.iter().all(|&c| !pos(c))
                };
                t.check(ok, || {
                    format!(
                        "config {} sub {} round {round}: segment {s:?} right {rs:?} left {ls:?}",
                        e.config, e.sub
                    )
                });
            }
        }
    }
    t.finish()
}

/// (5) Watertight: for every axis and every pair of entries that can meet across it (the same
/// corner signs on the shared face and the same decision there), the segments on the shared
/// face coincide with opposite orientation.
pub fn watertight(shard: Shard) -> ProofOutcome {
    let mut t = Tally::new(
        "mc.table-watertight",
        "3 axes × every pair of entries with matching signs and decision on the shared face: segments coincide, opposite direction",
        shard,
    );
    if !t.owns(0) {
        return t.finish();
    }
    let tab = table();
    for axis in 0..3 {
        let (hi, lo) = (face_on(axis, 1), face_on(axis, 0));
        // Group the side-0 faces of all entries by (signs on the face, decision).
        let key = |config: u8, face: u8, corners_of: &dyn Fn(u8) -> u8, joined: bool| {
            let f = &FACES[face as usize];
            let mut signs: Vec<(u8, bool)> = f
                .corners
                .iter()
                .map(|&c| (corners_of(c), config >> c & 1 == 1))
                .collect();
            signs.sort();
            (signs, joined)
        };
        let mut groups: std::collections::HashMap<_, Vec<&Entry>> = Default::default();
        for e in &tab.entries {
            let k = key(e.config, lo, &|c| c, e.joined(lo));
            groups.entry(k).or_default().push(e);
        }
        for e1 in &tab.entries {
            let k = key(e1.config, hi, &|c| corner_across(c, axis), e1.joined(hi));
            let mine: BTreeSet<(u8, u8)> = face_segments(e1.config, hi, e1.joined(hi))
                .iter()
                .map(|s| (edge_across(s.from, axis), edge_across(s.to, axis)))
                .collect();
            for e2 in groups.get(&k).map(|v| v.as_slice()).unwrap_or(&[]) {
                let theirs: BTreeSet<(u8, u8)> = face_segments(e2.config, lo, e2.joined(lo))
                    .iter()
                    .map(|s| (s.to, s.from))
                    .collect();
                t.check(mine == theirs, || {
                    format!(
                        "axis {axis}: ({}, {}) against ({}, {}): {mine:?} vs reversed {theirs:?}",
                        e1.config, e1.sub, e2.config, e2.sub
                    )
                });
            }
        }
    }
    t.finish()
}

/// The 48 symmetries of the cube as corner permutations, with whether each preserves
/// orientation.
pub(super) fn cube_symmetries() -> Vec<([u8; 8], bool)> {
    let perms = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    let mut out = Vec::new();
    for p in perms {
        // Parity of the axis permutation.
        let inversions = (0..3)
            .flat_map(|i| (i + 1..3).map(move |j| (i, j)))
            .filter(|&(i, j)| p[i] > p[j])
            .count();
        for flips in 0..8u8 {
            let map = [0u8, 1, 2, 3, 4, 5, 6, 7].map(|c| {
                let x = CORNERS[c as usize];
                let mut y = [0u8; 3];
                for a in 0..3 {
                    y[a] = x[p[a]];
                    if flips >> a & 1 == 1 {
                        y[a] = 1 - y[a];
                    }
                }
                CORNERS.iter().position(|q| *q == y).expect("a corner") as u8
            });
            let proper = (inversions + flips.count_ones() as usize).is_multiple_of(2);
            out.push((map, proper));
        }
    }
    out
}

/// Cycles as a set of sequences rotated to start at their least edge.
fn canonical(polys: &[Vec<u8>]) -> BTreeSet<Vec<u8>> {
    polys
        .iter()
        .map(|p| {
            let i = (0..p.len()).min_by_key(|&i| p[i]).unwrap_or(0);
            p[i..].iter().chain(&p[..i]).copied().collect()
        })
        .collect()
}

/// (6) Symmetry: under each of the 48 cube symmetries, and under sign inversion, every entry
/// maps onto the entry of the image configuration with the image decisions, polygon for
/// polygon (reversed under orientation-reversing maps and under inversion).
pub fn symmetry(shard: Shard) -> ProofOutcome {
    let mut t = Tally::new(
        "mc.table-symmetry",
        "656 entries × (48 cube symmetries + sign inversion): image entry = mapped polygons",
        shard,
    );
    if !t.owns(0) {
        return t.finish();
    }
    let tab = table();
    let face_map = |map: &[u8; 8], f: u8| -> u8 {
        let img: BTreeSet<u8> = FACES[f as usize]
            .corners
            .iter()
            .map(|&c| map[c as usize])
            .collect();
        FACES
            .iter()
            .position(|g| g.corners.iter().copied().collect::<BTreeSet<u8>>() == img)
            .expect("a face") as u8
    };
    for (map, proper) in cube_symmetries() {
        let edge_map = |e: u8| {
            let [a, b] = EDGES[e as usize];
            crate::mc::table::edge_between(map[a as usize], map[b as usize]).expect("an edge")
        };
        for e in &tab.entries {
            let config = (0..8u8)
                .filter(|&c| e.config >> c & 1 == 1)
                .fold(0u8, |acc, c| acc | 1 << map[c as usize]);
            let amb = ambiguous_faces(config);
            let sub = e
                .ambiguous
                .iter()
                .filter(|&&f| e.joined(f))
                .map(|&f| {
                    amb.iter()
                        .position(|&g| g == face_map(&map, f))
                        .expect("ambiguous")
                })
                .fold(0u8, |acc, j| acc | 1 << j);
            let mapped: Vec<Vec<u8>> = e
                .polygons
                .iter()
                .map(|p| {
                    let mut q: Vec<u8> = p.iter().map(|&x| edge_map(x)).collect();
                    if !proper {
                        q.reverse();
                    }
                    q
                })
                .collect();
            let target = tab.entry(config, sub);
            t.check(canonical(&mapped) == canonical(&target.polygons), || {
                format!("config {} sub {} under {map:?}", e.config, e.sub)
            });
        }
    }
    for e in &tab.entries {
        let config = !e.config;
        let k = e.ambiguous.len();
        let sub = if k == 0 {
            0
        } else {
            !e.sub & ((1u16 << k) - 1) as u8
        };
        let mapped: Vec<Vec<u8>> = e
            .polygons
            .iter()
            .map(|p| p.iter().rev().copied().collect())
            .collect();
        t.check(
            canonical(&mapped) == canonical(&tab.entry(config, sub).polygons),
            || format!("config {} sub {} under inversion", e.config, e.sub),
        );
    }
    t.finish()
}

/// Which face-decision patterns of a configuration trilinear cells realise: corner values
/// `±m` with magnitudes `m ∈ 1..=4` (isovalue 0) are enumerated and each face decided by the
/// product rule (positive corners joined iff the positive diagonal's product exceeds the
/// negative one's; ties skipped). Returns one bit per subconfiguration.
pub fn realised_patterns(config: u8) -> Vec<bool> {
    let amb = ambiguous_faces(config);
    let mut seen = vec![false; 1 << amb.len()];
    if amb.is_empty() {
        seen[0] = true;
        return seen;
    }
    let mut mags = [1i64; 8];
    loop {
        let mut sub = 0usize;
        let mut tie = false;
        for (j, &f) in amb.iter().enumerate() {
            let c = FACES[f as usize].corners;
            // Alternating face: corners 0, 2 share a sign, as do 1, 3.
            let (d0, d1) = (
                mags[c[0] as usize] * mags[c[2] as usize],
                mags[c[1] as usize] * mags[c[3] as usize],
            );
            let (pos, neg) = if config >> c[0] & 1 == 1 {
                (d0, d1)
            } else {
                (d1, d0)
            };
            if pos == neg {
                tie = true;
                break;
            }
            if pos > neg {
                sub |= 1 << j;
            }
        }
        if !tie {
            seen[sub] = true;
        }
        // Next magnitude vector.
        let mut i = 0;
        while i < 8 {
            mags[i] += 1;
            if mags[i] <= 4 {
                break;
            }
            mags[i] = 1;
            i += 1;
        }
        if i == 8 {
            return seen;
        }
    }
}

/// Whether a pattern has a certificate of impossibility: two opposite faces both joined and
/// two other opposite faces both separated. (With `x`, `y` the logarithms of the positive and
/// negative magnitudes, a face is joined iff `x_i + x_j > y_k + y_l`; a pair of opposite faces
/// covers all 8 corners, so both joined means `Σx > Σy` and both separated `Σx < Σy`.)
fn impossible(entry: &Entry) -> bool {
    let pair_state = |axis: usize| -> Option<bool> {
        let faces: Vec<u8> = (0..6u8)
            .filter(|&f| FACES[f as usize].axis == axis)
            .collect();
        let both_amb = faces.iter().all(|f| entry.ambiguous.contains(f));
        if !both_amb {
            return None;
        }
        let (a, b) = (entry.joined(faces[0]), entry.joined(faces[1]));
        (a == b).then_some(a)
    };
    let states: Vec<bool> = (0..3).filter_map(pair_state).collect();
    states.contains(&true) && states.contains(&false)
}

/// (7) What the table does not guarantee: the entries no trilinear cell produces. Every entry
/// is either realised by an enumerated trilinear witness or carries the opposite-faces
/// certificate of impossibility — never both, never neither. Returns the proof and the
/// number of unrealisable entries (also its counter `unrealisable`).
pub fn trilinear_realisability() -> (ProofOutcome, usize) {
    let p = trilinear_realisability_slice(Shard::WHOLE);
    let n = p.detail.counter("unrealisable") as usize;
    (p, n)
}

/// [`trilinear_realisability`] on one slice (one part per configuration).
pub fn trilinear_realisability_slice(shard: Shard) -> ProofOutcome {
    let mut t = Tally::new(
        "mc.table-trilinear-realisability",
        "656 entries: a trilinear witness (corner magnitudes 1…4, 4⁸ per configuration) xor the opposite-faces certificate of impossibility",
        shard,
    );
    let tab = table();
    for config in 0..=255u8 {
        if !t.owns(config as u64) {
            continue;
        }
        let seen = realised_patterns(config);
        for (sub, &realised) in seen.iter().enumerate() {
            let e = tab.entry(config, sub as u8);
            let cert = impossible(e);
            t.count("unrealisable", u64::from(cert));
            t.check(realised != cert, || {
                format!("config {config} sub {sub}: realised {realised}, certificate {cert}")
            });
        }
    }
    t.finish()
}

/// The proof of 7 as a plain proof.
pub fn trilinear(shard: Shard) -> ProofOutcome {
    trilinear_realisability_slice(shard)
}

/// Exact comparison of `p/q` with `r/s` (any signs, `q, s ≠ 0`): the sign of `p/q − r/s`.
fn cmp_fraction(p: i128, q: i128, r: i128, s: i128) -> std::cmp::Ordering {
    let (p, q) = if q < 0 { (-p, -q) } else { (p, q) };
    let (r, s) = if s < 0 { (-r, -s) } else { (r, s) };
    (p * s).cmp(&(r * q))
}

/// Mackerras' rule (the paper's Section 4.1): the cut points along `ξ₁`; `Some(true)` when the
/// cut-off corners are the negative ones (positive joined), `None` on a tie.
fn mackerras(a: i128, b: i128, c: i128, d: i128) -> Option<bool> {
    // Cut points on A–B (ξ₂ = 0) and C–D (ξ₂ = 1): ξ₁ = a/(a−b), c/(c−d). The points on
    // A–C (ξ₁ = 0) and B–D (ξ₁ = 1) sort first and last; the first pair isolates A when the
    // A–B point comes before the C–D point (and then the last pair isolates D).
    match cmp_fraction(a, a - b, c, c - d) {
        std::cmp::Ordering::Equal => None,
        std::cmp::Ordering::Less => Some(a < 0), // A, D cut off: joined iff they are negative
        std::cmp::Ordering::Greater => Some(b < 0), // B, C cut off
    }
}

/// The product rule: positive diagonal's product against the negative one's.
fn product_rule(a: i128, b: i128, c: i128, d: i128) -> Option<bool> {
    let (pos, neg) = if a >= 0 {
        (a * d, b * c)
    } else {
        (b * c, a * d)
    };
    (pos != neg).then_some(pos > neg)
}

/// The asymptotic decider on the values themselves: the saddle value `(AD − BC)/(A+D−B−C)`
/// against the isovalue, with `a, …` and the isovalue `n` all scaled by the isovalue's
/// denominator (`m·A = a + n`).
fn asymptotic(a: i128, b: i128, c: i128, d: i128, n: i128) -> Option<bool> {
    let (va, vb, vc, vd) = (a + n, b + n, c + n, d + n); // m·A, …
    let num = va * vd - vb * vc; // m²(AD − BC)
    let den = va + vd - vb - vc; // m(A + D − B − C), nonzero on an ambiguous face
                                 // S > iso ⇔ num/(m·den) > n/m ⇔ num/den > n.
    match cmp_fraction(num, den, n, 1) {
        std::cmp::Ordering::Equal => None,
        o => Some(o == std::cmp::Ordering::Greater),
    }
}

/// Face ambiguity, exhaustively: for every integer face `A, B, C, D ∈ [−R, R]⁴` (R = 40) and
/// isovalues `0` and `1/3`, on every ambiguous face Mackerras' sort, the product rule and the
/// asymptotic decider agree (ties included: each reports a tie exactly when the others do);
/// the library's exact decider (integer entry point on every face, rational entry point on
/// every tie and every 64th face) equals them off ties and is `joined` on ties; the certified
/// `f64` decider never contradicts the exact decision at the isovalue it sees.
///
/// Why they must agree: with `a = A − c` etc., `ξ₁(A–B) − ξ₁(C–D) = (bc − ad)/((a−b)(c−d))`
/// whose denominator is negative on an ambiguous face, so Mackerras isolates `A, D` exactly
/// when `ad < bc`; and `ad − bc = (a + d − b − c)(S − c)` with `a + d − b − c` of the sign of
/// `a`, so `S > c` exactly when the positive diagonal's product is the larger.
pub fn face_deciders(shard: Shard) -> ProofOutcome {
    const R: i64 = 40;
    let mut t = Tally::new(
        "mc.face-deciders",
        "all integer faces in [−40, 40]⁴ at isovalues 0 and 1/3 (2 × 81⁴ faces; the ambiguous ones checked): Mackerras = product rule = asymptotic decider, ties alike; exact decider and certified f64 decider consistent",
        shard,
    );
    let (mut ambiguous, mut ties, mut uncertain) = (0u64, 0u64, 0u64);
    for (iso_index, (n, m)) in [(0i128, 1i128), (1, 3)].into_iter().enumerate() {
        let iso = Rational::new((n as i64).into(), (m as i64).into());
        let iso_f64 = n as f64 / m as f64;
        let iso_rounded = crate::num::rational_from_f64(iso_f64, "isovalue").expect("finite");
        // The rounded isovalue is dyadic, p/2^k with k ≤ 54: scaled values stay within i128.
        let (iso_num, iso_den): (i128, i128) = (
            i128::try_from(iso_rounded.numer()).expect("small"),
            i128::try_from(iso_rounded.denom()).expect("small"),
        );
        for va in -R..=R {
            // One part per isovalue and first corner value.
            if !t.owns(iso_index as u64 * (2 * R + 1) as u64 + (va + R) as u64) {
                continue;
            }
            for vb in -R..=R {
                for vc in -R..=R {
                    for vd in -R..=R {
                        // Scaled by m: a = m·A − n (the isovalue n/m); sign rule a ≥ 0.
                        let s = |v: i64| m * v as i128 - n;
                        let (a, b, c, d) = (s(va), s(vb), s(vc), s(vd));
                        let amb =
                            (a >= 0) == (d >= 0) && (b >= 0) == (c >= 0) && (a >= 0) != (b >= 0);
                        if !amb {
                            continue;
                        }
                        ambiguous += 1;
                        let mk = mackerras(a, b, c, d);
                        let pr = product_rule(a, b, c, d);
                        let asy = asymptotic(a, b, c, d, n);
                        let exact = Some(crate::mc::decider::decide_shifted(&a, &b, &c, &d));
                        // The rational entry point on every tie and on a fixed 1/64 of the faces (by a hash
                        // of the values, so that every slice samples the same faces).
                        let sampled = pr.is_none() || (a + 7 * b + 13 * c + 29 * d) % 64 == 0;
                        let vals = [va, vb, vc, vd].map(|x| Rational::from_integer(x.into()));
                        let rational_ok = !sampled
                            || crate::mc::decider::decide_exact(
                                [&vals[0], &vals[1], &vals[2], &vals[3]],
                                &iso,
                            ) == exact;
                        // The f64 decider sees the rounded isovalue: compare it with the exact
                        // decision at that same value.
                        let fast = crate::mc::decider::decide_fast(
                            [va, vb, vc, vd].map(|x| x as f64),
                            iso_f64,
                        );
                        let r = |v: i64| iso_den * v as i128 - iso_num;
                        let (ra, rb, rc, rd) = (r(va), r(vb), r(vc), r(vd));
                        let at_rounded = ((ra >= 0) == (rd >= 0)
                            && (rb >= 0) == (rc >= 0)
                            && (ra >= 0) != (rb >= 0))
                            .then(|| crate::mc::decider::decide_shifted(&ra, &rb, &rc, &rd));
                        if pr.is_none() {
                            ties += 1;
                        }
                        if fast.is_none() {
                            uncertain += 1;
                        }
                        let ok = mk == pr
                            && pr == asy
                            && exact == Some(pr.unwrap_or(true))
                            && rational_ok
                            && fast.is_none_or(|f| f == at_rounded);
                        t.check(ok, || {
                            format!(
                                "A,B,C,D = {va},{vb},{vc},{vd} at {n}/{m}: Mackerras {mk:?}, product {pr:?}, asymptotic {asy:?}, exact {exact:?}, f64 {fast:?}"
                            )
                        });
                    }
                }
            }
        }
    }
    t.count("ambiguous", ambiguous);
    t.count("ties", ties);
    t.count("uncertain", uncertain);
    t.template("{ambiguous} ambiguous faces, {ties} ties (joined by the tie rule), f64 uncertain on {uncertain}");
    t.finish()
}
