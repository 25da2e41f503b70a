//! `F`, `G` (eqs. 1–2, with the cofactor normal) as exact tensor Bernstein polynomials in
//! `(u, v, s)`, `t = a + (b − a) s`, through homogeneous coordinates.
//!
//! With `S = X / w` (`X = (wx, wy, wz)`), `S_u = (w X_u − w_u X)/w²` and
//! `S_u × S_v = N_h / w³`, `N_h = w X_u × X_v − w_u X × X_v − w_v X_u × X` (expand the cross
//! product; the `X × X` term vanishes). With `A(t) p = (M̂ p + T̂)/δ`:
//!
//! * `F = det[A′S, M S_u, M S_v] = ⟨A′S, cof(M) N⟩`, and
//!   `F · w⁴ δ⁴ = ⟨(M̂′X + T̂′w) δ − (M̂X + T̂w) δ′, cof(M̂) N_h⟩ =: F̃`;
//! * `G · w⁴ δ³ = ⟨M̂X + (T̂ − δP) w, cof(M̂) N_h⟩ =: G̃`.
//!
//! `w > 0` (positive weights) and `δ > 0` (checked), so `F̃`, `G̃` have the zeros of `F`, `G`;
//! derivatives are taken in `s`, which scales `F̃` by `b − a > 0`.
//!
//! Degrees: `N_h` has degree at most `(3du − 1, 3dv − 1)` (computed at its exact degree, which
//! is lower for rational patches: `(4, 4)` for the biquadratic sphere patches); with `m` the
//! degree of `M̂`, `τ` of `T̂` and `e` of `δ`, `F̃` has degree `du + deg_u N_h` in `u` (likewise
//! `v`) and at most `max(m, τ) + e − 1 + 2m` in `s`, `G̃` at most `max(m, τ, e) + 2m`.
//!
//! **Parametric singularities.** Where a patch edge collapses to a point (a sphere's poles),
//! `S_v = 0` along `u = 0`, so `N_h` vanishes identically there and so do `F̃` and `G̃`: the
//! whole edge would be a spurious component of `{F = G = 0}`. `N_h`'s three components are
//! then all divisible by `u` (exactly: their Bernstein coefficients on the face are zero), and
//! the factor is divided out of `N_h` — the quotient is the true normal direction up to a
//! positive factor (`u > 0` inside the patch), continuous up to the edge.

use super::scene::Patch;
use super::{Motion, Poly, Scene, SweepError};
use crate::bernstein::{
    prove_positive, Bernstein, Limits, PositivityOptions, PositivityVerdict, ScaledBernstein,
};
use crate::num::Rational;
use crate::Path;
use num_traits::{One, Zero};

type B = Bernstein<Rational>;

/// A vector of three polynomials (a patch's homogeneous normal).
pub type Normal = [B; 3];

/// The silhouette equations of one patch under the scene's motion, in `(u, v, s)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Equations {
    /// `F̃` (eq. 1 times a positive factor).
    pub f: B,
    /// `G̃` with the cofactor normal (the contour from the eye).
    pub g: B,
    /// Eq. 2 exactly as printed, `⟨A(t)S − P, M(t) N⟩` (times the same positive factor as
    /// `G̃`): the contour only when `M(t)` is a similarity.
    pub g_printed: B,
    /// The patch's homogeneous normal `N_h` with the collapsed-edge factors divided out.
    pub normal: Normal,
    /// `cof(M̂) N_h` in `(u, v, s)`: the moved surface's normal direction (`G̃` is the sight
    /// vector's product with it).
    pub cof_normal: [B; 3],
    /// `M̂X + (T̂ − δP) w` (3-D): zero exactly where the eye lies on the moving surface.
    pub sight: [B; 3],
    /// The moved patch in homogeneous form, `(M̂X + T̂w, δw)` (3-D): `A(t)S = image[0..3] /
    /// image[3]`.
    pub image: [B; 4],
    /// The faces `(axis, upper)` whose factor (`u`, `1 − u`, `v` or `1 − v`) was divided out
    /// of `N_h`, once per entry.
    pub divided: Vec<(usize, bool)>,
}

/// The exact product, in integers over a common denominator (no gcd per term).
fn mul(a: &B, b: &B) -> Result<B, SweepError> {
    Ok(ScaledBernstein::from_rational(a)
        .product(&ScaledBernstein::from_rational(b))?
        .to_rational())
}

