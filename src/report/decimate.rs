//! The decimation report (Krivograd et al.): Table-1-like timings on height grids with the
//! linearity plot, the peers (vtkDecimatePro, meshoptimizer) side by side on the 810k-node
//! grid with quality at equal triangle count, the Table-2-like size table of the Kirsch
//! plate, undecimation exactness, and the exact-vs-fast agreement.

use super::campaign::median;
use crate::decimate::{check, data, decimate, quality, History, Options, Stage, Stats, Target};
use crate::mesh::Mesh;
use std::fmt::Write as _;
use std::path::{Path as FsPath, PathBuf};
use std::time::Instant;

/// One row of the Table-1-like timing table.
#[derive(Clone, Debug, serde::Serialize)]
pub struct GridRow {
    pub nodes_in: usize,
    pub nodes_out: usize,
    pub triangles_out: usize,
    pub runs: usize,
    pub decimate_s: f64,
    pub undecimate_s: f64,
    /// Undoing every step gave the original mesh (fingerprint and equality).
    pub undecimated_exactly: bool,
    pub max_height_error: f64,
    pub rms_height_error: f64,
}

/// One decimator on the peers' grid.
#[derive(Clone, Debug, serde::Serialize)]
pub struct PeerRow {
    pub name: String,
    pub seconds: Option<f64>,
    pub triangles: usize,
    pub errors: Option<quality::Errors>,
    /// Symmetric Hausdorff distance to the input, sampled at both meshes' vertices.
    pub hausdorff: Option<f64>,
    pub note: String,
}

impl PeerRow {
    /// A row with no measurement yet (or none possible): `note` says why.
    fn absent(name: &str, note: String) -> PeerRow {
        PeerRow {
            name: name.into(),
            seconds: None,
            triangles: 0,
            errors: None,
            hausdorff: None,
            note,
        }
    }
}

/// One row of the Table-2-like plate table.
#[derive(Clone, Debug, serde::Serialize)]
pub struct PlateRow {
    pub percent: f64,
    pub nodes: usize,
    pub triangles: usize,
    pub ascii_bytes: usize,
    pub zip_bytes: usize,
    pub history_bytes: usize,
    pub max_scalar_error: f64,
    pub rms_scalar_error: f64,
}

/// Everything the report shows.
#[derive(Clone, Debug, serde::Serialize)]
pub struct DecimateCampaign {
    pub grids: Vec<GridRow>,
    pub peers: Vec<PeerRow>,
    /// Nodes of the grid the peers ran on.
    pub peer_nodes: usize,
    pub plate: Vec<PlateRow>,
    pub plate_verified: Result<check::Verified, String>,
    pub plate_verify_s: f64,
    /// (input, criterion, histories equal, steps).
    pub exact_vs_fast: Vec<(String, String, bool, usize)>,
    /// Surfaces in 3-D against the quadric simplifiers.
    pub surfaces: super::decimate_surfaces::SurfaceCampaign,
}

fn undo_all(mesh: &Mesh, out: &Mesh, history: &History) -> (f64, bool) {
    let mut stage = match Stage::decimated(out, history) {
        Ok(s) => s,
        Err(_) => return (f64::NAN, false),
    };
    let clock = Instant::now();
    while stage.applied > 0 {
        if stage.undo(history).is_err() {
            return (f64::NAN, false);
        }
    }
    let s = clock.elapsed().as_secs_f64();
    (s, stage.to_mesh() == *mesh)
}

/// The peers row of the fast path on one thread.
const ONE_THREAD: &str = "geocert fast path, one thread";

fn keep_one_percent() -> Options {
    Options {
        target: Target::Keep(0.01),
        ..Options::default()
    }
}

/// Rounds of Table 1: every size once per round, so that the drift of a shared machine falls
/// on all sizes alike rather than on whichever ran during a slow spell.
const GRID_ROUNDS: usize = 5;
/// geocert / meshoptimizer run pairs on the peers' grid (each pair back to back).
const PAIRS: usize = 5;

