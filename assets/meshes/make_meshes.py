#!/usr/bin/env python3
"""Generate softgrip's mesh test fixtures and shipped object meshes.

What it makes
-------------
* Test fixtures, in ``crates/softgrip-core/tests/data/meshes/`` (small, coarse, for the Rust mesh
  importers):

  - ``cube_v22.msh``, ``cube.msh``, ``cube_binary.msh``, ``cube_binary22.msh``:
    one tetrahedral mesh of the cube [0, 0.02]^3 m, written by Gmsh as MSH 2.2
    ASCII, 4.1 ASCII, 4.1 binary and 2.2 binary.  ``Mesh.SaveAll=1`` and no
    physical groups, so every file mixes element types (points, lines,
    triangles, tetrahedra): an importer must keep the tetrahedra and skip the
    rest.
  - ``sphere.msh``: a coarse (h = 4 mm) tetrahedral ball of radius 10 mm
    centred at the origin, Gmsh 4.1 ASCII, ``Mesh.SaveAll=1``.
  - The cube's tetrahedra (same nodes, same order) converted with meshio to
    ``cube.vtk`` (legacy ASCII), ``cube_binary.vtk`` (legacy binary),
    ``cube_v42.vtk`` (legacy ASCII in the older 4.2 layout), ``cube.vtu``
    (XML, ASCII) and ``cube_binary.vtu`` (XML, base64 + zlib, meshio's
    default), and to TetGen's ``cube.node`` + ``cube.ele`` (meshio's "tetgen"
    writer).  ``cube.face`` (TetGen .face, boundary triangles with the Gmsh
    surface number as boundary marker) is written by this script itself.
  - ``cube_vtk_appended_raw.vtu``, ``cube_vtk_appended_base64.vtu``,
    ``cube_vtk_binary.vtu``, ``cube_vtk_ascii.vtu``: the same points and
    tetrahedra, plus two of Gmsh's boundary triangles (the first and the last
    cell), written by VTK's own ``vtkXMLUnstructuredGridWriter`` (Kitware's
    ``vtk`` wheel) in its four data modes: appended raw (zlib, UInt64
    headers), appended base64 (uncompressed, UInt32 headers), inline binary
    (base64, zlib, UInt64 headers) and ascii.  Optional: without ``vtk`` the
    script leaves these files as they are and says so.
  - ``sphere_surface.stl`` (binary) and ``sphere_surface_ascii.stl`` (ASCII),
    written by Gmsh from its 2-D mesh (h = 2 mm) of the sphere of radius 10 mm,
    closed and outward-oriented; ``sphere_surface.obj`` (meshio) from the same
    triangles; ``open_surface.stl`` (the same with the triangles around the
    north pole removed) and ``inside_out.stl`` (every triangle's winding
    reversed), both written by meshio as binary STL.

* Shipped objects, in ``assets/meshes/`` (tetrahedral, Gmsh 4.1 ASCII, edge
  about 3.5 mm, centred at the origin): ``tomato.msh`` (oblate spheroid, semi-
  axes 30, 30, 25 mm), ``cylinder.msh`` (radius 20 mm, height 50 mm, axis z),
  ``rounded_box.msh`` (60 x 40 x 30 mm box, every edge filleted with 5 mm).

* ``crates/softgrip-core/tests/data/meshes/README.md`` and ``assets/meshes/README.md``: the figures
  a test should check (counts by cell type, volumes), computed by reading every
  written file back with meshio and checked against what Gmsh holds in memory.

All lengths are in metres.

How to run
----------
    pip install gmsh==4.15.2 meshio==5.3.5 numpy
    pip install vtk==9.7.2                      # optional: cube_vtk_*.vtu
    python3 assets/meshes/make_meshes.py        # from anywhere; paths are
                                                # relative to this file

The script overwrites the files listed above and nothing else.  It exits
non-zero if a read-back check fails.

Versions used
-------------
Python 3.11.7, gmsh 4.15.2 (PyPI wheel, bundles the Gmsh library),
meshio 5.3.5, numpy 2.4.6, vtk 9.7.2 (PyPI wheel).  Other versions may mesh
differently; the script warns when the installed gmsh, meshio or vtk differs
from these.

Determinism
-----------
Gmsh runs with one thread, Mesh.RandomSeed=1, Mesh.Algorithm=6 (2-D
Frontal-Delaunay), Mesh.Algorithm3D=1 (Delaunay) and Mesh.Optimize=1, so two
runs give byte-identical files.  meshio's OBJ writer puts the current date and
time in its first comment line; this script removes the time stamp from that
line so the OBJ file is reproducible too.  VTK's XML writer embeds nothing
variable; each VTK file is written from a freshly built grid, so no file
depends on the ones written before it (VTK caches the points' norm range on
the array during a write and would add it to later files).

Licence: this script and the meshes it writes are part of softgrip
(MIT OR Apache-2.0).  Gmsh (GPL) is only used as a tool; its output carries no
licence obligation.
"""

from __future__ import annotations

import re
import sys
import tempfile
import warnings
from collections import Counter
from pathlib import Path

import gmsh
import meshio
import numpy as np

try:  # optional: only needed to remake the cube_vtk_*.vtu fixtures
    from vtkmodules.vtkCommonCore import vtkIdList, vtkPoints, vtkVersion
    from vtkmodules.vtkCommonDataModel import VTK_TETRA, VTK_TRIANGLE, vtkUnstructuredGrid
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader, vtkXMLUnstructuredGridWriter

    VTK_VERSION = vtkVersion.GetVTKVersion()
except ImportError as exc:
    VTK_VERSION = None
    VTK_IMPORT_ERROR = exc

HERE = Path(__file__).resolve().parent  # assets/meshes
REPO = HERE.parent.parent
TESTDATA = REPO / "crates" / "softgrip-core" / "tests" / "data" / "meshes"
ASSETS = HERE

GMSH_VERSION_USED = "4.15.2"
MESHIO_VERSION_USED = "5.3.5"
VTK_VERSION_USED = "9.7.2"

# Gmsh element type numbers (see the MSH format documentation).
GMSH_POINT, GMSH_LINE, GMSH_TRIANGLE, GMSH_TETRA = 15, 1, 2, 4
GMSH_TYPE_NAMES = {
    GMSH_POINT: "vertex",
    GMSH_LINE: "line",
    GMSH_TRIANGLE: "triangle",
    GMSH_TETRA: "tetra",
}

# The cube written by VTK's vtkXMLUnstructuredGridWriter: file name, data mode,
# appended data base64-encoded?, compressor, header type (None: VTK's default,
# not set), and the README's format column.
VTK_VTU_SPECS = [
    ("cube_vtk_appended_raw.vtu", "Appended", False, "ZLib", "UInt64",
     "VTK XML UnstructuredGrid, appended raw + zlib, UInt64 headers"),
    ("cube_vtk_appended_base64.vtu", "Appended", True, "None", "UInt32",
     "VTK XML UnstructuredGrid, appended base64, uncompressed, UInt32 headers"),
    ("cube_vtk_binary.vtu", "Binary", None, "ZLib", "UInt64",
     "VTK XML UnstructuredGrid, inline base64 + zlib, UInt64 headers"),
    ("cube_vtk_ascii.vtu", "Ascii", None, None, None,
     "VTK XML UnstructuredGrid, ascii"),
]

