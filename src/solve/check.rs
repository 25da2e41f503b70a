//! The independent checker of root certificates. It does not call the subdivision: it
//! restricts the original equations to the root's box directly, forms `g = A f` and reads
//! the faces and the partial derivatives itself, all in exact rationals.

use super::input::{certificate_from_json, parse_box, system_from_json, system_to_json};
use super::{RationalBox, RootCertificate, Solution, SolveError, System};
use crate::bernstein::{Bernstein, BernsteinError};
use crate::num::{rational_to_string, Rational};
use num_traits::{Signed, Zero};
use serde_json::{json, Value};

/// The kind string of a root-certificate file.
pub const CERTIFICATE_KIND: &str = "geocert/solve-roots";

/// What [`verify_root`] re-established.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RootCheck {
    /// The number of unknowns (and of Miranda sign conditions checked per face pair).
    pub unknowns: usize,
}

impl std::fmt::Display for RootCheck {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "exactly one root in the box: A·f changes sign across all {} pairs of opposite faces \
             (Miranda) and its interval Jacobian is diagonally dominant (uniqueness)",
            self.unknowns
        )
    }
}

/// Why [`verify_root`] refused a certificate.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RootRefusal {
    /// The box is empty, inverted or not inside the domain on this axis.
    #[error("box axis {axis}: empty, inverted or outside the domain")]
    Bounds {
        /// The axis.
        axis: usize,
    },
    /// The box or matrix does not have the system's dimension.
    #[error("the box or preconditioner does not have the system's {0} unknowns")]
    Shape(usize),
    /// `g_i` is not of the certified strict sign on a face.
    #[error("g_{equation} is not strictly {} on the face t_{equation} = {}", if *negative { "negative" } else { "positive" }, if *upper { 1 } else { 0 })]
    Miranda {
        /// The row `i` of `g = A f` (and the axis of the face pair).
        equation: usize,
        /// Whether the upper face failed.
        upper: bool,
        /// The sign it should have had.
        negative: bool,
    },
    /// Row `i` of the interval Jacobian of `g` is not strictly diagonally dominant.
    #[error("row {row} of the interval Jacobian of A·f is not strictly diagonally dominant")]
    Uniqueness {
        /// The row.
        row: usize,
    },
    /// The Bernstein kernel refused an operation.
    #[error("Bernstein kernel: {0}")]
    Kernel(#[from] BernsteinError),
}

