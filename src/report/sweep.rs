//! `reports/sweep.md`: the swept-volume silhouettes of the built-in scenes on the filtered and
//! fast paths (components, types, certified t-extreme points re-checked), how far every
//! traced vertex is from the characteristic curve and the contour (measured by finite
//! differences of the surface and the motion, not from the library's F and G), eq. 2 as
//! printed against the cofactor normal, timings, a perspective picture per scene, and a
//! moving eye (Section 4): its certified events, re-checked, and frames between them.

use super::RunMeta;
use crate::num::rational_to_f64;
use crate::solve::SolveOptions;
use crate::sweep::{
    apply_motion, builtin_scene, eye_point, frames, silhouette, verify_cap_border_touch,
    verify_cap_corner_passage, verify_corner_crossing, verify_events, verify_ruling,
    verify_t_extreme, ComponentKind, Scene, SilhouetteOptions, Silhouettes,
};
use crate::Path;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path as FsPath, PathBuf};

/// Runs per scene and path for the median time.
const RUNS: usize = 3;

/// One scene on one path.
#[derive(Clone, Debug, Serialize)]
pub struct SceneRow {
    pub scene: String,
    pub path: String,
    pub patches: usize,
    pub envelope: usize,
    pub types: [usize; 3],
    pub caps: usize,
    pub t_extreme: usize,
    pub t_extreme_verified: usize,
    /// Certified passages through patch corners (and the caps' touches on patch borders),
    /// and how many their checkers re-checked.
    pub corners: usize,
    pub corners_verified: usize,
    /// Rulings of a sweep invariant in `t`, and how many `verify_ruling` re-checks.
    pub rulings: usize,
    pub rulings_verified: usize,
    pub clusters: usize,
    pub vertices: usize,
    /// The largest normalised `|F|` and `|G|` over the envelope's vertices.
    pub max_f: f64,
    pub max_g: f64,
    pub median_seconds: f64,
    pub error: Option<String>,
}

/// Eq. 2 as printed against the cofactor normal on one scene.
#[derive(Clone, Debug, Serialize)]
pub struct Eq2Row {
    pub scene: String,
    pub similarity: bool,
    pub cofactor_max_g: f64,
    pub printed_max_g: f64,
    pub vertices: usize,
}

/// One critical event of the moving eye.
#[derive(Clone, Debug, Serialize)]
pub struct EventRow {
    pub r: f64,
    /// Its group ([`crate::sweep::event_groups`]): the same event seen from another patch.
    pub group: usize,
    /// `interior`, `face` or `edge`.
    pub kind: String,
    pub on_patch_border: bool,
    pub verified: bool,
}

/// One frame of the moving eye.
#[derive(Clone, Debug, Serialize)]
pub struct FrameRow {
    pub r: f64,
    pub traced: bool,
    pub components: usize,
    /// The tracer's unresolved boxes in a traced frame.
    pub clusters: usize,
    pub vertices: usize,
    /// The largest normalised `|F|` and `|G|` (from the frame's eye) over its vertices.
    pub max_f: f64,
    pub max_g: f64,
}

/// Section 4 on one scene with an eye path: the events and the frames.
#[derive(Clone, Debug, Serialize)]
pub struct MovingEyeRun {
    pub scene: String,
    /// The frames' eye parameters: from, to, how many.
    pub range: (f64, f64),
    pub frame_count: usize,
    pub events: Vec<EventRow>,
    pub systems: usize,
    pub clusters: usize,
    /// Roots across patch borders (`BorderRoot`), and how many `verify_border_root`
    /// re-checks.
    pub border_roots: usize,
    pub border_roots_verified: usize,
    /// Solving the events alone.
    pub events_seconds: f64,
    /// Events and frames together (`frames` solves the events first).
    pub seconds: f64,
    /// Of which the continued frames.
    pub continued_seconds: f64,
    /// Re-checking every event's certificate.
    pub verify_seconds: f64,
    pub frames: Vec<FrameRow>,
    /// The closed form's check, for a scene that has one.
    pub oracle: Option<MergeOracle>,
    pub error: Option<String>,
}

/// A scene with a closed-form event (the cylinder, the cone) against it: the unit sphere swept
/// along x into a cylinder or a cone, the eye on a line that crosses its surface; the two
/// contour lines exist exactly where `r² > c` and merge at `r² = c`.
#[derive(Clone, Debug, Serialize)]
pub struct MergeOracle {
    /// The merge's `r` in words (`−4/5`, `√(2881/315)`) and in `f64`.
    pub closed_form: String,
    pub r: f64,
    /// The events whose certified `r` interval holds the merge (`face t=0`, …), decided
    /// exactly by the sign of `r² − c` at its ends.
    pub at_merge: Vec<String>,
    /// For the cylinder: the largest `|x|`, `|y² + z² − 1|` and `|1 − r·y − (3/5)·z|` over
    /// every event's point (on the characteristic circle and on the contour from `P(r)`).
    pub worst: Option<f64>,
    /// Frames with two components where `r² > c` and none elsewhere.
    pub frames_as_closed_form: usize,
}

/// OpenCASCADE's outline of a static capsule against geocert's silhouette of a sweep whose
/// swept volume it is (`benches/peers/occ_outline.py`); distances in OCC's view plane.
#[derive(Clone, Debug, Serialize)]
pub struct OccRow {
    pub scene: String,
    pub version: String,
    /// OCC: building the capsule and its hidden-line outline, median of 5.
    pub occ_seconds: f64,
    /// geocert: the whole silhouette (median of the scene row's runs).
    pub geocert_seconds: f64,
    pub edges: usize,
    /// The outline's bounding-box diagonal in the view plane (the unit of the relative
    /// figures).
    pub diagonal: f64,
    pub occ_to_geocert: f64,
    pub envelope_to_occ: f64,
    pub occ_to_closed_form: f64,
    pub geocert_to_closed_form: f64,
}

