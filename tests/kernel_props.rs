//! Property tests of the scalar, Bernstein and B-spline kernel: exact identities in rational
//! arithmetic, and the fast path checked against the exact one.

use geocert::bernstein::{
    prove_positive_exact, prove_positive_fast, prove_positive_filtered,
    verify_positive_certificate, verify_positive_certificate_scaled, Bernstein, FastBernstein,
    Limits, PositivityVerdict, ScaledBernstein,
};
use geocert::bernstein::{verify_witness, CertificateError, WitnessValue};
use geocert::bspline::{morken_product, ScaledSpline, Spline, TableCache, TensorSpline};
use geocert::num::{rational_from_f64, rational_to_f64, Field, Interval, Rational, Sign};
use geocert::strategies::{bernstein_poly, spline};
use num_bigint::BigInt;
use num_traits::{Signed, Zero};
use proptest::prelude::*;

fn q(n: i64, d: i64) -> Rational {
    Rational::new(BigInt::from(n), BigInt::from(d))
}

fn unit_param() -> impl Strategy<Value = Rational> {
    (1i64..=15, 16i64..=17).prop_map(|(n, d)| q(n, d))
}

fn point(dim: usize) -> impl Strategy<Value = Vec<Rational>> {
    proptest::collection::vec((0i64..=12).prop_map(|n| q(n, 12)), dim)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, .. ProptestConfig::default() })]

    #[test]
    fn f64_rational_round_trip(bits in any::<u64>()) {
        let x = f64::from_bits(bits);
        if x.is_finite() {
            let r = rational_from_f64(x, "x").unwrap();
            prop_assert_eq!(rational_to_f64(&r), x);
        } else {
            prop_assert!(rational_from_f64(x, "x").is_err());
        }
    }

    #[test]
    fn nearest_f64_is_nearest(n in any::<i64>(), d in 1i64..i64::MAX) {
        let r = q(n, d);
        let x = rational_to_f64(&r);
        let ex = rational_from_f64(x, "x").unwrap();
        let err = (&ex - &r).abs();
        for y in [x.next_up(), x.next_down()] {
            let ey = rational_from_f64(y, "y").unwrap();
            prop_assert!(err <= (&ey - &r).abs());
        }
    }

    #[test]
    fn intervals_enclose(a in any::<i32>(), b in 1i32..i32::MAX, c in any::<i32>(), d in 1i32..i32::MAX) {
        let (x, y) = (q(a as i64, b as i64), q(c as i64, d as i64));
        let (ix, iy) = (Interval::from_rational(&x), Interval::from_rational(&y));
        prop_assert!((ix + iy).contains(&(&x + &y)));
        prop_assert!((ix - iy).contains(&(&x - &y)));
        prop_assert!((ix * iy).contains(&(&x * &y)));
        if y != q(0, 1) {
            prop_assert!((ix / iy).contains(&(&x / &y)));
        }
    }

    #[test]
    fn split_halves_reevaluate(p in bernstein_poly(vec![3, 2], 20), t in unit_param(), s in point(2), axis in 0usize..2) {
        let (l, r) = p.split(axis, &t).unwrap();
        let mut pl = s.clone();
        pl[axis] = &s[axis] * &t;
        prop_assert_eq!(l.eval(&s).unwrap(), p.eval(&pl).unwrap());
        let mut pr = s.clone();
        pr[axis] = &t + &s[axis] * (q(1, 1) - &t);
        prop_assert_eq!(r.eval(&s).unwrap(), p.eval(&pr).unwrap());
    }

    #[test]
    fn restrict_matches_eval(p in bernstein_poly(vec![2, 3], 20), a in 0i64..6, w in 1i64..6, s in point(2)) {
        let b = vec![(q(a, 12), q(a + w, 12)), (q(w, 12), q(12, 12))];
        let sub = p.restrict(&b).unwrap();
        let x: Vec<Rational> = s.iter().zip(&b).map(|(t, (lo, hi))| lo + t * (hi - lo)).collect();
        prop_assert_eq!(sub.eval(&s).unwrap(), p.eval(&x).unwrap());
    }

    /// `on_box` on boxes reaching past the unit box on either side (or lying wholly outside
    /// it, or ending at 1) is the polynomial there, exactly, and `restrict` inside.
    #[test]
    fn on_box_extends_beyond_the_unit_box(p in bernstein_poly(vec![2, 3], 20), a in -13i64..13, w in 1i64..14, c in 0i64..6, s in point(2)) {
        let b = vec![(q(a, 12), q(a + w, 12)), (q(c, 12), q(12, 12))];
        let sub = p.on_box(&b).unwrap();
        let x: Vec<Rational> = s.iter().zip(&b).map(|(t, (lo, hi))| lo + t * (hi - lo)).collect();
        prop_assert_eq!(sub.eval(&s).unwrap(), p.eval(&x).unwrap());
        if a >= 0 && a + w <= 12 {
            prop_assert_eq!(&sub, &p.restrict(&b).unwrap());
        }
        let one = vec![(q(1, 1), q(12 + w, 12)), (q(-w, 12), q(0, 1))];
        let x: Vec<Rational> = s.iter().zip(&one).map(|(t, (lo, hi))| lo + t * (hi - lo)).collect();
        prop_assert_eq!(p.on_box(&one).unwrap().eval(&s).unwrap(), p.eval(&x).unwrap());
        prop_assert!(p.on_box(&[(q(1, 2), q(1, 2)), (q(0, 1), q(1, 1))]).is_err());
    }

    #[test]
    fn elevation_preserves(p in bernstein_poly(vec![2, 1], 20), by in 1usize..4, s in point(2)) {
        let e = p.elevate(1, by).unwrap().elevate(0, 1).unwrap();
        prop_assert_eq!(e.eval(&s).unwrap(), p.eval(&s).unwrap());
    }

    /// `at_exact_degrees` (top differences and inverted elevation) gives back a polynomial
    /// elevated along each axis, at its exact degrees as the power basis reads them (the
    /// highest power present), and a lower-degree term dropped to zero is trimmed too.
    #[test]
    fn exact_degrees_undo_elevation(p in bernstein_poly(vec![2, 1, 3], 20), by in 0usize..3, axis in 0usize..3, s in point(3)) {
        let e = p.elevate(axis, by).unwrap().elevate((axis + 1) % 3, 1).unwrap();
        let back = e.at_exact_degrees();
        let power = p.to_power();
        let mut exact = vec![0usize; 3];
        for (flat, c) in power.iter().enumerate() {
            if !c.is_zero() {
                let idx = [flat % 3, flat / 3 % 2, flat / 6];
                for k in 0..3 {
                    exact[k] = exact[k].max(idx[k]);
                }
            }
        }
        prop_assert_eq!(back.degrees(), &exact[..]);
        prop_assert_eq!(back.eval(&s).unwrap(), p.eval(&s).unwrap());
        if exact == [2, 1, 3] {
            prop_assert_eq!(&back, &p);
        }
    }

    #[test]
    fn power_basis_round_trip_and_derivative(p in bernstein_poly(vec![4], 20)) {
        let power = p.to_power();
        let back = Bernstein::from_power(vec![4], power.clone()).unwrap();
        prop_assert_eq!(&back, &p);
        // d/dt Σ a_j t^j = Σ j a_j t^{j-1}
        let dpow: Vec<Rational> = (1..power.len()).map(|j| &power[j] * Rational::from_integer(BigInt::from(j))).collect();
        prop_assert_eq!(p.derivative(0).unwrap().to_power(), dpow);
    }

    #[test]
    fn product_evaluates_to_product(a in bernstein_poly(vec![2, 1], 10), b in bernstein_poly(vec![1, 3], 10), s in point(2)) {
        let c = a.product(&b).unwrap();
        prop_assert_eq!(c.eval(&s).unwrap(), a.eval(&s).unwrap() * b.eval(&s).unwrap());
    }

    /// A univariate factor `c(x_k)` multiplied into a random polynomial: when `c` keeps one
    /// strict sign on `[0, 1]` (`c = x² + a x + b` with `b > 0`, `1 + a + b > 0` and no root
    /// between), `without_signed_contents` removes at least its degrees along `k`, the
    /// reduced polynomial times the factors it reports is the product times one positive
    /// constant, and nothing signed is left to remove.
    #[test]
    fn signed_univariate_factors_divide_out(p in bernstein_poly(vec![2, 1, 2], 10), a in -3i64..4, b in 1i64..5, axis in 0usize..3, s in point(3)) {
        // x² + a x + b has a root in [0, 1] only when a² ≥ 4b and the vertex −a/2 or an end
        // value says so: decided exactly by the end values and the minimum inside.
        let (af, bf) = (a as f64, b as f64);
        let vertex = -af / 2.0;
        let min_inside = if (0.0..=1.0).contains(&vertex) { bf - af * af / 4.0 } else { f64::INFINITY };
        prop_assume!(1.0 + af + bf > 0.0 && min_inside > 0.0);
        prop_assume!(p.coeffs().iter().any(|c| !c.is_zero()));
        let mut degrees = vec![0, 0, 0];
        degrees[axis] = 2;
        let mut power = vec![Rational::from_integer(BigInt::from(0)); 3];
        power[0] = Rational::from_integer(BigInt::from(b));
        power[1] = Rational::from_integer(BigInt::from(a));
        power[2] = Rational::from_integer(BigInt::from(1));
        let c = Bernstein::from_power(degrees, power).unwrap();
        let product = c.product(&p).unwrap();
        let (reduced, divided) = product.without_signed_contents().unwrap();
        prop_assert!(reduced.degrees()[axis] + 2 <= product.degrees()[axis]);
        let mut value = reduced.eval(&s).unwrap();
        for (k, f) in &divided {
            value *= f.iter().rev().fold(Rational::from_integer(BigInt::from(0)), |acc, fi| acc * &s[*k] + fi);
        }
        let original = product.eval(&s).unwrap();
        if original.is_zero() {
            prop_assert!(value.is_zero());
        } else {
            // The constant: the same at a second point, and positive.
            let k = &value / &original;
            prop_assert!(k.is_positive());
            let t: Vec<Rational> = s.iter().map(|x| (x + q(1, 3)) / q(2, 1)).collect();
            let (v2, o2) = (reduced.eval(&t).unwrap(), product.eval(&t).unwrap());
            let mut v2 = v2;
            for (kk, f) in &divided {
                v2 *= f.iter().rev().fold(Rational::from_integer(BigInt::from(0)), |acc, fi| acc * &t[*kk] + fi);
            }
            prop_assert_eq!(v2, o2 * k);
        }
        prop_assert!(reduced.without_signed_contents().unwrap().1.is_empty());
    }

    #[test]
    fn faces_are_slices(p in bernstein_poly(vec![2, 3], 20), s in point(1), upper in any::<bool>()) {
        let f = p.face(0, upper).unwrap();
        let t = if upper { q(1, 1) } else { q(0, 1) };
        prop_assert_eq!(f.eval(&s).unwrap(), p.eval(&[t, s[0].clone()]).unwrap());
    }

    #[test]
    fn scaled_split_is_exact(p in bernstein_poly(vec![3, 2], 20), num in 1i64..7, axis in 0usize..2) {
        let sp = ScaledBernstein::from_rational(&p);
        let (l, r) = sp.split_half(axis).unwrap();
        let (el, er) = p.split(axis, &q(1, 2)).unwrap();
        prop_assert_eq!(l.to_rational(), el);
        prop_assert_eq!(r.to_rational(), er);
        let (l, r) = sp.split(axis, &BigInt::from(num), &BigInt::from(7)).unwrap();
        let (el, er) = p.split(axis, &q(num, 7)).unwrap();
        prop_assert_eq!(l.to_rational(), el);
        prop_assert_eq!(r.to_rational(), er);
    }

    #[test]
    fn fast_split_within_bound_and_signs_certified(p in bernstein_poly(vec![5, 3], 20), axis in 0usize..2, depth in 1usize..6) {
        let mut f = FastBernstein::from_rational(&p).unwrap();
        let mut e = p.clone();
        for _ in 0..depth {
            let (mut l, mut r) = (f.buffer_like(), f.buffer_like());
            f.split_half_into(axis, &mut l, &mut r);
            f = r;
            e = e.split(axis, &q(1, 2)).unwrap().1;
        }
        let err = rational_from_f64(f.err(), "err").unwrap();
        for (k, (c, x)) in f.coeffs().iter().zip(e.coeffs()).enumerate() {
            let c = rational_from_f64(*c, "c").unwrap();
            prop_assert!((&c - x).abs() <= err);
            let s = f.coeff_sign(k);
            prop_assert!(!s.contradicts(x.sign()), "certified {:?} vs exact {:?}", s, x.sign());
        }
    }

    #[test]
    fn fast_product_within_bound(a in bernstein_poly(vec![2, 3], 10), b in bernstein_poly(vec![3, 3], 10)) {
        let fa = FastBernstein::from_rational(&a).unwrap();
        let fb = FastBernstein::from_rational(&b).unwrap();
        let fc = fa.product(&fb).unwrap();
        let c = a.product(&b).unwrap();
        let err = rational_from_f64(fc.err(), "err").unwrap();
        for (x, y) in fc.coeffs().iter().zip(c.coeffs()) {
            prop_assert!((rational_from_f64(*x, "x").unwrap() - y).abs() <= err);
        }
    }

    #[test]
    fn positivity_routes_agree_and_certify(p in bernstein_poly(vec![2, 2], 12), shift in 0i64..12) {
        // Shift up so that roughly half the cases are positive.
        let p = p.map(|c| c + q(shift, 2));
        let limits = Limits::new().with_max_depth(8);
        let exact = prove_positive_exact(&p, limits);
        let fast = prove_positive_fast(&FastBernstein::from_rational(&p).unwrap(), limits);
        let filtered = prove_positive_filtered(&p, limits);
        check_verdict(&p, &exact)?;
        check_verdict(&p, &filtered)?;
        let class = |v: &PositivityVerdict| match v {
            PositivityVerdict::Positive { .. } => Sign::Positive,
            PositivityVerdict::NotPositive { .. } => Sign::Negative,
            _ => Sign::Uncertain,
        };
        // Certified verdicts never contradict each other.
        prop_assert!(!class(&fast).contradicts(class(&exact)) || class(&exact) == Sign::Uncertain);
        prop_assert!(!class(&filtered).contradicts(class(&exact)) || class(&exact) == Sign::Uncertain);
        if let PositivityVerdict::Positive { leaves, .. } = &fast {
            prop_assert!(verify_positive_certificate(&p, leaves).is_ok());
        }
        if let PositivityVerdict::NotPositive { witness, value: WitnessValue::AtMost(b) } = &fast {
            let v = verify_witness(&p, witness, None);
            prop_assert!(v.is_ok());
            prop_assert!(v.unwrap() <= rational_from_f64(*b, "b").unwrap());
        }
    }

    #[test]
    fn knot_insertion_preserves(s in spline(4), x in (1i64..11).prop_map(|n| q(n, 11)), y in point(1)) {
        let b = s.insert_knot(&x).unwrap();
        prop_assert_eq!(b.eval(&y[0]).unwrap(), s.eval(&y[0]).unwrap());
        let o = s.insert_knots(&[x.clone(), q(1, 5), x.clone()]).unwrap();
        prop_assert_eq!(o.eval(&y[0]).unwrap(), s.eval(&y[0]).unwrap());
        // Oslo equals repeated Boehm on every B-spline with non-empty support (a degree-0
        // B-spline on a repeated knot is identically zero and its coefficient is arbitrary).
        let mut bb = s.clone();
        for k in [x.clone(), q(1, 5), x.clone()] {
            bb = bb.insert_knot(&k).unwrap();
        }
        prop_assert_eq!(o.knots(), bb.knots());
        let p = o.degree();
        for j in 0..o.coeffs().len() {
            if o.knots()[j] < o.knots()[j + p + 1] {
                prop_assert_eq!(&o.coeffs()[j], &bb.coeffs()[j]);
            }
        }
    }

    #[test]
    fn bezier_routes_agree(s in spline(4), y in (1i64..12).prop_map(|n| vec![q(n, 12)])) {
        // Interior points of each piece: a degree-0 spline jumps at its breakpoints.
        let a = s.bezier_pieces();
        let b = s.bezier_pieces_by_insertion().unwrap();
        prop_assert_eq!(&a, &b);
        for (lo, hi, ctrl) in &a {
            let x = lo + &y[0] * (hi - lo);
            let p = Bernstein::new(vec![s.degree()], ctrl.clone()).unwrap();
            prop_assert_eq!(p.eval(&y).unwrap(), s.eval(&x).unwrap());
        }
    }

    /// The Bézier matrix (blossom weights, computed once per span and box) applied to the
    /// span's coefficients gives the blossom route's Bézier coefficients on any sub-interval,
    /// exactly; the integer dot product equals the term-by-term rational sum.
    #[test]
    fn bezier_matrix_is_the_blossom(s in spline(4), a in 0i64..12, b in 0i64..12) {
        let p = s.degree();
        let (a, b) = (a.min(b), a.max(b));
        for mu in s.spans() {
            let (k0, k1) = (&s.knots()[mu], &s.knots()[mu + 1]);
            let lo = k0 + (k1 - k0) * q(a, 11);
            let hi = k0 + (k1 - k0) * q(b, 11);
            let c = &s.coeffs()[mu - p..=mu];
            let want = s.bezier_on(mu, &lo, &hi);
            for (row, w) in s.bezier_matrix(mu, &lo, &hi).iter().zip(&want) {
                prop_assert_eq!(&Rational::dot(row, c), w);
                let sum = row.iter().zip(c).fold(q(0, 1), |t, (x, y)| t + x * y);
                prop_assert_eq!(&sum, w);
            }
        }
    }

    #[test]
    fn spline_derivative_matches_bezier_derivative(s in spline(4), y in (1i64..12).prop_map(|n| vec![q(n, 12)])) {
        // Interior points only: at a breakpoint the derivative may jump.
        let d = s.derivative();
        for (lo, hi, ctrl) in s.bezier_pieces() {
            let p = Bernstein::new(vec![s.degree()], ctrl).unwrap().derivative(0).unwrap();
            let x = &lo + &y[0] * (&hi - &lo);
            // Chain rule: d/dx = (1/(hi−lo)) d/dt.
            let want = p.eval(&y).unwrap() / (&hi - &lo);
            prop_assert_eq!(d.eval(&x).unwrap(), want);
        }
    }

    #[test]
    fn morken_product_is_exact(f in spline(3), g in spline(3), h in spline(2), y in point(1)) {
        let prod = morken_product(&[&f, &g, &h]).unwrap();
        let x = &y[0];
        prop_assert_eq!(prod.eval(x).unwrap(), f.eval(x).unwrap() * g.eval(x).unwrap() * h.eval(x).unwrap());
        // Route B: per interval, Bernstein products of the factors' Bézier pieces.
        for (lo, hi, ctrl) in prod.bezier_pieces() {
            let piece = |s: &Spline<Rational>| {
                let mu = s.find_span(&lo).unwrap();
                Bernstein::new(vec![s.degree()], s.bezier_on(mu, &lo, &hi)).unwrap()
            };
            let b = piece(&f).product(&piece(&g)).unwrap().product(&piece(&h)).unwrap();
            prop_assert_eq!(b.coeffs(), &ctrl[..]);
        }
    }
}

