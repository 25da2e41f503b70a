//! Exhaustive proofs about the numeric, Bernstein and B-spline kernel.

use super::{Lcg, ProofOutcome, Shard, Tally};
use crate::bernstein::positivity::{verify_witness, WitnessValue};
use crate::bernstein::{
    prove_positive_exact, prove_positive_fast, prove_positive_filtered,
    verify_positive_certificate, Bernstein, FastBernstein, Limits, PositivityVerdict,
};
use crate::bspline::{morken_product, Spline, TensorSpline};
use crate::num::{rational_from_f64, rational_to_f64, Rational, Sign};
use num_bigint::BigInt;
use num_traits::One;

fn q(n: i64, d: i64) -> Rational {
    Rational::new(BigInt::from(n), BigInt::from(d))
}

/// Every exponent field 0…2046, eight mantissa patterns, both signs: `f64 → Rational → f64` is
/// the identity, and the midpoint between each value and its successor rounds to the neighbour
/// with the even significand (ties-to-even, i.e. correct rounding at the hardest points).
pub fn f64_round_trip(shard: Shard) -> ProofOutcome {
    let mut t = Tally::new(
        "kernel.f64-rational-round-trip",
        "2047 exponent fields × 8 mantissa patterns × 2 signs: round trip, and ties at each successor midpoint",
        shard,
    );
    if !t.owns(0) {
        return t.finish();
    }
    let mantissas = [
        0u64,
        1,
        2,
        3,
        1 << 51,
        (1 << 52) - 1,
        (1 << 52) - 2,
        0x5555_5555_5555,
    ];
    for e in 0u64..2047 {
        for &m in &mantissas {
            for sign in [0u64, 1] {
                let x = f64::from_bits(sign << 63 | e << 52 | m);
                let r = rational_from_f64(x, "x").expect("finite");
                let back = rational_to_f64(&r);
                t.check(back == x || (x == 0.0 && back == 0.0), || {
                    format!("{x:e} came back as {back:e}")
                });
                if x > 0.0 && x < f64::MAX {
                    let y = x.next_up();
                    let mid = (&r + rational_from_f64(y, "y").expect("finite")) / q(2, 1);
                    let even = if x.to_bits() & 1 == 0 { x } else { y };
                    let got = rational_to_f64(&mid);
                    t.check(got == even, || {
                        format!("midpoint of {x:e} and its successor rounded to {got:e}")
                    });
                }
            }
        }
    }
    t.finish()
}

/// A clamped spline on [0,1] with interior breakpoints 1/3 and 1/2 of the given multiplicities.
fn clamped(p: usize, m13: usize, m12: usize, rng: &mut Lcg) -> Spline<Rational> {
    let mut knots = vec![q(0, 1); p + 1];
    knots.extend(std::iter::repeat_n(q(1, 3), m13));
    knots.extend(std::iter::repeat_n(q(1, 2), m12));
    knots.extend(std::iter::repeat_n(q(1, 1), p + 1));
    let n = knots.len() - p - 1;
    let coeffs = (0..n).map(|_| rng.rational(9, 5)).collect();
    Spline::new(p, knots, coeffs).expect("valid by construction")
}

/// Mørken route (product spline, then Bézier pieces) against the Bernstein route (Bézier pieces
/// of each factor, then Bernstein products), coefficient for coefficient, on every piece.
fn compare_routes(t: &mut Tally, factors: &[&Spline<Rational>], label: &str) {
    let prod = match morken_product(factors) {
        Ok(p) => p,
        Err(e) => {
            t.check(false, || format!("{label}: {e}"));
            return;
        }
    };
    let mut ok = true;
    for (lo, hi, ctrl) in prod.bezier_pieces() {
        let mut acc: Option<Bernstein<Rational>> = None;
        for f in factors {
            let mu = f.find_span(&lo).expect("inside the domain");
            let piece = Bernstein::new(vec![f.degree()], f.bezier_on(mu, &lo, &hi)).expect("count");
            acc = Some(match acc {
                None => piece,
                Some(a) => a.product(&piece).expect("same dimension"),
            });
        }
        ok &= acc.map(|a| a.coeffs() == &ctrl[..]).unwrap_or(false);
    }
    t.check(ok, || format!("{label}: routes differ"));
}

