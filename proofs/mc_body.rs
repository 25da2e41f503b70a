//! Body (interior) ambiguity: which table entries a trilinear interpolant may connect
//! differently inside the cell (tunnels), measured exactly on enumerated trilinear cells.
//!
//! The table fills every boundary loop with a disc, so its positive region's components are
//! the groups of positive corners joined along cube edges and across joined ambiguous faces
//! (likewise the negative region, across faces that are not joined). A trilinear interpolant
//! has no interior extrema, so its regions can only be coarser: a tunnel joins two groups.
//!
//! The interpolant's groups come from the event sweep of [`crate::mc::trilinear::sweep`]
//! along z and along x, which must agree.

use super::{ProofOutcome, Shard, Tally};
use crate::mc::table::{ambiguous_faces, table, EDGES, FACES};
use crate::mc::trilinear::sweep::{sweep_groups, Dsu};
use crate::mc::trilinear::Groups;
use std::cmp::Ordering;

/// The sweep's groups as a pair (magnitudes here are far below the sweep's limit).
fn trilinear_groups(v: &[i64; 8], axis: usize) -> (Groups, Groups) {
    let [p, n] = sweep_groups(v, axis).unwrap_or([[u8::MAX; 8]; 2]);
    (p, n)
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
