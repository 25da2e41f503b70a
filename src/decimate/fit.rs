//! Re-placement of the kept nodes after a decimation (an extension for surfaces in 3-D, after
//! the distance energy of Hoppe, DeRose, Duchamp, McDonald and Stuetzle, "Mesh optimization",
//! SIGGRAPH 1993, eq. 2, with their fixed-connectivity step): node decimation keeps a subset
//! of the original vertices, so every kept triangle is a chord of the original surface and
//! the whole result lies on one side of it where the surface curves. Moving the kept nodes
//! to the least-squares fit of the original vertices lets the result straddle the surface.
//!
//! One round: every vertex `oᵢ` of the original surface (one some triangle uses) is
//! attached to its closest point on the current result, with barycentric coordinates `bᵢ`
//! in triangle `tᵢ`; then Gauss–Seidel sweeps over the kept nodes minimise
//! `Σᵢ |Σₖ bᵢₖ x_{tᵢₖ} − oᵢ|² + Σ_v μ (1 + d_v) |x_v − x_v⁰|²` (the regulariser holds a
//! node near its start `x_v⁰` along directions its points do not constrain;
//! `d_v = Σᵢ bᵢᵥ²`). A move is taken only when every triangle around the node
//! keeps a normal within about 72° of its normal before the fit ([`MIN_COS`]) and, if it
//! faced along its corners' original vertex normals, still does, and (when the decimation
//! ran the facing test, [`Options::facing`](super::Options::facing)) no triangle around it
//! faces against the original surface nearest it; the first is decided with `f64` only where
//! it provably gets the sign right ([`normals_agree`]), so the fit flips no triangle and
//! [`check`](super::check) re-verifies that exactly.
//!
//! Everything is `f64` and runs alike after either engine (the closest points on all cores,
//! each a function of its point alone; the sweeps in node order), so both paths move the
//! same nodes to the same places. The history records every move (from, to) bit for bit, so
//! undecimation still restores the original exactly.

use super::origin::Origin;
use super::quality::{ClosestPoints, OriginalSurface};
use crate::mesh::{area_vector, Mesh};
use crate::num::rational::f64s_over_shared_power;
use num_bigint::BigInt;
use num_traits::Signed;

/// One node moved by the fit: its id in the original mesh and its position before and after.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Moved {
    /// The node (its index in the original mesh).
    pub node: u32,
    /// Where it was (its original coordinates).
    pub from: [f64; 3],
    /// Where the fit put it (its coordinates in the decimated mesh).
    pub to: [f64; 3],
}

/// The regulariser weight `μ` of a node's start position (relative to `1 + d_v`).
pub const REGULARISER: f64 = 0.01;

/// Gauss–Seidel sweeps per round.
pub const SWEEPS: usize = 3;

/// The smallest cosine between a triangle's normal after a move and before the fit that the
/// fit accepts (about 72°).
pub const MIN_COS: f64 = 0.3;

/// Fits the nodes of `decimated` (whose vertex `k` is node `kept[k]` of `original`) to the
/// original vertices in `rounds` rounds (module docs) and returns the moves, in node order;
/// `decimated`'s vertices are updated. Nothing moves when `rounds` is 0 or either mesh has
/// no triangles. Non-finite results are never taken. With `surface` (the original's, as the
/// decimation checked its removals against it), a move is also refused when a triangle
/// around the node would face against it
/// ([`OriginalSurface::faces_against`]).
pub fn fit(
    original: &Mesh,
    decimated: &mut Mesh,
    kept: &[u32],
    rounds: usize,
    surface: Option<&OriginalSurface>,
) -> Vec<Moved> {
    fit_in(
        original,
        decimated,
        kept,
        rounds,
        surface,
        Origin::default(),
    )
}

