//! Legacy VTK (`# vtk DataFile Version 2.0`..`5.1`), ASCII `POLYDATA`: `POINTS`, `POLYGONS`
//! (the classic `n i j k …` layout; polygons of more than three vertices are triangulated,
//! module `polygon`), and one `POINT_DATA` `SCALARS` array (with its
//! `LOOKUP_TABLE` line) as the nodal field. Binary files and other dataset types are refused
//! with a clear error.

use super::{Mesh, MeshError, Scalars};

fn err(place: impl Into<String>, why: impl Into<String>) -> MeshError {
    MeshError::Parse {
        format: "VTK",
        place: place.into(),
        why: why.into(),
    }
}

/// Largest count accepted from a header.
const MAX_COUNT: usize = 1 << 28;

/// Reads a legacy VTK polydata mesh; `scalar` picks a `SCALARS` array by name (the first one
/// when `None` and there is any).
pub fn read(bytes: &[u8], scalar: Option<&str>) -> Result<Mesh, MeshError> {
    let text = std::str::from_utf8(bytes).map_err(|_| {
        err(
            "file",
            "not ASCII text (binary legacy VTK is not supported)",
        )
    })?;
    let mut lines = text.lines().enumerate();
    match lines.next() {
        Some((_, l)) if l.starts_with("# vtk DataFile") => {}
        _ => return Err(err("line 1", "does not start with \"# vtk DataFile\"")),
    }
    lines.next(); // title
    match lines.next() {
        Some((_, l)) if l.trim() == "ASCII" => {}
        Some((i, l)) => {
            return Err(err(
                format!("line {}", i + 1),
                format!("expected ASCII, found {l:?}"),
            ))
        }
        None => return Err(err("file", "ends in the header")),
    }
    // The rest as a token stream with line numbers.
    let mut toks: Vec<(usize, &str)> = Vec::new();
    for (i, l) in lines {
        toks.extend(l.split_whitespace().map(|t| (i + 1, t)));
    }
    let mut at = 0usize;
    let mut next = |what: &str| -> Result<(usize, &str), MeshError> {
        let t = toks
            .get(at)
            .copied()
            .ok_or_else(|| err("file", format!("ends before {what}")))?;
        at += 1;
        Ok(t)
    };
    let count = |(line, t): (usize, &str)| -> Result<usize, MeshError> {
        t.parse::<usize>()
            .ok()
            .filter(|&n| n <= MAX_COUNT)
            .ok_or_else(|| err(format!("line {line}"), format!("bad count {t:?}")))
    };
    let number = |(line, t): (usize, &str)| -> Result<f64, MeshError> {
        t.parse::<f64>()
            .map_err(|_| err(format!("line {line}"), format!("not a number: {t:?}")))
    };
    let mut mesh = Mesh::default();
    let mut have_points = false;
    let mut point_count = 0usize;
    while let Ok((line, key)) = next("a section") {
        match key.to_ascii_uppercase().as_str() {
            "DATASET" => {
                let (l, kind) = next("the dataset type")?;
                if !kind.eq_ignore_ascii_case("POLYDATA") {
                    return Err(err(
                        format!("line {l}"),
                        format!("dataset {kind} (only POLYDATA is read)"),
                    ));
                }
            }
            "POINTS" => {
                point_count = count(next("the point count")?)?;
                next("the point type")?;
                mesh.vertices.reserve(point_count.min(1 << 20));
                for _ in 0..point_count {
                    let v = [
                        number(next("a coordinate")?)?,
                        number(next("a coordinate")?)?,
                        number(next("a coordinate")?)?,
                    ];
                    mesh.vertices.push(v);
                }
                have_points = true;
            }
            "POLYGONS" | "TRIANGLE_STRIPS" | "LINES" | "VERTICES" => {
                if !key.eq_ignore_ascii_case("POLYGONS") {
                    return Err(err(
                        format!("line {line}"),
                        format!("{key} cells are not read (POLYGONS only)"),
                    ));
                }
                let cells = count(next("the cell count")?)?;
                let size = count(next("the list size")?)?;
                let mut read = 0usize;
                let mut face = Vec::new();
                for c in 0..cells {
                    let (l, n) = next("a polygon")?;
                    let n = count((l, n))?;
                    read += n + 1;
                    if read > size {
                        return Err(err(
                            format!("line {l}"),
                            format!("polygon {c} runs past the list size {size}"),
                        ));
                    }
                    face.clear();
                    for _ in 0..n {
                        let (l, x) = next("a vertex index")?;
                        face.push(x.parse().map_err(|_| {
                            err(format!("line {l}"), format!("bad vertex index {x:?}"))
                        })?);
                    }
                    super::polygon::triangulate(&mesh.vertices, &face, &mut mesh.triangles)
                        .map_err(|why| err(format!("line {l}"), format!("polygon {c}: {why}")))?;
                }
                if read != size {
                    return Err(err(
                        format!("line {line}"),
                        format!("{cells} polygons take {read} numbers, the header says {size}"),
                    ));
                }
            }
            "POINT_DATA" => {
                let n = count(next("the point-data count")?)?;
                if have_points && n != point_count {
                    return Err(err(
                        format!("line {line}"),
                        format!("POINT_DATA {n} for {point_count} points"),
                    ));
                }
            }
            "SCALARS" => {
                let (_, name) = next("the array name")?;
                let (l, _ty) = next("the array type")?;
                // Optional component count, then LOOKUP_TABLE name.
                let (l2, t) = next("LOOKUP_TABLE")?;
                let t = if t.parse::<usize>().is_ok() {
                    if t != "1" {
                        return Err(err(
                            format!("line {l2}"),
                            "only 1-component scalars are read",
                        ));
                    }
                    next("LOOKUP_TABLE")?.1
                } else {
                    t
                };
                if !t.eq_ignore_ascii_case("LOOKUP_TABLE") {
                    return Err(err(
                        format!("line {l}"),
                        format!("expected LOOKUP_TABLE, found {t:?}"),
                    ));
                }
                next("the lookup table name")?;
                let mut values = Vec::with_capacity(point_count.min(1 << 20));
                for _ in 0..point_count {
                    values.push(number(next("a scalar value")?)?);
                }
                let wanted = scalar.is_none_or(|s| s == name);
                if wanted && mesh.scalars.is_none() {
                    mesh.scalars = Some(Scalars {
                        name: name.to_string(),
                        values,
                    });
                }
            }
            "METADATA" | "FIELD" | "NORMALS" | "CELL_DATA" => {
                return Err(err(
                    format!("line {line}"),
                    format!("section {key} is not read"),
                ));
            }
            _ => return Err(err(format!("line {line}"), format!("unexpected {key:?}"))),
        }
    }
    if !have_points {
        return Err(err("file", "no POINTS section"));
    }
    if let Some(name) = scalar {
        if mesh.scalars.is_none() {
            return Err(err("file", format!("no SCALARS array named {name}")));
        }
    }
    mesh.validate()?;
    Ok(mesh)
}

