fn main() {
    let t = std::time::Instant::now();
    let l = geocert::ffd::Lattice::identity(geocert::ffd::Basis::Bspline, [4, 4, 4], [2, 2, 2])
        .unwrap();
    let s = geocert::ffd::jacobian::jacobian_spline(&l).unwrap();
    println!("spline {:?}", t.elapsed());
    let c = s.bezier_cells_by_insertion().unwrap();
    println!("cells {:?} {}", t.elapsed(), c.len());
}
