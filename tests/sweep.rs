//! Swept-volume silhouettes against an independent oracle: a moving ellipsoid is the zero set
//! of `φ(x, t) = |D⁻¹(M(t)⁻¹(x − T(t)) − c)|² − 1` (`D` its radii), so an envelope silhouette
//! point satisfies `φ = 0`, `φ_t = 0` (the characteristic curve) and `∇φ · (x − P) = 0` (the
//! contour from the eye) — conditions computed here in `f64` from the scene's motion, not from
//! the library's F and G.

use geocert::internals::report::sweep as report;
use geocert::num::{rational_to_f64, Rational};
use geocert::solve::RootCheck;
use geocert::sweep::{
    builtin_scene, equations, scene_from_json, silhouette, verify_cap_border_touch,
    verify_cap_corner_passage, verify_ruling, verify_t_extreme, ComponentEnd, ComponentKind,
    ComponentType, Eye, RulingEvidence, Scene, SilhouetteOptions, Silhouettes, SweepError,
};
use geocert::Path;

/// An ellipsoid under the scene's motion, in `f64`.
struct Oracle {
    centre: [f64; 3],
    radii: [f64; 3],
    eye: [f64; 3],
    scene: Scene,
}

fn horner(p: &[geocert::num::Rational], t: f64) -> f64 {
    p.iter()
        .rev()
        .fold(0.0, |acc, c| acc * t + rational_to_f64(c))
}

fn inverse(m: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    // The adjugate's (i, j) entry is the cofactor of (j, i).
    [0, 1, 2].map(|i| {
        [0, 1, 2].map(|j| {
            let (a, b) = ((j + 1) % 3, (j + 2) % 3);
            let (c, d) = ((i + 1) % 3, (i + 2) % 3);
            (m[a][c] * m[b][d] - m[a][d] * m[b][c]) / det
        })
    })
}

impl Oracle {
    fn new(scene: Scene, centre: [f64; 3], radii: [f64; 3]) -> Oracle {
        let Eye::Point(p) = &scene.eye else {
            panic!("a fixed eye")
        };
        let eye = [0, 1, 2].map(|k| rational_to_f64(&p[k]));
        Oracle {
            centre,
            radii,
            eye,
            scene,
        }
    }

    /// `y(x, t)`: the point's preimage on the unit sphere's scale.
    fn y(&self, x: [f64; 3], t: f64) -> [f64; 3] {
        let m = &self.scene.motion;
        let d = horner(&m.denominator, t);
        let lin = [0, 1, 2].map(|i| [0, 1, 2].map(|j| horner(&m.linear[i][j], t) / d));
        let tr = [0, 1, 2].map(|i| horner(&m.translation[i], t) / d);
        let inv = inverse(lin);
        let v = [0, 1, 2].map(|k| x[k] - tr[k]);
        [0, 1, 2].map(|i| {
            let s: f64 = (0..3).map(|j| inv[i][j] * v[j]).sum();
            (s - self.centre[i]) / self.radii[i]
        })
    }

    fn phi(&self, x: [f64; 3], t: f64) -> f64 {
        self.y(x, t).iter().map(|a| a * a).sum::<f64>() - 1.0
    }

    fn gradient(&self, x: [f64; 3], t: f64) -> [f64; 3] {
        let h = 1e-6;
        [0, 1, 2].map(|k| {
            let (mut a, mut b) = (x, x);
            a[k] += h;
            b[k] -= h;
            (self.phi(a, t) - self.phi(b, t)) / (2.0 * h)
        })
    }

    /// `(|φ|, |φ_t| / |∇φ|, |∇φ·(x−P)| / (|∇φ| |x−P|))` at a traced point.
    fn residuals(&self, x: [f64; 3], t: f64) -> (f64, f64, f64) {
        let h = 1e-6;
        let g = self.gradient(x, t);
        let gn = g.iter().map(|a| a * a).sum::<f64>().sqrt();
        let phi_t = (self.phi(x, t + h) - self.phi(x, t - h)) / (2.0 * h);
        let s = [0, 1, 2].map(|k| x[k] - self.eye[k]);
        let sn = s.iter().map(|a| a * a).sum::<f64>().sqrt();
        let contour: f64 = (0..3).map(|k| g[k] * s[k]).sum::<f64>() / (gn * sn);
        (self.phi(x, t).abs(), phi_t.abs() / gn, contour.abs())
    }

    /// The largest residuals over every vertex of every component of a kind.
    fn worst(&self, s: &Silhouettes, kind: ComponentKind) -> (f64, f64, f64, usize) {
        let mut w = (0.0f64, 0.0f64, 0.0f64, 0);
        for c in s.components.iter().filter(|c| c.kind == kind) {
            for (x, uvt) in c.points.iter().zip(&c.uvt) {
                let (a, b, d) = self.residuals(*x, uvt[2]);
                w = (w.0.max(a), w.1.max(b), w.2.max(d), w.3 + 1);
            }
        }
        w
    }
}

fn oracle_for(name: &str) -> Oracle {
    let scene = builtin_scene(name).unwrap();
    let (centre, radii) = match name {
        "sphere-line" | "sphere-cone" => ([0.0; 3], [1.0; 3]),
        "ellipsoid-line" => ([0.0; 3], [1.0, 0.5, 0.5]),
        "ellipsoid-turn" => ([0.0; 3], [2.0, 0.5, 0.5]),
        _ => unreachable!(),
    };
    Oracle::new(scene, centre, radii)
}

fn types(s: &Silhouettes) -> Vec<(Option<ComponentType>, Vec<ComponentEnd>)> {
    let mut v: Vec<_> = s
        .components
        .iter()
        .filter(|c| c.kind == ComponentKind::Envelope)
        .map(|c| {
            let mut ends = c.ends.clone();
            ends.sort_by_key(|e| format!("{e:?}"));
            (c.component_type, ends)
        })
        .collect();
    v.sort_by_key(|x| format!("{x:?}"));
    v
}

#[test]
fn moving_ellipsoids_silhouettes_lie_on_the_oracles_contour() {
    let time = ComponentEnd::Time { upper: false };
    let time_b = ComponentEnd::Time { upper: true };
    for name in [
        "sphere-line",
        "sphere-cone",
        "ellipsoid-line",
        "ellipsoid-turn",
    ] {
        let o = oracle_for(name);
        let s = silhouette(&o.scene, &SilhouetteOptions::default()).unwrap();
        assert!(
            s.clusters.is_empty(),
            "{name}: {} clusters",
            s.clusters.len()
        );
        let (phi, speed, contour, n) = o.worst(&s, ComponentKind::Envelope);
        println!(
            "{name}: {} components, {} t-extreme, {n} envelope vertices: |φ| ≤ {phi:.1e}, |φ_t|/|∇φ| ≤ {speed:.1e}, contour ≤ {contour:.1e}",
            s.components.len(),
            s.t_extreme.len()
        );
        assert!(n > 20, "{name}: {n} vertices");
        assert!(phi < 1e-9 && speed < 1e-6 && contour < 1e-9, "{name}");
        for kind in [ComponentKind::CapA, ComponentKind::CapB] {
            let t = if kind == ComponentKind::CapA { 0 } else { 1 };
            let (phi, _, contour, n) = o.worst(&s, kind);
            assert!(n > 20 && phi < 1e-9 && contour < 1e-9, "{name} cap {t}");
            // A convex body's contour from outside is one closed loop.
            let caps: Vec<_> = s.components.iter().filter(|c| c.kind == kind).collect();
            assert!(
                caps.len() == 1 && caps[0].closed,
                "{name}: {} caps",
                caps.len()
            );
        }
        // Each envelope silhouette of a convex body moving forward runs from t = a to t = b.
        let ty = types(&s);
        assert_eq!(ty.len(), 2, "{name}: {ty:?}");
        for (t, ends) in &ty {
            assert_eq!(ends, &vec![time, time_b], "{name}");
            if name == "ellipsoid-turn" {
                assert!(t.is_some());
            } else {
                assert_eq!(*t, Some(ComponentType::Monotone), "{name}");
            }
        }
    }
}

#[test]
fn the_turning_ellipsoid_has_certified_t_extreme_points_on_a_type_2_component() {
    let o = oracle_for("ellipsoid-turn");
    let s = silhouette(&o.scene, &SilhouetteOptions::default().with_caps(false)).unwrap();
    assert!(!s.t_extreme.is_empty());
    for x in &s.t_extreme {
        let c = x.component.expect("on a component");
        assert_eq!(
            s.components[c].component_type,
            Some(ComponentType::Extremes)
        );
        // The extreme's (u, v, t) maps onto the oracle's contour and characteristic curve.
        let patch = &o.scene.surfaces[0].patches[x.patch];
        let p = patch.point(x.root.approx[0], x.root.approx[1]).unwrap();
        let m = &o.scene.motion;
        let t = x.root.approx[2];
        let d = horner(&m.denominator, t);
        let world = [0, 1, 2].map(|i| {
            (horner(&m.translation[i], t)
                + (0..3)
                    .map(|j| horner(&m.linear[i][j], t) * p[j])
                    .sum::<f64>())
                / d
        });
        let (phi, speed, contour) = o.residuals(world, t);
        assert!(phi < 1e-9 && speed < 1e-6 && contour < 1e-9);
        // The certificate re-checks independently of the solver.
        verify_t_extreme(&o.scene, x, false).unwrap().unwrap();
    }
    println!(
        "ellipsoid-turn: {} certified t-extreme points, all on type-2 components",
        s.t_extreme.len()
    );
}

#[test]
fn eq_2_as_printed_is_off_the_contour_under_a_non_uniform_scale_and_exact_under_a_similarity() {
    for (name, similarity) in [("ellipsoid-line", false), ("sphere-cone", true)] {
        let o = oracle_for(name);
        let opts = SilhouetteOptions::default().with_caps(false);
        let right = silhouette(&o.scene, &opts).unwrap();
        let printed = silhouette(&o.scene, &opts.with_printed_eq2(true)).unwrap();
        let (_, _, good, _) = o.worst(&right, ComponentKind::Envelope);
        let (_, _, bad, n) = o.worst(&printed, ComponentKind::Envelope);
        println!(
            "{name}: contour residual with cof(M)N {good:.1e}, with eq. 2 as printed {bad:.1e} ({n} vertices)"
        );
        assert!(good < 1e-9);
        if similarity {
            assert!(bad < 1e-9, "{name}: a similarity keeps eq. 2 right");
        } else {
            assert!(
                bad > 1e-3,
                "{name}: eq. 2 as printed should miss the contour"
            );
        }
    }
}

#[test]
fn sphere_poles_are_divided_out_not_traced() {
    let scene = builtin_scene("sphere-line").unwrap();
    let eye = match &scene.eye {
        Eye::Point(p) => p.clone(),
        _ => unreachable!(),
    };
    for (k, patch) in scene.surfaces[0].patches.iter().enumerate() {
        let eq = equations(&scene, patch, &eye).unwrap();
        assert_eq!(eq.divided, vec![(0, k >= 4)], "patch {k}: its pole edge");
    }
    let s = silhouette(&scene, &SilhouetteOptions::default()).unwrap();
    // No component runs along a pole edge (u = 0 or u = 1 on every vertex).
    for c in &s.components {
        let on_pole = c.uvt.iter().filter(|p| p[0] == 0.0 || p[0] == 1.0).count();
        assert!(on_pole < c.uvt.len() / 2, "a component along a pole edge");
    }
    assert!(s.clusters.is_empty() && s.extreme_clusters.is_empty());
}

/// [`types`] of two `t`-monotone components from `t = a` to `t = b` (a capsule's outline).
fn two_monotone() -> Vec<(Option<ComponentType>, Vec<ComponentEnd>)> {
    let t3 = (
        Some(ComponentType::Monotone),
        vec![
            ComponentEnd::Time { upper: false },
            ComponentEnd::Time { upper: true },
        ],
    );
    vec![t3.clone(), t3]
}

