//! Diamond hierarchies and supercubes (Weiss and De Floriani, "Supercubes: a high-level primitive
//! for diamond hierarchies", IEEE TVCG 15(6), 2009).
//!
//! A grid of `(2^N + 1)^d` points on `[0, 2^N]^d` is refined by longest-edge bisection from the
//! `d!` Kuhn simplices of the cube (Section 3). The simplices that share a bisection edge (the
//! *spine*) form a *diamond*; every grid point except the `2^d` domain corners is the *central
//! vertex* (the spine's midpoint) of exactly one diamond. Everything about a diamond follows
//! from its central vertex by bit operations (Section 5.1, eq. 1, and Section 5.4 for `d ≠ 3`):
//!
//! * the **scale** `γ` is the fewest trailing zeros among the coordinates, the **level**
//!   `N − γ`, and `h = 2^γ`;
//! * the bits at positions `γ` and `γ + 1` (the paper's `γ+1`, `γ+2`, counting from one) per axis
//!   are the **type** `τ` (`4^d − 2^d` valid types); the axes whose bit `γ` is zero are the
//!   *even* axes, and their number is the **class** `i`;
//! * the remaining high bits are the **supercube origin** (Section 4): `v_c = σ + (τ ≪ γ)`.
//!
//! A class-`i` diamond's spine is the diagonal of the `(d−i)`-cube of side `2h` spanned by the
//! odd axes, running from the corner `≡ 0 (mod 4h)` to the corner `≡ 2h (mod 4h)`; its simplices
//! are the Kuhn simplices of that cube that contain the spine, each joined with a chain
//! `c + h σ₁e_{π₁}, c + h(σ₁e_{π₁} + σ₂e_{π₂}), …` through the even axes — `(d−i)!·i!·2^i`
//! simplices in all, fewer where the domain boundary cuts the diamond.
//!
//! Two routes compute all of this and are compared diamond for diamond by the exhaustive proof
//! `diamond.implicit-vs-explicit`:
//!
//! * [`explicit`] (reference): recursive bisection of the Kuhn simplices by Maubach's
//!   vertex-order rule, with integer coordinates, grouped by bisection edge;
//! * [`Hierarchy`] / [`Diamond`] (fast): the bit encoding, no stored hierarchy at all.
//!
//! For `d ≥ 4` "longest edge" is not well defined (an LEB simplex can have several longest
//! edges); Maubach's rule picks the bisection edge, and in 2-D and 3-D it equals longest-edge
//! bisection — proved by `diamond.maubach-is-longest-edge`.

mod code;
mod dmv;
mod error;
pub mod explicit;
mod field;
mod file;
mod front;
mod refine;
mod supercube;
mod table;
mod volumes;

pub use code::{Diamond, Hierarchy, Points, MAX_LEVELS};
pub use dmv::{
    flag_words, index_bytes, storage, DiamondData, DiamondDmv, DmvAccess, DmvSummary, FullDmv,
    PointHasher, Selection, StorageSizes, SupercubeDmv,
};
pub use error::{
    diamond_stats_exact, diamond_stats_fast, diamond_stats_integer, integer_samples,
    simplices_stats_exact, DiamondStats, ExactStats, MAX_INTEGER_SAMPLE,
};
pub use field::Field;
pub use file::write_vtk_tets;
pub use front::{absent_parent_flags, full_flags, DiamondFront, Front, SupercubeFront};
pub use refine::{
    check_conforming, current_mesh, marching_tetrahedra, Conformity, Lod, RefineError, Refiner,
    TetSurface,
};
pub use supercube::{supercube_edges, DiamondType, Supercube};
pub(crate) use table::PointMap;
pub use volumes::{builtin_volume, BUILTIN_VOLUMES};

use num_bigint::{BigInt, BigUint};
use num_traits::Zero;
use thiserror::Error;

/// A grid point `[x₀, …, x_{d−1}]`, each coordinate in `[0, 2^N]`.
pub type Point<const D: usize> = [u32; D];

/// The supported dimensions: `2 ≤ d ≤ MAX_DIM`.
pub const MAX_DIM: usize = 5;

/// Why a hierarchy or a diamond cannot be made.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
#[non_exhaustive]
pub enum DiamondError {
    /// `N` outside `1..=MAX_LEVELS`.
    #[error(
        "N = {levels}: a grid of (2^N + 1)^d points needs 1 <= N <= {max} (coordinates are u32)"
    )]
    Levels {
        /// The requested `N`.
        levels: u32,
        /// The largest supported `N`.
        max: u32,
    },
    /// A point outside `[0, 2^N]^d`.
    #[error("point {point:?} lies outside the grid [0, {side}]^d")]
    OutOfRange {
        /// The point.
        point: Vec<u64>,
        /// `2^N`.
        side: u64,
    },
    /// One of the `2^d` domain corners, which are no diamond's central vertex.
    #[error("point {point:?} is a corner of the domain: the 2^d corners are no diamond's central vertex")]
    Corner {
        /// The point.
        point: Vec<u64>,
    },
    /// A computation that would exceed its limit.
    #[error("the hierarchy would hold {simplices} simplices, more than the limit {limit}")]
    TooLarge {
        /// What it would take.
        simplices: u128,
        /// The limit given.
        limit: u64,
    },
    /// A volume that cannot be a field: too small, sizes that disagree, NaN or infinite
    /// samples.
    #[error("volume: {0}")]
    Volume(String),
    /// A `.dmv` file that cannot be read.
    #[error(".dmv file, byte {offset}: {what}")]
    File {
        /// Where.
        offset: usize,
        /// What is wrong.
        what: String,
    },
    /// A type code with bits beyond `2d` or with every low bit zero.
    #[error(
        "type code {code:#b} is not a valid {d}-D diamond type (2 bits per axis, some low bit set)"
    )]
    InvalidType {
        /// The code.
        code: u32,
        /// The dimension.
        d: usize,
    },
}

