//! The PNG plots of the command-line reports: decoded and checked pixel by
//! pixel at the points the layout says the data lands on.
//!
//! `SOFTGRIP_PLOT_EXAMPLES=/some/dir cargo test -p softgrip-lab plot::` also writes one
//! example of each kind there, to look at.

use softgrip_lab::plot::{
    Bars, Chart, HeatMap, Layout, Mark, PlotError, Series, bars_layout, bars_png, chart_layout,
    chart_png, chart_svg, heat_map_layout, heat_map_png, palette, write_png,
};

/// A decoded 8-bit RGB image.
struct Image {
    width: u32,
    height: u32,
    rgb: Vec<u8>,
}

impl Image {
    fn at(&self, x: i32, y: i32) -> [u8; 3] {
        assert!(
            x >= 0 && y >= 0 && (x as u32) < self.width && (y as u32) < self.height,
            "pixel ({x}, {y}) outside {}x{}",
            self.width,
            self.height
        );
        let k = (y as usize * self.width as usize + x as usize) * 3;
        [self.rgb[k], self.rgb[k + 1], self.rgb[k + 2]]
    }
}

fn decode(png_bytes: &[u8]) -> Image {
    let decoder = png::Decoder::new(std::io::Cursor::new(png_bytes));
    let mut reader = decoder.read_info().expect("PNG header");
    let mut rgb = vec![0; reader.output_buffer_size().expect("buffer size")];
    let info = reader.next_frame(&mut rgb).expect("PNG data");
    assert_eq!(info.color_type, png::ColorType::Rgb, "plots are 8-bit RGB");
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    rgb.truncate(info.buffer_size());
    Image {
        width: info.width,
        height: info.height,
        rgb,
    }
}

fn close(a: [u8; 3], b: [u8; 3], tol: u8) -> bool {
    a.iter().zip(b).all(|(x, y)| x.abs_diff(y) <= tol)
}

fn red_line_chart() -> Chart {
    Chart {
        title: "Red line".into(),
        x_label: "x (m)".into(),
        y_label: "y (N)".into(),
        series: vec![Series {
            label: "y = 0.5".into(),
            points: vec![(0.0, 0.5), (0.25, 0.5), (0.5, 0.5), (0.75, 0.5), (1.0, 0.5)],
            mark: Mark::Line,
            color: [220, 0, 0],
        }],
        size: (640, 400),
        ..Chart::default()
    }
}

fn ramp_heat_map() -> HeatMap {
    let x = vec![1.0, 2.0, 3.0, 4.0, 5.0];
    let y = vec![10.0, 20.0, 30.0];
    let mut values = Vec::new();
    for j in 0..y.len() {
        for i in 0..x.len() {
            values.push(i as f64 + 0.1 * j as f64);
        }
    }
    HeatMap {
        title: "Ramp".into(),
        x_label: "stiffness (N/m)".into(),
        y_label: "damping (N s/m)".into(),
        value_label: "error (mm)".into(),
        x,
        y,
        values,
        size: (640, 420),
        ..HeatMap::default()
    }
}

fn some_bars() -> Bars {
    Bars {
        title: "Timing".into(),
        y_label: "time (ms)".into(),
        labels: vec!["broad phase".into(), "narrow phase".into(), "solve".into()],
        values: vec![1.5, 4.0, 12.25],
        colors: vec![palette(0), palette(1)],
        size: (480, 320),
    }
}

#[test]
fn images_have_the_requested_size() {
    let img = decode(&chart_png(&red_line_chart()).unwrap());
    assert_eq!((img.width, img.height), (640, 400));
    let img = decode(&heat_map_png(&ramp_heat_map()).unwrap());
    assert_eq!((img.width, img.height), (640, 420));
    let img = decode(&bars_png(&some_bars()).unwrap());
    assert_eq!((img.width, img.height), (480, 320));
}

