//! The necessary-and-sufficient injectivity test (paper Section 6, Theorem 1): every Bézier
//! cell of `det J` is subdivided by de Casteljau along `u`, `v`, `w` (an octree) until each
//! leaf has all coefficients positive (`Injective`) or a vertex coefficient — the value of
//! `det J` at that vertex — is `≤ 0` (`NotInjective`; zero is failure, Theorem 1).
//!
//! Paths: `exact` (sign-only integers, no `f64` anywhere), `fast` (certified `f64`, may say
//! `Uncertain`), `filtered` (fast first, exact on the boxes the fast path left uncertain).
//! Every decided verdict comes with a certificate that [`verify_injectivity_certificate`]
//! re-checks through the *other* Jacobian route (Mørken products).

use super::fast::{jacobian_cell_fast, JacobianWorkspace};
use super::jacobian::{
    cell_point, jacobian_cell_scaled_net, jacobian_cells_morken_scaled, jacobian_in_cell,
};
use super::lattice::{lattice_from_value, Basis, Lattice};
use super::FfdError;
use crate::bernstein::positivity::{round_down, LimitHit, WitnessValue};
use crate::bernstein::ScaledBernstein;
use crate::bernstein::{
    prove_positive_fast, prove_positive_filtered_with, prove_positive_scaled,
    verify_positive_certificate_scaled, Bernstein, DyadicBox, FastBernstein, Limits,
    PositivityVerdict,
};
use crate::num::UNIT_ROUNDOFF;
use crate::num::{parse_rational, rational_from_f64, rational_to_string, Rational, Sign};
use crate::Path;
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};

/// Options of [`check_injectivity`]; `limits` apply to each cell's subdivision.
#[derive(Clone, Copy, Debug)]
#[non_exhaustive]
pub struct CheckOptions {
    /// The arithmetic ([`Path::Filtered`] by default).
    pub path: Path,
    /// Limits of each cell's subdivision.
    pub limits: Limits,
}

crate::choice::setters!(CheckOptions {
    with_path => path: Path,
    with_limits => limits: Limits,
});

impl Default for CheckOptions {
    fn default() -> Self {
        CheckOptions {
            path: Path::Filtered,
            limits: Limits::default(),
        }
    }
}

/// One cell's positivity proof: leaf boxes of the cell's unit box, and a certified lower
/// bound of `det J` on the cell.
#[derive(Clone, Debug, PartialEq)]
pub struct CellProof {
    pub cell: [usize; 3],
    pub leaves: Vec<DyadicBox>,
    pub lower_bound: f64,
}

/// The verdict of the necessary-and-sufficient test, with its evidence.
#[derive(Clone, Debug, PartialEq)]
#[allow(clippy::large_enum_variant)] // one verdict per lattice; boxing buys nothing
pub enum InjectivityVerdict {
    /// `det J > 0` on every cell.
    Injective {
        /// Per cell, the leaf boxes that prove it.
        cells: Vec<CellProof>,
    },
    /// `det J(point) = det ≤ 0` (exact), `point` in the lattice's parameter domain.
    NotInjective {
        /// The cell holding the witness.
        cell: [usize; 3],
        /// The witness, in the lattice's parameter domain.
        point: [Rational; 3],
        /// `det J` there, exactly (`≤ 0`).
        det: Rational,
    },
    /// A caller-set limit was hit on `cell` at box `at` (cell-local), where `det J ≥
    /// lower_bound`.
    Undecided {
        /// The cell.
        cell: [usize; 3],
        /// Which limit.
        limit: LimitHit,
        /// The undecided box, cell-local.
        at: DyadicBox,
        /// Certified lower bound of `det J` on `at`.
        lower_bound: f64,
    },
    /// Fast path only: rounding left these boxes of `cell` undecided.
    Uncertain {
        /// The cell.
        cell: [usize; 3],
        /// The undecided boxes, cell-local.
        boxes: Vec<DyadicBox>,
    },
}

