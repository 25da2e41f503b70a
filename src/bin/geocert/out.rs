//! Shared plumbing of every subcommand: stdout that survives a closed pipe, file reading and
//! writing with the file named in every error, JSON output, exit codes, option parsers.

use std::path::Path;
use std::process::ExitCode;

/// Writes to stdout; exits with status 0 when the reader has gone (broken pipe), with
/// status 2 and a message on any other write error, instead of panicking as `println!` does.
pub(crate) fn say(args: std::fmt::Arguments) {
    use std::io::Write;
    if let Err(e) = std::io::stdout().lock().write_fmt(args) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: cannot write to stdout: {e}");
        std::process::exit(2);
    }
}

/// A file's text, or an error naming the file.
pub(crate) fn read(file: &Path) -> Result<String, String> {
    std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))
}

/// A file's bytes, or an error naming the file.
pub(crate) fn read_bytes(file: &Path) -> Result<Vec<u8>, String> {
    std::fs::read(file).map_err(|e| format!("{}: {e}", file.display()))
}

/// Writes a file, or an error naming it.
pub(crate) fn write(file: &Path, contents: impl AsRef<[u8]>) -> Result<(), String> {
    std::fs::write(file, contents).map_err(|e| format!("{}: {e}", file.display()))
}

/// Pretty-printed JSON of any serialisable value.
pub(crate) fn pretty(value: &impl serde::Serialize) -> Result<String, String> {
    serde_json::to_string_pretty(value).map_err(|e| e.to_string())
}

/// `--time-limit S` as a duration: a positive, finite number of seconds.
pub(crate) fn time_limit(seconds: Option<f64>) -> Result<Option<std::time::Duration>, String> {
    match seconds {
        Some(t) if !(t.is_finite() && t > 0.0) => Err(format!(
            "--time-limit must be a positive number of seconds, got {t}"
        )),
        t => Ok(t.map(std::time::Duration::from_secs_f64)),
    }
}

/// Exit code 0 when `ok`, else 1 (a refused certificate, a failed proof, a lost original).
pub(crate) fn status(ok: bool) -> ExitCode {
    if ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

/// A clap parser for a library option enum: lists its names in `--help` and parses through
/// the enum's own `FromStr`.
pub(crate) fn choice<T>(
    names: &'static [&'static str],
) -> impl clap::builder::TypedValueParser<Value = T>
where
    T: std::str::FromStr + Clone + Send + Sync + 'static,
    T::Err: std::fmt::Display,
{
    use clap::builder::TypedValueParser;
    clap::builder::PossibleValuesParser::new(names)
        .try_map(|s: String| s.parse::<T>().map_err(|e| e.to_string()))
}
