//! The degenerate-but-legal eyes of `reports/sweep.md`: an eye on the extension of a
//! capsule's cylinder (the two contour lines merge into one tangential ruling), a contour
//! through a sphere's pole (a collapsed patch edge), a ruling along a patch corner where
//! three patches meet, and a contour tangent to a patch border. Each is measured against its
//! closed form.

use crate::sweep::{
    scene_from_json, silhouette, verify_cap_border_touch, verify_cap_corner_passage, verify_ruling,
    ComponentKind, RulingEvidence, Scene, SilhouetteOptions, Silhouettes,
};
use serde::Serialize;
use std::fmt::Write as _;

/// Runs per case for the median time.
const RUNS: usize = 3;

/// One degenerate eye.
#[derive(Clone, Debug, Serialize)]
pub struct DegenerateRow {
    /// What is degenerate.
    pub case: String,
    /// The scene (JSON, one line).
    pub scene: String,
    /// Envelope components.
    pub envelope: usize,
    /// Rulings certified as roots.
    pub root_rulings: usize,
    /// Tangential rulings.
    pub tangent_rulings: usize,
    /// Rulings that pass `verify_ruling`.
    pub verified: usize,
    /// The largest certified bound on `|Ĝ|` at a tangential ruling's critical point.
    pub g_bound: f64,
    /// Unresolved boxes on the envelope.
    pub envelope_clusters: usize,
    /// Unresolved boxes on the caps.
    pub cap_clusters: usize,
    /// Whether both caps are closed curves.
    pub caps_closed: bool,
    /// The caps' certified passages through patch corners and touches on patch borders, and
    /// how many re-check.
    pub cap_passages: usize,
    pub cap_passages_verified: usize,
    /// The closed-form measure (see `check`).
    pub closed_form: f64,
    /// What `closed_form` measures.
    pub check: String,
    /// Median wall time of the whole silhouette, seconds.
    pub median_seconds: f64,
    /// Set when the run failed.
    pub error: Option<String>,
}

/// A case: name, scene JSON, what is measured, and the measure on the result.
type Case = (
    &'static str,
    &'static str,
    &'static str,
    fn(&Scene, &Silhouettes) -> f64,
);

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
}

/// The envelope's vertices' largest distance to the line `(0, 0, 1) + (t/2)(4, 1, 0)`.
fn off_cylinder_line(_: &Scene, s: &Silhouettes) -> f64 {
    s.components
        .iter()
        .filter(|c| c.kind == ComponentKind::Envelope)
        .flat_map(|c| c.points.iter().zip(&c.uvt))
        .map(|(p, uvt)| {
            let h = uvt[2] / 2.0;
            dist(*p, [4.0 * h, h, 1.0])
        })
        .fold(0.0, f64::max)
}

/// The start position's contour's nearest vertex to the pole.
fn cap_to_pole(scene: &Scene, s: &Silhouettes) -> f64 {
    let Some(pole) = scene.surfaces[0].patches[0].point(0.0, 0.5) else {
        return f64::NAN;
    };
    s.components
        .iter()
        .filter(|c| c.kind == ComponentKind::CapA)
        .flat_map(|c| c.points.iter())
        .map(|p| dist(*p, pole))
        .fold(f64::INFINITY, f64::min)
}

/// The number of envelope components starting at the corner `(−247, 398, 194)/507`.
fn through_corner(_: &Scene, s: &Silhouettes) -> f64 {
    let corner = [-247.0 / 507.0, 398.0 / 507.0, 194.0 / 507.0];
    s.components
        .iter()
        .filter(|c| c.kind == ComponentKind::Envelope && dist(c.points[0], corner) < 1e-12)
        .count() as f64
}

/// The start position's contour's largest distance from its closed form, the circle
/// `|X| = 1`, `⟨X, E⟩ = 1` with `E = (−6, −1, −8)`: the larger of `||X| − 1|` and the
/// distance to the plane.
fn off_contour_circle(_: &Scene, s: &Silhouettes) -> f64 {
    let e = [-6.0, -1.0, -8.0];
    let norm = |p: [f64; 3]| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    s.components
        .iter()
        .filter(|c| c.kind == ComponentKind::CapA)
        .flat_map(|c| c.points.iter())
        .map(|&p| {
            let plane = (p[0] * e[0] + p[1] * e[1] + p[2] * e[2] - 1.0).abs() / norm(e);
            (norm(p) - 1.0).abs().max(plane)
        })
        .fold(0.0, f64::max)
}

