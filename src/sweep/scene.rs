//! Scenes: rational patches (primitives made exact), motions and eyes, from JSON or built in.

use super::{Eye, Motion, Poly, Scene, Surface, SweepError, MAX_MOTION_DEGREE, MAX_PATCH_DEGREE};
use crate::bernstein::{parse_number, Bernstein};
use crate::bspline::TensorSpline;
use crate::num::{rational_to_f64, Rational};
use num_bigint::BigInt;
use num_traits::{One, Signed, Zero};
use serde_json::Value;

/// The built-in scenes, for `builtin:NAME`.
pub const BUILTIN_SCENES: &[&str] = &[
    "sphere-line",
    "sphere-cone",
    "ellipsoid-line",
    "ellipsoid-turn",
    "tuba",
    "ellipsoid-turn-eye",
    "sphere-line-eye",
    "sphere-cone-eye",
    "sphere-edge-roll",
    "sphere-corner",
];

/// A rational tensor Bézier patch on the unit square in homogeneous form: `hom[0..3]` are
/// `w·x, w·y, w·z` and `hom[3]` is the weight `w`, each of degrees `(du, dv)`, `u` axis 0.
/// Every weight is positive, so `w > 0` on the patch.
#[derive(Clone, Debug, PartialEq)]
pub struct Patch {
    /// `(w x, w y, w z, w)`.
    pub hom: [Bernstein<Rational>; 4],
}

impl Patch {
    /// A patch from Cartesian control points and weights `[x, y, z, w]`, `u` fastest.
    pub fn from_points(
        degrees: [usize; 2],
        points: &[[Rational; 4]],
        place: &str,
    ) -> Result<Patch, SweepError> {
        if degrees.iter().any(|&d| d > MAX_PATCH_DEGREE) {
            return Err(SweepError::field(
                format!("{place}.degrees"),
                format!("degree above the limit of {MAX_PATCH_DEGREE}"),
            ));
        }
        let need = (degrees[0] + 1) * (degrees[1] + 1);
        if points.len() != need {
            return Err(SweepError::field(
                format!("{place}.points"),
                format!("{} points, degrees {degrees:?} need {need}", points.len()),
            ));
        }
        let mut hom: [Vec<Rational>; 4] = Default::default();
        for (i, p) in points.iter().enumerate() {
            if !p[3].is_positive() {
                return Err(SweepError::field(
                    format!("{place}.points[{i}]"),
                    "weights must be positive",
                ));
            }
            for k in 0..3 {
                hom[k].push(&p[k] * &p[3]);
            }
            hom[3].push(p[3].clone());
        }
        let d = vec![degrees[0], degrees[1]];
        let [x, y, z, w] = hom;
        Ok(Patch {
            hom: [
                Bernstein::new(d.clone(), x)?,
                Bernstein::new(d.clone(), y)?,
                Bernstein::new(d.clone(), z)?,
                Bernstein::new(d, w)?,
            ],
        })
    }

    /// The degrees `(du, dv)`.
    pub fn degrees(&self) -> [usize; 2] {
        let d = self.hom[3].degrees();
        [d[0], d[1]]
    }

    /// `S(u, v)` in `f64` (de Casteljau on the coefficients rounded to `f64`); `None` outside
    /// the unit square or for a non-finite parameter.
    pub fn point(&self, u: f64, v: f64) -> Option<[f64; 3]> {
        if !((0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v)) {
            return None;
        }
        let at = [u, v];
        let eval = |p: &Bernstein<Rational>| p.map(rational_to_f64).eval(&at).ok();
        let w = eval(&self.hom[3])?;
        Some([
            eval(&self.hom[0])? / w,
            eval(&self.hom[1])? / w,
            eval(&self.hom[2])? / w,
        ])
    }

    /// The patch under `x ↦ L x + c` (applied to the homogeneous coordinates).
    fn mapped(&self, l: &[[Rational; 3]; 3], c: &[Rational; 3]) -> Patch {
        let w = &self.hom[3];
        let row = |i: usize| -> Bernstein<Rational> {
            let mut acc = w.scale(&c[i]);
            for (j, m) in l[i].iter().enumerate() {
                acc = acc.add(&self.hom[j].scale(m)).expect("same degrees");
            }
            acc
        };
        Patch {
            hom: [row(0), row(1), row(2), w.clone()],
        }
    }
}

fn r(n: i64) -> Rational {
    Rational::from_integer(BigInt::from(n))
}

/// A quarter of the unit circle from `a` to `b` (`b ⊥ a`, both unit) as a rational quadratic
/// in homogeneous form `(p w, q w, w)`: control points `a, a + b, b` with weights `1, 1, 2`
/// (the stereographic parametrisation; `w₁² / (w₀ w₂) = ½` as for the usual `1, √2/2, 1`).
fn quarter_arc(a: &[Rational; 2], b: &[Rational; 2]) -> [[Rational; 3]; 3] {
    [
        [a[0].clone(), a[1].clone(), r(1)],
        [&a[0] + &b[0], &a[1] + &b[1], r(1)],
        [&b[0] * r(2), &b[1] * r(2), r(2)],
    ]
}

