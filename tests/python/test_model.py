"""Meshes, pictures and model files of the Python package (issue 23): `Drawable.mesh`,
`write`, `render`, `svg`, `png`, Jupyter's `_repr_svg_` / `_repr_png_`, `geomkit.Mesh`,
`geomkit.Polyline`, and `load` / `loads` / `save` of every file kind the CLI writes.

Independent references: trimesh and meshio read every written mesh (counts, watertightness,
volume), Pillow decodes the PNGs, xml.etree parses the SVGs; NumPy's Bernstein sums and cross
products check the geometry (points on the curve, the tolerance at the quarter points, the
volume by the divergence theorem); exact volumes of the bodies (the cube's 8, a box's a*b*c).
The model files come from the CLI itself (target/release/geomkit, run in a temporary
directory) and from docs/formats.md, so the package reads exactly what the tools write.
"""

from __future__ import annotations

import io
import json
import os
import pickle
import re
import subprocess
import xml.etree.ElementTree as ET
from concurrent.futures import ThreadPoolExecutor
from math import comb
from pathlib import Path

import meshio
import numpy as np
import pytest
import trimesh
from PIL import Image

import geomkit

ROOT = Path(__file__).resolve().parents[2]
CLI = ROOT / "target" / "release" / "geomkit"

CURVE = {"type": "bezier_curve", "points": [[0, 0], [1, 2], [3, 1], [4, 0]]}
SURFACE = {
    "type": "bezier_surface",
    "net": [
        [[0, 0, 0], [1, 0, 1], [2, 0, 0]],
        [[0, 1, 1], [1, 1, 2], [2, 1, 1]],
        [[0, 2, 0], [1, 2, 1], [2, 2, 0]],
    ],
}
THREE_FACTORS = {
    "type": "pointcalc-model",
    "factors": [{"name": n, "nodes": [0.0, 1.0]} for n in "abc"],
    "response": ["y"],
    "values": [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0],
}


def bernstein(points: np.ndarray, t: np.ndarray) -> np.ndarray:
    """A Bézier curve at `t` by its Bernstein sum (NumPy; the reference)."""
    n = len(points) - 1
    t = np.asarray(t)[:, None]
    return sum(comb(n, i) * t**i * (1 - t) ** (n - i) * points[i] for i in range(n + 1))


