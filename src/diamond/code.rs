//! The implicit encoding (fast path): everything about a diamond from its central vertex by bit
//! operations (Section 5.1, eq. 1; Section 5.4 for `d ≠ 3`). No hierarchy is stored.

use super::{DiamondError, Point, Simplex, MAX_DIM};
use std::sync::OnceLock;

/// The largest `N`: coordinates up to `2^30` keep every `c ± 2h` inside `u32`.
pub const MAX_LEVELS: u32 = 30;

/// The grid `[0, 2^N]^d` of a diamond hierarchy with `N` levels of supercubes' scales.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Hierarchy<const D: usize> {
    levels: u32,
}

impl<const D: usize> Hierarchy<D> {
    const SUPPORTED: () = assert!(
        D >= 2 && D <= MAX_DIM,
        "diamond hierarchies need 2 <= d <= 5"
    );

    /// The hierarchy on `(2^N + 1)^d` points; `N` must be in `1..=MAX_LEVELS`.
    pub fn new(levels: u32) -> Result<Hierarchy<D>, DiamondError> {
        let () = Self::SUPPORTED;
        if levels == 0 || levels > MAX_LEVELS {
            return Err(DiamondError::Levels {
                levels,
                max: MAX_LEVELS,
            });
        }
        Ok(Hierarchy { levels })
    }

    /// `N`.
    pub fn levels(&self) -> u32 {
        self.levels
    }

    /// `2^N`, the domain's side.
    pub fn side(&self) -> u32 {
        1 << self.levels
    }

    /// `(2^N + 1)^d − 2^d`, the number of diamonds (`None` beyond `u128`).
    pub fn diamond_count(&self) -> Option<u128> {
        (u128::from(self.side()) + 1)
            .checked_pow(D as u32)
            .map(|n| n - (1u128 << D))
    }

    /// `d! · (2^(dN+1) − 1)`, the number of simplices of the whole hierarchy down to the unit
    /// cubes' Kuhn simplices (`None` beyond `u128`).
    pub fn simplex_count(&self) -> Option<u128> {
        let exp = (D as u32).checked_mul(self.levels)?.checked_add(1)?;
        let all = 1u128.checked_shl(exp).filter(|_| exp < 128)? - 1;
        all.checked_mul((1..=D as u128).product())
    }

    /// True when `p` lies in `[0, 2^N]^d`.
    pub fn contains(&self, p: &Point<D>) -> bool {
        p.iter().all(|&x| x <= self.side())
    }

    /// True when `p` is one of the `2^d` domain corners.
    pub fn is_corner(&self, p: &Point<D>) -> bool {
        p.iter().all(|&x| x == 0 || x == self.side())
    }

    /// The diamond whose central vertex is `center`.
    pub fn diamond(&self, center: Point<D>) -> Result<Diamond<D>, DiamondError> {
        if !self.contains(&center) {
            return Err(DiamondError::OutOfRange {
                point: center.iter().map(|&x| u64::from(x)).collect(),
                side: u64::from(self.side()),
            });
        }
        if self.is_corner(&center) {
            return Err(DiamondError::Corner {
                point: center.iter().map(|&x| u64::from(x)).collect(),
            });
        }
        Ok(self.diamond_unchecked(center))
    }

    /// [`Hierarchy::diamond`] for a point known to be a valid central vertex.
    pub(super) fn diamond_unchecked(&self, center: Point<D>) -> Diamond<D> {
        // The scale: the fewest trailing zeros (eq. 1); `0` has 32, more than any `N`.
        let scale = center.iter().map(|x| x.trailing_zeros()).min().unwrap_or(0);
        Diamond {
            center,
            scale: scale as u8,
            levels: self.levels as u8,
        }
    }

    /// The base diamond: the class-0 diamond at the domain's centre, spine the main diagonal.
    pub fn root(&self) -> Diamond<D> {
        self.diamond_unchecked([self.side() / 2; D])
    }
}

/// A diamond, identified by its central vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Diamond<const D: usize> {
    center: Point<D>,
    scale: u8,
    levels: u8,
}

impl<const D: usize> Diamond<D> {
    /// The central vertex `v_c`.
    pub fn center(&self) -> Point<D> {
        self.center
    }

