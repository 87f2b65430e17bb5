#!/usr/bin/env python3
"""Independent finite element reference for softgrip's neo-Hookean model, computed with NGSolve.

usage: scripts/reference/ngsolve_reference.py [--problem hanging|cylinder|cantilever|indentation|all]
                                              [--levels both|fine|coarse] [--out DIR] [--threads N]
                                              [--verbose]

`all` runs hanging, cylinder and cantilever; `indentation` (about 5 minutes on 2 cores) runs only
when asked for by name.

Four problems, each solved at two refinement levels ("coarse" and "fine": a finer mesh or a
higher polynomial order, stated per problem) so that the change between them bounds the
discretisation error; the fine level is the reference value. Writes DIR/ngsolve.json
(default DIR: tests/reference next to this script's repository root) and prints a summary.

Material: the energy softgrip's `forces::fem` uses (docs/design/neo-hookean.md), per unit rest
volume  Psi(F) = mu/2 (tr F^T F - 3) + lam/2 (J - a)^2,  a = 1 + mu/lam,
mu = E / (2 (1 + nu)),  lam = E nu / ((1 + nu)(1 - 2 nu)) + mu,
discretised with H1 vector elements of order 3 to 4 (the indentation: 2 to 3): tetrahedra, except
the cylinder, which is solved axisymmetric (triangles in (r, z), an exact reduction). The symmetric
problems are solved on a quarter (or half) of the body with symmetry conditions; the figures are
the whole body's.

Test-time tool only: NGSolve (LGPL-2.1) is not linked into softgrip. Requires the PyPI package
`ngsolve` (tested with 6.2.2608) and numpy; nothing else.
"""
import argparse
import datetime
import json
import math
import os
import platform
import sys
import time

import numpy as np
import ngsolve
from ngsolve import (BBND, BND, BitArray, CF, Det, GridFunction, Grad, H1, Id, IfPos, Integrate,
                     InnerProduct, Mesh, Norm, NumberSpace, Parameter, SetNumThreads, Sym,
                     TaskManager, Trace, VectorH1, BilinearForm, Variation, ds, dx, x, y, z)
from ngsolve.comp import DifferentialSymbol
from netgen.meshing import MeshingParameters
from netgen.occ import Box, MoveTo, OCCGeometry, Pnt, X, Y, Z

G = 9.81
VERBOSE = False


def log(*a):
    if VERBOSE:
        print(*a, file=sys.stderr, flush=True)
SIG = 6  # significant digits kept in the JSON (the solver's own accuracy is ~1e-9 relative)


# --------------------------------------------------------------------------------------------
# common pieces
# --------------------------------------------------------------------------------------------

def material(E, nu):
    """softgrip's constants: mu the shear modulus, lam = Lame lambda + mu, a = 1 + mu / lam."""
    mu = E / (2 * (1 + nu))
    lame = E * nu / ((1 + nu) * (1 - 2 * nu))
    lam = lame + mu
    return {"E": E, "nu": nu, "mu": mu, "lam": lam, "lame_lambda": lame, "a": 1 + mu / lam}


def psi(u, m):
    """Strain energy per unit rest volume (softgrip's stable neo-Hookean without log term)."""
    F = Id(3) + Grad(u)
    J = Det(F)
    return m["mu"] / 2 * (InnerProduct(F, F) - 3) + m["lam"] / 2 * (J - m["a"]) ** 2


def rnd(v):
    """Round floats (recursively) to SIG significant digits for a stable JSON."""
    if isinstance(v, float):
        if v == 0.0 or not math.isfinite(v):
            return v
        return float(f"{v:.{SIG}g}")
    if isinstance(v, dict):
        return {k: rnd(w) for k, w in v.items()}
    if isinstance(v, (list, tuple)):
        return [rnd(w) for w in v]
    return v


def rel_change(coarse, fine):
    return abs(fine - coarse) / max(abs(fine), 1e-300)


class Minimizer:
    """Newton's method on an energy (a BilinearForm of Variation terms): exact Hessian, sparse
    Cholesky (LDL^T), backtracking line search on the energy. Where the Hessian is not positive
    or the line search fails, a proximal term sig/2 |u - u_k|^2 (a Levenberg-Marquardt shift,
    zero at the solution) is switched on and relaxed again as Newton converges."""

    def __init__(self, A, gf, prox=None, rtol=1e-13, atol=1e-22, maxit=60):
        self.A, self.gf, self.prox = A, gf, prox  # prox: (Parameter sig, GridFunction anchor, sig0)
        self.rtol, self.atol, self.maxit = rtol, atol, maxit
        self.iterations = 0
        self.shifts = 0  # iterations where the shift had to be switched on or raised

    def solve(self, freedofs):
        A, gf = self.A, self.gf
        res = gf.vec.CreateVector()
        du = gf.vec.CreateVector()
        first = None
        sig = 0.0
        for it in range(self.maxit):
            if self.prox is not None:
                self.prox[0].Set(sig)
                self.prox[1].vec.data = gf.vec
            A.Apply(gf.vec, res)
            A.AssembleLinearization(gf.vec)
            inv = A.mat.Inverse(freedofs, inverse="sparsecholesky")
            self.inv = inv  # A.mat and its inverse at the last iterate (for a tangent predictor)
            du.data = inv * res
            dec = InnerProduct(du, res)
            self.iterations += 1
            E0 = A.Energy(gf.vec)
            ok = dec > 0
            s = 1.0
            if ok:
                near = dec < 1e-10 * abs(E0) + 1e-30
                while True:
                    gf.vec.data -= s * du
                    E1 = A.Energy(gf.vec)
                    if near or E1 <= E0 - 1e-4 * s * dec:
                        break
                    gf.vec.data += s * du
                    s *= 0.5
                    if s < 1e-3:
                        ok = False
                        break
            if not ok:
                if self.prox is None:
                    raise RuntimeError(f"Newton: no descent (decrement {dec:.3e})")
                sig = self.prox[2] if sig == 0 else sig * 10
                self.shifts += 1
                continue
            if sig > 0:
                sig = sig / 100 if sig > self.prox[2] * 1e-6 else 0.0
                continue
            first = max(first or 0.0, dec)
            if s == 1.0 and (dec < self.rtol * first or dec < self.atol):
                if self.prox is not None:
                    self.prox[0].Set(0.0)
                return it + 1
        raise RuntimeError(f"Newton did not converge in {self.maxit} iterations (decrement {dec:.3e})")