/// Everything the report shows.
#[derive(Clone, Debug, Serialize)]
pub struct SweepCampaign {
    pub rows: Vec<SceneRow>,
    pub eq2: Vec<Eq2Row>,
    pub moving: Vec<MovingEyeRun>,
    /// The degenerate-but-legal eyes (module `sweep_degenerate`).
    pub degenerate: Vec<super::sweep_degenerate::DegenerateRow>,
    /// The OpenCASCADE peer per scene (`sphere-line`, `sphere-edge-roll`, `sphere-corner`), or why
    /// it did not run.
    pub occ: Vec<(String, Result<OccRow, String>)>,
}

/// The OpenCASCADE peer's scenes, each a unit sphere centred at the origin moved along a
/// segment (turning about its centre in the last two), so that the swept volume is a capsule
/// OCC builds exactly (a cylinder fused with two spheres): the plain translation, and the
/// two degenerate cases where geocert's silhouette runs along patch edges
/// (`sphere-edge-roll`) and through a patch corner (`sphere-corner`) of the turning sphere.
const OCC_SCENES: [&str; 3] = ["sphere-line", "sphere-edge-roll", "sphere-corner"];
/// Their sphere's radius (its centre is the origin).
const OCC_RADIUS: f64 = 1.0;

/// Runs `benches/peers/occ_outline.py` on scene `name`'s silhouette `s` (computed in a median
/// `seconds`).
fn occ_peer(
    root: &FsPath,
    name: &str,
    scene: &Scene,
    s: &Silhouettes,
    seconds: f64,
) -> Result<OccRow, String> {
    let python = root.join(".venv-peers/bin/python");
    if !python.exists() {
        return Err("`.venv-peers` not found (benches/peers/setup.sh installs it)".into());
    }
    let t = |x: &crate::num::Rational| rational_to_f64(x);
    let (a, b) = (
        apply_motion(scene, t(&scene.t.0), [0.0; 3]),
        apply_motion(scene, t(&scene.t.1), [0.0; 3]),
    );
    let curves = |envelope: bool| -> Vec<&Vec<[f64; 3]>> {
        s.components
            .iter()
            .filter(|c| (c.kind == ComponentKind::Envelope) == envelope)
            .map(|c| &c.points)
            .collect()
    };
    let spec = serde_json::json!({
        "a": a, "b": b, "radius": OCC_RADIUS, "eye": eye_f64(scene),
        "envelope": curves(true), "caps": curves(false),
    });
    let file = std::env::temp_dir().join(format!("geocert-occ-{}.json", std::process::id()));
    std::fs::write(&file, spec.to_string()).map_err(|e| e.to_string())?;
    let out = std::process::Command::new(python)
        .arg(root.join("benches/peers/occ_outline.py"))
        .arg(&file)
        .output();
    let _ = std::fs::remove_file(&file);
    let v = super::peer_json(out)?;
    let num = |k: &str| v[k].as_f64().ok_or_else(|| format!("no {k} in {v}"));
    Ok(OccRow {
        scene: name.into(),
        version: v["version"].as_str().unwrap_or("unknown").into(),
        occ_seconds: num("median_s")?,
        geocert_seconds: seconds,
        edges: v["edges"].as_u64().unwrap_or(0) as usize,
        diagonal: num("diagonal")?,
        occ_to_geocert: num("occ_to_geocert")?,
        envelope_to_occ: num("envelope_to_occ")?,
        occ_to_closed_form: num("occ_to_closed_form")?,
        geocert_to_closed_form: num("geocert_to_closed_form")?,
    })
}

/// The moving eye's scenes, and the frames drawn (from, to, how many): around the turning
/// ellipsoid's interior event, and across the cylinder's merge.
const MOVING: [(&str, (f64, f64), usize); 3] = [
    ("ellipsoid-turn-eye", (1.55, 1.75), 13),
    ("sphere-line-eye", (-2.0, -0.1), 8),
    ("sphere-cone-eye", (0.0, 6.0), 9),
];
/// Solves of the events timed; the report quotes their median.
const EVENT_RUNS: usize = 3;