/// [`fit`] in local coordinates `origin`: every target is first rounded to a point that
/// translates back to the original frame exactly ([`Origin::snap`]; a target that cannot be
/// is not taken), and the checks run on the rounded point.
pub(crate) fn fit_in(
    original: &Mesh,
    decimated: &mut Mesh,
    kept: &[u32],
    rounds: usize,
    surface: Option<&OriginalSurface>,
    origin: Origin,
) -> Vec<Moved> {
    let n = decimated.vertices.len();
    if rounds == 0 || decimated.triangles.is_empty() || original.triangles.is_empty() {
        return Vec::new();
    }
    let start = decimated.vertices.clone();
    let around = crate::mesh::incident_triangles(n, &decimated.triangles);
    // Triangles whose normal `f64` cannot trust keep their corners where they are.
    let before: Vec<Option<[f64; 3]>> = decimated
        .triangles
        .iter()
        .map(|t| trusted_normal(t.map(|i| start[i as usize])))
        .collect();
    let normals = border_normals(decimated);
    // The original surface's normals at the kept nodes: a triangle that faces along its
    // corners' normals before the fit must still after it (the decimation's fold test).
    let original_normals = super::vertex_normals(original);
    let corner_normal = |tri: [u32; 3]| -> [f64; 3] {
        let [a, b, c] = tri.map(|i| original_normals[kept[i as usize] as usize]);
        std::array::from_fn(|k| a[k] + b[k] + c[k])
    };
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let facing: Vec<bool> = decimated
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| start[i as usize]);
            dot(area_vector(a, b, c), corner_normal(*t)) > 0.0
        })
        .collect();
    // Every vertex of the original surface (a strided subset was tried: every 4th cost the
    // dragon scan 0.03 of RMS and 30 more flipped triangles for 0.33 s, and the bunny a
    // quarter of its gain); vertices no triangle uses are not on it and pull nothing.
    let samples = &original.vertices;
    let on_surface = original.used_vertices();
    for _ in 0..rounds {
        let attached = attach(samples, decimated);
        // Per triangle, the original vertex attached nearest its middle (the largest
        // smallest barycentric coordinate): where the facing test's search starts.
        let mut seeds: Vec<(f64, u32)> =
            vec![(f64::NEG_INFINITY, u32::MAX); decimated.triangles.len()];
        if surface.is_some() {
            for (i, &(t, b)) in attached.iter().enumerate() {
                if !on_surface[i] {
                    continue;
                }
                let depth = b[0].min(b[1]).min(b[2]);
                if depth > seeds[t as usize].0 {
                    seeds[t as usize] = (depth, i as u32);
                }
            }
        }
        // Per node, the attached points whose triangle it is a corner of (CSR, in point order).
        let mut first = vec![0u32; n + 1];
        for (&(t, _), _) in attached.iter().zip(&on_surface).filter(|(_, &u)| u) {
            for &v in &decimated.triangles[t as usize] {
                first[v as usize + 1] += 1;
            }
        }
        for v in 0..n {
            first[v + 1] += first[v];
        }
        let mut fill = first.clone();
        let mut points = vec![0u32; first[n] as usize];
        for (i, &(t, _)) in attached.iter().enumerate() {
            if !on_surface[i] {
                continue;
            }
            for &v in &decimated.triangles[t as usize] {
                points[fill[v as usize] as usize] = i as u32;
                fill[v as usize] += 1;
            }
        }
        for _ in 0..SWEEPS {
            for v in 0..n {
                let mine = &points[first[v] as usize..first[v + 1] as usize];
                let Some(target) =
                    node_target(samples, decimated, &attached, mine, v, start[v], normals[v])
                        .and_then(|x| origin.snap(x))
                else {
                    continue;
                };
                if target == decimated.vertices[v] {
                    continue;
                }
                let triangles = &around.1[around.0[v] as usize..around.0[v + 1] as usize];
                // Triangle `t`'s corners with `v` at its target.
                let moved = |t: u32| {
                    decimated.triangles[t as usize].map(|i| {
                        if i as usize == v {
                            target
                        } else {
                            decimated.vertices[i as usize]
                        }
                    })
                };
                let ok = triangles.iter().all(|&t| {
                    let c = moved(t);
                    before[t as usize].is_some_and(|n| normals_agree(n, c))
                        && (!facing[t as usize]
                            || dot(
                                area_vector(c[0], c[1], c[2]),
                                corner_normal(decimated.triangles[t as usize]),
                            ) > 0.0)
                }) && surface.is_none_or(|s| {
                    triangles.iter().all(|&t| {
                        let c = moved(t);
                        let seed = match seeds[t as usize].1 {
                            u32::MAX => kept[v],
                            i => i,
                        };
                        !s.faces_against(c, &[seed])
                    })
                });
                if ok {
                    decimated.vertices[v] = target;
                }
            }
        }
    }
    (0..n)
        .filter(|&v| decimated.vertices[v] != start[v])
        .map(|v| Moved {
            node: kept[v],
            from: start[v],
            to: decimated.vertices[v],
        })
        .collect()
}