    /// The scale `γ`: the fewest trailing zeros of the central vertex's coordinates (eq. 1).
    pub fn scale(&self) -> u32 {
        u32::from(self.scale)
    }

    /// The level `N − γ` (Section 5.1).
    pub fn level(&self) -> u32 {
        u32::from(self.levels) - self.scale()
    }

    /// `h = 2^γ`: half the spine's extent along each odd axis.
    pub fn half_width(&self) -> u32 {
        1 << self.scale
    }

    /// The hierarchy this diamond belongs to.
    pub fn hierarchy(&self) -> Hierarchy<D> {
        Hierarchy {
            levels: u32::from(self.levels),
        }
    }

    /// The odd axes as a bit mask: bit `k` set when bit `γ` of coordinate `k` is one.
    pub fn odd_axes(&self) -> u32 {
        (0..D).fold(0, |m, k| m | (((self.center[k] >> self.scale) & 1) << k))
    }

    /// The class `i`: the number of zeros among the bits at position `γ` (Section 5.1).
    pub fn class(&self) -> usize {
        D - self.odd_axes().count_ones() as usize
    }

    /// The type `τ`: bits `γ` and `γ + 1` of every coordinate, two bits per axis.
    pub fn diamond_type(&self) -> super::DiamondType<D> {
        let code = (0..D).fold(0, |t, k| {
            t | (((self.center[k] >> self.scale) & 3) << (2 * k))
        });
        super::DiamondType::from_code_unchecked(code)
    }

    /// The origin `σ` of the supercube holding this diamond: the central vertex with its low
    /// `γ + 2` bits cleared (`v_c = σ + (τ ≪ γ)`).
    pub fn supercube_origin(&self) -> Point<D> {
        let mask = !((4u32 << self.scale) - 1);
        self.center.map(|x| x & mask)
    }

    /// The spine `[a, b]`: `a = c − h·s`, `b = c + h·s` on the odd axes, where `s_k = +1` when
    /// bit `γ + 1` of `c_k` is zero; `a ≡ 0` and `b ≡ 2h (mod 4h)` there.
    pub fn spine(&self) -> [Point<D>; 2] {
        let h = self.half_width();
        let odd = self.odd_axes();
        let mut a = self.center;
        let mut b = self.center;
        for k in 0..D {
            if odd >> k & 1 == 1 {
                if self.up(k) {
                    a[k] -= h;
                    b[k] += h;
                } else {
                    a[k] += h;
                    b[k] -= h;
                }
            }
        }
        [a, b]
    }

    /// True when the spine runs towards increasing `x_k` (bit `γ + 1` of `c_k` is zero).
    fn up(&self, k: usize) -> bool {
        (self.center[k] >> (self.scale + 1)) & 1 == 0
    }

    /// `c + h·offset`, or `None` outside the domain.
    fn offset(&self, offset: [i64; D], unit: u32) -> Option<Point<D>> {
        let side = i64::from(self.hierarchy().side());
        let mut p = self.center;
        for k in 0..D {
            let x = i64::from(self.center[k]) + offset[k] * i64::from(unit);
            if !(0..=side).contains(&x) {
                return None;
            }
            p[k] = x as u32;
        }
        Some(p)
    }

    /// True when the domain boundary cuts the diamond (fewer simplices, vertices, parents).
    pub fn is_clipped(&self) -> bool {
        let side = self.hierarchy().side();
        let odd = self.odd_axes();
        (0..D).any(|k| odd >> k & 1 == 0 && (self.center[k] == 0 || self.center[k] == side))
    }

    /// The vertices inside the domain: the `2^(d−i)` corners of the odd axes' cube and the
    /// points `c + h·v`, `v ∈ {−1, 0, 1}^even ∖ {0}`.
    pub fn vertices(&self) -> Vec<Point<D>> {
        let (odd, even) = self.axes();
        let mut out = Vec::new();
        for t in 0..1u32 << odd.len() {
            let mut off = [0i64; D];
            for (j, &k) in odd.iter().enumerate() {
                off[k] = if t >> j & 1 == 1 { 1 } else { -1 };
            }
            out.extend(self.offset(off, self.half_width()));
        }
        for t in 0..3usize.pow(even.len() as u32) {
            let mut off = [0i64; D];
            let mut r = t;
            for &k in even.iter() {
                off[k] = (r % 3) as i64 - 1;
                r /= 3;
            }
            if off.iter().any(|&o| o != 0) {
                out.extend(self.offset(off, self.half_width()));
            }
        }
        out
    }

