//! The reference path: the hierarchy of diamonds built explicitly (Section 3), by recursive
//! bisection of the `d!` Kuhn simplices of `[0, 2^N]^d` with integer coordinates, the
//! simplices grouped by bisection edge into diamonds.
//!
//! The bisection edge is chosen by Maubach's vertex-order rule: a simplex `(x₀, …, x_d)` with
//! tag `k` is bisected at the midpoint `z` of `x₀x_k` into `(x₀, …, x_{k−1}, z, x_{k+1}, …, x_d)`
//! and `(x₁, …, x_k, z, x_{k+1}, …, x_d)`, both with tag `k − 1` (or `d` when `k = 1`); the Kuhn
//! simplices `x_j = x_{j−1} + 2^N e_{π(j)}` have tag `d`. In 2-D and 3-D this is longest-edge
//! bisection (counted here and proved by `diamond.maubach-is-longest-edge`); in 4-D and above an
//! LEB simplex can have several longest edges and the rule decides.
//!
//! The parent–child relation of diamonds is the containment of simplices (Section 3): `δ_p` is a
//! parent of `δ_c` when a simplex of `δ_c` is a half of a simplex of `δ_p`.

use super::{DiamondError, Point, Simplex, MAX_DIM};
use std::collections::{BTreeMap, BTreeSet};

/// One diamond of the explicit hierarchy.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExplicitDiamond<const D: usize> {
    /// The bisection edge shared by its simplices, ends sorted.
    pub spine: [Point<D>; 2],
    /// Its simplices, each with sorted vertices, the list sorted.
    pub simplices: Vec<Simplex<D>>,
    /// The central vertices of its parents.
    pub parents: BTreeSet<Point<D>>,
    /// The central vertices of its children.
    pub children: BTreeSet<Point<D>>,
}

/// How the bisection edges compare with the simplices' other edges.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LongestEdgeTally {
    /// Bisected simplices whose bisection edge is their unique longest edge.
    pub unique_longest: u64,
    /// Bisected simplices whose bisection edge is a longest edge tied with others.
    pub tied_longest: u64,
    /// Bisected simplices with an edge longer than the bisection edge.
    pub not_longest: u64,
}

/// The whole hierarchy of diamonds on `[0, 2^N]^d`, built explicitly.
#[derive(Clone, Debug)]
pub struct ExplicitHierarchy<const D: usize> {
    /// `N`.
    pub levels: u32,
    /// The diamonds by central vertex.
    pub diamonds: BTreeMap<Point<D>, ExplicitDiamond<D>>,
    /// Every simplex of the hierarchy, the unit cubes' Kuhn simplices (never bisected)
    /// included.
    pub simplices: u64,
    /// Bisected simplices whose bisection edge has an odd coordinate sum (a midpoint off the
    /// grid): must be zero.
    pub off_grid_midpoints: u64,
    /// Simplices that disagree with an earlier simplex of the same midpoint about the spine:
    /// must be zero.
    pub inconsistent_spines: u64,
    /// Bisection edges against longest edges.
    pub longest_edge: LongestEdgeTally,
}

