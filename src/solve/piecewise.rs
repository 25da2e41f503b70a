//! Piecewise systems: an equation given as a tensor B-spline field is a polynomial only
//! between its knots. The box is cut by every equation's knot planes into a grid of cells,
//! each with every equation in Bernstein form; the subdivision then runs over the whole box
//! with boxes free to cross knot planes: a box is cut into parts (one per cell it meets, each
//! carrying the equations on it, split with the box by de Casteljau), and culling,
//! Miranda's test and the interval Jacobian are taken over all its parts. A root on a knot
//! plane is thus an ordinary root — inside a box that straddles the plane — found once; split
//! planes are chosen where some equation is of one strict sign, as in [`solve`].
//!
//! Why the two tests still hold across pieces: the field is continuous (interior knots of
//! multiplicity at most the degree), which is all Miranda's theorem asks; and along any
//! segment of the box each `g_i = Σ_j A_ij f_j` is continuous and piecewise polynomial, so
//! `g_i(x) − g_i(y) = ∫₀¹ ∇g_i(y + s(x − y))·(x − y) ds` with the gradient taken piece by
//! piece. That integral is a convex combination of gradients from the pieces, so its row
//! lies in the interval row formed over *all* pieces; a strictly diagonally dominant interval
//! Jacobian over all pieces makes every such matrix non-singular and rules out a second root.

use super::check::{extended_equations, point_is_the_root};
use super::subdivision::{
    certify_and_refine, elevated, max_abs, precondition, root_in, rounded_inverse, solve,
    strict_sign, Coefficient, Decision, SPLITS,
};
use super::{
    check_domain, check_square, touching_groups, Cluster, ClusterReason, RationalBox, Root,
    RootCertificate, Solution, SolveError, SolveOptions, System, MAX_DEGREE,
};
use crate::bernstein::Bernstein;
use crate::bspline::TensorSpline;
use crate::num::rational::lerp;
use crate::num::{rational_from_f64, rational_to_f64, Field, Interval, Rational, Sign};
use crate::Path;
use num_traits::{One, Zero};
use std::time::Instant;

/// The most cells (products of knot spans inside the box) a piecewise system may have.
pub const MAX_CELLS: usize = 4096;

/// One equation of a [`PiecewiseSystem`].
#[derive(Clone, Debug, PartialEq)]
pub enum Equation {
    /// A polynomial in tensor Bernstein form on the whole domain.
    Polynomial(Bernstein<Rational>),
    /// A tensor B-spline field in domain coordinates; its domain covers the box.
    Spline(TensorSpline<Rational>),
}

/// A system whose equations may be tensor B-spline fields: the box, the equations as given,
/// the grid of cells their knots cut the box into, and each cell's polynomial [`System`].
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseSystem {
    domain: RationalBox,
    equations: Vec<Equation>,
    breaks: Vec<Vec<Rational>>,
    kinks: Vec<Vec<Rational>>,
    cells: Vec<System>,
}

impl PiecewiseSystem {
    /// Checks the equations against the box and cuts it into cells. A B-spline field must
    /// have the box's dimension, degrees up to [`MAX_DEGREE`], a domain `[s_p, s_n]` covering
    /// the box on every axis, and no knot strictly inside the box of multiplicity above its
    /// degree (the field would jump there, and its zero set on that plane is not defined).
    /// At most [`MAX_CELLS`] cells.
    pub fn new(domain: RationalBox, equations: Vec<Equation>) -> Result<Self, SolveError> {
        let n = domain.len();
        check_domain(&domain)?;
        let mut breaks: Vec<Vec<Rational>> = domain
            .iter()
            .map(|(a, b)| vec![a.clone(), b.clone()])
            .collect();
        let mut kinks: Vec<Vec<Rational>> = vec![Vec::new(); n];
        for (i, e) in equations.iter().enumerate() {
            if let Equation::Spline(s) = e {
                spline_fits(s, &domain).map_err(|why| SolveError::Equation { equation: i, why })?;
                for (k, knots) in s.knots().iter().enumerate() {
                    let (a, b) = &domain[k];
                    let inside = knots.iter().filter(|x| a < *x && *x < b);
                    breaks[k].extend(inside.clone().cloned());
                    // Multiplicity m gives continuity C^(p−m) at least: C⁰ at most where m = p.
                    let p = s.degrees()[k];
                    kinks[k].extend(
                        inside
                            .filter(|x| knots.iter().filter(|y| y == x).count() >= p)
                            .cloned(),
                    );
                }
            }
        }
        for b in breaks.iter_mut().chain(kinks.iter_mut()) {
            b.sort();
            b.dedup();
        }
        let counts: Vec<usize> = breaks.iter().map(|b| b.len() - 1).collect();
        let total = counts
            .iter()
            .try_fold(1usize, |acc, &c| acc.checked_mul(c))
            .filter(|&t| t <= MAX_CELLS)
            .ok_or_else(|| SolveError::Field {
                field: "equations".into(),
                why: format!(
                    "the knots cut the box into {} cells, more than the limit of {MAX_CELLS}",
                    counts
                        .iter()
                        .map(|c| c.to_string())
                        .collect::<Vec<_>>()
                        .join(" × ")
                ),
            })?;
        let mut cells = Vec::with_capacity(total);
        for flat in 0..total {
            let bounds = cell_bounds(&breaks, &counts, flat);
            let mut eqs = Vec::with_capacity(equations.len());
            for (i, e) in equations.iter().enumerate() {
                eqs.push(match e {
                    Equation::Polynomial(p) if total == 1 => p.clone(),
                    Equation::Polynomial(p) => {
                        if p.dim() != n {
                            return Err(SolveError::Equation {
                                equation: i,
                                why: format!("has {} variables, the box {n}", p.dim()),
                            });
                        }
                        let unit: Vec<(Rational, Rational)> = bounds
                            .iter()
                            .zip(&domain)
                            .map(|((lo, hi), (a, b))| ((lo - a) / (b - a), (hi - a) / (b - a)))
                            .collect();
                        p.restrict(&unit)?
                    }
                    Equation::Spline(s) => {
                        s.bezier_on_box_exact(&bounds)
                            .map_err(|e| SolveError::Equation {
                                equation: i,
                                why: e.to_string(),
                            })?
                    }
                });
            }
            cells.push(System::new(bounds, eqs)?);
        }
        let kinks = true_kinks(&breaks, &counts, &cells, kinks)?;
        Ok(PiecewiseSystem {
            domain,
            equations,
            breaks,
            kinks,
            cells,
        })
    }

