//! Diamond hierarchies: the fast error against the exact one, and bad input.

use geocert::diamond::{
    diamond_stats_exact, diamond_stats_fast, diamond_stats_integer, integer_samples, DiamondError,
    DiamondType, Field, Hierarchy,
};
use geocert::num::rational_to_f64;
use proptest::prelude::*;

/// Every diamond of a small random field: the fast error interval holds the exact error, the
/// ranges agree.
fn fast_matches_exact<const D: usize>(dims: [usize; D], values: &[f64]) -> Result<usize, String> {
    let field = Field::<D>::pad(dims, values).map_err(|e| e.to_string())?;
    let hier = field.hierarchy();
    let ints = integer_samples(&field);
    let mut checked = 0;
    for i in 0..field.values().len() {
        let p = field.point(i);
        let Ok(dia) = hier.diamond(p) else { continue };
        let fast = diamond_stats_fast(&field, &dia);
        let exact = diamond_stats_exact(&field, &dia);
        let e = rational_to_f64(&exact.error);
        if let Some(ints) = &ints {
            // The integer route is exact: the error is a dyadic rational an f64 holds.
            let s = diamond_stats_integer(ints, hier.side(), &dia);
            if geocert::num::rational_from_f64(s.error_hi, "e").unwrap() != exact.error
                || s.error_lo != s.error_hi
                || s.min != exact.min
                || s.max != exact.max
            {
                return Err(format!("diamond {p:?}: integer {s:?}, exact {e}"));
            }
        }
        if !(fast.error_lo <= e && e <= fast.error_hi)
            || fast.min != exact.min
            || fast.max != exact.max
        {
            return Err(format!(
                "diamond {p:?}: fast [{}, {}] range [{}, {}], exact {e} range [{}, {}]",
                fast.error_lo, fast.error_hi, fast.min, fast.max, exact.min, exact.max
            ));
        }
        checked += 1;
    }
    Ok(checked)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn fast_error_holds_the_exact_error_3d(
        dims in (2usize..=9, 2usize..=9, 2usize..=9),
        seed in any::<u64>(),
        float in any::<bool>(),
    ) {
        let n = dims.0 * dims.1 * dims.2;
        let mut x = seed | 1;
        let values: Vec<f64> = (0..n).map(|_| {
            x ^= x << 13; x ^= x >> 7; x ^= x << 17;
            if float { (x % 20001) as f64 / 64.0 - 150.0 + 1.0 / 3.0 } else { (x % 256) as f64 - 100.0 }
        }).collect();
        let checked = fast_matches_exact([dims.0, dims.1, dims.2], &values);
        prop_assert!(checked.is_ok(), "{:?}", checked);
    }

    #[test]
    fn fast_error_holds_the_exact_error_2d_4d(seed in any::<u64>(), side in 2usize..=9, side4 in 2usize..=3) {
        let mut x = seed | 1;
        let mut next = || { x ^= x << 13; x ^= x >> 7; x ^= x << 17; (x % 1000) as f64 / 8.0 };
        let v2: Vec<f64> = (0..side * side).map(|_| next()).collect();
        let v2i: Vec<f64> = v2.iter().map(|v| (v * 8.0).round()).collect();
        prop_assert!(fast_matches_exact([side, side], &v2i).is_ok());
        prop_assert!(fast_matches_exact([side, side], &v2).is_ok());
        let v4: Vec<f64> = (0..side4.pow(4)).map(|_| next().round()).collect();
        let r = fast_matches_exact([side4; 4], &v4);
        prop_assert!(r.is_ok(), "{:?}", r);
    }
}

#[test]
fn a_linear_field_has_zero_error_everywhere() {
    let dims = [9, 9, 9];
    let values: Vec<f64> = (0..729)
        .map(|i| {
            let (x, y, z) = (i % 9, i / 9 % 9, i / 81);
            3.0 * x as f64 - 2.0 * y as f64 + 0.5 * z as f64 + 7.0
        })
        .collect();
    let field = Field::<3>::pad(dims, &values).unwrap();
    for i in 0..729 {
        if let Ok(d) = field.hierarchy().diamond(field.point(i)) {
            let s = diamond_stats_fast(&field, &d);
            assert!(
                s.error_lo == 0.0 && s.error_hi < 1e-9,
                "{:?}: {:?}",
                d.center(),
                s
            );
            assert!(num_traits::Zero::is_zero(
                &diamond_stats_exact(&field, &d).error
            ));
        }
    }
}

