//! The trilinear-topology campaign: the exact topology of the trilinear isosurface of noise
//! and smooth volumes, and `mc verify` on the meshes geocert's table and other programs
//! (scikit-image, VTK, PyMCubes, through `benches/peers/mc_meshes.py`) make from them.

use super::campaign::median;
use crate::mc::grid::{extract_fast, Volume};
use crate::mc::trilinear::{volume_topology, VolumeTopology};
use crate::mc::verify::{verify_mesh, CellMismatch, MeshVerdict, MismatchKind, VerifyOptions};
use crate::mesh::Mesh;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

/// One program's mesh of one volume, checked.
#[derive(Clone, Debug, Serialize)]
pub struct ProgramRow {
    /// The program (and method).
    pub program: String,
    /// Its version.
    pub version: String,
    /// The verdict, or why there is none (not installed, a file the verifier refuses).
    pub verdict: Result<MeshVerdict, String>,
}

/// One volume.
#[derive(Clone, Debug, Serialize)]
pub struct TopologyCase {
    pub name: String,
    pub dims: [usize; 3],
    pub iso: f64,
    pub truth: VolumeTopology,
    /// Median seconds of the whole-volume topology (certified f64, exact fallback).
    pub seconds: f64,
    pub programs: Vec<ProgramRow>,
    /// Triangles of the `isosurface` crate beyond the volume (its extra layer), dropped.
    pub isosurface_beyond: usize,
}

/// The campaign.
#[derive(Clone, Debug, Serialize)]
pub struct TopologyCampaign {
    pub cases: Vec<TopologyCase>,
    /// Why the peers are missing, when they are.
    pub peers_missing: Option<String>,
}

/// Deterministic uniform noise in `[−1, 1]`, as `f32` (what every program reads).
fn noise(n: usize, seed: u64) -> Vec<f32> {
    let mut s = seed;
    (0..n * n * n)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 40) as f64 / (1u64 << 24) as f64 * 2.0 - 1.0) as f32
        })
        .collect()
}

/// A smooth field: a gyroid (period 16 voxels) or a sum of three Gaussian blobs.
fn smooth(name: &str, n: usize) -> Vec<f32> {
    let mut v = Vec::with_capacity(n * n * n);
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let p = [i, j, k].map(|c| c as f64);
                v.push(if name == "gyroid" {
                    let s = std::f64::consts::TAU / 16.0;
                    let [x, y, z] = p.map(|c| c * s);
                    x.sin() * y.cos() + y.sin() * z.cos() + z.sin() * x.cos()
                } else {
                    let c = n as f64;
                    [[0.3, 0.4, 0.5], [0.62, 0.55, 0.45], [0.5, 0.7, 0.6]]
                        .iter()
                        .map(|q| {
                            let d2: f64 = (0..3).map(|a| (p[a] - q[a] * c).powi(2)).sum();
                            (-d2 / (0.02 * c * c)).exp()
                        })
                        .sum::<f64>()
                } as f32);
            }
        }
    }
    v
}

/// The `mcubes` crate's version (pinned in Cargo.toml).
const MCUBES_VERSION: &str = "0.1.7";

/// The `mcubes` crate's mesh of the volume (x fastest, as geocert's; voxel units, no
/// offset), one side: its triangles come as separate vertex triples, which `mc verify`
/// joins by grid edge like any unwelded mesh.
fn mcubes_mesh(data: &[f32], dims: [usize; 3], iso: f64) -> Result<Mesh, String> {
    let mc = mcubes::MarchingCubes::new(
        (dims[0], dims[1], dims[2]),
        (1.0, 1.0, 1.0),
        (1.0, 1.0, 1.0),
        lin_alg::f32::Vec3::new_zero(),
        data.to_vec(),
        iso as f32,
    )
    .map_err(|e| e.to_string())?;
    let out = mc.generate(mcubes::MeshSide::OutsideOnly);
    let vertices: Vec<[f64; 3]> = out
        .vertices
        .iter()
        .map(|v| [v.posit.x as f64, v.posit.y as f64, v.posit.z as f64])
        .collect();
    let triangles = out
        .indices
        .chunks_exact(3)
        .map(|t| [t[0] as u32, t[1] as u32, t[2] as u32])
        .collect();
    Ok(Mesh {
        vertices,
        triangles,
        scalars: None,
        normals: None,
    })
}

/// The `isosurface` crate's version (pinned in Cargo.toml).
const ISOSURFACE_VERSION: &str = "0.0.4";

