//! The independent checker of traced curves and the curve certificate file. It does not run
//! the tracer: every vertex is re-verified as a root of the equations on its plane
//! ([`verify_root`] on [`plane_system`]), every arc box's tangent minor is recomputed from
//! the original equations restricted to the box and its strict sign checked exactly, and the
//! components are re-walked through the arcs.
//!
//! What a certificate does not carry, and the checker therefore does not re-establish, is
//! completeness: that no other curve point lies on an arc box's boundary and that the boxes
//! between arcs hold no curve. Those are the tracer's cross-section solves.

use super::check::{knot_parts, part_equations, verify_piecewise_root, verify_root};
use super::curve::tangent_minor;
use super::input::{
    certificate_from_json, parse_box, piecewise_system_from_json, piecewise_system_to_json,
    system_to_json,
};
use super::{
    plane_system, Arc, CurvePoint, Curves, PiecewiseSystem, RationalBox, RootRefusal, SolveError,
    System,
};
use crate::bernstein::Bernstein;
use crate::num::{rational_to_string, Rational};
use num_traits::Signed;
use serde_json::{json, Value};

/// The kind string of a curve-certificate file.
pub const CURVE_CERTIFICATE_KIND: &str = "geocert/solve-curves";

/// What [`verify_curves`] re-established.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CurveCheck {
    /// Vertices verified as certified curve points.
    pub points: usize,
    /// Arc boxes whose tangent minor was re-checked.
    pub arcs: usize,
    /// Components re-walked.
    pub components: usize,
}

impl std::fmt::Display for CurveCheck {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} curve points each the unique root on its plane, {} arc boxes each monotone along \
             its axis with both ends on its boundary, {} components joined arc to arc",
            self.points, self.arcs, self.components
        )
    }
}

/// Why [`verify_curves`] refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CurveRefusal {
    /// A point's box is not on a plane or not in the domain.
    #[error("point {point}: its box is not on the plane of its axis inside the domain")]
    PointBox {
        /// The point.
        point: usize,
    },
    /// A point's root certificate failed.
    #[error("point {point}: {why}")]
    Point {
        /// The point.
        point: usize,
        /// The refusal.
        why: RootRefusal,
    },
    /// An arc box is empty, outside the domain, or its tangent minor is not of one strict
    /// sign.
    #[error("arc {arc}: {why}")]
    Arc {
        /// The arc.
        arc: usize,
        /// What failed.
        why: String,
    },
    /// A component is not a chain of arcs through its points.
    #[error("component {component}: {why}")]
    Component {
        /// The component.
        component: usize,
        /// What failed.
        why: String,
    },
}

/// Re-checks a traced curve against `system` (see the module docs for what is checked).
pub fn verify_curves(system: &System, curves: &Curves) -> Result<CurveCheck, CurveRefusal> {
    verify_with(
        &system.domain,
        curves,
        |pt| {
            // The plane system on the point's own box: its domain is the box without the axis.
            let b = &pt.root.bounds;
            let plane = plane_system(system, pt.axis, &b[pt.axis].0, b).map_err(|_| None)?;
            verify_root(&plane, &plane.domain, &pt.root.certificate)
                .map(|_| ())
                .map_err(Some)
        },
        |arc| {
            let sub = system.unit_bounds(&arc.bounds);
            let f: Vec<Bernstein<Rational>> = system
                .equations
                .iter()
                .map(|e| e.restrict(&sub))
                .collect::<Result<_, _>>()
                .map_err(|e| e.to_string())?;
            monotone(&[f], arc.monotone_axis)
        },
    )
}

