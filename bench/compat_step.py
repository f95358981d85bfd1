"""Reads geomkit's STEP files with OpenCASCADE (cadquery-ocp) and geomkit's import of files
OpenCASCADE wrote, and checks both ways.

Usage: python bench/compat_step.py PATH/TO/geomkit [--fixtures DIR]

Export: model files (Bézier, rational Bézier and B-spline curves, clamped, extended and
periodic; Bézier and B-spline surfaces, a periodic one, the 14 x 14 interpolated surface;
composite surfaces; the closed bodies) are written by `geomkit export`, read by
STEPControl_Reader (transfer must succeed), checked by BRepCheck_Analyzer (valid), and OCCT's
points at 1000 parameters of each curve/face are compared with `geomkit eval` of the same
model file at the same parameters (1e-12 relative to the model's size). Bodies must come back
as one closed solid whose volume (BRepGProp, adaptive to 1e-12) is the exact volume within
1e-9 relative.

Import: OCCT writes a B-spline surface, a Bézier curve and a box with STEPControl_Writer;
`geomkit import` reads them, and `geomkit eval` of each imported model at 1000 parameters
equals OCCT's points within 1e-12 (the box's faces: every geomkit point lies on OCCT's plane,
and the patch corners are the face's vertices). With --fixtures DIR those three files are
also copied to DIR (the test fixtures of `cargo test`).

Prints a Markdown table; exit code 1 on any failure.
"""

import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
from OCP.BRep import BRep_Tool
from OCP.BRepAdaptor import BRepAdaptor_Curve
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.BRepGProp import BRepGProp
from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox
from OCP.Geom import (Geom_BezierCurve, Geom_BSplineSurface, Geom_Circle,
                      Geom_SphericalSurface)
from OCP.GeomConvert import (GeomConvert, GeomConvert_BSplineCurveToBezierCurve,
                             GeomConvert_BSplineSurfaceToBezierSurface)
from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf
from OCP.GProp import GProp_GProps
from OCP.IFSelect import IFSelect_RetDone
from OCP.Interface import Interface_Static
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Reader, STEPControl_Writer
from OCP.TColgp import TColgp_Array1OfPnt, TColgp_Array2OfPnt
from OCP.TColStd import TColStd_Array1OfInteger, TColStd_Array1OfReal
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE, TopAbs_SHELL, TopAbs_SOLID
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS
from OCP.gp import gp_Ax2, gp_Ax3, gp_Dir, gp_Pnt

N_PARAMS = 1000
REL = 1e-12
VOLUME_REL = 1e-9

rows = []
failures = 0


def record(name, check, value, limit, ok):
    global failures
    rows.append((name, check, value, limit, "pass" if ok else "FAIL"))
    if not ok:
        failures += 1


def run(geomkit, *args):
    r = subprocess.run([geomkit, *map(str, args)], capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"geomkit {' '.join(map(str, args))}: {r.stderr.strip()}")
    return r.stderr


def geomkit_eval(geomkit, model, params, work):
    """geomkit eval MODEL --at params: the coordinates (3 columns, z = 0 for plane curves)."""
    at = work / "at.csv"
    np.savetxt(at, params, delimiter=",", fmt="%.17g",
               header=",".join(["t"] if params.ndim == 1 else ["u", "v"]), comments="")
    out = work / "eval.csv"
    run(geomkit, "eval", model, "--at", at, "-o", out)
    data = np.loadtxt(out, delimiter=",", skiprows=1, ndmin=2)
    k = 1 if params.ndim == 1 else 2
    xyz = data[:, k:]
    if xyz.shape[1] == 2:
        xyz = np.hstack([xyz, np.zeros((len(xyz), 1))])
    return xyz


def read_step(path):
    reader = STEPControl_Reader()
    status = reader.ReadFile(str(path))
    if status != IFSelect_RetDone:
        return None, f"ReadFile status {status}"
    n = reader.TransferRoots()
    if n == 0:
        return None, "nothing transferred"
    return reader.OneShape(), ""


def shapes(shape, kind):
    out = []
    e = TopExp_Explorer(shape, kind)
    while e.More():
        out.append(e.Current())
        e.Next()
    return out


def extent(points):
    return max(1.0, float(np.max(np.abs(points))))