/// The `isosurface` crate's marching cubes of a cubic volume, in voxel units. It samples a
/// [`Source`](isosurface::source::Source) at `i / (size − 1)` and marks a corner inside when
/// the sample is `≤ 0`: the source returns `iso − v`, so inside is geocert's positive side
/// `v ≥ iso`. Its layer loop runs one layer of cells past `z = 1` (sampled there as the last
/// layer, clamped); the triangles with a vertex beyond the volume are dropped and counted.
fn isosurface_mesh(data: &[f32], dims: [usize; 3], iso: f64) -> Result<(Mesh, usize), String> {
    use isosurface::marching_cubes::MarchingCubes;
    use isosurface::source::Source;
    if dims[0] != dims[1] || dims[1] != dims[2] {
        return Err(format!("the crate samples cubes only, not {dims:?}"));
    }
    struct Samples<'a> {
        data: &'a [f32],
        size: usize,
        iso: f32,
    }
    impl Source for Samples<'_> {
        fn sample(&self, x: f32, y: f32, z: f32) -> f32 {
            let last = self.size - 1;
            let index = |t: f32| ((t * last as f32).round().max(0.0) as usize).min(last);
            let (i, j, k) = (index(x), index(y), index(z));
            self.iso - self.data[i + self.size * (j + self.size * k)]
        }
    }
    let size = dims[0];
    let source = Samples {
        data,
        size,
        iso: iso as f32,
    };
    let (mut flat, mut indices) = (Vec::new(), Vec::new());
    MarchingCubes::new(size).extract(&source, &mut flat, &mut indices);
    let scale = (size - 1) as f64;
    let vertices: Vec<[f64; 3]> = flat
        .chunks_exact(3)
        .map(|v| [0, 1, 2].map(|a| v[a] as f64 * scale))
        .collect();
    let beyond = |t: &[u32; 3]| t.iter().any(|&v| vertices[v as usize][2] > scale + 1e-3);
    let all: Vec<[u32; 3]> = indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    let triangles: Vec<[u32; 3]> = all.iter().filter(|t| !beyond(t)).copied().collect();
    let dropped = all.len() - triangles.len();
    Ok((
        Mesh {
            vertices,
            triangles,
            scalars: None,
            normals: None,
        },
        dropped,
    ))
}

/// `mesh` with every triangle's corners as vertices of their own (as STL stores a mesh).
fn unindexed(mesh: &Mesh) -> Mesh {
    let vertices = mesh
        .triangles
        .iter()
        .flat_map(|t| t.map(|v| mesh.vertices[v as usize]))
        .collect();
    let triangles = (0..mesh.triangles.len() as u32)
        .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
        .collect();
    Mesh {
        vertices,
        triangles,
        scalars: None,
        normals: None,
    }
}

/// A peer's mesh: (program, version, mesh path or why there is none).
type PeerMesh = (String, String, Result<std::path::PathBuf, String>);

/// Runs the peer script on a volume; returns (program, version, mesh path or error).
fn peer_meshes(
    root: &Path,
    data: &[f32],
    dims: [usize; 3],
    iso: f64,
    dir: &Path,
) -> Result<Vec<PeerMesh>, String> {
    let python = root.join(".venv-peers/bin/python");
    if !python.exists() {
        return Err("`.venv-peers` not found (run benches/peers/setup.sh)".into());
    }
    std::fs::create_dir_all(dir).map_err(|e| e.to_string())?;
    let file = dir.join("volume.raw");
    let bytes: Vec<u8> = data.iter().flat_map(|x| x.to_le_bytes()).collect();
    std::fs::write(&file, bytes).map_err(|e| e.to_string())?;
    let out = std::process::Command::new(python)
        .arg(root.join("benches/peers/mc_meshes.py"))
        .arg(&file)
        .args(dims.map(|d| d.to_string()))
        .arg(format!("{iso:?}"))
        .arg(dir)
        .output();
    let v = super::peer_json(out)?;
    let obj = v.as_object().ok_or("the peer script printed no object")?;
    Ok(obj
        .iter()
        .map(|(name, r)| {
            let version = r["version"].as_str().unwrap_or("").to_string();
            let path = match (r["path"].as_str(), r["error"].as_str()) {
                (Some(p), _) => Ok(std::path::PathBuf::from(p)),
                (None, Some(e)) => Err(e.to_string()),
                _ => Err("no result".to_string()),
            };
            (name.clone(), version, path)
        })
        .collect())
}

