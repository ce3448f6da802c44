"""Deviation of the confined-cylinder drag K(Wi) from the published table (Oldroyd-B, beta = 0.59,
blockage 0.5; Wi = 0, 0.1, ..., 0.9) for one or more branch files of `keller trace`, in percent,
with the band of +-0.011% (the FEniCS peer's largest deviation on its mesh M2) shaded. A branch
point at Wi <= 1e-4 stands for Wi = 0. A peer's results file (JSON with points of Wi and K_vol,
as ../shared/peers/fenics_cylinder writes them) can be added with --fenics.

    python3 -m keller.plot cylinder_deviation A.h5 [B.h5 ...] [--labels C3 W3]
        [--fenics bench.json] -o FIG.png"""

import argparse
import json
import sys

import matplotlib.pyplot as plt

from keller.labels import distinguishing_labels, readable
from keller.outputs import OutputError, check_outputs, save_figure
from keller.plot.common import columns

PUBLISHED = {0.0: 132.36, 0.1: 130.36, 0.2: 126.62, 0.3: 123.19, 0.4: 120.59, 0.5: 118.83, 0.6: 117.78,
             0.7: 117.32, 0.8: 117.36, 0.9: 117.79}
BAND = 0.011


def deviations(wi, k):
    """Percent deviations from the table at the table's Wi found in the branch (Wi <= 1e-4: 0)."""
    out = []
    for w, ref in PUBLISHED.items():
        hits = [kk for x, kk in zip(wi, k) if abs(x - w) < 1e-6 or (w == 0.0 and x <= 1e-4 + 1e-12)]
        if hits:
            out.append((w, 100.0 * (hits[0] / ref - 1.0)))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("branches", nargs="+", help="branch files (HDF5) of the cylinder scene")
    ap.add_argument("--labels", nargs="*", help="legend labels, one per file")
    ap.add_argument("--fenics", help="results JSON of the FEniCS peer")
    ap.add_argument("--fenics-label", default="FEniCS M2")
    ap.add_argument("--title", help="a title (default: none)")
    ap.add_argument("-o", "--output", default="cylinder_deviation.png")
    args = ap.parse_args(argv)
    inputs = args.branches + ([args.fenics] if args.fenics else [])
    try:
        check_outputs([args.output], inputs)
    except OutputError as e:
        sys.exit(f"keller.plot cylinder_deviation: {e}")
    labels = args.labels or [readable(x) for x in distinguishing_labels(args.branches, ignore={"parameters.Wi"})]
    if len(labels) != len(args.branches):
        sys.exit("keller.plot cylinder_deviation: --labels needs one label per branch file")

    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.axhspan(-BAND, BAND, color="0.85", label=f"within {BAND}% of the table")
    ax.axhline(0.0, color="k", lw=0.6)
    for path, label in zip(args.branches, labels):
        parameter, cols, _ = columns(path)
        d = deviations(cols[parameter], cols["K"])
        ax.plot(*zip(*d), "o-", ms=4, lw=1.2, label=label)
    if args.fenics:
        with open(args.fenics) as f:
            pts = json.load(f)["points"]
        d = deviations([p["Wi"] for p in pts], [p["K_vol"] for p in pts])
        ax.plot(*zip(*d), "k^--", ms=5, lw=1.0, mfc="none", label=args.fenics_label)
    ax.set_xlabel("Wi")
    ax.set_ylabel(r"$K / K_{published} - 1$ (%)")
    if args.title:
        ax.set_title(args.title, fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, args.output, inputs, dpi=150)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
