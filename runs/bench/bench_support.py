"""What the benchmarks of runs/bench share: where the repository is, the machine they ran on, and
the shipped collapsible-channel branch scenes."""

import os
import platform

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))

FLUIDS = ["newtonian", "oldroyd_b", "fene_p", "owens"]
BRANCHES = ["gamma", "thickness", "wi_low_gamma", "wi_high_gamma"]


def machine():
    """The machine, in one line: CPU model, cores, memory, OPENBLAS_NUM_THREADS and the load average
    (over 1, 5 and 15 minutes) now; a benchmark prints it first (and last, for the load after it)."""
    model = platform.processor() or "?"
    memory = "?"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
        with open("/proc/meminfo") as f:
            memory = f"{int(f.readline().split()[1]) / 2**20:.0f}"
    except OSError:
        pass
    # the limit only: the keller program takes one BLAS thread below 20,000 unknowns by itself, the
    # Python package leaves the BLAS as it is (core/BlasThreads.hpp)
    blas = os.environ.get("OPENBLAS_NUM_THREADS", "unset")
    load = " ".join(f"{x:.2f}" for x in os.getloadavg())
    return f"{model}, {os.cpu_count()} cores, {memory} GiB, OPENBLAS_NUM_THREADS {blas}, load average {load}"


def scenes():
    """The names of the shipped collapsible-channel branch scenes (runs/scenes/collapsible_NAME.toml):
    a Gamma and a thickness branch per fluid, and two Wi branches per viscoelastic fluid."""
    for fluid in FLUIDS:
        for branch in BRANCHES:
            if fluid == "newtonian" and branch.startswith("wi"):
                continue
            yield f"{fluid}_{branch}"
