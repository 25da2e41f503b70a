//! The finite-element polygonisation campaign for `reports/mc.md`: the heart demo and an
//! exactly represented sphere on both paths, and a differential run on random models.

use crate::mc::fe::exact::polygonise_exact;
use crate::mc::fe::fast::polygonise_fast;
use crate::mc::fe::{heart, models, FeModel, FeOptions, FeStats, NormalSource};
use crate::num::{rational_from_f64, xorshift};
use std::time::Instant;

/// One model at one sampling.
#[derive(Clone, Debug)]
pub struct FeRow {
    pub name: String,
    pub cells_per_element: [usize; 3],
    pub stats: FeStats,
    pub triangles: usize,
    pub vertices: usize,
    /// Median seconds of the fast path, one thread (one element range).
    pub fast_seconds: f64,
    /// Median seconds of the fast path on all cores ([`FeOptions::parts`] automatic).
    pub parallel_seconds: f64,
    /// The all-cores mesh equals the one-thread mesh in every run.
    pub parallel_same: bool,
    /// Seconds of the exact path (`None`: not run at this size).
    pub exact_seconds: Option<f64>,
    /// Exact and fast triangle structures equal (`None`: exact not run).
    pub exact_agrees: Option<bool>,
    pub manifold: Result<usize, String>,
    pub euler: i64,
    /// Largest `| |x| − r |` over the vertices (the sphere only).
    pub radius_error: Option<f64>,
    /// Largest angle (degrees) between the vertex normals and the sphere's normal, for
    /// interpolant and finite-difference normals (the sphere only).
    pub normal_error_deg: Option<(f64, f64)>,
}

/// The FE path beside grid extractors on the same samples: the trilinear gyroid block's
/// lattice gathered into one regular grid.
#[derive(Clone, Debug)]
pub struct SameSamples {
    /// Elements per direction and cells per element per direction.
    pub elements: usize,
    pub cells: usize,
    /// Median seconds: geocert's FE path and grid path, one thread each.
    pub fe_one: f64,
    pub grid_one: f64,
    /// Median seconds on all cores: geocert's FE path.
    pub fe_all: f64,
    /// VTK's version and vtkFlyingEdges3D's median seconds, one thread; and on the threaded
    /// backend with as many threads as geocert.
    pub vtk: Result<(String, f64), String>,
    pub vtk_threaded: Result<f64, String>,
}

/// The campaign.
#[derive(Clone, Debug)]
pub struct FeCampaign {
    pub runs: usize,
    pub rows: Vec<FeRow>,
    /// Random models through `fuzzing::check_mc_fe`: (run, passed).
    pub random: (usize, usize),
    /// Random integer-valued warped trilinear blocks under `CellRule::Trilinear`: (models,
    /// models where exact = fast and the mesh is a valid oriented manifold, cells drawn
    /// with a tube, cut cells).
    pub trilinear: (usize, usize, usize, usize),
    /// The FE path beside grid extractors on the same samples.
    pub same_samples: SameSamples,
    pub random_failures: Vec<String>,
}

fn run(
    name: &str,
    m: &FeModel<f64>,
    iso: f64,
    cells: [usize; 3],
    runs: usize,
    exact: bool,
) -> FeRow {
    let one = FeOptions {
        cells,
        parts: 1,
        ..FeOptions::default()
    };
    let all = one.with_parts(0);
    // One thread and all cores interleaved, so that both see the same drift of the machine.
    let (mut times, mut times_all) = (Vec::new(), Vec::new());
    let mut last = None;
    let mut same_mesh = true;
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool");
    for _ in 0..runs.max(1) {
        let t = Instant::now();
        let s = single
            .install(|| polygonise_fast(m, iso, &one))
            .expect("built-in model");
        times.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        let p = polygonise_fast(m, iso, &all).expect("built-in model");
        times_all.push(t.elapsed().as_secs_f64());
        same_mesh &= p.mesh.triangles == s.mesh.triangles
            && p.mesh.vertices == s.mesh.vertices
            && p.stats == s.stats;
        last = Some(s);
    }
    times.sort_by(f64::total_cmp);
    times_all.sort_by(f64::total_cmp);
    let fast = last.expect("one run");
    let opts = one;
    let (exact_seconds, exact_agrees) = if exact {
        let q = m.to_exact().expect("finite");
        let t = Instant::now();
        let e = polygonise_exact(&q, &rational_from_f64(iso, "iso").expect("finite"), &opts)
            .expect("built-in model");
        (
            Some(t.elapsed().as_secs_f64()),
            Some(e.triangles == fast.mesh.triangles),
        )
    } else {
        (None, None)
    };
    FeRow {
        name: name.into(),
        cells_per_element: cells,
        stats: fast.stats,
        triangles: fast.mesh.triangles.len(),
        vertices: fast.mesh.vertices.len(),
        fast_seconds: times[times.len() / 2],
        parallel_seconds: times_all[times_all.len() / 2],
        parallel_same: same_mesh,
        exact_seconds,
        exact_agrees,
        manifold: fast.mesh.check_manifold().map_err(|e| e.to_string()),
        euler: fast.mesh.euler_characteristic(),
        radius_error: None,
        normal_error_deg: None,
    }
}

