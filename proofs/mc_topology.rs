//! The trilinear topology oracle against the independent event sweep, on every integer cell
//! of a cube of corner values at two isovalues: one where corners may equal the isovalue and
//! saddles may sit on the level (every tie rule exercised), and one where no corner can.

use super::{Lcg, ProofOutcome, Shard, Tally};
use crate::mc::table::table;
use crate::mc::trilinear::polygonise::{cell_mesh, check_cell_mesh};
use crate::mc::trilinear::sweep::sweep_groups;
use crate::mc::trilinear::{
    cell_topology_exact, cell_topology_fast, shifted_integers, topology_of_small, verify_cell,
};
use crate::num::{rational_to_f64, Rational};
use num_traits::ToPrimitive;
use std::collections::HashSet;

/// Random rational cells (values `n/d`, `|n| ≤ 40`, `d ≤ 4`, and a random isovalue of the
/// same kind): how many, in how many parts, and every how many the certificate checker
/// re-verifies.
pub const RANDOM_CELLS: usize = 200_000;
const RANDOM_PARTS: usize = 20;
const CHECK_EVERY: usize = 64;
const SYMMETRY_EVERY: usize = 16;

/// Corner values run over `[−RANGE, RANGE]⁸` in the proof `cargo test` runs.
pub const RANGE: i64 = 3;
/// The wider cube of [`oracle_vs_sweep_wide`] (about 7.5 times the cells).
pub const WIDE_RANGE: i64 = 4;

/// Oracle (closed form, slices across z) against the sweep (events, slices across x) on
/// `[−RANGE, RANGE]⁸` at isovalues 0 and 1/2; the certified `f64` path, where it decides,
/// against the exact one. One part per (isovalue, corner 7, corner 6).
pub fn oracle_vs_sweep(shard: Shard) -> ProofOutcome {
    oracle_vs_sweep_on(shard, "mc.trilinear-topology", RANGE, RANDOM_CELLS)
}

/// The same integer checks on `[−WIDE_RANGE, WIDE_RANGE]⁸` (43 M cells per isovalue, about
/// four minutes on one core): run by `geocert prove`, not by `cargo test`.
pub fn oracle_vs_sweep_wide(shard: Shard) -> ProofOutcome {
    oracle_vs_sweep_on(shard, "mc.trilinear-topology-wide", WIDE_RANGE, 0)
}