/// The four quarter arcs of the unit circle, counter-clockwise (`clockwise = false`) from the
/// rational unit vector `start`.
fn circle_arcs(start: &[Rational; 2], clockwise: bool) -> Vec<[[Rational; 3]; 3]> {
    let turn = |a: &[Rational; 2]| -> [Rational; 2] {
        if clockwise {
            [a[1].clone(), -a[0].clone()]
        } else {
            [-a[1].clone(), a[0].clone()]
        }
    };
    let mut a = start.clone();
    let mut out = Vec::with_capacity(4);
    for _ in 0..4 {
        let b = turn(&a);
        out.push(quarter_arc(&a, &b));
        a = b;
    }
    out
}

/// Where the built-in primitives' circles start: the rational unit vector (5/13, 12/13), so
/// that patch edges do not lie on the coordinate planes, where axis-aligned motions and eyes
/// would put silhouette curves along them (a curve inside a patch edge is not traced).
fn generic_start() -> [Rational; 2] {
    [
        Rational::new(5.into(), 13.into()),
        Rational::new(12.into(), 13.into()),
    ]
}

/// The rotation by the quaternion (5, 1, 2, 3), `R̂(q)/|q|²` with `|q|² = 39`: applied to the
/// built-in sphere's patches, it puts their poles and edges in general position for the same
/// reason.
fn generic_rotation() -> [[Rational; 3]; 3] {
    let (w, x, y, z) = (5i64, 1i64, 2i64, 3i64);
    let m = [
        [
            w * w + x * x - y * y - z * z,
            2 * (x * y - w * z),
            2 * (x * z + w * y),
        ],
        [
            2 * (x * y + w * z),
            w * w - x * x + y * y - z * z,
            2 * (y * z - w * x),
        ],
        [
            2 * (x * z - w * y),
            2 * (y * z + w * x),
            w * w - x * x - y * y + z * z,
        ],
    ];
    let n = w * w + x * x + y * y + z * z;
    m.map(|row| row.map(|e| Rational::new(e.into(), n.into())))
}

/// The tensor product of a meridian `(ρ w, z w, w)` (axis `u`) and a circle arc
/// `(x w, y w, w)` (axis `v`): the surface of revolution about `z`, biquadratic.
fn revolve(meridian: &[[Rational; 3]; 3], arc: &[[Rational; 3]; 3]) -> Patch {
    let mut hom: [Vec<Rational>; 4] = Default::default();
    for c in arc {
        for m in meridian {
            hom[0].push(&m[0] * &c[0]);
            hom[1].push(&m[0] * &c[1]);
            hom[2].push(&m[1] * &c[2]);
            hom[3].push(&m[2] * &c[2]);
        }
    }
    let [x, y, z, w] = hom;
    let b = |c| Bernstein::new(vec![2, 2], c).expect("3×3 coefficients");
    Patch {
        hom: [b(x), b(y), b(z), b(w)],
    }
}

/// The unit sphere as 8 rational biquadratic patches (two meridian quarter arcs from a pole,
/// four arcs around the polar axis), turned by [`generic_rotation`]; each patch's edge `u = 0`
/// or `u = 1` is collapsed to a pole. Normals point outward.
fn unit_sphere() -> Vec<Patch> {
    let meridians = [
        quarter_arc(&[r(0), r(1)], &[r(1), r(0)]),
        quarter_arc(&[r(1), r(0)], &[r(0), r(-1)]),
    ];
    let turn = generic_rotation();
    let origin = [r(0), r(0), r(0)];
    let mut out = Vec::new();
    for m in &meridians {
        for c in circle_arcs(&generic_start(), false) {
            out.push(revolve(m, &c).mapped(&turn, &origin));
        }
    }
    out
}

/// The torus about `z` through the origin, major radius `major`, minor `minor`, as 16
/// rational biquadratic patches (the meridian circle clockwise in `(ρ, z)` so that normals
/// point outward; both circles start at [`generic_start`]).
fn z_torus(major: &Rational, minor: &Rational) -> Vec<Patch> {
    let mut out = Vec::new();
    for unit in circle_arcs(&generic_start(), true) {
        let meridian = unit.map(|[p, q, w]| [&w * major + &p * minor, &q * minor, w]);
        for c in circle_arcs(&generic_start(), false) {
            out.push(revolve(&meridian, &c));
        }
    }
    out
}

fn exact_sqrt(x: &Rational) -> Option<Rational> {
    if x.is_negative() {
        return None;
    }
    let (n, d) = (x.numer(), x.denom());
    let (sn, sd) = (n.sqrt(), d.sqrt());
    (&sn * &sn == *n && &sd * &sd == *d).then(|| Rational::new(sn, sd))
}

