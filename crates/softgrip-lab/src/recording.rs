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

/// Why a recording could not be read: each names the file (and line) and what to write instead.
#[derive(Debug, thiserror::Error)]
pub enum RecordingError {
    /// A file of the recording could not be read.
    #[error(
        "cannot read {path}: {source}. Check the path (relative paths are relative to the recording file)."
    )]
    Read {
        /// The file.
        path: PathBuf,
        /// Why not.
        source: std::io::Error,
    },
    /// The recording.toml is not a recording, or a value in it is wrong.
    #[error("{file}: {message}")]
    Header {
        /// The file.
        file: String,
        /// What is wrong and what to write.
        message: String,
    },
    /// The samples CSV has a bad row or header.
    #[error("{file}:{line}: {message}")]
    Samples {
        /// The samples file.
        file: String,
        /// The line, from 1.
        line: usize,
        /// What is wrong and what to write.
        message: String,
    },
    /// The recording's scene could not be loaded.
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

/// A marker of the object: a point on its surface, tracked in the recording.
#[derive(Debug, Clone, PartialEq)]
pub struct Marker {
    /// Its name in `[markers]` and the samples' `marker` column.
    pub name: String,
    /// On the undeformed object's surface (m).
    pub reference: DVec3,
}

/// One observed position: `None` where the axis was not observed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Observation {
    /// The marker observed.
    pub marker: MarkerRef,
    /// Its observed position, m, per axis x, y, z.
    pub position: [Option<f64>; 3],
    /// 1-based line in the samples file.
    pub line: usize,
}

/// One sample: the markers observed at one load (quasi-static) or one time (time series).
#[derive(Debug, Clone, PartialEq)]
pub struct Sample {
    /// s; `None` in quasi-static mode.
    pub time: Option<f64>,
    /// N, on the first force-controlled finger along its scene force.
    pub load: f64,
    /// Each marker's observed position, in file order.
    pub observations: Vec<Observation>,
}