def bernstein_surface(net: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """A Bézier surface on the grid u x v: shape (len(u), len(v), dim)."""
    n, m = net.shape[0] - 1, net.shape[1] - 1
    bu = np.array([[comb(n, i) * x**i * (1 - x) ** (n - i) for i in range(n + 1)] for x in u])
    bv = np.array([[comb(m, j) * y**j * (1 - y) ** (m - j) for j in range(m + 1)] for y in v])
    return np.einsum("ai,bj,ijd->abd", bu, bv, net)


def divergence_volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    """The signed volume of a closed triangle mesh (divergence theorem, NumPy)."""
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def cli(*args: str, cwd: Path) -> None:
    subprocess.run([str(CLI), *args], cwd=cwd, check=True, capture_output=True)


@pytest.fixture(scope="module")
def cli_files(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """Model files written by the CLI: every kind its commands write as JSON."""
    if not CLI.is_file():
        pytest.skip(f"{CLI} not built (cargo build --release -p geomkit-cli)")
    d = tmp_path_factory.mktemp("cli")
    (d / "c.json").write_text(json.dumps(CURVE))
    (d / "s.json").write_text(json.dumps(SURFACE))
    (d / "pts.csv").write_text("0,0\n1,2\n2,1\n3,3\n4,0\n")
    (d / "h.csv").write_text("0,1,0,1\n1,2,1,0\n0,1,3,1\n2,0,1,1\n")
    (d / "exp.csv").write_text("a,b,y\n0,0,1\n0,1,2\n1,0,3\n1,1,5\n2,0,1\n2,1,0\n")
    (d / "curve.csv").write_text("a,y\n0,1\n1,3\n2,2\n")
    (d / "src.json").write_text("[[0, 0], [1, 2], [2, 0]]")
    (d / "net.json").write_text(json.dumps(SURFACE["net"]))
    (d / "ruled.json").write_text(json.dumps({
        "type": "ruled", "v": [0, 1],
        "curves": [{"circle": {"center": [0, 0, 0], "radius": 1}}, {"point": [0, 0, 2]}],
    }))
    (d / "pieces.json").write_text(json.dumps(
        {"type": "piecewise", "knots": [0, 1, 2], "pieces": ["x^2", "2*x - 1"]}))
    cli("bezier", "elevate", "c.json", "--to", "5", "-o", "elevated_curve.json", cwd=d)
    cli("bezier", "elevate", "s.json", "--to", "3,4", "-o", "elevated_surface.json", cwd=d)
    cli("interpolate", "curve", "pts.csv", "-o", "interp_curve.json", cwd=d)
    cli("interpolate", "surface", "--heights", "h.csv", "-o", "interp_surface.json", cwd=d)
    for ext in ("csv", "npy"):
        cli("interpolate", "curve", "pts.csv", "--control", "-o", f"control.{ext}", cwd=d)
    cli("compose", "body", "cube", "-o", "cube.json", cwd=d)
    cli("compose", "body", "box", "--size", "1,2,3", "-o", "box.json", cwd=d)
    cli("compose", "patches", "interp_surface.json", "-o", "patches.json", cwd=d)
    cli("compose", "ruled", "ruled.json", "-o", "cone.json", cwd=d)
    cli("compose", "piecewise", "pieces.json", "-o", "piecewise.json", cwd=d)
    cli("pointcalc", "fit", "exp.csv", "--factors", "a,b", "--response", "y",
        "-o", "fit2.json", cwd=d)
    cli("pointcalc", "fit", "curve.csv", "--factors", "a", "--response", "y",
        "-o", "fit1.json", cwd=d)
    cli("pointcalc", "curve", "src.json", "-o", "pc_curve.json", cwd=d)
    cli("pointcalc", "surface", "net.json", "-o", "pc_surface.json", cwd=d)
    return {p.stem: p for p in d.glob("*.json")}


# --- model files ---------------------------------------------------------------------------

CLI_KINDS = {
    "elevated_curve": "bezier_curve",
    "elevated_surface": "bezier_surface",
    "interp_curve": "bspline_curve",
    "interp_surface": "bspline_surface",
    "cube": "formula",
    "box": "formula",
    "patches": "formula",
    "cone": "formula",
    "piecewise": "formula",
    "fit2": "pointcalc-model",
    "fit1": "pointcalc-model",
    "pc_curve": "pointcalc-curve",
    "pc_surface": "pointcalc-surface-samples",
}


@pytest.mark.parametrize("name", sorted(CLI_KINDS))
def test_every_cli_file_loads_saves_and_loads_again(cli_files, tmp_path, name):
    path = cli_files[name]
    model = geomkit.load(path)
    assert isinstance(model, geomkit.Drawable)
    assert model._model().kind == CLI_KINDS[name]
    # save writes the same model: the JSON values equal the CLI's file's.
    out = tmp_path / "again.json"
    model.save(out)
    assert json.loads(out.read_text()) == json.loads(path.read_text())
    assert geomkit.load(out).to_json() == model.to_json()
    # The CLI reads what save wrote: its mesh of the saved file is the package's, byte for
    # byte (the same library writers; a PLY of f64 is exact).
    cli("mesh", str(out), "-o", "cli.ply", cwd=tmp_path)
    model.write(tmp_path / "py.ply")
    assert (tmp_path / "cli.ply").read_bytes() == (tmp_path / "py.ply").read_bytes()


@pytest.mark.parametrize("ext", ["csv", "npy"])
def test_control_points_with_their_knots_load(cli_files, tmp_path, ext):
    """`interpolate curve --control -o NAME.EXT` writes control points and NAME.knots.EXT:
    they load as the B-spline curve SciPy evaluates the same (knots, coefficients) to, through
    the five points; the CLI's mesh of the pair is the package's, byte for byte."""
    from scipy.interpolate import BSpline

    d = cli_files["interp_curve"].parent
    model = geomkit.load(d / f"control.{ext}")
    assert model._model().kind == "bspline_curve"
    spec = json.loads(model.to_json())
    knots, control = np.array(spec["knots"]), np.array(spec["control_points"])
    if ext == "npy":
        np.testing.assert_array_equal(control, np.load(d / "control.npy"))
    reference = BSpline(knots, control, spec["degree"])
    line = model.mesh(tolerance=1e-4)
    np.testing.assert_allclose(line.points, reference(line.parameters), rtol=0, atol=1e-12)
    points = np.loadtxt(d / "pts.csv", delimiter=",")
    on = [np.min(np.linalg.norm(reference(np.linspace(*line.parameters[[0, -1]], 20001))
                                - p, axis=1)) for p in points]
    assert max(on) < 1e-3  # passes through the points (to the sampling of the check)
    cli("mesh", str(d / f"control.{ext}"), "-o", str(tmp_path / "cli.ply"), cwd=tmp_path)
    model.write(tmp_path / "py.ply")
    assert (tmp_path / "cli.ply").read_bytes() == (tmp_path / "py.ply").read_bytes()


def test_control_points_errors(tmp_path):
    (tmp_path / "c.csv").write_text("x,y\n0,0\n1,1\n")
    with pytest.raises(ValueError, match="knots"):
        geomkit.load(tmp_path / "c.csv")  # no sibling
    (tmp_path / "c.knots.csv").write_text("knot\n0\n0\n1\n")
    with pytest.raises(ValueError, match="3 knots for 2 control points"):
        geomkit.load(tmp_path / "c.csv")
    (tmp_path / "c.knots.csv").write_text("0\n0\n1\n1\n")
    line = geomkit.load(tmp_path / "c.csv").mesh(samples=3)  # degree 1: the segment
    np.testing.assert_allclose(line.points, [[0, 0], [0.5, 0.5], [1, 1]], atol=1e-15)
    (tmp_path / "c.knots.csv").write_text("0\n1\n0\n1\n")
    with pytest.raises(ValueError, match="c.csv"):
        geomkit.load(tmp_path / "c.csv")  # decreasing knots: the library's message
    (tmp_path / "c.csv").write_text("x,y\n0,0\n1,a\n")
    with pytest.raises(ValueError, match="line 3"):
        geomkit.load(tmp_path / "c.csv")
    with pytest.raises(OSError):
        geomkit.load(tmp_path / "missing.csv")
    np.save(tmp_path / "s.npy", np.array(["a", "b"]))
    np.save(tmp_path / "s.knots.npy", np.zeros(4))
    with pytest.raises(ValueError, match="numbers"):
        geomkit.load(tmp_path / "s.npy")


def test_every_demo_file_loads(tmp_path):
    """`geomkit demo` writes model files of many kinds: every one loads and saves back."""
    if not CLI.is_file():
        pytest.skip("CLI not built")
    cli("demo", "--out", str(tmp_path / "demo"), cwd=tmp_path)
    files = sorted((tmp_path / "demo").rglob("*.json"))
    assert len(files) >= 20
    for path in files:
        model = geomkit.load(path)
        assert json.loads(model.to_json()) == json.loads(path.read_text()), path.name


def docs_examples() -> list[str]:
    text = (ROOT / "docs" / "formats.md").read_text(encoding="utf-8")
    return re.findall(r"```json\n(.*?)```", text, flags=re.S)


def test_every_docs_example_loads():
    examples = docs_examples()
    assert len(examples) >= 15
    kinds = set()
    for text in examples:
        model = geomkit.loads(text)
        kinds.add(model._model().kind)
        again = geomkit.loads(model.to_json())
        assert type(again) is type(model) and again.to_json() == model.to_json()
    # Every type of the format's page.
    assert {"bezier_curve", "bezier_surface", "bspline_curve", "bspline_surface", "ruled",
            "composite_surface", "composite_explicit", "piecewise", "polyline", "polygon",
            "formula", "pointcalc-model", "pointcalc-curve",
            "pointcalc-surface-samples"} <= kinds


def test_load_errors(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{"type": "bezier_curve", "points": [[0, 0], [1, "a"]]}')
    with pytest.raises(ValueError, match="bad.json"):
        geomkit.load(bad)
    with pytest.raises(OSError):
        geomkit.load(tmp_path / "missing.json")
    with pytest.raises(TypeError):
        geomkit.loads(b"{}")  # type: ignore[arg-type]


# --- meshes of surfaces --------------------------------------------------------------------

def read_all(path: Path) -> dict[str, tuple[int, int]]:
    """(vertices, faces) as trimesh and meshio read the file (no merging by trimesh)."""
    out = {}
    mesh = trimesh.load(path, force="mesh", process=False)
    out["trimesh"] = (len(mesh.vertices), len(mesh.faces))
    if path.suffix != ".glb":
        m = meshio.read(path)
        out["meshio"] = (len(m.points), sum(len(c.data) for c in m.cells if c.type == "triangle"))
    return out


def test_cube_mesh_arrays_and_exact_volume(cli_files):
    cube = geomkit.load(cli_files["cube"])
    assert isinstance(cube, geomkit.Drawable)
    mesh = cube.mesh()
    assert isinstance(mesh, geomkit.Mesh)
    v, f, n = mesh.vertices, mesh.faces, mesh.normals
    assert v.shape[1] == 3 and f.shape[1] == 3 and n.shape == v.shape
    assert f.dtype == np.int64 and v.dtype == np.float64
    assert not v.flags.writeable
    # The cube (±1)^3: vertices on its surface, volume 8, area 24 (NumPy, exact).
    assert np.all(np.isclose(np.abs(v).max(axis=1), 1.0, rtol=0, atol=1e-15))
    assert abs(divergence_volume(v, f) - 8.0) < 1e-9
    assert abs(mesh.volume - 8.0) < 1e-9 and abs(mesh.area - 24.0) < 1e-9
    assert mesh.is_watertight
    np.testing.assert_array_equal(mesh.bounds, [[-1, -1, -1], [1, 1, 1]])
    # Face normals: NumPy's cross products, outward (dot with the centroid > 0).
    a, b, c = (v[f[:, k]] for k in range(3))
    cross = np.cross(b - a, c - a)
    np.testing.assert_allclose(mesh.face_normals,
                               cross / np.linalg.norm(cross, axis=1)[:, None], atol=1e-14)
    assert np.all(np.einsum("ij,ij->i", mesh.face_normals, (a + b + c) / 3) > 0)
    # Vertex normals: unit; a cube corner's is (±1, ±1, ±1)/sqrt(3).
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-14)
    corner = np.where(np.all(np.abs(v) == 1.0, axis=1))[0]
    assert len(corner) == 8
    np.testing.assert_allclose(n[corner], v[corner] / np.sqrt(3), atol=1e-14)
    r = mesh.report
    assert r is not None and r.closed and not r.capped
    assert r.deviation is not None and r.deviation <= 2e-3 * 2


@pytest.mark.parametrize("ext", [".obj", ".stl", ".ply", ".glb"])
def test_cube_files_read_by_trimesh_and_meshio(cli_files, tmp_path, ext):
    cube = geomkit.load(cli_files["cube"])
    mesh = cube.mesh()
    path = tmp_path / f"cube{ext}"
    cube.write(path)
    nv, nf = len(mesh.vertices), len(mesh.faces)
    counts = read_all(path)
    for reader, (v, f) in counts.items():
        assert f == nf, (reader, f, nf)
        if ext == ".obj":  # positions shared (auto normals on a body with edges: none)
            assert v == nv, (reader, v, nv)
    # trimesh: merged (STL stores corners; PLY and glTF split vertices at the creases) it is
    # the Mesh's vertices, watertight, volume 8.
    tm = trimesh.load(path, force="mesh", process=False)
    tm.merge_vertices(merge_tex=True, merge_norm=True)
    assert len(tm.vertices) == nv and len(tm.faces) == nf
    assert tm.is_watertight and tm.is_winding_consistent
    assert abs(tm.volume - 8.0) < (1e-9 if ext in (".obj", ".ply") else 1e-5)
    if ext == ".glb":  # glTF's y up: the z-up body turned, the same box
        np.testing.assert_allclose(tm.bounds, [[-1, -1, -1], [1, 1, 1]], atol=1e-6)


@pytest.mark.parametrize("layout", ["auto", "indexed", "per-vertex", "none"])
def test_obj_normal_layouts(cli_files, tmp_path, layout):
    """Every OBJ layout of `geomkit mesh --obj-normals` reads back in trimesh as the closed
    cube of volume 8; the normals in the file are the layout's."""
    cube = geomkit.load(cli_files["cube"])
    mesh = cube.mesh()
    path = tmp_path / "cube.obj"
    cube.write(path, obj_normals=layout)
    lines = path.read_text().splitlines()
    vn = [ln for ln in lines if ln.startswith("vn ")]
    v = [ln for ln in lines if ln.startswith("v ")]
    if layout in ("auto", "none"):  # a body with sharp edges: no normals under auto
        assert vn == [] and len(v) == len(mesh.vertices)
    elif layout == "indexed":  # positions shared, one vn per distinct normal: the 6 faces'
        assert len(v) == len(mesh.vertices)
        normals = np.array([[float(x) for x in ln.split()[1:]] for ln in vn])
        assert len(np.unique(np.round(normals, 12), axis=0)) == 6
    else:  # one vn per v, vertices split at the edges
        assert len(vn) == len(v) > len(mesh.vertices)
    tm = trimesh.load(path, force="mesh", process=False)
    tm.merge_vertices(merge_tex=True, merge_norm=True)
    assert len(tm.vertices) == len(mesh.vertices) and len(tm.faces) == len(mesh.faces)
    assert tm.is_watertight and abs(tm.volume - 8.0) < 1e-9


def test_box_volume_and_stl_ascii(cli_files, tmp_path):
    box = geomkit.load(cli_files["box"])
    path = tmp_path / "box.stl"
    box.write(path, ascii=True)
    assert path.read_text().startswith("solid")
    tm = trimesh.load(path, force="mesh")  # process=True merges STL's corners
    assert tm.is_watertight
    assert abs(tm.volume - 6.0) < 1e-9  # 1 * 2 * 3
    mesh = box.mesh(samples=5)
    assert abs(divergence_volume(mesh.vertices, mesh.faces) - 6.0) < 1e-12


def test_cone_volume_within_the_tolerance(cli_files):
    """A ruled cone over the unit circle, height 2: the mesh within `tolerance` of the surface,
    so its volume within tolerance x area of the exact (pi r^2 h / 3)."""
    cone = geomkit.load(cli_files["cone"])
    tol = 1e-3
    mesh = cone.mesh(tolerance=tol)
    assert mesh.report is not None and mesh.report.deviation is not None
    assert mesh.report.deviation <= tol
    exact = np.pi * 2 / 3
    area = np.pi * 1 * np.sqrt(1 + 4)  # lateral area: pi r s
    vol = divergence_volume(mesh.vertices, mesh.faces)
    assert abs(abs(vol) - exact) <= tol * (area + np.pi)
    # Vertices on the cone: r = 1 - z/2.
    v = mesh.vertices
    np.testing.assert_allclose(np.hypot(v[:, 0], v[:, 1]), 1 - v[:, 2] / 2, atol=1e-12)


def test_bezier_surface_uniform_samples_are_the_surface(tmp_path):
    s = geomkit.loads(json.dumps(SURFACE))
    mesh = s.mesh(samples=(5, 4))
    assert isinstance(mesh, geomkit.Mesh)
    assert mesh.vertices.shape == (20, 3) and mesh.faces.shape == (2 * 4 * 3, 3)
    assert mesh.report is not None and mesh.report.deviation is None
    ref = bernstein_surface(np.array(SURFACE["net"], float), np.linspace(0, 1, 5),
                            np.linspace(0, 1, 4)).reshape(-1, 3)
    d = np.linalg.norm(mesh.vertices[:, None, :] - ref[None, :, :], axis=2)
    assert np.all(d.min(axis=1) < 1e-14) and np.all(d.min(axis=0) < 1e-14)
    # A smooth surface: one normal per vertex in every file, counts equal everywhere.
    for ext in (".obj", ".stl", ".ply", ".glb"):
        path = tmp_path / f"s{ext}"
        mesh.write(path)
        for reader, (nv, nf) in read_all(path).items():
            assert nf == 24, (ext, reader)
            if ext != ".stl":
                assert nv == 20, (ext, reader, nv)
    # The normals: unit and perpendicular to the surface's tangents (NumPy derivative).
    np.testing.assert_allclose(np.linalg.norm(mesh.normals, axis=1), 1.0, atol=1e-14)


def test_adaptive_surface_deviation_at_its_tolerance():
    s = geomkit.loads(json.dumps(SURFACE))
    coarse, fine = s.mesh(tolerance=1e-2), s.mesh(tolerance=1e-4)
    assert coarse.report.deviation <= 1e-2 and fine.report.deviation <= 1e-4
    assert len(fine.faces) > len(coarse.faces)
    # Default: 1/1000 of the extent per axis.
    default = s.mesh()
    assert default.report.relative_deviation <= 1e-3


def test_mesh_of_arrays_and_pickle(tmp_path):
    v = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
    f = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
    tet = geomkit.Mesh(v, f)
    assert tet.is_watertight and abs(tet.volume - 1 / 6) < 1e-15
    assert tet.report is None
    path = tmp_path / "tet.ply"
    tet.write(path)
    m = meshio.read(path)
    assert len(m.cells[0].data) == 4
    again = pickle.loads(pickle.dumps(tet))
    np.testing.assert_array_equal(again.vertices, tet.vertices)
    np.testing.assert_array_equal(again.faces, tet.faces)
    np.testing.assert_array_equal(again.normals, tet.normals)
    s = geomkit.loads(json.dumps(SURFACE)).mesh(tolerance=1e-3)
    s2 = pickle.loads(pickle.dumps(s))
    np.testing.assert_array_equal(s2.normals, s.normals)
    assert s2.report == s.report
    assert "4 vertices, 4 faces, watertight" in repr(tet)


@pytest.mark.parametrize(
    ("vertices", "faces", "error"),
    [
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 3]], ValueError),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, -1]], ValueError),
        ([[0, 0, np.nan], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], ValueError),
        ([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], ValueError),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1]], ValueError),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0.0, 1.0, 2.0]], TypeError),
        ([["a", "b", "c"]], [[0, 0, 0]], TypeError),
        (np.zeros(3), [[0, 1, 2]], ValueError),
    ],
)
def test_mesh_of_bad_arrays(vertices, faces, error):
    with pytest.raises(error):
        geomkit.Mesh(vertices, faces)