/// The built-in sphere's patches are laid out around an axis through the direction
/// `n = (−286, −313, 278)/507` (the generic rotation of the meridian plane's normal
/// `(−12, 5, 0)/13`), so its meridian edges lie in the plane `⟨x, n⟩ = 0`. A translation along
/// `n` makes that great circle the characteristic curve at every time, along four patch edges;
/// a roll about `n` on top of it moves the contour points along the circle across patch
/// corners (`builtin:sphere-edge-roll`).
const ALONG_EDGES: &str = r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": 1}}], "t": [0, 1],
 "motion": {"translation": [[0, "-22/13"], [0, "-313/169"], [0, "278/169"]]},
 "eye": [5, "3/10", "11/10"]}"#;
/// Silhouettes that run along patch edges (the characteristic curve on a patch edge at every
/// time) are traced on the edge, once per shared edge, on every path, and lie on the oracle's
/// contour; before, every cross-section there had an identically zero equation and the tracer
/// ended in tens of thousands of clusters.
#[test]
fn silhouettes_along_patch_edges_are_traced_on_the_edges() {
    for name in ["translation", "roll"] {
        let scene = if name == "roll" {
            builtin_scene("sphere-edge-roll").unwrap()
        } else {
            scene_from_json(ALONG_EDGES).unwrap()
        };
        let oracle = Oracle::new(scene.clone(), [0.0; 3], [1.0; 3]);
        let opts = SilhouetteOptions::default().with_caps(false);
        let s = silhouette(&scene, &opts).unwrap();
        assert!(
            s.clusters.is_empty() && s.extreme_clusters.is_empty(),
            "{name}: {} clusters",
            s.clusters.len()
        );
        // The capsule's two outline lines, t-monotone from t = a to t = b.
        assert_eq!(types(&s), two_monotone(), "{name}");
        for c in &s.components {
            // Every vertex on a meridian edge (v = 0 or 1), none twice (each shared edge is
            // traced once).
            assert!(c.uvt.iter().all(|p| p[1] == 0.0 || p[1] == 1.0), "{name}");
        }
        let (c0, c1) = (&s.components[0], &s.components[1]);
        let overlap = c0
            .points
            .iter()
            .filter(|p| {
                c1.points
                    .iter()
                    .any(|q| (0..3).all(|k| (p[k] - q[k]).abs() < 1e-6))
            })
            .count();
        assert_eq!(overlap, 0, "{name}: the components overlap");
        let (phi, phi_t, contour, n) = oracle.worst(&s, ComponentKind::Envelope);
        assert!(
            phi < 1e-9 && phi_t < 1e-6 && contour < 1e-6,
            "{name}: residuals {phi:e} {phi_t:e} {contour:e}"
        );
        // The roll carries the contour points across patch corners: pieces of several
        // patches joined.
        let patches: std::collections::BTreeSet<usize> = s
            .components
            .iter()
            .flat_map(|c| c.patches.clone())
            .collect();
        let exact = silhouette(&scene, &opts.with_path(Path::Exact)).unwrap();
        let fast = silhouette(&scene, &opts.with_path(Path::Fast)).unwrap();
        assert_eq!(types(&exact), types(&s), "{name}: exact");
        if fast.clusters.is_empty() {
            assert_eq!(types(&fast), types(&s), "{name}: fast");
        }
        println!(
            "{name}: {n} vertices on {} patches within {phi:.1e} / {phi_t:.1e} / {contour:.1e} of \
             the oracle; filtered {:.3} s, exact {:.3} s",
            patches.len(),
            s.seconds,
            exact.seconds
        );
        if name == "roll" {
            assert!(patches.len() > 2, "roll: {patches:?}");
        }
    }
    // With an eye path, the face curve's own critical points are events too: here the
    // contour points reach patch corners at t = a and t = b for the same eye (the roll turns
    // by a quarter between them), which is a border event on each patch meeting there; all
    // re-check from the scene.
    let moving = r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": 1}}], "t": [0, 1],
        "motion": {"translation": [[0, "-22/13"], [0, "-313/169"], [0, "278/169"]],
                   "rotation": {"quaternion": [[1], [0, "-286/507"], [0, "-313/507"], [0, "278/507"]]}},
        "eye": {"path": [[5], ["3/10", 2], ["11/10"]], "r": [0, 1]}}"#;
    let scene = scene_from_json(moving).unwrap();
    let opts = geocert::solve::SolveOptions::new().with_tolerance(geocert::sweep::EVENT_TOLERANCE);
    let ev = geocert::sweep::events(&scene, &opts).unwrap();
    assert!(ev.clusters.is_empty(), "{} clusters", ev.clusters.len());
    assert!(!ev.events.is_empty());
    for e in &ev.events {
        assert!(
            matches!(e.kind, geocert::sweep::EventKind::AlongEdge { .. }),
            "{:?}",
            e.kind
        );
        assert!(e.kind.on_patch_border());
    }
    let checks = geocert::sweep::verify_events(&scene, &ev.events);
    assert!(checks.iter().all(|c| matches!(c, Ok(Ok(_)))));
    let groups = geocert::sweep::event_groups(&scene, &ev.events);
    println!(
        "moving eye along the edges: {} events ({} distinct), all re-checked",
        ev.events.len(),
        groups.len()
    );
    // Between its events the frames are continued along the edges (G alone there, F ≡ 0),
    // and the continued points lie on the oracle's contour from each frame's eye.
    let rs = [0.0, 0.1, 0.2, 0.3];
    let fr = geocert::sweep::frames(&scene, &rs, &SilhouetteOptions::default(), &opts).unwrap();
    let continued: Vec<_> = fr.frames.iter().filter(|f| !f.traced).collect();
    assert_eq!(continued.len(), 3, "continued frames");
    let mut worst = (0.0f64, 0.0f64, 0.0f64);
    for f in &continued {
        let mut fixed = scene.clone();
        fixed.eye = Eye::Point(
            [0, 1, 2].map(|k| geocert::num::rational_from_f64(f.eye[k], "eye").unwrap()),
        );
        let oracle = Oracle::new(fixed, [0.0; 3], [1.0; 3]);
        for c in &f.components {
            for (x, uvt) in c.points.iter().zip(&c.uvt) {
                let (a, b, d) = oracle.residuals(*x, uvt[2]);
                worst = (worst.0.max(a), worst.1.max(b), worst.2.max(d));
            }
        }
    }
    assert!(
        worst.0 < 1e-9 && worst.1 < 1e-6 && worst.2 < 1e-6,
        "continued frames off the contour: {worst:?}"
    );
}

/// `builtin:sphere-corner`: the silhouette passes through a patch corner at t = 1/2. Before,
/// the tracer left a cluster on each of the four patches there and the component in two
/// pieces ending in them; now the passage is certified (the crossing time exactly, the
/// boxes around it regular with the corner point alone on the patch borders), re-checked
/// from the scene, and the pieces are joined through the corner on every path.
#[test]
fn a_silhouette_through_a_patch_corner_is_certified_and_joined_there() {
    use geocert::num::Rational;
    use geocert::sweep::verify_corner_crossing;
    let scene = builtin_scene("sphere-corner").unwrap();
    let opts = SilhouetteOptions::default().with_caps(false);
    let oracle = Oracle::new(scene.clone(), [0.0; 3], [1.0; 3]);
    let mut seen = Vec::new();
    for path in [Path::Filtered, Path::Fast, Path::Exact] {
        let s = silhouette(&scene, &opts.with_path(path)).unwrap();
        assert!(
            s.clusters.is_empty() && s.extreme_clusters.is_empty(),
            "{path:?}: {} clusters",
            s.clusters.len()
        );
        assert_eq!(types(&s), two_monotone(), "{path:?}");
        // Four patches meet at the corner: the curve passes from one into the opposite one
        // (one arc in each) and touches the other two only there.
        assert_eq!(s.corner_crossings.len(), 4, "{path:?}");
        let mut arcs: Vec<usize> = s.corner_crossings.iter().map(|c| c.arcs).collect();
        arcs.sort();
        assert_eq!(arcs, vec![0, 0, 1, 1], "{path:?}");
        let half = Rational::new(1.into(), 2.into());
        for c in &s.corner_crossings {
            assert!(c.t.0 <= half && half <= c.t.1, "{:?}", c.t);
            assert!(verify_corner_crossing(&scene, c, false).unwrap());
        }
        // The joined component runs through the corner point (u, v) ∈ {0, 1}² at t = 1/2.
        let through = s
            .components
            .iter()
            .filter(|c| {
                c.uvt.iter().any(|p| {
                    (p[0] == 0.0 || p[0] == 1.0)
                        && (p[1] == 0.0 || p[1] == 1.0)
                        && (p[2] - 0.5).abs() < 1e-9
                })
            })
            .count();
        assert_eq!(through, 1, "{path:?}");
        let (phi, phi_t, contour, n) = oracle.worst(&s, ComponentKind::Envelope);
        assert!(
            phi < 1e-9 && phi_t < 1e-6 && contour < 1e-6,
            "{path:?}: residuals {phi:e} {phi_t:e} {contour:e}"
        );
        println!(
            "{path:?}: {} corner passages re-checked, {n} vertices within {phi:.1e} / \
             {phi_t:.1e} / {contour:.1e} of the oracle, {:.3} s",
            s.corner_crossings.len(),
            s.seconds
        );
        seen.push(s);
    }
    // A certificate that claims another arc count, or a box off the corner, is refused.
    let c = &seen[0].corner_crossings[0];
    let mut wrong = c.clone();
    wrong.arcs = 1 - c.arcs;
    assert!(!verify_corner_crossing(&scene, &wrong, false).unwrap());
    let mut off = c.clone();
    let w = &off.bounds[0].1 - &off.bounds[0].0;
    off.bounds[0] = (&off.bounds[0].0 + &w, &off.bounds[0].1 + &w);
    assert!(!verify_corner_crossing(&scene, &off, false).unwrap());
}

#[test]
fn the_fast_and_exact_paths_agree_with_the_filtered_one() {
    let scene = builtin_scene("sphere-line").unwrap();
    let opts = SilhouetteOptions::default().with_caps(false);
    let filtered = silhouette(&scene, &opts).unwrap();
    let fast = silhouette(&scene, &opts.with_path(Path::Fast)).unwrap();
    let exact = silhouette(&scene, &opts.with_path(Path::Exact)).unwrap();
    assert_eq!(types(&filtered), types(&exact));
    // The fast path may leave uncertain clusters; where it has none it must agree.
    if fast.clusters.is_empty() {
        assert_eq!(types(&filtered), types(&fast));
    }
    // The same certified vertices up to the refinement tolerance.
    let ends = |s: &Silhouettes| {
        let mut v: Vec<[f64; 3]> = s
            .components
            .iter()
            .flat_map(|c| [c.uvt[0], *c.uvt.last().unwrap()])
            .collect();
        v.sort_by(|a, b| a.partial_cmp(b).unwrap());
        v
    };
    // Matched as sets: sorting alone pairs them wrongly when two ends share (u, v) to the
    // last bits (a type-3 component of a translation starts and ends at the same (u, v)).
    let (f_ends, e_ends) = (ends(&filtered), ends(&exact));
    assert_eq!(f_ends.len(), e_ends.len());
    let near = |a: &[f64; 3], b: &[f64; 3]| (0..3).all(|k| (a[k] - b[k]).abs() < 1e-9);
    for (x, y) in [(&f_ends, &e_ends), (&e_ends, &f_ends)] {
        for a in x {
            assert!(y.iter().any(|b| near(a, b)), "{a:?} has no match in {y:?}");
        }
    }
    println!(
        "sphere-line: filtered {:.3} s, fast {:.3} s, exact {:.3} s; {} components on each",
        filtered.seconds,
        fast.seconds,
        exact.seconds,
        filtered.components.len()
    );
}

