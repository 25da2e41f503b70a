//! The solver on B-spline equations: polynomials rewritten as B-splines with knots through
//! their roots keep exactly their roots (each found once, certified across the knot planes,
//! re-checked by the piecewise checker), genuinely piecewise fields (a linear form times a
//! positive spline) have exactly the constructed root, and bad fields are refused clearly.
//! Curves of B-spline equations keep the polynomial trace's topology, pass through C⁰ kinks
//! (in 3-D with a certified vertex on every kink plane), and their certificates re-check.

use geocert::bernstein::Bernstein;
use geocert::bspline::TensorSpline;
use geocert::num::Rational;
use geocert::solve::{
    piecewise_curve_certificate, piecewise_solution_certificate, piecewise_system_from_json,
    solve_piecewise, system_from_json, trace_piecewise, verify_curve_certificate,
    verify_piecewise_curves, verify_piecewise_root, verify_solution_certificate, ClusterReason,
    CurveEnd, CurveOptions, Curves, Equation, PiecewiseSystem, Solution, SolveError, SolveOptions,
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

/// `Π_j (x_k − r_j)`.
fn product_of_roots(n: usize, k: usize, roots: &[Rational]) -> Bernstein<Rational> {
    roots
        .iter()
        .fold(Bernstein::constant(vec![0; n], q(1, 1)), |acc, r| {
            acc.product(&linear(n, k, r)).unwrap()
        })
}

/// `Σ_j m_ij e_j` at the common degrees.
fn mix(eqs: &[Bernstein<Rational>], m: &[Vec<i64>]) -> Vec<Bernstein<Rational>> {
    let n = eqs[0].dim();
    let top: Vec<usize> = (0..n)
        .map(|k| eqs.iter().map(|e| e.degrees()[k]).max().unwrap())
        .collect();
    let up: Vec<_> = eqs
        .iter()
        .map(|e| {
            let mut e = e.clone();
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

/// A polynomial in Bernstein form on the unit box as a clamped B-spline without interior
/// knots (the same coefficients), then with `knots[k]` inserted along each axis `k`.
fn as_spline(p: &Bernstein<Rational>, knots: &[Vec<Rational>]) -> TensorSpline<Rational> {
    let clamped: Vec<Vec<Rational>> = p
        .degrees()
        .iter()
        .map(|&d| {
            let mut k = vec![q(0, 1); d + 1];
            k.extend(vec![q(1, 1); d + 1]);
            k
        })
        .collect();
    let mut s = TensorSpline::new(p.degrees().to_vec(), clamped, p.coeffs().to_vec()).unwrap();
    for (axis, xs) in knots.iter().enumerate() {
        if p.degrees()[axis] > 0 && !xs.is_empty() {
            s = s.insert_knots(axis, xs).unwrap();
        }
    }
    s
}

fn contains(bounds: &[(Rational, Rational)], p: &[Rational]) -> bool {
    bounds.iter().zip(p).all(|((a, b), x)| a <= x && x <= b)
}

/// Every constructed root is in exactly one certified box or in some cluster; every
/// certified box holds exactly one constructed root and passes the piecewise checker.
fn account(system: &PiecewiseSystem, s: &Solution, roots: &[Vec<Rational>]) -> Result<(), String> {
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
        verify_piecewise_root(system, &x.bounds, &x.certificate).map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// The grid of roots `per_axis[0] × per_axis[1] × …`.
fn grid(per_axis: &[Vec<Rational>]) -> Vec<Vec<Rational>> {
    let mut roots: Vec<Vec<Rational>> = vec![vec![]];
    for axis in per_axis {
        roots = roots
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
    roots
}

fn unit(n: usize) -> Vec<(Rational, Rational)> {
    vec![(q(0, 1), q(1, 1)); n]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    /// Grids of roots (products of linear factors) mixed by a shear, written as B-splines
    /// whose knots pass through every root coordinate (with multiplicity 1 up to the
    /// degree) and through one more random point: every root is certified exactly once, on
    /// every path, and the checker accepts each.
    #[test]
    fn polynomials_as_b_splines_keep_their_roots(
        n in 1usize..=3,
        xs in proptest::collection::btree_set(1i64..41, 2),
        ys in proptest::collection::btree_set(1i64..37, 2),
        zs in proptest::collection::btree_set(1i64..31, 1),
        extra in 1i64..7,
        repeat in 1usize..=2,
        shear in -3i64..=3,
    ) {
        let per_axis: Vec<Vec<Rational>> = [(xs, 41), (ys, 37), (zs, 31)]
            .into_iter()
            .take(n)
            .map(|(s, den)| s.into_iter().map(|k| q(k, den)).collect())
            .collect();
        let eqs: Vec<_> = (0..n).map(|k| product_of_roots(n, k, &per_axis[k])).collect();
        let m: Vec<Vec<i64>> = (0..n)
            .map(|i| (0..n).map(|j| if i == j { 1 } else if j < i { shear } else { 0 }).collect())
            .collect();
        let polys = mix(&eqs, &m);
        let knots: Vec<Vec<Rational>> = per_axis
            .iter()
            .map(|rs| {
                let mut k: Vec<Rational> = rs.iter().flat_map(|r| vec![r.clone(); repeat]).collect();
                k.push(q(extra, 7));
                k
            })
            .collect();
        let equations = polys
            .iter()
            .map(|p| {
                // Multiplicity above the degree would make the field jump: cap it.
                let capped: Vec<Vec<Rational>> = knots
                    .iter()
                    .enumerate()
                    .map(|(k, ks)| {
                        let mut out: Vec<Rational> = Vec::new();
                        for x in ks {
                            if out.iter().filter(|y| *y == x).count() < p.degrees()[k] {
                                out.push(x.clone());
                            }
                        }
                        out
                    })
                    .collect();
                Equation::Spline(as_spline(p, &capped))
            })
            .collect();
        let system = PiecewiseSystem::new(unit(n), equations).unwrap();
        prop_assert!(system.cells().len() > 1);
        let roots = grid(&per_axis);
        let paths: &[Path] = if n <= 2 { &[Path::Exact, Path::Fast, Path::Filtered] } else { &[Path::Filtered] };
        for &path in paths {
            let s = solve_piecewise(&system, &SolveOptions::new().with_path(path)).unwrap();
            account(&system, &s, &roots).map_err(TestCaseError::fail)?;
            prop_assert_eq!(s.roots.len(), roots.len(), "{}: {:?}", path, s.clusters);
        }
    }

    /// `f_i = L_i · P_i` with `L = M (x − r)` (`M` invertible) and `P_i` B-splines with
    /// positive coefficients on random knots (one of them through `r`): genuinely piecewise
    /// equations whose only root is `r`.
    #[test]
    fn linear_forms_times_positive_splines_have_one_root(
        n in 2usize..=3,
        r in proptest::collection::vec(1i64..16, 3),
        knot in proptest::collection::vec(1i64..16, 3),
        coeffs in proptest::collection::vec(1i64..9, 64),
        shear in -2i64..=2,
    ) {
        let root: Vec<Rational> = r.iter().take(n).map(|&k| q(k, 16)).collect();
        let system = linear_times_positive(&root, &knot, &coeffs, shear, true);
        for path in [Path::Fast, Path::Filtered] {
            let s = solve_piecewise(&system, &SolveOptions::new().with_path(path)).unwrap();
            account(&system, &s, std::slice::from_ref(&root)).map_err(TestCaseError::fail)?;
            if path == Path::Fast {
                // Rounding may leave the root open at the depth limit: then only uncertain
                // clusters hold it.
                prop_assert!(s.roots.len() == 1 && s.clusters.is_empty()
                    || s.roots.is_empty()
                        && s.clusters.iter().all(|c| c.reason == ClusterReason::Uncertain),
                    "fast: {:?}", s.clusters);
            } else {
                prop_assert_eq!((s.roots.len(), s.clusters.len()), (1, 0), "{}: {:?}", path, s.clusters);
            }
        }
    }
}

/// `f_i = L_i · P_i` on the unit box with `L = M (x − root)` (`M` unit lower-bidiagonal with
/// `shear`) and `P_i` quadratic B-splines with positive coefficients from `coeffs`, knots at
/// `knot[k]/16` and (with `through`) at the root's coordinates inside the box: genuinely
/// piecewise equations whose only root is `root`.
fn linear_times_positive(
    root: &[Rational],
    knot: &[i64],
    coeffs: &[i64],
    shear: i64,
    through: bool,
) -> PiecewiseSystem {
    let n = root.len();
    let lines: Vec<Bernstein<Rational>> = (0..n).map(|k| linear(n, k, &root[k])).collect();
    let m: Vec<Vec<i64>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| {
                    if i == j {
                        1
                    } else if j + 1 == i {
                        shear
                    } else {
                        0
                    }
                })
                .collect()
        })
        .collect();
    let forms = mix(&lines, &m);
    let mut equations = Vec::new();
    for (i, l) in forms.iter().enumerate() {
        let knots: Vec<Vec<Rational>> = (0..n)
            .map(|k| {
                let mut ks = vec![q(0, 1); 3];
                let mut inner: Vec<Rational> = [root[k].clone(), q(knot[k], 16)]
                    .into_iter()
                    .skip(usize::from(!through))
                    .filter(|x| *x != q(0, 1) && *x != q(1, 1))
                    .collect();
                inner.sort();
                inner.dedup();
                ks.extend(inner);
                ks.extend(vec![q(1, 1); 3]);
                ks
            })
            .collect();
        let count: usize = knots.iter().map(|k| k.len() - 3).product();
        let c: Vec<Rational> = (0..count).map(|j| q(coeffs[(j + 7 * i) % 64], 1)).collect();
        let p = TensorSpline::new(vec![2; n], knots, c).unwrap();
        let l = as_spline(l, &vec![vec![]; n]);
        equations.push(Equation::Spline(l.product_exact(&p).unwrap()));
    }
    PiecewiseSystem::new(unit(n), equations).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    /// The systems of `linear_forms_times_positive_splines_have_one_root` with the root on
    /// the box's boundary (each coordinate at 0 or 1 where `ends` says so, at least one),
    /// knots through the root's other coordinates or not (`through`). Where no interior knot
    /// passes through the root, the exact and filtered paths certify it once, with the root
    /// itself as the certificate's point, and the piecewise checker accepts it; a root on a
    /// face and on a knot plane at once is accounted for (certified or in clusters).
    #[test]
    fn b_spline_roots_on_the_boundary_are_certified_with_their_point(
        n in 2usize..=3,
        r in proptest::collection::vec(1i64..16, 3),
        ends in proptest::collection::vec(0u8..3, 3),
        knot in proptest::collection::vec(1i64..16, 3),
        coeffs in proptest::collection::vec(1i64..9, 64),
        shear in -2i64..=2,
        through: bool,
    ) {
        let mut root: Vec<Rational> = (0..n)
            .map(|k| match ends[k] {
                0 => q(0, 1),
                1 => q(1, 1),
                _ => q(r[k], 16),
            })
            .collect();
        if ends.iter().take(n).all(|&e| e == 2) {
            root[0] = q(1, 1);
        }
        let system = linear_times_positive(&root, &knot, &coeffs, shear, through);
        let inside = |x: &Rational| *x != q(0, 1) && *x != q(1, 1);
        let on_knot = (0..n).any(|k| inside(&root[k]) && (through || root[k] == q(knot[k], 16)));
        for path in [Path::Exact, Path::Filtered] {
            let s = solve_piecewise(&system, &SolveOptions::new().with_path(path)).unwrap();
            account(&system, &s, std::slice::from_ref(&root)).map_err(TestCaseError::fail)?;
            if !on_knot {
                prop_assert_eq!((s.roots.len(), s.clusters.len()), (1, 0), "{}: {:?}", path, s.clusters);
                prop_assert_eq!(s.roots[0].certificate.point.as_ref(), Some(&root));
            }
        }
    }
}

#[test]
fn a_root_where_four_cells_meet_is_certified_once_and_rechecked_from_the_file() {
    // x − y = 0 and x + y − 1 = 0 meet at (½, ½); both fields are cubic B-splines with a
    // double knot at ½ on each axis.
    let n = 2;
    let half = q(1, 2);
    let polys = mix(
        &[linear(n, 0, &half), linear(n, 1, &half)],
        &[vec![1, -1], vec![1, 1]],
    );
    let equations = polys
        .iter()
        .map(|p| {
            let mut p = p.elevate(0, 2).unwrap();
            p = p.elevate(1, 2).unwrap();
            Equation::Spline(as_spline(
                &p,
                &[vec![half.clone(); 2], vec![half.clone(); 2]],
            ))
        })
        .collect();
    let system = PiecewiseSystem::new(unit(n), equations).unwrap();
    assert_eq!(system.cells().len(), 4);
    for path in [Path::Exact, Path::Fast, Path::Filtered] {
        let s = solve_piecewise(&system, &SolveOptions::new().with_path(path)).unwrap();
        account(&system, &s, &[vec![half.clone(), half.clone()]]).unwrap();
        assert_eq!((s.roots.len(), s.clusters.len()), (1, 0), "{path}");
        // Refined to the default tolerance, around the knot corner.
        let w = &s.roots[0].bounds[0].1 - &s.roots[0].bounds[0].0;
        assert!(w <= q(1, 1_000_000_000), "{path}: width {w}");
        // The certificate file, written and re-checked from its text.
        let file = piecewise_solution_certificate(&system, &s).to_string();
        let outcomes = verify_solution_certificate(&file).unwrap();
        assert_eq!(outcomes.len(), 1);
        assert!(outcomes[0].is_ok(), "{:?}", outcomes[0]);
        // The same file with the field changed on one side of the knot is refused.
        let tampered = file.replacen("\"coeffs\":[\"-1/2\"", "\"coeffs\":[\"1/2\"", 1);
        if tampered != file {
            let again = verify_solution_certificate(&tampered).unwrap();
            assert!(again[0].is_err());
        }
    }
}

#[test]
fn a_c0_field_with_a_root_on_its_kink_is_certified() {
    // f1: the piecewise-linear field through (0, −⅓), (⅓, 0), (1, 2) — slope 1 left of the
    // knot ⅓, slope 3 right of it, zero on the kink; f2 = y − ¼.
    let text = r#"{"box": [["0", "1"], ["0", "1"]], "equations": [
        {"bspline": {"orders": [2, 1], "knots": [["0", "0", "1/3", "1", "1"], ["0", "1"]],
                     "coeffs": ["-1/3", "0", "2"]}},
        {"terms": [[[0, 1], 1], [[0, 0], "-1/4"]]}]}"#;
    let system = piecewise_system_from_json(text).unwrap();
    assert_eq!(system.cells().len(), 2);
    for path in [Path::Exact, Path::Fast, Path::Filtered] {
        let s = solve_piecewise(&system, &SolveOptions::new().with_path(path)).unwrap();
        account(&system, &s, &[vec![q(1, 3), q(1, 4)]]).unwrap();
        assert_eq!((s.roots.len(), s.clusters.len()), (1, 0), "{path}");
    }
    // The polynomial reader points to the piecewise one.
    let e = system_from_json(text).unwrap_err().to_string();
    assert!(e.contains("piecewise"), "{e}");
}

#[test]
fn an_unclamped_uniform_spline_is_read_on_its_domain() {
    // Cubic B-splines on the knots 0, 1, 2, 3, 7/2, 4, 5, 6, 7 have the domain [s_3, s_5] =
    // [3, 4]; with coefficients ξ_i − 7/2 at the Greville abscissae ξ_i (the means of three
    // consecutive inner knots: 2, 17/6, 7/2, 25/6, 5) the field is exactly x − 7/2, whose
    // root lies on the knot 7/2.
    let text = r#"{"box": [["3", "4"]], "equations": [
        {"bspline": {"orders": [4], "knots": [[0, 1, 2, 3, "7/2", 4, 5, 6, 7]],
                     "coeffs": ["-3/2", "-2/3", "0", "2/3", "3/2"]}}]}"#;
    let system = piecewise_system_from_json(text).unwrap();
    assert_eq!(system.cells().len(), 2);
    for path in [Path::Exact, Path::Fast, Path::Filtered] {
        let s = solve_piecewise(&system, &SolveOptions::new().with_path(path)).unwrap();
        account(&system, &s, &[vec![q(7, 2)]]).unwrap();
        assert_eq!((s.roots.len(), s.clusters.len()), (1, 0), "{path}");
    }
}

