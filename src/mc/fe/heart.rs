//! A left-ventricle-like demo model (Section 4): 16 elements, cubic Hermite
//! circumferentially (`ξ₁`) and longitudinally (`ξ₂`), linear Lagrange radially (`ξ₃`), as in
//! Young et al.'s model the paper uses; with an analytic strain-like field.
//!
//! Geometry in prolate spheroidal coordinates `(λ, μ, θ)` with focal length `d`:
//! `x = d sinh λ sin μ cos θ`, `y = d sinh λ sin μ sin θ`, `z = −d cosh λ cos μ`. Four elements
//! around (`θ` in quarter turns), four from the apex (`μ = 0`) to the base (`μ = 120°`), one
//! through the wall (`λ` from endocardium to epicardium). Nodal `ξ`-derivatives are the
//! analytic ones scaled by the element sizes, so the interpolated wall is C¹ around and along.
//! At the apex the four nodes of each wall surface coincide in world space: the apical
//! elements are degenerate (a face collapses to a line), the Figure 7 situation.
//!
//! The field imitates radial strain: positive (thickening) in most of the wall, negative in
//! two bands along the septal and lateral walls (`θ = 0, π`) and in a small region inside the
//! apex, like the healthy ventricle of Figure 8.

use super::{ElementKind, FeModel, FeOptions, NormalSource};
use std::f64::consts::PI;

/// Focal length (mm).
const FOCUS: f64 = 42.0;
/// `λ` at the endocardium and epicardium.
const LAMBDA: [f64; 2] = [0.6, 1.0];
/// `μ` at the base.
const MU_BASE: f64 = 2.0 * PI / 3.0;
const AROUND: usize = 4;
const ALONG: usize = 4;

/// The strain-like field and its derivatives `(f, f_θ, f_μ, f_θμ)` at wall depth `s ∈ {0, 1}`.
fn strain(theta: f64, mu: f64, s: f64) -> [f64; 4] {
    let (g, g1) = (theta.cos().powi(2), -(2.0 * theta).sin());
    let (p, p1) = (mu.sin().powi(2), (2.0 * mu).sin());
    let (q, q1) = (mu.cos().powi(6), -6.0 * mu.cos().powi(5) * mu.sin());
    let (wa, wb) = (0.7 + 0.6 * s, 1.2 - 0.8 * s);
    [
        0.12 - 0.3 * p * g * wa - 0.22 * q * wb,
        -0.3 * p * g1 * wa,
        -0.3 * p1 * g * wa - 0.22 * q1 * wb,
        -0.3 * p1 * g1 * wa,
    ]
}

/// The wall point and its derivatives `(x, x_θ, x_μ, x_θμ)`.
fn wall(theta: f64, mu: f64, lambda: f64) -> [[f64; 3]; 4] {
    let (sh, ch) = (FOCUS * lambda.sinh(), FOCUS * lambda.cosh());
    let (st, ct) = theta.sin_cos();
    let (sm, cm) = mu.sin_cos();
    [
        [sh * sm * ct, sh * sm * st, -ch * cm],
        [-sh * sm * st, sh * sm * ct, 0.0],
        [sh * cm * ct, sh * cm * st, ch * sm],
        [-sh * cm * st, sh * cm * ct, 0.0],
    ]
}

/// Node id of circumferential index `a` (mod 4), longitudinal `b`, wall surface `r`.
fn node(a: usize, b: usize, r: usize) -> u32 {
    ((a % AROUND) + AROUND * b + AROUND * (ALONG + 1) * r) as u32
}

/// The 16-element left ventricle with its strain-like field.
pub fn left_ventricle() -> FeModel<f64> {
    let (dt, dm) = (2.0 * PI / AROUND as f64, MU_BASE / ALONG as f64);
    let scale = [1.0, dt, dm, dt * dm];
    let mut coordinates = Vec::new();
    let mut field = Vec::new();
    for (r, &lambda) in LAMBDA.iter().enumerate() {
        for b in 0..=ALONG {
            for a in 0..AROUND {
                let (theta, mu) = (a as f64 * dt, b as f64 * dm);
                let x = wall(theta, mu, lambda);
                let f = strain(theta, mu, r as f64);
                for k in 0..4 {
                    coordinates.push(x[k].map(|c| c * scale[k]));
                    field.push(f[k] * scale[k]);
                }
            }
        }
    }
    let mut elements = Vec::new();
    for b in 0..ALONG {
        for a in 0..AROUND {
            elements.push(std::array::from_fn(|l| {
                node(a + (l & 1), b + (l >> 1 & 1), l >> 2 & 1)
            }));
        }
    }
    FeModel {
        kind: ElementKind::HERMITE_HERMITE_LAGRANGE,
        coordinates,
        field,
        elements,
    }
}

/// The paper's sampling: 10 × 10 × 6 points per element, i.e. 9 × 9 × 5 cells.
pub fn paper_options() -> FeOptions {
    FeOptions {
        cells: [9, 9, 5],
        normals: NormalSource::Interpolant,
        ..FeOptions::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivatives_match_differences() {
        let h = 1e-6;
        for (t, m) in [(0.3, 0.7), (2.0, 1.9), (4.0, 0.1)] {
            let f = strain(t, m, 1.0);
            let ft = (strain(t + h, m, 1.0)[0] - strain(t - h, m, 1.0)[0]) / (2.0 * h);
            let fm = (strain(t, m + h, 1.0)[0] - strain(t, m - h, 1.0)[0]) / (2.0 * h);
            let ftm = (strain(t + h, m + h, 1.0)[0]
                - strain(t + h, m - h, 1.0)[0]
                - strain(t - h, m + h, 1.0)[0]
                + strain(t - h, m - h, 1.0)[0])
                / (4.0 * h * h);
            assert!((f[1] - ft).abs() < 1e-6 && (f[2] - fm).abs() < 1e-6);
            assert!((f[3] - ftm).abs() < 1e-3);
            let x = wall(t, m, 0.8);
            for (a, (dt, dm)) in x[1].iter().zip(x[2]).enumerate() {
                let xt = (wall(t + h, m, 0.8)[0][a] - wall(t - h, m, 0.8)[0][a]) / (2.0 * h);
                let xm = (wall(t, m + h, 0.8)[0][a] - wall(t, m - h, 0.8)[0][a]) / (2.0 * h);
                assert!((dt - xt).abs() < 1e-5 && (dm - xm).abs() < 1e-5);
            }
        }
        let m = left_ventricle();
        assert_eq!(m.elements.len(), 16);
        assert_eq!(m.node_count(), 40);
        m.validate().unwrap();
    }
}