def test_mesh_of_non_contiguous_arrays():
    v = np.asfortranarray(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float))
    f = np.array([[0, 9, 1, 9, 2, 9]])[:, ::2]
    assert not f.flags.c_contiguous
    tri = geomkit.Mesh(v, f)
    np.testing.assert_array_equal(tri.faces, [[0, 1, 2]])


# --- curves --------------------------------------------------------------------------------

def test_curve_polyline_on_the_curve_and_within_tolerance(tmp_path):
    c = geomkit.loads(json.dumps(CURVE))
    pts = np.array(CURVE["points"], float)
    tol = 1e-4
    line = c.mesh(tolerance=tol)
    assert isinstance(line, geomkit.Polyline)
    assert line.dim == 2 and line.points.shape == (len(line), 2)
    t = line.parameters
    assert t[0] == 0 and t[-1] == 1 and np.all(np.diff(t) > 0)
    np.testing.assert_allclose(line.points, bernstein(pts, t), rtol=0, atol=1e-14)
    # The distance from the curve at each segment's quarter points to the segment.
    for q in (0.25, 0.5, 0.75):
        tq = t[:-1] + q * np.diff(t)
        p = bernstein(pts, tq)
        a, b = line.points[:-1], line.points[1:]
        s = np.clip(np.einsum("ij,ij->i", p - a, b - a) / np.einsum("ij,ij->i", b - a, b - a),
                    0, 1)
        dist = np.linalg.norm(p - (a + s[:, None] * (b - a)), axis=1)
        assert dist.max() <= tol
    # Uniform samples: the Bernstein sum at k/(K-1).
    line = c.mesh(samples=7)
    np.testing.assert_allclose(line.parameters, np.linspace(0, 1, 7), rtol=0, atol=1e-15)
    np.testing.assert_allclose(line.points, bernstein(pts, np.linspace(0, 1, 7)), atol=1e-14)
    lifted = np.column_stack([line.points, np.zeros(7)])  # R^2 in the plane z = 0
    c.write(tmp_path / "c.ply", samples=7)
    path3d = trimesh.load(tmp_path / "c.ply")  # vertices and edges (meshio has no edges)
    np.testing.assert_array_equal(path3d.vertices, lifted)
    assert len(path3d.entities) >= 1
    c.write(tmp_path / "c.obj", samples=7)
    np.testing.assert_allclose(meshio.read(tmp_path / "c.obj").points, lifted, atol=1e-15)
    c.write(tmp_path / "c.glb", samples=7)
    gltf, positions = read_glb(tmp_path / "c.glb")
    assert gltf["meshes"][0]["primitives"][0]["mode"] == 3  # LINE_STRIP
    # float32 positions as they are; the node turns z up to glTF's y up (-90 degrees about x).
    np.testing.assert_allclose(positions, lifted, rtol=1e-7)
    np.testing.assert_allclose(gltf["nodes"][0]["rotation"], [-np.sqrt(0.5), 0, 0, np.sqrt(0.5)])
    with pytest.raises(ValueError, match="STL"):
        c.write(tmp_path / "c.stl")
    assert not (tmp_path / "c.stl").exists()
    with pytest.raises(ValueError, match="STL"):
        line.write(tmp_path / "c.stl")


