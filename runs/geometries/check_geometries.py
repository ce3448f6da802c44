#!/usr/bin/env python3
"""Meshes the shipped geometries with the gmsh command line program and checks what keller's Gmsh
reader requires of them, without keller:

  - only 9-node quadrilaterals (Gmsh type 10) in 2D and 3-node lines (type 8) in 1D;
  - every element positively oriented: det J > 0 at the 3x3 Gauss points (Gmsh's node order:
    corners counter-clockwise, then the mid-sides of edges 01, 12, 23, 30, then the centre; keller's
    order is the lexicographic 3x3 grid, the same element with the same orientation);
  - the mesh conforming (every edge shared by at most two elements) and every outer edge, with its
    mid-side node, in a 1D element of a physical curve;
  - the area, integrated by 3x3 Gauss on the curved elements, against the exact area of the domain,
    at two or three refinement levels with the observed order of the error;
  - for cylinder.geo, every node against the node keller's built-in `cylinder` problem puts there
    (build_cylinder_mesh's formulas, evaluated here; they reproduce the /mesh/nodes that
    `keller solve` writes for C1, C2, W1 and W2 to 4e-15), for the C and W presets.

Usage: PATH=/usr/bin:$PATH python3 runs/geometries/check_geometries.py [--levels 3] [--keep DIR]
           [--figure docs/figures/geometries.png]
Exit status 1 if a check fails. --figure draws the coarsest mesh of each geometry near its feature.
"""

import argparse
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))

# Gmsh's quad9 node k sits at the logical grid position (a, b) in {0, 1, 2}^2
GMSH_QUAD9 = [(0, 0), (2, 0), (2, 2), (0, 2), (1, 0), (2, 1), (1, 2), (0, 1), (1, 1)]


def run_gmsh(geo, params, out):
    cmd = ["gmsh", "-2", os.path.join(HERE, geo), "-format", "msh41", "-o", out]
    for name, value in params.items():
        cmd += ["-setnumber", name, repr(float(value))]
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0 or "Error" in res.stdout + res.stderr:
        sys.exit(f"gmsh failed on {geo} {params}:\n{res.stdout}{res.stderr}")


def read_msh41(path):
    """The parts of an ASCII .msh 4.1 file the checks need."""
    with open(path) as fh:
        lines = fh.read().split("\n")
    pos = 0

    def section(name):
        nonlocal pos
        while lines[pos] != "$" + name:
            pos += 1
        pos += 1

    section("MeshFormat")
    if not lines[pos].startswith("4.1 0"):
        sys.exit(f"{path}: not an ASCII .msh 4.1 file")
    section("PhysicalNames")
    names = {}
    for _ in range(int(lines[pos])):
        pos += 1
        dim, tag, name = lines[pos].split(maxsplit=2)
        names[(int(dim), int(tag))] = name.strip('"')
    section("Entities")
    counts = [int(v) for v in lines[pos].split()]
    physical = {}  # (dim, entity tag) -> physical tags
    for dim in range(4):
        for _ in range(counts[dim]):
            pos += 1
            v = lines[pos].split()
            n_head = 4 if dim == 0 else 7
            n_phys = int(v[n_head])
            physical[(dim, int(v[0]))] = [int(t) for t in v[n_head + 1 : n_head + 1 + n_phys]]
    section("Nodes")
    n_blocks, n_nodes = [int(v) for v in lines[pos].split()[:2]]
    xy = {}
    for _ in range(n_blocks):
        pos += 1
        n = int(lines[pos].split()[3])
        tags = [int(lines[pos + 1 + k]) for k in range(n)]
        for k in range(n):
            c = lines[pos + 1 + n + k].split()
            xy[tags[k]] = (float(c[0]), float(c[1]))
        pos += 2 * n
    section("Elements")
    n_blocks = int(lines[pos].split()[0])
    blocks = []  # (dim, entity, type, [node tag lists])
    for _ in range(n_blocks):
        pos += 1
        dim, ent, etype, n = [int(v) for v in lines[pos].split()]
        els = [[int(t) for t in lines[pos + 1 + k].split()[1:]] for k in range(n)]
        blocks.append((dim, ent, etype, els))
        pos += n
    return names, physical, xy, blocks