const CASES: [Case; 4] = [
    (
        "eye on the cylinder's extension",
        r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": 1}}], "t": [0, 2], "motion": {"translation": [[0, 2], [0, "1/2"], [0]]}, "eye": [8, 2, 1]}"#,
        "largest distance of the envelope's vertices from the line (0, 0, 1) + (t/2)(4, 1, 0)",
        off_cylinder_line,
    ),
    (
        "start position's contour through the pole",
        r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": 1}}], "t": [0, 1], "motion": {"translation": [[0, -2], [0, -1], [0, 3]]}, "eye": [7, 1, -5]}"#,
        "distance from the pole to the nearest vertex of the start position's contour",
        cap_to_pole,
    ),
    (
        "silhouette along a patch corner (a cone)",
        r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": 1}}], "t": [0, 1], "motion": {"translation": [[0, "613/338"], [0, "295/507"], [0, "-97/507"]], "linear": [[[1, "1/2"], [0], [0]], [[0], [1, "1/2"], [0]], [[0], [0], [1, "1/2"]]]}, "eye": ["151/507", "603/169", "-2194/507"]}"#,
        "envelope components through the corner (−247, 398, 194)/507 at t = 0 (three patches meet there)",
        through_corner,
    ),
    (
        "start position's contour tangent to a patch border",
        r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": 1}}], "t": [0, 1], "motion": {"translation": [[0, -2], [0, -2], [0, 1]]}, "eye": [-6, -1, -8]}"#,
        "largest distance of the start position's contour's vertices from the circle ‖X‖ = 1, ⟨X, (−6, −1, −8)⟩ = 1 (it touches the border between two patches at one point)",
        off_contour_circle,
    ),
];

/// Runs every case on the filtered path.
pub fn degenerate_runs() -> Vec<DegenerateRow> {
    CASES
        .iter()
        .map(|&(case, json, check, measure)| {
            let mut row = DegenerateRow {
                case: case.into(),
                scene: json.into(),
                envelope: 0,
                root_rulings: 0,
                tangent_rulings: 0,
                verified: 0,
                g_bound: 0.0,
                envelope_clusters: 0,
                cap_clusters: 0,
                caps_closed: false,
                cap_passages: 0,
                cap_passages_verified: 0,
                closed_form: f64::NAN,
                check: check.into(),
                median_seconds: f64::NAN,
                error: None,
            };
            let scene = match scene_from_json(json) {
                Ok(s) => s,
                Err(e) => {
                    row.error = Some(e.to_string());
                    return row;
                }
            };
            let mut times = Vec::new();
            let mut last = None;
            for _ in 0..RUNS {
                let clock = std::time::Instant::now();
                match silhouette(&scene, &SilhouetteOptions::default()) {
                    Ok(s) => last = Some(s),
                    Err(e) => {
                        row.error = Some(e.to_string());
                        return row;
                    }
                }
                times.push(clock.elapsed().as_secs_f64());
            }
            times.sort_by(f64::total_cmp);
            row.median_seconds = times[times.len() / 2];
            let Some(s) = last else { return row };
            let is = |k: ComponentKind| move |c: &&crate::sweep::SilhouetteComponent| c.kind == k;
            row.envelope = s
                .components
                .iter()
                .filter(is(ComponentKind::Envelope))
                .count();
            for r in &s.rulings {
                match &r.evidence {
                    RulingEvidence::Root(_) => row.root_rulings += 1,
                    RulingEvidence::Tangent { g_bound, .. } => {
                        row.tangent_rulings += 1;
                        row.g_bound = row.g_bound.max(*g_bound);
                    }
                }
                if matches!(verify_ruling(&scene, r, false), Ok(Ok(_))) {
                    row.verified += 1;
                }
            }
            row.envelope_clusters = s
                .clusters
                .iter()
                .filter(|c| c.2 == ComponentKind::Envelope)
                .count();
            row.cap_clusters = s.clusters.len() - row.envelope_clusters;
            row.caps_closed = [ComponentKind::CapA, ComponentKind::CapB].iter().all(|&k| {
                let caps: Vec<_> = s.components.iter().filter(is(k)).collect();
                !caps.is_empty() && caps.iter().all(|c| c.closed)
            });
            row.cap_passages = s.cap_corner_passages.len() + s.cap_border_touches.len();
            row.cap_passages_verified = s
                .cap_corner_passages
                .iter()
                .filter(|x| matches!(verify_cap_corner_passage(&scene, x, false), Ok(true)))
                .count()
                + s.cap_border_touches
                    .iter()
                    .filter(|x| matches!(verify_cap_border_touch(&scene, x, false), Ok(true)))
                    .count();
            row.closed_form = measure(&scene, &s);
            row
        })
        .collect()
}