def domain_of(model):
    """The parameter domain of a model file as geomkit defines it."""
    t = model["type"]
    if t == "bezier_curve":
        return [(0.0, 1.0)]
    if t == "bezier_surface":
        return [(0.0, 1.0), (0.0, 1.0)]
    if t == "bspline_curve":
        p, k = model["degree"], model["knots"]
        n = len(model["control_points"])
        return [(k[p], k[n])]
    if t == "bspline_surface":
        (p, q), ku, kv = model["degree"], model["knots_u"], model["knots_v"]
        r, c = len(model["net"]), len(model["net"][0])
        return [(ku[p], ku[r]), (kv[q], kv[c])]
    raise ValueError(t)


def sample_params(dom, rng):
    if len(dom) == 1:
        a, b = dom[0]
        t = np.concatenate([[a, b], rng.uniform(a, b, N_PARAMS - 2)])
        return t
    (a, b), (c, d) = dom
    uv = np.column_stack([rng.uniform(a, b, N_PARAMS), rng.uniform(c, d, N_PARAMS)])
    uv[0] = (a, c)
    uv[1] = (b, d)
    return uv


def occt_curve_points(edge, ts):
    c = BRepAdaptor_Curve(TopoDS.Edge_s(edge))
    out = []
    for t in ts:
        p = c.Value(float(t))
        out.append((p.X(), p.Y(), p.Z()))
    return np.array(out)


def occt_surface_points(face, uv):
    s = BRep_Tool.Surface_s(TopoDS.Face_s(face))
    out = []
    for u, v in uv:
        p = s.Value(float(u), float(v))
        out.append((p.X(), p.Y(), p.Z()))
    return np.array(out)


def export_and_read(geomkit, name, model, work):
    """`geomkit export`, then STEPControl_Reader and BRepCheck_Analyzer: the shape or None."""
    step = work / f"{name}.step"
    try:
        run(geomkit, "export", model, "-o", step)
    except RuntimeError as e:
        record(name, "geomkit export", str(e)[:70], "", False)
        return None
    shape, why = read_step(step)
    record(name, "STEPControl_Reader transfers", why or "ok", "", shape is not None)
    if shape is None:
        return None
    valid = BRepCheck_Analyzer(shape).IsValid()
    record(name, "BRepCheck_Analyzer valid", str(valid), "True", valid)
    return shape


def check_export(geomkit, name, model_path, work, rng):
    """Export, read with OCCT, check validity and points."""
    shape = export_and_read(geomkit, name, model_path, work)
    if shape is None:
        return
    model = json.loads(Path(model_path).read_text())
    dom = domain_of(model)
    params = sample_params(dom, rng)
    ours = geomkit_eval(geomkit, model_path, params, work)
    scale = extent(ours)
    if len(dom) == 1:
        edges = shapes(shape, TopAbs_EDGE)
        if len(edges) != 1:
            record(name, "one edge", len(edges), 1, False)
            return
        theirs = occt_curve_points(edges[0], params)
    else:
        faces = shapes(shape, TopAbs_FACE)
        if len(faces) != 1:
            record(name, "one face", len(faces), 1, False)
            return
        theirs = occt_surface_points(faces[0], params)
    err = float(np.max(np.abs(ours - theirs))) / scale
    record(name, f"OCCT points = geomkit eval ({N_PARAMS} params)", f"{err:.1e}", f"{REL:.0e}",
           err <= REL)


def check_body(geomkit, name, body_args, volume, work):
    model = work / f"{name}.json"
    run(geomkit, "compose", "body", *body_args, "-o", model)
    shape = export_and_read(geomkit, name, model, work)
    if shape is None:
        return
    check_solid(name, shape, volume)


def bernstein(n, t):
    """The n + 1 Bernstein polynomials of degree n at the parameters t (rows)."""
    k = np.arange(n + 1)
    binom = np.array([math.comb(n, i) for i in k], dtype=float)
    t = np.asarray(t)[:, None]
    return binom * t**k * (1 - t) ** (n - k)