/// Largest `| |x| − r |` and largest normal angle to the radial direction.
fn sphere_errors(m: &FeModel<f64>, iso: f64, cells: [usize; 3]) -> (f64, (f64, f64)) {
    let r = iso.sqrt();
    let mut radius = 0.0f64;
    let mut angles = [0.0f64; 2];
    for (slot, normals) in [NormalSource::Interpolant, NormalSource::FiniteDifference]
        .into_iter()
        .enumerate()
    {
        let opts = FeOptions {
            cells,
            normals,
            ..FeOptions::default()
        };
        let s = polygonise_fast(m, iso, &opts).expect("built-in model");
        let ns = s.mesh.normals.as_ref().expect("normals");
        for (v, n) in s.mesh.vertices.iter().zip(ns) {
            let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            radius = radius.max((len - r).abs());
            let cos = ((v[0] * n[0] + v[1] * n[1] + v[2] * n[2]) / len).clamp(-1.0, 1.0);
            angles[slot] = angles[slot].max(cos.acos().to_degrees());
        }
    }
    (radius, (angles[0], angles[1]))
}

/// The samples of `gyroid_block(e)` at `n` cells per element as one `(e n + 1)³` grid (the
/// block's elements are unit cubes in ξ, `i` fastest).
fn gathered_samples(e: usize, n: usize) -> Vec<f64> {
    use crate::mc::fe::tensor::{slot_table, ElementTensor};
    let m = models::gyroid_block(e);
    let side = e * n + 1;
    let lattice = ElementTensor::lattice_bases(m.kind, [n; 3]);
    let (mut scratch, mut vals) = (Vec::new(), Vec::new());
    let mut grid = vec![0.0; side * side * side];
    let (mut tensor, table) = (ElementTensor::empty(m.kind), slot_table(m.kind));
    for (idx, nodes) in m.elements.iter().enumerate() {
        let o = [idx % e, idx / e % e, idx / (e * e)].map(|x| x * n);
        tensor.load(&m, nodes, &table);
        tensor.sample_field(&lattice, &mut scratch, &mut vals);
        for k in 0..=n {
            for j in 0..=n {
                for i in 0..=n {
                    let g = (o[0] + i) + side * ((o[1] + j) + side * (o[2] + k));
                    grid[g] = vals[i + (n + 1) * (j + (n + 1) * k)];
                }
            }
        }
    }
    grid
}

/// The FE path on the trilinear gyroid block (`8³` elements, `16³` cells each) beside
/// geocert's grid path and vtkFlyingEdges3D on the same `129³` samples, interleaved.
fn same_samples(root: &std::path::Path, runs: usize) -> SameSamples {
    let (e, n) = (8, 16);
    let m = models::gyroid_block(e);
    let grid = gathered_samples(e, n);
    let side = e * n + 1;
    let vol = crate::mc::grid::Volume::new([side; 3], grid.clone()).expect("finite");
    let data: Vec<f32> = grid.iter().map(|&v| v as f32).collect();
    let one = FeOptions::new().with_cells([n; 3]).with_parts(1);
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool");
    let threads = crate::par::threads();
    let (mut fe_one, mut grid_one, mut fe_all) = (Vec::new(), Vec::new(), Vec::new());
    let (mut vtk_one, mut vtk_all) = (Vec::new(), Vec::new());
    let mut vtk: Result<(String, f64), String> = Err(String::new());
    let mut vtk_threaded: Result<f64, String> = Err("not run (one core)".into());
    for _ in 0..runs.max(1) {
        let t = Instant::now();
        single
            .install(|| polygonise_fast(&m, 0.1, &one))
            .expect("built-in model");
        fe_one.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        single
            .install(|| crate::mc::grid::extract_fast(&vol, 0.1))
            .expect("finite");
        grid_one.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        polygonise_fast(&m, 0.1, &one.with_parts(0)).expect("built-in model");
        fe_all.push(t.elapsed().as_secs_f64());
        if vtk.as_ref().is_err_and(|e| !e.is_empty()) {
            continue; // VTK is not available: do not retry every round
        }
        let v = super::mc_grid::vtk_script(root, &data, side, 0.1, 1, 1);
        vtk = v.and_then(|v| {
            let s = v["flying_edges"]["median_s"]
                .as_f64()
                .ok_or("no flying_edges.median_s")?;
            vtk_one.push(s);
            Ok((v["version"].as_str().unwrap_or("?").to_string(), s))
        });
        if threads > 1 && vtk.is_ok() {
            vtk_threaded =
                super::mc_grid::vtk_script(root, &data, side, 0.1, 1, threads).and_then(|v| {
                    let s = v["flying_edges"]["median_s"]
                        .as_f64()
                        .ok_or("no flying_edges.median_s")?;
                    vtk_all.push(s);
                    Ok(s)
                });
        }
    }
    let med = super::campaign::median;
    SameSamples {
        elements: e,
        cells: n,
        fe_one: med(fe_one),
        grid_one: med(grid_one),
        fe_all: med(fe_all),
        vtk: vtk.map(|(version, _)| (version, med(vtk_one))),
        vtk_threaded: vtk_threaded.map(|_| med(vtk_all)),
    }
}