/// `p` at its exact degrees ([`Bernstein::at_exact_degrees`]), decided and reduced in
/// integers over one denominator ([`ScaledBernstein::at_exact_degrees`]): no gcd per step.
pub(super) fn exact_degrees(p: &B) -> B {
    let reduced = ScaledBernstein::from_rational(p).at_exact_degrees();
    if reduced.degrees() == p.degrees() {
        p.clone()
    } else {
        reduced.to_rational()
    }
}

fn add(a: &B, b: &B) -> Result<B, SweepError> {
    Ok(a.add_elevated(b)?)
}

fn sub(a: &B, b: &B) -> Result<B, SweepError> {
    Ok(a.add_elevated(&b.scale(&-Rational::one()))?)
}

fn cross(a: &[B; 3], b: &[B; 3]) -> Result<[B; 3], SweepError> {
    Ok([
        sub(&mul(&a[1], &b[2])?, &mul(&a[2], &b[1])?)?,
        sub(&mul(&a[2], &b[0])?, &mul(&a[0], &b[2])?)?,
        sub(&mul(&a[0], &b[1])?, &mul(&a[1], &b[0])?)?,
    ])
}

fn dot(a: &[B; 3], b: &[B; 3]) -> Result<B, SweepError> {
    add(
        &add(&mul(&a[0], &b[0])?, &mul(&a[1], &b[1])?)?,
        &mul(&a[2], &b[2])?,
    )
}

/// `p(a + (b − a) s)` in Bernstein form on `s ∈ [0, 1]` (1-D).
pub(crate) fn on_interval(p: &Poly, a: &Rational, b: &Rational) -> B {
    let h = b - a;
    // Horner in polynomials of s: q ← q·(a + h s) + c.
    let mut q: Vec<Rational> = vec![Rational::zero()];
    for c in p.iter().rev() {
        let mut next = vec![Rational::zero(); q.len() + 1];
        for (i, x) in q.iter().enumerate() {
            next[i] += x * a;
            next[i + 1] += x * &h;
        }
        next[0] += c;
        q = next;
    }
    while q.len() > 1 && q.last().is_some_and(Zero::is_zero) {
        q.pop();
    }
    B::from_power(vec![q.len() - 1], q).expect("1-D power coefficients")
}

/// The homogeneous normal `N_h` of a patch at its exact degrees, with the factor of every
/// face on which it vanishes identically divided out (as often as it divides), and the faces
/// divided. Errors when `N_h ≡ 0` (a degenerate patch).
pub fn patch_normal(patch: &Patch) -> Result<(Normal, Vec<(usize, bool)>), SweepError> {
    let [x, y, z, w] = &patch.hom;
    let xs = [x.clone(), y.clone(), z.clone()];
    let du = |p: &B| p.derivative(0);
    let dv = |p: &B| p.derivative(1);
    let xu = [du(x)?, du(y)?, du(z)?];
    let xv = [dv(x)?, dv(y)?, dv(z)?];
    let (wu, wv) = (du(w)?, dv(w)?);
    let a = cross(&xu, &xv)?;
    let b = cross(&xs, &xv)?;
    let c = cross(&xu, &xs)?;
    let mut n: Vec<B> = Vec::with_capacity(3);
    for k in 0..3 {
        let term = sub(&sub(&mul(w, &a[k])?, &mul(&wu, &b[k])?)?, &mul(&wv, &c[k])?)?;
        n.push(term.at_exact_degrees());
    }
    if n.iter().all(|p| p.coeffs().iter().all(Zero::is_zero)) {
        return Err(SweepError::DegeneratePatch {
            surface: usize::MAX,
            patch: usize::MAX,
        });
    }
    let mut divided = Vec::new();
    'faces: loop {
        for axis in 0..2 {
            for upper in [false, true] {
                let q: Vec<Option<B>> = n
                    .iter()
                    .map(|p| p.divide_by_face(axis, upper))
                    .collect::<Result<_, _>>()?;
                if q.iter().all(Option::is_some) {
                    n = q.into_iter().map(|p| p.expect("checked")).collect();
                    divided.push((axis, upper));
                    continue 'faces;
                }
            }
        }
        break;
    }
    let [n0, n1, n2]: [B; 3] = n.try_into().expect("three components");
    Ok(([n0, n1, n2], divided))
}

