//! Lab recordings (`docs/formats.md`, "Recording"): a
//! TOML header naming the scene, the samples CSV, the mode and the
//! markers' reference positions, and the CSV of observed positions, one
//! row per marker per sample, an empty cell for an axis not observed.
//!
//! Rows become samples in file order: in quasi-static mode a sample is a
//! run of consecutive rows with the same load (a load that comes back is
//! a new sample, never merged with the earlier one); in time-series mode,
//! a run of rows with the same time. Every error names the file and line.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::DVec3;
use serde::Deserialize;

use softgrip_core::scene::{Scene, SceneError};

#[derive(Debug, thiserror::Error)]
pub enum RecordingError {
    #[error(
        "cannot read {path}: {source}. Check the path (relative paths are relative to the recording file)."
    )]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{file}: {message}")]
    Header { file: String, message: String },
    #[error("{file}:{line}: {message}")]
    Samples {
        file: String,
        line: usize,
        message: String,
    },
    #[error("the recording's scene: {0}")]
    Scene(#[from] SceneError),
}

/// How the samples were taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Each change of load is a new equilibrium, reached from the previous one.
    QuasiStatic,
    /// Samples at given times from the start.
    TimeSeries,
}

impl Mode {
    /// As the recording file writes it.
    pub fn name(self) -> &'static str {
        match self {
            Mode::QuasiStatic => "quasi-static",
            Mode::TimeSeries => "time-series",
        }
    }
}

/// Where a time series starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Start {
    /// The undeformed scene at t = 0.
    Rest,
    /// Static equilibrium under the first sample's load.
    Equilibrium,
}

/// What a marker name refers to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum MarkerRef {
    /// `[markers]` entry `k` (sorted by name): a material point of the
    /// object's surface.
    Object(usize),
    /// The centre of finger `k` (`finger` is 0, `finger1` is 1, ...).
    Finger(usize),
}

#[derive(Debug, Clone, PartialEq)]
pub struct Marker {
    pub name: String,
    /// On the undeformed object's surface (m).
    pub reference: DVec3,
}

/// One observed position: `None` where the axis was not observed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Observation {
    pub marker: MarkerRef,
    pub position: [Option<f64>; 3],
    /// 1-based line in the samples file.
    pub line: usize,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Sample {
    /// s; `None` in quasi-static mode.
    pub time: Option<f64>,
    /// N, on the first force-controlled finger along its scene force.
    pub load: f64,
    pub observations: Vec<Observation>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Recording {
    /// The recording file.
    pub source: PathBuf,
    pub scene: Scene,
    pub scene_path: PathBuf,
    pub samples_path: PathBuf,
    pub mode: Mode,
    pub start: Start,
    pub description: String,
    /// The `[markers]`, sorted by name.
    pub markers: Vec<Marker>,
    pub samples: Vec<Sample>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRecording {
    scene: Option<String>,
    samples: Option<String>,
    mode: Option<String>,
    start: Option<String>,
    description: Option<String>,
    markers: Option<toml::Table>,
    #[allow(dead_code)] // free-form by contract
    extra: Option<toml::Table>,
}

/// The finger index of a reserved marker name (`finger`, `finger1`, ...).
pub fn finger_marker(name: &str) -> Option<usize> {
    let rest = name.strip_prefix("finger")?;
    if rest.is_empty() {
        return Some(0);
    }
    if rest.starts_with('0') {
        return None;
    }
    rest.parse::<usize>().ok()
}

/// The largest recording.toml read (bytes).
pub const MAX_HEADER_BYTES: u64 = 10_000_000;
/// The largest samples CSV read (bytes): a million rows of 30 markers.
pub const MAX_SAMPLES_BYTES: u64 = 500_000_000;

/// What a recording may point to: its `scene` and `samples` are relative paths (a recording is
/// shared as a directory; `../scene.toml` may name a scene its takes share) of a `.toml` scene
/// and a `.csv` table. An absolute path, or a file of another kind, is refused before it is
/// opened, so that a recording from elsewhere cannot have softgrip read (and quote) any file
/// (`docs/recordings.md`, "What a recording may name").
fn within_reach<'a>(key: &str, rel: &'a str, extension: &str) -> Result<&'a str, String> {
    let p = Path::new(rel);
    if p.is_absolute() || rel.starts_with('~') {
        return Err(format!(
            "{key} = {rel:?}: give the path relative to this recording file (a recording is shared as a directory; absolute paths are refused)"
        ));
    }
    let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("");
    if !ext.eq_ignore_ascii_case(extension) {
        return Err(format!(
            "{key} = {rel:?}: a recording's {key} is a .{extension} file (docs/recordings.md)"
        ));
    }
    Ok(rel)
}