def eval_points(gfu, mesh, pts):
    """Values of a vector GridFunction at points (n x 3 array); each point must lie in the mesh."""
    pts = np.asarray(pts, dtype=float)
    mips = mesh(*(pts[:, i] for i in range(pts.shape[1])))
    vals = np.asarray(gfu(mips)).reshape(len(pts), -1)
    return vals


def lowest_eigs(K, M, freedofs, nev, ncv=None, seed=1, inv=None):
    """The nev lowest eigenpairs of K x = lam M x (K, M symmetric, K positive definite on the free
    dofs): shift-and-invert Lanczos (shift 0) in the M inner product with full
    reorthogonalisation. Returns eigenvalues, eigenvectors (numpy), relative residuals."""
    ncv = ncv or max(3 * nev, nev + 20)
    inv = inv or K.Inverse(freedofs, inverse="sparsecholesky")
    tmp, mx, w = K.CreateColVector(), K.CreateColVector(), K.CreateColVector()
    n = tmp.size
    fd = np.array([freedofs[i] for i in range(n)], dtype=bool)

    def mul(mat, v):
        tmp.FV().NumPy()[:] = v
        mx.data = mat * tmp
        return mx.FV().NumPy().copy()

    def op(v):
        tmp.FV().NumPy()[:] = v
        mx.data = M * tmp
        w.data = inv * mx
        return w.FV().NumPy().copy()

    rng = np.random.default_rng(seed)
    x0 = rng.standard_normal(n)
    x0[~fd] = 0
    q = op(x0)
    q /= math.sqrt(q @ mul(M, q))
    Q, MQ, alpha, beta = [q], [mul(M, q)], [], []
    for j in range(ncv):
        r = op(Q[-1])
        alpha.append(r @ MQ[-1])
        for _ in range(2):
            for qi, mqi in zip(Q, MQ):
                r -= (r @ mqi) * qi
        Mr = mul(M, r)
        b = math.sqrt(max(r @ Mr, 0.0))
        if j == ncv - 1 or b < 1e-14:
            break
        beta.append(b)
        Q.append(r / b)
        MQ.append(Mr / b)
    m = len(alpha)
    T = np.diag(alpha) + np.diag(beta[:m - 1], 1) + np.diag(beta[:m - 1], -1)
    theta, S = np.linalg.eigh(T)
    order = np.argsort(-theta)[:nev]
    Qm = np.array(Q[:m]).T
    lams = [1.0 / theta[i] for i in order]
    vecs = [Qm @ S[:, i] for i in order]
    res = []
    for lam, v in zip(lams, vecs):
        kx, mv = mul(K, v)[fd], mul(M, v)[fd]
        res.append(float(np.linalg.norm(kx - lam * mv) / np.linalg.norm(lam * mv)))
    return lams, vecs, res


def name_faces(shape, names):
    """names: list of (selector function on the face centre, name)."""
    for f in shape.faces:
        c = f.center
        for sel, nm in names:
            if sel(c):
                f.name = nm


def near(a, b, tol=1e-9):
    return abs(a - b) < tol


# --------------------------------------------------------------------------------------------
# 1. hanging block
# --------------------------------------------------------------------------------------------

HANGING = {
    "geometry": "cuboid x,y in [-0.01, 0.01], z in [0, 0.06] m; quarter model x,y >= 0",
    "rho": 1070.0, "E": 57.6e3, "nus": [0.45, 0.49], "L": 0.06, "a": 0.01,
    "levels": {"coarse": {"order": 3, "maxh": 0.004}, "fine": {"order": 4, "maxh": 0.004}},
}


def hanging(level, nu):
    p = HANGING
    lv = p["levels"][level]
    t0 = time.time()
    a, L = p["a"], p["L"]
    box = Box(Pnt(0, 0, 0), Pnt(a, a, L))
    name_faces(box, [(lambda c: near(c.z, L), "top"), (lambda c: near(c.z, 0), "bottom"),
                     (lambda c: near(c.x, 0), "symx"), (lambda c: near(c.y, 0), "symy")])
    mesh = Mesh(OCCGeometry(box).GenerateMesh(maxh=lv["maxh"]))
    fes = VectorH1(mesh, order=lv["order"], dirichlet="top", dirichletx="symx", dirichlety="symy")
    m = material(p["E"], nu)
    u = fes.TrialFunction()
    A = BilinearForm(fes, symmetric=True)
    A += Variation((psi(u, m) + p["rho"] * G * u[2]).Compile() * dx)
    gf = GridFunction(fes)
    with TaskManager():
        its = Minimizer(A, gf).solve(fes.FreeDofs())
    uz_bottom = Integrate(gf[2], mesh, BND, definedon=mesh.Boundaries("bottom")) / (a * a)
    ux_side = float(eval_points(gf, mesh, [[a, 0.0, L / 2]])[0, 0])
    return {"mean_uz_bottom_m": uz_bottom, "ux_side_midpoint_m": ux_side,
            "order": lv["order"], "maxh_m": lv["maxh"], "ndof": fes.ndof, "elements": mesh.ne,
            "newton_iterations": its, "seconds": time.time() - t0}


def run_hanging(levels):
    p = HANGING
    out = {"description": "hanging block under its own weight, top face z = 0.06 clamped",
           "inputs": {"geometry": p["geometry"], "rho_kg_m3": p["rho"], "E_Pa": p["E"],
                      "nu": p["nus"], "g_m_s2": G, "clamped": "z = 0.06 (all components)"},
           "linear_bar_rho_g_L2_over_2E_m": p["rho"] * G * p["L"] ** 2 / (2 * p["E"]),
           "refinement": "p: same mesh (maxh 4 mm, quarter), order 3 -> 4",
           "runs": {}}
    for nu in p["nus"]:
        r = {lv: hanging(lv, nu) for lv in levels}
        entry = {"levels": r, "result": r[levels[-1]], "material": material(p["E"], nu)}
        if len(levels) == 2:
            entry["change_coarse_to_fine"] = {
                k: rel_change(r["coarse"][k], r["fine"][k])
                for k in ("mean_uz_bottom_m", "ux_side_midpoint_m")}
        out["runs"][f"nu={nu}"] = entry
    return out


# --------------------------------------------------------------------------------------------
# 2. cylinder between bonded plates
# --------------------------------------------------------------------------------------------

CYLINDER = {
    "R": 0.025, "H": 0.03, "E": 103.46e3, "nu": 0.49,
    "strains": [round(0.02 * k, 2) for k in range(1, 11)],
    "levels": {"coarse": {"order": 3, "maxh": 0.001, "h_rim": 0.0002},
               "fine": {"order": 4, "maxh": 0.001, "h_rim": 0.0002}},
}


