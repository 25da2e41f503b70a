//! The certified solver on systems with known rational roots by construction: every root lies
//! in exactly one certified box or in a cluster, every certified box holds exactly one of the
//! constructed roots and passes the independent checker, the fast path's certified roots
//! agree with the exact path's, tangential roots come back as clusters, roots on split planes
//! and close pairs are certified, simple roots on the domain's boundary are certified with
//! their exact point (clusters with that stage off); non-separable
//! systems in up to 4 unknowns, degrees up to 6 and coefficients up to 10⁸ certify their
//! constructed root once on every path.

use geocert::bernstein::Bernstein;
use geocert::num::Rational;
use geocert::solve::{
    solve, verify_root, verify_root_exactly, ClusterReason, RootCertificate, Solution,
    SolveOptions, System,
};
use geocert::Path;
use proptest::prelude::*;

fn q(n: i64, d: i64) -> Rational {
    Rational::new(n.into(), d.into())
}

/// `x_k − r` on the unit box in `n` variables (degree 1 along `k`).
fn linear(n: usize, k: usize, r: &Rational) -> Bernstein<Rational> {
    let mut degrees = vec![0; n];
    degrees[k] = 1;
    Bernstein::new(degrees, vec![-r.clone(), q(1, 1) - r]).unwrap()
}

fn constant(n: usize, c: Rational) -> Bernstein<Rational> {
    Bernstein::constant(vec![0; n], c)
}

/// `Π_j (x_k − r_j)`.
fn product_of_roots(n: usize, k: usize, roots: &[Rational]) -> Bernstein<Rational> {
    roots.iter().fold(constant(n, q(1, 1)), |acc, r| {
        acc.product(&linear(n, k, r)).unwrap()
    })
}

/// Raises every equation to the common degrees and mixes them with the integer matrix `m`
/// (invertible: the roots do not change).
fn mix(eqs: Vec<Bernstein<Rational>>, m: &[Vec<i64>]) -> Vec<Bernstein<Rational>> {
    let n = eqs[0].dim();
    let top: Vec<usize> = (0..n)
        .map(|k| eqs.iter().map(|e| e.degrees()[k]).max().unwrap())
        .collect();
    let up: Vec<_> = eqs
        .into_iter()
        .map(|mut e| {
            for (k, &t) in top.iter().enumerate() {
                if e.degrees()[k] < t {
                    e = e.elevate(k, t - e.degrees()[k]).unwrap();
                }
            }
            e
        })
        .collect();
    m.iter()
        .map(|row| {
            row.iter()
                .zip(&up)
                .map(|(&a, e)| e.scale(&q(a, 1)))
                .reduce(|s, t| s.add(&t).unwrap())
                .unwrap()
        })
        .collect()
}

fn unit_system(eqs: Vec<Bernstein<Rational>>) -> System {
    let n = eqs[0].dim();
    System::new(vec![(q(0, 1), q(1, 1)); n], eqs).unwrap()
}

fn contains(bounds: &[(Rational, Rational)], p: &[Rational]) -> bool {
    bounds.iter().zip(p).all(|((a, b), x)| a <= x && x <= b)
}

/// Every constructed root is in exactly one certified box or in some cluster; every
/// certified box holds exactly one constructed root and passes the checker.
fn account(system: &System, s: &Solution, roots: &[Vec<Rational>]) -> Result<(), String> {
    for r in roots {
        let in_roots = s.roots.iter().filter(|x| contains(&x.bounds, r)).count();
        let in_clusters = s.clusters.iter().filter(|c| contains(&c.bounds, r)).count();
        if !(in_roots == 1 && in_clusters == 0 || in_roots == 0 && in_clusters >= 1) {
            return Err(format!(
                "root {r:?}: in {in_roots} certified boxes and {in_clusters} clusters"
            ));
        }
    }
    for x in &s.roots {
        let held = roots.iter().filter(|r| contains(&x.bounds, r)).count();
        if held != 1 {
            return Err(format!("certified box {:?} holds {held} roots", x.bounds));
        }
        verify_root(system, &x.bounds, &x.certificate).map_err(|e| e.to_string())?;
        // The interval filter accepts nothing the exact check refuses.
        verify_root_exactly(system, &x.bounds, &x.certificate).map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// Every point of the grid `axes[0] × … × axes[n−1]`.
fn grid_points(axes: &[Vec<Rational>]) -> Vec<Vec<Rational>> {
    let mut points: Vec<Vec<Rational>> = vec![vec![]];
    for axis in axes {
        points = points
            .into_iter()
            .flat_map(|r| {
                axis.iter().map(move |x| {
                    let mut r = r.clone();
                    r.push(x.clone());
                    r
                })
            })
            .collect();
    }
    points
}

/// The grid of roots `per_axis[0] × … × per_axis[n−1]` (a product of linear factors per
/// unknown), mixed by a unit lower-triangular matrix with `shear` below the diagonal
/// (invertible: the roots do not change).
fn sheared_grid(n: usize, per_axis: &[Vec<Rational>; 3], shear: i64) -> System {
    let eqs: Vec<_> = (0..n)
        .map(|k| product_of_roots(n, k, &per_axis[k]))
        .collect();
    let m: Vec<Vec<i64>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| match (i == j, j < i) {
                    (true, _) => 1,
                    (false, true) => shear,
                    _ => 0,
                })
                .collect()
        })
        .collect();
    unit_system(mix(eqs, &m))
}