/// Table 1: grids of `sides²` nodes decimated by 99 % (fast path, error criterion), the
/// median of 5 rounds over all sizes (`GRID_ROUNDS`); also returns the 900² grid (or the last)
/// and its decimation for the peers.
pub fn grid_rows(sides: &[usize]) -> (Vec<GridRow>, Option<(Mesh, Mesh)>) {
    let mut dec = vec![Vec::new(); sides.len()];
    let mut und = vec![Vec::new(); sides.len()];
    let mut exact = vec![true; sides.len()];
    let mut rows = Vec::new();
    let mut last = None;
    for round in 0..GRID_ROUNDS {
        for (i, &side) in sides.iter().enumerate() {
            let mesh = data::height_grid(side);
            let out = decimate(&mesh, &keep_one_percent()).expect("built-in grid");
            dec[i].push(out.stats.seconds);
            let (s, ok) = undo_all(&mesh, &out.mesh, &out.history);
            und[i].push(s);
            exact[i] &= ok;
            if round + 1 < GRID_ROUNDS {
                continue;
            }
            let e = quality::xy_errors(&mesh, &out.mesh);
            rows.push(GridRow {
                nodes_in: out.stats.nodes_in,
                nodes_out: out.stats.nodes_out,
                triangles_out: out.stats.triangles_out,
                runs: GRID_ROUNDS,
                decimate_s: median(std::mem::take(&mut dec[i])),
                undecimate_s: median(std::mem::take(&mut und[i])),
                undecimated_exactly: exact[i],
                max_height_error: e.max_height,
                rms_height_error: e.rms_height,
            });
            // The peers run on the paper's largest grid (810k nodes) when it is among the sizes.
            if last.is_none() || side == 900 || sides.last() == Some(&side) && !sides.contains(&900)
            {
                last = Some((mesh, out.mesh));
            }
        }
    }
    (rows, last)
}

/// meshoptimizer's `simplify` on one mesh: its inputs prepared once, each run timed alone.
struct Meshopt {
    bytes: Vec<u8>,
    indices: Vec<u32>,
}

impl Meshopt {
    fn new(mesh: &Mesh) -> Meshopt {
        Meshopt {
            bytes: mesh
                .vertices
                .iter()
                .flat_map(|p| p.map(|x| x as f32))
                .flat_map(|x| x.to_le_bytes())
                .collect(),
            indices: mesh.triangles.iter().flatten().copied().collect(),
        }
    }

    /// One simplification to `triangles` triangles: its seconds and its index buffer.
    fn run(&self, triangles: usize) -> Result<(f64, Vec<u32>), String> {
        let adapter =
            meshopt::VertexDataAdapter::new(&self.bytes, 12, 0).map_err(|e| e.to_string())?;
        let clock = Instant::now();
        let result = meshopt::simplify(
            &self.indices,
            &adapter,
            3 * triangles,
            1.0,
            meshopt::SimplifyOptions::None,
            None,
        );
        Ok((clock.elapsed().as_secs_f64(), result))
    }
}

/// The meshoptimizer row from the timed pairs `(geocert's seconds, meshoptimizer's)` and
/// its last result.
fn meshopt_row(mesh: &Mesh, triangles: usize, pairs: &[(f64, f64)], result: &[u32]) -> PeerRow {
    let runs = pairs.len();
    let paired = median(pairs.iter().map(|&(ours, theirs)| theirs / ours).collect());
    let times = pairs.iter().map(|&(_, theirs)| theirs).collect();
    let out = Mesh {
        normals: None,
        vertices: mesh.vertices.clone(),
        triangles: result.chunks(3).map(|c| [c[0], c[1], c[2]]).collect(),
        scalars: None,
    };
    PeerRow {
        name: "meshoptimizer 0.7 `simplify` (edge collapse, meshopt crate)".into(),
        seconds: Some(median(times)),
        triangles: out.triangles.len(),
        errors: Some(quality::xy_errors(mesh, &out)),
        hausdorff: Some(quality::hausdorff_at_vertices(mesh, &out)),
        note: format!(
            "median of {runs}, each run right after one of geocert's (median of the {runs} \
             paired ratios: geocert {paired:.2}× faster); target {triangles} triangles"
        ),
    }
}

