"""What the figure modules share: matplotlib without a display, a branch's columns as a dict (the
form the figure code computes with), and the messages of a figure command."""

import sys

import matplotlib

matplotlib.use("Agg")

import keller.results  # noqa: E402


def columns(path):
    """(parameter, {column: array}, status) of a branch file, read by keller.open."""
    b = keller.results.open(path)
    return b.parameter, dict(b.table.items()), b.status


def fail(kind, message):
    """Ends a figure command with exit 1 and `keller.plot KIND: message` (argparse's usage errors
    are exit 2)."""
    sys.exit(f"keller.plot {kind}: {message}")
