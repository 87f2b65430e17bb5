//! The commit the binary is built from, for reports that must say which rules ran (`softgrip
//! prove`'s DIAGNOSIS.md): `SOFTGRIP_COMMIT`, empty outside a git checkout, ending in `-dirty`
//! when the code differs from that commit (as `git describe --dirty` says it).

use std::process::Command;

fn main() {
    let git = |args: &[&str]| {
        Command::new("git")
            .args(args)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    // The code only: a changed doc or result file leaves the rules as they were.
    const CODE: [&str; 5] = ["src", "crates", "Cargo.toml", "Cargo.lock", "build.rs"];
    let mut commit = git(&["rev-parse", "--short=7", "HEAD"]).unwrap_or_default();
    let mut diff = vec!["diff", "--quiet", "HEAD", "--"];
    diff.extend(CODE);
    let clean = Command::new("git")
        .args(&diff)
        .status()
        .map(|s| s.success());
    if !commit.is_empty() && clean.is_ok_and(|c| !c) {
        commit.push_str("-dirty");
    }
    println!("cargo:rustc-env=SOFTGRIP_COMMIT={commit}");
    for path in CODE {
        println!("cargo:rerun-if-changed={path}");
    }
    // A new commit moves HEAD or the branch it names; only files that exist, or cargo reruns
    // the script on every build.
    if let Some(dir) = git(&["rev-parse", "--git-dir"]) {
        let mut watched = vec![format!("{dir}/HEAD")];
        if let Some(branch) = git(&["symbolic-ref", "-q", "HEAD"]) {
            watched.push(format!("{dir}/{branch}"));
        }
        watched.push(format!("{dir}/packed-refs"));
        for path in watched {
            if std::path::Path::new(&path).exists() {
                println!("cargo:rerun-if-changed={path}");
            }
        }
    }
}
