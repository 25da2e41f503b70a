//! Finite-element polygonisation: exact against fast, against the regular-grid extractor, on
//! closed surfaces, degenerate elements (Figure 7) and the heart demo.

use geocert::mc::fe::heart::{left_ventricle, paper_options};
use geocert::mc::fe::models::block;
use geocert::mc::fe::polygonise_exact;
use geocert::mc::fe::polygonise_fast;
use geocert::mc::fe::{ElementKind, FeError, FeModel, FeOptions, NormalSource};
use geocert::mc::grid::{extract_exact, Volume};
use geocert::mesh::area_vector;
use geocert::num::{rational_from_f64, rational_to_f64, Rational};
use proptest::prelude::*;
use std::collections::BTreeSet;

fn no_derivative(_: [f64; 3], _: [bool; 3]) -> f64 {
    0.0
}

fn identity(p: [f64; 3]) -> [f64; 3] {
    p
}

fn opts(n: usize) -> FeOptions {
    FeOptions::new().with_cells([n; 3])
}

/// Asserts exact and fast agree on structure, and on positions to rounding.
fn assert_paths_agree(m: &FeModel<f64>, iso: f64, o: &FeOptions) -> geocert::mesh::Mesh {
    let exact = polygonise_exact(
        &m.to_exact().unwrap(),
        &rational_from_f64(iso, "iso").unwrap(),
        o,
    )
    .unwrap();
    let fast = polygonise_fast(m, iso, o).unwrap();
    assert_eq!(fast.mesh.triangles, exact.triangles, "triangle structure");
    assert_eq!(fast.mesh.vertices.len(), exact.vertices.len());
    let scale = m
        .coordinates
        .iter()
        .flat_map(|c| c.iter())
        .fold(1.0f64, |a, x| a.max(x.abs()));
    for (f, e) in fast.mesh.vertices.iter().zip(&exact.vertices) {
        for a in 0..3 {
            let d = (f[a] - rational_to_f64(&e[a])).abs();
            assert!(d <= 1e-9 * scale, "position off by {d}");
        }
    }
    let (mut s_exact, mut s_fast) = (exact.stats, fast.stats);
    // The fast path counts its exact fallbacks; the rest must match.
    s_fast.exact_values = 0;
    s_fast.exact_faces = 0;
    s_exact.exact_values = 0;
    s_exact.exact_faces = 0;
    assert_eq!(s_fast, s_exact);
    fast.mesh.validate().unwrap();
    fast.mesh
}

/// Triangles as sets of rotated position triples (independent of vertex numbering).
fn triangle_set(vertices: &[[Rational; 3]], tris: &[[u32; 3]]) -> BTreeSet<Vec<[Rational; 3]>> {
    tris.iter()
        .map(|t| {
            let p: Vec<[Rational; 3]> = t.iter().map(|&v| vertices[v as usize].clone()).collect();
            let r = (0..3).min_by_key(|&i| p[i].clone()).unwrap();
            (0..3).map(|k| p[(r + k) % 3].clone()).collect()
        })
        .collect()
}