#[test]
fn red_line_lands_where_the_layout_maps_it() {
    let chart = red_line_chart();
    let layout = chart_layout(&chart).unwrap();
    let img = decode(&chart_png(&chart).unwrap());
    let (px, py) = layout.pixel(0.5, 0.5).unwrap();
    assert!(px > layout.left && px < layout.right && py > layout.top && py < layout.bottom);
    let on = img.at(px, py);
    assert!(
        on[0] > 180 && on[1] < 60 && on[2] < 60,
        "pixel at the mapped (0.5, 0.5) is {on:?}, expected red"
    );
    // Well below the line, inside the plot area: background or grid, not red.
    let (qx, qy) = layout.pixel(0.5, layout.y_range.0).unwrap();
    let away = img.at(qx, (py + qy) / 2 + 3);
    assert!(
        away[0] > 200 && away[0] == away[1] && away[1] == away[2],
        "pixel away from the line is {away:?}, expected white or light grey"
    );
}

#[test]
fn layout_maps_ranges_to_the_plot_edges() {
    let layout: Layout = chart_layout(&red_line_chart()).unwrap();
    let (x0, x1) = layout.x_range;
    let (y0, y1) = layout.y_range;
    assert!(x0 < 0.0 && x1 > 1.0, "x range {x0}..{x1} misses the data");
    assert!(
        y0 < 0.5 && y1 > 0.5,
        "constant y still gets a range: {y0}..{y1}"
    );
    assert_eq!(layout.pixel(x0, y0), Some((layout.left, layout.bottom)));
    assert_eq!(layout.pixel(x1, y1), Some((layout.right, layout.top)));
}

#[test]
fn equal_aspect_draws_units_the_same_length() {
    let chart = Chart {
        series: vec![Series {
            label: String::new(),
            points: vec![(0.0, 0.0), (0.01, 0.002)],
            mark: Mark::LineAndPoints,
            color: palette(0),
        }],
        equal_aspect: true,
        ..Chart::default()
    };
    let l = chart_layout(&chart).unwrap();
    let (ax, ay) = l.map(0.0, 0.0).unwrap();
    let (bx, _) = l.map(0.01, 0.0).unwrap();
    let (_, cy) = l.map(0.0, 0.01).unwrap();
    assert!(
        ((bx - ax) - (ay - cy)).abs() < 1e-6,
        "1 cm is {} px across, {} px up",
        bx - ax,
        ay - cy
    );
}

#[test]
fn heat_map_ends_take_the_colormap_ends() {
    let h = ramp_heat_map();
    let layout = heat_map_layout(&h).unwrap();
    let img = decode(&heat_map_png(&h).unwrap());
    let to8 = |c: [f32; 3]| c.map(|v| (f64::from(v) * 255.0).round() as u8);
    let start = to8(softgrip_core::fields::colormap(0.0, false));
    let end = to8(softgrip_core::fields::colormap(1.0, false));
    let (lx, ly) = layout.pixel(h.x[0], h.y[0]).unwrap();
    let (hx, hy) = layout.pixel(h.x[4], h.y[2]).unwrap();
    assert!(
        close(img.at(lx, ly), start, 2),
        "lowest cell {:?}, colormap start {start:?}",
        img.at(lx, ly)
    );
    assert!(
        close(img.at(hx, hy), end, 2),
        "highest cell {:?}, colormap end {end:?}",
        img.at(hx, hy)
    );
    // The middle of the ramp is neither end.
    let (mx, my) = layout.pixel(h.x[2], h.y[1]).unwrap();
    let mid = img.at(mx, my);
    assert!(
        !close(mid, start, 20) && !close(mid, end, 20),
        "middle cell {mid:?}"
    );
}

#[test]
fn heat_map_missing_values_are_grey_and_the_mark_is_drawn() {
    let mut h = ramp_heat_map();
    h.values[1] = f64::NAN;
    h.mark = Some((h.x[3], h.y[1]));
    let layout = heat_map_layout(&h).unwrap();
    let img = decode(&heat_map_png(&h).unwrap());
    let (gx, gy) = layout.pixel(h.x[1], h.y[0]).unwrap();
    let grey = img.at(gx, gy);
    assert!(
        grey[0] == grey[1] && grey[1] == grey[2] && grey[0] > 100 && grey[0] < 220,
        "NaN cell {grey:?}"
    );
    let (mx, my) = layout.pixel(h.x[3], h.y[1]).unwrap();
    let centre = img.at(mx, my);
    assert!(
        centre.iter().all(|&c| c < 80),
        "mark centre {centre:?} should be dark"
    );
}

