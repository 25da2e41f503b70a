//! Turns run results into the published Markdown reports in `reports/`.
//!
//! Every number in a report comes from the run that writes it; each report names the command,
//! commit, date and machine that produced it. Reports are never edited by hand.

pub mod campaign;
pub mod decimate;
pub mod decimate_surfaces;
pub mod diamond;
pub mod ffd;
pub mod ffd_dmffd;
pub mod ffd_markdown;
pub mod mc_fe;
pub mod mc_grid;
pub mod mc_markdown;
pub mod mc_topology;
pub mod solve;
pub mod solve_curves;
pub mod solve_silhouette;
pub mod sweep;
pub mod sweep_degenerate;

use crate::proofs::ProofOutcome;
use campaign::{KernelCampaign, SubdivisionTiming};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A peer script's JSON report from its finished process: the last line of its stderr as the
/// error when it failed, or the parse error.
pub(crate) fn peer_json(
    out: std::io::Result<std::process::Output>,
) -> Result<serde_json::Value, String> {
    let out = out.map_err(|e| e.to_string())?;
    if !out.status.success() {
        return Err(String::from_utf8_lossy(&out.stderr)
            .lines()
            .last()
            .unwrap_or("failed")
            .to_string());
    }
    serde_json::from_slice(&out.stdout).map_err(|e| e.to_string())
}

/// Who, what and where produced a report.
#[derive(Clone, Debug, serde::Serialize)]
pub struct RunMeta {
    pub command: String,
    pub commit: String,
    pub date_utc: String,
    pub machine: String,
}

impl RunMeta {
    /// Reads the command line, `git rev-parse HEAD`, the clock and `/proc` (best effort).
    pub fn collect() -> RunMeta {
        let command = std::env::args().collect::<Vec<_>>().join(" ");
        let commit = std::process::Command::new("git")
            .args(["rev-parse", "--short=12", "HEAD"])
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
            .unwrap_or_else(|| "unknown".into());
        let dirty = std::process::Command::new("git")
            .args(["status", "--porcelain", "--untracked-files=no"])
            .output()
            .ok()
            .map(|o| !o.stdout.is_empty())
            .unwrap_or(false);
        let commit = if dirty {
            format!("{commit} (with uncommitted changes)")
        } else {
            commit
        };
        let cpu = std::fs::read_to_string("/proc/cpuinfo")
            .ok()
            .and_then(|s| {
                s.lines()
                    .find(|l| l.starts_with("model name"))
                    .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
            })
            .unwrap_or_else(|| "unknown CPU".into());
        let cores = std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1);
        let mem = std::fs::read_to_string("/proc/meminfo")
            .ok()
            .and_then(|s| {
                s.lines()
                    .next()
                    .map(|l| l.split_whitespace().nth(1).unwrap_or("0").to_string())
            })
            .and_then(|kb| kb.parse::<u64>().ok())
            .map(|kb| format!("{:.0} GiB", kb as f64 / 1048576.0))
            .unwrap_or_else(|| "unknown memory".into());
        RunMeta {
            command,
            commit,
            date_utc: utc_now(),
            machine: format!(
                "{cpu}, {cores} cores, {mem}, {} {}",
                std::env::consts::OS,
                std::env::consts::ARCH
            ),
        }
    }

    fn markdown(&self) -> String {
        format!(
            "| | |\n|---|---|\n| command | `{}` |\n| commit | `{}` |\n| date (UTC) | {} |\n| machine | {} |\n",
            self.command, self.commit, self.date_utc, self.machine
        )
    }
}

/// The current UTC time as `YYYY-MM-DD HH:MM:SS` (civil-from-days, H. Hinnant's algorithm).
pub fn utc_now() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0) as i64;
    let (days, rem) = (secs.div_euclid(86400), secs.rem_euclid(86400));
    let z = days + 719468;
    let era = z.div_euclid(146097);
    let doe = z - era * 146097;
    let yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + if m <= 2 { 1 } else { 0 };
    format!(
        "{y:04}-{m:02}-{d:02} {:02}:{:02}:{:02}",
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
}

