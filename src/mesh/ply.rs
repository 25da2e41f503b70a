//! PLY (Turk's polygon file format): `ascii`, `binary_little_endian` and `binary_big_endian`.
//! Reads the `vertex` element's `x y z` (and optionally one named scalar property) and the
//! `face` element's index list (`vertex_indices` or `vertex_index`); other elements and
//! properties are skipped. Faces of more than three vertices are triangulated (module
//! `polygon`).

use super::{Mesh, MeshError, Scalars};

#[derive(Clone, Copy, Debug, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }
    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
    fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }
}

#[derive(Clone, Debug)]
enum Property {
    Scalar {
        name: String,
        ty: Scalar,
    },
    List {
        name: String,
        count: Scalar,
        item: Scalar,
    },
}

impl Property {
    fn name(&self) -> &str {
        match self {
            Property::Scalar { name, .. } | Property::List { name, .. } => name,
        }
    }
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: usize,
    props: Vec<Property>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Encoding {
    Ascii,
    Little,
    Big,
}

fn err(place: impl Into<String>, why: impl Into<String>) -> MeshError {
    MeshError::Parse {
        format: "PLY",
        place: place.into(),
        why: why.into(),
    }
}

/// Largest element count accepted from a header (guards allocation on hostile input).
const MAX_COUNT: usize = 1 << 28;

fn parse_header(bytes: &[u8]) -> Result<(Encoding, Vec<Element>, usize), MeshError> {
    let end_marker = b"end_header";
    let pos = bytes
        .windows(end_marker.len())
        .position(|w| w == end_marker)
        .ok_or_else(|| err("header", "no end_header line"))?;
    let mut body = pos + end_marker.len();
    // The header ends at the newline after end_header (\n or \r\n).
    while body < bytes.len() && bytes[body] != b'\n' {
        body += 1;
    }
    body += 1;
    let text = std::str::from_utf8(&bytes[..pos]).map_err(|_| err("header", "not ASCII text"))?;
    let mut lines = text.lines().map(str::trim).enumerate();
    match lines.next() {
        Some((_, "ply")) => {}
        _ => return Err(err("line 1", "does not start with \"ply\"")),
    }
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    for (i, line) in lines {
        let place = format!("header line {}", i + 1);
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            [] | ["comment", ..] | ["obj_info", ..] => {}
            ["format", kind, version] => {
                if *version != "1.0" {
                    return Err(err(place, format!("unsupported version {version}")));
                }
                encoding = Some(match *kind {
                    "ascii" => Encoding::Ascii,
                    "binary_little_endian" => Encoding::Little,
                    "binary_big_endian" => Encoding::Big,
                    other => return Err(err(place, format!("unknown format {other}"))),
                });
            }
            ["element", name, count] => {
                let count: usize = count
                    .parse()
                    .ok()
                    .filter(|c| *c <= MAX_COUNT)
                    .ok_or_else(|| err(&place, format!("bad element count {count}")))?;
                elements.push(Element {
                    name: name.to_string(),
                    count,
                    props: Vec::new(),
                });
            }
            ["property", "list", count, item, name] => {
                let el = elements
                    .last_mut()
                    .ok_or_else(|| err(&place, "property before any element"))?;
                let count = Scalar::parse(count)
                    .filter(|c| c.is_integer())
                    .ok_or_else(|| err(&place, format!("bad list count type {count}")))?;
                let item = Scalar::parse(item)
                    .ok_or_else(|| err(&place, format!("unknown type {item}")))?;
                el.props.push(Property::List {
                    name: name.to_string(),
                    count,
                    item,
                });
            }
            ["property", ty, name] => {
                let el = elements
                    .last_mut()
                    .ok_or_else(|| err(&place, "property before any element"))?;
                let ty =
                    Scalar::parse(ty).ok_or_else(|| err(&place, format!("unknown type {ty}")))?;
                el.props.push(Property::Scalar {
                    name: name.to_string(),
                    ty,
                });
            }
            _ => return Err(err(place, format!("cannot read {line:?}"))),
        }
    }
    let encoding = encoding.ok_or_else(|| err("header", "no format line"))?;
    Ok((encoding, elements, body.min(bytes.len())))
}

