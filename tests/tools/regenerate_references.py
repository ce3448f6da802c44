#!/usr/bin/env python3
"""Regenerates the regression references: runs every scene listed in
tests/regression/scenes.txt through `keller trace` (with its coarse overrides) and writes the
located points (folds, events, requested values, branch points, ends) of each branch to
tests/regression/references/<scene>.csv; the same for the hard cases of
tests/regression/hard_cases.txt (on their coarse mesh) into references/hard/<name>.csv.

Run it on purpose, after a change that is meant to move the numbers, and say why in the
commit:  PYTHONPATH=build/python python3 tests/tools/regenerate_references.py [--keller build/bin/keller]
             [--only SCENE ...]"""

import argparse
import os
import subprocess
import sys
import tempfile

from keller import open as open_result

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))  # the repository


# A branch that ended at the step-size floor ends where the step controller gave up, which
# depends on its path: that end is not a reference.
STEP_FLOOR = "fell below min_step"


def regenerate(keller, scene, overrides, ref, tmp):
    """Traces the scene and writes its located points to `ref`."""
    name = os.path.splitext(os.path.basename(ref))[0]
    out = os.path.join(tmp, name + ".h5")
    cmd = [keller, "trace", os.path.join(ROOT, scene), "-o", out, "--set", "output.xdmf=false"]
    for o in overrides:
        cmd += ["--set", o]
    subprocess.run(cmd, check=False, stdout=subprocess.DEVNULL)
    branch = open_result(out)
    parameter, cols, status = branch.parameter, branch.table, branch.status
    fixed = {"row", "kind", "s", parameter, "iterations", "step", "seconds", "det_sign", "tangent_parameter",
             "saved_slot"}
    keep = ["kind", parameter] + [c for c in cols if c not in fixed and not c.startswith("monitor:")]
    located = [i for i, k in enumerate(cols["kind"]) if k not in (0, 1)]
    if STEP_FLOOR in status and located and cols["kind"][located[-1]] == 6:
        located = located[:-1]
    os.makedirs(os.path.dirname(ref), exist_ok=True)
    with open(ref, "w") as f:
        f.write(",".join(keep) + "\n")
        for i in located:
            f.write(",".join(f"{cols[c][i]:.17g}" for c in keep) + "\n")
    print(f"{ref}: {len(located)} located points ({status})")


def lines_of(path):
    with open(path) as f:
        return [l.strip() for l in f if l.strip() and not l.startswith("#")]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--keller", default=os.path.join(ROOT, "build", "bin", "keller"))
    ap.add_argument("--only", nargs="*", help="regenerate only these scenes or hard cases (names without .toml)")
    args = ap.parse_args()
    refs = os.path.join(ROOT, "tests", "regression", "references")
    with tempfile.TemporaryDirectory() as tmp:
        for line in lines_of(os.path.join(ROOT, "tests", "regression", "scenes.txt")):
            scene, _, rest = line.partition("|")
            name = os.path.splitext(os.path.basename(scene.strip()))[0]
            if not args.only or name in args.only:
                regenerate(args.keller, scene.strip(), rest.split(), os.path.join(refs, name + ".csv"), tmp)
        for line in lines_of(os.path.join(ROOT, "tests", "regression", "hard_cases.txt")):
            name, scene, rest = (x.strip() for x in line.split("|"))
            if not args.only or name in args.only:
                regenerate(args.keller, scene, rest.split(), os.path.join(refs, "hard", name + ".csv"), tmp)


if __name__ == "__main__":
    sys.exit(main())