fn oracle_vs_sweep_on(shard: Shard, name: &str, range: i64, random_cells: usize) -> ProofOutcome {
    let side = (2 * range + 1) as usize;
    let random = if random_cells > 0 {
        format!(", and {random_cells} random rational cells")
    } else {
        String::new()
    };
    let mut t = Tally::new(
        name,
        &format!(
            "every integer cell in [−{range}, {range}]⁸ at isovalues 0 and 1/2 ({} cells each){random}: the closed-form oracle's corner groups (slices across z) equal the event sweep's (slices across x), and the certified f64 path equals the exact one wherever it decides",
            side.pow(8)
        ),
        shard,
    );
    let tab = table();
    let entries = tab.entries.len();
    let mut tunnel_entries = vec![false; entries];
    // cells, crossed, tunnel cells, components with 1, 2, ≥3 cycles, fast decided, fast ties
    let mut counts = [0u64; 8];
    // The trilinear cases: a table entry and the grouping of its polygons into components
    // (component of polygon i in base-4 digit i; at most four polygons). Each is
    // triangulated by `cell_mesh` and checked once per part; the set met is a flag set
    // (entry × grouping), so slices merge.
    const GROUPINGS: usize = 256;
    let mut cases: HashSet<usize> = HashSet::new();
    for (iso_index, half) in [false, true].into_iter().enumerate() {
        for hi in 0..side * side {
            if !t.owns((iso_index * side * side + hi) as u64) {
                continue;
            }
            // Checked once per part (so slices count as the whole run does).
            cases.clear();
            let v7 = (hi / side) as i64 - range;
            let v6 = (hi % side) as i64 - range;
            let mut idx = [0usize; 6];
            loop {
                let mut v = [0i64; 8];
                for c in 0..6 {
                    v[c] = idx[c] as i64 - range;
                }
                v[6] = v6;
                v[7] = v7;
                // Shifted by the isovalue and scaled to integers: 2v − 1 at 1/2.
                let g = if half { v.map(|x| 2 * x - 1) } else { v };
                counts[0] += 1;
                let crossed = g.iter().any(|&x| x >= 0) && g.iter().any(|&x| x < 0);
                if crossed {
                    counts[1] += 1;
                    let oracle = topology_of_small(&g);
                    let sweep = sweep_groups(&g, 0);
                    let ok = matches!((&oracle, &sweep), (Some(o), Some(s)) if o.groups == *s);
                    t.check(ok, || {
                        format!(
                            "values {v:?} iso {}: oracle {:?}, sweep {sweep:?}",
                            if half { "1/2" } else { "0" },
                            oracle.as_ref().map(|o| o.groups)
                        )
                    });
                    if let Some(o) = oracle {
                        let entry_index = tab.offsets[o.config as usize] as usize + o.sub as usize;
                        let polygons = &o.entry().polygons;
                        let code: usize = polygons
                            .iter()
                            .enumerate()
                            .map(|(i, p)| {
                                let c = o.components.iter().position(|c| c.cycles.contains(p));
                                c.unwrap_or(0) << (2 * i)
                            })
                            .sum();
                        let case = entry_index * GROUPINGS + code % GROUPINGS;
                        if cases.insert(case) {
                            t.flag("trilinear_cases", entries * GROUPINGS, case);
                            let shifted = || g.map(|x| Rational::from_integer(x.into()));
                            let built = cell_mesh(&o, shifted).map_err(|e| e.to_string());
                            let verdict = built.and_then(|m| check_cell_mesh(&o, &m));
                            t.check(verdict.is_ok(), || {
                                format!("values {v:?}: trilinear triangulation: {verdict:?}")
                            });
                        }
                        if o.tunnels() > 0 {
                            counts[2] += 1;
                            tunnel_entries
                                [tab.offsets[o.config as usize] as usize + o.sub as usize] = true;
                        }
                        for c in &o.components {
                            counts[3 + c.cycles.len().min(3) - 1] += 1;
                        }
                        let f = v.map(|x| x as f64);
                        let iso = if half { 0.5 } else { 0.0 };
                        if let Some(fast) = cell_topology_fast(&f, iso) {
                            counts[6] += 1;
                            t.check(fast == o, || {
                                format!("values {v:?} iso {iso}: fast {fast:?} != exact {o:?}")
                            });
                        } else if !half && v.contains(&0) {
                            counts[7] += 1;
                        }
                    }
                }
                let mut i = 0;
                while i < 6 {
                    idx[i] += 1;
                    if idx[i] < side {
                        break;
                    }
                    idx[i] = 0;
                    i += 1;
                }
                if i == 6 {
                    break;
                }
            }
        }
    }
    // Random rational cells: the exact oracle (BigInt-free after scaling) against the sweep
    // on the same integers, and the certificate checker on a sample.
    let base = (2 * side * side) as u64;
    let mut checked = 0u64;
    let mut symmetric = 0u64;
    let symmetries = super::mc::cube_symmetries();
    for part in 0..RANDOM_PARTS {
        if random_cells == 0 || !t.owns(base + part as u64) {
            continue;
        }
        let mut rng = Lcg::new(0x7121_1ea5 + part as u64);
        for i in 0..random_cells / RANDOM_PARTS {
            let values: [Rational; 8] = std::array::from_fn(|_| rng.rational(40, 4));
            let iso = rng.rational(40, 4);
            let g = shifted_integers(&values, &iso);
            let small: Option<[i64; 8]> = g
                .iter()
                .map(|x| x.to_i64())
                .collect::<Option<Vec<_>>>()
                .and_then(|v| v.try_into().ok());
            let exact = cell_topology_exact(&values, &iso);
            let sweep = small.and_then(|g| sweep_groups(&g, 0));
            t.check(sweep == Some(exact.groups), || {
                format!(
                    "values {values:?} iso {iso}: oracle {:?}, sweep {sweep:?}",
                    exact.groups
                )
            });
            if i % SYMMETRY_EVERY == 0 {
                // The oracle commutes with the 48 symmetries of the cube: moving corner c to
                // map[c] moves the groups and keeps the tunnels.
                for (map, _) in &symmetries {
                    let mut moved = values.clone();
                    for c in 0..8 {
                        moved[map[c] as usize] = values[c].clone();
                    }
                    let image = cell_topology_exact(&moved, &iso);
                    let same = |g: &[u8; 8], a: usize, b: usize| g[a] != u8::MAX && g[a] == g[b];
                    let ok = (0..2).all(|s| {
                        (0..8).all(|a| {
                            (0..8).all(|b| {
                                same(&exact.groups[s], a, b)
                                    == same(&image.groups[s], map[a] as usize, map[b] as usize)
                            })
                        })
                    }) && image.tunnels() == exact.tunnels()
                        && image.components.len() == exact.components.len();
                    symmetric += 1;
                    t.check(ok, || {
                        format!("values {values:?} iso {iso}: not symmetric under {map:?}")
                    });
                }
            }
            if i % CHECK_EVERY == 0 {
                checked += 1;
                let verdict = verify_cell(&values, &iso, &exact);
                t.check(verdict.is_ok(), || {
                    format!("values {values:?} iso {iso}: checker refuses: {verdict:?}")
                });
            }
            let f = values.clone().map(|x| rational_to_f64(&x));
            if let Some(fast) = cell_topology_fast(&f, rational_to_f64(&iso)) {
                // Values like 1/3 round; the fast path then answers for the rounded cell, so
                // compare only cells whose values are exact in f64.
                if values
                    .iter()
                    .chain([&iso])
                    .all(|x| x.denom().to_u64().is_some_and(|d| d.is_power_of_two()))
                {
                    t.check(fast == exact, || {
                        format!("values {values:?} iso {iso}: fast differs")
                    });
                }
            }
        }
    }
    t.count("certificates", checked);
    t.count("symmetric", symmetric);
    for (name, c) in [
        "cells",
        "crossed",
        "tunnel_cells",
        "discs",
        "tubes",
        "three_holed",
        "fast_decided",
        "fast_ties",
    ]
    .iter()
    .zip(counts)
    {
        t.count(name, c);
    }
    for (i, _) in tunnel_entries.iter().enumerate().filter(|(_, &b)| b) {
        t.flag("tunnel_entries", entries, i);
    }
    let random = if random_cells > 0 {
        "; the certificate checker re-verified {certificates} random cells; {symmetric} images of random cells under the 48 cube symmetries have the moved groups and the same tunnels"
    } else {
        ""
    };
    t.template(&format!(
        "{{crossed}} cells crossed by the level; {{tunnel_cells}} with a tube (a tunnel), realising {{#tunnel_entries}} table entries; components: {{discs}} discs, {{tubes}} tubes, {{three_holed}} with three or more holes; the f64 path decided {{fast_decided}} (of the undecided, {{fast_ties}} have a corner on the level){random}; {{#trilinear_cases}} distinct trilinear cases (table entry and grouping of its polygons into components) met, each triangulated with its topology (oriented, the table's face segments, no chord in a face, the oracle's components and cycles)",
    ));
    t.finish()
}