/// A cursor over the body: ascii tokens or binary values.
struct Body<'a> {
    bytes: &'a [u8],
    at: usize,
    encoding: Encoding,
}

impl Body<'_> {
    fn next(&mut self, ty: Scalar, place: &dyn Fn() -> String) -> Result<f64, MeshError> {
        match self.encoding {
            Encoding::Ascii => {
                while self.at < self.bytes.len() && self.bytes[self.at].is_ascii_whitespace() {
                    self.at += 1;
                }
                let start = self.at;
                while self.at < self.bytes.len() && !self.bytes[self.at].is_ascii_whitespace() {
                    self.at += 1;
                }
                if start == self.at {
                    return Err(err(place(), "file ends early"));
                }
                let tok = std::str::from_utf8(&self.bytes[start..self.at]).unwrap_or("?");
                let v: f64 = tok
                    .parse()
                    .map_err(|_| err(place(), format!("not a number: {tok:?}")))?;
                if ty.is_integer() && v.fract() != 0.0 {
                    return Err(err(place(), format!("{tok:?} is not an integer")));
                }
                Ok(v)
            }
            Encoding::Little | Encoding::Big => {
                let n = ty.size();
                let raw = self
                    .bytes
                    .get(self.at..self.at + n)
                    .ok_or_else(|| err(place(), "file ends early"))?;
                self.at += n;
                let mut buf = [0u8; 8];
                buf[..n].copy_from_slice(raw);
                if self.encoding == Encoding::Big {
                    buf[..n].reverse();
                }
                Ok(match ty {
                    Scalar::I8 => buf[0] as i8 as f64,
                    Scalar::U8 => buf[0] as f64,
                    Scalar::I16 => i16::from_le_bytes([buf[0], buf[1]]) as f64,
                    Scalar::U16 => u16::from_le_bytes([buf[0], buf[1]]) as f64,
                    Scalar::I32 => i32::from_le_bytes([buf[0], buf[1], buf[2], buf[3]]) as f64,
                    Scalar::U32 => u32::from_le_bytes([buf[0], buf[1], buf[2], buf[3]]) as f64,
                    Scalar::F32 => f32::from_le_bytes([buf[0], buf[1], buf[2], buf[3]]) as f64,
                    Scalar::F64 => f64::from_le_bytes(buf),
                })
            }
        }
    }
}