/// A lab recording: the scene, the markers and the samples ([module docs](crate::recording)).
#[derive(Debug, Clone, PartialEq)]
pub struct Recording {
    /// The recording file.
    pub source: PathBuf,
    /// The scene the recording is of.
    pub scene: Scene,
    /// The scene file, resolved from the recording's directory.
    pub scene_path: PathBuf,
    /// The samples CSV, resolved from the recording's directory.
    pub samples_path: PathBuf,
    /// How the samples were taken.
    pub mode: Mode,
    /// Where a time series starts (`Rest` for a quasi-static recording).
    pub start: Start,
    /// The header's `description` (empty if none).
    pub description: String,
    /// The `[markers]`, sorted by name.
    pub markers: Vec<Marker>,
    /// The samples, in file order.
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

/// The recording.toml's fields; a scene given in its place is said to be one.
fn parse_header(text: &str) -> Result<RawRecording, String> {
    let table = text.parse::<toml::Table>().ok();
    if table.is_some_and(|t| t.contains_key("object") && !t.contains_key("samples")) {
        return Err(
            "this is a scene (it has [object]), not a recording: give the recording.toml that names it (scene = \"...\", samples = \"...\", mode = ...; docs/recordings.md), or run the scene with `softgrip run`".into(),
        );
    }
    toml::from_str(text).map_err(|e| softgrip_core::scene::describe_toml_error(text, &e))
}

/// The recording's `mode`, which it must give.
fn mode_of(mode: Option<&str>) -> Result<Mode, String> {
    match mode {
        Some("quasi-static") => Ok(Mode::QuasiStatic),
        Some("time-series") => Ok(Mode::TimeSeries),
        Some(other) => Err(format!(
            "mode = {other:?}: must be \"quasi-static\" or \"time-series\""
        )),
        None => Err("mode is required: \"quasi-static\" or \"time-series\"".into()),
    }
}

/// The recording's `start` (rest by default), which only a time series may give.
fn start_of(start: Option<&str>, mode: Mode) -> Result<Start, String> {
    let parsed = match start {
        None | Some("rest") => Start::Rest,
        Some("equilibrium") => Start::Equilibrium,
        Some(other) => {
            return Err(format!(
                "start = {other:?}: must be \"rest\" or \"equilibrium\""
            ));
        }
    };
    if start.is_some() && mode == Mode::QuasiStatic {
        return Err("start applies to mode = \"time-series\" only; remove it".into());
    }
    Ok(parsed)
}

/// The `[markers]` table's object markers, by name (finger markers need no reference).
fn markers_of(table: toml::Table) -> Result<Vec<Marker>, String> {
    let mut markers = Vec::new();
    for (name, value) in table {
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
            .ok_or_else(|| format!("[markers] {name} = {value}: must be [x, y, z] in metres"))?;
        markers.push(Marker {
            name,
            reference: DVec3::new(p[0], p[1], p[2]),
        });
    }
    Ok(markers)
}

/// A time series whose last sample needs more than [`MAX_STEPS`] steps of the scene's `dt` is
/// refused: hours of simulated time are a unit slip (ms for s), not a lab's recording.
fn check_duration(
    samples: &[Sample],
    scene: &Scene,
    samples_path: &Path,
) -> Result<(), RecordingError> {
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
    Ok(())
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
        let raw = parse_header(&text).map_err(header)?;
        let dir = path.parent().unwrap_or(Path::new("."));
        let scene_rel = raw.scene.ok_or_else(|| {
            header("scene = \"scene.toml\" is required (relative to this file)".into())
        })?;
        let samples_rel = raw.samples.ok_or_else(|| {
            header("samples = \"samples.csv\" is required (relative to this file)".into())
        })?;
        let mode = mode_of(raw.mode.as_deref()).map_err(header)?;
        let start = start_of(raw.start.as_deref(), mode).map_err(header)?;
        let markers = markers_of(raw.markers.unwrap_or_default()).map_err(header)?;
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
        check_duration(&samples, &scene, &samples_path)?;
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

/// Time steps a time series may need at its scene's `dt` to reach its last sample.
pub const MAX_STEPS: f64 = 1e7;

/// Parses the samples CSV (see the module docs).
pub fn parse_samples(
    text: &str,
    file: &str,
    mode: Mode,
    markers: &[Marker],
    fingers: usize,
) -> Result<Vec<Sample>, RecordingError> {
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
    let (header_line, header) = lines
        .by_ref()
        .find(|(_, l)| !l.trim().is_empty())
        .ok_or_else(|| {
            samples_error(
                file,
                1,
                "the file is empty; a header `time,load,marker,x,y,z` is required".into(),
            )
        })?;
    let reader = SamplesReader {
        file,
        mode,
        markers,
        fingers,
        columns: Columns::parse(file, header_line, header)?,
        names: markers
            .iter()
            .enumerate()
            .map(|(k, m)| (m.name.as_str(), k))
            .collect(),
    };
    let mut grouping = Grouping {
        samples: Vec::new(),
        seen: BTreeMap::new(),
        last_time: f64::NEG_INFINITY,
    };
    for (line, row) in lines {
        if row.trim().is_empty() {
            continue;
        }
        let row = reader.row(line, row)?;
        grouping.add(&reader, line, row)?;
    }
    if grouping.samples.is_empty() {
        return Err(samples_error(
            file,
            header_line,
            "no samples after the header".into(),
        ));
    }
    Ok(grouping.samples)
}

/// An error at `line` (from 1) of the samples file `file`.
fn samples_error(file: &str, line: usize, message: String) -> RecordingError {
    RecordingError::Samples {
        file: file.to_string(),
        line,
        message,
    }
}

/// The samples CSV's header: its columns, and where the required ones are.
struct Columns {
    /// Every column's name, trimmed and lower-case, in order.
    names: Vec<String>,
    /// The `time` column's index.
    time: usize,
    /// The `load` column's index.
    load: usize,
    /// The `marker` column's index.
    marker: usize,
    /// The `x`, `y` and `z` columns' indices.
    axes: [usize; 3],
}

impl Columns {
    /// Reads the header `header` at `line` (from 1); each required column once.
    fn parse(file: &str, line: usize, header: &str) -> Result<Columns, RecordingError> {
        let names: Vec<String> = header
            .split(',')
            .map(|c| c.trim().to_ascii_lowercase())
            .collect();
        let column = |name: &str| -> Result<usize, RecordingError> {
            let found: Vec<usize> = names
                .iter()
                .enumerate()
                .filter(|(_, c)| *c == name)
                .map(|(i, _)| i)
                .collect();
            match found.as_slice() {
                [i] => Ok(*i),
                [] => Err(samples_error(
                    file,
                    line,
                    format!(
                        "no `{name}` column in the header {:?}; required: time,load,marker,x,y,z",
                        softgrip_core::files::quote(header, 60)
                    ),
                )),
                _ => Err(samples_error(
                    file,
                    line,
                    format!("the `{name}` column appears twice"),
                )),
            }
        };
        let (time, load, marker) = (column("time")?, column("load")?, column("marker")?);
        let axes = [column("x")?, column("y")?, column("z")?];
        Ok(Columns {
            names,
            time,
            load,
            marker,
            axes,
        })
    }
}

/// One row of the samples CSV, read and checked on its own.
struct Row<'r> {
    /// s; `None` in quasi-static mode.
    time: Option<f64>,
    /// N.
    load: f64,
    /// The marker observed.
    marker: MarkerRef,
    /// The marker's name as the row gives it.
    name: &'r str,
    /// m; `None` where the axis was not observed.
    position: [Option<f64>; 3],
}

/// What reading the rows of a samples CSV needs.
struct SamplesReader<'a> {
    /// The samples file, as errors name it.
    file: &'a str,
    /// The recording's mode.
    mode: Mode,
    /// The recording's `[markers]`, sorted by name.
    markers: &'a [Marker],
    /// The scene's finger count.
    fingers: usize,
    /// The header's columns.
    columns: Columns,
    /// Each object marker's index in `markers`, by name.
    names: BTreeMap<&'a str, usize>,
}