def read_glb(path: Path) -> tuple[dict, np.ndarray]:
    """The JSON chunk and the first accessor's VEC3 float32 positions of a glTF binary
    (the container of the glTF 2.0 spec, read with struct: trimesh skips line primitives)."""
    import struct

    data = path.read_bytes()
    magic, version, total = struct.unpack_from("<4sII", data, 0)
    assert magic == b"glTF" and version == 2 and total == len(data)
    jlen, jtype = struct.unpack_from("<I4s", data, 12)
    assert jtype == b"JSON"
    gltf = json.loads(data[20:20 + jlen])
    blen, btype = struct.unpack_from("<I4s", data, 20 + jlen)
    assert btype == b"BIN\0"
    binary = data[28 + jlen:28 + jlen + blen]
    acc = gltf["accessors"][0]
    view = gltf["bufferViews"][acc["bufferView"]]
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    assert acc["componentType"] == 5126 and acc["type"] == "VEC3"
    pos = np.frombuffer(binary, "<f4", count=3 * acc["count"], offset=start).reshape(-1, 3)
    return gltf, pos.astype(float)


def test_polyline_of_arrays_pickle_and_bad_input(tmp_path):
    line = geomkit.Polyline([[0, 0, 0], [1, 2, 3], [2, 0, 1]], [0, 0.5, 2])
    assert len(line) == 3 and line.dim == 3
    again = pickle.loads(pickle.dumps(line))
    np.testing.assert_array_equal(again.points, line.points)
    np.testing.assert_array_equal(again.parameters, line.parameters)
    c = geomkit.loads(json.dumps(CURVE)).mesh(tolerance=1e-3)
    c2 = pickle.loads(pickle.dumps(c))
    np.testing.assert_array_equal(c2.points, c.points)
    c2.write(tmp_path / "c.obj")
    assert len(meshio.read(tmp_path / "c.obj").points) == len(c)
    for points, params, error in [
        ([[0, 0], [1, 1]], [1, 0], ValueError),  # not increasing
        ([[0, 0], [1, np.inf]], [0, 1], ValueError),
        ([[0, 0], [1, 1]], [0, np.nan], ValueError),
        ([[0, 0], [1, 1]], [0, 1, 2], ValueError),
        ([0, 1], [0, 1], ValueError),  # 1-D points array
        (np.zeros((2, 0)), [0, 1], ValueError),
        ([["a", "b"]], [0], TypeError),
    ]:
        with pytest.raises(error):
            geomkit.Polyline(points, params)