def cylinder(level):
    """Axisymmetric (exact for this problem): (r, z) in [0, R] x [0, H], u = (u_r, u_z),
    F = [[1 + u_r,r, 0, u_r,z], [0, 1 + u_r / r, 0], [u_z,r, 0, 1 + u_z,z]], dV = 2 pi r dr dz.
    Triangles of order 3 / 4, graded to h_rim at the two bonded rims (the stress singularities)."""
    p = CYLINDER
    lv = p["levels"][level]
    t0 = time.time()
    R, H = p["R"], p["H"]
    face = MoveTo(0, 0).Rectangle(R, H).Face()
    face.edges.Min(X).name = "axis"
    face.edges.Max(X).name = "free"
    face.edges.Min(Y).name = "bottom"
    face.edges.Max(Y).name = "top"
    mp = MeshingParameters(maxh=lv["maxh"], grading=0.3)
    for pz in (0.0, H):
        mp.RestrictH(R, pz, 0.0, lv["h_rim"])
    mesh = Mesh(OCCGeometry(face, dim=2).GenerateMesh(mp))
    fes = VectorH1(mesh, order=lv["order"], dirichlet="top|bottom", dirichletx="axis")
    m = material(p["E"], p["nu"])
    u = fes.TrialFunction()
    g = Grad(u)
    F = CF((1 + g[0, 0], 0, g[0, 1], 0, 1 + u[0] / x, 0, g[1, 0], 0, 1 + g[1, 1]), dims=(3, 3))
    J = Det(F)
    sig = Parameter(0.0)
    anchor = GridFunction(fes)
    dens = (m["mu"] / 2 * (InnerProduct(F, F) - 3) + m["lam"] / 2 * (J - m["a"]) ** 2
            + sig / 2 * InnerProduct(u - anchor, u - anchor)) * 2 * math.pi * x
    A = BilinearForm(fes, symmetric=True)
    A += Variation(dens.Compile() * dx)
    gf = GridFunction(fes)
    probe = GridFunction(fes)  # u_z = 1 on the top face's dofs: the reaction's virtual displacement
    probe.Set(CF((0, 1)), BND, definedon=mesh.Boundaries("top"))
    res = gf.vec.CreateVector()
    newton = Minimizer(A, gf, prox=(sig, anchor, 1e-3 * m["mu"] / lv["h_rim"] ** 2))
    steps = []
    s_prev = 0.0
    jump = GridFunction(fes)
    for s in p["strains"]:
        # predictor: the tangent (linearised) response to the plate's increment at the last state
        jump.vec[:] = 0
        jump.Set(CF((0, -(s - s_prev) * H)), BND, definedon=mesh.Boundaries("top"))
        with TaskManager():
            A.AssembleLinearization(gf.vec)
            res.data = A.mat * jump.vec
            gf.vec.data += jump.vec
            gf.vec.data -= A.mat.Inverse(fes.FreeDofs(), inverse="sparsecholesky") * res
            its = newton.solve(fes.FreeDofs())
            A.Apply(gf.vec, res)
        force = -InnerProduct(res, probe.vec)  # positive in compression
        ur = float(eval_points(gf, mesh, [[R, H / 2]])[0, 0])
        # how far the free surface next to the top rim passes the plate (no plate contact is
        # modelled: the bulge folds over the bonded rim)
        zs = H - np.geomspace(1e-6, 2e-3, 40)
        uz = eval_points(gf, mesh, np.c_[np.full_like(zs, R), zs])[:, 1]
        past = float(np.max(zs + uz - (H - s * H)))
        steps.append({"strain": s, "top_displacement_m": -s * H, "force_N": force,
                      "max_radial_displacement_m": ur, "barrel_radius_m": R + ur,
                      "free_surface_past_plate_m": max(past, 0.0), "newton_iterations": its})
        s_prev = s
    return {"steps": steps, "order": lv["order"], "maxh_m": lv["maxh"], "h_rim_m": lv["h_rim"],
            "ndof": fes.ndof, "elements": mesh.ne, "seconds": time.time() - t0}


def run_cylinder(levels):
    p = CYLINDER
    r = {lv: cylinder(lv) for lv in levels}
    m = material(p["E"], p["nu"])
    S = p["R"] / (2 * p["H"])  # shape factor: loaded area / bulge area
    K = p["E"] / (3 * (1 - 2 * p["nu"]))
    Ec = 1 / (1 / (p["E"] * (1 + 2 * S * S)) + 1 / K)
    out = {"description": "cylinder compressed between bonded plates (displacement control)",
           "inputs": {"radius_m": p["R"], "height_m": p["H"], "E_Pa": p["E"], "nu": p["nu"],
                      "gravity": False, "bottom": "clamped", "top": "u_x = u_y = 0, u_z = -s H",
                      "strains_s": p["strains"]},
           "material": m,
           "discretisation": "axisymmetric (r, z) triangles, exact reduction of the 3-D problem",
           "refinement": "p: same mesh (maxh 1 mm, 0.2 mm at the bonded rims), order 3 -> 4",
           "levels": r, "result": r[levels[-1]],
           "small_strain_check": {
               "shape_factor_S": S,
               "gent_apparent_modulus_Pa": Ec,
               "gent_force_at_first_strain_N": Ec * math.pi * p["R"] ** 2 * p["strains"][0],
               "formula": "E_c = 1 / (1 / (E (1 + 2 S^2)) + 1 / K), K = E / (3 (1 - 2 nu))"}}
    if len(levels) == 2:
        out["change_coarse_to_fine"] = {
            "force_max": max(rel_change(a["force_N"], b["force_N"])
                             for a, b in zip(r["coarse"]["steps"], r["fine"]["steps"])),
            "max_radial_displacement_max": max(
                rel_change(a["max_radial_displacement_m"], b["max_radial_displacement_m"])
                for a, b in zip(r["coarse"]["steps"], r["fine"]["steps"]))}
    return out


# --------------------------------------------------------------------------------------------
# 3. thesis indentation (force-controlled rigid sphere, penalty contact)
# --------------------------------------------------------------------------------------------

