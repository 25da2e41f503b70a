//! The fast path's Jacobian: per cell, the Bézier net's partial derivatives and Bernstein
//! products in `f64` (a different route from the reference's Mørken products), with a
//! rigorous forward error bound.
//!
//! Products are formed in the scaled basis `C(n,i) tⁱ(1−t)ⁿ⁻ⁱ`, where a Bernstein product is a
//! plain convolution (NOTES: Bernstein product), and divided by the product's binomials at the
//! end. Every term passes through at most `K` roundings (factor subtraction and scaling, two
//! multiplications, the summation chains, the final scaling), so `|fl(c_k) − c_k| ≤ γ_K S_k`
//! with `S_k = Σ|terms|` (Higham, *Accuracy and Stability*, §3.1, Lemma 3.3 and eq. 3.5).
//! With `M` the largest magnitude of each factor's coefficients, Vandermonde's identity
//! `Σ_{i+j=k} C(m,i) C(n,j) = C(m+n,k)` gives `S_k / C(N,k) ≤ pqr Σ_c M(∂_u F_c) (M(∂_v F_a)
//! M(∂_w F_b) + M(∂_v F_b) M(∂_w F_a))` for every `k` — one bound, no second convolution.
//! Inputs that are themselves rounded (relative error `η`) add `((1+η)³−1)` times the same
//! sum with magnitudes taken as `|P₁| + |P₀|`. The bound is rounded up.

use super::FfdError;
use crate::bernstein::FastBernstein;
use crate::num::{gamma, UNIT_ROUNDOFF};

/// Values with magnitudes too small or too large for the bound's assumptions (no underflow
/// below normal range, no overflow) send the cell to the exact path.
const SAFE_MIN: f64 = 1e-150;
const SAFE_MAX: f64 = 1e75;

/// Reusable buffers: after the first cell of a given order nothing is allocated.
#[derive(Default, Debug)]
pub struct JacobianWorkspace {
    /// `[axis][coord]` factor values (scaled basis).
    fval: [[Vec<f64>; 3]; 3],
    /// Cross product components.
    nval: [Vec<f64>; 3],
    det: Vec<f64>,
}

fn count(d: [usize; 3]) -> usize {
    (d[0] + 1) * (d[1] + 1) * (d[2] + 1)
}

/// Largest degree per axis of the Jacobian handled here (`3·(MAX_ORDER−1) − 1`).
const MAX_JAC_DEGREE: usize = 3 * (super::lattice::MAX_ORDER - 1) - 1;

/// Pascal's triangle up to [`MAX_JAC_DEGREE`], exact in `f64` (all entries < 2⁵³).
static BINOM: std::sync::LazyLock<Vec<Vec<f64>>> = std::sync::LazyLock::new(|| {
    let mut rows = vec![vec![1.0f64]];
    for n in 1..=MAX_JAC_DEGREE {
        let prev = &rows[n - 1];
        let mut row = vec![1.0f64; n + 1];
        for k in 1..n {
            row[k] = prev[k - 1] + prev[k];
        }
        rows.push(row);
    }
    rows
});

/// `C(n, k)` (exact).
fn binom(n: usize, k: usize) -> f64 {
    BINOM[n][k]
}

/// Terms summed into one coefficient of a product of degrees `a` and `b`.
fn terms(a: [usize; 3], b: [usize; 3]) -> usize {
    (0..3).map(|x| a[x].min(b[x]) + 1).product()
}

/// `out[i + j] += sign · a[i] · b[j]` over tensor indices (axis 0 fastest).
fn convolve(a: &[f64], da: [usize; 3], b: &[f64], db: [usize; 3], out: &mut [f64], sign: f64) {
    let dout = [da[0] + db[0], da[1] + db[1], da[2] + db[2]];
    let (s1, s2) = (dout[0] + 1, (dout[0] + 1) * (dout[1] + 1));
    let mut ia = 0;
    for ka in 0..=da[2] {
        for ja in 0..=da[1] {
            for iaa in 0..=da[0] {
                let av = sign * a[ia];
                ia += 1;
                if av == 0.0 {
                    continue;
                }
                let mut ib = 0;
                for kb in 0..=db[2] {
                    for jb in 0..=db[1] {
                        let row = (ka + kb) * s2 + (ja + jb) * s1 + iaa;
                        let o = &mut out[row..row + db[0] + 1];
                        for (slot, bv) in o.iter_mut().zip(&b[ib..ib + db[0] + 1]) {
                            *slot += av * bv;
                        }
                        ib += db[0] + 1;
                    }
                }
            }
        }
    }
}

