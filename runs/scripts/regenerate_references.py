#!/usr/bin/env python3
"""Regenerates the regression references: runs every scene listed in
tests/regression/scenes.txt through `keller trace` (with its coarse overrides) and writes the
located points (folds, events, requested values, branch points, ends) of each branch to
tests/regression/references/<scene>.csv.

Run it on purpose, after a change that is meant to move the numbers, and say why in the
commit:  python3 runs/scripts/regenerate_references.py [--keller build/bin/keller] [--only SCENE ...]"""

import argparse
import os
import subprocess
import sys
import tempfile

from keller_h5 import read_branch

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--keller", default=os.path.join(ROOT, "build", "bin", "keller"))
    ap.add_argument("--only", nargs="*", help="regenerate only these scenes (names without .toml)")
    args = ap.parse_args()
    with open(os.path.join(ROOT, "tests", "regression", "scenes.txt")) as f:
        lines = [l.strip() for l in f if l.strip() and not l.startswith("#")]
    with tempfile.TemporaryDirectory() as tmp:
        for line in lines:
            scene, _, rest = line.partition("|")
            scene = scene.strip()
            name = os.path.splitext(os.path.basename(scene))[0]
            if args.only and name not in args.only:
                continue
            out = os.path.join(tmp, name + ".h5")
            cmd = [args.keller, "trace", os.path.join(ROOT, scene), "-o", out]
            for o in rest.split():
                cmd += ["--set", o]
            subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
            parameter, cols, status = read_branch(out)
            fixed = {"row", "kind", "s", parameter, "iterations", "step", "seconds", "det_sign", "tangent_parameter",
                     "saved_slot"}
            keep = ["kind", parameter] + [c for c in cols if c not in fixed and not c.startswith("monitor:")]
            located = [i for i, k in enumerate(cols["kind"]) if k not in (0, 1)]
            ref = os.path.join(ROOT, "tests", "regression", "references", name + ".csv")
            with open(ref, "w") as f:
                f.write(",".join(keep) + "\n")
                for i in located:
                    f.write(",".join(f"{cols[c][i]:.17g}" for c in keep) + "\n")
            print(f"{ref}: {len(located)} located points ({status})")


if __name__ == "__main__":
    sys.exit(main())
