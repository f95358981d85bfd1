"""Reads geomkit's meshes with trimesh (an independent implementation) and checks them.

Usage: python bench/compat_mesh.py PATH/TO/geomkit

Runs `geomkit demo` into a temporary folder (its gallery writes every body as GLB, OBJ and
STL), meshes the Fig. 3 mushroom (a closed Bézier body) into all five formats with
`geomkit mesh`, and checks with trimesh: face counts equal in every format, vertex counts
equal after trimesh merges coincident vertices, watertight and winding-consistent, volumes
equal to the exact ones (cube 8, pyramid 8/3, the inscribed 128-gon cone and cylinder) and
the same in every format. Prints a Markdown table; exit code 1 on any failure.
"""

import math
import subprocess
import sys
import tempfile
from pathlib import Path

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
            checks = {
                "watertight": m.is_watertight,
                "winding": m.is_winding_consistent,
                "counts": (len(m.vertices), len(m.faces)) == ref[:2],
                # f32 formats (STL, glTF) round the coordinates.
                "volume": abs(m.volume - (volume if volume is not None else ref[2]))
                <= 1e-5 * abs(ref[2]),
            }
            ok = all(checks.values())
            failures += not ok
            expected = f"{volume:.10g}" if volume is not None else f"= {ref[2]:.10g}"
            rows.append(
                f"| {name} | {ext} | {len(m.vertices)} | {len(m.faces)} | {m.is_watertight} "
                f"| {m.is_winding_consistent} | {m.volume:.10g} | {expected} | "
                f"{'pass' if ok else 'FAIL ' + ', '.join(k for k, v in checks.items() if not v)} |"
            )
    print(f"trimesh {trimesh.__version__} reading geomkit's meshes\n")
    print("| mesh | format | vertices | faces | watertight | winding | volume | expected | result |")
    print("|---|---|---:|---:|---|---|---:|---:|---|")
    print("\n".join(rows))
    print(f"\n{len(rows) - failures} of {len(rows)} passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