#[test]
fn bad_scenes_are_refused_with_their_cause() {
    let base = |surface: &str, motion: &str, eye: &str| {
        format!(r#"{{"surfaces": [{surface}], "t": [0, 2], "motion": {motion}, "eye": {eye}}}"#)
    };
    let sphere = r#"{"sphere": {"center": [0, 0, 0], "radius": 1}}"#;
    let line = r#"{"translation": [[0, 2], [0, "1/2"], [0]]}"#;
    // det M(t) = 1 − t vanishes at t = 1.
    let singular = r#"{"linear": [[[1, -1], [0], [0]], [[0], [1], [0]], [[0], [0], [1]]]}"#;
    let scene = scene_from_json(&base(sphere, singular, "[0, -9, 0]")).unwrap();
    let e = silhouette(&scene, &SilhouetteOptions::default()).unwrap_err();
    assert!(matches!(e, SweepError::SingularMotion { .. }), "{e}");
    // The eye on the sphere at t = 1 (centre (2, ½, 0) plus the unit vector (0.48, 0.64, 0.6)).
    let scene = scene_from_json(&base(sphere, line, r#"["2.48", "1.14", "0.6"]"#)).unwrap();
    let e = silhouette(&scene, &SilhouetteOptions::default()).unwrap_err();
    assert!(matches!(e, SweepError::EyeOnSurface { .. }), "{e}");
    // A patch collapsed to a point has no normal anywhere.
    let flat = r#"{"bezier": {"degrees": [1, 1], "points": [[1,1,1],[1,1,1],[1,1,1],[1,1,1]]}}"#;
    let scene = scene_from_json(&base(flat, line, "[0, -9, 0]")).unwrap();
    let e = silhouette(&scene, &SilhouetteOptions::default()).unwrap_err();
    assert!(
        matches!(
            e,
            SweepError::DegeneratePatch {
                surface: 0,
                patch: 0
            }
        ),
        "{e}"
    );
    // A rational biquartic patch: F and G of degree 15 in u and v, so H up to 30 > 24, is
    // refused with the degrees named.
    let quartic: Vec<String> = (0..25)
        .map(|k| {
            let w = 1.0 + (k % 3) as f64 / 2.0;
            format!("[{}, {}, {}, {w}]", k % 5, k / 5, (k * 7 % 5) as f64 / 4.0)
        })
        .collect();
    let q = format!(
        r#"{{"bezier": {{"degrees": [4, 4], "points": [{}]}}}}"#,
        quartic.join(",")
    );
    let scene = scene_from_json(&base(&q, line, "[2, -9, 5]")).unwrap();
    let e = silhouette(&scene, &SilhouetteOptions::default()).unwrap_err();
    assert!(e.to_string().contains("eq. 3's H"), "{e}");
    // A sphere spinning about its centre moves within itself: F ≡ 0.
    let spin = r#"{"rotation": {"quaternion": [[1], [0], [0], [0, "1/2"]]}}"#;
    let scene = scene_from_json(&base(sphere, spin, "[5, 1, 1]")).unwrap();
    let e = silhouette(&scene, &SilhouetteOptions::default()).unwrap_err();
    assert!(
        matches!(
            e,
            SweepError::CharacteristicPatch {
                surface: 0,
                patch: 0
            }
        ),
        "{e}"
    );
    // A parabolic-cylinder patch whose straight edge u = 1 (x = 0, y = 1) moves along x: the
    // edge is characteristic at every time, and from an eye in its tangent plane y = 1 the
    // whole swept edge is silhouette.
    let sheet = r#"{"bezier": {"degrees": [2, 1], "points": [[1,0,0,1],[1,1,0,1],[0,1,0,1],[1,0,1,1],[1,1,1,1],[0,1,1,1]]}}"#;
    let along_x = r#"{"translation": [[0, 1], [0], [0]]}"#;
    let scene = scene_from_json(&base(sheet, along_x, r#"["1/2", 1, 3]"#)).unwrap();
    let e = silhouette(&scene, &SilhouetteOptions::default()).unwrap_err();
    assert!(
        matches!(
            e,
            SweepError::SilhouetteCoversEdge {
                surface: 0,
                patch: 0,
                axis: 0,
                upper: true
            }
        ),
        "{e}"
    );
    // A sphere growing while it moves, seen from an eye on the tangent plane at the patch
    // corner (−247, 398, 194)/507 halfway, with the motion chosen so that the corner lies on
    // the characteristic circle at every time: the envelope is a cone, whose contour line
    // through that corner stays on it at every time.
    let on_corner = r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": 1}}], "t": [0, 1],
        "motion": {"translation": [[0, "613/338"], [0, "295/507"], [0, "-97/507"]],
                   "linear": [[[1, "1/2"], [0], [0]], [[0], [1, "1/2"], [0]], [[0], [0], [1, "1/2"]]]},
        "eye": ["151/507", "603/169", "-2194/507"]}"#;
    // The sweep is invariant in t (a similarity moving along a line), so the silhouette is
    // made of rulings: the one through the corner is found by the three patches meeting
    // there and reported once, certified on each patch's widened square.
    let scene = scene_from_json(on_corner).unwrap();
    let s = silhouette(&scene, &SilhouetteOptions::default()).unwrap();
    let corner = [-247.0 / 507.0, 398.0 / 507.0, 194.0 / 507.0];
    let through_corner: Vec<_> = s
        .components
        .iter()
        .filter(|c| c.kind == ComponentKind::Envelope)
        .filter(|c| (0..3).all(|k| (c.points[0][k] - corner[k]).abs() < 1e-12))
        .collect();
    assert_eq!(through_corner.len(), 1, "{:?}", s.components);
    assert!(through_corner[0].ruling.is_some());
    // The start and end positions' contours pass through that corner too: certified there,
    // nothing left unresolved, both closed.
    assert!(s.clusters.is_empty(), "{:?}", s.clusters);
    assert!(!s.cap_corner_passages.is_empty());
    for x in &s.cap_corner_passages {
        assert!(verify_cap_corner_passage(&scene, x, false).unwrap());
    }
    assert!(s
        .components
        .iter()
        .filter(|c| c.kind != ComponentKind::Envelope)
        .all(|c| c.closed));
    for r in &s.rulings {
        assert!(matches!(
            verify_ruling(&scene, r, false).unwrap(),
            Ok(RootCheck {
                unknowns: 2,
                on_boundary: false
            })
        ));
    }
    // From off the tangent plane the same edge carries no silhouette, and nothing is left
    // unresolved.
    let scene = scene_from_json(&base(sheet, along_x, r#"["1/2", 5, 3]"#)).unwrap();
    let s = silhouette(&scene, &SilhouetteOptions::default()).unwrap();
    assert!(s.clusters.is_empty() && s.extreme_clusters.is_empty());
    // Degrees and malformed fields name the field.
    let big = r#"{"bezier": {"degrees": [7, 1], "points": []}}"#;
    let e = scene_from_json(&base(big, line, "[0, -9, 0]")).unwrap_err();
    assert!(e.to_string().contains("surfaces[0].bezier.degrees"), "{e}");
}

/// The largest normalised `(|F|, |G|)` over every envelope vertex, from finite differences
/// of `A(t)S(u, v)` (the report's measure), and the vertex count.
fn worst_fd(scene: &Scene, s: &Silhouettes) -> ((f64, f64), usize) {
    let eye = report::eye_f64(scene);
    let mut worst = (0.0f64, 0.0f64);
    let mut n = 0;
    for c in s
        .components
        .iter()
        .filter(|c| c.kind == ComponentKind::Envelope)
    {
        for (uvt, &patch) in c.uvt.iter().zip(&c.patches) {
            let (f, g) = report::residuals(scene, c.surface, patch, *uvt, eye);
            worst = (worst.0.max(f), worst.1.max(g));
            n += 1;
        }
    }
    (worst, n)
}

#[test]
fn the_tuba_traces_a_sphere_and_a_torus_onto_their_characteristic_curves_and_contours() {
    let scene = builtin_scene("tuba").unwrap();
    let s = silhouette(&scene, &SilhouetteOptions::default().with_caps(false)).unwrap();
    let (worst, n) = worst_fd(&scene, &s);
    println!(
        "tuba: {} components ({} on the torus), {n} vertices: |F| ≤ {:.1e}, |G| ≤ {:.1e} (normalised)",
        s.components.len(),
        s.components.iter().filter(|c| c.surface == 1).count(),
        worst.0,
        worst.1
    );
    assert!(s.components.iter().any(|c| c.surface == 0));
    assert!(s.components.iter().any(|c| c.surface == 1));
    assert!(n > 50 && worst.0 < 1e-5 && worst.1 < 1e-5);
}

#[test]
fn a_bspline_patch_is_split_into_its_bezier_pieces_and_traced() {
    // A bicubic bump over [0,2]² with one interior knot per axis, moving along (½, 0, ⅕) and
    // seen at a grazing angle from −y: its envelope silhouette crosses the knot lines between
    // the pieces. (Along x alone the characteristic curve would be the symmetry line x = 1,
    // which is a knot line: a curve inside a patch edge, see the module docs.)
    let mut points = Vec::new();
    for j in 0..5 {
        for i in 0..5 {
            let z = if (1..4).contains(&i) && (1..4).contains(&j) {
                1.0
            } else {
                0.0
            };
            points.push(format!("[{}, {}, {z}]", i as f64 / 2.0, j as f64 / 2.0));
        }
    }
    let text = format!(
        r#"{{"surfaces": [{{"bspline": {{"orders": [4, 4], "knots": [[0,0,0,0,1,2,2,2,2],[0,0,0,0,1,2,2,2,2]], "points": [{}]}}}}],
            "t": [0, 1], "motion": {{"translation": [[0, "1/2"], [0], [0, "1/5"]]}}, "eye": [1, -6, "1/2"]}}"#,
        points.join(",")
    );
    let scene = scene_from_json(&text).unwrap();
    assert_eq!(scene.surfaces[0].patches.len(), 4);
    let s = silhouette(&scene, &SilhouetteOptions::default().with_caps(false)).unwrap();
    let (worst, n) = worst_fd(&scene, &s);
    println!(
        "bicubic B-spline sweep: {} components over {} pieces, {n} vertices, {} clusters: |F| ≤ {:.1e}, |G| ≤ {:.1e}",
        s.components.len(),
        s.patches,
        s.clusters.len(),
        worst.0,
        worst.1
    );
    assert!(n > 10 && worst.0 < 1e-5 && worst.1 < 1e-5);
    // The bump's two flanks each carry one t-monotone component from t = a to t = b.
    assert_eq!(s.components.len(), 2);
    for c in &s.components {
        assert_eq!(c.component_type, Some(ComponentType::Monotone));
        let mut ends = c.ends.clone();
        ends.sort_by_key(|e| format!("{e:?}"));
        assert_eq!(
            ends,
            vec![
                ComponentEnd::Time { upper: false },
                ComponentEnd::Time { upper: true }
            ]
        );
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(12))]

    /// An ellipsoid under a random affine motion `M(t) = M₀ + t M₁` (kept invertible on
    /// `[0, 1]`), `T(t) = t T₁`, seen from a random far eye: on the filtered path every traced
    /// vertex lies on the implicit oracle's characteristic curve and contour, and where the
    /// fast path leaves no cluster its components and types equal the filtered ones.
    #[test]
    fn random_affine_sweeps_of_an_ellipsoid_match_the_oracle(
        m1 in proptest::collection::vec(-4i64..=4, 9),
        t1 in proptest::collection::vec(-6i64..=6, 3),
        radii in proptest::collection::vec(2i64..=6, 3),
        eye in proptest::collection::vec(-3i64..=3, 2),
    ) {
        // M(t) = I + t M₁, M₁'s diagonal in [−½, ½] and its off-diagonal entries in
        // [−⅕, ⅕]: strictly diagonally dominant on [0, 1], so invertible.
        let entry = |i: usize, j: usize| -> String {
            let v = m1[3 * i + j];
            if i == j {
                format!("[1, \"{}/8\"]", v)
            } else {
                format!("[0, \"{}/20\"]", v)
            }
        };
        let rows: Vec<String> = (0..3)
            .map(|i| format!("[{}, {}, {}]", entry(i, 0), entry(i, 1), entry(i, 2)))
            .collect();
        let text = format!(
            r#"{{"surfaces": [{{"ellipsoid": {{"center": [0, 0, 0], "radii": ["{}/4", "{}/4", "{}/4"]}}}}],
                "t": [0, 1],
                "motion": {{"translation": [[0, {}], [0, {}], [0, "{}/2"]], "linear": [{}]}},
                "eye": ["{}/2", -12, "{}/2"]}}"#,
            radii[0], radii[1], radii[2], t1[0], t1[1], t1[2], rows.join(", "), eye[0], eye[1]
        );
        let scene = scene_from_json(&text).unwrap();
        let o = Oracle::new(
            scene,
            [0.0; 3],
            [0, 1, 2].map(|k| radii[k] as f64 / 4.0),
        );
        let opts = SilhouetteOptions::default().with_caps(false);
        let s = match silhouette(&o.scene, &opts) {
            Ok(s) => s,
            // A sweep that passes through the eye is refused, never traced.
            Err(SweepError::EyeOnSurface { .. }) => return Ok(()),
            Err(e) => panic!("{e}"),
        };
        let (phi, speed, contour, _) = o.worst(&s, ComponentKind::Envelope);
        proptest::prop_assert!(phi < 1e-9 && speed < 1e-5 && contour < 1e-9,
            "{phi:e} {speed:e} {contour:e}");
        let fast = silhouette(&o.scene, &opts.with_path(Path::Fast)).unwrap();
        if fast.clusters.is_empty() && s.clusters.is_empty() {
            proptest::prop_assert_eq!(types(&s), types(&fast));
        }
    }
}

#[test]
fn a_tolerance_refines_until_every_chord_is_certified_within_it() {
    let scene = builtin_scene("ellipsoid-line").unwrap();
    let coarse = silhouette(&scene, &SilhouetteOptions::default()).unwrap();
    let worst = |s: &Silhouettes| {
        s.components
            .iter()
            .map(|c| c.chord_bound)
            .fold(0.0, f64::max)
    };
    let tol = worst(&coarse) / 4.0;
    let fine = silhouette(
        &scene,
        &SilhouetteOptions::default().with_tolerance(Some(tol)),
    )
    .unwrap();
    println!(
        "ellipsoid-line: chord bound {:.2e} at the default resolution, {:.2e} with tolerance {tol:.2e}; {} → {} vertices",
        worst(&coarse),
        worst(&fine),
        coarse.components.iter().map(|c| c.points.len()).sum::<usize>(),
        fine.components.iter().map(|c| c.points.len()).sum::<usize>()
    );
    assert!(worst(&coarse).is_finite() && worst(&fine) <= tol);
    // Every component (caps included) meets it, and refining changes no topology.
    for c in &fine.components {
        assert!(c.chord_bound > 0.0 && c.chord_bound <= tol);
    }
    assert_eq!(types(&coarse), types(&fine));
}

#[test]
fn axis_aligned_motions_and_eyes_do_not_meet_the_primitives_patch_edges() {
    // A sphere moving along x seen from eyes in coordinate planes: the characteristic curve is
    // the great circle x = const, which would run along a patch edge of an axis-aligned
    // parametrisation; the built-ins' patches are turned into general position. (From a point
    // on the motion's axis, inside the envelope's cylinder, there is no envelope contour.)
    for eye in [
        "[\"1/2\", -8, \"3/10\"]",
        "[0, -8, 0]",
        "[0, 0, 8]",
        "[8, 3, 0]",
    ] {
        let text = format!(
            r#"{{"surfaces": [{{"sphere": {{"center": [0, 0, 0], "radius": 1}}}}], "t": [0, 1],
                "motion": {{"translation": [[0, 1], [0], [0]]}}, "eye": {eye}}}"#
        );
        let scene = scene_from_json(&text).unwrap();
        let s = silhouette(&scene, &SilhouetteOptions::default()).unwrap();
        assert!(
            s.clusters.is_empty(),
            "eye {eye}: {} clusters",
            s.clusters.len()
        );
        let envelope = s
            .components
            .iter()
            .filter(|c| c.kind == ComponentKind::Envelope)
            .count();
        assert_eq!(envelope, 2, "eye {eye}");
    }
    let inside = r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": 1}}], "t": [0, 1],
        "motion": {"translation": [[0, 1], [0], [0]]}, "eye": [8, 0, 0]}"#;
    let s = silhouette(
        &scene_from_json(inside).unwrap(),
        &SilhouetteOptions::default(),
    )
    .unwrap();
    assert!(s.clusters.is_empty());
    assert!(s
        .components
        .iter()
        .all(|c| c.kind != ComponentKind::Envelope));
}

