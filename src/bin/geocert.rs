//! The geocert command-line tool: parses arguments, calls the library, prints.

use clap::{Parser, Subcommand, ValueEnum};
use geocert::bernstein::io::{
    certificate_for, poly_from_json, verify_certificate_file, CertificateFile,
};
use geocert::bernstein::positivity::WitnessValue;
use geocert::bernstein::{
    prove_positive_exact, prove_positive_fast, prove_positive_filtered, FastBernstein, Limits,
    PositivityVerdict,
};
use geocert::num::rational_to_string;
use geocert::report::{self, campaign, RunMeta};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;
use std::process::ExitCode;

/// Like std's `println!`, but a closed stdout (`geocert … | head`) ends the process quietly.
macro_rules! println {
    () => { say(format_args!("\n")) };
    ($($arg:tt)*) => { say(format_args!("{}\n", format_args!($($arg)*))) };
}

/// Like std's `print!`, but a closed stdout ends the process quietly.
macro_rules! print {
    ($($arg:tt)*) => { say(format_args!($($arg)*)) };
}

/// Writes to stdout; exits with status 0 when the reader has gone (broken pipe), with
/// status 2 and a message on any other write error, instead of panicking as `println!` does.
fn say(args: std::fmt::Arguments) {
    use std::io::Write;
    if let Err(e) = std::io::stdout().lock().write_fmt(args) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: cannot write to stdout: {e}");
        std::process::exit(2);
    }
}

#[derive(Parser)]
#[command(
    name = "geocert",
    version,
    about = "Exact-arithmetic verification and reference engine for geometric algorithms"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run every exhaustive proof and the exact-vs-fast campaign; write reports/.
    Prove {
        /// Only this part (`mc-table`: the marching-cubes table proofs; prints, writes nothing).
        #[arg(value_enum)]
        part: Option<ProvePart>,
        /// Where to write the reports.
        #[arg(long, default_value = "reports")]
        out: PathBuf,
        /// Print a JSON summary on stdout.
        #[arg(long)]
        json: bool,
    },
    /// Prove or refute p > 0 on the unit box for a Bernstein polynomial given as JSON.
    Positivity {
        /// `{"degrees": [..], "coeffs": [..]}`; coefficients are JSON numbers (exact f64) or "p/q" strings.
        file: PathBuf,
        #[arg(long, value_enum, default_value_t = PathKind::Filtered)]
        path: PathKind,
        #[arg(long, default_value_t = 12)]
        max_depth: u32,
        /// Write the certificate here (only for decided verdicts).
        #[arg(long)]
        cert: Option<PathBuf>,
        #[arg(long)]
        json: bool,
    },
    /// Re-check a positivity certificate independently.
    VerifyCert { file: PathBuf },
    /// Free-form deformation injectivity (Gain & Dodgson).
    #[command(subcommand)]
    Ffd(FfdCommand),
    /// Marching cubes (Wünsche & Lin): table audit and export.
    #[command(subcommand)]
    Mc(McCommand),
    /// Decimate a triangle mesh by node removal (Krivograd et al.) and write the history that
    /// restores it exactly. IN is a .ply/.obj/.stl/.vtk file, or `builtin:grid:SIDE` (a
    /// SIDE×SIDE height field like the paper's Table 1) or `builtin:plate` (the Kirsch plate
    /// of Fig. 9 with its von Mises field).
    Decimate {
        input: String,
        /// Keep this fraction of the nodes (default 0.01 unless --nodes or --max-error).
        #[arg(long, conflicts_with_all = ["nodes", "max_error"])]
        keep: Option<f64>,
        /// Keep this many nodes.
        #[arg(long, conflicts_with = "max_error")]
        nodes: Option<usize>,
        /// Remove nodes while their evaluation value is at most this.
        #[arg(long)]
        max_error: Option<f64>,
        #[arg(long, value_enum, default_value_t = CriterionArg::Error)]
        criterion: CriterionArg,
        #[arg(long, value_enum, default_value_t = McPath::Fast)]
        path: McPath,
        /// The decimated mesh (.ply, .obj, .stl or .vtk).
        #[arg(long)]
        out: PathBuf,
        /// The history file that undecimates OUT.
        #[arg(long)]
        history: PathBuf,
        /// The nodal scalar field: a PLY vertex property or VTK POINT_DATA array name.
        #[arg(long)]
        scalar: Option<String>,
        /// Never remove border nodes (default: only while the border stays intact).
        #[arg(long)]
        exclude_border: bool,
        #[arg(long, value_enum, default_value_t = ProjectionArg::Auto)]
        projection: ProjectionArg,
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
        #[arg(long)]
        json: bool,
    },
    /// Restore a decimated mesh with its history: undo the last N steps (all by default).
    Undecimate {
        input: PathBuf,
        #[arg(long)]
        history: PathBuf,
        #[arg(long)]
        steps: Option<usize>,
        #[arg(long)]
        out: PathBuf,
    },
}

#[derive(Clone, Copy, ValueEnum)]
enum CriterionArg {
    Angle,
    Scalar,
    Error,
}

#[derive(Clone, Copy, ValueEnum)]
enum ProjectionArg {
    Auto,
    Xy,
    PerFan,
}