#[test]
fn log_axis_rejects_non_positive_data() {
    let mut chart = red_line_chart();
    chart.y_log = true;
    chart.series[0].points[2].1 = 0.0;
    assert!(
        matches!(chart_png(&chart), Err(PlotError::LogAxis { axis: "y", value, .. }) if value == 0.0),
        "{:?}",
        chart_png(&chart).err()
    );
    let mut chart = red_line_chart();
    chart.x_log = true; // x starts at 0
    assert!(matches!(
        chart_layout(&chart),
        Err(PlotError::LogAxis { axis: "x", .. })
    ));
    let mut h = ramp_heat_map();
    h.y_log = true;
    h.y[0] = -1.0;
    assert!(matches!(
        heat_map_png(&h),
        Err(PlotError::LogAxis { axis: "y", .. })
    ));
}

#[test]
fn log_axes_place_decades_evenly() {
    let chart = Chart {
        series: vec![Series {
            label: "power law".into(),
            points: (0..=4)
                .map(|k| (10f64.powi(k), 10f64.powi(2 * k)))
                .collect(),
            mark: Mark::Points,
            color: palette(1),
        }],
        x_log: true,
        y_log: true,
        ..Chart::default()
    };
    let l = chart_layout(&chart).unwrap();
    let xs: Vec<f64> = (0..=4)
        .map(|k| l.map(10f64.powi(k), 1.0).unwrap().0)
        .collect();
    for w in xs.windows(3) {
        assert!(
            ((w[1] - w[0]) - (w[2] - w[1])).abs() < 1e-6,
            "decades at {xs:?}"
        );
    }
    decode(&chart_png(&chart).unwrap());
}

#[test]
fn nothing_finite_is_an_error() {
    let mut chart = red_line_chart();
    chart.series[0].points = vec![(f64::NAN, 1.0), (2.0, f64::INFINITY)];
    assert!(matches!(
        chart_png(&chart),
        Err(PlotError::NothingToPlot { .. })
    ));
    chart.series.clear();
    assert!(matches!(
        chart_layout(&chart),
        Err(PlotError::NothingToPlot { .. })
    ));
    let mut h = ramp_heat_map();
    h.values.iter_mut().for_each(|v| *v = f64::NAN);
    assert!(matches!(
        heat_map_png(&h),
        Err(PlotError::NothingToPlot { .. })
    ));
    let mut b = some_bars();
    b.values = vec![f64::NAN; 3];
    assert!(matches!(bars_png(&b), Err(PlotError::NothingToPlot { .. })));
}

#[test]
fn bad_sizes_and_shapes_are_errors() {
    let mut chart = red_line_chart();
    chart.size = (50, 40);
    assert!(matches!(
        chart_png(&chart),
        Err(PlotError::Size {
            width: 50,
            height: 40
        })
    ));
    let mut h = ramp_heat_map();
    h.values.pop();
    assert!(matches!(heat_map_png(&h), Err(PlotError::Shape { .. })));
    let mut h = ramp_heat_map();
    h.x.swap(0, 1);
    assert!(matches!(heat_map_layout(&h), Err(PlotError::Shape { .. })));
    let mut b = some_bars();
    b.labels.pop();
    assert!(matches!(bars_layout(&b), Err(PlotError::Shape { .. })));
}

#[test]
fn single_points_and_non_finite_points_still_plot() {
    let chart = Chart {
        series: vec![Series {
            label: "one".into(),
            points: vec![(f64::NAN, 0.0), (3.0, 7.0)],
            mark: Mark::Line,
            color: [0, 0, 200],
        }],
        ..Chart::default()
    };
    let l = chart_layout(&chart).unwrap();
    assert!(l.x_range.0 < 3.0 && l.x_range.1 > 3.0 && l.y_range.0 < 7.0 && l.y_range.1 > 7.0);
    let img = decode(&chart_png(&chart).unwrap());
    let (px, py) = l.pixel(3.0, 7.0).unwrap();
    let c = img.at(px, py);
    assert!(c[2] > 150 && c[0] < 80, "the lone point is drawn: {c:?}");
}

