//! Polygon faces (quads and n-gons in OBJ, PLY and VTK files) as triangles: ear clipping in
//! the coordinate plane most nearly perpendicular to the face's Newell normal, with exact
//! orientation signs (Shewchuk's predicates, the `robust` crate).
//!
//! A convex face becomes the fan from its first vertex (what most readers produce); a
//! non-convex planar face is cut into ears that lie inside it. Every face of `n` vertices
//! gives `n − 2` triangles over its own edges and diagonals, in its own winding, so a
//! manifold polygon mesh gives a manifold triangle mesh with the same orientation. A face
//! with no proper ear (self-intersecting or degenerate in that plane) is still cut, at the
//! first vertex that turns the right way, so that it always yields `n − 2` triangles.

use robust::{orient2d, Coord};

/// The most vertices a face may have (ear clipping costs up to `O(n³)` orientation tests).
pub(crate) const MAX_FACE_VERTICES: usize = 1024;

/// Appends the triangles of the face `face` (vertex indices in order, counter-clockwise
/// about its outward normal) to `out`. A face with an index outside `vertices` (a read
/// error the mesh's validation reports) becomes the fan from its first vertex.
///
/// # Errors
/// A face with fewer than three or more than [`MAX_FACE_VERTICES`] vertices: the count.
pub(crate) fn triangulate(
    vertices: &[[f64; 3]],
    face: &[u32],
    out: &mut Vec<[u32; 3]>,
) -> Result<(), String> {
    let n = face.len();
    if n < 3 {
        return Err(format!("a face with {n} vertices"));
    }
    if n > MAX_FACE_VERTICES {
        return Err(format!(
            "a face with {n} vertices (at most {MAX_FACE_VERTICES} are triangulated)"
        ));
    }
    if n == 3 {
        out.push([face[0], face[1], face[2]]);
        return Ok(());
    }
    let fan = |out: &mut Vec<[u32; 3]>| {
        for k in 1..n - 1 {
            out.push([face[0], face[k], face[k + 1]]);
        }
    };
    let Some(points) = face
        .iter()
        .map(|&i| vertices.get(i as usize).copied())
        .collect::<Option<Vec<[f64; 3]>>>()
    else {
        fan(out);
        return Ok(());
    };
    let Some(plane) = projection(&points) else {
        fan(out);
        return Ok(());
    };
    let p: Vec<Coord<f64>> = points.iter().map(|&x| plane(x)).collect();
    let turn = |a: usize, b: usize, c: usize| orient2d(p[a], p[b], p[c]);
    let mut left: Vec<usize> = (0..n).collect();
    while left.len() > 3 {
        let m = left.len();
        let corner = |k: usize| (left[(k + m - 1) % m], left[k], left[(k + 1) % m]);
        // An ear: a convex corner whose triangle holds no other remaining vertex (on its
        // boundary counts as inside, unless the vertex sits on a corner of it).
        let is_ear = |k: usize| {
            let (a, b, c) = corner(k);
            turn(a, b, c) > 0.0
                && left.iter().all(|&q| {
                    q == a
                        || q == b
                        || q == c
                        || [a, b, c].iter().any(|&x| p[x] == p[q])
                        || turn(a, b, q) < 0.0
                        || turn(b, c, q) < 0.0
                        || turn(c, a, q) < 0.0
                })
        };
        // From the second vertex on, so that a convex face is the fan from its first.
        let k = (1..=m)
            .map(|k| k % m)
            .find(|&k| is_ear(k))
            .or_else(|| {
                (1..=m).map(|k| k % m).find(|&k| {
                    let (a, b, c) = corner(k);
                    turn(a, b, c) >= 0.0
                })
            })
            .unwrap_or(1);
        let (a, b, c) = corner(k);
        out.push([face[a], face[b], face[c]]);
        left.remove(k);
    }
    out.push([face[left[0]], face[left[1]], face[left[2]]]);
    Ok(())
}