CUBE_SIDE = 0.02
CUBE_H = 0.006
SPHERE_R = 0.01
SPHERE_H = 0.004
SPHERE_SURF_H = 0.002
OBJECT_H = 0.0035

ERRORS: list[str] = []


# --------------------------------------------------------------------------
# Gmsh helpers
# --------------------------------------------------------------------------


def gmsh_start(name: str, h: float) -> None:
    """Start a fresh Gmsh session with the fixed, deterministic settings."""
    gmsh.initialize(["make_meshes.py"], readConfigFiles=False)
    gmsh.option.setNumber("General.Verbosity", 2)  # errors and warnings only
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.RandomSeed", 1)
    gmsh.option.setNumber("Mesh.Algorithm", 6)  # 2-D: Frontal-Delaunay
    gmsh.option.setNumber("Mesh.Algorithm3D", 1)  # 3-D: Delaunay
    gmsh.option.setNumber("Mesh.Optimize", 1)
    # The size comes from Mesh.MeshSizeMax alone: OpenCASCADE points carry a
    # default size of their own that would otherwise win when h is larger.
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 1)
    gmsh.option.setNumber("Mesh.MeshSizeMax", h)
    gmsh.option.setNumber("Mesh.SaveAll", 1)
    gmsh.model.add(name)


def gmsh_write(path: Path, version: float, binary: bool) -> None:
    """Write the current mesh; Gmsh picks the format from a .msh extension."""
    gmsh.option.setNumber("Mesh.MshFileVersion", version)
    gmsh.option.setNumber("Mesh.Binary", 1 if binary else 0)
    with tempfile.TemporaryDirectory() as tmp:
        tmp_path = Path(tmp) / "mesh.msh"
        gmsh.write(str(tmp_path))
        path.write_bytes(tmp_path.read_bytes())


def gmsh_snapshot() -> dict:
    """Nodes (sorted by tag) and elements of the current model, by type."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    order = np.argsort(tags)
    tags = tags[order]
    points = coords.reshape(-1, 3)[order]
    index = {int(t): i for i, t in enumerate(tags)}
    cells: dict[str, list[np.ndarray]] = {}
    per_entity: dict[str, list[tuple[int, np.ndarray]]] = {}
    for dim, ent in gmsh.model.getEntities():
        types, _, node_tags = gmsh.model.mesh.getElements(dim, ent)
        for etype, nt in zip(types, node_tags):
            name = GMSH_TYPE_NAMES[int(etype)]
            npe = {"vertex": 1, "line": 2, "triangle": 3, "tetra": 4}[name]
            conn = np.array([index[int(t)] for t in nt], dtype=np.int64)
            conn = conn.reshape(-1, npe)
            cells.setdefault(name, []).append(conn)
            per_entity.setdefault(name, []).append((ent, conn))
    cells_cat = {k: np.concatenate(v) for k, v in cells.items()}
    return {
        "tags": tags,
        "points": points,
        "cells": cells_cat,
        "per_entity": per_entity,
    }


# --------------------------------------------------------------------------
# Figures
# --------------------------------------------------------------------------


def tet_dets(points: np.ndarray, tets: np.ndarray) -> np.ndarray:
    p = points[tets]
    m = np.stack([p[:, 1] - p[:, 0], p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]], axis=1)
    return np.linalg.det(m)


def tet_volume(points: np.ndarray, tets: np.ndarray) -> float:
    """Total tetrahedral volume: sum of |det| / 6."""
    return float(np.sum(np.abs(tet_dets(points, tets))) / 6.0)


def enclosed_volume(points: np.ndarray, tris: np.ndarray) -> float:
    """Divergence theorem: sum of p0 . (p1 x p2) / 6 (positive if outward)."""
    p = points[tris]
    return float(np.sum(np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2]))) / 6.0)


def fmt_vol(v: float) -> str:
    return f"{v:.14e}"  # 15 significant digits


def weld(points: np.ndarray, tris: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Merge points with bit-identical coordinates (as an STL reader must)."""
    uniq, inverse = np.unique(points, axis=0, return_inverse=True)
    return uniq, inverse.reshape(-1)[tris]


def edge_counts(tris: np.ndarray) -> Counter:
    e = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    e.sort(axis=1)
    return Counter(map(tuple, e.tolist()))


def surface_figures(points: np.ndarray, tris: np.ndarray) -> dict:
    wp, wt = weld(points, tris)
    ec = edge_counts(wt)
    used = np.unique(wt)
    # Oriented-edge check: in a consistently wound closed surface every
    # directed edge appears exactly once.
    directed = Counter(
        map(
            tuple,
            np.concatenate([wt[:, [0, 1]], wt[:, [1, 2]], wt[:, [2, 0]]]).tolist(),
        )
    )
    return {
        "triangles": len(tris),
        "vertices": len(used),
        "boundary_edges": sum(1 for c in ec.values() if c == 1),
        "nonmanifold_edges": sum(1 for c in ec.values() if c > 2),
        "consistent": all(c == 1 for c in directed.values()),
        "volume": enclosed_volume(wp, wt),
        "bbox": (wp[used].min(axis=0), wp[used].max(axis=0)),
    }


def meshio_counts(mesh: meshio.Mesh) -> dict[str, int]:
    counts: Counter = Counter()
    for block in mesh.cells:
        counts[block.type] += len(block.data)
    return dict(counts)


def meshio_tets(mesh: meshio.Mesh) -> np.ndarray:
    blocks = [b.data for b in mesh.cells if b.type == "tetra"]
    return np.concatenate(blocks).astype(np.int64)


def check(cond: bool, what: str) -> None:
    if not cond:
        ERRORS.append(what)
        print(f"CHECK FAILED: {what}", file=sys.stderr)


def close(a: float, b: float, rel: float) -> bool:
    return abs(a - b) <= rel * max(abs(a), abs(b))


def meshio_read(path: Path) -> meshio.Mesh:
    # ".msh" is claimed by several formats; name Gmsh's so meshio does not
    # first try (and print the failure of) another reader.
    fmt = "gmsh" if path.suffix == ".msh" else None
    with warnings.catch_warnings():
        # meshio's STL reader first tests whether an ASCII file could be a
        # binary one and overflows a numpy scalar doing so: harmless.
        warnings.simplefilter("ignore", RuntimeWarning)
        return meshio.read(path, file_format=fmt)