#[test]
fn bad_fields_are_refused_naming_the_equation() {
    let refused = |text: &str, needle: &str| {
        let e = piecewise_system_from_json(text).unwrap_err();
        let m = e.to_string();
        assert!(m.contains(needle), "{m}");
        e
    };
    // A knot of multiplicity order inside the box: the field jumps there.
    let e = refused(
        r#"{"box": [["0", "1"]], "equations": [{"bspline": {"orders": [2],
            "knots": [[0, 0, "1/2", "1/2", 1, 1]], "coeffs": [-1, 1, -1, 1]}}]}"#,
        "jumps",
    );
    assert!(matches!(e, SolveError::Equation { equation: 0, .. }));
    // The spline's domain does not cover the box.
    refused(
        r#"{"box": [["0", "2"]], "equations": [{"bspline": {"orders": [2],
            "knots": [[0, 0, 1, 1]], "coeffs": [-1, 1]}}]}"#,
        "does not cover",
    );
    // Wrong coefficient count.
    refused(
        r#"{"box": [["0", "1"]], "equations": [{"bspline": {"orders": [2],
            "knots": [[0, 0, 1, 1]], "coeffs": [-1, 1, 2]}}]}"#,
        "equations[0].bspline",
    );
    // Decreasing knots.
    refused(
        r#"{"box": [["0", "1"]], "equations": [{"bspline": {"orders": [2],
            "knots": [[0, 0, "1/2", "1/4", 1, 1]], "coeffs": [-1, 1, 2, 3]}}]}"#,
        "not non-decreasing",
    );
    // Orders missing.
    refused(
        r#"{"box": [["0", "1"]], "equations": [{"bspline": {"knots": [[0, 1]], "coeffs": [1]}}]}"#,
        "orders",
    );
}

