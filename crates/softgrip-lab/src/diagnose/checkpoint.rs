//! Fits saved as they end, so that a diagnosis stopped midway (Ctrl-C, a cluster's preemption,
//! a closed laptop: a beam's takes hours) resumes where it was instead of from the start.
//!
//! Each line of the file is one fit: a key, its simulations, its seconds, its fitted values
//! (their bits, so exactly) and a checksum of the line, so that a line edited or damaged is
//! told from one softgrip wrote, and fitted again (with a word saying so). The key hashes what the fit depends on: the build, the recording, the options
//! and the fit's own task (its scene, parameters, search, budget, starts and the values of the
//! model it extends). A fit is taken from the file only when its key is there, so a changed
//! recording, option or binary fits again; a line cut short by a kill is skipped. A saved fit is
//! replayed once at its values from rest: the same model as the run that saved it, its
//! residuals within the replays' rest tolerance of that run's (whose last replay may have
//! started from a neighbour's equilibrium), and so the noise and the scores after it.
//!
//! A fit of a time series also logs each simulation as it ends (`sim1` lines: the point, its
//! weighted residuals' bits or that its replay failed), so that a stop in the middle of a fit
//! (one of a beam's takes an hour or two) loses one simulation, not the fit: the resumed fit
//! asks for the same points in the same order (a time series replays from rest, a pure
//! function of the point) and takes each logged one instead of simulating it, so it ends
//! where the uninterrupted fit would, bit for bit. Quasi-static fits log nothing: their
//! replays start from a neighbour's equilibrium, which a logged point does not keep, and they
//! take seconds.

use std::collections::HashMap;
use std::fmt::Debug;
use std::hash::{DefaultHasher, Hasher};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use crate::error::LabError;

/// The first word of every line: a file of another layout is not read as this one.
const VERSION: &str = "fit3";

/// The first word of a simulation's line.
const SIMULATION: &str = "sim1";

/// The most a checkpoint file is read (bytes): a diagnosis saves tens of lines of 100 bytes,
/// and a time series' a line of 17 bytes per residual for each simulation (a beam's diagnosis
/// of 400 simulations of 2,000 residuals, 14 MB).
const MAX_BYTES: u64 = 100_000_000;

/// A simulation as logged: its weighted residuals, `None` where its replay failed.
pub(super) type Logged = Option<Vec<f64>>;

/// The simulations logged under one fit's key, by point (its unit-box coordinates' bits).
pub(super) type Simulations = HashMap<Vec<u64>, Logged>;

/// A fit as saved: its simulations, its wall time and its values.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Saved {
    pub(super) evaluations: usize,
    pub(super) seconds: f64,
    pub(super) values: Vec<f64>,
}

/// A diagnosis's fits saved in a file (`DiagnoseOptions::checkpoint`).
#[derive(Clone)]
pub struct Checkpoint {
    path: PathBuf,
    build: String,
    saved: Arc<Mutex<HashMap<u64, Saved>>>,
    /// Simulations of fits that had not ended, by their fit's simulation key.
    simulations: Arc<Mutex<HashMap<u64, Simulations>>>,
    /// Simulations taken from the file in this run instead of run.
    reused_simulations: Arc<Mutex<usize>>,
    /// Fits taken from the file in this run, and the seconds they took the run that saved them.
    reused: Arc<Mutex<(usize, f64)>>,
    /// The first save that failed (a full disk): the diagnosis goes on, its fits unsaved.
    failed: Arc<Mutex<Option<String>>>,
    /// Lines that are not as softgrip wrote them (their checksum differs, or they are not
    /// text), and saved fits found outside their parameters' bounds: fitted again.
    damaged: Arc<Mutex<usize>>,
}

impl Debug for Checkpoint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Checkpoint({})", self.path.display())
    }
}

impl PartialEq for Checkpoint {
    fn eq(&self, other: &Self) -> bool {
        self.path == other.path && self.build == other.build
    }
}

