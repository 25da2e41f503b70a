//! `geocert prove`: every exhaustive proof and the exact-vs-fast campaigns; writes the reports.

use crate::out::{pretty, status};
use clap::ValueEnum;
use geocert::internals::proofs::{self, ProofOutcome};
use geocert::internals::report::{self, campaign, RunMeta};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub(crate) struct Args {
    /// Only this part (`mc-table`: the marching-cubes table proofs; prints, writes nothing).
    #[arg(value_enum)]
    part: Option<Part>,
    /// Where to write the reports.
    #[arg(long, default_value = "reports")]
    out: PathBuf,
    /// Print a JSON summary on stdout.
    #[arg(long)]
    json: bool,
    /// Run only slice K of N of every exhaustive proof (one-based, e.g. `3/8`) and write its
    /// outcomes to `OUT/proofs-slice-K-of-N.json` for `--merge`; no report is written.
    #[arg(long, value_name = "K/N", conflicts_with_all = ["merge", "part"])]
    shard: Option<String>,
    /// Write the reports with the proofs' outcomes merged from the slice files in these
    /// folders (every slice of one N exactly once) instead of running the proofs here; the
    /// campaigns and measurements run here as usual.
    #[arg(long, value_name = "DIR", num_args = 1.., conflicts_with = "part")]
    merge: Vec<PathBuf>,
}

/// The kind tag of slice files.
const SLICE_KIND: &str = "geocert/proof-slice";

/// A part of `prove` that runs alone.
#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum Part {
    /// The marching-cubes proofs `cargo test` runs (not the long ones).
    McTable,
    /// Marching cubes whole: the table proofs (the long ones too), grids and elements (and
    /// VTK), the trilinear topology and other programs' meshes checked against it; writes
    /// mc.md.
    Mc,
    /// The solver's campaign alone (constructed systems, msolve if installed); writes
    /// solve.md.
    Solve,
    /// The swept-volume silhouettes of the built-in scenes; writes sweep.md and its pictures.
    Sweep,
    /// Diamond hierarchies: the proofs at the report's sizes, partial DMVs, selective
    /// refinement, adaptive isosurfaces against the peers; writes diamond.md.
    Diamonds,
    /// Decimation: height grids, the plate, the peers, exact against fast, and surfaces in
    /// 3-D against the quadric simplifiers; writes decimate.md.
    Decimate,
}

pub(crate) fn run(a: Args) -> Result<ExitCode, String> {
    match a.part {
        Some(Part::McTable) => prove_mc_table(a.json),
        Some(Part::Mc) => prove_mc(a.out, a.json),
        Some(Part::Solve) => prove_solve(a.out, a.json),
        Some(Part::Sweep) => prove_sweep(a.out, a.json),
        Some(Part::Diamonds) => prove_diamonds(a.out, a.json),
        Some(Part::Decimate) => prove_decimate(a.out, a.json),
        None => match (a.shard, a.merge.is_empty()) {
            (Some(s), _) => prove_slice(&s, &a.out, a.json),
            (None, false) => {
                let merged = merge_slices(&a.merge)?;
                prove(a.out, a.json, Some(merged))
            }
            (None, true) => prove(a.out, a.json, None),
        },
    }
}

/// `prove --shard K/N`: one slice of every proof, written as JSON.
fn prove_slice(shard: &str, out: &std::path::Path, json: bool) -> Result<ExitCode, String> {
    let shard = proofs::Shard::parse(shard)?;
    let meta = RunMeta::collect();
    let outcomes: Vec<ProofOutcome> = proofs::everything()
        .into_iter()
        .map(|(_, proof)| proof(shard))
        .collect();
    let ok = outcomes.iter().all(|p| p.ok());
    let file = out.join(format!(
        "proofs-slice-{}-of-{}.json",
        shard.index + 1,
        shard.count
    ));
    let v = serde_json::json!({"kind": SLICE_KIND, "shard": shard, "commit": meta.commit,
        "machine": meta.machine, "date_utc": meta.date_utc, "ok": ok, "outcomes": outcomes});
    std::fs::create_dir_all(out).map_err(|e| format!("creating {}: {e}", out.display()))?;
    let tmp = file.with_extension("json.tmp");
    std::fs::write(&tmp, pretty(&v)?).map_err(|e| format!("writing {}: {e}", tmp.display()))?;
    std::fs::rename(&tmp, &file).map_err(|e| format!("writing {}: {e}", file.display()))?;
    if json {
        println!("{}", pretty(&v)?);
    } else {
        for o in &outcomes {
            println!("{}", o.summary());
        }
        println!("wrote {}", file.display());
    }
    Ok(status(ok))
}