/// Writes legacy VTK 3.0 ASCII polydata (shortest round-trip decimals), with the scalar field
/// and the normals as `POINT_DATA`.
pub fn write(mesh: &Mesh) -> Vec<u8> {
    use std::fmt::Write;
    let mut s =
        String::from("# vtk DataFile Version 3.0\nwritten by geocert\nASCII\nDATASET POLYDATA\n");
    let _ = writeln!(s, "POINTS {} double", mesh.vertices.len());
    for v in &mesh.vertices {
        let _ = writeln!(s, "{:?} {:?} {:?}", v[0], v[1], v[2]);
    }
    let _ = writeln!(
        s,
        "POLYGONS {} {}",
        mesh.triangles.len(),
        4 * mesh.triangles.len()
    );
    for t in &mesh.triangles {
        let _ = writeln!(s, "3 {} {} {}", t[0], t[1], t[2]);
    }
    if mesh.scalars.is_some() || mesh.normals.is_some() {
        let _ = writeln!(s, "POINT_DATA {}", mesh.vertices.len());
    }
    if let Some(sc) = &mesh.scalars {
        let _ = writeln!(s, "SCALARS {} double 1\nLOOKUP_TABLE default", sc.name);
        for x in &sc.values {
            let _ = writeln!(s, "{x:?}");
        }
    }
    if let Some(normals) = &mesh.normals {
        let _ = writeln!(s, "NORMALS normals double");
        for v in normals {
            let _ = writeln!(s, "{:?} {:?} {:?}", v[0], v[1], v[2]);
        }
    }
    s.into_bytes()
}