INDENT = {
    "L": 0.025, "H": 0.02, "rho": 1070.0, "E": 57.6e3, "nu": 0.49, "R": 0.015,
    "kappa": 3e9,  # penalty stiffness, Pa/m
    "kappa_check": 1e10,  # the first level's loads solved again with this kappa (sensitivity)
    "loads": [0.1, 9.73, 14.3],  # 0.1 N: the Hertz check
    "report": [9.73, 14.3],
    # the sphere's depth prescribed along this path (continuation with a tangent predictor) to
    # reach the loads; only the first refinement level walks it, the next starts each load from
    # the previous level's solution. 1 mm steps: Newton takes 6-9 iterations each (exact
    # Hessian, no shift needed); 1.5 mm steps took 17 and 52.
    "depth_path": [0.0004, 0.001, 0.002, 0.003, 0.004, 0.005, 0.006, 0.007, 0.008],
    "contact_refinement_radius": 0.017,
    "maxh": 0.004, "hc": 0.002,  # one mesh for both levels: 2 mm near the contact, 4 mm elsewhere
    "levels": {"coarse": {"order": 2}, "fine": {"order": 3}},
}


def hertz_depth(F, R, Estar):
    return (9 * F * F / (16 * R * Estar * Estar)) ** (1 / 3)


def indentation_mesh():
    p = INDENT
    L, H = p["L"], p["H"]
    box = Box(Pnt(0, 0, 0), Pnt(L, L, H))
    name_faces(box, [(lambda c: near(c.z, H), "top"), (lambda c: near(c.z, 0), "bottom"),
                     (lambda c: near(c.x, 0), "symx"), (lambda c: near(c.y, 0), "symy"),
                     (lambda c: near(c.x, L), "side")])
    mp = MeshingParameters(maxh=p["maxh"], grading=0.3)
    hc, rc = p["hc"], p["contact_refinement_radius"]
    n = int(math.ceil(rc / hc))
    for i in range(n + 1):
        for j in range(n + 1):
            px, py = i * hc, j * hc
            if px * px + py * py <= rc * rc:
                for depth in (0.0, hc, 2 * hc):
                    mp.RestrictH(px, py, H - depth, hc)
    return Mesh(OCCGeometry(box).GenerateMesh(mp))


def indentation(level, mesh, start=None):
    """One refinement level. start: None (walk the depth path from the unloaded block) or a
    dict F -> the previous level's solution (u, w) at load F, the initial guess of each load.
    Returns the figures and a dict F -> solution (GridFunction components)."""
    p = INDENT
    lv = p["levels"][level]
    t0 = time.time()
    L, H, R = p["L"], p["H"], p["R"]
    m = material(p["E"], p["nu"])
    fesu = VectorH1(mesh, order=lv["order"], dirichlet="bottom", dirichletx="symx",
                    dirichlety="symy")
    fes = fesu * NumberSpace(mesh)
    (u, w) = fes.TrialFunction()
    wdof = fes.ndof - 1
    Fq = Parameter(0.0)  # the quarter's share of the sphere's load
    kappa = Parameter(p["kappa"])
    sig = Parameter(0.0)
    anchor = GridFunction(fes)
    ua, wa = anchor.components
    centre = CF((0, 0, H + R)) + w * CF((0, 0, 1))
    rel = CF((x, y, z)) + u - centre
    gap = R - Norm(rel)  # > 0: penetration
    top_area = L * L
    vol_energy = psi(u, m) + p["rho"] * G * u[2] + sig / 2 * InnerProduct(u - ua, u - ua)
    # the proximal term on w: sig * (block volume) / 2 (w - w_k)^2, spread over the top face
    bnd_energy = (kappa / 2 * IfPos(gap, gap * gap, 0) + Fq / top_area * w
                  + sig / 2 * H * (w - wa) ** 2)
    A = BilinearForm(fes, symmetric=True)
    A += Variation(vol_energy.Compile() * dx)
    A += Variation(bnd_energy.Compile() * ds("top", bonus_intorder=2 * lv["order"]))
    gf = GridFunction(fes)
    gu, gw = gf.components
    newton = Minimizer(A, gf, prox=(sig, anchor, 1e-3 * m["mu"] / p["hc"] ** 2))
    fd_all = fes.FreeDofs()
    fd_u = BitArray(fd_all)
    fd_u[wdof] = False
    free = np.array([fd_all[i] for i in range(fes.ndof)], dtype=bool)
    log(f"   indentation {level}: {mesh.ne} elements, {fes.ndof} dofs, {time.time()-t0:.1f} s")
    if start is None:
        with TaskManager():
            newton.solve(fd_u)  # gravity alone, sphere held at w = 0 (touching, no force)
        sag = float(eval_points(gu, mesh, [[0, 0, H]])[0, 2])

    # outputs
    xs = np.arange(0, 25.0001, 2.5) * 1e-3
    top_line = np.c_[np.minimum(xs, L), np.zeros_like(xs), np.full_like(xs, H)]
    side_line = np.c_[np.full_like(xs[:9], L), np.zeros(9), np.arange(0, 20.0001, 2.5) * 1e-3]
    gr = np.linspace(0, 0.02, 81)
    GX, GY = np.meshgrid(gr, gr)
    msk = GX ** 2 + GY ** 2 <= 0.02 ** 2
    disc = np.c_[GX[msk], GY[msk], np.full(msk.sum(), H)]
    Estar = p["E"] / (1 - p["nu"] ** 2)
    steps, path, states, sols = [], [], [], {}
    ew, col, dv = gf.vec.CreateVector(), gf.vec.CreateVector(), gf.vec.CreateVector()

    def measure():
        wv = float(gw.vec[0])
        relv = CF((x, y, z)) + gu - CF((0, 0, H + R + wv))
        gapv = R - Norm(relv)
        fz = 4 * Integrate(kappa * IfPos(gapv, gapv, 0) * (-relv[2] / Norm(relv)), mesh, BND,
                           definedon=mesh.Boundaries("top"), order=4 * lv["order"])
        return -wv, fz  # fz: with the assembly's quadrature rule (order 2 p + bonus 2 p)

    def hold(depth):
        """Displacement control: the sphere moved to depth and held there. Predictor: the
        tangent d u / d w = -K_uu^-1 K_uw of the last converged state (whose factorisation the
        Minimizer kept), so that the contact zone moves with the sphere. With the previous field
        scaled instead, Newton stalled from about 3 mm on: its steps (driven by the penalty's
        large forces where the guess penetrates the sphere) were cut to ~1 % by the line search,
        with or without a positive semi-definite tangent."""
        d_now = -float(gw.vec[0])
        ew[:] = 0.0
        ew[wdof] = 1.0
        col.data = A.mat * ew
        dv.data = newton.inv * col
        gf.vec.data += (depth - d_now) * dv
        gw.vec[0] = -depth
        with TaskManager():
            return newton.solve(fd_u)

    def force_control(F):
        Fq.Set(F / 4)
        with TaskManager():
            return newton.solve(fd_all)

    def record(F, its):
        depth, fz = measure()
        Ud = eval_points(gu, mesh, disc)
        Pd = disc + Ud - np.array([0, 0, H + R - depth])
        pen = max(0.0, float(np.max(R - np.linalg.norm(Pd, axis=1))))
        top = [float(v) for v in eval_points(gu, mesh, top_line)[:, 2]]
        return {"F_N": F, "depth_m": depth, "contact_force_N": fz,
                "contact_force_over_F": fz / F, "penetration_max_m": pen,
                "penetration_over_depth": pen / depth, "top_centre_uz_m": top[0],
                "hertz_depth_m": hertz_depth(F, R, Estar), "top_uz_m": top,
                "side_ux_m": [float(v) for v in eval_points(gu, mesh, side_line)[:, 0]],
                "newton_iterations": its}

    def keep(F):
        sols[F] = [GridFunction(gu.space), float(gw.vec[0])]
        sols[F][0].vec.data = gu.vec

    if start is None:
        # 1. the load path in displacement control (the sphere's depth prescribed), each step's
        #    contact force measured
        for d in p["depth_path"]:
            its = hold(d)
            dd, fz = measure()
            path.append({"depth_m": dd, "contact_force_N": fz, "newton_iterations": its})
            states.append(gf.vec.CreateVector())
            states[-1].data = gf.vec
            log(f"   indentation {level}: depth {dd*1e3:.3f} mm held, force {fz:.4f} N, "
                f"Newton {its}, {time.time()-t0:.1f} s")
        # 2. each load in force control (the sphere's z a global unknown loaded by F), started
        #    from the path's state nearest to the depth interpolated (log-log) for F
        ld = np.log([q["depth_m"] for q in path])
        lf = np.log([q["contact_force_N"] for q in path])
    for F in p["loads"]:
        if start is None:
            d0 = float(np.exp(np.interp(math.log(F), lf, ld)))
            k = int(np.argmin([abs(math.log(q["depth_m"] / d0)) for q in path]))
            gf.vec.data = states[k]
        else:
            gu.Set(start[F][0])  # exact: the previous level's space is contained in this one
            gf.vec.FV().NumPy()[~free] = 0.0  # the Dirichlet / symmetry values exactly 0
            gw.vec[0] = start[F][1]
        its = force_control(F)
        steps.append(record(F, its))
        keep(F)
        s = steps[-1]
        log(f"   indentation {level}: F = {F} N, depth {s['depth_m']*1e3:.4f} mm, force "
            f"{s['contact_force_N']:.4f} N, penetration {s['penetration_max_m']*1e6:.2f} um, "
            f"Newton {its}, {time.time()-t0:.1f} s")
    out = {"steps": steps, "order": lv["order"], "maxh_m": p["maxh"], "contact_zone_h_m": p["hc"],
           "ndof": fes.ndof, "elements": mesh.ne}
    if start is None:
        out["gravity_sag_top_centre_m"] = sag
        out["displacement_path"] = path
        # 3. the penalty's effect: the reported loads again with a stiffer penalty (on the
        #    first level only, to save time: the penetration is a local effect)
        kappa.Set(p["kappa_check"])
        out["kappa_check"] = {"kappa_Pa_per_m": p["kappa_check"], "steps": []}
        for F in p["report"]:
            gu.vec.data = sols[F][0].vec
            gw.vec[0] = sols[F][1]
            its = force_control(F)
            s = record(F, its)
            out["kappa_check"]["steps"].append(
                {k: s[k] for k in ("F_N", "depth_m", "contact_force_N", "penetration_max_m",
                                   "top_centre_uz_m", "newton_iterations")})
            log(f"   indentation {level}: kappa {p['kappa_check']:.0e}: F = {F} N, depth "
                f"{s['depth_m']*1e3:.4f} mm, penetration {s['penetration_max_m']*1e6:.2f} um, "
                f"Newton {its}, {time.time()-t0:.1f} s")
        kappa.Set(p["kappa"])
    out["newton_iterations_total"] = newton.iterations
    out["newton_shifts"] = newton.shifts  # 0: the exact Hessian gave descent at every iterate
    out["seconds"] = time.time() - t0
    return out, sols