def bezier_volume(net):
    """(1/3) ∫∫ S · (S_u × S_v) du dv of a closed Bézier surface, by Gauss-Legendre with 40
    points per direction (exact for the polynomial integrand of degree < 80), in NumPy."""
    net = np.asarray(net, dtype=float)
    n, m = net.shape[0] - 1, net.shape[1] - 1
    x, w = np.polynomial.legendre.leggauss(40)
    t, w = (x + 1) / 2, w / 2
    bu, bv = bernstein(n, t), bernstein(m, t)
    # Derivatives: n (b_(n-1)) differences of the net.
    du = n * np.einsum("ai,bj,ijc->abc", bernstein(n - 1, t), bv, net[1:] - net[:-1])
    dv = m * np.einsum("ai,bj,ijc->abc", bu, bernstein(m - 1, t), net[:, 1:] - net[:, :-1])
    s = np.einsum("ai,bj,ijc->abc", bu, bv, net)
    f = np.einsum("abc,abc->ab", s, np.cross(du, dv)) / 3
    return float(w @ f @ w)


def check_solid(name, shape, volume):
    """One closed solid of the given volume (BRepGProp, adaptive)."""
    solids = shapes(shape, TopAbs_SOLID)
    closed = len(solids) == 1 and all(BRep_Tool.IsClosed_s(s) for s in shapes(shape, TopAbs_SHELL))
    record(name, "one closed solid", f"{len(solids)} solid(s), closed={closed}", "1, True", closed)
    # The adaptive integration (relative error 1e-12): the default fixed Gauss rule is off by
    # up to 1% on rational faces (the cylinder's side), for every STEP file alike.
    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, props, 1e-12)
    v = props.Mass()
    err = abs(v - volume) / volume
    record(name, f"volume {v:.12g} (exact {volume:.12g})", f"{err:.1e}", f"{VOLUME_REL:.0e}",
           err <= VOLUME_REL)


def check_composite(geomkit, work, rng):
    """2 x 2 bicubic Bézier patches of one 7 x 7 net: four faces sewn along shared edges
    (12 edges, 9 vertices), each face's points equal to geomkit's at the cell's parameters."""
    name = "composite_2x2"
    g = np.linspace(0, 1, 7)
    net = [[[3 * x, 2 * y, math.sin(2 * x + y) + x * y] for y in g] for x in g]
    patches = [[{"bezier": [row[3 * j:3 * j + 4] for row in net[3 * i:3 * i + 4]]}
                for j in range(2)] for i in range(2)]
    model = work / f"{name}.json"
    uk, vk = [0.0, 1.0, 2.5], [0.0, 2.0, 3.0]
    model.write_text(json.dumps({"type": "composite_surface", "u_knots": uk, "v_knots": vk,
                                 "patches": patches}))
    shape = export_and_read(geomkit, name, model, work)
    if shape is None:
        return
    from OCP.TopExp import TopExp
    from OCP.TopTools import TopTools_IndexedMapOfShape
    from OCP.TopAbs import TopAbs_VERTEX
    counts = []
    for kind in (TopAbs_FACE, TopAbs_EDGE, TopAbs_VERTEX):
        m = TopTools_IndexedMapOfShape()
        TopExp.MapShapes_s(shape, kind, m)
        counts.append(m.Extent())
    record(name, "faces, edges, vertices (shared where patches meet)", str(counts),
           "[4, 12, 9]", counts == [4, 12, 9])
    faces = shapes(shape, TopAbs_FACE)
    worst = 0.0
    for k, face in enumerate(faces):
        i, j = divmod(k, 2)
        st = sample_params([(0.0, 1.0), (0.0, 1.0)], rng)
        uv = np.column_stack([uk[i] + st[:, 0] * (uk[i + 1] - uk[i]),
                              vk[j] + st[:, 1] * (vk[j + 1] - vk[j])])
        ours = geomkit_eval(geomkit, model, uv, work)
        theirs = occt_surface_points(face, st)
        worst = max(worst, float(np.max(np.abs(ours - theirs))) / extent(ours))
    record(name, f"OCCT points = geomkit eval ({N_PARAMS} params per face)", f"{worst:.1e}",
           f"{REL:.0e}", worst <= REL)


def check_mushroom(geomkit, work, rng):
    """The demo's Fig. 3 Mushroom (a closed Bézier surface of degrees 8 x 10): a solid whose
    volume is the exact one of its net (Gauss-Legendre in NumPy), points as geomkit's."""
    demo = work / "demo"
    subprocess.run([geomkit, "demo", "--out", demo], capture_output=True, check=False)
    model = demo / "fig3-mushroom.json"
    check_export(geomkit, "mushroom", model, work, rng)
    shape, _ = read_step(work / "mushroom.step")
    if shape is not None:
        check_solid("mushroom", shape, bezier_volume(json.loads(model.read_text())["net"]))