/// Builds the hierarchy on `(2^N + 1)^d` points by Maubach bisection down to the unit cubes;
/// refuses (before any work) when it would hold more than `max_simplices` simplices.
pub fn build<const D: usize>(
    levels: u32,
    max_simplices: u64,
) -> Result<ExplicitHierarchy<D>, DiamondError> {
    let hierarchy = super::Hierarchy::<D>::new(levels)?;
    let total = hierarchy.simplex_count().unwrap_or(u128::MAX);
    if total > u128::from(max_simplices) {
        return Err(DiamondError::TooLarge {
            simplices: total,
            limit: max_simplices,
        });
    }
    let side = hierarchy.side();
    let depth_limit = D as u32 * levels;
    let mut out = ExplicitHierarchy {
        levels,
        diamonds: BTreeMap::new(),
        simplices: 0,
        off_grid_midpoints: 0,
        inconsistent_spines: 0,
        longest_edge: LongestEdgeTally::default(),
    };
    // The Kuhn simplices: x_j = x_{j−1} + 2^N e_{π(j)}, tag d.
    let mut stack: Vec<([Point<D>; MAX_DIM + 1], usize, u32, Option<Point<D>>)> = Vec::new();
    for pi in all_permutations(D) {
        let mut v = [[0u32; D]; MAX_DIM + 1];
        for j in 1..=D {
            v[j] = v[j - 1];
            v[j][pi[j - 1]] += side;
        }
        stack.push((v, D, 0, None));
    }
    while let Some((v, tag, depth, parent)) = stack.pop() {
        out.simplices += 1;
        if depth == depth_limit {
            continue;
        }
        let (x0, xk) = (v[0], v[tag]);
        if (0..D).any(|c| (x0[c] + xk[c]) % 2 == 1) {
            out.off_grid_midpoints += 1;
            continue;
        }
        let z: Point<D> = std::array::from_fn(|c| (x0[c] + xk[c]) / 2);
        tally_longest_edge(&v[..=D], 0, tag, &mut out.longest_edge);
        let spine = if x0 < xk { [x0, xk] } else { [xk, x0] };
        let simplex = Simplex::new(&v[..=D]).map(|s| s.sorted());
        let entry = out.diamonds.entry(z).or_insert_with(|| ExplicitDiamond {
            spine,
            simplices: Vec::new(),
            parents: BTreeSet::new(),
            children: BTreeSet::new(),
        });
        if entry.spine != spine {
            out.inconsistent_spines += 1;
        }
        entry.simplices.extend(simplex);
        if let Some(p) = parent {
            entry.parents.insert(p);
            if let Some(pd) = out.diamonds.get_mut(&p) {
                pd.children.insert(z);
            }
        }
        let next = if tag == 1 { D } else { tag - 1 };
        let mut first = v;
        first[tag] = z;
        let mut second = v;
        second[..tag].copy_from_slice(&v[1..=tag]);
        second[tag] = z;
        stack.push((first, next, depth + 1, Some(z)));
        stack.push((second, next, depth + 1, Some(z)));
    }
    for d in out.diamonds.values_mut() {
        d.simplices.sort_unstable();
        d.simplices.dedup();
    }
    Ok(out)
}

/// Counts whether edge `(i, j)` of the simplex is its unique, a tied, or not a longest edge.
fn tally_longest_edge<const D: usize>(
    v: &[Point<D>],
    i: usize,
    j: usize,
    t: &mut LongestEdgeTally,
) {
    let len = |a: &Point<D>, b: &Point<D>| -> u128 {
        (0..D)
            .map(|c| {
                let d = i128::from(a[c]) - i128::from(b[c]);
                (d * d) as u128
            })
            .sum()
    };
    let bisected = len(&v[i], &v[j]);
    let (mut ties, mut longer) = (0, 0);
    for a in 0..v.len() {
        for b in a + 1..v.len() {
            if (a, b) == (i.min(j), i.max(j)) {
                continue;
            }
            let l = len(&v[a], &v[b]);
            if l > bisected {
                longer += 1;
            } else if l == bisected {
                ties += 1;
            }
        }
    }
    if longer > 0 {
        t.not_longest += 1;
    } else if ties > 0 {
        t.tied_longest += 1;
    } else {
        t.unique_longest += 1;
    }
}

/// Every permutation of `0..n`.
fn all_permutations(n: usize) -> Vec<Vec<usize>> {
    if n == 0 {
        return vec![vec![]];
    }
    let mut out = Vec::new();
    for p in all_permutations(n - 1) {
        for pos in 0..=p.len() {
            let mut q = p.clone();
            q.insert(pos, n - 1);
            out.push(q);
        }
    }
    out
}