/// Writes `reports/kernel.md`; returns its path.
pub fn write_kernel_report(
    dir: &Path,
    meta: &RunMeta,
    proofs: &[ProofOutcome],
    campaign: &KernelCampaign,
    timing: &SubdivisionTiming,
) -> std::io::Result<PathBuf> {
    std::fs::create_dir_all(dir)?;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Kernel correctness report\n\nGenerated by `geocert prove`; do not edit.\n"
    );
    s.push_str(&meta.markdown());
    write_proofs_section(&mut s, proofs);
    let c = campaign;
    let _ = writeln!(
        s,
        "\n## Exact vs fast positivity campaign\n\n{} random trivariate Bernstein polynomials of degree {:?} \
         (seed {}; coefficients a positive offset plus noise, a quarter of them with coefficients within 2⁻⁴⁰…2⁻⁵⁰ of zero), \
         subdivision depth ≤ {}.\n",
        c.cases, c.degrees, c.seed, c.max_depth
    );
    let _ = writeln!(s, "| outcome | count |\n|---|---:|");
    for (k, v) in [
        (
            "exact: positive (certificate re-verified)",
            c.exact_positive,
        ),
        (
            "exact: not positive (witness re-verified)",
            c.exact_not_positive,
        ),
        ("exact: undecided (depth limit)", c.exact_undecided),
        ("fast: certified positive", c.fast_positive),
        ("fast: certified not positive", c.fast_not_positive),
        ("fast: uncertain (handed to exact)", c.fast_uncertain),
        ("fast: undecided", c.fast_undecided),
        ("filtered verdict = exact verdict", c.filtered_agrees),
        (
            "**certified fast verdicts contradicting exact**",
            c.contradictions,
        ),
        (
            "certificates refused by the checker",
            c.certificates_refused,
        ),
    ] {
        let _ = writeln!(s, "| {k} | {v} |");
    }
    let _ = writeln!(
        s,
        "\nMedian time per polynomial: exact {:.3} ms, fast {:.3} ms, filtered {:.3} ms.",
        c.exact_ms_median, c.fast_ms_median, c.filtered_ms_median
    );
    let t = timing;
    let _ = writeln!(
        s,
        "\n## Subdivision: exact representations against each other\n\n\
         Full binary subdivision tree of depth {} at ½ on a degree-{} univariate Bernstein polynomial \
         with random rational coefficients ({} splits), median of {} runs.\n\n\
         | representation | median ms | ratio to BigRational |\n|---|---:|---:|\n\
         | BigRational (gcd-normalised) | {:.3} | 1 |\n\
         | sign-only integers over a shared denominator | {:.3} | {:.1}× faster |\n\
         | certified f64 | {:.4} | {:.0}× faster |\n",
        t.depth,
        t.degree,
        (1usize << t.depth) - 1,
        t.runs,
        t.rational_ms,
        t.scaled_ms,
        t.rational_ms / t.scaled_ms,
        t.fast_ms,
        t.rational_ms / t.fast_ms
    );
    let _ = writeln!(
        s,
        "Leaf sign counts of the BigRational and integer trees agree: {}.\n",
        t.leaf_signs_agree
    );
    let _ = writeln!(s, "Criterion benches (`cargo bench --bench subdivision`) measure the same and the trivariate (8,8,8) case.");
    let kernel = dir.join("kernel.md");
    std::fs::write(&kernel, s)?;
    Ok(kernel)
}

/// True when the kernel results show no failure.
pub fn kernel_ok(proofs: &[ProofOutcome], c: &KernelCampaign, t: &SubdivisionTiming) -> bool {
    proofs.iter().all(|p| p.ok())
        && c.contradictions == 0
        && c.certificates_refused == 0
        && t.leaf_signs_agree
}

/// One line of the reports index.
pub struct IndexEntry {
    pub file: String,
    pub what: String,
    pub ok: bool,
}

/// Writes `reports/README.md`, the index of the reports of this run.
pub fn write_index(dir: &Path, meta: &RunMeta, entries: &[IndexEntry]) -> std::io::Result<PathBuf> {
    let mut index = String::new();
    let _ = writeln!(
        index,
        "# geocert reports\n\nGenerated by `geocert prove`; do not edit.\n"
    );
    index.push_str(&meta.markdown());
    let _ = writeln!(index);
    for e in entries {
        let _ = writeln!(
            index,
            "- [{}]({}) — {}: {}.",
            e.file,
            e.file,
            e.what,
            if e.ok {
                "all passed"
            } else {
                "FAILURES (see report)"
            }
        );
    }
    let readme = dir.join("README.md");
    std::fs::write(&readme, index)?;
    Ok(readme)
}

/// The "Exhaustive proofs" section every report carries: one row per proof, then the first
/// failures of any that failed.
pub fn write_proofs_section(s: &mut String, proofs: &[crate::proofs::ProofOutcome]) {
    let _ = writeln!(
        s,
        "\n## Exhaustive proofs\n\n| proof | enumerated | cases | passed | seconds |\n|---|---|---:|---:|---:|"
    );
    for p in proofs {
        let _ = writeln!(
            s,
            "| `{}` | {} | {} | {} | {:.2} |",
            p.name, p.enumerated, p.cases, p.passed, p.seconds
        );
    }
    for p in proofs.iter().filter(|p| !p.failures.is_empty()) {
        let _ = writeln!(s, "\nFailures of `{}`:\n", p.name);
        for f in &p.failures {
            let _ = writeln!(s, "- {f}");
        }
    }
}
