"""keller from Python (docs/python.md).

    import keller
    branch = keller.open("gamma.h5")            # results as objects: branch, curve, time series, study
    branch = keller.trace("scene.toml", output="gamma.h5", callback=print)   # runs in-process
    python3 -m keller.plot branch gamma.h5 --y dy_max -o gamma.png           # the figures

keller needs numpy, scipy, h5py and matplotlib; importing it without one of them is an ImportError
that names what is missing and how to install it.
"""

import importlib.util as _util
import sys as _sys

NEEDED = ("numpy", "scipy", "h5py", "matplotlib")
DEBIAN_PACKAGES = {"numpy": "python3-numpy", "scipy": "python3-scipy", "h5py": "python3-h5py",
                   "matplotlib": "python3-matplotlib"}


def missing_modules():
    """The modules keller needs that this Python cannot import."""
    return [m for m in NEEDED if _util.find_spec(m) is None]


def missing_message(missing, executable=None):
    """What keller says when this Python lacks the modules `missing`."""
    executable = executable or _sys.executable
    names = ", ".join(missing)
    debian = " ".join(DEBIAN_PACKAGES[m] for m in missing)
    return (f"keller needs the Python modules {', '.join(NEEDED)}; {executable} (Python "
            f"{_sys.version.split()[0]}) cannot import {names}. Install them into it with\n"
            f"    {executable} -m pip install {' '.join(missing)}\n"
            f"or use Debian's /usr/bin/python3 with `sudo apt-get install {debian}` (a virtual environment "
            f"made with `python3 -m venv --system-site-packages` sees Debian's packages).")


_missing = missing_modules()
if _missing:
    raise ImportError(missing_message(_missing))

from keller.results import Branch, Curve, Solution, Study, TimeSeries, open  # noqa: E402,F401
from keller.runs import KellerError, Point, evolve, solve, study, trace  # noqa: E402,F401
from keller.problem import NumericalFailure, Problem  # noqa: E402,F401

__all__ = ["Branch", "Curve", "KellerError", "NumericalFailure", "Point", "Problem", "Solution", "Study", "TimeSeries",
           "evolve", "open", "solve", "study", "trace"]
