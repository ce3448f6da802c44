"""keller's commands in this Python process: keller.solve, trace, evolve and study (docs/python.md).

Each takes a scene (a TOML file, or a dict of the same sections and keys), writes the same files as
the command line, point by point and crash-safe, and returns what it wrote as an object of
keller.open. Overrides are the command line's `--set`, validated the same way:

    branch = keller.trace("runs/scenes/bratu1d_fold.toml", "bratu.h5",
                          set={"bratu.intervals": 200}, callback=lambda point: print(point.values))

A callback gets a Point per branch point (trace) or accepted step (evolve), after it is written;
returning False stops the run as Ctrl-C does: the run keeps what it completed in OUT.h5.part, the
call returns it (opened, its status `interrupted ...`), and the same call again continues it. Ctrl-C
stops the run after its current point and raises KeyboardInterrupt. Bad input raises KellerError
with keller's message (file, key, what is allowed) and writes nothing. `problem=` runs a problem
written in Python (keller.Problem): its scene's [problem] type is "python".
"""

import dataclasses
import io
import json
import math
import os
import shutil
import sys
import tempfile
import threading
import tomllib

from keller.results import open as open_result


class KellerError(RuntimeError):
    """A command that keller refused or that failed: `code` is its exit code (2 bad input, 1 a
    numerical failure, 3 a file that could not be written, 4 an internal error) and the message is
    keller's."""

    def __init__(self, code, message, path=None):
        super().__init__(message)
        self.code = code
        self.path = path


@dataclasses.dataclass
class Point:
    """What a callback gets: the command ("trace" or "evolve"), the branch row or step, the kind
    ("point", "start", "stop", "event", "fold", "bp", "end", "hopf", "pd", "ns"; "step"), a located point's
    label (its monitor or bound), the values by name (the parameter or t first, the observables,
    the monitors) and the state u."""

    command: str
    row: int
    kind: str
    label: str
    values: dict
    u: object

    def __getitem__(self, name):
        return self.values[name]


def _extension():
    try:
        from keller import _keller
    except ImportError as e:
        raise ImportError(
            f"keller's C++ module (keller._keller) cannot be imported by {sys.executable} (Python "
            f"{sys.version.split()[0]}): {e}. It is made by keller's build (cmake --build build) for the Python "
            f"the build found (/usr/bin/python3 on Debian); another python3 must be the same minor version.") from e
    return _extension_configured(_keller)


_configured = []


def _extension_configured(module):
    if not _configured:
        program = keller_program()
        if program:
            module.set_task_program(program)
        _configured.append(True)
    return module


def keller_program():
    """The keller program of this package (a study's tasks run in it): $KELLER_EXE, else the one of
    the build or installation the package belongs to, else `keller` on the PATH; None if none."""
    if os.environ.get("KELLER_EXE"):
        return os.environ["KELLER_EXE"]
    here = os.path.dirname(os.path.abspath(__file__))
    for relative in ("../../bin/keller", "../../../../bin/keller", "../../../bin/keller"):
        candidate = os.path.normpath(os.path.join(here, relative))
        if os.path.isfile(candidate) and os.access(candidate, os.X_OK):
            return candidate
    return shutil.which("keller")


# --- scenes from dicts ---

