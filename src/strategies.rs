//! Proptest strategies for other crates' property tests (feature `proptest`).
//!
//! In a test suite use them inside `proptest! { … }`; here the runner is driven directly:
//!
//! ```
//! use geocert::strategies::bernstein_poly;
//! use geocert::num::Rational;
//! use proptest::test_runner::TestRunner;
//!
//! let half = Rational::new(1.into(), 2.into());
//! TestRunner::default()
//!     .run(&bernstein_poly(vec![3, 2], 20), |p| {
//!         // Compare your own subdivision against geocert's: the halves meet at t = ½.
//!         let (left, right) = p.split(0, &half).unwrap();
//!         let y = Rational::new(1.into(), 3.into());
//!         let one = Rational::new(1.into(), 1.into());
//!         let zero = Rational::new(0.into(), 1.into());
//!         assert_eq!(left.eval(&[one, y.clone()]).unwrap(), right.eval(&[zero, y]).unwrap());
//!         Ok(())
//!     })
//!     .unwrap();
//! ```

use crate::bernstein::Bernstein;
use crate::bspline::Spline;
use crate::num::Rational;
use num_bigint::BigInt;
use proptest::prelude::*;
use proptest::strategy::BoxedStrategy;

/// Rationals `n/d` with `|n| ≤ max_num`, `1 ≤ d ≤ max_den`.
pub type RationalStrategy = BoxedStrategy<Rational>;
/// Bernstein polynomials with rational coefficients.
pub type BernsteinStrategy = BoxedStrategy<Bernstein<Rational>>;
/// Univariate B-splines with rational knots and coefficients.
pub type SplineStrategy = BoxedStrategy<Spline<Rational>>;

/// `n/d` with `|n| ≤ max_num` and `1 ≤ d ≤ max_den`.
pub fn small_rational(max_num: i64, max_den: i64) -> RationalStrategy {
    (-max_num..=max_num, 1..=max_den.max(1))
        .prop_map(|(n, d)| Rational::new(BigInt::from(n), BigInt::from(d)))
        .boxed()
}

/// A value within `2⁻⁵⁰ … 2⁻⁴⁰` of zero, either sign, or exactly zero: the near-degenerate
/// inputs that break floating-point sign decisions.
pub fn near_zero_rational() -> RationalStrategy {
    prop_oneof![
        Just(Rational::from_integer(BigInt::from(0))),
        (40u32..=50, any::<bool>(), 1i64..8).prop_map(|(e, neg, k)| {
            Rational::new(
                BigInt::from(if neg { -k } else { k }),
                BigInt::from(1) << e as usize,
            )
        }),
    ]
    .boxed()
}

/// Bernstein polynomials of the given degrees with coefficients `n/d`, `|n| ≤ max_num`, `d ≤ 16`;
/// one in four has coefficients perturbed by `2⁻⁴⁰ … 2⁻⁵⁰` around zero.
pub fn bernstein_poly(degrees: Vec<usize>, max_num: i64) -> BernsteinStrategy {
    let count: usize = degrees.iter().map(|d| d + 1).product();
    let coeff = prop_oneof![3 => small_rational(max_num, 16), 1 => near_zero_rational()];
    proptest::collection::vec(coeff, count)
        .prop_map(move |c| Bernstein::new(degrees.clone(), c).expect("count matches"))
        .boxed()
}

/// A univariate spline of degree `≤ max_degree` on `[0, 1]`: clamped ends, up to 3 interior
/// breakpoints from `{1/4, 1/3, 1/2, 3/4}` with multiplicities up to the degree.
pub fn spline(max_degree: usize) -> SplineStrategy {
    (
        0..=max_degree,
        proptest::collection::vec((0usize..4, 1usize..=3), 0..=3),
    )
        .prop_flat_map(|(p, interior)| {
            let cands = [(1, 4), (1, 3), (1, 2), (3, 4)];
            let mut knots: Vec<Rational> = vec![Rational::from_integer(0.into()); p + 1];
            let mut seen = Vec::new();
            let mut sorted = interior.clone();
            sorted.sort();
            for (c, m) in sorted {
                if seen.contains(&c) {
                    continue;
                }
                seen.push(c);
                let (a, b) = cands[c];
                for _ in 0..m.min(p.max(1)) {
                    knots.push(Rational::new(a.into(), b.into()));
                }
            }
            knots.sort();
            knots.extend(vec![Rational::from_integer(1.into()); p + 1]);
            let n = knots.len() - p - 1;
            proptest::collection::vec(small_rational(20, 6), n)
                .prop_map(move |c| Spline::new(p, knots.clone(), c).expect("valid by construction"))
        })
        .boxed()
}