def volume_figures(path: Path, truth: dict, coord_tol: float = 0.0) -> dict:
    """Read a volume mesh back with meshio and compare it with Gmsh's data:
    same nodes (to coord_tol, in metres), same tetrahedra, same counts."""
    mesh = meshio_read(path)
    counts = meshio_counts(mesh)
    tets = meshio_tets(mesh)
    vol = tet_volume(mesh.points, tets)
    dets = tet_dets(mesh.points, tets)
    if mesh.points.shape == truth["points"].shape:
        dev = float(np.max(np.abs(mesh.points - truth["points"])))
        check(dev <= coord_tol, f"{path.name}: node coordinates differ by {dev}")
    if tets.shape == truth["cells"]["tetra"].shape:
        check(bool(np.all(tets == truth["cells"]["tetra"])), f"{path.name}: tetra connectivity")
    want_counts = {k: len(v) for k, v in truth["cells"].items() if k in counts or k == "tetra"}
    check(len(mesh.points) == len(truth["points"]), f"{path.name}: node count")
    check(counts.get("tetra") == len(truth["cells"]["tetra"]), f"{path.name}: tetra count")
    for k, v in counts.items():
        check(v == want_counts.get(k), f"{path.name}: {k} count {v} != {want_counts.get(k)}")
    truth_vol = tet_volume(truth["points"], truth["cells"]["tetra"])
    check(close(vol, truth_vol, 1e-12), f"{path.name}: volume {vol} != {truth_vol}")
    bbox = (mesh.points.min(axis=0), mesh.points.max(axis=0))
    return {
        "nodes": len(mesh.points),
        "counts": counts,
        "volume": vol,
        "negative": int(np.sum(dets < 0)),
        "bbox": bbox,
    }


# --------------------------------------------------------------------------
# Geometry
# --------------------------------------------------------------------------


def make_cube() -> dict:
    gmsh_start("cube", CUBE_H)
    gmsh.model.occ.addBox(0, 0, 0, CUBE_SIDE, CUBE_SIDE, CUBE_SIDE)
    gmsh.model.occ.synchronize()
    gmsh.model.mesh.generate(3)
    snap = gmsh_snapshot()
    gmsh_write(TESTDATA / "cube_v22.msh", 2.2, binary=False)
    gmsh_write(TESTDATA / "cube.msh", 4.1, binary=False)
    gmsh_write(TESTDATA / "cube_binary.msh", 4.1, binary=True)
    gmsh_write(TESTDATA / "cube_binary22.msh", 2.2, binary=True)
    gmsh.finalize()
    return snap


def make_sphere_volume() -> dict:
    gmsh_start("sphere", SPHERE_H)
    gmsh.model.occ.addSphere(0, 0, 0, SPHERE_R)
    gmsh.model.occ.synchronize()
    gmsh.model.mesh.generate(3)
    snap = gmsh_snapshot()
    gmsh_write(TESTDATA / "sphere.msh", 4.1, binary=False)
    gmsh.finalize()
    return snap


def make_sphere_surface() -> dict:
    gmsh_start("sphere_surface", SPHERE_SURF_H)
    gmsh.model.occ.addSphere(0, 0, 0, SPHERE_R)
    gmsh.model.occ.synchronize()
    gmsh.model.mesh.generate(2)
    snap = gmsh_snapshot()
    outward = enclosed_volume(snap["points"], snap["cells"]["triangle"]) > 0
    if not outward:
        # Make the triangles outward-oriented before Gmsh writes them.
        gmsh.model.mesh.reverse()
        snap = gmsh_snapshot()
    snap["gmsh_was_outward"] = outward
    gmsh.option.setNumber("Mesh.Binary", 1)
    with tempfile.TemporaryDirectory() as tmp:
        p = Path(tmp) / "s.stl"
        gmsh.write(str(p))
        (TESTDATA / "sphere_surface.stl").write_bytes(p.read_bytes())
        gmsh.option.setNumber("Mesh.Binary", 0)
        gmsh.write(str(p))
        (TESTDATA / "sphere_surface_ascii.stl").write_bytes(p.read_bytes())
    gmsh.finalize()
    return snap


def make_objects() -> dict[str, dict]:
    snaps = {}

    gmsh_start("tomato", OBJECT_H)
    s = gmsh.model.occ.addSphere(0, 0, 0, 0.03)
    gmsh.model.occ.dilate([(3, s)], 0, 0, 0, 1.0, 1.0, 0.025 / 0.03)
    gmsh.model.occ.synchronize()
    gmsh.model.mesh.generate(3)
    snaps["tomato.msh"] = gmsh_snapshot()
    gmsh_write(ASSETS / "tomato.msh", 4.1, binary=False)
    gmsh.finalize()

    gmsh_start("cylinder", OBJECT_H)
    gmsh.model.occ.addCylinder(0, 0, -0.025, 0, 0, 0.05, 0.02)
    gmsh.model.occ.synchronize()
    gmsh.model.mesh.generate(3)
    snaps["cylinder.msh"] = gmsh_snapshot()
    gmsh_write(ASSETS / "cylinder.msh", 4.1, binary=False)
    gmsh.finalize()

    gmsh_start("rounded_box", OBJECT_H)
    box = gmsh.model.occ.addBox(-0.03, -0.02, -0.015, 0.06, 0.04, 0.03)
    edges = [tag for _, tag in gmsh.model.occ.getEntities(1)]
    gmsh.model.occ.fillet([box], edges, [0.005])
    gmsh.model.occ.synchronize()
    gmsh.model.mesh.generate(3)
    snaps["rounded_box.msh"] = gmsh_snapshot()
    gmsh_write(ASSETS / "rounded_box.msh", 4.1, binary=False)
    gmsh.finalize()
    return snaps


# --------------------------------------------------------------------------
# Conversions with meshio, TetGen .face, OBJ, derived STL files
# --------------------------------------------------------------------------


def write_cube_conversions(cube: dict) -> None:
    tet_mesh = meshio.Mesh(cube["points"], [("tetra", cube["cells"]["tetra"])])
    meshio.write(TESTDATA / "cube.vtk", tet_mesh, file_format="vtk", binary=False)
    meshio.write(TESTDATA / "cube_binary.vtk", tet_mesh, file_format="vtk", binary=True)
    meshio.write(TESTDATA / "cube_v42.vtk", tet_mesh, file_format="vtk42", binary=False)
    meshio.write(TESTDATA / "cube.vtu", tet_mesh, file_format="vtu", binary=False)
    meshio.write(TESTDATA / "cube_binary.vtu", tet_mesh, file_format="vtu")
    meshio.write(TESTDATA / "cube.node", tet_mesh, file_format="tetgen")
    write_tetgen_face(TESTDATA / "cube.face", cube)