def test_one_dimensional_curve_is_a_graph(cli_files, tmp_path):
    """A one-factor point-calculus model through (0, 1), (1, 3), (2, 2): its polyline passes
    through the three points, written as the graph (t, y(t), 0)."""
    fit = geomkit.load(cli_files["fit1"])
    line = fit.mesh(samples=3)
    assert isinstance(line, geomkit.Polyline) and line.dim == 1
    np.testing.assert_allclose(line.parameters, [0, 1, 2], atol=1e-15)
    np.testing.assert_allclose(line.points[:, 0], [1, 3, 2], atol=1e-14)
    fit.write(tmp_path / "fit.obj", samples=3)
    np.testing.assert_allclose(meshio.read(tmp_path / "fit.obj").points,
                               [[0, 1, 0], [1, 3, 0], [2, 2, 0]], atol=1e-14)


def test_two_factor_model_passes_through_the_experiments(cli_files):
    """A two-factor point-calculus model is the surface (a, b, y(a, b)) through every
    experimental point of its CSV: a 3 x 3 uniform mesh holds the six of them."""
    fit = geomkit.load(cli_files["fit2"])
    mesh = fit.mesh(samples=3)
    assert mesh.vertices.shape == (9, 3)
    experiments = np.loadtxt(cli_files["fit2"].parent / "exp.csv", delimiter=",", skiprows=1)
    d = np.linalg.norm(mesh.vertices[:, None, :] - experiments[None, :, :], axis=2)
    assert np.all(d.min(axis=0) < 1e-14)


