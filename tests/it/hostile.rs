//! The hostile corpus (`tests/hostile/`): inputs a careless or unlucky user gives, each run
//! through the binary under a memory limit and a time limit. Every one must end with the exit
//! code its case says, a message naming the file (or argument) and the problem, no panic, no
//! abort, and no NaN printed. `tests/hostile/README.md` says how to add a case.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Address space each input may use: an input that needs more is a defect (issue: runaway
/// memory). `ulimit -v` counts reserved, not touched, memory, which threads' stacks inflate.
const MEMORY_KIB: u64 = 2 * 1024 * 1024;

/// The most an error message may print.
const MESSAGE_BYTES: usize = 4096;

/// How long one input may take (an optimised test build).
const TIME_LIMIT: Duration = Duration::from_secs(60);

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/hostile")
}

struct Case {
    name: String,
    args: Vec<String>,
    exit: i32,
    says: Vec<String>,
    /// Strings that must not appear (a warning gone once its advice is followed).
    never: Vec<String>,
    /// Advice the message gives, word for word, and the run that follows it: the advice (or
    /// `applied`, where it is a rule rather than a value) must appear in its arguments or in a
    /// file they name, and it must end as its case says.
    advice: Option<String>,
    applied: Option<String>,
    followed: Option<Box<Case>>,
}

fn cases() -> Vec<Case> {
    let path = corpus().join("cases.toml");
    let text = std::fs::read_to_string(&path).expect("tests/hostile/cases.toml");
    let table: toml::Table = text.parse().expect("cases.toml is TOML");
    let dir = corpus().join("files");
    let strings = |v: &toml::Value| -> Vec<String> {
        v.as_array()
            .expect("a list of strings")
            .iter()
            .map(|s| {
                s.as_str()
                    .expect("a string")
                    .replace("{files}", dir.to_str().expect("UTF-8 path"))
                    .replace("{repo}", env!("CARGO_MANIFEST_DIR"))
            })
            .collect()
    };
    fn case(c: &toml::Value, strings: &dyn Fn(&toml::Value) -> Vec<String>) -> Case {
        let name = c
            .get("name")
            .and_then(|n| n.as_str())
            .unwrap_or("")
            .to_string();
        Case {
            followed: c.get("followed").map(|f| {
                let mut f = case(f, strings);
                f.name = format!("{name}, its advice followed");
                Box::new(f)
            }),
            name,
            args: strings(&c["args"]),
            exit: c["exit"].as_integer().expect("exit") as i32,
            says: c.get("says").map(strings).unwrap_or_default(),
            never: c.get("never").map(strings).unwrap_or_default(),
            advice: c.get("advice").and_then(|a| a.as_str()).map(str::to_string),
            applied: c
                .get("applied")
                .and_then(|a| a.as_str())
                .map(str::to_string),
        }
    }
    table["case"]
        .as_array()
        .expect("[[case]] entries")
        .iter()
        .map(|c| case(c, &strings))
        .collect()
}

/// Writes the corpus's `[[generated]]` files (too large to keep in git) into `dir`: `start`,
/// then `repeat` `count` times, then `end`.
fn generate(dir: &Path) {
    let text = std::fs::read_to_string(corpus().join("cases.toml")).expect("cases.toml");
    let table: toml::Table = text.parse().expect("cases.toml is TOML");
    for g in table
        .get("generated")
        .and_then(|g| g.as_array())
        .into_iter()
        .flatten()
    {
        let s = |k: &str| g[k].as_str().expect("a string").to_string();
        // A copy of a corpus file, for a case that must not be able to damage the original.
        if let Some(from) = g.get("copy").and_then(|c| c.as_str()) {
            std::fs::copy(corpus().join("files").join(from), dir.join(s("file")))
                .expect("a copied file");
            continue;
        }
        let count = g["count"].as_integer().expect("count") as usize;
        let body = format!("{}{}{}", s("start"), s("repeat").repeat(count), s("end"));
        std::fs::write(dir.join(s("file")), body).expect("a generated file");
    }
}

/// What one input did.
struct Ran {
    /// `None`: killed, by a signal or at the time limit.
    code: Option<i32>,
    stdout: String,
    stderr: String,
    took: Duration,
}