/// Distinct values `k/den`, `0 < k < den`, at least `gap/den` apart.
fn spread(den: i64, count: usize, gap: i64) -> impl Strategy<Value = Vec<Rational>> {
    proptest::collection::btree_set(1..den, count).prop_filter_map("gap", move |s| {
        let v: Vec<i64> = s.into_iter().collect();
        v.windows(2)
            .all(|w| w[1] - w[0] >= gap)
            .then(|| v.into_iter().map(|k| q(k, den)).collect())
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Grids of roots (products of linear factors per unknown) mixed by an invertible
    /// integer matrix, 1–3 unknowns, up to 3 roots per axis: exact, fast and filtered paths.
    #[test]
    fn constructed_roots_are_accounted_for(
        n in 1usize..=3,
        xs in spread(97, 2, 5),
        ys in spread(89, 2, 5),
        zs in spread(83, 1, 5),
        shear in -3i64..=3,
    ) {
        let per_axis = [xs, ys, zs];
        let system = sheared_grid(n, &per_axis, shear);
        let roots = grid_points(&per_axis[..n]);
        let exact = solve(&system, &SolveOptions::new().with_path(Path::Exact)).unwrap();
        account(&system, &exact, &roots).map_err(TestCaseError::fail)?;
        prop_assert_eq!(exact.roots.len(), roots.len(), "simple, separated roots are certified");
        for path in [Path::Fast, Path::Filtered] {
            let s = solve(&system, &SolveOptions::new().with_path(path)).unwrap();
            account(&system, &s, &roots).map_err(TestCaseError::fail)?;
            // A certified fast root never contradicts the exact path.
            for r in &s.roots {
                prop_assert!(exact.roots.iter().any(|e| roots.iter().any(|p| contains(&e.bounds, p) && contains(&r.bounds, p))));
            }
        }
    }
}

/// Roots on `{0, 1}` or the grid `k/den` per axis (at least one on the boundary).
fn with_ends(den: i64) -> impl Strategy<Value = Vec<Rational>> {
    (0usize..3, spread(den, 1, 5)).prop_map(move |(ends, inner)| match ends {
        0 => vec![q(0, 1), inner[0].clone()],
        1 => vec![inner[0].clone(), q(1, 1)],
        _ => vec![q(0, 1), q(1, 1)],
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Grids of roots with some on the domain's faces, edges and corners, mixed as above,
    /// 1–3 unknowns: the exact and filtered paths certify every one once and leave no
    /// cluster, each root on the boundary with its exact point; the fast path accounts for
    /// every root and agrees where it certifies.
    #[test]
    fn roots_on_faces_and_corners_are_certified_once(
        n in 1usize..=3,
        xs in with_ends(97),
        ys in with_ends(89),
        zs in with_ends(83),
        shear in -3i64..=3,
    ) {
        let per_axis = [xs, ys, zs];
        let system = sheared_grid(n, &per_axis, shear);
        let roots = grid_points(&per_axis[..n]);
        let on_boundary = |r: &[Rational]| r.iter().any(|x| *x == q(0, 1) || *x == q(1, 1));
        for path in [Path::Exact, Path::Filtered] {
            let s = solve(&system, &SolveOptions::new().with_path(path)).unwrap();
            account(&system, &s, &roots).map_err(TestCaseError::fail)?;
            prop_assert_eq!((s.roots.len(), s.clusters.len()), (roots.len(), 0), "{}", path);
            for r in &s.roots {
                let held = roots.iter().find(|p| contains(&r.bounds, p)).unwrap();
                let expected = on_boundary(held).then(|| held.clone());
                prop_assert_eq!(&r.certificate.point, &expected);
            }
        }
        let fast = solve(&system, &SolveOptions::new().with_path(Path::Fast)).unwrap();
        account(&system, &fast, &roots).map_err(TestCaseError::fail)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// `verify_root` reads the conditions from `f64` interval enclosures first: it never
    /// accepts a box the exact check refuses. Boxes of the solved roots moved by fractions of
    /// their widths (the root leaves some), and boxes of width about 2⁻³⁰ around the
    /// constructed roots or just beside them, with the solved root's certificate. (The filter
    /// deciding such boxes at all is the unit test `interval_filter_decides_moderate_boxes`.)
    #[test]
    fn the_interval_filter_agrees_with_the_exact_check(
        n in 2usize..=3,
        xs in spread(97, 2, 5),
        ys in spread(89, 2, 5),
        zs in spread(83, 1, 5),
        shear in -3i64..=3,
        moves in proptest::collection::vec((-4i64..=4, -4i64..=4), 3),
        tiny in proptest::collection::vec((-2i64..=3, -2i64..=3), 3),
    ) {
        let per_axis = [xs, ys, zs];
        let system = sheared_grid(n, &per_axis, shear);
        // Boxes about 1e-8 wide: the size the interval filter decides.
        let exact = solve(
            &system,
            &SolveOptions::new().with_path(Path::Exact).with_tolerance(1e-8),
        )
        .unwrap();
        let (mut accepted, mut refused) = (0, 0);
        for r in &exact.roots {
            let moved: Vec<(Rational, Rational)> = r
                .bounds
                .iter()
                .zip(&moves)
                .map(|((a, b), &(s0, s1))| {
                    let w = b - a;
                    (a + &w * q(s0, 8), b + &w * q(s1, 8))
                })
                .collect();
            // The constructed root in this box (the one it holds).
            let root: Vec<Rational> = (0..n)
                .map(|k| {
                    per_axis[k]
                        .iter()
                        .find(|x| r.bounds[k].0 <= **x && **x <= r.bounds[k].1)
                        .unwrap()
                        .clone()
                })
                .collect();
            let eps = q(1, 1 << 30);
            let small: Vec<(Rational, Rational)> = root
                .iter()
                .zip(&tiny)
                .map(|(x, &(l, h))| (x - &eps * q(l, 1), x + &eps * q(h, 1)))
                .collect();
            for bounds in [moved, small] {
                let filtered = verify_root(&system, &bounds, &r.certificate).is_ok();
                let exactly = verify_root_exactly(&system, &bounds, &r.certificate).is_ok();
                prop_assert_eq!(filtered, exactly, "box {:?}", bounds);
                if exactly { accepted += 1 } else { refused += 1 }
            }
        }
        prop_assert!(accepted + refused > 0);
    }
}

/// The solution on `path`, asserted to hold no root and exactly one cluster (with what it
/// took printed).
fn one_cluster_no_root(system: &System, path: Path) -> Solution {
    let s = solve(system, &SolveOptions::new().with_path(path)).unwrap();
    println!(
        "{path}: {} roots, {} clusters, {} boxes",
        s.roots.len(),
        s.clusters.len(),
        s.boxes_visited
    );
    assert!(s.roots.is_empty(), "{path}: {:?}", s.roots);
    assert_eq!(s.clusters.len(), 1, "{path}: {:?}", s.clusters);
    s
}

#[test]
fn a_tangential_double_root_is_one_cluster_never_a_certified_root() {
    // (y − ½) − (x − ⅓)² = 0 and y − ½ = 0 touch at (⅓, ½). In intervals the boxes no test
    // can decide multiply at every level around it, so the group is given up after its budget
    // as one cluster, in a bounded number of boxes.
    let n = 2;
    let x = linear(n, 0, &q(1, 3));
    let y = linear(n, 1, &q(1, 2));
    let f1 = mix(vec![y.clone(), x.product(&x).unwrap()], &[vec![1, -1]]).remove(0);
    let system = unit_system(mix(vec![f1, y], &[vec![1, 0], vec![0, 1]]));
    for path in [Path::Exact, Path::Fast, Path::Filtered] {
        let s = one_cluster_no_root(&system, path);
        let c = &s.clusters[0];
        // Exact signs shrink it to one box at the depth limit; rounding leaves the group.
        assert!(
            matches!(
                c.reason,
                ClusterReason::DepthLimit | ClusterReason::Singular
            ),
            "{path}: {:?}",
            c.reason
        );
        assert!(contains(&c.bounds, &[q(1, 3), q(1, 2)]), "{path}");
        assert!(s.boxes_visited < 5_000, "{path}: {} boxes", s.boxes_visited);
    }
}

#[test]
fn a_curve_of_roots_is_one_cluster_along_it() {
    // x − y = 0 and (x − y)(x + y − ½)² = 0 share the whole diagonal: a curve of roots, which
    // no subdivision resolves; it comes back as one cluster covering it.
    let n = 2;
    let d = mix(
        vec![linear(n, 0, &q(0, 1)), linear(n, 1, &q(0, 1))],
        &[vec![1, -1]],
    )
    .remove(0);
    let s2 = mix(
        vec![linear(n, 0, &q(1, 4)), linear(n, 1, &q(1, 4))],
        &[vec![1, 1]],
    )
    .remove(0);
    let f2 = d.product(&s2).unwrap().product(&s2).unwrap();
    let system = unit_system(vec![d, f2]);
    for path in [Path::Exact, Path::Filtered] {
        let s = one_cluster_no_root(&system, path);
        let c = &s.clusters[0];
        assert_eq!(c.reason, ClusterReason::Singular, "{path}");
        for k in [1, 5, 9] {
            assert!(contains(&c.bounds, &[q(k, 10), q(k, 10)]), "{path}: {k}/10");
        }
    }
}

#[test]
fn a_root_on_the_split_plane_is_certified_once() {
    let n = 2;
    let system = unit_system(mix(
        vec![linear(n, 0, &q(1, 2)), linear(n, 1, &q(1, 2))],
        &[vec![1, 1], vec![1, -1]],
    ));
    let s = solve(&system, &SolveOptions::new().with_path(Path::Exact)).unwrap();
    account(&system, &s, &[vec![q(1, 2), q(1, 2)]]).unwrap();
    assert_eq!((s.roots.len(), s.clusters.len()), (1, 0));
}

#[test]
fn two_roots_two_to_the_minus_27_apart_are_separated() {
    let a = q(1, 3);
    let b = &a + q(1, 1 << 27);
    let system = unit_system(vec![product_of_roots(1, 0, &[a.clone(), b.clone()])]);
    let s = solve(&system, &SolveOptions::new()).unwrap();
    account(&system, &s, &[vec![a], vec![b]]).unwrap();
    assert_eq!(s.roots.len(), 2);
}

/// A simple root on the domain's boundary is certified by a box reaching across it, with the
/// root itself in the certificate; the checker refuses the certificate without its point, with
/// a point that is no zero or lies outside the box. With the boundary stage off it is a
/// cluster, as before.
#[test]
fn a_root_on_the_domain_boundary_is_certified_with_its_point() {
    let system = unit_system(vec![product_of_roots(1, 0, &[q(0, 1), q(1, 2)])]);
    for path in [Path::Exact, Path::Filtered] {
        let s = solve(&system, &SolveOptions::new().with_path(path)).unwrap();
        account(&system, &s, &[vec![q(0, 1)], vec![q(1, 2)]]).unwrap();
        assert_eq!((s.roots.len(), s.clusters.len()), (2, 0), "{path}");
        let r = s
            .roots
            .iter()
            .find(|r| r.certificate.point.is_some())
            .unwrap();
        assert_eq!(r.certificate.point, Some(vec![q(0, 1)]));
        assert!(r.bounds[0].0 < q(0, 1) && r.bounds[0].1 > q(0, 1));
        assert!(
            verify_root(&system, &r.bounds, &r.certificate)
                .unwrap()
                .on_boundary
        );
        let tamper = |point: Option<Vec<Rational>>| {
            let c = RootCertificate {
                point,
                ..r.certificate.clone()
            };
            verify_root(&system, &r.bounds, &c).is_err()
                && verify_root_exactly(&system, &r.bounds, &c).is_err()
        };
        assert!(tamper(None), "a box outside the domain needs the point");
        assert!(tamper(Some(vec![r.bounds[0].1.clone()])), "not a zero");
        assert!(tamper(Some(vec![q(1, 2)])), "a zero outside the box");
    }
    let s = solve(
        &system,
        &SolveOptions::new()
            .with_path(Path::Exact)
            .with_boundary(false),
    )
    .unwrap();
    account(&system, &s, &[vec![q(0, 1)], vec![q(1, 2)]]).unwrap();
    assert_eq!(s.roots.len(), 1);
    assert!(s
        .clusters
        .iter()
        .any(|c| c.reason == ClusterReason::DomainBoundary && contains(&c.bounds, &[q(0, 1)])));
}

#[test]
fn the_checker_refuses_a_tampered_certificate() {
    let n = 2;
    let system = unit_system(vec![linear(n, 0, &q(1, 3)), linear(n, 1, &q(2, 3))]);
    let s = solve(&system, &SolveOptions::new().with_path(Path::Exact)).unwrap();
    let r = &s.roots[0];
    verify_root(&system, &r.bounds, &r.certificate).unwrap();
    let mut flipped: RootCertificate = r.certificate.clone();
    flipped.lower_face_signs[0] = -flipped.lower_face_signs[0];
    assert!(verify_root(&system, &r.bounds, &flipped).is_err());
    assert!(verify_root_exactly(&system, &r.bounds, &flipped).is_err());
    // A box beside the root holds none: Miranda fails there.
    let beside = vec![(q(1, 2), q(1, 1)), r.bounds[1].clone()];
    assert!(verify_root(&system, &beside, &r.certificate).is_err());
    assert!(verify_root_exactly(&system, &beside, &r.certificate).is_err());
}

#[test]
fn rational_equations_use_the_numerator_once_the_denominator_keeps_its_sign() {
    use geocert::solve::{solve, system_from_json, SolveOptions};
    // (x − 1/3)/(1 + x²) = 0 and (y + 1/5)/(2 − y) = 0 on [−1, 1]²: one root (1/3, −1/5).
    let text = r#"{"box": [["-1","1"],["-1","1"]], "equations": [
        {"rational": {"numerator": {"terms": [[[1,0],1],[[0,0],"-1/3"]]},
                      "denominator": {"terms": [[[0,0],1],[[2,0],1]]}}},
        {"rational": {"numerator": {"terms": [[[0,1],1],[[0,0],"1/5"]]},
                      "denominator": {"terms": [[[0,0],2],[[0,1],-1]]}}}]}"#;
    let s = system_from_json(text).unwrap();
    let sol = solve(&s, &SolveOptions::new()).unwrap();
    assert_eq!(sol.roots.len(), 1);
    approx::assert_abs_diff_eq!(sol.roots[0].approx[0], 1.0 / 3.0, epsilon = 1e-12);
    approx::assert_abs_diff_eq!(sol.roots[0].approx[1], -0.2, epsilon = 1e-12);
    // A denominator that changes sign on the box (x) or vanishes on it (x², at 0) is refused,
    // naming the equation.
    for den in [r#"{"terms": [[[1,0],1]]}"#, r#"{"terms": [[[2,0],1]]}"#] {
        let text = format!(
            r#"{{"box": [["-1","1"],["-1","1"]], "equations": [{{"terms": [[[0,1],1]]}},
            {{"rational": {{"numerator": {{"terms": [[[1,0],1]]}}, "denominator": {den}}}}}]}}"#
        );
        let err = system_from_json(&text).unwrap_err().to_string();
        assert!(
            err.contains("equation 1") && err.contains("denominator"),
            "{err}"
        );
    }
}