#[test]
fn bad_input_is_a_typed_error() {
    assert!(matches!(
        Hierarchy::<3>::new(0),
        Err(DiamondError::Levels { .. })
    ));
    assert!(matches!(
        Hierarchy::<3>::new(31),
        Err(DiamondError::Levels { .. })
    ));
    let h = Hierarchy::<3>::new(4).unwrap();
    assert!(matches!(
        h.diamond([16, 0, 16]),
        Err(DiamondError::Corner { .. })
    ));
    assert!(matches!(
        h.diamond([17, 0, 3]),
        Err(DiamondError::OutOfRange { .. })
    ));
    assert!(h.diamond([8, 8, 8]).is_ok());
    assert!(matches!(
        DiamondType::<3>::from_code(0b101010),
        Err(DiamondError::InvalidType { .. })
    ));
    assert!(matches!(
        DiamondType::<3>::from_code(1 << 6),
        Err(DiamondError::InvalidType { .. })
    ));
    assert!(matches!(
        Field::<3>::pad([2, 2, 1], &[0.0; 4]),
        Err(DiamondError::Volume(_))
    ));
    assert!(matches!(
        Field::<3>::pad([2, 2, 2], &[0.0; 7]),
        Err(DiamondError::Volume(_))
    ));
    let mut v = vec![0.0; 8];
    v[5] = f64::NAN;
    assert!(
        matches!(Field::<3>::pad([2, 2, 2], &v), Err(DiamondError::Volume(m)) if m.contains("sample 5"))
    );
}

#[test]
fn padding_replicates_the_last_sample() {
    let values: Vec<f64> = (0..12).map(f64::from).collect();
    let f = Field::<2>::pad([4, 3], &values).unwrap();
    assert_eq!(f.hierarchy().levels(), 2);
    assert_eq!(f.at(&[4, 0]), 3.0);
    assert_eq!(f.at(&[1, 4]), 9.0);
    assert_eq!(f.at(&[4, 4]), 11.0);
    assert_eq!(f.real_count(), 12);
}

mod fronts {
    use geocert::diamond::{
        check_conforming, marching_tetrahedra, simplices_stats_exact, DiamondFront, Field, FullDmv,
        Lod, Refiner, Simplex, SupercubeFront,
    };
    use proptest::prelude::*;

    fn field(side: usize, seed: u64, smooth: bool) -> Field<3> {
        let mut x = seed | 1;
        let values: Vec<f64> = (0..side * side * side)
            .map(|i| {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                let (a, b, c) = (i % side, i / side % side, i / side / side);
                if smooth {
                    ((a * a + 2 * b * b + 3 * c * c) as f64).sqrt() + (x % 3) as f64 * 0.25
                } else {
                    (x % 64) as f64
                }
            })
            .collect();
        Field::pad([side; 3], &values).unwrap()
    }

    fn sorted(mut m: Vec<Simplex<3>>) -> Vec<Simplex<3>> {
        for s in &mut m {
            *s = s.sorted();
        }
        m.sort_unstable();
        m
    }

    fn lod(kind: u8, value: f64, side: f64) -> Lod<3> {
        match kind % 3 {
            0 => Lod {
                error: Some(value),
                ..Lod::default()
            },
            1 => Lod {
                isovalues: vec![value * 4.0],
                ..Lod::default()
            },
            _ => Lod {
                error: Some(value / 4.0),
                roi: Some(([0.0, 0.0, 0.0], [side / 3.0, side / 2.0, side])),
                ..Lod::default()
            },
        }
    }