fn small_values() -> impl Strategy<Value = ([usize; 3], Vec<i8>)> {
    (1usize..=3, 1usize..=3, 1usize..=2).prop_flat_map(|(x, y, z)| {
        let n = (x + 1) * (y + 1) * (z + 1);
        (Just([x, y, z]), proptest::collection::vec(-3i8..=3, n))
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(40))]

    /// Trilinear unit elements with one cell each are the regular grid: the same mesh,
    /// vertex for vertex, as the grid extractor (values avoid the isovalue, so nothing
    /// coincides).
    #[test]
    fn one_cell_trilinear_elements_are_the_grid((e, vals) in small_values()) {
        let idx = |p: [f64; 3]| p[0] as usize + (e[0] + 1) * (p[1] as usize + (e[1] + 1) * p[2] as usize);
        let value = |p: [f64; 3]| vals[idx(p)] as f64;
        let m = block(ElementKind::TRILINEAR_LAGRANGE, e, &value, &no_derivative, &identity);
        let fe = polygonise_exact(&m.to_exact().unwrap(), &Rational::new(1.into(), 2.into()), &opts(1)).unwrap();
        let vol = Volume::new([e[0] + 1, e[1] + 1, e[2] + 1], vals.iter().map(|&v| Rational::from_integer(v.into())).collect()).unwrap();
        let grid = extract_exact(&vol, &Rational::new(1.into(), 2.into()));
        prop_assert_eq!(&fe.vertices, &grid.vertices);
        prop_assert_eq!(&fe.triangles, &grid.triangles);
        prop_assert_eq!(fe.stats.welded_vertices, 0);
    }

    /// Two cells per element on trilinear elements give the grid extractor's surface on the
    /// trilinearly refined grid (as triangle sets: the numbering differs).
    #[test]
    fn refined_trilinear_elements_match_the_refined_grid((e, vals) in small_values()) {
        let idx = |p: [usize; 3]| p[0] + (e[0] + 1) * (p[1] + (e[1] + 1) * p[2]);
        let value = |p: [f64; 3]| vals[idx(p.map(|x| x as usize))] as f64 * 4.0 + 1.0;
        let m = block(ElementKind::TRILINEAR_LAGRANGE, e, &value, &no_derivative, &identity);
        let iso = Rational::from_integer(0.into());
        let fe = polygonise_exact(&m.to_exact().unwrap(), &iso, &opts(2)).unwrap();
        // The refined grid: trilinear interpolation at half steps (world = grid / 2).
        let d = [2 * e[0] + 1, 2 * e[1] + 1, 2 * e[2] + 1];
        let mut fine = Vec::new();
        for k in 0..d[2] { for j in 0..d[1] { for i in 0..d[0] {
            let mut s = 0.0;
            let (lo, hi) = ([i / 2, j / 2, k / 2], [i.div_ceil(2), j.div_ceil(2), k.div_ceil(2)]);
            let mut count = 0.0;
            for c in 0..8usize {
                let p = [if c & 1 == 0 { lo[0] } else { hi[0] }, if c & 2 == 0 { lo[1] } else { hi[1] }, if c & 4 == 0 { lo[2] } else { hi[2] }];
                s += value(p.map(|x| x as f64));
                count += 1.0;
            }
            fine.push(rational_from_f64(s / count, "v").unwrap());
        }}}
        let grid = extract_exact(&Volume::new(d, fine).unwrap(), &iso);
        let half = Rational::new(1.into(), 2.into());
        let scaled: Vec<[Rational; 3]> = grid.vertices.iter().map(|v| v.clone().map(|x| x * &half)).collect();
        // Coincident cut points (a value at the isovalue) are welded by the FE path only.
        prop_assume!(fe.stats.welded_vertices == 0);
        prop_assert_eq!(triangle_set(&fe.vertices, &fe.triangles), triangle_set(&scaled, &grid.triangles));
    }

    /// `CellRule::Trilinear` on warped trilinear blocks: both paths draw the same tubes and
    /// the same triangles (integer values: ambiguous faces and tunnels are common).
    #[test]
    fn trilinear_topology_paths_agree((e, vals) in small_values(), n in 1usize..=2) {
        let idx = |p: [f64; 3]| p[0] as usize + (e[0] + 1) * (p[1] as usize + (e[1] + 1) * p[2] as usize);
        let value = |p: [f64; 3]| vals[idx(p)] as f64;
        let warp = |p: [f64; 3]| [p[0] + 0.1 * p[1] * p[2], p[1] - 0.05 * p[0] * p[0], p[2] + 0.1 * p[0] * p[1]];
        let m = block(ElementKind::TRILINEAR_LAGRANGE, e, &value, &no_derivative, &warp);
        assert_paths_agree(&m, 0.5, &opts(n).with_topology(geocert::mc::fe::CellRule::Trilinear));
    }

    /// Random Hermite and warped Lagrange models (the exported strategy): the fast path's
    /// structure is the exact one.
    #[test]
    fn exact_and_fast_agree((m, iso) in geocert::strategies::fe_block_model(), n in 1usize..=3) {
        let o = FeOptions::new().with_cells([n, n + 1, n]);
        let mesh = assert_paths_agree(&m, iso, &o);
        // Welding points where the surface passes through a lattice point may pinch it; off
        // those, the welded surface is an oriented manifold.
        let fast = polygonise_fast(&m, iso, &o.with_parts(1)).unwrap();
        // One range per element welds to the one-pass mesh, vertex for vertex.
        let split = polygonise_fast(&m, iso, &o.with_parts(m.elements.len())).unwrap();
        prop_assert_eq!(&split.mesh.triangles, &fast.mesh.triangles);
        prop_assert_eq!(&split.mesh.vertices, &fast.mesh.vertices);
        prop_assert_eq!(&split.mesh.normals, &fast.mesh.normals);
        prop_assert_eq!(split.stats, fast.stats);
        if fast.stats.welded_vertices == 0 {
            prop_assert!(mesh.check_manifold().is_ok(), "{:?}", mesh.check_manifold());
        }
        // Normals by finite differences change nothing but the normals.
        let fd = polygonise_fast(&m, iso, &o.with_normals(NormalSource::FiniteDifference)).unwrap();
        prop_assert_eq!(&fd.mesh.triangles, &mesh.triangles);
        prop_assert!(fd.mesh.validate().is_ok());
    }
}

