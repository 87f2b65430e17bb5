//! Ranges, ticks and number formatting.

use super::error::PlotError;
use super::layout::{axis_inv, axis_t};
use super::style::TICK_PX;
use super::text::max_width;

/// A tick: its value in data units and its label.
#[derive(Debug, Clone)]
pub(super) struct Tick {
    pub(super) value: f64,
    pub(super) label: String,
}

/// The range to show for data spanning `lo..=hi`: 5 % margin on each side in
/// plotted (log) space, or a fixed widening when the data has no spread.
pub(super) fn padded_range(lo: f64, hi: f64, log: bool) -> (f64, f64) {
    let (a, b) = (axis_t(lo, log), axis_t(hi, log));
    let (a, b) = if degenerate(a, b) {
        let d = if log {
            0.5
        } else if a != 0.0 {
            a.abs() * 0.1
        } else {
            1.0
        };
        (a - d, b + d)
    } else {
        let m = 0.05 * (b - a);
        (a - m, b + m)
    };
    (axis_inv(a, log), axis_inv(b, log))
}

/// True when `a..b` is too narrow to divide into ticks.
pub(super) fn degenerate(a: f64, b: f64) -> bool {
    let spread = b - a;
    let divisible = spread.is_finite() && spread > 1e-9 * a.abs().max(b.abs());
    !divisible
}

/// The 1, 2 or 5 times a power of ten at or above `raw`.
pub fn nice_step(raw: f64) -> f64 {
    let e = raw.log10().floor();
    let p = 10f64.powf(e);
    let f = raw / p;
    let m = if f <= 1.0 + 1e-9 {
        1.0
    } else if f <= 2.0 + 1e-9 {
        2.0
    } else if f <= 5.0 + 1e-9 {
        5.0
    } else {
        10.0
    };
    m * p
}

/// The 1-2-5 step below `step`: 1 -> 0.5, 2 -> 1, 5 -> 2 (times a power of ten).
fn finer_step(step: f64) -> f64 {
    let p = 10f64.powf(step.log10().floor());
    let m = (step / p).round();
    if m <= 1.0 {
        0.5 * p
    } else if m <= 2.0 {
        p
    } else if m <= 5.0 {
        2.0 * p
    } else {
        5.0 * p
    }
}

/// `v` formatted compactly: scientific ("2.5e5", "1e-4") when `sci`, else
/// fixed; digits down to `resolution` (the smallest difference worth showing).
pub(super) fn format_number(v: f64, resolution: f64, sci: bool) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    let res = resolution.abs();
    if v == 0.0 || (res > 0.0 && v.abs() < res * 1e-6) {
        return "0".into();
    }
    let last_digit = if res > 0.0 && res.is_finite() {
        res.log10().floor() as i32
    } else {
        v.abs().log10().floor() as i32 - 3
    };
    let s = if sci {
        let mut e = v.abs().log10().floor() as i32;
        let decimals = (e - last_digit).clamp(0, 6) as usize;
        let mut m = format!("{:.*}", decimals, v / 10f64.powi(e));
        if m.trim_start_matches('-').starts_with("10") {
            e += 1;
            m = format!("{:.*}", decimals, v / 10f64.powi(e));
        }
        format!("{}e{e}", trim_zeros(&m))
    } else {
        let decimals = (-last_digit).clamp(0, 9) as usize;
        // Whole numbers keep only the digits that resolve: 31622.8 -> "31600".
        let v = if last_digit > 0 {
            let p = 10f64.powi(last_digit);
            (v / p).round() * p
        } else {
            v
        };
        trim_zeros(&format!("{v:.decimals$}"))
    };
    if s == "-0" { "0".into() } else { s }
}

/// "2.500" -> "2.5", "3.0" -> "3"; integers unchanged.
fn trim_zeros(s: &str) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s.to_string()
    }
}

/// Scientific notation when the largest magnitude is at least 1e5 or below 1e-3.
pub(super) fn wants_sci(largest: f64) -> bool {
    largest >= 1e5 || (largest > 0.0 && largest < 1e-3)
}

/// Scientific labels on a log axis whose values reach 1e4 or go below 0.01,
/// so a whole axis reads "1e3, 1e4, 1e5" rather than "1000, 10000, 1e5".
pub(super) fn log_wants_sci(values: &[f64]) -> bool {
    values.iter().any(|v| v.abs() >= 1e4 || v.abs() < 1e-2)
}

/// A compact label for one value on a log axis (3 significant digits).
pub(super) fn format_log_value(v: f64, sci: bool) -> String {
    format_number(v, v.abs() / 100.0, sci)
}