fn check_verdict(p: &Bernstein<Rational>, v: &PositivityVerdict) -> Result<(), TestCaseError> {
    match v {
        PositivityVerdict::Positive { leaves, .. } => {
            prop_assert!(
                verify_positive_certificate(p, leaves).is_ok(),
                "certificate refused"
            );
        }
        PositivityVerdict::NotPositive { witness, value } => {
            let claimed = match value {
                WitnessValue::Exact(r) => Some(r),
                WitnessValue::AtMost(_) => None,
            };
            prop_assert!(
                verify_witness(p, witness, claimed).is_ok(),
                "witness refused"
            );
        }
        PositivityVerdict::Undecided { .. } => {}
        PositivityVerdict::Uncertain { .. } => {
            prop_assert!(false, "exact routes are never uncertain")
        }
    }
    Ok(())
}

#[test]
fn positive_and_negative_examples() {
    // (t − ½)² + 1/1000 > 0 — needs subdivision; (t − ½)² touches zero at ½ — not positive.
    let sq = Bernstein::from_power(vec![2], vec![q(1, 4), q(-1, 1), q(1, 1)]).unwrap();
    let eps = Bernstein::constant(vec![2], q(1, 1000));
    let pos = sq.add(&eps).unwrap();
    match prove_positive_exact(&pos, Limits::default()) {
        PositivityVerdict::Positive { leaves, .. } => {
            assert!(leaves.len() > 1);
            assert_eq!(verify_positive_certificate(&pos, &leaves), Ok(leaves.len()));
        }
        other => panic!("expected positive, got {other:?}"),
    }
    match prove_positive_exact(&sq, Limits::default()) {
        PositivityVerdict::NotPositive { witness, value } => {
            assert_eq!(witness, vec![q(1, 2)]);
            assert_eq!(value, WitnessValue::Exact(q(0, 1)));
        }
        other => panic!("expected a witness, got {other:?}"),
    }
    // A certificate with a missing leaf is refused.
    if let PositivityVerdict::Positive { mut leaves, .. } =
        prove_positive_exact(&pos, Limits::default())
    {
        leaves.pop();
        assert!(verify_positive_certificate(&pos, &leaves).is_err());
    }
}

