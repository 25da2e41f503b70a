//! Marching cubes: extract the zero set of a gyroid sampled on an `N³` grid (default 48) on
//! the filtered and the exact path, and check that both give the same triangles.
//!
//! `cargo run --release --example mc_extract [N]`

use geocert::mc::grid::{extract, ExtractOptions, Volume};
use geocert::num::Rational;
use geocert::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: usize = std::env::args().nth(1).map_or(Ok(48), |s| s.parse())?;
    let k = 4.0 * std::f64::consts::PI / (n - 1) as f64;
    let values = (0..n * n * n)
        .map(|i| {
            let [x, y, z] = [i % n, i / n % n, i / (n * n)].map(|c| c as f64 * k);
            x.sin() * y.cos() + y.sin() * z.cos() + z.sin() * x.cos()
        })
        .collect();
    let volume = Volume::new([n, n, n], values)?;
    let iso = Rational::from_integer(0.into());
    let mut triangles = Vec::new();
    for path in [Path::Filtered, Path::Exact] {
        let clock = std::time::Instant::now();
        let (mesh, stats) = extract(&volume, &iso, &ExtractOptions::new().with_path(path))?;
        println!(
            "{path}: {} triangles, {} ambiguous faces, {} boundary edges (on the box), {:.3} s",
            mesh.triangles.len(),
            stats.ambiguous_faces,
            mesh.check_manifold()?,
            clock.elapsed().as_secs_f64()
        );
        triangles.push(mesh.triangles);
    }
    assert_eq!(
        triangles[0], triangles[1],
        "both paths give the same triangles"
    );
    Ok(())
}
