//! Curve tracing: constructed curves of known topology on every path, checked by the
//! independent checker, and exact rational points of each curve found inside the traced
//! arc or cluster boxes (nothing lost).

use geocert::num::Rational;
use geocert::solve::{
    curve_certificate, system_from_json, trace, verify_curve_certificate, verify_curves, CurveEnd,
    CurveOptions, Curves, System,
};
use geocert::Path;
use proptest::prelude::*;

fn r(p: i64, q: i64) -> Rational {
    Rational::new(p.into(), q.into())
}

fn traced(s: &System, path: Path) -> Curves {
    let c = trace(
        s,
        &CurveOptions::new()
            .with_path(path)
            .with_extreme_axis(Some(0)),
    )
    .unwrap();
    let check = verify_curves(s, &c).unwrap();
    assert_eq!(check.points, c.points.len());
    c
}

fn summary(c: &Curves) -> String {
    format!(
        "{} components ({} closed), {} arcs, {} points, {} clusters, {} extremes, {} boxes, {} cross-sections",
        c.components.len(),
        c.components.iter().filter(|k| k.closed).count(),
        c.arcs.len(),
        c.points.len(),
        c.clusters.len(),
        c.extremes.len(),
        c.boxes_visited,
        c.cross_sections
    )
}

/// Whether an exact curve point lies in some arc box or cluster box (closed boxes).
fn covered(c: &Curves, x: &[Rational]) -> bool {
    let inside =
        |b: &[(Rational, Rational)]| b.iter().zip(x).all(|((lo, hi), v)| lo <= v && v <= hi);
    c.arcs.iter().any(|a| inside(&a.bounds)) || c.clusters.iter().any(|k| inside(&k.bounds))
}

/// Rational points of the circle `(x−cx)² + (y−cy)² = ρ²` from Pythagorean triples.
fn circle_points(cx: &Rational, cy: &Rational, rho: &Rational, count: i64) -> Vec<Vec<Rational>> {
    (-count..=count)
        .map(|k| {
            let t = r(k, count.max(1)) * r(3, 1);
            let d = Rational::from_integer(1.into()) + &t * &t;
            let cos = (Rational::from_integer(1.into()) - &t * &t) / &d;
            let sin = (r(2, 1) * &t) / &d;
            vec![cx + rho * cos, cy + rho * sin]
        })
        .collect()
}

fn circle(cx: &str, cy: &str, rho2: &str, bx: &str) -> String {
    // (x − cx)² + (y − cy)² − ρ² = x² + y² − 2cx x − 2cy y + cx² + cy² − ρ².
    let (cx, cy, rho2) = (
        geocert::num::parse_rational(cx).unwrap(),
        geocert::num::parse_rational(cy).unwrap(),
        geocert::num::parse_rational(rho2).unwrap(),
    );
    let s = |q: Rational| format!("\"{q}\"");
    format!(
        r#"{{"box": {bx}, "equations": [{{"terms": [[[2,0],1],[[0,2],1],[[1,0],{}],[[0,1],{}],[[0,0],{}]]}}]}}"#,
        s(-r(2, 1) * &cx),
        s(-r(2, 1) * &cy),
        s(&cx * &cx + &cy * &cy - rho2)
    )
}

