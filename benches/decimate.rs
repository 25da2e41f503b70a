//! Node decimation of height grids by 99 % (fast path, error criterion, the defaults) and the
//! full undecimation: a grid that fits in cache (10k nodes) and one that does not (250k).
//! The report's Table 1 and peers table time the 810k-node grid end to end.
#![allow(missing_docs)] // criterion's group and main macros generate undocumented items

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use geocert::decimate::{self, data::height_grid, Options, Stage, Target};
use std::hint::black_box;

fn decimation(c: &mut Criterion) {
    let options = Options::new().with_target(Target::Keep(0.01));
    let mut g = c.benchmark_group("decimate_grid_99pct");
    g.sample_size(10);
    for side in [100, 500] {
        let mesh = height_grid(side);
        g.bench_function(format!("fast_{}", side * side), |b| {
            b.iter(|| black_box(decimate::decimate(&mesh, &options).unwrap()))
        });
    }
    g.finish();

    let mut g = c.benchmark_group("undecimate_grid_99pct");
    g.sample_size(10);
    for side in [100, 500] {
        let mesh = height_grid(side);
        let outcome = decimate::decimate(&mesh, &options).unwrap();
        let stage = Stage::decimated(&outcome.mesh, &outcome.history).unwrap();
        g.bench_function(format!("all_steps_{}", side * side), |b| {
            b.iter_batched(
                || stage.clone(),
                |mut s| {
                    while s.undo(&outcome.history).is_ok() {}
                    black_box(s)
                },
                BatchSize::LargeInput,
            )
        });
    }
    g.finish();
}

criterion_group!(benches, decimation);
criterion_main!(benches);