fn vtk_row(root: &FsPath, mesh: &Mesh, triangles: usize) -> PeerRow {
    let mut row = PeerRow::absent(
        "vtkDecimatePro (vertex removal, PreserveTopology)",
        String::new(),
    );
    let python = root.join(".venv-peers/bin/python");
    if !python.exists() {
        row.note = "`.venv-peers` not found (run benches/peers/setup.sh)".into();
        return row;
    }
    let dir = std::env::temp_dir();
    let input = dir.join(format!("geocert-dec-{}.ply", std::process::id()));
    let output = dir.join(format!("geocert-dec-{}-vtk.ply", std::process::id()));
    if let Err(e) = std::fs::write(&input, crate::mesh::ply::write(mesh, true)) {
        row.note = e.to_string();
        return row;
    }
    let reduction = 1.0 - triangles as f64 / mesh.triangles.len() as f64;
    let out = std::process::Command::new(python)
        .arg(root.join("benches/peers/vtk_decimate.py"))
        .arg(&input)
        .arg(format!("{reduction}"))
        .arg(&output)
        .arg("1")
        .output();
    let _ = std::fs::remove_file(&input);
    let result = (|| -> Result<(), String> {
        let v = super::peer_json(out)?;
        row.seconds = v["median_s"].as_f64();
        row.triangles = v["triangles"].as_u64().unwrap_or(0) as usize;
        row.note = format!(
            "VTK {}, one run (Update() only), target reduction {reduction:.5}",
            v["version"].as_str().unwrap_or("?")
        );
        let back = Mesh::read(&output, None).map_err(|e| e.to_string())?;
        row.errors = Some(quality::xy_errors(mesh, &back));
        row.hausdorff = Some(quality::hausdorff_at_vertices(mesh, &back));
        Ok(())
    })();
    let _ = std::fs::remove_file(&output);
    if let Err(e) = result {
        row.note = e;
    }
    row
}

/// The plate at 100/75/50/25/9.4 % of its nodes (Table 2), and the checker on the 9.4 % run.
fn plate_rows() -> (Vec<PlateRow>, Result<check::Verified, String>, f64) {
    use flate2::write::DeflateEncoder;
    use std::io::Write;
    let plate = data::paper_plate();
    let mut rows = Vec::new();
    let mut last = None;
    for percent in [100.0, 75.0, 50.0, 25.0, 9.4] {
        let options = Options {
            target: Target::Keep(percent / 100.0),
            ..Options::default()
        };
        let out = decimate(&plate, &options).expect("built-in plate");
        let ascii = crate::mesh::ply::write(&out.mesh, false);
        let mut z = DeflateEncoder::new(Vec::new(), flate2::Compression::default());
        let _ = z.write_all(&ascii);
        let zip = z.finish().map(|v| v.len()).unwrap_or(0);
        let e = quality::xy_errors(&plate, &out.mesh);
        rows.push(PlateRow {
            percent,
            nodes: out.mesh.vertices.len(),
            triangles: out.mesh.triangles.len(),
            ascii_bytes: ascii.len(),
            zip_bytes: zip,
            history_bytes: out.history.to_bytes().len(),
            max_scalar_error: e.max_scalar.unwrap_or(0.0),
            rms_scalar_error: e.rms_scalar.unwrap_or(0.0),
        });
        last = Some(out);
    }
    let out = last.expect("five runs");
    let clock = Instant::now();
    let verified = check::verify(&plate, &out.history, true, 0);
    (
        rows,
        verified.map_err(|e| e.to_string()),
        clock.elapsed().as_secs_f64(),
    )
}

fn exact_vs_fast() -> Vec<(String, String, bool, usize)> {
    use crate::decimate::Criterion;
    let mut rows = Vec::new();
    let inputs = [
        ("height grid 30×30".to_string(), data::height_grid(30)),
        ("Kirsch plate 36×7".to_string(), data::kirsch_plate(36, 7)),
    ];
    for (name, mesh) in &inputs {
        for criterion in [
            Criterion::Angle,
            Criterion::Scalar,
            Criterion::Error,
            Criterion::Quadric,
        ] {
            if criterion == Criterion::Scalar && mesh.scalars.is_none() {
                continue;
            }
            let options = Options {
                criterion,
                target: Target::Keep(0.05),
                ..Options::default()
            };
            let fast = decimate(mesh, &options).expect("built-in");
            let exact =
                decimate(mesh, &options.clone().with_path(crate::Path::Exact)).expect("built-in");
            rows.push((
                name.clone(),
                format!("{criterion:?}").to_lowercase(),
                fast.history == exact.history,
                fast.history.len(),
            ));
        }
    }
    rows
}