// ---- Curves of B-spline equations ----

/// A quadric `Σ_k a_k (x_k − c_k)² − r` on the unit box in `n` variables (a circle or a
/// sphere when every `a_k = 1`), in Bernstein form.
fn quadric(c: &[Rational], a: &[i64], r: &Rational) -> Bernstein<Rational> {
    let n = c.len();
    (0..n)
        .map(|k| {
            let l = linear(n, k, &c[k]);
            l.product(&l).unwrap().scale(&q(a[k], 1))
        })
        .fold(Bernstein::constant(vec![0; n], -r.clone()), |s, t| {
            s.add_elevated(&t).unwrap()
        })
}

/// The ends of a traced curve's open components as sorted (axis, upper) face pairs, and the
/// number of closed loops.
fn topology(c: &Curves) -> (Vec<Vec<(usize, bool)>>, usize) {
    let mut open: Vec<Vec<(usize, bool)>> = c
        .components
        .iter()
        .filter(|k| !k.closed)
        .map(|k| {
            let mut e: Vec<(usize, bool)> = k
                .ends
                .iter()
                .filter_map(|e| match *e {
                    CurveEnd::Face { axis, upper, .. } => Some((axis, upper)),
                    CurveEnd::Cluster { .. } => None,
                })
                .collect();
            e.sort();
            e
        })
        .collect();
    open.sort();
    (open, c.components.iter().filter(|k| k.closed).count())
}