/// The turning ellipsoid (`builtin:ellipsoid-turn`) seen from an eye moving past it along a
/// line that stays off the swept surface (certified by [`events`]).
const TURN_EYE: &str = r#"{"surfaces": [{"ellipsoid": {"center": [0, 0, 0], "radii": [2, "1/2", "1/2"]}}],
 "t": [0, 1],
 "motion": {"translation": [[0, 3], [0], [0, "1/2"]],
            "rotation": {"quaternion": [[1], [0], [0], [0, "1/2"]]}},
 "eye": {"path": [[-3, 3], [-2], [0, "1/3"]], "r": [0, 3]}}"#;

/// A sphere swept along a parabola with an eye path that runs into the swept volume.
const TUBE_THROUGH: &str = r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": "1/2"}}],
 "t": [0, 1],
 "motion": {"translation": [[0, 4], [0, 0, 2], [0]]},
 "eye": {"path": [[2], ["-1/2", "47/100"], ["1/10"]], "r": [0, 1]}}"#;

/// The envelope components of the silhouette seen from the eye path's point at `r`: their
/// types and ends.
fn envelope_components_at(
    scene: &Scene,
    r: f64,
) -> Vec<(Option<ComponentType>, Vec<ComponentEnd>)> {
    use geocert::num::Rational;
    let Eye::Path { path, .. } = &scene.eye else {
        panic!("an eye path")
    };
    let r = Rational::new(((r * 4096.0).round() as i64).into(), 4096.into());
    let point = path.clone().map(|p| {
        p.iter()
            .rev()
            .fold(Rational::from_integer(0.into()), |acc, c| acc * &r + c)
    });
    let mut fixed = scene.clone();
    fixed.eye = Eye::Point(point);
    let s = silhouette(
        &fixed,
        &SilhouetteOptions::new().with_resolution(1.0 / 64.0),
    )
    .unwrap();
    assert!(s.clusters.is_empty(), "clusters at r = {r}");
    types(&s)
}

#[test]
fn a_moving_eye_has_certified_events_and_the_silhouette_reconnects_at_the_interior_one() {
    use geocert::num::{rational_from_f64, Rational};
    use geocert::solve::SolveOptions;
    use geocert::sweep::{event_systems, events, verify_event, EventKind};
    let scene = scene_from_json(TURN_EYE).unwrap();
    let ev = events(&scene, &SolveOptions::new()).unwrap();
    println!(
        "turning ellipsoid with a moving eye: {} systems, {} events ({} interior), {} clusters",
        ev.systems,
        ev.events.len(),
        ev.events
            .iter()
            .filter(|e| e.kind == EventKind::Interior)
            .count(),
        ev.clusters.len()
    );
    assert!(ev.clusters.is_empty());
    assert!(ev.events.windows(2).all(|w| w[0].r <= w[1].r));
    for e in &ev.events {
        assert!(verify_event(&scene, e).unwrap().is_ok(), "{e:?}");
    }
    // The ellipsoid is closed: every event on a patch border is seen from each patch there
    // (two, or four at a pole), at the same r and 3-D point; the others stand alone.
    let groups = geocert::sweep::event_groups(&scene, &ev.events);
    println!(
        "{} events in {} groups: sizes {:?}",
        ev.events.len(),
        groups.len(),
        groups.iter().map(Vec::len).collect::<Vec<_>>()
    );
    for g in &groups {
        let border = ev.events[g[0]].kind.on_patch_border();
        assert!(g
            .iter()
            .all(|&i| ev.events[i].kind.on_patch_border() == border));
        if border {
            assert!(g.len() >= 2, "a border event seen from one patch: {g:?}");
        } else {
            assert_eq!(g.len(), 1);
        }
        let patches: std::collections::BTreeSet<usize> =
            g.iter().map(|&i| ev.events[i].patch).collect();
        assert_eq!(patches.len(), g.len(), "one event per patch in a group");
    }
    let interior: Vec<_> = ev
        .events
        .iter()
        .filter(|e| e.kind == EventKind::Interior)
        .collect();
    assert_eq!(interior.len(), 1);
    let e = interior[0];
    assert_eq!(e.pivot, Some(true));
    // At the event the silhouette curve is singular, ∇F ∥ ∇G in (u, v, t) — the Lagrange
    // condition — while ∇G itself is far from zero: eqs. 6–9 of the paper (G_u = G_v = G_t =
    // 0) do not hold there.
    let system = event_systems(&scene)
        .unwrap()
        .into_iter()
        .find(|s| s.patch == e.patch && s.surface == e.surface && s.kind == EventKind::Interior)
        .unwrap()
        .system;
    let unit: Vec<Rational> = system
        .domain
        .iter()
        .zip(&e.root.approx)
        .map(|((a, b), x)| (rational_from_f64(*x, "x").unwrap() - a) / (b - a))
        .collect();
    let grad = |k: usize| -> [f64; 3] {
        std::array::from_fn(|axis| {
            let d = system.equations[k].derivative(axis).unwrap();
            rational_to_f64(&d.eval(&unit).unwrap())
        })
    };
    let (gf, gg) = (grad(0), grad(1));
    println!(
        "box error bound {:.2e}; ∇F {gf:?} ∇G {gg:?}; F {:.3e} G {:.3e} minors {:.3e} {:.3e}",
        e.root.error_bound,
        rational_to_f64(&system.equations[0].eval(&unit).unwrap()),
        rational_to_f64(&system.equations[1].eval(&unit).unwrap()),
        rational_to_f64(&system.equations[2].eval(&unit).unwrap()),
        rational_to_f64(&system.equations[3].eval(&unit).unwrap())
    );
    let norm = |a: [f64; 3]| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    let cross = [
        gf[1] * gg[2] - gf[2] * gg[1],
        gf[2] * gg[0] - gf[0] * gg[2],
        gf[0] * gg[1] - gf[1] * gg[0],
    ];
    let scale = system.equations[1]
        .coeffs()
        .iter()
        .map(|c| rational_to_f64(c).abs())
        .fold(0.0, f64::max);
    println!(
        "interior event at r = {:.5}, (u, v, t) = {:?}: |∇F × ∇G| / (|∇F||∇G|) = {:.2e}, |∇G| / max|G| = {:.3}",
        e.r,
        e.uvt,
        norm(cross) / (norm(gf) * norm(gg)),
        norm(gg) / scale
    );
    assert!(norm(cross) < 1e-6 * norm(gf) * norm(gg));
    assert!(norm(gg) > 1e-2 * scale);
    // The silhouette seen from just before and just after the event (no other event between
    // r ± 0.01): a saddle — the two components, each from the start position to the end
    // position, exchange partners and become one from start to start and one from end to
    // end.
    let (before, after) = (
        envelope_components_at(&scene, e.r - 0.01),
        envelope_components_at(&scene, e.r + 0.01),
    );
    println!("envelope components: {before:?} before the event, {after:?} after");
    for g in ev.events.iter().filter(|g| !g.kind.on_patch_border()) {
        println!("genuine event at r = {:.4}: {:?}", g.r, g.kind);
    }
    let lower = ComponentEnd::Time { upper: false };
    let upper = ComponentEnd::Time { upper: true };
    assert_eq!(before.len(), 2);
    assert!(before.iter().all(|c| c.1 == vec![lower, upper]));
    assert_eq!(after.len(), 2);
    assert!(after.iter().any(|c| c.1 == vec![lower, lower]));
    assert!(after.iter().any(|c| c.1 == vec![upper, upper]));
    // A moved box is refused; a fixed eye has no events.
    let mut moved = e.clone();
    moved.root.bounds[3] = (
        Rational::from_integer(0.into()),
        Rational::new(1.into(), 2.into()),
    );
    assert!(!matches!(verify_event(&scene, &moved), Ok(Ok(_))));
    let through = scene_from_json(TUBE_THROUGH).unwrap();
    assert!(matches!(
        events(&through, &SolveOptions::new()),
        Err(SweepError::EyePathOnSurface { .. })
    ));
    let fixed = builtin_scene("sphere-line").unwrap();
    assert!(matches!(
        events(&fixed, &SolveOptions::new()),
        Err(SweepError::Field { .. })
    ));
}

