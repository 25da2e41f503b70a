use geocert::bernstein::Limits;
use geocert::ffd::*;
use std::time::Instant;
fn main() {
    let cells =
        geocert::report::ffd::perturbed_lattices(2026, 600, Basis::Bezier, [4, 4, 4], [1, 1, 1]);
    let limits = Limits {
        max_depth: 10,
        max_boxes: 20_000,
        time_limit: Some(std::time::Duration::from_secs(5)),
    };
    let mut v: Vec<(f64, usize, String, usize)> = cells
        .iter()
        .enumerate()
        .map(|(i, l)| {
            let t = Instant::now();
            let r = check_injectivity(
                l,
                CheckOptions {
                    path: TestPath::Fast,
                    limits,
                },
            )
            .unwrap();
            (
                t.elapsed().as_secs_f64() * 1e3,
                i,
                r.verdict.name().to_string(),
                r.leaves,
            )
        })
        .collect();
    let total: f64 = v.iter().map(|x| x.0).sum();
    v.sort_by(|a, b| b.0.partial_cmp(&a.0).unwrap());
    println!("total {total:.1} ms");
    for x in v.iter().take(15) {
        println!("{:.2} ms cell {} {} leaves {}", x.0, x.1, x.2, x.3);
    }
    let inj: Vec<f64> = v
        .iter()
        .filter(|x| x.2 == "injective")
        .map(|x| x.0)
        .collect();
    let not: Vec<f64> = v
        .iter()
        .filter(|x| x.2 != "injective")
        .map(|x| x.0)
        .collect();
    println!(
        "injective sum {:.1} n {}, not sum {:.1} n {}",
        inj.iter().sum::<f64>(),
        inj.len(),
        not.iter().sum::<f64>(),
        not.len()
    );
}
