//! JSON files for polynomials and positivity certificates.
//!
//! Polynomial: `{"degrees": [d0, d1, …], "coeffs": [c, …]}`, axis 0 fastest; each coefficient a
//! JSON number (taken exactly as the `f64` it denotes) or a string `"p/q"` / decimal (exact).
//! Certificate: the polynomial plus `{"verdict": "positive", "leaves": [{"level": L, "index":
//! [i0, …]}, …]}` or `{"verdict": "not_positive", "witness": ["p/q", …], "value": "p/q"}`.

use super::positivity::{verify_witness, CertificateError, PositivityVerdict, WitnessValue};
use super::{verify_positive_certificate, Bernstein, DyadicBox};
use crate::num::{parse_rational, rational_from_f64, rational_to_string, NumError, Rational};
use serde::{Deserialize, Serialize};
use serde_json::Value;
use thiserror::Error;

/// Errors reading a polynomial or certificate file.
#[derive(Debug, Error)]
pub enum InputError {
    #[error("not valid JSON: {0}")]
    /// The file is not JSON.
    Json(#[from] serde_json::Error),
    #[error("field `{field}`: {why}")]
    /// A field is missing or malformed.
    Field {
        /// The field's name.
        field: String,
        /// What is wrong with it.
        why: String,
    },
    #[error("coefficient {index}: {why}")]
    /// A coefficient is not an exact number.
    Coefficient {
        /// Its index in `coeffs`.
        index: usize,
        /// Why it does not parse.
        why: NumError,
    },
    #[error("polynomial: {0}")]
    /// The degrees and coefficients do not make a polynomial.
    Shape(#[from] super::BernsteinError),
}

/// Reads one number: a JSON number exactly (as the `f64` it denotes), or a `"p/q"`/decimal
/// string exactly.
pub fn parse_number(v: &Value) -> Result<Rational, NumError> {
    let refuse = |why: &str| NumError::Parse {
        text: v.to_string(),
        why: why.into(),
    };
    match v {
        Value::Number(n) => {
            let x = n.as_f64().ok_or_else(|| refuse("number out of range"))?;
            rational_from_f64(x, "number")
        }
        Value::String(s) => parse_rational(s),
        _ => Err(refuse("expected a number or a \"p/q\" string")),
    }
}

/// Parses a polynomial from a JSON value.
pub fn poly_from_json(v: &Value) -> Result<Bernstein<Rational>, InputError> {
    let field = |f: &str, why: &str| InputError::Field {
        field: f.into(),
        why: why.into(),
    };
    let degrees = v
        .get("degrees")
        .and_then(Value::as_array)
        .ok_or_else(|| field("degrees", "missing or not an array"))?;
    let degrees: Vec<usize> = degrees
        .iter()
        .map(|d| d.as_u64().filter(|&d| d <= 60).map(|d| d as usize))
        .collect::<Option<_>>()
        .ok_or_else(|| field("degrees", "each degree must be an integer 0…60"))?;
    if degrees.is_empty() || degrees.len() > 8 {
        return Err(field("degrees", "between 1 and 8 axes"));
    }
    let count = degrees
        .iter()
        .try_fold(1usize, |acc, d| acc.checked_mul(d + 1))
        .filter(|&c| c <= 1 << 20);
    let count = count.ok_or_else(|| field("degrees", "more than 2^20 coefficients"))?;
    let coeffs = v
        .get("coeffs")
        .and_then(Value::as_array)
        .ok_or_else(|| field("coeffs", "missing or not an array"))?;
    if coeffs.len() != count {
        return Err(field(
            "coeffs",
            &format!(
                "expected {count} coefficients for degrees {degrees:?}, found {}",
                coeffs.len()
            ),
        ));
    }
    let coeffs = coeffs
        .iter()
        .enumerate()
        .map(|(index, c)| parse_number(c).map_err(|why| InputError::Coefficient { index, why }))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Bernstein::new(degrees, coeffs)?)
}

/// Serialises a polynomial with exact `"p/q"` coefficients.
pub fn poly_to_json(p: &Bernstein<Rational>) -> Value {
    serde_json::json!({
        "degrees": p.degrees(),
        "coeffs": p.coeffs().iter().map(rational_to_string).collect::<Vec<_>>(),
    })
}

/// A positivity certificate as written to disk.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CertificateFile {
    /// The polynomial, in the input format.
    pub polynomial: Value,
    /// `"positive"` or `"not_positive"`.
    pub verdict: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    /// `positive`: the leaf boxes that tile the unit box.
    pub leaves: Option<Vec<DyadicBox>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    /// `not_positive`: the witness point, exact `"p/q"` strings.
    pub witness: Option<Vec<String>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    /// `not_positive`: the exact value there.
    pub value: Option<String>,
}