/// The event systems are built from `F` and `G` without their factors in one parameter that
/// keep one strict sign on the box (the quarter circles' weights, the Cayley rotation's
/// denominator): none is left in the systems' `F` and `G`, and the turning ellipsoid's
/// interior systems are of degrees at most `[5, 6, 5, 1]` (`[9, 12, 14, 1]` with them).
#[test]
fn event_systems_carry_no_factor_without_a_zero_on_the_box() {
    use geocert::sweep::{event_systems, EventKind};
    let scene = scene_from_json(TURN_EYE).unwrap();
    let systems = event_systems(&scene).unwrap();
    let mut checked = 0;
    // (On a face or an edge the restrictions may have such factors of their own.)
    for es in systems.iter().filter(|es| es.kind == EventKind::Interior) {
        for eq in es.system.equations.iter().take(2) {
            let (_, divided) = eq.without_signed_contents().unwrap();
            assert!(divided.is_empty(), "patch {}: {:?}", es.patch, divided);
            checked += 1;
        }
        for eq in &es.system.equations {
            assert!(
                eq.degrees().iter().zip([5, 6, 5, 1]).all(|(d, m)| *d <= m),
                "patch {}: {:?}",
                es.patch,
                eq.degrees()
            );
        }
    }
    println!("{checked} interior F and G without a signed univariate factor");
    assert_eq!(checked, 16);
}

/// Frames of the moving eye: continued between events, traced afresh across the interior
/// event; a continued frame matches a certified trace at the same eye position.
#[test]
fn frames_continue_between_events_and_are_traced_across_them() {
    use geocert::solve::SolveOptions;
    use geocert::sweep::{frames, EventKind};
    let scene = scene_from_json(TURN_EYE).unwrap();
    let rs: Vec<f64> = (0..21).map(|i| 1.60 + 0.005 * i as f64).collect();
    let opts = SilhouetteOptions::new().with_resolution(1.0 / 32.0);
    let f = frames(&scene, &rs, &opts, &SolveOptions::new()).unwrap();
    let event = f
        .events
        .events
        .iter()
        .find(|e| e.kind == EventKind::Interior)
        .unwrap()
        .r;
    let traced: Vec<f64> = f.frames.iter().filter(|x| x.traced).map(|x| x.r).collect();
    let continued = f.frames.len() - traced.len();
    println!(
        "{} frames, traced at {traced:?}; {continued} continued at {:.0} frames/s",
        f.frames.len(),
        continued as f64 / f.continued_seconds.max(1e-9)
    );
    assert!(traced[0] == rs[0]);
    let first_after = rs.iter().copied().find(|&r| r > event).unwrap();
    assert!(traced.contains(&first_after), "re-traced after the event");
    assert!(continued >= 15);
    // A continued frame against a fresh certified trace from the same eye point: the same
    // number of components, and every continued point close to the traced polylines.
    let frame = f.frames.iter().rev().find(|x| !x.traced).unwrap();
    let worst = farthest_from_a_fresh_trace(&scene, frame, &opts);
    assert!(worst < 0.1, "{worst}");
}

