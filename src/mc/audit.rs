//! The table auditor: checks someone else's 256-configuration triangle table for cut-edge
//! coverage, segments off the cube faces, wrong face pairings, winding inconsistencies and
//! cracks between neighbouring configurations, and names the rule it follows on ambiguous
//! faces.
//!
//! Two numberings: `bourke` (Lorensen–Cline / Bourke: edges 0-1, 1-2, 2-3, 3-0, 4-5, 5-6, 6-7,
//! 7-4, 0-4, 1-5, 2-6, 3-7; bit `i` set when corner `i` is below the isovalue) and `vtk`
//! (vtkMarchingCubesTriangleCases: edges 0-1, 1-2, 3-2, 0-3, 4-5, 5-6, 7-6, 4-7, 0-4, 1-5,
//! 3-7, 2-6; bit `i` set when corner `i` is at or above it). Corners as in [`mod@super::table`].

use super::table::{
    ambiguous_faces, corner_across, edge_across, edge_between, face_edges, face_on, face_segments,
    is_cut, table, FACES,
};
use serde::Serialize;
use std::collections::BTreeSet;
use thiserror::Error;

/// Edge and configuration numbering of a table file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Numbering {
    /// Paul Bourke's: edges 0-1, 1-2, 2-3, 3-0, 4-5, 5-6, 6-7, 7-4, 0-4, 1-5, 2-6, 3-7; bit `i`
    /// set when corner `i` is below the isovalue.
    Bourke,
    /// VTK's: edges 0-1, 1-2, 3-2, 0-3, 4-5, 5-6, 7-6, 4-7, 0-4, 1-5, 3-7, 2-6; bit set when at
    /// or above.
    Vtk,
}

crate::choice::named_enum!(Numbering {
    Bourke => "bourke",
    Vtk => "vtk",
});

const VTK_EDGES: [[u8; 2]; 12] = [
    [0, 1],
    [1, 2],
    [3, 2],
    [0, 3],
    [4, 5],
    [5, 6],
    [7, 6],
    [4, 7],
    [0, 4],
    [1, 5],
    [3, 7],
    [2, 6],
];

impl Numbering {
    /// geocert's edge id of the file's edge `e`.
    fn edge(self, e: u8) -> u8 {
        match self {
            Numbering::Bourke => e,
            Numbering::Vtk => {
                let [a, b] = VTK_EDGES[e as usize];
                edge_between(a, b).expect("an edge")
            }
        }
    }
    /// The file's edge id of geocert's edge `e`.
    fn file_edge(self, e: u8) -> u8 {
        (0..12u8).find(|&f| self.edge(f) == e).expect("a bijection")
    }
    /// geocert's configuration (bit set = positive, `v ≥ c`) of the file's index.
    fn config(self, index: u8) -> u8 {
        match self {
            Numbering::Bourke => !index,
            Numbering::Vtk => index,
        }
    }
}

/// A table file that cannot be read.
#[derive(Debug, Error, PartialEq)]
pub enum TableError {
    #[error("table: {0}")]
    /// The file is not a 256-entry table.
    Format(String),
    #[error("configuration {config}: {why}")]
    /// An entry is malformed.
    Entry {
        /// Its configuration.
        config: usize,
        /// What is wrong.
        why: String,
    },
}

/// Strips `//` and `/* */` comments.
fn strip_comments(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while !rest.is_empty() {
        if let Some(r) = rest.strip_prefix("//") {
            rest = r.find('\n').map_or("", |i| &r[i..]);
        } else if let Some(r) = rest.strip_prefix("/*") {
            rest = r.find("*/").map_or("", |i| &r[i + 2..]);
        } else {
            let c = rest.chars().next().expect("non-empty");
            out.push(c);
            rest = &rest[c.len_utf8()..];
        }
    }
    out
}

fn integers(text: &str) -> Result<Vec<i64>, TableError> {
    let mut out = Vec::new();
    let mut tok = String::new();
    for c in text.chars().chain(std::iter::once(' ')) {
        if c.is_ascii_digit() || (c == '-' && tok.is_empty()) {
            tok.push(c);
        } else if !tok.is_empty() {
            if tok != "-" {
                out.push(
                    tok.parse()
                        .map_err(|_| TableError::Format(format!("bad integer {tok:?}")))?,
                );
            }
            tok.clear();
        }
    }
    Ok(out)
}

