"""softgrip on more than one machine with Ray: a sweep's points, a series of recordings'
diagnoses and a series of scenes' grasp windows as independent Ray tasks. ``ray.init()`` alone uses this machine's cores;
``ray.init(address="auto")`` (or ``address=...`` here) a running cluster. The results are
those of one machine's run, byte for byte (the sweep's CSV and JSON). Every node must read the
recordings at the paths given (a shared file system). Without Ray: ``softgrip sweep --shard``
and ``softgrip merge`` (docs/cluster.md)."""

from __future__ import annotations

import os
from pathlib import Path

from . import _softgrip
from .results import Diagnosis, GraspWindow, SweepResult


def _ray(address: str | None):
    try:
        import ray
    except ImportError as e:
        raise ImportError("softgrip.distributed needs Ray: pip install 'ray>=2.9'") from e
    if not ray.is_initialized():
        ray.init(address=address)
    return ray


def sweep(
    recording: str | os.PathLike,
    params: list[str],
    tasks: int | None = None,
    address: str | None = None,
) -> SweepResult:
    """``softgrip sweep RECORDING --param ...`` as Ray tasks: shard ``i`` of ``tasks`` takes
    every ``tasks``-th grid point from the ``i``-th, on one core (default: four tasks a core
    of the cluster, so a slow corner of the grid does not hold up the rest). The merged
    result equals the single-machine sweep's, its ``csv`` and ``json`` byte for byte."""
    ray = _ray(address)
    name = os.fspath(recording)
    path = str(Path(name).resolve())
    if tasks is None:
        tasks = 4 * max(1, int(ray.cluster_resources().get("CPU", 1)))
    if tasks < 1:
        raise _softgrip.SoftgripError(f"tasks={tasks}: give 1 or more")
    part = ray.remote(num_cpus=1)(_part)
    parts = ray.get([part.remote(path, list(params), i, tasks, name) for i in range(tasks)])
    csv, json_text = _softgrip.sweep_merge(parts)
    return SweepResult.from_outputs(csv, json_text)


def _part(path: str, params: list[str], index: int, count: int, name: str) -> str:
    # One core, as the task asked Ray for: a second thread would spin on a core that
    # another task of this machine runs on (benchmarks.md#python: +16 % on 2 cores).
    _softgrip.limit_cores(1)
    return _softgrip.sweep_part(path, params, index, count, 1, name)


def diagnose(
    recordings: list[str | os.PathLike],
    address: str | None = None,
    **options,
) -> list[Diagnosis]:
    """:func:`softgrip.diagnose` of each recording as a Ray task (one core each), in the
    order given; ``options`` as :func:`softgrip.diagnose` takes them (``model``, ``bounds``,
    ...), except ``checkpoint``: a directory (on the shared file system) where each
    recording's fits are saved as they end, so that a task Ray retries, or a call made again,
    resumes. A recording whose diagnosis fails raises its ``SoftgripError`` here."""
    ray = _ray(address)
    task = ray.remote(num_cpus=1)(_diagnose)
    paths = [str(Path(os.fspath(r)).resolve()) for r in recordings]
    checkpoints = options.pop("checkpoint", None)
    files = [
        None
        if checkpoints is None
        else str(Path(os.fspath(checkpoints)).resolve() / (_name(p) + ".checkpoint"))
        for p in paths
    ]
    return [
        Diagnosis.from_json(t)
        for t in ray.get([task.remote(p, options, f) for p, f in zip(paths, files)])
    ]


def _name(path: str) -> str:
    # The recording's directory, slashes as _: two recordings of one name in different
    # directories keep apart.
    return str(Path(path).parent).strip("/").replace("/", "_")


def _diagnose(path: str, options: dict, checkpoint: str | None) -> str:
    _softgrip.limit_cores(1)
    return _softgrip.diagnose(
        _softgrip.Recording.load(path),
        options.get("model", "continuum"),
        options.get("max_effects", 2),
        list(options.get("bounds") or []),
        list(options.get("lock") or []),
        1,
        None,
        checkpoint,
    )


def grasp_windows(
    scenes: list[str | os.PathLike],
    address: str | None = None,
    **options,
) -> list[GraspWindow]:
    """:func:`softgrip.grasp_window` of each scene file as a Ray task (one core each), in the
    order given: a sweep of windows over object sizes or materials, one scene file each;
    ``options`` as :func:`softgrip.grasp_window` takes them (``acceleration``, ``damage``,
    ``limit``, ``fit``, ``confirm``, ...). A scene whose window fails raises its
    ``SoftgripError`` here."""
    ray = _ray(address)
    task = ray.remote(num_cpus=1)(_grasp_window)
    paths = [str(Path(os.fspath(s)).resolve()) for s in scenes]
    if "fit" in options and options["fit"] is not None:
        options["fit"] = str(Path(os.fspath(options["fit"])).resolve())
    return [GraspWindow.from_json(t) for t in ray.get([task.remote(p, options) for p in paths])]


def _grasp_window(path: str, options: dict) -> str:
    _softgrip.limit_cores(1)
    return _softgrip.grasp_window(
        _softgrip.Scene.load(path),
        options.get("acceleration"),
        options.get("shake"),
        options.get("slip_tolerance"),
        options.get("hold"),
        options.get("damage"),
        options.get("limit"),
        options.get("fit"),
        options.get("confirm", True),
    )