    /// The odd and the even axes, in increasing order.
    fn axes(&self) -> (Axes<D>, Axes<D>) {
        let odd = self.odd_axes();
        let mut o = Axes {
            list: [0; D],
            len: 0,
        };
        let mut e = o;
        for k in 0..D {
            let a = if odd >> k & 1 == 1 { &mut o } else { &mut e };
            a.list[a.len] = k;
            a.len += 1;
        }
        (o, e)
    }

    /// The slot in which `parent` (a parent of this diamond) appears, by the parents' formulas
    /// of [`Diamond::parent_in_slot`]; `None` when `parent` is no parent.
    #[inline]
    pub fn slot_of_parent(&self, parent: &Diamond<D>) -> Option<usize> {
        let slot = self.slot_of_parent_unchecked(parent)?;
        (self.parent_in_slot(slot).as_ref() == Some(parent)).then_some(slot)
    }

    /// [`Diamond::slot_of_parent`] for a `parent` known to be a parent (no re-check).
    #[inline]
    pub(crate) fn slot_of_parent_unchecked(&self, parent: &Diamond<D>) -> Option<usize> {
        let slot = if self.class() == 0 {
            // The parent (class d−1) has a single odd axis: its slot.
            let odd = parent.odd_axes();
            if odd.count_ones() != 1 {
                return None;
            }
            odd.trailing_zeros() as usize
        } else {
            let k = (0..D).find(|&k| self.center[k] != parent.center[k])?;
            let even = !self.odd_axes() & ((1 << D) - 1);
            let rank = (even & ((1 << k) - 1)).count_ones() as usize;
            2 * rank + usize::from(parent.center[k] > self.center[k])
        };
        Some(slot)
    }

    /// The flags of the slots whose parent does not exist: every slot of a class-0 diamond at
    /// scale `N − 1` (the root's parents would be domain corners), and for class `i ≥ 1` the
    /// slot `c ± h e_k` when `c_k` is `0` or `2^N`.
    #[inline]
    pub fn absent_parent_flags(&self) -> u32 {
        if self.class() == 0 {
            return if self.scale() + 1 == u32::from(self.levels) {
                (1 << D) - 1
            } else {
                0
            };
        }
        let side = self.hierarchy().side();
        let odd = self.odd_axes();
        let mut flags = 0;
        let mut j = 0;
        for k in 0..D {
            if odd >> k & 1 == 0 {
                if self.center[k] == 0 {
                    flags |= 1 << (2 * j);
                }
                if self.center[k] == side {
                    flags |= 1 << (2 * j + 1);
                }
                j += 1;
            }
        }
        flags
    }