/// The verdict as a certificate file (`None` for undecided/uncertain verdicts, which prove nothing).
pub fn certificate_for(p: &Bernstein<Rational>, v: &PositivityVerdict) -> Option<CertificateFile> {
    let polynomial = poly_to_json(p);
    match v {
        PositivityVerdict::Positive { leaves, .. } => Some(CertificateFile {
            polynomial,
            verdict: "positive".into(),
            leaves: Some(leaves.clone()),
            witness: None,
            value: None,
        }),
        PositivityVerdict::NotPositive { witness, value } => {
            let value = match value {
                WitnessValue::Exact(r) => r.clone(),
                WitnessValue::AtMost(_) => p.eval(witness).ok()?,
            };
            Some(CertificateFile {
                polynomial,
                verdict: "not_positive".into(),
                leaves: None,
                witness: Some(witness.iter().map(rational_to_string).collect()),
                value: Some(rational_to_string(&value)),
            })
        }
        _ => None,
    }
}

/// Why a certificate file was refused.
#[derive(Debug, Error)]
pub enum VerifyError {
    #[error("{0}")]
    /// The certificate's polynomial or witness is malformed.
    Input(#[from] InputError),
    #[error("certificate refused: {0}")]
    /// The evidence does not prove the verdict.
    Refused(#[from] CertificateError),
    #[error("unknown verdict {0:?} (expected \"positive\" or \"not_positive\")")]
    /// The verdict is neither `positive` nor `not_positive`.
    Verdict(String),
}

/// What [`verify_certificate_file`] re-established; `Display` gives a one-line summary.
#[derive(Clone, Debug, PartialEq)]
pub enum PositivityCheck {
    /// `p > 0` on the unit box: the leaves tile it with every coefficient positive.
    Positive {
        /// Leaf boxes checked.
        leaves: usize,
    },
    /// `p(point) = value ≤ 0`, recomputed exactly.
    NotPositive {
        /// The witness point.
        point: Vec<Rational>,
        /// The exact value there.
        value: Rational,
    },
}

impl std::fmt::Display for PositivityCheck {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PositivityCheck::Positive { leaves } => write!(
                f,
                "positive on the whole box: {leaves} leaf boxes tile it, every coefficient \
                 positive on each"
            ),
            PositivityCheck::NotPositive { point, value } => write!(
                f,
                "not positive: p({}) = {} ≤ 0",
                crate::num::point_to_string(point),
                rational_to_string(value)
            ),
        }
    }
}

/// Re-checks a certificate file from scratch with the generic rational kernel.
pub fn verify_certificate_file(c: &CertificateFile) -> Result<PositivityCheck, VerifyError> {
    let p = poly_from_json(&c.polynomial)?;
    let missing = |f: &str| InputError::Field {
        field: f.into(),
        why: "missing".into(),
    };
    match c.verdict.as_str() {
        "positive" => {
            let leaves = c.leaves.as_ref().ok_or_else(|| missing("leaves"))?;
            let leaves = verify_positive_certificate(&p, leaves)?;
            Ok(PositivityCheck::Positive { leaves })
        }
        "not_positive" => {
            let w = c.witness.as_ref().ok_or_else(|| missing("witness"))?;
            let point = w
                .iter()
                .enumerate()
                .map(|(index, s)| {
                    parse_rational(s).map_err(|why| InputError::Coefficient { index, why })
                })
                .collect::<Result<Vec<_>, _>>()?;
            let claimed = match &c.value {
                Some(s) => Some(parse_rational(s).map_err(|e| InputError::Field {
                    field: "value".into(),
                    why: e.to_string(),
                })?),
                None => None,
            };
            let value = verify_witness(&p, &point, claimed.as_ref())?;
            Ok(PositivityCheck::NotPositive { point, value })
        }
        other => Err(VerifyError::Verdict(other.to_string())),
    }
}
