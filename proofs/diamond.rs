//! Diamond hierarchies: the implicit bit encoding against the explicit Maubach bisection, the
//! longest-edge equality in 2-D and 3-D, and the supercube's edges and types.

use super::{ProofOutcome, Shard, Tally};
use crate::diamond::explicit::{self, ExplicitHierarchy};
use crate::diamond::{supercube_edges, Diamond, DiamondType, Hierarchy, Point, Supercube};
use std::collections::BTreeSet;

/// The grids enumerated by `cargo test`: `(d, largest N)`.
pub const TEST_GRIDS: [(usize, u32); 4] = [(2, 6), (3, 4), (4, 3), (5, 3)];

/// The explicit builds refuse beyond this many simplices.
const MAX_SIMPLICES: u64 = 50_000_000;

fn factorial(n: usize) -> usize {
    (1..=n).product()
}

fn binomial(n: usize, k: usize) -> usize {
    factorial(n) / (factorial(k) * factorial(n - k))
}

/// Every grid point of `[0, 2^N]^d`.
fn grid_points<const D: usize>(side: u32) -> impl Iterator<Item = Point<D>> {
    let n = (side as u64 + 1).pow(D as u32);
    (0..n).map(move |mut i| {
        std::array::from_fn(|_| {
            let x = (i % (side as u64 + 1)) as u32;
            i /= side as u64 + 1;
            x
        })
    })
}

/// Compares one dimension's hierarchies for `N = 1..=max_levels` diamond for diamond.
fn compare_dimension<const D: usize>(max_levels: u32, t: &mut Tally, counts: &mut Vec<String>) {
    for levels in 1..=max_levels {
        let hier = Hierarchy::<D>::new(levels).expect("supported N");
        let ex: ExplicitHierarchy<D> = match explicit::build(levels, MAX_SIMPLICES) {
            Ok(e) => e,
            Err(e) => {
                t.check(false, || format!("d={D} N={levels}: {e}"));
                continue;
            }
        };
        let want_diamonds = hier.diamond_count().expect("small grid");
        let want_simplices = hier.simplex_count().expect("small grid");
        t.check(
            ex.diamonds.len() as u128 == want_diamonds
                && u128::from(ex.simplices) == want_simplices
                && ex.off_grid_midpoints == 0
                && ex.inconsistent_spines == 0,
            || {
                format!(
                    "d={D} N={levels}: {} diamonds (want {want_diamonds}), {} simplices (want {want_simplices}), {} off-grid midpoints, {} inconsistent spines",
                    ex.diamonds.len(), ex.simplices, ex.off_grid_midpoints, ex.inconsistent_spines
                )
            },
        );
        let mut interior = [0usize; 6];
        for p in grid_points::<D>(hier.side()) {
            if hier.is_corner(&p) {
                t.check(!ex.diamonds.contains_key(&p), || {
                    format!("d={D} N={levels}: corner {p:?} is a diamond")
                });
                continue;
            }
            let dia = hier.diamond(p).expect("valid central vertex");
            let Some(e) = ex.diamonds.get(&p) else {
                t.check(false, || {
                    format!("d={D} N={levels}: {p:?} is no explicit diamond")
                });
                continue;
            };
            let why = differences(&dia, e);
            let class_ok = interior_counts_hold(&dia, &hier);
            if class_ok == Some(true) {
                interior[dia.class()] += 1;
            }
            t.check(why.is_empty() && class_ok != Some(false), || {
                format!(
                    "d={D} N={levels} diamond {p:?}: {}{}",
                    why.join("; "),
                    if class_ok == Some(false) {
                        " interior counts wrong"
                    } else {
                        ""
                    }
                )
            });
        }
        if levels == max_levels {
            counts.push(format!(
                "d={D}, N={levels}: {} diamonds, {} simplices, interior diamonds by class {:?}",
                ex.diamonds.len(),
                ex.simplices,
                &interior[..D]
            ));
        }
    }
}