/// Per node on a border, its unit normal (the sum of its triangles' area vectors,
/// normalised; `None` inside or when that sum vanishes): border nodes move only along it,
/// so that the fit does not pull borders in along the surface.
fn border_normals(mesh: &Mesh) -> Vec<Option<[f64; 3]>> {
    let n = mesh.vertices.len();
    let on_border = mesh.border_vertices();
    let mut sum = vec![[0.0; 3]; n];
    for tri in &mesh.triangles {
        let [a, b, c] = tri.map(|i| mesh.vertices[i as usize]);
        let m = area_vector(a, b, c);
        for &i in tri {
            for k in 0..3 {
                sum[i as usize][k] += m[k];
            }
        }
    }
    (0..n)
        .map(|v| {
            let m = sum[v];
            let l = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
            (on_border[v] && l > 0.0 && l.is_finite()).then(|| [m[0] / l, m[1] / l, m[2] / l])
        })
        .collect()
}

/// Every sample's closest point on `decimated`: its triangle and barycentric coordinates
/// there (on all cores; each a function of its point alone). Searching only near the
/// previous round's triangle was tried: starting the search there saved 8 %, searching only
/// the triangles around its corners cost 25 % more than the hierarchy.
fn attach(samples: &[[f64; 3]], decimated: &Mesh) -> Vec<(u32, [f64; 3])> {
    use crate::par::prelude::*;
    let Some(cp) = ClosestPoints::new(decimated) else {
        return Vec::new();
    };
    samples
        .par_iter()
        .map(|&o| {
            let c = cp.query(o);
            let t =
                decimated.triangles[c.triangle as usize].map(|i| decimated.vertices[i as usize]);
            (c.triangle, barycentric(c.point, t))
        })
        .collect()
}

/// The barycentric coordinates of `p` (a point of the triangle's plane) in triangle `t`
/// (least squares in the plane; `(1, 0, 0)` for a degenerate triangle).
fn barycentric(p: [f64; 3], t: [[f64; 3]; 3]) -> [f64; 3] {
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let (e0, e1, d) = (sub(t[1], t[0]), sub(t[2], t[0]), sub(p, t[0]));
    let (a00, a01, a11) = (dot(e0, e0), dot(e0, e1), dot(e1, e1));
    let (b0, b1) = (dot(d, e0), dot(d, e1));
    let den = a00 * a11 - a01 * a01;
    if den.is_nan() || den <= 0.0 {
        return [1.0, 0.0, 0.0];
    }
    let s = (a11 * b0 - a01 * b1) / den;
    let u = (a00 * b1 - a01 * b0) / den;
    [1.0 - s - u, s, u]
}

/// The Gauss–Seidel update of node `v` (module docs) from the points attached to its
/// triangles (`mine`), the other corners where they are now; `None` when no point constrains
/// it or the result is not finite. With a `normal` (a border node) the move is projected
/// onto it (the isotropic least squares' minimum on that line).
#[allow(clippy::too_many_arguments)]
fn node_target(
    samples: &[[f64; 3]],
    decimated: &Mesh,
    attached: &[(u32, [f64; 3])],
    mine: &[u32],
    v: usize,
    start: [f64; 3],
    normal: Option<[f64; 3]>,
) -> Option<[f64; 3]> {
    let mut num = [0.0; 3];
    let mut den = 0.0;
    for &i in mine {
        let (t, b) = attached[i as usize];
        let tri = decimated.triangles[t as usize];
        let mut rest = samples[i as usize];
        let mut bv = 0.0;
        for k in 0..3 {
            if tri[k] as usize == v {
                bv += b[k];
            } else {
                let x = decimated.vertices[tri[k] as usize];
                for c in 0..3 {
                    rest[c] -= b[k] * x[c];
                }
            }
        }
        for c in 0..3 {
            num[c] += bv * rest[c];
        }
        den += bv * bv;
    }
    if den.is_nan() || den <= 0.0 {
        return None;
    }
    let m = REGULARISER * (1.0 + den);
    let mut x: [f64; 3] = std::array::from_fn(|c| (num[c] + m * start[c]) / (den + m));
    if let Some(n) = normal {
        let s = (x[0] - start[0]) * n[0] + (x[1] - start[1]) * n[1] + (x[2] - start[2]) * n[2];
        x = std::array::from_fn(|c| start[c] + s * n[c]);
    }
    x.iter().all(|c| c.is_finite()).then_some(x)
}