def test_four_dimensional_curve_meshes_but_does_not_draw(tmp_path):
    c = geomkit.loads(json.dumps({"type": "bezier_curve",
                                  "points": [[0, 0, 0, 0], [1, 2, 3, 4], [2, 0, 1, 0]]}))
    line = c.mesh(samples=3)
    assert line.dim == 4
    np.testing.assert_allclose(line.points[1], [1, 1, 1.75, 2], atol=1e-15)
    with pytest.raises(ValueError, match="R\\^4"):
        c.svg()
    assert c._repr_svg_() is None and c._repr_png_() is None
    with pytest.raises(ValueError):
        c.render(tmp_path / "c.png")
    assert list(tmp_path.iterdir()) == []


def test_empty_mesh_of_arrays(tmp_path):
    empty = geomkit.Mesh(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64))
    assert empty.vertices.shape == (0, 3) and empty.faces.shape == (0, 3)
    assert empty.area == 0 and not empty.is_watertight
    empty.write(tmp_path / "e.obj")
    assert "0 vertices, 0 triangles" in (tmp_path / "e.obj").read_text()


def test_curve_obj_text(tmp_path):
    c = geomkit.loads(json.dumps(CURVE))
    path = tmp_path / "c.obj"
    c.write(path, samples=3)
    v = [list(map(float, line.split()[1:])) for line in path.read_text().splitlines()
         if line.startswith("v ")]
    np.testing.assert_allclose(np.array(v)[:, :2], bernstein(np.array(CURVE["points"], float),
                                                             np.array([0, 0.5, 1])), atol=1e-15)