/// Re-checks that `bounds` (domain coordinates) holds exactly one root of `system`, from the
/// certificate's preconditioner and face signs.
pub fn verify_root(
    system: &System,
    bounds: &RationalBox,
    certificate: &RootCertificate,
) -> Result<RootCheck, RootRefusal> {
    let n = system.unknowns();
    let a = &certificate.preconditioner;
    if bounds.len() != n
        || a.len() != n
        || a.iter().any(|r| r.len() != n)
        || certificate.lower_face_signs.len() != n
        || system.equations.len() != n
    {
        return Err(RootRefusal::Shape(n));
    }
    // The box in the unit coordinates of the domain.
    let mut sub = Vec::with_capacity(n);
    for (axis, ((lo, hi), (a0, b0))) in bounds.iter().zip(&system.domain).enumerate() {
        let w = b0 - a0;
        let (u, v) = ((lo - a0) / &w, (hi - a0) / &w);
        if u.is_negative() || v > Rational::from_integer(1.into()) || u >= v {
            return Err(RootRefusal::Bounds { axis });
        }
        sub.push((u, v));
    }
    // Each equation on the box, at the common degrees.
    let top: Vec<usize> = (0..n)
        .map(|k| {
            system
                .equations
                .iter()
                .map(|e| e.degrees()[k])
                .max()
                .unwrap_or(0)
        })
        .collect();
    let mut f = Vec::with_capacity(n);
    for e in &system.equations {
        let mut p = e.restrict(&sub)?;
        for (k, &t) in top.iter().enumerate() {
            let d = p.degrees()[k];
            if d < t {
                p = p.elevate(k, t - d)?;
            }
        }
        f.push(p);
    }
    // g = A f, coefficient by coefficient.
    let size = f[0].coeffs().len();
    let g: Vec<Bernstein<Rational>> = a
        .iter()
        .map(|row| {
            let coeffs = (0..size)
                .map(|c| {
                    row.iter()
                        .zip(&f)
                        .map(|(aij, fj)| aij * &fj.coeffs()[c])
                        .fold(Rational::zero(), |s, x| s + x)
                })
                .collect();
            Bernstein::new(top.clone(), coeffs)
        })
        .collect::<Result<_, _>>()?;
    // Miranda: every coefficient on the face t_i = 0 has the certified sign, on t_i = 1 the
    // other.
    let strides: Vec<usize> = (0..n)
        .scan(1, |s, k| {
            let here = *s;
            *s *= top[k] + 1;
            Some(here)
        })
        .collect();
    for (i, gi) in g.iter().enumerate() {
        let negative_below = certificate.lower_face_signs[i] < 0;
        for upper in [false, true] {
            let want_negative = negative_below != upper;
            let on_face =
                |c: usize| (c / strides[i]) % (top[i] + 1) == if upper { top[i] } else { 0 };
            let ok = gi
                .coeffs()
                .iter()
                .enumerate()
                .filter(|(c, _)| on_face(*c))
                .all(|(_, x)| {
                    if want_negative {
                        x.is_negative()
                    } else {
                        x.is_positive()
                    }
                });
            if !ok {
                return Err(RootRefusal::Miranda {
                    equation: i,
                    upper,
                    negative: want_negative,
                });
            }
        }
    }
    // Uniqueness: min |∂g_i/∂t_i| > Σ_{k≠i} max |∂g_i/∂t_k| over the coefficients, the
    // diagonal of one strict sign.
    for (i, gi) in g.iter().enumerate() {
        let mut off = Rational::zero();
        let mut diag = None;
        for (k, &degree) in top.iter().enumerate() {
            if degree == 0 {
                if k == i {
                    return Err(RootRefusal::Uniqueness { row: i });
                }
                continue;
            }
            let d = gi.derivative(k)?;
            if k == i {
                let all_pos = d.coeffs().iter().all(|c| c.is_positive());
                let all_neg = d.coeffs().iter().all(|c| c.is_negative());
                if !(all_pos || all_neg) {
                    return Err(RootRefusal::Uniqueness { row: i });
                }
                diag = d.coeffs().iter().map(|c| c.abs()).min();
            } else {
                off += d.coeffs().iter().map(|c| c.abs()).max().unwrap_or_default();
            }
        }
        if diag.is_none_or(|m| m <= off) {
            return Err(RootRefusal::Uniqueness { row: i });
        }
    }
    Ok(RootCheck { unknowns: n })
}

/// The certificate file of a solution: the system (exactly) and each root's box,
/// preconditioner and face signs.
pub fn solution_certificate(system: &System, solution: &Solution) -> Value {
    json!({
        "kind": CERTIFICATE_KIND,
        "system": system_to_json(system),
        "roots": solution.roots.iter().map(|r| json!({
            "box": r.bounds.iter()
                .map(|(a, b)| json!([rational_to_string(a), rational_to_string(b)]))
                .collect::<Vec<_>>(),
            "preconditioner": serde_json::to_value(&r.certificate).unwrap_or_default()["preconditioner"],
            "lower_face_signs": r.certificate.lower_face_signs,
        })).collect::<Vec<_>>(),
    })
}

/// Re-checks every root of a certificate file with [`verify_root`]. The outer error is a
/// malformed file; each root has its own outcome.
#[allow(clippy::type_complexity)]
pub fn verify_solution_certificate(
    text: &str,
) -> Result<Vec<Result<RootCheck, RootRefusal>>, SolveError> {
    let v: Value = serde_json::from_str(text).map_err(|e| SolveError::Json(e.to_string()))?;
    let field = |f: &str, why: &str| SolveError::Field {
        field: f.into(),
        why: why.into(),
    };
    if v.get("kind").and_then(Value::as_str) != Some(CERTIFICATE_KIND) {
        return Err(field("kind", &format!("expected {CERTIFICATE_KIND:?}")));
    }
    let system = system_from_json(&v["system"].to_string())?;
    let n = system.unknowns();
    let roots = v
        .get("roots")
        .and_then(Value::as_array)
        .ok_or_else(|| field("roots", "missing or not an array"))?;
    let mut out = Vec::with_capacity(roots.len());
    for (r, root) in roots.iter().enumerate() {
        let bounds = parse_box(root.get("box"), &format!("roots[{r}].box"), Some(n))?;
        let certificate = certificate_from_json(root, n)?;
        out.push(verify_root(&system, &bounds, &certificate));
    }
    Ok(out)
}
