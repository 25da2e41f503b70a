//! The curve-tracing part of `reports/solve.md`: curves whose exact rational points are
//! known (circles from Pythagorean parameters, space curves that are graphs over `x`),
//! traced on every path; every sampled point must lie in a traced arc or cluster box, every
//! traced curve must pass the independent checker, and circles well inside the box must come
//! back as exactly one loop. One family is of B-spline equations with C⁰ kinks.

use super::solve::{median, Rng};
use crate::bspline::{Spline, TensorSpline};
use crate::num::{rational_to_string, Rational};
use crate::solve::{
    system_from_json, trace_piecewise, verify_curves, verify_piecewise_curves, CurveOptions,
    Curves, Equation, PiecewiseSystem,
};
use crate::Path as Arith;
use std::fmt::Write as _;
use std::time::Instant;

/// One family's tally on one path.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct CurveTally {
    /// Curves traced.
    pub curves: usize,
    /// Components in all (loops among them).
    pub components: usize,
    /// Closed loops.
    pub loops: usize,
    /// Curves whose topology is known (a circle well inside the box: one loop) and came
    /// back right, of those known.
    pub topology_right: (usize, usize),
    /// Cluster boxes reported.
    pub clusters: usize,
    /// Exact curve points sampled inside the box.
    pub sampled: usize,
    /// Sampled points in no arc or cluster box: must be 0.
    pub missing: usize,
    /// Curves the checker refused: must be 0.
    pub refused: usize,
    /// Certified vertices in all.
    pub vertices: usize,
    /// Largest Hausdorff bound of a component, relative to the box's side.
    pub worst_hausdorff: f64,
    /// Median milliseconds per curve.
    pub median_ms: f64,
}

/// One family of curves.
#[derive(Clone, Debug, serde::Serialize)]
pub struct CurveRow {
    /// What the curves are.
    pub name: String,
    /// Per path.
    pub paths: Vec<(String, CurveTally)>,
}

struct CurveCase {
    system: PiecewiseSystem,
    points: Vec<Vec<Rational>>,
    one_loop: bool,
}

fn r(p: i64, q: i64) -> Rational {
    Rational::new(p.into(), q.into())
}

/// A circle about `(cx, cy)` of radius `rho` on `[−1, 1]²` and its rational points
/// `c + ρ((1 − t²), 2t)/(1 + t²)`.
fn circle(cx: Rational, cy: Rational, rho: Rational) -> CurveCase {
    let s = |q: &Rational| format!("\"{}\"", rational_to_string(q));
    let two = r(2, 1);
    let text = format!(
        r#"{{"box": [["-1","1"],["-1","1"]], "equations": [{{"terms": [[[2,0],1],[[0,2],1],[[1,0],{}],[[0,1],{}],[[0,0],{}]]}}]}}"#,
        s(&(-&two * &cx)),
        s(&(-&two * &cy)),
        s(&(&cx * &cx + &cy * &cy - &rho * &rho))
    );
    let one = r(1, 1);
    let points = (-24..=24)
        .map(|k| {
            let t = r(k, 8);
            let d = &one + &t * &t;
            vec![
                &cx + &rho * (&one - &t * &t) / &d,
                &cy + &rho * (&two * &t) / &d,
            ]
        })
        .filter(|p| p.iter().all(|v| v >= &-&one && v <= &one))
        .collect();
    let margin = r(1, 16);
    let one_loop = [&cx, &cy]
        .iter()
        .all(|c| *c - &rho > -&one + &margin && *c + &rho < &one - &margin);
    CurveCase {
        system: PiecewiseSystem::from_polynomial(
            system_from_json(&text).expect("well-formed circle"),
        ),
        points,
        one_loop,
    }
}

/// The space curve `y = p(x)`, `z = q(x)` (cubics) on `[−1, 1]³` and its rational points.
fn graph_curve(p: [i64; 4], q: [i64; 4], scale: i64) -> CurveCase {
    let term = |e: [usize; 3], c: Rational| format!("[[{},{},{}],\"{}\"]", e[0], e[1], e[2], c);
    let eq = |coef: [i64; 4], axis: usize| {
        let mut terms = vec![term(if axis == 1 { [0, 1, 0] } else { [0, 0, 1] }, r(1, 1))];
        for (k, &c) in coef.iter().enumerate() {
            if c != 0 {
                terms.push(term([k, 0, 0], r(-c, scale)));
            }
        }
        format!("{{\"terms\": [{}]}}", terms.join(","))
    };
    let text = format!(
        r#"{{"box": [["-1","1"],["-1","1"],["-1","1"]], "equations": [{}, {}]}}"#,
        eq(p, 1),
        eq(q, 2)
    );
    let eval = |c: [i64; 4], x: &Rational| {
        c.iter()
            .rev()
            .fold(r(0, 1), |acc, &k| acc * x + r(k, scale))
    };
    let one = r(1, 1);
    let points = (-48..=48)
        .map(|k| {
            let x = r(k, 48);
            let (y, z) = (eval(p, &x), eval(q, &x));
            vec![x, y, z]
        })
        .filter(|p| p.iter().all(|v| v >= &-&one && v <= &one))
        .collect();
    CurveCase {
        system: PiecewiseSystem::from_polynomial(
            system_from_json(&text).expect("well-formed curve"),
        ),
        points,
        one_loop: false,
    }
}

