"""The mesh and one flow field of a `flow` run (or any run on a mesh of 9-node quadrilaterals),
from the file keller wrote: a branch (`keller trace`, one of its stored solutions) or a steady
state (`keller solve`).

Top panel: the mesh, element edges drawn through their mid-side nodes, every named boundary in its
own colour with its name and its condition from the scene stored in the file. Bottom panel: the
speed |v| (or --colour) in colour and the streamlines as contours of the stream function psi
(v_x = dpsi/dy, v_y = -dpsi/dx; psi = 0 on a wall, --psi-zero), the main flow in black at equal
steps of psi and any recirculation (psi of the other sign) in white at fractions of its extremum, those beyond
psi's spread along the walls (the discrete velocity is a curl only to the discretisation error).

psi is computed here as keller's `stream-function` observable computes it: the Q2 least-squares
solution of grad psi = (-v_y, v_x) over the fluid (3 x 3 Gauss points per element), with its
mean over the nodes of that wall set to 0 (keller's `boundary`).

    python3 -m keller.plot flow RUN.h5 [--row N|last] [--xlim X0 X1] [--ylim Y0 Y1]
        [--psi-zero BOUNDARY] [--levels N] [--colour FIELD:COMPONENT [--log]] [--title TEXT]
        [--mesh-only | --flow-only] -o FIG.png

The shipped geometries' figures (docs/geometries.md) are made by it; it prints the flow rate q
between psi = 0 and the far side, the extremum of psi of the other sign (a recirculation's
intensity, in units of q) and how far psi is from constant along the walls."""

import argparse
import sys

import numpy as np
import matplotlib.pyplot as plt
import matplotlib.ticker
import matplotlib.tri as mtri
from matplotlib.collections import LineCollection

import keller.results
from keller.outputs import OutputError, check_outputs, save_figure

# the three nodes of edge k (0 bottom, 1 right, 2 top, 3 left) of the lexicographic 3 x 3 element
# (node i + 3 j at reference (s_i, t_j)), in the counter-clockwise order of the element
EDGE_NODES = {0: (0, 1, 2), 1: (2, 5, 8), 2: (8, 7, 6), 3: (6, 3, 0)}
# the element's outline, counter-clockwise, as four quadratic edges
OUTLINE = [EDGE_NODES[k] for k in range(4)]


class PlotError(Exception):
    pass


def read_run(path, row):
    """(nodes, elements, element groups, group names, boundaries {name: (E, 2) element, edge},
    scene dict, velocity (N x 2), nodal fields {name: (values, components)}, parameter values)
    of the stored solution `row` of a branch, or of the steady state of a solve; the nodes at
    the state's positions where it has a `position` field."""
    run = keller.results.open(path)
    if isinstance(run, keller.results.Branch):
        stored = [s for s in run.solutions if s.fields]
        if not stored:
            raise PlotError(f"'{path}': the branch has no stored fields (run `keller export {path} --xdmf`)")
        rows = [s.row for s in stored]
        if row == "last":
            state = stored[-1]
        else:
            try:
                state = stored[rows.index(int(row))]
            except ValueError:
                raise PlotError(f"'{path}': no stored solution at row {row}; stored rows: "
                                + ", ".join(map(str, rows))) from None
        # the branch's parameter at this point, and the others (fixed along the branch)
        values = {run.parameter: state.value}
        values.update({k: float(v) for k, v in run.parameters.items() if k != run.parameter})
    elif isinstance(run, keller.results.Solution):
        if row not in ("last", "0", 0):
            raise PlotError(f"'{path}' holds one steady state (keller solve): --row does not apply")
        state = run
        values = {k: float(v) for k, v in run.parameters.items()}
    else:
        raise PlotError(f"'{path}' holds neither a branch's stored solutions nor a steady state")
    mesh = state.mesh
    if mesh is None:
        raise PlotError(f"'{path}' has no mesh (/mesh): not a run on a 2D mesh")
    if "velocity" not in state.fields:
        raise PlotError(f"'{path}': the stored solution has no velocity field")
    # the nodal fields (Q2, and Q1 given at every node): name -> (values, components)
    nodal = {name: (np.asarray(f), f.components) for name, f in state.fields.items() if f.basis in ("Q2", "Q1")}
    return (mesh.nodes, mesh.elements, mesh.element_group, mesh.group_names, mesh.boundaries, run.scene,
            np.asarray(state.fields["velocity"]), nodal, values)


