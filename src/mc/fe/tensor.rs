//! Eqs. (1) and (2) by sum factorisation, in `f64`: an element's dofs regrouped as a tensor
//! of 1-D coefficients, contracted one `ξ` direction at a time.
//!
//! Along direction `d` the element uses `m_d` of the four 1-D functions `[φ₁⁰, φ₁¹, φ₂⁰, φ₂¹]`:
//! all four for cubic Hermite, `φ₁⁰, φ₂⁰` (`L₁, L₂`) for linear Lagrange. Dof `k` of local node
//! `(s₀, s₁, s₂)` multiplies `Π_d φ_{a_d}(ξ_d)` with `a_d = 2s_d + [k differentiates along d]`
//! (Hermite) or `a_d = s_d` (Lagrange), so eq. (1) is `u(ξ) = Σ_{a,b,c} C[c][b][a] B₀[a] B₁[b]
//! B₂[c]`: `m₀m₁m₂` products of three 1-D values instead of `8 · dofs` products of three, and
//! on a lattice the partial sums over `a` and `b` are shared by whole rows and planes.
//!
//! **Error bound.** Let `u` be the unit roundoff (`2⁻⁵³`). Every 1-D value computed in `f64`
//! at an `f64` point is within `12u` of the true one and every true value has `|φ| ≤ 1`
//! (Section 2's functions on `[0, 1]`). A stage `ŷ = fl(Σ_{a<m} φ̂_a x̂_a)` with `m ≤ 4` and
//! inputs `|x̂_a − x_a| ≤ e·S_a`, `|x_a| ≤ S_a`, errs by at most
//! `Σ|φ̂ − φ||x̂| + Σ|φ||x̂ − x| + γ₄ Σ|φ̂||x̂| ≤ (e + 16.01u)·Σ S_a` (to first order, with the
//! second-order terms below `0.01u` for `e ≤ 2⁻⁴⁰`). Three stages from exact coefficients give
//! `|fl(u(ξ)) − u(ξ)| ≤ 48.1u · Σ|C| < 2⁻⁴⁵ · Σ|C|`, and `Σ|C|` is the sum of the element's
//! absolute dofs: the bound the fast path uses ([`VALUE_BOUND`](super::fast)), with more than
//! a factor 5 to spare. The order of the additions does not enter the bound.

use super::basis::{basis_derivative_f64, basis_f64};
use super::{Basis, ElementKind, FeModel};

/// Active 1-D functions per direction: 2 (linear Lagrange) or 4 (cubic Hermite).
pub(crate) fn active(b: Basis) -> usize {
    match b {
        Basis::LinearLagrange => 2,
        Basis::CubicHermite => 4,
    }
}

/// The active entries of a 1-D basis vector `[φ₁⁰, φ₁¹, φ₂⁰, φ₂¹]`.
fn select(b: Basis, full: [f64; 4]) -> [f64; 4] {
    match b {
        Basis::LinearLagrange => [full[0], full[2], 0.0, 0.0],
        Basis::CubicHermite => full,
    }
}

/// Element `nodes`' dofs in tensor order: per dof, its slot `(c · m₁ + b) · m₀ + a` (the
/// module docs' `a_d`) and its index in the model's node-major arrays.
pub(crate) fn dof_slots(
    kind: ElementKind,
    nodes: &[u32; 8],
) -> impl Iterator<Item = (usize, usize)> + '_ {
    let ndof = kind.dofs_per_node();
    let md = kind.bases.map(active);
    nodes.iter().enumerate().flat_map(move |(local, &node)| {
        let side = [local & 1, local >> 1 & 1, local >> 2 & 1];
        (0..ndof).map(move |k| {
            let der = kind.derivative_of_dof(k);
            let a: [usize; 3] = std::array::from_fn(|d| match kind.bases[d] {
                Basis::LinearLagrange => side[d],
                Basis::CubicHermite => 2 * side[d] + usize::from(der[d]),
            });
            (
                (a[2] * md[1] + a[1]) * md[0] + a[0],
                node as usize * ndof + k,
            )
        })
    })
}

/// [`dof_slots`] as a table of (slot, local node, dof of the node), one row per dof of an
/// element of kind `kind`.
pub(crate) fn slot_table(kind: ElementKind) -> Vec<(u8, u8, u8)> {
    let ndof = kind.dofs_per_node();
    let local: [u32; 8] = std::array::from_fn(|l| l as u32);
    dof_slots(kind, &local)
        .map(|(slot, dof)| (slot as u8, (dof / ndof) as u8, (dof % ndof) as u8))
        .collect()
}

/// The four interpolated channels: the field `u` and the world coordinates `x, y, z`.
pub(crate) const CHANNELS: usize = 4;

/// One element's eqs. (1) and (2) in tensor form.
#[derive(Clone, Debug)]
pub(crate) struct ElementTensor {
    bases: [Basis; 3],
    /// `m_d`: active 1-D functions per direction.
    m: [usize; 3],
    /// `coeffs[(c · m₁ + b) · m₀ + a][channel]`; channel 0 is the field, 1–3 the coordinates
    /// (interleaved, so that one pass over the slots serves all four channels).
    coeffs: [[f64; CHANNELS]; 64],
}

