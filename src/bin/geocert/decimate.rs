//! `geocert decimate` and `geocert undecimate`: node decimation and exact undecimation
//! (Krivograd et al.).

use crate::out::{choice, read_bytes, status};
use geocert::decimate::{
    BorderPolicy, Criterion, Fit, History, Options, ProjectionChoice, Stage, Target,
};
use geocert::mesh::{Format, Mesh, MeshError};
use geocert::Path;
use std::path::{Path as FsPath, PathBuf};
use std::process::ExitCode;

#[derive(clap::Args)]
pub(crate) struct Args {
    input: String,
    /// Keep this fraction of the surface's nodes (default 0.01 unless --nodes or
    /// --max-error). Vertices no triangle uses are carried through and not counted.
    #[arg(long, conflicts_with_all = ["nodes", "max_error"])]
    keep: Option<f64>,
    /// Keep this many of the surface's nodes (vertices no triangle uses not counted).
    #[arg(long, conflicts_with = "max_error")]
    nodes: Option<usize>,
    /// Remove nodes while their evaluation value is at most this.
    #[arg(long)]
    max_error: Option<f64>,
    /// How nodes are evaluated: `auto` is `error` on height fields and planar meshes (holes
    /// cut in the xy plane) and `quadric` (accumulated error) on surfaces in 3-D.
    #[arg(long, default_value_t = Criterion::Auto, value_parser = choice::<Criterion>(Criterion::NAMES))]
    criterion: Criterion,
    #[arg(long, default_value_t = Path::Fast, value_parser = choice::<Path>(Path::NAMES))]
    path: Path,
    /// The decimated mesh (.ply, .obj, .stl or .vtk).
    #[arg(long)]
    out: PathBuf,
    /// The history file that undecimates OUT.
    #[arg(long)]
    history: PathBuf,
    /// The nodal scalar field: a PLY vertex property or VTK POINT_DATA array name.
    #[arg(long)]
    scalar: Option<String>,
    /// Border nodes: `keep` never removes them, `outline` only while the border stays
    /// exactly the same (collinear nodes; in the xy plane for height fields and planar
    /// meshes), `simplify` removes them like interior ones (the border's error measured),
    /// `auto` is `outline` in the xy plane and `simplify` on surfaces in 3-D.
    #[arg(long, default_value_t = BorderPolicy::Auto, value_parser = choice::<BorderPolicy>(BorderPolicy::NAMES))]
    border: BorderPolicy,
    /// The same as `--border keep` (kept for older scripts).
    #[arg(long, hide = true, conflicts_with = "border")]
    exclude_border: bool,
    /// Rounds of fitting the kept nodes to the original vertices after the last removal
    /// (least squares; no triangle flips; the history records the moves, so undecimation
    /// stays exact): `auto` is 2 on surfaces in 3-D and 0 on height fields and planar
    /// meshes (their nodes stay where they are).
    #[arg(long, default_value_t = Fit::Auto, value_parser = |s: &str| s.parse::<Fit>().map_err(|e| e.to_string()))]
    fit: Fit,
    /// Allow triangles that face against the original surface nearest them (by default, on
    /// surfaces in 3-D, every criterion refuses removals and fit moves that make one, at the
    /// cost of a closest-point search per new triangle).
    #[arg(long)]
    allow_facing_against: bool,
    /// Skip measuring the result against the input (the JSON's error fields are then null).
    #[arg(long)]
    no_measure: bool,
    #[arg(long, default_value_t = ProjectionChoice::Auto, value_parser = choice::<ProjectionChoice>(ProjectionChoice::NAMES))]
    projection: ProjectionChoice,
    /// The constant k of eq. (1): m = n/k intervals.
    #[arg(long, default_value_t = 10)]
    k: usize,
    /// Keep the paper's interval boundaries fixed from the initial range (default:
    /// re-bin the queue when re-evaluated values outgrow it).
    #[arg(long)]
    fixed_intervals: bool,
    /// Re-evaluate a removed node's neighbours at once, as the paper does (default:
    /// lazily, when they reach the front of the queue).
    #[arg(long)]
    eager: bool,
    /// Do not evaluate the nodes the loop takes next on a second thread (the fast path's
    /// default when the machine has two cores or more; the result is the same). With
    /// RAYON_NUM_THREADS=1 everything runs on one thread.
    #[arg(long)]
    no_look_ahead: bool,
    /// Split every bow-tie or pinched vertex (where more than one fan of triangles meets, as
    /// in many range maps) into one vertex per fan before decimating: the copies, at the
    /// same place, are appended after the input's vertices, and undecimation restores this
    /// split mesh.
    #[arg(long)]
    split_bowties: bool,
    #[arg(long)]
    json: bool,
}

