//! Decimation: the exact and fast paths remove the same nodes in the same order and write the
//! same history (on integer data, where both compute the same evaluation values); every step
//! passes the independent exact checker; undecimation through the history file gives the
//! original mesh bit for bit; undo and redo of any number of steps are inverse.

use geocert::decimate::{
    check, data, decimate, quality, BorderPolicy, Criterion, History, Options, ProjectionChoice,
    Stage, Target,
};
use geocert::mesh::Mesh;
use geocert::strategies::height_field_mesh;
use geocert::Path;
use proptest::prelude::*;

/// Options with the default loop (lazy re-evaluation, re-binned queue) when `paper` is
/// false, the paper's loop as printed when it is true.
fn options(criterion: Criterion, exclude: bool, keep: f64, k: usize) -> Options {
    loop_options(criterion, exclude, keep, k, false)
}

fn loop_options(criterion: Criterion, exclude: bool, keep: f64, k: usize, paper: bool) -> Options {
    Options::new()
        .with_criterion(criterion)
        .with_target(Target::Keep(keep))
        .with_border(if exclude {
            BorderPolicy::Exclude
        } else {
            BorderPolicy::Intact
        })
        .with_projection(ProjectionChoice::Auto)
        .with_k(k)
        .with_max_valence(64)
        .with_rebin(!paper)
        .with_lazy(!paper)
        .with_look_ahead(true)
}

fn criterion() -> impl Strategy<Value = Criterion> {
    prop_oneof![
        Just(Criterion::Angle),
        Just(Criterion::Scalar),
        Just(Criterion::Error)
    ]
}

/// Undoing `back` steps and redoing them returns to the decimated mesh; the file round trip
/// and a full undo give the original.
fn round_trip(original: &Mesh, decimated: &Mesh, history: &History, back: usize) {
    let bytes = history.to_bytes();
    let read = History::from_bytes(&bytes).expect("own history reads back");
    assert_eq!(&read, history);
    let mut stage = Stage::decimated(decimated, &read).expect("history belongs to the mesh");
    let back = back.min(read.len());
    for _ in 0..back {
        stage.undo(&read).unwrap();
    }
    for _ in 0..back {
        stage.redo(&read).unwrap();
    }
    assert_eq!(&stage.to_mesh(), decimated);
    while stage.applied > 0 {
        stage.undo(&read).unwrap();
    }
    assert_eq!(&stage.to_mesh(), original, "undecimation is exact");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn fast_path_steps_verify_and_undecimate_exactly(
        mesh in height_field_mesh(9, 6),
        criterion in criterion(),
        exclude in any::<bool>(),
        keep in 0.02f64..0.9,
        k in 1usize..20,
        back in 0usize..40,
        paper in any::<bool>(),
    ) {
        let opts = loop_options(criterion, exclude, keep, k, paper);
        let out = decimate(&mesh, &opts).unwrap();
        prop_assert_eq!(out.history.len(), out.stats.removed);
        let v = check::verify(&mesh, &out.history, true, 1).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert!(v.undecimated_exactly);
        prop_assert_eq!(v.full_checks, out.history.len() + 1);
        round_trip(&mesh, &out.mesh, &out.history, back);
        // The target is met unless the queue ran dry.
        let target = (keep * mesh.vertices.len() as f64).round() as usize;
        prop_assert!(out.stats.nodes_out >= target);
        if exclude {
            // Border nodes all stay.
            let n = mesh.vertices.len();
            prop_assert!(out.stats.nodes_out >= n.min(2 * (n / 3)).min(4));
        }
    }

    #[test]
    fn exact_and_fast_paths_agree(
        mesh in height_field_mesh(7, 5),
        criterion in prop_oneof![Just(Criterion::Angle), Just(Criterion::Scalar)],
        exclude in any::<bool>(),
        keep in 0.02f64..0.9,
        k in 1usize..20,
        paper in any::<bool>(),
    ) {
        let opts = loop_options(criterion, exclude, keep, k, paper);
        let fast = decimate(&mesh, &opts).unwrap();
        let exact = decimate(&mesh, &opts.clone().with_path(Path::Exact)).unwrap();
        prop_assert_eq!(&exact.history, &fast.history, "same removals, slots and triangles");
        prop_assert_eq!(&exact.mesh, &fast.mesh);
        prop_assert_eq!(exact.stats.blocked, fast.stats.blocked);
    }

    #[test]
    fn exact_path_error_criterion_verifies(
        mesh in height_field_mesh(6, 5),
        keep in 0.02f64..0.9,
    ) {
        let opts = options(Criterion::Error, false, keep, 4);
        let exact = decimate(&mesh, &opts.clone().with_path(Path::Exact)).unwrap();
        check::verify(&mesh, &exact.history, true, 1).map_err(|e| TestCaseError::fail(e.to_string()))?;
        round_trip(&mesh, &exact.mesh, &exact.history, 3);
    }

    #[test]
    fn closed_surfaces_in_per_fan_projection(
        level in 1u32..4,
        jitter in proptest::collection::vec(-2i32..=2, 3 * 66),
        criterion in prop_oneof![Just(Criterion::Angle), Just(Criterion::Error)],
        keep in 0.01f64..0.8,
    ) {
        let mesh = sphere(level, &jitter);
        let mut opts = options(criterion, false, keep, 3);
        opts.projection = ProjectionChoice::PerFan;
        let fast = decimate(&mesh, &opts).unwrap();
        let v = check::verify(&mesh, &fast.history, false, 1).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(v.euler, 2);
        // A closed surface cannot go below a tetrahedron.
        prop_assert!(fast.stats.nodes_out >= 4);
        blocked_accounts_for_the_nodes_left(&fast)?;
        round_trip(&mesh, &fast.mesh, &fast.history, 5);
        if criterion == Criterion::Angle && mesh.vertices.len() <= 66 {
            let exact = decimate(&mesh, &opts.clone().with_path(Path::Exact)).unwrap();
            prop_assert_eq!(&exact.history, &fast.history);
        }
    }
}