/// A rational rotation taking `z` to the unit vector `n` (rational): a Householder reflection
/// `I − 2vvᵀ/(vᵀv)`, `v = n − z`, with its first two columns swapped to keep the orientation.
fn frame_to(n: &[Rational; 3]) -> [[Rational; 3]; 3] {
    let z = [r(0), r(0), r(1)];
    let v: Vec<Rational> = (0..3).map(|k| &n[k] - &z[k]).collect();
    let vv: Rational = v.iter().map(|x| x * x).sum();
    let mut h: [[Rational; 3]; 3] = Default::default();
    if vv.is_zero() {
        for (i, row) in h.iter_mut().enumerate() {
            row[i] = r(1);
        }
        return h;
    }
    if n[2] == r(-1) {
        // Rotation by π about x: (x, −y, −z).
        return [[r(1), r(0), r(0)], [r(0), r(-1), r(0)], [r(0), r(0), r(-1)]];
    }
    for i in 0..3 {
        for j in 0..3 {
            let id = if i == j { r(1) } else { r(0) };
            h[i][j] = id - r(2) * &v[i] * &v[j] / &vv;
        }
    }
    // Columns (H e₁, H e₂, H e₃ = n) are left-handed; swap the first two.
    for row in h.iter_mut() {
        row.swap(0, 1);
    }
    h
}

fn scaled(c: &[Rational; 3], radii: &[Rational; 3], patches: Vec<Patch>) -> Vec<Patch> {
    let l: [[Rational; 3]; 3] =
        [0, 1, 2].map(|i| [0, 1, 2].map(|j| if i == j { radii[i].clone() } else { r(0) }));
    patches.iter().map(|p| p.mapped(&l, c)).collect()
}

/// A sphere as 8 rational biquadratic patches.
pub(crate) fn sphere(center: &[Rational; 3], radius: &Rational) -> Vec<Patch> {
    scaled(
        center,
        &[radius.clone(), radius.clone(), radius.clone()],
        unit_sphere(),
    )
}

/// An axis-aligned ellipsoid as 8 rational biquadratic patches.
pub(crate) fn ellipsoid(center: &[Rational; 3], radii: &[Rational; 3]) -> Vec<Patch> {
    scaled(center, radii, unit_sphere())
}

/// A torus as 16 rational biquadratic patches; the axis must have a rational length.
pub(crate) fn torus(
    center: &[Rational; 3],
    axis: &[Rational; 3],
    major: &Rational,
    minor: &Rational,
    place: &str,
) -> Result<Vec<Patch>, SweepError> {
    let len2: Rational = axis.iter().map(|x| x * x).sum();
    let len = exact_sqrt(&len2).filter(|l| !l.is_zero()).ok_or_else(|| {
        SweepError::field(
            format!("{place}.axis"),
            "the axis must be non-zero with a rational length (e.g. [0,0,1], [3,4,0], [1,2,2]) so that the torus is exact",
        )
    })?;
    if !(minor.is_positive() && major > minor) {
        return Err(SweepError::field(
            place,
            "needs 0 < minor < major (a ring torus)",
        ));
    }
    let n = axis.clone().map(|x| x / &len);
    let frame = frame_to(&n);
    Ok(z_torus(major, minor)
        .iter()
        .map(|p| p.mapped(&frame, center))
        .collect())
}

fn num(v: &Value, place: &str) -> Result<Rational, SweepError> {
    parse_number(v).map_err(|e| SweepError::field(place, e.to_string()))
}

fn array<'a>(v: &'a Value, place: &str) -> Result<&'a Vec<Value>, SweepError> {
    v.as_array()
        .ok_or_else(|| SweepError::field(place, "expected an array"))
}

/// Three things of one kind, `each` reading one (named `place[i]`).
fn three<T>(
    v: &Value,
    place: &str,
    what: &str,
    each: impl Fn(&Value, &str) -> Result<T, SweepError>,
) -> Result<[T; 3], SweepError> {
    let a = array(v, place)?;
    if a.len() != 3 {
        return Err(SweepError::field(place, format!("expected 3 {what}")));
    }
    Ok([
        each(&a[0], &format!("{place}[0]"))?,
        each(&a[1], &format!("{place}[1]"))?,
        each(&a[2], &format!("{place}[2]"))?,
    ])
}

fn triple(v: &Value, place: &str) -> Result<[Rational; 3], SweepError> {
    three(v, place, "numbers", num)
}

fn poly(v: &Value, place: &str) -> Result<Poly, SweepError> {
    let a = array(v, place)?;
    if a.is_empty() || a.len() > MAX_MOTION_DEGREE + 1 {
        return Err(SweepError::field(
            place,
            format!(
                "expected 1 to {} power-basis coefficients",
                MAX_MOTION_DEGREE + 1
            ),
        ));
    }
    a.iter()
        .enumerate()
        .map(|(i, c)| num(c, &format!("{place}[{i}]")))
        .collect()
}