/// The map to the coordinate plane most nearly perpendicular to the Newell normal of the
/// polygon `points`, oriented so that its winding about that normal is counter-clockwise in
/// the plane; `None` when the normal is zero or not finite.
fn projection(points: &[[f64; 3]]) -> Option<impl Fn([f64; 3]) -> Coord<f64>> {
    let o = points[0];
    let d = |x: [f64; 3]| [x[0] - o[0], x[1] - o[1], x[2] - o[2]];
    let mut normal = [0.0; 3];
    for (k, &x) in points.iter().enumerate() {
        let (a, b) = (d(x), d(points[(k + 1) % points.len()]));
        let c = super::cross(a, b);
        for (s, c) in normal.iter_mut().zip(c) {
            *s += c;
        }
    }
    let axis = (0..3).max_by(|&i, &j| normal[i].abs().total_cmp(&normal[j].abs()))?;
    let up = normal[axis];
    if !(up.is_finite() && up != 0.0) {
        return None;
    }
    // The two other axes in cyclic order (x, y about z; y, z about x; z, x about y), swapped
    // when the normal points down that axis.
    let (mut i, mut j) = ((axis + 1) % 3, (axis + 2) % 3);
    if up < 0.0 {
        std::mem::swap(&mut i, &mut j);
    }
    Some(move |x: [f64; 3]| Coord { x: x[i], y: x[j] })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Twice the triangles' summed area vector (as [`crate::mesh::area_vector`] gives it).
    fn area(vertices: &[[f64; 3]], tris: &[[u32; 3]]) -> [f64; 3] {
        let mut s = [0.0; 3];
        for t in tris {
            let [a, b, c] = t.map(|i| vertices[i as usize]);
            let v = crate::mesh::area_vector(a, b, c);
            for k in 0..3 {
                s[k] += v[k];
            }
        }
        s
    }

    #[test]
    fn convex_faces_fan_and_concave_faces_cut_into_ears_inside() {
        // A convex quad tilted out of every coordinate plane: the fan from vertex 0.
        let quad = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.5],
            [1.0, 1.0, 1.0],
            [0.0, 1.0, 0.5],
        ];
        let mut out = Vec::new();
        triangulate(&quad, &[0, 1, 2, 3], &mut out).unwrap();
        assert_eq!(out, vec![[0, 1, 2], [0, 2, 3]]);
        // An arrowhead (reflex at vertex 2), in both windings: the ears lie inside it, so
        // every triangle turns the face's way and their areas add up to the face's.
        let arrow = [
            [0.0, 0.0, 0.0],
            [2.0, 1.0, 0.0],
            [0.5, 1.0, 0.0],
            [-1.0, 2.0, 0.0],
        ];
        for order in [[0u32, 1, 2, 3], [3, 2, 1, 0]] {
            let mut out = Vec::new();
            triangulate(&arrow, &order, &mut out).unwrap();
            assert_eq!(out.len(), 2);
            let twice_face_area: f64 = {
                let mut s = 0.0;
                for k in 0..4 {
                    let (a, b) = (arrow[order[k] as usize], arrow[order[(k + 1) % 4] as usize]);
                    s += a[0] * b[1] - a[1] * b[0];
                }
                s
            };
            let got = area(&arrow, &out)[2];
            assert!(
                (got - twice_face_area).abs() < 1e-12,
                "{got} vs {twice_face_area}"
            );
            // Every triangle turns the face's way (an ear outside would turn the other).
            for t in &out {
                let [a, b, c] = t.map(|i| arrow[i as usize]);
                let z = crate::mesh::area_vector(a, b, c)[2];
                assert!(z * twice_face_area > 0.0, "{out:?}");
            }
        }
        // A hexagon with a reflex vertex: n − 2 triangles, area preserved.
        let l = [
            [0.0, 0.0, 1.0],
            [2.0, 0.0, 1.0],
            [2.0, 1.0, 1.0],
            [1.0, 1.0, 1.0],
            [1.0, 2.0, 1.0],
            [0.0, 2.0, 1.0],
        ];
        let mut out = Vec::new();
        triangulate(&l, &[0, 1, 2, 3, 4, 5], &mut out).unwrap();
        assert_eq!(out.len(), 4);
        assert!((area(&l, &out)[2] - 6.0).abs() < 1e-12);
        // Too few vertices is an error; a degenerate face still gives n − 2 triangles.
        assert!(triangulate(&l, &[0, 1], &mut out).is_err());
        let mut out = Vec::new();
        triangulate(&[[0.0; 3]; 5], &[0, 1, 2, 3, 4], &mut out).unwrap();
        assert_eq!(out.len(), 3);
    }
}