/// The distance from `p` to the nearest segment of the polylines `lines` (closed ones with
/// their closing segment).
fn to_polylines(p: &[f64; 3], lines: &[(Vec<[f64; 3]>, bool)]) -> f64 {
    let seg = |a: &[f64; 3], b: &[f64; 3]| {
        let d: [f64; 3] = std::array::from_fn(|k| b[k] - a[k]);
        let dd: f64 = d.iter().map(|x| x * x).sum();
        let t = if dd > 0.0 {
            ((0..3).map(|k| (p[k] - a[k]) * d[k]).sum::<f64>() / dd).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (0..3)
            .map(|k| (p[k] - a[k] - t * d[k]).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    lines
        .iter()
        .flat_map(|(pts, closed)| {
            let closing = closed.then(|| (pts[pts.len() - 1], pts[0]));
            pts.windows(2).map(|w| (w[0], w[1])).chain(closing)
        })
        .map(|(a, b)| seg(&a, &b))
        .fold(f64::INFINITY, f64::min)
}

/// A fresh certified trace of the frame's scene from its eye point.
fn fresh_trace(
    scene: &geocert::sweep::Scene,
    frame: &geocert::sweep::Frame,
    opts: &SilhouetteOptions,
) -> Silhouettes {
    let Eye::Path { path, .. } = &scene.eye else {
        unreachable!()
    };
    let rq = geocert::num::rational_from_f64(frame.r, "r").unwrap();
    let mut fixed = scene.clone();
    fixed.eye = Eye::Point(path.clone().map(|p| {
        p.iter()
            .rev()
            .fold(geocert::num::Rational::from_integer(0.into()), |acc, c| {
                acc * &rq + c
            })
    }));
    silhouette(&fixed, opts).unwrap()
}

/// The envelope's polylines of a trace, with whether each is closed.
fn envelope_lines(s: &Silhouettes) -> Vec<(Vec<[f64; 3]>, bool)> {
    s.components
        .iter()
        .filter(|c| c.kind == ComponentKind::Envelope)
        .map(|c| (c.points.clone(), c.closed))
        .collect()
}

/// Both ways between a continued frame and a fresh certified trace from the same eye point,
/// which has as many envelope components: the largest distance of the frame's points from
/// the trace's polylines (to their segments), and of the trace's vertices from the frame's
/// polylines.
fn both_ways_from_a_fresh_trace(
    scene: &geocert::sweep::Scene,
    frame: &geocert::sweep::Frame,
    opts: &SilhouetteOptions,
) -> (f64, f64) {
    let fresh = envelope_lines(&fresh_trace(scene, frame, opts));
    assert_eq!(fresh.len(), frame.components.len());
    let ours: Vec<(Vec<[f64; 3]>, bool)> = frame
        .components
        .iter()
        .map(|c| (c.points.clone(), c.closed))
        .collect();
    let farthest = |from: &[(Vec<[f64; 3]>, bool)], to: &[(Vec<[f64; 3]>, bool)]| {
        from.iter()
            .flat_map(|(pts, _)| pts.iter())
            .map(|p| to_polylines(p, to))
            .fold(0.0f64, f64::max)
    };
    let (there, back) = (farthest(&ours, &fresh), farthest(&fresh, &ours));
    println!(
        "continued frame at r = {:.3}: farthest point {there:.4} from the traced polylines, \
         farthest traced vertex {back:.4} from it",
        frame.r
    );
    (there, back)
}

/// [`both_ways_from_a_fresh_trace`]: the frame's points to the trace.
fn farthest_from_a_fresh_trace(
    scene: &geocert::sweep::Scene,
    frame: &geocert::sweep::Frame,
    opts: &SilhouetteOptions,
) -> f64 {
    both_ways_from_a_fresh_trace(scene, frame, opts).0
}

/// A component's piece on one patch shrinks as the eye moves (the border point joining it to
/// the next patch slides along the border): the inner point that converges across the
/// border moves to the neighbouring patch, and the frame is continued, not traced afresh;
/// its points stay on the silhouette of a fresh trace.
#[test]
fn a_continued_frame_moves_a_point_that_crossed_a_patch_border() {
    use geocert::solve::SolveOptions;
    use geocert::sweep::frames;
    let scene = scene_from_json(TURN_EYE).unwrap();
    let rs = [3.0 * 3.0 / 39.0, 3.0 * 4.0 / 39.0];
    let opts = SilhouetteOptions::new();
    let f = frames(&scene, &rs, &opts, &SolveOptions::new()).unwrap();
    let (first, second) = (&f.frames[0], &f.frames[1]);
    assert!(first.traced && !second.traced);
    let per_patch = |x: &geocert::sweep::Frame| -> Vec<usize> {
        let mut n = vec![0; 8];
        for c in &x.components {
            for &p in &c.patches {
                n[p] += 1;
            }
        }
        n
    };
    println!(
        "points per patch: {:?} → {:?}",
        per_patch(first),
        per_patch(second)
    );
    assert_eq!(first.components.len(), second.components.len());
    assert_ne!(per_patch(first), per_patch(second));
    let worst = farthest_from_a_fresh_trace(&scene, second, &opts);
    assert!(worst < 0.1, "{worst}");
}

/// Border events (a component's end on a patch border or on a time face crossing into the
/// next patch, a piece touching a border) do not change the silhouette's topology: the
/// frames across them are continued (points that cross a border move to the neighbouring
/// patch, a junction point whose crossing is gone is dropped, fast-moving points are followed
/// in substeps, gaps are refilled, inner points sliding past their component's time end are
/// dropped), and only the first frame and those after off-border events are traced. Each
/// frame continued across a border event matches a fresh certified trace both ways: its
/// points lie on the traced polylines, and the traced polylines' vertices are near its
/// points (nothing of the curve is lost).
#[test]
fn frames_are_continued_across_border_events() {
    use geocert::solve::SolveOptions;
    use geocert::sweep::frames;
    let scene = scene_from_json(TURN_EYE).unwrap();
    let rs: Vec<f64> = (0..40).map(|i| 3.0 * i as f64 / 39.0).collect();
    let opts = SilhouetteOptions::new();
    let f = frames(&scene, &rs, &opts, &SolveOptions::new()).unwrap();
    let off_border: Vec<f64> = f
        .events
        .events
        .iter()
        .filter(|e| !e.kind.on_patch_border())
        .map(|e| e.r)
        .collect();
    let traced: Vec<f64> = f.frames.iter().filter(|x| x.traced).map(|x| x.r).collect();
    // Traced: the first frame, and the first after each off-border event.
    let mut expected = vec![rs[0]];
    for &r in &off_border {
        if let Some(&after) = rs.iter().find(|&&x| x > r) {
            if !expected.contains(&after) {
                expected.push(after);
            }
        }
    }
    expected.sort_by(f64::total_cmp);
    println!("traced at {traced:?}; off-border events at {off_border:?}");
    assert_eq!(traced, expected);
    // No continued point leaves the time interval (a component meeting a time face anew is
    // traced afresh).
    for x in f.frames.iter().filter(|x| !x.traced) {
        for c in &x.components {
            assert!(
                c.uvt.iter().all(|y| (0.0..=1.0).contains(&y[2])),
                "r = {}",
                x.r
            );
        }
    }
    // The continued frames right after border events, against fresh traces.
    let mut checked = 0;
    for k in 1..rs.len() {
        let frame = &f.frames[k];
        let crossed = f
            .events
            .events
            .iter()
            .any(|e| e.kind.on_patch_border() && e.r > rs[k - 1] && e.r <= rs[k]);
        if frame.traced || !crossed {
            continue;
        }
        let (there, back) = both_ways_from_a_fresh_trace(&scene, frame, &opts);
        println!("r = {:.3}: there {there:.1e}, back {back:.1e}", frame.r);
        // Both within the chords' own sag (a continued frame keeps the previous frame's
        // spacing): before out-of-order border points were moved and gaps refilled from the
        // nearest surface points, a traced vertex lay 9e-2 from the frame at r = 1.538.
        assert!(
            there < 0.05 && back < 0.05,
            "r = {}: {there}, {back}",
            frame.r
        );
        checked += 1;
    }
    println!("{checked} frames continued across border events checked against fresh traces");
    assert!(checked >= 6, "{checked}");
}

/// The events whose certified `r` interval holds `r`.
fn holding_r<'a>(
    events: &'a [geocert::sweep::Event],
    r: &geocert::num::Rational,
) -> Vec<&'a geocert::sweep::Event> {
    events
        .iter()
        .filter(|e| {
            let (lo, hi) = e.root.bounds.last().unwrap();
            lo <= r && r <= hi
        })
        .collect()
}

/// The issue's closed-form event: a unit sphere translated along x (a sweep invariant in t)
/// seen from `P(r) = (5, r, 3/5)`. The envelope's contour is the cylinder's two lines where
/// `1 − r·y − (3/5)·z = 0` meets `y² + z² = 1`; they merge where the eye enters the infinite
/// cylinder, at `r = −4/5` exactly, and are gone after.
#[test]
fn a_translated_sphere_loses_its_contour_lines_where_the_eye_enters_the_cylinder() {
    use geocert::num::Rational;
    use geocert::solve::SolveOptions;
    use geocert::sweep::{events, frames, verify_event, EventKind};
    let scene = builtin_scene("sphere-line-eye").unwrap();
    let clock = std::time::Instant::now();
    let ev = events(&scene, &SolveOptions::new()).unwrap();
    let seconds = clock.elapsed().as_secs_f64();
    let merge = Rational::new((-4).into(), 5.into());
    let at_merge = holding_r(&ev.events, &merge);
    println!(
        "sphere-line-eye: {} systems, {} events in {seconds:.3} s, {} clusters; at r = -4/5: {:?}",
        ev.systems,
        ev.events.len(),
        ev.clusters.len(),
        at_merge.iter().map(|e| e.kind).collect::<Vec<_>>()
    );
    assert!(ev.clusters.is_empty());
    // The merge, seen at both ends of the rulings (the start and end positions).
    let t_faces: Vec<bool> = at_merge
        .iter()
        .filter_map(|e| match e.kind {
            EventKind::Face { axis: 2, upper } => Some(upper),
            _ => None,
        })
        .collect();
    assert!(
        t_faces.contains(&false) && t_faces.contains(&true),
        "{t_faces:?}"
    );
    for e in &ev.events {
        // Systems with t free have t-segments of roots here; they are not solved.
        assert!(
            matches!(e.kind, EventKind::Face { axis: 2, .. })
                || matches!(e.kind, EventKind::Edge { fixed } if fixed[1].0 == 2),
            "{:?}",
            e.kind
        );
        assert!(verify_event(&scene, e).unwrap().is_ok(), "{e:?}");
        // On the characteristic circle of the unit sphere and on the contour from P(r).
        let x = e.patch_point(&scene).unwrap();
        let tangency = 1.0 - e.r * x[1] - 0.6 * x[2];
        assert!(x[0].abs() < 1e-8, "{x:?}");
        assert!((x[1] * x[1] + x[2] * x[2] - 1.0).abs() < 1e-8, "{x:?}");
        assert!(tangency.abs() < 1e-8, "{e:?}: {tangency}");
    }
    // The exact path finds the same events (events at one r may come in either order).
    let exact = events(&scene, &SolveOptions::new().with_path(Path::Exact)).unwrap();
    assert_eq!(exact.events.len(), ev.events.len());
    for a in &exact.events {
        assert!(
            ev.events
                .iter()
                .any(|b| a.kind == b.kind && a.patch == b.patch && (a.r - b.r).abs() < 1e-9),
            "{a:?}"
        );
    }
    // Frames: two lines before the merge, none after, every frame resolved.
    let rs: Vec<f64> = (0..8).map(|i| -2.0 + 1.9 * i as f64 / 7.0).collect();
    let opts = SilhouetteOptions::new().with_caps(false);
    let f = frames(&scene, &rs, &opts, &SolveOptions::new()).unwrap();
    for x in &f.frames {
        println!(
            "r = {:.3}: {} components ({}), {} clusters",
            x.r,
            x.components.len(),
            if x.traced { "traced" } else { "continued" },
            x.clusters
        );
        assert_eq!(x.clusters, 0);
        assert_eq!(x.components.len(), if x.r < -0.8 { 2 } else { 0 });
    }
    let first_after = f.frames.iter().find(|x| x.r > -0.8).unwrap();
    assert!(first_after.traced, "re-traced after the merge");
}

/// An event exactly at an end of the eye path: `sphere-line-eye` with the path cut at the
/// merge, `r ∈ [−2, −4/5]` and `r ∈ [−4/5, 0]`. The systems are solved on the path's interval
/// widened by `2⁻²⁰` of it, so the merge is an inner root: certified on both t faces (boxes
/// holding −4/5, re-checked from the scene), no cluster, on both paths; and nothing beyond
/// the path's ends is reported.
#[test]
fn an_event_at_an_end_of_the_eye_path_is_certified() {
    use geocert::num::Rational;
    use geocert::solve::SolveOptions;
    use geocert::sweep::{events, verify_event, EventKind};
    let merge = Rational::new((-4).into(), 5.into());
    for (r, json_r) in [
        ((-2.0, -0.8), r#"[-2, "-4/5"]"#),
        ((-0.8, 0.0), r#"["-4/5", 0]"#),
    ] {
        let scene = scene_from_json(&format!(
            r#"{{"surfaces": [{{"sphere": {{"center": [0, 0, 0], "radius": 1}}}}],
                "t": [0, 1],
                "motion": {{"translation": [[0, 2], [0], [0]]}},
                "eye": {{"path": [[5], [0, 1], ["3/5"]], "r": {json_r}}}}}"#
        ))
        .unwrap();
        for path in [Path::Filtered, Path::Exact] {
            let ev = events(&scene, &SolveOptions::new().with_path(path)).unwrap();
            assert!(ev.clusters.is_empty(), "{r:?} {path:?}: {:?}", ev.clusters);
            let faces: Vec<EventKind> = holding_r(&ev.events, &merge)
                .iter()
                .map(|e| e.kind)
                .collect();
            println!(
                "r in {r:?} ({path:?}): {} events, at -4/5: {faces:?}",
                ev.events.len()
            );
            for upper in [false, true] {
                assert!(
                    faces.contains(&EventKind::Face { axis: 2, upper }),
                    "{faces:?}"
                );
            }
            for e in &ev.events {
                assert!(verify_event(&scene, e).unwrap().is_ok(), "{e:?}");
                assert!(
                    e.r >= r.0 - 1e-9 && e.r <= r.1 + 1e-9,
                    "{} outside {r:?}",
                    e.r
                );
            }
        }
    }
}

/// A sphere translated and uniformly scaled along x sweeps a cone (apex at x = −6, half-angle
/// `sin α = 1/6`), an invariant sweep with the scale `λ = s(t)²`. From `P(r) = (12, r, 1/3)`
/// its two contour lines merge where the eye enters the infinite cone,
/// `r² + 1/9 = 18² tan² α = 324/35`: `r = √(2881/315)`.
#[test]
fn a_scaled_sphere_loses_its_contour_lines_where_the_eye_enters_the_cone() {
    use geocert::num::Rational;
    use geocert::solve::SolveOptions;
    use geocert::sweep::{events, verify_event, EventKind};
    let scene = builtin_scene("sphere-cone-eye").unwrap();
    let ev = events(&scene, &SolveOptions::new()).unwrap();
    assert!(ev.clusters.is_empty());
    let square = Rational::new(2881.into(), 315.into());
    let at_merge: Vec<EventKind> = ev
        .events
        .iter()
        .filter(|e| {
            let (lo, hi) = e.root.bounds.last().unwrap();
            *lo > Rational::from_integer(0.into()) && lo * lo <= square && square <= hi * hi
        })
        .map(|e| e.kind)
        .collect();
    println!(
        "cone: {} events, at r = √(2881/315): {at_merge:?}",
        ev.events.len()
    );
    assert!(at_merge.contains(&EventKind::Face {
        axis: 2,
        upper: false
    }));
    assert!(at_merge.contains(&EventKind::Face {
        axis: 2,
        upper: true
    }));
    for e in &ev.events {
        assert!(!matches!(e.kind, EventKind::Interior));
        assert!(verify_event(&scene, e).unwrap().is_ok(), "{e:?}");
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(32))]

    /// A unit sphere translated along a random integer direction `d` (a sweep invariant in
    /// t), its eye on a random line `P(r) = E + r D` through the point `3d` of the axis beyond
    /// the capsule (`E = 3d − D`, at r = 1): the contour lines merge where the eye
    /// crosses the infinite cylinder around the axis, the roots of the integer quadratic
    /// `q(r) = |P|²|d|² − (P·d)² − |d|²`. Every event lies on the characteristic circle and on
    /// the contour from its eye; every event inside a start or end position has `q` changing
    /// sign in its certified `r` interval, exactly; every simple root of `q` inside the path's
    /// interval is seen at both t = 0 and t = 1.
    #[test]
    fn random_translations_of_a_sphere_merge_their_lines_where_the_eye_enters_the_cylinder(
        d in proptest::collection::vec(-3i64..=3, 3),
        dir in proptest::collection::vec(-4i64..=4, 3),
    ) {
        translation_merges(&d, &dir)?;
    }
}