#[test]
fn circle_inside_the_box_is_one_loop_on_every_path() {
    let s = system_from_json(&circle("0", "0", "1/4", r#"[["-1","1"],["-1","1"]]"#)).unwrap();
    for path in [Path::Fast, Path::Filtered, Path::Exact] {
        let c = traced(&s, path);
        println!("{path}: {}", summary(&c));
        assert_eq!(c.components.len(), 1);
        assert!(c.components[0].closed && c.components[0].ends.is_empty());
        assert!(c.clusters.is_empty());
        // Extreme in x at (±1/2, 0), both on the loop.
        assert_eq!(c.extremes.len(), 2);
        assert!(c.extremes.iter().all(|e| e.component == Some(0)));
        for p in &c.points {
            let (x, y) = (p.root.approx[0], p.root.approx[1]);
            assert!((x * x + y * y - 0.25).abs() < 1e-9);
        }
        for x in circle_points(&r(0, 1), &r(0, 1), &r(1, 2), 40) {
            assert!(covered(&c, &x), "{x:?} lost");
        }
        assert!(c.components[0].hausdorff_bound < 0.2);
    }
}

#[test]
fn circle_cut_by_the_box_is_two_open_arcs_ending_on_faces() {
    // Centre (1, 0), radius 1/2 on [-1, 1]²: the right half is outside.
    let s = system_from_json(&circle("1", "0", "1/4", r#"[["-1","1"],["-1","1"]]"#)).unwrap();
    let c = traced(&s, Path::Filtered);
    println!("{}", summary(&c));
    assert_eq!(c.components.len(), 1);
    let k = &c.components[0];
    assert!(!k.closed);
    assert_eq!(k.ends.len(), 2);
    for e in &k.ends {
        assert!(
            matches!(
                e,
                CurveEnd::Face {
                    axis: 0,
                    upper: true,
                    ..
                }
            ),
            "{e:?}"
        );
    }
    for x in circle_points(&r(1, 1), &r(0, 1), &r(1, 2), 40) {
        if x[0] <= r(1, 1) {
            assert!(covered(&c, &x));
        }
    }
}

#[test]
fn two_circles_are_two_loops_and_a_crossing_is_a_cluster() {
    // (x² + y² − 1/25)((x − 1/2)² + y² − 1/25) on [-1, 1]²: disjoint, two loops.
    let text = r#"{"box": [["-1","1"],["-1","1"]], "equations": [{"terms": [
        [[4,0],1],[[2,2],2],[[0,4],1],[[3,0],-1],[[1,2],-1],[[2,0],"17/100"],[[0,2],"17/100"],
        [[1,0],"1/25"],[[0,0],"-21/2500"]]}]}"#;
    let s = system_from_json(text).unwrap();
    let c = traced(&s, Path::Filtered);
    println!("two circles: {}", summary(&c));
    assert_eq!(c.components.iter().filter(|k| k.closed).count(), 2);
    assert!(c.clusters.is_empty());
    for x in circle_points(&r(0, 1), &r(0, 1), &r(1, 5), 20)
        .into_iter()
        .chain(circle_points(&r(1, 2), &r(0, 1), &r(1, 5), 20))
    {
        assert!(covered(&c, &x));
    }
    // Radius 1/4: the circles touch at (1/4, 0), a singular point of the product: a cluster.
    let text = r#"{"box": [["-1","1"],["-1","1"]], "equations": [{"terms": [
        [[4,0],1],[[2,2],2],[[0,4],1],[[3,0],-1],[[1,2],-1],[[2,0],"1/8"],[[0,2],"1/8"],
        [[1,0],"1/16"],[[0,0],"-3/256"]]}]}"#;
    let s = system_from_json(text).unwrap();
    let c = traced(&s, Path::Filtered);
    println!("touching circles: {}", summary(&c));
    let touch = [r(1, 4), r(0, 1)];
    assert!(c.clusters.iter().any(|k| k
        .bounds
        .iter()
        .zip(&touch)
        .all(|((a, b), v)| a <= v && v <= b)));
    for x in circle_points(&r(0, 1), &r(0, 1), &r(1, 4), 20)
        .into_iter()
        .chain(circle_points(&r(1, 2), &r(0, 1), &r(1, 4), 20))
    {
        assert!(covered(&c, &x));
    }
    // x·y = 0: the axes cross at the origin, a singular point: a cluster there, and four
    // open components each from a face to that cluster.
    let text = r#"{"box": [["-1","1"],["-1","1"]], "equations": [{"terms": [[[1,1],1]]}]}"#;
    let s = system_from_json(text).unwrap();
    let c = traced(&s, Path::Filtered);
    println!("cross: {}", summary(&c));
    assert!(!c.clusters.is_empty());
    let zero = vec![r(0, 1), r(0, 1)];
    assert!(c.clusters.iter().any(|k| k
        .bounds
        .iter()
        .zip(&zero)
        .all(|((a, b), v)| a <= v && v <= b)));
    assert_eq!(c.components.len(), 4);
    for k in &c.components {
        assert!(k.ends.iter().any(|e| matches!(e, CurveEnd::Face { .. })));
        assert!(k.ends.iter().any(|e| matches!(e, CurveEnd::Cluster { .. })));
    }
    for i in -20..=20 {
        assert!(covered(&c, &[r(i, 20), r(0, 1)]) && covered(&c, &[r(0, 1), r(i, 20)]));
    }
}