/// Runs everything (about two minutes with the peers).
pub fn decimate_campaign(root: &FsPath, sides: &[usize]) -> DecimateCampaign {
    let (grids, last) = grid_rows(sides);
    let mut peers = Vec::new();
    let peer_nodes = last.as_ref().map(|(m, _)| m.vertices.len()).unwrap_or(0);
    let peer_row = grids.iter().find(|g| g.nodes_in == peer_nodes);
    if let (Some((mesh, ours)), Some(_)) = (&last, peer_row) {
        // Timed again, each run paired with a meshoptimizer run at once after it, so that
        // both see the same state of this shared machine (its speed drifts over seconds).
        let meshopt = Meshopt::new(mesh);
        let (mut runs, mut pairs) = (Vec::new(), Vec::new());
        let mut meshopt_out = Ok(Vec::new());
        for _ in 0..PAIRS {
            let Ok(o) = decimate(mesh, &keep_one_percent()) else {
                continue;
            };
            meshopt_out = meshopt.run(ours.triangles.len()).map(|(t, result)| {
                pairs.push((o.stats.seconds, t));
                result
            });
            runs.push(o.stats);
        }
        let share = |count: fn(&Stats) -> usize| {
            runs.iter()
                .map(|r| count(r) as f64 / r.taken.max(1) as f64)
                .fold(f64::NAN, f64::min)
        };
        let (ahead, remembered) = (share(|r| r.evaluated_ahead), share(|r| r.remembered));
        peers.push(PeerRow {
            name: "geocert fast path (error criterion, k = 10)".into(),
            seconds: Some(median(runs.iter().map(|r| r.seconds).collect())),
            triangles: ours.triangles.len(),
            errors: Some(quality::xy_errors(mesh, ours)),
            hausdorff: Some(quality::hausdorff_at_vertices(mesh, ours)),
            note: format!(
                "median of {PAIRS}, each run followed by a meshoptimizer run; lazy \
                 re-evaluation, re-binned queue; \
                 initial pass on {} threads, the loop on one with the nodes it takes next \
                 evaluated ahead on a second (at least {:.0} % of taken nodes used that, and \
                 {:.0} % needed no evaluation: unchanged since filed, removed by the plan \
                 remembered from then); \
                 {:.2} s (median) before the first removal: adjacency, initial pass, queue fill",
                rayon::current_num_threads(),
                100.0 * ahead,
                100.0 * remembered,
                median(runs.iter().map(|r| r.setup_seconds).collect())
            ),
        });
        // The same on one thread: no lookahead, the initial pass in a pool of one.
        let alone = Options {
            look_ahead: false,
            ..keep_one_percent()
        };
        let one_thread = rayon::ThreadPoolBuilder::new().num_threads(1).build().ok();
        let times: Vec<f64> = (0..3)
            .filter_map(|_| one_thread.as_ref()?.install(|| decimate(mesh, &alone).ok()))
            .map(|o| o.stats.seconds)
            .collect();
        peers.push(PeerRow {
            name: ONE_THREAD.into(),
            seconds: (!times.is_empty()).then(|| median(times)),
            triangles: ours.triangles.len(),
            errors: Some(quality::xy_errors(mesh, ours)),
            hausdorff: Some(quality::hausdorff_at_vertices(mesh, ours)),
            note: "median of 3; the same removals, everything on one thread".into(),
        });
        // The paper's loop as printed, for comparison: eager re-evaluation, fixed intervals.
        let paper = Options {
            rebin: false,
            lazy: false,
            ..keep_one_percent()
        };
        if let Ok(out) = decimate(mesh, &paper) {
            peers.push(PeerRow {
                name: "geocert fast path, the paper's loop".into(),
                seconds: Some(out.stats.seconds),
                triangles: out.mesh.triangles.len(),
                errors: Some(quality::xy_errors(mesh, &out.mesh)),
                hausdorff: Some(quality::hausdorff_at_vertices(mesh, &out.mesh)),
                note: "one run; eager re-evaluation, intervals fixed from the initial range".into(),
            });
        }
        peers.push(vtk_row(root, mesh, ours.triangles.len()));
        peers.push(match meshopt_out {
            Ok(result) if !pairs.is_empty() => {
                meshopt_row(mesh, ours.triangles.len(), &pairs, &result)
            }
            other => PeerRow::absent(
                "meshoptimizer (meshopt crate)",
                other.err().unwrap_or_default(),
            ),
        });
    }
    let (plate, plate_verified, plate_verify_s) = plate_rows();
    DecimateCampaign {
        grids,
        peers,
        peer_nodes,
        plate,
        plate_verified,
        plate_verify_s,
        exact_vs_fast: exact_vs_fast(),
        surfaces: super::decimate_surfaces::surface_campaign(root),
    }
}