/// Reads every `proofs-slice-*.json` in `dirs` and merges them proof by proof.
fn merge_slices(dirs: &[PathBuf]) -> Result<Vec<ProofOutcome>, String> {
    let mut outcomes = Vec::new();
    let mut commits = std::collections::BTreeSet::new();
    let mut files = 0;
    for dir in dirs {
        let entries =
            std::fs::read_dir(dir).map_err(|e| format!("reading {}: {e}", dir.display()))?;
        let mut paths: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                p.file_name()
                    .and_then(|n| n.to_str())
                    .is_some_and(|n| n.starts_with("proofs-slice-") && n.ends_with(".json"))
            })
            .collect();
        paths.sort();
        for p in paths {
            let text =
                std::fs::read_to_string(&p).map_err(|e| format!("reading {}: {e}", p.display()))?;
            let v: serde_json::Value = serde_json::from_str(&text)
                .map_err(|e| format!("{}: not JSON: {e}", p.display()))?;
            if v["kind"] != SLICE_KIND {
                return Err(format!(
                    "{}: not a proof slice (kind {})",
                    p.display(),
                    v["kind"]
                ));
            }
            commits.insert(v["commit"].as_str().unwrap_or("unknown").to_string());
            let os: Vec<ProofOutcome> = serde_json::from_value(v["outcomes"].clone())
                .map_err(|e| format!("{}: bad outcomes: {e}", p.display()))?;
            outcomes.extend(os);
            files += 1;
        }
    }
    if files == 0 {
        return Err("--merge: no proofs-slice-*.json files in the folders given".into());
    }
    if commits.len() > 1 {
        return Err(format!(
            "--merge: slices come from different commits {commits:?}; run every slice on one commit"
        ));
    }
    let merged = proofs::merge_runs(outcomes)?;
    eprintln!(
        "merged {files} slice files (commit {})",
        commits.iter().next().map_or("unknown", String::as_str)
    );
    Ok(merged)
}

/// The marching-cubes table proofs alone.
fn prove_mc_table(json: bool) -> Result<ExitCode, String> {
    let (outcomes, unrealisable) = mc_table_proofs(false);
    let ok = outcomes.iter().all(|p| p.ok());
    if json {
        let v = report::mc_markdown::mc_table_summary(&outcomes, unrealisable);
        println!("{}", pretty(&v)?);
    } else {
        for o in &outcomes {
            println!("{}", o.summary());
        }
        println!("entries no trilinear cell produces: {unrealisable}");
        println!(
            "entries a trilinear cell may connect differently inside (witnessed, magnitudes 1…4): {}",
            proofs::mc_body::measured().1
        );
    }
    Ok(status(ok))
}

/// `prove mc`: the marching-cubes report alone.
fn prove_mc(out: PathBuf, json: bool) -> Result<ExitCode, String> {
    let meta = RunMeta::collect();
    let root = std::env::current_dir().map_err(|e| e.to_string())?;
    let (outcomes, unrealisable) = mc_table_proofs(true);
    let grid = report::mc_grid::grid_campaign(&root, 256, 3);
    let fe = report::mc_fe::fe_campaign(&root, 5, 300);
    let topology = report::mc_topology::topology_campaign(&root);
    let ok = outcomes.iter().all(|p| p.ok())
        && report::mc_grid::grid_ok(&grid)
        && report::mc_fe::fe_ok(&fe)
        && report::mc_topology::campaign_ok(&topology);
    let written = report::mc_markdown::write_mc_report(
        &out,
        &meta,
        &outcomes,
        unrealisable,
        &grid,
        &fe,
        &topology,
    )
    .map_err(|e| format!("writing {}: {e}", out.display()))?;
    if json {
        println!("{}", pretty(&topology)?);
    } else {
        for o in &outcomes {
            println!("{}", o.summary());
        }
        println!("wrote {}", written.display());
    }
    Ok(status(ok))
}