/// The largest `|f_i|` of the piecewise system at the traced vertices (in `f64`).
fn worst_residual(system: &PiecewiseSystem, c: &Curves) -> f64 {
    let mut worst = 0.0f64;
    for p in &c.points {
        let x: Vec<Rational> = p
            .root
            .approx
            .iter()
            .map(|&v| geocert::num::rational_from_f64(v, "x").unwrap())
            .collect();
        for e in system.equations() {
            let v = match e {
                Equation::Spline(s) => s.eval(&x).unwrap(),
                Equation::Polynomial(b) => b.eval(&x).unwrap(),
            };
            worst = worst.max(geocert::num::rational_to_f64(&v).abs());
        }
    }
    worst
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    /// Circles (2 unknowns) and circles cut from a sphere by a plane (3 unknowns), written as
    /// B-splines with random interior knots (multiplicity 1 up to the degree, so some are
    /// C⁰ knots the 3-D tracer must split at): the piecewise trace passes the piecewise
    /// checker on every path, its vertices lie on the curve, and where neither trace leaves a
    /// cluster it has the polynomial trace's topology (loops, and open components' faces).
    #[test]
    fn polynomial_curves_as_b_splines_keep_their_topology(
        n in 2usize..=3,
        centre in proptest::collection::vec(3i64..14, 3),
        radius in 2i64..9,
        tilt in proptest::collection::vec(-3i64..=3, 3),
        knots in proptest::collection::vec(1i64..16, 3),
        repeat in 1usize..=2,
    ) {
        let c: Vec<Rational> = centre.iter().take(n).map(|&k| q(k, 16)).collect();
        let r = q(radius * radius, 256);
        let mut polys = vec![quadric(&c, &[1; 3][..n], &r)];
        if n == 3 {
            // A plane through the centre, tilted.
            let forms: Vec<_> = (0..3).map(|k| linear(3, k, &c[k])).collect();
            let m = vec![vec![tilt[0], tilt[1], 4 + tilt[2].abs()]];
            polys.push(mix(&forms, &m).remove(0));
        }
        let system = PiecewiseSystem::from_polynomial(
            geocert::solve::System::new(unit(n), polys.clone()).unwrap(),
        );
        let equations = polys
            .iter()
            .map(|p| {
                let ks: Vec<Vec<Rational>> = (0..n)
                    .map(|k| {
                        let reps = repeat.min(p.degrees()[k]).max(1);
                        vec![q(knots[k], 16); reps]
                    })
                    .collect();
                Equation::Spline(as_spline(p, &ks))
            })
            .collect();
        let pw = PiecewiseSystem::new(unit(n), equations).unwrap();
        prop_assert!(pw.cells().len() > 1);
        // Knots of multiplicity up to the degree, but a polynomial: C¹ everywhere.
        prop_assert!(pw.kinks().iter().all(Vec::is_empty));
        let opts = CurveOptions::new().with_resolution(0.25);
        let reference = trace_piecewise(&system, &opts).unwrap();
        let paths: &[Path] = if n == 2 { &[Path::Exact, Path::Fast, Path::Filtered] } else { &[Path::Filtered] };
        for &path in paths {
            let traced = trace_piecewise(&pw, &opts.with_path(path)).unwrap();
            verify_piecewise_curves(&pw, &traced).map_err(|e| TestCaseError::fail(e.to_string()))?;
            prop_assert!(worst_residual(&pw, &traced) < 1e-9);
            if traced.clusters.is_empty() && reference.clusters.is_empty() {
                prop_assert_eq!(topology(&traced), topology(&reference), "{}", path);
            }
            if path == Path::Filtered && reference.clusters.is_empty() {
                // Knots do not make a curve harder to resolve (tangencies to the box's faces
                // leave clusters on both).
                prop_assert!(traced.clusters.is_empty(), "{:?}", traced.clusters);
            }
        }
    }
}