GAUSS = [(-math.sqrt(0.6), 5 / 9), (0.0, 8 / 9), (math.sqrt(0.6), 5 / 9)]


def lagrange(x):
    return [0.5 * x * (x - 1), 1 - x * x, 0.5 * x * (x + 1)], [x - 0.5, -2 * x, x + 0.5]


class Checked:
    def __init__(self):
        self.failures = []

    def expect(self, ok, message):
        if not ok:
            self.failures.append(message)
        return ok


def check_mesh(path, label, chk):
    """Element types, orientation, conformity, boundary coverage; returns (area, #quads, min det J)."""
    names, physical, xy, blocks = read_msh41(path)
    quads, lines = [], []
    for dim, ent, etype, els in blocks:
        if dim == 2:
            chk.expect(physical.get((2, ent)), f"{label}: surface {ent} is in no physical group")
            if chk.expect(etype == 10, f"{label}: surface {ent} has elements of type {etype}, not 10 (9-node quad)"):
                quads += els
        elif dim == 1:
            groups = [names.get((1, t), "?") for t in physical.get((1, ent), [])]
            chk.expect(len(groups) == 1, f"{label}: curve {ent} is in physical groups {groups}, not exactly one")
            if chk.expect(etype == 8, f"{label}: curve {ent} has elements of type {etype}, not 8 (3-node line)"):
                lines += [(tuple(e), groups[0] if groups else None) for e in els]
    if not quads:
        chk.expect(False, f"{label}: no 9-node quadrilaterals")
        return 0.0, 0, 0.0, xy, lines
    # Jacobians and area at the 3x3 Gauss points
    shape = []
    for xi, wx in GAUSS:
        for eta, wy in GAUSS:
            (lx, dx), (ly, dy) = lagrange(xi), lagrange(eta)
            dxi = [dx[a] * ly[b] for a, b in GMSH_QUAD9]
            deta = [lx[a] * dy[b] for a, b in GMSH_QUAD9]
            shape.append((np.array(dxi), np.array(deta), wx * wy))
    area, detmin = 0.0, math.inf
    for e in quads:
        p = np.array([xy[t] for t in e])
        for dxi, deta, w in shape:
            j = (dxi @ p[:, 0]) * (deta @ p[:, 1]) - (deta @ p[:, 0]) * (dxi @ p[:, 1])
            detmin = min(detmin, j)
            area += w * j
    chk.expect(detmin > 0, f"{label}: an element has det J = {detmin:.3e} <= 0 at a Gauss point")
    # conformity and boundary coverage: an edge is its corner pair with its mid-side node
    edges = {}
    for e in quads:
        for k in range(4):
            a, b, m = e[k], e[(k + 1) % 4], e[4 + k]
            edges.setdefault(frozenset((a, b)), []).append(m)
    chk.expect(all(len(ms) <= 2 for ms in edges.values()), f"{label}: an edge is shared by more than two elements")
    chk.expect(all(len(set(ms)) == 1 for ms in edges.values()), f"{label}: neighbours disagree on a mid-side node")
    outer = {k: ms[0] for k, ms in edges.items() if len(ms) == 1}
    covered = {frozenset(ln[:2]): ln[2] for ln, _ in lines}
    missing = [k for k in outer if k not in covered]
    chk.expect(not missing, f"{label}: {len(missing)} outer edges are in no physical curve")
    chk.expect(all(covered[k] == m for k, m in outer.items() if k in covered),
               f"{label}: a boundary line's mid node is not its element edge's")
    chk.expect(all(k in outer for k in covered), f"{label}: a physical curve has lines that are not outer edges")
    return area, len(quads), detmin, xy, lines


# ---- keller's built-in cylinder mesh (problems/cylinder/CylinderProblem.cpp, core/Grading.cpp) ----


def grading(n, ratio, fine_at_start=True):
    q = ratio ** (1.0 / (n - 1)) if n > 1 else 1.0
    h = [q ** (i if fine_at_start else n - 1 - i) for i in range(n)]
    s = np.concatenate([[0.0], np.cumsum(h)])
    return s / s[-1]


