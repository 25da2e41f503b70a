//! Property tests of the FFD family: the two exact Jacobian routes agree, the f64 Jacobian
//! stays inside its bound, certified fast verdicts never contradict exact ones, certificates
//! re-check.

use geocert::bernstein::{Bernstein, Limits};
use geocert::ffd::{
    check_injectivity, jacobian_cell_fast, verify_injectivity_certificate, Basis, CheckOptions,
    InjectivityCertificate, InjectivityVerdict, JacobianWorkspace, Lattice,
};
use geocert::ffd::{
    jacobian_at, jacobian_cell_bezier, jacobian_cell_scaled, jacobian_cells_morken,
    jacobian_in_cell,
};
use geocert::num::{rational_from_f64, Rational, Sign};
use num_bigint::BigInt;
use num_traits::Signed;
use proptest::prelude::*;

fn q(n: i64, d: i64) -> Rational {
    Rational::new(BigInt::from(n), BigInt::from(d))
}

/// A lattice perturbed from the identity by `amp`·(values in [-1,1] with denominator 16).
fn perturbed(
    basis: Basis,
    order: [usize; 3],
    cells: [usize; 3],
    amp: Rational,
    noise: &[i64],
) -> Lattice {
    let id = Lattice::identity(basis, order, cells).unwrap();
    let delta: Vec<[Rational; 3]> = (0..id.points().len())
        .map(|i| [0, 1, 2].map(|a| &amp * q(noise[(3 * i + a) % noise.len()], 16)))
        .collect();
    id.displaced(&delta).unwrap()
}

fn lattice_strategy(max_order: usize, max_cells: usize) -> impl Strategy<Value = Lattice> {
    (
        prop::bool::ANY,
        [2..=max_order, 2..=max_order, 2..=max_order],
        [1..=max_cells, 1..=max_cells, 1..=max_cells],
        0i64..12,
        prop::collection::vec(-16i64..=16, 1..64),
    )
        .prop_map(|(bez, order, cells, amp, noise)| {
            let (basis, cells) = if bez {
                (Basis::Bezier, [1, 1, 1])
            } else {
                (Basis::Bspline, cells)
            };
            perturbed(basis, order, cells, q(amp, 8), &noise)
        })
}