proptest! {
    /// The integer product (i64, i128, split 256-bit and BigInt routes) equals the rational one,
    /// for coefficients scaled by 2^0…2^150 so every route is taken.
    #[test]
    fn scaled_product_is_exact(
        a in bernstein_poly(vec![2, 1, 3], 20),
        b in bernstein_poly(vec![3, 2, 1], 20),
        sa in 0u32..150,
        sb in 0u32..80,
    ) {
        let big = |p: &Bernstein<Rational>, s: u32| {
            let k = Rational::from_integer(BigInt::from(1) << s) + q(1, 3);
            p.scale(&k)
        };
        let (a, b) = (big(&a, sa), big(&b, sb));
        let exact = a.product(&b).unwrap();
        let scaled = ScaledBernstein::from_rational(&a)
            .product(&ScaledBernstein::from_rational(&b))
            .unwrap();
        prop_assert_eq!(scaled.to_rational(), exact);
    }
}

/// A bivariate tensor spline whose axes carry the knots of two random univariate splines and
/// whose coefficients are scaled by `2^s + 1/3` (so both the `i128` and the `BigInt` routes of
/// the integer kernels are taken).
fn tensor_of(
    f: &Spline<Rational>,
    g: &Spline<Rational>,
    s: u32,
    seed: i64,
) -> TensorSpline<Rational> {
    let n = f.coeffs().len() * g.coeffs().len();
    let k = Rational::from_integer(BigInt::from(1) << s) + q(1, 3);
    let coeffs = (0..n as i64)
        .map(|i| q((i * 7 + seed) % 23 - 11, 1 + (i + seed).rem_euclid(5)) * &k)
        .collect();
    TensorSpline::new(
        vec![f.degree(), g.degree()],
        vec![f.knots().to_vec(), g.knots().to_vec()],
        coeffs,
    )
    .unwrap()
}

