//! `geocert mc`: marching cubes (Wünsche & Lin) — volume extraction, finite elements, the
//! table audit and export.

use crate::out::{choice, pretty, read, read_bytes, write};
use clap::{Subcommand, ValueEnum};
use geocert::mc::audit::{audit, export, parse_table, Numbering};
use geocert::mc::fe::{polygonise, CellRule, FeModel, FeOptions, NormalSource};
use geocert::mc::grid::{extract, extract_fast_parallel, read_raw, ExtractOptions, RawType};
use geocert::mc::trilinear::polygonise::extract_trilinear_path;
use geocert::mc::verify::{verify_mesh, MeshVerdict, Ties, VerifyOptions};
use geocert::mesh::Format;
use geocert::num::{parse_rational, Rational};
use geocert::Path;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Subcommand)]
pub(crate) enum Command {
    /// Extract the isosurface of a volume as a mesh: NIfTI-1 (`.nii`, `.nii.gz`), or raw
    /// little-endian samples (x fastest) with `--dims` and `--type`.
    Extract {
        volume: PathBuf,
        #[command(flatten)]
        raw: RawArgs,
        /// Isovalue: a number (exact as its f64) or "p/q" for the exact path.
        #[arg(long, allow_hyphen_values = true)]
        iso: String,
        /// Output mesh (.ply, .obj or .stl).
        #[arg(long)]
        out: PathBuf,
        #[arg(long, default_value_t = Path::Fast, value_parser = choice::<Path>(Path::NAMES))]
        path: Path,
        /// `table`: the paper's 656-entry table (a disc in every polygon); `trilinear`: the
        /// trilinear interpolant's topology in every cell (tubes where it has tunnels).
        #[arg(long, value_enum, default_value_t = Topology::Table)]
        topology: Topology,
        /// Fast path with the table: extract in slabs on this many threads (0: all cores),
        /// welded into the serial mesh.
        #[arg(long, default_value_t = 1)]
        threads: usize,
        #[arg(long)]
        json: bool,
    },
    /// Polygonise a finite element model (JSON: `{"kind": {"bases": [..]}, "coordinates":
    /// [[x,y,z], ..], "field": [..], "elements": [[8 node ids], ..]}`, see `mc demo
    /// --model-out`) in material space.
    Fe {
        model: PathBuf,
        /// Isovalue: a number (exact as its f64) or "p/q" for the exact path.
        #[arg(long, allow_hyphen_values = true)]
        iso: String,
        #[command(flatten)]
        fe: FeArgs,
    },
    /// The 0-isosurface of the built-in 16-element left ventricle (cubic Hermite ×
    /// cubic Hermite × linear Lagrange) with its strain-like field.
    Demo {
        /// Also write the model as JSON (the `mc fe` input format).
        #[arg(long)]
        model_out: Option<PathBuf>,
        #[command(flatten)]
        fe: FeArgs,
    },
    /// Audit a 256-configuration triangle table: 256 lines of edge ids, or a C/Rust array
    /// literal of 256×16 integers.
    Audit {
        table: PathBuf,
        #[arg(long, value_parser = choice::<Numbering>(Numbering::NAMES))]
        format: Numbering,
        #[arg(long)]
        json: bool,
    },
    /// Check a marching-cubes mesh made by any program from VOLUME against the trilinear
    /// interpolant's exact isosurface: vertices on cut edges at the crossings, watertight
    /// away from the volume's boundary, Euler characteristic and components, and cell by
    /// cell the face cycles and tunnels. Exit status 1 when the mesh differs.
    Verify {
        volume: PathBuf,
        /// The mesh (.ply, .obj, .stl or .vtk), in grid units unless --origin/--spacing.
        mesh: PathBuf,
        #[command(flatten)]
        raw: RawArgs,
        /// The isovalue the mesh was made at (an f64).
        #[arg(long, allow_hyphen_values = true)]
        iso: String,
        /// Mesh position of sample (0, 0, 0).
        #[arg(long, num_args = 3, value_names = ["X", "Y", "Z"], allow_hyphen_values = true)]
        origin: Option<Vec<f64>>,
        /// Distance between samples along x, y, z.
        #[arg(long, num_args = 3, value_names = ["X", "Y", "Z"])]
        spacing: Option<Vec<f64>>,
        /// How far (cell units) a vertex may be from a grid line or the crossing.
        #[arg(long, default_value_t = 1e-3)]
        tolerance: f64,
        /// Which side a sample equal to the isovalue lies on: `inside` (geocert, VTK),
        /// `outside` (scikit-image), or `auto` (inside, and outside where that fails or
        /// differs and some sample equals the isovalue).
        #[arg(long, default_value = "auto", value_parser = choice::<Ties>(Ties::NAMES))]
        ties: Ties,
        #[arg(long)]
        json: bool,
    },
    /// Print geocert's table as 256 lines in the given numbering, one decision for every
    /// ambiguous face.
    Export {
        #[arg(long, value_parser = choice::<Numbering>(Numbering::NAMES))]
        format: Numbering,
        /// `separate`: positive corners never joined across a face; `join`: always joined.
        #[arg(long, value_enum, default_value_t = FaceRule::Separate)]
        rule: FaceRule,
    },
}