/// Runs the campaign: `runs` timed repetitions, `random` random models; peers from `root`'s
/// `.venv-peers` when installed.
pub fn fe_campaign(root: &std::path::Path, runs: usize, random: usize) -> FeCampaign {
    let mut rows = Vec::new();
    let lv = heart::left_ventricle();
    for (cells, exact) in [
        ([9, 9, 5], true),
        ([18, 18, 10], false),
        ([45, 45, 25], false),
    ] {
        rows.push(run(
            "left ventricle, 16 elements",
            &lv,
            0.0,
            cells,
            runs,
            exact,
        ));
    }
    let ball = models::hermite_ball(2);
    for n in [4, 8, 16] {
        let mut row = run(
            "sphere r = 0.8, 8 tricubic elements",
            &ball,
            0.64,
            [n; 3],
            runs,
            n <= 8,
        );
        let (radius, normals) = sphere_errors(&ball, 0.64, [n; 3]);
        row.radius_error = Some(radius);
        row.normal_error_deg = Some(normals);
        rows.push(row);
    }
    let balls = models::hermite_ball(8);
    rows.push(run(
        "sphere r = 0.8, 512 tricubic elements",
        &balls,
        0.64,
        [8; 3],
        runs,
        false,
    ));
    // Trilinear Lagrange: a gyroid sampled at the nodes of warped element blocks.
    for (e, n, exact) in [(4, 4, true), (32, 4, false), (16, 8, false), (8, 16, false)] {
        rows.push(run(
            &format!("gyroid, {e}³ trilinear elements"),
            &models::gyroid_block(e),
            0.1,
            [n; 3],
            runs,
            exact,
        ));
    }
    // Random models through the differential fuzz check (xorshift bytes).
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut passed = 0;
    let mut failures = Vec::new();
    for _ in 0..random {
        let bytes: Vec<u8> = (0..320)
            .map(|_| (xorshift(&mut state) >> 24) as u8)
            .collect();
        match crate::fuzzing::check_mc_fe(&bytes) {
            Ok(()) => passed += 1,
            Err(e) => failures.push(e),
        }
    }
    let trilinear = trilinear_topology_campaign(random);
    let same_samples = same_samples(root, runs);
    FeCampaign {
        same_samples,
        runs: runs.max(1),
        rows,
        random: (random, passed),
        trilinear,
        random_failures: failures,
    }
}

/// `CellRule::Trilinear` on `count` warped blocks of 3 × 3 × 2 trilinear elements with
/// integer node values in [−3, 3] at the isovalue 1/2, 2 cells per element.
fn trilinear_topology_campaign(count: usize) -> (usize, usize, usize, usize) {
    use crate::mc::fe::{exact::polygonise_exact, CellRule, ElementKind};
    let mut state = 0x5851_F42D_4C95_7F2Du64;
    let (mut passed, mut tubes, mut cut) = (0, 0, 0);
    let half = crate::num::Rational::new(1.into(), 2.into());
    for _ in 0..count {
        let vals: Vec<f64> = (0..48)
            .map(|_| ((xorshift(&mut state) >> 20) % 7) as f64 - 3.0)
            .collect();
        let value = |p: [f64; 3]| vals[p[0] as usize + 4 * (p[1] as usize + 4 * p[2] as usize)];
        let m = models::block(
            ElementKind::TRILINEAR_LAGRANGE,
            [3, 3, 2],
            &value,
            &|_, _| 0.0,
            &|p| {
                [
                    p[0] + 0.1 * p[1] * p[2],
                    p[1] - 0.05 * p[0] * p[0],
                    p[2] + 0.1 * p[0] * p[1],
                ]
            },
        );
        let opts = FeOptions::new()
            .with_cells([2; 3])
            .with_topology(CellRule::Trilinear);
        let (Ok(fast), Ok(exact)) = (
            polygonise_fast(&m, 0.5, &opts),
            polygonise_exact(&m.to_exact().expect("finite"), &half, &opts),
        ) else {
            continue;
        };
        tubes += fast.stats.tunnel_cells;
        cut += fast.stats.cut_cells;
        passed += usize::from(
            fast.mesh.triangles == exact.triangles
                && fast.stats.tunnel_cells == exact.stats.tunnel_cells
                && fast.mesh.validate().is_ok(),
        );
    }
    (count, passed, tubes, cut)
}