/// A height-field triangle mesh for decimation tests: an `nx × ny` grid (3 ≤ n ≤ `max_side`)
/// with node spacing 8, integer jitter of up to ±3 in x and y (each square is cut along a
/// diagonal that keeps both triangles positive in xy; the jitter makes non-convex holes),
/// integer heights in `[−h, h]` and an integer nodal scalar field `"f"` in `[−h, h]`.
/// Integer data makes the exact and fast decimation paths compute identical evaluation
/// values for the angle and scalar criteria.
pub fn height_field_mesh(max_side: usize, h: i32) -> impl Strategy<Value = crate::mesh::Mesh> {
    let max_side = max_side.max(3);
    (3..=max_side, 3..=max_side, 0i32..=3).prop_flat_map(move |(nx, ny, jitter)| {
        let n = nx * ny;
        (
            proptest::collection::vec((-jitter..=jitter, -jitter..=jitter, -h..=h, -h..=h), n),
            Just((nx, ny)),
        )
            .prop_map(|(nodes, (nx, ny))| {
                let mut mesh = crate::mesh::Mesh::default();
                let mut f = Vec::with_capacity(nodes.len());
                for (k, &(dx, dy, z, s)) in nodes.iter().enumerate() {
                    let (i, j) = ((k % nx) as i32, (k / nx) as i32);
                    mesh.vertices
                        .push([(8 * i + dx) as f64, (8 * j + dy) as f64, z as f64]);
                    f.push(s as f64);
                }
                let id = |i: usize, j: usize| (j * nx + i) as u32;
                let positive = |m: &crate::mesh::Mesh, t: [u32; 3]| {
                    let [a, b, c] = t.map(|i| m.vertices[i as usize]);
                    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0.0
                };
                for j in 0..ny - 1 {
                    for i in 0..nx - 1 {
                        let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                        let one = [[a, b, c], [a, c, d]];
                        let pick = if one.iter().all(|&t| positive(&mesh, t)) {
                            one
                        } else {
                            [[a, b, d], [b, c, d]]
                        };
                        mesh.triangles.extend_from_slice(&pick);
                    }
                }
                mesh.scalars = Some(crate::mesh::Scalars {
                    name: "f".into(),
                    values: f,
                });
                mesh
            })
    })
}

/// Small finite element models for isosurface code, with an isovalue: a block of 1–3 × 1–3 ×
/// 1–2 elements of trilinear Lagrange, tricubic Hermite or Hermite × Lagrange kind
/// ([`models::block`](crate::mc::fe::models::block)), node values in halves from −3/2 to 3/2,
/// ξ-slopes in quarters from −2 to 2, node positions moved by a smooth warp of strength up to
/// 0.3; isovalues 0, 1/2 or an `f64` in [−1, 1]. Polygonise with your code and compare with
/// [`polygonise_exact`](crate::mc::fe::exact::polygonise_exact) or
/// [`polygonise_fast`](crate::mc::fe::fast::polygonise_fast) (same triangles, positions to
/// rounding).
pub fn fe_block_model() -> impl Strategy<Value = (crate::mc::fe::FeModel<f64>, f64)> {
    use crate::mc::fe::{models::block, ElementKind};
    let kind = prop_oneof![
        Just(ElementKind::TRILINEAR_LAGRANGE),
        Just(ElementKind::TRICUBIC_HERMITE),
        Just(ElementKind::HERMITE_HERMITE_LAGRANGE),
    ];
    let dims = (1usize..=3, 1usize..=3, 1usize..=2);
    (kind, dims, 0.0f64..0.3).prop_flat_map(|(kind, (x, y, z), warp)| {
        let nodes = (x + 1) * (y + 1) * (z + 1);
        (
            proptest::collection::vec(-3i8..=3, nodes),
            proptest::collection::vec(-8i8..=8, 8 * nodes),
            prop_oneof![Just(0.0), Just(0.5), -1.0f64..1.0],
        )
            .prop_map(move |(values, slopes, iso)| {
                let e = [x, y, z];
                let idx = move |p: [f64; 3]| {
                    p[0] as usize + (e[0] + 1) * (p[1] as usize + (e[1] + 1) * p[2] as usize)
                };
                let value = |p: [f64; 3]| values[idx(p)] as f64 / 2.0;
                let derivative = |p: [f64; 3], der: [bool; 3]| {
                    let k: usize = der
                        .iter()
                        .enumerate()
                        .map(|(d, &b)| usize::from(b) << d)
                        .sum();
                    slopes[8 * idx(p) + k] as f64 / 4.0
                };
                let w = |p: [f64; 3]| {
                    [
                        p[0] + warp * (p[1] * p[2]).sin(),
                        p[1] + warp * p[0].cos(),
                        p[2] - warp * p[1] * p[0] / 4.0,
                    ]
                };
                (block(kind, e, &value, &derivative, &w), iso)
            })
    })
}
