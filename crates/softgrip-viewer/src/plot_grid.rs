//! Grid steps for the viewer's small plots: 1-2-5 steps chosen so that the
//! labelled lines are far enough apart for egui_plot to print their values.
//!
//! egui_plot's default grid divides by 10, and it hides a label closer than
//! 20 px to the next. On a plot 140 px high the step between 1 and 10 is
//! the one that matters: a depth of 0..4.7 mm has lines 1 mm apart at 19 px,
//! so only "0" was printed.

use softgrip_lab::plot::nice_step;

/// Pixels between labelled lines: egui_plot hides a label closer than 20
/// px to the next on y (60 px on x, where labels are wide) and fades it in
/// up to 30 px (80 px on x) (`AxisHints`).
const LABEL_PX_Y: f64 = 24.0;
const LABEL_PX_X: f64 = 64.0;

/// egui_plot's own least spacing of printed y labels.
#[cfg(test)]
const HIDDEN_BELOW_PX: f64 = 20.0;

/// egui_plot's default `grid_spacing` is 8..300 px.
const GRID_PX: f64 = 8.0;

/// The three step sizes (thin, labelled, thick) for an axis whose
/// `base_step_size` is the plot units across `grid_px` pixels (egui_plot's
/// `GridInput`, `Plot::grid_spacing().min`), with labelled lines at least
/// `label_px` apart.
pub fn steps(base_step_size: f64, grid_px: f64, label_px: f64) -> [f64; 3] {
    if !(base_step_size.is_finite() && base_step_size > 0.0) {
        return [1.0, 1.0, 1.0];
    }
    let per_px = base_step_size / grid_px;
    let labelled = nice_step(per_px * label_px);
    let thin = nice_step(base_step_size).min(labelled);
    [thin, labelled, 10.0 * labelled]
}

/// `plot` with the y grid of [`steps`].
fn with_y_grid(plot: egui_plot::Plot<'_>) -> egui_plot::Plot<'_> {
    plot.grid_spacing(egui::Rangef::new(GRID_PX as f32, 300.0))
        .y_grid_spacer(egui_plot::uniform_grid_spacer(|input| {
            steps(input.base_step_size, GRID_PX, LABEL_PX_Y)
        }))
}

/// `plot` with the x and y grids of [`steps`] (egui_plot's own would label
/// a 0..1.8 s run at 0 and 1 only, and samples 1..7 not at all).
pub fn with_grids(plot: egui_plot::Plot<'_>) -> egui_plot::Plot<'_> {
    with_y_grid(plot).x_grid_spacer(egui_plot::uniform_grid_spacer(|input| {
        steps(input.base_step_size, GRID_PX, LABEL_PX_X)
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_are_one_two_five() {
        assert_eq!(nice_step(0.7), 1.0);
        assert_eq!(nice_step(1.0), 1.0);
        assert_eq!(nice_step(1.3), 2.0);
        assert_eq!(nice_step(3.0), 5.0);
        assert_eq!(nice_step(6.0), 10.0);
        assert!((nice_step(0.013) - 0.02).abs() < 1e-15);
    }

    /// The case seen by hand: 0..4.7 mm over about 90 px. The labelled
    /// lines are far enough apart to be printed and at most a few to the plot, so
    /// more than one value is printed.
    #[test]
    fn a_short_plot_gets_labelled_lines_more_than_one_apart() {
        let (span, px) = (4.7, 90.0);
        let base = span / px * 8.0;
        let [thin, labelled, thick] = steps(base, GRID_PX, LABEL_PX_Y);
        let labelled_px = labelled / span * px;
        assert!(
            labelled_px >= HIDDEN_BELOW_PX,
            "{labelled} is {labelled_px} px"
        );
        assert!(span / labelled >= 2.0, "{labelled} labels 0..{span} once");
        assert!(thin <= labelled && labelled < thick);
        // The force plot beside it: 0..36 N.
        let [_, force, _] = steps(36.0 / 90.0 * GRID_PX, GRID_PX, LABEL_PX_Y);
        assert!(
            force / 36.0 * 90.0 >= HIDDEN_BELOW_PX && 36.0 / force >= 2.0,
            "{force}"
        );
        // The residual plot's x axis: samples 1..7 over about 250 px get a
        // label every 2, at least egui_plot's 60 px apart.
        let [_, every, _] = steps(7.0 / 250.0 * GRID_PX, GRID_PX, LABEL_PX_X);
        assert_eq!(every, 2.0);
        assert!(every / 7.0 * 250.0 >= 60.0);
    }
}
