"""Shared fixtures: the repository's shipped recording, the CLI binary the Rust tests built,
and a local Ray cluster started on loopback for the distributed tests."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
SHIPPED = ROOT / "assets" / "recordings" / "synthetic" / "thesis_7_loads" / "recording.toml"


@pytest.fixture(scope="session")
def shipped() -> Path:
    return SHIPPED


@pytest.fixture(scope="session")
def cli() -> Path:
    """The `softgrip` binary: $SOFTGRIP_BIN, else target/release or target/debug (built by
    `cargo build` or `cargo test`, as .ci/run does before pytest)."""
    given = os.environ.get("SOFTGRIP_BIN")
    candidates = [Path(given)] if given else [
        ROOT / "target" / "release" / "softgrip",
        ROOT / "target" / "debug" / "softgrip",
    ]
    for c in candidates:
        if c.is_file():
            return c
    raise FileNotFoundError(
        f"no softgrip binary at {', '.join(map(str, candidates))}: run `cargo build` first "
        "or set SOFTGRIP_BIN"
    )


@pytest.fixture(scope="session")
def lattice_diagnosis(shipped, tmp_path_factory):
    """The shipped recording diagnosed from the scene's own model (one effect at most), its fits
    saved as they end, and its progress calls: one diagnosis the tests read (each takes seconds)."""
    import softgrip

    checkpoint = tmp_path_factory.mktemp("diagnosis") / "fits.checkpoint"
    calls = []
    d = softgrip.diagnose(softgrip.Recording.load(shipped), model="scene", max_effects=1,
                          checkpoint=checkpoint, progress=lambda *a: calls.append(a))
    return d, checkpoint, calls


@pytest.fixture(scope="session")
def ray_cluster(tmp_path_factory):
    """A Ray head on loopback with two worker CPUs, started and stopped by the test session."""
    import sys

    import ray

    ray_bin = str(Path(sys.executable).parent / "ray")
    if not Path(ray_bin).is_file():
        ray_bin = shutil.which("ray") or "ray"
    port = "6388"
    temp = tmp_path_factory.mktemp("ray")
    # One auth mode for the head and this client: Ray 2.59+ turns tokens on for local clusters,
    # and a ~/.ray/auth_token left by an earlier `ray.init()` made them disagree.
    os.environ["RAY_AUTH_MODE"] = "disabled"
    env = dict(os.environ, RAY_USAGE_STATS_ENABLED="0")
    subprocess.run(
        [ray_bin, "start", "--head", "--node-ip-address=127.0.0.1", f"--port={port}",
         "--num-cpus=2", "--include-dashboard=false", "--disable-usage-stats",
         f"--temp-dir={temp}"],
        check=True, env=env, capture_output=True,
    )
    try:
        ray.init(address=f"127.0.0.1:{port}", logging_level="ERROR")
        yield ray
    finally:
        ray.shutdown()
        subprocess.run([ray_bin, "stop", "--force"], env=env, capture_output=True)