/// Section 4 on `name`: the events, re-checked, and `count` frames over `range`, drawn into
/// `dir` as `sweep-NAME-frame-K.svg`.
fn moving_eye_run(name: &str, range: (f64, f64), count: usize, dir: &FsPath) -> MovingEyeRun {
    let mut run = MovingEyeRun {
        scene: name.into(),
        range,
        frame_count: count,
        oracle: None,
        events: Vec::new(),
        systems: 0,
        clusters: 0,
        border_roots: 0,
        border_roots_verified: 0,
        events_seconds: f64::NAN,
        seconds: f64::NAN,
        continued_seconds: f64::NAN,
        verify_seconds: f64::NAN,
        frames: Vec::new(),
        error: None,
    };
    let scene = match builtin_scene(name) {
        Ok(s) => s,
        Err(e) => {
            run.error = Some(e.to_string());
            return run;
        }
    };
    let (a, b) = range;
    let n = count - 1;
    let rs: Vec<f64> = (0..=n).map(|i| a + (b - a) * i as f64 / n as f64).collect();
    let opts = SilhouetteOptions::default()
        .with_resolution(1.0 / 32.0)
        .with_caps(false);
    let solve_opts = SolveOptions::new().with_tolerance(crate::sweep::EVENT_TOLERANCE);
    // The median of three solves: one run is at the mercy of the machine's load.
    let mut times = Vec::with_capacity(EVENT_RUNS);
    for _ in 0..EVENT_RUNS {
        let clock = std::time::Instant::now();
        if let Err(e) = crate::sweep::events(&scene, &solve_opts) {
            run.error = Some(e.to_string());
            return run;
        }
        times.push(clock.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    run.events_seconds = times[EVENT_RUNS / 2];
    // The frames three times as well (the continued frames take milliseconds): the medians.
    let mut runs = Vec::with_capacity(EVENT_RUNS);
    for _ in 0..EVENT_RUNS {
        let clock = std::time::Instant::now();
        match frames(&scene, &rs, &opts, &solve_opts) {
            Ok(f) => runs.push((clock.elapsed().as_secs_f64(), f)),
            Err(e) => {
                run.error = Some(e.to_string());
                return run;
            }
        }
    }
    let mut whole: Vec<f64> = runs.iter().map(|r| r.0).collect();
    let mut continued: Vec<f64> = runs.iter().map(|r| r.1.continued_seconds).collect();
    whole.sort_by(f64::total_cmp);
    continued.sort_by(f64::total_cmp);
    run.seconds = whole[EVENT_RUNS / 2];
    run.continued_seconds = continued[EVENT_RUNS / 2];
    let f = runs.swap_remove(0).1;
    let clock = std::time::Instant::now();
    let checks = verify_events(&scene, &f.events.events);
    run.verify_seconds = clock.elapsed().as_secs_f64();
    run.systems = f.events.systems;
    run.clusters = f.events.clusters.len();
    run.border_roots = f.events.border_roots.len();
    run.border_roots_verified = f
        .events
        .border_roots
        .iter()
        .filter(|b| crate::sweep::verify_border_root(&scene, &f.events.events, b).unwrap_or(false))
        .count();
    let group_of =
        crate::sweep::group_of_each(&crate::sweep::event_groups(&scene, &f.events.events));
    run.events = f
        .events
        .events
        .iter()
        .zip(&checks)
        .zip(&group_of)
        .map(|((e, c), &group)| EventRow {
            r: e.r,
            group,
            kind: match e.kind {
                crate::sweep::EventKind::Interior => "interior",
                crate::sweep::EventKind::Face { .. } => "face",
                crate::sweep::EventKind::Edge { .. } => "edge",
                crate::sweep::EventKind::AlongEdge { .. } => "along an edge",
            }
            .into(),
            on_patch_border: e.kind.on_patch_border(),
            verified: matches!(c, Ok(Ok(_))),
        })
        .collect();
    let _ = std::fs::create_dir_all(dir);
    for (k, frame) in f.frames.iter().enumerate() {
        let (max_f, max_g, vertices) = worst_at(
            &scene,
            frame.eye,
            frame.components.iter().flat_map(|c| {
                c.uvt
                    .iter()
                    .zip(&c.patches)
                    .map(|(x, &p)| (c.surface, p, *x))
            }),
        );
        run.frames.push(FrameRow {
            r: frame.r,
            traced: frame.traced,
            components: frame.components.len(),
            clusters: frame.clusters,
            vertices,
            max_f,
            max_g,
        });
        let _ = std::fs::write(
            dir.join(format!("sweep-{name}-frame-{k:02}.svg")),
            frame_svg(frame),
        );
    }
    if let Some(m) = MERGE_SCENES.iter().find(|m| m.name == name) {
        run.oracle = Some(merge_oracle(&scene, m, &f.events.events, &run.frames));
    }
    run
}

/// A scene with a closed-form event ([`MergeOracle`]).
struct MergeScene {
    name: &'static str,
    /// `c = (num, den)`: the lines exist where `r² > c` and merge at `r² = c`.
    c: (i64, i64),
    /// The merge's `r` is `−√c` (else `√c`).
    negative: bool,
    /// The merge in words.
    words: &'static str,
    /// The closed form, for the report.
    description: &'static str,
    /// Whether every event point is checked on the cylinder's contour (`sphere-line-eye`).
    cylinder: bool,
}

/// The scenes with a closed-form event.
const MERGE_SCENES: [MergeScene; 2] = [
    MergeScene {
        name: "sphere-line-eye",
        c: (16, 25),
        negative: true,
        words: "−4/5",
        description: "The unit sphere translated along x sweeps a cylinder. From \
         `P(r) = (5, r, 3/5)` the contour lines are where `1 − r·y − (3/5)·z = 0` meets \
         `y² + z² = 1` on the characteristic circle `x = 0`; they merge where the eye enters \
         the infinite cylinder, `r² + 9/25 = 1`: r = −4/5.",
        cylinder: true,
    },
    MergeScene {
        name: "sphere-cone-eye",
        c: (2881, 315),
        negative: false,
        words: "√(2881/315)",
        description: "The unit sphere translated along x while scaled by `1 + t/2` sweeps a \
         cone (apex at x = −6, `sin α = 1/6`). From `P(r) = (12, r, 1/3)` the contour lines \
         appear where the eye leaves the infinite cone, `r² + 1/9 = 18² tan² α = 324/35`: \
         r = √(2881/315).",
        cylinder: false,
    },
];

/// [`MergeOracle`] of the events and frames of a [`MergeScene`].
fn merge_oracle(
    scene: &Scene,
    m: &MergeScene,
    events: &[crate::sweep::Event],
    frames: &[FrameRow],
) -> MergeOracle {
    let c = m.c;
    use crate::num::Rational;
    let c_q = Rational::new(c.0.into(), c.1.into());
    let q = |r: &Rational| r * r - &c_q;
    let zero = Rational::from_integer(0.into());
    let axis = |a: usize| ["u", "v", "t"][a.min(2)];
    let at_merge = events
        .iter()
        .filter(|e| {
            e.root.bounds.last().is_some_and(|(lo, hi)| {
                let (a, b) = (q(lo), q(hi));
                (a <= zero && b >= zero) || (a >= zero && b <= zero)
            })
        })
        .map(|e| match e.kind {
            crate::sweep::EventKind::Face { axis: a, upper } => {
                format!("face {}={}", axis(a), u8::from(upper))
            }
            k => format!("{k:?}"),
        })
        .collect();
    // The cylinder's events against its closed form point by point.
    let worst = m.cylinder.then(|| {
        events
            .iter()
            .map(|e| {
                e.patch_point(scene).map_or(f64::INFINITY, |x| {
                    let on_circle = (x[1] * x[1] + x[2] * x[2] - 1.0).abs();
                    let tangent = (1.0 - e.r * x[1] - 0.6 * x[2]).abs();
                    x[0].abs().max(on_circle).max(tangent)
                })
            })
            .fold(0.0, f64::max)
    });
    let c_f = c.0 as f64 / c.1 as f64;
    let frames_as_closed_form = frames
        .iter()
        .filter(|f| f.components == if f.r * f.r > c_f { 2 } else { 0 })
        .count();
    let r = if m.negative { -c_f.sqrt() } else { c_f.sqrt() };
    MergeOracle {
        closed_form: m.words.into(),
        r,
        at_merge,
        worst,
        frames_as_closed_form,
    }
}

/// `(|F|, |G|)` at `(u, v, t)` of a patch, normalised, from central differences of
/// `A(t)S(u, v)`: `F = ⟨∂_t x, ∂_u x × ∂_v x⟩ / (|∂_t x||∂_u x||∂_v x|)` and
/// `G = ⟨x − P, ∂_u x × ∂_v x⟩ / (|x − P||∂_u x × ∂_v x|)` (the moved point's own derivatives:
/// their cross product is the true normal `cof(M) N`). Both are NaN at a parametric
/// singularity (a sphere's pole: one parameter's difference vanishes to rounding), where the
/// differences give no normal; the report leaves such vertices out of its maxima and its
/// count.
pub fn residuals(
    scene: &Scene,
    surface: usize,
    patch: usize,
    uvt: [f64; 3],
    eye: [f64; 3],
) -> (f64, f64) {
    let p = &scene.surfaces[surface].patches[patch];
    let at = |u: f64, v: f64, t: f64| -> [f64; 3] {
        let x = p
            .point(u.clamp(0.0, 1.0), v.clamp(0.0, 1.0))
            .unwrap_or([f64::NAN; 3]);
        apply_motion(scene, t, x)
    };
    let h = 1e-6;
    let [u, v, t] = uvt;
    let diff = |a: [f64; 3], b: [f64; 3], w: f64| [0, 1, 2].map(|k| (a[k] - b[k]) / w);
    // Central differences inside the patch; at its border the one-sided second-order
    // formula `(∓3f(x) ± 4f(x ± h) ∓ f(x ± 2h)) / 2h`, so that the error stays O(h²).
    let partial = |f: &dyn Fn(f64) -> [f64; 3], x: f64| -> [f64; 3] {
        if x - h >= 0.0 && x + h <= 1.0 {
            return diff(f(x + h), f(x - h), 2.0 * h);
        }
        let s = if x - h < 0.0 { 1.0 } else { -1.0 };
        let (a, b, c) = (f(x), f(x + s * h), f(x + 2.0 * s * h));
        [0, 1, 2].map(|k| s * (-3.0 * a[k] + 4.0 * b[k] - c[k]) / (2.0 * h))
    };
    let xu = partial(&|x| at(x, v, t), u);
    let xv = partial(&|x| at(u, x, t), v);
    let xt = diff(at(u, v, t + h), at(u, v, t - h), 2.0 * h);
    let n = [
        xu[1] * xv[2] - xu[2] * xv[1],
        xu[2] * xv[0] - xu[0] * xv[2],
        xu[0] * xv[1] - xu[1] * xv[0],
    ];
    let dot = |a: [f64; 3], b: [f64; 3]| (0..3).map(|k| a[k] * b[k]).sum::<f64>();
    let norm = |a: [f64; 3]| dot(a, a).sqrt();
    let x = at(u, v, t);
    if norm(xu).min(norm(xv)) <= 1e-6 * norm(xu).max(norm(xv)) {
        return (f64::NAN, f64::NAN);
    }
    let sight = [0, 1, 2].map(|k| x[k] - eye[k]);
    (
        (dot(xt, n) / (norm(xt) * norm(xu) * norm(xv))).abs(),
        (dot(sight, n) / (norm(sight) * norm(n))).abs(),
    )
}

/// The eye in `f64` (`P(r₀)` for a path).
pub fn eye_f64(scene: &Scene) -> [f64; 3] {
    eye_point(scene).map(|x| rational_to_f64(&x))
}

/// The largest residuals over the envelope's vertices, and their count.
fn worst(scene: &Scene, s: &Silhouettes) -> (f64, f64, usize) {
    let envelope = s
        .components
        .iter()
        .filter(|c| c.kind == ComponentKind::Envelope)
        .flat_map(|c| {
            c.uvt
                .iter()
                .zip(&c.patches)
                .map(|(x, &p)| (c.surface, p, *x))
        });
    worst_at(scene, eye_f64(scene), envelope)
}

/// The largest residuals seen from `eye` over `(surface, patch, (u, v, t))` points, and
/// how many were measured (not those at a parametric singularity, see [`residuals`]).
fn worst_at(
    scene: &Scene,
    eye: [f64; 3],
    points: impl Iterator<Item = (usize, usize, [f64; 3])>,
) -> (f64, f64, usize) {
    points.fold((0.0f64, 0.0f64, 0), |w, (surface, patch, uvt)| {
        let (f, g) = residuals(scene, surface, patch, uvt, eye);
        if f.is_nan() || g.is_nan() {
            return w;
        }
        (w.0.max(f), w.1.max(g), w.2 + 1)
    })
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

fn row(name: &str, scene: &Scene, path: Path) -> (SceneRow, Option<Silhouettes>) {
    let opts = SilhouetteOptions::default().with_path(path);
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..RUNS {
        match silhouette(scene, &opts) {
            Ok(s) => {
                times.push(s.seconds);
                last = Some(s);
            }
            Err(e) => {
                let mut r = empty_row(name, path);
                r.error = Some(e.to_string());
                return (r, None);
            }
        }
    }
    let s = last.expect("RUNS > 0");
    let (max_f, max_g, vertices) = worst(scene, &s);
    let mut types = [0; 3];
    for c in &s.components {
        if let Some(t) = c.component_type {
            types[t as usize - 1] += 1;
        }
    }
    let verified = s
        .t_extreme
        .iter()
        .filter(|x| matches!(verify_t_extreme(scene, x, false), Ok(Ok(_))))
        .count();
    let r = SceneRow {
        scene: name.into(),
        path: path.to_string(),
        patches: s.patches,
        envelope: s
            .components
            .iter()
            .filter(|c| c.kind == ComponentKind::Envelope)
            .count(),
        types,
        caps: s
            .components
            .iter()
            .filter(|c| c.kind != ComponentKind::Envelope)
            .count(),
        t_extreme: s.t_extreme.len(),
        t_extreme_verified: verified,
        corners: s.corner_crossings.len()
            + s.cap_corner_passages.len()
            + s.cap_border_touches.len(),
        corners_verified: s
            .corner_crossings
            .iter()
            .filter(|x| matches!(verify_corner_crossing(scene, x, false), Ok(true)))
            .count()
            + s.cap_corner_passages
                .iter()
                .filter(|x| matches!(verify_cap_corner_passage(scene, x, false), Ok(true)))
                .count()
            + s.cap_border_touches
                .iter()
                .filter(|x| matches!(verify_cap_border_touch(scene, x, false), Ok(true)))
                .count(),
        rulings: s.rulings.len(),
        rulings_verified: s
            .rulings
            .iter()
            .filter(|x| matches!(verify_ruling(scene, x, false), Ok(Ok(_))))
            .count(),
        clusters: s.clusters.len() + s.extreme_clusters.len(),
        vertices,
        max_f,
        max_g,
        median_seconds: median(times),
        error: None,
    };
    (r, Some(s))
}

fn empty_row(name: &str, path: Path) -> SceneRow {
    SceneRow {
        scene: name.into(),
        path: path.to_string(),
        patches: 0,
        envelope: 0,
        types: [0; 3],
        caps: 0,
        t_extreme: 0,
        t_extreme_verified: 0,
        corners: 0,
        corners_verified: 0,
        rulings: 0,
        rulings_verified: 0,
        clusters: 0,
        vertices: 0,
        max_f: f64::NAN,
        max_g: f64::NAN,
        median_seconds: f64::NAN,
        error: None,
    }
}

/// Runs every built-in scene on the filtered and fast paths, eq. 2 as printed on a
/// non-uniform scale and on a similarity, and draws each scene into `dir`; the OpenCASCADE
/// peer from `root`'s `.venv-peers` when it is installed.
pub fn sweep_campaign(root: &FsPath, dir: &FsPath) -> SweepCampaign {
    let mut rows = Vec::new();
    let mut occ: Vec<(String, Result<OccRow, String>)> = OCC_SCENES
        .iter()
        .map(|&n| (n.to_string(), Err(format!("scene {n} did not run"))))
        .collect();
    for &name in crate::sweep::BUILTIN_SCENES {
        let Ok(scene) = builtin_scene(name) else {
            continue;
        };
        let (r, s) = row(name, &scene, Path::Filtered);
        if let Some(s) = &s {
            let _ = std::fs::create_dir_all(dir);
            let _ = std::fs::write(dir.join(format!("sweep-{name}.svg")), svg(&scene, s));
            if let Some(slot) = occ.iter_mut().find(|(n, _)| n == name) {
                slot.1 = occ_peer(root, name, &scene, s, r.median_seconds);
            }
        }
        rows.push(r);
        rows.push(row(name, &scene, Path::Fast).0);
    }
    let mut eq2 = Vec::new();
    for (name, similarity) in [("ellipsoid-line", false), ("sphere-cone", true)] {
        let Ok(scene) = builtin_scene(name) else {
            continue;
        };
        let opts = SilhouetteOptions::default().with_caps(false);
        if let (Ok(right), Ok(printed)) = (
            silhouette(&scene, &opts),
            silhouette(&scene, &opts.with_printed_eq2(true)),
        ) {
            let (_, good, _) = worst(&scene, &right);
            let (_, bad, vertices) = worst(&scene, &printed);
            eq2.push(Eq2Row {
                scene: name.into(),
                similarity,
                cofactor_max_g: good,
                printed_max_g: bad,
                vertices,
            });
        }
    }
    let moving = MOVING
        .iter()
        .map(|&(name, range, count)| moving_eye_run(name, range, count, dir))
        .collect();
    SweepCampaign {
        rows,
        eq2,
        moving,
        degenerate: super::sweep_degenerate::degenerate_runs(),
        occ,
    }
}

/// The campaign passes when every filtered run succeeded without clusters, every certified
/// t-extreme point re-checks, every traced vertex is within 1e-6 of `F = G = 0`, eq. 2 as
/// printed is right exactly on the similarity, and the moving eye's events all re-check, its
/// frames are resolved with their vertices (continued ones too) within 1e-6 of `F = G = 0`,
/// and the cylinder's events and frames agree with the closed form, and the degenerate eyes
/// agree with theirs.
pub fn campaign_ok(c: &SweepCampaign) -> bool {
    super::sweep_degenerate::degenerate_ok(&c.degenerate)
        && c.rows.iter().filter(|r| r.path == "filtered").all(|r| {
            r.error.is_none()
                && r.clusters == 0
                && r.t_extreme == r.t_extreme_verified
                && r.corners == r.corners_verified
                && r.rulings == r.rulings_verified
                && r.max_f < 1e-6
                && r.max_g < 1e-6
        })
        && c.eq2
            .iter()
            .all(|e| e.cofactor_max_g < 1e-6 && (e.printed_max_g < 1e-6) == e.similarity)
        && c.moving.iter().all(|m| {
            m.error.is_none()
                && m.clusters == 0
                && m.border_roots_verified == m.border_roots
                && m.events.iter().all(|e| e.verified)
                && m.frames
                    .iter()
                    .all(|f| f.clusters == 0 && f.max_f < 1e-6 && f.max_g < 1e-6)
                && m.oracle.as_ref().is_none_or(|o| {
                    o.at_merge.len() >= 2
                        && o.worst.is_none_or(|w| w < 1e-8)
                        && o.frames_as_closed_form == m.frames.len()
                })
        })
}

fn e(x: f64) -> String {
    if x.is_nan() {
        "–".into()
    } else {
        format!("{x:.1e}")
    }
}

/// Writes `reports/sweep.md`; returns its path.
pub fn write_sweep_report(
    dir: &FsPath,
    meta: &RunMeta,
    c: &SweepCampaign,
) -> std::io::Result<PathBuf> {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Perspective silhouettes of swept volumes\n\nGenerated by `geocert prove`; do not edit.\n"
    );
    s.push_str(&meta.markdown());
    let _ = writeln!(
        s,
        "\n## The built-in scenes\n\nAlgorithm 1 of Seong, Kim, Kim and Elber (2006) per scene: \
         the envelope's silhouette components `F = G = 0` with their types (1 closed, 2 with \
         t-extremes, 3 t-monotone), the certified t-extreme points `F = G = H = 0` (each \
         re-checked by `verify_t_extreme`, which rebuilds the equations and does not call the \
         solver), the passages through patch corners (certified from the exact crossing time \
         and a regular box around it, each re-checked by `verify_corner_crossing`; \
         `sphere-corner`; the end positions' contours through patch corners likewise, each \
         re-checked by `verify_cap_corner_passage`, and their touches on patch borders, by \
         `verify_cap_border_touch`), the rulings of sweeps invariant in `t` (`sphere-line`, `sphere-cone`: \
         the silhouette's points solved in `(u, v)`, each re-checked by `verify_ruling`; see \
         *Degenerate eyes*), the contours of the start and end positions (*caps*), and the boxes the \
         tracer could not resolve (*clusters*, must be 0). *max F*, *max G*: the largest \
         normalised `|F|` and `|G|` over the envelope's traced vertices (*vertices*: those \
         measured; a vertex on a sphere's pole, where the parametrisation has no normal, is \
         left out: `sphere-edge-roll` passes two), computed by differences of `A(t)S(u, v)` \
         (central inside a patch, second-order one-sided at its borders) — not from the \
         library's polynomials (the differences' own error is about 1e-10 relative, more next to a pole). Time: median of {RUNS} runs of the \
         whole algorithm (equations, tracing, extremes, caps), one thread.\n\n\
         | scene | path | patches | envelope components | types 1/2/3 | caps | t-extreme (re-checked) | corner passages (re-checked) | rulings (re-checked) | clusters | vertices | max F | max G | median s |\n\
         |---|---|---:|---:|---|---:|---|---|---|---:|---:|---:|---:|---:|"
    );
    for r in &c.rows {
        if let Some(err) = &r.error {
            let _ = writeln!(
                s,
                "| {} | {} | refused: {err} | | | | | | | | | | | |",
                r.scene, r.path
            );
            continue;
        }
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {}/{}/{} | {} | {} ({}) | {} ({}) | {} ({}) | {} | {} | {} | {} | {:.3} |",
            r.scene,
            r.path,
            r.patches,
            r.envelope,
            r.types[0],
            r.types[1],
            r.types[2],
            r.caps,
            r.t_extreme,
            r.t_extreme_verified,
            r.corners,
            r.corners_verified,
            r.rulings,
            r.rulings_verified,
            r.clusters,
            r.vertices,
            e(r.max_f),
            e(r.max_g),
            r.median_seconds
        );
    }
    let _ = writeln!(
        s,
        "\n## Eq. 2 as printed\n\nThe paper's eq. 2, `G = ⟨A(t)S − P, A(t)N⟩`, transforms the \
         normal by the linear part `M(t)`; a normal transforms by `cof(M) = det(M) M⁻ᵀ`, and the \
         two agree only when `M(t)` is a similarity. Traced with each (caps off), the largest \
         normalised `|G|` of the true contour condition over the traced vertices:\n\n\
         | scene | M(t) | vertices | with cof(M)·N | with M·N (as printed) |\n|---|---|---:|---:|---:|"
    );
    for q in &c.eq2 {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} |",
            q.scene,
            if q.similarity {
                "similarity"
            } else {
                "non-uniform scale"
            },
            q.vertices,
            e(q.cofactor_max_g),
            e(q.printed_max_g)
        );
    }
    let _ = writeln!(
        s,
        "\n## Pictures\n\nEach scene's components in perspective from its eye (envelope \
         components in colour, the end positions' contours dashed):\n"
    );
    for r in c
        .rows
        .iter()
        .filter(|r| r.path == "filtered" && r.error.is_none())
    {
        let _ = writeln!(s, "![{0}](sweep-{0}.svg)\n", r.scene);
    }
    for m in &c.moving {
        moving_markdown(&mut s, m);
    }
    super::sweep_degenerate::degenerate_markdown(&mut s, &c.degenerate);
    occ_markdown(&mut s, &c.occ);
    let _ = writeln!(
        s,
        "## Not yet here\n\nThe paper's 0.1 s event budget on the turning ellipsoid: solving \
         its events (the 4-unknown interior systems take most of the time) and tracing the \
         frames near them (each traced frame is a whole certified run of Algorithm 1) are the \
         slow parts (see the times above); the cylinder's and the cone's events are well inside it."
    );
    std::fs::create_dir_all(dir)?;
    let path = dir.join("sweep.md");
    std::fs::write(&path, s)?;
    Ok(path)
}