/// What differs between the implicit and the explicit diamond (empty when they agree).
fn differences<const D: usize>(dia: &Diamond<D>, e: &explicit::ExplicitDiamond<D>) -> Vec<String> {
    let mut why = Vec::new();
    let [a, b] = dia.spine();
    let spine = if a < b { [a, b] } else { [b, a] };
    if spine != e.spine {
        why.push(format!("spine {spine:?} vs {:?}", e.spine));
    }
    let mut simplices: Vec<_> = dia.simplices().iter().map(|s| s.sorted()).collect();
    simplices.sort_unstable();
    if simplices != e.simplices {
        why.push(format!(
            "{} simplices vs {} explicit",
            simplices.len(),
            e.simplices.len()
        ));
    }
    let parents: BTreeSet<_> = dia.parents().iter().copied().collect();
    if parents != e.parents {
        why.push(format!("parents {parents:?} vs {:?}", e.parents));
    }
    let children: BTreeSet<_> = dia.children().iter().copied().collect();
    if children != e.children {
        why.push(format!("children {children:?} vs {:?}", e.children));
    }
    // The class from the explicit spine: the number of axes it does not span.
    let zeros = (0..D).filter(|&k| e.spine[0][k] == e.spine[1][k]).count();
    if zeros != dia.class() {
        why.push(format!("class {} vs explicit {zeros}", dia.class()));
    }
    // Every simplex's recorded parent slot names a parent of the diamond (or none at the root).
    let mut slots_ok = true;
    dia.for_each_simplex(|_, slot| {
        if let Some(p) = dia.parent_in_slot(slot) {
            slots_ok &= e.parents.contains(&p.center());
        } else {
            slots_ok &= e.parents.is_empty() || dia.is_clipped();
        }
    });
    if !slots_ok {
        why.push("a simplex's parent slot is no parent".into());
    }
    // The fast slot formulas: absent slots, and each parent found in its own slot.
    let absent = (0..dia.parent_slots())
        .filter(|&s| dia.parent_in_slot(s).is_none())
        .fold(0u32, |m, s| m | 1 << s);
    if absent != dia.absent_parent_flags() {
        why.push(format!(
            "absent parent flags {:#b} vs {absent:#b}",
            dia.absent_parent_flags()
        ));
    }
    for s in 0..dia.parent_slots() {
        if let Some(p) = dia.parent_in_slot(s) {
            if dia.slot_of_parent(&p) != Some(s) {
                why.push(format!("parent {:?} not found in its slot {s}", p.center()));
            }
        }
    }
    // The vertices are the simplices' vertices.
    let from_simplices: BTreeSet<_> = e
        .simplices
        .iter()
        .flat_map(|s| s.vertices().to_vec())
        .collect();
    let vertices: BTreeSet<_> = dia.vertices().into_iter().collect();
    if vertices != from_simplices {
        why.push(format!(
            "{} vertices vs {} on the simplices",
            vertices.len(),
            from_simplices.len()
        ));
    }
    why
}

/// For a diamond the boundary does not cut (and not the root): the paper's counts —
/// `(d−i)!·i!·2^i` simplices, `d` parents for class 0 else `2i`, `2(d−i)` children for
/// `i < d−1` else `2^d` (none at scale 0). `None` when the diamond is cut or the root.
fn interior_counts_hold<const D: usize>(dia: &Diamond<D>, hier: &Hierarchy<D>) -> Option<bool> {
    if dia.is_clipped() || dia.center() == hier.root().center() {
        return None;
    }
    let i = dia.class();
    let simplices = factorial(D - i) * factorial(i) * (1 << i);
    let parents = if i == 0 { D } else { 2 * i };
    let children = match (i + 1 < D, dia.scale()) {
        (true, _) => 2 * (D - i),
        (false, 0) => 0,
        (false, _) => 1 << D,
    };
    Some(
        dia.simplices().len() == simplices
            && dia.parents().len() == parents
            && dia.children().len() == children,
    )
}