impl InjectivityVerdict {
    /// `injective`, `not_injective`, `undecided` or `uncertain`.
    pub fn name(&self) -> &'static str {
        match self {
            InjectivityVerdict::Injective { .. } => "injective",
            InjectivityVerdict::NotInjective { .. } => "not_injective",
            InjectivityVerdict::Undecided { .. } => "undecided",
            InjectivityVerdict::Uncertain { .. } => "uncertain",
        }
    }
    /// `Positive` (injective), `Negative` (not injective) or `Uncertain` (no decision).
    pub fn sign(&self) -> Sign {
        match self {
            InjectivityVerdict::Injective { .. } => Sign::Positive,
            InjectivityVerdict::NotInjective { .. } => Sign::Negative,
            _ => Sign::Uncertain,
        }
    }
}

/// The result of checking one lattice.
#[derive(Clone, Debug, PartialEq)]
pub struct InjectivityReport {
    /// The verdict and its evidence.
    pub verdict: InjectivityVerdict,
    /// A certified lower bound of `det J` over the whole domain (leaf bounds on proven cells,
    /// the cell's smallest Bézier coefficient elsewhere), when every cell produced one.
    pub min_det_lower_bound: Option<Rational>,
    /// Leaf boxes proven positive, over all cells.
    pub leaves: usize,
    /// The path that decided.
    pub path: Path,
}

impl InjectivityReport {
    /// The `--json` form: `{"verdict", "witness"?, "min_det_lower_bound", "leaves", "path"}`.
    pub fn to_json(&self) -> Value {
        let mut v = json!({
            "verdict": self.verdict.name(),
            "min_det_lower_bound": self.min_det_lower_bound.as_ref().map(rational_to_string),
            "leaves": self.leaves,
            "path": self.path.name(),
        });
        match &self.verdict {
            InjectivityVerdict::NotInjective { point, det, cell } => {
                v["witness"] = json!({
                    "point": point.iter().map(rational_to_string).collect::<Vec<_>>(),
                    "det": rational_to_string(det),
                    "cell": cell,
                });
            }
            InjectivityVerdict::Undecided {
                cell,
                limit,
                at,
                lower_bound,
            } => {
                v["undecided"] = json!({"cell": cell, "limit": format!("{limit:?}").to_lowercase(), "box": at, "lower_bound": lower_bound});
            }
            InjectivityVerdict::Uncertain { cell, boxes } => {
                v["uncertain"] = json!({"cell": cell, "boxes": boxes.len()});
            }
            InjectivityVerdict::Injective { .. } => {}
        }
        v
    }
}

/// The `f64` Bézier net of a cell and its relative error against the exact net.
pub(crate) fn net_f64(net: &[Bernstein<Rational>; 3]) -> (Vec<[f64; 3]>, f64) {
    let mut exact = true;
    let pts = (0..net[0].coeffs().len())
        .map(|k| {
            [0, 1, 2].map(|c| {
                let r = &net[c].coeffs()[k];
                let x = crate::num::Field::approx(r);
                if exact && rational_from_f64(x, "x").map_or(true, |e| &e != r) {
                    exact = false;
                }
                x
            })
        })
        .collect();
    // Round-to-nearest in the normal range errs by at most u relative (the fast Jacobian
    // refuses subnormal magnitudes).
    (pts, if exact { 0.0 } else { UNIT_ROUNDOFF })
}

/// [`net_f64`] of a net in integers over a denominator: each coefficient rounded to nearest
/// without a gcd, and checked exact by multiplying back (`m · 2^e · den = num`).
pub(crate) fn net_f64_scaled(net: &[ScaledBernstein; 3]) -> (Vec<[f64; 3]>, f64) {
    use crate::num::rational::{f64_dyadic, ratio_to_f64};
    let mut exact = true;
    let pts = (0..net[0].numerators().len())
        .map(|k| {
            [0, 1, 2].map(|c| {
                let (num, den) = (&net[c].numerators()[k], net[c].denominator());
                let x = ratio_to_f64(num, den);
                if exact {
                    exact = x.is_finite() && {
                        let (m, e) = f64_dyadic(x);
                        let m = num_bigint::BigInt::from(m) * den;
                        if e >= 0 {
                            m << e as usize == *num
                        } else {
                            m == num << (-e) as usize
                        }
                    };
                }
                x
            })
        })
        .collect();
    (pts, if exact { 0.0 } else { UNIT_ROUNDOFF })
}

/// The smallest coefficient, as a certified lower bound.
fn fast_root_bound(f: &FastBernstein) -> f64 {
    let m = f.coeffs().iter().fold(f64::INFINITY, |m, &c| m.min(c));
    (m - f.err()).next_down()
}