/// The `mc.` proofs (with the long ones when `long`) and the unrealisable entries.
fn mc_table_proofs(long: bool) -> (Vec<ProofOutcome>, usize) {
    let list = if long {
        proofs::everything()
    } else {
        proofs::all()
    };
    let outcomes: Vec<_> = list
        .into_iter()
        .filter(|(name, _)| name.starts_with("mc."))
        .map(|(_, proof)| proof(proofs::Shard::WHOLE))
        .collect();
    let (_, unrealisable) = proofs::mc::trilinear_realisability();
    (outcomes, unrealisable)
}

fn prove(out: PathBuf, json: bool, merged: Option<Vec<ProofOutcome>>) -> Result<ExitCode, String> {
    let meta = RunMeta::collect();
    let proofs = proofs::everything();
    let bar = ProgressBar::new(proofs.len() as u64 + 6);
    bar.set_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}").map_err(|e| e.to_string())?,
    );
    let outcomes = match merged {
        Some(m) => {
            // The reports read the body measurement's tunnel count: take it from the slices.
            if let Some(body) = m.iter().find(|o| o.name == "mc.table-body-ambiguity") {
                proofs::mc_body::preset(body.clone());
            }
            bar.inc(proofs.len() as u64);
            m
        }
        None => {
            let mut outcomes = Vec::new();
            for (name, proof) in proofs {
                bar.set_message(name);
                outcomes.push(proof(proofs::Shard::WHOLE));
                bar.inc(1);
            }
            outcomes
        }
    };
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
    let root = std::env::current_dir().map_err(|e| e.to_string())?;
    let fe = report::mc_fe::fe_campaign(&root, 5, 300);
    bar.set_message("trilinear topology (and other programs' meshes, if installed)");
    let topology = report::mc_topology::topology_campaign(&root);
    bar.set_message("FFD campaign (and Gmsh, if installed)");
    let ffd_camp = report::ffd::ffd_campaign(&root, 2026, 600, 60);
    bar.inc(1);
    bar.set_message("decimation grids, plate and peers (VTK if installed, meshoptimizer)");
    let sides: Vec<usize> = (1..=10).map(|k| 100 * k).collect();
    let dec_camp = report::decimate::decimate_campaign(&root, &sides);
    bar.inc(1);
    bar.set_message("polynomial systems (and msolve, if installed)");
    let solve_camp = solve_campaign(&root)?;
    bar.inc(1);
    bar.set_message("swept-volume silhouettes of the built-in scenes");
    let sweep_camp = report::sweep::sweep_campaign(&root, &out);
    bar.set_message("diamond hierarchies, DMVs and refinement (and OpenVDB, VTK, pymartini)");
    let diamond_camp = report::diamond::diamond_campaign(&root, DIAMOND_SIDE);
    bar.finish_and_clear();
    let part = |prefix: &str| -> Vec<_> {
        outcomes
            .iter()
            .filter(|o| o.name.starts_with(prefix))
            .cloned()
            .collect()
    };
    let (kernel_proofs, ffd_proofs, mc_proofs) = (part("kernel."), part("ffd."), part("mc."));
    let (_, unrealisable) = proofs::mc::trilinear_realisability();
    let mc_ok = mc_proofs.iter().all(|p| p.ok())
        && report::mc_grid::grid_ok(&grid)
        && report::mc_fe::fe_ok(&fe)
        && report::mc_topology::campaign_ok(&topology);
    let io = |e: std::io::Error| format!("writing {}: {e}", out.display());
    let kernel_ok = report::kernel_ok(&kernel_proofs, &camp, &timing);
    let ffd_ok = report::ffd::campaign_ok(&ffd_camp) && ffd_proofs.iter().all(|p| p.ok());
    let mut written = vec![
        report::write_kernel_report(&out, &meta, &kernel_proofs, &camp, &timing).map_err(io)?,
        report::ffd_markdown::write_ffd_report(&out, &meta, &ffd_proofs, &ffd_camp).map_err(io)?,
        report::mc_markdown::write_mc_report(
            &out,
            &meta,
            &mc_proofs,
            unrealisable,
            &grid,
            &fe,
            &topology,
        )
        .map_err(io)?,
        report::decimate::write_decimate_report(&out, &meta, &dec_camp).map_err(io)?,
        report::solve::write_solve_report(&out, &meta, &solve_camp).map_err(io)?,
        report::sweep::write_sweep_report(&out, &meta, &sweep_camp).map_err(io)?,
        report::diamond::write_diamond_report(&out, &meta, &diamond_camp).map_err(io)?,
    ];
    let diamond_ok = report::diamond::campaign_ok(&diamond_camp);
    let solve_ok = report::solve::campaign_ok(&solve_camp);
    let sweep_ok = report::sweep::campaign_ok(&sweep_camp);
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
                report::IndexEntry {
                    file: "solve.md".into(),
                    what: format!(
                        "certified polynomial system solving ({} systems with constructed roots on three paths, dense systems against msolve)",
                        solve_camp.families.iter().map(|f| f.systems).sum::<usize>()
                    ),
                    ok: solve_ok,
                },
                report::IndexEntry {
                    file: "sweep.md".into(),
                    what: format!(
                        "perspective silhouettes of swept volumes ({} built-in scenes on two paths, eq. 2 as printed measured)",
                        sweep_camp.rows.len() / 2
                    ),
                    ok: sweep_ok,
                },
                report::IndexEntry {
                    file: "diamond.md".into(),
                    what: format!(
                        "diamond hierarchies and supercubes ({} proofs, {} cases; {} volumes: partial DMVs, refinement on three encodings and two fronts, peers)",
                        diamond_camp.proofs.len(),
                        diamond_camp.proofs.iter().map(|p| p.cases).sum::<usize>(),
                        diamond_camp.builds.len()
                    ),
                    ok: diamond_ok,
                },
            ],
        )
        .map_err(io)?,
    );
    let ok = kernel_ok && ffd_ok && mc_ok && dec_ok && solve_ok && sweep_ok && diamond_ok;
    if json {
        let v = serde_json::json!({"ok": ok, "proofs": outcomes, "campaign": camp, "timing": timing,
            "reports": written.iter().map(|p| p.display().to_string()).collect::<Vec<_>>()});
        println!("{}", pretty(&v)?);
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
    Ok(status(ok))
}