/// `Σ_i Σ_l (b_l − g_i) N_i(x_0) M_l(x_axis)` = `x_axis − g(x_0)` for `g` the spline with
/// coefficients `g` on `knots` (degree `p`), as a tensor spline in `n` unknowns (degree 1
/// along `axis`, 0 along the others).
fn graph_equation(
    n: usize,
    axis: usize,
    p: usize,
    knots: Vec<Rational>,
    g: &[Rational],
) -> Equation {
    let mut degrees = vec![0; n];
    degrees[0] = p;
    degrees[axis] = 1;
    let all_knots: Vec<Vec<Rational>> = (0..n)
        .map(|k| match k {
            0 => knots.clone(),
            k if k == axis => vec![q(0, 1), q(0, 1), q(1, 1), q(1, 1)],
            _ => vec![q(0, 1), q(1, 1)],
        })
        .collect();
    // Axis 0 fastest; the `axis` index (0 or 1) is the line coordinate b_l = l.
    let mut coeffs = Vec::new();
    for l in 0..2 {
        for gi in g {
            coeffs.push(q(l, 1) - gi);
        }
    }
    Equation::Spline(TensorSpline::new(degrees, all_knots, coeffs).unwrap())
}

#[test]
fn a_c0_graph_is_traced_through_its_kinks_in_two_and_three_unknowns() {
    // g: piecewise linear through (0, 1/5), (1/3, 3/5), (3/4, 2/5), (1, 7/10) — kinks at 1/3
    // and 3/4; h: quadratic with a double knot at 1/2 (C⁰ there).
    let g_knots = vec![q(0, 1), q(0, 1), q(1, 3), q(3, 4), q(1, 1), q(1, 1)];
    let g = [q(1, 5), q(3, 5), q(2, 5), q(7, 10)];
    let h_knots = vec![
        q(0, 1),
        q(0, 1),
        q(0, 1),
        q(1, 2),
        q(1, 2),
        q(1, 1),
        q(1, 1),
        q(1, 1),
    ];
    let h = [q(1, 4), q(3, 4), q(1, 2), q(1, 5), q(3, 5)];
    let mut compared = 0;
    for n in [2usize, 3] {
        let mut equations = vec![graph_equation(n, n - 1, 1, g_knots.clone(), &g)];
        if n == 3 {
            equations.push(graph_equation(3, 1, 2, h_knots.clone(), &h));
        }
        let system = PiecewiseSystem::new(unit(n), equations).unwrap();
        let kinks: Vec<Rational> = if n == 3 {
            vec![q(1, 3), q(1, 2), q(3, 4)]
        } else {
            vec![q(1, 3), q(3, 4)]
        };
        assert_eq!(system.kinks()[0], kinks);
        let paths: &[Path] = if n == 2 {
            &[Path::Exact, Path::Fast, Path::Filtered]
        } else {
            &[Path::Fast, Path::Filtered]
        };
        for &path in paths {
            let c = trace_piecewise(&system, &CurveOptions::new().with_path(path)).unwrap();
            assert!(
                c.clusters.is_empty(),
                "{n} unknowns, {path}: {:?}",
                c.clusters
            );
            assert_eq!(c.components.len(), 1, "{n}, {path}");
            assert_eq!(topology(&c).0, vec![vec![(0, false), (0, true)]]);
            verify_piecewise_curves(&system, &c).unwrap();
            assert!(worst_residual(&system, &c) < 1e-12, "{n}, {path}");
            if n == 3 {
                // In three unknowns every C⁰ plane the curve crosses is a split plane: the
                // curve has a certified vertex on it.
                for x in &kinks {
                    assert!(
                        c.points
                            .iter()
                            .any(|p| p.axis == 0 && &p.root.bounds[0].0 == x),
                        "no vertex on the kink x = {x}"
                    );
                }
            }
            compared += 1;
        }
    }
    assert_eq!(compared, 5);
}