/// Decides injectivity of `l` (Theorem 1) by the necessary-and-sufficient test.
pub fn check_injectivity(l: &Lattice, opts: CheckOptions) -> Result<InjectivityReport, FfdError> {
    // Every path starts from the integer nets over one denominator (no gcd): the exact path
    // multiplies them, the others round them to f64.
    let nets = l.bezier_nets_scaled();
    let deg = l.order().map(|o| o - 1);
    let mut ws = JacobianWorkspace::default();
    let mut proofs = Vec::with_capacity(nets.len());
    let mut bounds: Vec<Option<f64>> = Vec::with_capacity(nets.len());
    let mut pending: Option<InjectivityVerdict> = None;
    let mut leaves = 0usize;
    // Bézier lattices with exact f64 points are their own f64 net.
    let direct: Option<Vec<[f64; 3]>> = match l.basis() {
        Basis::Bezier => l.points_f64().map(<[_]>::to_vec),
        Basis::Bspline => None,
    };
    let net_f64 = |net: &[ScaledBernstein; 3]| match &direct {
        Some(p) => (p.clone(), 0.0),
        None => net_f64_scaled(net),
    };
    for c in 0..l.cell_count() {
        let cell = l.cell_index(c);
        let net = &nets[c];
        // The verdict, and the cell's smallest Bézier coefficient as a certified bound.
        let (verdict, root_bound) = match opts.path {
            Path::Exact => {
                let j = jacobian_cell_scaled_net(net)?;
                let rb = round_down(&j.coeff_value(j.argmin()));
                (prove_positive_scaled(&j, opts.limits), Some(rb))
            }
            Path::Fast => {
                let (pts, eta) = net_f64(net);
                match jacobian_cell_fast(&pts, deg, eta, &mut ws) {
                    Ok(f) => (
                        prove_positive_fast(&f, opts.limits),
                        Some(fast_root_bound(&f)),
                    ),
                    Err(_) => (
                        PositivityVerdict::Uncertain {
                            boxes: vec![DyadicBox::root(3)],
                            proven: vec![],
                            proven_lower_bound: f64::INFINITY,
                        },
                        None,
                    ),
                }
            }
            Path::Filtered => {
                let (pts, eta) = net_f64(net);
                let f = jacobian_cell_fast(&pts, deg, eta, &mut ws).ok();
                let mut failure = None;
                let mut witness_failure = None;
                let mut exact_bound = None;
                let v = prove_positive_filtered_with(
                    f.as_ref(),
                    || match jacobian_cell_scaled_net(net) {
                        Ok(j) => {
                            exact_bound = Some(round_down(&j.coeff_value(j.argmin())));
                            j
                        }
                        Err(e) => {
                            failure = Some(e);
                            net[0].clone()
                        }
                    },
                    |w| match jacobian_in_cell(l, cell, &cell_point(cell, w)) {
                        Ok(v) => v,
                        Err(e) => {
                            witness_failure = Some(e);
                            Rational::default()
                        }
                    },
                    opts.limits,
                );
                if let Some(e) = failure.or(witness_failure) {
                    return Err(e);
                }
                (v, f.as_ref().map(fast_root_bound).or(exact_bound))
            }
        };
        match verdict {
            PositivityVerdict::Positive {
                leaves: ls,
                lower_bound,
            } => {
                leaves += ls.len();
                bounds.push(Some(lower_bound));
                proofs.push(CellProof {
                    cell,
                    leaves: ls,
                    lower_bound,
                });
            }
            PositivityVerdict::NotPositive { witness, value } => {
                let point = cell_point(cell, &witness);
                let det = match value {
                    WitnessValue::Exact(v) => v,
                    WitnessValue::AtMost(_) => jacobian_in_cell(l, cell, &point)?,
                };
                bounds.push(root_bound);
                // Bounds of the remaining cells (root coefficients) for min_det_lower_bound.
                for rest in &nets[c + 1..] {
                    bounds.push(match opts.path {
                        Path::Exact => {
                            let j = jacobian_cell_scaled_net(rest)?;
                            Some(round_down(&j.coeff_value(j.argmin())))
                        }
                        _ => {
                            let (pts, eta) = net_f64(rest);
                            jacobian_cell_fast(&pts, deg, eta, &mut ws)
                                .ok()
                                .map(|f| fast_root_bound(&f))
                        }
                    });
                }
                let min = bounds
                    .iter()
                    .try_fold(f64::INFINITY, |m, b| b.map(|b| m.min(b)));
                return Ok(InjectivityReport {
                    verdict: InjectivityVerdict::NotInjective { cell, point, det },
                    min_det_lower_bound: min.and_then(|m| rational_from_f64(m, "bound").ok()),
                    leaves,
                    path: opts.path,
                });
            }
            PositivityVerdict::Undecided {
                limit,
                at,
                lower_bound,
            } => {
                bounds.push(Some(lower_bound));
                pending.get_or_insert(InjectivityVerdict::Undecided {
                    cell,
                    limit,
                    at,
                    lower_bound,
                });
            }
            PositivityVerdict::Uncertain { boxes, proven, .. } => {
                leaves += proven.len();
                bounds.push(root_bound);
                pending.get_or_insert(InjectivityVerdict::Uncertain { cell, boxes });
            }
        }
    }
    let min = bounds
        .iter()
        .try_fold(f64::INFINITY, |m, b| b.map(|b| m.min(b)));
    Ok(InjectivityReport {
        verdict: pending.unwrap_or(InjectivityVerdict::Injective { cells: proofs }),
        min_det_lower_bound: min.and_then(|m| rational_from_f64(m, "bound").ok()),
        leaves,
        path: opts.path,
    })
}

