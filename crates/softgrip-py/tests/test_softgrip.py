"""The Python API against the CLI and the physics it wraps: every function, the arrays' shapes
and dtypes, the exceptions, and the same JSON as `softgrip ... --json` on a shipped recording."""

from __future__ import annotations

import json
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import softgrip
from softgrip import Recording, Scene, Simulation, SoftgripError


def cli_json(cli, tmp_path, *args) -> dict:
    out = tmp_path / "out.json"
    subprocess.run([str(cli), *map(str, args), "--json", str(out), "--no-report"],
                   check=True, capture_output=True)
    return json.loads(out.read_text())


def test_scene_round_trips_and_checks_parameters():
    s = Scene.thesis()
    assert s["young_modulus"] == 57.6e3
    again = Scene.from_toml(s.to_toml())
    assert again.to_toml() == s.to_toml()
    s["young_modulus"] = 60e3
    assert s["young_modulus"] == 60e3 and again["young_modulus"] == 57.6e3
    with pytest.raises(SoftgripError, match="young_modulus"):
        s["young_modulus"] = -1.0
    with pytest.raises(SoftgripError, match="unknown parameter"):
        s["no_such_thing"]
    assert "young_modulus" in Scene.parameters()
    with pytest.raises(SoftgripError, match="line"):
        Scene.from_toml("[object\nsize = 1", "bad.toml")
    with pytest.raises(SoftgripError, match="nowhere.toml"):
        Scene.load("nowhere.toml")


def test_simulation_arrays_have_the_models_shapes_and_dtypes():
    sim = Simulation(Scene.thesis())
    n = sim.positions.shape[0]
    assert sim.positions.shape == (n, 3) and sim.positions.dtype == np.float64
    assert sim.velocities.shape == (n, 3) and sim.rest_positions.shape == (n, 3)
    assert sim.masses.shape == (n,) and sim.masses.dtype == np.float64
    tets, tris = sim.tetrahedra, sim.surface
    assert tets.shape[1] == 4 and tets.dtype == np.uint32 and tets.max() < n
    assert tris.shape[1] == 3 and tris.dtype == np.uint32 and tris.max() < n
    # Rest: the positions are the rest positions, nothing moves.
    np.testing.assert_array_equal(sim.positions, sim.rest_positions)
    f = sim.fingers
    assert f["position"].shape == (1, 3) and f["normal_force"].shape == (1,)


def test_stepping_conserves_mass_and_moves_time_by_dt():
    sim = Simulation(Scene.thesis())
    dt = sim.dt
    sim.step(10)
    assert sim.steps == 10 and sim.time == pytest.approx(10 * dt)
    sim.run(0.02)
    assert sim.steps == 10 + round(0.02 / dt)
    # The finger pressed into the top: contacts, each pushing the object down (-z).
    c = sim.contacts
    k = len(c["finger"])
    assert k > 0 and c["point"].shape == (k, 3) and c["normal_force"].shape == (k,)
    assert np.all(c["normal_force"] >= 0)
    assert set(sim.stats) >= {"cg_iterations", "energy", "volume_error", "contacts"}


def test_limiting_cores_changes_no_bit():
    two = Simulation(Scene.thesis(), threads=2)
    two.step(50)
    softgrip.limit_cores(1)
    try:
        capped = Simulation(Scene.thesis())
        capped.step(50)
    finally:
        softgrip.limit_cores(0)
    np.testing.assert_array_equal(capped.positions, two.positions)
    assert not np.array_equal(two.positions, two.rest_positions)


def test_run_calls_back_with_the_gil_and_the_steps_run_without_it():
    sim = Simulation(Scene.thesis())
    times = []
    sim.run(0.01, callback=lambda s: times.append(s.time), every=0.002)
    assert len(times) == 5 and times == sorted(times)
    # Another Python thread runs while the simulation steps (the GIL is released).
    ticks = []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(1)
            time.sleep(0.001)

    t = threading.Thread(target=tick)
    t.start()
    sim.step(50)
    stop.set()
    t.join()
    assert len(ticks) > 5
    with pytest.raises(SoftgripError, match="every"):
        sim.run(0.01, callback=print, every=0)
    with pytest.raises(SoftgripError, match="seconds"):
        sim.run(-1.0)