/// `r² = x² + y² + z²` on tricubic Hermite elements is represented exactly (quadratic per
/// direction): the 0.8-sphere inside a 2×2×2 block of elements over `[−1, 1]³` is a closed,
/// consistently oriented genus-0 surface whose vertex normals point outward and agree with
/// the triangles' winding.
#[test]
fn hermite_sphere_is_closed_and_outward() {
    let m = geocert::mc::fe::models::hermite_ball(2);
    for n in [3, 6] {
        let mesh = assert_paths_agree(&m, 0.64, &opts(n));
        assert_eq!(mesh.check_manifold().unwrap(), 0, "closed");
        assert_eq!(mesh.euler_characteristic(), 2);
        let normals = mesh.normals.as_ref().unwrap();
        for (v, nv) in mesh.vertices.iter().zip(normals) {
            let r = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            approx::assert_abs_diff_eq!(r, 0.8, epsilon = 0.02);
            let dot = (v[0] * nv[0] + v[1] * nv[1] + v[2] * nv[2]) / r;
            assert!(dot > 0.999, "normal not radial: {dot}");
        }
        for t in &mesh.triangles {
            let [a, b, cc] = t.map(|i| mesh.vertices[i as usize]);
            let nrm = area_vector(a, b, cc);
            let centroid = [0, 1, 2].map(|k| a[k] + b[k] + cc[k]);
            assert!(
                nrm.iter().zip(centroid).map(|(x, y)| x * y).sum::<f64>() > 0.0,
                "winding points inward"
            );
        }
    }
}

/// A left-handed element (mirrored) still yields outward winding: its triangles are flipped.
#[test]
fn mirrored_elements_are_flipped() {
    let value = |p: [f64; 3]| (p[0] - 0.5).powi(2) + (p[1] - 0.5).powi(2) + (p[2] - 0.5).powi(2);
    let m = block(
        ElementKind::TRILINEAR_LAGRANGE,
        [1, 1, 1],
        &value,
        &no_derivative,
        &|p| [-p[0], p[1], p[2]],
    );
    let mesh = assert_paths_agree(&m, 0.2, &opts(4));
    let fast = polygonise_fast(&m, 0.2, &opts(4)).unwrap();
    assert_eq!(fast.stats.flipped_elements, 1);
    // The field grows away from the centre (−0.5, 0.5, 0.5): triangle normals point away.
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
        let nrm = area_vector(a, b, c);
        let out = [a[0] + 0.5, a[1] - 0.5, a[2] - 0.5];
        assert!(nrm.iter().zip(out).map(|(x, y)| x * y).sum::<f64>() > 0.0);
    }
}