/// True when every undecimation was exact, the checker passed and the paths agreed where
/// their evaluation values are computed alike (angle criterion).
pub fn campaign_ok(c: &DecimateCampaign) -> bool {
    c.grids.iter().all(|g| g.undecimated_exactly)
        && c.plate_verified.is_ok()
        && c.exact_vs_fast
            .iter()
            .filter(|r| r.1 == "angle" || r.1 == "quadric")
            .all(|r| r.2)
        && c.surfaces.cases.iter().all(|k| k.verified.is_ok())
}

/// The linearity plot: microseconds per removed node against input nodes.
fn linearity_svg(rows: &[GridRow]) -> String {
    let (w, h, pad) = (640.0, 320.0, 50.0);
    let xs: Vec<f64> = rows.iter().map(|r| r.nodes_in as f64 / 1000.0).collect();
    let per = |s: f64, r: &GridRow| 1e6 * s / (r.nodes_in - r.nodes_out).max(1) as f64;
    let dec: Vec<f64> = rows.iter().map(|r| per(r.decimate_s, r)).collect();
    let und: Vec<f64> = rows.iter().map(|r| per(r.undecimate_s, r)).collect();
    let xmax = xs.iter().cloned().fold(1.0, f64::max);
    let ymax = dec
        .iter()
        .chain(&und)
        .cloned()
        .filter(|y| y.is_finite())
        .fold(1.0, f64::max)
        * 1.2;
    let px = |x: f64| pad + (w - 2.0 * pad) * x / xmax;
    let py = |y: f64| h - pad - (h - 2.0 * pad) * y / ymax;
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"{w}\" height=\"{h}\" fill=\"white\"/>\n"
    );
    let _ = writeln!(
        s,
        "<line x1=\"{pad}\" y1=\"{b}\" x2=\"{r}\" y2=\"{b}\" stroke=\"black\"/><line x1=\"{pad}\" y1=\"{pad}\" x2=\"{pad}\" y2=\"{b}\" stroke=\"black\"/>",
        b = h - pad,
        r = w - pad
    );
    for k in 0..=5 {
        let y = ymax * k as f64 / 5.0;
        let _ = writeln!(
            s,
            "<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{y:.1}</text>",
            pad - 4.0,
            py(y) + 4.0
        );
    }
    for (x, r) in xs.iter().zip(rows) {
        let _ = writeln!(
            s,
            "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}k</text>",
            px(*x),
            h - pad + 14.0,
            r.nodes_in / 1000
        );
    }
    for (ys, colour, label, dy) in [
        (&dec, "#c0392b", "decimation", 0.0),
        (&und, "#2471a3", "undecimation", 14.0),
    ] {
        let pts: Vec<String> = xs
            .iter()
            .zip(ys.iter())
            .filter(|(_, y)| y.is_finite())
            .map(|(x, y)| format!("{:.1},{:.1}", px(*x), py(*y)))
            .collect();
        let _ = writeln!(
            s,
            "<polyline fill=\"none\" stroke=\"{colour}\" stroke-width=\"2\" points=\"{}\"/>",
            pts.join(" ")
        );
        let _ = writeln!(
            s,
            "<text x=\"{}\" y=\"{}\" fill=\"{colour}\">{label}</text>",
            w - pad - 90.0,
            pad + dy
        );
    }
    let _ = writeln!(
        s,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">input nodes</text><text x=\"12\" y=\"{}\" transform=\"rotate(-90 12 {})\" text-anchor=\"middle\">µs per removed node</text>\n</svg>",
        w / 2.0,
        h - 8.0,
        h / 2.0,
        h / 2.0
    );
    s
}