/// Value and first derivatives of the four channels at one point.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Jet {
    /// `[u, x, y, z]`.
    pub(crate) value: [f64; CHANNELS],
    /// `∂/∂ξ_d` of `[u, x, y, z]`, per `d`.
    pub(crate) d: [[f64; CHANNELS]; 3],
}

impl ElementTensor {
    /// Gathers element `nodes`' dofs of `m` into the tensor.
    #[cfg(test)]
    pub(crate) fn new(m: &FeModel<f64>, nodes: &[u32; 8]) -> ElementTensor {
        let mut t = ElementTensor::empty(m.kind);
        t.load(m, nodes, &slot_table(m.kind));
        t
    }

    /// A tensor of kind `kind` with no element loaded (all coefficients zero).
    pub(crate) fn empty(kind: ElementKind) -> ElementTensor {
        ElementTensor {
            bases: kind.bases,
            m: kind.bases.map(active),
            coeffs: [[0.0; CHANNELS]; 64],
        }
    }

    /// Overwrites the coefficients with element `nodes`' dofs of `m` (of the tensor's kind),
    /// by `table` (from [`slot_table`]): every active slot holds one dof, so nothing of the
    /// previous element remains. Returns `Σ |u dof|` and `Σ max |x dof|` (for the bounds).
    pub(crate) fn load(
        &mut self,
        m: &FeModel<f64>,
        nodes: &[u32; 8],
        table: &[(u8, u8, u8)],
    ) -> (f64, f64) {
        let ndof = m.kind.dofs_per_node();
        let (mut s_u, mut s_x) = (0.0f64, 0.0f64);
        for &(slot, local, k) in table {
            let dof = nodes[local as usize] as usize * ndof + k as usize;
            let (u, x) = (m.field[dof], m.coordinates[dof]);
            s_u += u.abs();
            s_x += x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            self.coeffs[slot as usize] = [u, x[0], x[1], x[2]];
        }
        (s_u, s_x)
    }

    /// The element kind's active 1-D values at `t` along direction `d`.
    pub(crate) fn basis(&self, d: usize, t: f64) -> [f64; 4] {
        select(self.bases[d], basis_f64(self.bases[d], t))
    }

    /// The same for the derivatives.
    fn basis_derivative(&self, d: usize, t: f64) -> [f64; 4] {
        select(self.bases[d], basis_derivative_f64(self.bases[d], t))
    }

    /// The per-direction tables of active 1-D values at the lattice points `i / n_d`,
    /// `i = 0..=n_d`.
    pub(crate) fn lattice_bases(kind: ElementKind, n: [usize; 3]) -> [Vec<[f64; 4]>; 3] {
        std::array::from_fn(|d| {
            (0..=n[d])
                .map(|i| {
                    select(
                        kind.bases[d],
                        basis_f64(kind.bases[d], i as f64 / n[d] as f64),
                    )
                })
                .collect()
        })
    }

    /// Eq. (1) at every lattice point: `out[(k (n₁+1) + j)(n₀+1) + i] = u(i/n₀, j/n₁, k/n₂)`,
    /// three contractions over shared partial sums. `scratch` is reused between calls.
    pub(crate) fn sample_field(
        &self,
        lattice: &[Vec<[f64; 4]>; 3],
        scratch: &mut Vec<f64>,
        out: &mut Vec<f64>,
    ) {
        let [m0, m1, m2] = self.m;
        let (p0, p1, p2) = (lattice[0].len(), lattice[1].len(), lattice[2].len());
        let c: [f64; 64] = std::array::from_fn(|slot| self.coeffs[slot][0]);
        // t1[(c·m₁ + b)·p₀ + i] = Σ_a B₀[i][a] C[c][b][a]; then t2[(c·p₁ + j)·p₀ + i].
        let t1_len = m2 * m1 * p0;
        scratch.clear();
        scratch.resize(t1_len + m2 * p1 * p0, 0.0);
        let (t1, t2) = scratch.split_at_mut(t1_len);
        for cb in 0..m2 * m1 {
            let coef = &c[cb * m0..cb * m0 + m0];
            let row = &mut t1[cb * p0..(cb + 1) * p0];
            for (slot, b0) in row.iter_mut().zip(&lattice[0]) {
                let mut s = 0.0;
                for a in 0..m0 {
                    s += b0[a] * coef[a];
                }
                *slot = s;
            }
        }
        for cc in 0..m2 {
            for (j, b1) in lattice[1].iter().enumerate() {
                let row = &mut t2[(cc * p1 + j) * p0..(cc * p1 + j + 1) * p0];
                for (b, &w) in b1.iter().enumerate().take(m1) {
                    let src = &t1[(cc * m1 + b) * p0..(cc * m1 + b + 1) * p0];
                    for (r, s) in row.iter_mut().zip(src) {
                        *r += w * s;
                    }
                }
            }
        }
        out.clear();
        out.resize(p0 * p1 * p2, 0.0);
        for (k, b2) in lattice[2].iter().enumerate() {
            let plane = &mut out[k * p1 * p0..(k + 1) * p1 * p0];
            for (cc, &w) in b2.iter().enumerate().take(m2) {
                let src = &t2[cc * p1 * p0..(cc + 1) * p1 * p0];
                for (r, s) in plane.iter_mut().zip(src) {
                    *r += w * s;
                }
            }
        }
    }

