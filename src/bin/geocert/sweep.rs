//! `geocert sweep silhouette`, `geocert sweep events` and `geocert sweep animate`: the
//! perspective silhouette of a swept volume (Seong et al.) and, for an eye on a path, the
//! critical events where its topology can change and the frames between them.

use crate::out::{choice, pretty, read, write};
use clap::Subcommand;
use geocert::bernstein::Limits;
use geocert::internals::report::sweep::frame_svg;
use geocert::num::rational_to_string;
use geocert::sweep::{
    builtin_scene, event_groups, events, frames, group_of_each, scene_from_json, silhouette,
    verify_border_root, verify_cap_border_touch, verify_events, verify_ruling, ComponentEnd,
    EventKind, Events, Eye, RulingEvidence, Scene, SilhouetteOptions, Silhouettes,
};
use geocert::Path;
use serde_json::{json, Value};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Subcommand)]
pub(crate) enum Command {
    /// The silhouette components of a swept volume seen from the eye: the envelope's
    /// components (F = G = 0, with Algorithm 1's types 1–3), the certified t-extreme points
    /// (F = G = H = 0), and the contours of the start and end positions.
    Silhouette(SilhouetteArgs),
    /// For an eye moving along a path P(r): the certified critical events where the
    /// silhouette's topology can change (Section 4, with the Lagrange condition: the
    /// silhouette curve of that eye position is singular), on the patch's faces and edges too,
    /// sorted by r; each re-checked from the scene. A root exactly on a patch border (where
    /// the subdivision can only leave a cluster on its system's domain boundary) is solved
    /// again on the cluster's box widened across the border and matched with the border's
    /// own event (`border_roots`, each re-checked). The eye path must stay off the moving
    /// surface (certified first).
    Events(EventsArgs),
    /// For an eye moving along a path P(r): the silhouette at evenly spaced eye parameters
    /// (Section 4.2). The events are solved first; a frame is traced afresh by the certified
    /// tracer when an event lies since the previous frame, and otherwise continued from it
    /// (Newton's method on F = G = 0, each point checked against both equations).
    Animate(AnimateArgs),
}

#[derive(clap::Args)]
pub(crate) struct AnimateArgs {
    /// A scene JSON file whose eye is `{"path": [px, py, pz], "r": [r0, r1]}`, or
    /// `builtin:ellipsoid-turn-eye`, `builtin:sphere-line-eye`, `builtin:sphere-cone-eye`.
    scene: String,
    /// Frames, evenly spaced from --from to --to (both included).
    #[arg(long, default_value_t = 24)]
    frames: usize,
    /// The first eye parameter (default: the path's r0).
    #[arg(long)]
    from: Option<f64>,
    /// The last eye parameter (default: the path's r1).
    #[arg(long)]
    to: Option<f64>,
    #[arg(long, default_value_t = Path::Filtered, value_parser = choice::<Path>(Path::NAMES))]
    path: Path,
    /// The widest arc box of traced frames relative to the parameter domain.
    #[arg(long, default_value_t = 1.0 / 16.0)]
    resolution: f64,
    /// Wall-clock budget per system (events) and per patch (traced frames) in seconds.
    #[arg(long, default_value_t = 20.0)]
    time_limit: f64,
    /// Write one perspective drawing per frame, from that frame's eye, into this directory
    /// (`frame-0000.svg`, …); nothing is written when a frame fails.
    #[arg(long)]
    svg_dir: Option<PathBuf>,
    #[arg(long)]
    json: bool,
}

/// The most frames `animate` draws.
const MAX_FRAMES: usize = 100_000;

#[derive(clap::Args)]
pub(crate) struct EventsArgs {
    /// A scene JSON file whose eye is `{"path": [px, py, pz], "r": [r0, r1]}`.
    scene: String,
    #[arg(long, default_value_t = Path::Filtered, value_parser = choice::<Path>(Path::NAMES))]
    path: Path,
    /// Wall-clock budget per system in seconds (what it stops is reported as clusters).
    #[arg(long, default_value_t = 20.0)]
    time_limit: f64,
    #[arg(long)]
    json: bool,
}