/// Runs the campaign (`root`: the repository, for the peers).
pub fn topology_campaign(root: &Path) -> TopologyCampaign {
    let mut cases = Vec::new();
    let mut peers_missing = None;
    let volumes: Vec<(String, usize, Vec<f32>, f64)> = vec![
        ("noise 8³".into(), 8, noise(8, 11), 0.0),
        ("noise 16³".into(), 16, noise(16, 12), 0.0),
        ("noise 32³".into(), 32, noise(32, 13), 0.1),
        ("gyroid 48³".into(), 48, smooth("gyroid", 48), 0.1),
        ("three blobs 48³".into(), 48, smooth("blobs", 48), 0.5),
    ];
    let scratch = std::env::temp_dir().join(format!("geocert-mc-verify-{}", std::process::id()));
    for (name, n, data, iso) in volumes {
        let dims = [n, n, n];
        let Ok(vol) = Volume::new(dims, data.iter().map(|&x| x as f64).collect()) else {
            continue;
        };
        let mut times = Vec::new();
        let mut truth = None;
        for _ in 0..3 {
            let start = Instant::now();
            truth = volume_topology(&vol, iso).ok();
            times.push(start.elapsed().as_secs_f64());
        }
        let Some(truth) = truth else { continue };
        let opts = VerifyOptions::default();
        let mut programs = Vec::new();
        let own = extract_fast(&vol, iso)
            .map_err(|e| e.to_string())
            .and_then(|(mesh, _)| verify_mesh(&vol, iso, &mesh, &opts).map_err(|e| e.to_string()));
        programs.push(ProgramRow {
            program: "geocert (656-entry table)".into(),
            version: env!("CARGO_PKG_VERSION").into(),
            verdict: own,
        });
        let tri = crate::mc::trilinear::polygonise::extract_trilinear(&vol, iso)
            .map_err(|e| e.to_string())
            .and_then(|(mesh, _)| verify_mesh(&vol, iso, &mesh, &opts).map_err(|e| e.to_string()));
        programs.push(ProgramRow {
            program: "geocert --topology trilinear".into(),
            version: env!("CARGO_PKG_VERSION").into(),
            verdict: tri,
        });
        programs.push(ProgramRow {
            program: "mcubes (Rust crate)".into(),
            version: MCUBES_VERSION.into(),
            verdict: mcubes_mesh(&data, dims, iso)
                .and_then(|mesh| verify_mesh(&vol, iso, &mesh, &opts).map_err(|e| e.to_string())),
        });
        let mut dropped = 0;
        let iso_mesh = isosurface_mesh(&data, dims, iso).map(|(mesh, d)| {
            dropped = d;
            mesh
        });
        // As indexed, and as a triangle soup that `mc verify` welds by grid edge (which
        // separates its triangles from its vertex sharing).
        for (program, mesh) in [
            ("isosurface (Rust crate)", iso_mesh.clone()),
            (
                "isosurface, as a soup welded by grid edge",
                iso_mesh.map(|m| unindexed(&m)),
            ),
        ] {
            programs.push(ProgramRow {
                program: program.into(),
                version: ISOSURFACE_VERSION.into(),
                verdict: mesh
                    .and_then(|m| verify_mesh(&vol, iso, &m, &opts).map_err(|e| e.to_string())),
            });
        }
        match peer_meshes(
            root,
            &data,
            dims,
            iso,
            &scratch.join(name.replace([' ', '³'], "")),
        ) {
            Ok(list) => {
                for (program, version, path) in list {
                    let verdict = path.and_then(|p| {
                        let mesh = Mesh::read(&p, None).map_err(|e| e.to_string())?;
                        verify_mesh(&vol, iso, &mesh, &opts).map_err(|e| e.to_string())
                    });
                    programs.push(ProgramRow {
                        program,
                        version,
                        verdict,
                    });
                }
            }
            Err(e) => peers_missing = Some(e),
        }
        cases.push(TopologyCase {
            name,
            dims,
            iso,
            truth,
            seconds: median(times),
            programs,
            isosurface_beyond: dropped,
        });
    }
    let _ = std::fs::remove_dir_all(&scratch);
    TopologyCampaign {
        cases,
        peers_missing,
    }
}

/// geocert's own table mesh must differ from the truth exactly in the tunnel cells, by
/// missing tunnels only, and be watertight; its trilinear mode must agree with the truth.
pub fn campaign_ok(c: &TopologyCampaign) -> bool {
    !c.cases.is_empty()
        && c.cases.iter().all(|case| {
            case.programs
                .get(1)
                .is_some_and(|tri| tri.verdict.as_ref().is_ok_and(|v| v.agrees()))
        })
        && c.cases.iter().all(|case| {
            case.programs.first().is_some_and(|own| match &own.verdict {
                Ok(v) => {
                    v.watertight
                        && v.mismatching_cells() == v.tunnel_cells_compared
                        && v.mismatches
                            .iter()
                            .all(|(k, _)| *k == MismatchKind::MissingTunnel)
                }
                Err(_) => false,
            })
        })
}