def logical(v):  # vertices and midpoints: the 2n+1 logical node positions
    out = np.empty(2 * len(v) - 1)
    out[0::2] = v
    out[1::2] = 0.5 * (v[:-1] + v[1:])
    return out


def keller_cylinder_nodes(p):
    """Every node of build_cylinder_mesh as (x, y, kind), kind 'vertex', 'edge' or 'centre'."""
    f = int(p["f"])
    nq, nr, nxu, nxd = 8 * f, 8 * f, 12 * f, 24 * f
    nw = int(p["rear_per_f"]) * f
    lu, ld = p["upstream_length"], p["downstream_length"]
    qn = p["wake_ratio"] ** (nw / (nw - 1)) if nw > 1 else 1.0
    qr = p["rear_ratio"] ** (nw / (nw - 1)) if nw > 1 else 1.0

    def uniform_in(v):
        xi = math.log1p(v * (qn - 1)) / math.log(qn) if qn > 1 else v
        return math.expm1(xi * math.log(qr)) / (qr - 1) if qr > 1 else xi

    def arc(t):
        return np.array([math.cos(t), math.sin(t)])

    def blend(a, b, t):
        return (1 - t) * a + t * np.asarray(b)

    uniform = lambda n: grading(n, 1.0)  # noqa: E731
    blocks = [
        (grading(nxu, p["upstream_ratio"], False), uniform(nq),
         lambda u, v: np.array([-lu + (lu - 2) * u, 2 * v])),
        (uniform(nq), grading(nr, p["radial_ratio"]),
         lambda u, t: blend(arc(math.pi - 0.25 * math.pi * u), (-2, 2 * u), t)),
        (uniform(2 * nq), grading(nr, p["radial_ratio"]),
         lambda u, t: blend(arc(0.75 * math.pi - 0.5 * math.pi * u), (-2 + 4 * u, 2), t)),
        (grading(nr, p["radial_ratio"]), grading(nw, p["wake_ratio"]),
         lambda r, v: blend(arc(0.25 * math.pi * uniform_in(v)), (2, 2 * v), r)),
        (grading(nxd, p["downstream_ratio"]), grading(nw, p["wake_ratio"]),
         lambda u, v: np.array([2 + (ld - 2) * u, 2 * v])),
    ]
    out = []
    for sv, tv, m in blocks:
        ls, lt = logical(sv), logical(tv)
        for j, t in enumerate(lt):
            for i, s in enumerate(ls):
                kind = ["vertex", "edge", "centre"][(i % 2) + (j % 2)]
                x, y = m(s, t)
                out.append((x, y, kind))
    return out


def compare_cylinder(xy, p):
    """Largest distance from each kind of keller node to the nearest Gmsh node."""
    cell = 0.05
    buckets = {}
    for x, y in xy.values():
        buckets.setdefault((math.floor(x / cell), math.floor(y / cell)), []).append((x, y))
    worst = {}
    for x, y, kind in keller_cylinder_nodes(p):
        i, j = math.floor(x / cell), math.floor(y / cell)
        near = [q for di in (-1, 0, 1) for dj in (-1, 0, 1) for q in buckets.get((i + di, j + dj), [])]
        d = min(math.hypot(qx - x, qy - y) for qx, qy in near) if near else math.inf
        worst[kind] = max(worst.get(kind, 0.0), d)
    return worst


# ---- the geometries: parameters of each level and the exact area ----


def cylinder_area(p):
    return 2.0 * (p["upstream_length"] + p["downstream_length"]) - 0.5 * math.pi


def contraction_area(p):
    return 4.0 * p["upstream_length"] + 1.0 * p["downstream_length"]


def stenosis_area(p):
    # the bump 1 - h(x), h = severity (1 - (2x / length)^2)^3, removes severity * length * 16 / 35;
    # full = 1 is the whole channel, twice the upper half
    half = p["upstream_length"] + p["downstream_length"] - p["severity"] * p["length"] * 16.0 / 35.0
    return 2.0 * half if p.get("full", 0) == 1 else half


CYLINDER = {"f": 1, "rear_per_f": 8, "upstream_length": 20, "downstream_length": 30, "radial_ratio": 4,
            "upstream_ratio": 10, "downstream_ratio": 20, "wake_ratio": 1, "rear_ratio": 1}
