//! `softgrip screenshot`: a scene at a simulated time rendered to a PNG,
//! headless (`softgrip_viewer::render`).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use super::load::{load_scene, simulation};
use super::progress::progress_bar;

/// Render a scene at a simulated time to a PNG, headless (no window, no
/// display: a software adapter where there is no GPU).
#[derive(clap::Args)]
pub struct Args {
    /// Scene file (.toml); omit for the built-in thesis scene.
    scene: Option<PathBuf>,
    /// Simulated time of the picture (s).
    #[arg(long, default_value_t = 0.0, value_parser = super::args::non_negative)]
    at: f64,
    /// The PNG to write.
    #[arg(long)]
    out: PathBuf,
    /// Image size, WIDTHxHEIGHT in pixels.
    #[arg(long, default_value = "800x600", value_parser = parse_size)]
    size: (u32, u32),
    #[arg(long, value_enum, default_value_t = super::values::View(softgrip_viewer::render::View::Iso))]
    view: super::values::View,
    /// Colour the object by a field, with a colour bar at the right
    /// (its range is printed).
    #[arg(long, value_enum)]
    color: Option<super::values::Field>,
    /// Draw the springs as lines.
    #[arg(long)]
    wireframe: bool,
    /// Leave the surface out (with --wireframe: every spring inside shows).
    #[arg(long)]
    no_surface: bool,
    /// Cut the object open: AXIS:FRACTION, e.g. y:0.5 hides the
    /// elements in the front half (y below the middle); a leading `-`
    /// (-y:0.5) hides the other side.
    #[arg(long, value_parser = parse_cut)]
    cut: Option<softgrip_viewer::render::Cut>,
}

pub fn run(args: Args) -> Result<()> {
    let style = softgrip_viewer::render::Style {
        color_by: args.color.map(|f| f.0),
        wireframe: args.wireframe,
        surface: !args.no_surface,
        cut: args.cut,
        // See-through, as in the viewer: the dent under the finger shows.
        finger_opacity: 0.45,
        ..Default::default()
    };
    render(
        args.scene.as_deref(),
        args.at,
        &args.out,
        args.size,
        args.view.0,
        &style,
    )
}

fn render(
    scene_path: Option<&Path>,
    at: f64,
    out: &Path,
    (width, height): (u32, u32),
    view: softgrip_viewer::render::View,
    style: &softgrip_viewer::render::Style,
) -> Result<()> {
    anyhow::ensure!(
        at.is_finite() && at >= 0.0,
        "--at {at}: the simulated time must be 0 or more (s)"
    );
    let scene = load_scene(scene_path)?;
    super::outputs::Outputs::new()
        .scene(&scene)
        .file("--out", Some(out))
        .check()?;
    let mut sim = simulation(&scene)?;
    let steps = (at / sim.model.dt).round() as u64;
    let bar = progress_bar(steps, "steps");
    for _ in 0..steps {
        sim.step()?;
        bar.inc(1);
    }
    bar.finish_and_clear();
    let image =
        softgrip_viewer::render::screenshot(&sim.model, &sim.state, view, width, height, style)?;
    image
        .save(out)
        .with_context(|| format!("writing {}", out.display()))?;
    println!(
        "{}: {width}x{height}, t = {:.3} s, view {}",
        out.display(),
        sim.state.time,
        clap::ValueEnum::to_possible_value(&super::values::View(view))
            .map_or_else(String::new, |v| v.get_name().to_string())
    );
    if let Some(field) = style.color_by {
        let values = field.particle_values(&sim.model, &sim.state);
        let (lo, hi) = softgrip_core::fields::range(&values, field.signed());
        let k = field.display_scale();
        println!(
            "colour bar: {} from {:.4} {unit} (bottom) to {:.4} {unit} (top)",
            field.label(),
            lo * k,
            hi * k,
            unit = field.unit()
        );
    }
    Ok(())
}

/// `WIDTHxHEIGHT`, each 16 to 8192 pixels.
fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let bad = || format!("size {text:?}: expected WIDTHxHEIGHT, e.g. 800x600 (16 to 8192 each)");
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h): (u32, u32) = (
        w.trim().parse().map_err(|_| bad())?,
        h.trim().parse().map_err(|_| bad())?,
    );
    if !(16..=8192).contains(&w) || !(16..=8192).contains(&h) {
        return Err(bad());
    }
    Ok((w, h))
}

/// `[-]AXIS:FRACTION`, e.g. `y:0.5`.
fn parse_cut(text: &str) -> Result<softgrip_viewer::render::Cut, String> {
    let bad = || {
        format!(
            "cut {text:?}: expected AXIS:FRACTION with AXIS x, y or z (a leading - flips the side) and FRACTION from 0 to 1, e.g. y:0.5"
        )
    };
    let (axis, fraction) = text.split_once(':').ok_or_else(bad)?;
    let (flip, axis) = match axis.trim().strip_prefix('-') {
        Some(a) => (true, a),
        None => (false, axis.trim()),
    };
    let axis = match axis {
        "x" => 0,
        "y" => 1,
        "z" => 2,
        _ => return Err(bad()),
    };
    let fraction: f32 = fraction.trim().parse().map_err(|_| bad())?;
    if !(0.0..=1.0).contains(&fraction) {
        return Err(bad());
    }
    Ok(softgrip_viewer::render::Cut {
        axis,
        fraction,
        flip,
    })
}
