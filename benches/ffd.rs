//! FFD injectivity on tricubic Bézier cells perturbed from the identity (amplitudes 5–30 % of
//! the cell): the N&S test on each path, the conic-hull and phi tests. Gmsh's `minDetJac` on
//! the same cells is measured side by side by `geocert prove` (reports/ffd.md).
#![allow(missing_docs)] // criterion's group and main macros generate undocumented items

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use geocert::bernstein::Limits;
use geocert::ffd::{check_injectivity, Basis, CheckOptions};
use geocert::ffd::{conic_test_fast, phi_test_fast, ConicOptions, Scope};
use geocert::internals::report::ffd::perturbed_lattices;
use std::hint::black_box;

fn cells(c: &mut Criterion) {
    let lattices = perturbed_lattices(2026, 60, Basis::Bezier, [4, 4, 4], [1, 1, 1]);
    let limits = Limits::new().with_max_depth(10).with_max_boxes(20_000);
    let mut g = c.benchmark_group("tricubic_cells_x60");
    g.throughput(Throughput::Elements(lattices.len() as u64));
    g.sample_size(10);
    for path in [
        geocert::Path::Filtered,
        geocert::Path::Fast,
        geocert::Path::Exact,
    ] {
        g.bench_function(format!("ns_{}", path.name()), |b| {
            b.iter(|| {
                for l in &lattices {
                    black_box(
                        check_injectivity(
                            l,
                            CheckOptions::new().with_path(path).with_limits(limits),
                        )
                        .ok(),
                    );
                }
            })
        });
    }
    g.bench_function("conic_f64", |b| {
        b.iter(|| {
            for l in &lattices {
                black_box(conic_test_fast(l, ConicOptions::default()));
            }
        })
    });
    g.bench_function("phi_f64", |b| {
        b.iter(|| {
            for l in &lattices {
                black_box(phi_test_fast(l, Scope::PerCell));
            }
        })
    });
    g.finish();
}

criterion_group!(benches, cells);
criterion_main!(benches);