    /// The system on the plane `x_axis = c` over `bounds` (a box inside the domain whose
    /// `axis` interval holds `c`): an `(n − 1)`-unknown system on `bounds` without `axis`,
    /// each B-spline field restricted to the plane ([`TensorSpline::restrict_axis`]) and each
    /// polynomial restricted to `bounds` and cut at `c`. The field is continuous, so its
    /// restriction to a knot plane is well defined.
    pub fn plane(
        &self,
        axis: usize,
        c: &Rational,
        bounds: &RationalBox,
    ) -> Result<PiecewiseSystem, SolveError> {
        let n = self.unknowns();
        if axis >= n || bounds.len() != n || n < 2 {
            return Err(SolveError::Unknowns(n));
        }
        let unit = |k: usize, x: &Rational| {
            let (a, b) = &self.domain[k];
            (x - a) / (b - a)
        };
        let sub: Vec<(Rational, Rational)> = bounds
            .iter()
            .enumerate()
            .map(|(k, (lo, hi))| {
                if k == axis {
                    (<Rational as Zero>::zero(), <Rational as One>::one())
                } else {
                    (unit(k, lo), unit(k, hi))
                }
            })
            .collect();
        let whole = sub.iter().all(|(a, b)| a.is_zero() && b.is_one());
        let at = unit(axis, c);
        let mut equations = Vec::with_capacity(self.equations.len());
        for (i, e) in self.equations.iter().enumerate() {
            equations.push(match e {
                Equation::Polynomial(p) => {
                    let mut q = p.eval_axis(axis, &at)?;
                    if !whole {
                        q = q.restrict(&sub)?;
                    }
                    Equation::Polynomial(q.face(axis, false)?)
                }
                Equation::Spline(s) => Equation::Spline(s.restrict_axis(axis, c).map_err(|e| {
                    SolveError::Equation {
                        equation: i,
                        why: e.to_string(),
                    }
                })?),
            });
        }
        let domain = bounds
            .iter()
            .enumerate()
            .filter(|&(k, _)| k != axis)
            .map(|(_, b)| b.clone())
            .collect();
        PiecewiseSystem::new(domain, equations)
    }

    /// Per axis, the knots strictly inside the box across which some B-spline equation is
    /// not C¹: there the Jacobian jumps. A knot of multiplicity equal to the degree is only
    /// a candidate; it is a kink when the normal derivatives of two cells meeting on it
    /// differ (compared exactly, in Bernstein form on the common face).
    pub fn kinks(&self) -> &[Vec<Rational>] {
        &self.kinks
    }

    /// A polynomial system as a piecewise one with a single cell.
    pub fn from_polynomial(system: System) -> PiecewiseSystem {
        PiecewiseSystem {
            breaks: system
                .domain
                .iter()
                .map(|(a, b)| vec![a.clone(), b.clone()])
                .collect(),
            kinks: vec![Vec::new(); system.domain.len()],
            equations: system
                .equations
                .iter()
                .cloned()
                .map(Equation::Polynomial)
                .collect(),
            domain: system.domain.clone(),
            cells: vec![system],
        }
    }

    /// The box.
    pub fn domain(&self) -> &[(Rational, Rational)] {
        &self.domain
    }
    /// The equations as given.
    pub fn equations(&self) -> &[Equation] {
        &self.equations
    }
    /// The number of unknowns.
    pub fn unknowns(&self) -> usize {
        self.domain.len()
    }
    /// Per axis, the cell boundaries `a = x_0 < x_1 < … < x_m = b`: the box's ends and every
    /// equation's knots strictly inside it.
    pub fn breaks(&self) -> &[Vec<Rational>] {
        &self.breaks
    }
    /// The cells, axis 0 fastest, each with every equation in Bernstein form on it.
    pub fn cells(&self) -> &[System] {
        &self.cells
    }
    /// The system itself when it has one cell (no knot inside the box).
    pub fn polynomial(&self) -> Option<&System> {
        match self.cells.as_slice() {
            [only] => Some(only),
            _ => None,
        }
    }

    /// The index of a cell containing the point `x` (closed cells; the first on ties).
    fn cell_of(&self, x: &[Rational]) -> usize {
        let mut flat = 0;
        let mut stride = 1;
        for (k, b) in self.breaks.iter().enumerate() {
            let m = b.len() - 1;
            let j = b[1..m].partition_point(|t| t < &x[k]);
            flat += j * stride;
            stride *= m;
        }
        flat
    }
}

