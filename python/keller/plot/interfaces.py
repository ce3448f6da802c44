"""Interface shapes for several Gamma, one panel per fluid, the Newtonian shapes overlaid in grey
(reads only the branch files of the Gamma scenes):

    python3 -m keller.plot interfaces --newtonian collapsible_newtonian_gamma.h5 \\
        collapsible_oldroyd_b_gamma.h5 collapsible_fene_p_gamma.h5 collapsible_owens_gamma.h5 -o interfaces.png

Also draws dP against Gamma for every file in a last panel."""

import argparse
import sys

import matplotlib.pyplot as plt

import keller.results
from keller.outputs import OutputError, check_outputs, save_figure


def shapes(path):
    """[(parameter value, interface shape)] of the solutions stored with fields on a branch."""
    return [(s.value, s.fields["interface_shape"]) for s in keller.results.open(path).solutions if s.fields]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("branches", nargs="+", help="Gamma branch files, one panel each")
    ap.add_argument("--newtonian", help="the Newtonian Gamma branch, overlaid in grey")
    ap.add_argument("-o", "--output", default="interfaces.png")
    args = ap.parse_args(argv)
    files = args.branches
    inputs = files + ([args.newtonian] if args.newtonian else [])
    try:
        check_outputs([args.output], inputs)
    except OutputError as e:
        sys.exit(f"keller.plot interfaces: {e}")
    fig, axes = plt.subplots(len(files) + 1, 1, figsize=(7.0, 2.4 * (len(files) + 1)))
    cmap = plt.get_cmap("viridis")
    for ax, path in zip(axes, files):
        if args.newtonian:
            for _, s in shapes(args.newtonian):
                ax.plot(s[:, 0], s[:, 1], "-", color="0.75", lw=1.0)
        sols = shapes(path)
        for k, (v, s) in enumerate(sols):
            ax.plot(s[:, 0], s[:, 1], "-", color=cmap(k / max(1, len(sols) - 1)), lw=1.3, label=f"Gamma = {v:.3g}")
        ax.axhline(0, color="k", lw=0.8)
        ax.set_title(path.rsplit("/", 1)[-1] + (" (grey: Newtonian)" if args.newtonian else ""), fontsize=8)
        ax.set_ylabel("y")
        ax.legend(fontsize=6, ncol=3)
    ax = axes[-1]
    for path in ([args.newtonian] if args.newtonian else []) + files:
        branch = keller.results.open(path)
        ax.plot(branch[branch.parameter], branch["dP"], "-", label=path.rsplit("/", 1)[-1].replace(".h5", ""))
    ax.set_xlabel("Gamma")
    ax.set_ylabel("dP")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=6)
    fig.tight_layout()
    save_figure(fig, args.output, inputs, dpi=150)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
