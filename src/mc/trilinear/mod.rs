//! The exact topology of the trilinear interpolant's isosurface inside one cell, and of the
//! whole trilinear isosurface of a volume.
//!
//! The 656-entry table fills each boundary polygon of a cell with a disc. The trilinear
//! interpolant `f` of the eight corner values may instead join two polygons by a tube
//! through the cell (a tunnel). This module computes what `{f = c} ∩ cell` really is.
//!
//! **Degenerate values.** Ties follow the table's rules (a corner equal to the isovalue is
//! positive; a face saddle equal to it joins the positive corners). These are exactly the
//! topology at `c − ε` for an infinitesimal `ε > 0`, a regular value, and every decision
//! here is made at that perturbed level (the `ring` module's `Eps`), so any input has a manifold
//! answer that agrees with the table on the faces.
//!
//! **From regions to surface components.** The interpolant is harmonic (each of its second
//! derivatives along an axis vanishes), so the level set has no closed component inside the
//! cell, and each component of `{g > 0}` or `{g < 0}` (`g = f − c + ε`) reaches a corner. The
//! *corner groups* — which positive corners are connected inside the cell, likewise the
//! negative ones — are computed in closed form (below). A connected
//! two-sided surface in the ball separates it, and two complementary regions of the ball
//! meet along at most one surface component (a loop crossing one component once would
//! otherwise exist, but the ball has no such loops). So every surface component is the
//! interface between one positive and one negative region, and its boundary cycles on the
//! cube are the face polygons whose positive corners lie in the one group and negative
//! corners in the other. Each component is a sphere with `k` holes (the surface is a graph
//! over a face, hence planar), Euler characteristic `2 − k`; `k ≥ 2` is a tunnel.
//!
//! **The closed form.** Slice the cell by planes `t` across z. A slice is bilinear, so each
//! component of a slice's region of one sign contains a slice corner, a point of one of the
//! four vertical *sweep edges*, where the value `e_k(t)` is linear. Two sweep edges are
//! connected through the region iff at some `t` they are adjacent and both have the sign
//! (the slice side between them then has it), or they are opposite, both have it, the other
//! two the other sign, and the slice saddle lies in the region: `P_k(t) = e_k e_{k+2} −
//! e_{k+1} e_{k+3} > 0` (the asymptotic decider's numerator). The sign pattern holds on an
//! interval whose ends are `0`, `1` or edge zeros `g_k / (g_k − g_k')`, and the quadratic
//! `P_k` is positive somewhere on it iff it is at an end or at its vertex `−B / 2A` (when
//! `A < 0` and the vertex is inside): every decision is a sign at a rational point, and no
//! square root is ever taken.
//!
//! **Certificates.** Each connection carries its witness: the sweep axis, the slice
//! interval on which the connecting pattern holds, and for a connection through a slice's
//! saddle the point where the saddle lies in the region. [`verify_cell`] re-checks every
//! witness, re-derives the groups by slicing across a different axis, and re-derives the
//! components.
//!
//! Paths: [`cell_topology_exact`] (integers in `ℤ[ε]`, `i128` when the scaled values are
//! small, `BigInt` otherwise) and [`cell_topology_fast`] (outward-rounded intervals, `None`
//! when a sign is uncertain). [`sweep`] is an independent route — an event sweep of plane
//! slices, exact on small integer cells — used by the proofs to cross-check the oracle.

pub(crate) mod closed;
pub mod embedding;
pub mod polygonise;
pub(crate) mod ring;
pub mod sweep;
pub mod volume;

use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::ToPrimitive;
use std::cmp::Ordering;
use thiserror::Error;

use self::closed::{groups_from_joins, Slices};
use self::ring::{Coeff, Eps, OrderedRing};
use super::table::{ambiguous_faces, table, Entry, EDGES, FACES};
use crate::num::{Interval, Rational};

pub use volume::{
    cell_topologies, volume_topology, volume_topology_exact, SurfaceComponent, VolumeTopology,
};

