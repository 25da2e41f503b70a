//! Supercubes (Section 4) and diamond types (Sections 5.1, 5.4).
//!
//! A supercube at scale `γ` is the cube `[σ, σ + 4h]^d`, `h = 2^γ`, `σ` a multiple of `4h`. Its
//! edges are the segments joining the centre of a face `F` of the cube to the centre of a face
//! `G ⊊ F` (the cube itself counts as a face): in 3-D the paper's 8 + 30 + 60 = 98 edges
//! (Fig. 2), `5^d − 3^d` in `d`-D. Under the half-open rule an edge with both ends on one upper
//! face belongs to the neighbour, which leaves `4^d − 2^d` edges (56 in 3-D): exactly the spines
//! of the diamonds of types `τ` at that supercube, the central vertex being `σ + (τ ≪ γ)`.

use super::{Diamond, DiamondError, Hierarchy, Point};

/// A diamond type `τ`: for each axis `k`, bits `2k` and `2k+1` are bits `γ` and `γ + 1` of the
/// central vertex's coordinate `k`. Valid when some axis has its low bit set.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct DiamondType<const D: usize> {
    code: u32,
}

impl<const D: usize> DiamondType<D> {
    /// The type with this code; an error when bits beyond `2d` are set or every low bit is
    /// zero.
    pub fn from_code(code: u32) -> Result<DiamondType<D>, DiamondError> {
        let low = (0..D).fold(0, |m, k| m | (code >> (2 * k) & 1));
        if code >> (2 * D) != 0 || low == 0 {
            return Err(DiamondError::InvalidType { code, d: D });
        }
        Ok(DiamondType { code })
    }

    pub(super) fn from_code_unchecked(code: u32) -> DiamondType<D> {
        DiamondType { code }
    }

    /// Every valid type, in increasing code order: `4^d − 2^d` of them.
    pub fn all() -> impl Iterator<Item = DiamondType<D>> {
        (0..1u32 << (2 * D)).filter_map(|c| DiamondType::from_code(c).ok())
    }

    /// The code.
    pub fn code(&self) -> u32 {
        self.code
    }

    /// The position of this type among [`DiamondType::all`] (`0 ≤ index < 4^d − 2^d`): the
    /// slot of a supercube's internal map (Section 5.2).
    #[inline(always)]
    pub fn index(&self) -> usize {
        usize::from(Self::INDEX[self.code as usize])
    }

    /// [`DiamondType::index`] by code (`u16::MAX` for the `2^d` codes that are no type).
    const INDEX: [u16; 1 << (2 * super::MAX_DIM)] = type_indices(D);

    /// The offset of the central vertex from the supercube origin, in units of `h`: `τ_k ∈
    /// {0, 1, 2, 3}` per axis.
    pub fn offset(&self) -> [u32; D] {
        std::array::from_fn(|k| self.code >> (2 * k) & 3)
    }

    /// The class `i`: the number of axes whose low bit is zero.
    pub fn class(&self) -> usize {
        (0..D).filter(|&k| self.code >> (2 * k) & 1 == 0).count()
    }
}

/// A supercube: the diamonds of one scale whose central vertices share the high bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Supercube<const D: usize> {
    /// The origin `σ` (a multiple of `4h` per coordinate).
    pub origin: Point<D>,
    /// The scale `γ` of its diamonds.
    pub scale: u32,
}

impl<const D: usize> Supercube<D> {
    /// The supercube holding `diamond`.
    pub fn of(diamond: &Diamond<D>) -> Supercube<D> {
        Supercube {
            origin: diamond.supercube_origin(),
            scale: diamond.scale(),
        }
    }

    /// The diamond of type `tau` in this supercube, `σ + (τ ≪ γ)`; an error when that point
    /// is outside the grid or a corner.
    pub fn diamond(
        &self,
        hierarchy: &Hierarchy<D>,
        tau: DiamondType<D>,
    ) -> Result<Diamond<D>, DiamondError> {
        let off = tau.offset();
        let mut c = [0u32; D];
        for k in 0..D {
            c[k] = (off[k] << self.scale)
                .checked_add(self.origin[k])
                .ok_or_else(|| DiamondError::OutOfRange {
                    point: (0..D)
                        .map(|j| u64::from(self.origin[j]) + (u64::from(off[j]) << self.scale))
                        .collect(),
                    side: u64::from(hierarchy.side()),
                })?;
        }
        hierarchy.diamond(c)
    }
}

/// The supercube's edges in units of `h`, coordinates in `{0, …, 4}`, each as `[p, q]` with
/// `p < q`: face centre to sub-face centre (Fig. 2), with the half-open rule applied when
/// `half_open` (an edge with both ends on one upper face `x_k = 4` is left out).
pub fn supercube_edges<const D: usize>(half_open: bool) -> Vec<[[u32; D]; 2]> {
    // A face: per axis 0 = fixed low, 1 = free, 2 = fixed high; its centre coordinate is 2·state.
    let faces: Vec<[u32; D]> = (0..3u32.pow(D as u32))
        .map(|mut f| {
            std::array::from_fn(|_| {
                let s = f % 3;
                f /= 3;
                s
            })
        })
        .collect();
    let mut out = Vec::new();
    for f in &faces {
        for g in &faces {
            let sub = (0..D).all(|k| f[k] == 1 || f[k] == g[k]) && f != g;
            if !sub {
                continue;
            }
            let p = f.map(|s| 2 * s);
            let q = g.map(|s| 2 * s);
            if half_open && (0..D).any(|k| p[k] == 4 && q[k] == 4) {
                continue;
            }
            out.push(if p < q { [p, q] } else { [q, p] });
        }
    }
    out.sort_unstable();
    out
}

/// Per code of `2d` bits, its position among the valid codes (some low bit set) in increasing
/// order, or `u16::MAX`.
const fn type_indices(d: usize) -> [u16; 1 << (2 * super::MAX_DIM)] {
    let mut t = [u16::MAX; 1 << (2 * super::MAX_DIM)];
    let mut low = 0usize;
    let mut k = 0;
    while k < d {
        low |= 1 << (2 * k);
        k += 1;
    }
    let mut next = 0u16;
    let mut code = 0usize;
    while code < 1 << (2 * d) {
        if code & low != 0 {
            t[code] = next;
            next += 1;
        }
        code += 1;
    }
    t
}
