"""softgrip from Python: soft-object grasp simulation, lab recordings, fits and the diagnosis.

    import softgrip
    scene = softgrip.Scene.thesis()
    scene["young_modulus"] = 60e3
    sim = softgrip.Simulation(scene)
    sim.run(0.5)
    sim.positions            # (n, 3) numpy array, m

    rec = softgrip.Recording.load("assets/recordings/synthetic/thesis_7_loads/recording.toml")
    softgrip.compare(rec).nrmse
    softgrip.diagnose(rec).verdict

The figures are those of the CLI's ``--json`` (docs/formats.md); every result has
``to_dict()`` and ``to_frame()``. Errors raise :class:`SoftgripError` with the CLI's messages.
"""

from __future__ import annotations

import os

from ._softgrip import Scene, Simulation, SoftgripError, __version__, limit_cores
from . import _softgrip
from .recording import Recording
from .results import CompareResult, Diagnosis, FitResult, GraspWindow, Result, SweepResult

__all__ = [
    "Scene",
    "Simulation",
    "Recording",
    "SoftgripError",
    "compare",
    "fit",
    "sweep",
    "diagnose",
    "grasp_window",
    "limit_cores",
    "Result",
    "CompareResult",
    "FitResult",
    "SweepResult",
    "Diagnosis",
    "GraspWindow",
    "__version__",
]


def compare(recording: Recording, scene: Scene | None = None) -> CompareResult:
    """The recording replayed on its own scene (or ``scene``): NRMSE and RMSE as
    ``softgrip compare --json`` gives them."""
    return CompareResult.from_json(_softgrip.compare(recording._inner, scene))


def fit(
    recording: Recording,
    params: list[str],
    max_evaluations: int = 400,
    workers: int = 0,
) -> FitResult:
    """Fits ``params`` (``"young_modulus"`` or ``"young_modulus=30e3:120e3"``) of the
    recording's scene to it, as ``softgrip fit --json``; ``workers`` threads (0: one per core)."""
    return FitResult.from_json(
        _softgrip.fit(recording._inner, list(params), max_evaluations, workers)
    )


def sweep(recording: Recording, params: list[str], workers: int = 0) -> SweepResult:
    """Every point of a grid of one or two parameters (``"tau_c=0.01:0.25:25"``,
    ``"alpha=1e5:1e8:7:log"``, ``"young_modulus=50e3,60e3"``) against the recording, as
    ``softgrip sweep --csv --json``; ``workers`` threads (0: one per core). For a cluster:
    :func:`softgrip.distributed.sweep`."""
    csv, json_text = _softgrip.sweep(recording._inner, list(params), workers)
    return SweepResult.from_outputs(csv, json_text)


def diagnose(
    recording: Recording,
    model: str = "continuum",
    max_effects: int = 2,
    bounds: list[str] | None = None,
    lock: list[str] | None = None,
    workers: int = 0,
    progress=None,
    checkpoint: str | os.PathLike | None = None,
    region_scan: bool = False,
) -> Diagnosis:
    """What physics the model left out, as ``softgrip diagnose --json``: ``model`` is
    "continuum" (default), "lattice" or "scene"; ``bounds`` like ``"young_modulus=30e3:120e3"``;
    ``progress(done, planned, what)`` is called as each fit starts. Minutes of work (a beam's,
    hours): Ctrl-C stops it, and with ``checkpoint`` (a file) each fit is saved as it ends, so
    the same call resumes where it stopped. ``region_scan``: the region scan's shapes may
    name a region, not only the four halves (``--region-scan``; a region the halves name is placed
    by the scan either way)."""
    return Diagnosis.from_json(
        _softgrip.diagnose(
            recording._inner,
            model,
            max_effects,
            list(bounds or []),
            list(lock or []),
            workers,
            progress,
            None if checkpoint is None else os.fspath(checkpoint),
            region_scan,
        )
    )


def grasp_window(
    scene: Scene,
    acceleration: float | None = None,
    shake: float | None = None,
    slip_tolerance: float | None = None,
    hold: float | None = None,
    damage: str | None = None,
    limit: float | None = None,
    fit: str | os.PathLike | None = None,
    confirm: bool = True,
) -> GraspWindow:
    """How hard the scene's gripper may squeeze, as ``softgrip grasp window --json``: the least
    squeeze (N per finger) that holds the object through a lift of ``acceleration`` (m/s^2 up)
    and the most before ``damage`` ("strain", "stress" or "pressure") reaches ``limit``; each
    option left out comes from the scene's ``[grasp]``. ``fit``: a ``fit --json`` file whose
    material is set in and whose standard errors are carried to both bounds. ``confirm`` lifts
    each bound dynamically. The curves: :meth:`GraspWindow.to_frame`, :attr:`GraspWindow.curves`.
    A sweep of windows over sizes or materials: :func:`softgrip.distributed.map`."""
    return GraspWindow.from_json(
        _softgrip.grasp_window(
            scene,
            acceleration,
            shake,
            slip_tolerance,
            hold,
            damage,
            limit,
            None if fit is None else os.fspath(fit),
            confirm,
        )
    )