/// [`verify_curves`] for a system with B-spline equations. A point is re-verified as a root
/// of the [`PiecewiseSystem::plane`] system on its box ([`verify_piecewise_root`]); an arc
/// box is cut at the knots inside it, each equation taken on each part directly, and the
/// tangent minor must have the same strict sign on every part; in three or more unknowns no
/// C⁰ knot plane may lie inside an arc box (see [`trace_piecewise`](super::trace_piecewise)
/// for why).
pub fn verify_piecewise_curves(
    system: &PiecewiseSystem,
    curves: &Curves,
) -> Result<CurveCheck, CurveRefusal> {
    let n = system.unknowns();
    verify_with(
        system.domain(),
        curves,
        |pt| {
            let b = &pt.root.bounds;
            let plane = system.plane(pt.axis, &b[pt.axis].0, b).map_err(|_| None)?;
            let bounds = plane.domain().to_vec();
            verify_piecewise_root(&plane, &bounds, &pt.root.certificate)
                .map(|_| ())
                .map_err(Some)
        },
        |arc| {
            if n >= 3 {
                for (k, kinks) in system.kinks().iter().enumerate() {
                    let (lo, hi) = &arc.bounds[k];
                    if let Some(x) = kinks.iter().find(|x| lo < *x && *x < hi) {
                        return Err(format!("the C⁰ knot plane x{k} = {x} crosses the box"));
                    }
                }
            }
            let parts = knot_parts(system, &arc.bounds)
                .iter()
                .map(|part| part_equations(system, part))
                .collect::<Result<Vec<_>, _>>()
                .map_err(|e| e.to_string())?;
            monotone(&parts, arc.monotone_axis)
        },
    )
}

/// The tangent minor without column `axis` has one strict sign, the same on every part
/// (each part's equations in Bernstein form on it).
fn monotone(parts: &[Vec<Bernstein<Rational>>], axis: usize) -> Result<(), String> {
    let mut sign = 0;
    for f in parts {
        let minor = tangent_minor(f, axis).map_err(|e| e.to_string())?;
        let here = if minor.coeffs().iter().all(Signed::is_positive) {
            1
        } else if minor.coeffs().iter().all(Signed::is_negative) {
            -1
        } else {
            0
        };
        if here == 0 || (sign != 0 && here != sign) {
            return Err(format!(
                "the tangent minor without column {axis} is not of one strict sign on the box"
            ));
        }
        sign = here;
    }
    Ok(())
}

/// The checks common to both systems: `point(p)` re-verifies a point's root certificate on
/// its plane (`Err(None)` when the plane cannot be formed), `arc(a)` an arc box's
/// monotonicity.
fn verify_with(
    domain: &[(Rational, Rational)],
    curves: &Curves,
    point: impl Fn(&CurvePoint) -> Result<(), Option<RootRefusal>>,
    arc: impl Fn(&Arc) -> Result<(), String>,
) -> Result<CurveCheck, CurveRefusal> {
    let n = domain.len();
    for (p, pt) in curves.points.iter().enumerate() {
        let b = &pt.root.bounds;
        let on_plane =
            pt.axis < n && b.len() == n && b[pt.axis].0 == b[pt.axis].1 && inside(domain, b);
        if !on_plane {
            return Err(CurveRefusal::PointBox { point: p });
        }
        point(pt).map_err(|why| match why {
            None => CurveRefusal::PointBox { point: p },
            Some(why) => CurveRefusal::Point { point: p, why },
        })?;
    }
    for (i, a) in curves.arcs.iter().enumerate() {
        check_arc(domain, curves, a)
            .and_then(|()| arc(a))
            .map_err(|why| CurveRefusal::Arc { arc: i, why })?;
    }
    for (c, comp) in curves.components.iter().enumerate() {
        let refuse = |why: String| CurveRefusal::Component { component: c, why };
        let pts = &comp.points;
        let expected = if comp.closed {
            pts.len()
        } else {
            pts.len().saturating_sub(1)
        };
        if comp.arcs.len() != expected || pts.is_empty() {
            return Err(refuse(format!(
                "{} points need {expected} arcs, {} given",
                pts.len(),
                comp.arcs.len()
            )));
        }
        for (k, &a) in comp.arcs.iter().enumerate() {
            let (u, v) = (pts[k], pts[(k + 1) % pts.len()]);
            let ends = curves
                .arcs
                .get(a)
                .map(|arc| arc.ends)
                .ok_or_else(|| refuse(format!("arc {a} does not exist")))?;
            if !(ends == [u, v] || ends == [v, u]) {
                return Err(refuse(format!("arc {a} does not join points {u} and {v}")));
            }
        }
    }
    Ok(CurveCheck {
        points: curves.points.len(),
        arcs: curves.arcs.len(),
        components: curves.components.len(),
    })
}