/// The candidate kinks (per axis) across which some equation's derivative along the axis
/// really differs between two cells meeting there. Continuity makes the tangential
/// derivatives agree, so the normal one decides C¹.
fn true_kinks(
    breaks: &[Vec<Rational>],
    counts: &[usize],
    cells: &[System],
    candidates: Vec<Vec<Rational>>,
) -> Result<Vec<Vec<Rational>>, SolveError> {
    let strides: Vec<usize> = counts
        .iter()
        .scan(1, |s, &c| {
            let here = *s;
            *s *= c;
            Some(here)
        })
        .collect();
    let mut out = Vec::with_capacity(candidates.len());
    for (k, list) in candidates.into_iter().enumerate() {
        let mut kept = Vec::new();
        for x in list {
            // The cell index j along k whose lower end is x: cells j−1 and j meet on it.
            let Some(j) = breaks[k].iter().position(|b| *b == x) else {
                continue;
            };
            let mut jumps = false;
            'cells: for below in 0..cells.len() {
                if (below / strides[k]) % counts[k] != j - 1 {
                    continue;
                }
                let above = below + strides[k];
                let width = |c: &System| &c.domain[k].1 - &c.domain[k].0;
                let (wb, wa) = (width(&cells[below]), width(&cells[above]));
                for (fb, fa) in cells[below].equations.iter().zip(&cells[above].equations) {
                    if fb.degrees()[k] == 0 {
                        continue;
                    }
                    // d/dx_k = (d/dt_k) / width: compare (d/dt)_below · w_above with
                    // (d/dt)_above · w_below on the face.
                    let db = fb.derivative(k)?.face(k, true)?.scale(&wa);
                    let da = fa.derivative(k)?.face(k, false)?.scale(&wb);
                    if db != da {
                        jumps = true;
                        break 'cells;
                    }
                }
            }
            if jumps {
                kept.push(x);
            }
        }
        out.push(kept);
    }
    Ok(out)
}

/// Why a B-spline field does not fit the box, if it does not.
fn spline_fits(s: &TensorSpline<Rational>, domain: &RationalBox) -> Result<(), String> {
    let n = domain.len();
    if s.dim() != n {
        return Err(format!("has {} variables, the box {n}", s.dim()));
    }
    for (k, (&p, knots)) in s.degrees().iter().zip(s.knots()).enumerate() {
        if p > MAX_DEGREE {
            return Err(format!(
                "degree {p} on axis {k} exceeds the limit of {MAX_DEGREE}"
            ));
        }
        let count = knots.len() - p - 1;
        let (a, b) = &domain[k];
        if &knots[p] > a || &knots[count] < b {
            return Err(format!(
                "the B-spline's domain [s_p, s_n] = [{}, {}] on axis {k} does not cover the box [{}, {}]",
                knots[p], knots[count], a, b
            ));
        }
        for x in knots.iter().filter(|x| a < *x && *x < b) {
            let m = knots.iter().filter(|y| *y == x).count();
            if m > p {
                return Err(format!(
                    "knot {x} on axis {k} has multiplicity {m}, above the degree {p}: the field \
                     jumps across that plane inside the box and its zero set there is not defined"
                ));
            }
        }
    }
    Ok(())
}

/// The bounds of cell `flat` (axis 0 fastest) of the grid.
fn cell_bounds(breaks: &[Vec<Rational>], counts: &[usize], mut flat: usize) -> RationalBox {
    breaks
        .iter()
        .zip(counts)
        .map(|(b, &c)| {
            let j = flat % c;
            flat /= c;
            (b[j].clone(), b[j + 1].clone())
        })
        .collect()
}

/// Exact certificate attempts when refining a root.
const REFINE_TRIES: usize = 3;

/// Solves a piecewise system by one subdivision of the whole box whose boxes cross knot
/// planes (see the module docs), on `opts.path`: exact, fast (intervals; what rounding leaves
/// open at the depth limit is an uncertain cluster) or filtered (that last decision exact).
/// A system with no knot inside the box is handed to [`solve`].
///
/// The guarantee is [`solve`](super::solve)'s: every root in the box lies in exactly one
/// root's box (holding no other root) or in clusters' boxes.
pub fn solve_piecewise(
    system: &PiecewiseSystem,
    opts: &SolveOptions,
) -> Result<Solution, SolveError> {
    let n = system.unknowns();
    check_square(system.equations.len(), n)?;
    if let Some(only) = system.polynomial() {
        return solve(only, opts);
    }
    let clock = Instant::now();
    let found = match opts.path {
        Path::Exact => subdivide::<Rational>(system, opts, false, clock)?,
        Path::Fast => subdivide::<Interval>(system, opts, false, clock)?,
        Path::Filtered => subdivide::<Interval>(system, opts, true, clock)?,
    };
    let mut found = across_split_planes(system, found, opts.tolerance)?;
    if opts.boundary {
        found = across_boundary(system, found, opts.tolerance)?;
    }
    Ok(Solution {
        roots: found.roots,
        clusters: found.clusters,
        boxes_visited: found.visited,
        path: opts.path,
    })
}

/// What the solve has found so far.
struct Found {
    roots: Vec<Root>,
    clusters: Vec<Cluster>,
    visited: usize,
}

/// A root on a split plane leaves touching depth-limit clusters, none of which can certify
/// it: each group of them is tried once more as one box (their hull, grown by a quarter of
/// its width on every side inside the domain), certified exactly across its parts, and kept
/// only when that box meets no other root's or cluster's box, so nothing is counted twice.
fn across_split_planes(
    system: &PiecewiseSystem,
    found: Found,
    tolerance: f64,
) -> Result<Found, SolveError> {
    let quarter = Rational::new(1.into(), 4.into());
    retry_groups(
        system,
        found,
        |c| c.reason == ClusterReason::DepthLimit,
        |members| members.len() >= 2,
        |lo, hi| {
            for k in 0..lo.len() {
                let w = (&hi[k] - &lo[k]) * &quarter;
                lo[k] = (&lo[k] - &w).max(system.domain[k].0.clone());
                hi[k] = (&hi[k] + &w).min(system.domain[k].1.clone());
            }
        },
        |lo, hi| {
            let (Decision::Yes, Some(c), _) = certify_parts(
                &parts(system, |c| exact_cell(system, c), &lo, &hi)?,
                &lo,
                &hi,
            )?
            else {
                return Ok(None);
            };
            let (lo, hi, c) = refine_box(system, lo, hi, c, tolerance)?;
            Ok(Some(root_in(lo.into_iter().zip(hi).collect(), c)))
        },
    )
}