#[derive(Subcommand)]
enum McCommand {
    /// Extract the isosurface of a volume as a mesh: NIfTI-1 (`.nii`, `.nii.gz`), or raw
    /// little-endian samples (x fastest) with `--dims` and `--type`.
    Extract {
        volume: PathBuf,
        /// Raw volumes only: the sample counts along x, y, z.
        #[arg(long, num_args = 3, value_names = ["X", "Y", "Z"])]
        dims: Option<Vec<usize>>,
        /// Raw volumes only: the sample type.
        #[arg(long = "type", value_enum)]
        ty: Option<RawKind>,
        /// Isovalue: a number (exact as its f64) or "p/q" for the exact path.
        #[arg(long, allow_hyphen_values = true)]
        iso: String,
        /// Output mesh (.ply, .obj or .stl).
        #[arg(long)]
        out: PathBuf,
        #[arg(long, value_enum, default_value_t = McPath::Fast)]
        path: McPath,
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
        #[arg(long, value_enum)]
        format: TableFormat,
        #[arg(long)]
        json: bool,
    },
    /// Print geocert's table as 256 lines in the given numbering, one decision for every
    /// ambiguous face.
    Export {
        #[arg(long, value_enum)]
        format: TableFormat,
        /// `separate`: positive corners never joined across a face; `join`: always joined.
        #[arg(long, value_enum, default_value_t = FaceRule::Separate)]
        rule: FaceRule,
    },
}

#[derive(clap::Args)]
struct FeArgs {
    /// Output mesh (.ply, .obj, .stl or .vtk); normals are written where the format has them.
    #[arg(long)]
    out: PathBuf,
    /// Cells per element along ξ₁ ξ₂ ξ₃ (default: the paper's 9 9 5 for the demo, 8 8 8
    /// otherwise).
    #[arg(long, num_args = 3, value_names = ["N1", "N2", "N3"])]
    cells: Option<Vec<usize>>,
    #[arg(long, value_enum, default_value_t = McPath::Fast)]
    path: McPath,
    /// Vertex normals from the interpolant's gradient or from finite differences (fast path).
    #[arg(long, value_enum, default_value_t = NormalKind::Interpolant)]
    normals: NormalKind,
    #[arg(long)]
    json: bool,
}

#[derive(Clone, Copy, ValueEnum)]
enum NormalKind {
    Interpolant,
    FiniteDifference,
}

#[derive(Clone, Copy, ValueEnum)]
enum RawKind {
    F32,
    U8,
    I16,
}

#[derive(Clone, Copy, ValueEnum, PartialEq)]
enum McPath {
    Exact,
    Fast,
}

#[derive(Clone, Copy, ValueEnum)]
enum TableFormat {
    Bourke,
    Vtk,
}

#[derive(Clone, Copy, ValueEnum)]
enum FaceRule {
    Separate,
    Join,
}

