//! Mesh readers and writers: exact round trips, validation errors that name the element,
//! topology checks on the built-in dome.

use geocert::mesh::{obj, ply, squashed_hemisphere, stl, vtk, Mesh, MeshError, Scalars};
use proptest::prelude::*;

fn mesh_strategy() -> impl Strategy<Value = Mesh> {
    (3usize..30).prop_flat_map(|n| {
        (
            proptest::collection::vec(prop::array::uniform3(-1e6f64..1e6), n),
            proptest::collection::vec(
                (0..n as u32, 0..n as u32, 0..n as u32)
                    .prop_filter("distinct", |(a, b, c)| a != b && b != c && a != c),
                0..40,
            ),
            proptest::option::of(proptest::collection::vec(-1e3f64..1e3, n)),
        )
            .prop_map(|(vertices, tris, values)| Mesh {
                normals: None,
                vertices,
                triangles: tris.into_iter().map(|(a, b, c)| [a, b, c]).collect(),
                scalars: values.map(|values| Scalars {
                    name: "stress".into(),
                    values,
                }),
            })
    })
}

proptest! {
    #[test]
    fn ply_and_obj_round_trip_bit_for_bit(m in mesh_strategy()) {
        for binary in [false, true] {
            let back = ply::read(&ply::write(&m, binary), m.scalars.as_ref().map(|s| s.name.as_str())).unwrap();
            prop_assert_eq!(&back, &m);
        }
        let back = vtk::read(&vtk::write(&m), None).unwrap();
        prop_assert_eq!(&back, &m);
        let back = obj::read(&obj::write(&m)).unwrap();
        prop_assert_eq!(back.vertices, m.vertices.clone());
        prop_assert_eq!(back.triangles, m.triangles.clone());
    }

    #[test]
    fn readers_never_panic_on_arbitrary_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        let _ = ply::read(&bytes, None);
        let _ = obj::read(&bytes);
        let _ = stl::read(&bytes);
        let _ = vtk::read(&bytes, None);
    }
}

#[test]
fn stl_round_trip_welds_shared_corners() {
    let m = squashed_hemisphere(4, 0.5);
    // STL stores f32: round the vertices first so the round trip is exact.
    let m32 = Mesh {
        vertices: m
            .vertices
            .iter()
            .map(|v| v.map(|x| x as f32 as f64))
            .collect(),
        ..m.clone()
    };
    let back = stl::read(&stl::write(&m32)).unwrap();
    assert_eq!(back.vertices.len(), m.vertices.len());
    assert_eq!(back.triangles.len(), m.triangles.len());
    for (t, u) in back.triangles.iter().zip(&m32.triangles) {
        assert_eq!(
            t.map(|i| back.vertices[i as usize]),
            u.map(|i| m32.vertices[i as usize])
        );
    }
}

#[test]
fn dome_sizes_topology_and_orientation() {
    for (n, v) in [(8, 145), (16, 545), (32, 2113)] {
        let m = squashed_hemisphere(n, 0.5);
        m.validate().unwrap();
        assert_eq!(m.vertices.len(), v);
        assert_eq!(m.triangles.len(), 4 * (n * n) as usize);
        // An open disc: χ = 1, boundary = the equator's 4n edges.
        assert_eq!(m.euler_characteristic(), 1);
        assert_eq!(m.check_manifold().unwrap(), 4 * n as usize);
        // Outward: every triangle's normal points away from the centre.
        for t in &m.triangles {
            let p = t.map(|i| m.vertices[i as usize]);
            let e1 = [0, 1, 2].map(|a| p[1][a] - p[0][a]);
            let e2 = [0, 1, 2].map(|a| p[2][a] - p[0][a]);
            let nrm = [
                e1[1] * e2[2] - e1[2] * e2[1],
                e1[2] * e2[0] - e1[0] * e2[2],
                e1[0] * e2[1] - e1[1] * e2[0],
            ];
            let c = [0, 1, 2].map(|a| (p[0][a] + p[1][a] + p[2][a]) / 3.0);
            assert!(nrm[0] * c[0] + nrm[1] * c[1] + nrm[2] * c[2] > 0.0);
        }
    }
}

#[test]
fn topology_errors_name_the_edge_or_vertex() {
    let v = vec![[0.0; 3]; 6];
    // Two triangles traversing edge (0,1) the same way.
    let m = Mesh {
        normals: None,
        vertices: v.clone(),
        triangles: vec![[0, 1, 2], [0, 1, 3]],
        scalars: None,
    };
    assert!(matches!(
        m.check_manifold(),
        Err(MeshError::NonManifold { a: 0, b: 1, .. })
    ));
    // A bow-tie: two triangles meeting only at vertex 0.
    let m = Mesh {
        normals: None,
        vertices: v,
        triangles: vec![[0, 1, 2], [0, 3, 4]],
        scalars: None,
    };
    let e = m.check_manifold().unwrap_err();
    assert!(e.to_string().contains("vertex 0"), "{e}");
}