/// The retry both [`across_split_planes`] and [`across_boundary`] make (domain
/// coordinates): the clusters `eligible` admits are grouped by touching; each group `wanted`
/// is tried as one box, its hull `widen`ed; when that box meets no other root's or cluster's
/// box and `attempt` certifies a root on it, the root replaces the group.
fn retry_groups(
    system: &PiecewiseSystem,
    found: Found,
    eligible: impl Fn(&Cluster) -> bool,
    wanted: impl Fn(&[usize]) -> bool,
    widen: impl Fn(&mut [Rational], &mut [Rational]),
    attempt: impl Fn(Vec<Rational>, Vec<Rational>) -> Result<Option<Root>, SolveError>,
) -> Result<Found, SolveError> {
    let n = system.unknowns();
    let Found {
        mut roots,
        clusters,
        visited,
    } = found;
    let corners: Vec<(Vec<Rational>, Vec<Rational>)> = clusters
        .iter()
        .map(|c| c.bounds.iter().cloned().unzip())
        .collect();
    let candidates: Vec<usize> = (0..clusters.len())
        .filter(|&i| eligible(&clusters[i]))
        .collect();
    let boxes: Vec<(&[Rational], &[Rational])> = candidates
        .iter()
        .map(|&i| (corners[i].0.as_slice(), corners[i].1.as_slice()))
        .collect();
    let meets = |alo: &[Rational], ahi: &[Rational], lo: &[Rational], hi: &[Rational]| {
        (0..n).all(|k| alo[k] <= hi[k] && lo[k] <= ahi[k])
    };
    let mut replaced = vec![false; clusters.len()];
    for group in touching_groups(&boxes) {
        let members: Vec<usize> = group.into_iter().map(|g| candidates[g]).collect();
        if !wanted(&members) {
            continue;
        }
        let (mut lo, mut hi) = corners[members[0]].clone();
        for &m in &members {
            for k in 0..n {
                lo[k] = lo[k].clone().min(corners[m].0[k].clone());
                hi[k] = hi[k].clone().max(corners[m].1[k].clone());
            }
        }
        widen(&mut lo, &mut hi);
        let clear = roots.iter().all(|r| {
            let (rlo, rhi): (Vec<Rational>, Vec<Rational>) = r.bounds.iter().cloned().unzip();
            !meets(&rlo, &rhi, &lo, &hi)
        }) && (0..clusters.len())
            .filter(|i| !members.contains(i))
            .all(|i| !meets(&corners[i].0, &corners[i].1, &lo, &hi));
        if !clear {
            continue;
        }
        if let Some(root) = attempt(lo, hi)? {
            roots.push(root);
            for &m in &members {
                replaced[m] = true;
            }
        }
    }
    let clusters = clusters
        .into_iter()
        .zip(replaced)
        .filter(|(_, r)| !r)
        .map(|(c, _)| c)
        .collect();
    Ok(Found {
        roots,
        clusters,
        visited,
    })
}

/// Simple roots on the domain's boundary, as the polynomial solver certifies them
/// ([`SolveOptions::boundary`]): each group of touching depth-limit and boundary clusters
/// with one on the boundary is tried once more as one box reaching across the faces it
/// touches (mirrored there, grown by a quarter of its width elsewhere). On it every equation
/// is the polynomial it is on the box's part inside the domain, extended beyond
/// ([`extended_equations`]; a B-spline's part must lie in one knot span on every axis, else
/// the group stays). Certified exactly and refined, its root is kept when the refined box
/// lies inside the domain, or when the point of the refined box on the crossed faces (the
/// simplest rationals on the other axes) is an exact zero of every equation: the
/// certificate's point ([`RootCertificate::point`]).
fn across_boundary(
    system: &PiecewiseSystem,
    found: Found,
    tolerance: f64,
) -> Result<Found, SolveError> {
    let n = system.unknowns();
    let domain = &system.domain;
    let reasons: Vec<ClusterReason> = found.clusters.iter().map(|c| c.reason).collect();
    retry_groups(
        system,
        found,
        |c| {
            matches!(
                c.reason,
                ClusterReason::DomainBoundary | ClusterReason::DepthLimit
            )
        },
        |members| {
            members
                .iter()
                .any(|&m| reasons[m] == ClusterReason::DomainBoundary)
        },
        |lo, hi| super::reach_across(lo, hi, domain),
        |lo, hi| {
            let bounds: RationalBox = lo.iter().cloned().zip(hi.iter().cloned()).collect();
            // A part inside that crosses a knot: not one polynomial there.
            let Ok(f) = extended_equations(system, &bounds) else {
                return Ok(None);
            };
            let unit = |x: &[Rational]| -> Vec<Rational> {
                (0..n)
                    .map(|k| super::unit_coordinate(domain, k, &x[k]))
                    .collect()
            };
            let Some((ulo, uhi, mut c)) =
                certify_and_refine(unit(&lo), unit(&hi), elevated(&f)?, tolerance)?
            else {
                return Ok(None);
            };
            let refined = super::domain_bounds(domain, &ulo, &uhi);
            let Some(candidate) = super::boundary_candidate(domain, &refined) else {
                // Outside the domain.
                return Ok(None);
            };
            if let Some(point) = candidate {
                // The equations on the widened box hold the refined one (and its point).
                if point_is_the_root(domain, &f, &bounds, &point).is_err() {
                    return Ok(None);
                }
                c.point = Some(point);
            }
            Ok(Some(root_in(refined, c)))
        },
    )
}