#[derive(Subcommand)]
enum FfdCommand {
    /// Decide injectivity (det J > 0, Theorem 1) of one lattice or an array of lattices.
    Check {
        /// `{"basis": "bspline"|"bezier", "order": [l,m,n], "cells": [a,b,c], "points": [[x,y,z], ..]}` or an array of them.
        lattice: PathBuf,
        #[arg(long, value_enum, default_value_t = PathKind::Filtered)]
        path: PathKind,
        /// Deepest octree level per cell.
        #[arg(long, default_value_t = 12)]
        max_depth: u32,
        /// Wall-clock budget per cell, in seconds.
        #[arg(long)]
        time_limit: Option<f64>,
        /// Write the certificate(s) here (an array for an array input; `null` where undecided).
        #[arg(long)]
        cert: Option<PathBuf>,
        /// One JSON object per lattice (an array for an array input).
        #[arg(long)]
        json: bool,
    },
    /// Re-check an injectivity certificate (or an array of them) independently.
    VerifyCert { file: PathBuf },
    /// Injective DMFFD (Section 8): split the drags until every step is certified injective;
    /// write the ordered steps (constraints and lattice of each) as JSON.
    Drag {
        /// The lattice whose shape (basis, orders, cells) the drags act on; every step deforms
        /// the undeformed lattice of that shape (X ≡ U), as in the paper.
        lattice: PathBuf,
        /// `{"constraints": [{"point": [x,y,z], "delta": [dx,dy,dz]}, ..]}` in parameter
        /// space (the domain [0,a]×[0,b]×[0,c]); numbers exact as f64 or "p/q" strings.
        #[arg(long)]
        constraints: PathBuf,
        /// The test that certifies each step.
        #[arg(long, value_enum, default_value_t = DragTestKind::Conic)]
        test: DragTestKind,
        /// Deepest halving before the drag is refused.
        #[arg(long, default_value_t = 8)]
        max_depth: u32,
        /// f64 solve and certified f64 tests (each step's lattice is the rounded one, and it
        /// is that lattice which is certified); default: exact rationals, constraints met exactly.
        #[arg(long)]
        fast: bool,
        /// Write the steps here (default: stdout).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Deform a mesh (PLY, OBJ or STL) by a lattice, or by each lattice of an array in turn
    /// (the steps file written by `ffd drag` is accepted too).
    Deform {
        lattice: PathBuf,
        mesh: PathBuf,
        /// Output mesh; the format follows the extension.
        #[arg(long)]
        out: PathBuf,
        /// Embed the mesh by mapping its bounding box (grown by 10 % per side) onto the
        /// lattice's domain; otherwise mesh coordinates are parameters.
        #[arg(long)]
        fit: bool,
    },
}

#[derive(Clone, Copy, ValueEnum)]
enum ProvePart {
    McTable,
}

#[derive(Clone, Copy, ValueEnum)]
enum DragTestKind {
    Conic,
    Phi,
    Exact,
}

#[derive(Clone, Copy, ValueEnum)]
enum PathKind {
    Exact,
    Fast,
    Filtered,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

fn run(cli: Cli) -> Result<ExitCode, String> {
    match cli.command {
        Command::Prove {
            part: Some(ProvePart::McTable),
            json,
            ..
        } => prove_mc_table(json),
        Command::Prove { out, json, .. } => prove(out, json),
        Command::Positivity {
            file,
            path,
            max_depth,
            cert,
            json,
        } => positivity(file, path, max_depth, cert, json),
        Command::Ffd(c) => ffd(c),
        Command::Mc(c) => mc(c),
        Command::Decimate {
            input,
            keep,
            nodes,
            max_error,
            criterion,
            path,
            out,
            history,
            scalar,
            exclude_border,
            projection,
            k,
            fixed_intervals,
            eager,
            no_look_ahead,
            json,
        } => {
            use geocert::decimate::{BorderPolicy, Criterion, Options, ProjectionChoice, Target};
            let options = Options {
                criterion: match criterion {
                    CriterionArg::Angle => Criterion::Angle,
                    CriterionArg::Scalar => Criterion::Scalar,
                    CriterionArg::Error => Criterion::Error,
                },
                target: match (keep, nodes, max_error) {
                    (_, Some(n), _) => Target::Nodes(n),
                    (_, _, Some(e)) => Target::ErrorBound(e),
                    (k, _, _) => Target::Keep(k.unwrap_or(0.01)),
                },
                border: if exclude_border {
                    BorderPolicy::Exclude
                } else {
                    BorderPolicy::Intact
                },
                projection: match projection {
                    ProjectionArg::Auto => ProjectionChoice::Auto,
                    ProjectionArg::Xy => ProjectionChoice::Xy,
                    ProjectionArg::PerFan => ProjectionChoice::PerFan,
                },
                k,
                rebin: !fixed_intervals,
                lazy: !eager,
                look_ahead: !no_look_ahead,
                ..Options::default()
            };
            let path = match path {
                McPath::Fast => geocert::decimate::Path::Fast,
                McPath::Exact => geocert::decimate::Path::Exact,
            };
            decimate_cmd(
                &input,
                scalar.as_deref(),
                &options,
                path,
                &out,
                &history,
                json,
            )
        }
        Command::Undecimate {
            input,
            history,
            steps,
            out,
        } => undecimate_cmd(&input, &history, steps, &out),
        Command::VerifyCert { file } => {
            let text =
                std::fs::read_to_string(&file).map_err(|e| format!("{}: {e}", file.display()))?;
            let c: CertificateFile = serde_json::from_str(&text)
                .map_err(|e| format!("{}: not a certificate: {e}", file.display()))?;
            match verify_certificate_file(&c) {
                Ok(msg) => {
                    println!("valid: {msg}");
                    Ok(ExitCode::SUCCESS)
                }
                Err(e) => {
                    println!("invalid: {e}");
                    Ok(ExitCode::from(1))
                }
            }
        }
    }
}

fn read(file: &PathBuf) -> Result<String, String> {
    std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))
}

