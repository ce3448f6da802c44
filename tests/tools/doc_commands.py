#!/usr/bin/env python3
"""Runs the shell commands of the user guide (README.md and docs/**/*.md), as they are written,
so that a documented command cannot rot.

Every fenced block marked ```sh is taken, its lines joined where they end in a backslash; each
line that is not empty or a comment is a command. The commands of one markdown file run in
order, in one scratch folder of their own (later commands read what earlier ones wrote), with
`build/bin/keller` the keller under test, `runs/` the repository's, `python3` the configured
Python, and must exit 0. The keller Python package is the build's (--python-path, the folder
holding `keller/`): PYTHONPATH is set to it for every command, and a command's own
`PYTHONPATH=build/python` means it too (`build/python` is a link to it in the scratch folder).

A command too long for CI (a study of minutes, a benchmark against another program, a build)
says so in its comment, with the reason:

    build/bin/keller study runs/studies/x.toml --jobs 2   # not run in CI: 40 minutes on 2 cores
    build/bin/keller study run x.toml --task 7            # one task (not run in CI: a minute)

and a whole block says so in an HTML comment on the line before its fence:

    <!-- not run in CI: the install and build that CI has just done -->

The scenes and scripts a command that is not run names (`runs/...`, `.ci/...`) must still exist.
Nothing else is changed or substituted: a documented command that CI runs is run as written.

Usage: doc_commands.py --source ROOT --keller BINARY --python PYTHON [--python-path DIR] --scratch DIR
       [--list] [FILE.md ...]
(default: README.md and every docs/**/*.md; --list prints the commands and what is run)."""

import argparse
import glob
import os
import re
import shlex
import shutil
import subprocess
import sys
import time

SKIP_LINE = re.compile(r"#[^#]*?not run in CI:\s*([^)]*[^)\s])")
SKIP_BLOCK = re.compile(r"<!--\s*not run in CI:\s*(\S.*?)\s*-->")
SOURCE_PATH = re.compile(r"^(runs|\.ci)/")


class Command:
    def __init__(self, md, line, text, skip):
        self.md, self.line, self.text, self.skip = md, line, text, skip

    def where(self):
        return f"{self.md}:{self.line}"


def commands_of(md_path, rel):
    """The commands of the ```sh blocks of a markdown file, with why each is not run (or None)."""
    out = []
    lines = open(md_path, encoding="utf-8").read().split("\n")
    i = 0
    while i < len(lines):
        if lines[i].strip() != "```sh":
            i += 1
            continue
        block_skip = None
        if i > 0:
            m = SKIP_BLOCK.search(lines[i - 1])
            if m:
                block_skip = m.group(1)
        i += 1
        pending, start = "", None
        while i < len(lines) and lines[i].strip() != "```":
            line = lines[i]
            if start is None:
                start = i + 1
            if line.endswith("\\"):
                pending += line[:-1] + " "
            else:
                text = (pending + line).strip()
                pending = ""
                if text and not text.startswith("#"):
                    m = SKIP_LINE.search(text)
                    out.append(Command(rel, start, text, block_skip or (m.group(1) if m else None)))
                start = None
            i += 1
        if i >= len(lines):
            raise SystemExit(f"{rel}: a ```sh block is not closed")
        i += 1
    return out


def check_paths(cmd, source):
    """The source paths a command names (scenes, scripts, studies) exist."""
    try:
        words = shlex.split(cmd.text, comments=True)
    except ValueError as e:
        return [f"{cmd.where()}: not a shell command ({e}): {cmd.text}"]
    missing = []
    for w in words:
        if SOURCE_PATH.match(w) and not glob.glob(os.path.join(source, w)):
            missing.append(f"{cmd.where()}: '{w}' does not exist in the repository: {cmd.text}")
    return missing


def prepare(scratch, source, keller, python, python_path=None):
    """An empty scratch folder in which the documented paths mean the ones under test (the
    build's python folder too, where given)."""
    shutil.rmtree(scratch, ignore_errors=True)
    os.makedirs(os.path.join(scratch, "build", "bin"), exist_ok=True)
    os.makedirs(os.path.join(scratch, ".bin"), exist_ok=True)
    os.makedirs(os.path.join(scratch, "docs", "figures"), exist_ok=True)  # where documented figures go
    links = [(os.path.join(scratch, "build", "bin", "keller"), keller),
             (os.path.join(scratch, "runs"), os.path.join(source, "runs")),
             (os.path.join(scratch, ".bin", "python3"), python)]
    if python_path:
        links.append((os.path.join(scratch, "build", "python"), python_path))
    for link, target in links:
        if os.path.lexists(link):
            os.remove(link)
        os.symlink(os.path.abspath(target), link)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--source", required=True)
    ap.add_argument("--keller", required=True)
    ap.add_argument("--python", default=sys.executable)
    ap.add_argument("--python-path", help="the folder holding the keller Python package (the build's python/)")
    ap.add_argument("--scratch", required=True)
    ap.add_argument("--list", action="store_true", help="print the commands and whether they run; run nothing")
    ap.add_argument("files", nargs="*")
    a = ap.parse_args()
    source = os.path.abspath(a.source)
    files = a.files or ["README.md"] + sorted(
        os.path.relpath(p, source) for p in glob.glob(os.path.join(source, "docs", "**", "*.md"), recursive=True))

    problems, plan = [], []
    for rel in files:
        for cmd in commands_of(os.path.join(source, rel), rel):
            plan.append(cmd)
            if cmd.skip is not None:
                problems += check_paths(cmd, source)
    if a.list:
        for cmd in plan:
            print(f"{cmd.where()}: {'not run: ' + cmd.skip if cmd.skip else 'runs'}\n    {cmd.text}")
        return 0
    for p in problems:
        print(p)

    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", MPLBACKEND="Agg")
    if a.python_path:
        env["PYTHONPATH"] = os.path.abspath(a.python_path)
    failed = len(problems)
    ran = skipped = 0
    t0 = time.monotonic()
    for rel in files:
        cmds = [c for c in plan if c.md == rel]
        if not cmds:
            continue
        folder = os.path.join(os.path.abspath(a.scratch), rel.replace("/", "_").replace(".md", ""))
        prepare(folder, source, a.keller, a.python, a.python_path)
        env["PATH"] = os.path.join(folder, ".bin") + os.pathsep + os.environ.get("PATH", "")
        for cmd in cmds:
            if cmd.skip is not None:
                skipped += 1
                print(f"{cmd.where()}: not run in CI ({cmd.skip})")
                continue
            start = time.monotonic()
            p = subprocess.run(["sh", "-c", cmd.text], cwd=folder, env=env, stdin=subprocess.DEVNULL,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            ran += 1
            seconds = time.monotonic() - start
            print(f"{cmd.where()}: exit {p.returncode} in {seconds:.1f} s: {cmd.text}", flush=True)
            if p.returncode != 0:
                failed += 1
                print("    " + "\n    ".join(p.stdout.rstrip().split("\n")[-30:]))
    print(f"{ran} documented commands run, {skipped} not run in CI, {failed} failed, "
          f"{time.monotonic() - t0:.0f} s")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