/// `x_axis − s(x_0)` for the univariate spline `s` (degree `p`, `knots`, `coeffs`) as a
/// tensor B-spline in three unknowns on `[0, 1]³`.
fn graph_equation(axis: usize, s: &Spline<Rational>) -> Equation {
    let mut degrees = vec![0; 3];
    degrees[0] = s.degree();
    degrees[axis] = 1;
    let knots = (0..3)
        .map(|k| match k {
            0 => s.knots().to_vec(),
            k if k == axis => vec![r(0, 1), r(0, 1), r(1, 1), r(1, 1)],
            _ => vec![r(0, 1), r(1, 1)],
        })
        .collect();
    // Partition of unity: Σ_i Σ_l (l − c_i) N_i(x_0) M_l(x_axis) = x_axis − s(x_0).
    let coeffs = (0..2)
        .flat_map(|l| s.coeffs().iter().map(move |c| r(l, 1) - c))
        .collect();
    Equation::Spline(
        TensorSpline::new(degrees, knots, coeffs).expect("graph equations are well formed"),
    )
}

/// The space curve `y = g(x)`, `z = h(x)` on `[0, 1]³` with `g` piecewise linear (kinks at
/// `gk`) and `h` quadratic with a double knot at `hk` (a kink), coefficients in `[1/8, 7/8]`;
/// and its rational points.
fn kinked_graph(gk: &[Rational], gc: &[Rational], hk: &Rational, hc: &[Rational]) -> CurveCase {
    let clamp = |p: usize, inner: &[Rational]| {
        let mut k = vec![r(0, 1); p + 1];
        k.extend(inner.iter().cloned());
        k.extend(vec![r(1, 1); p + 1]);
        k
    };
    let g = Spline::new(1, clamp(1, gk), gc.to_vec()).expect("g is well formed");
    let h =
        Spline::new(2, clamp(2, &[hk.clone(), hk.clone()]), hc.to_vec()).expect("h is well formed");
    let system = PiecewiseSystem::new(
        vec![(r(0, 1), r(1, 1)); 3],
        vec![graph_equation(1, &g), graph_equation(2, &h)],
    )
    .expect("graph systems are well formed");
    let points = (0..=48)
        .map(|k| {
            let x = r(k, 48);
            let (y, z) = (g.eval(&x).expect("inside"), h.eval(&x).expect("inside"));
            vec![x, y, z]
        })
        .collect();
    CurveCase {
        system,
        points,
        one_loop: false,
    }
}

fn covered(c: &Curves, x: &[Rational]) -> bool {
    let inside =
        |b: &[(Rational, Rational)]| b.iter().zip(x).all(|((lo, hi), v)| lo <= v && v <= hi);
    c.arcs.iter().any(|a| inside(&a.bounds)) || c.clusters.iter().any(|k| inside(&k.bounds))
}

