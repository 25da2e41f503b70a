//! The independent checker of a decimation: replays its history on the original mesh and,
//! at every step, verifies in exact rational arithmetic what the issue promises:
//!
//! * the step's added triangles tile the removed fan's projection exactly: each has positive
//!   area in the projection plane, no ring node lies in an added triangle's closed region
//!   except at its corners, their areas sum to the fan's area, and no new edge existed
//!   before; the hole's ring is a simple counter-clockwise polygon in that projection (at a
//!   border node closed by the new border edge: the fan's area minus the triangle (last,
//!   node, first), zero when the border stays intact, cut off or filled when it is
//!   simplified). The projection is the axis plane most aligned with the fan's normal, else
//!   the first of the other two in which the step passes (any one proves the tiling). With
//!   the triangles forming a disc on the ring (the manifold check), positive orientation
//!   makes every point of the hole covered as often as the simple ring winds around it —
//!   once — so nothing flips, overlaps or leaves a T-junction in that projection;
//! * the mesh is an oriented 2-manifold with the original's Euler characteristic and number
//!   of border loops (full check every `full_every` steps and at the end);
//! * the fit's moves after the last step ([`super::fit`]) start where the kept nodes are
//!   and flip no triangle: every live triangle at a moved node has a normal whose exact dot
//!   product with its normal before the fit is positive;
//! * undoing every step gives the original mesh bit for bit, and redoing them gives the
//!   decimated mesh the history names.

use super::earcut::simple_ccw;
use super::history::{fingerprint, History, HistoryError, Stage};
use super::{fallback_planes, fan_normal, Plane};
use crate::mesh::{Mesh, MeshError};
use crate::num::rational::{dyadic_rational, f64s_over_shared_power};
use crate::num::Rational;
use num_bigint::BigInt;
use num_traits::{Signed, Zero};
use std::collections::{HashMap, HashSet};

/// What the checker verified.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct Verified {
    /// Steps replayed.
    pub steps: usize,
    /// Added triangles checked positive in their step's projection.
    pub triangles_checked: usize,
    /// Full manifold / Euler / border-loop checks performed.
    pub full_checks: usize,
    /// Nodes the fit moved.
    pub moved: usize,
    /// Triangles at moved nodes checked not flipped by the fit, exactly.
    pub fit_triangles_checked: usize,
    /// The original's Euler characteristic, kept at every full check.
    pub euler: i64,
    /// The original's number of border loops, kept at every full check.
    pub border_loops: usize,
    /// Undo of every step reproduced the original's fingerprint and triangles in order.
    pub undecimated_exactly: bool,
}