    /// The case proptest found against the earlier greedy coarsening (merge while unwanted
    /// and childless), which kept refined diamonds whose only reason was a refined
    /// descendant: everywhere refined (`ε > 0`), then the region of interest.
    #[test]
    fn coarsening_drops_diamonds_kept_only_by_descendants() {
        let dmv = FullDmv::build(field(5, 10990666046957445974, true));
        let n = dmv.field().hierarchy().side() as f64;
        let (fine, coarse) = (lod(0, 0.0, n), lod(2, 4.426914138374738, n));
        let mut inc: Refiner<'_, 3, _, SupercubeFront<3>> = Refiner::new(&dmv);
        inc.refine(&fine).unwrap();
        inc.update(&coarse).unwrap();
        let mut top: Refiner<'_, 3, _, SupercubeFront<3>> = Refiner::new(&dmv);
        top.refine(&coarse).unwrap();
        assert_eq!(sorted(inc.mesh()), sorted(top.mesh()));
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(24))]

        /// Random volumes and random sequences of LOD changes: the diamond and the supercube
        /// fronts give the same mesh, always conforming; refining changes from the current
        /// front give the top-down front.
        #[test]
        fn fronts_agree_and_conform(
            side in 3usize..=17,
            seed in any::<u64>(),
            smooth in any::<bool>(),
            steps in proptest::collection::vec((0u8..3, 0.0f64..12.0), 1..5),
        ) {
            let dmv = FullDmv::build(field(side, seed, smooth));
            let hier = dmv.field().hierarchy();
            let mut d: Refiner<'_, 3, _, DiamondFront<3>> = Refiner::new(&dmv);
            let mut s: Refiner<'_, 3, _, SupercubeFront<3>> = Refiner::new(&dmv);
            for &(kind, value) in &steps {
                let l = lod(kind, value, hier.side() as f64);
                d.update(&l).unwrap();
                s.update(&l).unwrap();
                let md = sorted(d.mesh());
                prop_assert_eq!(&md, &sorted(s.mesh()));
                let c = check_conforming(&hier, &md);
                prop_assert!(c.conforming, "{:?}", c);
                // The incremental front (coarsened and refined from the previous criterion's)
                // is the top-down front of this criterion.
                let mut top: Refiner<'_, 3, _, SupercubeFront<3>> = Refiner::new(&dmv);
                top.refine(&l).unwrap();
                prop_assert_eq!(&md, &sorted(top.mesh()));
            }
        }

        /// Marching tetrahedra on the simplices whose diamond's range holds the isovalue gives
        /// the surface of the whole current mesh.
        #[test]
        fn surface_near_the_isovalue_is_the_whole_surface(
            side in 3usize..=17,
            seed in any::<u64>(),
            e in 0.0f64..6.0,
            iso in 1.0f64..40.0,
        ) {
            let dmv = FullDmv::build(field(side, seed, true));
            let mut r: Refiner<'_, 3, _, DiamondFront<3>> = Refiner::new(&dmv);
            r.refine(&Lod { error: Some(e), isovalues: vec![iso], roi: None }).unwrap();
            let all = marching_tetrahedra(&dmv, &r.mesh(), iso).unwrap();
            let near = r.mesh_near(iso);
            prop_assert!(near.len() <= r.mesh().len());
            let some = marching_tetrahedra(&dmv, &near, iso).unwrap();
            let key = |m: &geocert::mesh::Mesh| {
                let mut t: Vec<[[u64; 3]; 3]> = m
                    .triangles
                    .iter()
                    .map(|t| t.map(|i| m.vertices[i as usize].map(f64::to_bits)))
                    .collect();
                t.sort_unstable();
                t
            };
            prop_assert_eq!(key(&all.mesh), key(&some.mesh));
            prop_assert_eq!(all.open_edges, some.open_edges);
        }

        /// Coarsening after refining: raising the threshold, shrinking or moving the region of
        /// interest, changing the isovalue — the incremental front equals the top-down one
        /// (the error alone is not monotone from parents to children, so the coarsening must
        /// also drop refined diamonds that only refined descendants kept).
        #[test]
        fn incremental_coarsening_equals_top_down(
            side in 3usize..=17,
            seed in any::<u64>(),
            smooth in any::<bool>(),
            fine in (0u8..3, 0.0f64..3.0),
            coarse in (0u8..3, 3.0f64..12.0),
        ) {
            let dmv = FullDmv::build(field(side, seed, smooth));
            let n = dmv.field().hierarchy().side() as f64;
            let (fine, coarse) = (lod(fine.0, fine.1, n), lod(coarse.0, coarse.1, n));
            let mut inc: Refiner<'_, 3, _, DiamondFront<3>> = Refiner::new(&dmv);
            inc.refine(&fine).unwrap();
            inc.update(&coarse).unwrap();
            let mut top: Refiner<'_, 3, _, DiamondFront<3>> = Refiner::new(&dmv);
            top.refine(&coarse).unwrap();
            prop_assert_eq!(sorted(inc.mesh()), sorted(top.mesh()));
            // And back: refining again from the coarse front.
            inc.update(&fine).unwrap();
            let mut top: Refiner<'_, 3, _, DiamondFront<3>> = Refiner::new(&dmv);
            top.refine(&fine).unwrap();
            prop_assert_eq!(sorted(inc.mesh()), sorted(top.mesh()));
        }

        /// Threshold 0: the partial DMV of the diamonds with error > 0 (and their ancestors),
        /// refined fully, interpolates every grid point exactly.
        #[test]
        fn zero_error_partial_dmv_is_lossless(side in 3usize..=9, seed in any::<u64>()) {
            let dmv = FullDmv::build(field(side, seed, true));
            let sel = dmv.select_by_error(0.0);
            for encoded in [true, false] {
                let mesh = if encoded {
                    let ds = dmv.supercube_encoding(&sel);
                    let mut r: Refiner<'_, 3, _, SupercubeFront<3>> = Refiner::new(&ds);
                    r.refine(&Lod::default()).unwrap();
                    r.mesh()
                } else {
                    let dd = dmv.diamond_encoding(&sel);
                    let mut r: Refiner<'_, 3, _, DiamondFront<3>> = Refiner::new(&dd);
                    r.refine(&Lod::default()).unwrap();
                    r.mesh()
                };
                let stats = simplices_stats_exact(dmv.field(), &mesh);
                prop_assert!(num_traits::Zero::is_zero(&stats.error));
            }
        }
    }
}