/// Figure 7: an element whose right face collapses to a segment (two pairs of nodes at the
/// same world point). The cut points on that face coincide; the collapsed triangle goes and
/// the coincident vertices become one.
#[test]
fn degenerate_element_loses_its_collapsed_triangles() {
    let mut m = block(
        ElementKind::TRILINEAR_LAGRANGE,
        [1, 1, 1],
        &|p| p[2] - 0.5,
        &no_derivative,
        &identity,
    );
    // Nodes at x = 1: (1,0,0)=1, (1,1,0)=3, (1,0,1)=5, (1,1,1)=7. Pull (1,1,·) onto (1,0,·):
    // the right face collapses to the segment from node 1 to node 5.
    m.coordinates[3] = m.coordinates[1];
    m.coordinates[7] = m.coordinates[5];
    // The field rises along z, so the right face's edges 1–5 and 3–7 are cut at the same
    // height: one world point. Corner 0 is made positive for a less symmetric case.
    m.field[0] = 1.0;
    for n in [1, 2] {
        let exact = polygonise_exact(
            &m.to_exact().unwrap(),
            &Rational::from_integer(0.into()),
            &opts(n),
        )
        .unwrap();
        let mesh = assert_paths_agree(&m, 0.0, &opts(n));
        assert!(
            exact.stats.degenerate_triangles > 0,
            "n = {n}: {:?}",
            exact.stats
        );
        assert!(exact.stats.welded_vertices > 0);
        assert!(mesh
            .triangles
            .iter()
            .all(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2]));
    }
}

