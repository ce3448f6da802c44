"""Drag coefficient K(Wi) of Oldroyd-B flow past a confined cylinder (blockage 0.5, beta = 0.59)
from one or more branch files of `keller trace`, with the published mesh-converged values
(method.md) overlaid. The point where the smallest conformation eigenvalue crosses zero (the
limiting Wi of the conformation form, a triangle) and the end of each finished branch (a cross) are
marked; a branch file still flagged as running (an interrupted run) gets no end mark.

    python3 -m keller.plot cylinder_drag A.h5 [B.h5 ...] [--labels "C2 conf" "C2 log"] [--title T] -o FIG.png

Each branch is drawn smoothly through its stored tangents; the legend names the files by the
scene keys that differ (or --labels); no title unless --title."""

import argparse
import sys

import matplotlib.pyplot as plt

from keller.labels import distinguishing_labels, quantity, readable
from keller.outputs import OutputError, check_outputs, save_figure
from keller.plot.common import columns
from keller.plot.curves import draw_branch

PUBLISHED = [(0.0, 132.36), (0.1, 130.36), (0.2, 126.62), (0.3, 123.19), (0.4, 120.59), (0.5, 118.83),
             (0.6, 117.78), (0.7, 117.32)]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("branches", nargs="+", help="branch files (HDF5) of the cylinder scene")
    ap.add_argument("--labels", nargs="*", help="legend labels, one per file")
    ap.add_argument("--xmax", type=float, help="upper limit of the Wi axis")
    ap.add_argument("--title", help="a title (default: none)")
    ap.add_argument("-o", "--output", default="cylinder_drag.png")
    args = ap.parse_args(argv)
    try:
        check_outputs([args.output], args.branches)
    except OutputError as e:
        sys.exit(f"keller.plot cylinder_drag: {e}")
    labels = args.labels or [readable(x) for x in distinguishing_labels(args.branches, ignore={"parameters.Wi"})]

    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    shown = [k for _, k in PUBLISHED]
    ax.plot(*zip(*PUBLISHED), "ks", mfc="none", ms=7, label="published (mesh converged)", zorder=4)
    for i, (path, label) in enumerate(zip(args.branches, labels)):
        parameter, cols, status = columns(path)
        wi, k, kind = cols[parameter], cols["K"], cols["kind"]
        shown += list(k[wi <= args.xmax] if args.xmax else k)
        ev = kind == 3
        if ev.any():
            label += r"; min $m_1$ = 0 at Wi = " + ", ".join(f"{w:.4f}" for w in wi[ev])
        _, line = draw_branch(ax, cols["s"], wi, k, cols.get("tangent_parameter"), color=f"C{i % 10}",
                              label=label, zorder=2)
        if ev.any():
            ax.plot(wi[ev], k[ev], "v", color=line.get_color(), ms=8, zorder=3)
        end = kind == 6
        if end.any():
            ax.plot(wi[end], k[end], "x", color=line.get_color(), ms=8, zorder=3)
    if args.xmax:
        ax.set_xlim(right=args.xmax)
        pad = 0.05 * (max(shown) - min(shown))
        ax.set_ylim(min(shown) - pad, max(shown) + pad)
    ax.set_xlabel(quantity("Wi"))
    ax.set_ylabel(quantity("K"))
    if args.title:
        ax.set_title(args.title, fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, args.output, args.branches, dpi=150)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
