//! Diamond hierarchies: building Δf (every diamond's certified error and range) and selective
//! refinement (Table 4's query) on the three encodings with the two fronts, on the built-in
//! gyroid at 65³ and 129³.
#![allow(missing_docs)] // criterion's group and main macros generate undocumented items

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use geocert::diamond::{
    builtin_volume, DiamondFront, DmvAccess, Front, FullDmv, Lod, Refiner, SupercubeFront,
};
use std::hint::black_box;

fn visited<A: DmvAccess<3>, F: Front<3>>(dmv: &A, lod: &Lod<3>) -> u64 {
    let mut r: Refiner<'_, 3, A, F> = Refiner::new(dmv);
    r.refine(lod).expect("closed DMV");
    r.visited
}

fn diamonds(c: &mut Criterion) {
    let mut g = c.benchmark_group("dmv_build");
    g.sample_size(10);
    for side in [65, 129] {
        let field = builtin_volume("gyroid", side).unwrap();
        g.throughput(Throughput::Elements(field.values().len() as u64));
        g.bench_function(format!("gyroid_{side}"), |b| {
            b.iter(|| FullDmv::build(black_box(field.clone())))
        });
    }
    g.finish();
    let full = FullDmv::build(builtin_volume("gyroid", 129).unwrap());
    let lod = Lod {
        error: Some(2.55),
        isovalues: vec![128.0],
        roi: None,
    };
    let sel = full.select_by_isovalues(&[128.0]);
    let ds = full.supercube_encoding(&sel);
    let dd = full.diamond_encoding(&sel);
    let n = visited::<_, DiamondFront<3>>(&full, &lod);
    let mut g = c.benchmark_group("dmv_refine_gyroid_129");
    g.sample_size(10);
    g.throughput(Throughput::Elements(n));
    g.bench_function("full_diamond_front", |b| {
        b.iter(|| visited::<_, DiamondFront<3>>(black_box(&full), &lod))
    });
    g.bench_function("full_supercube_front", |b| {
        b.iter(|| visited::<_, SupercubeFront<3>>(black_box(&full), &lod))
    });
    g.bench_function("diamond_dmv_diamond_front", |b| {
        b.iter(|| visited::<_, DiamondFront<3>>(black_box(&dd), &lod))
    });
    g.bench_function("supercube_dmv_supercube_front", |b| {
        b.iter(|| visited::<_, SupercubeFront<3>>(black_box(&ds), &lod))
    });
    g.finish();
}

criterion_group!(benches, diamonds);
criterion_main!(benches);