def fluid_elements(elements, groups, names):
    if "fluid" in names:
        return elements[groups == names.index("fluid")]
    return elements


def quadratic_edge(xy, n=9):
    """Points along the quadratic curve through three nodes (rows of xy)."""
    t = np.linspace(0.0, 1.0, n)
    la, lm, lb = (1 - t) * (1 - 2 * t), 4 * t * (1 - t), t * (2 * t - 1)
    return np.outer(la, xy[0]) + np.outer(lm, xy[1]) + np.outer(lb, xy[2])


def q2_shape(s, t):
    """Lexicographic Q2 shape functions and their s, t derivatives at the points (s, t)."""
    def q(x):
        return np.stack([0.5 * x * (x - 1), 1 - x * x, 0.5 * x * (x + 1)])

    def dq(x):
        return np.stack([x - 0.5, -2 * x, x + 0.5])

    N = np.stack([q(s)[i] * q(t)[j] for j in range(3) for i in range(3)], axis=-1)
    Ns = np.stack([dq(s)[i] * q(t)[j] for j in range(3) for i in range(3)], axis=-1)
    Nt = np.stack([q(s)[i] * dq(t)[j] for j in range(3) for i in range(3)], axis=-1)
    return N, Ns, Nt


def stream_function(nodes, fluid, velocity):
    """Q2 least-squares psi: min int |grad psi - (-v_y, v_x)|^2 over the fluid elements, up to a
    constant (NaN at nodes of no fluid element)."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    g = np.sqrt(0.6) * np.array([-1.0, 0.0, 1.0])
    w1 = np.array([5.0, 8.0, 5.0]) / 9.0
    S, T = np.meshgrid(g, g, indexing="xy")
    W = np.outer(w1, w1)
    N, Ns, Nt = q2_shape(S.ravel(), T.ravel())  # (9 points, 9 nodes)
    X = nodes[fluid]  # (E, 9, 2)
    xs = np.einsum("pa,ead->epd", Ns, X)  # dx/ds, dy/ds at each point
    xt = np.einsum("pa,ead->epd", Nt, X)
    det = xs[..., 0] * xt[..., 1] - xs[..., 1] * xt[..., 0]  # (E, P)
    if np.any(det <= 0):
        raise PlotError("an element of the mesh is inverted (det J <= 0)")
    # d/dx = ( yt d/ds - ys d/dt) / det, d/dy = (-xt d/ds + xs d/dt) / det
    dNx = (xt[..., 1, None] * Ns[None] - xs[..., 1, None] * Nt[None]) / det[..., None]
    dNy = (-xt[..., 0, None] * Ns[None] + xs[..., 0, None] * Nt[None]) / det[..., None]
    wdet = det * W.ravel()[None, :]
    V = velocity[fluid]  # (E, 9, 2)
    vx = np.einsum("pa,ea->ep", N, V[..., 0])
    vy = np.einsum("pa,ea->ep", N, V[..., 1])
    Ke = np.einsum("ep,epa,epb->eab", wdet, dNx, dNx) + np.einsum("ep,epa,epb->eab", wdet, dNy, dNy)
    be = np.einsum("ep,epa->ea", wdet * -vy, dNx) + np.einsum("ep,epa->ea", wdet * vx, dNy)
    n = len(nodes)
    rows = np.repeat(fluid[:, :, None], 9, axis=2).ravel()
    cols = np.repeat(fluid[:, None, :], 9, axis=1).ravel()
    K = sp.coo_matrix((Ke.ravel(), (rows, cols)), shape=(n, n)).tocsr()
    b = np.bincount(fluid.ravel(), weights=be.ravel(), minlength=n)
    used = np.unique(fluid)
    # psi is defined up to a constant: pin one node, then shift
    free = used[1:]
    psi = np.full(n, np.nan)
    psi[used[0]] = 0.0
    psi[free] = spla.spsolve(K[free][:, free].tocsc(), b[free])
    return psi


def refined(nodes, fluid, fields, m=6):
    """The Q2 interpolants of the nodal fields (N x k arrays) on an m x m grid of triangle pairs in
    each element (curved edges and contours follow the element's own quadratic map): a
    triangulation and the fields at its points."""
    r = np.linspace(-1.0, 1.0, m + 1)
    S, T = np.meshgrid(r, r, indexing="xy")
    N, _, _ = q2_shape(S.ravel(), T.ravel())  # ((m+1)^2 points, 9 nodes)
    xy = np.einsum("pa,ead->epd", N, nodes[fluid]).reshape(-1, 2)
    values = [np.einsum("pa,eak->epk", N, f[fluid]).reshape(-1, f.shape[1]) for f in fields]
    local = []
    for j in range(m):
        for i in range(m):
            a, b, c, d = i + (m + 1) * j, i + 1 + (m + 1) * j, i + (m + 1) * (j + 1), i + 1 + (m + 1) * (j + 1)
            local += [(a, b, d), (a, d, c)]
    local = np.array(local)
    per = (m + 1) ** 2
    tris = (np.arange(len(fluid))[:, None, None] * per + local[None]).reshape(-1, 3)
    return mtri.Triangulation(xy[:, 0], xy[:, 1], tris), values


def boundary_segments(nodes, elements, edges):
    return [quadratic_edge(nodes[elements[e][list(EDGE_NODES[k])]]) for e, k in edges]


def draw_mesh(ax, nodes, fluid, elements, boundaries, conditions):
    segs = [quadratic_edge(nodes[el[list(idx)]]) for el in fluid for idx in OUTLINE]
    ax.add_collection(LineCollection(segs, linewidths=0.35, colors="0.35"))
    colours = plt.get_cmap("tab10").colors
    for k, (name, edges) in enumerate(sorted(boundaries.items())):
        cond = conditions.get(name)
        label = f"{name} ({cond})" if cond and cond != name else name
        ax.add_collection(LineCollection(boundary_segments(nodes, elements, edges), linewidths=2.6,
                                         colors=[colours[k % len(colours)]], label=label, capstyle="round"))


def colour_field(nodal, velocity, spec):
    """The nodal values to colour the flow by, and their label."""
    if spec == "speed":
        return np.hypot(velocity[:, 0], velocity[:, 1]), "speed $|v|$"
    name, _, comp = spec.partition(":")
    if name not in nodal:
        raise PlotError(f"--colour {spec}: the stored solution has no nodal field '{name}'; it has: speed, "
                        + ", ".join(f"{n}:{c}" for n, (_, cs) in sorted(nodal.items()) for c in cs))
    values, comps = nodal[name]
    if comp not in comps:
        raise PlotError(f"--colour {spec}: field '{name}' has the components " + ", ".join(comps))
    k = comps.index(comp)
    label = f"${comp[0]}_{{{comp[1:]}}}$" if len(comp) > 1 else f"${comp}$"
    return values[:, k], label


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", help="the HDF5 file of keller trace (a branch) or keller solve")
    ap.add_argument("--row", default="last", help="the branch row of a stored solution, or 'last' (default)")
    ap.add_argument("--xlim", nargs=2, type=float, metavar=("X0", "X1"), help="the window in x (default: all)")
    ap.add_argument("--ylim", nargs=2, type=float, metavar=("Y0", "Y1"), help="the window in y (default: all)")
    ap.add_argument("--psi-zero", help="the boundary where psi = 0 (default: the wall along which psi is the "
                                       "most nearly constant)")
    ap.add_argument("--levels", type=int, default=10, help="streamlines of the main flow (default 10)")
    ap.add_argument("--colour", default="speed", metavar="FIELD:COMPONENT",
                    help="the field in colour: speed (default) or a nodal field's component, e.g. "
                         "conformation_M:Mxx (the stored fields: h5ls RUN.h5/branch/fields/0)")
    ap.add_argument("--log", action="store_true", help="a logarithmic colour scale")
    ap.add_argument("--title", help="a line above the figure (default: none; 'auto': the fluid and the "
                                    "parameter values)")
    ap.add_argument("--unit", default="", help="the length unit for the axis labels, e.g. H (default: none)")
    which = ap.add_mutually_exclusive_group()
    which.add_argument("--mesh-only", action="store_true")
    which.add_argument("--flow-only", action="store_true")
    ap.add_argument("-o", "--output", required=True)
    args = ap.parse_args(argv)
    try:
        check_outputs([args.output], [args.run])
        nodes, elements, groups, names, boundaries, scene, velocity, nodal, values = read_run(args.run, args.row)
        colour, colour_label = colour_field(nodal, velocity, args.colour)
    except (OutputError, PlotError) as e:
        sys.exit(f"keller.plot flow: {e}")
    except OSError as e:
        sys.exit(f"keller.plot flow: cannot read '{args.run}': {e}")
    fluid = fluid_elements(elements, groups, names)
    conditions = {name: b.get("type", "") for name, b in scene.get("boundaries", {}).items()}
    if args.psi_zero is not None and args.psi_zero not in boundaries:
        sys.exit(f"keller.plot flow: --psi-zero: the mesh has no boundary '{args.psi_zero}'; its boundaries: "
                 + ", ".join(sorted(boundaries)))

    used = np.unique(fluid)
    if args.xlim:
        x0, x1 = args.xlim
    else:
        x0, x1 = nodes[used, 0].min(), nodes[used, 0].max()
    if args.ylim:
        y0, y1 = args.ylim
    else:  # a margin, so that the boundaries on the window's edge are seen whole
        y0, y1 = nodes[used, 1].min(), nodes[used, 1].max()
        pad = 0.03 * (y1 - y0)
        y0, y1 = y0 - pad, y1 + pad
    panels = ["mesh"] if args.mesh_only else ["flow"] if args.flow_only else ["mesh", "flow"]
    # the layout in inches, top to bottom: each panel's title, axes (equal aspect), x label and,
    # below, the mesh's legend of boundaries or the flow's colour bar
    width, left, right = 9.0, 0.65, 0.25
    aw = width - left - right
    ah = aw * (y1 - y0) / (x1 - x0)
    legend_rows = (len(boundaries) + 2) // 3
    below = {"mesh": 0.3 + 0.17 * legend_rows, "flow": 0.6}
    top = 0.45 if args.title else 0.1
    heights = [(0.3, ah, 0.45, below[p]) for p in panels]
    height = top + sum(sum(h) for h in heights)
    fig = plt.figure(figsize=(width, height))
    unit = f" / {args.unit}" if args.unit else ""
    y = height - top
    for panel, (h_title, h_axes, h_label, h_below) in zip(panels, heights):
        y -= h_title + h_axes
        ax = fig.add_axes([left / width, y / height, aw / width, h_axes / height])
        if panel == "mesh":
            draw_mesh(ax, nodes, fluid, elements, boundaries, conditions)
            ax.legend(loc="upper center", bbox_to_anchor=(0.5, -(h_label + 0.05) / h_axes), ncol=3, fontsize=8,
                      frameon=False, title="boundary (condition)", title_fontsize=8)
            ax.set_title(f"mesh: {len(fluid)} elements (9-node quadrilaterals)", fontsize=9)
        else:
            psi = stream_function(nodes, fluid, velocity)

            def nodes_of(name):
                be = boundaries[name]
                return np.unique(elements[be[:, 0][:, None], np.array([EDGE_NODES[k] for k in be[:, 1]])])

            # psi = 0 on --psi-zero, or on the wall along which psi is the most nearly constant
            walls = [n for n, c in conditions.items() if c in ("wall", "moving-wall") and n in boundaries]
            candidates = [args.psi_zero] if args.psi_zero else walls or sorted(boundaries)
            zero = min(candidates, key=lambda n: np.ptp(psi[nodes_of(n)]))
            zero_nodes = nodes_of(zero)
            psi -= np.mean(psi[zero_nodes])
            tri, (c, ps) = refined(nodes, fluid, [colour[:, None], psi[:, None]])
            ps = ps[:, 0]
            c, label = c[:, 0], colour_label
            if args.log:
                if np.min(c) <= 0:
                    sys.exit(f"keller.plot flow: --log: {colour_label} is not positive everywhere (min {np.min(c):.3g})")
                c, label = np.log10(c), "$\\log_{10}$ " + colour_label
            pc = ax.tricontourf(tri, c, levels=np.linspace(np.min(c), np.max(c), 65), cmap="viridis",
                                antialiased=False)
            # the filled contours as images in a vector file (matplotlib >= 3.8: one artist)
            for coll in [pc] if isinstance(pc, matplotlib.artist.Artist) else pc.collections:
                coll.set_rasterized(True)
            cax = fig.add_axes([(left + 0.6 * aw) / width, (y - h_label - 0.05) / height, 0.4 * aw / width,
                                0.12 / height])
            fig.colorbar(pc, cax=cax, orientation="horizontal", label=label,
                         ticks=matplotlib.ticker.MaxNLocator(6))
            p = psi[used]
            main_sign = -1.0 if abs(p.min()) >= abs(p.max()) else 1.0
            q = np.max(main_sign * p)  # the flow rate between psi = 0 and the far side
            main = main_sign * q * np.linspace(0.0, 1.0, args.levels + 1)[1:-1]
            ax.tricontour(tri, ps, levels=np.sort(main), colors="k", linewidths=0.6,
                          linestyles="solid")
            eddy = np.max(-main_sign * p)
            # psi is one constant along a wall or a symmetry line only up to the discretisation
            # (the discrete velocity is not exactly a curl): recirculation contours are drawn at
            # levels beyond the largest spread of psi along one of them
            lines = [n for n in walls + [n for n, c in conditions.items() if c == "symmetry"] if n in boundaries]
            noise = max([np.ptp(psi[nodes_of(n)]) for n in lines] + [0.0])
            print(f"psi: q = {q:.10g}, extremum of the other sign {eddy / q:.10g} q, spread along a wall or "
                  f"symmetry line {noise / q:.3g} q")
            fractions = [f for f in (0.1, 0.3, 0.5, 0.7, 0.9) if f * eddy > noise]
            if fractions:
                levels = -main_sign * eddy * np.array(fractions)
                ax.tricontour(tri, ps, levels=np.sort(levels), colors="w", linewidths=0.6, linestyles="solid")
            ax.set_title(f"{colour_label} and streamlines: $\\psi$ = $k\\,q$ / {args.levels} (black)"
                         + (f", recirculation up to $\\psi$ = {eddy / q:.3g} $q$ (white)" if fractions else "")
                         + f"; $q$ = {q:.4g}", fontsize=9)
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_aspect("equal")
        ax.set_xlabel(f"$x${unit}", labelpad=1)
        ax.set_ylabel(f"$y${unit}")
        y -= h_label + h_below
    title = args.title
    if title == "auto":
        fluid_model = scene.get("fluid", {}).get("model", "newtonian")
        fluid_model = {"newtonian": "Newtonian", "oldroyd-b": "Oldroyd-B", "fene-p": "FENE-P",
                       "owens": "Owens"}.get(fluid_model, fluid_model)
        title = f"{fluid_model}, " + ", ".join(f"{k} = {v:.4g}" for k, v in values.items())
    if title:
        fig.suptitle(title, fontsize=10, y=1 - 0.12 / height, va="top")
    save_figure(fig, args.output, [args.run], dpi=150)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
