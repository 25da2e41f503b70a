//! Approximation quality of a decimated height field or planar FEM mesh: at every node of
//! the original, the difference between its height (z) or scalar and the decimated mesh's
//! linear interpolant at the same xy position (the node located by a uniform grid over the
//! decimated triangles' xy bounding boxes).

use crate::mesh::Mesh;

/// Max and RMS errors over the original's nodes.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct Errors {
    pub max_height: f64,
    pub rms_height: f64,
    /// `None` without a scalar field.
    pub max_scalar: Option<f64>,
    pub rms_scalar: Option<f64>,
    /// Nodes outside every decimated triangle in xy (0 for a decimation that keeps the
    /// border; then the node is measured against the nearest triangle found).
    pub unlocated: usize,
}

/// Interpolation errors of `decimated` against `original`, both in the xy plane. The
/// decimated mesh's scalar field is read when the original has one.
pub fn xy_errors(original: &Mesh, decimated: &Mesh) -> Errors {
    let tris = &decimated.triangles;
    let pv = &decimated.vertices;
    if tris.is_empty() {
        return Errors::default();
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in pv {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let cells = ((tris.len() as f64).sqrt().ceil() as usize).clamp(1, 2048);
    let size = [
        ((hi[0] - lo[0]) / cells as f64).max(f64::MIN_POSITIVE),
        ((hi[1] - lo[1]) / cells as f64).max(f64::MIN_POSITIVE),
    ];
    let cell =
        |x: f64, k: usize| (((x - lo[k]) / size[k]).floor().max(0.0) as usize).min(cells - 1);
    let mut grid: Vec<Vec<u32>> = vec![Vec::new(); cells * cells];
    for (t, tri) in tris.iter().enumerate() {
        let ps = tri.map(|i| pv[i as usize]);
        let (x0, x1) = (
            ps.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min),
            ps.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max),
        );
        let (y0, y1) = (
            ps.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min),
            ps.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max),
        );
        for j in cell(y0, 1)..=cell(y1, 1) {
            for i in cell(x0, 0)..=cell(x1, 0) {
                grid[j * cells + i].push(t as u32);
            }
        }
    }
    let scalars = original.scalars.as_ref().zip(decimated.scalars.as_ref());
    let mut e = Errors::default();
    let (mut sum_h, mut sum_s, mut max_s) = (0.0, 0.0, 0.0f64);
    for (v, p) in original.vertices.iter().enumerate() {
        let bucket = &grid[cell(p[1], 1) * cells + cell(p[0], 0)];
        let mut best: Option<(f64, u32, [f64; 3])> = None;
        for &t in bucket {
            let [a, b, c] = tris[t as usize].map(|i| pv[i as usize]);
            let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            if area <= 0.0 {
                continue;
            }
            let l0 = ((b[0] - p[0]) * (c[1] - p[1]) - (b[1] - p[1]) * (c[0] - p[0])) / area;
            let l1 = ((c[0] - p[0]) * (a[1] - p[1]) - (c[1] - p[1]) * (a[0] - p[0])) / area;
            let l2 = 1.0 - l0 - l1;
            let min = l0.min(l1).min(l2);
            if best.is_none_or(|b| min > b.0) {
                best = Some((min, t, [l0, l1, l2]));
            }
        }
        let Some((min, t, l)) = best else {
            e.unlocated += 1;
            continue;
        };
        if min < -1e-9 {
            e.unlocated += 1;
        }
        let tri = tris[t as usize];
        let z: f64 = (0..3).map(|k| l[k] * pv[tri[k] as usize][2]).sum();
        let dh = (p[2] - z).abs();
        e.max_height = e.max_height.max(dh);
        sum_h += dh * dh;
        if let Some((so, sd)) = scalars {
            let f: f64 = (0..3).map(|k| l[k] * sd.values[tri[k] as usize]).sum();
            let ds = (so.values[v] - f).abs();
            max_s = max_s.max(ds);
            sum_s += ds * ds;
        }
    }
    let n = original.vertices.len().max(1) as f64;
    e.rms_height = (sum_h / n).sqrt();
    if scalars.is_some() {
        e.max_scalar = Some(max_s);
        e.rms_scalar = Some((sum_s / n).sqrt());
    }
    e
}
