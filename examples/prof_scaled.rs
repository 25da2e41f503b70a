fn main() {
    let cells = geocert::report::ffd::perturbed_lattices(
        2026,
        20,
        geocert::ffd::Basis::Bezier,
        [4, 4, 4],
        [1, 1, 1],
    );
    let t = std::time::Instant::now();
    for l in &cells {
        for net in l.bezier_nets() {
            std::hint::black_box(geocert::ffd::jacobian::jacobian_cell_scaled(&net).unwrap());
        }
    }
    println!("{:?} per cell", t.elapsed() / 20);
    let t = std::time::Instant::now();
    for l in &cells {
        std::hint::black_box(l.bezier_nets());
    }
    println!("nets {:?} per cell", t.elapsed() / 20);
}
