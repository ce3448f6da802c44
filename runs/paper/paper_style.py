"""One style for the figures of runs/paper: a colour per fluid, a line style per mesh, a colour
map for a sequence of parameter values, axis labels that carry the quantity and its scaling
(model.md: lengths in W, pressures and stresses in G, velocities in G W / eta0, so the mean
inflow velocity is Gamma), and saving through a temporary name (keller.outputs.save_figure)."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from keller.labels import quantity  # noqa: E402
from keller.outputs import save_figure  # noqa: E402
from keller.plot.curves import draw_branch  # noqa: E402

FLUIDS = ["newtonian", "oldroyd-b", "fene-p", "owens"]
VISCOELASTIC = FLUIDS[1:]
FLUID_NAME = {"newtonian": "Newtonian", "oldroyd-b": "Oldroyd-B", "fene-p": "FENE-P (b = 100)", "owens": "Owens"}
FLUID_COLOUR = {"newtonian": "0.2", "oldroyd-b": "tab:blue", "fene-p": "tab:green", "owens": "tab:red"}
FLUID_MARKER = {"newtonian": "s", "oldroyd-b": "o", "fene-p": "^", "owens": "D"}
MESH_STYLE = {"M1": ":", "M2": "-", "M3": "--", "M4": "-.", "M5": (0, (5, 1, 1, 1))}

# the channel (model.md): the deformable section runs from x = 7 to 12, its centre at 9.5
WALL_START, WALL_END, WALL_CENTRE = 7.0, 12.0, 9.5

# labels of the quantities the figures draw beyond keller.labels.QUANTITIES
LABEL = {
    "x": "x / W",
    "y": "y / W",
    "p": "pressure p / G",
    "Mxx": "$M_{xx}$",
    "tangential_stress": "tangential stress $t \\cdot \\tau \\cdot n$ / G",
    "normal_extra_stress": "normal extra stress $n \\cdot \\tau \\cdot n$ / G",
    "limiting_wi": "limiting Wi (min $m_1$ = 0)",
}


def label(name):
    """The axis label of a quantity: its name, what it is and its scaling."""
    return LABEL.get(name) or quantity(name)


def setup():
    """The shared rcParams: sizes that stay legible at the width of docs/paper.md."""
    plt.rcParams.update({
        "font.size": 9, "axes.titlesize": 9, "axes.labelsize": 9, "legend.fontsize": 7, "xtick.labelsize": 8,
        "ytick.labelsize": 8, "figure.titlesize": 10, "axes.grid": True, "grid.alpha": 0.3, "lines.linewidth": 1.3,
        "legend.framealpha": 0.85, "savefig.dpi": 130,
    })


def fluid_label(fluid, mesh=None):
    return FLUID_NAME[fluid] + (f", {mesh}" if mesh else "")


def sequence_colours(n, cmap="viridis"):
    """n colours along a colour map, for a sequence of parameter values (dark to light)."""
    m = plt.get_cmap(cmap)
    return [m(0.9 * k / max(1, n - 1)) for k in range(n)]


def branch_line(ax, b, x, y, **kw):
    """A branch's y against x drawn smoothly through its points (keller.plot.curves): against its
    parameter with the stored tangents, against another column (a path) shape-preserving in s."""
    slope = b["tangent_parameter"] if x == b.parameter and "tangent_parameter" in b.cols else None
    colour = kw.pop("color", "0.3")
    ls = kw.pop("ls", "-")
    _, line = draw_branch(ax, b["s"], b[x], b[y], slope, color=colour, lw=kw.pop("lw", 1.3), label=kw.pop("label", None))
    line.set_linestyle(ls)
    return line


def fmt_value(name, v):
    """'Gamma = 4.95e-4', 'Wi = 0.5', 't = 0.2'."""
    symbol = "$\\Gamma$" if name == "Gamma" else name
    return f"{symbol} = {short(v)}"


def short(v):
    """A number as a reader writes it: 0.5, 4.95e-4, 3e-4."""
    if v == 0 or 1e-3 <= abs(v) < 1e4:
        return f"{v:.3g}"
    mantissa, exponent = f"{v:.2e}".split("e")
    return f"{mantissa.rstrip('0').rstrip('.')}e{int(exponent)}"


def figure(rows, cols, width=None, height=None, title=None, **kw):
    """A figure of rows x cols panels with the shared style; title is the figure's suptitle."""
    fig, axes = plt.subplots(rows, cols, figsize=(width or 3.6 * cols + 0.4, height or 2.8 * rows + 0.5),
                             squeeze=False, **kw)
    if title:
        fig.suptitle(title)
    return fig, axes


def mark_wall(ax):
    """Thin vertical lines at the ends of the deformable section."""
    for x in (WALL_START, WALL_END):
        ax.axvline(x, color="0.6", lw=0.6, ls=":", zorder=0)


def save(fig, path, inputs=(), rect=None):
    """Lays the figure out (in rect of the figure, if given) and writes it through PATH.part
    (check_outputs, then rename)."""
    fig.tight_layout(rect=rect)
    save_figure(fig, path, inputs)
    plt.close(fig)
    return path