/// Corner groups of one sign class: `label[c]` is the smallest corner of corner `c`'s group,
/// `u8::MAX` for corners of the other class.
pub type Groups = [u8; 8];

/// A point of a sweep axis named by what defines it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Mark {
    /// `t = 0`.
    Zero,
    /// `t = 1`.
    One,
    /// The zero of sweep edge `k` (0–3).
    Root(u8),
}

/// Where a slice saddle witnesses a diagonal connection.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WitnessPoint {
    /// At an end of the pattern interval (by continuity, just inside it).
    Mark(Mark),
    /// At the maximum `−B / 2A` of the diagonal quadratic `P_k`.
    Peak,
}

impl From<Mark> for WitnessPoint {
    fn from(m: Mark) -> WitnessPoint {
        WitnessPoint::Mark(m)
    }
}

/// The slice interval `(lo, hi)` on which a connection's sign pattern holds, and (for a
/// diagonal) where the saddle lies in the region.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Witness {
    /// Lower end.
    pub lo: Mark,
    /// Upper end.
    pub hi: Mark,
    /// The saddle witness (diagonal connections; `lo` otherwise).
    pub at: WitnessPoint,
}

/// What connects two corners in slices across an axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum JoinKind {
    /// Sweep edge `k` has the class's sign throughout.
    Edge(u8),
    /// Sweep edges `k` and `k + 1` both have it on the witness interval: the slice side
    /// between them does.
    Side(u8),
    /// Sweep edges `k` and `k + 2` have it, the other two the opposite sign, and the slice
    /// saddle lies in the region (`P_k > 0`) at the witness point.
    Diagonal(u8),
}

/// One connection between two corners of a sign class, with its witness.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Join {
    /// The positive class (`true`) or the negative one.
    pub positive: bool,
    /// The sweep axis (0 = x, 1 = y, 2 = z).
    pub axis: u8,
    /// What connects them.
    pub kind: JoinKind,
    /// The two cube corners connected.
    pub corners: [u8; 2],
    /// The evidence.
    pub witness: Witness,
}

/// One connected component of the isosurface inside a cell: a sphere with
/// `cycles.len()` holes.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct CellComponent {
    /// Its boundary cycles on the cube, each a table polygon (cut edges in order, wound
    /// about the normal into the positive region).
    pub cycles: Vec<Vec<u8>>,
}

/// The exact topology of the trilinear isosurface in one cell.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CellTopology {
    /// The corner signs (bit `i`: corner `i` positive).
    pub config: u8,
    /// The face decisions as the table's subconfiguration.
    pub sub: u8,
    /// Corner groups inside the cell: `[positive, negative]`.
    pub groups: [Groups; 2],
    /// The surface components, in order of their first polygon in the table entry.
    pub components: Vec<CellComponent>,
    /// The connections found, with their witnesses (slices across z).
    pub joins: Vec<Join>,
}

impl CellTopology {
    /// The table entry with the same corner signs and face decisions.
    pub fn entry(&self) -> &'static Entry {
        table().entry(self.config, self.sub)
    }
    /// Components with two or more boundary cycles (tubes).
    pub fn tunnels(&self) -> usize {
        self.components
            .iter()
            .filter(|c| c.cycles.len() >= 2)
            .count()
    }
    /// `Σ (2 − cycles)` over the components.
    pub fn euler_characteristic(&self) -> i64 {
        self.components
            .iter()
            .map(|c| 2 - c.cycles.len() as i64)
            .sum()
    }
    /// Whether the table entry (a disc in every polygon) has this topology.
    pub fn matches_table(&self) -> bool {
        self.tunnels() == 0
    }
}