/// The OpenCASCADE section.
fn occ_markdown(s: &mut String, occ: &[(String, Result<OccRow, String>)]) {
    let _ = writeln!(
        s,
        "## OpenCASCADE as a peer (static eye)\n\nScenes `sphere-line`, `sphere-edge-roll` and \
         `sphere-corner`: a unit sphere moved along a segment (in the last two while it turns \
         about its centre), so the swept volume is a capsule OpenCASCADE builds exactly (a \
         cylinder fused with two spheres, `BRepAlgoAPI_Fuse`). The turning spheres are the \
         degenerate cases of geocert's tracer: the silhouette runs along the turning patches' \
         edges (`sphere-edge-roll`, module `edges`) and through a patch corner \
         (`sphere-corner`, module `corners`); OCC, which sees only the capsule, is blind to \
         the parametrisation, so it checks those paths independently. OCC's outline is \
         `HLRBRep_Algo` with a perspective `HLRAlgo_Projector` (its viewing system at the \
         capsule's midpoint, Z towards the eye, focus = the eye's distance, so the eye sits at \
         Focus·Z), visible and hidden outline edges. geocert's polylines are projected by the \
         same projector (`HLRAlgo_Projector.Project`) and the curves compared in its view \
         plane (`benches/peers/occ_outline.py`). The closed form is the capsule's true outline \
         from the eye: the cylinder's two tangent lines and the end spheres' contour circles, \
         sampled at 4,000 points a circle (so distances to it below about 1e-6 are its own \
         sampling). geocert's caps are whole contours of the end spheres, partly inside the \
         capsule where OCC draws nothing, so only the envelope is measured against OCC's \
         outline; OCC's outline is measured against all of geocert's curves. Distances in % of \
         the outline's bounding-box diagonal in the view plane.\n"
    );
    let _ = writeln!(
        s,
        "| scene | OCC | outline edges | diagonal | OCC outline → geocert's curves (max %) | \
         geocert's envelope → OCC outline (max %) | OCC outline → closed form (max %) | \
         geocert's vertices → closed form (max %) | OCC s (median of 5) | geocert s (median \
         of {RUNS}) | geocert / OCC |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    for (name, row) in occ {
        match row {
            Err(e) => {
                let _ = writeln!(s, "| {name} | not run: {e} | | | | | | | | | |");
            }
            Ok(o) => {
                let rel = |x: f64| 100.0 * x / o.diagonal;
                let _ = writeln!(
                    s,
                    "| {name} | {} | {} | {:.3} | {:.3} | {:.1e} | {:.3} | {:.1e} | {:.4} | {:.4} | {:.1}× |",
                    o.version,
                    o.edges,
                    o.diagonal,
                    rel(o.occ_to_geocert),
                    rel(o.envelope_to_occ),
                    rel(o.occ_to_closed_form),
                    rel(o.geocert_to_closed_form),
                    o.occ_seconds,
                    o.geocert_seconds,
                    o.geocert_seconds / o.occ_seconds.max(1e-12),
                );
            }
        }
    }
    let _ = writeln!(
        s,
        "\nOCC's time is building the capsule and its outline; geocert's is the whole certified \
         silhouette (equations, tracing, extremes, corner passages, caps). OCC's outline is off \
         the closed form by its own approximation of the outline curves; geocert's vertices lie \
         on it to the tracer's tolerance.\n"
    );
}