/// The subdivision of the domain in the coefficient field `T`, its boxes free to cross knot
/// planes: a box is culled when some equation is of one strict sign on all its parts,
/// certified by [`certify_parts`], or split (its widest side relative to the domain, at the
/// first of the split points some equation is of one strict sign on), down to the depth
/// limit; deeper it is a cluster. Where rounding leaves a decision open the box is split on
/// (always sound); at the depth limit it is decided exactly with `finish` (the filtered
/// path) or reported [`ClusterReason::Uncertain`] (the fast path).
fn subdivide<T: Coefficient>(
    system: &PiecewiseSystem,
    opts: &SolveOptions,
    finish: bool,
    clock: Instant,
) -> Result<Found, SolveError> {
    let n = system.unknowns();
    let (limits, tolerance, levels) = (&opts.limits, opts.tolerance, opts.limits.max_depth);
    let (lo, hi): (Vec<Rational>, Vec<Rational>) = system.domain.iter().cloned().unzip();
    let mut found = Found {
        roots: Vec::new(),
        clusters: Vec::new(),
        visited: 0,
    };
    let cells_t: Vec<Vec<Bernstein<T>>> = system
        .cells
        .iter()
        .map(|c| {
            c.equations
                .iter()
                .map(|e| e.map(T::from_rational))
                .collect()
        })
        .collect();
    // Each box carries its parts, split with it (de Casteljau keeps the rounding relative to
    // the box, which restricting from the cell again would not).
    let first = parts(system, |c| cells_t[c].as_slice(), &lo, &hi)?;
    let mut stack = vec![(lo, hi, 0u32, first)];
    while let Some((lo, hi, depth, pieces)) = stack.pop() {
        let cluster = |reason| Cluster {
            bounds: lo.iter().cloned().zip(hi.iter().cloned()).collect(),
            reason,
            max_abs_f: pieces
                .iter()
                .map(|p| max_abs(&p.f))
                .fold(vec![0.0; n], |a, b| {
                    a.iter().zip(&b).map(|(x, y)| x.max(*y)).collect()
                }),
        };
        let over_time = limits.time_limit.is_some_and(|t| clock.elapsed() > t);
        if found.visited >= limits.max_boxes || over_time {
            found.clusters.push(cluster(ClusterReason::Budget));
            continue;
        }
        found.visited += 1;
        // Intervals; where rounding leaves a decision open the box is split on (always
        // sound), and at the depth limit it is decided exactly.
        let mut cull = culled(&pieces);
        let (mut certified, mut certificate) = if cull == Decision::Yes {
            (Decision::No, None)
        } else {
            let (d, c, empty) = certify_parts(&pieces, &lo, &hi)?;
            if empty {
                cull = Decision::Yes;
            }
            (d, c)
        };
        let deepest = depth >= levels.saturating_mul(n as u32);
        let open = cull == Decision::Uncertain || certified == Decision::Uncertain;
        if deepest && open && !finish {
            found.clusters.push(cluster(ClusterReason::Uncertain));
            continue;
        }
        if deepest && open {
            let exact = parts(system, |c| exact_cell(system, c), &lo, &hi)?;
            cull = culled(&exact);
            (certified, certificate) = if cull == Decision::Yes {
                (Decision::No, None)
            } else {
                let (d, c, empty) = certify_parts(&exact, &lo, &hi)?;
                if empty {
                    cull = Decision::Yes;
                }
                (d, c)
            };
        }
        if cull == Decision::Yes {
            continue;
        }
        if let (Decision::Yes, Some(c)) = (certified, certificate) {
            let (lo, hi, c) = refine_box(system, lo, hi, c, tolerance)?;
            found
                .roots
                .push(root_in(lo.into_iter().zip(hi).collect(), c));
            continue;
        }
        if deepest {
            let outer = (0..n).any(|k| lo[k] == system.domain[k].0 || hi[k] == system.domain[k].1);
            found.clusters.push(cluster(if outer {
                ClusterReason::DomainBoundary
            } else {
                ClusterReason::DepthLimit
            }));
            continue;
        }
        let relative: Vec<Rational> = (0..n)
            .map(|k| width(&lo[k], &hi[k]) / width(&system.domain[k].0, &system.domain[k].1))
            .collect();
        let axis = (0..n)
            .max_by(|&a, &b| relative[a].cmp(&relative[b]).then(b.cmp(&a)))
            .unwrap_or(0);
        let at = |s: &Rational| lerp(&lo[axis], &hi[axis], s);
        let mut mid = at(&Rational::new(1.into(), 2.into()));
        for &(p, q) in &SPLITS {
            let x = at(&Rational::new(p.into(), q.into()));
            if plane_root_free(&pieces, axis, &x)? {
                mid = x;
                break;
            }
        }
        let mut hi_left = hi.clone();
        hi_left[axis] = mid.clone();
        let mut lo_right = lo.clone();
        lo_right[axis] = mid.clone();
        let (mut left, mut right) = (Vec::new(), Vec::new());
        for p in pieces {
            if p.hi[axis] <= mid {
                left.push(p);
            } else if p.lo[axis] >= mid {
                right.push(p);
            } else {
                let t: T = width_ratio((&p.lo[axis], &mid), (&p.lo[axis], &p.hi[axis]));
                let (mut fl, mut fr) = (Vec::new(), Vec::new());
                for e in &p.f {
                    let (l, r) = e.split(axis, &t)?;
                    fl.push(l);
                    fr.push(r);
                }
                let (mut lhi, mut rlo) = (p.hi.clone(), p.lo.clone());
                lhi[axis] = mid.clone();
                rlo[axis] = mid.clone();
                left.push(Part {
                    lo: p.lo,
                    hi: lhi,
                    f: fl,
                    ratio: Vec::new(),
                });
                right.push(Part {
                    lo: rlo,
                    hi: p.hi,
                    f: fr,
                    ratio: Vec::new(),
                });
            }
        }
        for (blo, bhi, ps) in [(&lo_right, &hi, &mut right), (&lo, &hi_left, &mut left)] {
            for p in ps.iter_mut() {
                p.ratio = (0..n)
                    .map(|k| width_ratio((&blo[k], &bhi[k]), (&p.lo[k], &p.hi[k])))
                    .collect();
            }
        }
        stack.push((lo_right, hi, depth + 1, right));
        stack.push((lo, hi_left, depth + 1, left));
    }
    Ok(found)
}

