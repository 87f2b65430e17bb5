#!/usr/bin/env python3
"""Every other build .ci/run makes reuses the dependencies that `cargo test` compiled.

Cargo compiles a dependency once per feature set: a build that selects fewer packages (the
Python package, the TetGen tests, the binary without the viewer) asks some shared dependencies
for fewer features and compiles them, and everything above them, again. crates/workspace-hack
asks for the union. This check lists each shared dependency whose feature set in one of those
builds is not one the workspace's test build has, with the line to add to the hack crate.
Only `cargo tree` runs (no compiling): a few seconds.
"""

import subprocess
import sys
from collections import defaultdict

WORKSPACE = ["--workspace", "-e", "normal,build,dev"]
BUILDS = {
    "Python package (pip)": ["-p", "softgrip-py", "-e", "normal,build"],
    "TetGen tests": ["-p", "softgrip-core", "--features", "tetgen", "-e", "normal,build,dev"],
    "binary without the viewer": ["-p", "softgrip", "--no-default-features", "-e", "normal,build"],
}
# clap comes to the core's tests through criterion (benches) with fewer features than the binary
# asks: the TetGen step builds it again (seconds) rather than put clap in the core's graph.
ONLY_TETGEN = {"clap", "clap_builder"}


def feature_sets(args):
    run = subprocess.run(
        ["cargo", "tree", "--locked", "--prefix", "none", "-f", "{p}|{f}", *args],
        capture_output=True, text=True,
    )
    if run.returncode != 0:
        sys.exit(f"cargo tree {' '.join(args)} failed:\n{run.stderr}")
    out = run.stdout
    sets = defaultdict(set)
    for line in out.splitlines():
        line = line.replace(" (*)", "")
        if "|" not in line:
            continue
        package, features = line.split("|", 1)
        name_version = " ".join(package.split()[:2])
        sets[name_version].add(features.strip())
    return sets


def main():
    workspace = feature_sets(WORKSPACE)
    missing = []
    for build, args in BUILDS.items():
        for package, sets in sorted(feature_sets(args).items()):
            # The workspace's own crates differ by the features the build asks for.
            own = package.split()[0].startswith("softgrip")
            if own or package not in workspace or package.split()[0] in ONLY_TETGEN:
                continue
            for features in sorted(sets - workspace[package]):
                want = sorted(workspace[package], key=len)[-1]
                missing.append(f"{build}: {package} [{features}]; the test build has [{want}]")
    if missing:
        print("These builds would compile a shared dependency again (add its features to "
              "crates/workspace-hack/Cargo.toml):")
        print("\n".join("  " + m for m in missing))
        return 1
    print(f"{len(BUILDS)} builds reuse the test build's dependencies")
    return 0


if __name__ == "__main__":
    sys.exit(main())