mod partial {
    use geocert::diamond::{
        check_conforming, marching_tetrahedra, DiamondError, DiamondFront, DmvAccess, Field,
        FullDmv, Lod, Refiner, SupercubeDmv, SupercubeFront,
    };
    use proptest::prelude::*;

    /// Refines `values` for `ε > e` with both fronts: the same mesh, conforming.
    fn fronts_agree<const D: usize>(
        dims: [usize; D],
        values: &[f64],
        e: f64,
    ) -> Result<(), String> {
        let full = FullDmv::build(Field::<D>::pad(dims, values).map_err(|e| e.to_string())?);
        let lod = Lod::<D> {
            error: Some(e),
            ..Lod::default()
        };
        let mut a: Refiner<'_, D, _, DiamondFront<D>> = Refiner::new(&full);
        let mut b: Refiner<'_, D, _, SupercubeFront<D>> = Refiner::new(&full);
        a.refine(&lod).map_err(|e| e.to_string())?;
        b.refine(&lod).map_err(|e| e.to_string())?;
        let (mut ma, mut mb) = (a.mesh(), b.mesh());
        for m in [&mut ma, &mut mb] {
            for s in m.iter_mut() {
                *s = s.sorted();
            }
            m.sort_unstable();
        }
        if ma != mb {
            return Err(format!("{D}-D: the fronts' meshes differ"));
        }
        let c = check_conforming(&full.field().hierarchy(), &ma);
        if !c.conforming {
            return Err(format!("{D}-D: not conforming: {c:?}"));
        }
        Ok(())
    }

