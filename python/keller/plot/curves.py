"""What every figure of a branch shares: the branch drawn as a smooth curve through its points and
their stored tangents, its stable and unstable parts told apart, and the labels of its located
points placed where they overlap nothing.

The smooth curve (`smooth_branch`). A branch file stores per row the arclength s and
`tangent_parameter`, d(parameter)/ds of the unit tangent in the weighted norm that s measures: the
parameter is drawn as the cubic Hermite spline in s with those slopes (through every point, with
the stored slope at every point, so a fold is drawn where the continuation put it: the curve turns
with zero slope near the located fold, not at a polygon corner). The observable has no stored
slope: it is the shape-preserving cubic (PCHIP) in s, which adds no extremum between points. Rows
are sorted by s (a point located by bisection is written after the rows beyond it) and repeated s
dropped. Where a stored slope is not finite, or disagrees in sign with the secants on both sides
(a slope from another norm, or a row whose tangent was not stored), the parameter's slope there is
PCHIP's instead.

The labels (`place_labels`): greedy, in the order given; each label tries a list of offsets from
its point (in points, display coordinates) and takes the first whose text box, as the renderer
draws it, overlaps no label placed before, no marker, stays inside the axes and covers no drawn
curve; when none does, the one with the least overlap (of labels, markers and the frame first,
then of curves). Placed after the figure's layout is final (offsets are in points,
so later layout changes would move the points apart from the labels' tests)."""

import numpy as np
from scipy.interpolate import CubicHermiteSpline, PchipInterpolator

SAMPLES = 24  # samples per segment between two rows


def ordered(s, *columns):
    """The rows sorted by s with repeated s, and rows where a column is not finite (an observable
    not defined there), dropped: (index of the kept rows in the input, s, columns...)."""
    s = np.asarray(s, dtype=float)
    finite = np.isfinite(s)
    for c in columns:
        finite &= np.isfinite(np.asarray(c, dtype=float))
    order = np.nonzero(finite)[0][np.argsort(s[finite], kind="stable")]
    keep = np.concatenate(([True], np.diff(s[order]) > 0)) if len(s) else np.zeros(0, bool)
    idx = order[keep]
    return (idx, s[idx]) + tuple(np.asarray(c, dtype=float)[idx] for c in columns)


def parameter_slopes(s, x, slope):
    """The stored slopes dx/ds, PCHIP's where a stored one is not finite or has the sign of neither
    neighbouring secant (at an end: of its one secant)."""
    s, x = np.asarray(s, float), np.asarray(x, float)
    d = np.full(len(s), np.nan) if slope is None else np.array(slope, dtype=float)
    if len(s) < 2:
        return np.zeros(len(s))
    secant = np.diff(x) / np.diff(s)
    left = np.concatenate(([np.nan], secant))
    right = np.concatenate((secant, [np.nan]))

    def disagrees(sec):  # a secant that is there and has the other sign (a zero agrees with all)
        return ~np.isfinite(sec) | (np.sign(d) * np.sign(sec) < 0)

    bad = ~np.isfinite(d) | (disagrees(left) & disagrees(right))
    if bad.any():
        fallback = PchipInterpolator(s, x).derivative()(s) if len(s) > 2 else np.full(len(s), secant[0])
        d[bad] = fallback[bad]
    return d


def branch_splines(s, x, y, slope=None):
    """(x(s), y(s), rows): the parameter's cubic Hermite spline with the stored slopes (PCHIP's
    where a slope is not usable, parameter_slopes), the observable's PCHIP, over the rows sorted
    by s without repeats (`rows`, their indices into the input)."""
    rows, s, x, y = ordered(s, x, y)
    sl = None if slope is None else np.asarray(slope, dtype=float)[rows]
    if len(s) < 2:
        raise ValueError("a smooth curve needs two points with different s")
    fx = CubicHermiteSpline(s, x, parameter_slopes(s, x, sl))
    fy = PchipInterpolator(s, y) if len(s) > 2 else CubicHermiteSpline(s, y, np.full(2, (y[1] - y[0]) / (s[1] - s[0])))
    return fx, fy, rows


def smooth_branch(s, x, y, slope=None, samples=SAMPLES):
    """The branch as a smooth curve: (s, x, y, segment) sampled `samples` times per segment between
    consecutive rows (in the order of s), segment[j] the index (into the sorted, deduplicated rows)
    of the row a sample's segment starts at; every row is a sample. x is the Hermite spline in s
    with the slopes `slope` (dx/ds, the stored tangent_parameter; None: PCHIP's), y is PCHIP in s.
    Also returns the kept rows' indices into the input (`rows`) as a fifth item."""
    rows, s, x, y = ordered(s, x, y)
    if len(s) < 2:
        return s, x, y, np.zeros(len(s), int), rows
    fx, fy, _ = branch_splines(s, x, y, None if slope is None else np.asarray(slope, dtype=float)[rows])
    t = np.linspace(0.0, 1.0, samples + 1)[:-1]
    ss = np.concatenate([s[:-1, None] + t[None, :] * np.diff(s)[:, None]]).ravel()
    ss = np.concatenate((ss, s[-1:]))
    seg = np.concatenate((np.repeat(np.arange(len(s) - 1), samples), [len(s) - 2]))
    xs, ys = fx(ss), fy(ss)
    at_rows = np.arange(0, len(ss), samples)  # exactly the rows' values (no rounding of the splines)
    xs[at_rows], ys[at_rows] = x, y
    return ss, xs, ys, seg, rows


