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
    let l = id.displaced(&delta).unwrap();
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
    let pts = l.points_f64();
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
    let bs = Lattice::identity(Basis::Bspline, [4, 4, 4], [3, 3, 3]).unwrap();
    let t = Instant::now();
    let m = jacobian_cells_morken(&bs).unwrap();
    println!("morken 27 cells {:?} {}", t.elapsed(), m.len());
    let t = Instant::now();
    let n = bs.bezier_nets();
    println!("nets 27 cells {:?}", t.elapsed());
    let _ = (n, BigInt::from(1));
}