#[test]
fn space_curves() {
    // The twisted cubic y = x², z = x³ on [-1,1]³ … as y − x² = 0, z − x·y = 0: one open
    // component from the face x = −1 to the face x = 1, no extreme in x.
    let text = r#"{"box": [["-1","1"],["-1","1"],["-1","1"]], "equations": [
        {"terms": [[[0,1,0],1],[[2,0,0],-1]]}, {"terms": [[[0,0,1],1],[[1,1,0],-1]]}]}"#;
    let s = system_from_json(text).unwrap();
    for path in [Path::Fast, Path::Filtered] {
        let c = traced(&s, path);
        println!("twisted cubic {path}: {}", summary(&c));
        assert_eq!(c.components.len(), 1);
        assert!(c.extremes.is_empty());
        let k = &c.components[0];
        assert_eq!(k.ends.len(), 2);
        for i in -16..=16 {
            let x = r(i, 16);
            assert!(covered(&c, &[x.clone(), &x * &x, &x * &x * &x]));
        }
    }
    // A sphere cut by a plane: one loop, extreme twice in x.
    let text = r#"{"box": [["-1","1"],["-1","1"],["-1","1"]], "equations": [
        {"terms": [[[2,0,0],1],[[0,2,0],1],[[0,0,2],1],[[0,0,0],"-1/2"]]},
        {"terms": [[[0,0,1],1],[[1,0,0],"-1/3"],[[0,0,0],"-1/5"]]}]}"#;
    let s = system_from_json(text).unwrap();
    let c = traced(&s, Path::Filtered);
    println!("sphere ∩ plane: {}", summary(&c));
    assert_eq!(c.components.len(), 1);
    assert!(c.components[0].closed);
    assert_eq!(c.extremes.len(), 2);
    // The certificate file round-trips and re-checks.
    let cert = curve_certificate(&s, &c).to_string();
    let check = verify_curve_certificate(&cert).unwrap().unwrap();
    assert_eq!(check.arcs, c.arcs.len());
    // A tampered certificate is refused: an arc box moved off its points.
    let mut v: serde_json::Value = serde_json::from_str(&cert).unwrap();
    v["arcs"][0]["box"][0] = serde_json::json!(["-1", "-63/64"]);
    v["arcs"][0]["box"][1] = serde_json::json!(["-1", "-63/64"]);
    v["arcs"][0]["box"][2] = serde_json::json!(["-1", "-63/64"]);
    assert!(verify_curve_certificate(&v.to_string()).unwrap().is_err());
}

#[test]
fn wrong_counts_and_axes_are_errors() {
    let square = r#"{"box": [["0","1"],["0","1"]], "equations": [{"terms": [[[1,0],1]]}, {"terms": [[[0,1],1]]}]}"#;
    let s = system_from_json(square).unwrap();
    assert!(trace(&s, &CurveOptions::new()).is_err());
    let one = system_from_json(&circle("0", "0", "1/4", r#"[["-1","1"],["-1","1"]]"#)).unwrap();
    assert!(trace(&one, &CurveOptions::new().with_extreme_axis(Some(2))).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Random circles: every certified vertex passes the checker, the fast and exact paths
    /// agree on the topology where neither leaves a cluster, and rational points of the
    /// circle inside the box all lie in traced boxes.
    #[test]
    fn random_circles(cx in -12i64..=12, cy in -12i64..=12, rho in 1i64..=12) {
        let (cx, cy, rho) = (r(cx, 8), r(cy, 8), r(rho, 8));
        let text = circle(&cx.to_string(), &cy.to_string(), &(&rho * &rho).to_string(), r#"[["-1","1"],["-1","1"]]"#);
        let s = system_from_json(&text).unwrap();
        let fast = traced(&s, Path::Fast);
        let exact = traced(&s, Path::Exact);
        if fast.clusters.is_empty() && exact.clusters.is_empty() {
            let shape = |c: &Curves| {
                let mut v: Vec<(bool, usize)> = c.components.iter().map(|k| (k.closed, k.ends.len())).collect();
                v.sort();
                v
            };
            prop_assert_eq!(shape(&fast), shape(&exact));
        }
        let inside_box = |x: &[Rational]| x.iter().all(|v| v >= &r(-1, 1) && v <= &r(1, 1));
        for x in circle_points(&cx, &cy, &rho, 12) {
            if inside_box(&x) {
                prop_assert!(covered(&fast, &x) && covered(&exact, &x), "{:?} lost", x);
            }
        }
    }
}