/// Writes `reports/decimate.md` and `reports/decimate_linearity.svg`.
pub fn write_decimate_report(
    dir: &FsPath,
    meta: &super::RunMeta,
    c: &DecimateCampaign,
) -> std::io::Result<PathBuf> {
    std::fs::create_dir_all(dir)?;
    std::fs::write(dir.join("decimate_linearity.svg"), linearity_svg(&c.grids))?;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Decimation report (Krivograd, Hren, Žalik & Jezernik)\n\nGenerated by `geocert prove`; do not edit.\n"
    );
    s.push_str(&meta.markdown());
    let _ = writeln!(
        s,
        "\n## Method\n\nNode decimation (Section 1): every node evaluated, filed in the bucket queue \
         of eqs. (1)–(3) (`m = ⌊n/k⌋` intervals, `k = 10`, boundaries normalised to \
         `[ev_min, ev_max]`), the first node of the lowest non-empty interval removed with its \
         fan, the hole ear-cut in the xy plane (exact orientation signs: Shewchuk's adaptive \
         predicates on the fast path, rationals on the exact path), neighbours re-evaluated. \
         Criterion: the height (or scalar) deviation the removal would cause. Border nodes are \
         removed only while the domain's outline stays intact. Every removal is recorded \
         (Section 2) and undone by restoring the triangle slots.\n\n\
         Two extensions are on by default (`--eager --fixed-intervals` runs the paper's loop as \
         printed; the peers table has both): the queue is re-binned over the queued nodes' \
         current range once more than half of them were re-filed above it, into at least \
         1024 intervals (with fixed \
         boundaries, late re-evaluated values all land in the last interval and leave in FIFO \
         order), and a removed node's queued neighbours are marked stale and re-evaluated when \
         they reach the front rather than at once. Both keep every queue operation `O(1)` \
         amortised.\n\n\
         The fast engine keeps a list of neighbours at every node (the paper's Figure 4) in one \
         64-byte block, with the triangle slot that follows each neighbour; the initial \
         evaluation of every node runs on all cores (rayon). The removal loop runs on one \
         thread, and a second evaluates ahead: the loop hands the next 64 nodes in queue order \
         over with copies of their lists, and uses a result when the queue vouches that the \
         node's list has not changed since (a ticket that marks and moves void). Both threads \
         run the same code on the same inputs, so the removals are the same with or without \
         it (a unit test compares the histories); the peers table also times everything on \
         one thread. vtkDecimatePro and meshoptimizer run on one thread."
    );
    let _ = writeln!(
        s,
        "\n## Table 1: height grids decimated by 99 %\n\nFast path (the initial pass on all cores, the \
         loop on one with evaluation ahead on a second). Times are medians of {GRID_ROUNDS} rounds, each round running every size \
         once, so that the drift of this shared, noisy machine falls on all sizes alike. \
         Undecimation undoes every step and is compared with the original mesh.\n\n\
         | nodes in | nodes out | triangles out | decimation (s) | µs / node | undecimation (s) | µs / node | exact | max height err | RMS height err |\n\
         |---:|---:|---:|---:|---:|---:|---:|---|---:|---:|"
    );
    for r in &c.grids {
        let k = (r.nodes_in - r.nodes_out).max(1) as f64;
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.3} | {:.2} | {:.3} | {:.3} | {} | {:.2e} | {:.2e} |",
            r.nodes_in,
            r.nodes_out,
            r.triangles_out,
            r.decimate_s,
            1e6 * r.decimate_s / k,
            r.undecimate_s,
            1e6 * r.undecimate_s / k,
            if r.undecimated_exactly { "yes" } else { "NO" },
            r.max_height_error,
            r.rms_height_error
        );
    }
    let per: Vec<f64> = c
        .grids
        .iter()
        .map(|r| r.decimate_s / (r.nodes_in - r.nodes_out).max(1) as f64)
        .collect();
    let spread =
        per.iter().cloned().fold(0.0, f64::max) / per.iter().cloned().fold(f64::INFINITY, f64::min);
    let _ = writeln!(
        s,
        "\nTime per removed node, largest over smallest across the sizes: **{spread:.2}×** (the \
         goal: within 1.5×). The paper (Celeron 600): 0.140 s for 10k nodes, 14.681 s for 810k.\n\n\
         ![linearity](decimate_linearity.svg)"
    );
    let _ = writeln!(
        s,
        "\n## Peers on the {}-node grid, same triangle count\n\nErrors are measured at every \
         original node against the decimated surface's linear interpolant at the same xy \
         position; the Hausdorff distance is symmetric, from every vertex of each mesh to the \
         other surface (closest points on triangles).\n\n| decimator | seconds | triangles | max height err | RMS height err | Hausdorff | note |\n|---|---:|---:|---:|---:|---:|---|",
        c.peer_nodes
    );
    let ours = c.peers.first().and_then(|p| p.seconds);
    for p in &c.peers {
        let (mx, rms) = p
            .errors
            .map(|e| {
                (
                    format!("{:.2e}", e.max_height),
                    format!("{:.2e}", e.rms_height),
                )
            })
            .unwrap_or(("—".into(), "—".into()));
        let _ = writeln!(
            s,
            "| {} | {} | {} | {mx} | {rms} | {} | {} |",
            p.name,
            p.seconds.map(|t| format!("{t:.3}")).unwrap_or("—".into()),
            p.triangles,
            p.hausdorff
                .map(|h| format!("{h:.2e}"))
                .unwrap_or("—".into()),
            p.note
        );
    }
    let alone = c
        .peers
        .iter()
        .find(|p| p.name == ONE_THREAD)
        .and_then(|p| p.seconds);
    if let Some(o) = ours {
        for p in c.peers.iter().filter(|p| !p.name.starts_with("geocert")) {
            if let Some(t) = p.seconds {
                let _ = write!(s, "\n{}: geocert is **{:.2}×** its speed", p.name, t / o);
                if let Some(a) = alone {
                    let _ = write!(s, " ({:.2}× on one thread)", t / a);
                }
                let _ = writeln!(s, ".");
            }
        }
    }
    let _ = writeln!(
        s,
        "\n## Table 2: the Kirsch plate\n\nA {}×{} mm plate with a hole of radius {} mm under \
         uniaxial tension {} MPa along y; nodal field: von Mises stress of Kirsch's \
         infinite-plate solution (3σ at the hole's edge across the load). ASCII is geocert's \
         ascii PLY (x y z von_mises, triangles); zip is its raw deflate stream; the history \
         restores the full mesh.\n\n| kept | nodes | triangles | ASCII (B) | zip (B) | history (B) | max von Mises err (MPa) | RMS (MPa) |\n|---:|---:|---:|---:|---:|---:|---:|---:|",
        data::PLATE_WIDTH,
        data::PLATE_HEIGHT,
        data::HOLE_RADIUS,
        data::REMOTE_STRESS
    );
    for r in &c.plate {
        let _ = writeln!(
            s,
            "| {} % | {} | {} | {} | {} | {} | {:.3} | {:.3} |",
            r.percent,
            r.nodes,
            r.triangles,
            r.ascii_bytes,
            r.zip_bytes,
            r.history_bytes,
            r.max_scalar_error,
            r.rms_scalar_error
        );
    }
    match &c.plate_verified {
        Ok(v) => {
            let _ = writeln!(
                s,
                "\nThe independent checker replayed the 9.4 % run in exact rational arithmetic \
                 ({:.1} s): {} steps, {} added triangles positive in xy with no node in their \
                 closed region and the fan's area tiled exactly, no added edge pre-existing; \
                 the final mesh an oriented 2-manifold with Euler characteristic {} and {} \
                 border loops like the original; redo reproduced the decimated mesh and undo \
                 the original bit for bit: {}.",
                c.plate_verify_s,
                v.steps,
                v.triangles_checked,
                v.euler,
                v.border_loops,
                if v.undecimated_exactly { "yes" } else { "NO" }
            );
        }
        Err(e) => {
            let _ = writeln!(s, "\n**The checker refused the 9.4 % run:** {e}");
        }
    }
    let _ = writeln!(
        s,
        "\n## Exact path against fast path (95 % removed)\n\nThe same removals, slots and \
         added triangles (histories compared byte for byte). Both paths take every validity \
         decision with exact signs; the angle criterion is computed in `f64` by both from the \
         same differences, and the quadric criterion from the same `f64` quadrics and landing \
         points, so their histories must agree; the scalar and error criteria are \
         exact rationals rounded once on the exact path and `f64` sums on the fast path, so a \
         last-bit difference can file a node into a neighbouring interval.\n\n| input | criterion | steps | same history |\n|---|---|---:|---|"
    );
    for (name, crit, same, steps) in &c.exact_vs_fast {
        let _ = writeln!(
            s,
            "| {name} | {crit} | {steps} | {} |",
            if *same { "yes" } else { "no" }
        );
    }
    s.push_str(&super::decimate_surfaces::markdown(&c.surfaces));
    let path = dir.join("decimate.md");
    std::fs::write(&path, s)?;
    Ok(path)
}