#[test]
fn the_filtered_path_refines_to_the_requested_width_where_the_fast_one_stops_at_rounding() {
    // The unit circle and x − 2y + x³/3 = 0 on [−2, 2]²: two irrational roots.
    let system = geocert::solve::system_from_json(
        r#"{"box": [["-2","2"],["-2","2"]], "equations": [
            {"terms": [[[2,0],1],[[0,2],1],[[0,0],-1]]},
            {"terms": [[[1,0],1],[[0,1],-2],[[3,0],"1/3"]]}]}"#,
    )
    .unwrap();
    let side = q(4, 1);
    for (path, widest) in [
        (Path::Filtered, q(1, 100_000_000_000_000)),
        (Path::Exact, q(1, 100_000_000_000_000)),
        (Path::Fast, q(1, 1_000_000_000_000)),
    ] {
        let s = solve(&system, &SolveOptions::new().with_path(path)).unwrap();
        assert_eq!(s.roots.len(), 2, "{path}");
        for r in &s.roots {
            verify_root(&system, &r.bounds, &r.certificate).unwrap();
            for (a, b) in &r.bounds {
                assert!((b - a) / &side <= widest, "{path}: width {}", b - a);
            }
        }
    }
}

/// The non-separable system around the root `r` of the proptests below:
/// `f_i = 10^e (Σ_j a_ij (x_j − r_j) + h_i (x_i − r_i)^{d−1} (x_{i+1} − r_{i+1}))`, with 40
/// added to the diagonal of `a` (a 4 × 4 row-major table; its first rows and columns used).
fn around_root(r: &[Rational], a: &[i64], h: &[i64], e: u32, d: usize) -> Vec<Bernstein<Rational>> {
    let n = r.len();
    let lin: Vec<_> = (0..n).map(|k| linear(n, k, &r[k])).collect();
    let scale = q(10i64.pow(e), 1);
    (0..n)
        .map(|i| {
            let mut f = constant(n, q(0, 1));
            for j in 0..n {
                let aij = a[4 * i + j] + if i == j { 40 } else { 0 };
                f = f.add_elevated(&lin[j].scale(&q(aij, 1))).unwrap();
            }
            let next = (i + 1) % n;
            let mut t = lin[next].scale(&q(h[i], 1));
            for _ in 1..d {
                t = t.product(&lin[i]).unwrap();
            }
            f.add_elevated(&t).unwrap().scale(&scale)
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    /// The systems of `non_separable_systems_around_a_rational_root` with the root on the
    /// box's boundary: each coordinate of `r` at 0 or 1 where `ends` says so (at least one),
    /// else `k/61`. The exact and filtered paths certify `r` once, with `r` itself as the
    /// certificate's point, which the checker accepts; the fast path holds `r` in at most
    /// one certified box, and every certified box passes the checker.
    #[test]
    fn non_separable_systems_around_a_root_on_the_boundary(
        n in 1usize..=4,
        r in proptest::collection::vec(1i64..61, 4),
        ends in proptest::collection::vec(0u8..3, 4),
        a in proptest::collection::vec(-9i64..=9, 16),
        h in proptest::collection::vec(-9i64..=9, 4),
        e in 0u32..=8,
        d in 2usize..=6,
    ) {
        let mut r: Vec<Rational> = (0..n)
            .map(|k| match ends[k] {
                0 => q(0, 1),
                1 => q(1, 1),
                _ => q(r[k], 61),
            })
            .collect();
        if r.iter().all(|x| *x != q(0, 1) && *x != q(1, 1)) {
            r[0] = q(1, 1);
        }
        let system = unit_system(around_root(&r, &a, &h, e, d));
        let limits = geocert::bernstein::Limits::new().with_max_depth(30).with_max_boxes(20_000);
        for path in [Path::Exact, Path::Filtered, Path::Fast] {
            let s = solve(&system, &SolveOptions::new().with_path(path).with_limits(limits)).unwrap();
            let holding: Vec<_> = s.roots.iter().filter(|x| contains(&x.bounds, &r)).collect();
            if path == Path::Fast {
                prop_assert!(holding.len() <= 1, "fast: r in {} certified boxes", holding.len());
            } else {
                prop_assert_eq!(holding.len(), 1, "{}: r in {} certified boxes; clusters {:?}", path, holding.len(), s.clusters);
                prop_assert_eq!(holding[0].certificate.point.as_ref(), Some(&r));
            }
            for x in &s.roots {
                verify_root(&system, &x.bounds, &x.certificate).map_err(|e| TestCaseError::fail(e.to_string()))?;
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    /// Non-separable systems around a rational root `r` in 1–4 unknowns:
    /// `f_i = 10^e (Σ_j a_ij (x_j − r_j) + h_i (x_i − r_i)^{d−1} (x_{i+1} − r_{i+1}))` with a
    /// diagonally dominant `a` (so `r` is simple), `d` from 2 to 6 and coefficients up to
    /// 10⁸. They may have other roots in the box. On every path `r` is certified exactly once,
    /// every certified box passes the checker, and every certified root of the fast and the
    /// filtered path lies in a box the exact path reports (root or cluster).
    #[test]
    fn non_separable_systems_around_a_rational_root(
        n in 1usize..=4,
        r in proptest::collection::vec(1i64..61, 4),
        a in proptest::collection::vec(-9i64..=9, 16),
        h in proptest::collection::vec(-9i64..=9, 4),
        e in 0u32..=8,
        d in 2usize..=6,
    ) {
        let r: Vec<Rational> = r.iter().take(n).map(|&k| q(k, 61)).collect();
        let system = unit_system(around_root(&r, &a, &h, e, d));
        let limits = geocert::bernstein::Limits::new().with_max_depth(30).with_max_boxes(20_000);
        let run = |path| solve(&system, &SolveOptions::new().with_path(path).with_limits(limits)).unwrap();
        let exact = run(Path::Exact);
        for (path, s) in [(Path::Exact, &exact), (Path::Fast, &run(Path::Fast)), (Path::Filtered, &run(Path::Filtered))] {
            let holding = s.roots.iter().filter(|x| contains(&x.bounds, &r)).count();
            prop_assert_eq!(holding, 1, "{}: r in {} certified boxes; clusters {:?}", path, holding, s.clusters);
            for x in &s.roots {
                verify_root(&system, &x.bounds, &x.certificate).map_err(|e| TestCaseError::fail(e.to_string()))?;
                let meets = |b: &[(Rational, Rational)]| b.iter().zip(&x.bounds).all(|((a0, a1), (b0, b1))| a0 <= b1 && b0 <= a1);
                prop_assert!(
                    exact.roots.iter().any(|y| meets(&y.bounds)) || exact.clusters.iter().any(|c| meets(&c.bounds)),
                    "{}: certified root {:?} outside every exact box", path, x.approx
                );
            }
        }
    }
}

/// Flat equations refine to the requested width: `x²⁰ = 10⁻¹⁰` (its derivative at the roots
/// is about 6·10⁻⁹, so `f64` rounding in the values leaves Newton's point some 10⁻⁸ off) and
/// Wilkinson's `Π (x − k/10)`, `k = 1…10`. On the filtered path Newton's method is finished
/// on exact values before the smallest box is certified: every root's box is within the
/// tolerance (or `f64`'s floor of 8ε of the certified box, 2·10⁻¹⁵ here) and holds the root
/// (decided exactly). Before, they stopped at boxes of 1.4·10⁻⁴
/// and 7·10⁻¹¹.
#[test]
fn flat_roots_refine_to_the_tolerance() {
    let power = geocert::solve::system_from_json(
        r#"{"box": [["-1", "1"]], "equations": [{"terms": [[[20], "1"], [[0], "-1/10000000000"]]}]}"#,
    )
    .unwrap();
    let roots: Vec<Rational> = (1..=10).map(|k| q(k, 10)).collect();
    let wilkinson = System::new(
        vec![(q(0, 1), q(21, 20))],
        vec![product_of_roots(
            1,
            0,
            &roots.iter().map(|r| r * q(20, 21)).collect::<Vec<_>>(),
        )],
    )
    .unwrap();
    let opts = SolveOptions::default().with_path(Path::Filtered);
    let tol = opts.tolerance;
    let sol = solve(&power, &opts).unwrap();
    assert_eq!((sol.roots.len(), sol.clusters.len()), (2, 0));
    for r in &sol.roots {
        let (lo, hi) = &r.bounds[0];
        let width = num_traits::ToPrimitive::to_f64(&(hi - lo)).unwrap() / 2.0;
        assert!(width <= tol.max(2e-15), "{width:e}");
        // Holds ±10^(−1/2): lo² and hi² on either side of 1/10 (same signs).
        let tenth = q(1, 10);
        assert!(
            (lo * lo - &tenth) * (hi * hi - &tenth) < q(0, 1),
            "{lo} {hi}"
        );
        verify_root_exactly(&power, &r.bounds, &r.certificate).unwrap();
    }
    let sol = solve(&wilkinson, &opts).unwrap();
    assert_eq!((sol.roots.len(), sol.clusters.len()), (10, 0));
    for r in &sol.roots {
        let (lo, hi) = &r.bounds[0];
        let width = num_traits::ToPrimitive::to_f64(&(hi - lo)).unwrap() / (21.0 / 20.0);
        assert!(width <= tol.max(2e-15), "{width:e}");
        assert!(roots.iter().filter(|x| lo <= *x && *x <= hi).count() == 1);
    }
    println!(
        "x^20 = 1e-10 and Wilkinson's 10 roots: every box within {:e} of the domain",
        tol.max(2e-15)
    );
}
