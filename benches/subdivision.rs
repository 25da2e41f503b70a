//! Subdivision in the three representations: BigRational, sign-only integers, certified f64.
//!
//! * univariate degree 9, full binary tree of depth 10 (the NOTES.md measurement);
//! * trivariate degree (8,8,8) — the tricubic FFD Jacobian's degree — octree descent to depth 4:
//!   at each of 4 levels one box is split into its 8 octants (7 axis splits), 28 splits in all.
#![allow(missing_docs)] // criterion's group and main macros generate undocumented items

use criterion::{criterion_group, criterion_main, Criterion};
use geocert::bernstein::{Bernstein, FastBernstein, ScaledBernstein};
use geocert::internals::report::campaign::{timing_poly, tree_fast, tree_rational, tree_scaled};
use geocert::num::Rational;
use num_bigint::BigInt;
use std::hint::black_box;

fn univariate(c: &mut Criterion) {
    let p = timing_poly(9);
    let s = ScaledBernstein::from_rational(&p);
    let f = FastBernstein::from_rational(&p).unwrap();
    let mut g = c.benchmark_group("degree9_tree_depth10");
    g.sample_size(10);
    g.bench_function("bigrational", |b| {
        b.iter(|| black_box(tree_rational(&p, 10)))
    });
    g.bench_function("scaled_integers", |b| {
        b.iter(|| black_box(tree_scaled(&s, 10)))
    });
    let mut bufs = Vec::new();
    g.bench_function("certified_f64", |b| {
        b.iter(|| black_box(tree_fast(&f, 10, &mut bufs)))
    });
    g.finish();
}

fn trivariate_poly() -> Bernstein<Rational> {
    let mut x = 99u64;
    let coeffs = (0..729)
        .map(|_| {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            Rational::new(
                BigInt::from((x >> 40) as i64 % 200 - 50),
                BigInt::from(1 + (x >> 20) % 31),
            )
        })
        .collect();
    Bernstein::new(vec![8, 8, 8], coeffs).unwrap()
}

/// Splits into 8 octants; returns them.
fn octants<T, F: Fn(&T, usize) -> (T, T)>(p: T, split: F) -> Vec<T> {
    let mut parts = vec![p];
    for axis in 0..3 {
        parts = parts
            .iter()
            .flat_map(|q| {
                let (l, r) = split(q, axis);
                [l, r]
            })
            .collect();
    }
    parts
}

/// Depth-4 descent: at each level split the current box into 8 and descend into the first.
fn descend<T: Clone, F: Fn(&T, usize) -> (T, T) + Copy>(p: &T, split: F) -> usize {
    let mut cur = p.clone();
    let mut n = 0;
    for _ in 0..4 {
        let kids = octants(cur, split);
        n += kids.len();
        cur = kids[0].clone();
    }
    n
}

fn trivariate(c: &mut Criterion) {
    let p = trivariate_poly();
    let s = ScaledBernstein::from_rational(&p);
    let f = FastBernstein::from_rational(&p).unwrap();
    let half = Rational::new(1.into(), 2.into());
    let mut g = c.benchmark_group("degree888_octree_depth4");
    g.sample_size(10);
    g.bench_function("bigrational", |b| {
        b.iter(|| black_box(descend(&p, |q, a| q.split(a, &half).unwrap())))
    });
    g.bench_function("scaled_integers", |b| {
        b.iter(|| black_box(descend(&s, |q, a| q.split_half(a).unwrap())))
    });
    g.bench_function("certified_f64", |b| {
        b.iter(|| {
            black_box(descend(&f, |q, a| {
                let (mut l, mut r) = (q.buffer_like(), q.buffer_like());
                q.split_half_into(a, &mut l, &mut r);
                (l, r)
            }))
        })
    });
    g.finish();
}

criterion_group!(benches, univariate, trivariate);
criterion_main!(benches);