/// Whether every case ran, every ruling re-checked, and each matches its closed form: one
/// tangential ruling within 1e-7 of the line; the contour through the pole closed, with a
/// vertex on the pole and nothing unresolved; one component through the corner, the caps
/// through that corner certified there; the contour tangent to a patch border on its circle,
/// its two touches (one per patch) certified.
pub fn degenerate_ok(rows: &[DegenerateRow]) -> bool {
    rows.len() == CASES.len()
        && rows.iter().all(|r| {
            r.error.is_none()
                && r.verified == r.root_rulings + r.tangent_rulings
                && r.caps_closed
                && r.cap_clusters == 0
                && r.cap_passages == r.cap_passages_verified
        })
        && rows[0].tangent_rulings == 1
        && rows[0].envelope == 1
        && rows[0].closed_form < 1e-7
        && rows[1].envelope_clusters + rows[1].cap_clusters == 0
        && rows[1].closed_form < 1e-9
        && rows[2].closed_form == 1.0
        && rows[2].envelope_clusters == 0
        && rows[3].cap_passages == 2
        && rows[3].closed_form < 1e-9
}

/// The report's section.
pub fn degenerate_markdown(s: &mut String, rows: &[DegenerateRow]) {
    let _ = writeln!(
        s,
        "## Degenerate eyes\n\nLegal inputs at the edge of the general position. A sweep \
         invariant in `t` (a translation along a line, a similarity with a fixed rotation along a \
         line) has a silhouette made of rulings over the points of `F̂ = Ĝ = 0` in `(u, v)` \
         (module `rulings`), each re-checked by `verify_ruling` from the scene. With the eye on \
         the extension of the envelope, the two lines merge: a tangential root, reported through \
         the certified critical point of `Ĝ` along `F̂ = 0` with a certified bound on `|Ĝ|` \
         there (relative to `Ĝ`'s largest coefficient), its depth-30 box listed as a cluster. \
         A contour through a sphere's pole (a collapsed patch edge, where `G` vanishes along the \
         whole edge) has that factor divided out of the cap's equation. A contour through a \
         patch corner is certified there like the envelope's passages (module `corners`: the \
         corner on it exactly, a partial derivative of one strict sign on the tracer's box, the \
         crossings of the box's inner edges counted, the corner the only zero on its border \
         edges; re-checked by `verify_cap_corner_passage`). A contour tangent to a patch border \
         away from the corners (a double root of the border polynomial, which the tracer cannot \
         certify) is certified as a touch on each of the two patches (module `corners`: `G`'s \
         derivative across the border of one strict sign on the tracer's box, no zero on its \
         inner edge, one distinct zero on the border by an exact gcd, the arcs to it counted from \
         the signs at the box's corners; re-checked by `verify_cap_border_touch`). Median of \
         {RUNS} runs, filtered path.\n\n\
         | case | envelope components | rulings: root / tangent (re-checked) | max \\|Ĝ\\| bound | clusters: envelope / caps | caps closed | caps' corner passages and border touches (re-checked) | closed form | value | median s |\n\
         |---|---:|---|---:|---|---|---|---|---:|---:|"
    );
    for r in rows {
        if let Some(e) = &r.error {
            let _ = writeln!(s, "| {} | failed: {e} | | | | | | | | |", r.case);
            continue;
        }
        let _ = writeln!(
            s,
            "| {} | {} | {} / {} ({}) | {} | {} / {} | {} | {} ({}) | {} | {} | {:.3} |",
            r.case,
            r.envelope,
            r.root_rulings,
            r.tangent_rulings,
            r.verified,
            if r.tangent_rulings > 0 {
                format!("{:.1e}", r.g_bound)
            } else {
                "–".into()
            },
            r.envelope_clusters,
            r.cap_clusters,
            if r.caps_closed { "yes" } else { "no" },
            r.cap_passages,
            r.cap_passages_verified,
            r.check,
            if r.closed_form.fract() == 0.0 && r.closed_form >= 1.0 {
                format!("{}", r.closed_form)
            } else {
                format!("{:.1e}", r.closed_form)
            },
            r.median_seconds
        );
    }
    let _ = writeln!(s, "\nThe scenes:\n");
    for r in rows {
        let _ = writeln!(s, "- {}: `{}`", r.case, r.scene);
    }
    let _ = writeln!(s);
}
