//! `reports/diamond.md`: the diamond proofs at the report's sizes, the fast error against the
//! exact one, partial DMVs by error and by isovalues (the shape of Tables 2 and 3) with Table
//! 1's sizes, selective refinement rates on the three DMV encodings with the two fronts (Table
//! 4), adaptive isosurfaces against OpenVDB and VTK, and 2-D refinement against pymartini.

use super::RunMeta;
use crate::decimate::quality::ClosestPoints;
use crate::diamond::{
    builtin_volume, check_conforming, diamond_stats_exact, diamond_stats_fast, marching_tetrahedra,
    simplices_stats_exact, DiamondFront, DmvAccess, DmvSummary, Field, Front, FullDmv, Lod,
    Refiner, Selection, Simplex, SupercubeDmv, SupercubeFront,
};
use crate::mc::grid::{extract_fast, Volume};
use crate::num::rational_to_f64;
use crate::proofs::{self, ProofOutcome};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path as FsPath, PathBuf};
use std::time::Instant;

/// Timed repetitions for medians.
const RUNS: usize = 5;

/// Timed repetitions of Table 4's refinements (tenths of a second each on this machine, whose
/// timings vary by ±10 % from run to run).
const REFINE_RUNS: usize = 9;

/// A volume of the campaign.
struct Input {
    name: String,
    field: Field<3>,
}

/// The exact error against the fast interval on one volume.
#[derive(Clone, Debug, Serialize)]
pub struct ErrorCheck {
    pub volume: String,
    pub diamonds: usize,
    pub contained: usize,
    pub ranges_equal: usize,
    pub max_width: f64,
}

/// Building `Δf` (every diamond's certified error and range).
#[derive(Clone, Debug, Serialize)]
pub struct BuildRow {
    pub volume: String,
    pub dims: Vec<usize>,
    pub padded: usize,
    pub grid_points: usize,
    pub seconds: f64,
}

/// One partial DMV.
#[derive(Clone, Debug, Serialize)]
pub struct DmvRow {
    pub volume: String,
    pub criterion: String,
    pub summary: DmvSummary,
    pub file_bytes: usize,
    pub file_round_trip: bool,
}

/// One refinement query on one encoding with one front.
#[derive(Clone, Debug, Serialize)]
pub struct RefineRow {
    pub volume: String,
    pub dmv: String,
    pub front: String,
    pub visited: u64,
    pub median_seconds: f64,
    pub per_second: f64,
    /// `Σs` rows: the median over the interleaved rounds of this row's time over the `Σd`
    /// row's on the same encoding.
    pub against_diamond_front: Option<f64>,
    pub simplices: usize,
    pub front_bytes: u64,
    pub bytes_per_simplex: f64,
    pub conforming: bool,
    pub same_mesh: bool,
}

/// One isosurface method on one volume.
#[derive(Clone, Debug, Serialize)]
pub struct SurfaceRow {
    pub volume: String,
    pub iso: f64,
    pub method: String,
    pub median_seconds: Option<f64>,
    pub triangles: usize,
    /// The largest distance of the method's vertices from the full-resolution surface, and
    /// of the full-resolution vertices from the method's surface (grid units).
    pub distance: Option<(f64, f64)>,
    pub closed: Option<bool>,
    pub note: String,
}

/// 2-D refinement against pymartini.
#[derive(Clone, Debug, Serialize)]
pub struct MartiniRow {
    pub grid: usize,
    pub threshold: f64,
    pub geocert_build_s: f64,
    pub geocert_refine_s: f64,
    pub geocert_triangles: usize,
    pub geocert_max_error: f64,
    pub martini: Option<(f64, f64, usize)>,
    /// pymartini's mesh's largest interpolation error at the grid points, exactly (measured
    /// by geocert on the triangles pymartini returned).
    pub martini_max_error: Option<f64>,
    /// geocert refined with `ε > pymartini's measured error`: triangles and exact max error.
    pub geocert_at_martini_error: Option<(usize, f64)>,
    pub note: String,
}

/// Everything the report shows.
#[derive(Clone, Debug, Serialize)]
pub struct DiamondCampaign {
    pub proofs: Vec<ProofOutcome>,
    pub error_checks: Vec<ErrorCheck>,
    pub builds: Vec<BuildRow>,
    pub error_dmvs: Vec<DmvRow>,
    pub iso_dmvs: Vec<DmvRow>,
    pub refinement: Vec<RefineRow>,
    pub surfaces: Vec<SurfaceRow>,
    pub martini: Vec<MartiniRow>,
    pub notes: Vec<String>,
}

/// The report's proof sizes: `(d, largest N)`.
pub const REPORT_GRIDS: [(usize, u32); 4] = [(2, 8), (3, 5), (4, 4), (5, 3)];

/// The MNI152 T1 template inside the nilearn wheel in `.venv-peers`, when installed.
pub(super) fn mni_template(root: &FsPath) -> Option<PathBuf> {
    // lib/ holds python3.X/ and, with gmsh, other entries: look in every python one.
    std::fs::read_dir(root.join(".venv-peers/lib"))
        .ok()?
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().starts_with("python"))
        .map(|e| {
            e.path().join(
                "site-packages/nilearn/datasets/data/mni_icbm152_t1_tal_nlin_sym_09a_converted.nii.gz",
            )
        })
        .find(|p| p.exists())
}