/// The components of a cell from its corner groups: the polygons of the table entry
/// `(config, sub)`, grouped by the (positive group, negative group) pair they separate.
pub fn components_from_groups(config: u8, sub: u8, groups: &[Groups; 2]) -> Vec<CellComponent> {
    let entry = table().entry(config, sub);
    let mut keys: Vec<(u8, u8)> = Vec::new();
    let mut out: Vec<CellComponent> = Vec::new();
    for poly in &entry.polygons {
        let [a, b] = EDGES[poly[0] as usize];
        let (p, n) = if config >> a & 1 == 1 { (a, b) } else { (b, a) };
        let key = (groups[0][p as usize], groups[1][n as usize]);
        match keys.iter().position(|k| *k == key) {
            Some(i) => out[i].cycles.push(poly.clone()),
            None => {
                keys.push(key);
                out.push(CellComponent {
                    cycles: vec![poly.clone()],
                });
            }
        }
    }
    out
}

/// The face decisions at the perturbed level: on an ambiguous face the positive corners are
/// joined iff their diagonal's product exceeds the other's.
fn face_sub<S: OrderedRing>(config: u8, g: &[S; 8]) -> Option<u8> {
    let mut sub = 0u8;
    for (bit, &f) in ambiguous_faces(config).iter().enumerate() {
        let c = FACES[f as usize].corners.map(|x| x as usize);
        let d02 = g[c[0]].mul(&g[c[2]]);
        let d13 = g[c[1]].mul(&g[c[3]]);
        let own = if config >> c[0] & 1 == 1 {
            d02.sub(&d13)
        } else {
            d13.sub(&d02)
        };
        if own.sign()? == Ordering::Greater {
            sub |= 1 << bit;
        }
    }
    Some(sub)
}

/// The whole oracle on shifted values `g` (signs certain): slices across z.
fn topology_of<S: OrderedRing>(g: &[S; 8]) -> Option<CellTopology> {
    let slices = Slices::new(g, 2)?;
    let positive: [bool; 8] = std::array::from_fn(|c| slices.positive(c));
    let config = (0..8).fold(0u8, |acc, c| acc | (u8::from(positive[c]) << c));
    let sub = face_sub(config, g)?;
    let mut joins = slices.joins(true, 2)?;
    joins.extend(slices.joins(false, 2)?);
    let groups = groups_from_joins(&positive, &joins);
    let components = components_from_groups(config, sub, &groups);
    Some(CellTopology {
        config,
        sub,
        groups,
        components,
        joins,
    })
}

/// The largest scaled magnitude taken in `i128`. With `|g| < 2^b`: `δ < 2^(b+1)`, the peak
/// `−B / 2A` has numerator and denominator below `2^(2b+4)`, a sweep edge's value there
/// (times the denominator) is below `2^(3b+6)`, and the diagonal product below `2^(6b+13)`;
/// `b = 19` keeps it under `2¹²⁶`. Larger values take `BigInt`.
const I128_LIMIT: i64 = 1 << 19;

/// The shifted values `v − c` over their common denominator (integers, same signs).
pub fn shifted_integers(values: &[Rational; 8], iso: &Rational) -> [BigInt; 8] {
    let g: [Rational; 8] = std::array::from_fn(|i| &values[i] - iso);
    let den = g.iter().fold(BigInt::from(1), |acc, r| acc.lcm(r.denom()));
    g.map(|r| r.numer() * (&den / r.denom()))
}

fn eps_values<T: Coeff>(g: &[T; 8]) -> [Eps<T>; 8] {
    std::array::from_fn(|i| Eps::shifted(g[i].clone()))
}

/// The exact topology of the cell with corner `values` (table numbering) at isovalue `iso`.
pub fn cell_topology_exact(values: &[Rational; 8], iso: &Rational) -> CellTopology {
    topology_of_integers(&shifted_integers(values, iso))
}

/// [`cell_topology_exact`] on shifted integer values `g = v − c` (any common positive scale).
pub fn topology_of_integers(g: &[BigInt; 8]) -> CellTopology {
    let small: Option<[i64; 8]> = g
        .iter()
        .map(|x| x.to_i64().filter(|v| v.abs() < I128_LIMIT))
        .collect::<Option<Vec<_>>>()
        .and_then(|v| v.try_into().ok());
    let t = match small {
        Some(s) => topology_of(&eps_values(&s.map(i128::from))),
        None => topology_of(&eps_values(g)),
    };
    t.expect("exact signs are always known")
}

