//! The system file: `{"box": [["a", "b"], …], "equations": [E, …]}`, each equation either in
//! tensor Bernstein form on the box (`{"degrees": [d0, …], "coeffs": [c, …]}`, axis 0
//! fastest), in power form in the domain's coordinates (`{"terms": [[[e0, …], c], …]}`), or
//! a rational function `{"rational": {"numerator": P, "denominator": Q}}` of two such
//! polynomials: its zero set is the numerator's once the denominator is certified to keep
//! one strict sign on the box (else the file is refused, naming the equation), or a tensor
//! B-spline field `{"bspline": {"orders": [k0, …], "knots": [[…], …], "coeffs": […]}}` in
//! domain coordinates (order = degree + 1, full knot vectors, clamped or not, `len(knots_i) −
//! k_i` coefficients per axis, axis 0 fastest; its domain must cover the box, and a knot
//! inside the box may have any multiplicity up to the degree).
//! Numbers are JSON numbers (exact as the `f64` they denote) or `"p/q"` / decimal strings
//! (exact).

use super::{Equation, PiecewiseSystem, RationalBox, RootCertificate, SolveError, System};
use crate::bernstein::{parse_number, poly_from_json, poly_to_json, Bernstein};
use crate::bspline::TensorSpline;
use crate::num::{rational_to_string, Rational};
use num_traits::{One, Zero};
use serde_json::{json, Value};

/// Parses a system file (see the module docs) whose equations are polynomials on the whole
/// box: a B-spline equation with a knot strictly inside the box is refused here (read such a
/// file with [`piecewise_system_from_json`]).
pub fn system_from_json(text: &str) -> Result<System, SolveError> {
    let p = piecewise_system_from_json(text)?;
    match p.polynomial() {
        Some(s) => Ok(s.clone()),
        None => {
            let equation = p
                .equations()
                .iter()
                .position(|e| matches!(e, Equation::Spline(_)))
                .unwrap_or(0);
            Err(SolveError::Equation {
                equation,
                why: "is a B-spline with knots inside the box, piecewise: read the file with \
                      `piecewise_system_from_json` and solve it with `solve_piecewise`"
                    .into(),
            })
        }
    }
}

/// Parses a system file (see the module docs), B-spline equations included.
pub fn piecewise_system_from_json(text: &str) -> Result<PiecewiseSystem, SolveError> {
    let v: Value = serde_json::from_str(text).map_err(|e| SolveError::Json(e.to_string()))?;
    let field = |f: &str, why: &str| SolveError::Field {
        field: f.into(),
        why: why.into(),
    };
    let domain = parse_box(v.get("box"), "box", None)?;
    let n = domain.len();
    let eqs = v
        .get("equations")
        .and_then(Value::as_array)
        .ok_or_else(|| field("equations", "missing or not an array"))?;
    let mut equations = Vec::with_capacity(eqs.len());
    for (i, e) in eqs.iter().enumerate() {
        let name = format!("equations[{i}]");
        let p = if let Some(r) = e.get("rational") {
            // The zero set of a rational function is its numerator's where the denominator
            // keeps one strict sign on the box: certified here, or the file is refused.
            let num = polynomial(
                r.get("numerator"),
                &domain,
                &format!("{name}.rational.numerator"),
            )?;
            let den = polynomial(
                r.get("denominator"),
                &domain,
                &format!("{name}.rational.denominator"),
            )?;
            same_dim(&den, n, i)?;
            keeps_sign(&den).map_err(|why| SolveError::Equation {
                equation: i,
                why: format!("the denominator {why}"),
            })?;
            num
        } else if let Some(b) = e.get("bspline") {
            equations.push(Equation::Spline(bspline(b, &format!("{name}.bspline"))?));
            continue;
        } else {
            polynomial(Some(e), &domain, &name)?
        };
        same_dim(&p, n, i)?;
        equations.push(Equation::Polynomial(p));
    }
    PiecewiseSystem::new(domain, equations)
}