/// The real volumes, when installed: the MNI152 T1 template of the nilearn wheel in
/// `.venv-peers`, and mricron-data's ch2better.
fn real_volumes(root: &FsPath, notes: &mut Vec<String>) -> Vec<(String, PathBuf)> {
    let mut out = Vec::new();
    match mni_template(root) {
        Some(p) => out.push(("MNI152 T1 (nilearn)".to_string(), p)),
        None => notes.push(
            "MNI152 T1 template not available (nilearn is installed into .venv-peers by benches/peers/setup.sh)"
                .into(),
        ),
    }
    let ch2 = PathBuf::from("/usr/share/mricron/templates/ch2better.nii.gz");
    if ch2.exists() {
        out.push(("ch2better (mricron-data)".to_string(), ch2));
    } else {
        notes.push("ch2better not available (Debian mricron-data, installed by benches/peers/setup.sh as root)".into());
    }
    out
}

/// Vertices measured per distance: every k-th vertex so that at most this many are queried.
const DISTANCE_SAMPLES: usize = 20_000;

/// The largest distance from an evenly strided sample of `from`'s vertices (at most
/// [`DISTANCE_SAMPLES`]) to the surface `to`.
fn sampled_distance(from: &crate::mesh::Mesh, to: &crate::mesh::Mesh) -> f64 {
    let stride = from.vertices.len().div_ceil(DISTANCE_SAMPLES).max(1);
    let sample: Vec<[f64; 3]> = from.vertices.iter().step_by(stride).copied().collect();
    let Some(cp) = ClosestPoints::new(to) else {
        return f64::NAN;
    };
    sample
        .iter()
        .map(|&p| cp.query(p).distance)
        .fold(0.0, f64::max)
}