    /// A non-cubic volume (so that it is padded) of small integers plus noise.
    fn volume(side: usize, seed: u64) -> Field<3> {
        let dims = [side, side + 1, (side - 1).max(3)];
        let mut x = seed | 1;
        let values: Vec<f64> = (0..dims.iter().product::<usize>())
            .map(|i| {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                let (a, b, c) = (i % dims[0], i / dims[0] % dims[1], i / dims[0] / dims[1]);
                ((a * 7 + b * 3 + c * 5) % 40) as f64 + (x % 5) as f64
            })
            .collect();
        Field::pad(dims, &values).unwrap()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(16))]

        /// Partial DMVs are closed under ancestors, every vertex of a kept diamond is a kept
        /// central vertex or a corner, the .dmv file reads back bit for bit, and the
        /// isosurface on a refined mesh is closed away from the boundary.
        #[test]
        fn partial_dmvs_are_closed_and_files_round_trip(side in 3usize..=12, seed in any::<u64>(), iso in 1.0f64..40.0) {
            let full = FullDmv::build(volume(side, seed));
            let hier = full.field().hierarchy();
            for sel in [full.select_by_error(3.0), full.select_by_isovalues(&[iso + 0.5])] {
                let ds = full.supercube_encoding(&sel);
                for i in sel.indices() {
                    let d = hier.diamond(full.field().point(i)).unwrap();
                    for p in d.parents().iter() {
                        prop_assert!(sel.contains_index(full.field().index(p)));
                    }
                    for v in d.vertices() {
                        prop_assert!(ds.value(&v).is_some(), "vertex {:?} of {:?}", v, d.center());
                    }
                }
                let bytes = ds.to_bytes();
                let back = SupercubeDmv::<3>::from_bytes(&bytes).unwrap();
                prop_assert_eq!(back.to_bytes(), bytes.clone());
                prop_assert_eq!(back.len(), sel.count());
                for cut in [0, 8, bytes.len() / 2, bytes.len() - 1] {
                    let e = SupercubeDmv::<3>::from_bytes(&bytes[..cut]);
                    let refused = matches!(e, Err(DiamondError::File { .. }));
                    prop_assert!(refused, "cut at {}: {:?}", cut, e.err());
                }
                let lod = Lod { error: Some(1.0), isovalues: vec![iso + 0.5], roi: None };
                let mut r: Refiner<'_, 3, _, SupercubeFront<3>> = Refiner::new(&back);
                r.refine(&lod).unwrap();
                let mesh = r.mesh();
                prop_assert!(check_conforming(&hier, &mesh).conforming);
                let s = marching_tetrahedra(&back, &mesh, iso + 0.5).unwrap();
                prop_assert_eq!(s.open_edges, 0);
            }
        }

        /// Integer samples at an integer isovalue: a sample equal to it (outside) puts the
        /// vertices of all its cut edges at its grid point, so some triangles have no area;
        /// the surface is still closed and consistently oriented (no directed edge twice),
        /// as `geocert decimate` needs.
        #[test]
        fn isosurfaces_through_samples_are_oriented(side in 3usize..=12, seed in any::<u64>(), iso in 1u32..40) {
            let full = FullDmv::build(volume(side, seed));
            let hier = full.field().hierarchy();
            let iso = f64::from(iso);
            let sel = full.select_by_isovalues(&[iso]);
            let ds = full.supercube_encoding(&sel);
            let mut r: Refiner<'_, 3, _, SupercubeFront<3>> = Refiner::new(&ds);
            r.refine(&Lod { error: Some(1.0), isovalues: vec![iso], roi: None }).unwrap();
            let mesh = r.mesh();
            prop_assert!(check_conforming(&hier, &mesh).conforming);
            let s = marching_tetrahedra(&ds, &mesh, iso).unwrap();
            prop_assert_eq!(s.open_edges, 0);
            let mut directed: Vec<(u32, u32)> = s
                .mesh
                .triangles
                .iter()
                .flat_map(|t| (0..3).map(move |e| (t[e], t[(e + 1) % 3])))
                .collect();
            directed.sort_unstable();
            let repeated = directed.windows(2).filter(|w| w[0] == w[1]).count();
            prop_assert_eq!(repeated, 0, "{} triangles", s.mesh.triangles.len());
        }

        /// 2-D (terrains) and 4-D (time-varying volumes): the two fronts give the same
        /// conforming mesh.
        #[test]
        fn fronts_agree_in_2d_and_4d(seed in any::<u64>(), e in 0.0f64..8.0) {
            let mut x = seed | 1;
            let mut next = || { x ^= x << 13; x ^= x >> 7; x ^= x << 17; (x % 32) as f64 };
            let v2: Vec<f64> = (0..17 * 17).map(|_| next()).collect();
            let r = fronts_agree::<2>([17; 2], &v2, e);
            prop_assert!(r.is_ok(), "{:?}", r);
            let v4: Vec<f64> = (0..5usize.pow(4)).map(|_| next()).collect();
            let r = fronts_agree::<4>([5; 4], &v4, e);
            prop_assert!(r.is_ok(), "{:?}", r);
        }
    }
}

/// The conformity check on both of its face-counting routes (packed keys for grids up to
/// `2^13`, a hash map above): the Kuhn mesh of the cube conforms; a simplex left out, one
/// twice, and one bisected at the cube's diagonal (hanging faces, same volume) do not.
mod conformity {
    use geocert::diamond::{check_conforming, Hierarchy, Simplex};
    use proptest::prelude::*;

    /// The six Kuhn tetrahedra of `[0, s]³`: `0, s·e_π₀, s·(e_π₀ + e_π₁), (s, s, s)`.
    fn kuhn(s: u32) -> Vec<Simplex<3>> {
        let perms = [
            [0, 1, 2],
            [0, 2, 1],
            [1, 0, 2],
            [1, 2, 0],
            [2, 0, 1],
            [2, 1, 0],
        ];
        perms
            .iter()
            .map(|p| {
                let mut v = [[0u32; 3]; 4];
                for j in 0..3 {
                    v[j + 1] = v[j];
                    v[j + 1][p[j]] = s;
                }
                Simplex::new(&v).unwrap()
            })
            .collect()
    }