/// `diamond.implicit-vs-explicit` on the grids of [`TEST_GRIDS`].
pub fn implicit_vs_explicit(shard: Shard) -> ProofOutcome {
    implicit_vs_explicit_on(&TEST_GRIDS, shard)
}

/// `diamond.implicit-vs-explicit` for `(d, largest N)` pairs (`d` in 2..=5).
pub fn implicit_vs_explicit_on(grids: &[(usize, u32)], shard: Shard) -> ProofOutcome {
    let mut t = Tally::new(
        "diamond.implicit-vs-explicit",
        &format!(
            "every grid point of [0,2^N]^d for (d, N ≤) {grids:?}: the bit encoding's spine, class, simplices, vertices, parents, children, parent slots (and the fast slot formulas) equal the explicit Maubach hierarchy's; diamond and simplex totals (2^N+1)^d − 2^d and d!(2^(dN+1) − 1); interior class-i diamonds have (d−i)!i!2^i simplices, d or 2i parents, 2(d−i) or 2^d children"
        ),
        shard,
    );
    let mut counts = Vec::new();
    // One part per grid: the explicit hierarchy is built once per grid.
    for (part, &(d, n)) in grids.iter().enumerate() {
        if !t.owns(part as u64) {
            continue;
        }
        let before = counts.len();
        match d {
            2 => compare_dimension::<2>(n, &mut t, &mut counts),
            3 => compare_dimension::<3>(n, &mut t, &mut counts),
            4 => compare_dimension::<4>(n, &mut t, &mut counts),
            5 => compare_dimension::<5>(n, &mut t, &mut counts),
            _ => t.check(false, || format!("dimension {d} is not supported")),
        }
        if counts.len() > before {
            t.note(counts[before..].join("; "));
        }
    }
    t.finish()
}

/// `diamond.maubach-is-longest-edge`: in 2-D and 3-D every bisected simplex's Maubach edge is
/// its unique longest edge; for 4-D and 5-D the ties are counted.
pub fn maubach_is_longest_edge(shard: Shard) -> ProofOutcome {
    let mut t = Tally::new(
        "diamond.maubach-is-longest-edge",
        "every bisected simplex of the explicit hierarchies for d = 2 (N ≤ 6) and d = 3 (N ≤ 4): Maubach's bisection edge is the simplex's unique longest edge",
        shard,
    );
    if !t.owns(0) {
        return t.finish();
    }
    let mut remarks = Vec::new();
    fn tally<const D: usize>(levels: u32) -> Option<explicit::LongestEdgeTally> {
        explicit::build::<D>(levels, MAX_SIMPLICES)
            .ok()
            .map(|e| e.longest_edge)
    }
    for (d, levels, tl) in [(2, 6, tally::<2>(6)), (3, 4, tally::<3>(4))] {
        let Some(tl) = tl else {
            t.check(false, || format!("d={d} N={levels}: not built"));
            continue;
        };
        for _ in 0..tl.unique_longest {
            t.check(true, String::new);
        }
        for _ in 0..tl.tied_longest + tl.not_longest {
            t.check(false, || {
                format!(
                    "d={d} N={levels}: {} tied, {} not longest",
                    tl.tied_longest, tl.not_longest
                )
            });
        }
    }
    for (d, levels, tl) in [(4, 3, tally::<4>(3)), (5, 2, tally::<5>(2))] {
        if let Some(tl) = tl {
            remarks.push(format!(
                "d={d} N={levels} (not asserted): {} unique longest, {} tied, {} with a longer edge",
                tl.unique_longest, tl.tied_longest, tl.not_longest
            ));
        }
    }
    t.note(remarks.join("; "));
    t.finish()
}