fn poly3(v: &Value, place: &str) -> Result<[Poly; 3], SweepError> {
    three(v, place, "polynomials", poly)
}

fn get<'a>(v: &'a Value, key: &str, place: &str) -> Result<&'a Value, SweepError> {
    v.get(key)
        .ok_or_else(|| SweepError::field(format!("{place}.{key}"), "missing"))
}

fn positive(x: Rational, place: &str) -> Result<Rational, SweepError> {
    if x.is_positive() {
        Ok(x)
    } else {
        Err(SweepError::field(place, "must be positive"))
    }
}

fn surface(v: &Value, place: &str) -> Result<Surface, SweepError> {
    let obj = v
        .as_object()
        .filter(|o| o.len() == 1)
        .ok_or_else(|| {
            SweepError::field(
                place,
                "expected one of {\"sphere\"}, {\"ellipsoid\"}, {\"torus\"}, {\"bezier\"}, {\"bspline\"}",
            )
        })?;
    let (name, body) = obj.iter().next().expect("one entry");
    let here = format!("{place}.{name}");
    let patches = match name.as_str() {
        "sphere" => sphere(
            &triple(get(body, "center", &here)?, &format!("{here}.center"))?,
            &positive(
                num(get(body, "radius", &here)?, &format!("{here}.radius"))?,
                &format!("{here}.radius"),
            )?,
        ),
        "ellipsoid" => {
            let radii = triple(get(body, "radii", &here)?, &format!("{here}.radii"))?;
            if radii.iter().any(|x| !x.is_positive()) {
                return Err(SweepError::field(
                    format!("{here}.radii"),
                    "must be positive",
                ));
            }
            ellipsoid(
                &triple(get(body, "center", &here)?, &format!("{here}.center"))?,
                &radii,
            )
        }
        "torus" => torus(
            &triple(get(body, "center", &here)?, &format!("{here}.center"))?,
            &triple(get(body, "axis", &here)?, &format!("{here}.axis"))?,
            &num(get(body, "major", &here)?, &format!("{here}.major"))?,
            &num(get(body, "minor", &here)?, &format!("{here}.minor"))?,
            &here,
        )?,
        "bezier" => {
            let d = array(get(body, "degrees", &here)?, &format!("{here}.degrees"))?;
            let degrees = degrees2(d, &format!("{here}.degrees"))?;
            let points = points(get(body, "points", &here)?, &format!("{here}.points"))?;
            vec![Patch::from_points(degrees, &points, &here)?]
        }
        "bspline" => bspline_patches(body, &here)?,
        _ => {
            return Err(SweepError::field(
                place,
                format!("unknown surface `{name}` (sphere, ellipsoid, torus, bezier, bspline)"),
            ))
        }
    };
    Ok(Surface {
        name: name.clone(),
        patches,
    })
}

fn degrees2(d: &[Value], place: &str) -> Result<[usize; 2], SweepError> {
    let one = |v: &Value| v.as_u64().map(|x| x as usize);
    match (d.len(), d.first().and_then(one), d.get(1).and_then(one)) {
        (2, Some(a), Some(b)) => Ok([a, b]),
        _ => Err(SweepError::field(
            place,
            "expected two non-negative integers",
        )),
    }
}

fn points(v: &Value, place: &str) -> Result<Vec<[Rational; 4]>, SweepError> {
    array(v, place)?
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let here = format!("{place}[{i}]");
            let a = array(p, &here)?;
            if a.len() != 3 && a.len() != 4 {
                return Err(SweepError::field(
                    &here,
                    "expected [x, y, z] or [x, y, z, w]",
                ));
            }
            let w = match a.get(3) {
                Some(w) => num(w, &format!("{here}[3]"))?,
                None => Rational::one(),
            };
            Ok([
                num(&a[0], &format!("{here}[0]"))?,
                num(&a[1], &format!("{here}[1]"))?,
                num(&a[2], &format!("{here}[2]"))?,
                w,
            ])
        })
        .collect()
}