/// [`topology_of_integers`] on small integers (`|g| < 2¹⁹`), the proofs' fast entry.
pub fn topology_of_small(g: &[i64; 8]) -> Option<CellTopology> {
    if g.iter().any(|v| v.abs() >= I128_LIMIT) {
        return None;
    }
    topology_of(&eps_values(&g.map(i128::from)))
}

/// The certified `f64` path: the same topology, or `None` when a sign is uncertain (a value
/// equal to the isovalue, a tie at a face or slice saddle, or rounding too close to call) —
/// fall back to [`cell_topology_exact`] then.
pub fn cell_topology_fast(values: &[f64; 8], iso: f64) -> Option<CellTopology> {
    if !(values.iter().all(|v| v.is_finite()) && iso.is_finite()) {
        return None;
    }
    let g: [Interval; 8] = values.map(|v| Interval::point(v) - Interval::point(iso));
    topology_of(&g)
}

/// Why [`verify_cell`] rejected a claimed topology.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
pub enum CellCheckError {
    /// The corner signs or face decisions differ from the values'.
    #[error(
        "configuration {found}/{found_sub} claimed, the values give {expected}/{expected_sub}"
    )]
    Configuration {
        /// Claimed configuration.
        found: u8,
        /// Claimed subconfiguration.
        found_sub: u8,
        /// The values' configuration.
        expected: u8,
        /// The values' subconfiguration.
        expected_sub: u8,
    },
    /// A witness does not hold.
    #[error("join {index} ({join:?}): {why}")]
    Witness {
        /// Its position in the list.
        index: usize,
        /// The join.
        join: Join,
        /// What failed.
        why: &'static str,
    },
    /// The groups differ from those the witnesses or another axis give.
    #[error("corner groups {claimed:?} claimed; {route} gives {found:?}")]
    Groups {
        /// Claimed groups.
        claimed: [Groups; 2],
        /// The route that disagrees.
        route: &'static str,
        /// Its groups.
        found: [Groups; 2],
    },
    /// The components are not those the groups imply.
    #[error("components differ from those the corner groups imply")]
    Components,
}

/// Re-checks a claimed cell topology from the corner values: the configuration and face
/// decisions; every join's witness (the pattern holds on its interval — each sweep edge
/// involved has its required sign there and no zero inside — and a diagonal's `P_k` is
/// positive at the witness point, computed from the slice values); the groups the joins
/// make against the claim and against slices across x and y; the components.
pub fn verify_cell(
    values: &[Rational; 8],
    iso: &Rational,
    claim: &CellTopology,
) -> Result<(), CellCheckError> {
    let g = eps_values(&shifted_integers(values, iso));
    let config = (0..8).fold(0u8, |acc, c| {
        acc | (u8::from(g[c].sign() == Some(Ordering::Greater)) << c)
    });
    let sub = face_sub(config, &g).unwrap_or(0);
    if (config, sub) != (claim.config, claim.sub) {
        return Err(CellCheckError::Configuration {
            found: claim.config,
            found_sub: claim.sub,
            expected: config,
            expected_sub: sub,
        });
    }
    let positive: [bool; 8] = std::array::from_fn(|c| config >> c & 1 == 1);
    for (index, join) in claim.joins.iter().enumerate() {
        check_witness(&g, join).map_err(|why| CellCheckError::Witness {
            index,
            join: *join,
            why,
        })?;
    }
    let from_joins = groups_from_joins(&positive, &claim.joins);
    if from_joins != claim.groups {
        return Err(CellCheckError::Groups {
            claimed: claim.groups,
            route: "the witnessed joins",
            found: from_joins,
        });
    }
    for (axis, route) in [(0usize, "slicing across x"), (1, "slicing across y")] {
        let slices = Slices::new(&g, axis).ok_or(CellCheckError::Components)?;
        let mut joins = slices.joins(true, axis as u8).unwrap_or_default();
        joins.extend(slices.joins(false, axis as u8).unwrap_or_default());
        let found = groups_from_joins(&positive, &joins);
        if found != claim.groups {
            return Err(CellCheckError::Groups {
                claimed: claim.groups,
                route,
                found,
            });
        }
    }
    if components_from_groups(config, sub, &claim.groups) != claim.components {
        return Err(CellCheckError::Components);
    }
    Ok(())
}