def test_equilibrium_balances_the_weight_and_a_load():
    # The thesis scene loads its finger by the platform's weight: 0.992 kg.
    sim = Simulation(Scene.thesis())
    assert sim.equilibrium()["iterations"] > 0
    assert sim.fingers["contact_force"][0, 2] == pytest.approx(0.992 * 9.81, rel=1e-4)
    with pytest.raises(SoftgripError, match="no direction"):
        sim.equilibrium(2.0)
    # A mass-less finger pushed along -z: the contact balances each load in turn.
    text = Scene.thesis().to_toml()
    text = text.replace("force = [0.0, 0.0, 0.0]", "force = [0.0, 0.0, -1.0]")
    text = text.replace("mass = 0.992", "mass = 0.0")
    sim = Simulation(Scene.from_toml(text))
    for load in (1.0, 3.0):
        sim.equilibrium(load)
        assert sim.fingers["contact_force"][0, 2] == pytest.approx(load, rel=1e-4)


def test_recording_frame_round_trip(shipped):
    rec = Recording.load(shipped)
    assert rec.mode == "quasi-static" and len(rec) == 7
    df = rec.to_frame()
    assert list(df.columns) == ["time", "load", "marker", "x", "y", "z"]
    assert df["time"].isna().all() and df["y"].isna().all()
    again = Recording.from_frame(df, rec.scene, rec.markers)
    pd.testing.assert_frame_equal(again.to_frame(), df)
    assert softgrip.compare(again).nrmse == softgrip.compare(rec).nrmse
    with pytest.raises(SoftgripError, match="marker"):
        Recording.from_frame(df.drop(columns=["marker"]), rec.scene, rec.markers)
    bad = df.copy()
    bad.loc[0, "marker"] = "nobody"
    with pytest.raises(SoftgripError, match="nobody"):
        Recording.from_frame(bad, rec.scene, rec.markers)


def test_compare_is_the_clis_json(shipped, cli, tmp_path):
    rec = Recording.load(shipped)
    assert softgrip.compare(rec).to_dict() == cli_json(cli, tmp_path, "compare", shipped)


def test_fit_is_the_clis_json(shipped, cli, tmp_path):
    rec = Recording.load(shipped)
    py = softgrip.fit(rec, ["young_modulus=40e3:80e3"], max_evaluations=12, workers=1)
    ref = cli_json(cli, tmp_path, "fit", shipped, "--params", "young_modulus=40e3:80e3",
                   "--max-evaluations", 12, "--workers", 1)
    assert py.to_dict() == ref
    assert py.to_frame().loc[0, "param"] == "young_modulus"
    assert 40e3 <= py.params["young_modulus"] <= 80e3


def test_sweep_is_the_clis_csv_and_json(shipped, cli, tmp_path):
    rec = Recording.load(shipped)
    params = ["young_modulus=50e3:65e3:3", "tau_c=0.1,0.2"]
    py = softgrip.sweep(rec, params, workers=2)
    csv, out = tmp_path / "s.csv", tmp_path / "s.json"
    args = [str(cli), "sweep", str(shipped), "--csv", str(csv), "--json", str(out), "--no-report"]
    for p in params:
        args += ["--param", p]
    subprocess.run(args, check=True, capture_output=True)
    assert py.csv == csv.read_text() and py.json == out.read_text()
    frame = py.to_frame()
    assert len(frame) == 6 and frame["nrmse"].min() == py.nrmse


def test_diagnose_names_nothing_on_a_recording_of_its_own_model(shipped, lattice_diagnosis):
    """thesis_7_loads is the thesis lattice itself with noise: from the scene's own model the
    residual is noise, and the verdict "none"."""
    d, _, calls = lattice_diagnosis
    assert d.verdict == "none" and d.effects == [] and d.model == "lattice"
    # Loading only, and the model is the truth: nothing left, nothing set aside.
    assert d.set_aside == [] and d.unexplained_at == []
    assert calls and calls[0][0] == 0
    assert isinstance(d.to_frame(), pd.DataFrame)
    rec = Recording.load(shipped)
    with pytest.raises(SoftgripError, match="model"):
        softgrip.diagnose(rec, model="fem")
    with pytest.raises(SoftgripError, match="--bound"):
        softgrip.diagnose(rec, bounds=["young_modulus=1:"])


def test_a_diagnosis_resumes_from_its_checkpoint(shipped, lattice_diagnosis):
    """Each fit is saved as it ends; the same call again takes them from the file: it saves no
    fit again, and says the same."""
    first, path, _ = lattice_diagnosis
    saved = path.read_text().splitlines()
    assert len(saved) >= 2, saved
    again = softgrip.diagnose(Recording.load(shipped), model="scene", max_effects=1,
                              checkpoint=path)
    assert path.read_text().splitlines() == saved
    assert again.verdict == first.verdict


