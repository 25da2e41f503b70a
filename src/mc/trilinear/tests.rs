use super::sweep::sweep_groups;
use super::*;
use crate::mc::decider::decide_shifted;

fn lcg(state: &mut u64) -> u64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    *state >> 33
}

fn q(v: i64) -> Rational {
    Rational::from_integer(v.into())
}

#[test]
fn a_body_diagonal_tube() {
    // Corners 0 and 6 strongly positive, the rest weakly negative: a tube joins them.
    let mut v = [-1i64; 8];
    v[0] = 8;
    v[6] = 8;
    let t = topology_of_small(&v).unwrap();
    assert_eq!(t.config, 0b0100_0001);
    assert_eq!(
        t.groups[0][0], t.groups[0][6],
        "joined through the interior"
    );
    assert_eq!(t.components.len(), 1);
    assert_eq!(t.tunnels(), 1);
    assert_eq!(t.euler_characteristic(), 0, "an annulus");
    assert!(!t.matches_table());
    let values = v.map(q);
    verify_cell(&values, &q(0), &t).unwrap();
    // Weakly positive corners stay apart: two discs, as the table draws them.
    let mut w = [-8i64; 8];
    w[0] = 1;
    w[6] = 1;
    let t = topology_of_small(&w).unwrap();
    assert_eq!(t.components.len(), 2);
    assert!(t.matches_table());
    assert_eq!(t.euler_characteristic(), 2);
}

#[test]
fn oracle_agrees_with_the_sweep_and_the_fast_path_on_random_cells() {
    let mut s = 7u64;
    let mut checked = 0;
    for round in 0..20_000 {
        let m = [3, 9, 40, 1000][round % 4];
        let v: [i64; 8] = std::array::from_fn(|_| (lcg(&mut s) % (2 * m + 1)) as i64 - m as i64);
        let t = topology_of_small(&v).unwrap();
        for axis in 0..3 {
            assert_eq!(
                sweep_groups(&v, axis).unwrap(),
                t.groups,
                "values {v:?} axis {axis}"
            );
        }
        // The face decisions are the table's tie rule.
        for (bit, &f) in crate::mc::table::ambiguous_faces(t.config)
            .iter()
            .enumerate()
        {
            let c = crate::mc::table::FACES[f as usize]
                .corners
                .map(|x| v[x as usize]);
            let joined = decide_shifted(&c[0], &c[1], &c[3], &c[2]);
            assert_eq!(t.sub >> bit & 1 == 1, joined, "values {v:?} face {f}");
        }
        let f = v.map(|x| x as f64);
        if let Some(fast) = cell_topology_fast(&f, 0.0) {
            assert_eq!(fast, t, "values {v:?}");
            checked += 1;
        }
        if round % 50 == 0 {
            verify_cell(&v.map(q), &q(0), &t).unwrap();
        }
    }
    assert!(checked > 10_000, "the fast path decided {checked}");
}

#[test]
fn big_values_take_the_bigint_route() {
    let v: [i64; 8] = [1 << 40, -(1 << 41), 3, -5, -7, 11 << 35, -13, 1 << 45];
    let g = v.map(BigInt::from);
    let big = topology_of_integers(&g);
    let small = topology_of_small(&v.map(|x| x.signum() * (x.abs() >> 30).max(1)));
    assert!(small.is_some());
    verify_cell(&v.map(q), &q(0), &big).unwrap();
}