proptest! {
    /// The integer Mørken product (memoised tables, `i128` with a `BigInt` fallback) equals the
    /// generic rational product, and the integer Oslo map gives the same Bézier cells as knot
    /// insertion line by line; a field restricted to a plane keeps its values there.
    #[test]
    fn integer_spline_kernels_are_exact(
        f in spline(3), g in spline(3), h in spline(2), k in spline(2),
        s in 0u32..120, t in 0u32..60, seed in 0i64..50,
    ) {
        let a = tensor_of(&f, &g, s, seed);
        let b = tensor_of(&h, &k, t, seed + 1);
        let p = a.product_exact(&b).unwrap();
        prop_assert_eq!(&p, &a.product(&b).unwrap());
        for x in [&a, &p] {
            let fast = x.bezier_cells_by_insertion_exact().unwrap();
            let slow = x.bezier_cells_by_insertion().unwrap();
            prop_assert_eq!(fast.len(), slow.len());
            for (c, d) in fast.iter().zip(&slow) {
                prop_assert_eq!(&c.bounds, &d.bounds);
                prop_assert_eq!(&c.spans, &d.spans);
                prop_assert_eq!(&c.poly, &d.poly);
                // The per-box route (one Bézier matrix per axis) on the same cell.
                prop_assert_eq!(&x.bezier_on_box(&c.bounds).unwrap(), &c.poly);
                prop_assert_eq!(&x.bezier_on_box_exact(&c.bounds).unwrap(), &c.poly);
                // A sub-box (a third to a half of the cell per axis) and a flat one.
                let part: Vec<(Rational, Rational)> = c
                    .bounds
                    .iter()
                    .map(|(lo, hi)| (lo + (hi - lo) * q(1, 3), lo + (hi - lo) * q(1, 2)))
                    .collect();
                prop_assert_eq!(
                    x.bezier_on_box_exact(&part).unwrap(),
                    x.bezier_on_box(&part).unwrap()
                );
                let mut flat = part.clone();
                flat[0].1 = flat[0].0.clone();
                prop_assert_eq!(
                    x.bezier_on_box_exact(&flat).unwrap(),
                    x.bezier_on_box(&flat).unwrap()
                );
                // The field on a plane (through the cell's lower corner, a knot, and through
                // the sub-box) has the field's values there.
                for axis in 0..2 {
                    for at in [&c.bounds[axis].0, &part[axis].0] {
                        let plane = x.restrict_axis(axis, at).unwrap();
                        let other = &part[1 - axis].1;
                        let mut point = vec![other.clone(); 2];
                        point[axis] = at.clone();
                        prop_assert_eq!(
                            plane.eval(std::slice::from_ref(other)).unwrap(),
                            x.eval(&point).unwrap()
                        );
                    }
                }
            }
        }
    }
}