    #[test]
    fn kuhn_meshes_conform_and_broken_ones_do_not() {
        let mut checked = 0;
        for n in [1, 4, 13, 14, 20, 30] {
            let hier = Hierarchy::<3>::new(n).unwrap();
            let s = hier.side();
            let good = kuhn(s);
            let c = check_conforming(&hier, &good);
            assert!(c.conforming, "N = {n}: {c:?}");
            assert_eq!((c.interior_faces, c.boundary_faces), (6, 12), "N = {n}");
            let gap = good[1..].to_vec();
            let c = check_conforming(&hier, &gap);
            assert!(!c.conforming && c.bad_face_count == 2, "N = {n}: {c:?}");
            let mut twice = good.clone();
            twice.push(good[3]);
            let c = check_conforming(&hier, &twice);
            assert!(!c.conforming && c.bad_face_count == 4, "N = {n}: {c:?}");
            // Bisect the first tetrahedron at the diagonal's midpoint: its two faces on the
            // diagonal become four half-faces that no neighbour has.
            let v = good[0].vertices().to_vec();
            let m = [s / 2; 3];
            let mut split = good[1..].to_vec();
            split.push(Simplex::new(&[v[0], v[1], v[2], m]).unwrap());
            split.push(Simplex::new(&[m, v[1], v[2], v[3]]).unwrap());
            let c = check_conforming(&hier, &split);
            assert_eq!(c.volume_sum, c.domain_volume, "N = {n}");
            assert!(!c.conforming && c.bad_face_count == 6, "N = {n}: {c:?}");
            checked += 4;
        }
        println!("{checked} meshes checked on grids 2^1 to 2^30");
    }

    proptest! {
        /// `d!·volume` in machine words equals the `BigUint` route, in 2-D and 3-D (cofactor
        /// expansion) and 4-D (fraction-free elimination), for any `u32` coordinates.
        #[test]
        fn volume_routes_agree(c in proptest::collection::vec(any::<u32>(), 20)) {
            let p2: Vec<[u32; 2]> = c.chunks(2).take(3).map(|x| [x[0], x[1]]).collect();
            let s2 = Simplex::<2>::new(&p2).unwrap();
            prop_assert_eq!(s2.scaled_volume_u128().map(Into::into), Some(s2.scaled_volume()));
            let p3: Vec<[u32; 3]> = c.chunks(3).take(4).map(|x| [x[0], x[1], x[2]]).collect();
            let s3 = Simplex::<3>::new(&p3).unwrap();
            prop_assert_eq!(s3.scaled_volume_u128().map(Into::into), Some(s3.scaled_volume()));
            let p4: Vec<[u32; 4]> = c.chunks(4).take(5).map(|x| [x[0], x[1], x[2], x[3]]).collect();
            let s4 = Simplex::<4>::new(&p4).unwrap();
            if let Some(v) = s4.scaled_volume_u128() {
                prop_assert_eq!(num_bigint::BigUint::from(v), s4.scaled_volume());
            }
        }
    }
}

/// `for_each_child_slot` names, for every child of every diamond of small grids in 2-D to 5-D,
/// the slot in which `slot_of_parent` finds the parent, and yields the children in
/// `children()`'s order.
#[test]
fn children_name_the_slot_of_their_parent() {
    fn check<const D: usize>(levels: u32) -> usize {
        let hier = Hierarchy::<D>::new(levels).unwrap();
        let n = hier.side() as usize + 1;
        let mut pairs = 0;
        for i in 0..n.pow(D as u32) {
            let p: [u32; D] = std::array::from_fn(|k| (i / n.pow(k as u32) % n) as u32);
            let Ok(dia) = hier.diamond(p) else { continue };
            let mut seen = Vec::new();
            dia.for_each_child_slot(|child, slot| {
                assert_eq!(
                    child.slot_of_parent(&dia),
                    Some(slot),
                    "{p:?} → {:?}",
                    child.center()
                );
                seen.push(child.center());
                pairs += 1;
            });
            assert_eq!(seen, dia.children().to_vec());
        }
        pairs
    }
    let pairs = [check::<2>(4), check::<3>(3), check::<4>(2), check::<5>(2)];
    println!("child–parent pairs checked (d = 2, 3, 4, 5): {pairs:?}");
    assert!(pairs.iter().all(|&p| p > 0));
}
