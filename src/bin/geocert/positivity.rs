//! `geocert positivity` and `geocert verify-cert`: the Bernstein positivity prover.

use crate::out::{choice, pretty, read, status, write};
use geocert::bernstein::WitnessValue;
use geocert::bernstein::{
    certificate_for, poly_from_json, verify_certificate_file, CertificateFile,
};
use geocert::bernstein::{prove_positive, Limits, PositivityOptions, PositivityVerdict};
use geocert::num::rational_to_string;
use geocert::Path;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub(crate) struct Args {
    /// `{"degrees": [..], "coeffs": [..]}`; coefficients are JSON numbers (exact f64) or "p/q" strings.
    file: PathBuf,
    #[arg(long, default_value_t = Path::Filtered, value_parser = choice::<Path>(Path::NAMES))]
    path: Path,
    #[arg(long, default_value_t = 12)]
    max_depth: u32,
    /// Write the certificate here (only for decided verdicts).
    #[arg(long)]
    cert: Option<PathBuf>,
    #[arg(long)]
    json: bool,
}

#[derive(clap::Args)]
pub(crate) struct VerifyArgs {
    file: PathBuf,
}

pub(crate) fn run(a: Args) -> Result<ExitCode, String> {
    let file = &a.file;
    let value: serde_json::Value = serde_json::from_str(&read(file)?)
        .map_err(|e| format!("{}: not valid JSON: {e}", file.display()))?;
    let p = poly_from_json(&value).map_err(|e| format!("{}: {e}", file.display()))?;
    let opts = PositivityOptions::new()
        .with_path(a.path)
        .with_limits(Limits::new().with_max_depth(a.max_depth));
    let verdict = prove_positive(&p, &opts).map_err(|e| format!("{}: {e}", file.display()))?;
    let (name, detail) = match &verdict {
        PositivityVerdict::Positive { leaves, .. } => {
            ("positive", serde_json::json!({"leaves": leaves.len()}))
        }
        PositivityVerdict::NotPositive { witness, value } => (
            "not_positive",
            serde_json::json!({
                "witness": witness.iter().map(rational_to_string).collect::<Vec<_>>(),
                "value": match value {
                    WitnessValue::Exact(r) => rational_to_string(r),
                    WitnessValue::AtMost(b) => format!("<= {b:e}"),
                },
            }),
        ),
        PositivityVerdict::Undecided {
            limit,
            at,
            lower_bound,
        } => (
            "undecided",
            serde_json::json!({"limit": limit, "box": at, "lower_bound": lower_bound}),
        ),
        PositivityVerdict::Uncertain { boxes, .. } => (
            "uncertain",
            serde_json::json!({"uncertain_boxes": boxes.len()}),
        ),
    };
    if let Some(cp) = &a.cert {
        match certificate_for(&p, &verdict) {
            Some(c) => write(cp, pretty(&c)?)?,
            None => eprintln!(
                "note: a {name} verdict has no certificate; nothing written to {}",
                cp.display()
            ),
        }
    }
    if a.json {
        let mut v = serde_json::json!({"verdict": name});
        if let (Some(o), Some(d)) = (v.as_object_mut(), detail.as_object()) {
            for (k, x) in d {
                o.insert(k.clone(), x.clone());
            }
        }
        println!("{v}");
    } else {
        println!("{name}: {detail}");
    }
    Ok(ExitCode::SUCCESS)
}

pub(crate) fn verify(a: VerifyArgs) -> Result<ExitCode, String> {
    let file = &a.file;
    let c: CertificateFile = serde_json::from_str(&read(file)?)
        .map_err(|e| format!("{}: not a certificate: {e}", file.display()))?;
    let outcome = verify_certificate_file(&c);
    match &outcome {
        Ok(msg) => println!("valid: {msg}"),
        Err(e) => println!("invalid: {e}"),
    }
    Ok(status(outcome.is_ok()))
}