proptest! {
    /// Products, sums and differences over one denominator ([`ScaledSpline`], the Jacobian's
    /// Mørken route) equal the generic rational ones: `a·b − c·d + a·d`, the factors sharing a
    /// denominator or not.
    #[test]
    fn scaled_spline_expressions_are_exact(
        f in spline(3), g in spline(2), h in spline(2), k in spline(3),
        s in 0u32..80, seed in 0i64..50,
    ) {
        let a = tensor_of(&f, &g, s, seed);
        let c = tensor_of(&f, &g, 0, seed + 2);
        let b = tensor_of(&h, &k, s / 2, seed + 1);
        let d = tensor_of(&h, &k, 3, seed + 3);
        let want = a
            .product(&b)
            .unwrap()
            .sub(&c.product(&d).unwrap())
            .unwrap()
            .add(&a.product(&d).unwrap())
            .unwrap();
        let mut cache = TableCache::default();
        let [sa, sc] = ScaledSpline::common(&[&a, &c]).try_into().unwrap();
        let [sb, sd] = ScaledSpline::common(&[&b, &d]).try_into().unwrap();
        let lone_d = &ScaledSpline::common(&[&d])[0];
        let got = sa
            .product(&sb, &mut cache)
            .unwrap()
            .sub(&sc.product(&sd, &mut cache).unwrap())
            .unwrap()
            .add(&sa.product(lone_d, &mut cache).unwrap())
            .unwrap();
        prop_assert_eq!(got.to_rational().unwrap(), want.clone());
        // Bézier extraction in integers equals the rational route, cell by cell.
        let cells: Vec<Bernstein<Rational>> =
            got.bezier_cells().unwrap().iter().map(ScaledBernstein::to_rational).collect();
        let exact: Vec<Bernstein<Rational>> =
            want.bezier_cells_by_insertion_exact().unwrap().into_iter().map(|c| c.poly).collect();
        prop_assert_eq!(cells, exact);
        prop_assert!(sa.add(&sb).is_err() || f.knots() == h.knots() && g.knots() == k.knots());
    }
}