/// A tensor B-spline field `{"orders": [k0, …], "knots": [[…], …], "coeffs": […]}`: order
/// `k = degree + 1` per axis, full knot vectors, `len(knots_i) − k_i` coefficients per axis,
/// axis 0 fastest.
fn bspline(v: &Value, name: &str) -> Result<TensorSpline<Rational>, SolveError> {
    let field = |f: &str, why: String| SolveError::Field {
        field: format!("{name}.{f}"),
        why,
    };
    let orders: Vec<usize> = v
        .get("orders")
        .and_then(Value::as_array)
        .and_then(|a| {
            a.iter()
                .map(|k| {
                    k.as_u64()
                        .filter(|&k| (1..=super::MAX_DEGREE as u64 + 1).contains(&k))
                        .map(|k| k as usize)
                })
                .collect::<Option<Vec<_>>>()
        })
        .ok_or_else(|| {
            field(
                "orders",
                format!("expected integers 1…{} per axis", super::MAX_DEGREE + 1),
            )
        })?;
    let knot_lists = v
        .get("knots")
        .and_then(Value::as_array)
        .filter(|k| k.len() == orders.len())
        .ok_or_else(|| field("knots", format!("expected {} knot vectors", orders.len())))?;
    let mut knots = Vec::with_capacity(orders.len());
    for (k, list) in knot_lists.iter().enumerate() {
        let list = list
            .as_array()
            .filter(|l| l.len() > orders[k])
            .ok_or_else(|| {
                field(
                    &format!("knots[{k}]"),
                    format!("expected more than the order {} knots", orders[k]),
                )
            })?;
        knots.push(
            list.iter()
                .enumerate()
                .map(|(j, x)| {
                    parse_number(x).map_err(|e| field(&format!("knots[{k}][{j}]"), e.to_string()))
                })
                .collect::<Result<Vec<_>, _>>()?,
        );
    }
    let coeffs = v
        .get("coeffs")
        .and_then(Value::as_array)
        .ok_or_else(|| field("coeffs", "missing or not an array".into()))?
        .iter()
        .enumerate()
        .map(|(j, x)| parse_number(x).map_err(|e| field(&format!("coeffs[{j}]"), e.to_string())))
        .collect::<Result<Vec<_>, _>>()?;
    let degrees = orders.iter().map(|k| k - 1).collect();
    TensorSpline::new(degrees, knots, coeffs).map_err(|e| SolveError::Field {
        field: name.into(),
        why: e.to_string(),
    })
}

fn same_dim(p: &Bernstein<Rational>, n: usize, equation: usize) -> Result<(), SolveError> {
    if p.dim() != n {
        return Err(SolveError::Equation {
            equation,
            why: format!("has {} variables, the box {n}", p.dim()),
        });
    }
    Ok(())
}

/// One polynomial in Bernstein form on the box or in power form (see the module docs).
fn polynomial(
    e: Option<&Value>,
    domain: &[(Rational, Rational)],
    name: &str,
) -> Result<Bernstein<Rational>, SolveError> {
    let field = |why: &str| SolveError::Field {
        field: name.into(),
        why: why.into(),
    };
    let e = e.ok_or_else(|| field("missing"))?;
    if e.get("terms").is_some() {
        power_equation(e, domain, name)
    } else if e.get("degrees").is_some() {
        poly_from_json(e).map_err(|why| field(&why.to_string()))
    } else if e.get("bspline").is_some() {
        Err(field(
            "a B-spline is an equation of its own, not part of a rational function",
        ))
    } else {
        Err(field(
            "expected {\"degrees\", \"coeffs\"}, {\"terms\"} or {\"rational\": {\"numerator\", \"denominator\"}}",
        ))
    }
}

/// Certifies that `d` has one strict sign on the unit box (the positivity prover on `d` or
/// `−d`, both with the default limits); otherwise says why not.
fn keeps_sign(d: &Bernstein<Rational>) -> Result<(), String> {
    use crate::bernstein::{prove_positive, PositivityOptions, PositivityVerdict};
    let opts = PositivityOptions::default();
    let positive = prove_positive(d, &opts).map_err(|e| e.to_string())?;
    if matches!(positive, PositivityVerdict::Positive { .. }) {
        return Ok(());
    }
    let minus = d.scale(&Rational::from_integer((-1).into()));
    match prove_positive(&minus, &opts).map_err(|e| e.to_string())? {
        PositivityVerdict::Positive { .. } => Ok(()),
        PositivityVerdict::NotPositive { witness, .. } => match positive {
            PositivityVerdict::NotPositive { witness: w2, .. } => Err(format!(
                "changes sign or vanishes on the box (≤ 0 at unit point {}, ≥ 0 at {})",
                crate::num::point_to_string(&w2),
                crate::num::point_to_string(&witness)
            )),
            _ => Err("could not be proved of one sign within the limits".into()),
        },
        _ => Err("could not be proved of one sign within the limits".into()),
    }
}