# --- pictures ------------------------------------------------------------------------------

def decode_png(data: bytes) -> np.ndarray:
    img = Image.open(io.BytesIO(data))
    img.load()
    return np.asarray(img.convert("RGB"))


def test_png_sizes_and_not_blank(tmp_path):
    s = geomkit.loads(json.dumps(SURFACE))
    px = decode_png(s.png(size=(400, 300)))
    assert px.shape == (300, 400, 3)
    assert (px < 200).any() and (px == 255).all(axis=2).any()  # drawn on white
    assert len(np.unique(px.reshape(-1, 3), axis=0)) > 20  # shaded
    # Default: twice the picture's size (720 x 540).
    assert decode_png(s.png()).shape == (1080, 1440, 3)
    assert decode_png(s.png(scale=0.5)).shape == (270, 360, 3)
    path = tmp_path / "s.png"
    s.render(path, view="60,40", size="320x200")
    assert decode_png(path.read_bytes()).shape == (200, 320, 3)
    # Another view, another picture; no net, another picture.
    assert s.png(size=(200, 150), view=(0, 90)) != s.png(size=(200, 150))
    assert s.png(size=(200, 150), net=False) != s.png(size=(200, 150))


def test_svg_parses_with_title_and_description(tmp_path):
    c = geomkit.loads(json.dumps(CURVE))
    root = ET.fromstring(c.svg(title="Four points"))
    assert root.tag.endswith("svg")
    text = "".join(root.itertext())
    assert "Four points" in text and "Bézier curve of degree 3" in text
    path = tmp_path / "quartic.svg"
    c.render(path)
    assert "quartic" in "".join(ET.parse(path).getroot().itertext())  # default title
    assert "control polygon" in c.svg() and "control polygon" not in c.svg(net=False)


def test_jupyter_prefers_one_picture():
    curve = geomkit.loads(json.dumps(CURVE))
    surface = geomkit.loads(json.dumps(SURFACE))
    assert curve._repr_png_() is None
    svg = curve._repr_svg_()
    assert svg is not None and ET.fromstring(svg).tag.endswith("svg")
    assert surface._repr_svg_() is None
    png = surface._repr_png_()
    assert png is not None and decode_png(png).shape == (360, 480, 3)
    # A model that cannot be drawn shows as text: no picture, no exception.
    three = geomkit.loads(json.dumps(THREE_FACTORS))
    assert three._repr_svg_() is None and three._repr_png_() is None
    with pytest.raises(ValueError, match="3 factors"):
        three.mesh()
    with pytest.raises(ValueError, match="3 factors"):
        three.svg()


# --- bad options: ValueError / TypeError / OSError, never a file -----------------------------

@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"tolerance": float("nan")}, ValueError, "finite"),
        ({"tolerance": 0.0}, ValueError, "> 0"),
        ({"tolerance": -1.0}, ValueError, "> 0"),
        ({"tolerance": "1e-3"}, TypeError, "real number"),
        ({"tolerance": True}, TypeError, "real number"),
        ({"tolerance": 1e-300}, ValueError, "tolerance"),
        ({"samples": 1}, ValueError, "at least 2"),
        ({"samples": (2, 2, 2)}, ValueError, "K or"),
        ({"samples": 2.5}, TypeError, "integer"),
        ({"samples": 10**6}, ValueError, "sample count"),
        ({"samples": (3000, 3000)}, ValueError, "triangles"),
        ({"samples": 10**30}, ValueError, "at least 2"),
        ({"samples": 5, "tolerance": 1e-3}, ValueError, "not both"),
        ({"obj_normals": "smooth"}, ValueError, "obj_normals"),
        ({"ascii": "yes"}, TypeError, "ascii"),
    ],
)
def test_bad_mesh_options_leave_no_file(tmp_path, kwargs, error, match):
    s = geomkit.loads(json.dumps(SURFACE))
    path = tmp_path / "s.obj"
    with pytest.raises(error, match=match):
        s.write(path, **kwargs)
    assert list(tmp_path.iterdir()) == []