/// One join's witness, checked from the values directly.
fn check_witness(g: &[Eps<BigInt>; 8], join: &Join) -> Result<(), &'static str> {
    use self::closed::sweep_edges;
    let axis = join.axis as usize;
    if axis > 2 {
        return Err("no such axis");
    }
    let edges = sweep_edges(axis);
    // The sweep edge values at a point `n/d` of the axis, times `d` (sign-faithful).
    let at = |k: usize, t: &ring::Frac<Eps<BigInt>>| -> Eps<BigInt> {
        let [a, b] = edges[k];
        g[a].mul(&t.d).add(&g[b].sub(&g[a]).mul(&t.n))
    };
    let slices = Slices::new(g, axis).ok_or("a zero corner")?;
    let (lo, hi) = (slices.point(join.witness.lo), slices.point(join.witness.hi));
    if lo.cmp(&hi) != Some(Ordering::Less) {
        return Err("empty witness interval");
    }
    let mid = lo.mid(&hi);
    let pattern: Vec<(usize, bool)> = match join.kind {
        JoinKind::Edge(k) => vec![(k as usize, join.positive)],
        JoinKind::Side(k) => vec![
            (k as usize, join.positive),
            ((k as usize + 1) % 4, join.positive),
        ],
        JoinKind::Diagonal(k) => {
            let k = k as usize;
            if k > 1 {
                return Err("no such diagonal");
            }
            vec![
                (k, join.positive),
                (k + 2, join.positive),
                (k + 1, !join.positive),
                ((k + 3) % 4, !join.positive),
            ]
        }
    };
    for &(k, s) in &pattern {
        if k > 3 {
            return Err("no such sweep edge");
        }
        let want = if s { Ordering::Greater } else { Ordering::Less };
        if at(k, &mid).sign() != Some(want) {
            return Err("a sweep edge has the wrong sign inside the interval");
        }
        // No zero strictly inside: the edge's value keeps its sign at both ends.
        for end in [&lo, &hi] {
            let s_end = at(k, end).sign();
            if s_end != Some(want) && s_end != Some(Ordering::Equal) {
                return Err("a sweep edge changes sign inside the interval");
            }
        }
    }
    let [a, b] = join.corners.map(|c| c as usize);
    let corner_ok = |k: usize, c: usize| edges[k].contains(&c);
    let (ka, kb) = match join.kind {
        JoinKind::Edge(k) => (k as usize, k as usize),
        JoinKind::Side(k) => (k as usize, (k as usize + 1) % 4),
        JoinKind::Diagonal(k) => (k as usize, k as usize + 2),
    };
    let sign_ok = |c: usize| (g[c].sign() == Some(Ordering::Greater)) == join.positive;
    if !(corner_ok(ka, a) && corner_ok(kb, b) && sign_ok(a) && sign_ok(b)) {
        return Err("the corners are not the connected sweep edges' corners of the class");
    }
    if let JoinKind::Diagonal(k) = join.kind {
        let k = k as usize;
        let t = match join.witness.at {
            WitnessPoint::Mark(m) => slices.point(m),
            WitnessPoint::Peak => slices
                .diagonal_peak(k)
                .ok()
                .flatten()
                .ok_or("no peak: the diagonal quadratic opens upward")?,
        };
        if lo.cmp(&t) == Some(Ordering::Greater) || t.cmp(&hi) == Some(Ordering::Greater) {
            return Err("the saddle witness lies outside the interval");
        }
        // P_k from the four slice values at t (not from the quadratic's coefficients).
        let p = at(k, &t)
            .mul(&at(k + 2, &t))
            .sub(&at(k + 1, &t).mul(&at((k + 3) % 4, &t)));
        if p.sign() != Some(Ordering::Greater) {
            return Err("the slice saddle is not in the region at the witness");
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;