/// A text file of the recording, read at most `max` bytes; a file of another kind (a mesh, an
/// image) is said to be one.
fn read_text(path: &Path, max: u64, what: &str) -> Result<String, RecordingError> {
    use softgrip_core::files::{ReadError, kind_of, read_at_most};
    let file = path.display().to_string();
    let bytes = read_at_most(path, max).map_err(|e| match e {
        ReadError::Io(source) => RecordingError::Read {
            path: path.to_path_buf(),
            source,
        },
        e @ ReadError::TooLarge { .. } => RecordingError::Header {
            file: file.clone(),
            message: format!("{e} ({what} is read whole, at most {} MB)", max / 1_000_000),
        },
    })?;
    if let Some(kind) = kind_of(&bytes) {
        return Err(RecordingError::Header {
            file,
            message: format!("this is {kind}, not {what} (docs/recordings.md)"),
        });
    }
    let text = String::from_utf8(bytes).map_err(|e| RecordingError::Header {
        file: file.clone(),
        message: format!(
            "not UTF-8 text (byte {}): {what} is a text file; save it as UTF-8",
            e.utf8_error().valid_up_to()
        ),
    })?;
    // A byte-order mark (spreadsheets write one) is not part of the first column's name.
    Ok(text
        .strip_prefix('\u{feff}')
        .map(str::to_string)
        .unwrap_or(text))
}

impl Recording {
    /// Reads the header, its scene and its samples.
    pub fn load(path: &Path) -> Result<Recording, RecordingError> {
        let file = path.display().to_string();
        let header = |message: String| RecordingError::Header {
            file: file.clone(),
            message,
        };
        let text = read_text(path, MAX_HEADER_BYTES, "a recording.toml")?;
        let table = text.parse::<toml::Table>().ok();
        if table.is_some_and(|t| t.contains_key("object") && !t.contains_key("samples")) {
            return Err(header(
                "this is a scene (it has [object]), not a recording: give the recording.toml that names it (scene = \"...\", samples = \"...\", mode = ...; docs/recordings.md), or run the scene with `softgrip run`".into(),
            ));
        }
        let raw: RawRecording = toml::from_str(&text)
            .map_err(|e| header(softgrip_core::scene::describe_toml_error(&text, &e)))?;
        let dir = path.parent().unwrap_or(Path::new("."));
        let scene_rel = raw.scene.ok_or_else(|| {
            header("scene = \"scene.toml\" is required (relative to this file)".into())
        })?;
        let samples_rel = raw.samples.ok_or_else(|| {
            header("samples = \"samples.csv\" is required (relative to this file)".into())
        })?;
        let mode = match raw.mode.as_deref() {
            Some("quasi-static") => Mode::QuasiStatic,
            Some("time-series") => Mode::TimeSeries,
            Some(other) => {
                return Err(header(format!(
                    "mode = {other:?}: must be \"quasi-static\" or \"time-series\""
                )));
            }
            None => {
                return Err(header(
                    "mode is required: \"quasi-static\" or \"time-series\"".into(),
                ));
            }
        };
        let start = match raw.start.as_deref() {
            None | Some("rest") => Start::Rest,
            Some("equilibrium") => Start::Equilibrium,
            Some(other) => {
                return Err(header(format!(
                    "start = {other:?}: must be \"rest\" or \"equilibrium\""
                )));
            }
        };
        if raw.start.is_some() && mode == Mode::QuasiStatic {
            return Err(header(
                "start applies to mode = \"time-series\" only; remove it".into(),
            ));
        }
        let mut markers = Vec::new();
        for (name, value) in raw.markers.unwrap_or_default() {
            if finger_marker(&name).is_some() {
                // The finger's centre needs no reference; the thesis files
                // still give one (its starting position).
                continue;
            }
            let p = value
                .as_array()
                .filter(|a| a.len() == 3)
                .and_then(|a| {
                    let v: Option<Vec<f64>> = a
                        .iter()
                        .map(|x| x.as_float().or_else(|| x.as_integer().map(|i| i as f64)))
                        .collect();
                    v
                })
                .filter(|v| v.iter().all(|c| c.is_finite()))
                .ok_or_else(|| {
                    header(format!(
                        "[markers] {name} = {value}: must be [x, y, z] in metres"
                    ))
                })?;
            markers.push(Marker {
                name,
                reference: DVec3::new(p[0], p[1], p[2]),
            });
        }
        let scene_path = dir.join(within_reach("scene", &scene_rel, "toml").map_err(header)?);
        let scene = Scene::load(&scene_path)?;
        let samples_path = dir.join(within_reach("samples", &samples_rel, "csv").map_err(header)?);
        let csv = read_text(&samples_path, MAX_SAMPLES_BYTES, "a samples CSV")?;
        let samples = parse_samples(
            &csv,
            &samples_path.display().to_string(),
            mode,
            &markers,
            scene.fingers.len(),
        )?;
        // Hours of simulated time are a unit slip (ms for s), not a lab's recording.
        let last = samples.iter().filter_map(|s| s.time).fold(0.0, f64::max);
        let steps = last / scene.simulation.dt;
        if steps > MAX_STEPS {
            return Err(RecordingError::Header {
                file: samples_path.display().to_string(),
                message: format!(
                    "the last sample is at t = {last} s: {steps:.1e} steps of the scene's dt = {} s, more than {MAX_STEPS:.0e}; times are in seconds (a time in ms must be divided by 1000)",
                    scene.simulation.dt
                ),
            });
        }
        Ok(Recording {
            source: path.to_path_buf(),
            scene,
            scene_path,
            samples_path,
            mode,
            start,
            description: raw.description.unwrap_or_default(),
            markers,
            samples,
        })
    }

