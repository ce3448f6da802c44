"""What the install tests share: running a command, a check that says what it checked, a branch
file's table (by the program's own `export --csv`), installing keller into a moved prefix and
building an example against it with only find_package(keller)."""

import argparse
import csv
import io
import os
import shutil
import subprocess
import sys


def arguments():
    """(build, source, scratch) of the command line --build, --source, --scratch, absolute; the
    scratch folder emptied."""
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--scratch", required=True)
    a = ap.parse_args()
    build, source, scratch = (os.path.abspath(p) for p in (a.build, a.source, a.scratch))
    shutil.rmtree(scratch, ignore_errors=True)
    os.makedirs(scratch)
    return build, source, scratch


def run(*words, cwd=None, expect=0, env=None):
    p = subprocess.run(list(words), cwd=cwd, capture_output=True, text=True, env=env)
    if expect is not None and p.returncode != expect:
        sys.exit(f"FAIL: {' '.join(words)} exited {p.returncode}, expected {expect}\n{p.stdout}\n{p.stderr}")
    return p


def check(ok, what):
    if not ok:
        sys.exit("FAIL: " + what)
    print("ok: " + what)


def table(app, h5, cwd):
    rows = list(csv.DictReader(io.StringIO(run(app, "export", h5, "--csv", "-", cwd=cwd).stdout)))
    return [{k: (v if k == "kind" else float(v)) for k, v in r.items()} for r in rows]


def install_moved(build, scratch):
    """keller installed into scratch/installed, then moved to scratch/moved (the package is
    relocatable); returns the prefix."""
    run("cmake", "--install", build, "--prefix", os.path.join(scratch, "installed"))
    os.rename(os.path.join(scratch, "installed"), os.path.join(scratch, "moved"))
    return os.path.join(scratch, "moved")


def build_example(source, name, prefix, scratch):
    """examples/NAME built against the keller at prefix; returns the program's path."""
    example = os.path.join(source, "examples", name)
    folder = os.path.join(scratch, name)
    run("cmake", "-S", example, "-B", folder, "-DCMAKE_PREFIX_PATH=" + prefix)
    run("cmake", "--build", folder, "-j2")
    return os.path.join(folder, name)