fn ffd(c: FfdCommand) -> Result<ExitCode, String> {
    use geocert::ffd::{
        check_injectivity, lattices_from_json, verify_injectivity_certificate, CheckOptions,
        InjectivityCertificate, TestPath,
    };
    match c {
        FfdCommand::Check {
            lattice,
            path,
            max_depth,
            time_limit,
            cert,
            json,
        } => {
            let text = read(&lattice)?;
            let is_array = text.trim_start().starts_with('[');
            let lattices =
                lattices_from_json(&text).map_err(|e| format!("{}: {e}", lattice.display()))?;
            let time_limit = match time_limit {
                Some(t) if !(t.is_finite() && t > 0.0) => {
                    return Err(format!(
                        "--time-limit must be a positive number of seconds, got {t}"
                    ))
                }
                t => t.map(std::time::Duration::from_secs_f64),
            };
            let opts = CheckOptions {
                path: match path {
                    PathKind::Exact => TestPath::Exact,
                    PathKind::Fast => TestPath::Fast,
                    PathKind::Filtered => TestPath::Filtered,
                },
                limits: Limits {
                    max_depth,
                    time_limit,
                    ..Limits::default()
                },
            };
            let mut reports = Vec::new();
            for (i, l) in lattices.iter().enumerate() {
                let r = check_injectivity(l, opts).map_err(|e| format!("lattice {i}: {e}"))?;
                reports.push(r);
            }
            if let Some(cert_path) = cert {
                let certs: Vec<Option<InjectivityCertificate>> = lattices
                    .iter()
                    .zip(&reports)
                    .map(|(l, r)| InjectivityCertificate::from_report(l, r))
                    .collect();
                let value = if is_array {
                    serde_json::to_value(&certs)
                } else {
                    serde_json::to_value(&certs[0])
                }
                .map_err(|e| e.to_string())?;
                let body = serde_json::to_string_pretty(&value).map_err(|e| e.to_string())?;
                std::fs::write(&cert_path, body)
                    .map_err(|e| format!("{}: {e}", cert_path.display()))?;
            }
            if json {
                let values: Vec<_> = reports.iter().map(|r| r.to_json()).collect();
                let out = if is_array {
                    serde_json::Value::Array(values)
                } else {
                    values.into_iter().next().unwrap_or_default()
                };
                println!(
                    "{}",
                    serde_json::to_string_pretty(&out).map_err(|e| e.to_string())?
                );
            } else {
                for (i, r) in reports.iter().enumerate() {
                    let bound = r
                        .min_det_lower_bound
                        .as_ref()
                        .map(|b| format!(", det J ≥ {}", geocert::num::rational_to_f64(b)))
                        .unwrap_or_default();
                    let detail = match &r.verdict {
                        geocert::ffd::InjectivityVerdict::NotInjective { point, det, .. } => {
                            format!(
                                ": det J({}) = {} ≤ 0",
                                point
                                    .iter()
                                    .map(rational_to_string)
                                    .collect::<Vec<_>>()
                                    .join(", "),
                                rational_to_string(det)
                            )
                        }
                        geocert::ffd::InjectivityVerdict::Undecided { cell, limit, .. } => {
                            format!(": limit {limit:?} hit on cell {cell:?}")
                        }
                        geocert::ffd::InjectivityVerdict::Uncertain { cell, boxes } => {
                            format!(
                                ": {} boxes of cell {cell:?} need the exact path",
                                boxes.len()
                            )
                        }
                        _ => String::new(),
                    };
                    println!(
                        "lattice {i}: {}{detail} ({} leaves, {} path{bound})",
                        r.verdict.name(),
                        r.leaves,
                        r.path.name()
                    );
                }
            }
            Ok(ExitCode::SUCCESS)
        }
        FfdCommand::Drag {
            lattice,
            constraints,
            test,
            max_depth,
            fast,
            out,
        } => ffd_drag(lattice, constraints, test, max_depth, fast, out),
        FfdCommand::Deform {
            lattice,
            mesh,
            out,
            fit,
        } => ffd_deform(lattice, mesh, out, fit),
        FfdCommand::VerifyCert { file } => {
            let text = read(&file)?;
            let value: serde_json::Value = serde_json::from_str(&text)
                .map_err(|e| format!("{}: not JSON: {e}", file.display()))?;
            let items = match value {
                serde_json::Value::Array(a) => a,
                other => vec![other],
            };
            let mut all_ok = true;
            for (i, item) in items.into_iter().enumerate() {
                if item.is_null() {
                    println!("certificate {i}: none (undecided verdict)");
                    continue;
                }
                let c: InjectivityCertificate = match serde_json::from_value(item) {
                    Ok(c) => c,
                    Err(e) => {
                        println!("certificate {i}: invalid: not a certificate: {e}");
                        all_ok = false;
                        continue;
                    }
                };
                match verify_injectivity_certificate(&c) {
                    Ok(msg) => println!("certificate {i}: valid: {msg}"),
                    Err(e) => {
                        println!("certificate {i}: invalid: {e}");
                        all_ok = false;
                    }
                }
            }
            Ok(if all_ok {
                ExitCode::SUCCESS
            } else {
                ExitCode::from(1)
            })
        }
    }
}

/// Lattices from a lattice file, a lattice array, or a steps file of `ffd drag`.
fn lattices_or_steps(file: &PathBuf) -> Result<Vec<geocert::ffd::Lattice>, String> {
    let text = read(file)?;
    let value: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| format!("{}: not JSON: {e}", file.display()))?;
    let items = match &value {
        serde_json::Value::Array(a) => a.clone(),
        other => vec![other.clone()],
    };
    items
        .iter()
        .enumerate()
        .map(|(i, item)| {
            let v = item.get("lattice").unwrap_or(item);
            geocert::ffd::lattice::lattice_from_value(v)
                .map_err(|e| format!("{}: lattice {i}: {e}", file.display()))
        })
        .collect()
}

fn ffd_drag(
    lattice: PathBuf,
    constraints: PathBuf,
    test: DragTestKind,
    max_depth: u32,
    fast: bool,
    out: Option<PathBuf>,
) -> Result<ExitCode, String> {
    use geocert::ffd::manipulation::{
        constraints_from_json, injective_drag, steps_to_json, DragOptions, DragTest,
    };
    let shape = lattices_or_steps(&lattice)?
        .into_iter()
        .next()
        .ok_or_else(|| format!("{}: no lattice", lattice.display()))?;
    let cs = constraints_from_json(&read(&constraints)?)
        .map_err(|e| format!("{}: {e}", constraints.display()))?;
    let opts = DragOptions {
        test: match test {
            DragTestKind::Conic => DragTest::Conic,
            DragTestKind::Phi => DragTest::Phi,
            DragTestKind::Exact => DragTest::Exact,
        },
        max_depth,
        exact: !fast,
        ..Default::default()
    };
    let start = std::time::Instant::now();
    let steps = injective_drag(&shape, &cs, opts).map_err(|e| e.to_string())?;
    let secs = start.elapsed().as_secs_f64();
    let text = serde_json::to_string_pretty(&steps_to_json(&steps)).map_err(|e| e.to_string())?;
    match &out {
        Some(path) => std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))?,
        None => println!("{text}"),
    }
    eprintln!(
        "{} constraint(s) in {} certified step(s), deepest split {}, {:.3} s ({} path)",
        cs.len(),
        steps.len(),
        steps.iter().map(|s| s.depth).max().unwrap_or(0),
        secs,
        if fast { "f64" } else { "exact" }
    );
    Ok(ExitCode::SUCCESS)
}

