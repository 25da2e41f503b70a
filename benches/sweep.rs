//! Swept-volume silhouettes of the built-in scenes on the filtered path: the whole of
//! Algorithm 1 (equations, tracing, certified t-extreme points, the end positions' contours)
//! per scene, the equations alone, and the moving eye's certified events (Section 4) with
//! the options the CLI and the report use.
#![allow(missing_docs)] // criterion's group and main macros generate undocumented items

use criterion::{criterion_group, criterion_main, Criterion};
use geocert::bernstein::Limits;
use geocert::solve::SolveOptions;
use geocert::sweep::{
    builtin_scene, equations, events, silhouette, Eye, SilhouetteOptions, EVENT_TOLERANCE,
};
use std::hint::black_box;

fn scenes(c: &mut Criterion) {
    let mut g = c.benchmark_group("sweep_silhouette");
    g.sample_size(10);
    for name in ["sphere-line", "ellipsoid-line", "ellipsoid-turn"] {
        let scene = builtin_scene(name).unwrap();
        g.bench_function(name, |b| {
            b.iter(|| silhouette(black_box(&scene), &SilhouetteOptions::default()).unwrap())
        });
    }
    g.finish();
    let scene = builtin_scene("ellipsoid-turn").unwrap();
    let Eye::Point(eye) = scene.eye.clone() else {
        unreachable!()
    };
    c.bench_function("sweep_equations_ellipsoid_turn_8_patches", |b| {
        b.iter(|| {
            for p in &scene.surfaces[0].patches {
                black_box(equations(&scene, p, &eye).unwrap());
            }
        })
    });
}

fn moving_eye(c: &mut Criterion) {
    let scene = builtin_scene("ellipsoid-turn-eye").unwrap();
    let opts = SolveOptions::new()
        .with_limits(Limits::new().with_max_depth(40).with_max_boxes(200_000))
        .with_tolerance(EVENT_TOLERANCE);
    let mut g = c.benchmark_group("sweep_events");
    g.sample_size(10);
    g.bench_function("ellipsoid-turn-eye", |b| {
        b.iter(|| events(black_box(&scene), &opts).unwrap())
    });
    g.finish();
}

criterion_group!(benches, scenes, moving_eye);
criterion_main!(benches);
