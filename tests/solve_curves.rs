//! Curve tracing: constructed curves with known topology, on every path.

use geocert::solve::{system_from_json, trace, CurveEnd, CurveOptions, Curves};
use geocert::Path;

fn run(text: &str, path: Path) -> Curves {
    let s = system_from_json(text).unwrap();
    trace(
        &s,
        &CurveOptions::new()
            .with_path(path)
            .with_extreme_axis(Some(0)),
    )
    .unwrap()
}

fn summary(c: &Curves) -> String {
    format!(
        "{} components ({} closed), {} arcs, {} points, {} clusters, {} extremes, {} boxes",
        c.components.len(),
        c.components.iter().filter(|k| k.closed).count(),
        c.arcs.len(),
        c.points.len(),
        c.clusters.len(),
        c.extremes.len(),
        c.boxes_visited
    )
}

#[test]
fn circle_is_one_loop() {
    let text = r#"{"box": [["-1","1"],["-1","1"]], "equations": [{"terms": [[[2,0],1],[[0,2],1],[[0,0],"-1/4"]]}]}"#;
    for path in [Path::Fast, Path::Filtered, Path::Exact] {
        let c = run(text, path);
        println!("{path}: {}", summary(&c));
        assert_eq!(c.components.len(), 1);
        assert!(c.components[0].closed);
        assert!(c.clusters.is_empty());
        assert_eq!(c.extremes.len(), 2);
        for p in &c.points {
            let (x, y) = (p.root.approx[0], p.root.approx[1]);
            assert!((x * x + y * y - 0.25).abs() < 1e-9);
        }
    }
}