/// Runs the binary with `args` in `cwd` under the memory limit.
fn run(args: &[String], cwd: &Path) -> Ran {
    let mut command = Command::new("sh");
    command
        .arg("-c")
        .arg(format!("ulimit -v {MEMORY_KIB}; exec \"$0\" \"$@\""))
        .arg(env!("CARGO_BIN_EXE_softgrip"))
        .args(args)
        .current_dir(cwd)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let started = Instant::now();
    let mut child = command.spawn().expect("sh runs");
    // Read both streams beside the wait, so that a talkative input cannot block on a full pipe.
    let out = child.stdout.take().expect("stdout");
    let err = child.stderr.take().expect("stderr");
    let read = |mut from: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut text = Vec::new();
            let _ = from.read_to_end(&mut text);
            String::from_utf8_lossy(&text).into_owned()
        })
    };
    let (out, err) = (read(Box::new(out)), read(Box::new(err)));
    let code = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status.code();
        }
        if started.elapsed() > TIME_LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    Ran {
        code,
        stdout: out.join().expect("stdout"),
        stderr: err.join().expect("stderr"),
        took: started.elapsed(),
    }
}

/// "NaN" or "nan" as a word: a number that is not one.
fn has_nan(text: &str) -> bool {
    text.split(|c: char| !c.is_ascii_alphanumeric())
        .any(|w| w.eq_ignore_ascii_case("nan"))
}

#[test]
fn no_hostile_input_crashes_hangs_or_answers_silently() {
    let cases = cases();
    assert!(cases.len() >= 60, "the corpus has {} cases", cases.len());
    let cwd = crate::support::scratch_dir("softgrip-hostile");
    generate(&cwd);
    let mut failures = Vec::new();
    let followed: Vec<(&Case, &Case)> = cases
        .iter()
        .filter_map(|c| c.followed.as_deref().map(|f| (c, f)))
        .collect();
    let advised = followed.len();
    for (case, follow) in followed {
        let Some(advice) = case.applied.as_ref().or(case.advice.as_ref()) else {
            failures.push(format!("{}: a followed run without its advice", case.name));
            continue;
        };
        // The run follows the advice: it is in its arguments or in a file they name.
        let applied = follow.args.join(" ").contains(advice.as_str())
            || follow.args.iter().any(|a| {
                a.contains(advice.as_str())
                    || std::fs::read_to_string(a).is_ok_and(|t| t.contains(advice.as_str()))
                    || std::fs::read_to_string(cwd.join(a))
                        .is_ok_and(|t| t.contains(advice.as_str()))
            });
        if !applied {
            failures.push(format!(
                "{}: the followed run ({}) does not apply the advice {advice:?}",
                case.name,
                follow.args.join(" ")
            ));
        }
    }
    let all: Vec<&Case> = cases
        .iter()
        .flat_map(|c| std::iter::once(c).chain(c.followed.as_deref()))
        .collect();
    eprintln!(
        "{} cases, {advised} with their advice followed",
        cases.len()
    );
    for case in all {
        let ran = run(&case.args, &cwd);
        let (code, text) = (ran.code, format!("{}{}", ran.stdout, ran.stderr));
        eprintln!(
            "{}: exit {code:?} in {:.1} s",
            case.name,
            ran.took.as_secs_f64()
        );
        let mut wrong = Vec::new();
        if let Some(advice) = &case.advice
            && !text.contains(advice.as_str())
        {
            wrong.push(format!("does not give the advice {advice:?}"));
        }
        match code {
            None => wrong.push(format!("killed (time limit {TIME_LIMIT:?} or a signal)")),
            Some(101) => wrong.push("panicked".to_string()),
            Some(c) if c != case.exit => wrong.push(format!("exit {c}, not {}", case.exit)),
            Some(_) => {}
        }
        for s in &case.says {
            if !text.contains(s.as_str()) {
                wrong.push(format!("does not say {s:?}"));
            }
        }
        for s in &case.never {
            if text.contains(s.as_str()) {
                wrong.push(format!("says {s:?}"));
            }
        }
        // A message may quote the NaN a user typed; a result may not be one.
        if has_nan(&ran.stdout) {
            wrong.push("prints NaN".to_string());
        }
        // A message, not a dump (a damaged zlib block once printed 6.5 KB of zeros).
        if ran.stderr.len() > MESSAGE_BYTES {
            wrong.push(format!("{} bytes on stderr", ran.stderr.len()));
        }
        if text.contains("panicked") || text.contains("memory allocation of") {
            wrong.push("panics or aborts".to_string());
        }
        if !wrong.is_empty() {
            failures.push(format!(
                "{} ({}): {}\n--- output ---\n{}",
                case.name,
                case.args.join(" "),
                wrong.join("; "),
                text.chars().take(2000).collect::<String>()
            ));
        }
    }
    let _ = std::fs::remove_dir_all(&cwd);
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn nan_is_spotted_as_a_word_only() {
    assert!(has_nan("E = NaN Pa"));
    assert!(has_nan("t,x\n0.1,nan\n"));
    assert!(!has_nan("nano-indentation, Nancy"));
}
