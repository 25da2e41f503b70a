//! The geocert command-line tool: parses arguments, calls the library, prints. One module per
//! family; `out` holds the plumbing they share. No algorithm lives here.

/// Like std's `println!`, but a closed stdout (`geocert … | head`) ends the process quietly.
macro_rules! println {
    () => { $crate::out::say(format_args!("\n")) };
    ($($arg:tt)*) => { $crate::out::say(format_args!("{}\n", format_args!($($arg)*))) };
}

/// Like std's `print!`, but a closed stdout ends the process quietly.
macro_rules! print {
    ($($arg:tt)*) => { $crate::out::say(format_args!($($arg)*)) };
}

mod decimate;
mod dmv;
mod ffd;
mod mc;
mod out;
mod positivity;
mod prove;
mod solve;
mod sweep;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "geocert",
    version,
    about = "Exact-arithmetic verification and reference engine for geometric algorithms"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run every exhaustive proof and the exact-vs-fast campaign; write reports/.
    Prove(prove::Args),
    /// Prove or refute p > 0 on the unit box for a Bernstein polynomial given as JSON.
    Positivity(positivity::Args),
    /// Re-check a positivity certificate independently.
    VerifyCert(positivity::VerifyArgs),
    /// Free-form deformation injectivity (Gain & Dodgson).
    #[command(subcommand)]
    Ffd(ffd::Command),
    /// Marching cubes (Wünsche & Lin): extraction, finite elements, table audit and export.
    #[command(subcommand)]
    Mc(mc::Command),
    /// Decimate a triangle mesh by node removal (Krivograd et al.) and write the history that
    /// restores it exactly. IN is a .ply/.obj/.stl/.vtk file, or `builtin:grid:SIDE` (a
    /// SIDE×SIDE height field like the paper's Table 1) or `builtin:plate` (the Kirsch plate
    /// of Fig. 9 with its von Mises field).
    Decimate(decimate::Args),
    /// Restore a decimated mesh with its history: undo the last N steps (all by default; the
    /// fit's moves, if any, are undone first).
    Undecimate(decimate::UndoArgs),
    /// How far a simplified surface (from any program) lies from its original: symmetric
    /// Hausdorff and RMS distances both ways in % of the bounding-box diagonal, and the
    /// triangles whose normals flipped.
    Deviation(decimate::DeviationArgs),
    /// Every root of n polynomial equations in n unknowns on a box, each certified (Miranda
    /// existence, diagonally dominant interval Jacobian for uniqueness); what cannot be
    /// certified comes back as clusters. `solve verify-cert CERT.json` re-checks certificates.
    Solve(solve::Args),
    /// Perspective silhouettes of swept volumes (Seong, Kim, Kim and Elber): the envelope's
    /// components with their types and certified t-extreme points.
    #[command(subcommand)]
    Sweep(sweep::Command),
    /// Diamond-based multiresolution volumes (Weiss & De Floriani): supercube-encoded partial
    /// DMVs, selective refinement with diamond or supercube fronts, adaptive isosurfaces.
    #[command(subcommand)]
    Dmv(dmv::Command),
}

/// Exit codes: 0 done (whatever the verdict), 1 a refused certificate / failed proof / inexact
/// restoration, 2 bad input or an I/O error (with a message on stderr).
fn main() -> ExitCode {
    let result = match Cli::parse().command {
        Command::Prove(a) => prove::run(a),
        Command::Positivity(a) => positivity::run(a),
        Command::VerifyCert(a) => positivity::verify(a),
        Command::Ffd(c) => ffd::run(c),
        Command::Mc(c) => mc::run(c),
        Command::Decimate(a) => decimate::run(a),
        Command::Undecimate(a) => decimate::undo(a),
        Command::Deviation(a) => decimate::deviation(a),
        Command::Solve(a) => solve::run(a),
        Command::Sweep(c) => sweep::run(c),
        Command::Dmv(c) => dmv::run(c),
    };
    result.unwrap_or_else(|e| {
        eprintln!("error: {e}");
        ExitCode::from(2)
    })
}