def test_ctrl_c_stops_a_long_run(tmp_path):
    """SIGINT during `run(1000)` raises KeyboardInterrupt at once, as in Python code."""
    import signal
    import sys

    script = tmp_path / "long.py"
    script.write_text(
        # As an interactive Python does (a shell's background job starts with SIGINT ignored).
        "import signal, softgrip\n"
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        "sim = softgrip.Simulation(softgrip.Scene.thesis())\n"
        "print('ready', flush=True)\n"
        "try:\n"
        "    sim.run(1000.0)\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted at', sim.time, flush=True)\n"
    )
    p = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "ready"
    time.sleep(1.0)
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=60)
    assert p.returncode == 0 and out.startswith("interrupted at"), out
    assert float(out.split()[-1]) < 1000.0


ONE_SAMPLE = Path(__file__).resolve().parents[3] / "tests" / "hostile" / "files" / "i55" / "rec_one_sample" / "recording.toml"


def test_every_error_with_advice_is_followed_and_the_advice_works(tmp_path):
    """Each message of the API that says what to do (tests/hostile/ADVICE.md), then what it
    says done: the call works (or gets past that check to the next one)."""
    sim = Simulation(Scene.thesis())
    with pytest.raises(SoftgripError, match="give a number of simulated seconds, 0 or more"):
        sim.run(-1.0)
    sim.run(0.002)
    with pytest.raises(SoftgripError, match="give the simulated seconds between callbacks, above 0"):
        sim.run(0.002, callback=lambda s: None, every=0.0)
    sim.run(0.002, callback=lambda s: None, every=0.001)
    pushed = Scene.thesis().to_toml().replace("force = [0.0, 0.0, 0.0]", "force = [0.0, 0.0, -1.0]")
    pushed = pushed.replace("mass = 0.992", "mass = 0.0")
    with pytest.raises(SoftgripError, match="give a load in N"):
        Simulation(Scene.from_toml(pushed)).equilibrium(float("nan"))
    Simulation(Scene.from_toml(pushed)).equilibrium(1.0)
    with pytest.raises(SoftgripError, match=r"give it a force \(e.g. \[0, 0, -1\]\)"):
        Simulation(Scene.thesis()).equilibrium(1.0)
    driven = Scene.thesis().to_toml().replace('control = "force"', 'control = "velocity"')
    with pytest.raises(SoftgripError, match=r'add a \[\[finger\]\] with control = "force"'):
        Simulation(Scene.from_toml(driven)).equilibrium(1.0)
    one = Recording.load(ONE_SAMPLE)
    with pytest.raises(SoftgripError, match='give "continuum", "lattice" or "scene"'):
        softgrip.diagnose(one, model="springs")
    # Followed, the call gets past the model to the recording's own refusal (one sample).
    with pytest.raises(SoftgripError, match=r"1 sample\(s\)"):
        softgrip.diagnose(one, model="continuum")
    with pytest.raises(SoftgripError, match="give a file you can write"):
        softgrip.diagnose(one, checkpoint=tmp_path)  # a directory
    with pytest.raises(SoftgripError, match=r"1 sample\(s\)"):
        softgrip.diagnose(one, checkpoint=tmp_path / "fits.checkpoint")


def test_grasp_window_is_the_clis_json_and_its_curves(cli, tmp_path):
    """The shipped two-finger scene's window from Python: the CLI's JSON, and the squeezes tried
    as arrays and a frame (the least squeeze held, the one below it not)."""
    scene_path = Path(__file__).resolve().parents[3] / "assets" / "scenes" / "grasp_lift.toml"
    w = softgrip.grasp_window(Scene.load(scene_path), damage="pressure", limit=5e3, confirm=False)
    out = tmp_path / "window.json"
    subprocess.run([str(cli), "grasp", "window", str(scene_path), "--damage", "pressure",
                    "--limit", "5000", "--no-confirm", "--json", str(out)],
                   check=True, capture_output=True)
    ref = json.loads(out.read_text())
    assert w.to_dict() == ref
    assert w.window and 0.28 < w.least_squeeze < w.most_squeeze
    curves = w.curves
    held = curves["squeeze"][curves["held"]]
    assert held.min() == w.least_squeeze
    assert len(w.to_frame()) == len(curves["squeeze"])
