"""Writes this case's blockMeshDict (``python3 make_case.py mesh``) and, once blockMesh has run,
the parabolic inflow of ``0/U`` (``python3 make_case.py inflow``).

The Schaefer-Turek 2D-1 channel: [0, 2.2] x [0, 0.41] m, a cylinder of diameter 0.1 m centred at
(0.2, 0.2), mean inflow 0.2 m/s, nu = 1e-3 m^2/s (Re = 20). An O-grid of four blocks rings the
cylinder inside the square [0.1, 0.3]^2; eight rectangular blocks fill the rest of the channel.
The mesh is one cell, DEPTH_M, thick with empty front and back patches (a 2D flow).
"""

import gzip
import math
import re
import sys
from pathlib import Path

DEPTH_M = 0.01
CENTRE = (0.2, 0.2)
RADIUS_M = 0.05
N_AROUND = 20  # cells along each quarter of the cylinder and each side of the square
N_RADIAL = 16  # cells from the cylinder to the square, graded toward the cylinder
RADIAL_GRADING = 4.0
XS, YS = (0.0, 0.1, 0.3, 2.2), (0.0, 0.1, 0.3, 0.41)
NX, NY = (10, N_AROUND, 60), (10, N_AROUND, 11)
X_GRADING = (1.0, 1.0, 5.0)
U_MAX = 0.3


def mesh_dict() -> str:
    points: list[tuple[float, float]] = [(x, y) for y in YS for x in XS]
    square = {}
    for i in (1, 2):
        for j in (1, 2):
            square[(i, j)] = j * 4 + i
    circle = []
    for k in range(4):
        a = math.radians(-45 + 90 * k)
        circle.append(len(points))
        points.append((CENTRE[0] + RADIUS_M * math.cos(a), CENTRE[1] + RADIUS_M * math.sin(a)))
    n = len(points)
    corners = [square[(2, 1)], square[(2, 2)], square[(1, 2)], square[(1, 1)]]  # SE NE NW SW
    blocks, edges, faces = [], [], {"cylinder": [], "inlet": [], "outlet": [], "walls": []}
    for k in range(4):
        c0, c1 = circle[k], circle[(k + 1) % 4]
        s0, s1 = corners[k], corners[(k + 1) % 4]
        blocks.append(
            ((c0, s0, s1, c1), (N_RADIAL, N_AROUND), f"simpleGrading ({RADIAL_GRADING} 1 1)")
        )
        a = math.radians(90 * k)
        mid = (CENTRE[0] + RADIUS_M * math.cos(a), CENTRE[1] + RADIUS_M * math.sin(a))
        for off, z in ((0, 0.0), (n, DEPTH_M)):
            edges.append(f"    arc {c0 + off} {c1 + off} ({mid[0]:.10g} {mid[1]:.10g} {z:g})")
        faces["cylinder"].append((c1, c0, c0 + n, c1 + n))
    for i in range(3):
        for j in range(3):
            if i == 1 and j == 1:
                continue
            v = (j * 4 + i, j * 4 + i + 1, (j + 1) * 4 + i + 1, (j + 1) * 4 + i)
            blocks.append((v, (NX[i], NY[j]), f"simpleGrading ({X_GRADING[i]} 1 1)"))
            if i == 0:
                faces["inlet"].append((v[3], v[0], v[0] + n, v[3] + n))
            if i == 2:
                faces["outlet"].append((v[1], v[2], v[2] + n, v[1] + n))
            if j == 0:
                faces["walls"].append((v[0], v[1], v[1] + n, v[0] + n))
            if j == 2:
                faces["walls"].append((v[2], v[3], v[3] + n, v[2] + n))
    out = [
        HEADER.format(cls="dictionary", obj="blockMeshDict"),
        "convertToMeters 1;",
        "vertices",
        "(",
    ]
    out += [f"    ({x:.10g} {y:.10g} 0)" for x, y in points]
    out += [f"    ({x:.10g} {y:.10g} {DEPTH_M:g})" for x, y in points]
    out += [");", "blocks", "("]
    for v, (a, b), grading in blocks:
        ids = " ".join(str(x) for x in (*v, *(w + n for w in v)))
        out.append(f"    hex ({ids}) ({a} {b} 1) {grading}")
    out += [");", "edges", "(", *edges, ");", "boundary", "("]
    kinds = {"cylinder": "wall", "inlet": "patch", "outlet": "patch", "walls": "wall"}
    for name, quads in faces.items():
        out += [
            f"    {name}",
            "    {",
            f"        type {kinds[name]};",
            "        faces",
            "        (",
        ]
        out += [f"            ({' '.join(map(str, q))})" for q in quads]
        out += ["        );", "    }"]
    front = [tuple(b[0]) for b in blocks]
    out += ["    frontAndBack", "    {", "        type empty;", "        faces", "        ("]
    for v in front:
        out.append(f"            ({v[0]} {v[3]} {v[2]} {v[1]})")
        out.append(f"            ({v[0] + n} {v[1] + n} {v[2] + n} {v[3] + n})")
    out += ["        );", "    }", ");", ""]
    return "\n".join(out)


def _read(path: Path) -> str:
    gz = path.with_name(path.name + ".gz")
    if gz.exists():
        return gzip.decompress(gz.read_bytes()).decode()
    return path.read_text()


def _list_body(text: str) -> str:
    body = text.split("FoamFile", 1)[1].split("}", 1)[1]
    return body[body.index("(") + 1 : body.rindex(")")]


def inflow() -> None:
    mesh = Path("constant/polyMesh")
    pts = [
        tuple(float(v) for v in m.split())
        for m in re.findall(r"\(([^()]*)\)", _list_body(_read(mesh / "points")))
    ]
    faces = [
        [int(v) for v in m.split()]
        for m in re.findall(r"\d+\(([^()]*)\)", _list_body(_read(mesh / "faces")))
    ]
    boundary = _read(mesh / "boundary")
    block = boundary.split("inlet", 1)[1]
    count = int(re.search(r"nFaces\s+(\d+)", block).group(1))
    start = int(re.search(r"startFace\s+(\d+)", block).group(1))
    values = []
    for face in faces[start : start + count]:
        y = sum(pts[p][1] for p in face) / len(face)
        values.append(f"({4 * U_MAX * y * (0.41 - y) / 0.41**2:.10g} 0 0)")
    u = Path("0/U").read_text()
    listed = f"nonuniform List<vector> {count} (\n" + "\n".join(values) + "\n)"
    Path("0/U").write_text(re.sub(r"INLET_PROFILE", listed, u))


HEADER = """FoamFile
{{
    version     2.0;
    format      ascii;
    class       {cls};
    object      {obj};
}}
"""

if __name__ == "__main__":
    if sys.argv[1:] == ["mesh"]:
        Path("system/blockMeshDict").write_text(mesh_dict())
    elif sys.argv[1:] == ["inflow"]:
        inflow()
    else:
        raise SystemExit("usage: python3 make_case.py mesh|inflow")
