//! Marching cubes on curvilinear finite elements, fast path: the heart demo (cubic Hermite ×
//! cubic Hermite × linear Lagrange), a block of tricubic Hermite elements, and a block of
//! trilinear Lagrange elements, each with one element range (one pass) and with the default
//! ranges (all cores). `reports/mc.md` carries the same models' rates from `geocert prove`.
#![allow(missing_docs)] // criterion's group and main macros generate undocumented items

use criterion::{criterion_group, criterion_main, Criterion};
use geocert::mc::fe::{heart, models, polygonise_fast, FeModel, FeOptions};
use std::hint::black_box;

fn fe(c: &mut Criterion) {
    let cases: Vec<(&str, FeModel<f64>, f64, [usize; 3])> = vec![
        ("heart_45x45x25", heart::left_ventricle(), 0.0, [45, 45, 25]),
        (
            "tricubic_ball_512_elements_8x8x8",
            models::hermite_ball(8),
            0.64,
            [8; 3],
        ),
        (
            "trilinear_gyroid_4096_elements_8x8x8",
            models::gyroid_block(16),
            0.1,
            [8; 3],
        ),
    ];
    let mut g = c.benchmark_group("mc_fe_fast");
    g.sample_size(10);
    for (name, m, iso, cells) in &cases {
        for (label, parts) in [("one_range", 1), ("all_cores", 0)] {
            let o = FeOptions::new().with_cells(*cells).with_parts(parts);
            g.bench_function(format!("{name}/{label}"), |b| {
                b.iter(|| black_box(polygonise_fast(m, *iso, &o).expect("built-in model")))
            });
        }
    }
    g.finish();
}

criterion_group!(benches, fe);
criterion_main!(benches);
