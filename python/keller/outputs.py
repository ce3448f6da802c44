"""The rules of every file keller writes (core/RunFiles), kept by the figures the package writes:
no output is an input or another output, and a figure takes its name only once complete."""

import os


class OutputError(Exception):
    """An output path that keller's rules refuse (it would overwrite an input, or is not a file)."""


def _same_file(a, b):
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.realpath(a) == os.path.realpath(b)


def check_outputs(outputs, inputs=()):
    """The rules of every file keller writes (core/RunFiles): no output is an input or another
    output (compared by file identity, so ./, .., symbolic and hard links are seen through), and
    a target is a regular file or absent, in an existing folder. Raises OutputError."""
    for i, out in enumerate(outputs):
        if os.path.lexists(out) and not (os.path.isfile(out) and not os.path.islink(out)):
            raise OutputError(f"output '{out}' is not a regular file (a link, directory, FIFO or device)")
        folder = os.path.dirname(out) or "."
        if not os.path.isdir(folder):
            raise OutputError(f"output '{out}': folder '{folder}' does not exist")
        for inp in inputs:
            if _same_file(out, inp):
                raise OutputError(f"output '{out}' is the same file as the input '{inp}'; write to another file")
        for other in outputs[:i]:
            if _same_file(out, other):
                raise OutputError(f"outputs '{other}' and '{out}' are the same file")


def save_figure(fig, path, inputs=(), **savefig_args):
    """Saves a matplotlib figure under PATH.part and renames it to PATH once complete, after
    checking PATH against the inputs (check_outputs)."""
    check_outputs([path], inputs)
    fmt = os.path.splitext(path)[1].lstrip(".") or "png"
    tmp = path + ".part"
    try:
        fig.savefig(tmp, format=fmt, **savefig_args)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