/// The area vector of triangle `t` when `f64` gets its direction right to within 1e-8 (its
/// length at least 1e-6 of `|b − a||c − a|`, finite), else `None`: each computed component
/// of `(b − a) × (c − a)` is within `8ε|b − a||c − a|` of the true one (ε = 2⁻⁵³), so the
/// computed vector is within `14ε` of that product, a relative error below 3.2·10⁻⁹.
pub fn trusted_normal(t: [[f64; 3]; 3]) -> Option<[f64; 3]> {
    let [a, b, c] = t;
    let m = area_vector(a, b, c);
    let len = |u: [f64; 3], w: [f64; 3]| {
        ((u[0] - w[0]).powi(2) + (u[1] - w[1]).powi(2) + (u[2] - w[2]).powi(2)).sqrt()
    };
    let lm = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
    // `area_vector` is the cross product itself.
    (lm.is_finite() && lm > 0.0 && lm >= 1e-6 * len(b, a) * len(c, a)).then_some(m)
}

/// Whether the triangle `after` keeps a normal within the fit's angle ([`MIN_COS`]) of
/// `before` (a [`trusted_normal`]), in `f64`; `false` when `after`'s normal is not trusted.
/// Both directions being right to 3.2·10⁻⁹, an accepted cosine of at least 0.3 is truly
/// above 0.3 − 10⁻⁸: the exact dot product ([`normals_agree_exactly`]) is positive.
pub fn normals_agree(before: [f64; 3], after: [[f64; 3]; 3]) -> bool {
    let Some(m) = trusted_normal(after) else {
        return false;
    };
    let dot = before[0] * m[0] + before[1] * m[1] + before[2] * m[2];
    let lb = (before[0] * before[0] + before[1] * before[1] + before[2] * before[2]).sqrt();
    let lm = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
    dot >= MIN_COS * lb * lm
}

