"""The figure of keller.convergence: one panel per observable, the relative error of each mesh
against the run's time on log-log axes, one curve per group of tasks.

What makes it readable with many groups and observables: a marker per mesh (its key in the
legend) instead of the mesh's name written at every point (those overlap where groups lie close);
groups named by their values (`fluid.model = owens` as owens, `parameters.Gamma = 4.95e-05` as
Gamma = 4.95e-05); the legend in the panels the grid leaves free, or under the panels (never an
empty panel); log axes with at least two labelled ticks and no minor labels (which overlap on a
narrow panel spanning less than a decade); the y label once per row."""

import matplotlib.pyplot as plt
import numpy as np

from keller.labels import FLUID_NAMES, quantity, symbol
from keller.outputs import save_figure
from keller.plot.common import log_ticks

MESH_MARKERS = ["o", "s", "^", "D", "v", "P", "X", "*", "h", "<", ">"]


def group_name(values):
    """A group by its values: a law or formulation by its name, a parameter by its symbol."""
    parts = []
    for key, value in values.items():
        value = str(value).strip('"')
        if key.startswith("parameters."):
            parts.append(f"{symbol(key)} = {value}")
        elif key == "fluid.model":
            parts.append(FLUID_NAMES.get(value, value))
        elif key in ("fluid.formulation", "mesh.name"):
            parts.append(value)
        else:
            parts.append(f"{quantity(key)} = {value}")
    return ", ".join(parts) or "all tasks"


def draw(rows, published, path, inputs, title=None, mark_unsettled=False, parameter=None):
    """Draws the convergence figure of the analysed rows into path (save_figure)."""
    obs = list(dict.fromkeys(r["observable"] for r in rows))
    groups = list(dict.fromkeys(r["group"] for r in rows))
    meshes = list(dict.fromkeys(str(r["mesh"]) for r in rows))
    names = {r["group"]: group_name(r["group_values"]) for r in rows}
    ncols = min(4, len(obs))
    nrows = -(-len(obs) // ncols)
    free = nrows * ncols - len(obs)
    entries = len(groups) + len(meshes) + (1 if mark_unsettled else 0)
    below = 0.0 if free else 0.25 + 0.17 * -(-entries // 3)
    fig = plt.figure(figsize=(3.4 * ncols, 2.9 * nrows + below + (0.3 if title else 0.0)))
    grid = fig.add_gridspec(nrows, ncols)
    cmap = plt.get_cmap("tab10" if len(groups) <= 10 else "tab20")
    colour = {g: cmap(k % cmap.N) for k, g in enumerate(groups)}
    for n, o in enumerate(obs):
        ax = fig.add_subplot(grid[n // ncols, n % ncols])
        key = "published_error" if o in published else "error"
        xs, ys = [], []
        for g in groups:
            pts = [r for r in rows if r["observable"] == o and r["group"] == g]
            t = np.array([r["seconds"] for r in pts], dtype=float)
            e = np.array([r.get(key, float("nan")) for r in pts], dtype=float)
            ok = np.isfinite(t) & np.isfinite(e) & (t > 0) & (e > 0)
            if not ok.any():
                continue
            dashed = mark_unsettled and not pts[0]["settled"]
            ax.plot(t[ok], e[ok], "--" if dashed else "-", color=colour[g], lw=1.1)
            for r, ti, ei in zip(np.array(pts, dtype=object)[ok], t[ok], e[ok]):
                ax.plot([ti], [ei], MESH_MARKERS[meshes.index(str(r["mesh"])) % len(MESH_MARKERS)], ms=4,
                        color=colour[g], mfc="white" if dashed else colour[g])
            xs += list(t[ok])
            ys += list(e[ok])
        ax.set_xscale("log")
        ax.set_yscale("log")
        if xs:
            log_ticks(ax.xaxis, min(xs), max(xs))
            log_ticks(ax.yaxis, min(ys), max(ys))
        ax.tick_params(labelsize=7)
        ax.set_title(quantity(o, parameter), fontsize=8)
        ax.grid(alpha=0.3, which="major")
        if n // ncols == nrows - 1 or n + ncols >= len(obs):
            ax.set_xlabel("time of the run (s)", fontsize=8)
        if n % ncols == 0:
            ax.set_ylabel("relative error", fontsize=8)
    handles = [plt.Line2D([], [], color=colour[g], lw=1.4) for g in groups]
    labels = [names[g] for g in groups]
    handles += [plt.Line2D([], [], ls="", marker=MESH_MARKERS[k % len(MESH_MARKERS)], color="0.3", ms=5)
                for k in range(len(meshes))]
    labels += [f"mesh {m}" for m in meshes]
    if mark_unsettled:
        handles.append(plt.Line2D([], [], ls="--", color="0.3"))
        labels.append("observed order not settled")
    against = ("against the published value" if all(o in published for o in obs) else
               "against the extrapolation" if not any(o in published for o in obs) else
               "against the published value where there is one, else the extrapolation")
    labels[0:0], handles[0:0] = [f"relative error {against}"], [plt.Line2D([], [], ls="")]
    if title:
        fig.suptitle(title, fontsize=10)
    if free:
        lax = fig.add_subplot(grid[nrows - 1, ncols - free:])
        lax.set_axis_off()
        lax.legend(handles, labels, loc="center", fontsize=7, ncol=1 if free == 1 else 2, frameon=False)
        fig.tight_layout()
    else:
        fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=7, frameon=False)
        fig.tight_layout(rect=(0, below / fig.get_figheight(), 1, 1))
    save_figure(fig, path, inputs, dpi=150)