/// Traces `count` curves of each family on every path.
pub fn curve_campaign(seed: u64, count: usize) -> Vec<CurveRow> {
    let mut rng = Rng(seed | 1);
    let circles: Vec<CurveCase> = (0..count)
        .map(|_| {
            circle(
                r(rng.int(-12, 12), 16),
                r(rng.int(-12, 12), 16),
                r(rng.int(2, 16), 16),
            )
        })
        .collect();
    let graphs: Vec<CurveCase> = (0..count)
        .map(|_| {
            let mut c = || {
                [
                    rng.int(-4, 4),
                    rng.int(-6, 6),
                    rng.int(-6, 6),
                    rng.int(-6, 6),
                ]
            };
            let (p, q) = (c(), c());
            graph_curve(p, q, 8)
        })
        .collect();
    let kinked: Vec<CurveCase> = (0..count)
        .map(|_| {
            let mut gk: Vec<i64> = Vec::new();
            while gk.len() < 3 {
                let x = rng.int(2, 30);
                if !gk.contains(&x) {
                    gk.push(x);
                }
            }
            gk.sort_unstable();
            let gk: Vec<Rational> = gk.into_iter().map(|x| r(x, 32)).collect();
            let mut c = |count: usize| (0..count).map(|_| r(rng.int(4, 28), 32)).collect();
            let (gc, hc): (Vec<Rational>, Vec<Rational>) = (c(5), c(5));
            kinked_graph(&gk, &gc, &r(rng.int(3, 13), 16), &hc)
        })
        .collect();
    let mut rows = Vec::new();
    for (name, cases) in [
        ("circles on [−1, 1]² (radius 1/8 to 1)", circles),
        ("space cubics y = p(x), z = q(x) on [−1, 1]³", graphs),
        (
            "C⁰ B-spline graphs y = g(x), z = h(x) on [0, 1]³ (4 kinks)",
            kinked,
        ),
    ] {
        let mut paths = Vec::new();
        for path in [Arith::Exact, Arith::Fast, Arith::Filtered] {
            let mut t = CurveTally::default();
            let mut times = Vec::new();
            for case in &cases {
                let opts = CurveOptions::new().with_path(path);
                let limits = opts
                    .limits
                    .with_time_limit(Some(std::time::Duration::from_secs(20)));
                let clock = Instant::now();
                let Ok(c) = trace_piecewise(&case.system, &opts.with_limits(limits)) else {
                    t.refused += 1;
                    continue;
                };
                times.push(clock.elapsed().as_secs_f64());
                t.curves += 1;
                t.components += c.components.len();
                t.loops += c.components.iter().filter(|k| k.closed).count();
                t.clusters += c.clusters.len();
                t.vertices += c.points.len();
                if case.one_loop {
                    t.topology_right.1 += 1;
                    if c.components.len() == 1 && c.components[0].closed && c.clusters.is_empty() {
                        t.topology_right.0 += 1;
                    }
                }
                for x in &case.points {
                    t.sampled += 1;
                    if !covered(&c, x) {
                        t.missing += 1;
                    }
                }
                let check = match case.system.polynomial() {
                    Some(p) => verify_curves(p, &c),
                    None => verify_piecewise_curves(&case.system, &c),
                };
                if check.is_err() {
                    t.refused += 1;
                }
                let side = crate::num::rational_to_f64(
                    &(&case.system.domain()[0].1 - &case.system.domain()[0].0),
                );
                for k in &c.components {
                    t.worst_hausdorff = t.worst_hausdorff.max(k.hausdorff_bound / side);
                }
            }
            t.median_ms = 1e3 * median(times);
            paths.push((path.name().to_string(), t));
        }
        rows.push(CurveRow {
            name: name.into(),
            paths,
        });
    }
    rows
}

/// Whether nothing was missing or refused and every known topology came back right.
pub fn curves_ok(rows: &[CurveRow]) -> bool {
    rows.iter().all(|row| {
        row.paths.iter().all(|(_, t)| {
            t.missing == 0 && t.refused == 0 && t.topology_right.0 == t.topology_right.1
        })
    })
}

/// The markdown section.
pub fn curves_markdown(rows: &[CurveRow]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "\n## Curves (n − 1 equations in n unknowns)\n\n`solve::trace` subdivides into boxes \
         where one component of the tangent (a Jacobian minor) has one strict sign and the \
         boundary holds exactly two certified crossing points (one arc joins them) or none; \
         what cannot be resolved within 16 levels is a cluster. The curves here have exact \
         rational points known by construction: circles from Pythagorean parameters \
         `c + ρ(1 − t², 2t)/(1 + t²)`, space cubics that are graphs over x, and graphs over x \
         of B-splines with C⁰ kinks (`g` piecewise linear with three kinks, `h` quadratic with a \
         double knot), whose equations are B-spline fields (`solve::trace_piecewise`: boxes \
         split exactly at the kink planes, every crossing of one a certified vertex; checked \
         by `verify_piecewise_curves`). *Missing* counts \
         sampled points in no arc or cluster box, *refused* curves the independent checker \
         (`verify_curves`: every vertex the unique root on its plane, every arc box's minor of \
         one sign, components re-walked) rejects; both must be 0. A circle at least 1/16 inside \
         the box must come back as exactly one loop. The Hausdorff bound is the largest arc \
         box diagonal plus vertex error, relative to the box side, with the default \
         resolution 1/16.\n\n\
         | curves | path | traced | components | loops | one loop where known | clusters | \
         vertices | points sampled | missing | refused | worst Hausdorff bound | median ms |\n\
         |---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    for row in rows {
        for (p, t) in &row.paths {
            let _ = writeln!(
                s,
                "| {} | {p} | {} | {} | {} | {}/{} | {} | {} | {} | {} | {} | {:.3} | {:.1} |",
                row.name,
                t.curves,
                t.components,
                t.loops,
                t.topology_right.0,
                t.topology_right.1,
                t.clusters,
                t.vertices,
                t.sampled,
                t.missing,
                t.refused,
                t.worst_hausdorff,
                t.median_ms
            );
        }
    }
    s
}