fn supercube_dimension<const D: usize>(t: &mut Tally, remarks: &mut Vec<String>) {
    let all = supercube_edges::<D>(false);
    let half_open = supercube_edges::<D>(true);
    let want_all = 5usize.pow(D as u32) - 3usize.pow(D as u32);
    let want_half = 4usize.pow(D as u32) - 2usize.pow(D as u32);
    t.check(all.len() == want_all && half_open.len() == want_half, || {
        format!(
            "d={D}: {} edges (want 5^d − 3^d = {want_all}), {} half-open (want 4^d − 2^d = {want_half})",
            all.len(),
            half_open.len()
        )
    });
    // Types per class and the dense index.
    let types: Vec<DiamondType<D>> = DiamondType::all().collect();
    let mut per_class = vec![0usize; D];
    for (n, tau) in types.iter().enumerate() {
        per_class[tau.class()] += 1;
        t.check(tau.index() == n, || {
            format!(
                "d={D}: type {:#b} has index {} at position {n}",
                tau.code(),
                tau.index()
            )
        });
    }
    t.check(
        (0..D).all(|i| per_class[i] == (1 << D) * binomial(D, i)) && types.len() == want_half,
        || format!("d={D}: types per class {per_class:?}, want 2^d·C(d,i)"),
    );
    // Spines of an interior supercube at scales 0 and 1 are exactly the half-open edges.
    for scale in [0u32, 1] {
        let hier = Hierarchy::<D>::new(6).expect("N = 6");
        let h = 1u32 << scale;
        let cube = Supercube::<D> {
            origin: [8 * h; D],
            scale,
        };
        let mut spines = Vec::new();
        for tau in &types {
            let Ok(dia) = cube.diamond(&hier, *tau) else {
                t.check(false, || {
                    format!("d={D}: type {:#b} gives no diamond", tau.code())
                });
                continue;
            };
            let back = Supercube::of(&dia);
            let [a, b] = dia.spine().map(|p| p.map(|x| (x - cube.origin[0]) / h));
            let edge = if a < b { [a, b] } else { [b, a] };
            t.check(
                back == cube && dia.diamond_type() == *tau && dia.scale() == scale,
                || format!("d={D}: type {:#b} does not round-trip", tau.code()),
            );
            spines.push(edge);
        }
        spines.sort_unstable();
        t.check(spines == half_open, || {
            format!("d={D} scale {scale}: the spines are not the half-open supercube edges")
        });
    }
    remarks.push(format!(
        "d={D}: {} edges, {} half-open = types, per class {per_class:?}",
        all.len(),
        half_open.len()
    ));
}

/// `diamond.supercube`: the supercube's edges and the half-open rule (Section 4), the types
/// per class (Section 5.4), and diamond ↔ (scale, origin, type) both ways, for d = 2..5.
pub fn supercube(shard: Shard) -> ProofOutcome {
    let mut t = Tally::new(
        "diamond.supercube",
        "for d = 2..5: the supercube's face-centre edges (5^d − 3^d) and half-open edges (4^d − 2^d), every valid type's dense index, 2^d·C(d,i) types of class i, and for every type in an interior supercube at scales 0 and 1: σ + (τ ≪ γ) is a diamond whose spine is a half-open edge (a bijection) and which maps back to (σ, γ, τ); and every diamond of the 3-D N = 5 grid round-trips through its supercube",
        shard,
    );
    if !t.owns(0) {
        return t.finish();
    }
    let mut remarks = Vec::new();
    supercube_dimension::<2>(&mut t, &mut remarks);
    supercube_dimension::<3>(&mut t, &mut remarks);
    supercube_dimension::<4>(&mut t, &mut remarks);
    supercube_dimension::<5>(&mut t, &mut remarks);
    let hier = Hierarchy::<3>::new(5).expect("N = 5");
    for p in grid_points::<3>(hier.side()) {
        if let Ok(dia) = hier.diamond(p) {
            let cube = Supercube::of(&dia);
            let back = cube.diamond(&hier, dia.diamond_type());
            t.check(back == Ok(dia), || {
                format!("diamond {p:?} does not round-trip")
            });
        }
    }
    t.note(remarks.join("; "));
    t.finish()
}