#[derive(clap::Args)]
pub(crate) struct SilhouetteArgs {
    /// A scene JSON file (`{"surfaces": [...], "t": [a, b], "motion": {...}, "eye": ...}`), or
    /// `builtin:NAME` (sphere-line, sphere-cone, ellipsoid-line, ellipsoid-turn, tuba,
    /// ellipsoid-turn-eye, sphere-line-eye, sphere-cone-eye, sphere-edge-roll, sphere-corner).
    scene: String,
    #[arg(long, default_value_t = Path::Filtered, value_parser = choice::<Path>(Path::NAMES))]
    path: Path,
    /// The widest arc box relative to the parameter domain (the polylines' density).
    #[arg(long, default_value_t = 1.0 / 16.0)]
    resolution: f64,
    /// Refine each patch's polylines until every chord is certified within this 3-D distance
    /// of the curve (the resolution is halved down to 1/1024).
    #[arg(long)]
    tolerance: Option<f64>,
    /// Wall-clock budget per patch in seconds (what it stops is reported as clusters).
    #[arg(long, default_value_t = 20.0)]
    time_limit: f64,
    /// Deepest subdivision level per side of the tracer.
    #[arg(long, default_value_t = 14)]
    max_depth: u32,
    /// Leave out the contours of the start and end positions.
    #[arg(long)]
    no_caps: bool,
    /// Use eq. 2 exactly as printed (⟨A(t)S − P, M(t)N⟩) instead of the cofactor normal, to
    /// see how far it is from the contour under a non-similarity motion.
    #[arg(long)]
    printed_eq2: bool,
    /// Draw the silhouettes in perspective from the eye into this SVG file.
    #[arg(long)]
    svg: Option<PathBuf>,
    #[arg(long)]
    json: bool,
}

pub(crate) fn run(c: Command) -> Result<ExitCode, String> {
    match c {
        Command::Silhouette(a) => run_silhouette(a),
        Command::Events(a) => run_events(a),
        Command::Animate(a) => run_animate(a),
    }
}

