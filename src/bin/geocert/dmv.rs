//! `geocert dmv`: diamond-based multiresolution volumes (Weiss & De Floriani): build a
//! supercube-encoded partial DMV, refine it selectively, write the mesh and the isosurface.

use crate::mc::load_volume;
use crate::out::{choice, pretty, read_bytes, write};
use clap::{Subcommand, ValueEnum};
use geocert::diamond::{
    builtin_volume, check_conforming, marching_tetrahedra, write_vtk_tets, DiamondDmv,
    DiamondFront, DmvAccess, Field, Front, FullDmv, Lod, Refiner, Simplex, SupercubeDmv,
    SupercubeFront,
};
use geocert::mc::grid::RawType;
use geocert::mesh::Format;
use serde_json::json;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

#[derive(Subcommand)]
pub(crate) enum Command {
    /// Build a partial DMV (the diamonds with error above E, or whose value range holds one of
    /// the isovalues, closed under ancestors) and write it supercube-encoded as a .dmv file.
    Build(BuildArgs),
    /// Selective refinement of a .dmv file: the current mesh for the criterion (error above
    /// e, an isovalue in the range, inside a box; all that are given), checked conforming
    /// exactly; optionally the tetrahedra (VTK) and the isosurface by marching tetrahedra.
    Refine(RefineArgs),
}

#[derive(clap::Args)]
pub(crate) struct BuildArgs {
    /// A NIfTI (.nii, .nii.gz) or raw volume, or `builtin:NAME:SIDE` (sphere, gyroid, fuel).
    volume: String,
    /// Raw volumes only: the sizes X Y Z (x fastest).
    #[arg(long, num_args = 3)]
    dims: Option<Vec<usize>>,
    /// Raw volumes only: the sample type.
    #[arg(long = "type", value_parser = choice::<RawType>(RawType::NAMES))]
    ty: Option<RawType>,
    /// Keep the diamonds whose error exceeds E (0 keeps every diamond that is not exactly
    /// interpolated: lossless).
    #[arg(long, conflicts_with = "iso")]
    error: Option<f64>,
    /// Keep the diamonds whose value range holds one of these isovalues (comma-separated).
    #[arg(long, value_delimiter = ',')]
    iso: Vec<f64>,
    /// The .dmv file to write.
    #[arg(long)]
    out: PathBuf,
    #[arg(long)]
    json: bool,
}

/// The active front's representation.
#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum FrontKind {
    /// Σd: a hash of diamonds with parent flags.
    Diamond,
    /// Σs: a hash of supercubes with 168 flag bits (3-D).
    Supercube,
}

/// The DMV's representation during refinement.
#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum Encoding {
    /// Δd: a hash from central vertex to data.
    Diamond,
    /// Δs: supercubes with bit flags and packed data (as read).
    Supercube,
}

#[derive(clap::Args)]
pub(crate) struct RefineArgs {
    /// A .dmv file written by `dmv build`.
    dmv: PathBuf,
    /// Refine diamonds whose error exceeds e.
    #[arg(long)]
    error: Option<f64>,
    /// Refine diamonds whose range holds one of these isovalues (comma-separated); the first
    /// is the isosurface's.
    #[arg(long, value_delimiter = ',')]
    iso: Vec<f64>,
    /// Refine only diamonds meeting the box x0 y0 z0 x1 y1 z1 (grid coordinates).
    #[arg(long, num_args = 6, allow_negative_numbers = true)]
    roi: Option<Vec<f64>>,
    #[arg(long, value_enum, default_value_t = FrontKind::Supercube)]
    front: FrontKind,
    #[arg(long, value_enum, default_value_t = Encoding::Supercube)]
    encoding: Encoding,
    /// Write the current mesh's tetrahedra (legacy VTK unstructured grid).
    #[arg(long)]
    mesh: Option<PathBuf>,
    /// Write the isosurface at the first --iso by marching tetrahedra (.ply, .obj, .stl, .vtk).
    #[arg(long)]
    surface: Option<PathBuf>,
    #[arg(long)]
    json: bool,
}

pub(crate) fn run(c: Command) -> Result<ExitCode, String> {
    match c {
        Command::Build(a) => build(a),
        Command::Refine(a) => refine(a),
    }
}

/// A volume file or a built-in volume as a field on the padded grid.
pub(crate) fn load_field(
    volume: &str,
    dims: Option<Vec<usize>>,
    ty: Option<RawType>,
) -> Result<Field<3>, String> {
    if let Some(rest) = volume.strip_prefix("builtin:") {
        let (name, side) = rest
            .split_once(':')
            .ok_or_else(|| format!("{volume}: write builtin:NAME:SIDE, e.g. builtin:gyroid:65"))?;
        let side: usize = side
            .parse()
            .map_err(|_| format!("{volume}: the side {side:?} is not a number"))?;
        return builtin_volume(name, side).map_err(|e| format!("{volume}: {e}"));
    }
    let vol = load_volume(std::path::Path::new(volume), dims, ty)?;
    Field::pad(vol.dims, &vol.values).map_err(|e| format!("{volume}: {e}"))
}