/// The exact sign test behind the fit's guarantee: whether `(b − a) × (c − a)` of `after`
/// has a positive dot product with `(b − a) × (c − a)` of `before` (finite coordinates), in
/// integers over a shared power of two.
pub fn normals_agree_exactly(before: [[f64; 3]; 3], after: [[f64; 3]; 3]) -> bool {
    let coords: Vec<f64> = before
        .iter()
        .chain(after.iter())
        .flatten()
        .copied()
        .collect();
    let (ints, _) = f64s_over_shared_power(&coords);
    let normal = |p: &[BigInt]| {
        let d = |i: usize, k: usize| &p[3 * i + k] - &p[k];
        let (u, w) = ([d(1, 0), d(1, 1), d(1, 2)], [d(2, 0), d(2, 1), d(2, 2)]);
        [
            &u[1] * &w[2] - &u[2] * &w[1],
            &u[2] * &w[0] - &u[0] * &w[2],
            &u[0] * &w[1] - &u[1] * &w[0],
        ]
    };
    let (n0, n1) = (normal(&ints[..9]), normal(&ints[9..]));
    (&n0[0] * &n1[0] + &n0[1] * &n1[1] + &n0[2] * &n1[2]).is_positive()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_agreement_matches_the_rational_formula() {
        use crate::num::{rational_from_f64, Rational};
        let mut rng = crate::decimate::TestRng(0x05ee_df17);
        for _ in 0..2000 {
            let mut coord = || {
                let m = (rng.below(2001) as f64 - 1000.0) / 64.0;
                m * [1.0, 1e-9, 3.0e7][rng.below(3) as usize]
            };
            let tri = |c: &mut dyn FnMut() -> f64| -> [[f64; 3]; 3] {
                std::array::from_fn(|_| [c(), c(), c()])
            };
            let (x, y) = (tri(&mut coord), tri(&mut coord));
            let q = |t: [[f64; 3]; 3]| {
                t.map(|p| p.map(|c| rational_from_f64(c, "coordinate").unwrap()))
            };
            let normal = |t: [[Rational; 3]; 3]| {
                let d = |i: usize, k: usize| &t[i][k] - &t[0][k];
                let (u, w) = ([d(1, 0), d(1, 1), d(1, 2)], [d(2, 0), d(2, 1), d(2, 2)]);
                [
                    &u[1] * &w[2] - &u[2] * &w[1],
                    &u[2] * &w[0] - &u[0] * &w[2],
                    &u[0] * &w[1] - &u[1] * &w[0],
                ]
            };
            let (a, b) = (normal(q(x)), normal(q(y)));
            let dot = &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2];
            assert_eq!(
                normals_agree_exactly(x, y),
                dot.is_positive(),
                "{x:?} {y:?}"
            );
        }
    }

    #[test]
    fn the_filter_never_accepts_what_exact_signs_refuse() {
        let mut rng = crate::decimate::TestRng(0xf11e);
        let mut accepted = 0;
        for _ in 0..5000 {
            let s = (rng.below(1000) as f64) / 1000.0;
            let eps = [1e-3, 1e-9, 1e-15][rng.below(3) as usize];
            let mut c = || (rng.below(1 << 20) as f64 - (1 << 19) as f64) / 1024.0;
            let before: [[f64; 3]; 3] = std::array::from_fn(|_| [c(), c(), c()]);
            let mut after = before;
            // Nearly degenerate: the third corner close to the line of the first two.
            after[2] = std::array::from_fn(|k| {
                before[0][k] + s * (before[1][k] - before[0][k]) + eps * (c() - c())
            });
            let Some(n) = trusted_normal(before) else {
                continue;
            };
            if normals_agree(n, after) {
                accepted += 1;
                assert!(normals_agree_exactly(before, after), "{before:?} {after:?}");
            }
        }
        println!(
            "filter: {accepted} of 5000 near-degenerate moves accepted, all confirmed exactly"
        );
    }

    #[test]
    fn fitting_a_chord_moves_it_onto_the_arc_and_flips_nothing() {
        // A fine cylinder patch (radius 1) decimated to its outer columns: the chord lies
        // inside; the fit must move it outward toward the arc and reduce the RMS distance.
        let (cols, rows) = (33usize, 5usize);
        let mut original = Mesh::default();
        for r in 0..rows {
            for c in 0..cols {
                let a = -0.6 + 1.2 * c as f64 / (cols - 1) as f64;
                original.vertices.push([a.sin(), r as f64 * 0.25, a.cos()]);
            }
        }
        let id = |r: usize, c: usize| (r * cols + c) as u32;
        for r in 0..rows - 1 {
            for c in 0..cols - 1 {
                original
                    .triangles
                    .push([id(r, c), id(r + 1, c + 1), id(r, c + 1)]);
                original
                    .triangles
                    .push([id(r, c), id(r + 1, c), id(r + 1, c + 1)]);
            }
        }
        let kept: Vec<u32> = (0..rows)
            .flat_map(|r| [0, cols / 2, cols - 1].map(|c| id(r, c)))
            .collect();
        let mut coarse = Mesh {
            vertices: kept
                .iter()
                .map(|&k| original.vertices[k as usize])
                .collect(),
            ..Mesh::default()
        };
        for r in 0..rows - 1 {
            for c in 0..2 {
                let v = |r: usize, c: usize| (3 * r + c) as u32;
                coarse
                    .triangles
                    .push([v(r, c), v(r + 1, c + 1), v(r, c + 1)]);
                coarse
                    .triangles
                    .push([v(r, c), v(r + 1, c), v(r + 1, c + 1)]);
            }
        }
        let rms = |m: &Mesh| crate::decimate::quality::deviation(&original, m).forward_rms;
        let before_mesh = coarse.clone();
        let before = rms(&coarse);
        let moves = fit(&original, &mut coarse, &kept, 2, None);
        let after = rms(&coarse);
        println!(
            "chord fit: {} moves, RMS {before:.5} → {after:.5}",
            moves.len()
        );
        assert!(!moves.is_empty());
        assert!(after < 0.6 * before, "{before} → {after}");
        for m in &moves {
            let k = kept.iter().position(|&x| x == m.node).unwrap();
            assert_eq!(m.from, before_mesh.vertices[k]);
            assert_eq!(m.to, coarse.vertices[k]);
        }
        for (t, tri) in coarse.triangles.iter().enumerate() {
            let x = tri.map(|i| before_mesh.vertices[i as usize]);
            let y = tri.map(|i| coarse.vertices[i as usize]);
            assert!(normals_agree_exactly(x, y), "triangle {t} flipped");
        }
    }
}
