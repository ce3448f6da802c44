"""Figures of a collapsible-channel branch file of `keller trace` (reads only the HDF5 file):

  PREFIX_branch.png     dP, dy_max, gap_min (and min m1) against the branch parameter, with
                        events and the end of the branch marked
  PREFIX_interface.png  interface shapes of every saved solution, coloured by the parameter
  PREFIX_path.png       the path of the maximum-deflection point (dx_max, dy_max)
  PREFIX_wall.png       M_xx (viscoelastic) or the pressure along the interface, per saved solution
  PREFIX_fields.png     v_x, P and M_xx (if present) in the deformed domain of one saved solution

    python3 -m keller.plot collapsible BRANCH.h5 -o PREFIX [--solution K] [--overlay NEWTONIAN.h5]

--overlay adds the interface shapes of another branch file (e.g. the Newtonian one) in grey. The
branch panels draw it smoothly through its stored tangents (keller.plot.curves). No titles unless
--title (over the branch panels); --footer adds why the branch ended under them."""

import argparse
import sys

import matplotlib.pyplot as plt
import numpy as np

import keller.results
from keller.labels import quantity, symbol
from keller.outputs import OutputError, check_outputs, save_figure
from keller.plot.common import columns
from keller.plot.curves import draw_branch


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("branch")
    ap.add_argument("-o", "--output", default="collapsible", help="prefix of the figure files")
    ap.add_argument("--solution", type=int, default=-1, help="index of the saved solution for the field plot")
    ap.add_argument("--overlay", help="another branch file whose interface shapes are drawn in grey")
    ap.add_argument("--title", help="a title over the branch panels (default: none)")
    ap.add_argument("--footer", action="store_true", help="why the branch ended, under the branch panels")
    args = ap.parse_args(argv)
    inputs = [args.branch] + ([args.overlay] if args.overlay else [])
    try:
        check_outputs([args.output + s for s in ("_branch.png", "_interface.png", "_path.png", "_wall.png", "_fields.png")],
                      inputs)
    except OutputError as e:
        sys.exit(f"keller.plot collapsible: {e}")

    parameter, cols, status = columns(args.branch)
    p, kind = cols[parameter], cols["kind"]
    ev, end = kind == 3, kind == 6
    ys = [c for c in ("dP", "dy_max", "gap_min", "min_m1") if c in cols]
    fig, axes = plt.subplots(len(ys), 1, figsize=(6.4, 2.2 * len(ys)), sharex=True)
    for ax, c in zip(np.atleast_1d(axes), ys):
        draw_branch(ax, cols["s"], p, cols[c], cols.get("tangent_parameter"), cols.get("unstable"), color="C0")
        if ev.any():
            ax.plot(p[ev], cols[c][ev], "v", ms=7, color="tab:orange", label="event", ls="")
        if end.any():
            ax.plot(p[end], cols[c][end], "s", ms=5, color="black", label="end", ls="")
        ax.set_ylabel(quantity(c), fontsize=8)
        ax.grid(alpha=0.3)
    np.atleast_1d(axes)[0].legend(fontsize=7, loc="best")
    np.atleast_1d(axes)[-1].set_xlabel(quantity(parameter))
    if args.title:
        np.atleast_1d(axes)[0].set_title(args.title, fontsize=10)
    bottom = 0.0
    if args.footer:
        fig.text(0.01, 0.005, f"ended: {status}"[:120], fontsize=6, color="0.4", va="bottom")
        bottom = 0.03
    fig.align_ylabels(np.atleast_1d(axes))
    fig.tight_layout(rect=(0, bottom, 1, 1))
    save_figure(fig, args.output + "_branch.png", inputs, dpi=150)

    # the stored solutions with their fields (a killed run's file has none yet)
    sols = [s for s in keller.results.open(args.branch).solutions if s.fields]
    cmap = plt.get_cmap("viridis")
    fig, ax = plt.subplots(figsize=(7.0, 3.0))
    if args.overlay:
        for o in keller.results.open(args.overlay).solutions:
            if not o.fields:
                continue
            s = o.fields["interface_shape"]
            ax.plot(s[:, 0], s[:, 1], "-", color="0.7", lw=1.0)
    for k, sol in enumerate(sols):
        s = sol.fields["interface_shape"]
        ax.plot(s[:, 0], s[:, 1], "-", color=cmap(k / max(1, len(sols) - 1)), lw=1.3,
                label=f"{symbol(parameter)} = {sol.value:.4g}")
    ax.axhline(0, color="k", lw=0.8)
    ax.axhline(1, color="k", lw=0.5, ls=":")
    ax.set_xlabel("x / W")
    ax.set_ylabel("interface y / W")
    ax.legend(fontsize=6, ncol=2, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    fig.tight_layout()
    save_figure(fig, args.output + "_interface.png", inputs, dpi=150)

    fig, ax = plt.subplots(figsize=(4.8, 4.0))
    # a curve in s through its points (no stored slope of either coordinate: both shape-preserving)
    draw_branch(ax, cols["s"], cols["dx_max"], cols["dy_max"], color="C0")
    ax.plot(cols["dx_max"], cols["dy_max"], "o", ms=2.5, color="C0")
    ax.xaxis.set_major_locator(plt.MaxNLocator(5))  # the deflection's x varies in the third digit
    ax.set_xlabel(quantity("dx_max"))
    ax.set_ylabel(quantity("dy_max"))
    ax.grid(alpha=0.3)
    fig.tight_layout()
    save_figure(fig, args.output + "_path.png", inputs, dpi=150)

    fig, ax = plt.subplots(figsize=(6.4, 3.2))
    for k, sol in enumerate(sols):
        v = sol.value
        prof = sol.fields.get("interface_profiles")
        if prof is None:
            continue
        viscoelastic = not np.all(np.isnan(prof[:, 5]))
        ax.plot(prof[:, 0], prof[:, 5] if viscoelastic else prof[:, 2], color=cmap(k / max(1, len(sols) - 1)), lw=1.2,
                label=f"{symbol(parameter)} = {v:.4g}")
        ax.set_ylabel(r"$M_{xx}$ along the wall" if viscoelastic else "pressure along the wall / G")
    ax.set_xlabel("x / W")
    ax.legend(fontsize=6, ncol=2, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    save_figure(fig, args.output + "_wall.png", inputs, dpi=150)

    if sols:
        sol = sols[args.solution]
        row = sol.row
        tri = sol.triangulation("fluid")
        vel = sol.fields["velocity"]
        conf = sol.fields.get("conformation_M")
        if conf is None:
            conf = sol.fields.get("conformation")
        panels = [("$v_x$", vel[:, 0]), ("P / G", sol.nodal_pressure())]
        if conf is not None:
            panels.append(("$M_{xx}$", conf[:, 0]))
        fig, axes = plt.subplots(len(panels), 1, figsize=(9.0, 1.9 * len(panels)), sharex=True)
        for ax, (name, val) in zip(np.atleast_1d(axes), panels):
            cs = ax.tricontourf(tri, np.nan_to_num(val), levels=24, cmap="viridis")
            fig.colorbar(cs, ax=ax, fraction=0.03, pad=0.01)
            ax.set_aspect("equal")
            ax.set_ylabel(name)
        np.atleast_1d(axes)[0].set_title(f"{symbol(parameter)} = {sol.value:.4g} (row {row})", fontsize=9)
        np.atleast_1d(axes)[-1].set_xlabel("x / W")
        fig.tight_layout()
        save_figure(fig, args.output + "_fields.png", inputs, dpi=150)
    print(f"wrote {args.output}_{{branch,interface,path,wall,fields}}.png")


if __name__ == "__main__":
    main()