/// The trilinear tubes are embedded: every integer cell of `[−RANGE, RANGE]⁸` at the
/// isovalue 1/2 with a tunnel is triangulated ([`cell_mesh`]) and every pair of its
/// triangles tested for crossings in exact integer arithmetic
/// ([`crossings`](crate::mc::trilinear::embedding::crossings)). One part per (corner 7,
/// corner 6).
pub fn tube_embedding(shard: Shard) -> ProofOutcome {
    tube_embedding_on(shard, "mc.tube-embedding", RANGE)
}

/// [`tube_embedding`] on `[−WIDE_RANGE, WIDE_RANGE]⁸` (run by `geocert prove`).
pub fn tube_embedding_wide(shard: Shard) -> ProofOutcome {
    tube_embedding_on(shard, "mc.tube-embedding-wide", WIDE_RANGE)
}

fn tube_embedding_on(shard: Shard, name: &str, range: i64) -> ProofOutcome {
    use crate::mc::trilinear::embedding::{crossings, shifted};
    let side = (2 * range + 1) as usize;
    let mut t = Tally::new(
        name,
        &format!(
            "every integer cell in [−{range}, {range}]⁸ at the isovalue 1/2 ({} cells) whose trilinear surface has a tube: every pair of its triangles tested for crossings, exactly",
            side.pow(8)
        ),
        shard,
    );
    let (mut tubes, mut pairs) = (0u64, 0u64);
    for hi in 0..side * side {
        if !t.owns(hi as u64) {
            continue;
        }
        for lo in 0..side.pow(6) {
            let mut c = lo;
            let mut v = [0i64; 8];
            for x in v.iter_mut().take(6) {
                *x = (c % side) as i64 - range;
                c /= side;
            }
            v[6] = (hi % side) as i64 - range;
            v[7] = (hi / side) as i64 - range;
            let g = v.map(|x| 2 * x - 1);
            let Some(topo) = topology_of_small(&g) else {
                continue;
            };
            if topo.tunnels() == 0 {
                continue;
            }
            tubes += 1;
            let found = cell_mesh(&topo, || shifted(&g))
                .map_err(|e| e.to_string())
                .and_then(|m| crossings(&g, &m).ok_or_else(|| "out of range".to_string()));
            if let Ok(x) = &found {
                pairs += x.pairs as u64;
            }
            t.check(
                matches!(&found, Ok(x) if x.crossing == 0 && x.coplanar == 0),
                || format!("values {v:?} at 1/2: {found:?}"),
            );
        }
    }
    t.count("tubes", tubes);
    t.count("pairs", pairs);
    t.template("{tubes} tube cells, {pairs} triangle pairs, none crossing");
    t.finish()
}