def run_indentation(levels):
    p = INDENT
    t0 = time.time()
    mesh = indentation_mesh()
    log(f"   indentation: mesh {time.time()-t0:.1f} s")
    r, start = {}, None
    for lv in levels:
        r[lv], start = indentation(lv, mesh, start)
    out = {"description": "rigid frictionless sphere pressed into a block by a force, gravity on",
           "inputs": {"block": "x,y in [-0.025, 0.025], z in [0, 0.02] m (quarter model x,y >= 0)",
                      "rho_kg_m3": p["rho"], "E_Pa": p["E"], "nu": p["nu"], "g_m_s2": G,
                      "bottom": "clamped", "sphere_radius_m": p["R"],
                      "sphere_centre_start_m": [0, 0, p["H"] + p["R"]],
                      "loads_N": p["report"], "hertz_check_load_N": p["loads"][0],
                      "path": "the first level: the sphere's depth prescribed along depth_path_m "
                              "(displacement control, tangent predictor), then each load solved "
                              "in force control from the nearest path state; the next level "
                              "starts each load from the previous level's solution",
                      "depth_path_m": p["depth_path"],
                      "contact": "penalty kappa/2 max(0, R - |X + u - c(w)|)^2 per unit rest area "
                                 "of the top face, force F w on the sphere's z displacement w "
                                 "(a global unknown, NumberSpace)",
                      "depth": "the sphere's downward displacement from first touch (includes "
                               "the gravity sag and the penalty's penetration)",
                      "kappa_Pa_per_m": p["kappa"],
                      "top_contour_x_mm": list(np.arange(0, 25.0001, 2.5)),
                      "top_contour": "u_z along y = 0 on the top face",
                      "side_contour_z_mm": list(np.arange(0, 20.0001, 2.5)),
                      "side_contour": "u_x along x = 0.025, y = 0"},
           "material": material(p["E"], p["nu"]),
           "refinement": "p: same mesh (2 mm within 17 mm of the top centre, 4 mm elsewhere, "
                         "quarter), order " + " -> ".join(str(p["levels"][lv]["order"])
                                                          for lv in levels),
           "levels": r}
    fine = r[levels[-1]]
    out["result"] = {f"F={F}": next(s for s in fine["steps"] if s["F_N"] == F) for F in p["report"]}
    out["kappa_check"] = dict(r[levels[0]]["kappa_check"], level=levels[0])
    if len(levels) == 2:
        ch = {}
        for F in p["report"]:
            a = next(s for s in r["coarse"]["steps"] if s["F_N"] == F)
            b = next(s for s in r["fine"]["steps"] if s["F_N"] == F)
            ch[f"F={F}"] = {
                "depth": rel_change(a["depth_m"], b["depth_m"]),
                "top_centre_uz": rel_change(a["top_centre_uz_m"], b["top_centre_uz_m"]),
                "top_uz_max_abs_over_depth": max(abs(i - j) for i, j in
                                                 zip(a["top_uz_m"], b["top_uz_m"])) / b["depth_m"],
                "side_ux_max_abs_over_max": max(abs(i - j) for i, j in
                                                zip(a["side_ux_m"], b["side_ux_m"]))
                / max(abs(v) for v in b["side_ux_m"])}
        out["change_coarse_to_fine"] = ch
    return out