/// Why [`verify`] refused a history.
#[derive(Debug, thiserror::Error)]
pub enum CheckError {
    /// The original mesh is not a manifold mesh.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// The history's original fingerprint is not this mesh's.
    #[error("the history was not made from this mesh (fingerprint)")]
    NotThisMesh,
    /// The history file itself is inconsistent (a step that cannot be applied).
    #[error(transparent)]
    History(#[from] HistoryError),
    /// Step `step` (0-based; the history's length for the final checks) breaks a property.
    #[error("step {step}: {why}")]
    Step {
        /// The step.
        step: usize,
        /// The property it breaks, with the nodes or triangles involved.
        why: String,
    },
    /// Redoing every step does not give the decimated mesh's fingerprint.
    #[error("redoing every step does not give the decimated mesh (fingerprint)")]
    RedoMismatch,
    /// Undoing every step does not give the original mesh.
    #[error("undoing every step does not give the original mesh")]
    UndoMismatch,
}

fn step(step: usize, why: String) -> CheckError {
    CheckError::Step { step, why }
}

/// `det[b − a, c − a]` exactly (finite coordinates), in integers: the six coordinates are
/// dyadic, `m · 2^k`, and are brought over their smallest power of two, so no gcd is taken.
fn det(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Rational {
    let (ints, e) = f64s_over_shared_power(&[a[0], a[1], b[0], b[1], c[0], c[1]]);
    let [ax, ay, bx, by, cx, cy]: &[BigInt; 6] = ints[..].try_into().expect("six coordinates");
    dyadic_rational((bx - ax) * (cy - ay) - (by - ay) * (cx - ax), 2 * e)
}

/// The number of border loops of a manifold mesh.
pub fn border_loops(mesh: &Mesh) -> usize {
    let mut directed = HashSet::new();
    for t in &mesh.triangles {
        for e in 0..3 {
            directed.insert((t[e], t[(e + 1) % 3]));
        }
    }
    let mut next: HashMap<u32, u32> = HashMap::new();
    for &(a, b) in &directed {
        if !directed.contains(&(b, a)) {
            next.insert(a, b);
        }
    }
    let mut seen = HashSet::new();
    let mut loops = 0;
    for &start in next.keys() {
        if seen.contains(&start) {
            continue;
        }
        loops += 1;
        let mut v = start;
        while seen.insert(v) {
            v = next[&v];
        }
    }
    loops
}

/// Replays `history` on `original`, checking every step (full topology checks every
/// `full_every` steps, 0 for only at the end). `xy` names the global projection, else each
/// step is checked in the axis plane most aligned with its fan.
pub fn verify(
    original: &Mesh,
    history: &History,
    xy: bool,
    full_every: usize,
) -> Result<Verified, CheckError> {
    original.check_manifold()?;
    let euler = original.euler_characteristic();
    let loops = border_loops(original);
    if fingerprint(original) != history.original_fingerprint {
        return Err(CheckError::NotThisMesh);
    }
    let mut stage = Stage::original(original);
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
    for t in &original.triangles {
        for e in 0..3 {
            *edges.entry(key(t[e], t[(e + 1) % 3])).or_insert(0) += 1;
        }
    }
    let mut out = Verified {
        euler,
        border_loops: loops,
        ..Verified::default()
    };
    let full = |stage: &Stage, s: usize, out: &mut Verified| -> Result<(), CheckError> {
        let m = stage.to_mesh();
        m.check_manifold().map_err(|e| step(s, e.to_string()))?;
        if m.euler_characteristic() != euler {
            return Err(step(
                s,
                format!(
                    "Euler characteristic {} ≠ {euler}",
                    m.euler_characteristic()
                ),
            ));
        }
        if border_loops(&m) != loops {
            return Err(step(s, "border loops changed".into()));
        }
        out.full_checks += 1;
        Ok(())
    };
    for s in 0..history.len() {
        let st = history.step(s);
        let l = st.ring.len();
        let v = st.node as usize;
        let ring3: Vec<[f64; 3]> = st
            .ring
            .iter()
            .map(|&w| stage.vertices[w as usize])
            .collect();
        // The projection: the xy plane, or the axis plane most aligned with the fan's
        // normal, else the other two in order (the engines' rule); the step must tile its
        // hole exactly in the first in which it does (any one proves it).
        let planes: Vec<Plane> = if xy {
            vec![Plane::XY]
        } else {
            let n = fan_normal(stage.vertices[v], &ring3, !st.border);
            std::iter::once(Plane::most_aligned(n))
                .chain(fallback_planes(n))
                .collect()
        };
        let mut first_error = None;
        let mut tiled = false;
        for plane in planes {
            match tiles_in(&stage.vertices, &st, plane) {
                Ok(()) => {
                    tiled = true;
                    break;
                }
                Err(e) => {
                    first_error.get_or_insert(e);
                }
            }
        }
        if !tiled {
            return Err(step(s, first_error.unwrap_or_default()));
        }
        out.triangles_checked += l - 2;
        // No added edge may already exist outside the fan.
        for i in 0..l - 2 {
            let t = st.added_triangle(i);
            for e in 0..3 {
                let (a, b) = (t[e], t[(e + 1) % 3]);
                let pa = st.ring.iter().position(|&w| w == a).unwrap();
                let pb = st.ring.iter().position(|&w| w == b).unwrap();
                let link = pb == (pa + 1) % l && !(st.border && pa == l - 1);
                if !link && edges.contains_key(&key(a, b)) {
                    return Err(step(s, format!("added edge ({a}, {b}) already exists")));
                }
            }
        }
        for i in 0..st.slots.len() {
            let t = st.removed_triangle(i);
            for e in 0..3 {
                let k = key(t[e], t[(e + 1) % 3]);
                let c = edges.get_mut(&k).expect("edge of a live triangle");
                *c -= 1;
                if *c == 0 {
                    edges.remove(&k);
                }
            }
        }
        for i in 0..l - 2 {
            let t = st.added_triangle(i);
            for e in 0..3 {
                *edges.entry(key(t[e], t[(e + 1) % 3])).or_insert(0) += 1;
            }
        }
        stage.redo(history)?;
        out.steps += 1;
        if full_every > 0 && (s + 1) % full_every == 0 {
            full(&stage, s, &mut out)?;
        }
    }
    if !history.fit.is_empty() {
        let before = stage.vertices.clone();
        stage.redo(history)?;
        let mut moved = vec![false; stage.vertices.len()];
        for m in &history.fit {
            moved[m.node as usize] = true;
        }
        for (t, tri) in stage.slots.iter().enumerate() {
            if !stage.live[t] || !tri.iter().any(|&v| moved[v as usize]) {
                continue;
            }
            let (was, is) = (
                tri.map(|v| before[v as usize]),
                tri.map(|v| stage.vertices[v as usize]),
            );
            if !super::fit::normals_agree_exactly(was, is) {
                return Err(step(
                    history.len(),
                    format!("the fit flips triangle {tri:?} (slot {t})"),
                ));
            }
            out.fit_triangles_checked += 1;
        }
        out.moved = history.fit.len();
    }
    full(&stage, history.len(), &mut out)?;
    if fingerprint(&stage.to_mesh()) != history.decimated_fingerprint {
        return Err(CheckError::RedoMismatch);
    }
    while stage.applied > 0 {
        stage.undo(history)?;
    }
    let back = stage.to_mesh();
    out.undecimated_exactly =
        back == *original && fingerprint(&back) == history.original_fingerprint;
    if !out.undecimated_exactly {
        return Err(CheckError::UndoMismatch);
    }
    Ok(out)
}

/// Whether step `st` (applied to `vertices`) tiles its hole exactly in the projection
/// `plane`: every added triangle positive, no ring node in an added triangle's closed region
/// except at its corners, and the added areas summing to the hole's; else what fails.
fn tiles_in(
    vertices: &[[f64; 3]],
    st: &super::history::StepRef<'_>,
    plane: Plane,
) -> Result<(), String> {
    let l = st.ring.len();
    let v = st.node as usize;
    let p = |w: u32| plane.project(vertices[w as usize]);
    let centre = plane.project(vertices[v]);
    let mut fan_area = Rational::zero();
    for i in 0..st.slots.len() {
        fan_area += det(centre, p(st.ring[i]), p(st.ring[(i + 1) % l]));
    }
    let mut added_area = Rational::zero();
    for i in 0..l - 2 {
        let [a, b, c] = st.added_triangle(i).map(p);
        let d = det(a, b, c);
        if !d.is_positive() {
            return Err(format!(
                "added triangle {:?} has non-positive area in its projection",
                st.added_triangle(i)
            ));
        }
        added_area += d;
    }
    // No ring vertex lies in an added triangle's closed region except at its corners: no
    // T-junction on a new edge, no vertex covered.
    for i in 0..l - 2 {
        let t = st.added_triangle(i);
        let [a, b, c] = t.map(p);
        for &w in st.ring {
            if t.contains(&w) {
                continue;
            }
            let q = p(w);
            if !det(a, b, q).is_negative()
                && !det(b, c, q).is_negative()
                && !det(c, a, q).is_negative()
            {
                return Err(format!("node {w} lies in the closed added triangle {t:?}"));
            }
        }
    }
    // The hole is the ring as a closed polygon (at a border node closed by the new border
    // edge from its last node to its first): it must be simple and counter-clockwise, so that
    // positive triangles summing to its area tile it once. Its area is the fan's minus, at a
    // border node, the triangle (last, v, first) (flat when the border stays intact, cut off
    // or filled in when it is simplified).
    let ring2: Vec<[f64; 2]> = st
        .ring
        .iter()
        .map(|&w| plane.project(vertices[w as usize]))
        .collect();
    // Comparisons of finite f64 values are exact.
    let lower = |i: usize, j: usize| {
        (ring2[i][0], ring2[i][1]).partial_cmp(&(ring2[j][0], ring2[j][1]))
            == Some(std::cmp::Ordering::Less)
    };
    if !simple_ccw(l, &RingOrient(&ring2), lower) {
        return Err(
            "the hole's ring is not a simple counter-clockwise polygon in its projection".into(),
        );
    }
    let mut hole_area = fan_area;
    if st.border {
        hole_area -= det(p(st.ring[l - 1]), centre, p(st.ring[0]));
    }
    if hole_area != added_area {
        return Err("the added triangles do not tile the removed fan's hole (areas differ)".into());
    }
    Ok(())
}

/// Exact orientation of projected ring points (rational determinants).
struct RingOrient<'a>(&'a [[f64; 2]]);

impl super::earcut::Orient for RingOrient<'_> {
    fn orient(&self, a: usize, b: usize, c: usize) -> std::cmp::Ordering {
        let d = det(self.0[a], self.0[b], self.0[c]);
        if d.is_positive() {
            std::cmp::Ordering::Greater
        } else if d.is_negative() {
            std::cmp::Ordering::Less
        } else {
            std::cmp::Ordering::Equal
        }
    }
}

#[cfg(test)]
mod tests {
    use super::det;
    use crate::num::{rational_from_f64, Rational};

    /// The integer determinant equals the rational formula on coordinates of every magnitude:
    /// subnormals, huge values, zeros, exact cancellations.
    #[test]
    fn integer_det_equals_the_rational_formula() {
        let q = |x: f64| rational_from_f64(x, "x").unwrap();
        let values = [
            0.0,
            -0.0,
            1.0,
            -1.5,
            3.0e-310,
            -5e-324,
            1.0e300,
            -7.25e-3,
            0.1,
            2.0f64.powi(60),
            1.0 + f64::EPSILON,
        ];
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut pick = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            values[(state >> 33) as usize % values.len()]
        };
        for _ in 0..5_000 {
            let (a, b, c) = ([pick(), pick()], [pick(), pick()], [pick(), pick()]);
            let want: Rational = (q(b[0]) - q(a[0])) * (q(c[1]) - q(a[1]))
                - (q(b[1]) - q(a[1])) * (q(c[0]) - q(a[0]));
            assert_eq!(det(a, b, c), want, "{a:?} {b:?} {c:?}");
        }
    }
}
