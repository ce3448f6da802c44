"""python3 -m keller.plot KIND [ARGS ...]: runs the figure module of that kind (keller.plot lists
them); `python3 -m keller.plot KIND --help` says what it draws and its options."""

import importlib
import sys

import matplotlib

matplotlib.use("Agg")  # the commands write files: no display

from keller.plot import KINDS  # noqa: E402


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv or argv[0] in ("-h", "--help") or argv[0] not in KINDS:
        import keller.plot

        out = sys.stdout if argv and argv[0] in ("-h", "--help") else sys.stderr
        if argv and argv[0] not in ("-h", "--help"):
            print(f"keller.plot: no figure kind '{argv[0]}'", file=out)
        print("usage: python3 -m keller.plot KIND [ARGS ...]  (KIND --help for its options)\n\n"
              + keller.plot.__doc__, file=out)
        return 0 if out is sys.stdout else 2
    module = importlib.import_module(f"keller.plot.{argv[0]}")
    sys.argv[0] = f"python3 -m keller.plot {argv[0]}"  # argparse's program name in usage and errors
    return module.main(argv[1:]) or 0


if __name__ == "__main__":
    sys.exit(main())
