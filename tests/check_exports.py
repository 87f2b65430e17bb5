"""Issue 4, acceptance 4: what `softgrip run --out DIR --surface stl` writes
opens with meshio (the reader ParaView users script with) and carries the
fields softgrip documents, the object's frames (part 0 of trajectory.pvd)
and each finger's (parts 1, 2, ...). Run by .ci/run after `cargo test`:

    python3 tests/check_exports.py DIR

Exits non-zero, saying what is wrong, if a file does not read or a field
is missing or has the wrong shape.
"""

import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import meshio
import numpy as np

POINT_FIELDS = {"displacement": 3, "velocity": 3, "contact_force": 3, "fixed": 1}
CELL_FIELDS = {"volume_ratio": 1, "max_spring_strain": 1}
FINGER_FIELDS = {"displacement": 3, "velocity": 3, "contact_force": 3}


def fail(message: str) -> None:
    print(f"check_exports: {message}", file=sys.stderr)
    sys.exit(1)


def main() -> None:
    out = Path(sys.argv[1])
    pvd = out / "trajectory.pvd"
    everything = ET.parse(pvd).getroot().findall("./Collection/DataSet")
    datasets = [d for d in everything if d.get("part") == "0"]
    fingers = {}
    for d in everything:
        if d.get("part") != "0":
            fingers.setdefault(d.get("part"), []).append(d)
    if len(datasets) < 2:
        fail(f"{pvd}: {len(datasets)} frames, expected at least 2")
    times = [float(d.get("timestep")) for d in datasets]
    if times != sorted(times):
        fail(f"{pvd}: timesteps out of order: {times}")
    for d in datasets:
        path = out / d.get("file")
        mesh = meshio.read(path)
        tetra = [c for c in mesh.cells if c.type == "tetra"]
        if len(tetra) != 1 or len(tetra[0].data) == 0:
            fail(f"{path}: no tetra cell block")
        n, t = len(mesh.points), len(tetra[0].data)
        for name, width in POINT_FIELDS.items():
            a = mesh.point_data.get(name)
            if a is None:
                fail(f"{path}: no point data {name!r} (has {sorted(mesh.point_data)})")
            shape = (n, width) if width > 1 else (n,)
            if a.shape != shape or not np.all(np.isfinite(a)):
                fail(f"{path}: point data {name!r} has shape {a.shape}, expected {shape}, finite")
        for name, width in CELL_FIELDS.items():
            a = mesh.cell_data.get(name)
            if a is None:
                fail(f"{path}: no cell data {name!r} (has {sorted(mesh.cell_data)})")
            if a[0].shape != (t,) or not np.all(np.isfinite(a[0])):
                fail(f"{path}: cell data {name!r} has shape {a[0].shape}, expected ({t},)")
        # Contact somewhere by the last frame: the thesis finger lands.
    last = meshio.read(out / datasets[-1].get("file"))
    if not np.any(np.linalg.norm(last.point_data["contact_force"], axis=1) > 0):
        fail("no contact force in the last frame")
    # Each finger: a block of its own, a triangulated surface per frame at
    # the object's times, every point carrying the finger's fields.
    if not fingers:
        fail(f"{pvd}: no finger parts (part=\"1\", ...)")
    for part, sets in sorted(fingers.items()):
        part_times = [float(d.get("timestep")) for d in sets]
        if part_times != [float(d.get("timestep")) for d in datasets]:
            fail(f"{pvd}: part {part} has times {part_times}, the object {times}")
        for d in sets:
            path = out / d.get("file")
            mesh = meshio.read(path)
            tri = mesh.cells_dict.get("triangle")
            if tri is None or len(tri) == 0:
                fail(f"{path}: no triangles")
            m = len(mesh.points)
            for name, width in FINGER_FIELDS.items():
                a = mesh.point_data.get(name)
                if a is None:
                    fail(f"{path}: no point data {name!r} (has {sorted(mesh.point_data)})")
                if a.shape != (m, width) or not np.all(np.isfinite(a)):
                    fail(f"{path}: point data {name!r} has shape {a.shape}, expected ({m}, {width}), finite")
        if len(fingers) > 1:
            continue
        # One finger: its contact force is the reaction to the object's total, in the last frame.
        force = meshio.read(out / sets[-1].get("file")).point_data["contact_force"][0]
        total = last.point_data["contact_force"].sum(axis=0)
        if not np.allclose(force, -total, rtol=1e-6, atol=1e-9):
            fail(f"part {part}: finger contact force {force}, object's total {total}")
    surfaces = sorted(out.glob("surface_*.stl"))
    if len(surfaces) != len(datasets):
        fail(f"{len(surfaces)} surface files for {len(datasets)} frames")
    s = meshio.read(surfaces[-1])
    tri = s.cells_dict.get("triangle")
    if tri is None or len(tri) == 0:
        fail(f"{surfaces[-1]}: no triangles")
    print(f"check_exports: {len(datasets)} frames of {n} points and {t} tetrahedra, "
          f"fields {sorted(POINT_FIELDS)} and {sorted(CELL_FIELDS)}, "
          f"{len(surfaces)} surfaces of {len(tri)} triangles, {len(fingers)} finger part(s) "
          f"with {sorted(FINGER_FIELDS)}: all read with meshio {meshio.__version__}")


if __name__ == "__main__":
    main()