/// Reads a PLY mesh; `scalar` names a vertex property to read as the nodal field.
pub fn read(bytes: &[u8], scalar: Option<&str>) -> Result<Mesh, MeshError> {
    let (encoding, elements, body) = parse_header(bytes)?;
    let mut cur = Body {
        bytes,
        at: body,
        encoding,
    };
    let mut mesh = Mesh::default();
    let mut values = Vec::new();
    let mut saw_vertex = false;
    // Faces as read (their vertex indices one after another, and each face's count):
    // triangulated once every element is read, since a face may come before the vertices.
    let mut face_indices: Vec<u32> = Vec::new();
    let mut face_sizes: Vec<u32> = Vec::new();
    for el in &elements {
        let is_vertex = el.name == "vertex";
        let is_face = el.name == "face";
        if is_vertex {
            saw_vertex = true;
            for axis in ["x", "y", "z"] {
                if !el
                    .props
                    .iter()
                    .any(|p| matches!(p, Property::Scalar { name, .. } if name == axis))
                {
                    return Err(err(
                        "header",
                        format!("vertex element has no scalar property {axis}"),
                    ));
                }
            }
            if let Some(s) = scalar {
                if !el.props.iter().any(|p| p.name() == s) {
                    return Err(err("header", format!("vertex element has no property {s}")));
                }
            }
            mesh.vertices.reserve(el.count.min(1 << 20));
        }
        for e in 0..el.count {
            let place = || format!("{} {e}", el.name);
            let mut v = [0.0f64; 3];
            let mut value = 0.0;
            for prop in &el.props {
                match prop {
                    Property::Scalar { name, ty } => {
                        let x = cur.next(*ty, &place)?;
                        if is_vertex {
                            match name.as_str() {
                                "x" => v[0] = x,
                                "y" => v[1] = x,
                                "z" => v[2] = x,
                                _ => {}
                            }
                            if Some(name.as_str()) == scalar {
                                value = x;
                            }
                        }
                    }
                    Property::List { name, count, item } => {
                        let n = cur.next(*count, &place)?;
                        if !(0.0..=1e6).contains(&n) {
                            return Err(err(place(), format!("bad list length {n}")));
                        }
                        let n = n as usize;
                        let wanted =
                            is_face && (name == "vertex_indices" || name == "vertex_index");
                        if wanted && n < 3 {
                            return Err(err(place(), format!("a face with {n} vertices")));
                        }
                        for _ in 0..n {
                            let x = cur.next(*item, &place)?;
                            if wanted {
                                if !item.is_integer() || x < 0.0 || x > u32::MAX as f64 {
                                    return Err(err(place(), format!("bad vertex index {x}")));
                                }
                                face_indices.push(x as u32);
                            }
                        }
                        if wanted {
                            face_sizes.push(n as u32);
                        }
                    }
                }
            }
            if is_vertex {
                mesh.vertices.push(v);
                if scalar.is_some() {
                    values.push(value);
                }
            }
        }
    }
    if !saw_vertex {
        return Err(err("header", "no vertex element"));
    }
    mesh.triangles.reserve(face_indices.len() / 3);
    let mut at = 0;
    for (f, &n) in face_sizes.iter().enumerate() {
        let face = &face_indices[at..at + n as usize];
        at += n as usize;
        super::polygon::triangulate(&mesh.vertices, face, &mut mesh.triangles)
            .map_err(|why| err(format!("face {f}"), why))?;
    }
    if let Some(name) = scalar {
        mesh.scalars = Some(Scalars {
            name: name.to_string(),
            values,
        });
    }
    mesh.validate()?;
    Ok(mesh)
}

/// Writes `x y z` as doubles (then the scalar field and `nx ny nz`, if any) and `uint` triangle lists;
/// `binary` selects `binary_little_endian`, else `ascii` with shortest round-trip decimals.
pub fn write(mesh: &Mesh, binary: bool) -> Vec<u8> {
    let mut out = Vec::new();
    let mut header = format!(
        "ply\nformat {} 1.0\ncomment written by geocert\nelement vertex {}\nproperty double x\nproperty double y\nproperty double z\n",
        if binary { "binary_little_endian" } else { "ascii" },
        mesh.vertices.len()
    );
    if let Some(s) = &mesh.scalars {
        header += &format!("property double {}\n", s.name);
    }
    if mesh.normals.is_some() {
        header += "property double nx\nproperty double ny\nproperty double nz\n";
    }
    header += &format!(
        "element face {}\nproperty list uchar uint vertex_indices\nend_header\n",
        mesh.triangles.len()
    );
    out.extend_from_slice(header.as_bytes());
    let scalar = |i: usize| mesh.scalars.as_ref().map(|s| s.values[i]);
    let normal = |i: usize| mesh.normals.as_ref().map(|n| n[i]).into_iter().flatten();
    if binary {
        for (i, v) in mesh.vertices.iter().enumerate() {
            for x in v.iter().copied().chain(scalar(i)).chain(normal(i)) {
                out.extend_from_slice(&x.to_le_bytes());
            }
        }
        for t in &mesh.triangles {
            out.push(3);
            for i in t {
                out.extend_from_slice(&i.to_le_bytes());
            }
        }
    } else {
        use std::fmt::Write;
        let mut s = String::new();
        for (i, v) in mesh.vertices.iter().enumerate() {
            let _ = write!(s, "{:?} {:?} {:?}", v[0], v[1], v[2]);
            for x in scalar(i).into_iter().chain(normal(i)) {
                let _ = write!(s, " {x:?}");
            }
            s.push('\n');
        }
        for t in &mesh.triangles {
            let _ = writeln!(s, "3 {} {} {}", t[0], t[1], t[2]);
        }
        out.extend_from_slice(s.as_bytes());
    }
    out
}
