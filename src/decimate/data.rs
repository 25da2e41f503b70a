//! Built-in inputs: regular height-field grids like the paper's Table 1 (10k to 1M nodes) and
//! a steel plate with a centred hole under uniaxial tension carrying the analytic Kirsch
//! stress field, meshed like the paper's Fig. 9 (about 15.5k nodes, 30k triangles).

use crate::mesh::{Mesh, Scalars};

/// The terrain of the height grids: two ridges, a hill and a ripple on `[0, 1]²`.
pub fn terrain(x: f64, y: f64) -> f64 {
    use std::f64::consts::PI;
    0.15 * (3.0 * PI * x).sin() * (2.0 * PI * y).cos()
        + 0.3 * (-((x - 0.35).powi(2) + (y - 0.6).powi(2)) / 0.02).exp()
        + 0.02 * (20.0 * x + 7.0 * y).sin()
}

/// A `side × side` grid of nodes on `[0, 1]²` with heights from [`terrain`], each square
/// cut along the same diagonal, triangles counter-clockwise in xy (Fig. 7a is `side = 100`).
pub fn height_grid(side: usize) -> Mesh {
    let side = side.max(2);
    let step = 1.0 / (side - 1) as f64;
    let mut mesh = Mesh::default();
    for j in 0..side {
        for i in 0..side {
            let (x, y) = (i as f64 * step, j as f64 * step);
            mesh.vertices.push([x, y, terrain(x, y)]);
        }
    }
    mesh.triangles = grid_triangles(side, side);
    mesh
}