#[test]
fn bars_fill_their_slots_in_their_colours() {
    let b = some_bars();
    let layout = bars_layout(&b).unwrap();
    let img = decode(&bars_png(&b).unwrap());
    // Bar k is centred on x = k; the third bar has no colour given, so takes palette(2).
    for (k, want) in [(0, palette(0)), (1, palette(1)), (2, palette(2))] {
        let (px, py) = layout.pixel(k as f64, b.values[k] / 2.0).unwrap();
        assert!(
            close(img.at(px, py), want, 0),
            "bar {k}: {:?}, expected {want:?}",
            img.at(px, py)
        );
    }
    // Above the shortest bar's value label: background.
    let (px, py) = layout
        .pixel(0.0, b.values[0] + 0.6 * (layout.y_range.1 - b.values[0]))
        .unwrap();
    let bg = img.at(px, py + 1);
    assert!(
        bg[0] > 200 && bg[0] == bg[1] && bg[1] == bg[2],
        "above bar 0: {bg:?}"
    );
}

/// True if any pixel in rows `y0..y1` is dark (text).
fn dark_in_rows(img: &Image, y0: i32, y1: i32) -> bool {
    (y0..y1).any(|y| (0..img.width as i32).any(|x| img.at(x, y).iter().all(|&c| c < 100)))
}

#[test]
fn title_text_is_drawn_in_the_title_band() {
    let chart = red_line_chart();
    let layout = chart_layout(&chart).unwrap();
    let band = layout.top - 12;
    assert!(band > 10, "a title band above the plot area");
    let img = decode(&chart_png(&chart).unwrap());
    assert!(
        dark_in_rows(&img, 0, band),
        "no title text above row {band}"
    );
    let untitled = Chart {
        title: String::new(),
        ..chart
    };
    let img = decode(&chart_png(&untitled).unwrap());
    assert!(!dark_in_rows(
        &img,
        0,
        band.min(chart_layout(&untitled).unwrap().top - 8)
    ));
}

#[test]
fn same_input_same_bytes() {
    let chart = red_line_chart();
    assert_eq!(chart_png(&chart).unwrap(), chart_png(&chart).unwrap());
    let h = ramp_heat_map();
    assert_eq!(heat_map_png(&h).unwrap(), heat_map_png(&h).unwrap());
    let b = some_bars();
    assert_eq!(bars_png(&b).unwrap(), bars_png(&b).unwrap());
}