/// Products of two clamped splines of degrees 0…3 with every multiplicity pattern of the
/// breakpoints 1/3 and 1/2 (0…degree each), of three splines of degrees 0…2 with every
/// multiplicity of 1/2, and the FFD's uniform (l−2, l−1, l−1) products for orders 2…5.
pub fn morken_vs_bernstein(shard: Shard) -> ProofOutcome {
    let mut t = Tally::new(
        "kernel.morken-vs-bernstein",
        "900 two-factor products (degrees 0–3, all multiplicities of 1/3 and 1/2), 216 three-factor products (degrees 0–2), 12 uniform FFD products (orders 2–5, 1–3 cells): Mørken route = Bernstein route on every piece",
        shard,
    );
    // The factors are drawn in one sequence for every slice; each product is one part.
    let mut rng = Lcg::new(0x6765_6f63);
    let mut part = 0u64;
    let mut next_part = |t: &mut Tally| {
        part += 1;
        t.owns(part - 1)
    };
    for d1 in 0..=3 {
        for d2 in 0..=3 {
            for a1 in 0..=d1 {
                for b1 in 0..=d1 {
                    for a2 in 0..=d2 {
                        for b2 in 0..=d2 {
                            let f = clamped(d1, a1, b1, &mut rng);
                            let g = clamped(d2, a2, b2, &mut rng);
                            if !next_part(&mut t) {
                                continue;
                            }
                            compare_routes(
                                &mut t,
                                &[&f, &g],
                                &format!("deg ({d1},{d2}) mult ({a1},{b1}),({a2},{b2})"),
                            );
                        }
                    }
                }
            }
        }
    }
    for d in 0..27usize {
        let ds = [d % 3, d / 3 % 3, d / 9];
        for m in 0..8usize {
            let ms: Vec<usize> = (0..3).map(|i| (m >> i & 1) * ds[i]).collect();
            // Eight multiplicity patterns per degree triple (0 or full degree per factor).
            let fs: Vec<Spline<Rational>> =
                (0..3).map(|i| clamped(ds[i], 0, ms[i], &mut rng)).collect();
            if !next_part(&mut t) {
                continue;
            }
            compare_routes(
                &mut t,
                &[&fs[0], &fs[1], &fs[2]],
                &format!("deg {ds:?} mult {ms:?}"),
            );
        }
    }
    for order in 2..=5usize {
        for cells in 1..=3usize {
            // A uniform order-l spline with l + cells − 1 coefficients; its derivative has order l−1.
            let l = order;
            let coeffs = |rng: &mut Lcg| {
                (0..l + cells - 1)
                    .map(|_| rng.rational(9, 4))
                    .collect::<Vec<_>>()
            };
            let x = Spline::uniform(l - 1, coeffs(&mut rng)).expect("valid");
            let y = Spline::uniform(l - 1, coeffs(&mut rng)).expect("valid");
            let dx = x.derivative();
            if !next_part(&mut t) {
                continue;
            }
            compare_routes(
                &mut t,
                &[&dx, &x, &y],
                &format!("uniform order {l}, {cells} cells"),
            );
        }
    }
    t.finish()
}

fn classify(v: &PositivityVerdict) -> Sign {
    match v {
        PositivityVerdict::Positive { .. } => Sign::Positive,
        PositivityVerdict::NotPositive { .. } => Sign::Negative,
        _ => Sign::Uncertain,
    }
}

/// Checks one polynomial: the exact verdict's certificate re-verifies, the certified fast verdict
/// never contradicts it, the filtered verdict equals it.
fn check_positivity(t: &mut Tally, p: &Bernstein<Rational>, limits: Limits) {
    let exact = prove_positive_exact(p, limits);
    let cert_ok = match &exact {
        PositivityVerdict::Positive { leaves, .. } => {
            verify_positive_certificate(p, leaves).is_ok()
        }
        PositivityVerdict::NotPositive {
            witness,
            value: WitnessValue::Exact(v),
        } => verify_witness(p, witness, Some(v)).is_ok(),
        PositivityVerdict::Undecided { .. } => true,
        _ => false,
    };
    let fast = FastBernstein::from_rational(p).map(|f| prove_positive_fast(&f, limits));
    let fast_ok = match &fast {
        Ok(v) => !classify(v).contradicts(classify(&exact)) || classify(&exact) == Sign::Uncertain,
        Err(_) => false,
    };
    let filtered = prove_positive_filtered(p, limits);
    let filtered_ok = classify(&filtered) == classify(&exact);
    t.check(cert_ok && fast_ok && filtered_ok, || {
        format!(
            "{:?}: exact {:?}, fast {:?}, filtered {:?}",
            p.coeffs(),
            classify(&exact),
            fast.as_ref().map(classify),
            classify(&filtered)
        )
    });
}