    /// Values and first `ξ`-derivatives of the field and the world map at `ξ`. Each channel
    /// is summed in the same order as a channel-by-channel contraction would; the four run
    /// side by side.
    pub(crate) fn jet(&self, xi: [f64; 3]) -> Jet {
        let bv = [0, 1, 2].map(|d| self.basis(d, xi[d]));
        let bd = [0, 1, 2].map(|d| self.basis_derivative(d, xi[d]));
        let [m0, m1, m2] = self.m;
        let zero = [0.0; CHANNELS];
        let (mut val, mut d0, mut d1, mut d2) = (zero, zero, zero, zero);
        for cc in 0..m2 {
            let (mut vv, mut dv, mut vd) = (zero, zero, zero);
            for bb in 0..m1 {
                let base = (cc * m1 + bb) * m0;
                let (mut v, mut d) = (zero, zero);
                for a in 0..m0 {
                    let c = &self.coeffs[base + a];
                    for ch in 0..CHANNELS {
                        v[ch] += bv[0][a] * c[ch];
                        d[ch] += bd[0][a] * c[ch];
                    }
                }
                for ch in 0..CHANNELS {
                    vv[ch] += bv[1][bb] * v[ch];
                    dv[ch] += bv[1][bb] * d[ch];
                    vd[ch] += bd[1][bb] * v[ch];
                }
            }
            for ch in 0..CHANNELS {
                val[ch] += bv[2][cc] * vv[ch];
                d0[ch] += bv[2][cc] * dv[ch];
                d1[ch] += bv[2][cc] * vd[ch];
                d2[ch] += bd[2][cc] * vv[ch];
            }
        }
        Jet {
            value: val,
            d: [d0, d1, d2],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::basis::terms_f64;
    use super::super::{heart, models};
    use super::*;

    /// Eq. (1)/(2) term by term, the way the fast path evaluated them before this module.
    fn direct(m: &FeModel<f64>, nodes: &[u32; 8], xi: [f64; 3], der: Option<usize>) -> [f64; 4] {
        let mut terms = [(0usize, 0usize, 0.0f64); 64];
        let count = terms_f64(m.kind, xi, der, &mut terms);
        let ndof = m.kind.dofs_per_node();
        let mut out = [0.0; 4];
        for &(node, k, w) in &terms[..count] {
            let dof = nodes[node] as usize * ndof + k;
            out[0] += w * m.field[dof];
            for c in 0..3 {
                out[1 + c] += w * m.coordinates[dof][c];
            }
        }
        out
    }

    fn close(a: [f64; 4], b: [f64; 4], scale: f64) -> bool {
        a.iter()
            .zip(&b)
            .all(|(x, y)| (x - y).abs() <= 1e-12 * scale)
    }

    #[test]
    fn sum_factorisation_equals_the_term_by_term_sums() {
        let lagrange = models::block(
            ElementKind::TRILINEAR_LAGRANGE,
            [2, 2, 1],
            &|p| (p[0] - 0.3) * (p[1] + 0.7) - p[2],
            &|_, _| 0.0,
            &|p| {
                [
                    p[0] + 0.1 * p[1] * p[2],
                    p[1] - 0.2 * p[0],
                    p[2] + 0.05 * p[0] * p[1],
                ]
            },
        );
        for m in [heart::left_ventricle(), models::hermite_ball(2), lagrange] {
            let n = [3, 4, 5];
            let lattice = ElementTensor::lattice_bases(m.kind, n);
            let (mut scratch, mut out) = (Vec::new(), Vec::new());
            for nodes in &m.elements {
                let t = ElementTensor::new(&m, nodes);
                let scale: f64 = 1.0
                    + m.field.iter().map(|x| x.abs()).sum::<f64>()
                    + m.coordinates.iter().flatten().map(|x| x.abs()).sum::<f64>();
                t.sample_field(&lattice, &mut scratch, &mut out);
                for k in 0..=n[2] {
                    for j in 0..=n[1] {
                        for i in 0..=n[0] {
                            let xi = [i as f64 / 3.0, j as f64 / 4.0, k as f64 / 5.0];
                            let want = direct(&m, nodes, xi, None);
                            let got = out[(k * 5 + j) * 4 + i];
                            assert!((got - want[0]).abs() <= 1e-12 * scale, "{got} {want:?}");
                        }
                    }
                }
                let xi = [0.31, 0.77, 0.12];
                let jet = t.jet(xi);
                assert!(close(jet.value, direct(&m, nodes, xi, None), scale));
                for d in 0..3 {
                    assert!(close(jet.d[d], direct(&m, nodes, xi, Some(d)), scale));
                }
            }
        }
    }
}