# --------------------------------------------------------------------------------------------
# 4. cantilever modes
# --------------------------------------------------------------------------------------------

CANTI = {
    "x": (-0.05, 0.05), "y": (-0.015, 0.015), "z": (0.0, 0.03),
    "rho": 1070.0, "E": 215856.0, "nu": 0.499, "tip_masses": [0.0, 0.052, 0.101],
    "nev": 8,
    "levels": {"coarse": {"order": 3, "maxh": 0.0075}, "fine": {"order": 4, "maxh": 0.0075}},
}


def canti_mesh(maxh, half):
    p = CANTI
    y0 = 0.0 if half else p["y"][0]
    box = Box(Pnt(p["x"][0], y0, p["z"][0]), Pnt(p["x"][1], p["y"][1], p["z"][1]))
    name_faces(box, [(lambda c: near(c.x, p["x"][0]), "clamp"),
                     (lambda c: half and near(c.y, 0), "sym"),
                     (lambda c: near(c.x, p["x"][1]), "tip")])
    for e in box.edges:
        c = e.center
        if near(c.x, p["x"][1]) and near(c.z, p["z"][1]):
            e.name = "tipedge"
    return Mesh(OCCGeometry(box).GenerateMesh(maxh=maxh))


def canti_modes(mesh, order, kind, tip_masses, nev):
    """kind: 'sym' (u_y = 0 on y = 0: bending in z, axial), 'anti' (u_x = u_z = 0 on y = 0:
    bending in y, torsion) or 'full'. Linear elasticity with Lame mu and lam - mu."""
    p = CANTI
    kw = {"sym": {"dirichlety": "sym"}, "anti": {"dirichletx": "sym", "dirichletz": "sym"},
          "full": {}}[kind]
    fes = VectorH1(mesh, order=order, dirichlet="clamp", **kw)
    m = material(p["E"], p["nu"])
    mu, lame = m["mu"], m["lame_lambda"]
    u, v = fes.TnT()
    K = BilinearForm(fes, symmetric=True)
    K += (2 * mu * InnerProduct(Sym(Grad(u)), Sym(Grad(v)))
          + lame * Trace(Grad(u)) * Trace(Grad(v))) * dx
    edge_len = p["y"][1] - p["y"][0]
    line_mass = Parameter(0.0)  # kg/m on the tip's top edge
    M = BilinearForm(fes, symmetric=True)
    M += p["rho"] * u * v * dx
    M += line_mass * u * v * DifferentialSymbol(BBND)(definedon=mesh.BBoundaries("tipedge"))
    with TaskManager():
        K.Assemble()
        Kinv = K.mat.Inverse(fes.FreeDofs(), inverse="sparsecholesky")
    out = []
    gfu = GridFunction(fes)
    for mt in tip_masses:
        line_mass.Set(mt / edge_len)
        with TaskManager():
            M.Assemble()
            lams, vecs, res = lowest_eigs(K.mat, M.mat, fes.FreeDofs(), nev, inv=Kinv)
        modes = []
        for lam, vec in zip(lams, vecs):
            gfu.vec.FV().NumPy()[:] = vec
            modes.append({"frequency_Hz": math.sqrt(lam) / (2 * math.pi),
                          "label": classify(gfu, mesh, kind)})
        out.append({"tip_mass_kg": mt, "modes": modes, "max_residual": max(res)})
    return out, fes.ndof


def classify(gfu, mesh, kind):
    """Label a mode by its centre line's displacement (y = 0, z = 0.015) and, for torsion, the
    z displacement of the side line (y = 0.015, z = 0.015)."""
    p = CANTI
    xs = np.linspace(p["x"][0] + 0.005, p["x"][1], 20)
    zc = (p["z"][0] + p["z"][1]) / 2
    cl = eval_points(gfu, mesh, np.c_[xs, np.zeros_like(xs), np.full_like(xs, zc)])
    sl = eval_points(gfu, mesh, np.c_[xs, np.full_like(xs, p["y"][1]), np.full_like(xs, zc)])
    tip = eval_points(gfu, mesh, [[p["x"][1], a, b] for a in (0.0, p["y"][1])
                                  for b in (p["z"][0], zc, p["z"][1])])
    scale = max(np.abs(cl).max(), np.abs(sl).max(), np.abs(tip).max())

    def nodes(f):
        f = f[np.abs(f) > 0.05 * np.abs(f).max()]
        return int(np.sum(np.sign(f[1:]) != np.sign(f[:-1])))

    cx, cy, cz = (np.abs(cl[:, i]).max() for i in range(3))
    tors = np.abs(sl[:, 2] - cl[:, 2]).max()
    if kind in ("sym", "anti"):
        cand = {"sym": {"bending z": (cz, cl[:, 2]), "axial": (cx, cl[:, 0])},
                "anti": {"bending y": (cy, cl[:, 1]), "torsion": (tors, sl[:, 2] - cl[:, 2])}}[kind]
    else:
        cand = {"bending z": (cz, cl[:, 2]), "axial": (cx, cl[:, 0]),
                "bending y": (cy, cl[:, 1]), "torsion": (tors, sl[:, 2] - cl[:, 2])}
    name, (mag, f) = max(cand.items(), key=lambda kv: kv[1][0])
    if mag < 0.3 * scale:
        return "other (cross-section)"
    return f"{name} {nodes(f) + 1}"