    /// Calls `f(simplex, parent_slot)` for every simplex of the diamond inside the domain;
    /// `parent_slot` names the parent whose bisection created it (see
    /// [`Diamond::parent_in_slot`]).
    ///
    /// A simplex is the Kuhn chain `a, a + 2h s_{ρ₁}e_{ρ₁}, …, b` through the odd axes (`ρ` a
    /// permutation of them) followed by the chain `c + hσ_{π₁}e_{π₁}, c + h(σ_{π₁}e_{π₁} +
    /// σ_{π₂}e_{π₂}), …` through the even axes (`π` a permutation, `σ` signs):
    /// `(d−i)!·i!·2^i` of them before clipping.
    pub fn for_each_simplex(&self, mut f: impl FnMut(Simplex<D>, usize)) {
        let (odd, even) = self.axes();
        let h = i64::from(self.half_width());
        let side = i64::from(self.hierarchy().side());
        let [a, _] = self.spine();
        let mut s = Simplex {
            vertices: [[0; D]; MAX_DIM + 1],
        };
        for rho in permutations(odd.len()) {
            let mut p = a;
            s.vertices[0] = p;
            for (j, &r) in rho.iter().take(odd.len()).enumerate() {
                let k = odd[r as usize];
                p[k] = if self.up(k) {
                    p[k] + 2 * h as u32
                } else {
                    p[k] - 2 * h as u32
                };
                s.vertices[j + 1] = p;
            }
            for pi in permutations(even.len()) {
                'signs: for sigma in 0..1u32 << even.len() {
                    let mut q = self.center.map(i64::from);
                    for (j, &e) in pi.iter().take(even.len()).enumerate() {
                        let k = even[e as usize];
                        q[k] += if sigma >> e & 1 == 1 { h } else { -h };
                        if !(0..=side).contains(&q[k]) {
                            continue 'signs;
                        }
                        s.vertices[odd.len() + 1 + j] = q.map(|x| x as u32);
                    }
                    let slot = if even.is_empty() {
                        odd[rho[0] as usize]
                    } else {
                        2 * pi[0] as usize + (sigma >> pi[0] & 1) as usize
                    };
                    f(s, slot);
                }
            }
        }
    }

    /// The simplices inside the domain, in [`Diamond::for_each_simplex`]'s order.
    pub fn simplices(&self) -> Vec<Simplex<D>> {
        let mut out = Vec::new();
        self.for_each_simplex(|s, _| out.push(s));
        out
    }

    /// The number of parent slots: `d` for class 0, `2i` otherwise (Section 3: 3/2/4 in 3-D).
    pub fn parent_slots(&self) -> usize {
        match self.class() {
            0 => D,
            i => 2 * i,
        }
    }

    /// The parent in `slot`, or `None` where the domain boundary (or the root) leaves it out.
    ///
    /// Class 0: slot `k` is the class-`(d−1)` diamond at scale `γ + 1` centred at
    /// `a + 2h s_k e_k`. Class `i ≥ 1`: slot `2j + σ` is the class-`(i−1)` diamond at the same
    /// scale centred at `c ± h e_k`, `k` the `j`-th even axis, `+` when `σ = 1`.
    pub fn parent_in_slot(&self, slot: usize) -> Option<Diamond<D>> {
        let h = self.half_width();
        let odd = self.odd_axes();
        let mut p = self.center;
        let scale = if odd.count_ones() as usize == D {
            // Class 0: a + 2h s_k e_k, at scale γ + 1 (a corner, so absent, at γ + 1 = N).
            if slot >= D || self.scale + 1 >= self.levels {
                return None;
            }
            let [a, _] = self.spine();
            p = a;
            if self.up(slot) {
                p[slot] += 2 * h;
            } else {
                p[slot] -= 2 * h;
            }
            self.scale + 1
        } else {
            // Class i ≥ 1: c ± h e_k, k the (slot/2)-th even axis, at the same scale.
            let k = (0..D).filter(|&k| odd >> k & 1 == 0).nth(slot / 2)?;
            if slot % 2 == 1 {
                if self.center[k] == self.hierarchy().side() {
                    return None;
                }
                p[k] += h;
            } else {
                if self.center[k] == 0 {
                    return None;
                }
                p[k] -= h;
            }
            self.scale
        };
        Some(Diamond {
            center: p,
            scale,
            levels: self.levels,
        })
    }

    /// The parents inside the domain, in slot order.
    pub fn parents(&self) -> Points<D> {
        let mut out = Points::new();
        for slot in 0..self.parent_slots() {
            if let Some(p) = self.parent_in_slot(slot) {
                out.push(p.center);
            }
        }
        out
    }

    /// The children inside the domain: for class `i < d−1` the class-`(i+1)` diamonds at
    /// `c ± h e_k` over the odd axes (`2(d−i)`), for class `d−1` the class-0 diamonds at
    /// `c + (h/2)·t`, `t ∈ {±1}^d` (`2^d`, none at scale 0).
    pub fn children(&self) -> Points<D> {
        let mut out = Points::new();
        self.for_each_child(|c| out.push(c.center));
        out
    }

    /// Calls `f` with each child inside the domain, in [`Diamond::children`]'s order.
    #[inline]
    pub fn for_each_child(&self, mut f: impl FnMut(Diamond<D>)) {
        self.for_each_child_slot(|child, _| f(child));
    }

    /// [`Diamond::for_each_child`] with the slot in which this diamond is the child's parent
    /// (what [`Diamond::slot_of_parent`] would find): for same-scale children `c ± h e_k` the
    /// slot `2j + σ`, `j` the rank of `k` among the child's even axes and `σ = 1` for `c − h e_k`
    /// (its parent lies at `+h`); for the children of a class-`(d−1)` diamond its one odd axis.
    #[inline]
    pub fn for_each_child_slot(&self, mut f: impl FnMut(Diamond<D>, usize)) {
        let odd = self.odd_axes();
        let h = self.half_width();
        if (odd.count_ones() as usize) > 1 {
            // Same scale: an odd coordinate moves by ±h to a multiple of 2h.
            let even = !odd & ((1 << D) - 1);
            for k in 0..D {
                if odd >> k & 1 == 1 {
                    let rank = (even & ((1 << k) - 1)).count_ones() as usize;
                    for up in [false, true] {
                        let mut p = self.center;
                        p[k] = if up { p[k] + h } else { p[k] - h };
                        let child = Diamond {
                            center: p,
                            scale: self.scale,
                            levels: self.levels,
                        };
                        f(child, 2 * rank + usize::from(!up));
                    }
                }
            }
        } else if self.scale > 0 {
            let slot = odd.trailing_zeros() as usize;
            let side = self.hierarchy().side();
            let half = h / 2;
            'corners: for t in 0..1u32 << D {
                let mut p = self.center;
                for (k, x) in p.iter_mut().enumerate() {
                    if t >> k & 1 == 1 {
                        if *x == side {
                            continue 'corners;
                        }
                        *x += half;
                    } else {
                        if *x == 0 {
                            continue 'corners;
                        }
                        *x -= half;
                    }
                }
                let child = Diamond {
                    center: p,
                    scale: self.scale - 1,
                    levels: self.levels,
                };
                f(child, slot);
            }
        }
    }

    /// The diamond of a hierarchy with one level fewer centred at half this one's central
    /// vertex, for a diamond of scale at least 1 (its centre is even and no domain corner, so
    /// the half is a central vertex of scale `γ − 1`).
    #[inline]
    pub(crate) fn halved(&self) -> Diamond<D> {
        debug_assert!(self.scale > 0 && self.levels > 0);
        Diamond {
            center: self.center.map(|x| x / 2),
            scale: self.scale - 1,
            levels: self.levels - 1,
        }
    }
}

