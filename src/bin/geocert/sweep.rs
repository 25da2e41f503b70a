//! `geocert sweep silhouette`: the perspective silhouette of a swept volume (Seong et al.).

use crate::out::{choice, pretty, read, write};
use clap::Subcommand;
use geocert::bernstein::Limits;
use geocert::num::rational_to_string;
use geocert::sweep::{
    builtin_scene, scene_from_json, silhouette, ComponentEnd, Scene, SilhouetteOptions, Silhouettes,
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
}

#[derive(clap::Args)]
pub(crate) struct SilhouetteArgs {
    /// A scene JSON file (`{"surfaces": [...], "t": [a, b], "motion": {...}, "eye": ...}`), or
    /// `builtin:NAME` (sphere-line, sphere-cone, ellipsoid-line, ellipsoid-turn, tuba).
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
    }
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
    if a.json {
        println!("{}", pretty(&to_json(&s))?);
    } else {
        print_summary(&s);
    }
    Ok(ExitCode::SUCCESS)
}

fn end_name(e: &ComponentEnd) -> &'static str {
    match e {
        ComponentEnd::Time { upper: false } => "t=a",
        ComponentEnd::Time { upper: true } => "t=b",
        ComponentEnd::Border => "border",
        ComponentEnd::Cluster => "cluster",
    }
}

fn to_json(s: &Silhouettes) -> Value {
    let boxed = |b: &[(geocert::num::Rational, geocert::num::Rational)]| -> Value {
        b.iter()
            .map(|(lo, hi)| json!([rational_to_string(lo), rational_to_string(hi)]))
            .collect()
    };
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
        })).collect::<Vec<_>>(),
        "clusters": s.clusters.iter().map(|(surface, patch, kind, c)| json!({
            "surface": surface,
            "patch": patch,
            "kind": kind.name(),
            "reason": c.reason,
            "box": boxed(&c.bounds),
        })).collect::<Vec<_>>(),
        "extreme_clusters": s.extreme_clusters.len(),
        "patches": s.patches,
        "seconds": s.seconds,
    })
}

fn print_summary(s: &Silhouettes) {
    println!(
        "{} patches, {} components, {} certified t-extreme points, {} clusters ({} path, {:.3} s)",
        s.patches,
        s.components.len(),
        s.t_extreme.len(),
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
        println!(
            "  component {i}: {kind}, surface {}, {} points, {shape}, {} t-extreme, chords within {:.1e}",
            c.surface,
            c.points.len(),
            c.extremes.len(),
            c.chord_bound
        );
    }
}
