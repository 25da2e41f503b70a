//! FFD proofs: the two exact Jacobian routes agree coefficient for coefficient, and
//! undeformed lattices have `det J ≡ 1`.

use super::{Lcg, ProofOutcome, Shard, Tally};
use crate::bernstein::Bernstein;
use crate::ffd::jacobian::{
    cell_point, jacobian_cell_scaled, jacobian_cells_morken, jacobian_in_cell,
};
use crate::ffd::{Basis, Lattice};
use crate::num::{rational_to_string, Rational};
use num_bigint::BigInt;
use num_traits::One;

/// The lattice shapes enumerated: orders 2–5 (uniform and mixed) with one to three cells per
/// axis, B-spline and Bézier.
fn shapes() -> Vec<(Basis, [usize; 3], [usize; 3])> {
    let mut v = Vec::new();
    for o in 2..=5 {
        v.push((Basis::Bezier, [o, o, o], [1, 1, 1]));
        v.push((Basis::Bspline, [o, o, o], [1, 1, 1]));
        v.push((Basis::Bspline, [o, o, o], [2, 1, 1]));
    }
    for (order, cells) in [
        ([2, 3, 4], [2, 2, 1]),
        ([3, 3, 3], [2, 2, 2]),
        ([4, 4, 4], [2, 2, 1]),
        ([5, 3, 2], [1, 2, 3]),
        ([4, 2, 5], [1, 1, 2]),
        ([3, 4, 3], [3, 1, 1]),
    ] {
        v.push((Basis::Bspline, order, cells));
    }
    v.push((Basis::Bezier, [2, 4, 5], [1, 1, 1]));
    v
}

/// A lattice perturbed from the identity by random rationals (numerators ≤ 6, denominators
/// ≤ 16, scaled by ¼).
fn random_lattice(rng: &mut Lcg, basis: Basis, order: [usize; 3], cells: [usize; 3]) -> Lattice {
    let id = Lattice::identity(basis, order, cells).expect("valid shape");
    let quarter = Rational::new(BigInt::one(), BigInt::from(4));
    let delta: Vec<[Rational; 3]> = (0..id.points().len())
        .map(|_| [0, 1, 2].map(|_| rng.rational(6, 16) * &quarter))
        .collect();
    id.displaced(&delta).expect("same count")
}

/// Mørken route (eq. 8 then knot insertion) versus per-cell Bernstein products in integers,
/// on every cell of random lattices; plus `det J` at random points of each cell from the
/// derivative splines versus the Bézier form's value there.
pub fn jacobian_routes(shard: Shard) -> ProofOutcome {
    let shapes = shapes();
    let mut t = Tally::new(
        "ffd.jacobian-routes",
        &format!(
            "{} lattice shapes (orders 2–5, 1–3 cells per axis, B-spline and Bézier) × 2 random \
             perturbations, every cell: Mørken-route Bézier coefficients = per-cell product \
             coefficients, and det J at 3 random points per cell = Bézier value",
            shapes.len()
        ),
        shard,
    );
    for (s, (basis, order, cells)) in shapes.into_iter().enumerate() {
        for k in 0..2u64 {
            // One part per lattice, with its own generator.
            let part = 2 * s as u64 + k;
            if !t.owns(part) {
                continue;
            }
            let mut rng = Lcg::new(0xFFD + part);
            let l = random_lattice(&mut rng, basis, order, cells);
            let morken = match jacobian_cells_morken(&l) {
                Ok(m) => m,
                Err(e) => {
                    t.check(false, || {
                        format!("{order:?}/{cells:?}: Mørken route failed: {e}")
                    });
                    continue;
                }
            };
            let nets = l.bezier_nets();
            for (c, (m, net)) in morken.iter().zip(&nets).enumerate() {
                let b = jacobian_cell_scaled(net).map(|s| s.to_rational());
                t.check(b.as_ref() == Ok(m), || {
                    format!("{order:?}/{cells:?} cell {c}: routes differ")
                });
                for _ in 0..3 {
                    let local: Vec<Rational> = (0..3)
                        .map(|_| Rational::new(BigInt::from(rng.next() % 97), BigInt::from(96)))
                        .collect();
                    let at = cell_point(l.cell_index(c), &local);
                    let direct = jacobian_in_cell(&l, l.cell_index(c), &at);
                    let bez: Result<Rational, _> = Bernstein::eval(m, &local);
                    let same = matches!((&direct, &bez), (Ok(a), Ok(b)) if a == b);
                    t.check(same, || {
                        format!(
                            "{order:?}/{cells:?} cell {c} at {:?}: det J {:?} vs Bézier {:?}",
                            at.iter().map(rational_to_string).collect::<Vec<_>>(),
                            direct.map(|r| rational_to_string(&r)),
                            bez.map(|r| rational_to_string(&r))
                        )
                    });
                }
            }
        }
    }
    t.finish()
}

/// Undeformed lattices (points at the Greville abscissae) have `det J ≡ 1`: every Bézier
/// coefficient of every cell is exactly 1, by both routes.
pub fn identity_unit_jacobian(shard: Shard) -> ProofOutcome {
    let mut t = Tally::new(
        "ffd.identity-unit-jacobian",
        "every shape with orders 2–4 per axis (27 order triples) × cells 1–2 per axis (8) as \
         B-spline, and the 27 Bézier order triples: every Bézier coefficient of det J is 1 \
         by the Mørken route and by per-cell products",
        shard,
    );
    let one = Rational::one();
    let mut shapes = Vec::new();
    for l in 2..=4 {
        for m in 2..=4 {
            for n in 2..=4 {
                shapes.push((Basis::Bezier, [l, m, n], [1, 1, 1]));
                for a in 1..=2 {
                    for b in 1..=2 {
                        for c in 1..=2 {
                            shapes.push((Basis::Bspline, [l, m, n], [a, b, c]));
                        }
                    }
                }
            }
        }
    }
    for (part, (basis, order, cells)) in shapes.into_iter().enumerate() {
        if !t.owns(part as u64) {
            continue;
        }
        let l = Lattice::identity(basis, order, cells).expect("valid shape");
        let nets = l.bezier_nets();
        let morken = jacobian_cells_morken(&l);
        for (c, net) in nets.iter().enumerate() {
            let per_cell = jacobian_cell_scaled(net).map(|s| s.to_rational());
            let ok_cell = per_cell.is_ok_and(|p| p.coeffs().iter().all(|x| x == &one));
            let ok_morken = morken
                .as_ref()
                .is_ok_and(|m| m[c].coeffs().iter().all(|x| x == &one));
            t.check(ok_cell && ok_morken, || {
                format!("{basis:?} {order:?}/{cells:?} cell {c}: det J is not identically 1")
            });
        }
    }
    t.finish()
}