/// A rational tensor B-spline patch, split into its Bézier pieces (each reparametrised to the
/// unit square) in homogeneous coordinates.
fn bspline_patches(body: &Value, here: &str) -> Result<Vec<Patch>, SweepError> {
    let orders = degrees2(
        array(get(body, "orders", here)?, &format!("{here}.orders"))?,
        &format!("{here}.orders"),
    )?;
    if orders.iter().any(|&k| k == 0 || k > MAX_PATCH_DEGREE + 1) {
        return Err(SweepError::field(
            format!("{here}.orders"),
            format!("orders from 1 to {}", MAX_PATCH_DEGREE + 1),
        ));
    }
    let knots_v = array(get(body, "knots", here)?, &format!("{here}.knots"))?;
    if knots_v.len() != 2 {
        return Err(SweepError::field(
            format!("{here}.knots"),
            "expected two knot vectors",
        ));
    }
    let mut knots = Vec::new();
    for (a, k) in knots_v.iter().enumerate() {
        let place = format!("{here}.knots[{a}]");
        knots.push(
            array(k, &place)?
                .iter()
                .enumerate()
                .map(|(i, x)| num(x, &format!("{place}[{i}]")))
                .collect::<Result<Vec<_>, _>>()?,
        );
    }
    let pts = points(get(body, "points", here)?, &format!("{here}.points"))?;
    if let Some(i) = pts.iter().position(|p| !p[3].is_positive()) {
        return Err(SweepError::field(
            format!("{here}.points[{i}]"),
            "weights must be positive",
        ));
    }
    let degrees = vec![orders[0] - 1, orders[1] - 1];
    let mut coords = Vec::new();
    for k in 0..4 {
        let c: Vec<Rational> = pts
            .iter()
            .map(|p| if k == 3 { p[3].clone() } else { &p[k] * &p[3] })
            .collect();
        coords.push(
            TensorSpline::new(degrees.clone(), knots.clone(), c)
                .map_err(|e| SweepError::field(here, e.to_string()))?,
        );
    }
    let cells: Vec<_> = coords.iter().map(TensorSpline::bezier_cells).collect();
    Ok((0..cells[0].len())
        .map(|i| Patch {
            hom: [0, 1, 2, 3].map(|k| cells[k][i].poly.clone()),
        })
        .collect())
}

fn identity() -> [[Poly; 3]; 3] {
    let mut l: [[Poly; 3]; 3] = Default::default();
    for (i, row) in l.iter_mut().enumerate() {
        for (j, e) in row.iter_mut().enumerate() {
            *e = vec![r(i64::from(i == j))];
        }
    }
    l
}

pub(crate) fn pmul(a: &Poly, b: &Poly) -> Poly {
    let mut out = vec![Rational::zero(); a.len() + b.len() - 1];
    for (i, x) in a.iter().enumerate() {
        for (j, y) in b.iter().enumerate() {
            out[i + j] += x * y;
        }
    }
    out
}

pub(crate) fn padd(a: &Poly, b: &Poly) -> Poly {
    let mut out = vec![Rational::zero(); a.len().max(b.len())];
    for (i, x) in a.iter().enumerate() {
        out[i] += x;
    }
    for (i, x) in b.iter().enumerate() {
        out[i] += x;
    }
    out
}

fn pscale(a: &Poly, k: i64) -> Poly {
    a.iter().map(|x| x * r(k)).collect()
}

/// The unnormalised rotation matrix of a quaternion `q = (w, x, y, z)`: `|q|² R(q)`.
fn quaternion_matrix(q: &[Poly; 4]) -> [[Poly; 3]; 3] {
    let [w, x, y, z] = q;
    let m = pmul;
    let sq = |a: &Poly| m(a, a);
    let lin = |terms: &[(i64, Poly)]| {
        terms.iter().fold(vec![Rational::zero()], |acc, (k, p)| {
            padd(&acc, &pscale(p, *k))
        })
    };
    [
        [
            lin(&[(1, sq(w)), (1, sq(x)), (-1, sq(y)), (-1, sq(z))]),
            lin(&[(2, m(x, y)), (-2, m(w, z))]),
            lin(&[(2, m(x, z)), (2, m(w, y))]),
        ],
        [
            lin(&[(2, m(x, y)), (2, m(w, z))]),
            lin(&[(1, sq(w)), (-1, sq(x)), (1, sq(y)), (-1, sq(z))]),
            lin(&[(2, m(y, z)), (-2, m(w, x))]),
        ],
        [
            lin(&[(2, m(x, z)), (-2, m(w, y))]),
            lin(&[(2, m(y, z)), (2, m(w, x))]),
            lin(&[(1, sq(w)), (-1, sq(x)), (-1, sq(y)), (1, sq(z))]),
        ],
    ]
}