/// Evenly spaced ticks inside `range`, about `len_px / spacing_px` of them,
/// spaced wider on a horizontal axis until the labels stand 12 px apart.
pub(super) fn linear_ticks(
    range: (f64, f64),
    len_px: i32,
    spacing_px: i32,
    horizontal: bool,
) -> Result<Vec<Tick>, PlotError> {
    let (lo, hi) = range;
    let target = f64::from((len_px / spacing_px).clamp(2, 12));
    let mut step = nice_step((hi - lo) / target);
    // At least three ticks when the axis is long enough to hold them.
    let count = |step: f64| (hi / step + 1e-9).floor() - (lo / step - 1e-9).ceil() + 1.0;
    while count(step) < 3.0 && len_px >= 3 * spacing_px / 2 {
        let finer = finer_step(step);
        if finer.is_nan() || finer <= 0.0 || count(finer) > 12.0 {
            break;
        }
        step = finer;
    }
    let mut ticks = Vec::new();
    for _ in 0..8 {
        ticks.clear();
        let k0 = (lo / step - 1e-9).ceil();
        let k1 = (hi / step + 1e-9).floor();
        if !(k0.is_finite() && k1.is_finite()) || k1 - k0 > 100.0 {
            break;
        }
        let mut values = Vec::new();
        let mut k = k0;
        while k <= k1 {
            values.push(k * step);
            k += 1.0;
        }
        let largest = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let sci = wants_sci(largest);
        for v in values {
            ticks.push(Tick {
                value: v,
                label: format_number(v, step, sci),
            });
        }
        if !horizontal {
            break;
        }
        let widest = max_width(ticks.iter().map(|t| t.label.as_str()), TICK_PX)?;
        let step_px = f64::from(len_px) * step / (hi - lo);
        if f64::from(widest + 12) <= step_px {
            break;
        }
        step = nice_step(step * 1.5);
    }
    Ok(ticks)
}

/// Ticks on a log axis: powers of ten (thinned to fit), or 1-2-5 steps when
/// the range spans less than two decades, or linear ticks within one.
fn log_ticks(
    range: (f64, f64),
    len_px: i32,
    spacing_px: i32,
    horizontal: bool,
) -> Result<Vec<Tick>, PlotError> {
    let (a, b) = (range.0.log10(), range.1.log10());
    let max_count = (len_px / spacing_px).clamp(2, 12) as i64;
    let (e0, e1) = ((a - 1e-9).ceil() as i64, (b + 1e-9).floor() as i64);
    let mut values: Vec<f64> = Vec::new();
    if e1 - e0 >= 1 {
        let every = ((e1 - e0 + 1) + max_count - 1) / max_count;
        let mut e = e0;
        while e <= e1 {
            values.push(10f64.powi(e as i32));
            e += every.max(1);
        }
    } else {
        let mut e = a.floor() as i64;
        while e <= b.floor() as i64 {
            for m in [1.0, 2.0, 5.0] {
                let v = m * 10f64.powi(e as i32);
                if v >= range.0 * (1.0 - 1e-9) && v <= range.1 * (1.0 + 1e-9) {
                    values.push(v);
                }
            }
            e += 1;
        }
    }
    if values.len() < 2 {
        return linear_ticks(range, len_px, spacing_px, horizontal);
    }
    let sci = log_wants_sci(&values);
    Ok(values
        .into_iter()
        .map(|v| Tick {
            value: v,
            label: format_log_value(v, sci),
        })
        .collect())
}

pub(super) fn axis_ticks(
    range: (f64, f64),
    log: bool,
    len_px: i32,
    horizontal: bool,
) -> Result<Vec<Tick>, PlotError> {
    let spacing = if horizontal { 90 } else { 50 };
    if log {
        log_ticks(range, len_px, spacing, horizontal)
    } else {
        linear_ticks(range, len_px, spacing, horizontal)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_compact() {
        assert_eq!(format_number(1e5, 1e5, true), "1e5");
        assert_eq!(format_number(2.5e5, 5e4, true), "2.5e5");
        assert_eq!(format_number(0.3000000000000004, 0.1, false), "0.3");
        assert_eq!(format_number(-0.0, 0.1, false), "0");
        assert_eq!(format_number(0.25, 0.025, false), "0.25");
        assert_eq!(format_number(0.2, 0.2, false), "0.2");
        assert_eq!(format_number(31622.8, 100.0, false), "31600");
        assert_eq!(format_number(-1.5, 0.5, false), "-1.5");
        assert_eq!(format_number(3e-4, 1e-4, true), "3e-4");
        assert_eq!(format_number(99999.0, 10.0, true), "1e5");
        assert_eq!(format_number(99990.0, 10.0, true), "9.999e4");
        assert_eq!(format_log_value(1000.0, false), "1000");
        assert_eq!(format_log_value(31622.8, false), "31600");
        assert_eq!(format_log_value(31622.8, true), "3.16e4");
        assert_eq!(format_log_value(1e6, true), "1e6");
        assert_eq!(format_log_value(0.01, false), "0.01");
    }

    #[test]
    fn nice_steps() {
        assert_eq!(nice_step(0.13), 0.2);
        assert_eq!(nice_step(3.0), 5.0);
        assert_eq!(nice_step(7.0), 10.0);
        assert_eq!(nice_step(1.0), 1.0);
        assert_eq!(finer_step(1.0), 0.5);
        assert_eq!(finer_step(20.0), 10.0);
        assert_eq!(finer_step(0.05), 0.02);
    }
}