/// The body of the random-translation property for one direction `d` and eye-path
/// direction `dir` (its doc comment says what is checked).
fn translation_merges(d: &[i64], dir: &[i64]) -> Result<(), proptest::test_runner::TestCaseError> {
    use geocert::num::Rational;
    use geocert::solve::SolveOptions;
    use geocert::sweep::{events, verify_border_root, EventKind};
    proptest::prop_assume!(d.iter().any(|&x| x != 0) && dir.iter().any(|&x| x != 0));
    let e: Vec<i64> = (0..3).map(|k| 3 * d[k] - dir[k]).collect();
    let text = format!(
        r#"{{"surfaces": [{{"sphere": {{"center": [0, 0, 0], "radius": 1}}}}],
            "t": [0, 1],
            "motion": {{"translation": [[0, {}], [0, {}], [0, {}]]}},
            "eye": {{"path": [[{}, {}], [{}, {}], [{}, {}]], "r": [0, 2]}}}}"#,
        d[0], d[1], d[2], e[0], dir[0], e[1], dir[1], e[2], dir[2]
    );
    // q(r) = A r² + B r + C in integers.
    let dot = |a: &[i64], b: &[i64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<i64>();
    let dd = dot(d, d);
    let (a, b, c) = (
        dot(dir, dir) * dd - dot(dir, d).pow(2),
        2 * (dot(&e, dir) * dd - dot(&e, d) * dot(dir, d)),
        dot(&e, &e) * dd - dot(&e, d).pow(2) - dd,
    );
    let disc = b * b - 4 * a * c;
    // A tangent path (a double root) and an eye on the cylinder at an end of its interval
    // (an event on the domain's boundary, reported as a cluster) are left out.
    proptest::prop_assume!(a != 0 && disc != 0 && c != 0 && 4 * a + 2 * b + c != 0);
    let scene = scene_from_json(&text).unwrap();
    let ev = match events(&scene, &SolveOptions::new()) {
        Ok(ev) => ev,
        // An eye path through the swept sphere is refused.
        Err(SweepError::EyePathOnSurface { .. }) => return Ok(()),
        Err(err) => panic!("{err}"),
    };
    let q = |r: &Rational| -> Rational {
        let int = |k: i64| Rational::from_integer(k.into());
        int(a) * r * r + int(b) * r + int(c)
    };
    // A merge exactly on a patch border (the characteristic circle meets the eye's
    // contour on a border meridian, as for d = (2, 0, 2)) is a root on the boundary of
    // the two patches' t-face systems, where the solve leaves domain-boundary clusters;
    // each is solved again across the border (`BorderRoot`) and matched with the certified
    // edge event of the same patch at the same end of t. No cluster is left.
    proptest::prop_assert!(ev.clusters.is_empty(), "clusters {:?}", ev.clusters);
    for b in &ev.border_roots {
        let EventKind::Face { axis: 2, upper } = b.kind else {
            return Err(proptest::test_runner::TestCaseError::fail(format!(
                "border root of {:?}",
                b.kind
            )));
        };
        let e = &ev.events[b.event];
        let on_edge = e.patch == b.patch
            && matches!(e.kind, EventKind::Edge { fixed } if fixed[1] == (2, upper));
        proptest::prop_assert!(
            on_edge,
            "border root {:?} matched with {:?}",
            b.kind,
            e.kind
        );
        proptest::prop_assert!(verify_border_root(&scene, &ev.events, b).unwrap());
    }
    let at_ends: Vec<_> = ev
        .events
        .iter()
        .filter(|x| match x.kind {
            EventKind::Face { axis, .. } => axis == 2,
            EventKind::Edge { fixed } => fixed[1].0 == 2,
            _ => false,
        })
        .collect();
    for x in &ev.events {
        // On the characteristic circle (d·X = 0) and on the contour from P(r)
        // (1 − P(r)·X = 0; X the unit sphere's point, its own normal).
        let p = x.patch_point(&scene).unwrap();
        let eye: Vec<f64> = (0..3)
            .map(|k| (e[k] as f64) + x.r * dir[k] as f64)
            .collect();
        let along = (0..3).map(|k| d[k] as f64 * p[k]).sum::<f64>();
        let contour = 1.0 - (0..3).map(|k| eye[k] * p[k]).sum::<f64>();
        proptest::prop_assert!(
            along.abs() < 1e-8 && contour.abs() < 1e-8,
            "{:?} at r = {}: {along:e} {contour:e}",
            x.kind,
            x.r
        );
    }
    for x in at_ends
        .iter()
        .filter(|x| matches!(x.kind, EventKind::Face { .. }))
    {
        let (lo, hi) = x.root.bounds.last().unwrap();
        let (ql, qh) = (q(lo), q(hi));
        let zero = Rational::from_integer(0.into());
        proptest::prop_assert!(
            (ql <= zero && qh >= zero) || (ql >= zero && qh <= zero),
            "{:?} at r = {}: q does not change sign",
            x.kind,
            x.r
        );
    }
    if disc > 0 {
        let s = (disc as f64).sqrt();
        for root in [
            (-(b as f64) - s) / (2.0 * a as f64),
            (-(b as f64) + s) / (2.0 * a as f64),
        ] {
            if !(1e-6..=2.0 - 1e-6).contains(&root) {
                continue;
            }
            for t_end in [false, true] {
                let seen = at_ends.iter().any(|x| {
                    (x.r - root).abs() < 1e-8
                        && match x.kind {
                            EventKind::Face { upper, .. } => upper == t_end,
                            EventKind::Edge { fixed } => fixed[1].1 == t_end,
                            _ => false,
                        }
                });
                proptest::prop_assert!(
                    seen,
                    "merge at r = {root} not seen at t = {}",
                    u8::from(t_end)
                );
            }
        }
    }
    Ok(())
}

/// A merge exactly on a patch border (found by CI): for `d = (2, 0, 2)` the characteristic
/// circle meets the eye's contour on a border meridian of the sphere's patches. The t-face
/// systems' solves leave domain-boundary clusters there; each is solved again across the
/// border, its one root certified on the widened box and matched with the edge system's
/// certified event, and no cluster is left. A tampered record fails its check.
#[test]
fn a_merge_on_a_patch_border_is_certified_by_the_edge_systems() {
    use geocert::solve::SolveOptions;
    use geocert::sweep::{events, verify_border_root};
    translation_merges(&[2, 0, 2], &[4, 3, 0]).unwrap();
    let scene = scene_from_json(
        r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": 1}}], "t": [0, 1],
            "motion": {"translation": [[0, 2], [0, 0], [0, 2]]},
            "eye": {"path": [[2, 4], [-3, 3], [6, 0]], "r": [0, 2]}}"#,
    )
    .unwrap();
    let ev = events(&scene, &SolveOptions::new()).unwrap();
    assert!(ev.clusters.is_empty(), "{:?}", ev.clusters);
    assert!(!ev.border_roots.is_empty());
    for b in &ev.border_roots {
        assert!(verify_border_root(&scene, &ev.events, b).unwrap());
        // The root lies at the edge event's r, to the boxes' widths.
        let r = rational_to_f64(&b.root.bounds[2].0);
        assert!(
            (r - ev.events[b.event].r).abs() < 1e-9,
            "{r} vs {}",
            ev.events[b.event].r
        );
        let mut wrong = b.clone();
        wrong.event = (b.event + 1) % ev.events.len();
        if ev.events[wrong.event].patch != b.patch
            || ev.events[wrong.event].kind != ev.events[b.event].kind
        {
            assert!(!verify_border_root(&scene, &ev.events, &wrong).unwrap());
        }
        // The same box moved off the border, inside the patch.
        let mut moved = b.clone();
        let (lo, hi) = b.root.bounds[0].clone();
        let w = &hi - &lo;
        moved.root.bounds[0] = if lo < Rational::from_integer(0.into()) {
            (hi.clone(), &hi + &w)
        } else {
            (&lo - &w, lo.clone())
        };
        assert!(!verify_border_root(&scene, &ev.events, &moved).unwrap());
    }
    println!(
        "{} events, {} border roots re-checked, 0 clusters",
        ev.events.len(),
        ev.border_roots.len()
    );
}

/// The eye on the extension of the capsule's cylinder: the two contour lines of the envelope
/// merge into one ruling, a tangential root of `F̂ = Ĝ = 0` that the tracer in `(u, v, t)`
/// followed until its time limit. It is reported as a tangential ruling along the closed
/// form's line, with the unresolved box listed and nothing stopped by a budget.
#[test]
fn an_eye_on_the_extension_of_the_envelope_sees_one_tangential_ruling() {
    let scene = scene_from_json(
        r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": 1}}], "t": [0, 2],
            "motion": {"translation": [[0, 2], [0, "1/2"], [0]]}, "eye": [8, 2, 1]}"#,
    )
    .unwrap();
    let s = silhouette(&scene, &SilhouetteOptions::default()).unwrap();
    let envelope: Vec<_> = s
        .components
        .iter()
        .filter(|c| c.kind == ComponentKind::Envelope)
        .collect();
    assert_eq!(envelope.len(), 1);
    let ruling = &s.rulings[envelope[0].ruling.unwrap()];
    let RulingEvidence::Tangent { g_bound, .. } = &ruling.evidence else {
        panic!("{:?}", ruling.evidence)
    };
    assert!(*g_bound < 1e-12, "{g_bound:e}");
    // The line (0, 0, 1) + s (4, 1, 0), s ∈ [0, 1] (t = 2s).
    for (p, uvt) in envelope[0].points.iter().zip(&envelope[0].uvt) {
        let s = uvt[2] / 2.0;
        let q = [4.0 * s, s, 1.0];
        assert!((0..3).all(|k| (p[k] - q[k]).abs() < 1e-7), "{p:?} vs {q:?}");
    }
    assert!(matches!(
        verify_ruling(&scene, ruling, false).unwrap(),
        Ok(RootCheck {
            unknowns: 2,
            on_boundary: false
        })
    ));
    assert!(!s.clusters.is_empty());
    for (_, _, kind, c) in &s.clusters {
        assert_eq!(*kind, ComponentKind::Envelope);
        assert_eq!(c.reason, geocert::solve::ClusterReason::DepthLimit);
        for (lo, hi) in &c.bounds {
            assert!(rational_to_f64(&(hi - lo)) < 1e-8);
        }
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig {
        cases: 24,
        failure_persistence: None,
        ..Default::default()
    })]

    /// A unit sphere translated along `d` seen from an eye `E` off the capsule: the
    /// envelope's silhouette is two rulings where `E` is outside the infinite cylinder and
    /// none inside (decided exactly), each on the closed form's contour at `t = 0` and
    /// re-checked from the scene; the end positions' contours are closed curves with nothing
    /// left unresolved, their certified passages and touches re-checked.
    #[test]
    fn random_translated_spheres_have_the_closed_forms_rulings(
        d in proptest::array::uniform3(-3i64..=3),
        e in proptest::array::uniform3(-9i64..=9),
    ) {
        let dd: i64 = d.iter().map(|x| x * x).sum();
        proptest::prop_assume!(dd > 0);
        let ed: i64 = (0..3).map(|k| e[k] * d[k]).sum();
        let ee: i64 = e.iter().map(|x| x * x).sum();
        // Off the capsule (the segment from 0 to d, radius 1) with room to spare.
        let s = (ed as f64 / dd as f64).clamp(0.0, 1.0);
        let gap: f64 = (0..3).map(|k| (e[k] as f64 - s * d[k] as f64).powi(2)).sum::<f64>().sqrt();
        proptest::prop_assume!(gap > 1.01);
        // |E⊥|² − 1 = (|E|²|d|² − ⟨E, d⟩²)/|d|² − 1, its sign exactly.
        let outside = ee * dd - ed * ed - dd;
        proptest::prop_assume!(outside != 0);
        let json = format!(
            r#"{{"surfaces": [{{"sphere": {{"center": [0, 0, 0], "radius": 1}}}}], "t": [0, 1],
                "motion": {{"translation": [[0, {}], [0, {}], [0, {}]]}}, "eye": [{}, {}, {}]}}"#,
            d[0], d[1], d[2], e[0], e[1], e[2]
        );
        let scene = scene_from_json(&json).unwrap();
        let sil = silhouette(&scene, &SilhouetteOptions::default()).unwrap();
        // Nothing unresolved, on the envelope or the caps (a cap through a pole, a patch
        // corner or tangent to a patch border is certified there).
        proptest::prop_assert!(sil.clusters.is_empty(), "{:?}", sil.clusters);
        for x in &sil.cap_corner_passages {
            proptest::prop_assert!(verify_cap_corner_passage(&scene, x, false).unwrap());
        }
        for x in &sil.cap_border_touches {
            proptest::prop_assert!(verify_cap_border_touch(&scene, x, false).unwrap());
        }
        proptest::prop_assert!(sil
            .components
            .iter()
            .filter(|c| c.kind != ComponentKind::Envelope)
            .all(|c| c.closed));
        let envelope: Vec<_> = sil
            .components
            .iter()
            .filter(|c| c.kind == ComponentKind::Envelope)
            .collect();
        proptest::prop_assert_eq!(envelope.len(), if outside > 0 { 2 } else { 0 });
        // The exact path finds the same lines; the fast path too wherever it certified its
        // envelope (no envelope cluster left `Uncertain`).
        let starts = |s: &Silhouettes| -> Vec<[f64; 3]> {
            s.components
                .iter()
                .filter(|c| c.kind == ComponentKind::Envelope)
                .map(|c| c.points[0])
                .collect()
        };
        // The same points, in any order (each has a partner within 1e-9).
        let same = |a: &[[f64; 3]], b: &[[f64; 3]]| {
            let near = |p: &[f64; 3], q: &[f64; 3]| (0..3).all(|k| (p[k] - q[k]).abs() < 1e-9);
            a.len() == b.len()
                && a.iter().all(|p| b.iter().any(|q| near(p, q)))
                && b.iter().all(|q| a.iter().any(|p| near(p, q)))
        };
        let filtered = starts(&sil);
        for path in [Path::Exact, Path::Fast] {
            let other =
                silhouette(&scene, &SilhouetteOptions::default().with_path(path)).unwrap();
            if path == Path::Fast && other.clusters.iter().any(|c| c.2 == ComponentKind::Envelope) {
                continue;
            }
            let found = starts(&other);
            proptest::prop_assert!(same(&filtered, &found), "{:?}: {:?} vs {:?}", path, filtered, found);
        }
        let ef = e.map(|x| x as f64);
        let df = d.map(|x| x as f64);
        for c in envelope {
            let x = c.points[0];
            let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
            let on_sphere = dot(x, x) - 1.0;
            let on_circle = dot(x, df);
            let contour = 1.0 - dot(ef, x);
            proptest::prop_assert!(
                on_sphere.abs() < 1e-9 && on_circle.abs() < 1e-9 && contour.abs() < 1e-9,
                "{:?}: {} {} {}", x, on_sphere, on_circle, contour
            );
            // A line along a patch edge is traced on that edge (module `edges`); every other
            // one is a certified ruling.
            if let Some(i) = c.ruling {
                let r = &sil.rulings[i];
                proptest::prop_assert!(matches!(r.evidence, RulingEvidence::Root(_)));
                let check = verify_ruling(&scene, r, false).unwrap();
                proptest::prop_assert!(check.is_ok(), "{:?}", check);
            }
        }
    }
}