def cantilever(level, with_full):
    p = CANTI
    lv = p["levels"][level]
    t0 = time.time()
    mesh = canti_mesh(lv["maxh"], half=True)
    sym, nd_s = canti_modes(mesh, lv["order"], "sym", p["tip_masses"], p["nev"])
    anti, nd_a = canti_modes(mesh, lv["order"], "anti", [0.0], p["nev"])
    modes = sorted([dict(md, symmetry="u_y even (sym)") for md in sym[0]["modes"]]
                   + [dict(md, symmetry="u_y odd (anti)") for md in anti[0]["modes"]],
                   key=lambda md: md["frequency_Hz"])
    bz = {}
    for r in sym:
        f = [md["frequency_Hz"] for md in r["modes"] if md["label"].startswith("bending z")]
        # with a tip mass only the first is kept: the line mass on the soft edge adds local modes
        # (mesh-dependent, the edge load being singular) that mix with the higher bending modes
        bz[f"{r['tip_mass_kg']}"] = f[:2] if r["tip_mass_kg"] == 0 else f[:1]
    out = {"modes_no_tip_mass": modes, "bending_z_Hz_by_tip_mass_kg": bz,
           "sym_half": sym, "anti_half": anti, "order": lv["order"], "maxh_m": lv["maxh"],
           "ndof_half": nd_s, "elements_half": mesh.ne}
    if with_full:
        fm = canti_mesh(lv["maxh"], half=False)
        full, nd_f = canti_modes(fm, lv["order"], "full", [0.0, 0.052], p["nev"])
        out["full_model_check"] = {"ndof": nd_f, "runs": full}
    out["seconds"] = time.time() - t0
    return out


def timoshenko_cantilever(E, nu, rho, L, b, h, tip_mass=0.0, n=400):
    """Reference 1-D beam (bending in z): Timoshenko elements (linear w and theta, one-point
    shear), shear coefficient 10 (1 + nu) / (12 + 11 nu) (rectangle), consistent mass with rotary
    inertia; the tip mass with its rotary inertia about the section's centre (on the top edge,
    offset h/2). Returns the two lowest frequencies, Hz, and the Euler-Bernoulli ones."""
    Gs = E / (2 * (1 + nu))
    A, I = b * h, b * h ** 3 / 12
    k = 10 * (1 + nu) / (12 + 11 * nu)
    le = L / n
    N = 2 * (n + 1)
    Kg, Mg = np.zeros((N, N)), np.zeros((N, N))
    kb = E * I / le * np.array([[0, 0, 0, 0], [0, 1, 0, -1], [0, 0, 0, 0], [0, -1, 0, 1]])
    B = np.array([-1 / le, -0.5, 1 / le, -0.5])  # gamma = w' - theta at the midpoint
    ks = k * Gs * A * le * np.outer(B, B)
    mc = np.array([[2, 1], [1, 2]]) * le / 6
    me = np.zeros((4, 4))
    me[np.ix_([0, 2], [0, 2])] = rho * A * mc
    me[np.ix_([1, 3], [1, 3])] = rho * I * mc
    for e in range(n):
        idx = [2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3]
        Kg[np.ix_(idx, idx)] += kb + ks
        Mg[np.ix_(idx, idx)] += me
    Mg[N - 2, N - 2] += tip_mass
    Mg[N - 1, N - 1] += tip_mass * (h / 2) ** 2
    Kf, Mf = Kg[2:, 2:], Mg[2:, 2:]
    Lc = np.linalg.cholesky(Mf)
    Li = np.linalg.inv(Lc)
    lam = np.linalg.eigvalsh(Li @ Kf @ Li.T)
    f_t = [math.sqrt(v) / (2 * math.pi) for v in lam[:2]]
    # Euler-Bernoulli without tip mass: (beta_n L)^2 sqrt(E I / (rho A L^4)) / (2 pi)
    f_eb = [bl ** 2 * math.sqrt(E * I / (rho * A * L ** 4)) / (2 * math.pi)
            for bl in (1.8751040687, 4.6940911330)]
    return f_t, f_eb


def run_cantilever(levels):
    p = CANTI
    r = {lv: cantilever(lv, with_full=(lv == levels[0])) for lv in levels}
    L = p["x"][1] - p["x"][0]
    b = p["y"][1] - p["y"][0]
    h = p["z"][1] - p["z"][0]
    beam = {}
    for mt in p["tip_masses"]:
        ft, feb = timoshenko_cantilever(p["E"], p["nu"], p["rho"], L, b, h, mt)
        beam[f"{mt}"] = {"timoshenko_Hz": ft}
        if mt == 0:
            beam[f"{mt}"]["euler_bernoulli_Hz"] = feb
    out = {"description": "cantilever, linear modes about the undeformed state",
           "inputs": {"geometry": "x in [-0.05, 0.05], y in [-0.015, 0.015], z in [0, 0.03] m",
                      "clamped": "x = -0.05", "rho_kg_m3": p["rho"], "E_Pa": p["E"],
                      "nu": p["nu"], "tip_masses_kg": p["tip_masses"],
                      "tip_mass": "line mass m / 0.03 kg/m on the edge x = 0.05, z = 0.03 "
                                  "(consistent edge mass matrix)",
                      "method": "K u = w^2 M u, K: linear elasticity with Lame mu, lam - mu; "
                                "solved on the half y >= 0 twice (u_y even: bending in z, axial; "
                                "u_y odd: bending in y, torsion), shift-invert Lanczos"},
           "material": material(p["E"], p["nu"]),
           "refinement": "p: same mesh (maxh 7.5 mm, half), order 3 -> 4",
           "levels": r, "result": r[levels[-1]], "beam_theory": beam}
    if len(levels) == 2:
        ca, fi = r["coarse"], r["fine"]
        out["change_coarse_to_fine"] = {
            "modes_no_tip_mass_max": max(rel_change(a["frequency_Hz"], b["frequency_Hz"])
                                         for a, b in zip(ca["modes_no_tip_mass"][:8],
                                                         fi["modes_no_tip_mass"][:8])),
            "bending_z_first_by_tip_mass": {
                k: rel_change(ca["bending_z_Hz_by_tip_mass_kg"][k][0],
                              fi["bending_z_Hz_by_tip_mass_kg"][k][0])
                for k in fi["bending_z_Hz_by_tip_mass_kg"]}}
    return out


# --------------------------------------------------------------------------------------------
# driver
# --------------------------------------------------------------------------------------------

