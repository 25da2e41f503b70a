//! Replays every saved fuzz input in `fuzz/regressions/<target>/` through the same checks the
//! fuzz targets run, so a crash found once stays fixed.

use std::path::Path;

fn replay(target: &str, check: impl Fn(&[u8]) -> Result<(), String>) -> usize {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fuzz/regressions")
        .join(target);
    let mut n = 0;
    if let Ok(entries) = std::fs::read_dir(&dir) {
        for e in entries.flatten() {
            let data = std::fs::read(e.path()).expect("readable regression input");
            if let Err(msg) = check(&data) {
                panic!("{}: {msg}", e.path().display());
            }
            n += 1;
        }
    }
    println!("{target}: replayed {n} saved inputs");
    n
}

#[test]
fn subdivision_signs_regressions() {
    let n = replay(
        "subdivision_signs",
        |d| match geocert::internals::fuzzing::decode_poly(d) {
            Some(p) => geocert::internals::fuzzing::check_subdivision(&p),
            None => Ok(()),
        },
    );
    assert!(n > 0, "the regression corpus must not be empty");
}

#[test]
fn poly_json_regressions() {
    replay("poly_json", geocert::internals::fuzzing::check_poly_json);
}

#[test]
fn ffd_injectivity_regressions() {
    let n = replay(
        "ffd_injectivity",
        |d| match geocert::internals::fuzzing::decode_lattice(d) {
            Some(l) => geocert::internals::fuzzing::check_ffd(&l),
            None => Ok(()),
        },
    );
    assert!(n > 0, "the regression corpus must not be empty");
}

#[test]
fn lattice_json_regressions() {
    let n = replay(
        "lattice_json",
        geocert::internals::fuzzing::check_lattice_json,
    );
    assert!(n > 0, "the regression corpus must not be empty");
}

#[test]
fn mesh_readers_regressions() {
    let n = replay(
        "mesh_readers",
        geocert::internals::fuzzing::check_mesh_readers,
    );
    assert!(n > 0, "the regression corpus must not be empty");
}

#[test]
fn mc_grid_regressions() {
    let n = replay("mc_grid", geocert::internals::fuzzing::check_mc_grid);
    assert!(n > 0, "the regression corpus must not be empty");
}

#[test]
fn mc_table_regressions() {
    let n = replay("mc_table", geocert::internals::fuzzing::check_mc_table);
    assert!(n > 0, "the regression corpus must not be empty");
}

#[test]
fn decimate_round_trip_regressions() {
    let n = replay(
        "decimate_round_trip",
        geocert::internals::fuzzing::check_decimate,
    );
    assert!(n > 0, "the regression corpus must not be empty");
}

#[test]
fn volume_readers_regressions() {
    let n = replay(
        "volume_readers",
        geocert::internals::fuzzing::check_volume_readers,
    );
    assert!(n > 0, "the regression corpus must not be empty");
}

#[test]
fn mc_fe_regressions() {
    let n = replay("mc_fe", geocert::internals::fuzzing::check_mc_fe);
    assert!(n > 0, "the regression corpus must not be empty");
}

#[test]
fn solve_paths_regressions() {
    let n = replay("solve_paths", geocert::internals::fuzzing::check_solve);
    assert!(n > 0, "the regression corpus must not be empty");
}

#[test]
fn solve_bspline_regressions() {
    let n = replay(
        "solve_bspline",
        geocert::internals::fuzzing::check_solve_bspline,
    );
    assert!(n > 0, "the regression corpus must not be empty");
}

#[test]
fn solve_curves_regressions() {
    let n = replay("solve_curves", geocert::internals::fuzzing::check_curve);
    assert!(n > 0, "the regression corpus must not be empty");
}

#[test]
fn sweep_scene_regressions() {
    let n = replay(
        "sweep_scene",
        geocert::internals::fuzzing::check_sweep_scene,
    );
    assert!(n > 0, "the regression corpus must not be empty");
}

#[test]
fn dmv_file_regressions() {
    let n = replay("dmv_file", geocert::internals::fuzzing::check_dmv_file);
    assert!(n > 0, "the regression corpus must not be empty");
}

#[test]
fn dmv_refine_regressions() {
    let n = replay("dmv_refine", geocert::internals::fuzzing::check_dmv_refine);
    assert!(n > 0, "the regression corpus must not be empty");
}

#[test]
fn mc_topology_regressions() {
    let n = replay(
        "mc_topology",
        geocert::internals::fuzzing::check_mc_topology,
    );
    assert!(n > 0, "the regression corpus must not be empty");
}

#[test]
fn mc_verify_regressions() {
    let n = replay("mc_verify", geocert::internals::fuzzing::check_mc_verify);
    assert!(n > 0, "the regression corpus must not be empty");
}