fn triangles_of(config: usize, ids: &[i64]) -> Result<Vec<[u8; 3]>, TableError> {
    let end = ids.iter().position(|&x| x == -1).unwrap_or(ids.len());
    if ids[end..].iter().any(|&x| x != -1) {
        return Err(TableError::Entry {
            config,
            why: "an edge id after the terminating -1".into(),
        });
    }
    let ids = &ids[..end];
    if !ids.len().is_multiple_of(3) {
        return Err(TableError::Entry {
            config,
            why: format!("{} edge ids, not a multiple of 3", ids.len()),
        });
    }
    ids.chunks(3)
        .map(|t| {
            let mut tri = [0u8; 3];
            for (slot, &x) in tri.iter_mut().zip(t) {
                if !(0..12).contains(&x) {
                    return Err(TableError::Entry {
                        config,
                        why: format!("edge id {x} out of 0…11"),
                    });
                }
                *slot = x as u8;
            }
            Ok(tri)
        })
        .collect()
}

/// Reads a table: 256 lines of edge ids (three per triangle, spaces or commas, trailing `-1`s
/// ignored, a line may be empty), or a C/Rust array literal read as 256×16 integers.
pub fn parse_table(text: &str) -> Result<Vec<Vec<[u8; 3]>>, TableError> {
    let text = strip_comments(text);
    if text.contains('{') || text.contains('[') {
        let body = text.split_once('=').map_or(text.as_str(), |(_, b)| b);
        let ints = integers(body)?;
        if ints.len() != 256 * 16 {
            return Err(TableError::Format(format!(
                "an array literal must hold 256×16 = 4096 integers, found {}",
                ints.len()
            )));
        }
        return ints
            .chunks(16)
            .enumerate()
            .map(|(i, row)| triangles_of(i, row))
            .collect();
    }
    let mut lines: Vec<&str> = text.lines().collect();
    while lines.len() > 256 && lines.last().is_some_and(|l| l.trim().is_empty()) {
        lines.pop();
    }
    if lines.len() != 256 {
        return Err(TableError::Format(format!(
            "expected 256 lines (one per configuration), found {}",
            lines.len()
        )));
    }
    lines
        .iter()
        .enumerate()
        .map(|(i, l)| triangles_of(i, &integers(&l.replace(',', " "))?))
        .collect()
}

/// What the auditor found.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct AuditReport {
    /// Configurations read (256).
    pub configurations: usize,
    /// Configuration pairs (file indices) and the axis of the face where the surfaces of two
    /// neighbouring cells do not meet.
    pub cracks: usize,
    /// Neighbouring configurations that crack: `(a, b, axis)`.
    pub crack_pairs: Vec<(u8, u8, char)>,
    /// Boundary segments wound against the table's own majority convention, plus interior
    /// triangle sides traversed twice in the same direction or more than twice.
    pub winding_errors: usize,
    /// Configurations using an uncut edge or missing a cut edge.
    pub edge_errors: usize,
    /// Boundary segments whose two cut points share no cube face.
    pub face_errors: usize,
    /// Faces whose segments pair the cut points in a way no bilinear interpolant does.
    pub pairing_errors: usize,
    /// The table's winding: which side of its triangles the positive (`v ≥ c`) region is on.
    pub winding: String,
    /// The rule the table follows on ambiguous faces, in words.
    pub ambiguous_face_rule: String,
    /// The first few problems, described.
    pub details: Vec<String>,
}