/// A run that stopped above its target accounts for every node left in
/// [`Stats::blocked`](geocert::decimate::Stats::blocked), none of them removable (the queue
/// ran dry only when no removal was valid); a run that reached it has no account.
fn blocked_accounts_for_the_nodes_left(
    out: &geocert::decimate::Outcome,
) -> Result<(), TestCaseError> {
    let s = &out.stats;
    let stopped = s.target_nodes.is_some_and(|t| s.nodes_out > t);
    match s.blocked {
        Some(b) => {
            prop_assert!(stopped, "an account without a stop: {b:?}");
            let sum =
                b.border + b.valence + b.no_plane + b.fold + b.topology + b.facing + b.removable;
            prop_assert_eq!(sum, s.nodes_out - s.unused, "{:?}", b);
            prop_assert_eq!(b.removable, 0, "{:?}", b);
        }
        None => prop_assert!(!stopped, "stopped above the target without an account"),
    }
    Ok(())
}

fn border_policy() -> impl Strategy<Value = BorderPolicy> {
    prop_oneof![
        Just(BorderPolicy::Exclude),
        Just(BorderPolicy::Intact),
        Just(BorderPolicy::Simplify),
        Just(BorderPolicy::Auto),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(40))]

    /// The quadric criterion and border simplification: both engines compute the same `f64`
    /// quadrics and landing points and take the same exact validity decisions, so they write
    /// the same history; every step verifies, the border loops stay, undo is exact.
    #[test]
    fn quadric_criterion_and_border_policies_agree(
        mesh in height_field_mesh(7, 5),
        border in border_policy(),
        per_fan in any::<bool>(),
        keep in 0.02f64..0.9,
        k in 1usize..20,
    ) {
        let mut opts = options(Criterion::Quadric, false, keep, k).with_border(border);
        if per_fan {
            opts.projection = ProjectionChoice::PerFan;
        }
        let fast = decimate(&mesh, &opts).unwrap();
        let exact = decimate(&mesh, &opts.clone().with_path(Path::Exact)).unwrap();
        prop_assert_eq!(&exact.history, &fast.history, "same removals, slots and triangles");
        prop_assert_eq!(&exact.mesh, &fast.mesh);
        prop_assert_eq!(exact.stats.blocked, fast.stats.blocked);
        let v = check::verify(&mesh, &fast.history, fast.stats.projection_xy, 1)
            .map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(v.border_loops, 1);
        blocked_accounts_for_the_nodes_left(&fast)?;
        if border == BorderPolicy::Simplify {
            prop_assert_eq!(fast.stats.border.as_str(), "simplify");
        }
        round_trip(&mesh, &fast.mesh, &fast.history, 4);
    }

    /// Closed surfaces under the quadric criterion (the default there): exact = fast, Euler
    /// characteristic 2 at every check, exact undo.
    #[test]
    fn quadric_criterion_on_closed_surfaces(
        level in 1u32..3,
        jitter in proptest::collection::vec(-2i32..=2, 3 * 66),
        keep in 0.01f64..0.8,
    ) {
        let mesh = sphere(level, &jitter);
        let opts = Options::new().with_target(Target::Keep(keep)).with_k(3);
        let fast = decimate(&mesh, &opts).unwrap();
        prop_assert_eq!(fast.stats.criterion.as_str(), "quadric");
        let v = check::verify(&mesh, &fast.history, false, 1).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(v.euler, 2);
        prop_assert_eq!(quality::deviation(&mesh, &fast.mesh).flipped, 0, "no triangle faces against the original");
        blocked_accounts_for_the_nodes_left(&fast)?;
        let exact = decimate(&mesh, &opts.clone().with_path(Path::Exact)).unwrap();
        prop_assert_eq!(&exact.history, &fast.history);
        prop_assert_eq!(exact.stats.blocked, fast.stats.blocked);
        round_trip(&mesh, &fast.mesh, &fast.history, 5);
    }
}