fn ffd_deform(
    lattice: PathBuf,
    mesh: PathBuf,
    out: PathBuf,
    fit: bool,
) -> Result<ExitCode, String> {
    use geocert::ffd::deform::{deform_points_fast, Fit};
    use geocert::mesh::{Format, Mesh};
    let lattices = lattices_or_steps(&lattice)?;
    let first = lattices
        .first()
        .ok_or_else(|| format!("{}: no lattice", lattice.display()))?;
    let format = Format::from_path(&out).map_err(|e| e.to_string())?;
    let mut m = Mesh::read(&mesh, None).map_err(|e| format!("{}: {e}", mesh.display()))?;
    let fit = if fit {
        Some(Fit::bounding_box(&m.vertices, first, 0.1).map_err(|e| e.to_string())?)
    } else {
        None
    };
    deform_points_fast(&lattices, fit.as_ref(), &mut m.vertices)
        .map_err(|e| format!("{}: {e}", mesh.display()))?;
    m.write(&out, format).map_err(|e| e.to_string())?;
    eprintln!(
        "deformed {} vertices by {} lattice(s) into {}",
        m.vertices.len(),
        lattices.len(),
        out.display()
    );
    Ok(ExitCode::SUCCESS)
}

fn mc(c: McCommand) -> Result<ExitCode, String> {
    use geocert::mc::audit::{audit, export, parse_table, Numbering};
    let numbering = |f: TableFormat| match f {
        TableFormat::Bourke => Numbering::Bourke,
        TableFormat::Vtk => Numbering::Vtk,
    };
    match c {
        McCommand::Extract {
            volume,
            dims,
            ty,
            iso,
            out,
            path,
            json,
        } => mc_extract(volume, dims, ty, iso, out, path, json),
        McCommand::Fe { model, iso, fe } => {
            let text =
                std::fs::read_to_string(&model).map_err(|e| format!("{}: {e}", model.display()))?;
            let m: geocert::mc::fe::FeModel<f64> =
                serde_json::from_str(&text).map_err(|e| format!("{}: {e}", model.display()))?;
            m.validate()
                .map_err(|e| format!("{}: {e}", model.display()))?;
            let iso = geocert::num::parse_rational(&iso).map_err(|e| format!("--iso: {e}"))?;
            mc_fe(&m, iso, [8, 8, 8], fe)
        }
        McCommand::Demo { model_out, fe } => {
            let m = geocert::mc::fe::heart::left_ventricle();
            // Refuse a bad output name before writing anything.
            geocert::mesh::Format::from_path(&fe.out).map_err(|e| e.to_string())?;
            if let Some(p) = model_out {
                let text = serde_json::to_string_pretty(&m).map_err(|e| e.to_string())?;
                std::fs::write(&p, text).map_err(|e| format!("{}: {e}", p.display()))?;
            }
            let cells = geocert::mc::fe::heart::paper_options().cells;
            mc_fe(
                &m,
                geocert::num::Rational::from_integer(0.into()),
                cells,
                fe,
            )
        }
        McCommand::Audit {
            table,
            format,
            json,
        } => {
            let tris =
                parse_table(&read(&table)?).map_err(|e| format!("{}: {e}", table.display()))?;
            let r = audit(&tris, numbering(format));
            if json {
                println!(
                    "{}",
                    serde_json::to_string_pretty(&r).map_err(|e| e.to_string())?
                );
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
        McCommand::Export { format, rule } => {
            print!(
                "{}",
                export(numbering(format), |_| matches!(rule, FaceRule::Join))
            );
            Ok(ExitCode::SUCCESS)
        }
    }
}

fn mc_extract(
    volume: PathBuf,
    dims: Option<Vec<usize>>,
    ty: Option<RawKind>,
    iso: String,
    out: PathBuf,
    path: McPath,
    json: bool,
) -> Result<ExitCode, String> {
    use geocert::mc::grid::{extract_exact, extract_fast, read_raw, RawType, Volume};
    use geocert::mesh::Format;
    let format = Format::from_path(&out).map_err(|e| e.to_string())?;
    let iso_q = geocert::num::parse_rational(&iso).map_err(|e| format!("--iso: {e}"))?;
    let bytes = std::fs::read(&volume).map_err(|e| format!("{}: {e}", volume.display()))?;
    let name = volume.to_string_lossy().to_ascii_lowercase();
    let vol = if name.ends_with(".nii") || name.ends_with(".nii.gz") {
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
        let raw = match ty {
            RawKind::F32 => RawType::F32,
            RawKind::U8 => RawType::U8,
            RawKind::I16 => RawType::I16,
        };
        read_raw(&bytes, dims, raw)
    }
    .map_err(|e| format!("{}: {e}", volume.display()))?;
    let dims = vol.dims;
    let start = std::time::Instant::now();
    let (mesh, stats) = match path {
        McPath::Fast => {
            let iso_f = geocert::num::rational_to_f64(&iso_q);
            if geocert::num::rational_from_f64(iso_f, "iso").ok() != Some(iso_q.clone()) {
                return Err(format!(
                    "--iso {iso} is not an f64; use --path exact for rational isovalues"
                ));
            }
            extract_fast(&vol, iso_f).map_err(|e| e.to_string())?
        }
        McPath::Exact => {
            let q: Result<Vec<_>, _> = vol
                .values
                .iter()
                .map(|&v| geocert::num::rational_from_f64(v, "sample"))
                .collect();
            let qv = Volume::new(dims, q.map_err(|e| e.to_string())?).map_err(|e| e.to_string())?;
            let s = extract_exact(&qv, &iso_q);
            (s.to_mesh(), s.stats)
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

/// Polygonises a finite element model on either path and writes the mesh.
fn mc_fe(
    m: &geocert::mc::fe::FeModel<f64>,
    iso: geocert::num::Rational,
    default_cells: [usize; 3],
    a: FeArgs,
) -> Result<ExitCode, String> {
    use geocert::mc::fe::{
        exact::polygonise_exact, fast::polygonise_fast, FeOptions, NormalSource,
    };
    use geocert::mesh::Format;
    let format = Format::from_path(&a.out).map_err(|e| e.to_string())?;
    let cells: [usize; 3] = match a.cells {
        Some(c) => c
            .try_into()
            .map_err(|_| "--cells takes three counts".to_string())?,
        None => default_cells,
    };
    let opts = FeOptions {
        cells,
        normals: match a.normals {
            NormalKind::Interpolant => NormalSource::Interpolant,
            NormalKind::FiniteDifference => NormalSource::FiniteDifference,
        },
        ..FeOptions::default()
    };
    let start = std::time::Instant::now();
    let (mesh, stats) = match a.path {
        McPath::Fast => {
            let iso_f = geocert::num::rational_to_f64(&iso);
            if geocert::num::rational_from_f64(iso_f, "iso").ok() != Some(iso.clone()) {
                return Err("--iso is not an f64; use --path exact for rational isovalues".into());
            }
            let s = polygonise_fast(m, iso_f, &opts).map_err(|e| e.to_string())?;
            (s.mesh, s.stats)
        }
        McPath::Exact => {
            let q = m.to_exact().map_err(|e| e.to_string())?;
            let s = polygonise_exact(&q, &iso, &opts).map_err(|e| e.to_string())?;
            (s.to_mesh(), s.stats)
        }
    };
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
            "{} triangles, {} vertices; {} elements, {} cells ({} cut, {} with an ambiguous face); {} vertices welded and {} collapsed triangles removed (Figure 7); manifold: {}, boundary edges: {}, Euler characteristic {}; {:.2} Mcells/s",
            mesh.triangles.len(),
            mesh.vertices.len(),
            stats.elements,
            stats.cells,
            stats.cut_cells,
            stats.ambiguous_cells,
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

/// The marching-cubes table proofs alone.
fn prove_mc_table(json: bool) -> Result<ExitCode, String> {
    let (outcomes, unrealisable) = mc_table_proofs();
    let ok = outcomes.iter().all(|p| p.ok());
    if json {
        let v = report::mc_markdown::mc_table_summary(&outcomes, unrealisable);
        println!(
            "{}",
            serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
        );
    } else {
        for o in &outcomes {
            println!("{}", o.summary());
        }
        println!("entries no trilinear cell produces: {unrealisable}");
        println!(
            "entries a trilinear cell may connect differently inside (witnessed, magnitudes 1…4): {}",
            geocert::proofs::mc_body::measured().1
        );
    }
    Ok(if ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

fn mc_table_proofs() -> (Vec<geocert::proofs::ProofOutcome>, usize) {
    let outcomes: Vec<_> = geocert::proofs::all()
        .into_iter()
        .filter(|(name, _)| name.starts_with("mc."))
        .map(|(_, proof)| proof())
        .collect();
    let (_, unrealisable) = geocert::proofs::mc::trilinear_realisability();
    (outcomes, unrealisable)
}

fn prove(out: PathBuf, json: bool) -> Result<ExitCode, String> {
    let meta = RunMeta::collect();
    let proofs = geocert::proofs::all();
    let bar = ProgressBar::new(proofs.len() as u64 + 4);
    bar.set_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}").map_err(|e| e.to_string())?,
    );
    let mut outcomes = Vec::new();
    for (name, proof) in proofs {
        bar.set_message(name);
        outcomes.push(proof());
        bar.inc(1);
    }
    bar.set_message("kernel exact-vs-fast campaign");
    let camp = campaign::kernel_campaign(2026, 300, &[3, 3, 3], 8);
    bar.inc(1);
    bar.set_message("subdivision timing");
    let timing = campaign::subdivision_timing(9, 10, 5);
    bar.inc(1);
    bar.set_message("marching-cubes grids (and VTK, if installed)");
    let grid = report::mc_grid::grid_campaign(
        &std::env::current_dir().map_err(|e| e.to_string())?,
        256,
        3,
    );
    bar.set_message("finite-element polygonisation (heart demo, sphere, random models)");
    let fe = report::mc_fe::fe_campaign(5, 300);
    bar.set_message("FFD campaign (and Gmsh, if installed)");
    let root = std::env::current_dir().map_err(|e| e.to_string())?;
    let ffd_camp = report::ffd::ffd_campaign(&root, 2026, 600, 60);
    bar.inc(1);
    bar.set_message("decimation grids, plate and peers (VTK if installed, meshoptimizer)");
    let sides: Vec<usize> = (1..=10).map(|k| 100 * k).collect();
    let dec_camp = report::decimate::decimate_campaign(&root, &sides);
    bar.inc(1);
    bar.finish_and_clear();
    let part = |prefix: &str| -> Vec<_> {
        outcomes
            .iter()
            .filter(|o| o.name.starts_with(prefix))
            .cloned()
            .collect()
    };
    let (kernel_proofs, ffd_proofs, mc_proofs) = (part("kernel."), part("ffd."), part("mc."));
    let (_, unrealisable) = geocert::proofs::mc::trilinear_realisability();
    let mc_ok = mc_proofs.iter().all(|p| p.ok())
        && report::mc_grid::grid_ok(&grid)
        && report::mc_fe::fe_ok(&fe);
    let io = |e: std::io::Error| format!("writing {}: {e}", out.display());
    let kernel_ok = report::kernel_ok(&kernel_proofs, &camp, &timing);
    let ffd_ok = report::ffd::campaign_ok(&ffd_camp) && ffd_proofs.iter().all(|p| p.ok());
    let mut written = vec![
        report::write_kernel_report(&out, &meta, &kernel_proofs, &camp, &timing).map_err(io)?,
        report::ffd_markdown::write_ffd_report(&out, &meta, &ffd_proofs, &ffd_camp).map_err(io)?,
        report::mc_markdown::write_mc_report(&out, &meta, &mc_proofs, unrealisable, &grid, &fe)
            .map_err(io)?,
        report::decimate::write_decimate_report(&out, &meta, &dec_camp).map_err(io)?,
    ];
    let dec_ok = report::decimate::campaign_ok(&dec_camp);
    written.insert(
        0,
        report::write_index(
            &out,
            &meta,
            &[
                report::IndexEntry {
                    file: "kernel.md".into(),
                    what: format!(
                        "scalar, Bernstein and B-spline kernel ({} proofs, {} cases)",
                        kernel_proofs.len(),
                        kernel_proofs.iter().map(|p| p.cases).sum::<usize>()
                    ),
                    ok: kernel_ok,
                },
                report::IndexEntry {
                    file: "ffd.md".into(),
                    what: format!(
                        "FFD injectivity ({} proofs, {} cases; {} lattices in the campaign)",
                        ffd_proofs.len(),
                        ffd_proofs.iter().map(|p| p.cases).sum::<usize>(),
                        ffd_camp.families.iter().map(|f| f.lattices).sum::<usize>()
                    ),
                    ok: ffd_ok,
                },
                report::IndexEntry {
                    file: "mc.md".into(),
                    what: format!(
                        "marching-cubes table ({} entries; {} proofs, {} cases)",
                        geocert::mc::table().entries.len(),
                        mc_proofs.len(),
                        mc_proofs.iter().map(|p| p.cases).sum::<usize>()
                    ),
                    ok: mc_ok,
                },
                report::IndexEntry {
                    file: "decimate.md".into(),
                    what: format!(
                        "decimation and exact undecimation ({} grids up to {} nodes, the Kirsch plate, peers)",
                        dec_camp.grids.len(),
                        dec_camp.grids.last().map(|g| g.nodes_in).unwrap_or(0)
                    ),
                    ok: dec_ok,
                },
            ],
        )
        .map_err(io)?,
    );
    let ok = kernel_ok && ffd_ok && mc_ok && dec_ok;
    if json {
        let v = serde_json::json!({"ok": ok, "proofs": outcomes, "campaign": camp, "timing": timing,
            "reports": written.iter().map(|p| p.display().to_string()).collect::<Vec<_>>()});
        println!(
            "{}",
            serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
        );
    } else {
        for o in &outcomes {
            println!("{}", o.summary());
        }
        println!(
            "campaign: {} polynomials, {} contradictions, {} certificates refused, fast uncertain {}",
            camp.cases, camp.contradictions, camp.certificates_refused, camp.fast_uncertain
        );
        println!(
            "subdivision tree (degree {}, depth {}): BigRational {:.2} ms, integers {:.2} ms ({:.0}×), f64 {:.3} ms",
            timing.degree, timing.depth, timing.rational_ms, timing.scaled_ms, timing.rational_ms / timing.scaled_ms, timing.fast_ms
        );
        for f in &ffd_camp.families {
            println!(
                "ffd {}: {} lattices, {} contradictions, {} certificates refused, filtered = exact on {}",
                f.name, f.lattices, f.contradictions, f.certificates_refused, f.filtered_agrees
            );
        }
        match &ffd_camp.gmsh {
            Ok(g) => println!(
                "gmsh {}: {:.0} cells/s",
                g.version,
                g.cells as f64 / g.batch_seconds
            ),
            Err(e) => println!("gmsh: {e}"),
        }
        for p in &written {
            println!("wrote {}", p.display());
        }
    }
    Ok(if ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

fn positivity(
    file: PathBuf,
    path: PathKind,
    max_depth: u32,
    cert: Option<PathBuf>,
    json: bool,
) -> Result<ExitCode, String> {
    let text = std::fs::read_to_string(&file).map_err(|e| format!("{}: {e}", file.display()))?;
    let value: serde_json::Value = serde_json::from_str(&text)
        .map_err(|e| format!("{}: not valid JSON: {e}", file.display()))?;
    let p = poly_from_json(&value).map_err(|e| format!("{}: {e}", file.display()))?;
    let limits = Limits {
        max_depth,
        ..Limits::default()
    };
    let verdict = match path {
        PathKind::Exact => prove_positive_exact(&p, limits),
        PathKind::Fast => match FastBernstein::from_rational(&p) {
            Ok(f) => prove_positive_fast(&f, limits),
            Err(e) => return Err(format!("{}: fast path: {e}", file.display())),
        },
        PathKind::Filtered => prove_positive_filtered(&p, limits),
    };
    let (name, detail) = match &verdict {
        PositivityVerdict::Positive { leaves, .. } => {
            ("positive", serde_json::json!({"leaves": leaves.len()}))
        }
        PositivityVerdict::NotPositive { witness, value } => (
            "not_positive",
            serde_json::json!({
                "witness": witness.iter().map(rational_to_string).collect::<Vec<_>>(),
                "value": match value { WitnessValue::Exact(r) => rational_to_string(r), WitnessValue::AtMost(b) => format!("<= {b:e}") },
            }),
        ),
        PositivityVerdict::Undecided {
            limit,
            at,
            lower_bound,
        } => (
            "undecided",
            serde_json::json!({"limit": limit, "box": at, "lower_bound": lower_bound}),
        ),
        PositivityVerdict::Uncertain { boxes, .. } => (
            "uncertain",
            serde_json::json!({"uncertain_boxes": boxes.len()}),
        ),
    };
    if let Some(cp) = cert {
        match certificate_for(&p, &verdict) {
            Some(c) => {
                let s = serde_json::to_string_pretty(&c).map_err(|e| e.to_string())?;
                std::fs::write(&cp, s).map_err(|e| format!("{}: {e}", cp.display()))?;
            }
            None => eprintln!(
                "note: a {name} verdict has no certificate; nothing written to {}",
                cp.display()
            ),
        }
    }
    if json {
        let mut v = serde_json::json!({"verdict": name});
        if let (Some(o), Some(d)) = (v.as_object_mut(), detail.as_object()) {
            for (k, x) in d {
                o.insert(k.clone(), x.clone());
            }
        }
        println!("{v}");
    } else {
        println!("{name}: {detail}");
    }
    Ok(ExitCode::SUCCESS)
}

/// Reads a mesh file or builds a built-in input (`builtin:grid:SIDE`, `builtin:plate`).
fn decimation_input(input: &str, scalar: Option<&str>) -> Result<geocert::mesh::Mesh, String> {
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
    geocert::mesh::Mesh::read(std::path::Path::new(input), scalar).map_err(|e| e.to_string())
}

fn decimate_cmd(
    input: &str,
    scalar: Option<&str>,
    options: &geocert::decimate::Options,
    path: geocert::decimate::Path,
    out: &std::path::Path,
    history: &std::path::Path,
    json: bool,
) -> Result<ExitCode, String> {
    use geocert::mesh::Format;
    let format = Format::from_path(out).map_err(|e| e.to_string())?;
    let mesh = decimation_input(input, scalar)?;
    let result =
        geocert::decimate::decimate(&mesh, options, path).map_err(|e| format!("{input}: {e}"))?;
    // Height fields and planar meshes: errors at the same xy position; other surfaces: the
    // distance to the decimated surface and the scalar at the closest point.
    let errors = if result.stats.projection_xy {
        geocert::decimate::quality::xy_errors(&mesh, &result.mesh)
    } else {
        geocert::decimate::quality::surface_errors(&mesh, &result.mesh)
    };
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
            "triangles_out": s.triangles_out,
            "seconds": s.seconds,
            "max_scalar_error": errors.max_scalar,
            "max_height_error": s.projection_xy.then_some(errors.max_height),
            "max_distance_error": (!s.projection_xy).then_some(errors.max_height),
            "removed": s.removed,
            "refused": s.refused,
            "intervals": s.intervals,
            "rebuilds": s.rebuilds,
            "evaluations": s.evaluations,
            "taken": s.taken,
            "evaluated_ahead": s.evaluated_ahead,
            "remembered": s.remembered,
            "setup_seconds": s.setup_seconds,
            "projection": if s.projection_xy { "xy" } else { "per-fan" },
        });
        println!("{v}");
    } else {
        println!(
            "{} → {} nodes, {} → {} triangles in {:.3} s ({} removals refused); history: {} steps",
            s.nodes_in,
            s.nodes_out,
            s.triangles_in,
            s.triangles_out,
            s.seconds,
            s.refused,
            result.history.len()
        );
        let what = if s.projection_xy {
            "height error"
        } else {
            "distance to the decimated surface"
        };
        print!("max {what} {:.6e}", errors.max_height);
        if let Some(m) = errors.max_scalar {
            print!(", max scalar error {m:.6e}");
        }
        println!();
    }
    Ok(ExitCode::SUCCESS)
}

fn undecimate_cmd(
    input: &std::path::Path,
    history: &std::path::Path,
    steps: Option<usize>,
    out: &std::path::Path,
) -> Result<ExitCode, String> {
    use geocert::decimate::{History, Stage};
    use geocert::mesh::Format;
    let format = Format::from_path(out).map_err(|e| e.to_string())?;
    let bytes = std::fs::read(history).map_err(|e| format!("{}: {e}", history.display()))?;
    let h = History::from_bytes(&bytes).map_err(|e| format!("{}: {e}", history.display()))?;
    let name = h.has_scalars.then_some(h.scalar_name.as_str());
    let mesh = geocert::mesh::Mesh::read(input, name).map_err(|e| e.to_string())?;
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
    Ok(if stage.applied == 0 && !exact {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}