/// The moving eye's section.
fn moving_markdown(s: &mut String, m: &MovingEyeRun) {
    let _ = writeln!(
        s,
        "## A moving eye (Section 4): `{}`\n\nThe eye on a path `P(r)`. The critical \
         events (the Lagrange condition: the silhouette curve of that eye position is singular; \
         on the patches' faces and edges too), each certified by the solver and re-checked by \
         `verify_events` (which rebuilds the systems from the scene and does not call the \
         solver). Then {} frames from r = {} to {}: a frame is traced afresh by the certified \
         tracer when it is the first or an event off the patch borders (interior, or on a \
         start or end position) lies since the previous one, or when continuing fails, and is \
         otherwise continued from the previous frame by Newton's method on `F = G = 0`. *max F*, \
         *max G*: normalised residuals from central differences, as above, with each frame's \
         own eye.\n",
        m.scene, m.frame_count, m.range.0, m.range.1
    );
    if let Some(err) = &m.error {
        let _ = writeln!(s, "Refused: {err}\n");
        return;
    }
    let interior = m.events.iter().filter(|e| e.kind == "interior").count();
    let verified = m.events.iter().filter(|e| e.verified).count();
    let _ = writeln!(
        s,
        "{} events from {} systems ({} interior, {} on patch borders), {} re-checked, {} \
         clusters, {} roots across patch borders ({} re-checked). Solving the events {:.2} s (median of three; root boxes to {:e} of each \
         parameter's interval, on all cores); events and frames together {:.2} s, of which the {} continued frames \
         {:.4} s (medians of three; the rest is the traced frames); re-checking the events {:.2} s (two cores).\n\n\
         Events with the same *group* are one event seen from the patches that meet there \
         (`event_groups`: a border crossing shows on both patches, at a pole on four): {} \
         distinct.\n\n\
         | r | group | where | patch border | re-checked |\n|---:|---:|---|---|---|",
        m.events.len(),
        m.systems,
        interior,
        m.events.iter().filter(|e| e.on_patch_border).count(),
        verified,
        m.clusters,
        m.border_roots,
        m.border_roots_verified,
        m.events_seconds,
        crate::sweep::EVENT_TOLERANCE,
        m.seconds,
        m.frames.iter().filter(|f| !f.traced).count(),
        m.continued_seconds,
        m.verify_seconds,
        m.events.iter().map(|e| e.group + 1).max().unwrap_or(0)
    );
    for e in &m.events {
        let _ = writeln!(
            s,
            "| {:.6} | {} | {} | {} | {} |",
            e.r,
            e.group,
            e.kind,
            if e.on_patch_border { "yes" } else { "no" },
            if e.verified { "yes" } else { "NO" }
        );
    }
    let _ = writeln!(
        s,
        "\n| frame | r | made by | components | unresolved boxes | vertices | max F | max G |\n|---:|---:|---|---:|---:|---:|---:|---:|"
    );
    for (k, f) in m.frames.iter().enumerate() {
        let _ = writeln!(
            s,
            "| {k} | {:.6} | {} | {} | {} | {} | {} | {} |",
            f.r,
            if f.traced { "traced" } else { "continued" },
            f.components,
            f.clusters,
            f.vertices,
            e(f.max_f),
            e(f.max_g)
        );
    }
    let _ = writeln!(s, "\nThe frames, each from its own eye:\n");
    for k in 0..m.frames.len() {
        let _ = writeln!(s, "![frame {k}](sweep-{}-frame-{k:02}.svg)", m.scene);
    }
    s.push('\n');
    if let Some(o) = &m.oracle {
        let description = MERGE_SCENES
            .iter()
            .find(|x| x.name == m.scene)
            .map_or("", |x| x.description);
        let _ = writeln!(
            s,
            "**Closed form.** {description} The sweep is invariant in t (the characteristic \
             circle is the same circle of the sphere at every time): the silhouette is made of \
             rulings, an event moves a whole ruling, and the systems with t free, which have \
             segments of roots, are not solved; the segments' ends are the events on the faces \
             t = 0 and t = 1. Certified intervals holding {} ≈ {:.9}, decided exactly by the \
             sign of `r² − c` at their ends: {} ({}).{} Frames with two lines where the eye is \
             outside and none inside: {} of {}.\n",
            o.closed_form,
            o.r,
            o.at_merge.len(),
            o.at_merge.join(", "),
            o.worst.map_or(String::new(), |w| format!(
                " Every event's point against the closed form (its `|x|`, `|y² + z² − 1|`, \
                 `|1 − r·y − (3/5)·z|`): at most {w:.1e}."
            )),
            o.frames_as_closed_form,
            m.frames.len()
        );
    }
}

