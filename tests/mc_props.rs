//! Marching cubes on grids: the exact and fast paths give the same triangle index structure
//! and vertices equal to rounding; surfaces away from the grid boundary are closed, oriented
//! 2-manifolds.

use geocert::mc::grid::{extract_exact, extract_fast, Volume};
use geocert::num::{rational_from_f64, rational_to_f64, Rational};
use proptest::prelude::*;

fn grid(dims: [usize; 3], vals: &[i8], pad: bool) -> Vec<f64> {
    let n = dims[0] * dims[1] * dims[2];
    (0..n)
        .map(|idx| {
            let (i, j, k) = (
                idx % dims[0],
                (idx / dims[0]) % dims[1],
                idx / (dims[0] * dims[1]),
            );
            let edge = i == 0
                || j == 0
                || k == 0
                || i + 1 == dims[0]
                || j + 1 == dims[1]
                || k + 1 == dims[2];
            if pad && edge {
                -3.0
            } else {
                vals[idx % vals.len()] as f64
            }
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn exact_and_fast_agree(
        dims in prop::array::uniform3(2usize..7),
        vals in proptest::collection::vec(-4i8..5, 1..64),
        iso_num in -8i32..8,
    ) {
        // Integer values against isovalues on a quarter grid: ties (value = isovalue) and face
        // ties (saddle = isovalue) both occur.
        let iso = iso_num as f64 / 4.0;
        let v = grid(dims, &vals, false);
        let (fast, fstats) = extract_fast(&Volume::new(dims, v.clone()).unwrap(), iso).unwrap();
        let exact_vol = Volume::new(dims, v.iter().map(|x| rational_from_f64(*x, "v").unwrap()).collect()).unwrap();
        let exact = extract_exact(&exact_vol, &rational_from_f64(iso, "iso").unwrap());
        prop_assert_eq!(&fast.triangles, &exact.triangles);
        prop_assert_eq!(fstats.ambiguous_faces, exact.stats.ambiguous_faces);
        prop_assert_eq!(fstats.cells, exact.stats.cells);
        for (f, e) in fast.vertices.iter().zip(&exact.vertices) {
            for a in 0..3 {
                prop_assert!((f[a] - rational_to_f64(&e[a])).abs() <= 1e-12);
            }
        }
    }

    #[test]
    fn interior_surfaces_are_closed_oriented_manifolds(
        dims in prop::array::uniform3(3usize..8),
        vals in proptest::collection::vec(-4i8..5, 1..97),
    ) {
        // Isovalue ½ never equals an integer value: no vertex at a corner.
        let v = grid(dims, &vals, true);
        let (mesh, _) = extract_fast(&Volume::new(dims, v).unwrap(), 0.5).unwrap();
        mesh.validate().unwrap();
        let boundary = mesh.check_manifold();
        prop_assert_eq!(boundary, Ok(0));
        prop_assert_eq!(mesh.euler_characteristic() % 2, 0);
    }
}

#[test]
fn sphere_is_a_closed_genus_zero_surface() {
    let n = 24;
    let c = (n - 1) as f64 / 2.0;
    let vals: Vec<f64> = (0..n * n * n)
        .map(|idx| {
            let (i, j, k) = (idx % n, (idx / n) % n, idx / (n * n));
            let d = |x: usize| x as f64 - c;
            (d(i).powi(2) + d(j).powi(2) + d(k).powi(2)).sqrt()
        })
        .collect();
    // Inside (distance below 8) negative: positive region outside, normals point outward.
    let (mesh, stats) = extract_fast(&Volume::new([n, n, n], vals).unwrap(), 8.0).unwrap();
    assert_eq!(mesh.check_manifold(), Ok(0));
    assert_eq!(mesh.euler_characteristic(), 2);
    assert_eq!(stats.cells, (n - 1).pow(3));
    // Signed volume (divergence theorem) of the outward-wound surface ≈ 4/3 π 8³.
    let vol: f64 = mesh
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
            (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]))
                / 6.0
        })
        .sum();
    let expect = 4.0 / 3.0 * std::f64::consts::PI * 512.0;
    assert!(
        (vol.abs() - expect).abs() / expect < 0.03,
        "volume {vol} vs {expect}"
    );
    let _ = Rational::default();
}