fn motion(v: Option<&Value>) -> Result<Motion, SweepError> {
    let mut linear = identity();
    let mut translation: [Poly; 3] = [vec![r(0)], vec![r(0)], vec![r(0)]];
    let mut denominator = vec![r(1)];
    let Some(v) = v else {
        return Ok(Motion {
            linear,
            translation,
            denominator,
        });
    };
    if let Some(t) = v.get("translation") {
        translation = poly3(t, "motion.translation")?;
    }
    if let Some(l) = v.get("linear") {
        let rows = array(l, "motion.linear")?;
        if rows.len() != 3 {
            return Err(SweepError::field("motion.linear", "expected 3 rows"));
        }
        for (i, row) in rows.iter().enumerate() {
            linear[i] = poly3(row, &format!("motion.linear[{i}]"))?;
        }
    }
    if let Some(rot) = v.get("rotation") {
        let q = array(
            get(rot, "quaternion", "motion.rotation")?,
            "motion.rotation.quaternion",
        )?;
        if q.len() != 4 {
            return Err(SweepError::field(
                "motion.rotation.quaternion",
                "expected 4 polynomials (w, x, y, z)",
            ));
        }
        let q: Vec<Poly> = q
            .iter()
            .enumerate()
            .map(|(i, p)| poly(p, &format!("motion.rotation.quaternion[{i}]")))
            .collect::<Result<_, _>>()?;
        let q = [q[0].clone(), q[1].clone(), q[2].clone(), q[3].clone()];
        let rot = quaternion_matrix(&q);
        // A(t) p = L R̂ p / |q|² + T: M̂ = L R̂, T̂ = |q|² T, δ = |q|².
        let norm = q.iter().fold(vec![r(0)], |acc, p| padd(&acc, &pmul(p, p)));
        let mut m: [[Poly; 3]; 3] = Default::default();
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] = (0..3).fold(vec![r(0)], |acc, k| {
                    padd(&acc, &pmul(&linear[i][k], &rot[k][j]))
                });
            }
        }
        linear = m;
        translation = translation.map(|p| pmul(&p, &norm));
        denominator = norm;
    }
    Ok(Motion {
        linear,
        translation,
        denominator,
    })
}

/// Reads a scene (see the module docs of [`crate::sweep`] and the CLI's `sweep` help for the
/// format). Every number is exact: JSON numbers as the `f64` they denote, `"p/q"` and
/// decimal strings as written.
pub fn scene_from_json(text: &str) -> Result<Scene, SweepError> {
    let v: Value = serde_json::from_str(text).map_err(|e| SweepError::Json {
        line: e.line(),
        column: e.column(),
        why: e.to_string(),
    })?;
    let surfaces = array(get(&v, "surfaces", "scene")?, "surfaces")?
        .iter()
        .enumerate()
        .map(|(i, s)| surface(s, &format!("surfaces[{i}]")))
        .collect::<Result<Vec<_>, _>>()?;
    if surfaces.is_empty() {
        return Err(SweepError::field("surfaces", "no surface"));
    }
    let t = array(get(&v, "t", "scene")?, "t")?;
    if t.len() != 2 {
        return Err(SweepError::field("t", "expected [a, b]"));
    }
    let (a, b) = (num(&t[0], "t[0]")?, num(&t[1], "t[1]")?);
    if a >= b {
        return Err(SweepError::field("t", "needs a < b"));
    }
    let motion = motion(v.get("motion"))?;
    let eye_v = get(&v, "eye", "scene")?;
    let eye = if eye_v.is_array() {
        Eye::Point(triple(eye_v, "eye")?)
    } else {
        let path = poly3(get(eye_v, "path", "eye")?, "eye.path")?;
        let rr = array(get(eye_v, "r", "eye")?, "eye.r")?;
        if rr.len() != 2 {
            return Err(SweepError::field("eye.r", "expected [r0, r1]"));
        }
        let (r0, r1) = (num(&rr[0], "eye.r[0]")?, num(&rr[1], "eye.r[1]")?);
        if r0 >= r1 {
            return Err(SweepError::field("eye.r", "needs r0 < r1"));
        }
        Eye::Path { path, r: (r0, r1) }
    };
    Ok(Scene {
        surfaces,
        t: (a, b),
        motion,
        eye,
    })
}

