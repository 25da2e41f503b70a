//! `geocert ffd`: FFD injectivity (Gain & Dodgson) — check, certificates, drags, deformation.

use crate::out::{choice, pretty, read, status, write};
use clap::Subcommand;
use geocert::bernstein::Limits;
use geocert::ffd::{
    check_injectivity, lattices_from_json, verify_injectivity_certificate, CheckOptions,
    InjectivityCertificate,
};
use geocert::ffd::{constraints_from_json, injective_drag, steps_to_json, DragOptions, DragTest};
use geocert::num::rational_to_string;
use geocert::Path;
use std::path::{Path as FsPath, PathBuf};
use std::process::ExitCode;

#[derive(Subcommand)]
pub(crate) enum Command {
    /// Decide injectivity (det J > 0, Theorem 1) of one lattice or an array of lattices.
    Check {
        /// `{"basis": "bspline"|"bezier", "order": [l,m,n], "cells": [a,b,c], "points": [[x,y,z], ..]}` or an array of them.
        lattice: PathBuf,
        #[arg(long, default_value_t = Path::Filtered, value_parser = choice::<Path>(Path::NAMES))]
        path: Path,
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
        #[arg(long, default_value_t = DragTest::Conic, value_parser = choice::<DragTest>(DragTest::NAMES))]
        test: DragTest,
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

pub(crate) fn run(c: Command) -> Result<ExitCode, String> {
    match c {
        Command::Check {
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
            let time_limit = crate::out::time_limit(time_limit)?;
            let opts = CheckOptions::new().with_path(path).with_limits(
                Limits::new()
                    .with_max_depth(max_depth)
                    .with_time_limit(time_limit),
            );
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
                write(&cert_path, pretty(&value)?)?;
            }
            if json {
                let values: Vec<_> = reports.iter().map(|r| r.to_json()).collect();
                let out = if is_array {
                    serde_json::Value::Array(values)
                } else {
                    values.into_iter().next().unwrap_or_default()
                };
                println!("{}", pretty(&out)?);
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
                                geocert::num::point_to_string(point),
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
        Command::Drag {
            lattice,
            constraints,
            test,
            max_depth,
            fast,
            out,
        } => ffd_drag(lattice, constraints, test, max_depth, fast, out),
        Command::Deform {
            lattice,
            mesh,
            out,
            fit,
        } => ffd_deform(lattice, mesh, out, fit),
        Command::VerifyCert { file } => {
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
            Ok(status(all_ok))
        }
    }
}

/// Lattices from a lattice file, a lattice array, or a steps file of `ffd drag`.
fn lattices_or_steps(file: &FsPath) -> Result<Vec<geocert::ffd::Lattice>, String> {
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
            geocert::ffd::lattice_from_value(v)
                .map_err(|e| format!("{}: lattice {i}: {e}", file.display()))
        })
        .collect()
}

fn ffd_drag(
    lattice: PathBuf,
    constraints: PathBuf,
    test: DragTest,
    max_depth: u32,
    fast: bool,
    out: Option<PathBuf>,
) -> Result<ExitCode, String> {
    let shape = lattices_or_steps(&lattice)?
        .into_iter()
        .next()
        .ok_or_else(|| format!("{}: no lattice", lattice.display()))?;
    let cs = constraints_from_json(&read(&constraints)?)
        .map_err(|e| format!("{}: {e}", constraints.display()))?;
    let opts = DragOptions::new()
        .with_test(test)
        .with_max_depth(max_depth)
        .with_path(if fast { Path::Fast } else { Path::Exact });
    let start = std::time::Instant::now();
    let steps = injective_drag(&shape, &cs, opts).map_err(|e| e.to_string())?;
    let secs = start.elapsed().as_secs_f64();
    let text = pretty(&steps_to_json(&steps))?;
    match &out {
        Some(path) => write(path, text)?,
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
    use geocert::ffd::{deform_points_fast, Fit};
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
