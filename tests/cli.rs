//! The command-line tool end to end: decisions with certificates, independent re-checks, and
//! clear errors (exit code 2, nothing written) on malformed input.

use std::process::Command;

fn geocert() -> Command {
    Command::new(env!("CARGO_BIN_EXE_geocert"))
}

/// Asserts that the command succeeded, showing its error output otherwise.
fn assert_success(out: &std::process::Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// `geocert undecimate MESH --history HIST --out BACK`.
fn undecimate(
    mesh: &std::path::Path,
    hist: &std::path::Path,
    back: &std::path::Path,
) -> std::process::Output {
    let s = |p: &std::path::Path| p.to_str().unwrap().to_string();
    geocert()
        .args([
            "undecimate",
            &s(mesh),
            "--history",
            &s(hist),
            "--out",
            &s(back),
        ])
        .output()
        .unwrap()
}

fn tmp(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("geocert-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Runs `geocert SUBCOMMAND FILE --cert CERT` on `text` and asserts the refusal: exit code 2,
/// `needle` in the message, no certificate written.
fn refuses(subcommand: &str, name: &str, text: &str, needle: &str) {
    let f = tmp(name);
    std::fs::write(&f, text).unwrap();
    let cert = tmp(&format!("{name}.cert"));
    let out = geocert()
        .args([
            subcommand,
            f.to_str().unwrap(),
            "--cert",
            cert.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "{name}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains(needle), "{name}: {err}");
    assert!(!cert.exists(), "{name}: nothing may be written on failure");
}

#[test]
fn positive_polynomial_certificate_round_trip() {
    // (t − ½)² + 1/1000 in Bernstein form on [0,1]: coefficients 1/4+ε, −1/4+ε, 1/4+ε.
    let poly = tmp("pos.json");
    std::fs::write(
        &poly,
        r#"{"degrees":[2],"coeffs":["251/1000","-249/1000","251/1000"]}"#,
    )
    .unwrap();
    let cert = tmp("pos.cert.json");
    let out = geocert()
        .args([
            "positivity",
            poly.to_str().unwrap(),
            "--json",
            "--cert",
            cert.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["verdict"], "positive");
    assert!(v["leaves"].as_u64().unwrap() > 1);
    let out = geocert()
        .args(["verify-cert", cert.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    // Tamper: drop a leaf; the checker must refuse.
    let mut c: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&cert).unwrap()).unwrap();
    c["leaves"].as_array_mut().unwrap().pop();
    std::fs::write(&cert, c.to_string()).unwrap();
    let out = geocert()
        .args(["verify-cert", cert.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
}

#[test]
fn witness_for_a_touching_polynomial() {
    let poly = tmp("touch.json");
    std::fs::write(&poly, r#"{"degrees":[2],"coeffs":[0.25,-0.25,0.25]}"#).unwrap();
    // The minimum is exactly 0 at t = ½: the exact routes find the witness; the certified f64
    // route cannot tell 0 from a rounding error there and must say `uncertain`, not decide.
    for path in ["exact", "fast", "filtered"] {
        let out = geocert()
            .args([
                "positivity",
                poly.to_str().unwrap(),
                "--json",
                "--path",
                path,
            ])
            .output()
            .unwrap();
        assert!(out.status.success());
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        if path == "fast" {
            assert!(
                v["verdict"] == "uncertain" || v["verdict"] == "not_positive",
                "fast said {}",
                v["verdict"]
            );
            continue;
        }
        assert_eq!(v["verdict"], "not_positive", "path {path}");
        assert_eq!(v["witness"][0], "1/2");
        assert_eq!(v["value"], "0");
    }
}

#[test]
fn malformed_inputs_are_clear_errors() {
    let cases = [
        (
            "nan.json",
            r#"{"degrees":[1],"coeffs":["nan",1]}"#,
            "coefficient 0",
        ),
        (
            "count.json",
            r#"{"degrees":[2],"coeffs":[1,2]}"#,
            "expected 3 coefficients",
        ),
        ("degrees.json", r#"{"coeffs":[1,2]}"#, "degrees"),
        (
            "zero.json",
            r#"{"degrees":[1],"coeffs":["1/0",1]}"#,
            "zero denominator",
        ),
        ("json.json", r#"{"degrees":[1],"#, "not valid JSON"),
    ];
    for (name, text, needle) in cases {
        refuses("positivity", name, text, needle);
    }
    let out = geocert()
        .args(["positivity", "/nonexistent/file.json"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn ffd_check_json_and_certificate_round_trip() {
    let cert = tmp("twist-cert.json");
    let out = geocert()
        .args([
            "ffd",
            "check",
            "examples/ffd/twist.json",
            "--json",
            "--cert",
        ])
        .arg(&cert)
        .output()
        .unwrap();
    assert_success(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let verdict = v["verdict"].as_str().unwrap();
    assert!(["injective", "not_injective"].contains(&verdict), "{v}");
    let out = geocert()
        .args(["ffd", "verify-cert"])
        .arg(&cert)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
}

#[test]
fn ffd_drag_then_deform_a_mesh() {
    use geocert::mesh::{squashed_hemisphere, Format, Mesh};
    let steps = tmp("dome-steps.json");
    let out = geocert()
        .args([
            "ffd",
            "drag",
            "examples/ffd/dome-lattice.json",
            "--constraints",
            "examples/ffd/dome-drag.json",
            "--fast",
            "--out",
        ])
        .arg(&steps)
        .output()
        .unwrap();
    assert_success(&out);
    let parsed: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&steps).unwrap()).unwrap();
    assert!(
        parsed.as_array().unwrap().len() >= 2,
        "the long drag must be split"
    );

    // The dome, placed in the middle of the domain [0,4]³ by hand.
    let mut dome = squashed_hemisphere(8, 0.5);
    for v in &mut dome.vertices {
        *v = [2.0 + v[0], 2.0 + v[1], 2.3 + v[2]];
    }
    let input = tmp("dome.ply");
    dome.write(&input, Format::PlyBinary).unwrap();
    let output = tmp("dome-dragged.obj");
    let out = geocert()
        .args(["ffd", "deform"])
        .arg(&steps)
        .arg(&input)
        .arg("--out")
        .arg(&output)
        .output()
        .unwrap();
    assert_success(&out);
    let back = Mesh::read(&output, None).unwrap();
    assert_eq!(back.triangles, dome.triangles);
    // The dragged apex (0, 0, 0.5) + (2, 2, 2.3) = (2, 2, 2.8) moved by (0, 0, −1.6).
    let apex = dome
        .vertices
        .iter()
        .position(|v| *v == [2.0, 2.0, 2.8])
        .unwrap();
    approx::assert_abs_diff_eq!(back.vertices[apex][2], 1.2, epsilon = 1e-12);

    // Dependent constraints: a clear error, nothing written.
    let bad = tmp("twice.json");
    std::fs::write(
        &bad,
        r#"{"constraints": [{"point": [1,1,1], "delta": [0,0,1]}, {"point": [1,1,1], "delta": [0,1,0]}]}"#,
    )
    .unwrap();
    let never = tmp("never.json");
    let out = geocert()
        .args([
            "ffd",
            "drag",
            "examples/ffd/dome-lattice.json",
            "--constraints",
        ])
        .arg(&bad)
        .arg("--out")
        .arg(&never)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("constraint 1"));
    assert!(!never.exists());
}

#[test]
fn prove_mc_table_json_counts() {
    let out = geocert()
        .args(["prove", "mc-table", "--json"])
        .output()
        .unwrap();
    assert_success(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["entries"], 656);
    assert_eq!(v["cracks"], 0);
    assert_eq!(v["winding_errors"], 0);
    assert_eq!(v["edge_errors"], 0);
    assert_eq!(v["trilinear_unrealisable"], 36);
    assert_eq!(v["interior_ambiguous"], 140);
    assert!(v["interior_ambiguous_candidates"].as_u64().unwrap() >= 140);
}

#[test]
fn mc_export_then_audit() {
    let table = tmp("geocert-bourke.txt");
    let out = geocert()
        .args(["mc", "export", "--format", "bourke"])
        .output()
        .unwrap();
    assert!(out.status.success());
    std::fs::write(&table, &out.stdout).unwrap();
    let out = geocert()
        .args(["mc", "audit", "--format", "bourke", "--json"])
        .arg(&table)
        .output()
        .unwrap();
    assert_success(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["cracks"], 0);
    assert_eq!(v["winding_errors"], 0);
    assert_eq!(v["edge_errors"], 0);
    // The same file read with the other numbering is full of defects.
    let out = geocert()
        .args(["mc", "audit", "--format", "vtk", "--json"])
        .arg(&table)
        .output()
        .unwrap();
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(v["cracks"].as_u64().unwrap() > 0);
    // A malformed table: exit 2 with the configuration named.
    let bad = tmp("bad-table.txt");
    std::fs::write(&bad, "0 1\n".repeat(256)).unwrap();
    let out = geocert()
        .args(["mc", "audit", "--format", "vtk"])
        .arg(&bad)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("configuration 0"));
}

#[test]
fn mc_extract_raw_volume_both_paths() {
    // A 12³ u8 ball: distance to the centre, inverted so the inside is high.
    let n = 12usize;
    let c = (n - 1) as f64 / 2.0;
    let bytes: Vec<u8> = (0..n * n * n)
        .map(|idx| {
            let (i, j, k) = (idx % n, (idx / n) % n, idx / (n * n));
            let d =
                ((i as f64 - c).powi(2) + (j as f64 - c).powi(2) + (k as f64 - c).powi(2)).sqrt();
            (200.0 - 30.0 * d).max(0.0) as u8
        })
        .collect();
    let raw = tmp("ball.raw");
    std::fs::write(&raw, &bytes).unwrap();
    let mut results = Vec::new();
    for (path, iso) in [("fast", "100.5"), ("exact", "201/2")] {
        let out = tmp(&format!("ball-{path}.ply"));
        let o = geocert()
            .args(["mc", "extract"])
            .arg(&raw)
            .args([
                "--dims", "12", "12", "12", "--type", "u8", "--iso", iso, "--path", path, "--json",
                "--out",
            ])
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(v["closed"], true);
        assert!(v["triangles"].as_u64().unwrap() > 0);
        results.push((v["triangles"].clone(), v["vertices"].clone()));
        assert!(out.exists());
    }
    assert_eq!(results[0], results[1], "both paths give the same structure");
    // Wrong dimensions: exit 2, nothing written.
    let never = tmp("never.ply");
    let o = geocert()
        .args(["mc", "extract"])
        .arg(&raw)
        .args([
            "--dims", "12", "12", "11", "--type", "u8", "--iso", "100", "--out",
        ])
        .arg(&never)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(!never.exists());
}

#[test]
fn mc_extract_nifti_and_fe_demo() {
    // A ball in a gzipped NIfTI volume gives the same surface as the raw volume.
    let n = 10u16;
    let values: Vec<f32> = (0..n as usize * n as usize * n as usize)
        .map(|i| {
            let (x, y, z) = (i % 10, i / 10 % 10, i / 100);
            let d = |a: usize| a as f32 - 4.5;
            d(x) * d(x) + d(y) * d(y) + d(z) * d(z)
        })
        .collect();
    let nii = tmp("ball.nii.gz");
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    std::io::Write::write_all(
        &mut gz,
        &geocert::mc::nifti::nifti_f32_bytes([n, n, n], &values),
    )
    .unwrap();
    std::fs::write(&nii, gz.finish().unwrap()).unwrap();
    let raw = tmp("ball.f32");
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(&raw, bytes).unwrap();
    let run = |args: &[&str], input: &std::path::Path, out: &std::path::Path| {
        let o = geocert()
            .args(["mc", "extract"])
            .arg(input)
            .args(args)
            .args(["--iso", "12", "--json", "--out"])
            .arg(out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()
    };
    let a = run(&[], &nii, &tmp("ball-nii.obj"));
    let b = run(
        &["--dims", "10", "10", "10", "--type", "f32"],
        &raw,
        &tmp("ball-raw.obj"),
    );
    assert_eq!(a["closed"], true);
    assert_eq!(a["triangles"], b["triangles"]);
    assert_eq!(
        std::fs::read(tmp("ball-nii.obj")).unwrap(),
        std::fs::read(tmp("ball-raw.obj")).unwrap()
    );
    // A raw volume without --dims is a clear error.
    let o = geocert()
        .args(["mc", "extract"])
        .arg(&raw)
        .args(["--iso", "1", "--out"])
        .arg(tmp("never2.ply"))
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--dims"));

    // A bad output name: exit 2 and no model file either.
    let never = tmp("never-model.json");
    let o = geocert()
        .args(["mc", "demo", "--model-out"])
        .arg(&never)
        .arg("--out")
        .arg(tmp("never.xyz"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(!never.exists());

    // The heart demo, both paths, and its model file back through `mc fe`.
    let model = tmp("lv.json");
    let mut counts = Vec::new();
    for path in ["fast", "exact"] {
        let out = tmp(&format!("lv-{path}.vtk"));
        let o = geocert()
            .args([
                "mc", "demo", "--path", path, "--json", "--cells", "4", "4", "3",
            ])
            .arg("--model-out")
            .arg(&model)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(v["manifold"], true);
        assert!(v["stats"]["welded_vertices"].as_u64().unwrap() > 0);
        counts.push((v["triangles"].clone(), v["vertices"].clone()));
    }
    assert_eq!(counts[0], counts[1]);
    assert!(std::fs::read_to_string(tmp("lv-fast.vtk"))
        .unwrap()
        .contains("NORMALS"));
    let o = geocert()
        .args(["mc", "fe"])
        .arg(&model)
        .args(["--iso", "0", "--cells", "4", "4", "3", "--json", "--out"])
        .arg(tmp("lv-fe.ply"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!((v["triangles"].clone(), v["vertices"].clone()), counts[0]);
    // `--topology trilinear` is refused on Hermite elements, with nothing written.
    let refused = tmp("lv-trilinear.ply");
    let o = geocert()
        .args(["mc", "fe"])
        .arg(&model)
        .args(["--iso", "0", "--topology", "trilinear", "--out"])
        .arg(&refused)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("trilinear Lagrange"));
    assert!(!refused.exists());
    // One trilinear element whose interpolant has a tunnel at 1/2 (found by searching
    // integer cells with `cell_topology_exact`; local node (a, b, c) at a + 2b + 4c): one
    // component, a tube, where the table draws two discs.
    let cell = tmp("tunnel.json");
    let coords: Vec<[f64; 3]> = (0..8)
        .map(|l| [(l & 1) as f64, (l >> 1 & 1) as f64, (l >> 2 & 1) as f64])
        .collect();
    let field = [-1.0, 2.0, 1.0, 0.0, -3.0, 1.0, 0.0, 1.0];
    let model_json = serde_json::json!({
        "kind": {"bases": ["linear-lagrange", "linear-lagrange", "linear-lagrange"]},
        "coordinates": coords,
        "field": field,
        "elements": [[0, 1, 2, 3, 4, 5, 6, 7]],
    });
    std::fs::write(&cell, model_json.to_string()).unwrap();
    let mut stats = Vec::new();
    for topology in ["table", "trilinear"] {
        let o = geocert()
            .args(["mc", "fe"])
            .arg(&cell)
            .args([
                "--iso",
                "0.5",
                "--cells",
                "1",
                "1",
                "1",
                "--json",
                "--topology",
                topology,
            ])
            .arg("--out")
            .arg(tmp(&format!("tunnel-{topology}.ply")))
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        stats.push((
            v["stats"]["tunnel_cells"].clone(),
            v["euler_characteristic"].clone(),
        ));
    }
    assert_eq!(stats[0].0, 0);
    assert_eq!(stats[1].0, 1, "{stats:?}");
    // A tube (annulus, χ = 0) where the table draws discs.
    assert_eq!(
        stats[1].1.as_i64().unwrap(),
        stats[0].1.as_i64().unwrap() - 2,
        "{stats:?}"
    );
}

#[test]
fn decimate_undecimate_round_trip_and_refusals() {
    let (out, hist, back, full, fullh) = (
        tmp("dec.ply"),
        tmp("dec.bin"),
        tmp("back.ply"),
        tmp("full.ply"),
        tmp("full.bin"),
    );
    let s = |p: &std::path::PathBuf| p.to_str().unwrap().to_string();
    // `geocert decimate builtin:plate ARGS --json --out OUT --history HIST`, parsed.
    let plate_json = |args: &[&str]| -> serde_json::Value {
        let o = geocert()
            .args(["decimate", "builtin:plate"])
            .args(args)
            .args(["--json", "--out", &s(&out), "--history", &s(&hist)])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice(&o.stdout).unwrap()
    };
    let v = plate_json(&["--keep", "0.1"]);
    assert_eq!(v["nodes_in"], 15606);
    assert_eq!(v["nodes_out"], 1561);
    assert!(v["max_scalar_error"].as_f64().unwrap() > 0.0);
    assert!(v["seconds"].as_f64().unwrap() > 0.0);
    assert!(v["max_distance_error"].is_null());
    // Per-fan projection: errors against the closest point of the decimated surface. The
    // plate is flat: without the fit the distance vanishes; the fit moves the hole's border
    // nodes across it in the plane, so that its chords straddle the circle, and the distance
    // is then a fraction of a chord's sagitta (the plate's diagonal is 224). The scalar
    // error remains either way.
    let v = plate_json(&["--keep", "0.25", "--projection", "per-fan", "--fit", "0"]);
    assert_eq!(v["projection"], "per-fan");
    assert!(v["max_height_error"].is_null());
    assert!(v["max_distance_error"].as_f64().unwrap() < 1e-9);
    let v = plate_json(&["--keep", "0.25", "--projection", "per-fan"]);
    assert_eq!(v["fit_rounds"], 2);
    assert!(v["moved"].as_u64().unwrap() > 0);
    let d = v["max_distance_error"].as_f64().unwrap();
    assert!(d > 0.0 && d < 1e-3, "{d}");
    assert!(v["max_scalar_error"].as_f64().unwrap() > 0.0);
    // The original, written the same way, and the undecimated mesh are the same bytes.
    let o = geocert()
        .args([
            "decimate",
            "builtin:plate",
            "--keep",
            "1",
            "--out",
            &s(&full),
            "--history",
            &s(&fullh),
        ])
        .output()
        .unwrap();
    assert!(o.status.success());
    let o = undecimate(&out, &hist, &back);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stdout).contains("identical to the original"));
    assert_eq!(std::fs::read(&back).unwrap(), std::fs::read(&full).unwrap());
    // A history that belongs to another mesh is refused and nothing is written.
    let wrong = tmp("wrong.ply");
    let o = geocert()
        .args([
            "undecimate",
            &s(&full),
            "--history",
            &s(&hist),
            "--out",
            &s(&wrong),
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("does not belong"));
    assert!(!wrong.exists());
    // Non-manifold input: a clear error naming the edge, no outputs.
    let bad = tmp("bad.obj");
    std::fs::write(
        &bad,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n",
    )
    .unwrap();
    let (bo, bh) = (tmp("bad-out.ply"), tmp("bad.bin"));
    let o = geocert()
        .args(["decimate", &s(&bad), "--out", &s(&bo), "--history", &s(&bh)])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("edge ("));
    assert!(!bo.exists() && !bh.exists());
}

#[test]
fn closed_stdout_ends_quietly() {
    // The reader is gone before geocert writes: `geocert … --json | head -c0`.
    let mut child = geocert()
        .args(["decimate", "builtin:grid:30", "--json"])
        .arg("--out")
        .arg(tmp("pipe.ply"))
        .arg("--history")
        .arg(tmp("pipe.bin"))
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "status {:?}: {stderr}", out.status);
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn solve_certifies_roots_and_the_checker_agrees() {
    // The unit circle and x − 2y + x³/3 = 0 on [−2, 2]²: two roots, (±0.8497…, ±0.5271…).
    let system = tmp("circle.json");
    std::fs::write(
        &system,
        r#"{"box": [["-2","2"],["-2","2"]], "equations": [
            {"terms": [[[2,0],1],[[0,2],1],[[0,0],-1]]},
            {"terms": [[[1,0],1],[[0,1],-2],[[3,0],"1/3"]]}]}"#,
    )
    .unwrap();
    let cert = tmp("circle.cert.json");
    for path in ["exact", "fast", "filtered"] {
        let out = geocert()
            .args(["solve", system.to_str().unwrap(), "--json", "--path", path])
            .args(["--cert", cert.to_str().unwrap()])
            .output()
            .unwrap();
        assert_success(&out);
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let roots = v["roots"].as_array().unwrap();
        assert_eq!(roots.len(), 2, "{path}: {v}");
        for r in roots {
            let x = r["approx"][0].as_f64().unwrap();
            let y = r["approx"][1].as_f64().unwrap();
            approx::assert_abs_diff_eq!(x * x + y * y, 1.0, epsilon = 1e-9);
            assert!(r["error_bound"].as_f64().unwrap() < 1e-9, "{path}: {r}");
        }
        assert_eq!(accepted(&cert).matches("valid").count(), 2);
    }
    // A tampered certificate is refused with exit code 1.
    let text = std::fs::read_to_string(&cert).unwrap();
    let tampered = text.replacen(
        "\"lower_face_signs\": [\n        -1",
        "\"lower_face_signs\": [\n        1",
        1,
    );
    let tampered = if tampered == text {
        text.replacen(
            "\"lower_face_signs\": [\n        1",
            "\"lower_face_signs\": [\n        -1",
            1,
        )
    } else {
        tampered
    };
    assert_ne!(tampered, text);
    refused_as(&cert, &tampered, "invalid");
}

/// `geocert solve verify-cert CERT` (which must accept every certificate in it): its output.
fn accepted(cert: &std::path::Path) -> String {
    let out = geocert()
        .args(["solve", "verify-cert", cert.to_str().unwrap()])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(out.status.success(), "{text}");
    text
}

/// `geocert solve verify-cert` on `text` written to `cert` exits with 1, saying `why`.
fn refused_as(cert: &std::path::Path, text: &str, why: &str) {
    std::fs::write(cert, text).unwrap();
    let out = geocert()
        .args(["solve", "verify-cert", cert.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stdout).contains(why));
}

/// `geocert solve SYSTEM --json --cert CERT` (which must succeed): its JSON.
fn solve_with_cert(system: &std::path::Path, cert: &std::path::Path) -> serde_json::Value {
    let out = geocert()
        .args(["solve", system.to_str().unwrap(), "--json"])
        .args(["--cert", cert.to_str().unwrap()])
        .output()
        .unwrap();
    assert_success(&out);
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn solve_certifies_katsura_3_with_a_root_on_the_box_boundary() {
    // Katsura-3 on [−1, 1]⁴ (msolve: six real roots, all in the box); (1, 0, 0, 0) lies on
    // the face u₀ = 1 and on three split planes.
    let system = tmp("katsura3.json");
    std::fs::write(
        &system,
        r#"{"box": [["-1","1"],["-1","1"],["-1","1"],["-1","1"]], "equations": [
            {"terms": [[[1,0,0,0],1],[[0,1,0,0],2],[[0,0,1,0],2],[[0,0,0,1],2],[[0,0,0,0],-1]]},
            {"terms": [[[2,0,0,0],1],[[0,2,0,0],2],[[0,0,2,0],2],[[0,0,0,2],2],[[1,0,0,0],-1]]},
            {"terms": [[[1,1,0,0],2],[[0,1,1,0],2],[[0,0,1,1],2],[[0,1,0,0],-1]]},
            {"terms": [[[0,2,0,0],1],[[1,0,1,0],2],[[0,1,0,1],2],[[0,0,1,0],-1]]}]}"#,
    )
    .unwrap();
    let cert = tmp("katsura3.cert.json");
    let v = solve_with_cert(&system, &cert);
    assert_eq!(v["roots"].as_array().unwrap().len(), 6, "{v}");
    assert!(v["clusters"].as_array().unwrap().is_empty(), "{v}");
    let on_face: Vec<_> = v["roots"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|r| r.get("point"))
        .collect();
    assert_eq!(on_face, [&serde_json::json!(["1", "0", "0", "0"])]);
    let text = accepted(&cert);
    assert_eq!(text.matches(": valid").count(), 6, "{text}");
    assert_eq!(text.matches("vanishes exactly").count(), 1, "{text}");
    // The point moved off the root is refused.
    let tampered = std::fs::read_to_string(&cert).unwrap().replacen(
        "\"point\": [\n        \"1\"",
        "\"point\": [\n        \"1/2\"",
        1,
    );
    refused_as(&cert, &tampered, "invalid: the certificate's point");
}

#[test]
fn solve_certifies_all_twelve_real_roots_of_katsura_4() {
    // Katsura-4 on [−1, 1]⁵ (msolve: twelve real roots, all in the box). Four of them lie
    // within about 0.06 of each other and (1, 0, 0, 0, 0) on a face: with a group budget that
    // did not grow with the number of unknowns they were left in two singular clusters.
    let system = tmp("katsura4.json");
    std::fs::write(
        &system,
        r#"{"box": [["-1","1"],["-1","1"],["-1","1"],["-1","1"],["-1","1"]], "equations": [
            {"terms": [[[1,0,0,0,0],1],[[0,1,0,0,0],2],[[0,0,1,0,0],2],[[0,0,0,1,0],2],[[0,0,0,0,1],2],[[0,0,0,0,0],-1]]},
            {"terms": [[[2,0,0,0,0],1],[[1,0,0,0,0],-1],[[0,2,0,0,0],2],[[0,0,2,0,0],2],[[0,0,0,2,0],2],[[0,0,0,0,2],2]]},
            {"terms": [[[1,1,0,0,0],2],[[0,1,1,0,0],2],[[0,1,0,0,0],-1],[[0,0,1,1,0],2],[[0,0,0,1,1],2]]},
            {"terms": [[[1,0,1,0,0],2],[[0,2,0,0,0],1],[[0,1,0,1,0],2],[[0,0,1,0,1],2],[[0,0,1,0,0],-1]]},
            {"terms": [[[1,0,0,1,0],2],[[0,1,1,0,0],2],[[0,1,0,0,1],2],[[0,0,0,1,0],-1]]}]}"#,
    )
    .unwrap();
    let cert = tmp("katsura4.cert.json");
    let v = solve_with_cert(&system, &cert);
    let roots = v["roots"].as_array().unwrap();
    assert_eq!(roots.len(), 12, "{v}");
    assert!(v["clusters"].as_array().unwrap().is_empty(), "{v}");
    // The four close roots (msolve's, rounded) are among them.
    for expected in [
        [0.167675, 0.059631, 0.057356, 0.054242, 0.244933],
        [0.226541, 0.0, 0.11327, 0.0, 0.273459],
        [0.280729, 0.053657, -0.05632, 0.060155, 0.302143],
        [0.333333, 0.0, 0.0, 0.0, 0.333333],
    ] {
        let near = roots.iter().any(|r| {
            let a = r["approx"].as_array().unwrap();
            a.iter()
                .zip(expected)
                .all(|(x, e)| (x.as_f64().unwrap() - e).abs() < 1e-5)
        });
        assert!(near, "no root near {expected:?}: {v}");
    }
    let text = accepted(&cert);
    assert_eq!(text.matches(": valid").count(), 12, "{text}");
}

#[test]
fn solve_reads_b_spline_equations_and_certifies_a_root_on_a_knot() {
    // f1: the piecewise-linear field through (0, −⅓), (⅓, 0), (1, 2) with its kink and root
    // on the knot ⅓; f2: a uniform quadratic B-spline in y (unclamped knots) equal to y − ¼.
    let system = tmp("kink.json");
    std::fs::write(
        &system,
        r#"{"box": [["0","1"],["0","1"]], "equations": [
            {"bspline": {"orders": [2, 1], "knots": [["0","0","1/3","1","1"], ["0","1"]],
                         "coeffs": ["-1/3", "0", "2"]}},
            {"bspline": {"orders": [1, 3], "knots": [["0","1"], ["-1","-1/2","0","1/2","1","3/2","2"]],
                         "coeffs": ["-1/2", "0", "1/2", "1"]}}]}"#,
    )
    .unwrap();
    let cert = tmp("kink.cert.json");
    let v = solve_with_cert(&system, &cert);
    let roots = v["roots"].as_array().unwrap();
    assert_eq!(roots.len(), 1, "{v}");
    assert_eq!(v["clusters"].as_array().unwrap().len(), 0, "{v}");
    approx::assert_abs_diff_eq!(
        roots[0]["approx"][0].as_f64().unwrap(),
        1.0 / 3.0,
        epsilon = 1e-12
    );
    approx::assert_abs_diff_eq!(
        roots[0]["approx"][1].as_f64().unwrap(),
        0.25,
        epsilon = 1e-12
    );
    accepted(&cert);
    // The curve of a piecewise equation: f = 0 is the line x = 1/3, which lies on the kink
    // (C⁰ knot) itself; it is traced from face y = 0 to face y = 1, and its certificate file
    // re-checks.
    let curve = tmp("kink-curve.json");
    std::fs::write(
        &curve,
        r#"{"box": [["0","1"],["0","1"]], "equations": [
            {"bspline": {"orders": [2, 1], "knots": [["0","0","1/3","1","1"], ["0","1"]],
                         "coeffs": ["-1/3", "0", "2"]}}]}"#,
    )
    .unwrap();
    let curve_cert = tmp("kink-curve.cert.json");
    let out = geocert()
        .args(["solve", curve.to_str().unwrap(), "--curves", "--json"])
        .args(["--cert", curve_cert.to_str().unwrap()])
        .output()
        .unwrap();
    assert_success(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let curves = v["curves"].as_array().unwrap();
    assert_eq!(curves.len(), 1, "{v}");
    assert_eq!(v["clusters"].as_array().unwrap().len(), 0, "{v}");
    for p in curves[0]["polyline"].as_array().unwrap() {
        approx::assert_abs_diff_eq!(p[0].as_f64().unwrap(), 1.0 / 3.0, epsilon = 1e-12);
    }
    accepted(&curve_cert);
    // Extreme points of B-spline equations are refused with a clear error, nothing written.
    let refused = tmp("kink-curve-refused.cert.json");
    let out = geocert()
        .args([
            "solve",
            curve.to_str().unwrap(),
            "--curves",
            "--extreme-axis",
            "0",
        ])
        .args(["--cert", refused.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("extreme"));
    assert!(!refused.exists());
}

#[test]
fn solve_traces_curves_and_the_checker_agrees() {
    // A circle of radius 1/2 about (3/4, 0) on [−1, 1]²: it leaves through the face x = 1.
    let system = tmp("arc.json");
    std::fs::write(
        &system,
        r#"{"box": [["-1","1"],["-1","1"]], "equations": [
            {"terms": [[[2,0],1],[[0,2],1],[[1,0],"-3/2"],[[0,0],"5/16"]]}]}"#,
    )
    .unwrap();
    let cert = tmp("arc.cert.json");
    let out = geocert()
        .args(["solve", system.to_str().unwrap(), "--curves", "--json"])
        .args(["--extreme-axis", "0", "--cert", cert.to_str().unwrap()])
        .output()
        .unwrap();
    assert_success(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let curves = v["curves"].as_array().unwrap();
    assert_eq!(curves.len(), 1, "{v}");
    assert_eq!(curves[0]["closed"], false);
    for e in curves[0]["ends"].as_array().unwrap() {
        assert_eq!(e["face"], serde_json::json!([0, "upper"]), "{e}");
    }
    for p in curves[0]["polyline"].as_array().unwrap() {
        let (x, y) = (p[0].as_f64().unwrap(), p[1].as_f64().unwrap());
        approx::assert_abs_diff_eq!(x * x - 1.5 * x + y * y + 0.3125, 0.0, epsilon = 1e-9);
    }
    // The only extreme in x inside the box is (1/4, 0).
    let extremes = v["extremes"].as_array().unwrap();
    assert_eq!(extremes.len(), 1, "{v}");
    assert!(accepted(&cert).contains("curve: valid"));
    // --curves on a square system, and an extreme axis out of range, are refused (exit 2,
    // nothing written).
    let square = tmp("square-curves.json");
    std::fs::write(
        &square,
        r#"{"box": [["-1","1"],["-1","1"]], "equations": [{"terms": [[[2,0],1],[[0,2],1],[[0,0],-1]]},{"terms": [[[1,0],1]]}]}"#,
    )
    .unwrap();
    for (file, extra, needle) in [
        (&square, "0", "2 equations in 2 unknowns"),
        (&system, "5", "axis 5"),
    ] {
        let cert = tmp("refused-curves.cert.json");
        let out = geocert()
            .args([
                "solve",
                file.to_str().unwrap(),
                "--curves",
                "--extreme-axis",
                extra,
            ])
            .args(["--cert", cert.to_str().unwrap()])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2));
        assert!(String::from_utf8_lossy(&out.stderr).contains(needle));
        assert!(!cert.exists());
    }
}

#[test]
fn solve_refuses_malformed_systems() {
    let cases = [
        (
            r#"{"box": [["1","0"]], "equations": [{"terms": [[[1], 1]]}]}"#,
            "box interval 0",
        ),
        (
            r#"{"box": [["0","1"],["0","1"]], "equations": [{"terms": [[[1,0], 1]]}]}"#,
            "1 equations in 2 unknowns",
        ),
        (
            r#"{"box": [["0","1"]], "equations": [{"terms": [[[1,0], 1]]}]}"#,
            "equations[0].terms[0]",
        ),
        (
            r#"{"box": [["0","1"]], "equations": [{"degrees": [2], "coeffs": [1, 2]}]}"#,
            "equations[0]",
        ),
        (r#"{"box": [["0","x"]], "equations": []}"#, "box[0][1]"),
        (r#"{"equations": []}"#, "box"),
    ];
    for (i, (text, expect)) in cases.iter().enumerate() {
        refuses("solve", &format!("bad-system-{i}.json"), text, expect);
    }
}

#[test]
fn sweep_silhouette_writes_components_json_and_a_drawing() {
    let svg = tmp("sphere-line.svg");
    let out = geocert()
        .args(["sweep", "silhouette", "builtin:sphere-line", "--json"])
        .args(["--svg", svg.to_str().unwrap()])
        .output()
        .unwrap();
    assert_success(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let comps = v["components"].as_array().unwrap();
    let envelope: Vec<_> = comps.iter().filter(|c| c["kind"] == "envelope").collect();
    assert_eq!(envelope.len(), 2, "{v}");
    for c in &envelope {
        assert_eq!(c["type"], 3);
        assert_eq!(
            c["points"].as_array().unwrap().len(),
            c["uvt"].as_array().unwrap().len()
        );
    }
    assert_eq!(comps.iter().filter(|c| c["kind"] == "cap_a").count(), 1);
    assert_eq!(v["clusters"].as_array().unwrap().len(), 0);
    let drawing = std::fs::read_to_string(&svg).unwrap();
    assert!(drawing.starts_with("<svg") && drawing.matches("<path").count() == comps.len());
    // Bad scenes: exit 2, the field named, nothing written.
    let bad = tmp("bad-scene.json");
    std::fs::write(
        &bad,
        r#"{"surfaces": [{"sphere": {"center": [0,0,0], "radius": -1}}], "t": [0,1], "eye": [0,0,9]}"#,
    )
    .unwrap();
    let none = tmp("never.svg");
    let out = geocert()
        .args(["sweep", "silhouette", bad.to_str().unwrap()])
        .args(["--svg", none.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("surfaces[0].sphere.radius"));
    assert!(!none.exists());
    let out = geocert()
        .args(["sweep", "silhouette", "builtin:nope"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("sphere-line"));
}

#[test]
fn sweep_events_lists_certified_events_for_an_eye_path() {
    let scene = tmp("turn-eye.json");
    std::fs::write(
        &scene,
        r#"{"surfaces": [{"ellipsoid": {"center": [0, 0, 0], "radii": [2, "1/2", "1/2"]}}],
            "t": [0, 1],
            "motion": {"translation": [[0, 3], [0], [0, "1/2"]],
                       "rotation": {"quaternion": [[1], [0], [0], [0, "1/2"]]}},
            "eye": {"path": [[-3, 3], [-2], [0, "1/3"]], "r": [0, 3]}}"#,
    )
    .unwrap();
    let out = geocert()
        .args(["sweep", "events", scene.to_str().unwrap(), "--json"])
        .output()
        .unwrap();
    assert_success(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let events = v["events"].as_array().unwrap();
    assert!(events.iter().all(|e| e["verified"] == true));
    let r: Vec<f64> = events.iter().map(|e| e["r"].as_f64().unwrap()).collect();
    assert!(r.windows(2).all(|w| w[0] <= w[1]));
    let interior: Vec<_> = events
        .iter()
        .filter(|e| e["kind"]["where"] == "interior")
        .collect();
    assert_eq!(interior.len(), 1);
    assert_eq!(interior[0]["pivot_certified"], true);
    assert!((interior[0]["r"].as_f64().unwrap() - 1.6525).abs() < 1e-3);
    // A fixed eye has no events: exit 2 with the field named.
    let out = geocert()
        .args(["sweep", "events", "builtin:sphere-line"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("eye"));
}

/// `sweep animate`: a unit sphere on a line seen from an eye moving along a line. The envelope
/// is the cylinder of radius 1 about the path `(2t, t/2, 0)`, so every point of every frame,
/// continued or traced, lies on it and sees the eye along a tangent: `(X − E) · n = 0`.
#[test]
fn sweep_animate_draws_frames_on_the_true_contour() {
    let scene = tmp("sphere-line-eye.json");
    std::fs::write(
        &scene,
        r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": 1}}],
            "t": [0, 2],
            "motion": {"translation": [[0, 2], [0, "1/2"], [0]]},
            "eye": {"path": [[2, 1], [-8], [3]], "r": [0, 2]}}"#,
    )
    .unwrap();
    let dir = tmp("animate-frames");
    let _ = std::fs::remove_dir_all(&dir);
    let out = geocert()
        .args(["sweep", "animate", scene.to_str().unwrap(), "--frames", "9"])
        .args(["--svg-dir", dir.to_str().unwrap(), "--json"])
        .output()
        .unwrap();
    assert_success(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let frames = v["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 9);
    assert_eq!(frames[0]["traced"], true);
    assert_eq!(
        v["continued_frames"], 8,
        "no event on this path: {}",
        v["events"]
    );
    // The path's direction (2, 1/2, 0), normalised.
    let axis = [4.0 / 17f64.sqrt(), 1.0 / 17f64.sqrt(), 0.0];
    let mut worst = 0.0f64;
    for (k, f) in frames.iter().enumerate() {
        let r = f["r"].as_f64().unwrap();
        assert!((r - 0.25 * k as f64).abs() < 1e-12);
        let eye = [2.0 + r, -8.0, 3.0];
        let comps = f["components"].as_array().unwrap();
        assert_eq!(comps.len(), 2, "frame {k}");
        for c in comps {
            for p in c["points"].as_array().unwrap() {
                let x: Vec<f64> = p
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|c| c.as_f64().unwrap())
                    .collect();
                // The radial part of x about the axis through the origin.
                let along = x[0] * axis[0] + x[1] * axis[1];
                let n = [x[0] - along * axis[0], x[1] - along * axis[1], x[2]];
                let radius = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                let to = [x[0] - eye[0], x[1] - eye[1], x[2] - eye[2]];
                let tangency = (to[0] * n[0] + to[1] * n[1] + to[2] * n[2])
                    / (to[0] * to[0] + to[1] * to[1] + to[2] * to[2]).sqrt();
                worst = worst.max((radius - 1.0).abs()).max(tangency.abs());
            }
        }
        let drawing = std::fs::read_to_string(dir.join(format!("frame-{k:04}.svg"))).unwrap();
        assert_eq!(drawing.matches("<path").count(), 2);
    }
    println!("9 frames (8 continued): worst |radius − 1| or tangency {worst:.2e}");
    assert!(worst < 1e-6, "{worst}");
    // A fixed eye, no frames, a range outside the path: exit 2, nothing written.
    let none = tmp("animate-never");
    let _ = std::fs::remove_dir_all(&none);
    for args in [
        vec!["builtin:sphere-line"],
        vec![scene.to_str().unwrap(), "--frames", "0"],
        vec![scene.to_str().unwrap(), "--from", "1", "--to", "3"],
    ] {
        let out = geocert()
            .args(["sweep", "animate"])
            .args(&args)
            .args(["--svg-dir", none.to_str().unwrap()])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(!none.exists());
    }
}

#[test]
fn dmv_build_and_refine_end_to_end() {
    let dmv = tmp("fuel.dmv");
    let out = geocert()
        .args([
            "dmv",
            "build",
            "builtin:fuel:33",
            "--iso",
            "60,120",
            "--json",
            "--out",
        ])
        .arg(&dmv)
        .output()
        .unwrap();
    assert_success(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let np = v["diamonds"].as_u64().unwrap();
    assert!(np > 0 && v["supercubes"].as_u64().unwrap() > 0);
    assert!(v["bytes"]["supercube"].as_u64().unwrap() < v["bytes"]["full"].as_u64().unwrap());
    let surface = tmp("fuel.ply");
    let mesh = tmp("fuel.vtk");
    for front in ["diamond", "supercube"] {
        let out = geocert()
            .args(["dmv", "refine"])
            .arg(&dmv)
            .args([
                "--iso",
                "60",
                "--error",
                "1",
                "--front",
                front,
                "--json",
                "--surface",
            ])
            .arg(&surface)
            .arg("--mesh")
            .arg(&mesh)
            .output()
            .unwrap();
        assert_success(&out);
        let r: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(r["conforming"], true);
        assert_eq!(r["surface_closed"], true);
        assert!(r["simplices"].as_u64().unwrap() > 6);
        assert!(std::fs::read_to_string(&mesh)
            .unwrap()
            .contains("UNSTRUCTURED_GRID"));
    }
    // A corrupt file is refused with the byte offset, exit code 2.
    let mut bytes = std::fs::read(&dmv).unwrap();
    let n = bytes.len();
    bytes[n / 2] ^= 0x55;
    let bad = tmp("bad.dmv");
    std::fs::write(&bad, &bytes).unwrap();
    let out = geocert()
        .args(["dmv", "refine"])
        .arg(&bad)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("checksum"));
    // Unknown built-ins and missing criteria are clear errors; nothing is written.
    let none = tmp("none.dmv");
    for args in [
        vec!["dmv", "build", "builtin:nothing:9", "--error", "0", "--out"],
        vec!["dmv", "build", "builtin:gyroid:9", "--out"],
    ] {
        let out = geocert().args(&args).arg(&none).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(!none.exists());
    }
}

#[test]
fn mc_verify_against_the_trilinear_truth() {
    // f32 noise: tunnels and ambiguous faces are common.
    let n = 10usize;
    let mut s = 5u64;
    let values: Vec<f32> = (0..n * n * n)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 40) % 2001) as f32 / 1000.0 - 1.0
        })
        .collect();
    let raw = tmp("noise-verify.f32");
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(&raw, bytes).unwrap();
    let dims = ["--dims", "10", "10", "10", "--type", "f32"];
    let extract = |topology: &str, out: &std::path::Path| {
        let o = geocert()
            .args(["mc", "extract"])
            .arg(&raw)
            .args(dims)
            .args(["--iso", "0.0625", "--topology", topology, "--json", "--out"])
            .arg(out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    let verify = |mesh: &std::path::Path, iso: &str| {
        geocert()
            .args(["mc", "verify"])
            .arg(&raw)
            .arg(mesh)
            .args(dims)
            .args(["--iso", iso, "--json"])
            .output()
            .unwrap()
    };
    let (table, trilinear) = (tmp("noise-table.ply"), tmp("noise-trilinear.ply"));
    extract("table", &table);
    extract("trilinear", &trilinear);
    // The trilinear mode agrees (exit 0); the table misses exactly the tunnels (exit 1).
    let o = verify(&trilinear, "0.0625");
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    let o = verify(&table, "0.0625");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(v["watertight"], true);
    assert!(v["truth_tunnel_cells"].as_u64().unwrap() > 0);
    assert_eq!(
        v["mismatches"][0],
        serde_json::json!(["missing_tunnel", v["tunnel_cells_compared"]])
    );
    // Another isovalue: a clear error naming a vertex, exit 2.
    let o = verify(&table, "0.5");
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("vertex"));
}

/// Two fans meeting at one vertex (a bow-tie, as in range maps): refused with the way out
/// named, then decimated with `--split-bowties` and undone exactly to the split mesh; loose
/// vertices are carried through and counted apart.
#[test]
fn bow_ties_are_split_on_request_and_loose_vertices_carried() {
    let s = |p: &std::path::PathBuf| p.to_str().unwrap().to_string();
    // Two 5×5 grids of triangles in the plane z = x·y/10 touching at their corner vertex 0,
    // and two loose vertices.
    let mut obj = String::new();
    let side = 5;
    for sheet in [1.0, -1.0] {
        for j in 0..side {
            for i in 0..side {
                if sheet < 0.0 && i == 0 && j == 0 {
                    continue;
                }
                let (x, y) = (sheet * i as f64, sheet * j as f64);
                obj += &format!(
                    "v {x} {y} {}\n",
                    x * y / 10.0 + 0.01 * ((i * 7 + j * 3) % 5) as f64
                );
            }
        }
    }
    obj += "v 50 50 50\nv -50 50 50\n";
    // Vertex numbers (1-based): sheet A at 1 + i + side·j; sheet B shares A's vertex 1 at
    // (0, 0) and numbers its others from side² + 1 on.
    let a = |i: usize, j: usize| 1 + i + side * j;
    let b = |i: usize, j: usize| {
        if i == 0 && j == 0 {
            1
        } else {
            side * side + i + side * j
        }
    };
    for j in 0..side - 1 {
        for i in 0..side - 1 {
            for v in [&a as &dyn Fn(usize, usize) -> usize, &b] {
                let (p, q, r, t) = (v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1));
                obj += &format!("f {p} {q} {r}\nf {p} {r} {t}\n");
            }
        }
    }
    let (input, out, hist, back) = (
        tmp("bowtie.obj"),
        tmp("bowtie-out.ply"),
        tmp("bowtie.bin"),
        tmp("bowtie-back.ply"),
    );
    std::fs::write(&input, obj).unwrap();
    let decimate = |extra: &[&str]| {
        geocert()
            .args(["decimate", &s(&input), "--nodes", "6", "--out", &s(&out)])
            .args(["--history", &s(&hist)])
            .args(extra)
            .output()
            .unwrap()
    };
    let o = decimate(&[]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("bow-tie") && err.contains("--split-bowties"),
        "{err}"
    );
    assert!(!out.exists() && !hist.exists());
    let o = decimate(&["--split-bowties", "--json"]);
    assert_success(&o);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["bowtie_copies"], 1);
    assert_eq!(v["unused_vertices"], 2);
    assert_eq!(v["nodes_in"], 2 * side * side + 2);
    let (kept, target) = (
        v["nodes_out"].as_u64().unwrap(),
        v["target_nodes"].as_u64().unwrap(),
    );
    assert_eq!(target, 8);
    assert!(kept >= target, "{v}");
    let o = undecimate(&out, &hist, &back);
    assert_success(&o);
    assert!(String::from_utf8_lossy(&o.stdout).contains("identical to the original"));
    // In the plane, each sheet's outline is kept: the run stops above its target and says why.
    let o = decimate(&["--split-bowties", "--projection", "xy"]);
    assert_success(&o);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("stopped above the target of 8 nodes") && text.contains("on the border"),
        "{text}"
    );
    // Node by node: the outline keeps the border nodes.
    assert!(text.contains("kept by the border policy"), "{text}");
    let o = decimate(&["--split-bowties", "--projection", "xy", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let b = &v["blocked"];
    let sum: u64 = [
        "border",
        "valence",
        "no_plane",
        "fold",
        "topology",
        "facing",
        "removable",
    ]
    .iter()
    .map(|k| b[k].as_u64().unwrap())
    .sum();
    assert_eq!(sum, v["nodes_out"].as_u64().unwrap() - 2, "{v}");
    assert!(b["border"].as_u64().unwrap() > 0, "{v}");
}