/// The built-in scene `name` (one of [`BUILTIN_SCENES`]), as JSON text.
pub fn builtin_scene_json(name: &str) -> Option<&'static str> {
    Some(match name {
        // A unit sphere on a straight line: the envelope is a cylinder, whose contour from a
        // point is two straight lines.
        "sphere-line" => {
            r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": 1}}],
                "t": [0, 2],
                "motion": {"translation": [[0, 2], [0, "1/2"], [0]]},
                "eye": [2, -8, 3]}"#
        }
        // A sphere translated and uniformly scaled: the envelope is a cone.
        "sphere-cone" => {
            r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": 1}}],
                "t": [0, 2],
                "motion": {"translation": [[0, 3], [0], [0]],
                           "linear": [[[1, "1/2"], [0], [0]], [[0], [1, "1/2"], [0]], [[0], [0], [1, "1/2"]]]},
                "eye": [3, -10, 4]}"#
        }
        // Fig. 4: a scaled ellipsoid on a linear trajectory (a non-uniform scale change, so
        // eq. 2 as printed is off the contour).
        "ellipsoid-line" => {
            r#"{"surfaces": [{"ellipsoid": {"center": [0, 0, 0], "radii": [1, "1/2", "1/2"]}}],
                "t": [0, 1],
                "motion": {"translation": [[0, 4], [0, 1], [0]],
                           "linear": [[[1, 1], [0], [0]], [[0], [1], [0]], [[0], [0], [1, "1/2"]]]},
                "eye": [3, -8, 5]}"#
        }
        // An ellipsoid turning about z (a rational rotation, quaternion (1, 0, 0, t/2)) while
        // it moves.
        "ellipsoid-turn" => {
            r#"{"surfaces": [{"ellipsoid": {"center": [0, 0, 0], "radii": [2, "1/2", "1/2"]}}],
                "t": [0, 1],
                "motion": {"translation": [[0, 3], [0], [0, "1/2"]],
                           "rotation": {"quaternion": [[1], [0], [0], [0, "1/2"]]}},
                "eye": [1, -9, 4]}"#
        }
        // Fig. 5b: a tuba, a sphere and a torus swept along a curved path while growing.
        "tuba" => {
            r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": "1/2"}},
                             {"torus": {"center": [0, 0, 0], "axis": [1, 0, 0], "major": 1, "minor": "1/4"}}],
                "t": [0, 1],
                "motion": {"translation": [[0, 4], [0, 0, 1], [0]],
                           "linear": [[[1, 1], [0], [0]], [[0], [1, 1], [0]], [[0], [0], [1, 1]]]},
                "eye": [2, -9, 4]}"#
        }
        // Section 4: `ellipsoid-turn` seen from an eye moving along a parabola; one interior
        // event (near r = 1.6525) where the silhouette's topology changes.
        "ellipsoid-turn-eye" => {
            r#"{"surfaces": [{"ellipsoid": {"center": [0, 0, 0], "radii": [2, "1/2", "1/2"]}}],
                "t": [0, 1],
                "motion": {"translation": [[0, 3], [0], [0, "1/2"]],
                           "rotation": {"quaternion": [[1], [0], [0], [0, "1/2"]]}},
                "eye": {"path": [[-3, 3], [-2], [0, "1/3"]], "r": [0, 3]}}"#
        }
        // A closed-form event (a sweep invariant in t, module `events`): a unit sphere
        // translated along x, seen from an eye moving along y past the capsule's end. The
        // envelope's two contour lines from P(r) = (5, r, 3/5) exist while the eye is outside
        // the infinite cylinder y² + z² = 1 and merge where it enters, at r = −4/5; the eye
        // stays at least 2 from the capsule.
        "sphere-line-eye" => {
            r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": 1}}],
                "t": [0, 1],
                "motion": {"translation": [[0, 2], [0], [0]]},
                "eye": {"path": [[5], [0, 1], ["3/5"]], "r": [-2, 0]}}"#
        }
        // A closed-form event through a scale (module `events`): a unit sphere translated
        // along x while scaled by 1 + t/2 sweeps a cone (apex at x = −6, sin α = 1/6); from
        // P(r) = (12, r, 1/3) its contour lines appear where the eye leaves the infinite
        // cone, r² + 1/9 = 324/35, r = √(2881/315).
        "sphere-cone-eye" => {
            r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": 1}}],
                "t": [0, 2],
                "motion": {"translation": [[0, 3], [0], [0]],
                           "linear": [[[1, "1/2"], [0], [0]], [[0], [1, "1/2"], [0]], [[0], [0], [1, "1/2"]]]},
                "eye": {"path": [[12], [0, 1], ["1/3"]], "r": [0, 6]}}"#
        }
        // The silhouette along patch edges: the sphere's meridian edges lie in the plane
        // through the centre normal to n = (−286, −313, 278)/507 (the generic rotation of
        // (−12, 5, 0)/13); it rolls about n while moving along n, so that great circle is the
        // characteristic curve at every time, and the contour points run along it across
        // patch corners (module `edges`).
        "sphere-edge-roll" => {
            r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": 1}}],
                "t": [0, 1],
                "motion": {"translation": [[0, "-22/13"], [0, "-313/169"], [0, "278/169"]],
                           "rotation": {"quaternion": [[1], [0, "-286/507"], [0, "-313/507"], [0, "278/507"]]}},
                "eye": [5, "3/10", "11/10"]}"#
        }
        // A unit sphere rolling about z while it moves, seen from an eye placed (exactly) so
        // that at t = 1/2 the silhouette passes through the patch corner
        // R·(5/13, 12/13, 0) = (−247, 398, 194)/507, where four patches meet (module
        // `corners`).
        "sphere-corner" => {
            r#"{"surfaces": [{"sphere": {"center": [0, 0, 0], "radius": 1}}],
                "t": [0, 1],
                "motion": {"translation": [[0, "1356725/1456611"], [0, "3880141/1456611"], [0, "-219413/171366"]],
                           "rotation": {"quaternion": [[1], [0], [0], [0, "1/2"]]}},
                "eye": ["-5096479/971074", "125027/971074", "-16518687/1942148"]}"#
        }
        _ => return None,
    })
}