def write_step(shape, path):
    Interface_Static.SetCVal_s("write.step.schema", "AP214IS")
    w = STEPControl_Writer()
    # OCCT prints transfer statistics on standard output: keep them out of the table.
    sys.stdout.flush()
    saved = os.dup(1)
    with open(os.devnull, "w") as null:
        os.dup2(null.fileno(), 1)
        try:
            w.Transfer(shape, STEPControl_AsIs)
            status = w.Write(str(path))
        finally:
            os.dup2(saved, 1)
            os.close(saved)
    if status != IFSelect_RetDone:
        raise RuntimeError(f"OCCT could not write {path}")


def occt_files(work):
    """A B-spline surface, a Bézier curve and a box, written by OCCT."""
    files = {}
    # A bicubic B-spline surface on a 6 x 5 net with an interior double knot in u.
    nu, nv = 6, 5
    poles = TColgp_Array2OfPnt(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            poles.SetValue(i + 1, j + 1,
                           gp_Pnt(i * 1.5, j * 1.25, math.sin(i) * math.cos(0.7 * j) + 0.1 * i * j))
    uk, um = [0.0, 0.4, 1.0], [4, 2, 4]
    vk, vm = [0.0, 0.5, 2.0], [4, 1, 4]

    def real_array(xs):
        a = TColStd_Array1OfReal(1, len(xs))
        for k, x in enumerate(xs):
            a.SetValue(k + 1, x)
        return a

    def int_array(xs):
        a = TColStd_Array1OfInteger(1, len(xs))
        for k, x in enumerate(xs):
            a.SetValue(k + 1, x)
        return a

    surf = Geom_BSplineSurface(poles, real_array(uk), real_array(vk), int_array(um),
                               int_array(vm), 3, 3)
    face = BRepBuilderAPI_MakeFace(surf, 1e-7).Face()
    files["occt_bspline_surface"] = (work / "occt_bspline_surface.step", face, surf)
    # A quintic Bézier curve in space.
    pts = TColgp_Array1OfPnt(1, 6)
    for k, p in enumerate([(0, 0, 0), (1, 2, 0.5), (2.5, 2, -1), (4, 0, 0), (5, -1, 2), (6, 1, 1)]):
        pts.SetValue(k + 1, gp_Pnt(*p))
    bez = Geom_BezierCurve(pts)
    edge = BRepBuilderAPI_MakeEdge(bez).Edge()
    files["occt_bezier_curve"] = (work / "occt_bezier_curve.step", edge, bez)
    box = BRepPrimAPI_MakeBox(gp_Pnt(-1, -2, -0.5), 2.0, 4.0, 1.5).Shape()
    files["occt_box"] = (work / "occt_box.step", box, None)
    # Rational B-splines of several spans: OCCT's B-spline form of a circle of radius 2 about
    # (1, -1, 0.5) in a tilted plane, and of a sphere of radius 1.5 (GeomConvert).
    axis = gp_Ax2(gp_Pnt(1, -1, 0.5), gp_Dir(0.3, -0.2, 1.0))
    circle = GeomConvert.CurveToBSplineCurve_s(Geom_Circle(axis, 2.0))
    edge = BRepBuilderAPI_MakeEdge(circle).Edge()
    files["occt_rational_circle"] = (work / "occt_rational_circle.step", edge, circle)
    sphere = GeomConvert.SurfaceToBSplineSurface_s(
        Geom_SphericalSurface(gp_Ax3(gp_Pnt(0.5, 0.25, -1), gp_Dir(0, 0, 1)), 1.5))
    face = BRepBuilderAPI_MakeFace(sphere, 1e-7).Face()
    files["occt_rational_sphere"] = (work / "occt_rational_sphere.step", face, sphere)
    for path, shape, _ in files.values():
        write_step(shape, path)
    return files


def check_import(geomkit, files, work, rng):
    for name, (path, shape, geom) in files.items():
        out = work / f"import-{name}"
        try:
            log = run(geomkit, "import", path, "-o", out)
        except RuntimeError as e:
            record(name, "geomkit import", str(e)[:70], "", False)
            continue
        models = sorted(out.glob("*.json"))
        if name == "occt_box":
            ok = len(models) == 6
            record(name, "geomkit import: 6 faces", f"{len(models)} models", "6", ok)
            plane_faces = [TopoDS.Face_s(f) for f in shapes(shape, TopAbs_FACE)]
            worst = 0.0
            verts = set()
            for m in models:
                data = json.loads(m.read_text())
                uv = sample_params([(0.0, 1.0), (0.0, 1.0)], rng)
                ours = geomkit_eval(geomkit, m, uv, work)
                # The nearest OCCT face: every point must lie on it.
                best = None
                for f in plane_faces:
                    s = BRep_Tool.Surface_s(f)
                    d = max(GeomAPI_ProjectPointOnSurf(gp_Pnt(*p), s).LowerDistance()
                            for p in ours[:50])
                    if best is None or d < best[0]:
                        best = (d, s)
                d = max(GeomAPI_ProjectPointOnSurf(gp_Pnt(*p), best[1]).LowerDistance()
                        for p in ours)
                worst = max(worst, d / 4.0)
                net = np.array(data["net"]).reshape(-1, 3)
                for c in net:
                    verts.add(tuple(np.round(c, 12)))
            box_corners = {(x, y, z) for x in (-1.0, 1.0) for y in (-2.0, 2.0) for z in (-0.5, 1.0)}
            corners_ok = verts == box_corners
            record(name, "face points on OCCT's planes (1000 per face)", f"{worst:.1e}",
                   f"{REL:.0e}", worst <= REL)
            record(name, "patch corners = the box's 8 vertices", str(corners_ok), "True",
                   corners_ok)
            continue
        if name.startswith("occt_rational"):
            check_rational_pieces(geomkit, name, models, geom, work, rng)
            continue
        if len(models) != 1:
            record(name, "geomkit import: one model", f"{len(models)}: {log.strip()[:60]}", "1",
                   False)
            continue
        data = json.loads(models[0].read_text())
        dom = domain_of(data)
        params = sample_params(dom, rng)
        ours = geomkit_eval(geomkit, models[0], params, work)
        if len(dom) == 1:
            theirs = np.array([(lambda p: (p.X(), p.Y(), p.Z()))(geom.Value(float(t)))
                               for t in params])
        else:
            theirs = np.array([(lambda p: (p.X(), p.Y(), p.Z()))(geom.Value(float(u), float(v)))
                               for u, v in params])
        err = float(np.max(np.abs(ours - theirs))) / extent(theirs)
        record(name, f"imported as {data['type']}: points = OCCT ({N_PARAMS} params)",
               f"{err:.1e}", f"{REL:.0e}", err <= REL)


def span_of(path):
    """The span of a piece file KIND-N-I(-J).json: (I,) or (I, J)."""
    return tuple(int(k) for k in path.stem.split("-")[2:])


def check_rational_pieces(geomkit, name, models, geom, work, rng):
    """A rational B-spline of several spans imported as rational Bézier pieces: each piece
    equals OCCT's own Bézier decomposition of the same geometry (GeomConvert) at 1000
    parameters."""
    models = sorted(models, key=span_of)
    if name == "occt_rational_circle":
        conv = GeomConvert_BSplineCurveToBezierCurve(geom)
        arcs = [conv.Arc(k + 1) for k in range(conv.NbArcs())]
        record(name, "geomkit import: one rational Bézier piece per span",
               f"{len(models)} pieces", f"{len(arcs)}", len(models) == len(arcs))
        worst = 0.0
        for m, arc in zip(models, arcs):
            t = sample_params([(0.0, 1.0)], rng)
            ours = geomkit_eval(geomkit, m, t, work)
            theirs = np.array([(lambda p: (p.X(), p.Y(), p.Z()))(arc.Value(float(x))) for x in t])
            worst = max(worst, float(np.max(np.abs(ours - theirs))) / extent(theirs))
    else:
        conv = GeomConvert_BSplineSurfaceToBezierSurface(geom)
        nu, nv = conv.NbUPatches(), conv.NbVPatches()
        record(name, "geomkit import: one rational Bézier patch per span",
               f"{len(models)} patches", f"{nu * nv}", len(models) == nu * nv)
        worst = 0.0
        for m in models:
            i, j = span_of(m)
            patch = conv.Patch(i + 1, j + 1)
            uv = sample_params([(0.0, 1.0), (0.0, 1.0)], rng)
            ours = geomkit_eval(geomkit, m, uv, work)
            theirs = np.array([(lambda p: (p.X(), p.Y(), p.Z()))(patch.Value(float(u), float(v)))
                               for u, v in uv])
            worst = max(worst, float(np.max(np.abs(ours - theirs))) / extent(theirs))
    record(name, f"pieces = OCCT's Bézier decomposition ({N_PARAMS} params each)",
           f"{worst:.1e}", f"{REL:.0e}", worst <= REL)


# Formulas without an exact B-spline form, with the same formulas in NumPy: (name, model,
# formula of piece k at parameters (u, v) or t). `geomkit export` writes each piece as an
# interpolating B-spline on the piece's own parameters and reports its deviation.
TAU = 2 * math.pi


def _torus(u, v):
    return np.stack([np.cos(u) * (2 + np.cos(v)), np.sin(u) * (2 + np.cos(v)), np.sin(v)], -1)


def _ruled_curves():
    return [lambda t: np.stack([0 * t, 0 * t, 0 * t], -1),
            lambda t: np.stack([np.cos(t), np.sin(t), 0.2 * np.sin(3 * t)], -1),
            lambda t: np.stack([0.5 * np.cos(t), 0.5 * np.sin(t), 1 + 0 * t], -1),
            lambda t: np.stack([0 * t, 0 * t, 1 + 0 * t], -1)]


def _ruled(k):
    """Strip k (1-based) of the ruled body: v in [k - 1, k], u in [0, 1] -> t = 2π u."""
    c = _ruled_curves()

    def f(u, v):
        lam = (v - (k - 1))[..., None]
        return c[k - 1](TAU * u) * (1 - lam) + c[k](TAU * u) * lam
    return f


APPROX = [
    ("approx_explicit",
     {"type": "composite_explicit", "x_knots": [0, 1, 2], "y_knots": [0, 1],
      "patches": [["sin(x) * exp(y)"], ["sqrt(1 + x^2 + y^2)"]]},
     [lambda u, v: np.stack([u, v, np.sin(u) * np.exp(v)], -1),
      lambda u, v: np.stack([u, v, np.sqrt(1 + u**2 + v**2)], -1)]),
    ("approx_torus_halves",
     {"type": "composite_surface", "u_knots": [0, math.pi, TAU], "v_knots": [0, TAU],
      "patches": [[{"x": "cos(u)*(2+cos(v))", "y": "sin(u)*(2+cos(v))", "z": "sin(v)"}]] * 2},
     [_torus, _torus]),
    ("approx_ruled_body",
     {"type": "ruled", "u": [0, 1], "v": [0, 1, 2, 3], "curves": [
         {"point": [0, 0, 0]},
         {"x": "cos(t)", "y": "sin(t)", "z": "0.2*sin(3*t)", "t": [0, TAU]},
         {"x": "0.5*cos(t)", "y": "0.5*sin(t)", "z": "1", "t": [0, TAU]},
         {"point": [0, 0, 1]}]},
     [_ruled(1), _ruled(2), _ruled(3)]),
    ("approx_curve",
     {"type": "piecewise", "knots": [0, 1, 2], "pieces": [
         {"x": "t", "y": "sqrt(1 + t)", "z": "exp(t)"},
         {"x": "t", "y": "sqrt(1 + t)", "z": "exp(t)"}]},
     [lambda t: np.stack([t, np.sqrt(1 + t), np.exp(t)], -1)] * 2),
]

APPROX_LINE = re.compile(r"warning: approximated (.*?): a ([\d x]+)-point interpolating "
                         r"B-spline, max deviation (\S+) \(tolerance (\S+)\)")


def check_approx(geomkit, work, rng):
    """Export formulas, read with OCCT: valid, and OCCT's points of each face / edge at 1000
    parameters within the deviation geomkit reports for that piece (x 1.05: the report is
    measured on a grid 8 times denser than the samples, these points are random)."""
    for name, model, formulas in APPROX:
        path = work / f"{name}.json"
        path.write_text(json.dumps(model))
        step = work / f"{name}.step"
        try:
            log = run(geomkit, "export", path, "-o", step)
        except RuntimeError as e:
            record(name, "geomkit export", str(e)[:70], "", False)
            continue
        report = APPROX_LINE.findall(log)
        record(name, "warning: per approximated piece", f"{len(report)}", f"{len(formulas)}",
               len(report) == len(formulas))
        deviations = [float(r[2]) for r in report]
        tolerances = [float(r[3]) for r in report]
        ok = all(d <= t for d, t in zip(deviations, tolerances))
        record(name, "reported deviation <= tolerance",
               f"max {max(deviations):.1e}" if deviations else "-",
               f"{min(tolerances):.1e}" if tolerances else "-", ok and bool(report))
        shape, why = read_step(step)
        record(name, "STEPControl_Reader transfers", why or "ok", "", shape is not None)
        if shape is None:
            continue
        valid = BRepCheck_Analyzer(shape).IsValid()
        record(name, "BRepCheck_Analyzer valid", str(valid), "True", valid)
        curve = model["type"] == "piecewise"
        items = shapes(shape, TopAbs_EDGE if curve else TopAbs_FACE)
        # Each face / edge by its parameter range: the piece whose domain it is.
        worst = 0.0
        matched = 0
        for k, (formula, dev) in enumerate(zip(formulas, deviations)):
            if curve:
                a, b = model["knots"][k], model["knots"][k + 1]
                for e in items:
                    c = BRepAdaptor_Curve(TopoDS.Edge_s(e))
                    if abs(c.FirstParameter() - a) < 1e-12 and abs(c.LastParameter() - b) < 1e-12:
                        t = sample_params([(a, b)], rng)
                        d = np.linalg.norm(occt_curve_points(e, t) - formula(t), axis=1)
                        worst = max(worst, float(d.max()) / dev)
                        matched += 1
                        break
                continue
            if model["type"] == "ruled":
                dom = [tuple(model["u"]), (model["v"][k], model["v"][k + 1])]
            else:
                uk = model.get("u_knots") or model["x_knots"]
                vk = model.get("v_knots") or model["y_knots"]
                nv = len(vk) - 1
                i, j = divmod(k, nv)
                dom = [(uk[i], uk[i + 1]), (vk[j], vk[j + 1])]
            for f in items:
                s = BRep_Tool.Surface_s(TopoDS.Face_s(f))
                u1, u2, v1, v2 = s.Bounds()
                if max(abs(u1 - dom[0][0]), abs(u2 - dom[0][1]), abs(v1 - dom[1][0]),
                       abs(v2 - dom[1][1])) < 1e-12:
                    uv = sample_params(dom, rng)
                    d = np.linalg.norm(occt_surface_points(f, uv) - formula(uv[:, 0], uv[:, 1]),
                                       axis=1)
                    worst = max(worst, float(d.max()) / dev)
                    matched += 1
                    break
        record(name, f"OCCT points within the reported deviation ({N_PARAMS} params per piece, "
               "distance / deviation)", f"{worst:.2f} ({matched} pieces)", "1.05",
               worst <= 1.05 and matched == len(formulas))
        if model["type"] == "ruled":
            solids = shapes(shape, TopAbs_SOLID)
            closed = len(solids) == 1 and all(BRep_Tool.IsClosed_s(x)
                                              for x in shapes(shape, TopAbs_SHELL))
            record(name, "one closed solid", f"{len(solids)} solid(s), closed={closed}",
                   "1, True", closed)


def write_models(geomkit, work):
    """Model files of every exported kind: (name, path)."""
    models = []

    def save(name, obj):
        p = work / f"{name}.json"
        p.write_text(json.dumps(obj))
        models.append((name, p))

    save("bezier_curve_3d", {"type": "bezier_curve",
                             "points": [[0, 0, 0], [1, 2, 0.5], [3, 2.5, -1], [4, 0, 0.25],
                                        [5.5, -1, 2], [7, 0.5, 1]]})
    h = math.sqrt(0.5)
    save("rational_quarter_circle", {"type": "bezier_curve", "points": [[1, 0], [1, 1], [0, 1]],
                                     "weights": [1, h, 1]})
    save("rational_cubic_3d", {"type": "bezier_curve",
                               "points": [[0, 0, 0], [1, 3, 1], [3, 3, -1], [4, 0, 0.5]],
                               "weights": [1, 0.3, 2.5, 1]})
    save("bezier_surface", {"type": "bezier_surface",
                            "net": [[[i, j, math.sin(i + 0.3 * j)] for j in range(5)]
                                    for i in range(4)]})
    # Rational Bézier surfaces: an octant of the unit sphere (w_ij = w_i w_j, a pole where
    # one side collapses) and a saddle with uneven weights.
    octant = [[[r * c, r * sn, z] for r, z in [(1, 0), (1, 1), (0, 1)]]
              for c, sn in [(1, 0), (1, 1), (0, 1)]]
    w = [1, h, 1]
    save("rational_sphere_octant", {"type": "bezier_surface", "net": octant,
                                    "weights": [[a * b for b in w] for a in w]})
    save("rational_saddle", {"type": "bezier_surface",
                             "net": [[[i, j, (i - 1.5) * (j - 1) * 0.5] for j in range(3)]
                                     for i in range(4)],
                             "weights": [[1, 2, 1], [0.5, 3, 1], [1, 0.25, 2], [1, 1, 1]]})
    # Interpolated curves: SciPy's form (clamped), the paper's extended knots, periodic.
    t = np.linspace(0, 2 * math.pi, 12, endpoint=False)
    pts = np.column_stack([np.cos(t) * (2 + 0.3 * np.sin(3 * t)), np.sin(t) * 2, 0.5 * np.cos(2 * t)])
    csv = work / "curve_points.csv"
    np.savetxt(csv, pts, delimiter=",", fmt="%.17g", header="x,y,z", comments="")
    for name, args in [("bspline_curve_scipy", ["--form", "scipy"]),
                       ("bspline_curve_extended", ["--end", "natural", "--form", "extended"]),
                       ("bspline_curve_periodic", ["--end", "periodic"])]:
        p = work / f"{name}.json"
        run(geomkit, "interpolate", "curve", csv, *args, "-o", p)
        models.append((name, p))
    # Surfaces: the 14 x 14 interpolated one (as the demo's), a torus (periodic both ways).
    g = np.linspace(0, 1, 14)
    grid = np.array([[x * 13, y * 13, math.sin(3 * x) * math.cos(2 * y) * 3] for x in g for y in g])
    csv = work / "grid14.csv"
    np.savetxt(csv, grid, delimiter=",", fmt="%.17g", header="x,y,z", comments="")
    p = work / "bspline_surface_14x14.json"
    run(geomkit, "interpolate", "surface", csv, "--rows", "14", "--cols", "14", "-o", p)
    models.append(("bspline_surface_14x14", p))
    a = np.linspace(0, 2 * math.pi, 10, endpoint=False)
    torus = np.array([[(3 + math.cos(v)) * math.cos(u), (3 + math.cos(v)) * math.sin(u), math.sin(v)]
                      for u in a for v in a])
    csv = work / "torus.csv"
    np.savetxt(csv, torus, delimiter=",", fmt="%.17g", header="x,y,z", comments="")
    p = work / "bspline_torus_periodic.json"
    run(geomkit, "interpolate", "surface", csv, "--rows", "10", "--cols", "10", "--end",
        "periodic", "-o", p)
    models.append(("bspline_torus_periodic", p))
    return models


def main():
    geomkit = sys.argv[1]
    fixtures = None
    if "--fixtures" in sys.argv:
        fixtures = Path(sys.argv[sys.argv.index("--fixtures") + 1])
    rng = np.random.default_rng(20261204)
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for name, path in write_models(geomkit, work):
            check_export(geomkit, name, path, work, rng)
        check_composite(geomkit, work, rng)
        check_mushroom(geomkit, work, rng)
        check_approx(geomkit, work, rng)
        tau = 2 * math.pi
        for name, args, volume in [
            ("cube", ["cube"], 8.0),
            ("box", ["box", "--size", "1,2,3"], 6.0),
            ("prism", ["prism", "--ngon", "6", "--radius", "1", "--height", "2"],
             6 * 0.5 * math.sin(tau / 6) * 2),
            ("pyramid", ["pyramid"], 8.0 / 3.0),
            ("cylinder", ["cylinder"], math.pi * 2),
            ("cone", ["cone"], math.pi * 2 / 3),
            ("frustum", ["frustum"], math.pi * 2 / 3 * (1 + 0.25 + 0.5)),
        ]:
            check_body(geomkit, name, args, volume, work)
        files = occt_files(work)
        if fixtures is not None:
            fixtures.mkdir(parents=True, exist_ok=True)
            for path, _, _ in files.values():
                shutil.copy(path, fixtures / path.name)
        check_import(geomkit, files, work, rng)
    print("| model | check | measured | limit | result |")
    print("|---|---|---|---|---|")
    for r in rows:
        print("| " + " | ".join(str(x) for x in r) + " |")
    print(f"\n{len(rows) - failures} of {len(rows)} checks passed")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