/// A box `[[a, b], …]` of exact numbers, at `field` in the file; with `unknowns`, it must
/// have that many intervals.
pub(crate) fn parse_box(
    v: Option<&Value>,
    field: &str,
    unknowns: Option<usize>,
) -> Result<RationalBox, SolveError> {
    let refuse = |f: String, why: String| SolveError::Field { field: f, why };
    let bx = v
        .and_then(Value::as_array)
        .filter(|b| unknowns.is_none_or(|n| b.len() == n))
        .ok_or_else(|| {
            refuse(
                field.into(),
                match unknowns {
                    Some(n) => format!("expected {n} [a, b] intervals"),
                    None => "missing or not an array of [a, b] intervals".into(),
                },
            )
        })?;
    let mut out = Vec::with_capacity(bx.len());
    for (k, iv) in bx.iter().enumerate() {
        let pair = iv
            .as_array()
            .filter(|p| p.len() == 2)
            .ok_or_else(|| refuse(format!("{field}[{k}]"), "expected [a, b]".into()))?;
        let num = |j: usize| {
            parse_number(&pair[j]).map_err(|e| refuse(format!("{field}[{k}][{j}]"), e.to_string()))
        };
        out.push((num(0)?, num(1)?));
    }
    Ok(out)
}

/// A power-form equation `Σ c_e x^e` in domain coordinates, in Bernstein form on the box.
fn power_equation(
    e: &Value,
    domain: &[(Rational, Rational)],
    name: &str,
) -> Result<Bernstein<Rational>, SolveError> {
    let n = domain.len();
    let field = |f: String, why: String| SolveError::Field { field: f, why };
    let terms = e
        .get("terms")
        .and_then(Value::as_array)
        .ok_or_else(|| field(format!("{name}.terms"), "not an array".into()))?;
    let mut parsed = Vec::with_capacity(terms.len());
    let mut degrees = vec![0usize; n];
    for (t, term) in terms.iter().enumerate() {
        let place = format!("{name}.terms[{t}]");
        let pair = term
            .as_array()
            .filter(|p| p.len() == 2)
            .ok_or_else(|| field(place.clone(), "expected [[e0, …], c]".into()))?;
        let exps: Vec<usize> = pair[0]
            .as_array()
            .filter(|a| a.len() == n)
            .and_then(|a| {
                a.iter()
                    .map(|x| x.as_u64().filter(|&x| x <= super::MAX_DEGREE as u64))
                    .map(|x| x.map(|x| x as usize))
                    .collect::<Option<Vec<_>>>()
            })
            .ok_or_else(|| {
                field(
                    place.clone(),
                    format!("exponents: {n} integers 0…{}", super::MAX_DEGREE),
                )
            })?;
        let c = parse_number(&pair[1]).map_err(|e| field(place.clone(), e.to_string()))?;
        for (d, &x) in degrees.iter_mut().zip(&exps) {
            *d = (*d).max(x);
        }
        parsed.push((exps, c));
    }
    // Dense power coefficients in x, axis 0 fastest.
    let strides: Vec<usize> = (0..n)
        .scan(1, |s, k| {
            let here = *s;
            *s *= degrees[k] + 1;
            Some(here)
        })
        .collect();
    let size: usize = degrees.iter().map(|d| d + 1).product();
    let mut coeffs = vec![Rational::zero(); size];
    for (exps, c) in parsed {
        let at: usize = exps.iter().zip(&strides).map(|(e, s)| e * s).sum();
        coeffs[at] += c;
    }
    // Substitute x_k = a_k + w_k t_k along each axis: the coefficient of t^m is
    // Σ_{e ≥ m} c_e C(e, m) a^(e−m) w^m.
    for k in 0..n {
        let (a, b) = &domain[k];
        let w = b - a;
        let d = degrees[k];
        let mut next = vec![Rational::zero(); size];
        for (idx, _) in coeffs.iter().enumerate() {
            if !(idx / strides[k]).is_multiple_of(d + 1) {
                continue;
            }
            for m in 0..=d {
                let mut acc = Rational::zero();
                for ex in m..=d {
                    let c = &coeffs[idx + ex * strides[k]];
                    if c.is_zero() {
                        continue;
                    }
                    acc += c * binomial(ex, m) * pow(a, ex - m) * pow(&w, m);
                }
                next[idx + m * strides[k]] = acc;
            }
        }
        coeffs = next;
    }
    Ok(Bernstein::from_power(degrees, coeffs)?)
}

