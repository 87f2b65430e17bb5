//! Progress bars on stderr for the commands that take a while; each is
//! cleared when its work is done, so stdout keeps only the figures.

use indicatif::{ProgressBar, ProgressStyle};

/// A progress bar counting `unit`s (steps, samples, grid points).
pub fn progress_bar(len: u64, unit: &str) -> ProgressBar {
    let bar = ProgressBar::new(len);
    if let Ok(style) = ProgressStyle::with_template(&format!(
        "{{bar:40}} {{pos}}/{{len}} {unit}  {{msg}}  [{{elapsed}} < {{eta}}]"
    )) {
        bar.set_style(style);
    }
    bar
}

/// A search's bar: the simulations run so far, out of at most `len`.
pub fn simulations_bar(len: u64) -> ProgressBar {
    let bar = ProgressBar::new(len);
    if let Ok(style) = ProgressStyle::with_template(
        "{bar:40} {pos} simulations (at most {len})  {msg}  [{elapsed}]",
    ) {
        bar.set_style(style);
    }
    bar
}

/// The lab's `(done, total, what)` progress shown on `bar`: its length,
/// its position and the stage's name.
pub fn show_stages(bar: &ProgressBar) -> impl Fn(usize, usize, &str) + '_ {
    move |done, total, what| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
        bar.set_message(what.to_string());
    }
}