fn count(v: &MeshVerdict, kind: MismatchKind) -> usize {
    v.mismatches
        .iter()
        .find(|(k, _)| *k == kind)
        .map_or(0, |(_, n)| *n)
}

fn example_line(program: &str, case: &str, m: &CellMismatch) -> String {
    format!(
        "- **{program}**, {case}, cell {:?} ({:?}): corner values {:?} (Lorensen–Cline order); \
         the trilinear surface has components {:?}, the mesh {:?}; the oracle's corner groups \
         (positive, negative) {:?}.",
        m.cell, m.kind, m.values, m.expected, m.found, m.groups
    )
}

/// Writes the report section.
pub fn write_topology(s: &mut String, c: &TopologyCampaign) {
    let _ = writeln!(
        s,
        "\n## The trilinear interpolant's exact topology\n\n\
         `geocert::mc::trilinear` decides, for one cell, the connected components of the \
         trilinear isosurface inside it and the boundary cycles of each (a component with two \
         cycles is a tunnel). Ties follow the table's rules, which are the topology at the \
         isovalue minus an infinitesimal; every decision is the sign of a polynomial in the \
         corner values at a rational point of one axis, made in integers with the \
         infinitesimal as a formal variable (no square roots are needed: the slice saddles' \
         values are compared through their numerators). The proof \
         `mc.trilinear-topology` above checks it against an independent event sweep on every \
         integer cell in [−3, 3]⁸ at isovalues 0 and 1/2 and on random rational cells (what \
         `cargo test` runs), and `mc.trilinear-topology-wide` on every integer cell in \
         [−4, 4]⁸ (run by `geocert prove` only: minutes on one core). Whole \
         volumes add up exactly: `χ = Σ cells (2 − cycles per component) − face arcs + cut \
         edges`, components glued through cut edges.\n\n\
         | volume | isovalue | crossed cells | tunnel cells | χ | components (closed) | exact fallbacks | seconds (median of 3) |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|"
    );
    for case in &c.cases {
        let t = &case.truth;
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} ({}) | {} | {:.4} |",
            case.name,
            case.iso,
            t.cells,
            t.tunnel_cells,
            t.euler_characteristic,
            t.components.len(),
            t.components.iter().filter(|x| x.closed).count(),
            t.exact_fallbacks,
            case.seconds
        );
    }
    let _ = writeln!(
        s,
        "\n### Other programs' meshes against the trilinear truth (`geocert mc verify`)\n\n\
         Each program's mesh of the same `f32` volume, checked cell by cell: *face cycles* — \
         the mesh's boundary cycles in the cell differ (an ambiguous face decided unlike the \
         interpolant); *missing* / *extra tunnel* — the same cycles, grouped into a tube where \
         the interpolant has none or not where it has one. χ and components of the whole mesh \
         beside the truth's. The Python programs run through `benches/peers`; the `mcubes` \
         crate (Rust) runs in-process (a dependency of the `reports` feature), its triangles \
         unwelded as it writes them (`mc verify` joins vertices by grid edge).\n"
    );
    let beyond: Vec<String> = c
        .cases
        .iter()
        .map(|case| format!("{} on {}", case.isosurface_beyond, case.name))
        .collect();
    let _ = writeln!(
        s,
        "The `isosurface` crate (Rust, in-process too) marches one layer of cells past the \
         volume's last sample plane (its loop runs over all `size` layers and samples at \
         `z = size/(size − 1)`; the adapter clamps that to the last plane). Its triangles with \
         a vertex beyond the volume are dropped before checking: {}. Its second row is the \
         same triangles read as a soup, which `mc verify` welds by grid edge: it separates \
         the crate's triangles from its vertex sharing (its index cache gives one crossing \
         several vertices, so the indexed mesh is open).\n",
        beyond.join(", ")
    );
    if let Some(why) = &c.peers_missing {
        let _ = writeln!(s, "The other programs did not run: {why}.\n");
    }
    let _ = writeln!(
        s,
        "| volume | program | version | watertight | χ (truth) | components (truth) | cells compared | face cycles | missing tunnel | extra tunnel | shape |\n\
         |---|---|---|---|---:|---:|---:|---:|---:|---:|---:|"
    );
    let mut examples: Vec<(String, String, CellMismatch)> = Vec::new();
    for case in &c.cases {
        for p in &case.programs {
            match &p.verdict {
                Ok(v) => {
                    let _ = writeln!(
                        s,
                        "| {} | {} | {} | {} | {} ({}) | {} ({}) | {} | {} | {} | {} | {} |",
                        case.name,
                        p.program,
                        p.version,
                        v.watertight,
                        v.euler_characteristic,
                        v.truth_euler_characteristic,
                        v.components,
                        v.truth_components,
                        v.cells_compared,
                        count(v, MismatchKind::FaceCycles),
                        count(v, MismatchKind::MissingTunnel),
                        count(v, MismatchKind::ExtraTunnel),
                        count(v, MismatchKind::ComponentShape),
                    );
                    // One worked example per program and kind.
                    for m in &v.examples {
                        if !examples
                            .iter()
                            .any(|(prog, _, e)| *prog == p.program && e.kind == m.kind)
                        {
                            examples.push((p.program.clone(), case.name.clone(), m.clone()));
                        }
                    }
                }
                Err(e) => {
                    let _ = writeln!(
                        s,
                        "| {} | {} | {} | refused: {e} | | | | | | | |",
                        case.name, p.program, p.version
                    );
                }
            }
        }
    }
    if !examples.is_empty() {
        let _ = writeln!(
            s,
            "\nOne worked cell per program and kind (re-check with \
             `geocert::mc::trilinear::verify_cell`, which re-verifies the oracle's witnesses and \
             re-derives the groups by slicing across the other two axes):\n"
        );
        for (program, case, m) in &examples {
            let _ = writeln!(s, "{}", example_line(program, case, m));
        }
    }
    let _ = writeln!(
        s,
        "\ngeocert's own table mesh differs from the trilinear surface exactly in the tunnel \
         cells (the table draws two discs where the interpolant has a tube), and \
         `mc extract --topology trilinear` (tubes built as annuli through the cell, every \
         other polygon as the table triangulates it) agrees with it everywhere — no false \
         alarm: {}.",
        if campaign_ok(c) {
            "yes, on every volume"
        } else {
            "NO — see the table"
        }
    );
    let _ = writeln!(
        s,
        "\n**Are the tubes embedded?** The tube's topology is proved above; that its triangles \
         do not cross each other is geometry, proved by `mc.tube-embedding` (and \
         `mc.tube-embedding-wide`): every tube cell of [−3, 3]⁸ (and [−4, 4]⁸) at the isovalue \
         1/2, every pair of its triangles tested in exact integer arithmetic \
         (`geocert::mc::trilinear::embedding`). The two rings are zipped with their steps \
         interleaved by index ratio, aligned at the pair of start vertices whose zip has the \
         shortest diagonals (sum of squared lengths, compared exactly). Zipped from the cycles' \
         first vertices instead, as an earlier version did, 20,357 of the 39,456 tube cells of \
         [−3, 3]⁸ had crossing triangles."
    );
    let _ = writeln!(s);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The `isosurface` crate's mesh of three blobs is read as marching cubes on the volume's
    /// grid (every vertex on a cut edge: the adapter's scale and sign are right) with the
    /// table's triangle count. As indexed it is open: its index cache gives one crossing
    /// several vertices. As a soup welded by grid edge it is watertight with the truth's χ
    /// and components, and no cell differs.
    #[test]
    fn isosurface_crate_mesh_is_checked_on_the_grid() {
        let n = 24;
        let data = smooth("blobs", n);
        let vol = Volume::new([n; 3], data.iter().map(|&x| x as f64).collect()).unwrap();
        let (mesh, dropped) = isosurface_mesh(&data, [n; 3], 0.5).unwrap();
        assert_eq!(dropped, 0, "the blobs stay inside the volume");
        let opts = VerifyOptions::default();
        let own = extract_fast(&vol, 0.5).unwrap().0;
        let indexed = verify_mesh(&vol, 0.5, &mesh, &opts).unwrap();
        assert_eq!(indexed.interior_vertices, 0);
        assert_eq!(indexed.edge_vertices, indexed.vertices);
        assert_eq!(mesh.triangles.len(), own.triangles.len());
        assert!(indexed.vertices > own.vertices.len() && !indexed.watertight);
        let soup = verify_mesh(&vol, 0.5, &unindexed(&mesh), &opts).unwrap();
        assert_eq!(soup.vertices, own.vertices.len());
        assert!(soup.watertight);
        assert_eq!(soup.euler_characteristic, soup.truth_euler_characteristic);
        assert_eq!(soup.components, soup.truth_components);
        assert!(soup.mismatches.is_empty());
        // Non-cubic volumes are refused with a reason.
        assert!(isosurface_mesh(&data, [n, n, n - 1], 0.5).is_err());
    }
}