#[derive(clap::Args)]
pub(crate) struct DeviationArgs {
    /// The original surface (.ply, .obj, .stl or .vtk).
    original: PathBuf,
    /// The simplified surface, by any program.
    simplified: PathBuf,
    #[arg(long)]
    json: bool,
}

#[derive(clap::Args)]
pub(crate) struct UndoArgs {
    input: PathBuf,
    #[arg(long)]
    history: PathBuf,
    #[arg(long)]
    steps: Option<usize>,
    #[arg(long)]
    out: PathBuf,
}

pub(crate) fn run(a: Args) -> Result<ExitCode, String> {
    let wall = std::time::Instant::now();
    let target = match (a.keep, a.nodes, a.max_error) {
        (_, Some(n), _) => Target::Nodes(n),
        (_, _, Some(e)) => Target::ErrorBound(e),
        (k, _, _) => Target::Keep(k.unwrap_or(0.01)),
    };
    let options = Options::new()
        .with_criterion(a.criterion)
        .with_target(target)
        .with_border(if a.exclude_border {
            BorderPolicy::Exclude
        } else {
            a.border
        })
        .with_projection(a.projection)
        .with_fit(a.fit)
        .with_facing(!a.allow_facing_against)
        .with_k(a.k)
        .with_rebin(!a.fixed_intervals)
        .with_lazy(!a.eager)
        .with_look_ahead(!a.no_look_ahead)
        .with_path(a.path);
    let format = Format::from_path(&a.out).map_err(|e| e.to_string())?;
    let mut mesh = decimation_input(&a.input, a.scalar.as_deref())?;
    let (input, out, history, json) = (&a.input, &a.out, &a.history, a.json);
    let mut copies = 0;
    if a.split_bowties {
        let split = geocert::mesh::split::split_pinched(&mesh);
        copies = split.copied_from.len();
        mesh = split.mesh;
    }
    let result = geocert::decimate::decimate(&mesh, &options).map_err(|e| {
        let hint = match &e {
            geocert::decimate::DecimateError::Mesh(MeshError::PinchedVertex { .. })
                if !a.split_bowties =>
            {
                " (--split-bowties splits such vertices into one per fan)"
            }
            _ => "",
        };
        format!("{input}: {e}{hint}")
    })?;
    // Height fields and planar meshes: errors at the same xy position; other surfaces: the
    // distance to the decimated surface and the scalar at the closest point.
    let measure = std::time::Instant::now();
    let errors = match (a.no_measure, result.stats.projection_xy) {
        (true, _) => None,
        (false, true) => Some(geocert::decimate::quality::xy_errors(&mesh, &result.mesh)),
        (false, false) => Some(geocert::decimate::quality::surface_errors(
            &mesh,
            &result.mesh,
        )),
    };
    let measure_seconds = measure.elapsed().as_secs_f64();
    // The history goes to a temporary file first so that a failing mesh write leaves nothing.
    let mut tmp = history.as_os_str().to_owned();
    tmp.push(".geocert-history-partial");
    let tmp = std::path::PathBuf::from(tmp);
    std::fs::write(&tmp, result.history.to_bytes())
        .map_err(|e| format!("{}: {e}", history.display()))?;
    if let Err(e) = result.mesh.write(out, format) {
        let _ = std::fs::remove_file(&tmp);
        return Err(e.to_string());
    }
    std::fs::rename(&tmp, history).map_err(|e| format!("{}: {e}", history.display()))?;
    let s = &result.stats;
    if json {
        let v = serde_json::json!({
            "nodes_in": s.nodes_in,
            "nodes_out": s.nodes_out,
            "unused_vertices": s.unused,
            "target_nodes": s.target_nodes,
            "bowtie_copies": copies,
            "triangles_out": s.triangles_out,
            "seconds": s.seconds,
            "measure_seconds": errors.map(|_| measure_seconds),
            "wall_seconds": wall.elapsed().as_secs_f64(),
            "criterion": s.criterion,
            "border": s.border,
            "max_scalar_error": errors.and_then(|e| e.max_scalar),
            "max_height_error": errors.filter(|_| s.projection_xy).map(|e| e.max_height),
            "max_distance_error": errors.filter(|_| !s.projection_xy).map(|e| e.max_height),
            "rms_distance_error": errors.filter(|_| !s.projection_xy).map(|e| e.rms_height),
            "removed": s.removed,
            "refused": s.refused,
            "deferred": s.deferred,
            "fan_filled": s.fan_filled,
            "blocked": s.blocked,
            "intervals": s.intervals,
            "rebuilds": s.rebuilds,
            "evaluations": s.evaluations,
            "taken": s.taken,
            "evaluated_ahead": s.evaluated_ahead,
            "remembered": s.remembered,
            "setup_seconds": s.setup_seconds,
            "fit_rounds": s.fit_rounds,
            "moved": s.moved,
            "fit_seconds": s.fit_seconds,
            "projection": if s.projection_xy { "xy" } else { "per-fan" },
        });
        println!("{v}");
    } else {
        println!(
            "{} → {} nodes, {} → {} triangles in {:.3} s ({} removals refused, {} nodes fitted); history: {} steps",
            s.nodes_in,
            s.nodes_out,
            s.triangles_in,
            s.triangles_out,
            s.seconds,
            s.refused,
            s.moved,
            result.history.len()
        );
        if copies > 0 {
            println!(
                "{copies} copies of bow-tie or pinched vertices appended (undecimation restores the split mesh)"
            );
        }
        if let Some(t) = s.target_nodes.filter(|&t| s.nodes_out > t) {
            let border = result.mesh.border_vertices().iter().filter(|&&b| b).count();
            print!("stopped above the target of {t} nodes: no further removal was valid");
            if let Some(b) = &s.blocked {
                print!(" ({})", blocked_reasons(b));
            }
            if s.border == "outline" && border > 0 {
                print!(
                    "; {border} kept nodes are on the border, whose outline --border outline keeps exactly (--border simplify or --projection per-fan removes border nodes with measured error)"
                );
            }
            println!();
        }
        if s.unused > 0 {
            println!(
                "{} vertices in no triangle carried through (not counted by --keep or --nodes)",
                s.unused
            );
        }
        let what = if s.projection_xy {
            "height error"
        } else {
            "distance to the decimated surface"
        };
        if let Some(errors) = errors {
            print!("max {what} {:.6e}", errors.max_height);
            if let Some(m) = errors.max_scalar {
                print!(", max scalar error {m:.6e}");
            }
            println!(" (measured in {measure_seconds:.3} s)");
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// Reads a mesh file or builds a built-in input (`builtin:grid:SIDE`, `builtin:plate`).
fn decimation_input(input: &str, scalar: Option<&str>) -> Result<Mesh, String> {
    use geocert::decimate::data;
    if let Some(rest) = input.strip_prefix("builtin:") {
        return match rest.split(':').collect::<Vec<_>>().as_slice() {
            ["plate"] => Ok(data::paper_plate()),
            ["grid", side] => {
                let side: usize = side
                    .parse()
                    .map_err(|_| format!("{input}: grid side {side:?} is not a number"))?;
                if !(2..=4000).contains(&side) {
                    return Err(format!("{input}: grid side must be in 2..=4000"));
                }
                Ok(data::height_grid(side))
            }
            _ => Err(format!(
                "{input}: unknown built-in (builtin:grid:SIDE or builtin:plate)"
            )),
        };
    }
    let path = FsPath::new(input);
    if matches!(Format::from_path(path), Ok(Format::Stl)) {
        // STL soups from CAD often carry slivers whose corners weld together: skipped, said.
        let bytes = read_bytes(path)?;
        let (mesh, dropped) = geocert::mesh::stl::read_dropping_slivers(&bytes)
            .map_err(|e| format!("{input}: {e}"))?;
        if dropped > 0 {
            eprintln!("{input}: skipped {dropped} facets with two equal corners (no area)");
        }
        return Ok(mesh);
    }
    Mesh::read(path, scalar).map_err(|e| e.to_string())
}

pub(crate) fn undo(a: UndoArgs) -> Result<ExitCode, String> {
    let (input, history, steps, out) = (&a.input, &a.history, a.steps, &a.out);
    let format = Format::from_path(out).map_err(|e| e.to_string())?;
    let bytes = read_bytes(history)?;
    let h = History::from_bytes(&bytes).map_err(|e| format!("{}: {e}", history.display()))?;
    let name = h.has_scalars.then_some(h.scalar_name.as_str());
    let mesh = Mesh::read(input, name).map_err(|e| e.to_string())?;
    let mut stage =
        Stage::decimated(&mesh, &h).map_err(|e| format!("{}: {e}", history.display()))?;
    let n = steps.unwrap_or(h.len());
    if n > h.len() {
        return Err(format!(
            "--steps {n}: the history has only {} steps",
            h.len()
        ));
    }
    let clock = std::time::Instant::now();
    // Any undo starts by putting the fit's moved nodes back.
    if n > 0 && stage.fitted {
        stage.undo(&h).map_err(|e| e.to_string())?;
    }
    for _ in 0..n {
        stage.undo(&h).map_err(|e| e.to_string())?;
    }
    let seconds = clock.elapsed().as_secs_f64();
    let back = stage.to_mesh();
    let exact = stage.applied == 0
        && geocert::decimate::history::fingerprint(&back) == h.original_fingerprint;
    back.write(out, format).map_err(|e| e.to_string())?;
    println!(
        "undid {n} of {} steps in {seconds:.3} s: {} nodes, {} triangles{}",
        h.len(),
        back.vertices.len(),
        back.triangles.len(),
        if stage.applied == 0 {
            if exact {
                "; identical to the original (fingerprint)"
            } else {
                "; DIFFERS from the original's fingerprint"
            }
        } else {
            ""
        }
    );
    Ok(status(stage.applied != 0 || exact))
}

pub(crate) fn deviation(a: DeviationArgs) -> Result<ExitCode, String> {
    let original = Mesh::read(&a.original, None).map_err(|e| e.to_string())?;
    let simplified = Mesh::read(&a.simplified, None).map_err(|e| e.to_string())?;
    let clock = std::time::Instant::now();
    let d = geocert::decimate::quality::deviation(&original, &simplified);
    let seconds = clock.elapsed().as_secs_f64();
    if a.json {
        let mut v = serde_json::to_value(d).map_err(|e| e.to_string())?;
        v["triangles"] = simplified.triangles.len().into();
        v["vertices"] = simplified.vertices.len().into();
        v["seconds"] = seconds.into();
        println!("{v}");
    } else {
        println!(
            "{} triangles: Hausdorff {:.4} % of the diagonal (original → simplified max {:.4} %, rms {:.4} %; back max {:.4} %, rms {:.4} %), {} flipped triangles ({} points in {seconds:.3} s)",
            simplified.triangles.len(),
            d.percent(d.hausdorff),
            d.percent(d.forward_max),
            d.percent(d.forward_rms),
            d.percent(d.backward_max),
            d.percent(d.backward_rms),
            d.flipped,
            d.samples
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// The nonzero counts of a [`Blocked`](geocert::decimate::Blocked), in words.
fn blocked_reasons(b: &geocert::decimate::Blocked) -> String {
    let parts = [
        (b.no_plane, "no axis plane holds the hole"),
        (b.fold, "would fold the surface over"),
        (b.facing, "would face against the original surface"),
        (b.topology, "would repeat an edge of the mesh"),
        (b.border, "kept by the border policy"),
        (b.valence, "over the valence limit"),
        (b.removable, "removable"),
    ];
    let said: Vec<String> = parts
        .iter()
        .filter(|(n, _)| *n > 0)
        .map(|(n, why)| format!("{n} {why}"))
        .collect();
    format!("of the nodes left: {}", said.join(", "))
}
