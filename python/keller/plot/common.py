"""What the figure modules share: a branch's columns as a dict (the
form the figure code computes with), the messages of a figure command, and log axes whose ticks
are labelled however short their span."""

import sys

import keller.results
import matplotlib.ticker as ticker
import numpy as np


def columns(path):
    """(parameter, {column: array}, status) of a branch file, read by keller.open."""
    b = keller.results.open(path)
    return b.parameter, dict(b.table.items()), b.status


def fail(kind, message):
    """Ends a figure command with exit 1 and `keller.plot KIND: message` (argparse's usage errors
    are exit 2)."""
    sys.exit(f"keller.plot {kind}: {message}")


def log_ticks(axis, lo, hi):
    """Labelled ticks on a log axis spanning [lo, hi]: decades where it spans two or more, else
    1-2-5 steps, plain numbers, no minor labels."""
    if not (np.isfinite(lo) and np.isfinite(hi) and lo > 0 and hi > 0):
        return
    decades = np.log10(hi) - np.log10(lo)
    if decades < 1.5:
        axis.set_major_locator(ticker.LogLocator(base=10, subs=(1.0, 2.0, 5.0) if decades > 0.5 else
                                                 (1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 7.0)))
        axis.set_major_formatter(ticker.FuncFormatter(lambda v, _: f"{v:.3g}"))
    axis.set_minor_formatter(ticker.NullFormatter())