/// Certifies that a 1-D polynomial in `s` keeps one strict sign on `[0, 1]`.
fn keeps_sign(p: &B) -> bool {
    let neg = p.scale(&-Rational::one());
    let opts = PositivityOptions::new()
        .with_path(Path::Filtered)
        .with_limits(Limits::new().with_max_depth(40).with_max_boxes(100_000));
    let positive = |q: &B| {
        matches!(
            prove_positive(q, &opts),
            Ok(PositivityVerdict::Positive { .. })
        )
    };
    positive(p) || positive(&neg)
}

/// The motion on `[a, b]` in Bernstein form in `s`, checked: `δ > 0` and `det M̂ ≠ 0`
/// throughout (certified).
pub(crate) struct MotionForms {
    pub(crate) m: [[B; 3]; 3],
    pub(crate) t: [B; 3],
    pub(crate) delta: B,
}

pub(crate) fn motion_forms(
    motion: &Motion,
    a: &Rational,
    b: &Rational,
) -> Result<MotionForms, SweepError> {
    let m = motion
        .linear
        .clone()
        .map(|row| row.map(|p| on_interval(&p, a, b)));
    let t = motion.translation.clone().map(|p| on_interval(&p, a, b));
    let delta = on_interval(&motion.denominator, a, b);
    let positive = PositivityOptions::new().with_path(Path::Filtered);
    if !matches!(
        prove_positive(&delta, &positive)?,
        PositivityVerdict::Positive { .. }
    ) {
        return Err(SweepError::SingularMotion {
            why: "the rotation's denominator |q(t)|² is not positive on [a, b]".into(),
        });
    }
    let col = |j: usize| [m[0][j].clone(), m[1][j].clone(), m[2][j].clone()];
    let det = dot(&col(0), &cross(&col(1), &col(2))?)?.at_exact_degrees();
    if !keeps_sign(&det) {
        return Err(SweepError::SingularMotion {
            why: "det M(t) is not certified non-zero on [a, b] (the moving object collapses)"
                .into(),
        });
    }
    Ok(MotionForms { m, t, delta })
}

/// `F̃`, `G̃` and eq. 2 as printed for one patch, the eye at `eye`, each without its factors
/// in one parameter that keep one strict sign on the box ([`Equations::without_signed_factors`]).
pub fn equations(
    scene: &Scene,
    patch: &Patch,
    eye: &[Rational; 3],
) -> Result<Equations, SweepError> {
    let (a, b) = &scene.t;
    equations_with(&motion_forms(&scene.motion, a, b)?, patch, eye)?.without_signed_factors()
}

impl Equations {
    /// The same equations with `F̃`, `G̃` and eq. 2 as printed each divided by its factors in
    /// one parameter that keep one strict sign on the box
    /// ([`Bernstein::without_signed_contents`](crate::bernstein::Bernstein::without_signed_contents)):
    /// a quarter circle's weight `1 + u²`, a Cayley rotation's denominator `(1 + t²)ᵏ`. The
    /// zero sets and the signs on the box are unchanged, the degrees lower (the turning
    /// ellipsoid's `F̃` goes from `[5, 6, 8]` to `[4, 4, 2]`); where `F̃ = a·F̂` and `G̃ = b·Ĝ`,
    /// `H` of `F̂, Ĝ` is `H/(a·b)` wherever `F̂ = Ĝ = 0`. The other fields are left as they are.
    pub fn without_signed_factors(self) -> Result<Self, SweepError> {
        Ok(Equations {
            f: self.f.without_signed_contents()?.0,
            g: self.g.without_signed_contents()?.0,
            g_printed: self.g_printed.without_signed_contents()?.0,
            ..self
        })
    }
}

