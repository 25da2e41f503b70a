//! The polygonisation campaign: a sphere and a gyroid on 256³ grids through the fast path
//! (timed, checked for manifoldness), the same fields on 48³ grids through both paths
//! (identical triangle structure), and VTK's flying edges and marching cubes on the same
//! volumes in the same run when `.venv-peers` has VTK.

use super::campaign::median;
use crate::mc::grid::{extract_exact, extract_fast, extract_fast_parallel, Volume};
use crate::num::rational_from_f64;
use serde::Serialize;
use std::path::Path;
use std::time::Instant;

/// One volume's results.
#[derive(Clone, Debug, Serialize)]
pub struct GridRow {
    pub name: String,
    pub n: usize,
    pub cells: usize,
    pub triangles: usize,
    pub ambiguous_cells: usize,
    /// Median seconds of the fast extraction.
    pub seconds: f64,
    /// Boundary edges of the mesh (0: closed), or the manifold check's error.
    pub manifold: Result<usize, String>,
    pub euler: i64,
    /// On the 48³ version: exact and fast give the same triangles.
    pub exact_agrees: bool,
    pub exact_seconds_48: f64,
    /// VTK: (version, flying-edges seconds, triangles, marching-cubes seconds, triangles).
    pub vtk: Result<(String, f64, usize, f64, usize), String>,
    /// geocert in slabs on all cores: (threads, slabs, median seconds, the serial mesh).
    pub parallel: (usize, usize, f64, bool),
    /// vtkFlyingEdges3D on its threaded backend with as many threads: median seconds.
    pub vtk_threaded: Result<f64, String>,
}

/// The campaign.
#[derive(Clone, Debug, Serialize)]
pub struct GridCampaign {
    pub runs: usize,
    pub rows: Vec<GridRow>,
}

fn field(name: &str, n: usize) -> (Vec<f32>, f32) {
    let c = (n - 1) as f64 / 2.0;
    let mut v = Vec::with_capacity(n * n * n);
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let (x, y, z) = (i as f64, j as f64, k as f64);
                v.push(match name {
                    "sphere" => ((x - c).powi(2) + (y - c).powi(2) + (z - c).powi(2)).sqrt() as f32,
                    _ => {
                        // Gyroid with a period of 32 voxels at 256³ (scaled with n).
                        let s = std::f64::consts::TAU * 8.0 / n as f64;
                        let (x, y, z) = (x * s, y * s, z * s);
                        (x.sin() * y.cos() + y.sin() * z.cos() + z.sin() * x.cos()) as f32
                    }
                });
            }
        }
    }
    let iso = if name == "sphere" {
        0.39 * n as f32
    } else {
        0.0
    };
    (v, iso)
}

/// Runs `benches/peers/vtk_isosurface.py` on the volume (`threads > 1`: flying edges alone
/// on VTK's threaded backend) and returns its JSON.
pub(super) fn vtk_script(
    root: &Path,
    data: &[f32],
    n: usize,
    iso: f32,
    runs: usize,
    threads: usize,
) -> Result<serde_json::Value, String> {
    debug_assert_eq!(data.len(), n * n * n, "a cube of samples");
    let python = root.join(".venv-peers/bin/python");
    if !python.exists() {
        return Err("`.venv-peers` not found (run benches/peers/setup.sh)".into());
    }
    let file = std::env::temp_dir().join(format!(
        "geocert-vtk-{}-{n}-{threads}.raw",
        std::process::id()
    ));
    let bytes: Vec<u8> = data.iter().flat_map(|x| x.to_le_bytes()).collect();
    std::fs::write(&file, bytes).map_err(|e| e.to_string())?;
    let mut cmd = std::process::Command::new(python);
    cmd.arg(root.join("benches/peers/vtk_isosurface.py"))
        .arg(&file)
        .args([n, n, n].map(|d| d.to_string()))
        .arg(iso.to_string())
        .arg(runs.to_string());
    if threads > 1 {
        cmd.arg(threads.to_string());
    }
    let out = cmd.output();
    let _ = std::fs::remove_file(&file);
    super::peer_json(out)
}

/// vtkFlyingEdges3D with `threads` threads (STDThread backend): median seconds.
fn vtk_threaded_run(
    root: &Path,
    data: &[f32],
    n: usize,
    iso: f32,
    runs: usize,
    threads: usize,
) -> Result<f64, String> {
    let v = vtk_script(root, data, n, iso, runs, threads)?;
    v["flying_edges"]["median_s"]
        .as_f64()
        .ok_or_else(|| "no flying_edges.median_s".into())
}