/// Whether every check held.
pub fn fe_ok(c: &FeCampaign) -> bool {
    c.trilinear.0 == c.trilinear.1
        && c.random.0 == c.random.1
        && c.rows
            .iter()
            .all(|r| r.exact_agrees != Some(false) && r.manifold.is_ok() && r.parallel_same)
}

/// The Markdown section.
pub fn write_fe(s: &mut String, c: &FeCampaign) {
    use std::fmt::Write as _;
    let _ = writeln!(
        s,
        "\n## Polygonisation of curvilinear finite elements (Section 3)\n\n\
         Marching cubes in material space: each element's parent cube divided into \
         n₁ × n₂ × n₃ cells, the field sampled by the element's own interpolation (eq. 1), cut \
         points by linear interpolation in ξ, world positions by eq. 2, normals `J⁻ᵀ ∇_ξ s`. \
         Lattice points and cut edges on shared element faces, edges and nodes are named by \
         global node numbers, so the mesh is welded across elements; vertices that meet in \
         world space (degenerate elements, Figure 7) are merged and collapsed triangles \
         removed. The fast path is `f64` with a rounding bound on every sample; signs, face \
         decisions and world coincidences the bound cannot settle are recomputed exactly. \
         Fast timings are medians of {} runs; each run times one thread (one element range) \
         and then all cores (two element ranges per thread, polygonised in parallel and welded \
         by the names of the cut edges on shared faces), so both see the same drift of this \
         shared machine.\n\n\
         **How the fast path reaches grid speed.** An element's dofs are regrouped as a tensor \
         of 1-D coefficients (4 per direction for cubic Hermite, 2 for linear Lagrange) and \
         the lattice is sampled by sum factorisation: contracted along ξ₁ for whole rows, \
         then ξ₂, then ξ₃ (about m₃ multiply-adds per sample instead of 8 · dofs products of \
         three basis values); the bound `2⁻⁴⁵ Σ|dofs|` on every sample still holds (derived \
         in `src/mc/fe/tensor.rs`). Signs go into one bitset per lattice row and the cut \
         cells of a row are found 64 at a time, as on grids; only cut cells are visited. A \
         cut edge on an element's boundary finds its vertex in a block of slots of the face \
         or element edge it lies in (the entity named once per element by its global nodes, \
         its lattice edges indexed in the entity's canonical frame), not by hashing each \
         edge's name. Exact fallbacks (signs, cut points, the Figure 7 coincidence test) evaluate eqs. 1 \
         and 2 in integers over a shared denominator with one gcd at the end \
         (`src/mc/fe/integer.rs`), not in normalised rationals. Goals (one thread): at least \
         30 Mcells/s on Hermite and 60 Mcells/s on trilinear Lagrange elements.\n",
        c.runs
    );
    let _ = writeln!(
        s,
        "| model | cells / element | cells | cut cells | ambiguous cells | triangles | vertices | welded (Fig. 7) | collapsed triangles removed | exact fallbacks (values, faces) | manifold (boundary edges), χ | fast Mcells/s, one thread | fast Mcells/s, {} threads | same mesh | exact s | exact = fast |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---|---|---:|---:|---|---:|---|",
        crate::par::threads()
    );
    for r in &c.rows {
        let st = &r.stats;
        let manifold = match &r.manifold {
            Ok(b) => format!("yes ({b}), χ = {}", r.euler),
            Err(e) => format!("**no**: {e}"),
        };
        let _ = writeln!(
            s,
            "| {} | {:?} | {} | {} | {} ({:.2} % of cut) | {} | {} | {} | {} | {}, {} | {} | {:.2} | {:.2} | {} | {} | {} |",
            r.name,
            r.cells_per_element,
            st.cells,
            st.cut_cells,
            st.ambiguous_cells,
            100.0 * st.ambiguous_cells as f64 / st.cut_cells.max(1) as f64,
            r.triangles,
            r.vertices,
            st.welded_vertices,
            st.degenerate_triangles,
            st.exact_values,
            st.exact_faces,
            manifold,
            st.cells as f64 / r.fast_seconds / 1e6,
            st.cells as f64 / r.parallel_seconds / 1e6,
            if r.parallel_same { "yes" } else { "**no**" },
            r.exact_seconds.map_or("–".into(), |t| format!("{t:.2}")),
            match r.exact_agrees {
                Some(true) => "yes",
                Some(false) => "**no**",
                None => "not run",
            }
        );
    }
    let _ = writeln!(
        s,
        "\nThe left ventricle's four apical elements are degenerate: their apex face collapses \
         to a line, so cut points from different cells and elements meet there and the \
         triangles between them collapse (the welded and removed counts above). Its \
         0-isosurface meets the wall (the boundary edges): the field changes sign across the \
         endocardium and epicardium in the septal and lateral bands.\n"
    );
    let _ = writeln!(
        s,
        "| sphere sampling | largest radius error | largest normal angle, interpolant gradient | largest normal angle, finite differences |\n|---|---:|---:|---:|"
    );
    for r in c.rows.iter().filter(|r| r.radius_error.is_some()) {
        let (a, b) = r.normal_error_deg.unwrap_or_default();
        let _ = writeln!(
            s,
            "| {:?} | {:.2e} | {:.3}° | {:.3}° |",
            r.cells_per_element,
            r.radius_error.unwrap_or_default(),
            a,
            b
        );
    }
    let _ = writeln!(
        s,
        "\nThe sphere's field is represented exactly, so the radius error is the linear \
         interpolation along cell edges alone (it falls as the square of the cell size), and \
         interpolant normals are exact at the vertices up to that displacement.\n\n\
         Differential run: {} random one- or two-element models (trilinear, tricubic and \
         Hermite × Lagrange; warped, some with a collapsed face; 1–3 cells per direction) \
         through both paths: {} gave the same triangles and a valid mesh.",
        c.random.0, c.random.1
    );
    for f in c.random_failures.iter().take(5) {
        let _ = writeln!(s, "- failure: {f}");
    }
    let g = &c.same_samples;
    let side = g.elements * g.cells + 1;
    let cells = ((side - 1) as f64).powi(3);
    let rate = |t: f64| format!("{:.1}", cells / t / 1e6);
    let vtk = match &g.vtk {
        Ok((version, t)) => format!("{} (VTK {version})", rate(*t)),
        Err(e) => format!("not run: {e}"),
    };
    let vtk_all = match &g.vtk_threaded {
        Ok(t) => rate(*t),
        Err(e) => format!("not run: {e}"),
    };
    let _ = writeln!(
        s,
        "\n**The same samples on a grid.** The trilinear gyroid block of {e}³ elements at {n}³ \
         cells each samples a {side}³ lattice in ξ; gathered into one regular grid, the same \
         samples go through geocert's grid path and vtkFlyingEdges3D (medians of {runs} \
         interleaved rounds, Mcells/s). The FE path also names shared cut edges, maps every \
         vertex by eq. 2, computes `J⁻ᵀ` normals and tests world coincidences; the grid paths \
         do none of that.\n\n\
         | FE path, one thread | grid path, one thread | vtkFlyingEdges3D, one thread | FE path, {t} threads | vtkFlyingEdges3D, {t} threads |\n|---:|---:|---:|---:|---:|\n\
         | {} | {} | {vtk} | {} | {vtk_all} |",
        rate(g.fe_one),
        rate(g.grid_one),
        rate(g.fe_all),
        e = g.elements,
        n = g.cells,
        runs = c.runs,
        t = crate::par::threads(),
    );
    let (models, ok, tubes, cut) = c.trilinear;
    let _ = writeln!(
        s,
        "\n**Trilinear topology on elements** (`mc fe --topology trilinear`, trilinear Lagrange \
         elements only): inside a cell such an element's field is exactly the trilinear \
         interpolant of the cell's corner values, so the exact cell oracle decides each cell \
         whose table entry has two or more polygons, and a cell where the interpolant has a \
         tunnel is drawn with a tube through its interior (the construction of `mc extract \
         --topology trilinear`). {models} warped 3 × 3 × 2 blocks with integer node values in \
         [−3, 3] at the isovalue 1/2, 2 cells per element: {ok} gave the same triangles and \
         tubes on both paths and a valid mesh; {tubes} of their {cut} cut cells were drawn \
         with a tube."
    );
}
