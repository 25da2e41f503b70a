//! Mørken products: the exact B-spline form of a product of splines.
//!
//! For splines `f_1 … f_r` of degrees `d_1 … d_r` on a common domain, `h = Π f_i` has degree
//! `D = Σ d_i`. A degree-`d` spline is `C^{d−m}` at a knot of multiplicity `m`, so at an interior
//! breakpoint `z` with multiplicities `m_i(z)` (0 if absent) the product is `C^{min_i(d_i − m_i)}`
//! and gets multiplicity `D − min_i (d_i − m_i)` (capped at `D+1`); the ends are clamped (`D+1`).
//! (K. Mørken, "Some identities for products and degree raising of splines", Constr. Approx. 7,
//! 1991.) Coefficients come from the blossom identity: `e_k = H(u_{k+1} … u_{k+D})` with
//! `H(y) = Σ_{S_1⊔…⊔S_r, |S_i| = d_i} Π F_i(y_{S_i}) / (D! / Π d_i!)`, evaluated on any non-empty
//! interval `[u_j, u_{j+1})`, `k ≤ j ≤ k+D`. Arguments are grouped as a multiset: an allocation
//! `a_{i,s}` of the `n_s` copies of value `v_s` to factor `i` stands for
//! `Π_s n_s! / Π_i a_{i,s}!` of the subsets.

use super::{spline::lt, BsplineError, Spline};
use crate::num::Field;
use std::collections::HashMap;

/// The product knot vector for factors of the given degrees and knot vectors (same domain).
pub fn product_knots<T: Field + PartialOrd>(
    factors: &[&Spline<T>],
) -> Result<Vec<T>, BsplineError> {
    let first = factors.first().ok_or(BsplineError::NoFactors)?;
    let (a, b) = first.domain();
    for (i, f) in factors.iter().enumerate() {
        let (fa, fb) = f.domain();
        if fa != a || fb != b {
            return Err(BsplineError::DomainMismatch { factor: i });
        }
    }
    let big_d: usize = factors.iter().map(|f| f.degree()).sum();
    // Interior breakpoints of all factors.
    let mut zs: Vec<T> = Vec::new();
    for f in factors {
        for k in f.knots() {
            if lt(&a, k) && lt(k, &b) && !zs.contains(k) {
                zs.push(k.clone());
            }
        }
    }
    zs.sort_by(|x, y| x.partial_cmp(y).expect("finite knots"));
    let mut knots = vec![a.clone(); big_d + 1];
    for z in zs {
        let smooth = factors
            .iter()
            .map(|f| f.degree() as i64 - f.multiplicity(&z) as i64)
            .min()
            .expect("non-empty");
        let m = (big_d as i64 - smooth).clamp(0, big_d as i64 + 1) as usize;
        knots.extend(std::iter::repeat_n(z, m));
    }
    knots.extend(std::iter::repeat_n(b, big_d + 1));
    Ok(knots)
}

/// The product `Π f_i` as one spline on [`product_knots`], exactly (for exact `T`).
pub fn morken_product<T: Field + PartialOrd>(
    factors: &[&Spline<T>],
) -> Result<Spline<T>, BsplineError> {
    let knots = product_knots(factors)?;
    let big_d: usize = factors.iter().map(|f| f.degree()).sum();
    let n = knots.len() - big_d - 1;
    let degrees: Vec<usize> = factors.iter().map(|f| f.degree()).collect();
    let mut coeffs = Vec::with_capacity(n);
    for k in 0..n {
        let j = (k..=k + big_d)
            .find(|&j| lt(&knots[j], &knots[j + 1]))
            .expect("every B-spline has a non-empty interval");
        let mus: Vec<usize> = factors
            .iter()
            .map(|f| f.find_span(&knots[j]).expect("inside the domain"))
            .collect();
        let args = &knots[k + 1..k + big_d + 1];
        coeffs.push(product_blossom(factors, &mus, &degrees, args));
    }
    Spline::new(big_d, knots, coeffs)
}

/// `H(args)` for the product of `factors` on the interval whose factor spans are `mus`.
fn product_blossom<T: Field + PartialOrd>(
    factors: &[&Spline<T>],
    mus: &[usize],
    degrees: &[usize],
    args: &[T],
) -> T {
    // Distinct values and their counts.
    let mut values: Vec<T> = Vec::new();
    let mut counts: Vec<usize> = Vec::new();
    for y in args {
        match values.iter().position(|v| v == y) {
            Some(s) => counts[s] += 1,
            None => {
                values.push(y.clone());
                counts.push(1);
            }
        }
    }
    let r = factors.len();
    let big_d: usize = degrees.iter().sum();
    // Denominator D! / Π d_i!, numerators Π_s n_s! / Π a_{i,s}!: use exact factorial ratios.
    let fact = |n: usize| -> T { (1..=n).fold(T::one(), |acc, k| acc.mul_int(k as i64)) };
    let total = degrees
        .iter()
        .fold(fact(big_d), |acc, &d| acc.div(&fact(d)));
    let mut memo: Vec<HashMap<Vec<usize>, T>> = vec![HashMap::new(); r];
    let mut alloc = vec![vec![0usize; values.len()]; r];
    let mut sum = T::zero();
    let mut remaining_cap: Vec<usize> = degrees.to_vec();
    enumerate(
        0,
        0,
        &counts,
        &mut remaining_cap,
        &mut alloc,
        &mut |alloc: &[Vec<usize>]| {
            let mut weight = T::one();
            for (s, &ns) in counts.iter().enumerate() {
                weight = weight.mul(&fact(ns));
                for a in alloc.iter() {
                    weight = weight.div(&fact(a[s]));
                }
            }
            let mut term = weight;
            for (i, a) in alloc.iter().enumerate() {
                let f = memo[i]
                    .entry(a.clone())
                    .or_insert_with(|| {
                        let mut ys = Vec::with_capacity(degrees[i]);
                        for (s, &c) in a.iter().enumerate() {
                            ys.extend(std::iter::repeat_n(values[s].clone(), c));
                        }
                        factors[i].blossom(mus[i], &ys)
                    })
                    .clone();
                term = term.mul(&f);
            }
            sum = sum.add(&term);
        },
    );
    sum.div(&total)
}

/// Enumerates allocations of the copies of each value (`counts[s]`) to factors, factor `i`
/// receiving exactly `cap[i]` arguments in all.
fn enumerate<F: FnMut(&[Vec<usize>])>(
    s: usize,
    i: usize,
    counts: &[usize],
    cap: &mut [usize],
    alloc: &mut [Vec<usize>],
    visit: &mut F,
) {
    let r = alloc.len();
    if s == counts.len() {
        if cap.iter().all(|&c| c == 0) {
            visit(alloc);
        }
        return;
    }
    // Copies of value s already given to factors < i.
    let given: usize = (0..i).map(|f| alloc[f][s]).sum();
    let left = counts[s] - given;
    if i == r - 1 {
        if left <= cap[i] {
            alloc[i][s] = left;
            cap[i] -= left;
            enumerate(s + 1, 0, counts, cap, alloc, visit);
            cap[i] += left;
            alloc[i][s] = 0;
        }
        return;
    }
    for take in 0..=left.min(cap[i]) {
        alloc[i][s] = take;
        cap[i] -= take;
        enumerate(s, i + 1, counts, cap, alloc, visit);
        cap[i] += take;
    }
    alloc[i][s] = 0;
}
