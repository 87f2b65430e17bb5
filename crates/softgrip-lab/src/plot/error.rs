//! Why a plot could not be made or written.

use std::path::PathBuf;

use super::style::{MAX_SIDE, MIN_SIZE};

/// Why a plot could not be made or written.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// No series point (or heat-map value, or bar) is finite.
    #[error("plot \"{title}\": nothing finite to plot")]
    NothingToPlot {
        /// The plot's title, to tell which plot of a report failed.
        title: String,
    },
    /// A logarithmic axis was given a value that is zero or negative.
    #[error(
        "plot \"{title}\": the {axis} axis is logarithmic but the data has {value}, which is not positive"
    )]
    LogAxis {
        /// The plot's title.
        title: String,
        /// `"x"` or `"y"`.
        axis: &'static str,
        /// The first offending value.
        value: f64,
    },
    /// The image size is outside [`MIN_SIZE`] .. [`MAX_SIDE`], or leaves no
    /// room for the plot area once the labels are placed.
    #[error(
        "plot size {width}x{height} px is too small or too large (at least {}x{}, at most {MAX_SIDE} per side, with room for the labels)",
        MIN_SIZE.0,
        MIN_SIZE.1
    )]
    Size {
        /// Requested width in px.
        width: u32,
        /// Requested height in px.
        height: u32,
    },
    /// The input's parts do not fit together (lengths, ordering of centres).
    #[error("plot \"{title}\": {detail}")]
    Shape {
        /// The plot's title.
        title: String,
        /// What does not fit.
        detail: String,
    },
    /// The embedded font could not be loaded (a corrupt build).
    #[error("the embedded plot font could not be loaded: {0}")]
    Font(String),
    /// plotters failed while drawing.
    #[error("drawing the plot failed: {0}")]
    Draw(String),
    /// The PNG encoder failed.
    #[error("encoding the plot as PNG failed: {0}")]
    Encode(String),
    /// Writing the PNG file failed.
    #[error("could not write plot {}: {source}", path.display())]
    Write {
        /// The file that could not be written.
        path: PathBuf,
        /// The underlying I/O error.
        source: std::io::Error,
    },
}
