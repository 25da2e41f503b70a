//! Local coordinates for meshes far from the origin (a scan in georeferenced coordinates, a
//! part placed in a large assembly): the decimation runs on the mesh translated exactly to
//! near its bounding box's centre, and its outcome is translated back.
//!
//! The `f64` heuristics (quadric errors, plane fits, the facing test's slack) lose about
//! `log₂(|x| / size)` bits when the coordinates are large against the mesh: a sphere of
//! radius 0.5 at `(5·10⁵, 4.2·10⁶, 120)` decimated to 5 % came out 7× farther from its
//! original than the same sphere at the origin, one of radius 0.005 there 80× farther.
//! Validity decisions are exact and do not care; the values the queue orders by do.
//!
//! The translation is exact by Sterbenz's lemma: on an axis whose coordinates all lie in
//! `[lo, hi]` with `0 < lo` and `hi ≤ 2·lo` (or the mirror image below zero), the shift `c`
//! is a float in `[lo, hi]`, so `c/2 ≤ x ≤ 2c` for every coordinate `x` and `x − c` is
//! exact; so is `(x − c) + c = x` on the way back. Other axes are not shifted (a shift there
//! would gain at most a factor of two). The fit's moved nodes are rounded in the local frame
//! to points whose translation back is exact too ([`Origin::snap`]), so the history records
//! where they really are.

use crate::mesh::Mesh;

/// A per-axis translation `c` (zero on axes left alone): local = original − c.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Origin(pub(crate) [f64; 3]);

impl Origin {
    /// The shift for `vertices` (module docs); the default (none) when no axis qualifies.
    pub(crate) fn for_vertices(vertices: &[[f64; 3]]) -> Origin {
        let mut c = [0.0; 3];
        for (k, ck) in c.iter_mut().enumerate() {
            let (lo, hi) = vertices
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                    (lo.min(v[k]), hi.max(v[k]))
                });
            if !(lo.is_finite() && hi.is_finite()) {
                continue;
            }
            // Mirror a negative range; `hi − lo` is exact under the same lemma.
            let (a, b, sign) = if lo > 0.0 {
                (lo, hi, 1.0)
            } else if hi < 0.0 {
                (-hi, -lo, -1.0)
            } else {
                continue;
            };
            if b <= 2.0 * a {
                // In [a, b]: the rounded midpoint cannot leave it.
                *ck = sign * (a + 0.5 * (b - a));
            }
        }
        // Checked, not only argued: every coordinate must come back bit for bit.
        for (k, ck) in c.iter_mut().enumerate() {
            if *ck != 0.0 && vertices.iter().any(|v| (v[k] - *ck) + *ck != v[k]) {
                *ck = 0.0;
            }
        }
        Origin(c)
    }

    /// Whether no axis is shifted.
    pub(crate) fn is_none(self) -> bool {
        self.0 == [0.0; 3]
    }

    /// `p − c` (exact for the mesh's own coordinates).
    pub(crate) fn to_local(self, p: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|k| {
            if self.0[k] == 0.0 {
                p[k]
            } else {
                p[k] - self.0[k]
            }
        })
    }

    /// `p + c`: exact for a point of the mesh in local coordinates or one [`Origin::snap`]
    /// returned.
    pub(crate) fn to_global(self, p: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|k| {
            if self.0[k] == 0.0 {
                p[k]
            } else {
                p[k] + self.0[k]
            }
        })
    }

    /// A local point near `p` whose translation back is exact (`p` rounded through the
    /// original frame: `(p + c) − c`), or `None` when that round trip is not exact (a point
    /// so far from the mesh that Sterbenz's lemma does not apply). Axes left alone are
    /// returned as they are.
    pub(crate) fn snap(self, p: [f64; 3]) -> Option<[f64; 3]> {
        let mut q = p;
        for k in 0..3 {
            let c = self.0[k];
            if c == 0.0 {
                continue;
            }
            let global = p[k] + c;
            let local = global - c;
            if local + c != global {
                return None;
            }
            q[k] = local;
        }
        Some(q)
    }

    /// `mesh` translated into the local frame (vertices only; normals and scalars do not
    /// change).
    pub(crate) fn local_mesh(self, mesh: &Mesh) -> Mesh {
        Mesh {
            vertices: mesh.vertices.iter().map(|&v| self.to_local(v)).collect(),
            triangles: mesh.triangles.clone(),
            scalars: mesh.scalars.clone(),
            normals: mesh.normals.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shifts_only_axes_far_from_the_origin_and_round_trips_exactly() {
        let vertices = vec![
            [5e5 + 0.1, 4.2e6 - 0.3, -1.0],
            [5e5 - 0.7, 4.2e6 + 0.9, 2.0],
            [5e5 + 1e-9, 4.2e6 + 1e-7, 0.5],
        ];
        let o = Origin::for_vertices(&vertices);
        assert!(o.0[0] != 0.0 && o.0[1] != 0.0);
        // The z range spans zero: left alone.
        assert_eq!(o.0[2], 0.0);
        for v in &vertices {
            let local = o.to_local(*v);
            assert_eq!(o.to_global(local), *v);
            assert!(local[0].abs() < 1.0 && local[1].abs() < 1.0);
        }
        // A point the fit might produce: snapped, then exact on the way back.
        let p = [0.123456789012345, -0.98765432109876, 0.25];
        let s = o.snap(p).unwrap();
        assert_eq!(o.to_local(o.to_global(s)), s);
        assert!((s[0] - p[0]).abs() < 1e-9 && (s[1] - p[1]).abs() < 1e-9 && s[2] == p[2]);
        // A mirror image below zero, and ranges too wide for an exact shift.
        let o = Origin::for_vertices(&[[-3.0, 1.0, 0.0], [-2.0, 3.0, 5.0]]);
        assert_eq!(o.0, [-2.5, 0.0, 0.0]);
        assert!(Origin::for_vertices(&[[1.0, 1.0, 1.0], [2.5, 2.5, 2.5]]).is_none());
        assert!(Origin::for_vertices(&[]).is_none());
    }
}