PROBLEMS = {"hanging": run_hanging, "cylinder": run_cylinder, "indentation": run_indentation,
            "cantilever": run_cantilever}


def summary(name, r):
    lines = [f"== {name}: {r['description']}"]
    if name == "hanging":
        lines.append(f"   linear bar rho g L^2/(2E) = {r['linear_bar_rho_g_L2_over_2E_m']*1e3:.4f} mm")
        for k, e in r["runs"].items():
            res = e["result"]
            ch = e.get("change_coarse_to_fine", {})
            lines.append(f"   {k}: mean uz(bottom) = {res['mean_uz_bottom_m']*1e3:.4f} mm, "
                         f"ux(side mid) = {res['ux_side_midpoint_m']*1e3:.5f} mm  "
                         f"(change {ch.get('mean_uz_bottom_m', float('nan'))*100:.3f} %, "
                         f"{ch.get('ux_side_midpoint_m', float('nan'))*100:.3f} %)")
    elif name == "cylinder":
        for s in r["result"]["steps"]:
            lines.append(f"   s = {s['strain']:.2f}: F = {s['force_N']:.4f} N, "
                         f"max u_r = {s['max_radial_displacement_m']*1e3:.4f} mm")
        lines.append(f"   Gent small-strain force at s = 0.02: "
                     f"{r['small_strain_check']['gent_force_at_first_strain_N']:.3f} N")
        if "change_coarse_to_fine" in r:
            c = r["change_coarse_to_fine"]
            lines.append(f"   change coarse -> fine: force {c['force_max']*100:.3f} %, "
                         f"u_r {c['max_radial_displacement_max']*100:.3f} %")
    elif name == "indentation":
        for k, s in r["result"].items():
            lines.append(f"   {k}: depth = {s['depth_m']*1e3:.4f} mm, top-centre uz = "
                         f"{s['top_centre_uz_m']*1e3:.4f} mm, contact force = "
                         f"{s['contact_force_N']:.4f} N, penetration = "
                         f"{s['penetration_max_m']*1e6:.2f} um")
            lines.append("      top uz (mm): " + " ".join(f"{v*1e3:.3f}" for v in s["top_uz_m"]))
            lines.append("      side ux (mm): " + " ".join(f"{v*1e3:.4f}" for v in s["side_ux_m"]))
        for s in r["kappa_check"]["steps"]:
            lines.append(f"   kappa {r['kappa_check']['kappa_Pa_per_m']:.0e}: F={s['F_N']}: depth "
                         f"{s['depth_m']*1e3:.4f} mm, penetration {s['penetration_max_m']*1e6:.2f} um")
        st = r["levels"][next(reversed(r["levels"]))]["steps"][0]
        lines.append(f"   smallest load {st['F_N']} N: depth {st['depth_m']*1e3:.4f} mm, "
                     f"Hertz {st['hertz_depth_m']*1e3:.4f} mm")
        if "change_coarse_to_fine" in r:
            for k, c in r["change_coarse_to_fine"].items():
                lines.append(f"   change coarse -> fine {k}: depth {c['depth']*100:.3f} %, "
                             f"top centre {c['top_centre_uz']*100:.3f} %, top "
                             f"contour {c['top_uz_max_abs_over_depth']*100:.3f} % of depth, side "
                             f"{c['side_ux_max_abs_over_max']*100:.3f} % of its max")
    elif name == "cantilever":
        for md in r["result"]["modes_no_tip_mass"]:
            lines.append(f"   {md['frequency_Hz']:9.4f} Hz  {md['label']}")
        for k, f in r["result"]["bending_z_Hz_by_tip_mass_kg"].items():
            lines.append(f"   tip mass {k} kg: bending z " + ", ".join(f"{v:.4f}" for v in f)
                         + f" Hz  (Timoshenko beam {r['beam_theory'][k]['timoshenko_Hz'][0]:.4f})")
        if "change_coarse_to_fine" in r:
            c = r["change_coarse_to_fine"]
            lines.append(f"   change coarse -> fine: modes {c['modes_no_tip_mass_max']*100:.3f} %, "
                         + ", ".join(f"{k} kg {v*100:.3f} %"
                                     for k, v in c["bending_z_first_by_tip_mass"].items()))
    return "\n".join(lines)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(os.path.dirname(here))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--problem", default="all", choices=["all"] + list(PROBLEMS))
    ap.add_argument("--levels", default="both", choices=["both", "fine", "coarse"],
                    help="both: the refinement study (default); fine: the reference level only")
    ap.add_argument("--out", default=os.path.join(root, "tests", "reference"))
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--verbose", action="store_true", help="progress on stderr")
    args = ap.parse_args()
    global VERBOSE
    VERBOSE = args.verbose
    SetNumThreads(args.threads)
    levels = ["coarse", "fine"] if args.levels == "both" else [args.levels]
    names = ["hanging", "cylinder", "cantilever"] if args.problem == "all" else [args.problem]
    os.makedirs(args.out, exist_ok=True)
    path = os.path.join(args.out, "ngsolve.json")
    doc = {}
    if os.path.exists(path):
        with open(path) as f:
            doc = json.load(f)  # keep the other problems' results
    doc.setdefault("problems", {})
    t_all = time.time()
    for nm in names:
        t0 = time.time()
        r = PROBLEMS[nm](levels)
        r["run_seconds"] = time.time() - t0
        doc["problems"][nm] = r
        print(summary(nm, r))
        print(f"   ({r['run_seconds']:.1f} s)", flush=True)
    doc["meta"] = {
        "generator": "scripts/reference/ngsolve_reference.py",
        "command": " ".join(["scripts/reference/ngsolve_reference.py"] + sys.argv[1:]),
        "ngsolve_version": ngsolve.__version__, "numpy_version": np.__version__,
        "python": platform.python_version(), "threads": args.threads,
        "date": datetime.date.today().isoformat(),
        "last_run_seconds": time.time() - t_all,
        "energy": "Psi = mu/2 (tr F^T F - 3) + lam/2 (J - a)^2, a = 1 + mu/lam, "
                  "mu = E/(2(1+nu)), lam = E nu/((1+nu)(1-2nu)) + mu",
        "units": "SI (m, N, Pa, kg, s, Hz)",
        "levels": levels,
    }
    with open(path, "w") as f:
        json.dump(rnd(doc), f, indent=1, sort_keys=True)
        f.write("\n")
    print(f"wrote {path} ({time.time() - t_all:.1f} s)")


if __name__ == "__main__":
    main()
