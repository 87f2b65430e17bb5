"""Scale-out gives the single-machine result byte for byte: a sweep through Ray on a local
cluster (a head on loopback, two worker CPUs) and through `sweep --shard` + `merge`."""

from __future__ import annotations

import subprocess

import softgrip
import softgrip.distributed

PARAMS = ["young_modulus=50e3:65e3:4", "tau_c=0.1,0.2"]


def single(cli, shipped, tmp_path):
    csv, out = tmp_path / "one.csv", tmp_path / "one.json"
    args = [str(cli), "sweep", str(shipped), "--csv", str(csv), "--json", str(out), "--no-report"]
    for p in PARAMS:
        args += ["--param", p]
    subprocess.run(args, check=True, capture_output=True)
    return csv.read_text(), out.read_text()


def test_a_sweep_through_ray_is_the_single_machine_sweep(ray_cluster, cli, shipped, tmp_path):
    assert ray_cluster.cluster_resources().get("CPU") == 2
    csv, out = single(cli, shipped, tmp_path)
    # More tasks than points: some shards are empty, and still nothing changes.
    for tasks in (3, 11):
        r = softgrip.distributed.sweep(str(shipped), PARAMS, tasks=tasks)
        assert r.csv == csv and r.json == out, tasks


def test_shards_merged_are_the_single_machine_sweep(cli, shipped, tmp_path):
    csv, out = single(cli, shipped, tmp_path)
    parts = []
    for i in range(3):
        part = tmp_path / f"part{i}.json"
        args = [str(cli), "sweep", str(shipped), "--shard", f"{i}/3", "--part", str(part)]
        for p in PARAMS:
            args += ["--param", p]
        subprocess.run(args, check=True, capture_output=True)
        parts.append(part)
    mcsv, mout = tmp_path / "m.csv", tmp_path / "m.json"
    subprocess.run([str(cli), "merge", *map(str, parts), "--csv", str(mcsv), "--json", str(mout)],
                   check=True, capture_output=True)
    assert mcsv.read_text() == csv and mout.read_text() == out
    # A missing shard is named, not merged into a smaller sweep.
    missing = subprocess.run([str(cli), "merge", str(parts[0]), str(parts[2])],
                             capture_output=True, text=True)
    assert missing.returncode != 0 and "in no shard" in missing.stderr


def test_diagnoses_through_ray_are_the_single_machine_ones_and_resume(ray_cluster, shipped,
                                                                     lattice_diagnosis,
                                                                     tmp_path):
    """A diagnosis on the cluster says what the one on this machine says, saves its fits in one
    file a recording, and resumes from it."""
    one, _, _ = lattice_diagnosis
    (many,) = softgrip.distributed.diagnose([shipped], model="scene", max_effects=1,
                                            checkpoint=tmp_path)
    assert many.to_dict() == one.to_dict()
    (file,) = tmp_path.iterdir()
    assert file.name.endswith("thesis_7_loads.checkpoint") and file.read_text().count("\n") >= 2
    (again,) = softgrip.distributed.diagnose([shipped], model="scene", max_effects=1,
                                             checkpoint=tmp_path)
    assert again.verdict == many.verdict


def test_grasp_windows_through_ray_are_the_single_machine_ones(ray_cluster):
    """Windows of scene files as Ray tasks: each the one :func:`softgrip.grasp_window` gives."""
    from pathlib import Path

    scene = Path(__file__).resolve().parents[3] / "assets" / "scenes" / "grasp_lift.toml"
    options = dict(damage="pressure", limit=5e3, confirm=False)
    local = softgrip.grasp_window(softgrip.Scene.load(scene), **options)
    remote = softgrip.distributed.grasp_windows([scene, scene], **options)
    assert [w.to_dict() for w in remote] == [local.to_dict()] * 2