#[test]
fn the_checker_rejects_wrong_claims() {
    let mut v = [-1i64; 8];
    v[0] = 8;
    v[6] = 8;
    let values = v.map(q);
    let t = topology_of_small(&v).unwrap();
    let mut wrong = t.clone();
    wrong.groups[0][6] = 6;
    assert!(verify_cell(&values, &q(0), &wrong).is_err());
    let mut wrong = t.clone();
    wrong
        .joins
        .retain(|j| !matches!(j.kind, JoinKind::Diagonal(_)));
    assert!(matches!(
        verify_cell(&values, &q(0), &wrong),
        Err(CellCheckError::Groups { .. })
    ));
    let mut wrong = t.clone();
    if let Some(j) = wrong
        .joins
        .iter_mut()
        .find(|j| matches!(j.kind, JoinKind::Diagonal(_)))
    {
        j.witness.at = WitnessPoint::Mark(Mark::Zero);
        j.witness.lo = Mark::Zero;
    }
    assert!(verify_cell(&values, &q(0), &wrong).is_err());
    let mut wrong = t;
    wrong.components[0].cycles.pop();
    assert!(verify_cell(&values, &q(0), &wrong).is_err());
}

#[test]
fn ties_follow_the_table() {
    // f = z at iso 1/2 (shifted by 2: g = 2z − 1): one flat disc; every slice across z in the
    // middle is level.
    let g = [-1i64, -1, -1, -1, 1, 1, 1, 1];
    let t = topology_of_small(&g).unwrap();
    assert_eq!(t.components.len(), 1);
    assert_eq!(t.euler_characteristic(), 1);
    // Corner values equal to the isovalue count positive.
    let t = topology_of_small(&[0, -1, -1, -1, -1, -1, -1, -1]).unwrap();
    assert_eq!(t.config, 1);
    assert_eq!(t.components.len(), 1);
    // A face saddle on the level joins the positive corners (1·1 = 1·1 on face z = 0).
    let t = topology_of_small(&[1, -1, 1, -1, 5, 5, 5, 5]).unwrap();
    assert_eq!(t.sub & 1, 1);
}

fn field(n: usize, f: impl Fn([f64; 3]) -> f64) -> crate::mc::grid::Volume<f64> {
    let values = (0..n * n * n)
        .map(|i| f([i % n, i / n % n, i / (n * n)].map(|c| c as f64)))
        .collect();
    crate::mc::grid::Volume::new([n, n, n], values).unwrap()
}

#[test]
fn volumes_have_the_topology_of_their_shapes() {
    use crate::mc::grid::{extract, ExtractOptions};
    let c = 7.5;
    let sphere = field(16, |p| {
        p.iter().map(|x| (x - c) * (x - c)).sum::<f64>() - 30.0
    });
    let torus = field(20, |[x, y, z]| {
        let (x, y, z) = (x - 9.5, y - 9.5, z - 9.5);
        let r = (x * x + y * y).sqrt() - 6.0;
        r * r + z * z - 4.0
    });
    let two = field(18, |[x, y, z]| {
        let a = (x - 4.5).powi(2) + (y - 8.5).powi(2) + (z - 8.5).powi(2) - 9.0;
        let b = (x - 12.5).powi(2) + (y - 8.5).powi(2) + (z - 8.5).powi(2) - 9.0;
        a.min(b)
    });
    // A plane through the box: one disc reaching the boundary.
    let plane = field(8, |[x, y, z]| x + 2.0 * y - z - 3.3);
    for (vol, chi, comps, closed) in [
        (&sphere, 2, 1, true),
        (&torus, 0, 1, true),
        (&two, 4, 2, true),
        (&plane, 1, 1, false),
    ] {
        let t = volume_topology(vol, 0.0).unwrap();
        assert_eq!(t.euler_characteristic, chi, "{t:?}");
        assert_eq!(t.components.len(), comps);
        assert!(t.components.iter().all(|c| c.closed == closed));
        assert_eq!(t.tunnel_cells, 0);
        // The table draws the same surface here: its mesh has the same characteristic.
        let iso = Rational::from_integer(0.into());
        let (mesh, _) = extract(vol, &iso, &ExtractOptions::new()).unwrap();
        assert_eq!(mesh.euler_characteristic(), chi);
    }
}