/// A closed surface decimated to nothing stops at a handful of nodes and says why each one
/// left cannot go: every count adds up, and on a sphere the last nodes are held by the
/// mesh's topology (a tetrahedron has no removable node) or their folds, not by a plane.
#[test]
fn a_run_that_stops_above_its_target_says_why() {
    let mesh = unit_sphere(2);
    let out = decimate(&mesh, &Options::new().with_target(Target::Nodes(0))).unwrap();
    let b = out.stats.blocked.expect("stopped above the target");
    blocked_accounts_for_the_nodes_left(&out).unwrap();
    assert!(
        out.stats.nodes_out >= 4 && out.stats.nodes_out < 12,
        "{:?}",
        out.stats
    );
    assert_eq!(
        b.topology + b.fold + b.facing + b.no_plane,
        out.stats.nodes_out,
        "{b:?}"
    );
    let exact = decimate(
        &mesh,
        &Options::new()
            .with_target(Target::Nodes(0))
            .with_path(Path::Exact),
    )
    .unwrap();
    assert_eq!(
        exact.stats.blocked,
        Some(b),
        "the exact engine gives the same account"
    );
    // An error bound reached is not a stop: no account.
    let bounded = decimate(&mesh, &Options::new().with_target(Target::ErrorBound(1e-9))).unwrap();
    assert!(bounded.stats.blocked.is_none());
    // Nor is a target reached.
    let reached = decimate(&mesh, &Options::new().with_target(Target::Keep(0.5))).unwrap();
    assert!(reached.stats.blocked.is_none());
}

/// A thin spherical shell (an outer sphere and, 2 % of the radius inside it, an inner one
/// facing inwards) decimated hard: the outer sphere's large triangles are chords that pass
/// nearer the inner sphere than the outer one, so without the facing test triangles face
/// against the original surface nearest them; with it (the default) none does, both engines
/// refuse the same removals, and the result verifies and undoes exactly — under the quadric,
/// error and angle criteria alike.
#[test]
fn a_thin_shell_keeps_every_triangle_facing_along_the_original() {
    let outer = unit_sphere(3);
    let mut mesh = outer.clone();
    let n = outer.vertices.len() as u32;
    mesh.vertices
        .extend(outer.vertices.iter().map(|p| p.map(|x| 0.98 * x)));
    mesh.triangles.extend(
        outer
            .triangles
            .iter()
            .map(|t| [t[0] + n, t[2] + n, t[1] + n]),
    );
    // Every criterion runs the test on a surface in 3-D (per-fan planes).
    for criterion in [Criterion::Quadric, Criterion::Error, Criterion::Angle] {
        let opts = Options::new()
            .with_target(Target::Keep(0.05))
            .with_k(3)
            .with_criterion(criterion);
        let unchecked = decimate(&mesh, &opts.clone().with_facing(false)).unwrap();
        let against = quality::deviation(&mesh, &unchecked.mesh).flipped;
        assert!(
            against > 0,
            "{criterion:?}: the shell must provoke flipped triangles without the test"
        );
        let fast = decimate(&mesh, &opts).unwrap();
        let d = quality::deviation(&mesh, &fast.mesh);
        assert_eq!(d.flipped, 0, "{criterion:?}");
        assert!(fast.stats.refused > unchecked.stats.refused);
        let exact = decimate(&mesh, &opts.clone().with_path(Path::Exact)).unwrap();
        assert_eq!(exact.history, fast.history, "{criterion:?}");
        check::verify(&mesh, &fast.history, false, 1).unwrap();
        round_trip(&mesh, &fast.mesh, &fast.history, 5);
        assert_eq!(exact.stats.fan_filled, fast.stats.fan_filled);
        assert_eq!(exact.stats.deferred, fast.stats.deferred);
        println!(
            "thin shell, {criterion:?}: {} triangles face against the original without the test, 0 with it ({} → {} triangles); {} removals by a fan fill, {} put off",
            against, unchecked.stats.triangles_out, fast.stats.triangles_out, fast.stats.fan_filled, fast.stats.deferred
        );
    }
}

/// Flat ellipsoids (a sphere pressed to a twentieth of its height, and one also narrowed):
/// near the rim the planned cut of a hole makes triangles whose centroids lie nearer the
/// other face, which the facing test refuses. Those removals take the cheapest fan fill
/// that passes instead, now when it files no higher than the interval the node was taken
/// from, else filed again at its value; both engines take the same fills and put off the
/// same removals, nothing faces against the original, and the history verifies and undoes
/// exactly.
#[test]
fn flat_ellipsoids_take_fan_fills_where_the_cut_would_face_against() {
    let (mut filled, mut deferred) = (0, 0);
    for (sy, sz, keep) in [(1.0, 0.05, 0.05), (0.2, 0.02, 0.03)] {
        let mut mesh = unit_sphere(4);
        for p in &mut mesh.vertices {
            p[1] *= sy;
            p[2] *= sz;
        }
        let opts = Options::new().with_target(Target::Keep(keep));
        let fast = decimate(&mesh, &opts).unwrap();
        let exact = decimate(&mesh, &opts.clone().with_path(Path::Exact)).unwrap();
        assert_eq!(exact.history, fast.history);
        assert_eq!(
            (exact.stats.fan_filled, exact.stats.deferred),
            (fast.stats.fan_filled, fast.stats.deferred)
        );
        assert_eq!(quality::deviation(&mesh, &fast.mesh).flipped, 0);
        check::verify(&mesh, &fast.history, false, 1).unwrap();
        round_trip(&mesh, &fast.mesh, &fast.history, 5);
        println!(
            "ellipsoid 1 × {sy} × {sz} at {keep}: {} removals by a fan fill, {} put off, {} refused; exact = fast",
            fast.stats.fan_filled, fast.stats.deferred, fast.stats.refused
        );
        filled += fast.stats.fan_filled;
        deferred += fast.stats.deferred;
    }
    assert!(filled > 0 && deferred > 0, "{filled} {deferred}");
}