fn run_animate(a: AnimateArgs) -> Result<ExitCode, String> {
    if !(1..=MAX_FRAMES).contains(&a.frames) {
        return Err(format!(
            "--frames must be from 1 to {MAX_FRAMES}, got {}",
            a.frames
        ));
    }
    if !(a.resolution.is_finite() && a.resolution > 0.0) {
        return Err(format!(
            "--resolution must be a positive number, got {}",
            a.resolution
        ));
    }
    let time_limit = crate::out::time_limit(Some(a.time_limit))?;
    let scene = load(&a.scene)?;
    let Eye::Path { r, .. } = &scene.eye else {
        return Err(format!(
            "{}: eye: animate needs an eye path {{\"path\": [px, py, pz], \"r\": [r0, r1]}}",
            a.scene
        ));
    };
    let (r0, r1) = (
        geocert::num::rational_to_f64(&r.0),
        geocert::num::rational_to_f64(&r.1),
    );
    let (from, to) = (a.from.unwrap_or(r0), a.to.unwrap_or(r1));
    let inside = r0 <= from && to <= r1;
    let ordered = from < to || (a.frames == 1 && from == to);
    if !(inside && ordered) {
        return Err(format!(
            "--from {from} and --to {to} must satisfy {r0} ≤ from < to ≤ {r1} (the eye path's r)"
        ));
    }
    let rs: Vec<f64> = if a.frames == 1 {
        vec![from]
    } else {
        let n = (a.frames - 1) as f64;
        (0..a.frames)
            .map(|i| {
                if i + 1 == a.frames {
                    to
                } else {
                    from + (to - from) * i as f64 / n
                }
            })
            .collect()
    };
    if rs.windows(2).any(|w| w[0] >= w[1]) {
        return Err(format!(
            "{} frames from {from} to {to} are not distinct in f64",
            a.frames
        ));
    }
    let limits = Limits::new()
        .with_max_depth(40)
        .with_max_boxes(200_000)
        .with_time_limit(time_limit);
    let solve_opts = geocert::solve::SolveOptions::new()
        .with_path(a.path)
        .with_limits(limits)
        .with_tolerance(geocert::sweep::EVENT_TOLERANCE);
    let opts = SilhouetteOptions::default()
        .with_path(a.path)
        .with_resolution(a.resolution)
        .with_limits(limits.with_max_depth(14))
        .with_caps(false);
    let clock = std::time::Instant::now();
    let f = frames(&scene, &rs, &opts, &solve_opts).map_err(|e| e.to_string())?;
    let seconds = clock.elapsed().as_secs_f64();
    let verified: Vec<bool> = verify_events(&scene, &f.events.events)
        .iter()
        .map(|c| matches!(c, Ok(Ok(_))))
        .collect();
    let (border_roots, borders_verified) = border_roots_json(&scene, &f.events)?;
    let all_verified = verified.iter().all(|&v| v) && borders_verified;
    let groups = event_groups(&scene, &f.events.events);
    let group_of = group_of_each(&groups);
    if let Some(dir) = &a.svg_dir {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        for (k, frame) in f.frames.iter().enumerate() {
            write(&dir.join(format!("frame-{k:04}.svg")), frame_svg(frame))?;
        }
    }
    let traced = f.frames.iter().filter(|x| x.traced).count();
    if a.json {
        let v = json!({
            "events": f.events.events.iter().zip(&verified).zip(&group_of).map(|((e, ok), group)| json!({
                "r": e.r,
                "group": group,
                "kind": kind_json(&e.kind),
                "on_patch_border": e.kind.on_patch_border(),
                "verified": ok,
            })).collect::<Vec<_>>(),
            "distinct_events": groups.len(),
            "clusters": event_clusters_json(&f.events.clusters),
            "border_roots": border_roots,
            "frames": f.frames.iter().map(|x| json!({
                "r": x.r,
                "eye": x.eye,
                "traced": x.traced,
                "clusters": x.clusters,
                "components": x.components.iter().map(|c| json!({
                    "surface": c.surface,
                    "closed": c.closed,
                    "patches": c.patches,
                    "uvt": c.uvt,
                    "points": c.points,
                })).collect::<Vec<_>>(),
            })).collect::<Vec<_>>(),
            "traced_frames": traced,
            "continued_frames": f.frames.len() - traced,
            "continued_seconds": f.continued_seconds,
            "seconds": seconds,
        });
        println!("{}", pretty(&v)?);
    } else {
        println!(
            "{} frames from r = {from} to {to} in {seconds:.2} s: {traced} traced, {} continued \
             ({:.4} s); {} events, {} distinct ({} clusters){}",
            f.frames.len(),
            f.frames.len() - traced,
            f.continued_seconds,
            f.events.events.len(),
            groups.len(),
            f.events.clusters.len(),
            if all_verified {
                ", every event re-checked"
            } else {
                "; SOME EVENTS FAILED THEIR RE-CHECK"
            }
        );
        for x in &f.frames {
            println!(
                "r = {:.6}  {} component(s), {} points  {}{}",
                x.r,
                x.components.len(),
                x.components.iter().map(|c| c.points.len()).sum::<usize>(),
                if x.traced { "traced" } else { "continued" },
                if x.clusters > 0 {
                    format!(", {} unresolved boxes (incomplete)", x.clusters)
                } else {
                    String::new()
                }
            );
        }
    }
    Ok(crate::out::status(
        all_verified && f.events.clusters.is_empty() && f.frames.iter().all(|x| x.clusters == 0),
    ))
}

fn kind_json(k: &EventKind) -> Value {
    let axis = |a: usize| ["u", "v", "t"][a.min(2)];
    match k {
        EventKind::Interior => json!({"where": "interior"}),
        EventKind::Face { axis: a, upper } => {
            json!({"where": "face", "fixed": [[axis(*a), if *upper { 1 } else { 0 }]]})
        }
        EventKind::Edge { fixed } => json!({"where": "edge", "fixed": fixed
            .iter()
            .map(|(a, u)| json!([axis(*a), if *u { 1 } else { 0 }]))
            .collect::<Vec<_>>()}),
        EventKind::AlongEdge { edge, fixed } => json!({"where": "along_edge",
            "edge": [axis(edge.0), if edge.1 { 1 } else { 0 }],
            "fixed": fixed
            .iter()
            .flatten()
            .map(|(a, u)| json!([axis(*a), if *u { 1 } else { 0 }]))
            .collect::<Vec<_>>()}),
    }
}