/// A frame of a moving eye drawn from that frame's eye (its components' titles say whether
/// it was traced or continued).
pub fn frame_svg(frame: &crate::sweep::Frame) -> String {
    let lines: Vec<SvgLine<'_>> = frame
        .components
        .iter()
        .map(|c| SvgLine {
            points: &c.points,
            closed: c.closed,
            envelope: true,
            title: if frame.traced { "traced" } else { "continued" },
        })
        .collect();
    svg_lines(frame.eye, &lines)
}

/// A perspective drawing from the eye towards the silhouettes' centroid.
pub fn svg(scene: &Scene, s: &Silhouettes) -> String {
    let lines: Vec<SvgLine<'_>> = s
        .components
        .iter()
        .map(|c| SvgLine {
            points: &c.points,
            closed: c.closed,
            envelope: c.kind == ComponentKind::Envelope,
            title: c.kind.name(),
        })
        .collect();
    svg_lines(eye_f64(scene), &lines)
}

/// One polyline of [`svg_lines`].
pub struct SvgLine<'a> {
    /// Its points in 3-D.
    pub points: &'a [[f64; 3]],
    /// Whether it closes.
    pub closed: bool,
    /// Drawn solid and coloured (an envelope component), else dashed grey (a cap).
    pub envelope: bool,
    /// The tooltip.
    pub title: &'a str,
}