/// The triangles of an `nx × ny` grid of nodes numbered row by row (x fastest), each square
/// cut along the diagonal from its lowest to its highest node, counter-clockwise in xy.
pub fn grid_triangles(nx: usize, ny: usize) -> Vec<[u32; 3]> {
    let id = |i: usize, j: usize| (j * nx + i) as u32;
    let mut triangles = Vec::with_capacity(2 * nx.saturating_sub(1) * ny.saturating_sub(1));
    for j in 0..ny.saturating_sub(1) {
        for i in 0..nx.saturating_sub(1) {
            triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    triangles
}

/// The plate of [`kirsch_plate`]: width, height, hole radius (mm) and remote stress (MPa).
pub const PLATE_WIDTH: f64 = 100.0;
/// The plate's height (Fig. 9).
pub const PLATE_HEIGHT: f64 = 200.0;
/// The hole's radius.
pub const HOLE_RADIUS: f64 = 10.0;
/// The remote tension.
pub const REMOTE_STRESS: f64 = 100.0;

/// Kirsch's solution for an infinite plate with a circular hole of radius `a` under remote
/// uniaxial stress `s`, at polar coordinates `(r, θ)` with `θ` measured from the load axis:
/// `(σ_rr, σ_θθ, σ_rθ)`. At the hole's edge `σ_θθ = s (1 − 2 cos 2θ)`, `3s` across the load.
pub fn kirsch(s: f64, a: f64, r: f64, theta: f64) -> (f64, f64, f64) {
    let q2 = (a / r).powi(2);
    let q4 = q2 * q2;
    let (c2, s2) = ((2.0 * theta).cos(), (2.0 * theta).sin());
    let rr = 0.5 * s * (1.0 - q2) + 0.5 * s * (1.0 + 3.0 * q4 - 4.0 * q2) * c2;
    let tt = 0.5 * s * (1.0 + q2) - 0.5 * s * (1.0 + 3.0 * q4) * c2;
    let rt = -0.5 * s * (1.0 - 3.0 * q4 + 2.0 * q2) * s2;
    (rr, tt, rt)
}

/// The von Mises equivalent stress of a plane stress state in polar components.
pub fn von_mises(rr: f64, tt: f64, rt: f64) -> f64 {
    (rr * rr - rr * tt + tt * tt + 3.0 * rt * rt).sqrt()
}

/// A `PLATE_WIDTH × PLATE_HEIGHT` plate in the xy plane, centred at the origin, with a hole
/// of radius `HOLE_RADIUS`, loaded along y; nodal field `von_mises` from [`kirsch`].
/// `around` nodes around the hole (a multiple of 6: the plate's perimeter gets them in
/// proportion, corners included) and `layers` rings of nodes from the hole to the
/// perimeter, graded towards the hole. `kirsch_plate(306, 51)` gives 15,606 nodes and 30,600
/// triangles, the size of the paper's Fig. 9 model (15,559 / 30,458).
pub fn kirsch_plate(around: usize, layers: usize) -> Mesh {
    let around = (around / 6).max(1) * 6;
    let layers = layers.max(2);
    let (w, h) = (PLATE_WIDTH / 2.0, PLATE_HEIGHT / 2.0);
    // Perimeter points counter-clockwise from (w, -h): n_w per width side, 2 n_w per height.
    let nw = around / 6;
    let nh = 2 * nw;
    let mut outer = Vec::with_capacity(around);
    let side = |from: [f64; 2], to: [f64; 2], n: usize, out: &mut Vec<[f64; 2]>| {
        for k in 0..n {
            let t = k as f64 / n as f64;
            out.push([
                from[0] + t * (to[0] - from[0]),
                from[1] + t * (to[1] - from[1]),
            ]);
        }
    };
    side([w, -h], [w, h], nh, &mut outer);
    side([w, h], [-w, h], nw, &mut outer);
    side([-w, h], [-w, -h], nh, &mut outer);
    side([-w, -h], [w, -h], nw, &mut outer);
    let mut mesh = Mesh::default();
    let mut field = Vec::new();
    for j in 0..layers {
        let t = (j as f64 / (layers - 1) as f64).powf(1.6);
        for o in &outer {
            let phi = o[1].atan2(o[0]);
            let c = [HOLE_RADIUS * phi.cos(), HOLE_RADIUS * phi.sin()];
            let p = [c[0] + t * (o[0] - c[0]), c[1] + t * (o[1] - c[1])];
            mesh.vertices.push([p[0], p[1], 0.0]);
            let r = p[0].hypot(p[1]).max(HOLE_RADIUS);
            // θ from the load axis (y).
            let theta = p[0].atan2(p[1]);
            let (rr, tt, rt) = kirsch(REMOTE_STRESS, HOLE_RADIUS, r, theta);
            field.push(von_mises(rr, tt, rt));
        }
    }
    let id = |i: usize, j: usize| (j * around + i % around) as u32;
    let area = |m: &Mesh, t: [u32; 3]| {
        let [a, b, c] = t.map(|i| m.vertices[i as usize]);
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    };
    for j in 0..layers - 1 {
        for i in 0..around {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            // Counter-clockwise in xy: outward (j + 1) is to the right of the ring's direction.
            let one = [[a, c, b], [a, d, c]];
            let other = [[a, d, b], [b, d, c]];
            let worst = |ts: &[[u32; 3]; 2]| area(&mesh, ts[0]).min(area(&mesh, ts[1]));
            let pick = if worst(&one) >= worst(&other) {
                one
            } else {
                other
            };
            mesh.triangles.extend_from_slice(&pick);
        }
    }
    mesh.scalars = Some(Scalars {
        name: "von_mises".into(),
        values: field,
    });
    mesh
}

/// The plate at the paper's size (Fig. 9).
pub fn paper_plate() -> Mesh {
    kirsch_plate(306, 51)
}

/// A wheel: a centre node joined to `spokes` inner-ring nodes, and an outer ring (the border),
/// with integer scalars named `s`: 5 at the centre and the inner ring (so that the centre, at
/// 0 by the scalar criterion, goes first with its whole ring), varied on the outer ring. For
/// tests of large holes: with more than 16 spokes the centre's cut is too large to pack, with
/// more than 64 it passes the small ear cutter and the fan lists' inline capacity.
pub fn wheel(spokes: u32) -> Mesh {
    let mut vertices = vec![[0.0, 0.0, 0.0]];
    let mut values = vec![5.0];
    for ring in 1..=2u32 {
        for k in 0..spokes {
            let t = (k as f64 + 0.5 * (ring - 1) as f64) * std::f64::consts::TAU / spokes as f64;
            let r = ring as f64;
            vertices.push([r * t.cos(), r * t.sin(), 0.0]);
            values.push(if ring == 1 {
                5.0
            } else {
                ((k * 7) % 11) as f64
            });
        }
    }
    let inner = |k: u32| 1 + k % spokes;
    let outer = |k: u32| 1 + spokes + k % spokes;
    let triangles = (0..spokes)
        .flat_map(|k| {
            [
                [0, inner(k), inner(k + 1)],
                [inner(k), outer(k), inner(k + 1)],
                [inner(k + 1), outer(k), outer(k + 1)],
            ]
        })
        .collect();
    Mesh {
        normals: None,
        vertices,
        triangles,
        scalars: Some(Scalars {
            name: "s".into(),
            values,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids_and_plate_are_valid_planar_meshes() {
        let g = height_grid(100);
        assert_eq!(g.vertices.len(), 10_000);
        assert_eq!(g.triangles.len(), 2 * 99 * 99);
        assert_eq!(g.check_manifold().unwrap(), 4 * 99);
        let p = paper_plate();
        assert_eq!(p.vertices.len(), 15_606);
        assert_eq!(p.triangles.len(), 30_600);
        let boundary = p.check_manifold().unwrap();
        assert_eq!(boundary, 2 * 306);
        assert_eq!(p.euler_characteristic(), 0, "an annulus");
        for t in &p.triangles {
            let [a, b, c] = t.map(|i| p.vertices[i as usize]);
            assert!((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0.0);
        }
        // Stress concentration 3σ at the hole's edge across the load, σ far away along it.
        let (rr, tt, rt) = kirsch(100.0, 10.0, 10.0, std::f64::consts::FRAC_PI_2);
        assert!((von_mises(rr, tt, rt) - 300.0).abs() < 1e-9);
        let (rr, tt, rt) = kirsch(100.0, 10.0, 1e6, 0.0);
        assert!((von_mises(rr, tt, rt) - 100.0).abs() < 1e-6);
    }
}