/// The solver's campaign at the report's sizes.
fn solve_campaign(root: &std::path::Path) -> Result<report::solve::SolveCampaign, String> {
    Ok(report::solve::solve_campaign(root, 2026, 12, 12))
}

/// `prove solve`: the solver's campaign alone; writes solve.md.
fn prove_solve(out: PathBuf, json: bool) -> Result<ExitCode, String> {
    let meta = RunMeta::collect();
    let root = std::env::current_dir().map_err(|e| e.to_string())?;
    let c = solve_campaign(&root)?;
    let written = report::solve::write_solve_report(&out, &meta, &c)
        .map_err(|e| format!("writing {}: {e}", out.display()))?;
    let ok = report::solve::campaign_ok(&c);
    if json {
        println!("{}", pretty(&c)?);
    } else {
        for f in &c.families {
            for (p, t) in &f.paths {
                println!(
                    "{} ({p}): {} found, {} in clusters, {} missing, {} extra, {} refused",
                    f.name, t.found, t.in_clusters, t.missing, t.extra, t.refused
                );
            }
        }
        println!("wrote {}", written.display());
    }
    Ok(status(ok))
}

/// `prove sweep`: the swept-volume scenes alone; writes sweep.md.
fn prove_sweep(out: PathBuf, json: bool) -> Result<ExitCode, String> {
    let meta = RunMeta::collect();
    let root = std::env::current_dir().map_err(|e| e.to_string())?;
    let c = report::sweep::sweep_campaign(&root, &out);
    let written = report::sweep::write_sweep_report(&out, &meta, &c)
        .map_err(|e| format!("writing {}: {e}", out.display()))?;
    let ok = report::sweep::campaign_ok(&c);
    if json {
        println!("{}", pretty(&c)?);
    } else {
        for r in &c.rows {
            println!(
                "{} ({}): {} envelope components, {} t-extreme ({} re-checked), {} corner passages ({} re-checked), {} clusters, max |F| {:.1e}, max |G| {:.1e}, {:.3} s",
                r.scene, r.path, r.envelope, r.t_extreme, r.t_extreme_verified, r.corners, r.corners_verified, r.clusters, r.max_f, r.max_g, r.median_seconds
            );
        }
        println!("wrote {}", written.display());
    }
    Ok(status(ok))
}

