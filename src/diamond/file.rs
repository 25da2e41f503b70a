//! The `.dmv` file: a supercube-encoded partial DMV `Δs`, versioned, checksummed,
//! little-endian, read back bit for bit.
//!
//! ```text
//! magic "GEOCDMV1" | version u32 = 1 | d u32 | N u32 | value bytes u32 (4: f32, 8: f64)
//! real sides: d × u64 | corner values: 2^d × f64 | supercubes u64 | diamonds u64
//! per supercube, in increasing (scale, origin): scale u8 | origin d × u32 |
//!     flags ⌈(4^d − 2^d)/64⌉ × u64 | per set flag, in type order:
//!     value (f32 or f64) | error f32 | min f32 | max f32
//! FNV-1a 64 of every byte before it: u64
//! ```

use super::dmv::{flag_words, DiamondData, DmvAccess, SupercubeDmv};
use super::{DiamondError, DiamondType, Hierarchy, Point, Supercube, MAX_LEVELS};

const MAGIC: &[u8; 8] = b"GEOCDMV1";
const VERSION: u32 = 1;

/// FNV-1a, 64 bits.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

impl<const D: usize> SupercubeDmv<D> {
    /// The `.dmv` bytes; values are stored as `f32` when every value is an `f32` exactly.
    pub fn to_bytes(&self) -> Vec<u8> {
        let exact_f32 = self
            .data
            .iter()
            .map(|d| d.value)
            .chain(self.corners.iter().copied())
            .all(|v| f64::from(v as f32) == v);
        let mut out = Vec::with_capacity(64 + self.data.len() * 20);
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&VERSION.to_le_bytes());
        out.extend_from_slice(&(D as u32).to_le_bytes());
        out.extend_from_slice(&self.hier.levels().to_le_bytes());
        out.extend_from_slice(&(if exact_f32 { 4u32 } else { 8 }).to_le_bytes());
        for &r in &self.real {
            out.extend_from_slice(&(r as u64).to_le_bytes());
        }
        for &c in &self.corners {
            out.extend_from_slice(&c.to_le_bytes());
        }
        out.extend_from_slice(&(self.keys.len() as u64).to_le_bytes());
        out.extend_from_slice(&(self.data.len() as u64).to_le_bytes());
        let w = flag_words(D);
        for (n, &(scale, origin)) in self.keys.iter().enumerate() {
            out.push(scale as u8);
            for x in origin {
                out.extend_from_slice(&x.to_le_bytes());
            }
            let flags = &self.flags[n * w..(n + 1) * w];
            for f in flags {
                out.extend_from_slice(&f.to_le_bytes());
            }
            let count: u32 = flags.iter().map(|f| f.count_ones()).sum();
            let start = self.start[n] as usize;
            for d in &self.data[start..start + count as usize] {
                if exact_f32 {
                    out.extend_from_slice(&(d.value as f32).to_le_bytes());
                } else {
                    out.extend_from_slice(&d.value.to_le_bytes());
                }
                out.extend_from_slice(&d.error.to_le_bytes());
                out.extend_from_slice(&d.min.to_le_bytes());
                out.extend_from_slice(&d.max.to_le_bytes());
            }
        }
        let sum = fnv1a(&out);
        out.extend_from_slice(&sum.to_le_bytes());
        out
    }

    /// Reads `.dmv` bytes; a truncated, corrupt or inconsistent file is an error naming the
    /// byte offset and what is wrong.
    pub fn from_bytes(bytes: &[u8]) -> Result<SupercubeDmv<D>, DiamondError> {
        let r = Reader { bytes, at: 0 };
        if bytes.len() < 8 + 8 || &bytes[..8] != MAGIC {
            return Err(r.error("not a .dmv file (magic GEOCDMV1 missing)"));
        }
        let body = bytes.len() - 8;
        let stored = u64::from_le_bytes(bytes[body..].try_into().expect("8 bytes"));
        if fnv1a(&bytes[..body]) != stored {
            return Err(DiamondError::File {
                offset: body,
                what: "checksum mismatch: the file is corrupt or truncated".into(),
            });
        }
        let mut r = Reader {
            bytes: &bytes[..body],
            at: 8,
        };
        let version = r.u32()?;
        if version != VERSION {
            return Err(r.error(&format!("version {version}, this reader knows {VERSION}")));
        }
        let d = r.u32()?;
        if d as usize != D {
            return Err(r.error(&format!("a {d}-D DMV, expected {D}-D")));
        }
        let levels = r.u32()?;
        // Refinement runs on the doubled grid (N + 1 levels), so N stays below MAX_LEVELS.
        if levels == 0 || levels >= MAX_LEVELS {
            return Err(r.error(&format!("N = {levels} out of 1..={}", MAX_LEVELS - 1)));
        }
        let hier = Hierarchy::<D>::new(levels)?;
        let value_bytes = r.u32()?;
        if value_bytes != 4 && value_bytes != 8 {
            return Err(r.error(&format!("value size {value_bytes}, expected 4 or 8")));
        }
        let mut real = [0usize; D];
        for x in &mut real {
            let v = r.u64()?;
            if v < 2 || v > u64::from(hier.side()) + 1 {
                return Err(r.error(&format!("real side {v} out of 2..={}", hier.side() + 1)));
            }
            *x = v as usize;
        }
        let mut corners = Vec::with_capacity(1 << D);
        for _ in 0..1 << D {
            corners.push(r.f64_finite()?);
        }
        let ns = r.u64()?;
        let np = r.u64()?;
        let w = flag_words(D);
        let per_cube = 1 + 4 * D + 8 * w;
        let per_diamond = value_bytes as usize + 12;
        let left = (r.bytes.len() - r.at) as u64;
        if ns.saturating_mul(per_cube as u64) + np.saturating_mul(per_diamond as u64) != left {
            return Err(r.error(&format!(
                "{ns} supercubes and {np} diamonds do not fill the {left} bytes left"
            )));
        }
        let types: Vec<DiamondType<D>> = DiamondType::all().collect();
        let mut dmv = SupercubeDmv::empty(hier, real, corners);
        let mut items: Vec<(usize, DiamondData)> = Vec::with_capacity(types.len());
        let mut last: Option<(u32, Point<D>)> = None;
        let mut diamonds = 0u64;
        for _ in 0..ns {
            let scale = u32::from(r.u8()?);
            if scale >= levels {
                return Err(r.error(&format!("supercube scale {scale} >= N = {levels}")));
            }
            let mut origin = [0u32; D];
            for x in &mut origin {
                *x = r.u32()?;
                if *x % (4u32 << scale) != 0 || *x > hier.side() {
                    return Err(r.error(&format!(
                        "supercube origin coordinate {x} is not a multiple of 4h = {} inside the grid",
                        4u32 << scale
                    )));
                }
            }
            if last.is_some_and(|l| l >= (scale, origin)) {
                return Err(r.error("supercubes out of order or repeated"));
            }
            last = Some((scale, origin));
            let mut flags = vec![0u64; w];
            for f in &mut flags {
                *f = r.u64()?;
            }
            let cube = Supercube { origin, scale };
            items.clear();
            for t in 0..w * 64 {
                if flags[t / 64] >> (t % 64) & 1 == 0 {
                    continue;
                }
                let Some(tau) = types.get(t) else {
                    return Err(r.error(&format!("flag {t} beyond the {} types", types.len())));
                };
                if cube.diamond(&hier, *tau).is_err() {
                    return Err(r.error(&format!(
                        "type {t} of supercube {origin:?} at scale {scale} is no diamond of the grid"
                    )));
                }
                let value = if value_bytes == 4 {
                    f64::from(r.f32_finite()?)
                } else {
                    r.f64_finite()?
                };
                let error = r.f32_finite()?;
                let min = r.f32_finite()?;
                let max = r.f32_finite()?;
                if error < 0.0 || min > max {
                    return Err(r.error("a diamond's error is negative or its range empty"));
                }
                items.push((
                    t,
                    DiamondData {
                        value,
                        error,
                        min,
                        max,
                    },
                ));
                diamonds += 1;
            }
            if items.is_empty() {
                return Err(r.error("a supercube without diamonds"));
            }
            dmv.push_cube(scale, origin, &items);
        }
        if diamonds != np {
            return Err(r.error(&format!("{diamonds} diamonds, the header says {np}")));
        }
        // A partial DMV is closed under ancestors (Section 6): every parent of a held diamond
        // is held.
        for &(scale, origin) in &dmv.keys {
            let cube = Supercube { origin, scale };
            for tau in &types {
                let Ok(dia) = cube.diamond(&hier, *tau) else {
                    continue;
                };
                if dmv.data(&dia).is_none() {
                    continue;
                }
                for slot in 0..dia.parent_slots() {
                    if let Some(p) = dia.parent_in_slot(slot) {
                        if dmv.data(&p).is_none() {
                            return Err(DiamondError::File {
                                offset: r.at,
                                what: format!(
                                    "diamond {:?} is held but its parent {:?} is not: not closed under ancestors",
                                    dia.center(),
                                    p.center()
                                ),
                            });
                        }
                    }
                }
            }
        }
        Ok(dmv)
    }
}

struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn error(&self, what: &str) -> DiamondError {
        DiamondError::File {
            offset: self.at,
            what: what.into(),
        }
    }
    fn take<const N: usize>(&mut self) -> Result<[u8; N], DiamondError> {
        let end = self.at.checked_add(N).filter(|&e| e <= self.bytes.len());
        let Some(end) = end else {
            return Err(self.error("truncated"));
        };
        let out = self.bytes[self.at..end].try_into().expect("N bytes");
        self.at = end;
        Ok(out)
    }
    fn u8(&mut self) -> Result<u8, DiamondError> {
        Ok(self.take::<1>()?[0])
    }
    fn u32(&mut self) -> Result<u32, DiamondError> {
        Ok(u32::from_le_bytes(self.take()?))
    }
    fn u64(&mut self) -> Result<u64, DiamondError> {
        Ok(u64::from_le_bytes(self.take()?))
    }
    fn f32_finite(&mut self) -> Result<f32, DiamondError> {
        let v = f32::from_le_bytes(self.take()?);
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.error("a value is not finite"))
        }
    }
    fn f64_finite(&mut self) -> Result<f64, DiamondError> {
        let v = f64::from_le_bytes(self.take()?);
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.error("a value is not finite"))
        }
    }
}

/// A tetrahedral mesh as a legacy-VTK unstructured grid (ASCII, cell type 10), with the point
/// values when given; points are numbered in order of first use.
pub fn write_vtk_tets(
    tets: &[super::Simplex<3>],
    value: impl Fn(&Point<3>) -> Option<f64>,
) -> Vec<u8> {
    use std::fmt::Write;
    let mut ids: std::collections::HashMap<Point<3>, usize> = std::collections::HashMap::new();
    let mut points: Vec<Point<3>> = Vec::new();
    let cells: Vec<[usize; 4]> = tets
        .iter()
        .map(|t| {
            std::array::from_fn(|j| {
                let p = t.vertices()[j];
                *ids.entry(p).or_insert_with(|| {
                    points.push(p);
                    points.len() - 1
                })
            })
        })
        .collect();
    let mut s = String::new();
    let _ = writeln!(s, "# vtk DataFile Version 3.0\ngeocert diamond current mesh\nASCII\nDATASET UNSTRUCTURED_GRID");
    let _ = writeln!(s, "POINTS {} double", points.len());
    for p in &points {
        let _ = writeln!(s, "{} {} {}", p[0], p[1], p[2]);
    }
    let _ = writeln!(s, "CELLS {} {}", cells.len(), cells.len() * 5);
    for c in &cells {
        let _ = writeln!(s, "4 {} {} {} {}", c[0], c[1], c[2], c[3]);
    }
    let _ = writeln!(s, "CELL_TYPES {}", cells.len());
    for _ in &cells {
        let _ = writeln!(s, "10");
    }
    let values: Option<Vec<f64>> = points.iter().map(&value).collect();
    if let Some(values) = values {
        let _ = writeln!(
            s,
            "POINT_DATA {}\nSCALARS value double 1\nLOOKUP_TABLE default",
            points.len()
        );
        for v in values {
            let _ = writeln!(s, "{v}");
        }
    }
    s.into_bytes()
}