#[test]
fn a_loop_around_a_kink_is_closed_and_its_certificate_file_is_rechecked() {
    // |x − 1/2| + (y − 1/2)² − 1/16 = 0: a loop crossing the C⁰ plane x = 1/2 twice.
    let a = [q(1, 2), q(0, 1), q(1, 2)];
    let b = [q(3, 16), q(-5, 16), q(3, 16)];
    let coeffs: Vec<Rational> = b
        .iter()
        .flat_map(|bl| a.iter().map(move |ai| ai + bl))
        .collect();
    let spline = TensorSpline::new(
        vec![1, 2],
        vec![
            vec![q(0, 1), q(0, 1), q(1, 2), q(1, 1), q(1, 1)],
            vec![q(0, 1), q(0, 1), q(0, 1), q(1, 1), q(1, 1), q(1, 1)],
        ],
        coeffs,
    )
    .unwrap();
    let system = PiecewiseSystem::new(unit(2), vec![Equation::Spline(spline)]).unwrap();
    for path in [Path::Exact, Path::Fast, Path::Filtered] {
        let c = trace_piecewise(&system, &CurveOptions::new().with_path(path)).unwrap();
        assert!(c.clusters.is_empty(), "{path}: {:?}", c.clusters);
        assert_eq!(topology(&c), (vec![], 1), "{path}");
        assert!(worst_residual(&system, &c) < 1e-12);
        let text = piecewise_curve_certificate(&system, &c).to_string();
        let check = verify_curve_certificate(&text).unwrap().unwrap();
        assert_eq!(check.points, c.points.len());
        // A vertex moved off the curve is refused.
        let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
        let axis = v["points"][0]["axis"].as_u64().unwrap() as usize;
        let other = 1 - axis;
        v["points"][0]["box"][other] = serde_json::json!(["1/100", "1/50"]);
        assert!(verify_curve_certificate(&v.to_string()).unwrap().is_err());
    }
    // Extreme points are for polynomial equations: asked here, a clear error.
    let e = trace_piecewise(&system, &CurveOptions::new().with_extreme_axis(Some(0)))
        .unwrap_err()
        .to_string();
    assert!(e.contains("extreme"), "{e}");
}