    /// The name of a marker reference.
    pub fn marker_name(&self, m: MarkerRef) -> String {
        match m {
            MarkerRef::Object(k) => self.markers[k].name.clone(),
            MarkerRef::Finger(0) => "finger".into(),
            MarkerRef::Finger(k) => format!("finger{k}"),
        }
    }
}

/// Parses the samples CSV (see the module docs).
/// Time steps a time series may need at its scene's `dt` to reach its last sample.
pub const MAX_STEPS: f64 = 1e7;

pub fn parse_samples(
    text: &str,
    file: &str,
    mode: Mode,
    markers: &[Marker],
    fingers: usize,
) -> Result<Vec<Sample>, RecordingError> {
    let err = |line: usize, message: String| RecordingError::Samples {
        file: file.to_string(),
        line,
        message,
    };
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
    let (header_line, header) = lines
        .by_ref()
        .find(|(_, l)| !l.trim().is_empty())
        .ok_or_else(|| {
            err(
                1,
                "the file is empty; a header `time,load,marker,x,y,z` is required".into(),
            )
        })?;
    let columns: Vec<String> = header
        .split(',')
        .map(|c| c.trim().to_ascii_lowercase())
        .collect();
    let column = |name: &str| -> Result<usize, RecordingError> {
        let found: Vec<usize> = columns
            .iter()
            .enumerate()
            .filter(|(_, c)| *c == name)
            .map(|(i, _)| i)
            .collect();
        match found.as_slice() {
            [i] => Ok(*i),
            [] => Err(err(
                header_line,
                format!(
                    "no `{name}` column in the header {:?}; required: time,load,marker,x,y,z",
                    softgrip_core::files::quote(header, 60)
                ),
            )),
            _ => Err(err(
                header_line,
                format!("the `{name}` column appears twice"),
            )),
        }
    };
    let (ct, cl, cm) = (column("time")?, column("load")?, column("marker")?);
    let axes = [column("x")?, column("y")?, column("z")?];
    let names: BTreeMap<&str, usize> = markers
        .iter()
        .enumerate()
        .map(|(k, m)| (m.name.as_str(), k))
        .collect();
    let mut samples: Vec<Sample> = Vec::new();
    let mut seen: BTreeMap<MarkerRef, usize> = BTreeMap::new();
    let mut last_time = f64::NEG_INFINITY;
    for (line, row) in lines {
        if row.trim().is_empty() {
            continue;
        }
        let cells: Vec<&str> = row.split(',').map(str::trim).collect();
        // A short row would read as axes "not observed": say so instead.
        if cells.len() != columns.len() {
            return Err(err(
                line,
                format!(
                    "{} cells, but the header has {} ({}): an axis not observed is an empty cell between commas, e.g. `,1.39,t0_0,0.01,,0.02`",
                    cells.len(),
                    columns.len(),
                    columns.join(",")
                ),
            ));
        }
        let cell = |i: usize| cells.get(i).copied().unwrap_or("");
        let number = |i: usize, what: &str| -> Result<Option<f64>, RecordingError> {
            let c = cell(i);
            if c.is_empty() {
                return Ok(None);
            }
            let v: f64 = c
                .parse()
                .map_err(|_| err(line, format!("{what} {c:?} is not a number")))?;
            if !v.is_finite() {
                return Err(err(line, format!("{what} is {c}: must be finite")));
            }
            Ok(Some(v))
        };
        let time = number(ct, "time")?;
        match (mode, time) {
            (Mode::TimeSeries, None) => {
                return Err(err(
                    line,
                    "time is empty: required in time-series mode (s)".into(),
                ));
            }
            (Mode::TimeSeries, Some(t)) if t < 0.0 => {
                return Err(err(
                    line,
                    format!("time {t} s is before the start: times count from 0 s"),
                ));
            }
            (Mode::QuasiStatic, Some(_)) => {
                return Err(err(
                    line,
                    "time is given in quasi-static mode: leave it empty (or make the recording mode = \"time-series\")".into(),
                ));
            }
            _ => {}
        }
        let load = number(cl, "load")?.ok_or_else(|| {
            err(
                line,
                "load is empty: give the load in N (0 for none)".into(),
            )
        })?;
        let name = cell(cm);
        let marker = if let Some(k) = finger_marker(name) {
            if k >= fingers {
                return Err(err(
                    line,
                    format!(
                        "marker {name:?} is finger {} but the scene has {fingers} finger(s)",
                        k + 1
                    ),
                ));
            }
            MarkerRef::Finger(k)
        } else if let Some(&k) = names.get(name) {
            MarkerRef::Object(k)
        } else {
            return Err(err(
                line,
                format!(
                    "marker {name:?} is not in [markers] (known: {}{})",
                    markers
                        .iter()
                        .map(|m| m.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", "),
                    if fingers > 0 { ", finger" } else { "" }
                ),
            ));
        };
        let position = [
            number(axes[0], "x")?,
            number(axes[1], "y")?,
            number(axes[2], "z")?,
        ];
        if position.iter().all(Option::is_none) {
            return Err(err(
                line,
                format!("marker {name:?} has no observed axis (x, y and z all empty)"),
            ));
        }
        let same = samples.last().is_some_and(|s| match mode {
            Mode::QuasiStatic => s.load == load,
            Mode::TimeSeries => s.time == time,
        });
        if !same {
            if let Some(t) = time {
                if t <= last_time {
                    return Err(err(
                        line,
                        format!(
                            "time {t} s does not follow {last_time} s: samples must be in time order"
                        ),
                    ));
                }
                last_time = t;
            }
            samples.push(Sample {
                time,
                load,
                observations: Vec::new(),
            });
            seen.clear();
        } else if mode == Mode::TimeSeries && samples.last().is_some_and(|s| s.load != load) {
            return Err(err(
                line,
                format!(
                    "load {load} differs from the {} given before at the same time",
                    samples.last().map_or(0.0, |s| s.load)
                ),
            ));
        }
        if let Some(first) = seen.insert(marker, line) {
            return Err(err(
                line,
                format!("marker {name:?} appears twice in one sample (also line {first})"),
            ));
        }
        if let Some(s) = samples.last_mut() {
            s.observations.push(Observation {
                marker,
                position,
                line,
            });
        }
    }
    if samples.is_empty() {
        return Err(err(header_line, "no samples after the header".into()));
    }
    Ok(samples)
}
