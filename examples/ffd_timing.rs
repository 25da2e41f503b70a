use geocert::bernstein::Limits;
use geocert::ffd::fast::*;
use geocert::ffd::jacobian::*;
use geocert::ffd::*;
use geocert::num::Rational;
use num_bigint::BigInt;
use std::time::Instant;

fn main() {
    let id = Lattice::identity(Basis::Bezier, [4, 4, 4], [1, 1, 1]).unwrap();
    let mut x = 7u64;
    let delta: Vec<[Rational; 3]> = (0..64)
        .map(|_| {
            [0, 1, 2].map(|_| {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let v = ((x >> 33) % 2001) as i64 - 1000;
                Rational::from_float(v as f64 * 0.15 / 1000.0).unwrap()
            })
        })
        .collect();
    let pts: Vec<[Rational; 3]> = id
        .points()
        .iter()
        .zip(&delta)
        .map(|(p, d)| {
            [0, 1, 2].map(|a| {
                Rational::from_float(
                    geocert::num::rational_to_f64(&p[a]) + geocert::num::rational_to_f64(&d[a]),
                )
                .unwrap()
            })
        })
        .collect();
    let l = Lattice::new(Basis::Bezier, [4, 4, 4], [1, 1, 1], pts).unwrap();
    let nets = l.bezier_nets();
    let t = Instant::now();
    let m = jacobian_cells_morken(&l).unwrap();
    println!("morken {:?}", t.elapsed());
    let t = Instant::now();
    let b = jacobian_cell_bezier(&nets[0]).unwrap();
    println!("bezier rational {:?}", t.elapsed());
    let t = Instant::now();
    let s = jacobian_cell_scaled(&nets[0]).unwrap();
    println!("scaled {:?}", t.elapsed());
    assert_eq!(m[0], b);
    assert_eq!(s.to_rational(), b);
    let pts = l.points_f64().unwrap().to_vec();
    let mut ws = JacobianWorkspace::default();
    let t = Instant::now();
    for _ in 0..1000 {
        jacobian_cell_fast(&pts, [3, 3, 3], 0.0, &mut ws).unwrap();
    }
    println!("fast x1000 {:?}", t.elapsed());
    for path in [TestPath::Exact, TestPath::Fast, TestPath::Filtered] {
        let t = Instant::now();
        let r = check_injectivity(
            &l,
            CheckOptions {
                path,
                limits: Limits::default(),
            },
        )
        .unwrap();
        println!(
            "{path:?} {} leaves {} {:?}",
            r.verdict.name(),
            r.leaves,
            t.elapsed()
        );
    }
    use geocert::ffd::sufficient::*;
    let t = Instant::now();
    for _ in 0..10000 {
        conic_test_fast(&l, ConicOptions::default());
    }
    println!(
        "conic fast x10000 {:?} {:?}",
        t.elapsed(),
        conic_test_fast(&l, ConicOptions::default())
    );
    let t = Instant::now();
    println!(
        "conic exact {:?} {:?}",
        conic_test_exact(&l, ConicOptions::default()),
        t.elapsed()
    );
    let t = Instant::now();
    println!(
        "phi exact {:?} {:?}",
        phi_test_exact(&l, Scope::PerCell),
        t.elapsed()
    );
    let t = Instant::now();
    println!(
        "phi fast {:?} {:?}",
        phi_test_fast(&l, Scope::PerCell),
        t.elapsed()
    );
    let t = Instant::now();
    println!(
        "bez exact {:?} {:?}",
        bezier_coefficient_test_exact(&l),
        t.elapsed()
    );
    let t = Instant::now();
    println!(
        "conic sub2 {:?} {:?}",
        conic_test_exact(
            &l,
            ConicOptions {
                scope: Scope::PerCell,
                subdivision_depth: 2
            }
        ),
        t.elapsed()
    );
    let t = Instant::now();
    println!(
        "conic sub2 fast {:?} {:?}",
        conic_test_fast(
            &l,
            ConicOptions {
                scope: Scope::PerCell,
                subdivision_depth: 2
            }
        ),
        t.elapsed()
    );
    let bs = Lattice::identity(Basis::Bspline, [4, 4, 4], [3, 3, 3]).unwrap();
    let t = Instant::now();
    let m = jacobian_cells_morken(&bs).unwrap();
    println!("morken 27 cells {:?} {}", t.elapsed(), m.len());
    let t = Instant::now();
    let n = bs.bezier_nets();
    println!("nets 27 cells {:?}", t.elapsed());
    let _ = (n, BigInt::from(1));
}
