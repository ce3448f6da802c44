"""Time series written by `keller evolve`: any column of its time table (an observable, the
deviation from the start's steady state, the components along the perturbation's eigenvector)
against time. With --log the vertical axis is logarithmic and, for a run perturbed along an
eigenvector, the line exp(-Re sigma t) through the first point is drawn beside it, with the rate
fitted to the run (least squares of log |y| against t) in the legend: the check of the spectrum by
dynamics (docs/dynamics.md).

    python3 -m keller.plot evolve RUN.h5 [--y COLUMN] [--log] [--title T] [--footer] [-o FIGURE.png]

No title unless --title; --footer adds why the run ended under the axes.

Reads only the HDF5 file (keller.open; also one whose run was killed)."""

import argparse
import sys

import numpy as np

import matplotlib.pyplot as plt

import keller.results
from keller.labels import quantity
from keller.outputs import OutputError, check_outputs, save_figure
from keller.plot.common import log_ticks

BOOKKEEPING = {"step", "t", "h", "order", "error", "iterations", "factorisations", "rejected", "next_step", "seconds",
               "saved_slot"}


def fitted_rate(t, y):
    """The slope of log |y| against t by least squares (the points with y != 0 after the start)."""
    keep = (t > 0) & (np.abs(y) > 0)
    if keep.sum() < 2:
        return float("nan")
    return float(np.polyfit(t[keep], np.log(np.abs(y[keep])), 1)[0])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", help="time-series file (HDF5) written by keller evolve")
    ap.add_argument("--y", help="column on the vertical axis (default: mode_amplitude when there, else deviation)")
    ap.add_argument("--log", action="store_true", help="logarithmic vertical axis (|y|), with the eigenvalue's rate")
    ap.add_argument("--title", help="a title (default: none)")
    ap.add_argument("--footer", action="store_true", help="why the run ended, under the axes")
    ap.add_argument("-o", "--output", help="figure file (default: RUN with .png)")
    args = ap.parse_args(argv)
    series = keller.results.open(args.run)
    if not isinstance(series, keller.results.TimeSeries):
        sys.exit(f"keller.plot evolve: {args.run} is not a time series (keller evolve)")
    cols, status = series.table, series.status
    mode = None if series.mode is None else (series.mode.sigma.real, series.mode.sigma.imag)
    y = args.y or ("mode_amplitude" if "mode_amplitude" in cols else "deviation")
    if y not in cols:
        choices = [c for c in cols if c not in BOOKKEEPING]
        sys.exit(f"keller.plot evolve: no column '{y}' in {args.run}; it has: {', '.join(choices)}")
    out = args.output or args.run.rsplit(".", 1)[0] + ".png"
    try:
        check_outputs([out], [args.run])
    except OutputError as e:
        sys.exit(f"keller.plot evolve: {e}")

    t, v = cols["t"], cols[y]
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    if args.log:
        rate = fitted_rate(t, v)
        ax.semilogy(t, np.abs(v), color="0.25", label=f"keller evolve (fitted rate {rate:.6g})")
        if mode is not None and y in ("mode_amplitude", "deviation"):
            ax.semilogy(t, abs(v[0]) * np.exp(-mode[0] * t), "--", color="tab:red",
                        label=rf"$e^{{-\mathrm{{Re}}\,\sigma\, t}}$, $\sigma$ = {mode[0]:.6g} {mode[1]:+.6g} i")
        ax.legend(frameon=False, fontsize=8)
        shown = np.abs(v)[np.abs(v) > 0]
        if len(shown):
            log_ticks(ax.yaxis, shown.min(), shown.max())  # a span under a decade still gets labels
    else:
        ax.plot(t, v, color="0.25")
    ax.set_xlabel("time t")
    ax.set_ylabel(quantity(y) if not args.log else f"|{quantity(y)}|")
    if args.title:
        ax.set_title(args.title, fontsize=10)
    bottom = 0.0
    if args.footer:
        fig.text(0.01, 0.005, f"ended: {status}"[:120], fontsize=6, color="0.4", va="bottom")
        bottom = 0.03
    fig.tight_layout(rect=(0, bottom, 1, 1))
    save_figure(fig, out, [args.run], dpi=130)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