/// A perspective drawing of 3-D polylines seen from `eye`, looking at their centroid, fitted
/// into 800 px.
pub fn svg_lines(eye: [f64; 3], lines: &[SvgLine<'_>]) -> String {
    let pts: Vec<[f64; 3]> = lines.iter().flat_map(|c| c.points.to_vec()).collect();
    let n = pts.len().max(1) as f64;
    let centre: Vec<f64> = (0..3)
        .map(|k| pts.iter().map(|p| p[k]).sum::<f64>() / n)
        .collect();
    let norm = |v: [f64; 3]| {
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
            .sqrt()
            .max(f64::MIN_POSITIVE);
        [v[0] / l, v[1] / l, v[2] / l]
    };
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let d = norm([centre[0] - eye[0], centre[1] - eye[1], centre[2] - eye[2]]);
    let up0 = if d[2].abs() > 0.9 {
        [0.0, 1.0, 0.0]
    } else {
        [0.0, 0.0, 1.0]
    };
    let right = norm(cross(d, up0));
    let up = cross(right, d);
    let project = |p: &[f64; 3]| {
        let v = [p[0] - eye[0], p[1] - eye[1], p[2] - eye[2]];
        let z = dot(v, d).max(1e-9);
        (dot(v, right) / z, -dot(v, up) / z)
    };
    let projected: Vec<Vec<(f64, f64)>> = lines
        .iter()
        .map(|c| c.points.iter().map(project).collect())
        .collect();
    let all = projected.iter().flatten();
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in all {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    // The frame fits the drawing: 800 px across its wider side.
    let span = (x1 - x0).max(y1 - y0).max(1e-12);
    let size = 800.0;
    let margin = 20.0;
    let width = margin * 2.0 + (x1 - x0).max(0.0) / span * (size - 2.0 * margin);
    let height = margin * 2.0 + (y1 - y0).max(0.0) / span * (size - 2.0 * margin);
    let (width, height) = (width.round(), height.round());
    let to_px = |(x, y): (f64, f64)| {
        (
            margin + (x - x0) / span * (size - 2.0 * margin),
            margin + (y - y0) / span * (size - 2.0 * margin),
        )
    };
    let colours = [
        "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#e377c2",
    ];
    let mut out = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" viewBox=\"0 0 {width} {height}\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    );
    for (i, (c, line)) in lines.iter().zip(&projected).enumerate() {
        let mut d = String::new();
        for (k, &p) in line.iter().enumerate() {
            let (x, y) = to_px(p);
            d.push_str(&format!("{}{x:.2},{y:.2} ", if k == 0 { "M" } else { "L" }));
        }
        if c.closed {
            d.push('Z');
        }
        let (colour, dash, stroke) = if c.envelope {
            (colours[i % colours.len()], "", 2.5)
        } else {
            ("#555555", " stroke-dasharray=\"6 4\"", 1.2)
        };
        out.push_str(&format!(
            "<path d=\"{d}\" fill=\"none\" stroke=\"{colour}\" stroke-width=\"{stroke}\"{dash}><title>component {i}: {}</title></path>\n",
            c.title
        ));
    }
    out.push_str("</svg>\n");
    out
}