/// Which topology `mc extract` draws in each cell.
#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum Topology {
    /// The 656-entry table.
    Table,
    /// The trilinear interpolant's.
    Trilinear,
}

/// How to read a raw volume (ignored, and refused, for NIfTI files).
#[derive(clap::Args)]
pub(crate) struct RawArgs {
    /// Raw volumes only: the sample counts along x, y, z.
    #[arg(long, num_args = 3, value_names = ["X", "Y", "Z"])]
    dims: Option<Vec<usize>>,
    /// Raw volumes only: the sample type.
    #[arg(long = "type", value_parser = choice::<RawType>(RawType::NAMES))]
    ty: Option<RawType>,
}

#[derive(clap::Args)]
pub(crate) struct FeArgs {
    /// Output mesh (.ply, .obj, .stl or .vtk); normals are written where the format has them.
    #[arg(long)]
    out: PathBuf,
    /// Cells per element along ξ₁ ξ₂ ξ₃ (default: the paper's 9 9 5 for the demo, 8 8 8
    /// otherwise).
    #[arg(long, num_args = 3, value_names = ["N1", "N2", "N3"])]
    cells: Option<Vec<usize>>,
    #[arg(long, default_value_t = Path::Fast, value_parser = choice::<Path>(Path::NAMES))]
    path: Path,
    /// Vertex normals from the interpolant's gradient or from finite differences (fast path).
    #[arg(long, default_value_t = NormalSource::Interpolant, value_parser = choice::<NormalSource>(NormalSource::NAMES))]
    normals: NormalSource,
    /// `table`: the 656-entry table in every cell; `trilinear` (trilinear Lagrange elements
    /// only): the interpolant's topology, with a tube through every cell where it has a
    /// tunnel.
    #[arg(long, default_value_t = CellRule::Table, value_parser = choice::<CellRule>(CellRule::NAMES))]
    topology: CellRule,
    #[arg(long)]
    json: bool,
}

/// The rule `mc export` applies on ambiguous faces.
#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum FaceRule {
    /// Positive corners never joined across a face.
    Separate,
    /// Always joined.
    Join,
}

