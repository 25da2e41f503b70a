//! Decimation: decimate a mesh file (or a built-in 200×200 height grid) to 2 % of its nodes,
//! replay every step with the independent exact checker, and undo it bit for bit.
//!
//! `cargo run --release --example decimate_undo [MESH.{ply,obj,stl,vtk}]`

use geocert::decimate::{check, data, decimate, Options, Stage, Target};
use geocert::mesh::Mesh;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mesh = match std::env::args().nth(1) {
        Some(file) => Mesh::read(std::path::Path::new(&file), None)?,
        None => data::height_grid(200),
    };
    let out = decimate(&mesh, &Options::new().with_target(Target::Keep(0.02)))?;
    println!(
        "{} → {} nodes in {:.3} s ({} steps)",
        out.stats.nodes_in,
        out.stats.nodes_out,
        out.stats.seconds,
        out.history.len()
    );
    let verified = check::verify(&mesh, &out.history, out.stats.projection_xy, 100)?;
    println!(
        "checker: {} steps, {} added triangles verified exactly",
        verified.steps, verified.triangles_checked
    );
    let mut stage = Stage::decimated(&out.mesh, &out.history)?;
    while stage.applied > 0 {
        stage.undo(&out.history)?;
    }
    assert_eq!(
        stage.to_mesh(),
        mesh,
        "undecimation restores the original bit for bit"
    );
    println!("undone: identical to the original");
    Ok(())
}