#[test]
fn identity_lattices_have_unit_jacobian_and_are_injective() {
    for basis in [Basis::Bspline, Basis::Bezier] {
        for order in 2..=4 {
            let cells = if basis == Basis::Bezier {
                [1, 1, 1]
            } else {
                [2, 1, 3]
            };
            let l = Lattice::identity(basis, [order, order, order], cells).unwrap();
            let u = [q(1, 3), q(2, 5), q(1, 2)];
            assert_eq!(jacobian_at(&l, &u).unwrap(), q(1, 1));
            for path in [
                geocert::Path::Exact,
                geocert::Path::Fast,
                geocert::Path::Filtered,
            ] {
                let r = check_injectivity(&l, CheckOptions::new().with_path(path)).unwrap();
                assert!(
                    matches!(r.verdict, InjectivityVerdict::Injective { .. }),
                    "{basis:?} {order} {path:?}"
                );
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn both_exact_routes_give_identical_bezier_coefficients(l in lattice_strategy(4, 2)) {
        let morken = jacobian_cells_morken(&l).unwrap();
        let nets = l.bezier_nets();
        prop_assert_eq!(morken.len(), nets.len());
        for (m, net) in morken.iter().zip(&nets) {
            let b = jacobian_cell_bezier(net).unwrap();
            prop_assert_eq!(m, &b);
            prop_assert_eq!(&jacobian_cell_scaled(net).unwrap().to_rational(), &b);
        }
    }

    #[test]
    fn fast_jacobian_within_its_bound(l in lattice_strategy(5, 2)) {
        let deg = l.order().map(|o| o - 1);
        let mut ws = JacobianWorkspace::default();
        for net in l.bezier_nets() {
            let exact = jacobian_cell_bezier(&net).unwrap();
            let mut inexact = false;
            let pts: Vec<[f64; 3]> = (0..net[0].coeffs().len()).map(|k| [0, 1, 2].map(|c| {
                let r = &net[c].coeffs()[k];
                let x = geocert::num::rational_to_f64(r);
                inexact |= &rational_from_f64(x, "x").unwrap() != r;
                x
            })).collect();
            let eta = if inexact { geocert::num::UNIT_ROUNDOFF } else { 0.0 };
            let f = jacobian_cell_fast(&pts, deg, eta, &mut ws).unwrap();
            let err = rational_from_f64(f.err(), "err").unwrap();
            for (c, e) in f.coeffs().iter().zip(exact.coeffs()) {
                let c = rational_from_f64(*c, "c").unwrap();
                prop_assert!((&c - e).abs() <= err, "coefficient {} vs exact {} (err {})", c, e, f.err());
            }
        }
    }

    #[test]
    fn certified_fast_never_contradicts_exact_and_certificates_recheck(l in lattice_strategy(4, 2)) {
        let limits = Limits::new().with_max_depth(6);
        let exact = check_injectivity(&l, CheckOptions::new().with_path(geocert::Path::Exact).with_limits(limits)).unwrap();
        let fast = check_injectivity(&l, CheckOptions::new().with_path(geocert::Path::Fast).with_limits(limits)).unwrap();
        let filtered = check_injectivity(&l, CheckOptions::new().with_path(geocert::Path::Filtered).with_limits(limits)).unwrap();
        prop_assert!(!fast.verdict.sign().contradicts(exact.verdict.sign()));
        prop_assert!(!filtered.verdict.sign().contradicts(exact.verdict.sign()));
        let filtered_decided = filtered.verdict.sign() != Sign::Uncertain
            || matches!(filtered.verdict, InjectivityVerdict::Undecided { .. });
        prop_assert!(filtered_decided);
        for r in [&exact, &fast, &filtered] {
            if let Some(cert) = InjectivityCertificate::from_report(&l, r) {
                let text = serde_json::to_string(&cert).unwrap();
                let back: InjectivityCertificate = serde_json::from_str(&text).unwrap();
                prop_assert!(verify_injectivity_certificate(&back).is_ok(), "{:?}", verify_injectivity_certificate(&back));
            }
            if let InjectivityVerdict::NotInjective { point, det, cell } = &r.verdict {
                prop_assert!(det <= &Rational::default());
                prop_assert_eq!(&jacobian_in_cell(&l, *cell, point).unwrap(), det);
            }
            if let (Some(lb), InjectivityVerdict::NotInjective { det, .. }) = (&r.min_det_lower_bound, &r.verdict) {
                prop_assert!(lb <= det);
            }
        }
    }
}

#[test]
fn folded_lattice_is_not_injective_with_exact_witness() {
    // Swap two control points along u in a Bézier cell: the cell folds over.
    let l = Lattice::identity(Basis::Bezier, [3, 3, 3], [1, 1, 1]).unwrap();
    let mut pts = l.points().to_vec();
    pts.swap(0, 2);
    let l = Lattice::new(Basis::Bezier, [3, 3, 3], [1, 1, 1], pts).unwrap();
    for path in [
        geocert::Path::Exact,
        geocert::Path::Fast,
        geocert::Path::Filtered,
    ] {
        let r = check_injectivity(&l, CheckOptions::new().with_path(path)).unwrap();
        match &r.verdict {
            InjectivityVerdict::NotInjective { point, det, cell } => {
                assert!(det <= &Rational::default());
                assert_eq!(&jacobian_in_cell(&l, *cell, point).unwrap(), det);
            }
            other => panic!("{path:?}: {other:?}"),
        }
    }
    let _ = Bernstein::<Rational>::constant(vec![1], q(1, 1));
}

mod sufficient_tests {
    use super::*;
    use geocert::ffd::*;

    /// Lattices on an f64 grid (so the plain-f64 conic route runs too).
    fn f64_lattice() -> impl Strategy<Value = Lattice> {
        (
            prop::bool::ANY,
            [2usize..=4, 2usize..=4, 2usize..=4],
            [1usize..=2, 1usize..=2, 1usize..=2],
            0u32..6,
            prop::collection::vec(-1.0f64..1.0, 1..64),
        )
            .prop_map(|(bez, order, cells, amp, noise)| {
                let (basis, cells) = if bez {
                    (Basis::Bezier, [1, 1, 1])
                } else {
                    (Basis::Bspline, cells)
                };
                let id = Lattice::identity(basis, order, cells).unwrap();
                let amp = 0.04 * amp as f64;
                let pts = id
                    .points()
                    .iter()
                    .enumerate()
                    .map(|(i, p)| {
                        [0, 1, 2].map(|a| {
                            let x = geocert::num::rational_to_f64(&p[a])
                                + amp * noise[(3 * i + a) % noise.len()];
                            rational_from_f64(x, "x").unwrap()
                        })
                    })
                    .collect();
                Lattice::new(basis, order, cells, pts).unwrap()
            })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// conic ⇒ phi ⇒ Bézier coefficients ⇒ N&S, per cell and for the whole lattice, and
        /// subdivided conic ⇐ conic.
        #[test]
        fn weaker_tests_imply_stronger(l in f64_lattice()) {
            let limits = Limits::new().with_max_depth(8);
            let ns = check_injectivity(&l, CheckOptions::new().with_path(geocert::Path::Exact).with_limits(limits)).unwrap().verdict.sign();
            let bez = bezier_coefficient_test_exact(&l).unwrap().sign();
            let phi = phi_test_exact(&l, Scope::PerCell).sign();
            let phi_all = phi_test_exact(&l, Scope::Lattice).sign();
            let conic = conic_test_exact(&l, ConicOptions::default()).sign();
            let conic_all = conic_test_exact(&l, ConicOptions::new().with_scope(Scope::Lattice).with_subdivision_depth(0)).sign();
            let conic_sub = conic_test_exact(&l, ConicOptions::new().with_scope(Scope::PerCell).with_subdivision_depth(1)).sign();
            let implies = |a: Sign, b: Sign| a != Sign::Positive || b == Sign::Positive;
            prop_assert!(implies(conic, phi), "conic passes, phi does not");
            prop_assert!(implies(conic_all, conic));
            prop_assert!(implies(phi_all, phi));
            prop_assert!(implies(phi, bez), "phi passes, Bézier coefficients do not");
            prop_assert!(implies(bez, ns) || ns == Sign::Uncertain);
            prop_assert!(implies(conic_sub, ns) || ns == Sign::Uncertain);
            prop_assert!(implies(conic, conic_sub), "subdivision lost a pass");
        }

        #[test]
        fn certified_fast_sufficient_tests_agree_with_exact(l in f64_lattice()) {
            for scope in [Scope::PerCell, Scope::Lattice] {
                let e = phi_test_exact(&l, scope).sign();
                prop_assert!(!phi_test_fast(&l, scope).sign().contradicts(e));
                for depth in [0, 1] {
                    let opts = ConicOptions::new().with_scope(scope).with_subdivision_depth(depth);
                    let e = conic_test_exact(&l, opts).sign();
                    prop_assert!(!conic_test_fast(&l, opts).sign().contradicts(e));
                }
            }
            let e = bezier_coefficient_test_exact(&l).unwrap().sign();
            prop_assert!(!bezier_coefficient_test_fast(&l).sign().contradicts(e));
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    /// Injective DMFFD: every step is injective by the N&S test, the exact composition meets
    /// the constraints exactly, the f64 one to rounding; a refusal is a typed error.
    #[test]
    fn injective_drag_steps_are_injective_and_compose(
        pts in proptest::collection::vec((4i64..13, 4i64..13, 4i64..13), 1..3),
        deltas in proptest::collection::vec((-7i64..8, -7i64..8, -7i64..8), 2),
        fast in any::<bool>(),
    ) {
        use geocert::ffd::deform_points_fast;
        use geocert::ffd::{compose, injective_drag, Constraint, DragOptions};
        use geocert::ffd::FfdError;
        let shape = Lattice::identity(Basis::Bspline, [3, 3, 3], [2, 2, 2]).unwrap();
        let cs: Vec<Constraint> = pts
            .iter()
            .zip(&deltas)
            .map(|(p, d)| Constraint {
                point: [q(p.0, 8), q(p.1, 8), q(p.2, 8)],
                delta: [q(d.0, 16), q(d.1, 16), q(d.2, 16)],
            })
            .collect();
        let opts = DragOptions::new().with_path(if fast { geocert::Path::Fast } else { geocert::Path::Exact }).with_max_depth(6);
        // Paths stay strictly inside the domain [0,2]³: points in [½, 1½], moves below ½.
        match injective_drag(&shape, &cs, opts) {
            Ok(steps) => {
                prop_assert!(!steps.is_empty());
                for s in &steps {
                    let r = check_injectivity(&s.lattice, CheckOptions::default()).unwrap();
                    let injective = matches!(r.verdict, InjectivityVerdict::Injective { .. });
                    prop_assert!(injective, "step at depth {} not injective", s.depth);
                }
                let lattices: Vec<Lattice> = steps.iter().map(|s| s.lattice.clone()).collect();
                for c in &cs {
                    let target: [Rational; 3] = [0, 1, 2].map(|a| &c.point[a] + &c.delta[a]);
                    if fast {
                        // Exact images through rounded steps grow like degree^steps digits:
                        // compose in f64.
                        let f = |x: &Rational| geocert::num::rational_to_f64(x);
                        let mut p = [c.point.clone().map(|x| f(&x))];
                        deform_points_fast(&lattices, None, &mut p).unwrap();
                        for a in 0..3 {
                            let e = (p[0][a] - f(&target[a])).abs();
                            prop_assert!(e < 1e-12, "error {e}");
                        }
                    } else {
                        prop_assert_eq!(compose(&steps, &c.point).unwrap(), target);
                    }
                }
            }
            Err(FfdError::RankDeficient { .. })
            | Err(FfdError::DragNotInjective { .. })
            | Err(FfdError::Input { .. })
            | Err(FfdError::OutsideDomain { .. }) => {}
            Err(e) => prop_assert!(false, "unexpected error {e}"),
        }
    }
}
