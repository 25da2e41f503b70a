//! The certified solver on dense random systems (bicubic, biquintic, tricubic: the report's
//! msolve comparison sizes) on the filtered path, and curve tracing (a circle in the plane, a
//! sphere cut by a plane in space). `reports/solve.md` times the same sizes side by side
//! with msolve.
#![allow(missing_docs)] // criterion's group and main macros generate undocumented items

use criterion::{criterion_group, criterion_main, Criterion};
use geocert::solve::{solve, system_from_json, trace, CurveOptions, SolveOptions, System};
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
    g.finish();
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