/// A unit sphere: the octahedron subdivided `level` times, its vertices put on the sphere.
fn unit_sphere(level: u32) -> Mesh {
    let mut m = sphere(level, &[]);
    for p in &mut m.vertices {
        let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        *p = p.map(|x| x / r);
    }
    m
}

/// On a surface with a hole, simplifying the border removes border nodes that the outline
/// policy keeps, keeps the border loops, and the error it reports is the quadric's measure:
/// a removed border node's own value is its distance from the new border edge (checked on
/// the flat annulus, where the face planes contribute nothing).
#[test]
fn border_simplification_on_an_annulus() {
    // A flat annulus in the plane z = 0, not a height field in xy order (tilted 90° to the
    // xz plane so that the per-fan projection runs): 48 × 4 nodes, radii 10..16.
    let (m, rings) = (48usize, 4usize);
    let mut mesh = Mesh::default();
    for r in 0..rings {
        for i in 0..m {
            let a = std::f64::consts::TAU * i as f64 / m as f64;
            let rad = 10.0 + 2.0 * r as f64;
            mesh.vertices.push([rad * a.cos(), 0.0, rad * a.sin()]);
        }
    }
    for r in 0..rings - 1 {
        for i in 0..m {
            let (a, b) = ((r * m + i) as u32, (r * m + (i + 1) % m) as u32);
            let (c, d) = (a + m as u32, b + m as u32);
            mesh.triangles.push([a, c, b]);
            mesh.triangles.push([b, c, d]);
        }
    }
    assert_eq!(check::border_loops(&mesh), 2);
    let run = |border| {
        let opts = Options::new()
            .with_target(Target::Keep(0.1))
            .with_border(border)
            .with_k(2);
        let out = decimate(&mesh, &opts).unwrap();
        let v = check::verify(&mesh, &out.history, out.stats.projection_xy, 1).unwrap();
        assert_eq!(v.border_loops, 2);
        assert!(!out.stats.projection_xy);
        let exact = decimate(&mesh, &opts.clone().with_path(Path::Exact)).unwrap();
        assert_eq!(exact.history, out.history);
        out
    };
    let outline = run(BorderPolicy::Intact);
    let simplify = run(BorderPolicy::Simplify);
    // The outline policy keeps all 96 border nodes (none is collinear on a circle).
    assert!(
        outline.stats.nodes_out >= 2 * m,
        "{}",
        outline.stats.nodes_out
    );
    assert!(simplify.stats.nodes_out < outline.stats.nodes_out);
    assert!(simplify.stats.nodes_out <= (m * rings) / 10 + 1);
    // The distance from the original vertices to the result is bounded by the circle's
    // chord sagitta at the coarsest spacing left, not zero, and small.
    let e = geocert::decimate::quality::surface_errors(&mesh, &simplify.mesh);
    assert!(
        e.max_height > 0.0 && e.max_height < 16.0,
        "{}",
        e.max_height
    );
}

/// An octahedron subdivided `level` times, pushed to a sphere of radius 64 and rounded to
/// integers, with integer jitter: a closed genus-0 mesh.
fn sphere(level: u32, jitter: &[i32]) -> Mesh {
    let mut v: Vec<[f64; 3]> = vec![
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let mut t: Vec<[u32; 3]> = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    for _ in 0..level {
        let mut mid = std::collections::HashMap::new();
        let mut next = Vec::new();
        for tri in &t {
            let mut m = [0u32; 3];
            for e in 0..3 {
                let (a, b) = (tri[e].min(tri[(e + 1) % 3]), tri[e].max(tri[(e + 1) % 3]));
                m[e] = *mid.entry((a, b)).or_insert_with(|| {
                    let (p, q) = (v[a as usize], v[b as usize]);
                    v.push([
                        (p[0] + q[0]) / 2.0,
                        (p[1] + q[1]) / 2.0,
                        (p[2] + q[2]) / 2.0,
                    ]);
                    (v.len() - 1) as u32
                });
            }
            next.push([tri[0], m[0], m[2]]);
            next.push([m[0], tri[1], m[1]]);
            next.push([m[2], m[1], tri[2]]);
            next.push([m[0], m[1], m[2]]);
        }
        t = next;
    }
    let vertices = v
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            let j = |k: usize| jitter.get(3 * i + k).copied().unwrap_or(0) as f64;
            [
                (64.0 * p[0] / r).round() + j(0),
                (64.0 * p[1] / r).round() + j(1),
                (64.0 * p[2] / r).round() + j(2),
            ]
        })
        .collect();
    Mesh {
        normals: None,
        vertices,
        triangles: t,
        scalars: None,
    }
}

