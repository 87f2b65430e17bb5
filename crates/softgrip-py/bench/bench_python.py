"""Python's overhead, side by side in one run (docs/results/benchmarks.md#python):

1. stepping: wall seconds per simulated second of the thesis scene, `softgrip run` against
   `Simulation(Scene.thesis()).run(...)`, alternated;
2. a 200-point sweep of thesis_7_loads: `softgrip sweep --workers 2` against
   `softgrip.distributed.sweep` on a local Ray with two CPUs, alternated.

Usage: python bench_python.py [--bin target/release/softgrip] [--repeats 3]
Run it on a quiet machine: nothing else running."""

from __future__ import annotations

import argparse
import platform
import statistics
import subprocess
import time
from pathlib import Path

import softgrip
import softgrip.distributed

ROOT = Path(__file__).resolve().parents[3]
REC = ROOT / "assets/recordings/synthetic/thesis_7_loads/recording.toml"
GRID = ["young_modulus=40e3:80e3:20", "tau_c=0.05:0.3:10"]


def wall(f) -> float:
    t = time.perf_counter()
    f()
    return time.perf_counter() - t


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default=str(ROOT / "target/release/softgrip"))
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--seconds", type=float, default=1.0)
    a = ap.parse_args()
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if "model name" in l), "?")
    print(f"{platform.node()}, {cpu}, {time.strftime('%Y-%m-%d')}, softgrip {softgrip.__version__}")

    cli_run, py_run = [], []
    for _ in range(a.repeats):
        cli_run.append(wall(lambda: subprocess.run(
            [a.bin, "run", "--duration", str(a.seconds)], check=True, capture_output=True)))
        py_run.append(wall(lambda: softgrip.Simulation(softgrip.Scene.thesis()).run(a.seconds)))
    c, p = statistics.median(cli_run), statistics.median(py_run)
    print(f"| stepping, wall s per simulated s | {c / a.seconds:.3f} | {p / a.seconds:.3f} | "
          f"{100 * (p / c - 1):+.1f} % |")

    import ray
    ray.init(num_cpus=2, include_dashboard=False, logging_level="ERROR")
    cli_sweep, ray_sweep = [], []
    args = [a.bin, "sweep", str(REC), "--workers", "2", "--no-report"]
    for g in GRID:
        args += ["--param", g]
    for _ in range(max(1, a.repeats - 1)):
        cli_sweep.append(wall(lambda: subprocess.run(args, check=True, capture_output=True)))
        ray_sweep.append(wall(lambda: softgrip.distributed.sweep(str(REC), GRID)))
    c, r = statistics.median(cli_sweep), statistics.median(ray_sweep)
    print(f"| 200-point sweep, wall s | {c:.1f} (--workers 2) | {r:.1f} (Ray, 2 CPUs) | "
          f"{100 * (r / c - 1):+.1f} % |")


if __name__ == "__main__":
    main()