/// Whether some equation is of one certified strict sign on the plane `x_axis = x` across
/// all parts.
fn plane_root_free<T: Coefficient>(
    parts: &[Part<T>],
    axis: usize,
    x: &Rational,
) -> Result<bool, SolveError> {
    let on: Vec<&Part<T>> = parts
        .iter()
        .filter(|p| p.lo[axis] <= *x && *x <= p.hi[axis])
        .collect();
    for i in 0..on.first().map_or(0, |p| p.f.len()) {
        let mut sign = None;
        let mut ok = true;
        for p in &on {
            let t: T = width_ratio((&p.lo[axis], x), (&p.lo[axis], &p.hi[axis]));
            let s = strict_sign(&p.f[i].eval_axis(axis, &t)?);
            if !matches!(s, Sign::Positive | Sign::Negative) || sign.is_some_and(|o| o != s) {
                ok = false;
                break;
            }
            sign = Some(s);
        }
        if ok {
            return Ok(true);
        }
    }
    Ok(false)
}

/// One cell's part of a box: its bounds (domain coordinates), the equations on it (Bernstein
/// form on the part, common degrees, in the coefficient field `T`), and per axis the box's
/// width over the part's, which turns a derivative in the part's unit coordinates into one in
/// the box's.
struct Part<T> {
    lo: Vec<Rational>,
    hi: Vec<Rational>,
    f: Vec<Bernstein<T>>,
    ratio: Vec<T>,
}

/// `b − a`, without a gcd when both are dyadic.
fn width(a: &Rational, b: &Rational) -> Rational {
    <Rational as Field>::sub(b, a)
}

/// `(b − a)/(d − c)` for `num = (a, b)`, `den = (c, d)`, `c < d`, in `T`: exact for
/// rationals (dyadic differences without a gcd), an enclosure for intervals (no rational
/// division, no big-integer rounding where the bounds are `f64`s).
fn width_ratio<T: Field>(num: (&Rational, &Rational), den: (&Rational, &Rational)) -> T {
    let width = |(lo, hi): (&Rational, &Rational)| T::from_rational(hi).sub(&T::from_rational(lo));
    width(num).div(&width(den))
}

/// Calls `visit(cell, unit)` for every cell the box `[lo, hi]` meets with positive volume,
/// `unit` the intersection in the cell's unit coordinates.
fn for_each_part(
    system: &PiecewiseSystem,
    lo: &[Rational],
    hi: &[Rational],
    mut visit: impl FnMut(usize, Vec<(Rational, Rational)>) -> Result<(), SolveError>,
) -> Result<(), SolveError> {
    let n = system.unknowns();
    let ranges: Vec<Vec<usize>> = (0..n)
        .map(|k| {
            let b = &system.breaks[k];
            (0..b.len() - 1)
                .filter(|&j| b[j] < hi[k] && b[j + 1] > lo[k])
                .collect()
        })
        .collect();
    let strides: Vec<usize> = system
        .breaks
        .iter()
        .scan(1, |s, b| {
            let here = *s;
            *s *= b.len() - 1;
            Some(here)
        })
        .collect();
    let total: usize = ranges.iter().map(Vec::len).product();
    for mut flat in 0..total {
        let mut cell = 0;
        for k in 0..n {
            cell += ranges[k][flat % ranges[k].len()] * strides[k];
            flat /= ranges[k].len();
        }
        let domain = &system.cells[cell].domain;
        let unit = (0..n)
            .map(|k| {
                let (a, b) = &domain[k];
                let (l, h) = (lo[k].clone().max(a.clone()), hi[k].clone().min(b.clone()));
                ((&l - a) / (b - a), (&h - a) / (b - a))
            })
            .collect();
        visit(cell, unit)?;
    }
    Ok(())
}

/// The exact equations of cell `index`.
fn exact_cell(system: &PiecewiseSystem, index: usize) -> &[Bernstein<Rational>] {
    &system.cells[index].equations
}

/// The parts of the box `[lo, hi]`: one per cell it meets with positive volume, each
/// restricted from `cell(index)` (a cell's equations in `T`).
fn parts<'a, T: Coefficient + 'a>(
    system: &PiecewiseSystem,
    cell: impl Fn(usize) -> &'a [Bernstein<T>],
    lo: &[Rational],
    hi: &[Rational],
) -> Result<Vec<Part<T>>, SolveError> {
    let n = system.unknowns();
    let mut out = Vec::new();
    for_each_part(system, lo, hi, |index, unit| {
        let c = &system.cells[index];
        let (mut plo, mut phi, mut ratio) = (vec![], vec![], vec![]);
        for k in 0..n {
            let (a, b) = &c.domain[k];
            let (l, h) = (a + (b - a) * &unit[k].0, a + (b - a) * &unit[k].1);
            ratio.push(width_ratio((&lo[k], &hi[k]), (&l, &h)));
            plo.push(l);
            phi.push(h);
        }
        let sub: Vec<(T, T)> = unit
            .iter()
            .map(|(a, b)| (T::from_rational(a), T::from_rational(b)))
            .collect();
        let mut f: Vec<Bernstein<T>> = cell(index)
            .iter()
            .map(|e| e.restrict(&sub))
            .collect::<Result<_, _>>()?;
        for k in 0..n {
            let top = f.iter().map(|e| e.degrees()[k]).max().unwrap_or(0);
            for e in &mut f {
                if e.degrees()[k] < top {
                    *e = e.elevate(k, top - e.degrees()[k])?;
                }
            }
        }
        out.push(Part {
            lo: plo,
            hi: phi,
            f,
            ratio,
        });
        Ok(())
    })?;
    Ok(out)
}