fn vtk_run(
    root: &Path,
    data: &[f32],
    n: usize,
    iso: f32,
    runs: usize,
) -> Result<(String, f64, usize, f64, usize), String> {
    let v = vtk_script(root, data, n, iso, runs, 1)?;
    let get = |k: &str, f: &str| v[k][f].as_f64().ok_or_else(|| format!("no {k}.{f}"));
    Ok((
        v["version"].as_str().unwrap_or("?").to_string(),
        get("flying_edges", "median_s")?,
        get("flying_edges", "triangles")? as usize,
        get("marching_cubes", "median_s")?,
        get("marching_cubes", "triangles")? as usize,
    ))
}

/// Runs the campaign at `n`³ (256 in the report), `runs` timed repetitions.
pub fn grid_campaign(root: &Path, n: usize, runs: usize) -> GridCampaign {
    let mut rows = Vec::new();
    for name in ["sphere", "gyroid"] {
        let (data, iso) = field(name, n);
        let vol = Volume::new([n, n, n], data.iter().map(|&x| x as f64).collect()).expect("dims");
        // Rounds alternate one geocert extraction and one VTK run (flying edges, then
        // marching cubes, in a fresh interpreter), so that both see the same drift of this
        // shared machine; the medians over the rounds are reported.
        let mut times = Vec::new();
        let mut last = None;
        let (mut fe, mut mc) = (Vec::new(), Vec::new());
        let mut vtk: Result<(String, f64, usize, f64, usize), String> = Err(String::new());
        for _ in 0..runs.max(1) {
            let t = Instant::now();
            let r = extract_fast(&vol, iso as f64).expect("finite");
            times.push(t.elapsed().as_secs_f64());
            last = Some(r);
            if vtk.as_ref().is_err_and(|e| !e.is_empty()) {
                continue;
            }
            vtk = vtk_run(root, &data, n, iso, 1);
            if let Ok(v) = &vtk {
                fe.push(v.1);
                mc.push(v.3);
            }
        }
        times.sort_by(f64::total_cmp);
        let vtk = vtk.map(|(version, _, fe_tris, _, mc_tris)| {
            (
                version,
                median(fe.clone()),
                fe_tris,
                median(mc.clone()),
                mc_tris,
            )
        });
        let (mesh, stats) = last.expect("one run");
        // Slabs on all cores, interleaved with VTK's threaded flying edges.
        let threads = std::thread::available_parallelism().map_or(1, |t| t.get());
        let slabs = 2 * threads;
        let (mut par_times, mut vtk_t) = (Vec::new(), Vec::new());
        let mut same = true;
        let mut vtk_threaded: Result<f64, String> = Err("not run (one core)".into());
        for _ in 0..runs.max(1) {
            let t = Instant::now();
            let r = extract_fast_parallel(&vol, iso as f64, slabs).expect("finite");
            par_times.push(t.elapsed().as_secs_f64());
            same &= r.0 == mesh;
            if threads > 1 {
                vtk_threaded = vtk_threaded_run(root, &data, n, iso, 1, threads);
                if let Ok(s) = &vtk_threaded {
                    vtk_t.push(*s);
                }
            }
        }
        let vtk_threaded = vtk_threaded.map(|_| median(vtk_t));
        // Both paths on the 48³ version of the field.
        let (small, small_iso) = field(name, 48);
        let small_f: Vec<f64> = small.iter().map(|&x| x as f64).collect();
        let (fast_small, _) = extract_fast(
            &Volume::new([48; 3], small_f.clone()).expect("dims"),
            small_iso as f64,
        )
        .expect("finite");
        let q: Vec<_> = small_f
            .iter()
            .map(|&x| rational_from_f64(x, "v").expect("finite"))
            .collect();
        let t = Instant::now();
        let exact = extract_exact(
            &Volume::new([48; 3], q).expect("dims"),
            &rational_from_f64(small_iso as f64, "iso").expect("finite"),
        );
        let exact_seconds_48 = t.elapsed().as_secs_f64();
        rows.push(GridRow {
            name: name.into(),
            n,
            cells: stats.cells,
            triangles: mesh.triangles.len(),
            ambiguous_cells: stats.ambiguous_cells,
            seconds: times[times.len() / 2],
            manifold: mesh.check_manifold().map_err(|e| e.to_string()),
            euler: mesh.euler_characteristic(),
            exact_agrees: exact.triangles == fast_small.triangles,
            exact_seconds_48,
            vtk,
            parallel: (threads, slabs, median(par_times), same),
            vtk_threaded,
        });
    }
    GridCampaign {
        runs: runs.max(1),
        rows,
    }
}

/// Whether every check held.
pub fn grid_ok(c: &GridCampaign) -> bool {
    c.rows
        .iter()
        .all(|r| r.exact_agrees && r.manifold.is_ok() && r.parallel.3)
}