/// The built-in scene `name` (one of [`BUILTIN_SCENES`]).
pub fn builtin_scene(name: &str) -> Result<Scene, SweepError> {
    let text = builtin_scene_json(name).ok_or_else(|| SweepError::UnknownBuiltin(name.into()))?;
    scene_from_json(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn normal_f64(p: &Patch, u: f64, v: f64) -> [f64; 3] {
        let h = 1e-6;
        let a = p.point(u + h, v).unwrap();
        let b = p.point(u - h, v).unwrap();
        let c = p.point(u, v + h).unwrap();
        let d = p.point(u, v - h).unwrap();
        let su: Vec<f64> = (0..3).map(|k| a[k] - b[k]).collect();
        let sv: Vec<f64> = (0..3).map(|k| c[k] - d[k]).collect();
        [
            su[1] * sv[2] - su[2] * sv[1],
            su[2] * sv[0] - su[0] * sv[2],
            su[0] * sv[1] - su[1] * sv[0],
        ]
    }

    #[test]
    fn primitives_lie_on_their_surfaces_with_outward_normals() {
        let c = [r(1), r(-2), Rational::new(1.into(), 3.into())];
        let radius = r(2);
        let radii = [r(3), r(1), r(2)];
        let mut checked = 0;
        for (kind, patches) in [
            ("sphere", sphere(&c, &radius)),
            ("ellipsoid", ellipsoid(&c, &radii)),
        ] {
            assert_eq!(patches.len(), 8);
            for p in &patches {
                for &(u, v) in &[(0.3, 0.2), (0.5, 0.5), (0.9, 0.7)] {
                    let x = p.point(u, v).unwrap();
                    let q: Vec<f64> = (0..3)
                        .map(|k| (x[k] - rational_to_f64(&c[k])) / rational_to_f64(&radii[k]))
                        .collect();
                    let level = if kind == "sphere" {
                        (0..3)
                            .map(|k| (x[k] - rational_to_f64(&c[k])).powi(2))
                            .sum::<f64>()
                            - 4.0
                    } else {
                        q.iter().map(|a| a * a).sum::<f64>() - 1.0
                    };
                    assert!(level.abs() < 1e-12, "{kind} off its surface: {level}");
                    let n = normal_f64(p, u, v);
                    let out: f64 = (0..3).map(|k| n[k] * (x[k] - rational_to_f64(&c[k]))).sum();
                    assert!(out > 0.0, "{kind} normal points inward");
                    checked += 1;
                }
            }
        }
        let axis = [r(1), r(2), r(2)];
        let t = torus(&c, &axis, &r(3), &r(1), "t").unwrap();
        assert_eq!(t.len(), 16);
        let n3: Vec<f64> = axis.iter().map(|a| rational_to_f64(a) / 3.0).collect();
        for p in &t {
            let x = p.point(0.4, 0.6).unwrap();
            let d: Vec<f64> = (0..3).map(|k| x[k] - rational_to_f64(&c[k])).collect();
            let h: f64 = (0..3).map(|k| d[k] * n3[k]).sum();
            let radial: Vec<f64> = (0..3).map(|k| d[k] - h * n3[k]).collect();
            let rho = radial.iter().map(|a| a * a).sum::<f64>().sqrt();
            assert!(((rho - 3.0).powi(2) + h * h - 1.0).abs() < 1e-12);
            let core: Vec<f64> = (0..3).map(|k| d[k] - radial[k] * 3.0 / rho).collect();
            let n = normal_f64(p, 0.4, 0.6);
            assert!(
                (0..3).map(|k| n[k] * core[k]).sum::<f64>() > 0.0,
                "torus normal inward"
            );
            checked += 1;
        }
        assert_eq!(checked, 2 * 8 * 3 + 16);
    }

    #[test]
    fn every_builtin_reads() {
        for name in BUILTIN_SCENES {
            let s = builtin_scene(name).unwrap();
            assert!(!s.surfaces.is_empty(), "{name}");
        }
        assert!(matches!(
            builtin_scene("nope"),
            Err(SweepError::UnknownBuiltin(_))
        ));
    }

    #[test]
    fn bad_scenes_name_the_field() {
        let e = scene_from_json(r#"{"surfaces": [{"torus": {"center": [0,0,0], "axis": [1,1,0], "major": 2, "minor": 1}}], "t": [0,1], "eye": [0,0,5]}"#)
            .unwrap_err();
        assert!(e.to_string().contains("surfaces[0].torus.axis"), "{e}");
        let e = scene_from_json(r#"{"surfaces": [{"bezier": {"degrees": [1,1], "points": [[0,0,0],[1,0,0],[0,1,0],[1,1,0,-1]]}}], "t": [0,1], "eye": [0,0,5]}"#)
            .unwrap_err();
        assert!(e.to_string().contains("points[3]"), "{e}");
        let e = scene_from_json(r#"{"surfaces": [], "t": [1,0], "eye": [0,0,5]}"#).unwrap_err();
        assert!(e.to_string().contains("surfaces"), "{e}");
    }
}