/// The built-in volumes' side in the diamond report (the sparse fuel volume is twice as fine).
const DIAMOND_SIDE: usize = 129;

/// `prove diamonds`: the diamond campaign alone; writes diamond.md.
fn prove_diamonds(out: PathBuf, json: bool) -> Result<ExitCode, String> {
    let meta = RunMeta::collect();
    let root = std::env::current_dir().map_err(|e| e.to_string())?;
    let c = report::diamond::diamond_campaign(&root, DIAMOND_SIDE);
    let written = report::diamond::write_diamond_report(&out, &meta, &c)
        .map_err(|e| format!("writing {}: {e}", out.display()))?;
    let ok = report::diamond::campaign_ok(&c);
    if json {
        println!("{}", pretty(&c)?);
    } else {
        for p in &c.proofs {
            println!("{}", p.summary());
        }
        for b in &c.builds {
            println!(
                "{}: Δf built in {:.2} s ({} grid points)",
                b.volume, b.seconds, b.grid_points
            );
        }
        for r in &c.refinement {
            println!(
                "{} {} {}: {:.2} M diamonds/s, {} tetrahedra, {:.2} bytes/tet, conforming {}, same mesh {}",
                r.volume, r.dmv, r.front, r.per_second / 1e6, r.simplices, r.bytes_per_simplex, r.conforming, r.same_mesh
            );
        }
        for n in &c.notes {
            println!("note: {n}");
        }
        println!("wrote {}", written.display());
    }
    Ok(status(ok))
}

/// The decimation report alone.
fn prove_decimate(out: PathBuf, json: bool) -> Result<ExitCode, String> {
    let meta = RunMeta::collect();
    let root = std::env::current_dir().map_err(|e| e.to_string())?;
    let sides: Vec<usize> = (1..=10).map(|k| 100 * k).collect();
    let c = report::decimate::decimate_campaign(&root, &sides);
    let written = report::decimate::write_decimate_report(&out, &meta, &c)
        .map_err(|e| format!("writing {}: {e}", out.display()))?;
    let ok = report::decimate::campaign_ok(&c);
    if json {
        println!("{}", pretty(&c)?);
    } else {
        for case in &c.surfaces.cases {
            let (rms, haus, speed) = report::decimate_surfaces::ratios(case);
            println!(
                "{}: RMS {rms:.2?}× / Hausdorff {haus:.2?}× the best quadric peer, {speed:.2?}× fast-simplification's speed; checker {}",
                case.name,
                if case.verified.is_ok() { "passed" } else { "FAILED" }
            );
        }
        for n in &c.surfaces.notes {
            println!("note: {n}");
        }
        println!("wrote {}", written.display());
    }
    Ok(status(ok))
}
