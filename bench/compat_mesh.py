"""Reads geomkit's meshes with independent readers (trimesh, meshio, manifold3d) and checks
them.

Usage: python bench/compat_mesh.py PATH/TO/geomkit

Runs `geomkit demo` into a temporary folder (its gallery writes every body as GLB, OBJ and
STL), meshes the Fig. 3 mushroom (a closed Bézier body) into all five formats with
`geomkit mesh`, and checks with trimesh: face counts equal in every format, vertex counts
equal after trimesh merges coincident vertices, watertight and winding-consistent, volumes
equal to the exact ones (cube 8, pyramid 8/3, the inscribed 128-gon cone and cylinder) and
the same in every format; manifold3d accepts each as a manifold of the same volume.

Every OBJ is also read with meshio (5.x takes the k-th `vn` as the normal of the k-th `v`
and refuses a file whose counts differ): it must read it, and the faces must close by index
alone (no merging) where the body is closed. A second table shows the three layouts of
`--obj-normals` on the cube: the default (auto) and none are read by meshio and closed,
indexed is refused by meshio (sharp normals for trimesh, Blender, OCCT), per-vertex is read
by meshio but closes only after merging coincident vertices.
Prints Markdown tables; exit code 1 on any failure.
"""

import math
import subprocess
import sys
import tempfile
from pathlib import Path

import manifold3d
import meshio
import numpy as np
import trimesh


def ngon_area(n, r):
    return n / 2 * r * r * math.sin(2 * math.pi / n)


BODIES = {
    "cube": 8.0,
    "pyramid": 8.0 / 3.0,
    "cone": ngon_area(128, 1.0) * 2.0 / 3.0,
    "cylinder": ngon_area(128, 1.0) * 2.0,
}


def load(path):
    # force="mesh" flattens a glTF scene (applying its z-up rotation) into one mesh.
    m = trimesh.load(path, force="mesh", process=True)
    m.merge_vertices(merge_tex=True, merge_norm=True)
    return m


def closed_by_index(faces):
    """Every directed edge once and its reverse once, by vertex index alone."""
    edges = {}
    for a, b, c in np.asarray(faces).tolist():
        for e in ((a, b), (b, c), (c, a)):
            edges[e] = edges.get(e, 0) + 1
    return bool(edges) and all(n == 1 and edges.get((b, a)) == 1 for (a, b), n in edges.items())


def meshio_check(path):
    """(read, faces, closed by index, vn per v) of meshio reading an OBJ, or the error."""
    try:
        m = meshio.read(path)
    except Exception as e:  # meshio raises ValueError for vn/v count mismatches
        return False, 0, False, f"refused: {str(e).splitlines()[0][:60]}"
    tris = np.concatenate([c.data for c in m.cells if c.type == "triangle"])
    vn = m.point_data.get("obj:vn")
    return True, len(tris), closed_by_index(tris), "none" if vn is None else f"{len(vn)} for {len(m.points)}"


def manifold_volume(m):
    """The volume manifold3d gives the merged mesh, or None if it is not a manifold."""
    mesh = manifold3d.Mesh(
        vert_properties=np.asarray(m.vertices, dtype=np.float32),
        tri_verts=np.asarray(m.faces, dtype=np.uint32),
    )
    solid = manifold3d.Manifold(mesh)
    if solid.status() != manifold3d.Error.NoError:
        return None
    return solid.volume()