impl Checkpoint {
    /// The fits saved at `path` (none if it does not exist yet); new ones are added to it.
    /// `build` names the code that fits (the CLI gives a hash of its own binary): fits saved
    /// by another build are fitted again.
    /// It is opened for writing here, so that a place it cannot be written is said at the start,
    /// not hours later.
    pub fn open(path: &Path, build: &str) -> Result<Checkpoint, LabError> {
        let unusable = |e: std::io::Error| {
            LabError::Input(format!(
                "{}: {e} (where the diagnosis saves its fits)",
                path.display()
            ))
        };
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(unusable)?;
        }
        append(path).map_err(unusable)?;
        let bytes = softgrip_core::files::read_at_most(path, MAX_BYTES).map_err(|e| {
            LabError::Input(format!(
                "{}: {e} (where the diagnosis saves its fits: delete it to start afresh)",
                path.display()
            ))
        })?;
        let mut damaged = 0;
        let mut saved = HashMap::new();
        let mut simulations: HashMap<u64, Simulations> = HashMap::new();
        // Line by line: bytes that are not text damage their line, not the file.
        for line in bytes.split(|&b| b == b'\n').filter(|l| !l.is_empty()) {
            match std::str::from_utf8(line).map(parse) {
                Ok(Line::Fit(key, fit)) => {
                    saved.insert(key, fit);
                }
                Ok(Line::Simulation(key, point, logged)) => {
                    simulations.entry(key).or_default().insert(point, logged);
                }
                Ok(Line::Other) => {}
                Ok(Line::Damaged) | Err(_) => damaged += 1,
            }
        }
        Ok(Checkpoint {
            path: path.to_path_buf(),
            build: build.to_string(),
            saved: Arc::new(Mutex::new(saved)),
            simulations: Arc::new(Mutex::new(simulations)),
            reused_simulations: Arc::default(),
            reused: Arc::default(),
            failed: Arc::default(),
            damaged: Arc::new(Mutex::new(damaged)),
        })
    }

    /// Why a fit could not be saved, if one could not (the first such).
    pub fn failed(&self) -> Option<String> {
        self.failed.lock().ok()?.clone()
    }

    /// Lines of the file not as softgrip wrote them, and saved fits outside their bounds: each
    /// fitted again rather than trusted.
    pub fn damaged(&self) -> usize {
        self.damaged.lock().map_or(0, |d| *d)
    }

    /// Counts a saved fit refused on use (its values outside their parameters' bounds).
    pub(super) fn refused(&self) {
        if let Ok(mut d) = self.damaged.lock() {
            *d += 1;
        }
    }

    /// The file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Fits in the file (of any build or diagnosis).
    pub fn len(&self) -> usize {
        self.saved.lock().map_or(0, |s| s.len())
    }

    /// No fit in the file.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Simulations in the file of fits that had not ended when they were logged (of any build
    /// or diagnosis).
    pub fn simulations_len(&self) -> usize {
        self.simulations
            .lock()
            .map_or(0, |s| s.values().map(HashMap::len).sum())
    }

    /// Simulations this run took from the file instead of running them.
    pub fn reused_simulations(&self) -> usize {
        self.reused_simulations.lock().map_or(0, |r| *r)
    }

    /// Fits this run took from the file instead of fitting.
    pub fn reused(&self) -> usize {
        self.reused.lock().map_or(0, |r| r.0)
    }

    /// The seconds those fits took the run that saved them.
    pub fn reused_seconds(&self) -> f64 {
        self.reused.lock().map_or(0.0, |r| r.1)
    }

    /// The key of a fit whose inputs print (`Debug`) as `inputs` do, under this build.
    pub(super) fn key(&self, inputs: &dyn Debug) -> u64 {
        // Through `fmt::Write`: a recording's text is hashed as it is printed, never held whole.
        struct Hashing(DefaultHasher);
        impl std::fmt::Write for Hashing {
            fn write_str(&mut self, s: &str) -> std::fmt::Result {
                self.0.write(s.as_bytes());
                Ok(())
            }
        }
        let mut h = Hashing(DefaultHasher::new());
        // Writing to a hasher cannot fail.
        let _ = std::fmt::write(&mut h, format_args!("{VERSION} {} {inputs:?}", self.build));
        h.0.finish()
    }

    /// The fit saved under `key`, if any.
    pub(super) fn get(&self, key: u64) -> Option<Saved> {
        self.saved.lock().ok()?.get(&key).cloned()
    }

    /// The simulations logged under a fit's simulation `key` (see [`Checkpoint::key`]).
    pub(super) fn simulations(&self, key: u64) -> Simulations {
        self.simulations
            .lock()
            .ok()
            .and_then(|s| s.get(&key).cloned())
            .unwrap_or_default()
    }

    /// Counts a logged simulation as taken from the file.
    pub(super) fn simulation_taken(&self) {
        if let Ok(mut r) = self.reused_simulations.lock() {
            *r += 1;
        }
    }

    /// Logs one simulation of a fit under its simulation `key`: `point`'s weighted residuals,
    /// or `None` where its replay failed. Appended and flushed at once, as [`Checkpoint::save`].
    pub(super) fn log_simulation(&self, key: u64, point: &[u64], logged: Option<&[f64]>) {
        self.write(&format_simulation(key, point, logged));
        if let Ok(mut s) = self.simulations.lock() {
            s.entry(key)
                .or_default()
                .insert(point.to_vec(), logged.map(<[f64]>::to_vec));
        }
    }

    /// Appends `line` to the file; a write that fails is kept for [`Checkpoint::failed`].
    fn write(&self, line: &str) {
        let written = append(&self.path).and_then(|mut file| {
            file.write_all(line.as_bytes())?;
            file.flush()
        });
        if let Err(e) = written
            && let Ok(mut f) = self.failed.lock()
        {
            f.get_or_insert_with(|| format!("{}: {e}", self.path.display()));
        }
    }

    /// Counts `fit` as taken from the file (not when its replay failed and it was fitted again).
    pub(super) fn taken(&self, fit: &Saved) {
        if let Ok(mut r) = self.reused.lock() {
            r.0 += 1;
            r.1 += fit.seconds;
        }
    }

    /// Saves a fit under `key`: appended to the file and flushed at once, so that a kill loses
    /// at most the fit it interrupts. A save that fails does not fail the fit: it is kept for
    /// [`Checkpoint::failed`].
    pub(super) fn save(&self, key: u64, fit: Saved) {
        self.write(&format_line(key, &fit));
        if let Ok(mut s) = self.saved.lock() {
            s.insert(key, fit);
        }
    }
}