fn run_events(a: EventsArgs) -> Result<ExitCode, String> {
    let time_limit = crate::out::time_limit(Some(a.time_limit))?;
    let scene = load(&a.scene)?;
    let opts = geocert::solve::SolveOptions::new()
        .with_path(a.path)
        .with_limits(
            Limits::new()
                .with_max_depth(40)
                .with_max_boxes(200_000)
                .with_time_limit(time_limit),
        )
        .with_tolerance(geocert::sweep::EVENT_TOLERANCE);
    let clock = std::time::Instant::now();
    let ev = events(&scene, &opts).map_err(|e| e.to_string())?;
    let seconds = clock.elapsed().as_secs_f64();
    let checks = verify_events(&scene, &ev.events);
    let groups = event_groups(&scene, &ev.events);
    let group_of = group_of_each(&groups);
    let mut rows = Vec::new();
    let mut all_verified = true;
    for ((e, check), group) in ev.events.iter().zip(&checks).zip(&group_of) {
        let verified = matches!(check, Ok(Ok(_)));
        all_verified &= verified;
        rows.push(json!({
            "r": e.r,
            "group": group,
            "surface": e.surface,
            "patch": e.patch,
            "kind": kind_json(&e.kind),
            "on_patch_border": e.kind.on_patch_border(),
            "uvt": e.uvt,
            "error_bound": e.root.error_bound,
            "pivot_certified": e.pivot,
            "verified": verified,
        }));
    }
    let (border_roots, borders_verified) = border_roots_json(&scene, &ev)?;
    all_verified &= borders_verified;
    if a.json {
        let v = json!({
            "events": rows,
            "distinct": groups.len(),
            "clusters": event_clusters_json(&ev.clusters),
            "border_roots": border_roots,
            "systems": ev.systems,
            "seconds": seconds,
        });
        println!("{}", pretty(&v)?);
    } else {
        println!(
            "{} events ({} distinct: border events seen from several patches joined) from {} \
             systems in {seconds:.2} s ({} clusters, {} roots across patch borders){}",
            ev.events.len(),
            groups.len(),
            ev.systems,
            ev.clusters.len(),
            ev.border_roots.len(),
            if all_verified {
                "; every event re-checked"
            } else {
                "; SOME EVENTS FAILED THEIR RE-CHECK"
            }
        );
        for e in &ev.events {
            println!(
                "r = {:.6}  surface {} patch {}  {:?}{}  (u, v, t) = ({:.4}, {:.4}, {:.4})",
                e.r,
                e.surface,
                e.patch,
                e.kind,
                if e.kind.on_patch_border() {
                    " (patch border)"
                } else {
                    ""
                },
                e.uvt[0],
                e.uvt[1],
                e.uvt[2]
            );
        }
    }
    Ok(crate::out::status(all_verified && ev.clusters.is_empty()))
}

fn load(scene: &str) -> Result<Scene, String> {
    match scene.strip_prefix("builtin:") {
        Some(name) => builtin_scene(name).map_err(|e| e.to_string()),
        None => {
            let file = PathBuf::from(scene);
            scene_from_json(&read(&file)?).map_err(|e| format!("{}: {e}", file.display()))
        }
    }
}