#[test]
fn malformed_files_are_clear_errors() {
    let e = ply::read(b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n3 0 1 5\n", None).unwrap_err();
    assert!(
        e.to_string().contains("triangle 0") && e.to_string().contains("out of range"),
        "{e}"
    );
    let e = ply::read(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 nan 0\n", None).unwrap_err();
    assert!(matches!(e, MeshError::NonFinite { vertex: 0, .. }), "{e}");
    let e = ply::read(b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 0\n", None).unwrap_err();
    assert!(
        e.to_string().contains("vertex 1") && e.to_string().contains("ends early"),
        "{e}"
    );
    // Quads and n-gons are triangulated (convex ones as the fan from the first vertex);
    // a face of two vertices is an error naming its line.
    let m = obj::read(b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap();
    assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    let e = obj::read(b"v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2\n").unwrap_err();
    assert!(
        e.to_string().contains("line 4") && e.to_string().contains("2 vertices"),
        "{e}"
    );
    let mut big = String::new();
    for k in 0..2000 {
        let a = k as f64 * std::f64::consts::TAU / 2000.0;
        big += &format!("v {} {} 0\n", a.cos(), a.sin());
    }
    big += "f";
    for k in 1..=2000 {
        big += &format!(" {k}");
    }
    let e = obj::read(big.as_bytes()).unwrap_err();
    assert!(e.to_string().contains("2000 vertices"), "{e}");
    let quads = b"ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n2 0 0\n0 1 0\n1 1 0\n2 1 0\n4 0 1 4 3\n4 1 2 5 4\n";
    let m = ply::read(quads, None).unwrap();
    assert_eq!(
        m.triangles,
        vec![[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]]
    );
    let e = ply::read(b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n2 0 1\n", None).unwrap_err();
    assert!(
        e.to_string().contains("face 0") && e.to_string().contains("2 vertices"),
        "{e}"
    );
    let e = obj::read(b"v 0 0 0\nf 1 2 -7\n").unwrap_err();
    assert!(e.to_string().contains("line 2"), "{e}");
    let m = obj::read(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1/1 -1//1\n").unwrap();
    assert_eq!(m.triangles, vec![[0, 1, 2]]);
    let e = ply::read(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n", Some("stress")).unwrap_err();
    assert!(e.to_string().contains("stress"), "{e}");
}

#[test]
fn writing_fails_cleanly_and_leaves_no_file() {
    let dir = std::env::temp_dir().join(format!("geocert-mesh-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = Mesh {
        normals: None,
        vertices: vec![[0.0, f64::NAN, 0.0]],
        triangles: vec![],
        scalars: None,
    };
    let path = dir.join("bad.ply");
    assert!(bad.write(&path, geocert::mesh::Format::PlyBinary).is_err());
    assert!(!path.exists());
    let good = squashed_hemisphere(2, 0.5);
    let path = dir.join("dome.obj");
    good.write(&path, geocert::mesh::Format::Obj).unwrap();
    assert_eq!(Mesh::read(&path, None).unwrap(), good);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn legacy_vtk_errors_name_the_line() {
    let e = vtk::read(b"# vtk DataFile Version 3.0\nt\nBINARY\n", None).unwrap_err();
    assert!(e.to_string().contains("line 3"), "{e}");
    let e = vtk::read(
        b"# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\n",
        None,
    )
    .unwrap_err();
    assert!(e.to_string().contains("POLYDATA"), "{e}");
    let quad = b"# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 4 float\n0 0 0 1 0 0 1 1 0 0 1 0\nPOLYGONS 1 5\n4 0 1 2 3\n";
    assert_eq!(
        vtk::read(quad, None).unwrap().triangles,
        vec![[0, 1, 2], [0, 2, 3]]
    );
    let short = b"# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 4 float\n0 0 0 1 0 0 1 1 0 0 1 0\nPOLYGONS 1 4\n4 0 1 2 3\n";
    let e = vtk::read(short, None).unwrap_err();
    assert!(
        e.to_string().contains("line 8") && e.to_string().contains("list size"),
        "{e}"
    );
    let ok = b"# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 1 2\nPOINT_DATA 3\nSCALARS vm float\nLOOKUP_TABLE default\n1 2 3\n";
    let m = vtk::read(ok, Some("vm")).unwrap();
    assert_eq!(m.scalars.unwrap().values, vec![1.0, 2.0, 3.0]);
    assert!(vtk::read(ok, Some("other")).is_err());
}

/// A CAD export's sliver (two corners welded together) is refused by `stl::read`, naming the
/// facet, and skipped and counted by `stl::read_dropping_slivers`, which leaves no vertex
/// that only the sliver used.
#[test]
fn stl_slivers_are_refused_or_skipped_and_counted() {
    let facet = |c: [[f64; 3]; 3]| {
        let mut s = String::from("facet normal 0 0 1\nouter loop\n");
        for p in c {
            s += &format!("vertex {} {} {}\n", p[0], p[1], p[2]);
        }
        s + "endloop\nendfacet\n"
    };
    let (a, b, c, d) = ([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]);
    let text = format!(
        "solid t\n{}{}{}endsolid t\n",
        facet([a, b, c]),
        facet([b, [5.0, 5.0, 5.0], b]),
        facet([b, d, c])
    );
    let e = stl::read(text.as_bytes()).unwrap_err();
    assert!(e.to_string().contains("facet 1") && e.to_string().contains("two equal corners"));
    let (mesh, dropped) = stl::read_dropping_slivers(text.as_bytes()).unwrap();
    assert_eq!(dropped, 1);
    assert_eq!(mesh.triangles.len(), 2);
    assert_eq!(
        mesh.vertices.len(),
        4,
        "the sliver's own corner is no vertex"
    );
    assert!(mesh.used_vertices().iter().all(|&u| u));
}