/// The start position's contour, which must be one closed curve.
fn the_closed_start_cap(s: &Silhouettes) -> &geocert::sweep::SilhouetteComponent {
    let caps: Vec<_> = s
        .components
        .iter()
        .filter(|c| c.kind == ComponentKind::CapA)
        .collect();
    assert_eq!(caps.len(), 1);
    assert!(caps[0].closed);
    caps[0]
}

/// The start position's contour touches the border between two patches (a meridian of the
/// sphere) at one point, tangentially: the border polynomial has a double root there, which
/// the tracer cannot certify (it left a cluster on both patches, and the cap open). Each
/// cluster is certified as a touch instead: on the patch the contour lies in, two arcs meet
/// at the touch point; on the other, the point alone. The cap is then one closed curve on the
/// closed-form contour circle (`|X| = 1`, `⟨X, E⟩ = 1`), through the touch point, and both
/// touches re-check from the scene (a tampered one does not).
#[test]
fn a_contour_tangent_to_a_patch_border_is_certified_there() {
    let scene = scene_from_json(
        r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": 1}}], "t": [0, 1],
            "motion": {"translation": [[0, -2], [0, -2], [0, 1]]}, "eye": [-6, -1, -8]}"#,
    )
    .unwrap();
    let s = silhouette(&scene, &SilhouetteOptions::default()).unwrap();
    assert!(s.clusters.is_empty(), "{:?}", s.clusters);
    let mut arcs: Vec<usize> = s.cap_border_touches.iter().map(|x| x.arcs).collect();
    arcs.sort_unstable();
    assert_eq!(arcs, [0, 2]);
    for x in &s.cap_border_touches {
        assert!(!x.upper);
        assert!(verify_cap_border_touch(&scene, x, false).unwrap());
        let mut tampered = x.clone();
        tampered.arcs = 1;
        assert!(!verify_cap_border_touch(&scene, &tampered, false).unwrap());
    }
    let cap = the_closed_start_cap(&s);
    let e = [-6.0, -1.0, -8.0];
    for p in &cap.points {
        let norm = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        let plane = p[0] * e[0] + p[1] * e[1] + p[2] * e[2];
        assert!(
            (norm - 1.0).abs() < 1e-9 && (plane - 1.0).abs() < 1e-9,
            "{p:?}"
        );
    }
    // The touch point is a vertex of the cap.
    let x = s.cap_border_touches.iter().find(|x| x.arcs == 2).unwrap();
    let mid = |(lo, hi): &(Rational, Rational)| {
        rational_to_f64(&((lo + hi) / Rational::from_integer(2.into())))
    };
    let (axis, upper) = x.border;
    let mut uv = [0.0; 2];
    uv[axis] = if upper { 1.0 } else { 0.0 };
    uv[1 - axis] = mid(&x.along);
    let touch = scene.surfaces[0].patches[x.patch]
        .point(uv[0], uv[1])
        .unwrap();
    let near = cap
        .points
        .iter()
        .map(|p| {
            (0..3)
                .map(|k| (p[k] - touch[k]).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .fold(f64::INFINITY, f64::min);
    assert!(near < 1e-12, "{near}");
}

/// The start position's contour passes exactly through the sphere's pole, a collapsed patch
/// edge where `G̃` then vanishes along the whole edge: its factor is divided out of the
/// cap's equation, and the contour is traced across the pole as one closed curve instead of
/// subdividing along the edge until the time limit (54,456 clusters in 133 s before).
#[test]
fn a_contour_through_a_pole_is_traced_across_it() {
    let scene = scene_from_json(
        r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": 1}}], "t": [0, 1],
            "motion": {"translation": [[0, -2], [0, -1], [0, 3]]}, "eye": [7, 1, -5]}"#,
    )
    .unwrap();
    let pole = scene.surfaces[0].patches[0].point(0.0, 0.5).unwrap();
    // The pole is on the contour from (7, 1, −5): ⟨P, pole⟩ = 1 on the unit sphere.
    let on_contour = 7.0 * pole[0] + pole[1] - 5.0 * pole[2];
    assert!((on_contour - 1.0).abs() < 1e-12, "{on_contour}");
    let s = silhouette(&scene, &SilhouetteOptions::default()).unwrap();
    assert!(s.clusters.is_empty(), "{:?}", s.clusters.len());
    let cap = the_closed_start_cap(&s);
    let near = cap
        .points
        .iter()
        .map(|p| (0..3).map(|k| (p[k] - pole[k]).powi(2)).sum::<f64>().sqrt())
        .fold(f64::INFINITY, f64::min);
    assert!(near < 1e-9, "{near}");
}

/// An ellipsoid rolling about an axis across its motion, seen from a moving eye, whose
/// silhouette passes over a pole (found by a random campaign; before, the pole faces' systems
/// had whole segments of roots and ran each to its limit, 19,378 clusters in 18 minutes).
/// On a pole the face equations separate as `λ(w)·φ(t)` and `μ(w)·γ(t, r)`, proved exactly,
/// so those face systems are left out; the edge systems at the pole's ends certify the
/// events in `(t, r)`, and the interior system's root on the pole is solved again across it
/// and matched with them.
#[test]
fn a_pole_passing_the_silhouette_is_an_event_of_the_pole_edges() {
    use geocert::solve::SolveOptions;
    use geocert::sweep::{events, verify_border_root, verify_events, EventKind};
    let scene = scene_from_json(
        r#"{"surfaces": [{"ellipsoid": {"center": [0, 0, 0], "radii": ["1/2", 2, 1]}}],
            "t": [0, 1],
            "motion": {"translation": [[0, -1], [0, -1], [0, 0]],
                       "rotation": {"quaternion": [[1], [0, "1/2"], [0, "-1/2"], [0]]}},
            "eye": {"path": [[-4, 2], [-8, -3], [-3, 1]], "r": [0, 1]}}"#,
    )
    .unwrap();
    let clock = std::time::Instant::now();
    let ev = events(&scene, &SolveOptions::new()).unwrap();
    let seconds = clock.elapsed().as_secs_f64();
    assert!(ev.clusters.is_empty(), "{:?}", ev.clusters);
    // 8 patches × 19 systems, less the 8 pole faces.
    assert_eq!(ev.systems, 8 * 19 - 8);
    for (e, check) in ev.events.iter().zip(verify_events(&scene, &ev.events)) {
        assert!(check.unwrap().is_ok(), "{e:?}");
    }
    assert!(!ev.border_roots.is_empty());
    for b in &ev.border_roots {
        assert_eq!(b.kind, EventKind::Interior);
        assert!(verify_border_root(&scene, &ev.events, b).unwrap());
        let e = &ev.events[b.event];
        // The pole of patches 4–7 is u = 1: the event is on a pole's end, at the root's t, r.
        assert!(
            e.kind.fixed().contains(&(0, true)) && e.kind.fixed().len() == 2,
            "{e:?}"
        );
        let t = rational_to_f64(&b.root.bounds[2].0);
        let r = rational_to_f64(&b.root.bounds[3].0);
        assert!((t - e.uvt[2]).abs() < 1e-9 && (r - e.r).abs() < 1e-9);
    }
    println!(
        "{} events from {} systems, {} roots on the pole re-checked, 0 clusters, {seconds:.2} s",
        ev.events.len(),
        ev.systems,
        ev.border_roots.len()
    );
}

#[test]
fn singular_event_roots_are_one_cluster_each() {
    use geocert::solve::{ClusterReason, SolveOptions};
    use geocert::sweep::{events, verify_events, EventKind};
    let contains = |b: &[(Rational, Rational)], p: &[f64]| {
        b.iter()
            .zip(p)
            .all(|((lo, hi), &x)| rational_to_f64(lo) <= x && x <= rational_to_f64(hi))
    };
    // A unit sphere turning about its centre while it moves along d = (−3, −2, 3): the
    // envelope is a cylinder, but the turn moves the characteristic curve in (u, v), so the
    // sweep is not invariant in t. The eye (−4 + r, −3 − 3r, 3 + 3r) leaves the cylinder at
    // 274 r² − 32 r − 3 = 0: there the two contour lines merge along a whole ruling, a curve
    // of roots of the interior system.
    let cylinder = scene_from_json(
        r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": 1}}], "t": [0, 1],
            "motion": {"translation": [[0, -3], [0, -2], [0, 3]],
                       "rotation": {"quaternion": [[1], [0, "-1/4"], [0, "-1/4"], [0, "1/2"]]}},
            "eye": {"path": [[-4, 1], [-3, -3], [3, 3]], "r": [0, 1]}}"#,
    )
    .unwrap();
    let r_leave = (16.0 + 1078f64.sqrt()) / 274.0;
    // An ellipsoid turning and moving down: a singular root of the start position's face
    // system near (u, v, r) = (0.99764, 0.51991, 0.29457) on patch 3.
    let ellipsoid = scene_from_json(
        r#"{"surfaces": [{"ellipsoid": {"center": [0, 0, 0], "radii": ["1/2", 2, "5/2"]}}],
            "t": [0, 1],
            "motion": {"translation": [[0, 0], [0, 0], [0, -1]],
                       "rotation": {"quaternion": [[1], [0, "-1/4"], [0, "-1/4"], [0]]}},
            "eye": {"path": [[0, 2], [1, 4], [-5, 2]], "r": [0, 1]}}"#,
    )
    .unwrap();
    let cases = [
        (cylinder, EventKind::Interior, vec![0.5, r_leave]),
        (
            ellipsoid,
            EventKind::Face {
                axis: 2,
                upper: false,
            },
            vec![0.99764, 0.51991, 0.29457],
        ),
    ];
    for (scene, kind, point) in cases {
        let clock = std::time::Instant::now();
        let ev = events(&scene, &SolveOptions::new()).unwrap();
        let seconds = clock.elapsed().as_secs_f64();
        assert_eq!(ev.clusters.len(), 1, "{kind:?}: {:?}", ev.clusters.len());
        let (_, _, k, c) = &ev.clusters[0];
        assert_eq!((*k, c.reason), (kind, ClusterReason::Singular));
        match kind {
            // The ruling's r; its (u, v, t) run along the curve.
            EventKind::Interior => assert!(contains(&c.bounds[3..], &point[1..])),
            _ => assert!(contains(&c.bounds, &point), "{:?}", c.bounds),
        }
        for (e, check) in ev.events.iter().zip(verify_events(&scene, &ev.events)) {
            assert!(check.unwrap().is_ok(), "{e:?}");
        }
        println!(
            "{kind:?}: {} events re-checked, one singular cluster, {seconds:.2} s",
            ev.events.len()
        );
    }
}