STYLES = {"stable": "-", "unstable": "--", "not analysed": ":"}


def segment_states(unstable):
    """The state of each segment between consecutive rows from the rows' unstable counts: unstable
    where either end is, not analysed where an end is NaN and neither is unstable, else stable."""
    u = np.asarray(unstable, dtype=float)
    a, b = u[:-1], u[1:]
    state = np.where((a > 0) | (b > 0), "unstable", np.where(np.isnan(a) | np.isnan(b), "not analysed", "stable"))
    return state


def draw_branch(ax, s, x, y, slope=None, unstable=None, color="0.3", lw=1.4, label=None, zorder=1):
    """Draws a branch smoothly (smooth_branch); with `unstable` (a count per row) solid where stable,
    dashed where unstable, dotted where not analysed. Returns the set of states drawn (for a legend
    entry each) and the line of the curve's label (the first one drawn)."""
    ss, xs, ys, seg, rows = smooth_branch(s, x, y, slope)
    if unstable is None or len(rows) < 2:
        line, = ax.plot(xs, ys, "-", color=color, lw=lw, zorder=zorder, label=label)
        return set(), line
    state = segment_states(np.asarray(unstable, dtype=float)[rows])
    drawn, first = set(), None
    # runs of segments in the same state, each one line (the runs share their end samples)
    start = 0
    for k in range(1, len(state) + 1):
        if k == len(state) or state[k] != state[start]:
            sel = (seg >= start) & (seg < k)
            idx = np.nonzero(sel)[0]
            idx = np.append(idx, min(idx[-1] + 1, len(xs) - 1))
            line, = ax.plot(xs[idx], ys[idx], STYLES[state[start]], color=color, lw=lw, zorder=zorder,
                            label=label if first is None else None)
            first = first or line
            drawn.add(state[start])
            start = k
    return drawn, first


OFFSETS = [(6, 6), (6, -12), (-6, 6), (-6, -12), (0, 12), (0, -16), (10, -3), (-10, -3)]


def _overlap(a, b):
    w = min(a.x1, b.x1) - max(a.x0, b.x0)
    h = min(a.y1, b.y1) - max(a.y0, b.y0)
    return w * h if w > 0 and h > 0 else 0.0


def place_labels(ax, points, texts, colors=None, marker_px=6.0, fontsize=8, offsets=None):
    """Labels each point (data coordinates) with its text, greedily: the first offset (points) of
    `offsets` (default OFFSETS, then the same twice and three times as far) whose text box overlaps
    no placed label and no marker (a square of half-side marker_px pixels round each point) and
    stays inside the axes and covers no drawn curve, else the one of least overlap (an overlap of
    labels, markers or the frame outweighs any number of curve samples). Returns the annotations."""
    fig = ax.figure
    renderer = fig.canvas.get_renderer()
    base = offsets or OFFSETS
    tries = [(dx * f, dy * f) for f in (1, 2, 3) for dx, dy in base]
    disp = ax.transData.transform(np.asarray(points, dtype=float).reshape(-1, 2)) if len(points) else []
    from matplotlib.transforms import Bbox

    r = marker_px * fig.dpi / 72.0
    markers = [Bbox.from_extents(px - r, py - r, px + r, py + r) for px, py in disp]
    frame = ax.get_window_extent(renderer)
    # the drawn curves: a label should not hide them either (a lesser fault than an overlap)
    curve = [ax.transData.transform(np.column_stack(line.get_data()).astype(float)) for line in ax.get_lines()
             if len(line.get_xdata())]
    curve = np.concatenate(curve) if curve else np.zeros((0, 2))
    curve = curve[np.isfinite(curve).all(axis=1)]
    placed, out = [], []
    for k, ((x, y), text) in enumerate(zip(points, texts)):
        color = colors[k] if colors else "black"
        best = None
        for dx, dy in tries:
            ann = ax.annotate(text, (x, y), textcoords="offset points", xytext=(dx, dy), fontsize=fontsize,
                              color=color, ha="left" if dx >= 0 else "right", va="bottom" if dy >= 0 else "top",
                              zorder=5)
            box = ann.get_window_extent(renderer)
            cost = sum(_overlap(box, b) for b in placed) + sum(_overlap(box, m) for m in markers)
            outside = box.x0 < frame.x0 or box.x1 > frame.x1 or box.y0 < frame.y0 or box.y1 > frame.y1
            cost += (box.width * box.height) if outside else 0.0
            cost = 1e6 * cost + np.count_nonzero((curve[:, 0] > box.x0) & (curve[:, 0] < box.x1) &
                                                 (curve[:, 1] > box.y0) & (curve[:, 1] < box.y1))
            if best is None or cost < best[0]:
                if best is not None:
                    best[1].remove()
                best = (cost, ann, box)
            else:
                ann.remove()
            if cost == 0:
                break
        placed.append(best[2])
        out.append(best[1])
    return out


def boxes_overlap(annotations):
    """Whether any two of the annotations' text boxes overlap (as drawn)."""
    renderer = annotations[0].figure.canvas.get_renderer() if annotations else None
    boxes = [a.get_window_extent(renderer) for a in annotations]
    return any(_overlap(boxes[i], boxes[j]) > 0 for i in range(len(boxes)) for j in range(i))