fn build(a: BuildArgs) -> Result<ExitCode, String> {
    if a.error.is_none() && a.iso.is_empty() {
        return Err("give --error E or --iso K[,K...]".into());
    }
    if let Some(e) = a.error.filter(|e| !e.is_finite() || *e < 0.0) {
        return Err(format!("--error {e}: a finite threshold >= 0"));
    }
    if let Some(k) = a.iso.iter().find(|k| !k.is_finite()) {
        return Err(format!("--iso {k}: isovalues must be finite"));
    }
    let field = load_field(&a.volume, a.dims, a.ty)?;
    let start = Instant::now();
    let dmv = FullDmv::build(field);
    let sel = match a.error {
        Some(e) => dmv.select_by_error(e),
        None => dmv.select_by_isovalues(&a.iso),
    };
    let ds = dmv.supercube_encoding(&sel);
    let seconds = start.elapsed().as_secs_f64();
    let bytes = ds.to_bytes();
    let value_bytes = if dmv
        .field()
        .values()
        .iter()
        .all(|&v| f64::from(v as f32) == v)
    {
        4
    } else {
        8
    };
    write(&a.out, &bytes)?;
    let s = dmv.summary(&sel, &ds, value_bytes);
    if a.json {
        let v = json!({
            "diamonds": s.diamonds,
            "supercubes": s.supercubes,
            "density": s.density,
            "concentration": s.concentration,
            "bytes": s.bytes,
            "file_bytes": bytes.len(),
            "seconds": seconds,
        });
        println!("{}", pretty(&v)?);
    } else {
        println!(
            "{} diamonds in {} supercubes (density {:.4}, concentration {:.1}); Table 1 bytes: full {}, diamond {}, supercube {}, ideal {}; wrote {} ({} bytes) in {seconds:.2} s",
            s.diamonds, s.supercubes, s.density, s.concentration, s.bytes.full, s.bytes.diamond,
            s.bytes.supercube, s.bytes.ideal, a.out.display(), bytes.len()
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// What one refinement produced.
struct Refined {
    visited: u64,
    seconds: f64,
    simplices: Vec<Simplex<3>>,
    front_bytes: u64,
}

fn run_front<A: DmvAccess<3>, F: Front<3>>(dmv: &A, lod: &Lod<3>) -> Result<Refined, String> {
    let start = Instant::now();
    let mut r: Refiner<'_, 3, A, F> = Refiner::new(dmv);
    r.refine(lod).map_err(|e| e.to_string())?;
    let seconds = start.elapsed().as_secs_f64();
    Ok(Refined {
        visited: r.visited,
        seconds,
        simplices: r.mesh(),
        front_bytes: r.front.bookkeeping_bytes(),
    })
}

fn refine(a: RefineArgs) -> Result<ExitCode, String> {
    let bytes = read_bytes(&a.dmv)?;
    let ds =
        SupercubeDmv::<3>::from_bytes(&bytes).map_err(|e| format!("{}: {e}", a.dmv.display()))?;
    let roi = match a.roi.as_deref() {
        Some([x0, y0, z0, x1, y1, z1]) => Some(([*x0, *y0, *z0], [*x1, *y1, *z1])),
        Some(_) => return Err("--roi takes six numbers".into()),
        None => None,
    };
    if a.surface.is_some() && a.iso.is_empty() {
        return Err("--surface needs --iso K (the isosurface's value)".into());
    }
    let lod = Lod {
        error: a.error,
        isovalues: a.iso.clone(),
        roi,
    };
    let dd;
    let r = match (a.encoding, a.front) {
        (Encoding::Supercube, FrontKind::Supercube) => {
            run_front::<_, SupercubeFront<3>>(&ds, &lod)?
        }
        (Encoding::Supercube, FrontKind::Diamond) => run_front::<_, DiamondFront<3>>(&ds, &lod)?,
        (Encoding::Diamond, front) => {
            dd = DiamondDmv::from_supercubes(&ds);
            match front {
                FrontKind::Supercube => run_front::<_, SupercubeFront<3>>(&dd, &lod)?,
                FrontKind::Diamond => run_front::<_, DiamondFront<3>>(&dd, &lod)?,
            }
        }
    };
    let conformity = check_conforming(&ds.hierarchy(), &r.simplices);
    let mut surface_closed = None;
    let mut triangles = None;
    if let Some(path) = &a.surface {
        let format = Format::from_path(path).map_err(|e| e.to_string())?;
        let s = marching_tetrahedra(&ds, &r.simplices, a.iso[0]).map_err(|e| e.to_string())?;
        surface_closed = Some(s.open_edges == 0);
        triangles = Some(s.mesh.triangles.len());
        s.mesh.write(path, format).map_err(|e| e.to_string())?;
    }
    if let Some(path) = &a.mesh {
        write(path, write_vtk_tets(&r.simplices, |p| ds.value(p)))?;
    }
    let per_second = r.visited as f64 / r.seconds.max(1e-9);
    let per_simplex = r.front_bytes as f64 / r.simplices.len().max(1) as f64;
    if a.json {
        let v = json!({
            "diamonds_visited": r.visited,
            "diamonds_per_second": per_second,
            "simplices": r.simplices.len(),
            "front_bytes": r.front_bytes,
            "bytes_per_simplex": per_simplex,
            "conforming": conformity.conforming,
            "surface_closed": surface_closed,
            "triangles": triangles,
        });
        println!("{}", pretty(&v)?);
    } else {
        println!(
            "{} diamonds visited ({:.2} M/s), {} tetrahedra, front {} bytes ({per_simplex:.2} per tetrahedron), conforming: {}{}",
            r.visited,
            per_second / 1e6,
            r.simplices.len(),
            r.front_bytes,
            conformity.conforming,
            surface_closed.map_or(String::new(), |c| format!(", isosurface closed: {c}"))
        );
    }
    Ok(if conformity.conforming && surface_closed != Some(false) {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}