/// A build's name for [`Checkpoint::open`] from the file that holds its code (the binary, the
/// Python extension): `label` and a hash of the file's bytes, read in pieces (a binary with its
/// debug lines is a hundred megabytes).
pub fn build_of(label: &str, file: &Path) -> std::io::Result<String> {
    struct Hashing(DefaultHasher);
    impl Write for Hashing {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            self.0.write(buf);
            Ok(buf.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }
    let mut h = Hashing(DefaultHasher::new());
    std::io::copy(&mut std::fs::File::open(file)?, &mut h)?;
    Ok(format!("{label} {:016x}", h.0.finish()))
}

fn append(path: &Path) -> std::io::Result<std::fs::File> {
    std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
}

fn format_line(key: u64, fit: &Saved) -> String {
    let mut line = format!(
        "{VERSION} {key:016x} {} {:016x}",
        fit.evaluations,
        fit.seconds.to_bits()
    );
    for v in &fit.values {
        line.push_str(&format!(" {:016x}", v.to_bits()));
    }
    line.push_str(&format!(" {:016x}\n", checksum(&line)));
    line
}

/// `sim1 KEY N POINT... ok RESIDUAL... CHECKSUM` (or `failed` and no residuals), every number
/// but N as the hex of its bits.
fn format_simulation(key: u64, point: &[u64], logged: Option<&[f64]>) -> String {
    let mut line = format!("{SIMULATION} {key:016x} {}", point.len());
    for b in point {
        line.push_str(&format!(" {b:016x}"));
    }
    match logged {
        Some(r) => {
            line.push_str(" ok");
            for v in r {
                line.push_str(&format!(" {:016x}", v.to_bits()));
            }
        }
        None => line.push_str(" failed"),
    }
    line.push_str(&format!(" {:016x}\n", checksum(&line)));
    line
}

/// FNV-1a over a line's text before its checksum: the same on every build and platform.
fn checksum(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// A line of the file.
#[derive(Debug, PartialEq)]
enum Line {
    Fit(u64, Saved),
    /// A simulation of a fit: its fit's simulation key, its point, what it gave.
    Simulation(u64, Vec<u64>, Logged),
    /// Of another layout (an older softgrip's): not read, not damaged.
    Other,
    /// This layout, but not as it was written: cut short by a kill, edited, or damaged.
    Damaged,
}

fn parse(line: &str) -> Line {
    let line = line.trim_end_matches('\r');
    let first = line.split_ascii_whitespace().next();
    match first {
        Some(VERSION | SIMULATION) => {}
        // Another softgrip's layout.
        Some(w)
            if ["fit", "sim"]
                .iter()
                .any(|p| w.strip_prefix(p).is_some_and(|n| n.parse::<u32>().is_ok())) =>
        {
            return Line::Other;
        }
        _ => return Line::Damaged,
    }
    let Some((body, sum)) = line.rsplit_once(' ') else {
        return Line::Damaged;
    };
    if u64::from_str_radix(sum, 16).ok() != Some(checksum(body)) || sum.len() != 16 {
        return Line::Damaged;
    }
    let words = body.split_ascii_whitespace().skip(1);
    if first == Some(SIMULATION) {
        return parse_simulation(words).unwrap_or(Line::Damaged);
    }
    let mut words = words;
    let number = |w: &str| bits(w).map(f64::from_bits);
    let fit = (|| {
        let key = u64::from_str_radix(words.next()?, 16).ok()?;
        let evaluations = words.next()?.parse().ok()?;
        let seconds = number(words.next()?)?;
        let values = words.map(number).collect::<Option<Vec<f64>>>()?;
        Some((
            key,
            Saved {
                evaluations,
                seconds,
                values,
            },
        ))
    })();
    fit.map_or(Line::Damaged, |(k, f)| Line::Fit(k, f))
}

/// A 16-digit hex word as the bits it writes.
fn bits(w: &str) -> Option<u64> {
    (w.len() == 16)
        .then(|| u64::from_str_radix(w, 16).ok())
        .flatten()
}

/// A `sim1` line's words after the first, its checksum already checked.
fn parse_simulation<'a>(mut words: impl Iterator<Item = &'a str>) -> Option<Line> {
    let key = u64::from_str_radix(words.next()?, 16).ok()?;
    let n: usize = words.next()?.parse().ok()?;
    let point = (0..n)
        .map(|_| bits(words.next()?))
        .collect::<Option<Vec<u64>>>()?;
    let logged = match words.next()? {
        "ok" => Some(
            words
                .map(|w| bits(w).map(f64::from_bits))
                .collect::<Option<Vec<f64>>>()?,
        ),
        "failed" => words.next().is_none().then_some(None)?,
        _ => return None,
    };
    Some(Line::Simulation(key, point, logged))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Appends `bytes` with no line end: a line a kill cut short.
    fn cut_short(path: &Path, bytes: &[u8]) {
        let mut f = append(path).expect("append");
        f.write_all(bytes).expect("write");
    }

    fn temp(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("softgrip-checkpoint-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        dir.join("fits.checkpoint")
    }

    /// Values come back bit for bit, in a new run of the same build; another build, or other
    /// inputs, find nothing; a line cut short by a kill is skipped.
    #[test]
    fn a_saved_fit_comes_back_exactly_and_only_for_its_own_inputs() {
        let path = temp("roundtrip");
        let c = Checkpoint::open(&path, "build-a").expect("open");
        assert!(c.is_empty());
        let fit = Saved {
            evaluations: 17,
            seconds: 612.5,
            values: vec![61_234.567_890_123_4, 0.1 + 0.2, -0.0, 1e-300],
        };
        let key = c.key(&("scene", 0.25, [1.0, 2.0]));
        c.save(key, fit.clone());
        c.save(c.key(&"another fit"), fit.clone());
        assert_eq!(c.failed(), None);
        // Killed while writing a third.
        cut_short(&path, b"fit3 00000000000000ab 3 3ff00000000");

        let again = Checkpoint::open(&path, "build-a").expect("reopen");
        assert_eq!(again.len(), 2, "the line cut short is skipped");
        assert_eq!(again.damaged(), 1, "and counted as not as written");
        let back = again.get(again.key(&("scene", 0.25, [1.0, 2.0])));
        assert_eq!(back, Some(fit.clone()));
        again.taken(back.as_ref().expect("saved"));
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&back.expect("saved").values), bits(&fit.values));
        assert_eq!((again.reused(), again.reused_seconds()), (1, 612.5));
        assert_eq!(
            again.get(again.key(&("scene", f64::from_bits(0.25f64.to_bits() + 1), [1.0, 2.0]))),
            None,
            "other inputs"
        );
        let other = Checkpoint::open(&path, "build-b").expect("reopen");
        assert_eq!(other.get(other.key(&("scene", 0.25, [1.0, 2.0]))), None);
        assert_eq!(other.reused(), 0);
        let _ = std::fs::remove_dir_all(path.parent().expect("dir"));
    }

    /// A logged simulation comes back bit for bit under its key, a failed one as failed; a
    /// line cut short by a kill is counted as damaged, another key finds nothing.
    #[test]
    fn a_logged_simulation_comes_back_exactly_under_its_key() {
        let path = temp("simulations");
        let c = Checkpoint::open(&path, "build-a").expect("open");
        let key = c.key(&("fit", 1));
        let (a, b) = (vec![0.25f64.to_bits(), 0.5f64.to_bits()], vec![1, 2]);
        let residuals = vec![1e-300, -0.0, 0.1 + 0.2, f64::MAX];
        c.log_simulation(key, &a, Some(&residuals));
        c.log_simulation(key, &b, None);
        assert_eq!(c.failed(), None);
        cut_short(&path, b"sim1 00000000000000ab 1 3ff0000000000000 ok 3ff00");
        let again = Checkpoint::open(&path, "build-a").expect("reopen");
        assert_eq!((again.len(), again.simulations_len()), (0, 2));
        assert_eq!(again.damaged(), 1, "the line cut short");
        let back = again.simulations(again.key(&("fit", 1)));
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        let got = back
            .get(&a)
            .expect("logged")
            .as_deref()
            .expect("not failed");
        assert_eq!(bits(got), bits(&residuals));
        assert_eq!(back.get(&b), Some(&None), "failed");
        assert!(again.simulations(again.key(&("fit", 2))).is_empty());
        let other = Checkpoint::open(&path, "build-b").expect("reopen");
        assert!(other.simulations(other.key(&("fit", 1))).is_empty());
        let _ = std::fs::remove_dir_all(path.parent().expect("dir"));
    }

    /// A build is named by its file's bytes: the same file the same name, one byte changed
    /// another, a missing file an error.
    #[test]
    fn a_build_is_named_by_its_files_bytes() {
        let path = temp("build");
        std::fs::create_dir_all(path.parent().expect("dir")).expect("dir");
        let mut bytes: Vec<u8> = (0..200_000u32).map(|i| (i % 251) as u8).collect();
        std::fs::write(&path, &bytes).expect("write");
        let a = build_of("x", &path).expect("named");
        assert_eq!(build_of("x", &path).expect("named"), a);
        bytes[150_000] ^= 1;
        std::fs::write(&path, &bytes).expect("write");
        assert_ne!(build_of("x", &path).expect("named"), a);
        assert!(build_of("x", &path.with_extension("missing")).is_err());
        let _ = std::fs::remove_dir_all(path.parent().expect("dir"));
    }

    #[test]
    fn a_place_it_cannot_use_is_named_at_the_start() {
        // A directory where the file should be.
        let path = temp("unreadable");
        std::fs::create_dir_all(&path).expect("dir");
        let e = Checkpoint::open(&path, "b")
            .expect_err("a directory")
            .to_string();
        assert!(
            e.contains("fits.checkpoint") && e.contains("saves its fits"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(path.parent().expect("dir"));
    }

    /// A value edited in place breaks its line's checksum; bytes that are not text damage
    /// their lines, not the file: both are counted and fitted again, the rest kept.
    #[test]
    fn an_edited_or_damaged_line_is_told_from_one_softgrip_wrote() {
        let path = temp("damaged");
        let c = Checkpoint::open(&path, "b").expect("open");
        let fit = Saved {
            evaluations: 5,
            seconds: 1.0,
            values: vec![0.3],
        };
        c.save(1, fit.clone());
        c.save(2, fit.clone());
        let text = std::fs::read_to_string(&path).expect("read");
        let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
        // 0.3 -> 1.8e308 in the first line, checksum untouched.
        lines[0] = lines[0].replace(
            &format!("{:016x}", 0.3f64.to_bits()),
            &format!("{:016x}", f64::MAX.to_bits()),
        );
        let mut bytes = (lines.join("\n") + "\n").into_bytes();
        bytes.extend_from_slice(&[0xff, 0xfe, 0x00, 0x9c, b'\n']);
        std::fs::write(&path, bytes).expect("write");
        let again = Checkpoint::open(&path, "b").expect("reopen");
        assert_eq!(again.len(), 1);
        assert_eq!(again.get(2), Some(fit));
        assert_eq!(again.get(1), None);
        assert_eq!(again.damaged(), 2);
        let _ = std::fs::remove_dir_all(path.parent().expect("dir"));
    }
}