fn binomial(n: usize, k: usize) -> Rational {
    let mut r = Rational::one();
    for i in 0..k {
        r = r * Rational::from_integer((n - i).into()) / Rational::from_integer((i + 1).into());
    }
    r
}

fn pow(x: &Rational, e: usize) -> Rational {
    (0..e).fold(Rational::one(), |acc, _| acc * x)
}

/// The system in the file format (Bernstein form, exact strings).
pub fn system_to_json(s: &System) -> Value {
    json!({
        "box": s.domain.iter()
            .map(|(a, b)| json!([rational_to_string(a), rational_to_string(b)]))
            .collect::<Vec<_>>(),
        "equations": s.equations.iter().map(poly_to_json).collect::<Vec<_>>(),
    })
}

/// A piecewise system in the file format (exact strings; B-spline equations as given).
pub fn piecewise_system_to_json(s: &PiecewiseSystem) -> Value {
    json!({
        "box": s.domain().iter()
            .map(|(a, b)| json!([rational_to_string(a), rational_to_string(b)]))
            .collect::<Vec<_>>(),
        "equations": s.equations().iter().map(|e| match e {
            Equation::Polynomial(p) => poly_to_json(p),
            Equation::Spline(t) => json!({"bspline": {
                "orders": t.degrees().iter().map(|d| d + 1).collect::<Vec<_>>(),
                "knots": t.knots().iter()
                    .map(|k| k.iter().map(rational_to_string).collect::<Vec<_>>())
                    .collect::<Vec<_>>(),
                "coeffs": t.coeffs().iter().map(rational_to_string).collect::<Vec<_>>(),
            }}),
        }).collect::<Vec<_>>(),
    })
}

/// Serialises a rational matrix as rows of exact strings.
pub(crate) fn serialize_matrix<S: serde::Serializer>(
    m: &[Vec<Rational>],
    ser: S,
) -> Result<S::Ok, S::Error> {
    use serde::Serialize;
    m.iter()
        .map(|row| row.iter().map(rational_to_string).collect::<Vec<_>>())
        .collect::<Vec<_>>()
        .serialize(ser)
}

/// Reads a certificate's preconditioner back.
pub(crate) fn certificate_from_json(v: &Value, n: usize) -> Result<RootCertificate, SolveError> {
    let field = |f: &str, why: &str| SolveError::Field {
        field: f.into(),
        why: why.into(),
    };
    let rows = v
        .get("preconditioner")
        .and_then(Value::as_array)
        .filter(|r| r.len() == n)
        .ok_or_else(|| field("preconditioner", "expected n rows"))?;
    let mut preconditioner = Vec::with_capacity(n);
    for (i, row) in rows.iter().enumerate() {
        let row = row
            .as_array()
            .filter(|r| r.len() == n)
            .ok_or_else(|| field(&format!("preconditioner[{i}]"), "expected n entries"))?;
        preconditioner.push(
            row.iter()
                .map(|x| parse_number(x).map_err(|e| field("preconditioner", &e.to_string())))
                .collect::<Result<Vec<_>, _>>()?,
        );
    }
    let lower_face_signs = v
        .get("lower_face_signs")
        .and_then(Value::as_array)
        .filter(|s| s.len() == n)
        .and_then(|s| {
            s.iter()
                .map(|x| x.as_i64().filter(|&x| x == 1 || x == -1).map(|x| x as i8))
                .collect::<Option<Vec<_>>>()
        })
        .ok_or_else(|| field("lower_face_signs", "expected n entries, each 1 or -1"))?;
    let point = match v.get("point") {
        None | Some(Value::Null) => None,
        Some(p) => Some(
            p.as_array()
                .filter(|p| p.len() == n)
                .ok_or_else(|| field("point", "expected n coordinates"))?
                .iter()
                .map(|x| parse_number(x).map_err(|e| field("point", &e.to_string())))
                .collect::<Result<Vec<_>, _>>()?,
        ),
    };
    Ok(RootCertificate {
        preconditioner,
        lower_face_signs,
        point,
    })
}