fn run_silhouette(a: SilhouetteArgs) -> Result<ExitCode, String> {
    if !(a.resolution.is_finite() && a.resolution > 0.0) {
        return Err(format!(
            "--resolution must be a positive number, got {}",
            a.resolution
        ));
    }
    if let Some(t) = a.tolerance.filter(|t| !(t.is_finite() && *t > 0.0)) {
        return Err(format!("--tolerance must be a positive number, got {t}"));
    }
    let time_limit = crate::out::time_limit(Some(a.time_limit))?;
    let scene = load(&a.scene)?;
    let opts = SilhouetteOptions::default()
        .with_path(a.path)
        .with_resolution(a.resolution)
        .with_limits(
            Limits::new()
                .with_max_depth(a.max_depth)
                .with_max_boxes(200_000)
                .with_time_limit(time_limit),
        )
        .with_caps(!a.no_caps)
        .with_printed_eq2(a.printed_eq2)
        .with_tolerance(a.tolerance);
    let s = silhouette(&scene, &opts).map_err(|e| e.to_string())?;
    if let Some(file) = &a.svg {
        write(file, geocert::internals::report::sweep::svg(&scene, &s))?;
    }
    // Every ruling re-checked from the scene (module `rulings`), without the solver.
    let verified: Vec<bool> = s
        .rulings
        .iter()
        .map(|r| matches!(verify_ruling(&scene, r, a.printed_eq2), Ok(Ok(_))))
        .collect();
    // And every touch of a cap on a patch border (module `corners`).
    let touches: Vec<bool> = s
        .cap_border_touches
        .iter()
        .map(|x| matches!(verify_cap_border_touch(&scene, x, a.printed_eq2), Ok(true)))
        .collect();
    if a.json {
        println!("{}", pretty(&to_json(&s, &verified, &touches))?);
    } else {
        print_summary(&s, &verified);
    }
    Ok(if verified.iter().chain(&touches).all(|&v| v) {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

fn end_name(e: &ComponentEnd) -> &'static str {
    match e {
        ComponentEnd::Time { upper: false } => "t=a",
        ComponentEnd::Time { upper: true } => "t=b",
        ComponentEnd::Border => "border",
        ComponentEnd::Cluster => "cluster",
    }
}

/// A box as `[[lo, hi], …]` of exact rationals.
fn boxed(b: &[(geocert::num::Rational, geocert::num::Rational)]) -> Value {
    b.iter()
        .map(|(lo, hi)| json!([rational_to_string(lo), rational_to_string(hi)]))
        .collect()
}

/// The events' clusters: where (surface, patch, kind), why, and the box over the system's
/// unknowns (the free parameters among u, v, t, then r).
fn event_clusters_json(
    clusters: &[(usize, usize, EventKind, geocert::solve::Cluster)],
) -> Vec<Value> {
    clusters
        .iter()
        .map(|(surface, patch, kind, c)| {
            json!({
                "surface": surface,
                "patch": patch,
                "kind": kind_json(kind),
                "reason": c.reason,
                "box": boxed(&c.bounds),
            })
        })
        .collect()
}

/// The events' roots across patch borders ([`geocert::sweep::BorderRoot`]), each re-checked;
/// with whether all passed.
fn border_roots_json(scene: &Scene, ev: &Events) -> Result<(Vec<Value>, bool), String> {
    let mut all = true;
    let mut rows = Vec::new();
    for b in &ev.border_roots {
        let verified = verify_border_root(scene, &ev.events, b).map_err(|e| e.to_string())?;
        all &= verified;
        rows.push(json!({
            "surface": b.surface,
            "patch": b.patch,
            "kind": kind_json(&b.kind),
            "cluster": boxed(&b.cluster.bounds),
            "widened": boxed(&b.extended),
            "box": boxed(&b.root.bounds),
            "event": b.event,
            "verified": verified,
        }));
    }
    Ok((rows, all))
}

/// A patch border `(axis, upper)` in the JSON.
fn border_json((axis, upper): (usize, bool)) -> Value {
    let name = ["u", "v"][axis];
    json!({"axis": name, "upper": upper})
}

fn to_json(s: &Silhouettes, verified: &[bool], touches: &[bool]) -> Value {
    json!({
        "path": s.path.to_string(),
        "components": s.components.iter().map(|c| json!({
            "kind": c.kind.name(),
            "type": c.component_type.map(|t| t as u8),
            "surface": c.surface,
            "patches": c.patches,
            "closed": c.closed,
            "ends": c.ends.iter().map(end_name).collect::<Vec<_>>(),
            "extremes": c.extremes,
            "hausdorff_bound_uvt": c.hausdorff_bound,
            "chord_bound": c.chord_bound,
            "ruling": c.ruling,
            "uvt": c.uvt,
            "points": c.points,
        })).collect::<Vec<_>>(),
        "t_extreme": s.t_extreme.iter().map(|x| json!({
            "surface": x.surface,
            "patch": x.patch,
            "component": x.component,
            "box": boxed(&x.root.bounds),
            "approx": x.root.approx,
            "certificate": x.root.certificate,
            "edge": x.edge.map(|(axis, upper)| { let name = ["u", "v"][axis]; json!({"axis": name, "upper": upper}) }),
        })).collect::<Vec<_>>(),
        "corner_crossings": s.corner_crossings.iter().map(|c| json!({
            "surface": c.surface,
            "patch": c.patch,
            "corner": [u8::from(c.corner[0]), u8::from(c.corner[1])],
            "t": [c.t.0.to_string(), c.t.1.to_string()],
            "box": boxed(&c.bounds),
            "monotone_axis": c.monotone_axis,
            "arcs": c.arcs,
        })).collect::<Vec<_>>(),
        "clusters": s.clusters.iter().map(|(surface, patch, kind, c)| json!({
            "surface": surface,
            "patch": patch,
            "kind": kind.name(),
            "reason": c.reason,
            "box": boxed(&c.bounds),
        })).collect::<Vec<_>>(),
        "cap_corner_passages": s.cap_corner_passages.iter().map(|c| json!({
            "surface": c.surface,
            "patch": c.patch,
            "cap": if c.upper { "cap_b" } else { "cap_a" },
            "corner": [u8::from(c.corner[0]), u8::from(c.corner[1])],
            "box": boxed(&c.bounds),
            "monotone_axis": c.monotone_axis,
            "arcs": c.arcs,
        })).collect::<Vec<_>>(),
        "cap_border_touches": s.cap_border_touches.iter().zip(touches).map(|(x, &ok)| json!({
            "surface": x.surface,
            "patch": x.patch,
            "cap": if x.upper { "cap_b" } else { "cap_a" },
            "border": border_json(x.border),
            "along": [x.along.0.to_string(), x.along.1.to_string()],
            "box": boxed(&x.bounds),
            "arcs": x.arcs,
            "verified": ok,
        })).collect::<Vec<_>>(),
        "rulings": s.rulings.iter().zip(verified).map(|(r, &ok)| {
            let (kind, root, g_bound) = match &r.evidence {
                RulingEvidence::Root(root) => ("root", root, None),
                RulingEvidence::Tangent { critical, g_bound, .. } => ("tangent", critical, Some(*g_bound)),
            };
            json!({
                "surface": r.surface,
                "patch": r.patch,
                "component": r.component,
                "evidence": kind,
                "box": boxed(&root.bounds),
                "certificate": root.certificate,
                "g_bound": g_bound,
                "verified": ok,
            })
        }).collect::<Vec<_>>(),
        "extreme_clusters": s.extreme_clusters.len(),
        "patches": s.patches,
        "seconds": s.seconds,
    })
}

fn print_summary(s: &Silhouettes, verified: &[bool]) {
    println!(
        "{} patches, {} components, {} certified t-extreme points, {} passages through patch corners and touches on patch borders, {} clusters ({} path, {:.3} s)",
        s.patches,
        s.components.len(),
        s.t_extreme.len(),
        s.corner_crossings.len() + s.cap_corner_passages.len() + s.cap_border_touches.len(),
        s.clusters.len() + s.extreme_clusters.len(),
        s.path,
        s.seconds
    );
    for (i, c) in s.components.iter().enumerate() {
        let kind = match c.component_type {
            Some(t) => format!("{} type {}", c.kind.name(), t as u8),
            None => c.kind.name().to_string(),
        };
        let shape = if c.closed {
            "closed".to_string()
        } else {
            format!("{} → {}", end_name(&c.ends[0]), end_name(&c.ends[1]))
        };
        let ruling = match c.ruling {
            Some(r) => {
                let how = match &s.rulings[r].evidence {
                    RulingEvidence::Root(_) => "a certified ruling".to_string(),
                    RulingEvidence::Tangent { g_bound, .. } => {
                        format!("a tangential ruling (|G| ≤ {g_bound:.1e} at the critical point)")
                    }
                };
                let check = if verified[r] {
                    "re-checked"
                } else {
                    "FAILED its re-check"
                };
                format!(", {how}, {check}")
            }
            None => String::new(),
        };
        println!(
            "  component {i}: {kind}, surface {}, {} points, {shape}, {} t-extreme, chords within {:.1e}{ruling}",
            c.surface,
            c.points.len(),
            c.extremes.len(),
            c.chord_bound
        );
    }
}