/// The 16-element left ventricle: both paths agree; the apex collapses (welded vertices and
/// removed triangles); the surface is an oriented manifold with boundary only on the wall.
#[test]
fn heart_demo_paths_agree() {
    let m = left_ventricle();
    let o = paper_options();
    let exact = polygonise_exact(
        &m.to_exact().unwrap(),
        &Rational::from_integer(0.into()),
        &o,
    )
    .unwrap();
    let mesh = assert_paths_agree(&m, 0.0, &o);
    assert_eq!(exact.stats.cells, 16 * 9 * 9 * 5);
    assert!(exact.stats.cut_cells > 100);
    assert!(exact.stats.welded_vertices > 0, "{:?}", exact.stats);
    assert!(mesh.check_manifold().is_ok(), "{:?}", mesh.check_manifold());
    assert!(mesh
        .normals
        .as_ref()
        .unwrap()
        .iter()
        .all(|n| approx::abs_diff_eq!(
            (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt(),
            1.0,
            epsilon = 1e-9
        )));
}

#[test]
fn bad_models_are_refused() {
    let good = block(
        ElementKind::TRILINEAR_LAGRANGE,
        [1, 1, 1],
        &|p| p[0],
        &no_derivative,
        &identity,
    );
    let mut m = good.clone();
    m.elements[0][3] = 99;
    assert!(matches!(
        polygonise_fast(&m, 0.5, &opts(1)),
        Err(FeError::NodeIndex {
            element: 0,
            local: 3,
            node: 99,
            ..
        })
    ));
    let mut m = good.clone();
    m.field[2] = f64::NAN;
    assert!(matches!(
        polygonise_fast(&m, 0.5, &opts(1)),
        Err(FeError::NonFinite { node: 2, .. })
    ));
    let mut m = good.clone();
    m.field.pop();
    assert!(matches!(
        polygonise_fast(&m, 0.5, &opts(1)),
        Err(FeError::Layout { .. })
    ));
    assert!(matches!(
        polygonise_fast(&good, f64::INFINITY, &opts(1)),
        Err(FeError::Isovalue)
    ));
    assert!(matches!(
        polygonise_fast(&good, 0.5, &FeOptions::new().with_cells([1, 0, 1])),
        Err(FeError::Cells(_))
    ));
    assert!(matches!(
        polygonise_fast(&good, 0.5, &opts(2).with_max_cells(7)),
        Err(FeError::TooManyCells { cells: 8, limit: 7 })
    ));
    let mut m = good.clone();
    m.elements.clear();
    assert!(matches!(
        polygonise_fast(&m, 0.5, &opts(1)),
        Err(FeError::NoElements)
    ));
}

/// Element ranges polygonised apart and welded give the one-pass mesh exactly, for every
/// number of ranges: on the heart (Hermite, degenerate apex) and on a trilinear block whose
/// surface crosses many element faces.
#[test]
fn element_ranges_weld_to_the_one_pass_mesh() {
    let gyroid = |p: [f64; 3]| {
        let s = 0.7;
        (s * p[0]).sin() * (s * p[1]).cos()
            + (s * p[1]).sin() * (s * p[2]).cos()
            + (s * p[2]).sin() * (s * p[0]).cos()
    };
    let block = geocert::mc::fe::models::block(
        geocert::mc::fe::ElementKind::TRILINEAR_LAGRANGE,
        [5, 4, 3],
        &gyroid,
        &no_derivative,
        &|p| {
            [
                p[0] + 0.1 * (p[1] * p[2]).sin(),
                p[1],
                p[2] - 0.1 * p[0].cos(),
            ]
        },
    );
    let heart = geocert::mc::fe::heart::left_ventricle();
    for (m, iso, n) in [(&heart, 0.0, [5, 4, 3]), (&block, 0.1, [3, 3, 3])] {
        let o = FeOptions::new().with_cells(n);
        let one = polygonise_fast(m, iso, &o.with_parts(1)).unwrap();
        for parts in [2, 3, 7, m.elements.len()] {
            let s = polygonise_fast(m, iso, &o.with_parts(parts)).unwrap();
            assert_eq!(s.mesh.triangles, one.mesh.triangles, "{parts} ranges");
            assert_eq!(s.mesh.vertices, one.mesh.vertices, "{parts} ranges");
            assert_eq!(s.mesh.normals, one.mesh.normals, "{parts} ranges");
            assert_eq!(s.stats, one.stats, "{parts} ranges");
        }
        println!(
            "{} elements: {} triangles, {} welded vertices, identical for 2, 3, 7 and {} ranges",
            m.elements.len(),
            one.mesh.triangles.len(),
            one.stats.welded_vertices,
            m.elements.len()
        );
    }
}

/// Corner values (in `[−3, 3]`, table numbering) of cells whose trilinear surface has a tube
/// at the isovalue 1/2, found by a deterministic search.
fn tunnel_cells(count: usize) -> Vec<[i8; 8]> {
    let mut out = Vec::new();
    let mut s = 0x2545_F491_4F6C_DD1Du64;
    while out.len() < count {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        let v: [i8; 8] = std::array::from_fn(|i| ((s >> (8 * i)) % 7) as i8 - 3);
        let q = v.map(|x| Rational::from_integer(x.into()));
        if geocert::mc::trilinear::cell_topology_exact(&q, &Rational::new(1.into(), 2.into()))
            .tunnels()
            > 0
        {
            out.push(v);
        }
    }
    out
}

/// `--topology trilinear` on trilinear elements: one element per tunnel cell draws the
/// tube (an annulus: χ = 0 where the table draws two discs), both paths alike, and a block
/// of such cells gives the grid's trilinear extraction as triangle sets.
#[test]
fn trilinear_topology_draws_the_tubes() {
    use geocert::mc::fe::CellRule;
    use geocert::mc::trilinear::polygonise::extract_trilinear_exact;
    let half = Rational::new(1.into(), 2.into());
    let corners = geocert::mc::table::CORNERS;
    let cells = tunnel_cells(12);
    for v in &cells {
        // Local node a + 2b + 4c at (a, b, c); the table numbers corners differently.
        let value = |p: [f64; 3]| {
            let c = corners
                .iter()
                .position(|q| q.map(f64::from) == p)
                .expect("a corner");
            v[c] as f64
        };
        let m = block(
            ElementKind::TRILINEAR_LAGRANGE,
            [1, 1, 1],
            &value,
            &no_derivative,
            &identity,
        );
        let o = opts(1).with_topology(CellRule::Trilinear);
        let exact = polygonise_exact(&m.to_exact().unwrap(), &half, &o).unwrap();
        let fast = polygonise_fast(&m, 0.5, &o).unwrap();
        assert_eq!(fast.mesh.triangles, exact.triangles);
        assert_eq!(exact.stats.tunnel_cells, 1);
        assert_eq!(fast.stats.tunnel_cells, 1);
        let mesh = fast.mesh;
        mesh.validate().unwrap();
        let table = polygonise_fast(&m, 0.5, &opts(1)).unwrap().mesh;
        assert_eq!(
            mesh.euler_characteristic(),
            table.euler_characteristic() - 2,
            "a tube where the table has two discs"
        );
        assert!(mesh.check_manifold().is_ok());
    }
    // Warped two-element blocks with tunnel cells inside: exact = fast, and on the unwarped
    // block the grid's trilinear extraction (triangle sets).
    for pair in cells.chunks(2) {
        let vals: Vec<i8> = (0..12)
            .map(|i| {
                let (x, y, z) = (i % 3, i / 3 % 2, i / 6);
                let c = |v: &[i8; 8], x: usize| {
                    let p = [x as u8, y as u8, z as u8];
                    v[corners.iter().position(|q| *q == p).unwrap()]
                };
                if x < 2 {
                    c(&pair[0], x)
                } else {
                    c(&pair[1], 1)
                }
            })
            .collect();
        let idx = |p: [f64; 3]| p[0] as usize + 3 * (p[1] as usize + 2 * p[2] as usize);
        let value = |p: [f64; 3]| vals[idx(p)] as f64;
        let m = block(
            ElementKind::TRILINEAR_LAGRANGE,
            [2, 1, 1],
            &value,
            &no_derivative,
            &identity,
        );
        let o = opts(1).with_topology(CellRule::Trilinear);
        let fe = polygonise_exact(&m.to_exact().unwrap(), &half, &o).unwrap();
        let vol = Volume::new(
            [3, 2, 2],
            vals.iter()
                .map(|&v| Rational::from_integer(v.into()))
                .collect(),
        )
        .unwrap();
        let (gv, gt, _) = extract_trilinear_exact(&vol, &half).unwrap();
        assert_eq!(
            triangle_set(&fe.vertices, &fe.triangles),
            triangle_set(&gv, &gt)
        );
        let warped = block(
            ElementKind::TRILINEAR_LAGRANGE,
            [2, 1, 1],
            &value,
            &no_derivative,
            &|p| {
                [
                    p[0] + 0.1 * p[1] * p[2],
                    p[1] - 0.05 * p[0],
                    p[2] + 0.1 * p[0] * p[1],
                ]
            },
        );
        for n in [1, 2] {
            let o = opts(n).with_topology(CellRule::Trilinear);
            assert_paths_agree(&warped, 0.5, &o);
        }
    }
    println!(
        "{} tunnel cells: tubes drawn on both paths, equal to the grid's",
        cells.len()
    );
}

#[test]
fn trilinear_topology_refuses_hermite_elements() {
    let o = opts(2).with_topology(geocert::mc::fe::CellRule::Trilinear);
    let err = polygonise_fast(&left_ventricle(), 0.0, &o).unwrap_err();
    assert!(matches!(err, FeError::TopologyNeedsTrilinear(_)), "{err}");
}