/// All permutations of `0..n` (`n ≤ MAX_DIM`), each padded to `MAX_DIM` entries.
fn permutations(n: usize) -> &'static [[u8; MAX_DIM]] {
    static TABLES: [OnceLock<Vec<[u8; MAX_DIM]>>; MAX_DIM + 1] =
        [const { OnceLock::new() }; MAX_DIM + 1];
    TABLES[n].get_or_init(|| {
        let mut out = Vec::new();
        let mut cur = [0u8; MAX_DIM];
        fn rec(
            n: usize,
            used: u32,
            depth: usize,
            cur: &mut [u8; MAX_DIM],
            out: &mut Vec<[u8; MAX_DIM]>,
        ) {
            if depth == n {
                out.push(*cur);
                return;
            }
            for v in 0..n {
                if used >> v & 1 == 0 {
                    cur[depth] = v as u8;
                    rec(n, used | 1 << v, depth + 1, cur, out);
                }
            }
        }
        rec(n, 0, 0, &mut cur, &mut out);
        out
    })
}

/// A short list of axes.
#[derive(Clone, Copy, Debug)]
struct Axes<const D: usize> {
    list: [usize; D],
    len: usize,
}

impl<const D: usize> std::ops::Deref for Axes<D> {
    type Target = [usize];
    fn deref(&self) -> &[usize] {
        &self.list[..self.len]
    }
}

/// A short list of grid points (at most `2^MAX_DIM`), without allocation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Points<const D: usize> {
    items: [Point<D>; 1 << MAX_DIM],
    len: u8,
}

impl<const D: usize> Points<D> {
    fn new() -> Points<D> {
        Points {
            items: [[0; D]; 1 << MAX_DIM],
            len: 0,
        }
    }

    fn push(&mut self, p: Point<D>) {
        self.items[self.len as usize] = p;
        self.len += 1;
    }
}

impl<const D: usize> std::ops::Deref for Points<D> {
    type Target = [Point<D>];
    fn deref(&self) -> &[Point<D>] {
        &self.items[..self.len as usize]
    }
}