pub(crate) fn run(c: Command) -> Result<ExitCode, String> {
    match c {
        Command::Extract {
            volume,
            raw,
            iso,
            out,
            path,
            topology,
            threads,
            json,
        } => extract_volume(volume, raw, &iso, out, path, (topology, threads), json),
        Command::Fe { model, iso, fe } => {
            let m: FeModel<f64> = serde_json::from_str(&read(&model)?)
                .map_err(|e| format!("{}: {e}", model.display()))?;
            m.validate()
                .map_err(|e| format!("{}: {e}", model.display()))?;
            let iso = parse_rational(&iso).map_err(|e| format!("--iso: {e}"))?;
            polygonise_model(&m, &iso, [8, 8, 8], fe)
        }
        Command::Demo { model_out, fe } => {
            let m = geocert::mc::fe::heart::left_ventricle();
            // Refuse a bad output name before writing anything.
            Format::from_path(&fe.out).map_err(|e| e.to_string())?;
            if let Some(p) = model_out {
                write(&p, pretty(&m)?)?;
            }
            let cells = geocert::mc::fe::heart::paper_options().cells;
            polygonise_model(&m, &Rational::from_integer(0.into()), cells, fe)
        }
        Command::Audit {
            table,
            format,
            json,
        } => {
            let tris =
                parse_table(&read(&table)?).map_err(|e| format!("{}: {e}", table.display()))?;
            let r = audit(&tris, format);
            if json {
                println!("{}", pretty(&r)?);
            } else {
                println!(
                    "{}: {} cracks, {} winding errors, {} edge errors, {} segments off the faces, {} wrong pairings",
                    table.display(),
                    r.cracks,
                    r.winding_errors,
                    r.edge_errors,
                    r.face_errors,
                    r.pairing_errors
                );
                println!("winding: {}", r.winding);
                println!("ambiguous faces: {}", r.ambiguous_face_rule);
                for d in &r.details {
                    println!("  {d}");
                }
                for (a, b, axis) in r.crack_pairs.iter().take(10) {
                    println!("  crack: configurations {a} and {b} across {axis}");
                }
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Verify {
            volume,
            mesh,
            raw,
            iso,
            origin,
            spacing,
            tolerance,
            ties,
            json,
        } => {
            let iso: f64 = iso
                .parse()
                .map_err(|_| format!("--iso {iso}: not a number"))?;
            let three = |v: Option<Vec<f64>>, d: f64, name: &str| -> Result<[f64; 3], String> {
                v.map_or(Ok([d; 3]), |v| {
                    v.try_into()
                        .map_err(|_| format!("--{name} takes three numbers"))
                })
            };
            let opts = VerifyOptions {
                origin: three(origin, 0.0, "origin")?,
                spacing: three(spacing, 1.0, "spacing")?,
                tolerance,
                ties,
            };
            let vol = load_volume(&volume, raw.dims, raw.ty)?;
            let m = geocert::mesh::Mesh::read(&mesh, None)
                .map_err(|e| format!("{}: {e}", mesh.display()))?;
            let v = verify_mesh(&vol, iso, &m, &opts)
                .map_err(|e| format!("{}: {e}", mesh.display()))?;
            if json {
                println!("{}", pretty(&v)?);
            } else {
                print_verdict(&mesh, &v);
            }
            Ok(if v.agrees() {
                ExitCode::SUCCESS
            } else {
                ExitCode::from(1)
            })
        }
        Command::Export { format, rule } => {
            print!("{}", export(format, |_| matches!(rule, FaceRule::Join)));
            Ok(ExitCode::SUCCESS)
        }
    }
}

/// The verdict of `mc verify` as text.
fn print_verdict(mesh: &std::path::Path, v: &MeshVerdict) {
    println!(
        "{}: {} triangles, {} vertices ({} on cut edges, {} off the grid lines, {} ambiguous on grid points)",
        mesh.display(),
        v.triangles,
        v.vertices,
        v.edge_vertices,
        v.interior_vertices,
        v.ambiguous_vertices
    );
    println!("samples equal to the isovalue read as {}", v.ties);
    println!(
        "watertight away from the volume boundary: {} ({} open, {} non-manifold edges)",
        v.watertight, v.open_edges, v.nonmanifold_edges
    );
    println!(
        "Euler characteristic {} (trilinear {}), components {} (trilinear {})",
        v.euler_characteristic, v.truth_euler_characteristic, v.components, v.truth_components
    );
    println!(
        "cells compared {}, skipped {}; trilinear tunnels in {} cells",
        v.cells_compared, v.cells_skipped, v.truth_tunnel_cells
    );
    if v.mismatches.is_empty() {
        println!("every compared cell has the trilinear topology");
    }
    for (kind, n) in &v.mismatches {
        println!("  {n} cells: {kind:?}");
    }
    for m in &v.examples {
        println!(
            "  cell {:?} {:?}: expected {:?}, found {:?}; corner values {:?}",
            m.cell, m.kind, m.expected, m.found, m.values
        );
    }
    println!(
        "verdict: {}",
        if v.agrees() {
            "the trilinear topology"
        } else {
            "differs from the trilinear topology"
        }
    );
}

/// `mc extract`: reads a NIfTI or raw volume and polygonises it.
fn extract_volume(
    volume: PathBuf,
    raw: RawArgs,
    iso: &str,
    out: PathBuf,
    path: Path,
    (topology, threads): (Topology, usize),
    json: bool,
) -> Result<ExitCode, String> {
    let format = Format::from_path(&out).map_err(|e| e.to_string())?;
    let iso_q = parse_rational(iso).map_err(|e| format!("--iso: {e}"))?;
    let vol = load_volume(&volume, raw.dims, raw.ty)?;
    let start = std::time::Instant::now();
    let threads = match threads {
        0 => std::thread::available_parallelism().map_or(1, |t| t.get()),
        t => t,
    };
    let (mesh, stats) = match topology {
        Topology::Table if threads > 1 && path != Path::Exact => {
            let iso_f = geocert::num::rational_to_f64(&iso_q);
            if geocert::num::rational_from_f64(iso_f, "iso").ok().as_ref() != Some(&iso_q) {
                return Err(format!(
                    "--iso {iso}: not an f64; the fast path takes f64 isovalues"
                ));
            }
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .map_err(|e| e.to_string())?;
            pool.install(|| extract_fast_parallel(&vol, iso_f, 2 * threads))
                .map_err(|e| format!("--iso {iso}: {e}"))?
        }
        Topology::Table => extract(&vol, &iso_q, &ExtractOptions::new().with_path(path))
            .map_err(|e| format!("--iso {iso}: {e}"))?,
        Topology::Trilinear => {
            let (mesh, t) = extract_trilinear_path(&vol, &iso_q, path)
                .map_err(|e| format!("--iso {iso}: {e}"))?;
            if !json {
                println!(
                    "trilinear topology: {} crossed cells, {} with a tunnel, {} decided exactly",
                    t.cells, t.tunnel_cells, t.exact_fallbacks
                );
            }
            let cells = vol.dims.iter().map(|d| d - 1).product();
            (
                mesh,
                geocert::mc::grid::ExtractStats {
                    cells,
                    ..Default::default()
                },
            )
        }
    };
    let seconds = start.elapsed().as_secs_f64();
    let closed = mesh.check_manifold().map(|b| b == 0).unwrap_or(false);
    mesh.write(&out, format).map_err(|e| e.to_string())?;
    let cells_per_second = stats.cells as f64 / seconds.max(1e-9);
    if json {
        let v = serde_json::json!({
            "triangles": mesh.triangles.len(),
            "vertices": mesh.vertices.len(),
            "ambiguous_faces": stats.ambiguous_faces,
            "cells_per_second": cells_per_second,
            "closed": closed,
        });
        println!("{v}");
    } else {
        println!(
            "{} triangles, {} vertices, {} ambiguous faces, {:.1} Mcells/s, closed: {closed}",
            mesh.triangles.len(),
            mesh.vertices.len(),
            stats.ambiguous_faces,
            cells_per_second / 1e6
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// Reads a NIfTI (`.nii`, `.nii.gz`) or raw volume (`--dims X Y Z --type T`).
pub(crate) fn load_volume(
    volume: &std::path::Path,
    dims: Option<Vec<usize>>,
    ty: Option<RawType>,
) -> Result<geocert::mc::grid::Volume<f64>, String> {
    let bytes = read_bytes(volume)?;
    let name = volume.to_string_lossy().to_ascii_lowercase();
    if name.ends_with(".nii") || name.ends_with(".nii.gz") {
        if dims.is_some() || ty.is_some() {
            return Err(
                "--dims and --type are for raw volumes; NIfTI files carry their own".into(),
            );
        }
        geocert::mc::nifti::read_nifti(&bytes)
    } else {
        let (Some(dims), Some(ty)) = (dims, ty) else {
            return Err(format!(
                "{}: a raw volume needs --dims X Y Z and --type (or use a .nii / .nii.gz file)",
                volume.display()
            ));
        };
        let dims: [usize; 3] = dims
            .try_into()
            .map_err(|_| "--dims takes three sizes".to_string())?;
        read_raw(&bytes, dims, ty)
    }
    .map_err(|e| format!("{}: {e}", volume.display()))
}

/// Polygonises a finite element model on either path and writes the mesh.
fn polygonise_model(
    m: &FeModel<f64>,
    iso: &Rational,
    default_cells: [usize; 3],
    a: FeArgs,
) -> Result<ExitCode, String> {
    let format = Format::from_path(&a.out).map_err(|e| e.to_string())?;
    let cells: [usize; 3] = match a.cells {
        Some(c) => c
            .try_into()
            .map_err(|_| "--cells takes three counts".to_string())?,
        None => default_cells,
    };
    let opts = FeOptions::new()
        .with_cells(cells)
        .with_normals(a.normals)
        .with_path(a.path)
        .with_topology(a.topology);
    let start = std::time::Instant::now();
    let surface = polygonise(m, iso, &opts).map_err(|e| e.to_string())?;
    let (mesh, stats) = (surface.mesh, surface.stats);
    let seconds = start.elapsed().as_secs_f64();
    let manifold = mesh.check_manifold();
    let boundary_edges = manifold.as_ref().ok().copied();
    mesh.write(&a.out, format).map_err(|e| e.to_string())?;
    let v = serde_json::json!({
        "triangles": mesh.triangles.len(),
        "vertices": mesh.vertices.len(),
        "cells_per_second": stats.cells as f64 / seconds.max(1e-9),
        "manifold": manifold.is_ok(),
        "boundary_edges": boundary_edges,
        "closed": boundary_edges == Some(0),
        "euler_characteristic": mesh.euler_characteristic(),
        "stats": stats,
    });
    if a.json {
        println!("{v}");
    } else {
        println!(
            "{} triangles, {} vertices; {} elements, {} cells ({} cut, {} with an ambiguous face, {} drawn with a tube); {} vertices welded and {} collapsed triangles removed (Figure 7); manifold: {}, boundary edges: {}, Euler characteristic {}; {:.2} Mcells/s",
            mesh.triangles.len(),
            mesh.vertices.len(),
            stats.elements,
            stats.cells,
            stats.cut_cells,
            stats.ambiguous_cells,
            stats.tunnel_cells,
            stats.welded_vertices,
            stats.degenerate_triangles,
            manifold.is_ok(),
            boundary_edges.map(|b| b.to_string()).unwrap_or_else(|| "-".into()),
            mesh.euler_characteristic(),
            stats.cells as f64 / seconds.max(1e-9) / 1e6
        );
    }
    Ok(ExitCode::SUCCESS)
}
