"""A branch of periodic orbits written by `keller trace --orbit`: the amplitude of an observable (max
minus min over the period) and the period against the parameter, in two panels. Stable orbits are
drawn solid and unstable ones dashed, by their Floquet multipliers (unstable where one besides the
trivial one, the nearest 1, lies outside the unit circle); located period doublings, Neimark-Sacker
points, folds and branch points of orbits and requested stops are marked. With the Hopf point the
branch started from (--hopf FILE.h5:LABEL; by default the file and row the run names, where that
file is found), its normal form's predictions are drawn beside: the amplitude
2 a sqrt(|lambda - lambda0|) (a = `amplitude:NAME`) and the period 2 pi / omega at the point.

    python3 -m keller.plot orbits ORBITS.h5 [--y OBSERVABLE] [--hopf HOPF.h5:hopf1] [--title T] [-o FIGURE.png]

Reads only the HDF5 files (keller.open; also one whose run was killed)."""

import argparse
import os
import sys

import numpy as np

import matplotlib.pyplot as plt

import keller.results
from keller.labels import quantity, symbol
from keller.outputs import OutputError, check_outputs, save_figure

MARKERS = {  # kind code: (legend label, marker, colour, size)
    3: ("stop", ".", "tab:blue", 40),
    4: ("fold of cycles", "^", "tab:red", 44),
    5: ("branch point of cycles", "X", "tab:purple", 48),
    8: ("period doubling", "D", "tab:orange", 40),
    9: ("Neimark-Sacker", "*", "tab:cyan", 70),
}
REQUESTED = 2  # the stops' kind code


def multipliers(table):
    """The Floquet multipliers of each row: an array (rows, k) of complex numbers from the columns
    mu1_re, mu1_im, ..."""
    k = 1
    columns = []
    while f"mu{k}_re" in table:
        columns.append(np.asarray(table[f"mu{k}_re"]) + 1j * np.asarray(table[f"mu{k}_im"]))
        k += 1
    return np.array(columns).T if columns else np.zeros((len(table["row"]), 0), complex)


def unstable(mu):
    """Per row of multipliers (rows, k): True where one other than the trivial one (the nearest 1)
    lies outside the unit circle; False for a row without multipliers."""
    out = np.zeros(len(mu), bool)
    for i, row in enumerate(mu):
        row = row[np.isfinite(row)]
        if len(row) == 0:
            continue
        trivial = int(np.argmin(np.abs(row - 1.0)))
        out[i] = bool(np.any(np.abs(np.delete(row, trivial)) > 1.0))
    return out


def normal_form_prediction(nf, lam0, observable, lam):
    """The normal form's amplitude (max - min) of `observable` at parameter values lam on the side
    where the orbits are (nan on the other), and its period 2 pi / omega."""
    lam = np.asarray(lam, float)
    d = (lam - lam0) * nf.get("side", 1.0)
    a = nf.get(f"amplitude:{observable}")
    amp = np.where(d >= 0, 2.0 * a * np.sqrt(np.abs(d)), np.nan) if a is not None else np.full(lam.shape, np.nan)
    return amp, nf["period"]


def hopf_of(path, given):
    """(normal form, lambda0) of the Hopf point named by --hopf or by the run's orbit_from, or None."""
    where = given
    if where is None:
        import h5py
        with h5py.File(path, "r") as f:
            where = f["problem"].attrs.get("orbit_from") if "problem" in f else None
        where = where.decode() if isinstance(where, bytes) else where
        if where is None or not os.path.exists(where.rsplit(":", 1)[0]):
            return None
    file, label = where.rsplit(":", 1) if ":" in where else (where, "hopf1")
    point = keller.results.open(file).point(label)
    return point.normal_form, point.value


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("orbits", help="an orbit branch file (HDF5) written by keller trace --orbit")
    ap.add_argument("--y", help="the observable whose amplitude is drawn (default: the largest-moving unknown's, "
                                "column `amplitude`)")
    ap.add_argument("--hopf", help="the Hopf point FILE.h5:LABEL (default: the one the run started from)")
    ap.add_argument("--title", help="a title (default: none)")
    ap.add_argument("-o", "--output", help="figure file (default: ORBITS with .png)")
    args = ap.parse_args(argv)
    branch = keller.results.open(args.orbits)
    table = branch.table
    if "period" not in table:
        sys.exit(f"keller.plot orbits: {args.orbits} is not an orbit branch (no column 'period')")
    column = f"amplitude:{args.y}" if args.y else "amplitude"
    if column not in table:
        names = [c.split(":", 1)[1] for c in table if c.startswith("amplitude:")]
        sys.exit(f"keller.plot orbits: no column '{column}' in {args.orbits}; observables: {', '.join(names)}")
    out = args.output or args.orbits.rsplit(".", 1)[0] + ".png"
    inputs = [args.orbits] + ([args.hopf.rsplit(":", 1)[0]] if args.hopf else [])
    try:
        check_outputs([out], inputs)
        hopf = hopf_of(args.orbits, args.hopf)
    except (OutputError, KeyError, OSError) as e:
        sys.exit(f"keller.plot orbits: {e}")

    lam, amp, period = (np.asarray(table[c], float) for c in (branch.parameter, column, "period"))
    kinds = np.asarray(table["kind"], int)
    bad = unstable(multipliers(table))
    fig, axes = plt.subplots(2, 1, figsize=(6.4, 6.4), sharex=True)
    for ax, y in zip(axes, (amp, period)):
        for i in range(len(lam) - 1):  # each segment by the stability of its two ends
            style = "--" if bad[i] or bad[i + 1] else "-"
            ax.plot(lam[i:i + 2], y[i:i + 2], style, color="0.2", lw=1.4)
        ax.plot(lam, y, ".", color="0.2", ms=4)
        for code, (label, marker, colour, size) in MARKERS.items():
            at = kinds == (REQUESTED if code == 3 else code)
            if at.any():
                ax.scatter(lam[at], y[at], marker=marker, s=size, color=colour, zorder=3,
                           label=label if ax is axes[0] else None)
    if hopf is not None:
        nf, lam0 = hopf
        grid = np.linspace(min(lam.min(), lam0), max(lam.max(), lam0), 200)
        amp_nf, period_nf = normal_form_prediction(nf, lam0, args.y or "", grid)
        if args.y and np.isfinite(amp_nf).any():
            axes[0].plot(grid, amp_nf, ":", color="tab:red", lw=1.2, label="normal form")
        axes[1].scatter([lam0], [period_nf], marker="*", s=70, color="tab:cyan", zorder=3,
                        label=r"Hopf point, $2\pi/\omega$")
        axes[0].scatter([lam0], [0.0], marker="*", s=70, color="tab:cyan", zorder=3)
    axes[0].plot([], [], "-", color="0.2", label="stable orbits")
    if bad.any():
        axes[0].plot([], [], "--", color="0.2", label="unstable orbits")
    axes[0].set_ylabel(f"amplitude of {quantity(args.y)}" if args.y else "amplitude (max - min)")
    axes[1].set_ylabel("period T")
    axes[1].set_xlabel(quantity(branch.parameter) if branch.parameter else symbol(branch.parameter))
    for ax in axes:
        handles, _ = ax.get_legend_handles_labels()
        if handles:
            ax.legend(frameon=False, fontsize=8)
    if args.title:
        axes[0].set_title(args.title, fontsize=10)
    fig.tight_layout()
    save_figure(fig, out, inputs, dpi=130)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