def test_unknown_extension_lists_the_formats(tmp_path):
    s = geomkit.loads(json.dumps(SURFACE))
    for name in ("s.off", "s", "s.png"):
        with pytest.raises(ValueError, match=r"\.obj, \.stl, \.ply or \.glb"):
            s.write(tmp_path / name)
    with pytest.raises(ValueError, match=r"\.png or \.svg"):
        s.render(tmp_path / "s.jpg")
    with pytest.raises(ValueError, match=r"\.obj, \.stl, \.ply or \.glb"):
        s.mesh().write(tmp_path / "s.txt")
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(TypeError):
        s.write(b"s.obj")  # type: ignore[arg-type]
    with pytest.raises(TypeError):
        s.write(3)  # type: ignore[arg-type]


def test_written_files_have_the_usual_permissions(tmp_path):
    """Like a plain open(): 0o666 minus the umask (not the temporary file's 0o600)."""
    mask = os.umask(0o022)
    os.umask(mask)
    s = geomkit.loads(json.dumps(SURFACE))
    s.write(tmp_path / "s.obj", samples=3)
    s.render(tmp_path / "s.svg")
    s.save(tmp_path / "s.json")
    for p in tmp_path.iterdir():
        assert p.stat().st_mode & 0o777 == 0o666 & ~mask, p.name


def test_failed_write_keeps_the_old_file(tmp_path):
    """glTF stores float32: a model beyond its range is an error after meshing, and the file
    there before stays as it was, with no temporary left behind."""
    big = geomkit.loads(json.dumps({"type": "bezier_curve",
                                    "points": [[0, 0, 0], [1e300, 1, 0], [2e300, 0, 1]]}))
    path = tmp_path / "big.glb"
    path.write_bytes(b"old")
    with pytest.raises(ValueError, match="f32"):
        big.write(path)
    assert path.read_bytes() == b"old"
    assert [p.name for p in tmp_path.iterdir()] == ["big.glb"]
    with pytest.raises(OSError):
        big.write(tmp_path / "no" / "such" / "dir.obj")
    (tmp_path / "a-directory.obj").mkdir()
    with pytest.raises(OSError):
        big.write(tmp_path / "a-directory.obj")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a-directory.obj", "big.glb"]
    with pytest.raises(OSError):
        big.render(tmp_path / "no" / "dir.svg")


@pytest.mark.parametrize(
    ("kwargs", "error"),
    [
        ({"view": (0, 91)}, ValueError),
        ({"view": (float("inf"), 0)}, ValueError),
        ({"view": "35;25"}, ValueError),
        ({"view": (1, 2, 3)}, TypeError),
        ({"view": ("a", 2)}, TypeError),
        ({"size": (8, 100)}, ValueError),
        ({"size": (100, 10**9)}, ValueError),
        ({"size": (100.0, 100)}, TypeError),
        ({"size": "100by100"}, ValueError),
        ({"net": 1}, TypeError),
        ({"title": 5}, TypeError),
        ({"scale": 0.0}, ValueError),
        ({"scale": float("nan")}, ValueError),
        ({"scale": 100.0}, ValueError),
    ],
)
def test_bad_picture_options(tmp_path, kwargs, error):
    s = geomkit.loads(json.dumps(SURFACE))
    with pytest.raises(error):
        s.render(tmp_path / "s.png", **kwargs)
    assert list(tmp_path.iterdir()) == []


def test_threads_mesh_the_same_bits():
    """The GIL is released while tessellating; one model meshed from 8 threads gives the
    same arrays as one thread."""
    s = geomkit.loads(json.dumps(SURFACE))
    one = s.mesh(tolerance=1e-4)
    with ThreadPoolExecutor(8) as pool:
        many = list(pool.map(lambda _: s.mesh(tolerance=1e-4), range(8)))
    for m in many:
        np.testing.assert_array_equal(m.vertices, one.vertices)
        np.testing.assert_array_equal(m.faces, one.faces)
    with ThreadPoolExecutor(4) as pool:
        pngs = list(pool.map(lambda _: s.png(size=(64, 48)), range(4)))
    assert len(set(pngs)) == 1


def test_docstring_examples():
    import doctest

    from geomkit import _model

    finder, runner = doctest.DocTestFinder(), doctest.DocTestRunner()
    names = [
        _model.Drawable.mesh, _model.Drawable.write, _model.Drawable.svg,
        _model.Drawable.png, _model.Drawable.render, _model.Mesh, _model.Mesh.write,
        _model.Polyline,
    ]
    count = 0
    for obj in names:
        for test in finder.find(obj, obj.__qualname__, globs={}):
            count += len(test.examples)
            runner.run(test)
    assert count >= 10
    assert runner.failures == 0


def test_docs_page_runs(tmp_path, monkeypatch):
    """The Python block of docs/python-meshes.md runs as it stands."""
    text = (ROOT / "docs" / "python-meshes.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert len(blocks) == 1
    monkeypatch.chdir(tmp_path)
    exec(compile(blocks[0], "docs/python-meshes.md", "exec"), {})


def test_public_names():
    for name in ("Mesh", "MeshReport", "Polyline"):
        assert name in geomkit.__all__
        assert getattr(geomkit, name).__doc__
    assert os.fspath  # noqa: B018