/// Whether the closed box lies in the domain.
fn inside(domain: &[(Rational, Rational)], b: &RationalBox) -> bool {
    b.iter()
        .zip(domain)
        .all(|((lo, hi), (a, bb))| lo <= hi && lo >= a && hi <= bb)
}

/// An arc's box and ends: a non-empty box inside the domain, a valid axis, two distinct end
/// points on the box's boundary.
fn check_arc(domain: &[(Rational, Rational)], curves: &Curves, arc: &Arc) -> Result<(), String> {
    let n = domain.len();
    let b = &arc.bounds;
    if b.len() != n || !inside(domain, b) || b.iter().any(|(lo, hi)| lo >= hi) {
        return Err("the box is empty or not inside the domain".into());
    }
    if arc.monotone_axis >= n {
        return Err(format!("monotone axis {} out of range", arc.monotone_axis));
    }
    if arc.ends[0] == arc.ends[1] {
        return Err("both ends are the same point".into());
    }
    for &p in &arc.ends {
        let point = curves
            .points
            .get(p)
            .ok_or_else(|| format!("end point {p} does not exist"))?;
        let pb = &point.root.bounds;
        let k = point.axis;
        let within = pb.len() == n
            && pb
                .iter()
                .zip(b)
                .all(|((lo, hi), (alo, ahi))| lo >= alo && hi <= ahi);
        let on_face = k < n && (pb[k].0 == b[k].0 || pb[k].0 == b[k].1);
        if !(within && on_face) {
            return Err(format!("end point {p} is not on the box's boundary"));
        }
    }
    Ok(())
}

/// The certificate file of a traced curve: the system, every point's box and root
/// certificate, every arc and every component.
pub fn curve_certificate(system: &System, curves: &Curves) -> Value {
    certificate_with(system_to_json(system), curves)
}

/// [`curve_certificate`] for a system with B-spline equations (stored as given).
pub fn piecewise_curve_certificate(system: &PiecewiseSystem, curves: &Curves) -> Value {
    certificate_with(piecewise_system_to_json(system), curves)
}

fn certificate_with(system: Value, curves: &Curves) -> Value {
    let exact = |b: &RationalBox| {
        b.iter()
            .map(|(lo, hi)| json!([rational_to_string(lo), rational_to_string(hi)]))
            .collect::<Vec<_>>()
    };
    json!({
        "kind": CURVE_CERTIFICATE_KIND,
        "system": system,
        "points": curves.points.iter().map(|p| json!({
            "axis": p.axis,
            "box": exact(&p.root.bounds),
            "preconditioner": serde_json::to_value(&p.root.certificate).unwrap_or_default()["preconditioner"],
            "lower_face_signs": p.root.certificate.lower_face_signs,
        })).collect::<Vec<_>>(),
        "arcs": curves.arcs.iter().map(|a| json!({
            "box": exact(&a.bounds),
            "ends": a.ends,
            "monotone_axis": a.monotone_axis,
        })).collect::<Vec<_>>(),
        "components": curves.components.iter().map(|c| json!({
            "points": c.points,
            "arcs": c.arcs,
            "closed": c.closed,
        })).collect::<Vec<_>>(),
    })
}