/// One cell's leaves in a certificate file.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct CellLeaves {
    pub cell: [usize; 3],
    pub leaves: Vec<DyadicBox>,
}

/// A witness in a certificate file (exact strings).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct WitnessFile {
    /// The cell whose (one-sided) derivatives are meant; cells matter only for order-2
    /// lattices, which are C⁰ across cell faces.
    pub cell: [usize; 3],
    pub point: Vec<String>,
    pub det: String,
}

/// An injectivity certificate as written to disk.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct InjectivityCertificate {
    /// Always `"geocert/ffd-injectivity"`.
    pub kind: String,
    /// The lattice, in the input format.
    pub lattice: Value,
    /// `"injective"` or `"not_injective"`.
    pub verdict: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    /// `injective`: per cell, its leaf boxes.
    pub cells: Option<Vec<CellLeaves>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    /// `not_injective`: the witness.
    pub witness: Option<WitnessFile>,
}

/// The kind tag of injectivity certificates.
pub(crate) const CERTIFICATE_KIND: &str = "geocert/ffd-injectivity";

impl InjectivityCertificate {
    /// The certificate of a decided verdict (`None` for undecided or uncertain ones).
    pub fn from_report(l: &Lattice, r: &InjectivityReport) -> Option<InjectivityCertificate> {
        let base = |verdict: &str| InjectivityCertificate {
            kind: CERTIFICATE_KIND.into(),
            lattice: l.to_json(),
            verdict: verdict.into(),
            cells: None,
            witness: None,
        };
        match &r.verdict {
            InjectivityVerdict::Injective { cells } => Some(InjectivityCertificate {
                cells: Some(
                    cells
                        .iter()
                        .map(|p| CellLeaves {
                            cell: p.cell,
                            leaves: p.leaves.clone(),
                        })
                        .collect(),
                ),
                ..base("injective")
            }),
            InjectivityVerdict::NotInjective { point, det, cell } => Some(InjectivityCertificate {
                witness: Some(WitnessFile {
                    cell: *cell,
                    point: point.iter().map(rational_to_string).collect(),
                    det: rational_to_string(det),
                }),
                ..base("not_injective")
            }),
            _ => None,
        }
    }
}