#[test]
fn fast_and_exact_volume_topologies_agree_on_noise() {
    let mut s = 3u64;
    for round in 0..20 {
        let n = 5 + round % 4;
        let values: Vec<f64> = (0..n * n * n)
            .map(|_| (lcg(&mut s) % 9) as f64 - 4.0)
            .collect();
        let vol = crate::mc::grid::Volume::new([n, n, n], values.clone()).unwrap();
        let exact =
            crate::mc::grid::Volume::new([n, n, n], values.iter().map(|&v| q(v as i64)).collect())
                .unwrap();
        let iso = if round % 2 == 0 { 0.0 } else { 0.5 };
        let iso_q = crate::num::rational_from_f64(iso, "iso").unwrap();
        let a = volume_topology(&vol, iso).unwrap();
        let b = volume_topology_exact(&exact, &iso_q);
        assert_eq!(a.euler_characteristic, b.euler_characteristic);
        assert_eq!(a.components, b.components);
        assert_eq!(a.tunnel_cells, b.tunnel_cells);
        if iso == 0.0 {
            assert!(
                a.exact_fallbacks > 0,
                "corners on the level need the exact path"
            );
        }
        // With no tunnel the table's mesh has the trilinear surface's characteristic.
        if a.tunnel_cells == 0 {
            let (mesh, _) =
                crate::mc::grid::extract(&vol, &iso_q, &crate::mc::grid::ExtractOptions::new())
                    .unwrap();
            assert_eq!(mesh.euler_characteristic(), a.euler_characteristic);
        }
    }
}

#[test]
fn trilinear_extraction_has_the_trilinear_topology() {
    use super::polygonise::{extract_trilinear, extract_trilinear_exact};
    use crate::mc::verify::{verify_mesh, VerifyOptions};
    let mut s = 21u64;
    let mut tunnels = 0;
    for round in 0..12 {
        let n = 5 + round % 5;
        let values: Vec<f64> = (0..n * n * n)
            .map(|_| (lcg(&mut s) % 2001) as f64 / 1000.0 - 1.0)
            .collect();
        let vol = crate::mc::grid::Volume::new([n, n, n], values.clone()).unwrap();
        let iso = 0.0625;
        let (mesh, stats) = extract_trilinear(&vol, iso).unwrap();
        tunnels += stats.tunnel_cells;
        mesh.validate().unwrap();
        let v = verify_mesh(&vol, iso, &mesh, &VerifyOptions::default()).unwrap();
        assert!(v.agrees(), "{v:?}");
        assert_eq!(mesh.euler_characteristic(), v.truth_euler_characteristic);
        // The exact path gives the same triangles and (rounded) the same vertices.
        let q = |x: f64| crate::num::rational_from_f64(x, "v").unwrap();
        let exact_vol =
            crate::mc::grid::Volume::new([n, n, n], values.iter().map(|&x| q(x)).collect())
                .unwrap();
        let (ev, et, es) = extract_trilinear_exact(&exact_vol, &q(iso)).unwrap();
        assert_eq!(
            (es.cells, es.tunnel_cells),
            (stats.cells, stats.tunnel_cells)
        );
        assert_eq!(et, mesh.triangles);
        for (a, b) in ev.iter().zip(&mesh.vertices) {
            for i in 0..3 {
                assert!((crate::num::rational_to_f64(&a[i]) - b[i]).abs() < 1e-12);
            }
        }
    }
    assert!(tunnels > 0, "noise has tunnels");
}

#[test]
fn values_at_the_i128_limit_match_bigint() {
    // The largest magnitudes the i128 route takes, with peaks inside the pattern intervals.
    let mut s = 99u64;
    let m = (1i64 << 19) - 1;
    for _ in 0..2000 {
        let v: [i64; 8] = std::array::from_fn(|_| {
            let r = (lcg(&mut s) % 2001) as i64 - 1000;
            r * m / 1000
        });
        let small = topology_of_small(&v).unwrap();
        let big = topology_of(&eps_values(&v.map(BigInt::from))).unwrap();
        assert_eq!(small, big, "{v:?}");
    }
    assert!(topology_of_small(&[1 << 19, 0, 0, 0, 0, 0, 0, 0]).is_none());
}
