//! The certified solver on dense random systems (bicubic, biquintic, tricubic: the report's
//! msolve comparison sizes) on the filtered path, a B-spline system with its six roots on
//! knot planes, and curve tracing (a circle in the plane, a sphere cut by a plane in space). `reports/solve.md` times the same sizes side by side
//! with msolve.
#![allow(missing_docs)] // criterion's group and main macros generate undocumented items

use criterion::{criterion_group, criterion_main, Criterion};
use geocert::solve::{
    piecewise_system_from_json, solve, solve_piecewise, system_from_json, trace, CurveOptions,
    SolveOptions, System,
};
use std::hint::black_box;

/// `n` equations with every monomial up to degree `d` in each of `n` unknowns, integer
/// coefficients in [−20, 20] from a fixed seed, on `[−1, 1]ⁿ`.
fn dense(n: usize, d: usize, seed: u64) -> System {
    let mut s = seed | 1;
    let mut int = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s % 41) as i64 - 20
    };
    let count = (d + 1).pow(n as u32);
    let equations: Vec<String> = (0..n)
        .map(|_| {
            let terms: Vec<String> = (0..count)
                .map(|k| {
                    let e: Vec<String> = (0..n)
                        .map(|a| ((k / (d + 1).pow(a as u32)) % (d + 1)).to_string())
                        .collect();
                    format!("[[{}],{}]", e.join(","), int())
                })
                .collect();
            format!("{{\"terms\": [{}]}}", terms.join(","))
        })
        .collect();
    let bx = vec!["[\"-1\",\"1\"]"; n].join(",");
    system_from_json(&format!(
        "{{\"box\": [{bx}], \"equations\": [{}]}}",
        equations.join(",")
    ))
    .expect("well-formed dense system")
}

fn zero_dimensional(c: &mut Criterion) {
    let mut g = c.benchmark_group("solve_filtered");
    g.sample_size(10);
    for (name, n, d) in [("bicubic", 2, 3), ("biquintic", 2, 5), ("tricubic", 3, 3)] {
        let system = dense(n, d, 2026);
        let opts = SolveOptions::new();
        g.bench_function(name, |b| {
            b.iter(|| black_box(solve(&system, &opts).unwrap()))
        });
    }
    // (x − 1/4)(x − 1/2)(x − 3/4) + (y − 1/3)(y − 2/3) and (x − 1/4)(x − 1/2)(x − 3/4) −
    // (y − 1/3)(y − 2/3) as quadratic-by-cubic B-splines with knots at every root coordinate:
    // six roots, each where four cells meet.
    let bspline = piecewise_system_from_json(&knotted_grid()).expect("well-formed");
    let opts = SolveOptions::new();
    g.bench_function("bspline_roots_on_knots", |b| {
        b.iter(|| black_box(solve_piecewise(&bspline, &opts).unwrap()))
    });
    g.finish();
}

/// The system of `bspline_roots_on_knots` in the file format: the polynomials written as
/// clamped B-splines (Bernstein coefficients) with the root coordinates inserted as knots.
fn knotted_grid() -> String {
    use geocert::bernstein::Bernstein;
    use geocert::bspline::TensorSpline;
    use geocert::num::{rational_to_string, Rational};
    let q = |a: i64, b: i64| Rational::new(a.into(), b.into());
    let lin = |k: usize, r: Rational| {
        let mut d = vec![0, 0];
        d[k] = 1;
        Bernstein::new(d, vec![-r.clone(), q(1, 1) - r]).unwrap()
    };
    let one = Bernstein::constant(vec![0, 0], q(1, 1));
    let xs = [q(1, 4), q(1, 2), q(3, 4)];
    let ys = [q(1, 3), q(2, 3)];
    let a = xs
        .iter()
        .fold(one.clone(), |p, r| p.product(&lin(0, r.clone())).unwrap());
    let b = ys
        .iter()
        .fold(one, |p, r| p.product(&lin(1, r.clone())).unwrap());
    let (a, b) = (a.elevate(1, 2).unwrap(), b.elevate(0, 3).unwrap());
    let eqs: Vec<String> = [a.add(&b).unwrap(), a.add(&b.scale(&q(-1, 1))).unwrap()]
        .iter()
        .map(|p| {
            let clamped = |d: usize| {
                let mut k = vec![q(0, 1); d + 1];
                k.extend(vec![q(1, 1); d + 1]);
                k
            };
            let s = TensorSpline::new(vec![3, 2], vec![clamped(3), clamped(2)], p.coeffs().to_vec())
                .and_then(|s| s.insert_knots(0, &xs))
                .and_then(|s| s.insert_knots(1, &ys))
                .unwrap();
            let list = |v: &[Rational]| {
                v.iter()
                    .map(|x| format!("\"{}\"", rational_to_string(x)))
                    .collect::<Vec<_>>()
                    .join(",")
            };
            format!(
                "{{\"bspline\": {{\"orders\": [4, 3], \"knots\": [[{}], [{}]], \"coeffs\": [{}]}}}}",
                list(&s.knots()[0]),
                list(&s.knots()[1]),
                list(s.coeffs())
            )
        })
        .collect();
    format!(
        "{{\"box\": [[\"0\", \"1\"], [\"0\", \"1\"]], \"equations\": [{}]}}",
        eqs.join(",")
    )
}

fn curves(c: &mut Criterion) {
    let mut g = c.benchmark_group("trace_filtered");
    g.sample_size(10);
    let circle = system_from_json(
        r#"{"box": [["-1","1"],["-1","1"]], "equations": [{"terms": [[[2,0],1],[[0,2],1],[[1,0],"-1/3"],[[0,0],"-1/5"]]}]}"#,
    )
    .unwrap();
    let sphere_plane = system_from_json(
        r#"{"box": [["-1","1"],["-1","1"],["-1","1"]], "equations": [
        {"terms": [[[2,0,0],1],[[0,2,0],1],[[0,0,2],1],[[0,0,0],"-1/2"]]},
        {"terms": [[[0,0,1],1],[[1,0,0],"-1/3"],[[0,0,0],"-1/5"]]}]}"#,
    )
    .unwrap();
    let opts = CurveOptions::new();
    g.bench_function("circle", |b| {
        b.iter(|| black_box(trace(&circle, &opts).unwrap()))
    });
    g.bench_function("sphere_cut_by_plane", |b| {
        b.iter(|| black_box(trace(&sphere_plane, &opts).unwrap()))
    });
    g.finish();
}

criterion_group!(benches, zero_dimensional, curves);
criterion_main!(benches);