#[test]
fn bad_inputs_and_foreign_histories_are_refused() {
    use geocert::decimate::{DecimateError, HistoryError};
    // A non-manifold edge (three triangles on edge 0-1).
    let mesh = Mesh {
        normals: None,
        vertices: vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
        ],
        triangles: vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]],
        scalars: None,
    };
    for path in [Path::Fast, Path::Exact] {
        match decimate(&mesh, &Options::new().with_path(path)) {
            Err(DecimateError::Mesh(e)) => assert!(e.to_string().contains("edge (")),
            other => panic!("{path:?}: {other:?}"),
        }
    }
    // The scalar criterion without scalars.
    let grid = geocert::decimate::data::height_grid(6);
    let opts = Options::new().with_criterion(Criterion::Scalar);
    assert!(matches!(
        decimate(&grid, &opts),
        Err(DecimateError::NoScalars(_))
    ));
    // A history applied to another mesh.
    let out = decimate(&grid, &Options::default()).unwrap();
    let half = Options::new().with_target(Target::Keep(0.5));
    let other = decimate(&geocert::decimate::data::height_grid(7), &half).unwrap();
    let r = Stage::decimated(&other.mesh, &out.history);
    assert!(matches!(r, Err(HistoryError::Mismatch(_))), "{r:?}");
    let mut moved = out.mesh.clone();
    moved.vertices[0][2] += 1e-9;
    assert!(matches!(
        Stage::decimated(&moved, &out.history),
        Err(HistoryError::Mismatch(_))
    ));
    // Corrupted or truncated history files.
    let bytes = out.history.to_bytes();
    for cut in [0, 5, 20, bytes.len() / 2, bytes.len() - 1] {
        assert!(History::from_bytes(&bytes[..cut]).is_err());
    }
    let mut flipped = bytes.clone();
    let mid = flipped.len() / 2;
    flipped[mid] ^= 0x40;
    assert!(History::from_bytes(&flipped).is_err());
    let mut v3 = bytes.clone();
    v3[8] = 3;
    assert_eq!(History::from_bytes(&v3), Err(HistoryError::Version(3)));
    // A version 1 file (no fit section) still reads: the same bytes without the fit's count.
    assert!(out.history.fit.is_empty());
    let mut v1 = bytes[..bytes.len() - 12].to_vec();
    v1[8] = 1;
    let sum = geocert::decimate::history::fnv1a(&v1);
    v1.extend_from_slice(&sum.to_le_bytes());
    assert_eq!(History::from_bytes(&v1).as_ref(), Ok(&out.history));
}

/// The fit after the last removal (the default on surfaces in 3-D): it moves kept nodes,
/// lowers the RMS distance to the original, the checker confirms exactly that no triangle
/// flipped, both engines fit alike, and undecimation is still exact. A fit moved elsewhere is
/// refused by the checker (a flipped triangle) and by the stage (the mesh is not where the
/// history says).
#[test]
fn the_fit_moves_nodes_verifiably_and_undoes_exactly() {
    use geocert::decimate::{quality, Fit, HistoryError};
    let mesh = sphere(3, &[]);
    let opts = Options::new().with_target(Target::Keep(0.1)).with_k(3);
    let fitted = decimate(&mesh, &opts).unwrap();
    let plain = decimate(&mesh, &opts.clone().with_fit(Fit::Rounds(0))).unwrap();
    assert_eq!(fitted.stats.fit_rounds, Fit::DEFAULT_ROUNDS);
    assert!(plain.history.fit.is_empty());
    assert!(fitted.stats.moved > 0 && fitted.stats.moved == fitted.history.fit.len());
    let (a, b) = (
        quality::deviation(&mesh, &plain.mesh).forward_rms,
        quality::deviation(&mesh, &fitted.mesh).forward_rms,
    );
    println!(
        "sphere (level 3) at 10 %: {} nodes moved, RMS {a:.4} → {b:.4}",
        fitted.stats.moved
    );
    assert!(b < 0.8 * a, "{a} → {b}");
    let v = check::verify(&mesh, &fitted.history, false, 1).unwrap();
    assert_eq!(v.moved, fitted.stats.moved);
    assert!(v.fit_triangles_checked >= fitted.stats.moved);
    let exact = decimate(&mesh, &opts.clone().with_path(Path::Exact)).unwrap();
    assert_eq!(exact.history, fitted.history);
    round_trip(&mesh, &fitted.mesh, &fitted.history, 7);
    // Tampering: a moved node sent through the sphere flips its triangles.
    let mut bad = fitted.history.clone();
    let m = &mut bad.fit[0];
    m.to = m.to.map(|x| -3.0 * x);
    let e = check::verify(&mesh, &bad, false, 1).unwrap_err();
    assert!(e.to_string().contains("the fit flips triangle"), "{e}");
    assert!(matches!(
        Stage::decimated(&fitted.mesh, &bad),
        Err(HistoryError::Mismatch(_))
    ));
}