/// Audits a table given in `numbering`.
pub fn audit(tris: &[Vec<[u8; 3]>], numbering: Numbering) -> AuditReport {
    let mut r = AuditReport {
        configurations: tris.len(),
        cracks: 0,
        crack_pairs: Vec::new(),
        winding_errors: 0,
        edge_errors: 0,
        face_errors: 0,
        pairing_errors: 0,
        winding: String::new(),
        ambiguous_face_rule: String::new(),
        details: Vec::new(),
    };
    let note = |r: &mut AuditReport, s: String| {
        if r.details.len() < 20 {
            r.details.push(s);
        }
    };
    // Per geocert configuration: the table's boundary segments per face (directed).
    let mut boundary: Vec<[Vec<(u8, u8)>; 6]> = vec![Default::default(); 256];
    let (mut agree, mut disagree) = (0usize, 0usize);
    let mut decisions: Vec<(u8, u8, bool)> = Vec::new(); // (config, face, joined)
    for (index, t) in tris.iter().enumerate().take(256) {
        let config = numbering.config(index as u8);
        let ours: Vec<[u8; 3]> = t.iter().map(|tri| tri.map(|e| numbering.edge(e))).collect();
        let used: BTreeSet<u8> = ours.iter().flatten().copied().collect();
        let cut: BTreeSet<u8> = (0..12u8).filter(|&e| is_cut(config, e)).collect();
        if used != cut {
            r.edge_errors += 1;
            note(
                &mut r,
                format!("configuration {index}: uses edges {used:?}, cut edges are {cut:?}"),
            );
        }
        // Directed sides.
        let mut sides: std::collections::BTreeMap<(u8, u8), usize> = Default::default();
        for tri in &ours {
            for k in 0..3 {
                *sides.entry((tri[k], tri[(k + 1) % 3])).or_default() += 1;
            }
        }
        for (&(p, q), &n) in &sides {
            let back = sides.get(&(q, p)).copied().unwrap_or(0);
            if n > 1 || (back > 0 && n + back != 2) {
                r.winding_errors += 1;
                note(&mut r, format!("configuration {index}: side {p}-{q} traversed {n}× one way, {back}× the other"));
            }
            if back > 0 || p == q {
                continue;
            }
            // A boundary side: it must lie on a face.
            let face = (0..6u8).find(|&f| {
                let fe = face_edges(&FACES[f as usize]);
                fe.contains(&p) && fe.contains(&q)
            });
            match face {
                Some(f) => boundary[config as usize][f as usize].push((p, q)),
                None => {
                    r.face_errors += 1;
                    note(
                        &mut r,
                        format!("configuration {index}: segment {p}-{q} lies on no face"),
                    );
                }
            }
        }
        for f in 0..6u8 {
            let got: BTreeSet<BTreeSet<u8>> = boundary[config as usize][f as usize]
                .iter()
                .map(|&(p, q)| [p, q].into_iter().collect())
                .collect();
            let pairing = |joined: bool| -> BTreeSet<BTreeSet<u8>> {
                face_segments(config, f, joined)
                    .iter()
                    .map(|s| [s.from, s.to].into_iter().collect())
                    .collect()
            };
            let ambiguous = ambiguous_faces(config).contains(&f);
            let joined = if got == pairing(false) {
                Some(false)
            } else if ambiguous && got == pairing(true) {
                Some(true)
            } else {
                None
            };
            let Some(joined) = joined else {
                r.pairing_errors += 1;
                note(
                    &mut r,
                    format!("configuration {index}, face {f}: pairing {got:?}"),
                );
                continue;
            };
            if ambiguous {
                decisions.push((config, f, joined));
            }
            for s in face_segments(config, f, joined) {
                if boundary[config as usize][f as usize].contains(&(s.from, s.to)) {
                    agree += 1;
                } else {
                    disagree += 1;
                }
            }
        }
    }
    r.winding = if disagree == 0 {
        "positive region on the right of boundary segments seen from outside (counter-clockwise about the normal into the positive region)".into()
    } else if agree == 0 {
        "positive region on the left (counter-clockwise about the normal into the negative region)"
            .into()
    } else {
        format!("mixed: {agree} segments one way, {disagree} the other")
    };
    r.winding_errors += agree.min(disagree);
    // Cracks: neighbours across each axis with the same signs on the shared face.
    for axis in 0..3 {
        let (hi, lo) = (face_on(axis, 1), face_on(axis, 0));
        for c1 in 0..=255u8 {
            for c2 in 0..=255u8 {
                let matches = FACES[hi as usize]
                    .corners
                    .iter()
                    .all(|&c| (c1 >> c & 1) == (c2 >> corner_across(c, axis) & 1));
                if !matches {
                    continue;
                }
                let mine: BTreeSet<BTreeSet<u8>> = boundary[c1 as usize][hi as usize]
                    .iter()
                    .map(|&(p, q)| {
                        [edge_across(p, axis), edge_across(q, axis)]
                            .into_iter()
                            .collect()
                    })
                    .collect();
                let theirs: BTreeSet<BTreeSet<u8>> = boundary[c2 as usize][lo as usize]
                    .iter()
                    .map(|&(p, q)| [p, q].into_iter().collect())
                    .collect();
                if mine != theirs {
                    r.cracks += 1;
                    let file = |c: u8| match numbering {
                        Numbering::Bourke => !c,
                        Numbering::Vtk => c,
                    };
                    r.crack_pairs
                        .push((file(c1), file(c2), ['x', 'y', 'z'][axis]));
                }
            }
        }
    }
    let joined = decisions.iter().filter(|d| d.2).count();
    let separated = decisions.len() - joined;
    let minority = decisions.iter().all(|&(config, _, j)| {
        let positives = config.count_ones();
        // Separates the minority sign: positive corners joined iff they are the majority.
        (positives > 4 && j) || (positives < 4 && !j) || positives == 4
    });
    r.ambiguous_face_rule = if decisions.is_empty() {
        "no ambiguous face decided".into()
    } else if joined == 0 {
        "always separates the positive corners (a consistent rule: no cracks from ambiguity)".into()
    } else if separated == 0 {
        "always joins the positive corners (a consistent rule: no cracks from ambiguity)".into()
    } else if minority {
        format!("separates the minority sign of each cell (complementary symmetry, as Lorensen–Cline): {joined} faces join the positive corners, {separated} separate them — inconsistent between neighbours")
    } else {
        format!("mixed: {joined} faces join the positive corners, {separated} separate them")
    };
    r
}