/// Why [`verify_injectivity_certificate`] refused a certificate: what failed, and where.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum CertificateRefusal {
    /// The `kind` field is not geocert's injectivity certificate.
    #[error("kind is {found:?}, expected {CERTIFICATE_KIND:?}")]
    Kind {
        /// The `kind` found.
        found: String,
    },
    /// The `verdict` is neither `injective` nor `not_injective`.
    #[error("unknown verdict {0:?} (expected \"injective\" or \"not_injective\")")]
    Verdict(String),
    /// The field the verdict needs (`cells` or `witness`) is absent.
    #[error("{verdict} certificate without `{field}`")]
    Missing {
        /// The certificate's verdict.
        verdict: &'static str,
        /// The absent field.
        field: &'static str,
    },
    /// The number of certified cells differs from the lattice's.
    #[error("{certified} cells certified, the lattice has {cells}")]
    CellCount {
        /// Cells in the certificate.
        certified: usize,
        /// Cells of the lattice.
        cells: usize,
    },
    /// A certified cell index is outside the lattice.
    #[error("cell {0:?} outside the lattice")]
    CellOutside([usize; 3]),
    /// A cell is certified twice.
    #[error("cell {0:?} certified twice")]
    CellTwice([usize; 3]),
    /// A cell's leaves do not prove `det J > 0` on it.
    #[error("cell {cell:?}: {why}")]
    Leaves {
        /// The cell.
        cell: [usize; 3],
        /// Why its leaves were refused.
        why: crate::bernstein::CertificateError,
    },
    /// The witness point does not have three coordinates.
    #[error("witness point needs 3 coordinates, found {0}")]
    WitnessArity(usize),
    /// A witness number does not parse as an exact rational.
    #[error("witness {field}: {why}")]
    WitnessNumber {
        /// `point[i]` or `det`.
        field: String,
        /// The parser's reason.
        why: crate::num::NumError,
    },
    /// The claimed `det J` at the witness is not the exact value.
    #[error("det J at the witness is {exact}, the certificate claims {claimed}")]
    WitnessValue {
        /// The exact value, recomputed.
        exact: String,
        /// The certificate's value.
        claimed: String,
    },
    /// `det J` at the witness is positive: it witnesses nothing.
    #[error("det J at the witness is {0} > 0")]
    WitnessPositive(String),
}

/// What [`verify_injectivity_certificate`] re-established; `Display` gives a one-line summary.
#[derive(Clone, Debug, PartialEq)]
#[allow(clippy::large_enum_variant)] // one outcome per certificate; boxing buys nothing
pub enum InjectivityCheck {
    /// `det J > 0` on every cell: every leaf box of every cell has all coefficients positive.
    Injective {
        /// Cells of the lattice.
        cells: usize,
        /// Leaf boxes checked in all.
        leaves: usize,
        /// The lattice's basis.
        basis: Basis,
    },
    /// `det J ≤ 0` at the witness, recomputed exactly.
    NotInjective {
        /// The witness point, exactly.
        point: [Rational; 3],
        /// `det J` there (≤ 0).
        det: Rational,
    },
}

impl std::fmt::Display for InjectivityCheck {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            InjectivityCheck::Injective {
                cells,
                leaves,
                basis,
            } => write!(
                f,
                "injective: det J > 0 on all {cells} cells ({} basis), {leaves} leaf boxes, every \
                 coefficient positive (Jacobian recomputed by Mørken products)",
                match basis {
                    Basis::Bspline => "B-spline",
                    Basis::Bezier => "Bézier",
                }
            ),
            InjectivityCheck::NotInjective { point, det } => write!(
                f,
                "not injective: det J({}) = {} ≤ 0",
                crate::num::point_to_string(point),
                rational_to_string(det)
            ),
        }
    }
}

/// Re-checks a certificate independently of the code that produced it: the Jacobian's Bézier
/// cells come from the Mørken route
/// ([`jacobian_cells_morken`](super::jacobian::jacobian_cells_morken), in integers), the
/// leaves must tile each cell with every restricted coefficient positive, and a witness is
/// re-evaluated exactly from the derivative splines. A refusal is [`FfdError::Certificate`]
/// naming what failed (or [`FfdError::Input`] when the embedded lattice is malformed).
pub fn verify_injectivity_certificate(
    c: &InjectivityCertificate,
) -> Result<InjectivityCheck, FfdError> {
    verify_certificate_with(c, jacobian_cells_morken_scaled)
}