/// The Bézier coefficients of `det J` on one cell, with a certified error bound.
///
/// `net` holds the cell's Bézier control points (`u` fastest), degrees `deg` per axis (the
/// lattice order minus one); `input_rel_err` is the relative error of the points against the
/// exact net (0 when the points are exactly the net). Fails (the caller goes exact) on
/// non-finite values, magnitudes outside a safe range, or degree 0 on some axis.
pub fn jacobian_cell_fast(
    net: &[[f64; 3]],
    deg: [usize; 3],
    input_rel_err: f64,
    ws: &mut JacobianWorkspace,
) -> Result<FastBernstein, FfdError> {
    let unfit = FfdError::FastUnfit;
    if deg.contains(&0) || net.len() != count(deg) {
        return Err(unfit("degree 0 or wrong net size"));
    }
    for p in net.iter().flatten() {
        let m = p.abs();
        if !p.is_finite() || m > SAFE_MAX || (m != 0.0 && m < SAFE_MIN) {
            return Err(unfit("coordinate outside the safe range"));
        }
    }
    let exact_inputs = input_rel_err == 0.0;
    let (s1, s2) = (deg[0] + 1, (deg[0] + 1) * (deg[1] + 1));
    // Factors: ∂_x F_c in the scaled basis, values and magnitudes.
    let mut fdeg = [[0usize; 3]; 3];
    // Largest magnitude of each factor's (unscaled) coefficients.
    let mut fmax = [[0.0f64; 3]; 3];
    for x in 0..3 {
        let mut d = deg;
        d[x] -= 1;
        fdeg[x] = d;
        let step = [1, s1, s2][x];
        for c in 0..3 {
            let v = &mut ws.fval[x][c];
            v.clear();
            let mut m = 0.0f64;
            for k in 0..=d[2] {
                let wk = binom(d[2], k);
                for j in 0..=d[1] {
                    let wj = wk * binom(d[1], j);
                    for i in 0..=d[0] {
                        let w = wj * binom(d[0], i);
                        let at = i + j * s1 + k * s2;
                        let (p0, p1) = (net[at][c], net[at + step][c]);
                        let diff = p1 - p0;
                        v.push(diff * w);
                        m = m.max(if exact_inputs {
                            diff.abs()
                        } else {
                            p1.abs() + p0.abs()
                        });
                    }
                }
            }
            fmax[x][c] = m;
        }
    }
    // Cross products N_c = ∂_v F_a ∂_w F_b − ∂_v F_b ∂_w F_a.
    let ndeg = [0, 1, 2].map(|x| fdeg[1][x] + fdeg[2][x]);
    for c in 0..3 {
        let (a, b) = ((c + 1) % 3, (c + 2) % 3);
        let n = count(ndeg);
        ws.nval[c].clear();
        ws.nval[c].resize(n, 0.0);
        convolve(
            &ws.fval[1][a],
            fdeg[1],
            &ws.fval[2][b],
            fdeg[2],
            &mut ws.nval[c],
            1.0,
        );
        convolve(
            &ws.fval[1][b],
            fdeg[1],
            &ws.fval[2][a],
            fdeg[2],
            &mut ws.nval[c],
            -1.0,
        );
    }
    // det = Σ_c ∂_u F_c · N_c.
    let ddeg = [0, 1, 2].map(|x| fdeg[0][x] + ndeg[x]);
    let n = count(ddeg);
    ws.det.clear();
    ws.det.resize(n, 0.0);
    for c in 0..3 {
        convolve(&ws.fval[0][c], fdeg[0], &ws.nval[c], ndeg, &mut ws.det, 1.0);
    }
    // Back to the Bernstein basis, times the derivative factors p·q·r.
    let pqr = (deg[0] * deg[1] * deg[2]) as f64;
    let (t1, t2) = (terms(fdeg[1], fdeg[2]), terms(fdeg[0], ndeg));
    let k_roundings = 6 + 2 * t1 + 3 * t2 + 4;
    let g = gamma(k_roundings as u32);
    let eta = input_rel_err;
    let rel = (3.01 * eta + g * (1.0 + 3.01 * eta)) * (1.0 + g);
    // Σ_c M(∂_u F_c)(M(∂_v F_a) M(∂_w F_b) + M(∂_v F_b) M(∂_w F_a)), times p·q·r.
    let mut s_max = 0.0f64;
    for c in 0..3 {
        let (a, b) = ((c + 1) % 3, (c + 2) % 3);
        s_max += fmax[0][c] * (fmax[1][a] * fmax[2][b] + fmax[1][b] * fmax[2][a]);
    }
    let err = rel * s_max * pqr * (1.0 + 8.0 * UNIT_ROUNDOFF);
    let (d1, d2) = (ddeg[0] + 1, (ddeg[0] + 1) * (ddeg[1] + 1));
    for k in 0..=ddeg[2] {
        let bk = binom(ddeg[2], k);
        for j in 0..=ddeg[1] {
            let bj = binom(ddeg[1], j);
            for i in 0..=ddeg[0] {
                let bi = binom(ddeg[0], i);
                let at = i + j * d1 + k * d2;
                ws.det[at] = ws.det[at] * pqr / bi / bj / bk;
            }
        }
    }
    // Slack for the bound's own rounding (a handful of products and sums above).
    let err = (err * (1.0 + 4.0 * UNIT_ROUNDOFF)).next_up();
    if !err.is_finite() || ws.det.iter().any(|c| !c.is_finite()) {
        return Err(unfit("overflow"));
    }
    Ok(FastBernstein::with_error(
        ddeg.to_vec(),
        ws.det.clone(),
        err,
    )?)
}