#[test]
fn write_png_names_the_path_on_failure() {
    let png = bars_png(&some_bars()).unwrap();
    let dir = std::env::temp_dir().join(format!("softgrip-plot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let ok = dir.join("bars.png");
    write_png(&ok, &png).unwrap();
    assert_eq!(std::fs::read(&ok).unwrap(), png);
    let bad = dir.join("missing-dir").join("bars.png");
    let err = write_png(&bad, &png).unwrap_err();
    assert!(
        err.to_string().contains(&bad.display().to_string()),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Renders one realistic example of each kind; with `SOFTGRIP_PLOT_EXAMPLES`
/// set, writes them there to look at.
#[test]
fn example_plots() {
    let t: Vec<f64> = (0..=200).map(|k| k as f64 * 0.005).collect();
    let model: Vec<(f64, f64)> = t
        .iter()
        .map(|&t| (t, 12.0 * (1.0 - (-4.0 * t).exp()) + 0.8 * (9.0 * t).sin()))
        .collect();
    let measured: Vec<(f64, f64)> = t
        .iter()
        .step_by(10)
        .map(|&t| (t, 12.0 * (1.0 - (-4.2 * t).exp()) + 0.3 * (37.0 * t).sin()))
        .collect();
    let reference: Vec<(f64, f64)> = t
        .iter()
        .map(|&t| (t, 12.0 * (1.0 - (-4.0 * t).exp())))
        .collect();
    let arrows = measured
        .iter()
        .zip(model.iter().step_by(10))
        .take(6)
        .map(|(&m, &s)| (m, s, [120, 120, 120]))
        .collect();
    let chart = Chart {
        title: "Grip force: simulation against lab".into(),
        x_label: "time (s)".into(),
        y_label: "force (N)".into(),
        series: vec![
            Series {
                label: "simulation".into(),
                points: model,
                mark: Mark::Line,
                color: palette(0),
            },
            Series {
                label: "lab".into(),
                points: measured,
                mark: Mark::Points,
                color: palette(1),
            },
            Series {
                label: "first order".into(),
                points: reference,
                mark: Mark::Dashed,
                color: palette(2),
            },
        ],
        arrows,
        ..Chart::default()
    };
    let stiff: Vec<f64> = (0..8).map(|k| 1e3 * 10f64.powf(k as f64 * 0.5)).collect();
    let damp: Vec<f64> = (0..6).map(|k| 0.5 + k as f64 * 0.25).collect();
    let mut values = Vec::new();
    for &d in &damp {
        for &k in &stiff {
            let e: f64 = (k.log10() - 4.6).powi(2) + 2.0 * (d - 1.1).powi(2);
            values.push(if k > 2e6 && d > 1.5 {
                f64::NAN
            } else {
                0.2 + e
            });
        }
    }
    let heat = HeatMap {
        title: "Sweep: RMS force error".into(),
        x_label: "stiffness (N/m)".into(),
        y_label: "damping (N s/m)".into(),
        value_label: "RMS error (N)".into(),
        x: stiff.clone(),
        y: damp.clone(),
        values,
        x_log: true,
        mark: Some((stiff[3], damp[2])),
        ..HeatMap::default()
    };
    let bars = Bars {
        title: "Step time by stage".into(),
        y_label: "time (ms)".into(),
        labels: [
            "springs", "volume", "contact", "assemble", "CG solve", "limits",
        ]
        .map(String::from)
        .to_vec(),
        values: vec![0.8, 0.35, 1.9, 0.6, 4.2, 0.15],
        colors: Vec::new(),
        ..Bars::default()
    };
    let pngs = [
        ("chart.png", chart_png(&chart).unwrap()),
        ("heat_map.png", heat_map_png(&heat).unwrap()),
        ("bars.png", bars_png(&bars).unwrap()),
    ];
    for (_, png) in &pngs {
        let img = decode(png);
        assert_eq!((img.width, img.height), softgrip_lab::plot::DEFAULT_SIZE);
    }
    if let Some(dir) = std::env::var_os("SOFTGRIP_PLOT_EXAMPLES") {
        let dir = std::path::PathBuf::from(dir);
        std::fs::create_dir_all(&dir).unwrap();
        for (name, png) in &pngs {
            write_png(&dir.join(name), png).unwrap();
        }
    }
}

/// Harder cases, written beside the examples: an equal-aspect path in metres
/// with residual arrows, a log-log chart, long and negative bars, and a
/// heat map with more cells than labels fit.
#[test]
fn edge_case_plots() {
    let path: Vec<(f64, f64)> = (0..=60)
        .map(|k| {
            let a = k as f64 / 60.0 * std::f64::consts::TAU;
            (0.03 * a.cos() + 0.002 * (5.0 * a).sin(), 0.012 * a.sin())
        })
        .collect();
    let measured: Vec<(f64, f64)> = path
        .iter()
        .step_by(6)
        .map(|&(x, y)| (x * 1.05, y * 1.1 + 0.001))
        .collect();
    let arrows = measured
        .iter()
        .zip(path.iter().step_by(6))
        .map(|(&m, &p)| (p, m, [200, 60, 60]))
        .collect();
    let marker = Chart {
        title: "Marker path".into(),
        x_label: "x (m)".into(),
        y_label: "z (m)".into(),
        series: vec![
            Series {
                label: "simulated marker".into(),
                points: path,
                mark: Mark::Line,
                color: palette(0),
            },
            Series {
                label: "tracked marker".into(),
                points: measured,
                mark: Mark::Points,
                color: palette(3),
            },
        ],
        arrows,
        equal_aspect: true,
        ..Chart::default()
    };
    let loglog = Chart {
        title: "Convergence".into(),
        x_label: "time step (s)".into(),
        y_label: "error (m)".into(),
        series: vec![
            Series {
                label: "implicit Euler".into(),
                points: (0..12)
                    .map(|k| {
                        let h = 1e-5 * 2f64.powi(k);
                        (h, 3e-2 * h)
                    })
                    .collect(),
                mark: Mark::LineAndPoints,
                color: palette(0),
            },
            Series {
                label: "first order".into(),
                points: vec![(1e-5, 1e-7), (2e-2, 2e-4)],
                mark: Mark::Dashed,
                color: palette(7),
            },
        ],
        x_log: true,
        y_log: true,
        size: (600, 420),
        ..Chart::default()
    };
    let bars = Bars {
        title: "Change against the previous run".into(),
        y_label: "relative change (%)".into(),
        labels: [
            "hanging cuboid, 10 s",
            "pinch with two spheres",
            "plate squeeze",
            "drag across the table",
            "cylinder grasp",
            "volume preservation only",
            "stick-slip ramp",
        ]
        .map(String::from)
        .to_vec(),
        values: vec![2.5, -12.0, 0.4, f64::NAN, 7.75, -0.3, 31.0],
        colors: Vec::new(),
        size: (640, 480),
    };
    let x: Vec<f64> = (0..40).map(|k| 0.05 * k as f64).collect();
    let y = vec![2.0e5];
    let values = x.iter().map(|v| (3.0 * v).sin()).collect();
    let strip = HeatMap {
        title: "One row, many columns".into(),
        x_label: "friction coefficient".into(),
        y_label: "E (Pa)".into(),
        value_label: "slip (mm)".into(),
        x,
        y,
        values,
        size: (700, 260),
        ..HeatMap::default()
    };
    let pngs = [
        ("marker_path.png", chart_png(&marker).unwrap()),
        ("log_log.png", chart_png(&loglog).unwrap()),
        ("bars_long_labels.png", bars_png(&bars).unwrap()),
        ("heat_strip.png", heat_map_png(&strip).unwrap()),
    ];
    for (_, png) in &pngs {
        decode(png);
    }
    if let Some(dir) = std::env::var_os("SOFTGRIP_PLOT_EXAMPLES") {
        let dir = std::path::PathBuf::from(dir);
        std::fs::create_dir_all(&dir).unwrap();
        for (name, png) in &pngs {
            write_png(&dir.join(name), png).unwrap();
        }
    }
}

/// The SVG beside a report's PNG is the same plot: the red line lies along the row the layout
/// maps y = 0.5 to, from the first x to the last, and the text names a font viewers have.
#[test]
fn a_charts_svg_draws_its_series_where_the_layout_says() {
    let chart = red_line_chart();
    let layout = chart_layout(&chart).unwrap();
    let svg = chart_svg(&chart).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    let (x0, y) = layout.map(0.0, 0.5).unwrap();
    let (x1, _) = layout.map(1.0, 0.5).unwrap();
    let red: Vec<&str> = svg
        .lines()
        .filter(|l| l.starts_with("<polyline") && l.contains("stroke=\"#DC0000\""))
        .collect();
    assert!(!red.is_empty(), "no red polyline");
    let points: Vec<(f64, f64)> = red
        .iter()
        .flat_map(|l| {
            let list = l
                .split("points=\"")
                .nth(1)
                .unwrap()
                .split('"')
                .next()
                .unwrap();
            list.split_whitespace()
                .map(|p| {
                    let (a, b) = p.split_once(',').unwrap();
                    (a.parse().unwrap(), b.parse().unwrap())
                })
                .collect::<Vec<_>>()
        })
        .collect();
    // The series, not the legend's short sample of it (in a top corner, far above the row).
    let points: Vec<(f64, f64)> = points.into_iter().filter(|p| p.1 > y - 20.0).collect();
    assert!(!points.is_empty());
    for &(_, py) in &points {
        assert!(
            (py - y).abs() <= 2.0,
            "a red point at y = {py}, the line at {y}"
        );
    }
    let xs = points.iter().map(|p| p.0);
    let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    assert!(
        (lo - x0).abs() <= 2.0 && (hi - x1).abs() <= 2.0,
        "{lo}..{hi} against {x0}..{x1}"
    );
    assert!(svg.contains("font-family=\"DejaVu Sans"));
}

/// Twenty markers get twenty colours (a report once repeated ten colours over fourteen).
#[test]
fn the_palette_has_twenty_distinct_colours() {
    let colours: Vec<[u8; 3]> = (0..20).map(palette).collect();
    for (i, a) in colours.iter().enumerate() {
        for b in &colours[i + 1..] {
            let d: i32 = a
                .iter()
                .zip(b)
                .map(|(x, y)| (i32::from(*x) - i32::from(*y)).abs())
                .sum();
            assert!(d > 30, "{a:?} and {b:?} are nearly the same");
        }
    }
}
