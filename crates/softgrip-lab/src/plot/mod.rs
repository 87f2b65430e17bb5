//! PNG plots for the command-line reports (`softgrip compare`, `fit`, `sweep`,
//! `diagnose`): line and point charts, heat maps and bar charts.
//!
//! Drawing goes through `plotters` into an RGB buffer, text through its `ab_glyph`
//! renderer with DejaVu Sans embedded (`assets/fonts/`), and the `png` crate encodes
//! the result: the same input gives the same bytes on every machine. Layout is
//! computed here, not by plotters' chart builder: [`chart_layout`],
//! [`heat_map_layout`] and [`bars_layout`] return the exact data-to-pixel mapping
//! the drawing uses. The stages: the inputs (`types`), `layout` and `ticks`, then `axes`,
//! `text` and `canvas` draw, one file per kind of plot. More: `docs/design/plots.md`.

mod axes;
mod bars;
mod canvas;
mod chart;
mod error;
mod heat_map;
mod layout;
mod style;
mod text;
mod ticks;
mod types;

pub use bars::{bars_layout, bars_png};
pub use canvas::write_png;
pub use chart::{chart_layout, chart_png, chart_svg};
pub use error::PlotError;
pub use heat_map::{heat_map_layout, heat_map_png};
pub use layout::Layout;
pub use style::{DEFAULT_SIZE, MAX_SIDE, MIN_SIZE, palette};
pub use ticks::nice_step;
pub use types::{Arrow, Bars, Chart, HeatMap, Mark, Series};
