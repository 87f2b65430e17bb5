//! Argument blocks several commands share, flattened into their `Args`
//! with `#[command(flatten)]`. They carry no doc comment: clap would take
//! it for the command's own description.

use std::path::{Path, PathBuf};

// The lab commands' report: where it goes, or none.
#[derive(clap::Args, Debug, Clone)]
pub struct ReportArgs {
    /// Write the report (Markdown, its plots as PNG and SVG) in this directory
    /// [default: report-COMMAND-RECORDING in the current directory].
    #[arg(long, value_parser = report_dir)]
    report: Option<PathBuf>,
    /// Write no report.
    #[arg(long, conflicts_with = "report")]
    no_report: bool,
}

/// `--report` names a directory: a file name (`report.md`) is refused at
/// once, before the work, rather than made into a directory after it.
fn report_dir(s: &str) -> Result<PathBuf, String> {
    let p = PathBuf::from(s);
    let ext = p
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some(e @ ("md" | "html" | "txt" | "png" | "svg" | "json" | "csv" | "pdf")) => Err(format!(
            "--report takes a directory (the report is written there as Markdown with its plots as PNG and SVG), not a .{e} file: try --report {}",
            p.with_extension("").display()
        )),
        _ => Ok(p),
    }
}

impl ReportArgs {
    /// The report's directory for `command` on `recording`, or none with
    /// `--no-report`.
    pub fn dir(&self, command: &str, recording: &Path) -> Option<PathBuf> {
        if self.no_report {
            return None;
        }
        if let Some(d) = &self.report {
            return Some(d.clone());
        }
        let name = softgrip_lab::report::recording_name(recording);
        Some(PathBuf::from(format!("report-{command}-{name}")))
    }

    /// The report's directory for `command` on several recordings: `--report`, or
    /// report-COMMAND-NAME1-NAME2-... in the current directory; none with `--no-report`.
    pub fn dir_many(&self, command: &str, recordings: &[PathBuf]) -> Option<PathBuf> {
        match recordings {
            [one] => self.dir(command, one),
            _ if self.no_report => None,
            _ => Some(self.report.clone().unwrap_or_else(|| {
                let names: Vec<String> = recordings
                    .iter()
                    .map(|r| softgrip_lab::report::recording_name(r))
                    .collect();
                PathBuf::from(format!("report-{command}-{}", names.join("-")))
            })),
        }
    }
}

// How many simulations the searching commands run at once.
#[derive(clap::Args, Debug, Clone)]
pub struct WorkersArgs {
    /// Simulations at once (0: one per core).
    #[arg(long, default_value_t = 0)]
    pub workers: usize,
}

// How a quasi-static load is brought to rest.
#[derive(clap::Args, Debug, Clone, Copy)]
pub struct SettleArgs {
    /// How each quasi-static load reaches rest: `dynamic` runs time steps until nothing
    /// moves; `static` solves for the equilibrium by Newton's method (docs/design/equilibrium.md).
    /// Default: the scene's `[simulation] settle` (static unless it says otherwise).
    #[arg(long, value_enum)]
    pub settle: Option<SettleMode>,
}

#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum SettleMode {
    Static,
    Dynamic,
}

impl SettleMode {
    pub fn replay(self) -> softgrip_core::scene::Settle {
        match self {
            SettleMode::Static => softgrip_core::scene::Settle::Static,
            SettleMode::Dynamic => softgrip_core::scene::Settle::Dynamic,
        }
    }
}

/// A number that is one: NaN and infinities are refused where they are typed.
pub fn finite(s: &str) -> Result<f64, String> {
    let x: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("{s:?} is not a number"))?;
    if x.is_finite() {
        Ok(x)
    } else {
        Err(format!("{s} is not a finite number"))
    }
}

/// A finite number above zero (a duration, a rate, a length, a tolerance).
pub fn positive(s: &str) -> Result<f64, String> {
    let x = finite(s)?;
    if x > 0.0 {
        Ok(x)
    } else {
        Err(format!("{s}: must be greater than 0"))
    }
}

/// A finite number, zero or above (a time to start at, a noise level).
pub fn non_negative(s: &str) -> Result<f64, String> {
    let x = finite(s)?;
    if x >= 0.0 {
        Ok(x)
    } else {
        Err(format!("{s}: must be 0 or more"))
    }
}

/// A seed, decimal or hexadecimal with `0x` (as reports print them; `_` allowed).
pub fn seed(s: &str) -> Result<u64, String> {
    let t = s.trim().replace('_', "");
    let parsed = match t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
        Some(hex) => u64::from_str_radix(hex, 16),
        None => t.parse(),
    };
    parsed.map_err(|_| format!("{s}: give a whole number from 0 to 2^64-1, decimal or 0x-hex"))
}

/// A value as a user would type it, to six significant digits: plain between 1e-3 and 1e6, with
/// an exponent outside (a sweep's `dt = 1e-9` printed with six decimals read `0.000000`).
pub fn number(v: f64) -> String {
    let v: f64 = format!("{v:.5e}").parse().unwrap_or(v);
    if v == 0.0 || (1e-3..1e6).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn seeds_read_as_reports_print_them() {
        assert_eq!(super::seed("0x9b3e77a04d12c865"), Ok(0x9b3e_77a0_4d12_c865));
        assert_eq!(
            super::seed("0x5eed_2f71_09c4_a1d3"),
            Ok(0x5eed_2f71_09c4_a1d3)
        );
        assert_eq!(super::seed("17"), Ok(17));
        assert!(super::seed("-1").is_err());
        assert!(super::seed("0xg").is_err());
    }

    #[test]
    fn a_number_keeps_six_significant_digits_at_any_scale() {
        use super::number;
        assert_eq!(number(1e-9), "1e-9");
        assert_eq!(number(1e-3), "0.001");
        assert_eq!(number(0.1 + 0.2), "0.3");
        assert_eq!(number(2.5e7), "2.5e7");
        assert_eq!(number(-123.4567891), "-123.457");
        assert_eq!(number(0.0), "0");
    }
}