/// All cubics with integer coefficients in [−3,3]⁴, all bilinear patches in [−2,2]⁴, all
/// (2,1) patches in [−1,1]⁶, and all cubics over {−3·2⁻⁵³, 0, 3·2⁻⁵³, 1}⁴ (rounding-hard).
pub fn subdivision_signs(shard: Shard) -> ProofOutcome {
    let mut t = Tally::new(
        "kernel.subdivision-signs",
        "2401 cubics in [−3,3]⁴, 625 bilinear in [−2,2]⁴, 729 (2,1)-patches in [−1,1]⁶, 256 cubics over {−3·2⁻⁵³,0,3·2⁻⁵³,1}⁴: exact certificate re-verifies, fast never contradicts, filtered = exact",
        shard,
    );
    if !t.owns(0) {
        return t.finish();
    }
    let limits = Limits {
        max_depth: 10,
        ..Limits::default()
    };
    let grid = |n: usize, lo: i64, hi: i64| -> Vec<Vec<Rational>> {
        let base = (hi - lo + 1) as usize;
        (0..base.pow(n as u32))
            .map(|mut k| {
                (0..n)
                    .map(|_| {
                        let v = lo + (k % base) as i64;
                        k /= base;
                        q(v, 1)
                    })
                    .collect()
            })
            .collect()
    };
    for c in grid(4, -3, 3) {
        check_positivity(&mut t, &Bernstein::new(vec![3], c).expect("count"), limits);
    }
    for c in grid(4, -2, 2) {
        check_positivity(
            &mut t,
            &Bernstein::new(vec![1, 1], c).expect("count"),
            limits,
        );
    }
    for c in grid(6, -1, 1) {
        check_positivity(
            &mut t,
            &Bernstein::new(vec![2, 1], c).expect("count"),
            limits,
        );
    }
    let tiny = Rational::new(BigInt::from(3), BigInt::one() << 53usize);
    let vals = [-tiny.clone(), q(0, 1), tiny, q(1, 1)];
    for k in 0..256usize {
        let c: Vec<Rational> = (0..4).map(|i| vals[k >> (2 * i) & 3].clone()).collect();
        check_positivity(&mut t, &Bernstein::new(vec![3], c).expect("count"), limits);
    }
    t.finish()
}

/// Uniform trivariate splines of orders 2…4 per axis with 1–2 cells per axis: each Bézier cell
/// evaluates to the spline's value at 27 rational points of the cell (incl. its corners).
pub fn bezier_extraction_routes(shard: Shard) -> ProofOutcome {
    let mut t = Tally::new(
        "kernel.tensor-bezier-cells",
        "27 order triples (2–4) × 8 cell-count triples (1–2): every Bézier cell at 27 points = de Boor value",
        shard,
    );
    for orders in 0..27usize {
        let l = [2 + orders % 3, 2 + orders / 3 % 3, 2 + orders / 9];
        for cells in 0..8usize {
            // One part per shape, with its own generator.
            let part = (orders * 8 + cells) as u64;
            if !t.owns(part) {
                continue;
            }
            let mut rng = Lcg::new(7 + part);
            let c = [1 + (cells & 1), 1 + (cells >> 1 & 1), 1 + (cells >> 2 & 1)];
            let degrees: Vec<usize> = l.iter().map(|o| o - 1).collect();
            let knots: Vec<Vec<Rational>> = (0..3)
                .map(|a| {
                    (0..(l[a] + c[a] - 1) + l[a])
                        .map(|i| q(i as i64, 1))
                        .collect()
                })
                .collect();
            let n: usize = (0..3).map(|a| l[a] + c[a] - 1).product();
            let coeffs = (0..n).map(|_| rng.rational(20, 7)).collect();
            let s = TensorSpline::new(degrees, knots, coeffs).expect("valid");
            let mut ok = true;
            for cell in s.bezier_cells() {
                for k in 0..27usize {
                    let local: Vec<Rational> = (0..3)
                        .map(|a| q((k / 3usize.pow(a as u32) % 3) as i64, 2))
                        .collect();
                    let global: Vec<Rational> = local
                        .iter()
                        .zip(&cell.bounds)
                        .map(|(u, (lo, hi))| lo + u * (hi - lo))
                        .collect();
                    // At a cell's upper face de Boor uses the next span; both sides agree (C⁰ at least
                    // for order ≥ 2), so equality must hold everywhere.
                    ok &= cell.poly.eval(&local).expect("dim") == s.eval(&global).expect("inside");
                }
            }
            t.check(ok, || format!("orders {l:?} cells {c:?}"));
        }
    }
    t.finish()
}