/// Some equation of one strict sign on every part (the same sign on all): `Yes` culls.
fn culled<T: Coefficient>(parts: &[Part<T>]) -> Decision {
    let rows: Vec<&[Bernstein<T>]> = parts.iter().map(|p| p.f.as_slice()).collect();
    one_sign_somewhere(&rows)
}

/// Some row index `i` whose polynomial has one strict sign on every part (`rows[p][i]` on
/// part `p`), the same on all.
fn one_sign_somewhere<T: Coefficient>(rows: &[&[Bernstein<T>]]) -> Decision {
    let n = rows.first().map_or(0, |p| p.len());
    let mut uncertain = false;
    for i in 0..n {
        let mut sign = None;
        let mut ok = true;
        for p in rows {
            match strict_sign(&p[i]) {
                s @ (Sign::Positive | Sign::Negative) if sign.is_none_or(|o| o == s) => {
                    sign = Some(s)
                }
                Sign::Uncertain => {
                    uncertain = true;
                    ok = false;
                }
                _ => ok = false,
            }
        }
        if ok {
            return Decision::Yes;
        }
    }
    if uncertain {
        Decision::Uncertain
    } else {
        Decision::No
    }
}

/// Existence and uniqueness on the box `[lo, hi]` across its parts, in `T`: the
/// certificate, `No`, or `Uncertain` (rounding); and whether the preconditioned system
/// culls the box (some `g_i` of one strict sign on every part: no root).
fn certify_parts<T: Coefficient>(
    parts: &[Part<T>],
    lo: &[Rational],
    hi: &[Rational],
) -> Result<(Decision, Option<RootCertificate>, bool), SolveError> {
    let n = lo.len();
    // The preconditioner: the inverse Jacobian (in the box's unit coordinates) at the centre.
    let half = Rational::new(1.into(), 2.into());
    let centre: Vec<Rational> = (0..n).map(|k| lerp(&lo[k], &hi[k], &half)).collect();
    let Some(at) = parts
        .iter()
        .find(|p| (0..n).all(|k| p.lo[k] <= centre[k] && centre[k] <= p.hi[k]))
    else {
        return Ok((Decision::No, None, false));
    };
    // Only an approximation is needed (the preconditioner may be any matrix).
    let tau: Vec<f64> = (0..n)
        .map(|k| {
            let t = rational_to_f64(&width(&at.lo[k], &centre[k]))
                / rational_to_f64(&width(&at.lo[k], &at.hi[k]));
            if t.is_finite() {
                t
            } else {
                0.5
            }
        })
        .collect();
    let mut j = vec![vec![0.0; n]; n];
    for (fi, row) in at.f.iter().zip(j.iter_mut()) {
        let fi = fi.map(|c| c.approx());
        for (k, jk) in row.iter_mut().enumerate() {
            if fi.degrees()[k] > 0 {
                *jk = fi.derivative(k)?.eval(&tau)? * at.ratio[k].approx();
            }
        }
    }
    let a = rounded_inverse(j);
    let g: Vec<Vec<Bernstein<T>>> = parts
        .iter()
        .map(|p| precondition(&a, &p.f))
        .collect::<Result<_, _>>()?;
    let rows: Vec<&[Bernstein<T>]> = g.iter().map(Vec::as_slice).collect();
    if n > 1 && one_sign_somewhere(&rows) == Decision::Yes {
        return Ok((Decision::No, None, true));
    }
    let mut uncertain = false;
    // Miranda: g_i of one strict sign on every part of the face t_i = 0, the other on t_i = 1.
    let mut signs = Vec::with_capacity(n);
    for i in 0..n {
        let mut sides = [None, None];
        let mut row_uncertain = false;
        for (p, gp) in parts.iter().zip(&g) {
            for (upper, on) in [(false, p.lo[i] == lo[i]), (true, p.hi[i] == hi[i])] {
                if !on {
                    continue;
                }
                match strict_sign(&gp[i].face(i, upper)?) {
                    Sign::Uncertain => row_uncertain = true,
                    s @ (Sign::Positive | Sign::Negative)
                        if sides[usize::from(upper)].is_none_or(|o| o == s) =>
                    {
                        sides[usize::from(upper)] = Some(s)
                    }
                    _ => return Ok((Decision::No, None, false)),
                }
            }
        }
        match sides {
            [Some(Sign::Negative), Some(Sign::Positive)] if !row_uncertain => signs.push(-1),
            [Some(Sign::Positive), Some(Sign::Negative)] if !row_uncertain => signs.push(1),
            [Some(a), Some(b)] if a == b => return Ok((Decision::No, None, false)),
            _ if row_uncertain => {
                uncertain = true;
                signs.push(0);
            }
            _ => return Ok((Decision::No, None, false)),
        }
    }
    // Uniqueness: the interval Jacobian over all parts, strictly diagonally dominant by rows.
    for i in 0..n {
        let mut diag: Option<(Sign, T)> = None;
        let mut off = vec![T::zero(); n];
        for (p, gp) in parts.iter().zip(&g) {
            for (k, off_k) in off.iter_mut().enumerate() {
                if gp[i].degrees()[k] == 0 {
                    if k == i {
                        return Ok((Decision::No, None, false));
                    }
                    continue;
                }
                let d = gp[i].derivative(k)?;
                let ratio = &p.ratio[k];
                if k == i {
                    let s = strict_sign(&d);
                    if s == Sign::Uncertain {
                        uncertain = true;
                        continue;
                    }
                    let least = d
                        .coeffs()
                        .iter()
                        .map(Coefficient::abs_lower)
                        .reduce(|a, b| a.min_lower(&b))
                        .unwrap_or_else(T::zero)
                        .mul(ratio);
                    diag = match (diag, s) {
                        (None, Sign::Positive | Sign::Negative) => Some((s, least)),
                        (Some((o, m)), s) if o == s => Some((s, m.min_lower(&least))),
                        _ => return Ok((Decision::No, None, false)),
                    };
                } else {
                    let most = d
                        .coeffs()
                        .iter()
                        .map(Coefficient::abs_upper)
                        .reduce(|a, b| a.max_upper(&b))
                        .unwrap_or_else(T::zero)
                        .mul(ratio);
                    *off_k = off_k.max_upper(&most);
                }
            }
        }
        let off = off.iter().fold(T::zero(), |s, x| s.add(x));
        let Some((_, m)) = diag else {
            if uncertain {
                continue;
            }
            return Ok((Decision::No, None, false));
        };
        match m.sub(&off).sign() {
            Sign::Positive => {}
            Sign::Uncertain => uncertain = true,
            _ => return Ok((Decision::No, None, false)),
        }
    }
    if uncertain {
        return Ok((Decision::Uncertain, None, false));
    }
    Ok((
        Decision::Yes,
        Some(RootCertificate {
            preconditioner: a,
            lower_face_signs: signs,
            point: None,
        }),
        false,
    ))
}