/// geocert's table as 256 lines in `numbering`, one decision for every ambiguous face:
/// `joined(config)` gives whether the positive corners are joined in that configuration.
pub fn export(numbering: Numbering, joined: impl Fn(u8) -> bool) -> String {
    let tab = table();
    let mut out = String::new();
    for index in 0..=255u8 {
        let config = numbering.config(index);
        let k = ambiguous_faces(config).len();
        let sub = if joined(config) && k > 0 {
            ((1u16 << k) - 1) as u8
        } else {
            0
        };
        let ids: Vec<String> = tab
            .entry(config, sub)
            .triangles()
            .iter()
            .flatten()
            .map(|&e| numbering.file_edge(e).to_string())
            .collect();
        out.push_str(&ids.join(" "));
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geocert_tables_audit_clean_in_both_numberings() {
        for numbering in [Numbering::Bourke, Numbering::Vtk] {
            for rule in [false, true] {
                let text = export(numbering, |_| rule);
                let r = audit(&parse_table(&text).unwrap(), numbering);
                assert_eq!(
                    (
                        r.cracks,
                        r.winding_errors,
                        r.edge_errors,
                        r.face_errors,
                        r.pairing_errors
                    ),
                    (0, 0, 0, 0, 0),
                    "{numbering:?} {rule}: {:?}",
                    r.details
                );
                assert!(r.winding.starts_with("positive region on the right"));
                let expect = if rule {
                    "always joins"
                } else {
                    "always separates"
                };
                assert!(
                    r.ambiguous_face_rule.starts_with(expect),
                    "{}",
                    r.ambiguous_face_rule
                );
            }
        }
    }

    #[test]
    fn complementary_symmetry_cracks_and_defects_are_named() {
        // Separate the minority sign (Lorensen–Cline's complementary cases): cracks.
        let text = export(Numbering::Bourke, |c| c.count_ones() > 4);
        let r = audit(&parse_table(&text).unwrap(), Numbering::Bourke);
        assert!(r.cracks > 0 && !r.crack_pairs.is_empty());
        assert!(
            r.ambiguous_face_rule.contains("minority"),
            "{}",
            r.ambiguous_face_rule
        );
        // Reverse one triangle: a winding error; drop one: an edge error.
        let mut tris = parse_table(&export(Numbering::Bourke, |_| false)).unwrap();
        tris[1][0].swap(1, 2);
        tris[7].pop();
        let r = audit(&tris, Numbering::Bourke);
        assert!(r.winding_errors > 0 && r.edge_errors > 0, "{r:?}");
        // The same table as a C array literal.
        let rows: Vec<String> = parse_table(&export(Numbering::Vtk, |_| false))
            .unwrap()
            .iter()
            .map(|t| {
                let mut ids: Vec<i64> = t.iter().flatten().map(|&e| e as i64).collect();
                ids.resize(16, -1);
                format!(
                    "{{{}}}",
                    ids.iter()
                        .map(|x| x.to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            })
            .collect();
        let c = format!(
            "/* 256 x 16 */ static const int tri[256][16] = {{\n{}\n}};",
            rows.join(",\n")
        );
        let r = audit(&parse_table(&c).unwrap(), Numbering::Vtk);
        assert_eq!(r.cracks, 0);
        assert!(matches!(parse_table("1 2 3\n"), Err(TableError::Format(_))));
        let mut lines = vec![String::new(); 256];
        lines[5] = "0 1".into();
        assert!(matches!(
            parse_table(&lines.iter().map(|l| format!("{l}\n")).collect::<String>()),
            Err(TableError::Entry { config: 5, .. })
        ));
    }
}