/// A `d`-simplex of the hierarchy by its `d + 1` vertices.
///
/// From [`Diamond::for_each_simplex`] the order is the spine's first end, the Kuhn chain
/// through the odd axes ending at the spine's other end, then the chain through the even axes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Simplex<const D: usize> {
    vertices: [Point<D>; MAX_DIM + 1],
}

impl<const D: usize> Simplex<D> {
    /// A simplex from its `d + 1` vertices; `None` when `vertices.len() != d + 1`.
    pub fn new(vertices: &[Point<D>]) -> Option<Simplex<D>> {
        if vertices.len() != D + 1 || D > MAX_DIM {
            return None;
        }
        let mut s = Simplex {
            vertices: [[0; D]; MAX_DIM + 1],
        };
        s.vertices[..=D].copy_from_slice(vertices);
        Some(s)
    }

    /// The `d + 1` vertices.
    pub fn vertices(&self) -> &[Point<D>] {
        &self.vertices[..=D]
    }

    /// The same simplex with its vertices sorted (a canonical key for comparisons).
    pub fn sorted(&self) -> Simplex<D> {
        let mut s = *self;
        s.vertices[..=D].sort_unstable();
        s
    }

    /// [`Simplex::scaled_volume`] when it fits a `u128` and the elimination fits `i128`.
    pub fn scaled_volume_u128(&self) -> Option<u128> {
        let v = self.vertices();
        let mut m = [[0i128; MAX_DIM]; MAX_DIM];
        for r in 0..D {
            for c in 0..D {
                m[r][c] = i128::from(v[r + 1][c]) - i128::from(v[0][c]);
            }
        }
        match D {
            // Cofactor expansion: entries below 2^33 in magnitude keep every term below 2^102.
            2 => Some((m[0][0] * m[1][1] - m[0][1] * m[1][0]).unsigned_abs()),
            3 => Some(
                (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
                    - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                    + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
                    .unsigned_abs(),
            ),
            _ => bareiss_det_checked(&mut m, D).map(i128::unsigned_abs),
        }
    }

    /// `d! · volume`, exactly: `|det(v₁ − v₀, …, v_d − v₀)|`.
    ///
    /// The differences' common power-of-two factor `g` is taken out first (grid simplices'
    /// edges are multiples of their diamond's `h`), the small determinant is computed by
    /// fraction-free elimination in checked `i128` (in `BigInt` should it overflow), and
    /// multiplied by `g^d`.
    pub fn scaled_volume(&self) -> BigUint {
        let v = self.vertices();
        let mut m = [[0i128; MAX_DIM]; MAX_DIM];
        let mut shift = u32::MAX;
        for r in 0..D {
            for c in 0..D {
                let e = i128::from(v[r + 1][c]) - i128::from(v[0][c]);
                if e != 0 {
                    shift = shift.min(e.trailing_zeros());
                }
                m[r][c] = e;
            }
        }
        if shift == u32::MAX {
            return BigUint::from(0u8);
        }
        for row in m.iter_mut().take(D) {
            for e in row.iter_mut().take(D) {
                *e >>= shift;
            }
        }
        let det = match bareiss_det_checked(&mut m.clone(), D) {
            Some(d) => BigInt::from(d),
            None => bareiss_det_big(&m, D),
        };
        det.magnitude() << (shift as usize * D)
    }
}

/// The determinant of the leading `n × n` block by Bareiss's fraction-free elimination (every
/// division is exact); `None` on `i128` overflow.
pub(crate) fn bareiss_det_checked(m: &mut [[i128; MAX_DIM]; MAX_DIM], n: usize) -> Option<i128> {
    let mut sign = 1i128;
    let mut prev = 1i128;
    for k in 0..n {
        if m[k][k] == 0 {
            match (k + 1..n).find(|&r| m[r][k] != 0) {
                Some(r) => {
                    m.swap(k, r);
                    sign = -sign;
                }
                None => return Some(0),
            }
        }
        for i in k + 1..n {
            for j in k + 1..n {
                let a = m[i][j].checked_mul(m[k][k])?;
                let b = m[i][k].checked_mul(m[k][j])?;
                m[i][j] = a.checked_sub(b)? / prev;
            }
        }
        prev = m[k][k];
    }
    Some(sign * m[n - 1][n - 1])
}

/// [`bareiss_det_checked`] in `BigInt`.
fn bareiss_det_big(m: &[[i128; MAX_DIM]; MAX_DIM], n: usize) -> BigInt {
    let mut a: Vec<Vec<BigInt>> = (0..n)
        .map(|r| (0..n).map(|c| BigInt::from(m[r][c])).collect())
        .collect();
    let mut sign = 1;
    let mut prev = BigInt::from(1);
    for k in 0..n {
        if a[k][k].is_zero() {
            match (k + 1..n).find(|&r| !a[r][k].is_zero()) {
                Some(r) => {
                    a.swap(k, r);
                    sign = -sign;
                }
                None => return BigInt::from(0),
            }
        }
        for i in k + 1..n {
            for j in k + 1..n {
                a[i][j] = (&a[i][j] * &a[k][k] - &a[i][k] * &a[k][j]) / &prev;
            }
        }
        prev = a[k][k].clone();
    }
    &a[n - 1][n - 1] * sign
}