impl SamplesReader<'_> {
    /// An error at `line` of the samples file.
    fn err(&self, line: usize, message: String) -> RecordingError {
        samples_error(self.file, line, message)
    }

    /// Row `row` at `line`: its cells, time, load, marker and observed axes.
    fn row<'r>(&self, line: usize, row: &'r str) -> Result<Row<'r>, RecordingError> {
        let columns = &self.columns.names;
        let cells: Vec<&str> = row.split(',').map(str::trim).collect();
        // A short row would read as axes "not observed": say so instead.
        if cells.len() != columns.len() {
            return Err(self.err(
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
        let number = |i: usize, what: &str| self.number(line, cell(i), what);
        let time = number(self.columns.time, "time")?;
        self.check_time(line, time)?;
        let load = number(self.columns.load, "load")?.ok_or_else(|| {
            self.err(
                line,
                "load is empty: give the load in N (0 for none)".into(),
            )
        })?;
        let name = cell(self.columns.marker);
        let marker = self.marker(line, name)?;
        let axes = self.columns.axes;
        let position = [
            number(axes[0], "x")?,
            number(axes[1], "y")?,
            number(axes[2], "z")?,
        ];
        if position.iter().all(Option::is_none) {
            return Err(self.err(
                line,
                format!("marker {name:?} has no observed axis (x, y and z all empty)"),
            ));
        }
        Ok(Row {
            time,
            load,
            marker,
            name,
            position,
        })
    }

    /// Cell `c`'s number (`what` names it): `None` when empty, an error when not finite.
    fn number(&self, line: usize, c: &str, what: &str) -> Result<Option<f64>, RecordingError> {
        if c.is_empty() {
            return Ok(None);
        }
        let v: f64 = c
            .parse()
            .map_err(|_| self.err(line, format!("{what} {c:?} is not a number")))?;
        if !v.is_finite() {
            return Err(self.err(line, format!("{what} is {c}: must be finite")));
        }
        Ok(Some(v))
    }

    /// A time series gives every row a time from 0 s; a quasi-static recording none.
    fn check_time(&self, line: usize, time: Option<f64>) -> Result<(), RecordingError> {
        match (self.mode, time) {
            (Mode::TimeSeries, None) => {
                return Err(self.err(
                    line,
                    "time is empty: required in time-series mode (s)".into(),
                ));
            }
            (Mode::TimeSeries, Some(t)) if t < 0.0 => {
                return Err(self.err(
                    line,
                    format!("time {t} s is before the start: times count from 0 s"),
                ));
            }
            (Mode::QuasiStatic, Some(_)) => {
                return Err(self.err(
                    line,
                    "time is given in quasi-static mode: leave it empty (or make the recording mode = \"time-series\")".into(),
                ));
            }
            _ => {}
        }
        Ok(())
    }

    /// The marker named `name`: a finger the scene has, or one of `[markers]`.
    fn marker(&self, line: usize, name: &str) -> Result<MarkerRef, RecordingError> {
        let fingers = self.fingers;
        if let Some(k) = finger_marker(name) {
            if k >= fingers {
                return Err(self.err(
                    line,
                    format!(
                        "marker {name:?} is finger {} but the scene has {fingers} finger(s)",
                        k + 1
                    ),
                ));
            }
            Ok(MarkerRef::Finger(k))
        } else if let Some(&k) = self.names.get(name) {
            Ok(MarkerRef::Object(k))
        } else {
            Err(self.err(
                line,
                format!(
                    "marker {name:?} is not in [markers] (known: {}{})",
                    self.markers
                        .iter()
                        .map(|m| m.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", "),
                    if fingers > 0 { ", finger" } else { "" }
                ),
            ))
        }
    }
}

/// The rows gathered into samples, in file order.
struct Grouping {
    /// The samples so far.
    samples: Vec<Sample>,
    /// The markers of the last sample, each with its line.
    seen: BTreeMap<MarkerRef, usize>,
    /// The last sample's time, s (-inf before the first).
    last_time: f64,
}

impl Grouping {
    /// Adds `row` (at `line`) to the last sample, or starts a new one where its load
    /// (quasi-static) or time (time series) changes.
    fn add(&mut self, reader: &SamplesReader, line: usize, row: Row) -> Result<(), RecordingError> {
        let Row {
            time,
            load,
            marker,
            name,
            position,
        } = row;
        let mode = reader.mode;
        let samples = &mut self.samples;
        let same = samples.last().is_some_and(|s| match mode {
            Mode::QuasiStatic => s.load == load,
            Mode::TimeSeries => s.time == time,
        });
        if !same {
            if let Some(t) = time {
                let last_time = self.last_time;
                if t <= last_time {
                    return Err(reader.err(
                        line,
                        format!(
                            "time {t} s does not follow {last_time} s: samples must be in time order"
                        ),
                    ));
                }
                self.last_time = t;
            }
            samples.push(Sample {
                time,
                load,
                observations: Vec::new(),
            });
            self.seen.clear();
        } else if mode == Mode::TimeSeries && samples.last().is_some_and(|s| s.load != load) {
            return Err(reader.err(
                line,
                format!(
                    "load {load} differs from the {} given before at the same time",
                    samples.last().map_or(0.0, |s| s.load)
                ),
            ));
        }
        if let Some(first) = self.seen.insert(marker, line) {
            return Err(reader.err(
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
        Ok(())
    }
}