/// The certificate check with the Jacobian's Bézier cells (order as
/// [`Lattice::cell_index`]) from `cells_of`, given the certificate's own lattice.
pub(crate) fn verify_certificate_with(
    c: &InjectivityCertificate,
    cells_of: impl FnOnce(&Lattice) -> Result<Vec<ScaledBernstein>, FfdError>,
) -> Result<InjectivityCheck, FfdError> {
    use CertificateRefusal as R;
    if c.kind != CERTIFICATE_KIND {
        return Err(R::Kind {
            found: c.kind.clone(),
        }
        .into());
    }
    let l = lattice_from_value(&c.lattice)?;
    match c.verdict.as_str() {
        "injective" => {
            let cells = c.cells.as_ref().ok_or(R::Missing {
                verdict: "injective",
                field: "cells",
            })?;
            let polys = cells_of(&l)?;
            if cells.len() != polys.len() {
                return Err(R::CellCount {
                    certified: cells.len(),
                    cells: polys.len(),
                }
                .into());
            }
            let mut seen = vec![false; polys.len()];
            let mut leaves = 0;
            for cl in cells {
                let [i, j, k] = cl.cell;
                let dims = l.cells();
                if i >= dims[0] || j >= dims[1] || k >= dims[2] {
                    return Err(R::CellOutside(cl.cell).into());
                }
                let flat = i + dims[0] * (j + dims[1] * k);
                if std::mem::replace(&mut seen[flat], true) {
                    return Err(R::CellTwice(cl.cell).into());
                }
                leaves += verify_positive_certificate_scaled(&polys[flat], &cl.leaves)
                    .map_err(|why| R::Leaves { cell: cl.cell, why })?;
            }
            Ok(InjectivityCheck::Injective {
                cells: polys.len(),
                leaves,
                basis: l.basis(),
            })
        }
        "not_injective" => {
            let w = c.witness.as_ref().ok_or(R::Missing {
                verdict: "not_injective",
                field: "witness",
            })?;
            if w.point.len() != 3 {
                return Err(R::WitnessArity(w.point.len()).into());
            }
            let number = |field: String, s: &str| {
                parse_rational(s).map_err(|why| R::WitnessNumber { field, why })
            };
            let mut point: [Rational; 3] = Default::default();
            for (a, s) in w.point.iter().enumerate() {
                point[a] = number(format!("point[{a}]"), s)?;
            }
            let claimed = number("det".into(), &w.det)?;
            let det = jacobian_in_cell(&l, w.cell, &point)?;
            if det != claimed {
                return Err(R::WitnessValue {
                    exact: rational_to_string(&det),
                    claimed: w.det.clone(),
                }
                .into());
            }
            if det > Rational::default() {
                return Err(R::WitnessPositive(rational_to_string(&det)).into());
            }
            Ok(InjectivityCheck::NotInjective { point, det })
        }
        other => Err(R::Verdict(other.to_string()).into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_bigint::BigInt;

    /// The gcd-free f64 net equals the one rounded from the reduced rational net, points and
    /// error bound, on nets that are exactly f64 (dyadic perturbations) and nets that are not.
    #[test]
    fn scaled_f64_nets_equal_rational_f64_nets() {
        for (den, basis, order, cells) in [
            (8, Basis::Bspline, [2, 2, 2], [2, 1, 2]),
            (8, Basis::Bspline, [4, 4, 4], [2, 1, 2]),
            (7, Basis::Bspline, [3, 2, 4], [1, 2, 1]),
            (1i64 << 40, Basis::Bezier, [3, 2, 5], [1, 1, 1]),
            (1i64 << 40, Basis::Bezier, [4, 3, 2], [1, 1, 1]),
            (10, Basis::Bezier, [2, 2, 3], [1, 1, 1]),
        ] {
            let id = Lattice::identity(basis, order, cells).unwrap();
            let delta: Vec<[Rational; 3]> = (0..id.points().len())
                .map(|i| {
                    [0, 1, 2].map(|a| {
                        Rational::new(BigInt::from((i * 7 + a) as i64 % 11 - 5), BigInt::from(den))
                    })
                })
                .collect();
            let l = id.displaced(&delta).unwrap();
            let mut exact_seen = false;
            for (r, s) in l.bezier_nets().iter().zip(l.bezier_nets_scaled()) {
                let (a, b) = (net_f64(r), net_f64_scaled(&s));
                let bits =
                    |p: &[[f64; 3]]| p.iter().flatten().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&a.0), bits(&b.0));
                assert_eq!(a.1, b.1, "{basis:?} {order:?} over {den}");
                exact_seen |= a.1 == 0.0;
            }
            // Exact only for dyadic points on a dyadic identity (Bézier orders 2, 3, 5) and a
            // linear B-spline (the uniform cubic span map divides by 6, order 4 by 3).
            let dyadic_net = order == [2, 2, 2] || order == [3, 2, 5];
            assert_eq!(exact_seen, dyadic_net, "{basis:?} {order:?} over {den}");
        }
    }
}