/// Shrinks a certified box around its root as [`solve`](super::solve) does: Newton's method
/// in `f64` on the cell holding the current point, then [`certify_parts`] on boxes around the
/// result (inside the certified box, which holds exactly one root) from the requested width
/// upwards by factors of 16.
#[allow(clippy::type_complexity)]
fn refine_box(
    system: &PiecewiseSystem,
    lo: Vec<Rational>,
    hi: Vec<Rational>,
    certificate: RootCertificate,
    tolerance: f64,
) -> Result<(Vec<Rational>, Vec<Rational>, RootCertificate), SolveError> {
    let n = system.unknowns();
    let side: Vec<f64> = system
        .domain
        .iter()
        .map(|(a, b)| rational_to_f64(&(b - a)))
        .collect();
    let width = (0..n)
        .map(|k| rational_to_f64(&(&hi[k] - &lo[k])) / side[k])
        .fold(0.0, f64::max);
    if tolerance.is_nan() || tolerance <= 0.0 || width <= tolerance {
        return Ok((lo, hi, certificate));
    }
    let lof: Vec<f64> = lo.iter().map(rational_to_f64).collect();
    let hif: Vec<f64> = hi.iter().map(rational_to_f64).collect();
    let mut x: Vec<f64> = (0..n).map(|k| 0.5 * (lof[k] + hif[k])).collect();
    for _ in 0..40 {
        let Ok(xr) = x
            .iter()
            .map(|&v| rational_from_f64(v, "point"))
            .collect::<Result<Vec<_>, _>>()
        else {
            break;
        };
        let cell = &system.cells[system.cell_of(&xr)];
        let (mut tau, mut w) = (vec![0.0; n], vec![0.0; n]);
        for k in 0..n {
            let (a, b) = (
                rational_to_f64(&cell.domain[k].0),
                rational_to_f64(&cell.domain[k].1),
            );
            w[k] = b - a;
            tau[k] = ((x[k] - a) / w[k]).clamp(0.0, 1.0);
        }
        let mut m = vec![vec![0.0; n]; n];
        let mut fx = vec![0.0; n];
        for (i, e) in cell.equations.iter().enumerate() {
            let e = e.map(rational_to_f64);
            fx[i] = e.eval(&tau)?;
            for k in 0..n {
                if e.degrees()[k] > 0 {
                    m[i][k] = e.derivative(k)?.eval(&tau)? / w[k];
                }
            }
        }
        let Some(inv) = super::subdivision::invert(m) else {
            break;
        };
        let mut moved = 0.0f64;
        for k in 0..n {
            let step: f64 = inv[k].iter().zip(&fx).map(|(a, b)| a * b).sum();
            let next = (x[k] - step).clamp(lof[k], hif[k]);
            moved = moved.max((next - x[k]).abs() / side[k]);
            x[k] = next;
        }
        if !moved.is_finite() || moved <= 1e-17 {
            break;
        }
    }
    let mut rho = (0.5 * tolerance).max(4.0 * f64::EPSILON);
    // Each try is exact: three at most (ρ, 16ρ, 256ρ), then the certified box is kept.
    let mut tries = 0;
    while rho < 0.25 * width && tries < REFINE_TRIES {
        tries += 1;
        let mut slo = Vec::with_capacity(n);
        let mut shi = Vec::with_capacity(n);
        for k in 0..n {
            let (Ok(a), Ok(b)) = (
                rational_from_f64((x[k] - rho * side[k]).max(lof[k]), "box"),
                rational_from_f64((x[k] + rho * side[k]).min(hif[k]), "box"),
            ) else {
                return Ok((lo, hi, certificate));
            };
            slo.push(a.max(lo[k].clone()));
            shi.push(b.min(hi[k].clone()));
        }
        if (0..n).all(|k| slo[k] < shi[k]) {
            if let (Decision::Yes, Some(c), _) = certify_parts(
                &parts(system, |c| exact_cell(system, c), &slo, &shi)?,
                &slo,
                &shi,
            )? {
                return Ok((slo, shi, c));
            }
        }
        rho *= 16.0;
    }
    Ok((lo, hi, certificate))
}