/// The fit on an open surface with a curved border where the surface is flat: a dome on a
/// disc of radius 1, flat beyond radius 0.6, its border a circle in the plane z = 0. Along
/// their normals the border nodes barely move out (the surface's points near them lie in the
/// plane); across the border they do, so that the border's chords straddle the circle
/// (its largest gap to the original border shrinks), the RMS distance falls, the checker
/// confirms that no triangle flipped, both engines fit alike and undecimation is exact.
#[test]
fn the_fit_straddles_a_curved_border() {
    use geocert::decimate::{quality, Fit};
    let (rings, around) = (12u32, 48u32);
    let mut mesh = Mesh::default();
    mesh.vertices.push([0.0, 0.0, 0.3]);
    for i in 1..=rings {
        let r = i as f64 / rings as f64;
        let z = 0.3 * (1.0 - (r / 0.6).powi(2)).max(0.0).powi(2);
        for j in 0..around {
            // Every other ring turned by half a step.
            let a = std::f64::consts::TAU * (j as f64 + 0.5 * (i % 2) as f64) / around as f64;
            mesh.vertices.push([r * a.cos(), r * a.sin(), z]);
        }
    }
    let at = |i: u32, j: u32| 1 + (i - 1) * around + j % around;
    for j in 0..around {
        mesh.triangles.push([0, at(1, j), at(1, j + 1)]);
    }
    for i in 1..rings {
        for j in 0..around {
            mesh.triangles
                .push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            mesh.triangles
                .push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    let on_border = mesh.border_vertices();
    assert!(on_border.iter().any(|&b| b));
    // Decimated as a surface in 3-D (a height field's default keeps its outline and fits
    // nothing).
    let opts = Options::new()
        .with_target(Target::Keep(0.1))
        .with_k(3)
        .with_projection(ProjectionChoice::PerFan);
    let fitted = decimate(&mesh, &opts).unwrap();
    let plain = decimate(&mesh, &opts.clone().with_fit(Fit::Rounds(0))).unwrap();
    // The largest distance from an original border vertex to the result's border.
    let gap = |m: &Mesh| {
        let edges = m.border_edges();
        (0..mesh.vertices.len())
            .filter(|&i| on_border[i])
            .map(|i| {
                let o = mesh.vertices[i];
                edges
                    .iter()
                    .map(|&[a, b]| {
                        let (p, q) = (m.vertices[a as usize], m.vertices[b as usize]);
                        let d: [f64; 3] = std::array::from_fn(|k| q[k] - p[k]);
                        let t = ((0..3).map(|k| (o[k] - p[k]) * d[k]).sum::<f64>()
                            / (0..3).map(|k| d[k] * d[k]).sum::<f64>())
                        .clamp(0.0, 1.0);
                        (0..3)
                            .map(|k| (o[k] - p[k] - t * d[k]).powi(2))
                            .sum::<f64>()
                            .sqrt()
                    })
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    };
    let (g0, g1) = (gap(&plain.mesh), gap(&fitted.mesh));
    let (a, b) = (
        quality::deviation(&mesh, &plain.mesh).forward_rms,
        quality::deviation(&mesh, &fitted.mesh).forward_rms,
    );
    // Border nodes that moved out of the circle.
    let out = fitted
        .history
        .fit
        .iter()
        .filter(|m| on_border[m.node as usize] && m.to[0].hypot(m.to[1]) > 1.0)
        .count();

    println!(
        "dome on a disc at 10 %: {} nodes moved ({out} border nodes out), border gap {g0:.4} → \
         {g1:.4}, RMS {a:.4} → {b:.4}",
        fitted.stats.moved
    );
    assert!(out > 0);
    assert!(g1 < 0.8 * g0, "{g0} → {g1}");
    assert!(b < a, "{a} → {b}");
    let v = check::verify(&mesh, &fitted.history, false, 1).unwrap();
    assert_eq!(v.moved, fitted.stats.moved);
    assert_eq!(v.border_loops, 1);
    let exact = decimate(&mesh, &opts.clone().with_path(Path::Exact)).unwrap();
    assert_eq!(exact.history, fitted.history);
    round_trip(&mesh, &fitted.mesh, &fitted.history, 7);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    /// Ear cutting of star-shaped holes (a fan's ring around its removed node) with many
    /// reflex and straight angles, and the same cut after the quadric criterion's diagonal
    /// flips towards the fan: every triangle is positive, no polygon vertex lies in a closed
    /// triangle except at its corners, and the areas sum to the polygon's; the flipped cut
    /// in ear order packs and unpacks to itself.
    #[test]
    fn ear_cutting_tiles_star_shaped_holes(
        radii in proptest::collection::vec(1i32..=12, 3..24),
        offsets in proptest::collection::vec(0i32..=2, 24),
        heights in proptest::collection::vec(-8i32..=8, 25),
    ) {
        use geocert::internals::earcut::{
            ear_order, orient2d, pack_cut, unpack_cut, EarCutter, RobustOrient,
        };
        use std::cmp::Ordering;
        let l = radii.len();
        // Points on rays at increasing angles (lattice directions around a 16-gon), scaled.
        let dirs: [(i32, i32); 16] = [
            (4, 0), (4, 2), (4, 4), (2, 4), (0, 4), (-2, 4), (-4, 4), (-4, 2),
            (-4, 0), (-4, -2), (-4, -4), (-2, -4), (0, -4), (2, -4), (4, -4), (4, -2),
        ];
        // Pick l increasing directions among the 16 (l ≤ 16 here; longer rings reuse
        // in-between points at half radius on the same rays).
        let l = l.min(16);
        let mut idx: Vec<usize> = (0..16).collect();
        idx.retain(|i| offsets[*i] != 0 || (*i * l) % 16 < l);
        idx.truncate(l.max(3));
        prop_assume!(idx.len() >= 3);
        let pts: Vec<[f64; 2]> = idx
            .iter()
            .zip(&radii)
            .map(|(&i, &r)| [(dirs[i].0 * r) as f64, (dirs[i].1 * r) as f64])
            .collect();
        // The star around the origin must turn left at every fan triangle.
        let n = pts.len();
        prop_assume!((0..n).all(|i| orient2d([0.0, 0.0], pts[i], pts[(i + 1) % n]) == Ordering::Greater));
        let mut cut = Vec::new();
        prop_assert!(EarCutter::default().cut(&pts, &RobustOrient(&pts), &mut cut));
        prop_assert_eq!(cut.len(), n - 2);
        // The quadric criterion's flips towards the fan (the node at the origin, heights from
        // the strategy) keep a valid cut; back in ear order it packs to itself.
        let ring3: Vec<[f64; 3]> = pts.iter().zip(&heights).map(|(q, &h)| [q[0], q[1], h as f64]).collect();
        let node = [0.0, 0.0, heights[24] as f64];
        let mut flipped = cut.clone();
        let f = geocert::decimate::flip_toward_fan(node, [0.0, 0.0], &ring3, &pts, &mut flipped, 2, false, &RobustOrient(&pts));
        prop_assert_eq!(f.crossing, geocert::decimate::crossing_deviation(node, [0.0, 0.0], &ring3, &pts, &flipped, 2, false));
        prop_assert!(f.flipped || flipped == cut);
        prop_assert!(ear_order(n, &mut flipped));
        if n <= 16 {
            let mut back = Vec::new();
            unpack_cut(pack_cut(n, &flipped).unwrap(), &mut back);
            prop_assert_eq!(&back, &flipped);
        }
        let area = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        let polygon: f64 = (0..n).map(|i| area([0.0, 0.0], pts[i], pts[(i + 1) % n])).sum();
        for out in [&cut, &flipped] {
        let mut total = 0.0;
        for t in out {
            let [a, b, c] = t.map(|p| pts[p as usize]);
            prop_assert!(area(a, b, c) > 0.0);
            total += area(a, b, c);
            for (k, &q) in pts.iter().enumerate() {
                if t.contains(&(k as u8)) {
                    continue;
                }
                prop_assert!(
                    area(a, b, q) < 0.0 || area(b, c, q) < 0.0 || area(c, a, q) < 0.0,
                    "vertex {} in triangle {:?}", k, t
                );
            }
        }
        prop_assert_eq!(total, polygon);
        }
    }
}

#[test]
fn high_valence_fans_agree_and_verify() {
    for spokes in [9, 70, 120] {
        let mesh = data::wheel(spokes);
        for paper in [false, true] {
            let opts = loop_options(Criterion::Scalar, false, 0.05, 3, paper).with_max_valence(255);
            let fast = decimate(&mesh, &opts).unwrap();
            let exact = decimate(&mesh, &opts.clone().with_path(Path::Exact)).unwrap();
            assert_eq!(exact.history, fast.history, "{spokes} spokes");
            assert_eq!(exact.mesh, fast.mesh);
            let largest = (0..fast.history.len())
                .map(|s| fast.history.step(s).ring.len())
                .max()
                .unwrap_or(0);
            assert!(
                largest > 64 || spokes < 64,
                "{spokes} spokes: a hole of more than 64 nodes was cut"
            );
            check::verify(&mesh, &fast.history, true, 1).unwrap();
            round_trip(&mesh, &fast.mesh, &fast.history, 5);
            println!(
                "wheel of {spokes} spokes: {} removals (largest hole {largest} nodes), exact = fast, verified",
                fast.history.len()
            );
        }
    }
}

/// A small sphere far from the origin (radius 0.01 at georeferenced coordinates) decimates as
/// well as the same sphere at the origin: the engine runs in coordinates translated exactly
/// to near the mesh, so its `f64` error values keep their bits. Without that, the far sphere
/// came out about 7 times farther from its original (Hausdorff 4.4e-3 against 6.3e-4). The history is in the original frame:
/// both engines agree, the checker passes, undecimation is bit for bit.
#[test]
fn a_mesh_far_from_the_origin_decimates_as_at_the_origin() {
    let near = unit_sphere(4);
    let radius = 0.01;
    let place = [5e5, 4.2e6, 120.0];
    let at = |offset: [f64; 3]| Mesh {
        vertices: near
            .vertices
            .iter()
            .map(|p| std::array::from_fn(|k| radius * p[k] + offset[k]))
            .collect(),
        ..near.clone()
    };
    let (home, far) = (at([0.0; 3]), at(place));
    let opts = Options::new().with_target(Target::Keep(0.05)).with_k(3);
    let [h, f] = [&home, &far].map(|m| {
        let out = decimate(m, &opts).unwrap();
        let d = quality::deviation(m, &out.mesh);
        (out, d)
    });
    let (hd, fd) = (&h.1, &f.1);
    println!(
        "radius {radius} sphere at 5 %: at the origin Hausdorff {:.3e}, RMS {:.3e}; at {place:?} {:.3e}, {:.3e}; {} nodes moved by the fit",
        hd.hausdorff, hd.forward_rms, fd.hausdorff, fd.forward_rms, f.0.stats.moved
    );
    assert!(fd.hausdorff < 1.5 * hd.hausdorff && fd.forward_rms < 1.5 * hd.forward_rms);
    assert_eq!(fd.flipped, 0);
    assert!(
        f.0.stats.moved > 0,
        "the fit's moves come back to the original frame"
    );
    let exact = decimate(&far, &opts.clone().with_path(Path::Exact)).unwrap();
    assert_eq!(exact.history, f.0.history);
    check::verify(&far, &f.0.history, false, 1).unwrap();
    round_trip(&far, &f.0.mesh, &f.0.history, 7);
}

/// A surface in other units decimates alike: the quadric criterion's values are lengths, and
/// the queue measures them in diagonals of the input, so a mesh scaled by a power of two
/// (exact in `f64`) gives the same removals, the same triangles and the result scaled by
/// the same factor. Before, eq. (2)'s law saw values 2¹⁰ times larger as another
/// distribution: the pymeshlab cow in millimetres came out at 4× the RMS error in
/// diagonals it had in metres.
#[test]
fn a_surface_in_other_units_decimates_alike() {
    let jitter: Vec<i32> = (0..3 * 258).map(|i: i32| i * 7 % 5 - 2).collect();
    let base = sphere(3, &jitter);
    let scaled = |s: f64| Mesh {
        vertices: base.vertices.iter().map(|p| p.map(|x| x * s)).collect(),
        ..base.clone()
    };
    let opts = Options::new().with_target(Target::Keep(0.1));
    let one = decimate(&base, &opts).unwrap();
    let nodes = |h: &History| (0..h.len()).map(|s| h.step(s).node).collect::<Vec<_>>();
    let mut compared = 0;
    for s in [1.0 / 1024.0, 1024.0, 1048576.0] {
        let mesh = scaled(s);
        let out = decimate(&mesh, &opts).unwrap();
        assert_eq!(nodes(&out.history), nodes(&one.history), "scale {s}");
        assert_eq!(out.mesh.triangles, one.mesh.triangles, "scale {s}");
        let expect: Vec<[f64; 3]> = one.mesh.vertices.iter().map(|p| p.map(|x| x * s)).collect();
        assert_eq!(out.mesh.vertices, expect, "scale {s}");
        check::verify(&mesh, &out.history, false, 1).unwrap();
        compared += 1;
    }
    println!(
        "a {}-node sphere at 10 % and scaled by 2^-10, 2^10 and 2^20: {} removals, {} fitted nodes, the same in all {compared}",
        base.vertices.len(),
        one.history.len(),
        one.stats.moved
    );
    assert!(one.stats.moved > 0 && one.history.len() > 200);
}

/// Vertices no triangle uses (loose points, as OBJ and PLY files from modelling tools carry)
/// are carried through unchanged: the targets count the surface's nodes only, and neither
/// the fit nor the surface measures see them.
#[test]
fn loose_vertices_are_carried_through_and_not_counted() {
    let sphere = unit_sphere(4);
    let n = sphere.vertices.len();
    let loose: Vec<[f64; 3]> = (0..3 * n).map(|i| [10.0 + i as f64, -7.0, 3.0]).collect();
    let mut with_loose = sphere.clone();
    with_loose.vertices.extend(&loose);
    let opts = Options::new().with_target(Target::Keep(0.1)).with_k(3);
    let alone = decimate(&sphere, &opts).unwrap();
    let out = decimate(&with_loose, &opts).unwrap();
    let s = &out.stats;
    assert_eq!(s.unused, loose.len());
    assert_eq!(s.nodes_out - s.unused, (0.1 * n as f64).round() as usize);
    assert_eq!(alone.stats.nodes_out, s.nodes_out - s.unused);
    // Carried through at their places, after the surface's nodes.
    assert_eq!(&out.mesh.vertices[s.nodes_out - loose.len()..], &loose[..]);
    let (d, d_alone) = (
        quality::deviation(&with_loose, &out.mesh),
        quality::deviation(&sphere, &alone.mesh),
    );
    println!(
        "{} loose vertices: {} → {} nodes ({} of the surface); Hausdorff {:.3e} (the sphere alone {:.3e}), {} nodes fitted",
        loose.len(),
        s.nodes_in,
        s.nodes_out,
        s.nodes_out - s.unused,
        d.hausdorff,
        d_alone.hausdorff,
        s.moved
    );
    // A loose point counted would stand ≥ 9 away from the unit sphere.
    assert!(d.hausdorff < 2.0 * d_alone.hausdorff, "{d:?}");
    assert!((d.diagonal - d_alone.diagonal).abs() < 1e-12 * d.diagonal);
    assert_eq!(d.flipped, 0);
    assert!(s.moved > 0);
    let exact = decimate(&with_loose, &opts.clone().with_path(Path::Exact)).unwrap();
    assert_eq!(exact.history, out.history);
    check::verify(&with_loose, &out.history, false, 1).unwrap();
    round_trip(&with_loose, &out.mesh, &out.history, 5);
}