def _toml_value(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if hasattr(value, "item"):  # a numpy scalar
        return _toml_value(value.item())
    raise TypeError(f"a scene value must be a number, string, bool or list, not {type(value).__name__}: {value!r}")


def _flat(scene, prefix=""):
    for key, value in scene.items():
        if isinstance(value, dict):
            yield from _flat(value, f"{prefix}{key}.")
        else:
            yield f"{prefix}{key}", value


def _nested(scene):
    """A scene dict with sections as nested dicts or dotted keys ("mesh.name"), as nested dicts."""
    out = {}
    for dotted, value in _flat(scene):
        *sections, key = dotted.split(".")
        node = out
        for name in sections:
            node = node.setdefault(name, {})
            if not isinstance(node, dict):
                raise ValueError(f"scene key '{dotted}': '{name}' is a value, not a section")
        node[key] = value
    return out


def toml_text(scene):
    """The TOML text of a scene dict (sections as nested dicts or dotted keys)."""
    lines = []

    def section(name, table):
        values = [(k, v) for k, v in table.items() if not isinstance(v, dict)]
        if values or not name:
            if name:
                lines.append(f"[{name}]")
            lines.extend(f"{k} = {_toml_value(v)}" for k, v in values)
            lines.append("")
        for k, v in table.items():
            if isinstance(v, dict):
                section(f"{name}.{k}" if name else k, v)

    section("", _nested(scene))
    return "\n".join(lines)


# --- running a command ---

class _Output:
    """keller writes to the process's file descriptors 1 and 2; they are forwarded to Python's
    sys.stdout and sys.stderr (a notebook's cells), stdout only where `verbose`, and stderr is
    kept for the message of a KellerError."""

    def __init__(self, verbose):
        self.verbose = verbose
        self.errors, self.endings = [], []

    def __enter__(self):
        sys.stdout.flush()
        sys.stderr.flush()
        self.saved = {fd: os.dup(fd) for fd in (1, 2)}
        # Python's own writes while the command runs (a callback's print) go where they went
        self.streams = {}
        for fd, stream in ((1, "stdout"), (2, "stderr")):
            if _uses_fd(getattr(sys, stream), fd):
                self.streams[stream] = getattr(sys, stream)
                setattr(sys, stream, io.TextIOWrapper(io.FileIO(self.saved[fd], "w", closefd=False),
                                                      encoding=self.streams[stream].encoding, line_buffering=True))
        self.threads = []
        for fd, stream in ((1, "stdout"), (2, "stderr")):
            r, w = os.pipe()
            os.dup2(w, fd)
            os.close(w)
            t = threading.Thread(target=self._pump, args=(r, fd, stream), daemon=True)
            t.start()
            self.threads.append(t)
        return self

    def _pump(self, r, fd, stream):
        with os.fdopen(r, "rb", buffering=0) as pipe:
            for line in iter(pipe.readline, b""):
                text = line.decode(errors="replace")
                if fd == 2:
                    self.errors.append(text)
                elif "ended" in text or "failed" in text:
                    self.endings.append(text)  # why a run ended: the message of a numerical failure
                if fd == 2 or self.verbose:
                    if stream in self.streams:  # a terminal or file: straight to where fd pointed before
                        os.write(self.saved[fd], line)
                    else:  # a notebook's cell
                        target = getattr(sys, stream)
                        target.write(text)
                        target.flush()

    def __exit__(self, *exc):
        for stream, original in self.streams.items():
            getattr(sys, stream).flush()
            setattr(sys, stream, original)
        for fd in (1, 2):
            os.dup2(self.saved[fd], fd)  # closes the pipe's write end: the pump reads its end
        for t in self.threads:
            t.join()
        for fd in (1, 2):
            os.close(self.saved[fd])
        return False


def _uses_fd(stream, fd):
    """Whether a Python stream writes to the file descriptor fd (a terminal or file; not a notebook's)."""
    try:
        return stream.fileno() == fd
    except (AttributeError, OSError, ValueError):
        return False


def _row(start):
    """FILE.h5:ROW of a start given as text, or as (file or result object, row or label)."""
    if start is None or isinstance(start, str):
        return start
    where, row = start
    return f"{getattr(where, 'path', where)}:{row}"


def _run(command, scene, output, *, overrides, options, problem, callback, verbose):
    module = _extension()
    with tempfile.TemporaryDirectory(prefix="keller-scene-") as folder:
        scene_path, output = _scene_file(scene, output, folder, problem, command)
        args = [command, scene_path] + (["-o", os.fspath(output)] if output else [])
        for key, value in (overrides or {}).items():
            args += ["--set", f"{key}={_toml_value(value)}"]
        args += options
        wrapped = None
        if callback is not None:
            def wrapped(d):
                return callback(Point(d["command"], d["row"], d["kind"], d["label"], d["values"], d["u"]))
        with _Output(verbose) as out:
            code, stopped, interrupted = module.run(args, wrapped, problem)
        message = "".join(out.errors).strip() or "".join(out.endings[-2:]).strip()
        if not isinstance(scene, (str, os.PathLike)):
            message = message.replace(scene_path, "the scene dict")
    if output is None:
        output = os.path.splitext(os.path.basename(scene_path))[0] + ".h5"
    if code == 0:
        return output
    if code == 130 and interrupted:
        raise KeyboardInterrupt(f"keller {command} interrupted: what it completed is kept in {output}.part; "
                                f"the same call continues it")
    if code == 130 and stopped:
        return os.fspath(output) + ".part"
    raise KellerError(code, message or f"keller {command} ended with exit code {code}", output)


def _scene_file(scene, output, folder, problem, command):
    if isinstance(scene, (str, os.PathLike)):
        path = os.fspath(scene)
        if problem is not None:
            try:
                with open(path, "rb") as f:
                    declared = tomllib.load(f).get("problem", {}).get("type")
            except (OSError, tomllib.TOMLDecodeError):
                declared = "python"  # keller says what is wrong with the file
            if declared != "python":
                raise ValueError(f"{path}: [problem] type is {declared!r}; a scene run with problem= has type = \"python\"")
        return path, output
    if not isinstance(scene, dict):
        raise TypeError(f"a scene is a TOML file's path or a dict, not {type(scene).__name__}")
    if output is None:
        raise ValueError(f"keller.{command} with a scene dict needs output=, the file to write")
    scene = dict(scene)
    if problem is not None:
        nested = _nested(scene)
        if nested.get("problem", {}).get("type", "python") != "python":
            raise ValueError(f"the scene's [problem] type is {nested['problem']['type']!r}; a scene run with problem= "
                             f"has type = \"python\"")
        scene = nested
        scene.setdefault("problem", {})["type"] = "python"
    stem = os.path.splitext(os.path.basename(os.fspath(output)))[0] or "scene"
    path = os.path.join(folder, stem + ".toml")
    with open(path, "w") as f:
        f.write(toml_text(scene))
    return path, output


def solve(scene, output=None, *, set=None, problem=None, check_jacobian=False, verbose=True):
    """keller solve: one steady state (a keller.Solution). check_jacobian: J and dF/dp against
    differences first (a wrong one is a KellerError, exit 1)."""
    options = ["--check-jacobian"] if check_jacobian else []
    path = _run("solve", scene, output, overrides=set, options=options, problem=problem, callback=None,
                verbose=verbose)
    return open_result(path)


def trace(scene, output=None, *, set=None, restart=None, switch=None, direction=None, curve=None, curve_from=None,
          free=None, orbit_from=None, orbit_switch=None, fresh=False, force=False, problem=None, callback=None,
          verbose=True):
    """keller trace: a branch (a keller.Branch; a keller.Curve with curve=). restart and switch
    ("FILE.h5:ROW", or (branch, row or label)) start from a stored point or switch at a branch
    point (direction: 1 or -1); curve ("fold", "hopf", "event") with curve_from continues a
    located point in a second parameter (free); orbit_from (a located Hopf point) traces the branch
    of periodic orbits born there (keller trace --orbit), or, given as the path of a keller evolve
    run on a limit cycle, the branch through its last state; orbit_switch (a period doubling of an
    orbit branch, "ORBITS.h5:pd1" or (branch, "pd1")) the doubled branch born there (keller trace
    --orbit --switch); fresh discards an unfinished OUT.h5.part; force starts from a stored point
    that differs from the scene."""
    if orbit_from is not None and curve_from is not None:
        raise ValueError("orbit_from and curve_from exclude each other")
    if orbit_switch is not None and (switch is not None or orbit_from is not None):
        raise ValueError("orbit_switch excludes switch and orbit_from")
    options = []
    for flag, value in (("--restart", _row(restart)), ("--switch", _row(switch if orbit_switch is None else orbit_switch)),
                        ("--from", _row(curve_from if orbit_from is None else orbit_from)),
                        ("--curve", curve), ("--free", free),
                        ("--switch-direction", None if direction is None else str(int(direction)))):
        if value is not None:
            options += [flag, value]
    options += ["--orbit"] if orbit_from is not None or orbit_switch is not None else []
    options += ["--fresh"] if fresh else []
    options += ["--force"] if force else []
    path = _run("trace", scene, output, overrides=set, options=options, problem=problem, callback=callback,
                verbose=verbose)
    return open_result(path)


def evolve(scene, output=None, *, set=None, restart=None, fresh=False, force=False, problem=None, callback=None,
           verbose=True):
    """keller evolve: B du/dt = -F in time (a keller.TimeSeries); restart ("FILE.h5:ROW" of a
    branch, or (branch, row)) starts from a stored steady state."""
    options = []
    if restart is not None:
        options += ["--restart", _row(restart)]
    options += ["--fresh"] if fresh else []
    options += ["--force"] if force else []
    path = _run("evolve", scene, output, overrides=set, options=options, problem=problem, callback=callback,
                verbose=verbose)
    return open_result(path)


def study(study_file, output=None, *, jobs=None, verbose=True):
    """keller study: the tasks of a study file, each in its own keller process (keller_program()),
    `jobs` at a time; returns the collected table (a keller.Study)."""
    module = _extension()
    args = ["study", os.fspath(study_file)]
    if output is not None:
        args += ["-o", os.fspath(output)]
    if jobs is not None:
        args += ["--jobs", str(int(jobs))]
    with _Output(verbose) as out:
        code, _, interrupted = module.run(args, None, None)
    folder = os.fspath(output) if output else os.path.splitext(os.path.basename(os.fspath(study_file)))[0]
    if code == 130 and interrupted:
        raise KeyboardInterrupt(f"keller study interrupted: the same call continues it ({folder})")
    if code != 0:
        raise KellerError(code, "".join(out.errors).strip() or f"keller study ended with exit code {code}", folder)
    return open_result(folder)
