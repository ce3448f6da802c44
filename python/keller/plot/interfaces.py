"""Interface shapes for several Gamma, one panel per fluid, the Newtonian shapes overlaid in grey
(reads only the branch files of the Gamma scenes):

    python3 -m keller.plot interfaces --newtonian collapsible_newtonian_gamma.h5 \\
        collapsible_oldroyd_b_gamma.h5 collapsible_fene_p_gamma.h5 collapsible_owens_gamma.h5 -o interfaces.png

Also draws dP against Gamma for every file in a last panel, each branch smoothly through its
stored tangents. Panels are named by the fluid (the scene's fluid.model), not by the file."""

import argparse
import sys

import matplotlib.pyplot as plt

import keller.results
from keller.labels import quantity, symbol
from keller.outputs import OutputError, check_outputs, save_figure
from keller.plot.curves import draw_branch


def shapes(path):
    """[(parameter value, interface shape)] of the solutions stored with fields on a branch."""
    return [(s.value, s.fields["interface_shape"]) for s in keller.results.open(path).solutions if s.fields]


def fluid(branch):
    """The fluid of a branch as a reader names it (its scene's fluid.model)."""
    model = branch.scene.get("fluid", {}).get("model", "")
    return {"newtonian": "Newtonian", "oldroyd-b": "Oldroyd-B", "fene-p": "FENE-P", "owens": "Owens",
            "giesekus": "Giesekus", "ptt-linear": "linear PTT", "ptt-exponential": "exponential PTT",
            "fene-cr": "FENE-CR"}.get(model, model or "fluid")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("branches", nargs="+", help="Gamma branch files, one panel each")
    ap.add_argument("--newtonian", help="the Newtonian Gamma branch, overlaid in grey")
    ap.add_argument("--title", help="a title over the panels (default: none)")
    ap.add_argument("-o", "--output", default="interfaces.png")
    args = ap.parse_args(argv)
    files = args.branches
    inputs = files + ([args.newtonian] if args.newtonian else [])
    try:
        check_outputs([args.output], inputs)
    except OutputError as e:
        sys.exit(f"keller.plot interfaces: {e}")
    fig, axes = plt.subplots(len(files) + 1, 1, figsize=(7.0, 2.2 * (len(files) + 1)))
    cmap = plt.get_cmap("viridis")
    for ax, path in zip(axes, files):
        if args.newtonian:
            for _, s in shapes(args.newtonian):
                ax.plot(s[:, 0], s[:, 1], "-", color="0.75", lw=1.0)
        sols = shapes(path)
        branch = keller.results.open(path)
        for k, (v, s) in enumerate(sols):
            ax.plot(s[:, 0], s[:, 1], "-", color=cmap(k / max(1, len(sols) - 1)), lw=1.3,
                    label=f"{symbol(branch.parameter)} = {v:.3g}")
        ax.axhline(0, color="k", lw=0.8)
        ax.set_title(fluid(branch) + (" (grey: Newtonian)" if args.newtonian else ""), fontsize=9)
        ax.set_ylabel("y / W")
        ax.legend(fontsize=6, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    axes[-2].set_xlabel("x / W")
    ax = axes[-1]
    for k, path in enumerate(([args.newtonian] if args.newtonian else []) + files):
        branch = keller.results.open(path)
        t = branch.table
        draw_branch(ax, t["s"], t[branch.parameter], t["dP"], t.get("tangent_parameter"), color=f"C{k % 10}",
                    label=fluid(branch))
    ax.set_xlabel(quantity(branch.parameter))
    ax.set_ylabel(quantity("dP"), fontsize=8)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=6, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    if args.title:
        fig.suptitle(args.title, fontsize=10)
    fig.tight_layout()
    save_figure(fig, args.output, inputs, dpi=150)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