/// "quads split in two", and where some of the peer's vertices lie outside the sampled box
/// `[0, side]³`, how many and the largest distance to the reference over the others.
fn outside_note(mesh: &crate::mesh::Mesh, reference: &crate::mesh::Mesh, side: f64) -> String {
    let inside: Vec<[f64; 3]> = mesh
        .vertices
        .iter()
        .filter(|p| p.iter().all(|x| (0.0..=side).contains(x)))
        .copied()
        .collect();
    let outside = mesh.vertices.len() - inside.len();
    if outside == 0 {
        return "quads split in two".into();
    }
    let inner = crate::mesh::Mesh {
        vertices: inside,
        triangles: Vec::new(),
        scalars: None,
        normals: None,
    };
    format!(
        "quads split in two; {outside} of {} vertices lie outside the sampled box: OpenVDB \
         closes the surface against the background value beyond the volume, where the \
         full-resolution surface ends open; over the other vertices the max distance to full \
         is {:.3}",
        mesh.vertices.len(),
        sampled_distance(&inner, reference)
    )
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

fn sorted_mesh(mut m: Vec<Simplex<3>>) -> Vec<Simplex<3>> {
    for s in &mut m {
        *s = s.sorted();
    }
    m.sort_unstable();
    m
}

/// Every diamond of a small volume: the fast interval holds the exact error.
fn error_check(name: &str, field: &Field<3>) -> ErrorCheck {
    let hier = field.hierarchy();
    let (mut n, mut contained, mut ranges, mut width) = (0, 0, 0, 0.0f64);
    for i in 0..field.values().len() {
        let Ok(d) = hier.diamond(field.point(i)) else {
            continue;
        };
        let fast = diamond_stats_fast(field, &d);
        let exact = diamond_stats_exact(field, &d);
        let e = rational_to_f64(&exact.error);
        n += 1;
        contained += usize::from(fast.error_lo <= e && e <= fast.error_hi);
        ranges += usize::from(fast.min == exact.min && fast.max == exact.max);
        width = width.max(fast.error_hi - fast.error_lo);
    }
    ErrorCheck {
        volume: name.into(),
        diamonds: n,
        contained,
        ranges_equal: ranges,
        max_width: width,
    }
}

fn value_bytes(field: &Field<3>) -> u64 {
    if field.values().iter().all(|&v| f64::from(v as f32) == v) {
        4
    } else {
        8
    }
}

fn dmv_row(volume: &str, criterion: String, dmv: &FullDmv<3>, sel: &Selection<3>) -> DmvRow {
    let ds = dmv.supercube_encoding(sel);
    let bytes = ds.to_bytes();
    let back = SupercubeDmv::<3>::from_bytes(&bytes).map(|b| b.to_bytes() == bytes);
    DmvRow {
        volume: volume.into(),
        criterion,
        summary: dmv.summary(sel, &ds, value_bytes(dmv.field())),
        file_bytes: bytes.len(),
        file_round_trip: back == Ok(true),
    }
}

/// One timed refinement: its seconds, and its visited count, mesh and front bytes (`None`
/// when it failed).
type RefineRun = (f64, Option<(u64, Vec<Simplex<3>>, u64)>);

/// Refines once on `dmv` with front `F`, timed; the counts and mesh only when `keep` (the
/// last round: reading out a mesh of millions of simplices every round would be wasted).
fn refine_once<A: DmvAccess<3>, F: Front<3>>(dmv: &A, lod: &Lod<3>, keep: bool) -> RefineRun {
    let t = Instant::now();
    let mut r: Refiner<'_, 3, A, F> = Refiner::new(dmv);
    let ok = r.refine(lod).is_ok();
    let secs = t.elapsed().as_secs_f64();
    (
        secs,
        (ok && keep).then(|| (r.visited, r.mesh(), r.front.bookkeeping_bytes())),
    )
}

/// Table 4's six refinements (three encodings × two fronts), interleaved: each of the
/// `REFINE_RUNS` rounds runs all six, starting one further along each round, so that the
/// machine's drift (frequency, other load) falls on all alike. Per row the median time, the
/// last run's mesh and counts, and for `Σs` the median over rounds of its time over `Σd`'s on
/// the same encoding in the same round.
fn refine_rows(
    volume: &str,
    full: &FullDmv<3>,
    iso_sel: &Selection<3>,
    lod: &Lod<3>,
) -> Vec<RefineRow> {
    let ds = full.supercube_encoding(iso_sel);
    let dd = full.diamond_encoding(iso_sel);
    let hier = full.field().hierarchy();
    type Runner<'a> = Box<dyn Fn(bool) -> RefineRun + 'a>;
    let runners: Vec<(&str, &str, Runner<'_>)> = vec![
        (
            "Δf",
            "Σd",
            Box::new(|keep| refine_once::<_, DiamondFront<3>>(full, lod, keep)),
        ),
        (
            "Δf",
            "Σs",
            Box::new(|keep| refine_once::<_, SupercubeFront<3>>(full, lod, keep)),
        ),
        (
            "Δd",
            "Σd",
            Box::new(|keep| refine_once::<_, DiamondFront<3>>(&dd, lod, keep)),
        ),
        (
            "Δd",
            "Σs",
            Box::new(|keep| refine_once::<_, SupercubeFront<3>>(&dd, lod, keep)),
        ),
        (
            "Δs",
            "Σd",
            Box::new(|keep| refine_once::<_, DiamondFront<3>>(&ds, lod, keep)),
        ),
        (
            "Δs",
            "Σs",
            Box::new(|keep| refine_once::<_, SupercubeFront<3>>(&ds, lod, keep)),
        ),
    ];
    let n = runners.len();
    let mut times = vec![Vec::with_capacity(REFINE_RUNS); n];
    let mut last: Vec<Option<(u64, Vec<Simplex<3>>, u64)>> = vec![None; n];
    for round in 0..REFINE_RUNS {
        for k in 0..n {
            let j = (round + k) % n;
            let (secs, result) = (runners[j].2)(round + 1 == REFINE_RUNS);
            times[j].push(secs);
            if result.is_some() {
                last[j] = result;
            }
        }
    }
    let mut rows = Vec::new();
    let mut reference: Option<Vec<Simplex<3>>> = None;
    let mut conformity: Option<bool> = None;
    for (j, (dmv, front, _)) in runners.iter().enumerate() {
        let (visited, mesh, bytes) = last[j].take().unwrap_or((0, Vec::new(), 0));
        let secs = median(times[j].clone());
        let sorted = sorted_mesh(mesh);
        let same = match &reference {
            Some(m) => *m == sorted,
            None => {
                reference = Some(sorted.clone());
                true
            }
        };
        // The first mesh is checked exactly; the others are compared with it simplex for
        // simplex.
        let conforming = match &conformity {
            Some(c) => *c && same,
            None => {
                let c = check_conforming(&hier, &sorted).conforming;
                conformity = Some(c);
                c
            }
        };
        // Σs rows follow their encoding's Σd row.
        let against_diamond_front = (*front == "Σs").then(|| {
            median(
                times[j]
                    .iter()
                    .zip(&times[j - 1])
                    .map(|(s, d)| s / d.max(1e-12))
                    .collect(),
            )
        });
        rows.push(RefineRow {
            volume: volume.into(),
            dmv: (*dmv).into(),
            front: (*front).into(),
            visited,
            median_seconds: secs,
            per_second: visited as f64 / secs.max(1e-12),
            against_diamond_front,
            simplices: sorted.len(),
            front_bytes: bytes,
            bytes_per_simplex: bytes as f64 / sorted.len().max(1) as f64,
            conforming,
            same_mesh: same,
        });
    }
    rows
}

fn write_raw(data: &[f64], tag: &str) -> Result<PathBuf, String> {
    let file = std::env::temp_dir().join(format!("geocert-dmv-{}-{tag}.raw", std::process::id()));
    let bytes: Vec<u8> = data
        .iter()
        .flat_map(|&x| (x as f32).to_le_bytes())
        .collect();
    std::fs::write(&file, bytes).map_err(|e| e.to_string())?;
    Ok(file)
}

/// The adaptive isosurface against OpenVDB (adaptivity 0 and 0.5) and vtkFlyingEdges3D, all
/// measured against geocert's full-resolution marching cubes surface.
fn surface_rows(
    root: &FsPath,
    volume: &str,
    full: &FullDmv<3>,
    iso: f64,
    e: f64,
) -> Vec<SurfaceRow> {
    let field = full.field();
    let n = field.hierarchy().side() as usize + 1;
    let vol = Volume::new([n, n, n], field.values().to_vec()).expect("a cubic grid");
    let mut rows = Vec::new();
    let mut times = Vec::new();
    let mut reference = None;
    for _ in 0..3 {
        let t = Instant::now();
        let r = extract_fast(&vol, iso);
        times.push(t.elapsed().as_secs_f64());
        reference = r.ok();
    }
    let Some((reference, _)) = reference else {
        return rows;
    };
    rows.push(SurfaceRow {
        volume: volume.into(),
        iso,
        method: "geocert mc, full resolution (the reference)".into(),
        median_seconds: Some(median(times)),
        triangles: reference.triangles.len(),
        distance: Some((0.0, 0.0)),
        closed: None,
        note: String::new(),
    });
    // Adaptive: refine (error > e, isovalue in range) + marching tetrahedra on Δf, at 1 % of
    // the value range (the refinement table's query) and at five times that.
    for e in [e, 5.0 * e] {
        let lod = Lod {
            error: Some(e),
            isovalues: vec![iso],
            roi: None,
        };
        let mut times = Vec::new();
        let mut last = None;
        for _ in 0..3 {
            let t = Instant::now();
            let mut r: Refiner<'_, 3, _, SupercubeFront<3>> = Refiner::new(full);
            let ok = r.refine(&lod).is_ok();
            let mesh = r.mesh_near(iso);
            let s = marching_tetrahedra(full, &mesh, iso);
            times.push(t.elapsed().as_secs_f64());
            if ok {
                last = s.ok();
            }
        }
        if let Some(s) = last {
            let d = (
                sampled_distance(&s.mesh, &reference),
                sampled_distance(&reference, &s.mesh),
            );
            rows.push(SurfaceRow {
                volume: volume.into(),
                iso,
                method: format!("geocert Δf + Σs refine (ε > {e:.3}) + marching tetrahedra"),
                median_seconds: Some(median(times)),
                triangles: s.mesh.triangles.len(),
                distance: Some(d),
                closed: Some(s.open_edges == 0),
                note: String::new(),
            });
        }
    }
    let raw = match write_raw(field.values(), "surface") {
        Ok(f) => f,
        Err(e) => {
            rows.push(SurfaceRow {
                volume: volume.into(),
                iso,
                method: "peers".into(),
                median_seconds: None,
                triangles: 0,
                distance: None,
                closed: None,
                note: format!("could not write the volume for the peers: {e}"),
            });
            return rows;
        }
    };
    for adaptivity in [0.0, 0.5] {
        let out = std::env::temp_dir().join(format!("geocert-vdb-{}.ply", std::process::id()));
        let run = std::process::Command::new("/usr/bin/python3")
            .arg(root.join("benches/peers/openvdb_mesh.py"))
            .arg(&raw)
            .args([n, n, n].map(|d| d.to_string()))
            .arg(iso.to_string())
            .arg(adaptivity.to_string())
            .arg("3")
            .arg(&out)
            .output();
        let row = super::peer_json(run).and_then(|v| {
            let mesh = crate::mesh::Mesh::read(&out, None).map_err(|e| e.to_string())?;
            Ok((v, mesh))
        });
        let _ = std::fs::remove_file(&out);
        rows.push(match row {
            Ok((v, mesh)) => SurfaceRow {
                volume: volume.into(),
                iso,
                method: format!(
                    "OpenVDB {} volumeToMesh, adaptivity {adaptivity}",
                    v["version"].as_str().unwrap_or("?")
                ),
                median_seconds: v["median_s"].as_f64(),
                triangles: mesh.triangles.len(),
                distance: Some((
                    sampled_distance(&mesh, &reference),
                    sampled_distance(&reference, &mesh),
                )),
                closed: None,
                note: outside_note(&mesh, &reference, (n - 1) as f64),
            },
            Err(e) => SurfaceRow {
                volume: volume.into(),
                iso,
                method: format!("OpenVDB volumeToMesh, adaptivity {adaptivity}"),
                median_seconds: None,
                triangles: 0,
                distance: None,
                closed: None,
                note: format!("not available: {e}"),
            },
        });
    }
    let python = root.join(".venv-peers/bin/python");
    let vtk = std::process::Command::new(python)
        .arg(root.join("benches/peers/vtk_isosurface.py"))
        .arg(&raw)
        .args([n, n, n].map(|d| d.to_string()))
        .arg(iso.to_string())
        .arg("3")
        .output();
    rows.push(match super::peer_json(vtk) {
        Ok(v) => SurfaceRow {
            volume: volume.into(),
            iso,
            method: format!(
                "vtkFlyingEdges3D {} (one thread), full resolution",
                v["version"].as_str().unwrap_or("?")
            ),
            median_seconds: v["flying_edges"]["median_s"].as_f64(),
            triangles: v["flying_edges"]["triangles"].as_u64().unwrap_or(0) as usize,
            distance: None,
            closed: None,
            note: "the same surface as the reference up to ambiguous-face choices".into(),
        },
        Err(e) => SurfaceRow {
            volume: volume.into(),
            iso,
            method: "vtkFlyingEdges3D".into(),
            median_seconds: None,
            triangles: 0,
            distance: None,
            closed: None,
            note: format!("not available: {e}"),
        },
    });
    let _ = std::fs::remove_file(&raw);
    rows
}

/// A height grid (`size = 2^k + 1`): ridged hills, quantised to 1/16.
fn height_grid(size: usize) -> Vec<f64> {
    let s = (size - 1) as f64;
    let mut v = Vec::with_capacity(size * size);
    for j in 0..size {
        for i in 0..size {
            let (x, y) = (i as f64 / s, j as f64 / s);
            let h = 120.0 * (6.0 * x).sin() * (5.0 * y).cos()
                + 40.0 * (17.0 * x + 3.0 * y).sin().abs()
                + 300.0 * (-((x - 0.6).powi(2) + (y - 0.4).powi(2)) * 20.0).exp();
            v.push((h * 16.0).round() / 16.0);
        }
    }
    v
}

fn martini_rows(root: &FsPath, size: usize) -> Vec<MartiniRow> {
    let heights = height_grid(size);
    let field = Field::<2>::pad([size, size], &heights).expect("a square grid");
    let t = Instant::now();
    let full = FullDmv::build(field);
    let build = t.elapsed().as_secs_f64();
    let raw = write_raw(&heights, "martini");
    let mut rows = Vec::new();
    for threshold in [1.0, 5.0, 20.0] {
        let lod = Lod::<2> {
            error: Some(threshold),
            ..Lod::default()
        };
        let mut times = Vec::new();
        let mut mesh = Vec::new();
        for _ in 0..RUNS {
            let t = Instant::now();
            let mut r: Refiner<'_, 2, _, DiamondFront<2>> = Refiner::new(&full);
            let _ = r.refine(&lod);
            times.push(t.elapsed().as_secs_f64());
            mesh = r.mesh();
        }
        let exact = simplices_stats_exact(full.field(), &mesh);
        let mesh_file =
            std::env::temp_dir().join(format!("geocert-martini-{}.raw", std::process::id()));
        let (martini, note) = match &raw {
            Ok(f) => {
                let run = std::process::Command::new(root.join(".venv-peers/bin/python"))
                    .arg(root.join("benches/peers/martini_tile.py"))
                    .arg(f)
                    .arg(size.to_string())
                    .arg(threshold.to_string())
                    .arg(RUNS.to_string())
                    .arg(&mesh_file)
                    .output();
                match super::peer_json(run) {
                    Ok(v) => (
                        Some((
                            v["median_s"].as_f64().unwrap_or(f64::NAN),
                            v["mesh_median_s"].as_f64().unwrap_or(f64::NAN),
                            v["triangles"].as_u64().unwrap_or(0) as usize,
                        )),
                        String::new(),
                    ),
                    Err(e) => (None, format!("pymartini not available: {e}")),
                }
            }
            Err(e) => (None, format!("could not write the grid: {e}")),
        };
        // pymartini's mesh measured exactly, and geocert refined to that measured error.
        // Only a conforming triangulation of the whole grid is measured. (The axis order read
        // back was checked on a field varying along one axis: the other order puts the
        // measured error far above pymartini's threshold.)
        let martini_mesh = martini
            .and_then(|_| read_martini_mesh(&mesh_file, size))
            .filter(|m| check_conforming(&full.field().hierarchy(), m).conforming);
        let _ = std::fs::remove_file(&mesh_file);
        let martini_max_error =
            martini_mesh.map(|m| rational_to_f64(&simplices_stats_exact(full.field(), &m).error));
        let geocert_at_martini_error = martini_max_error.map(|e| {
            let mut r: Refiner<'_, 2, _, DiamondFront<2>> = Refiner::new(&full);
            let _ = r.refine(&Lod {
                error: Some(e),
                ..Lod::default()
            });
            let m = r.mesh();
            let err = rational_to_f64(&simplices_stats_exact(full.field(), &m).error);
            (m.len(), err)
        });
        rows.push(MartiniRow {
            grid: size,
            threshold,
            geocert_build_s: build,
            geocert_refine_s: median(times),
            geocert_triangles: mesh.len(),
            geocert_max_error: rational_to_f64(&exact.error),
            martini,
            martini_max_error,
            geocert_at_martini_error,
            note,
        });
    }
    if let Ok(f) = raw {
        let _ = std::fs::remove_file(f);
    }
    rows
}

/// The triangles pymartini wrote (see `martini_tile.py`) as grid simplices: its vertex
/// `(a, b)` is the height grid's point `(x, y) = (b, a)` (it reads the transposed grid).
/// `None` when the file is missing or malformed.
fn read_martini_mesh(path: &FsPath, size: usize) -> Option<Vec<Simplex<2>>> {
    let bytes = std::fs::read(path).ok()?;
    let words: Vec<u32> = bytes
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    let (nv, nt) = (*words.first()? as usize, *words.get(1)? as usize);
    if words.len() != 2 + 2 * nv + 3 * nt {
        return None;
    }
    let vertices = &words[2..2 + 2 * nv];
    let mut out = Vec::with_capacity(nt);
    for t in words[2 + 2 * nv..].chunks_exact(3) {
        let mut v = [[0u32; 2]; 3];
        for (p, &i) in v.iter_mut().zip(t) {
            let (a, b) = (
                *vertices.get(2 * i as usize)?,
                *vertices.get(2 * i as usize + 1)?,
            );
            if a as usize >= size || b as usize >= size {
                return None;
            }
            *p = [b, a];
        }
        out.push(Simplex::new(&v)?);
    }
    Some(out)
}

/// Runs the campaign: built-in volumes at `side³` (and the sparse fuel at `2·side − 1`), the
/// real volumes when installed.
pub fn diamond_campaign(root: &FsPath, side: usize) -> DiamondCampaign {
    let mut notes = Vec::new();
    let proofs = vec![
        proofs::diamond::implicit_vs_explicit_on(&REPORT_GRIDS, proofs::Shard::WHOLE),
        proofs::diamond::maubach_is_longest_edge(proofs::Shard::WHOLE),
        proofs::diamond::supercube(proofs::Shard::WHOLE),
    ];
    let error_checks = ["sphere", "gyroid", "fuel"]
        .iter()
        .filter_map(|n| {
            builtin_volume(n, 17)
                .ok()
                .map(|f| error_check(&format!("{n} 17³"), &f))
        })
        .collect();
    let mut inputs: Vec<Input> = Vec::new();
    for (name, s) in [("gyroid", side), ("sphere", side), ("fuel", 2 * side - 1)] {
        if let Ok(field) = builtin_volume(name, s) {
            inputs.push(Input {
                name: format!("{name} {s}³"),
                field,
            });
        }
    }
    for (name, path) in real_volumes(root, &mut notes) {
        let read = std::fs::read(&path)
            .map_err(|e| e.to_string())
            .and_then(|b| crate::mc::nifti::read_nifti(&b).map_err(|e| e.to_string()))
            .and_then(|v| Field::pad(v.dims, &v.values).map_err(|e| e.to_string()));
        match read {
            Ok(field) => inputs.push(Input { name, field }),
            Err(e) => notes.push(format!("{name}: {e}")),
        }
    }
    let (mut builds, mut error_dmvs, mut iso_dmvs) = (Vec::new(), Vec::new(), Vec::new());
    let (mut refinement, mut surfaces) = (Vec::new(), Vec::new());
    for (n, input) in inputs.into_iter().enumerate() {
        let dims = input.field.real_dims().to_vec();
        let padded = input.field.hierarchy().side() as usize + 1;
        let t = Instant::now();
        let full = FullDmv::build(input.field);
        builds.push(BuildRow {
            volume: input.name.clone(),
            dims,
            padded,
            grid_points: full.len(),
            seconds: t.elapsed().as_secs_f64(),
        });
        let (lo, hi) = full
            .field()
            .values()
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        let range = hi - lo;
        for (label, e) in [("ε > 0", 0.0), ("ε > 1 %", 0.01 * range)] {
            let sel = full.select_by_error(e);
            error_dmvs.push(dmv_row(&input.name, label.into(), &full, &sel));
        }
        let isos: Vec<f64> = [0.3, 0.5, 0.7]
            .iter()
            .map(|q| (lo + q * range).round())
            .collect();
        for k in 1..=3 {
            let sel = full.select_by_isovalues(&isos[..k]);
            let label = isos[..k]
                .iter()
                .map(|x| format!("{x}"))
                .collect::<Vec<_>>()
                .join(", ");
            iso_dmvs.push(dmv_row(
                &input.name,
                format!("k ∈ {{{label}}}"),
                &full,
                &sel,
            ));
        }
        let lod = Lod {
            error: Some(0.01 * range),
            isovalues: vec![isos[1]],
            roi: None,
        };
        let iso_sel = full.select_by_isovalues(&isos[1..2]);
        refinement.extend(refine_rows(&input.name, &full, &iso_sel, &lod));
        // Isosurfaces side by side on the first volume and the MNI template.
        if n == 0 || input.name.starts_with("MNI") {
            surfaces.extend(surface_rows(
                root,
                &input.name,
                &full,
                isos[1] + 0.5,
                0.01 * range,
            ));
        }
    }
    let martini = martini_rows(root, 2 * side - 1);
    DiamondCampaign {
        proofs,
        error_checks,
        builds,
        error_dmvs,
        iso_dmvs,
        refinement,
        surfaces,
        martini,
        notes,
    }
}

/// True when every proof passed, every fast interval held the exact error, every file read
/// back bit for bit, and every refinement was conforming with the same mesh on every
/// encoding and front.
pub fn campaign_ok(c: &DiamondCampaign) -> bool {
    c.proofs.iter().all(|p| p.ok())
        && c.error_checks
            .iter()
            .all(|e| e.contained == e.diamonds && e.ranges_equal == e.diamonds)
        && c.error_dmvs
            .iter()
            .chain(&c.iso_dmvs)
            .all(|r| r.file_round_trip)
        && c.refinement.iter().all(|r| r.conforming && r.same_mesh)
        && c.surfaces.iter().all(|s| s.closed != Some(false))
}

fn mb(b: u64) -> String {
    format!("{:.2}", b as f64 / (1024.0 * 1024.0))
}

/// Writes `diamond.md`.
pub fn write_diamond_report(
    dir: &FsPath,
    meta: &RunMeta,
    c: &DiamondCampaign,
) -> std::io::Result<PathBuf> {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Diamond hierarchies and supercubes (Weiss & De Floriani)\n"
    );
    let _ = writeln!(
        s,
        "Generated by `geocert prove` (or `geocert prove diamonds`); do not edit.\n"
    );
    s.push_str(&meta.markdown());
    let _ = writeln!(
        s,
        "\nEvery diamond is computed from its central vertex by bit operations (scale, type, class, supercube, spine, simplices, parents, children, boundary clipping) and checked against an explicit hierarchy built by Maubach bisection of the Kuhn simplices. A DMV keeps per diamond `F(v_c)`, the error `ε(δ)` (a certified upper bound from the fast path, rounded up to `f32`) and the value range; partial DMVs are closed under ancestors. Selective refinement runs on a doubled grid so that the unit cubes' Kuhn simplices (children of the finest edge diamonds) are part of the current mesh."
    );
    super::write_proofs_section(&mut s, &c.proofs);
    let _ = writeln!(s, "\nThe 5-D Maubach counts show that in 5-D Maubach's rule bisects an edge that is not the longest in some simplices, and in 4-D it bisects a longest edge that is tied with others: \"longest edge\" alone does not define the hierarchy there.");
    let _ = writeln!(
        s,
        "\n## The fast error against the exact error\n\nFor every diamond of small built-in volumes, the exact `ε(δ)` (barycentric coordinates by Cramer's rule over every simplex's bounding box, in rationals) lies in the fast path's certified interval (join/Freudenthal formula, `f64` with a rounding bound), and the ranges agree.\n\n| volume | diamonds | exact within the fast interval | ranges equal | widest interval |\n|---|---:|---:|---:|---:|"
    );
    for e in &c.error_checks {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.1e} |",
            e.volume, e.diamonds, e.contained, e.ranges_equal, e.max_width
        );
    }
    let _ = writeln!(
        s,
        "\n## Building Δf\n\nEvery diamond's certified error and range, on all cores (the machine above). Volumes whose sides are not `2^N + 1` are padded by repeating the last sample along each axis; only original samples count in the density ρ.\n\n| volume | samples | padded to | grid points | seconds |\n|---|---|---:|---:|---:|"
    );
    for b in &c.builds {
        let _ = writeln!(
            s,
            "| {} | {:?} | {}³ | {} | {:.2} |",
            b.volume, b.dims, b.padded, b.grid_points, b.seconds
        );
    }
    let _ = writeln!(
        s,
        "\n## Partial DMVs (Tables 1–3)\n\nTable 1's model: `Δf = n_f b_δ`, `Δd = n_p (b_δ + b_v)`, `Δs = n_p b_δ + n_s b_σ`, ideal `Δp = n_p b_δ`; density `ρ = n_p/n_f`, concentration `κ = n_p/n_s`. geocert's counts: `b_δ` = value (4 bytes when every sample is an `f32`, else 8) + error + range (12), `b_v` = 3 coordinates of ⌈(N+1)/8⌉ bytes, `b_σ` = origin + 7 flag bytes + a 4-byte offset (17 with 16-bit coordinates, as the paper's). MB = 1024² bytes; the .dmv file is Δs with its header and checksum, and reads back bit for bit."
    );
    for (title, rows) in [
        ("By error (Table 2's shape)", &c.error_dmvs),
        ("By isovalues (Table 3's shape)", &c.iso_dmvs),
    ] {
        let _ = writeln!(
            s,
            "\n### {title}\n\n| volume | kept | n_p | n_s | ρ | κ | Δf MB | Δd MB | Δs MB | ideal MB | Δs over ideal | Δd over ideal | Δf/Δs | .dmv bytes | read back |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"
        );
        for r in rows {
            let b = &r.summary.bytes;
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {:.3} | {:.1} | {} | {} | {} | {} | {:.1} % | {:.0} % | {:.1} | {} | {} |",
                r.volume,
                r.criterion,
                r.summary.diamonds,
                r.summary.supercubes,
                r.summary.density,
                r.summary.concentration,
                mb(b.full),
                mb(b.diamond),
                mb(b.supercube),
                mb(b.ideal),
                100.0 * (b.supercube as f64 / b.ideal.max(1) as f64 - 1.0),
                100.0 * (b.diamond as f64 / b.ideal.max(1) as f64 - 1.0),
                b.full as f64 / b.supercube.max(1) as f64,
                r.file_bytes,
                if r.file_round_trip { "yes" } else { "**no**" }
            );
        }
    }
    let _ = writeln!(
        s,
        "\n## Selective refinement (Table 4)\n\nThe query of Table 4: refine diamonds with error above 1 % of the value range whose range holds the middle isovalue, top-down from the base diamond, on Δf (the full array), and on Δd and Δs built from the one-isovalue DMV above. Median of {REFINE_RUNS} runs, one thread, including the front's memory management; the six runs of a volume are interleaved (each round runs all six, starting one further along), so that the machine's drift falls on all alike, and \"Σs/Σd\" is the median over rounds of Σs's time over Σd's on the same encoding in the same round; \"visited\" counts every diamond examined (popped from the queue or forced). Front bytes by the paper's model: Σd 7 bytes per diamond, Σs 27 per supercube; so Σs's bytes per tetrahedron is 27 over the mesh's tetrahedra per supercube, fixed by the volume and the query, not by the implementation (the paper's Section 8: 26.5 tetrahedra per supercube on its test, ≈ 1 byte; 25.6 on Fuel, 1.05 bytes). The first mesh (Δf, Σd) is checked conforming exactly (faces matched, volumes summing to the domain's); the other five are compared with it simplex for simplex.\n\n| volume | DMV | front | visited | median s | M diamonds/s | Σs/Σd | tetrahedra | front bytes | bytes/tet | conforming | same mesh |\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|---|---|"
    );
    for r in &c.refinement {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.4} | {:.2} | {} | {} | {} | {:.2} | {} | {} |",
            r.volume,
            r.dmv,
            r.front,
            r.visited,
            r.median_seconds,
            r.per_second / 1e6,
            r.against_diamond_front
                .map_or(String::new(), |x| format!("{x:.3}")),
            r.simplices,
            r.front_bytes,
            r.bytes_per_simplex,
            r.conforming,
            r.same_mesh
        );
    }
    if !c.refinement.is_empty() {
        let slowest = c
            .refinement
            .iter()
            .min_by(|a, b| a.per_second.total_cmp(&b.per_second));
        let widest = c
            .refinement
            .iter()
            .filter_map(|r| r.against_diamond_front.map(|x| (x, r)))
            .max_by(|a, b| a.0.total_cmp(&b.0));
        if let (Some(low), Some((ratio, wide))) = (slowest, widest) {
            let _ = writeln!(
                s,
                "\nSlowest row: {:.2} M diamonds/s ({}, {} {}; goal ≥ 10). Largest Σs/Σd: {:.3} ({}, {}; goal ≤ 1.05).",
                low.per_second / 1e6,
                low.volume,
                low.dmv,
                low.front,
                ratio,
                wide.volume,
                wide.dmv
            );
        }
    }
    let _ = writeln!(
        s,
        "\n## Adaptive isosurfaces against OpenVDB and VTK\n\nSame volume and isovalue (half-way between samples so that no sample lies on it). Distances in grid units: the largest distance of a method's vertices from geocert's full-resolution marching-cubes surface, and of that surface's vertices from the method's surface, each over an evenly strided sample of at most {DISTANCE_SAMPLES} vertices (a lower bound of the one-sided Hausdorff distance). OpenVDB runs `FloatGrid.copyFromArray` (background = the volume's minimum) then `convertToPolygons(iso, adaptivity)` (its time includes the copy); VTK one thread. Medians of 3 runs. \"closed\" is checked for the adaptive surface only: every edge in two triangles except in the domain's boundary faces (the full-resolution surfaces end open at the domain boundary). Where a peer's \"max dist. to full\" is several grid units, the peer's surface has parts the full-resolution surface does not: its note says which. geocert's adaptive surface is marching tetrahedra on the current mesh: it has more triangles per cell than marching cubes, so where the criterion refines the whole isosurface region to the finest level (the MNI template at this error) it is larger than the full-resolution surface.\n\n| volume | iso | method | median s | triangles | max dist. to full | max dist. from full | closed |\n|---|---:|---|---:|---:|---:|---:|---|"
    );
    for r in &c.surfaces {
        let _ = writeln!(
            s,
            "| {} | {} | {}{} | {} | {} | {} | {} | {} |",
            r.volume,
            r.iso,
            r.method,
            if r.note.is_empty() {
                String::new()
            } else {
                format!(" ({})", r.note)
            },
            r.median_seconds.map_or("—".into(), |t| format!("{t:.3}")),
            r.triangles,
            r.distance.map_or("—".into(), |d| format!("{:.3}", d.0)),
            r.distance.map_or("—".into(), |d| format!("{:.3}", d.1)),
            r.closed.map_or("—".into(), |c| c.to_string())
        );
    }
    let _ = writeln!(
        s,
        "\n## 2-D: refinement against pymartini\n\nThe same height grid (ridged hills, quantised to 1/16). geocert: Δf build (every diamond's certified error) and top-down refinement with `ε > threshold` (Σd); the mesh's largest interpolation error at the grid points, exactly. pymartini (RTIN, 2-D longest-edge bisection): `create_tile` (its errors) and `get_mesh(threshold)`; its error measure is its own (the error at each triangle's split point, carried up to the ancestors), so at equal thresholds the two criteria differ. The last columns compare at equal *measured* error: pymartini's triangles are read back and their largest interpolation error at the grid points is computed exactly by geocert; geocert then refines with `ε >` that error, so its mesh's error is at most pymartini's.\n\n| grid | threshold | geocert build s | geocert refine s | geocert triangles | geocert max error (exact) | pymartini total s | pymartini get_mesh s | pymartini triangles | pymartini max error (exact) | geocert triangles at pymartini's error | its max error (exact) |\n|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    for r in &c.martini {
        let (a, b, t) = r
            .martini
            .map_or(("—".into(), "—".into(), "—".into()), |(a, b, t)| {
                (format!("{a:.4}"), format!("{b:.4}"), t.to_string())
            });
        let me = r.martini_max_error.map_or("—".into(), |e| e.to_string());
        let (gt, ge) = r
            .geocert_at_martini_error
            .map_or(("—".into(), "—".into()), |(t, e)| {
                (t.to_string(), e.to_string())
            });
        let _ = writeln!(
            s,
            "| {}² | {} | {:.3} | {:.4} | {} | {} | {a} | {b} | {t} | {me} | {gt} | {ge} |",
            r.grid,
            r.threshold,
            r.geocert_build_s,
            r.geocert_refine_s,
            r.geocert_triangles,
            r.geocert_max_error
        );
    }
    let mut martini_notes: Vec<&str> = c
        .martini
        .iter()
        .map(|r| r.note.as_str())
        .filter(|n| !n.is_empty())
        .collect();
    martini_notes.dedup();
    for n in martini_notes {
        let _ = writeln!(s, "\n{n}");
    }
    if !c.notes.is_empty() {
        let _ = writeln!(s, "\n## Not available in this run\n");
        for n in &c.notes {
            let _ = writeln!(s, "- {n}");
        }
    }
    std::fs::create_dir_all(dir)?;
    let path = dir.join("diamond.md");
    std::fs::write(&path, s)?;
    Ok(path)
}