proptest! {
    /// The certificate checker's tree walk (integer midpoint subdivision) decides every leaf as
    /// restricting the polynomial to it with the generic rational kernel does: a certificate of
    /// `p + s` is checked against `p + t` for other shifts `t`, so some leaves fail.
    #[test]
    fn certificate_checker_agrees_with_leafwise_restriction(
        p in bernstein_poly(vec![3, 2], 12),
        s in 2i64..14,
        t in -4i64..14,
    ) {
        let certified = p.map(|c| c + q(s, 2));
        let PositivityVerdict::Positive { leaves, .. } =
            prove_positive_exact(&certified, Limits::new().with_max_depth(7))
        else {
            return Ok(());
        };
        let other = p.map(|c| c + q(t, 2));
        let failing: Vec<usize> = leaves
            .iter()
            .enumerate()
            .filter(|(_, l)| {
                other
                    .restrict(&l.bounds())
                    .unwrap()
                    .coeffs()
                    .iter()
                    .any(|c| c.sign() != Sign::Positive)
            })
            .map(|(i, _)| i)
            .collect();
        // The integer entry point decides the same, on numerators with a common factor left in.
        let reduced = ScaledBernstein::from_rational(&other);
        let unreduced = ScaledBernstein::with_denominator(
            reduced.degrees().to_vec(),
            reduced.numerators().iter().map(|v| v * 3).collect(),
            reduced.denominator() * 3,
        )
        .unwrap();
        prop_assert_eq!(
            verify_positive_certificate_scaled(&unreduced, &leaves),
            verify_positive_certificate(&other, &leaves)
        );
        match verify_positive_certificate(&other, &leaves) {
            Ok(n) => prop_assert!(failing.is_empty() && n == leaves.len()),
            Err(CertificateError::NotPositiveLeaf { index, .. }) => {
                prop_assert!(failing.contains(&index), "leaf {} reported, failing {:?}", index, failing)
            }
            Err(e) => prop_assert!(false, "unexpected refusal {:?}", e),
        }
    }
}