def main():
    geomkit = sys.argv[1]
    rows = []
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        subprocess.run([geomkit, "demo", "--out", str(tmp)], check=True, stdout=subprocess.DEVNULL)
        cases = []
        for name, volume in BODIES.items():
            for ext in ["glb", "obj", "stl"]:
                cases.append((name, ext, tmp / f"gallery-{name}.{ext}", volume))
        for ext in ["obj", "stl", "ply", "glb"]:
            out = tmp / f"mushroom.{ext}"
            subprocess.run(
                [geomkit, "mesh", str(tmp / "fig3-mushroom.json"), "-o", str(out), "--samples", "97x121"],
                check=True,
                stderr=subprocess.DEVNULL,
            )
            cases.append(("mushroom", ext, out, None))
        stl_ascii = tmp / "mushroom-ascii.stl"
        subprocess.run(
            [geomkit, "mesh", str(tmp / "fig3-mushroom.json"), "-o", str(stl_ascii), "--samples", "97x121", "--ascii"],
            check=True,
            stderr=subprocess.DEVNULL,
        )
        cases.append(("mushroom", "stl (ascii)", stl_ascii, None))

        reference = {}
        for name, ext, path, volume in cases:
            m = load(path)
            ref = reference.setdefault(name, (len(m.vertices), len(m.faces), m.volume))
            mv = manifold_volume(m)
            checks = {
                "watertight": m.is_watertight,
                "winding": m.is_winding_consistent,
                "counts": (len(m.vertices), len(m.faces)) == ref[:2],
                # f32 formats (STL, glTF) round the coordinates.
                "volume": abs(m.volume - (volume if volume is not None else ref[2]))
                <= 1e-5 * abs(ref[2]),
                "manifold3d": mv is not None and abs(mv - ref[2]) <= 1e-5 * abs(ref[2]),
            }
            meshio_cell = "-"
            if ext == "obj":
                read, faces, closed, vn = meshio_check(path)
                checks["meshio"] = read and faces == len(m.faces) and closed
                meshio_cell = f"read, {'closed' if closed else 'OPEN'}, vn {vn}" if read else vn
            ok = all(checks.values())
            failures += not ok
            expected = f"{volume:.10g}" if volume is not None else f"= {ref[2]:.10g}"
            rows.append(
                f"| {name} | {ext} | {len(m.vertices)} | {len(m.faces)} | {m.is_watertight} "
                f"| {m.is_winding_consistent} | {m.volume:.10g} | {expected} | "
                f"{'-' if mv is None else f'{mv:.8g}'} | {meshio_cell} | "
                f"{'pass' if ok else 'FAIL ' + ', '.join(k for k, v in checks.items() if not v)} |"
            )

        # The --obj-normals layouts of a body with sharp edges, read by meshio and trimesh.
        layouts = []
        expect = {
            "auto": (True, True),
            "none": (True, True),
            "indexed": (False, None),
            "per-vertex": (True, False),
        }
        for layout, (meshio_reads, meshio_closed) in expect.items():
            out = tmp / f"cube-{layout}.obj"
            subprocess.run(
                [geomkit, "compose", "body", "cube", "-o", str(out), "--obj-normals", layout],
                check=True,
                stderr=subprocess.DEVNULL,
            )
            read, faces, closed, vn = meshio_check(out)
            m = load(out)
            ok = read == meshio_reads and (not read or closed == meshio_closed) and m.is_watertight
            failures += not ok
            layouts.append(
                f"| {layout} | {('read, ' + ('closed' if closed else 'not closed by index') + f', vn {vn}') if read else vn} "
                f"| {m.is_watertight} | {'pass' if ok else 'FAIL'} |"
            )
    print(
        f"trimesh {trimesh.__version__}, meshio {meshio.__version__}, "
        f"manifold3d {getattr(manifold3d, '__version__', '3.5.4')} reading geomkit's meshes\n"
    )
    print(
        "| mesh | format | vertices | faces | watertight | winding | volume | expected "
        "| manifold3d volume | meshio (OBJ) | result |"
    )
    print("|---|---|---:|---:|---|---|---:|---:|---:|---|---|")
    print("\n".join(rows))
    print("\n`compose body cube -o cube.obj --obj-normals LAYOUT`:\n")
    print("| layout | meshio | trimesh watertight (merged) | result |")
    print("|---|---|---|---|")
    print("\n".join(layouts))
    total = len(rows) + len(layouts)
    print(f"\n{total - failures} of {total} passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