/// Reads a curve certificate file back and re-checks it with [`verify_curves`] (or
/// [`verify_piecewise_curves`] when its equations have knots inside the box).
pub fn verify_curve_certificate(
    text: &str,
) -> Result<Result<CurveCheck, CurveRefusal>, SolveError> {
    let v: Value = serde_json::from_str(text).map_err(|e| SolveError::Json(e.to_string()))?;
    let field = |f: String, why: &str| SolveError::Field {
        field: f,
        why: why.into(),
    };
    if v.get("kind").and_then(Value::as_str) != Some(CURVE_CERTIFICATE_KIND) {
        return Err(field(
            "kind".into(),
            &format!("expected {CURVE_CERTIFICATE_KIND:?}"),
        ));
    }
    let system = piecewise_system_from_json(&v["system"].to_string())?;
    let n = system.unknowns();
    let list = |name: &str| {
        v.get(name)
            .and_then(Value::as_array)
            .ok_or_else(|| field(name.into(), "missing or not an array"))
    };
    let index_list = |x: &Value, name: String| -> Result<Vec<usize>, SolveError> {
        x.as_array()
            .and_then(|a| {
                a.iter()
                    .map(|i| i.as_u64().map(|i| i as usize))
                    .collect::<Option<Vec<_>>>()
            })
            .ok_or_else(|| field(name, "expected an array of indices"))
    };
    let mut points = Vec::new();
    for (i, p) in list("points")?.iter().enumerate() {
        let axis = p
            .get("axis")
            .and_then(Value::as_u64)
            .map(|a| a as usize)
            .filter(|&a| a < n)
            .ok_or_else(|| field(format!("points[{i}].axis"), "expected an axis index"))?;
        let bounds = parse_box(p.get("box"), &format!("points[{i}].box"), Some(n))?;
        let certificate = certificate_from_json(p, n - 1)?;
        let approx = bounds
            .iter()
            .map(|(a, b)| {
                crate::num::rational_to_f64(&((a + b) / Rational::from_integer(2.into())))
            })
            .collect();
        points.push(super::CurvePoint {
            axis,
            root: super::Root {
                bounds,
                approx,
                error_bound: 0.0,
                certificate,
            },
        });
    }
    let mut arcs = Vec::new();
    for (i, a) in list("arcs")?.iter().enumerate() {
        let bounds = parse_box(a.get("box"), &format!("arcs[{i}].box"), Some(n))?;
        let ends = index_list(&a["ends"], format!("arcs[{i}].ends"))?;
        let ends: [usize; 2] = ends
            .try_into()
            .map_err(|_| field(format!("arcs[{i}].ends"), "expected two indices"))?;
        let monotone_axis = a
            .get("monotone_axis")
            .and_then(Value::as_u64)
            .map(|a| a as usize)
            .ok_or_else(|| field(format!("arcs[{i}].monotone_axis"), "expected an axis"))?;
        arcs.push(Arc {
            bounds,
            ends,
            monotone_axis,
        });
    }
    let mut components = Vec::new();
    for (i, c) in list("components")?.iter().enumerate() {
        components.push(super::Component {
            points: index_list(&c["points"], format!("components[{i}].points"))?,
            arcs: index_list(&c["arcs"], format!("components[{i}].arcs"))?,
            closed: c
                .get("closed")
                .and_then(Value::as_bool)
                .ok_or_else(|| field(format!("components[{i}].closed"), "expected a boolean"))?,
            ends: Vec::new(),
            hausdorff_bound: 0.0,
        });
    }
    let curves = Curves {
        points,
        arcs,
        components,
        extremes: Vec::new(),
        extreme_clusters: Vec::new(),
        clusters: Vec::new(),
        cluster_groups: Vec::new(),
        boxes_visited: 0,
        cross_sections: 0,
        path: crate::Path::Exact,
    };
    Ok(match system.polynomial() {
        Some(p) => verify_curves(p, &curves),
        None => verify_piecewise_curves(&system, &curves),
    })
}
