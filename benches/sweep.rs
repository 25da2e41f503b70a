//! Swept-volume silhouettes of the built-in scenes on the filtered path: the whole of
//! Algorithm 1 (equations, tracing, certified t-extreme points, the end positions' contours)
//! per scene, the equations alone, the moving eye's certified events (Section 4) with
//! the options the CLI and the report use, and the frames continued between events
//! (Section 4.2: the time of the continuation alone, per 99 frames).
#![allow(missing_docs)] // criterion's group and main macros generate undocumented items

use criterion::{criterion_group, criterion_main, Criterion};
use geocert::bernstein::Limits;
use geocert::solve::SolveOptions;
use geocert::sweep::{
    builtin_scene, equations, events, frames, silhouette, Eye, SilhouetteOptions, EVENT_TOLERANCE,
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

/// 100 frames of the turning ellipsoid between its events (`r` from 1.55 to 1.64; the
/// interior event lies near 1.66): the first is traced, the other 99 are continued from the
/// frame before. Each iteration reports the continuation's own time (`continued_seconds`:
/// the events and the traced frame are not counted), so the figure is per 99 frames.
fn continued_frames(c: &mut Criterion) {
    let scene = builtin_scene("ellipsoid-turn-eye").unwrap();
    let opts = SolveOptions::new()
        .with_limits(Limits::new().with_max_depth(40).with_max_boxes(200_000))
        .with_tolerance(EVENT_TOLERANCE);
    let rs: Vec<f64> = (0..100).map(|k| 1.55 + 0.09 * k as f64 / 99.0).collect();
    let mut g = c.benchmark_group("sweep_frames");
    g.sample_size(10)
        .sampling_mode(criterion::SamplingMode::Flat)
        .warm_up_time(std::time::Duration::from_millis(500))
        .measurement_time(std::time::Duration::from_secs(2));
    g.bench_function("ellipsoid-turn-eye_99_continued", |b| {
        b.iter_custom(|iters| {
            let mut total = std::time::Duration::ZERO;
            for _ in 0..iters {
                let f = frames(&scene, &rs, &SilhouetteOptions::default(), &opts).unwrap();
                assert!(f.frames.iter().skip(1).all(|x| !x.traced));
                total += std::time::Duration::from_secs_f64(f.continued_seconds);
            }
            total
        })
    });
    g.finish();
}

criterion_group!(benches, scenes, moving_eye, continued_frames);
criterion_main!(benches);