def vtk_cube_cells() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Points, tetrahedra and the first two boundary triangles of
    cube_binary.msh as meshio reads it (0-based, the file's order)."""
    mesh = meshio_read(TESTDATA / "cube_binary.msh")
    tets = meshio_tets(mesh)
    tris = np.concatenate([b.data for b in mesh.cells if b.type == "triangle"])[:2]
    return np.asarray(mesh.points, dtype=np.float64), tets, tris.astype(np.int64)


def vtk_cube_grid(points: np.ndarray, tets: np.ndarray, tris: np.ndarray):
    """A fresh vtkUnstructuredGrid: cell 0 is tris[0], cells 1..len(tets) the
    tetrahedra in order, the last cell tris[1]."""
    vpoints = vtkPoints()
    vpoints.SetDataTypeToDouble()
    for x, y, z in points.tolist():
        vpoints.InsertNextPoint(x, y, z)
    grid = vtkUnstructuredGrid()
    grid.SetPoints(vpoints)
    grid.Allocate(len(tets) + 2)
    grid.InsertNextCell(VTK_TRIANGLE, 3, tris[0].tolist())
    for tet in tets.tolist():
        grid.InsertNextCell(VTK_TETRA, 4, tet)
    grid.InsertNextCell(VTK_TRIANGLE, 3, tris[1].tolist())
    return grid


def write_vtk_conversions() -> None:
    """The cube_vtk_*.vtu fixtures, written by VTK itself (if installed)."""
    if VTK_VERSION is None:
        print(f"note: VTK not importable ({VTK_IMPORT_ERROR}); "
              "cube_vtk_*.vtu left as they are (pip install vtk to remake them)")
        return
    points, tets, tris = vtk_cube_cells()
    for name, mode, encode, compressor, header, _ in VTK_VTU_SPECS:
        writer = vtkXMLUnstructuredGridWriter()
        # A fresh grid per file: a write caches the points' L2 norm range on
        # the array, and later writes would add it as an <InformationKey>.
        writer.SetInputData(vtk_cube_grid(points, tets, tris))
        getattr(writer, f"SetDataModeTo{mode}")()
        if encode is not None:
            writer.SetEncodeAppendedData(1 if encode else 0)
        if compressor is not None:
            getattr(writer, f"SetCompressorTypeTo{compressor}")()
        if header is not None:
            getattr(writer, f"SetHeaderTypeTo{header}")()
        with tempfile.TemporaryDirectory() as tmp:
            tmp_path = Path(tmp) / name
            writer.SetFileName(str(tmp_path))
            ok = writer.Write() == 1 and tmp_path.exists()
            check(ok, f"{name}: VTK write failed")
            if ok:
                (TESTDATA / name).write_bytes(tmp_path.read_bytes())


def vtk_read_figures(path: Path, truth: dict) -> dict:
    """Read a .vtu back with VTK's own reader and compare it with the truth
    (points bit-identical, tetrahedra and triangles in the written order)."""
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutput()
    n = grid.GetNumberOfPoints()
    points = np.array([grid.GetPoint(i) for i in range(n)], dtype=np.float64)
    names = {VTK_TETRA: "tetra", VTK_TRIANGLE: "triangle"}
    cells: dict[str, list[list[int]]] = {}
    ids = vtkIdList()
    for i in range(grid.GetNumberOfCells()):
        grid.GetCellPoints(i, ids)
        name = names.get(grid.GetCellType(i), f"vtk type {grid.GetCellType(i)}")
        cells.setdefault(name, []).append([ids.GetId(k) for k in range(ids.GetNumberOfIds())])
    counts = {k: len(v) for k, v in cells.items()}
    tets = np.array(cells.get("tetra", []), dtype=np.int64).reshape(-1, 4)
    tag = f"{path.name} (VTK reader)"
    check(points.shape == truth["points"].shape and bool(np.all(points == truth["points"])),
          f"{tag}: points")
    for k, v in truth["cells"].items():
        got = np.array(cells.get(k, []), dtype=np.int64)
        check(got.shape == v.shape and bool(np.all(got == v)), f"{tag}: {k} cells")
    check(set(counts) == set(truth["cells"]), f"{tag}: cell types {sorted(counts)}")
    vol = tet_volume(points, tets) if len(tets) and len(points) else 0.0
    truth_vol = tet_volume(truth["points"], truth["cells"]["tetra"])
    check(close(vol, truth_vol, 1e-12), f"{tag}: volume {vol} != {truth_vol}")
    return {"nodes": n, "counts": counts, "volume": vol}


def cube_boundary_faces(cube: dict) -> tuple[np.ndarray, np.ndarray]:
    """Gmsh's boundary triangles, wound counter-clockwise seen from outside,
    with the Gmsh surface number as marker (0-based node numbers)."""
    points = cube["points"]
    tets = cube["cells"]["tetra"]
    # Map each tet face (sorted) to the tet's opposite vertex.
    opposite = {}
    for tet in tets.tolist():
        for k in range(4):
            face = tuple(sorted(tet[:k] + tet[k + 1 :]))
            opposite.setdefault(face, []).append(tet[k])
    faces, markers = [], []
    for surf, conn in cube["per_entity"]["triangle"]:
        for tri in conn.tolist():
            opp = opposite[tuple(sorted(tri))]
            assert len(opp) == 1, "boundary triangle shared by two tets"
            a, b, c = (points[i] for i in tri)
            n = np.cross(b - a, c - a)
            if np.dot(n, points[opp[0]] - a) > 0:
                tri = [tri[0], tri[2], tri[1]]
            faces.append(tri)
            markers.append(surf)
    boundary_from_tets = sorted(f for f, o in opposite.items() if len(o) == 1)
    assert boundary_from_tets == sorted(tuple(sorted(f)) for f in faces)
    return np.array(faces, dtype=np.int64), np.array(markers, dtype=np.int64)


def write_tetgen_face(path: Path, cube: dict) -> None:
    faces, markers = cube_boundary_faces(cube)
    lines = [
        "# TetGen .face file written by softgrip's assets/meshes/make_meshes.py",
        "# boundary triangles of cube.ele, counter-clockwise seen from outside;",
        "# node numbers are 0-based like cube.node; marker = Gmsh surface number",
        f"{len(faces)} 1",
    ]
    for i, (f, m) in enumerate(zip(faces.tolist(), markers.tolist())):
        lines.append(f"{i} {f[0]} {f[1]} {f[2]} {m}")
    path.write_text("\n".join(lines) + "\n")


def read_tetgen_face(path: Path) -> tuple[np.ndarray, np.ndarray]:
    rows = []
    for line in path.read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            rows.append([int(x) for x in line.split()])
    header, body = rows[0], rows[1:]
    assert len(body) == header[0]
    arr = np.array(body, dtype=np.int64)
    return arr[:, 1:4], (arr[:, 4] if header[1] == 1 else np.zeros(len(arr), np.int64))


def write_surface_derivatives(surf: dict) -> None:
    points = surf["points"]
    tris = surf["cells"]["triangle"]
    # OBJ: meshio puts a date and time in its first line; drop the time stamp.
    obj = TESTDATA / "sphere_surface.obj"
    meshio.write(obj, meshio.Mesh(points, [("triangle", tris)]), file_format="obj")
    text = obj.read_text().split("\n", 1)
    first = re.sub(r",\s*\S+$", "", text[0])
    obj.write_text(first + "\n" + text[1])

    # Open surface: drop every triangle that touches the north-pole node.
    pole = int(np.argmax(points[:, 2]))
    keep = ~np.any(tris == pole, axis=1)
    meshio.write(
        TESTDATA / "open_surface.stl",
        meshio.Mesh(points, [("triangle", tris[keep])]),
        file_format="stl",
        binary=True,
    )
    meshio.write(
        TESTDATA / "inside_out.stl",
        meshio.Mesh(points, [("triangle", tris[:, ::-1].copy())]),
        file_format="stl",
        binary=True,
    )
    surf["removed_for_open"] = int(np.sum(~keep))


# --------------------------------------------------------------------------
# Read-back checks and READMEs
# --------------------------------------------------------------------------


def read_surface(path: Path) -> tuple[np.ndarray, np.ndarray]:
    mesh = meshio_read(path)
    tris = np.concatenate([b.data for b in mesh.cells if b.type == "triangle"])
    return np.asarray(mesh.points, dtype=np.float64), tris.astype(np.int64)


def count_cell(counts: dict, name: str) -> int:
    return counts.get(name, 0)


def main() -> int:
    for mod, want in (("gmsh", GMSH_VERSION_USED), ("meshio", MESHIO_VERSION_USED)):
        have = sys.modules[mod].__version__
        if have != want:
            print(
                f"warning: {mod} {have} installed, fixtures were made with {want}; "
                "the meshes may differ",
                file=sys.stderr,
            )
    if VTK_VERSION is not None and VTK_VERSION != VTK_VERSION_USED:
        print(
            f"warning: vtk {VTK_VERSION} installed, fixtures were made with "
            f"{VTK_VERSION_USED}; the cube_vtk_*.vtu files may differ",
            file=sys.stderr,
        )
    TESTDATA.mkdir(parents=True, exist_ok=True)

    cube = make_cube()
    sphere = make_sphere_volume()
    surf = make_sphere_surface()
    write_cube_conversions(cube)
    write_vtk_conversions()
    write_surface_derivatives(surf)
    objects = make_objects()

    gv, mv = gmsh.__version__, meshio.__version__
    np_v = np.__version__
    vv = VTK_VERSION or VTK_VERSION_USED  # without vtk: the files as they are

    # ---- volume meshes ----------------------------------------------------
    vol_rows = []
    specs = [
        ("cube_v22.msh", f"Gmsh {gv}", "MSH 2.2 ASCII", cube),
        ("cube.msh", f"Gmsh {gv}", "MSH 4.1 ASCII", cube),
        ("cube_binary.msh", f"Gmsh {gv}", "MSH 4.1 binary (little-endian)", cube),
        ("cube_binary22.msh", f"Gmsh {gv}", "MSH 2.2 binary (little-endian)", cube),
        ("sphere.msh", f"Gmsh {gv}", "MSH 4.1 ASCII", sphere),
    ]
    tet_only = {"points": cube["points"], "cells": {"tetra": cube["cells"]["tetra"]}}
    specs += [
        ("cube.vtk", f"meshio {mv}", "VTK legacy 5.1 ASCII", tet_only),
        ("cube_binary.vtk", f"meshio {mv}", "VTK legacy 5.1 binary (big-endian)", tet_only),
        ("cube_v42.vtk", f"meshio {mv}", "VTK legacy 4.2 ASCII", tet_only),
        ("cube.vtu", f"meshio {mv}", "VTK XML UnstructuredGrid, ascii", tet_only),
        ("cube_binary.vtu", f"meshio {mv}", "VTK XML UnstructuredGrid, base64 + zlib", tet_only),
        ("cube.node + cube.ele", f"meshio {mv}", "TetGen .node/.ele, 0-based", tet_only),
    ]
    # VTK's files: cell 0 is Gmsh's first boundary triangle, then the
    # tetrahedra, then the second triangle.
    vtk_truth = {
        "points": cube["points"],
        "cells": {"tetra": cube["cells"]["tetra"],
                  "triangle": cube["cells"]["triangle"][[0, 1]]},
    }
    vtk_names = []
    for name, _, _, _, _, fmt in VTK_VTU_SPECS:
        if (TESTDATA / name).exists():
            specs.append((name, f"VTK {vv}", fmt, vtk_truth))
            vtk_names.append(name)
        else:
            check(False, f"{name}: missing (install vtk to make it)")
    for name, tool, fmt, truth in specs:
        path = TESTDATA / name.split(" ")[0]
        # meshio's ASCII VTU keeps 12 significant digits (%.11e); Gmsh's ASCII
        # MSH keeps 16 (%.16g, so up to 1 ulp off); the binary files and
        # meshio's other text formats (17 digits) hold the exact doubles.
        tol = {"cube.vtu": 1e-13, "cube_v22.msh": 1e-16, "cube.msh": 1e-16,
               "sphere.msh": 1e-16}.get(name, 0.0)
        fig = volume_figures(path, truth, tol)
        vol_rows.append((name, tool, fmt, fig))

    # VTK's own reader must see the same as meshio in VTK's files.
    vtk_rows = []
    if VTK_VERSION is not None:
        for name in vtk_names:
            vtk_rows.append((name, vtk_read_figures(TESTDATA / name, vtk_truth)))

    # TetGen .face
    faces, markers = read_tetgen_face(TESTDATA / "cube.face")
    cube_pts = meshio_read(TESTDATA / "cube.node").points
    face_fig = surface_figures(cube_pts, faces)
    check(len(faces) == len(cube["cells"]["triangle"]), "cube.face: face count")
    check(face_fig["boundary_edges"] == 0 and face_fig["consistent"], "cube.face: closed, wound")
    check(close(face_fig["volume"], tet_volume(cube["points"], cube["cells"]["tetra"]), 1e-12),
          "cube.face: enclosed volume equals tet volume")
    marker_counts = Counter(markers.tolist())

    # ---- surfaces ---------------------------------------------------------
    surf_truth = surface_figures(surf["points"], surf["cells"]["triangle"])
    check(surf_truth["boundary_edges"] == 0, "sphere surface closed in Gmsh")
    check(surf_truth["consistent"], "sphere surface consistently wound in Gmsh")
    check(surf_truth["volume"] > 0, "sphere surface outward in Gmsh")
    surf_rows = []
    surf_specs = [
        ("sphere_surface.stl", f"Gmsh {gv}", "STL binary", 1e-6),
        ("sphere_surface_ascii.stl", f"Gmsh {gv}", "STL ASCII", 1e-5),
        ("sphere_surface.obj", f"meshio {mv}", "Wavefront OBJ", 1e-14),
        ("open_surface.stl", f"meshio {mv}", "STL binary", None),
        ("inside_out.stl", f"meshio {mv}", "STL binary", 1e-6),
    ]
    for name, tool, fmt, rel in surf_specs:
        pts, tris = read_surface(TESTDATA / name)
        fig = surface_figures(pts, tris)
        if name == "inside_out.stl":
            check(close(fig["volume"], -surf_truth["volume"], rel), f"{name}: volume")
            check(fig["boundary_edges"] == 0 and fig["consistent"], f"{name}: closed")
            check(fig["triangles"] == surf_truth["triangles"], f"{name}: triangles")
        elif name == "open_surface.stl":
            check(fig["boundary_edges"] > 0, f"{name}: open")
            check(fig["triangles"] == surf_truth["triangles"] - surf["removed_for_open"],
                  f"{name}: triangles")
        else:
            check(close(fig["volume"], surf_truth["volume"], rel), f"{name}: volume")
            check(fig["boundary_edges"] == 0 and fig["consistent"], f"{name}: closed")
            check(fig["triangles"] == surf_truth["triangles"], f"{name}: triangles")
            check(fig["vertices"] == surf_truth["vertices"], f"{name}: vertices")
        surf_rows.append((name, tool, fmt, fig))

    # ---- shipped objects ----------------------------------------------------
    obj_rows = []
    for name, snap in objects.items():
        fig = volume_figures(ASSETS / name, snap, 1e-16)
        size = (ASSETS / name).stat().st_size
        obj_rows.append((name, fig, size))

    write_test_readme(gv, mv, np_v, vv, vtk_truth["cells"]["triangle"].tolist(), vol_rows,
                      face_fig, marker_counts, surf_rows, surf)
    write_assets_readme(gv, mv, np_v, obj_rows)

    for name, tool, fmt, fig in vol_rows:
        c = fig["counts"]
        print(f"{name:28s} nodes={fig['nodes']:5d} tets={c.get('tetra', 0):6d} "
              f"tris={c.get('triangle', 0):5d} lines={c.get('line', 0):4d} "
              f"verts={c.get('vertex', 0):2d} vol={fmt_vol(fig['volume'])} neg={fig['negative']}")
    for name, fig in vtk_rows:
        c = fig["counts"]
        print(f"{name:28s} VTK reader: nodes={fig['nodes']} tets={c.get('tetra', 0)} "
              f"tris={c.get('triangle', 0)} vol={fmt_vol(fig['volume'])}")
    print(f"{'cube.face':24s} faces={len(faces)} markers={dict(sorted(marker_counts.items()))} "
          f"vol={fmt_vol(face_fig['volume'])}")
    for name, tool, fmt, fig in surf_rows:
        print(f"{name:24s} tris={fig['triangles']} verts={fig['vertices']} "
              f"open_edges={fig['boundary_edges']} vol={fmt_vol(fig['volume'])}")
    for name, fig, size in obj_rows:
        c = fig["counts"]
        print(f"{name:24s} nodes={fig['nodes']} tets={c.get('tetra', 0)} "
              f"tris={c.get('triangle', 0)} vol={fmt_vol(fig['volume'])} size={size}")
    if ERRORS:
        print(f"{len(ERRORS)} check(s) failed", file=sys.stderr)
        return 1
    print("all read-back checks passed")
    return 0


def bbox_str(bbox) -> str:
    lo, hi = bbox
    return "[" + ", ".join(f"{a:.6g}..{b:.6g}" for a, b in zip(lo, hi)) + "]"


def write_test_readme(gv, mv, np_v, vv, vtk_tris, vol_rows, face_fig, marker_counts, surf_rows,
                      surf) -> None:
    L = []
    L.append("# Mesh importer fixtures")
    L.append("")
    L.append("<!-- Generated by assets/meshes/make_meshes.py; edit that script, not this file. -->")
    L.append("")
    L.append("Small, real mesh files written by the real tools, for testing softgrip's mesh")
    L.append("importers. All of them are made by one script,")
    L.append("")
    L.append("    pip install gmsh==4.15.2 meshio==5.3.5 numpy")
    L.append("    pip install vtk==9.7.2    # optional, for the cube_vtk_*.vtu files")
    L.append("    python3 assets/meshes/make_meshes.py")
    L.append("")
    L.append(f"with gmsh {gv} (the PyPI wheel, which bundles the Gmsh library), meshio {mv},")
    L.append(f"numpy {np_v}, VTK {vv} (Kitware's `vtk` wheel), Python 3.11. Two runs give")
    L.append("byte-identical files. Lengths are in metres. The script reads every file back")
    L.append("with meshio (VTK's files also with VTK's own reader) and checks the figures")
    L.append("below against what Gmsh held in memory; it fails if they differ. Without the")
    L.append("`vtk` package it leaves the `cube_vtk_*.vtu` files as they are.")
    L.append("")
    L.append("Gmsh settings: `General.NumThreads=1`, `Mesh.RandomSeed=1`, `Mesh.Algorithm=6`,")
    L.append("`Mesh.Algorithm3D=1` (Delaunay), `Mesh.Optimize=1`, `Mesh.MeshSizeFromPoints=0`,")
    L.append("`Mesh.MeshSizeMax=h`, `Mesh.SaveAll=1`, OpenCASCADE kernel, no physical groups.")
    L.append("")
    L.append("## Volume meshes")
    L.append("")
    L.append(f"The cube is [0, 0.02]^3 (h = {CUBE_H}); one Gmsh mesh is written in the four")
    L.append("MSH variants, and its tetrahedra alone (same nodes, same order, 0-based") 
    L.append("node *i* = Gmsh node tag *i*+1) are converted with meshio. `sphere.msh` is")
    L.append(f"a ball of radius {SPHERE_R} centred at the origin (h = {SPHERE_H}).")
    L.append("")
    L.append("The `cube_vtk_*.vtu` files are written by VTK's own")
    L.append("`vtkXMLUnstructuredGridWriter` from `cube_binary.msh` as meshio reads it:")
    L.append("the same 143 points (Float64, bit-identical) and 386 cells. Cell 0 is the")
    L.append("first triangle of Gmsh's triangle block (0-based nodes "
             + " ".join(map(str, vtk_tris[0])) + "), cells 1..384")
    L.append("are the tetrahedra in Gmsh's order, cell 385 is Gmsh's second triangle")
    L.append("(" + " ".join(map(str, vtk_tris[1])) + ").")
    L.append("An importer keeps the 384 tetrahedra and skips the two triangles (VTK type")
    L.append("5) with a warning. VTK's reader gives the same figures as meshio's.")
    L.append("")
    L.append("Volume = sum over tetrahedra of |det(b-a, c-a, d-a)| / 6, computed with numpy")
    L.append("from the file as read back (15 significant digits). \"neg\" = tetrahedra")
    L.append("with negative det (Gmsh writes all of them positively oriented).")
    L.append("")
    L.append("| file | written by | format | nodes | tetra | triangle | line | vertex | neg | tet volume (m^3) |")
    L.append("| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for name, tool, fmt, fig in vol_rows:
        c = fig["counts"]
        L.append(
            f"| `{name}` | {tool} | {fmt} | {fig['nodes']} | {count_cell(c, 'tetra')} | "
            f"{count_cell(c, 'triangle')} | {count_cell(c, 'line')} | "
            f"{count_cell(c, 'vertex')} | {fig['negative']} | {fmt_vol(fig['volume'])} |"
        )
    L.append("")
    L.append(f"Exact cube volume: 8.00000000000000e-06. Exact ball volume:")
    L.append(f"{fmt_vol(4.0 / 3.0 * np.pi * SPHERE_R**3)} (the coarse mesh is smaller).")
    L.append("")
    L.append("`cube.face` (written by make_meshes.py itself, TetGen .face format: first")
    L.append("line `<#faces> 1`, then `index n1 n2 n3 marker`, 0-based like `cube.node`,")
    L.append("`#` comment lines at the top): the cube's boundary triangles, wound")
    L.append("counter-clockwise seen from outside, marker = Gmsh surface number.")
    L.append(f"{sum(marker_counts.values())} faces; per marker: "
             + ", ".join(f"{k}: {v}" for k, v in sorted(marker_counts.items()))
             + f"; enclosed volume {fmt_vol(face_fig['volume'])}.")
    L.append("")
    L.append("## Surface meshes")
    L.append("")
    L.append(f"Gmsh's 2-D mesh (h = {SPHERE_SURF_H}) of the sphere of radius {SPHERE_R} centred at the")
    L.append("origin, outward-oriented and closed ("
             + ("Gmsh's own winding was already outward" if surf["gmsh_was_outward"]
                else "the script reversed Gmsh's inward winding")
             + ").")
    L.append("`open_surface.stl` is the same without")
    L.append(f"the {surf['removed_for_open']} triangles around the north-pole node (one hole);")
    L.append("`inside_out.stl` has every triangle's winding reversed (and its normal")
    L.append("flipped). \"vertices\" counts distinct points after merging bit-identical")
    L.append("coordinates; \"open edges\" are edges used by one triangle only. Enclosed")
    L.append("volume = sum of p0 . (p1 x p2) / 6 over the triangles (divergence theorem;")
    L.append("for the open surface it is just that sum, about the origin). STL stores")
    L.append("float32, so STL volumes differ from the OBJ's in the last digits.")
    L.append("")
    L.append("| file | written by | format | triangles | vertices | open edges | enclosed volume (m^3) |")
    L.append("| --- | --- | --- | ---: | ---: | ---: | ---: |")
    for name, tool, fmt, fig in surf_rows:
        L.append(
            f"| `{name}` | {tool} | {fmt} | {fig['triangles']} | {fig['vertices']} | "
            f"{fig['boundary_edges']} | {fmt_vol(fig['volume'])} |"
        )
    L.append("")
    L.append(f"Exact sphere volume: {fmt_vol(4.0 / 3.0 * np.pi * SPHERE_R**3)}.")
    L.append("")
    L.append("## Format notes")
    L.append("")
    for line in FORMAT_NOTES.strip("\n").split("\n"):
        L.append(line)
    L.append("")
    L.append("## Licence")
    L.append("")
    L.append("These files and the script that makes them are part of softgrip")
    L.append("(MIT OR Apache-2.0). Gmsh (GPL) was used only as a tool; its output carries")
    L.append("no licence obligation.")
    (TESTDATA / "README.md").write_text("\n".join(L) + "\n")


FORMAT_NOTES = """
- **MSH, all four**: no physical groups and `Mesh.SaveAll=1`, so the element
  list holds points (type 15), lines (1), triangles (2) and tetrahedra (4); an
  importer keeps the tetrahedra and skips the rest. Node tags run 1..N with no
  gaps, grouped by the entity they lie on (the 8 corners first, then edges,
  faces, the volume); node 1 is the corner (0, 0, 0.02), not the origin
  (OpenCASCADE's vertex order). Element tags also run 1..N, lowest dimension
  first. Gmsh writes all tetrahedra positively oriented.
- **MSH 2.2**: `$MeshFormat` is `2.2 0 8` (ASCII) or `2.2 1 8` (binary).
  ASCII element lines are `tag type ntags phys elementary nodes...` with
  2 tags (physical 0, elementary entity), e.g. `1 15 2 0 1 1`. In the binary
  file the header line is followed by the int32 1 (endianness check) and a
  newline; the node and element counts stay ASCII lines; nodes are
  `int32 tag, 3 x float64`; elements come in blocks `int32 type, int32 count,
  int32 ntags` then per element `int32 tag, ntags x int32, nodes x int32`.
- **MSH 4.1**: `$MeshFormat` is `4.1 0 8` or `4.1 1 8`; an `$Entities`
  section (with bounding boxes padded by 1e-7) comes first, and `$Nodes` and
  `$Elements` come in entity blocks (in a node block, all tags first, then all
  coordinates). ASCII element lines end with a trailing space. In the binary
  file (after the int32 1) counts and node/element tags are uint64 (size_t),
  entity dims/tags and element types int32, coordinates float64, all
  little-endian.
- **VTK legacy**: meshio's default "vtk" writer produces the **5.1** layout
  (`# vtk DataFile Version 5.1`): `CELLS 385 1536`, then `OFFSETS vtktypeint64`
  (385 values, starting at 0) and `CONNECTIVITY vtktypeint64` (1536 values),
  instead of 4.2's count-prefixed cell lists; the ASCII file puts all point
  coordinates on one line and every integer on its own line. Binary legacy VTK
  (`cube_binary.vtk`) is big-endian (`double` points, int64 offsets and
  connectivity, int32 cell types). `cube_v42.vtk` (not asked for by the
  importer spec, added for coverage) holds the same mesh in the 4.2 layout:
  `CELLS 384 1920`, then `4 a b c d` for each cell, but written one integer
  per line. Cell type 10 = tetrahedron. The second line is
  `written by meshio v5.3.5`.
- **VTU**: `<VTKFile type="UnstructuredGrid" version="0.1"
  byte_order="LittleEndian">`, no `header_type` attribute (so the UInt32
  default). Points are Float64; connectivity, offsets **and types** are Int64
  (VTK itself writes types as UInt8). `cube.vtu` has `format="ascii"` arrays,
  one value per line, and coordinates rounded to 12 significant digits
  (`%.11e`, so they differ from the MSH coordinates by up to about 1e-15 m).
  `cube_binary.vtu` has `compressor="vtkZLibDataCompressor"` and inline
  `format="binary"` arrays, each made of two base64 strings back to back: the
  block header (UInt32: number of blocks, uncompressed block size 32768, size
  of the last block, compressed size of each block), then the zlib stream;
  one block per array here.
- **VTU written by VTK 9.7.2** (`cube_vtk_*.vtu`): points Float64,
  connectivity and offsets Int64, types UInt8 (5 = triangle, 10 =
  tetrahedron); `offsets` holds the 386 end offsets (3, 7, 11, ..., 1539, 1542,
  no leading 0). `<VTKFile>` has `version="1.0"` with `header_type="UInt64"`
  and `version="0.1"` with `"UInt32"`, and a `compressor` attribute unless the
  compressor is none: the ascii file still says `header_type="UInt32"
  compressor="vtkZLibDataCompressor"` (VTK's defaults) though nothing in it is
  encoded. Inline arrays (binary, ascii) carry `RangeMin`/`RangeMax` (for the
  points: the range of the point norms, 0 to 0.034641016151377546), and the
  Points `<DataArray>` holds, after its data, a child element
  `<InformationKey name="L2_NORM_RANGE" location="vtkDataArray" length="2">`
  with two `<Value index="i">` children whose text is a number: a reader must
  not take those as array values. In appended mode VTK fills the attributes in
  after writing the data, so they are padded with spaces after the closing
  quote (`NumberOfPoints="143"` + 18 spaces, `offset="0"` + 19 spaces), the
  points' range is filled in, the cell arrays get `RangeMin=""` and
  `RangeMax=""` (empty), and Points has no `<InformationKey>`.
  `cube_vtk_appended_raw.vtu` starts directly with `<VTKFile` (**no**
  `<?xml version="1.0"?>` line; the file is not well-formed XML). Its
  `<AppendedData encoding="raw">` is followed by a newline, 3 spaces, `_`, the
  four arrays back to back as raw bytes (which include `<`, `_`, newlines and
  NULs), a newline, `  </AppendedData>` and `</VTKFile>`; the `offset`
  attributes (0, 1106, 3294, 3896) count bytes from the one after `_`; each
  array is a UInt64 header (number of blocks 1, block size 32768, size of the
  last block = the uncompressed size, compressed size of each block) followed
  by the zlib stream. `cube_vtk_appended_base64.vtu` has `<AppendedData
  encoding="base64">`, `_`, then one base64 string per array, each padded on
  its own, back to back without whitespace; the offsets (0, 4584, 21040,
  25164) count base64 characters; each string decodes to a UInt32 byte count
  followed by the values (header and data encoded together, as the data is
  not compressed). `cube_vtk_binary.vtu` has inline `format="binary"` arrays
  like meshio's, but with UInt64 headers: the header is its own base64 string
  (32 bytes, 44 characters ending in `=`), then the zlib stream's own.
  `cube_vtk_ascii.vtu` writes 6 values a line (two points a line),
  coordinates in shortest round-trip form (`0.004999999999999988`,
  bit-identical to the MSH doubles).
- **TetGen**: meshio's writer starts `cube.node` and `cube.ele` with a
  `# This file was created by meshio v5.3.5` comment, numbers from 0 (the first
  index says so), and writes no attributes and no boundary markers
  (`143 3 0 0` and `384 4 0`); coordinates are `%.16e`.
- **STL**: Gmsh's binary header is `Created by Gmsh` padded with NUL bytes;
  its ASCII file is `solid Created by Gmsh` ... `endsolid Created by Gmsh`,
  vertices printed to 16 significant digits, normals to 6. meshio's binary
  header is `This file was generated by meshio v5.3.5.` padded with `X` and
  ending in a newline (never `solid`). Facet normals are unit outward normals;
  attribute words are 0. The poles are not exactly on the z axis:
  OpenCASCADE puts them at (6.1e-19, -1.5e-34, +-0.01).
- **OBJ**: a `# Created by meshio v5.3.5` comment (meshio would add the date
  and time; the script strips it), `v x y z` lines (Python's shortest float
  repr) and 1-based `f a b c` lines.
"""


def write_assets_readme(gv, mv, np_v, obj_rows) -> None:
    L = []
    L.append("# Shipped object meshes")
    L.append("")
    L.append("<!-- Generated by make_meshes.py; edit that script, not this file. -->")
    L.append("")
    L.append("Tetrahedral meshes of agri-food and gripper-test objects, for scenes. Gmsh")
    L.append("MSH 4.1 ASCII, lengths in metres, each object centred at the origin (the")
    L.append("importer places it in the scene). Element edge about 3.5 mm. The files also")
    L.append("hold Gmsh's points, lines and triangles (no physical groups, `Mesh.SaveAll=1`);")
    L.append("the importer keeps only the tetrahedra.")
    L.append("")
    L.append("- `tomato.msh`: oblate spheroid, semi-axes 30, 30, 25 mm (OpenCASCADE sphere")
    L.append("  scaled by 25/30 in z).")
    L.append("- `cylinder.msh`: radius 20 mm, height 50 mm, axis z (z from -25 to 25 mm).")
    L.append("- `rounded_box.msh`: 60 x 40 x 30 mm box with every edge filleted at 5 mm")
    L.append("  (OpenCASCADE `addBox` + `fillet`).")
    L.append("")
    L.append("Made by `make_meshes.py` in this folder (it also makes the importer test")
    L.append("fixtures in `crates/softgrip-core/tests/data/meshes/`):")
    L.append("")
    L.append("    pip install gmsh==4.15.2 meshio==5.3.5 numpy")
    L.append("    python3 assets/meshes/make_meshes.py")
    L.append("")
    L.append(f"with gmsh {gv}, meshio {mv} (read-back check), numpy {np_v}. Two runs give")
    L.append("byte-identical files.")
    L.append("")
    L.append("Volume = sum of |det| / 6 over the tetrahedra, from the file as read back.")
    L.append("")
    L.append("| file | nodes | tetra | triangle | line | vertex | tet volume (m^3) | exact solid (m^3) | bounding box (m) | bytes |")
    L.append("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- | ---: |")
    exact = {
        "tomato.msh": 4.0 / 3.0 * np.pi * 0.03 * 0.03 * 0.025,
        "cylinder.msh": np.pi * 0.02**2 * 0.05,
        "rounded_box.msh": rounded_box_volume(0.06, 0.04, 0.03, 0.005),
    }
    for name, fig, size in obj_rows:
        c = fig["counts"]
        L.append(
            f"| `{name}` | {fig['nodes']} | {count_cell(c, 'tetra')} | "
            f"{count_cell(c, 'triangle')} | {count_cell(c, 'line')} | "
            f"{count_cell(c, 'vertex')} | {fmt_vol(fig['volume'])} | "
            f"{fmt_vol(exact[name])} | {bbox_str(fig['bbox'])} | {size} |"
        )
    L.append("")
    L.append("\"exact solid\" is the volume of the smooth shape; the meshes are slightly")
    L.append("smaller because curved faces are cut by flat triangles. For the rounded box")
    L.append("it is abc - 4 (1 - pi/4) r^2 ((a - 2r) + (b - 2r) + (c - 2r)) - 8 (1 - pi/6) r^3")
    L.append("(12 edge strips over their straight length, 8 corners rounded to sphere")
    L.append("octants).")
    L.append("")
    L.append("## Licence")
    L.append("")
    L.append("The script and the meshes are part of softgrip (MIT OR Apache-2.0). Gmsh")
    L.append("(GPL) was used only as a tool; its output carries no licence obligation.")
    (ASSETS / "README.md").write_text("\n".join(L) + "\n")


def rounded_box_volume(a: float, b: float, c: float, r: float) -> float:
    """Box a x b x c with every edge rounded with radius r."""
    edge_strip = (1.0 - np.pi / 4.0) * r * r  # cross-section removed along an edge
    straight = 4 * ((a - 2 * r) + (b - 2 * r) + (c - 2 * r))
    corner = 8 * (r**3 - np.pi / 6.0 * r**3)  # cube r^3 less a sphere octant
    return a * b * c - edge_strip * straight - corner


if __name__ == "__main__":
    sys.exit(main())