/// [`equations`] with the motion already in Bernstein form and checked (once per scene).
pub(crate) fn equations_with(
    forms: &MotionForms,
    patch: &Patch,
    eye: &[Rational; 3],
) -> Result<Equations, SweepError> {
    let (normal, divided) = patch_normal(patch)?;
    let lift_s = |p: &B| p.embed(&[2], 3);
    let lift_uv = |p: &B| p.embed(&[0, 1], 3);
    let m: Vec<Vec<B>> = forms
        .m
        .iter()
        .map(|row| row.iter().map(lift_s).collect::<Result<_, _>>())
        .collect::<Result<_, _>>()?;
    let t: Vec<B> = forms.t.iter().map(lift_s).collect::<Result<_, _>>()?;
    let delta = lift_s(&forms.delta)?;
    let x: Vec<B> = patch.hom.iter().map(lift_uv).collect::<Result<_, _>>()?;
    let n: Vec<B> = normal.iter().map(lift_uv).collect::<Result<_, _>>()?;
    let w = &x[3];
    let ds = |p: &B| p.derivative(2);
    // cof(M̂): column j is c_{j+1} × c_{j+2}, c_j the columns of M̂.
    let col = |j: usize| [m[0][j].clone(), m[1][j].clone(), m[2][j].clone()];
    let cof_cols = [
        cross(&col(1), &col(2))?,
        cross(&col(2), &col(0))?,
        cross(&col(0), &col(1))?,
    ];
    let apply = |cols: &[[B; 3]; 3]| -> Result<[B; 3], SweepError> {
        let row = |i: usize| -> Result<B, SweepError> {
            add(
                &add(&mul(&cols[0][i], &n[0])?, &mul(&cols[1][i], &n[1])?)?,
                &mul(&cols[2][i], &n[2])?,
            )
        };
        Ok([row(0)?, row(1)?, row(2)?])
    };
    let cof_n = apply(&cof_cols)?;
    let m_n = apply(&[col(0), col(1), col(2)])?;
    // M̂X + T̂w and its s-derivative.
    let mut image: Vec<B> = Vec::with_capacity(3);
    let mut velocity: Vec<B> = Vec::with_capacity(3);
    let delta_constant = forms.delta.degrees()[0] == 0;
    let ddelta = ds(&delta)?;
    for i in 0..3 {
        let mut p = mul(&t[i], w)?;
        let mut dp = mul(&ds(&t[i])?, w)?;
        for j in 0..3 {
            p = add(&p, &mul(&m[i][j], &x[j])?)?;
            dp = add(&dp, &mul(&ds(&m[i][j])?, &x[j])?)?;
        }
        let v = if delta_constant {
            dp
        } else {
            sub(&mul(&dp, &delta)?, &mul(&p, &ddelta)?)?
        };
        velocity.push(exact_degrees(&v));
        image.push(p);
    }
    let weight = mul(&delta, w)?;
    let mut sight: Vec<B> = Vec::with_capacity(3);
    for (i, p) in image.iter().enumerate() {
        sight.push(exact_degrees(&sub(p, &weight.scale(&eye[i]))?));
    }
    let image = [image[0].clone(), image[1].clone(), image[2].clone(), weight];
    let as3 = |v: Vec<B>| -> [B; 3] { v.try_into().expect("three components") };
    let (velocity, sight) = (as3(velocity), as3(sight));
    let f = exact_degrees(&dot(&velocity, &cof_n)?);
    let cof_normal = cof_n.clone();
    let g = exact_degrees(&dot(&sight, &cof_n)?);
    let g_printed = exact_degrees(&dot(&sight, &m_n)?);
    Ok(Equations {
        f,
        g,
        g_printed,
        normal,
        cof_normal,
        sight,
        image,
        divided,
    })
}

#[cfg(test)]
mod tests {
    use super::super::scene::builtin_scene;
    use super::*;

    #[test]
    fn sphere_poles_are_divided_out_and_degrees_are_exact() {
        let scene = builtin_scene("sphere-line").unwrap();
        for (k, p) in scene.surfaces[0].patches.iter().enumerate() {
            let (n, divided) = patch_normal(p).unwrap();
            // The northern patches collapse at u = 0, the southern ones at u = 1.
            let pole = (0, k >= 4);
            assert_eq!(divided, vec![pole], "patch {k}");
            // N_h has degree (4, 4) before the pole's factor: (3, 4) after.
            for c in &n {
                assert!(
                    c.degrees()[0] <= 3 && c.degrees()[1] <= 4,
                    "{:?}",
                    c.degrees()
                );
                // Not zero on the pole's edge any more.
                let face = c.face(0, pole.1).unwrap();
                let _ = face;
            }
            assert!(n.iter().any(|c| !c
                .face(0, pole.1)
                .unwrap()
                .coeffs()
                .iter()
                .all(Zero::is_zero)));
        }
    }

    #[test]
    fn singular_motions_are_refused() {
        let mut scene = builtin_scene("sphere-line").unwrap();
        // M(t) = diag(1 − t, 1, 1) is singular at t = 1 ∈ [0, 2].
        scene.motion.linear[0][0] = vec![Rational::one(), -Rational::one()];
        let e = equations(
            &scene,
            &scene.surfaces[0].patches[0],
            &[
                Rational::zero(),
                Rational::zero(),
                Rational::from_integer(9.into()),
            ],
        )
        .unwrap_err();
        assert!(matches!(e, SweepError::SingularMotion { .. }), "{e}");
    }
}