CYLINDER_W = dict(CYLINDER, rear_per_f=16, wake_ratio=20, rear_ratio=4)
CONTRACTION = {"f": 1, "upstream_length": 80, "downstream_length": 50, "corner": 0.04, "nx_upstream": 30,
               "nx_downstream": 30, "ny_lower": 8, "ny_step": 8}
STENOSIS = {"f": 1, "severity": 0.5, "length": 4, "upstream_length": 10, "downstream_length": 20, "n_throat": 8,
            "nx_upstream": 10, "nx_downstream": 16, "ny": 6, "wall_ratio": 1}

CYLINDER_GROUPS = {"fluid", "inflow", "outflow", "wall", "symmetry", "cylinder"}
GEOMETRIES = [  # label, file, parameters, levels of f, exact area, curved boundary, physical groups
    ("cylinder.geo (C<f>)", "cylinder.geo", CYLINDER, [1, 2, 3], cylinder_area, True, CYLINDER_GROUPS),
    ("cylinder.geo (W<f>)", "cylinder.geo", CYLINDER_W, [1, 2, 3], cylinder_area, True, CYLINDER_GROUPS),
    ("contraction.geo", "contraction.geo", CONTRACTION, [1, 2, 4], contraction_area, False,
     {"fluid", "inflow", "outflow", "symmetry", "upstream_wall", "step", "downstream_wall"}),
    ("stenosis.geo", "stenosis.geo", STENOSIS, [1, 2, 4], stenosis_area, True,
     {"fluid", "inflow", "outflow", "symmetry", "upstream_wall", "stenosis", "downstream_wall"}),
    ("stenosis.geo (full)", "stenosis.geo", dict(STENOSIS, full=1), [1, 2, 4], stenosis_area, True,
     {"fluid", "inflow", "outflow", "upstream_wall", "stenosis", "downstream_wall", "lower_upstream_wall",
      "lower_stenosis", "lower_downstream_wall"}),
]

# Tolerances. The area of a domain with straight sides is exact up to rounding (relative 1e-12).
# Quadratic isoparametric edges interpolate a smooth boundary to O(h^3) pointwise, an error whose
# integral over an edge is O(h^5) (it changes sign along the edge), so the area error is O(h^4);
# the observed order between two levels must be at least 3.5. Keller's cylinder nodes: Gmsh places
# the vertices of a graded curve by integrating its size function numerically, to about 1e-7 on
# the long channel sides (3e-9 around the cylinder), so the C meshes must agree within 1e-6 and
# the W meshes' vertices too; the W meshes' mid-side nodes differ by O(h^2) (straight interior
# edges of the east block against keller's curved ones): observed order at least 1.8.
STRAIGHT_AREA_REL = 1e-12
MIN_AREA_ORDER = 3.5
NODE_TOL = 1e-6
MIN_MIDSIDE_ORDER = 1.8


FIGURE_VIEWS = {  # geometry label -> (title, x range, y range) of its panel
    "cylinder.geo (C<f>)": ("confined cylinder, mesh C1 (f = 1)", (-4.5, 7.5), (0, 2)),
    "contraction.geo": ("4:1 contraction, mesh M1 (f = 1)", (-6.5, 5.5), (0, 4)),
    "stenosis.geo": ("stenosis, f = 1", (-5, 8), (0, 1)),
}


def draw(meshes, path):
    """The element edges (curved through their mid-side nodes) of each mesh in FIGURE_VIEWS."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    t = np.linspace(0.0, 1.0, 9)
    la, lm, lb = (1 - t) * (1 - 2 * t), 4 * t * (1 - t), t * (2 * t - 1)
    spans = [(FIGURE_VIEWS[label][1], FIGURE_VIEWS[label][2]) for label, _ in meshes]
    ratios = [(yr[1] - yr[0]) / (xr[1] - xr[0]) for xr, yr in spans]
    fig, axes = plt.subplots(len(meshes), 1, figsize=(9, 1.2 + 9 * sum(ratios)), constrained_layout=True,
                             gridspec_kw={"height_ratios": ratios})
    for ax, (label, mesh) in zip(np.atleast_1d(axes), meshes):
        title, xr, yr = FIGURE_VIEWS[label]
        _, _, xy, blocks = read_msh41(mesh)
        segs = []
        for e in (e for dim, _, _, els in blocks if dim == 2 for e in els):
            for k in range(4):
                a, m, b = (np.array(xy[n]) for n in (e[k], e[4 + k], e[(k + 1) % 4]))
                segs.append(np.outer(la, a) + np.outer(lm, m) + np.outer(lb, b))
        ax.add_collection(LineCollection(segs, linewidths=0.4, colors="k"))
        ax.set_xlim(*xr)
        ax.set_ylim(*yr)
        ax.set_aspect("equal")
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("x", fontsize=9)
        ax.set_ylabel("y", fontsize=9)
    fig.savefig(path, dpi=150)


def observed_order(previous, level, err):
    if previous is None or not (previous[1] > 0 and err > 0):
        return None
    return math.log(previous[1] / err) / math.log(level / previous[0])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--levels", type=int, default=3, choices=(2, 3), help="refinement levels per geometry")
    ap.add_argument("--keep", help="write the meshes into this folder instead of a temporary one")
    ap.add_argument("--figure", help="draw the coarsest meshes into this PNG (matplotlib)")
    args = ap.parse_args()
    coarsest = []
    chk = Checked()
    with tempfile.TemporaryDirectory() as tmp:
        folder = args.keep or tmp
        os.makedirs(folder, exist_ok=True)
        print(f"{'geometry':20} {'f':>2} {'quads':>6} {'min det J':>10} {'area error':>11} {'order':>6}"
              "   node offset from keller: vertex / mid-side / centre")
        for label, geo, base, levels, exact, curved, groups in GEOMETRIES:
            previous = previous_mid = None
            for level in levels[: args.levels]:
                p = dict(base, f=level)
                tag = label.split("(")[-1][0] if "(" in label else ""
                out = os.path.join(folder, f"{os.path.splitext(geo)[0]}{tag}_f{level}.msh")
                run_gmsh(geo, p, out)
                if level == levels[0] and label in FIGURE_VIEWS:
                    coarsest.append((label, out))
                name = f"{label} f={level}"
                area, nq, detmin, xy, lines = check_mesh(out, name, chk)
                names = set(read_msh41(out)[0].values())
                chk.expect(names == groups, f"{name}: physical groups {sorted(names)}, expected {sorted(groups)}")
                err = abs(area - exact(p))
                order = observed_order(previous, level, err) if curved else None
                if curved:
                    if order is not None:
                        chk.expect(order >= MIN_AREA_ORDER, f"{name}: area error order {order:.2f} < {MIN_AREA_ORDER}")
                else:
                    chk.expect(err <= STRAIGHT_AREA_REL * exact(p), f"{name}: area off by {err:.3e} (straight sides)")
                extra = ""
                if geo == "cylinder.geo":
                    w = compare_cylinder(xy, p)
                    extra = f"{w['vertex']:.1e} / {w['edge']:.1e} / {w['centre']:.1e}"
                    chk.expect(w["vertex"] <= NODE_TOL, f"{name}: a vertex is {w['vertex']:.2e} from keller's")
                    if base["wake_ratio"] == 1 and base["rear_ratio"] == 1:
                        worst = max(w.values())
                        chk.expect(worst <= NODE_TOL, f"{name}: a node is {worst:.2e} from keller's")
                    else:
                        mid_order = observed_order(previous_mid, level, w["edge"])
                        if mid_order is not None:
                            chk.expect(mid_order >= MIN_MIDSIDE_ORDER,
                                       f"{name}: mid-side offsets fall at order {mid_order:.2f} < {MIN_MIDSIDE_ORDER}")
                        previous_mid = (level, w["edge"])
                shown = f"{order:6.2f}" if order is not None else ("exact" if not curved else "")
                print(f"{label:20} {level:2} {nq:6} {detmin:10.3e} {err:11.3e} {shown:>6}   {extra}")
                previous = (level, err)
        if args.figure:
            draw(coarsest, args.figure)
    for f in chk.failures:
        print("FAILED:", f)
    if not chk.failures:
        print("all checks passed")
    sys.exit(1 if chk.failures else 0)


if __name__ == "__main__":
    main()
