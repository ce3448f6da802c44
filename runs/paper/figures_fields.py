"""The figures of the reference study drawn from the fields of stored solutions: the contour
figures 8, 12, 15 (v_x, the pressure and M_xx in the deformed channel, the fluids overlaid) and
the profiles along the interface, figures 11, 14, 16 (pressure, M_xx, the stresses on the wall).
figures.py lists them with the others; docs/paper.md says what each shows."""

import numpy as np
from matplotlib.colors import LogNorm
from matplotlib.lines import Line2D

import paper_style as st
from paper_context import GAMMAS, HIGH, MID, stored

# --- contour figures 8, 12, 15 -----------------------------------------------------------------

CASES = [(MID, 0.1), (MID, 0.5), (HIGH, 0.1), (HIGH, 0.5)]
ZOOM = (5.5, 13.5)


def state(ctx, fluid, Gamma, Wi):
    """(branch, stored group) of the M2 state of a fluid at (Gamma, Wi): the Gamma branch at
    Wi = 0.1 (every Newtonian state), the Wi branch otherwise."""
    if fluid == "newtonian" or Wi == 0.1:
        b = ctx.gamma(fluid)
        return b, b.solution(Gamma)
    b = ctx.wi(fluid, Gamma)
    return b, b.solution(Wi)


def contour_panel(ctx, ax, Gamma, Wi, field, levels):
    for fluid in st.FLUIDS:
        b, g = state(ctx, fluid, Gamma, Wi)
        tri, pos = b.triangulation(g)
        values = field(b, g, pos)
        ax.tricontour(tri, values, levels=levels, colors=st.FLUID_COLOUR[fluid], linewidths=0.8)
        s = b.array(g, "interface_shape")
        ax.plot(s[:, 0], s[:, 1], color=st.FLUID_COLOUR[fluid], lw=1.2)
    ax.set_xlim(*ZOOM)
    ax.set_ylim(0, 1.8)
    ax.set_title(f"{st.fmt_value('Gamma', Gamma)}, Wi = {Wi:g}")
    ax.set_xlabel(st.label("x"))
    ax.set_ylabel(st.label("y") + " (stretched)")


def fluids_legend(fig):
    """One legend for the whole figure, above the panels: the colour of each fluid."""
    fig.legend(handles=[Line2D([], [], color=st.FLUID_COLOUR[f], label=st.fluid_label(f)) for f in st.FLUIDS],
               loc="upper center", ncol=4, bbox_to_anchor=(0.5, 0.95))


def fig08(ctx):
    """Contours of v_x / Gamma, four fluids overlaid."""
    levels = [0.5, 1.0, 1.25, 2.0, 3.0, 5.0]  # not 1.5: the inflow maximum, where the contour is ill-defined
    fig, axes = st.figure(2, 2, width=12.0, height=6.4,
                          title="Contours of $v_x / \\Gamma$ (levels " + ", ".join(f"{v:g}" for v in levels)
                                + "; mean inflow velocity 1), four fluids overlaid; the Newtonian fluid has no Wi")
    for ax, (G, Wi) in zip(axes.flat, CASES):
        contour_panel(ctx, ax, G, Wi, lambda b, g, pos, G=G: b.array(g, "velocity")[:, 0] / G, levels)
    fluids_legend(fig)
    return ctx.save(fig, "fig08_vx_contours", rect=(0, 0, 1, 0.93))


def fig12(ctx):
    """Pressure contours, four fluids overlaid."""
    fig, axes = st.figure(2, 2, width=12.0, height=6.4,
                          title="Pressure contours p / G (16 levels between the extremes of the four fluids in the window), "
                                "four fluids overlaid; the Newtonian fluid has no Wi")
    for ax, (G, Wi) in zip(axes.flat, CASES):
        lo, hi = np.inf, -np.inf
        for fluid in st.FLUIDS:
            b, g = state(ctx, fluid, G, Wi)
            _, pos = b.triangulation(g)
            p = b.pressure(g, pos)
            inside = (pos[:, 0] > ZOOM[0]) & (pos[:, 0] < ZOOM[1]) & np.isfinite(p)
            lo, hi = min(lo, np.min(p[inside])), max(hi, np.max(p[inside]))
        levels = np.linspace(lo, hi, 18)[1:-1]
        contour_panel(ctx, ax, G, Wi, lambda b, g, pos: b.pressure(g, pos), levels)
    fluids_legend(fig)
    return ctx.save(fig, "fig12_pressure_contours", rect=(0, 0, 1, 0.93))


def fig15(ctx):
    """Contours of M_xx at Gamma = 1.98e-4, Wi = 0.1, per fluid."""
    fig, axes = st.figure(3, 1, width=8.5, height=7.0,
                          title="$M_{xx}$ at $\\Gamma$ = 1.98e-4, Wi = 0.1 (16 levels, logarithmic, between each fluid's extremes)")
    for ax, fluid in zip(axes[:, 0], st.VISCOELASTIC):
        b, g = state(ctx, fluid, MID, 0.1)
        tri, pos = b.triangulation(g)
        conf = b.conformation(g)
        fluid_nodes = np.isfinite(conf[:, 0])
        lo, hi = np.min(conf[fluid_nodes, 0]), np.max(conf[fluid_nodes, 0])
        levels = np.geomspace(lo, hi, 17)
        mxx = np.clip(np.nan_to_num(conf[:, 0], nan=1.0), lo, hi)
        cs = ax.tricontourf(tri, mxx, levels=levels, norm=LogNorm(lo, hi), cmap="viridis")
        fig.colorbar(cs, ax=ax, fraction=0.03, pad=0.01, label=st.label("Mxx"), format="%.3g")
        ax.set_xlim(*ZOOM)
        ax.set_ylim(0, 1.2)
        ax.set_aspect("equal")
        ax.grid(False)
        ax.set_title(st.fluid_label(fluid) + f": $M_{{xx}}$ from {lo:.3g} to {hi:.3g}")
        ax.set_xlabel(st.label("x"))
        ax.set_ylabel(st.label("y"))
    return ctx.save(fig, "fig15_mxx_contours")


# --- profiles along the interface: figures 11, 14, 16 ------------------------------------------


def profile(ax, branch, pts, colours, column, fmt, marks=False, **kw):
    names = ["x", "y", "p", "tangential_stress", "normal_extra_stress", "Mxx"]
    for (v, g, i), col in zip(pts, colours):
        pr = branch.array(g, "interface_profiles")
        ax.plot(pr[:, 0], pr[:, names.index(column)], color=col, label=None if fmt is None else st.fmt_value(fmt, v),
                **kw)
        if marks:
            ax.axvline(st.WALL_CENTRE + branch["dx_max"][i], color=col, lw=0.7, ls=(0, (2, 2)))


def gamma_points(b):
    rows = {int(r): i for i, r in enumerate(b["row"])}
    by_value = {v: (g, rows[r]) for v, r, g in b.saved}
    out = []
    for G in GAMMAS:
        g = b.solution(G)
        out.append((G, g, next(i for v, (gg, i) in by_value.items() if gg == g)))
    return out


CORNER = 0.3  # stresses within this distance of the ends of the wall (corner singularities) may leave the scale


def profile_axes(ax, title, column):
    """Axes of a profile along the interface; the vertical range is that of the profiles away
    from the corners at x = 7 and 12, where the stresses are singular (they leave the scale)."""
    st.mark_wall(ax)
    curves = [(np.asarray(ln.get_xdata(), float), np.asarray(ln.get_ydata(), float)) for ln in ax.get_lines()
              if len(ln.get_xdata()) > 2]
    if column in ("tangential_stress", "normal_extra_stress", "p"):
        ys = [y[(x > st.WALL_START + CORNER) & (x < st.WALL_END - CORNER)] for x, y in curves]
        ys = np.concatenate(ys)
        lo, hi = np.min(ys), np.max(ys)
        pad = 0.15 * (hi - lo) + 1e-12 * max(abs(lo), abs(hi))
        ax.set_ylim(lo - pad, hi + pad)
    elif column == "Mxx":
        ys = np.concatenate([y for _, y in curves])
        if np.nanmax(ys) > 10 * np.nanmin(ys):
            ax.set_yscale("log")
    ax.set_xlim(st.WALL_START - 0.5, st.WALL_END + 0.5)
    ax.set_title(title)
    ax.set_xlabel(st.label("x"))
    ax.set_ylabel(st.label(column))
    # under the panel, as shape_axes: profiles fill the panel, a legend inside covers some
    ax.legend(ncol=4, fontsize=6, loc="upper center", bbox_to_anchor=(0.5, -0.2), frameon=False,
              columnspacing=1.0, handlelength=1.6)


def fig11(ctx):
    """Pressure along the interface: against Gamma at Wi = 0.1 (Newtonian dashed; vertical marks at
    the x of largest deflection), against Wi at Gamma = 1.98e-4 and 4.95e-4."""
    fig, axes = st.figure(3, 3, width=11.5, height=11.4,
                          title="Pressure along the interface (dotted verticals: x of largest deflection)")
    newt = ctx.gamma("newtonian")
    for c, fluid in enumerate(st.VISCOELASTIC):
        b = ctx.gamma(fluid)
        colours = st.sequence_colours(len(GAMMAS))
        profile(axes[0, c], newt, gamma_points(newt), colours, "p", None, ls="--", lw=0.9)
        profile(axes[0, c], b, gamma_points(b), colours, "p", "Gamma", marks=True)
        profile_axes(axes[0, c], f"{st.fluid_label(fluid)}, Wi = 0.1 (Newtonian dashed)", "p")
        for r, G in ((1, MID), (2, HIGH)):
            w = ctx.wi(fluid, G)
            pts = stored(w)
            profile(axes[r, c], w, pts, st.sequence_colours(len(pts)), "p", "Wi", marks=True)
            profile_axes(axes[r, c], f"{st.fluid_label(fluid)}, {st.fmt_value('Gamma', G)}", "p")
    return ctx.save(fig, "fig11_wall_pressure")


def fig14(ctx):
    """M_xx along the interface against Gamma (Wi = 0.1) and against Wi (Gamma = 4.95e-4)."""
    fig, axes = st.figure(2, 3, width=11.5, height=8.2,
                          title="$M_{xx}$ along the interface: top, Wi = 0.1; bottom, $\\Gamma$ = 4.95e-4")
    for c, fluid in enumerate(st.VISCOELASTIC):
        b = ctx.gamma(fluid)
        profile(axes[0, c], b, gamma_points(b), st.sequence_colours(len(GAMMAS)), "Mxx", "Gamma")
        profile_axes(axes[0, c], f"{st.fluid_label(fluid)}, Wi = 0.1", "Mxx")
        w = ctx.wi(fluid, HIGH)
        pts = stored(w)
        profile(axes[1, c], w, pts, st.sequence_colours(len(pts)), "Mxx", "Wi")
        profile_axes(axes[1, c], f"{st.fluid_label(fluid)}, $\\Gamma$ = 4.95e-4", "Mxx")
    return ctx.save(fig, "fig14_mxx_interface")


def fig16(ctx):
    """Tangential stress and normal extra stress on the interface, against Gamma (Wi = 0.1) and
    against Wi (Gamma = 4.95e-4), per fluid."""
    fig, axes = st.figure(3, 4, width=15.0, height=11.4,
                          title="Stresses on the interface: tangential $t \\cdot \\tau \\cdot n$ and normal extra "
                                "$n \\cdot \\tau \\cdot n$ (t downstream, n out of the fluid; values at the "
                                "corners x = 7, 12 leave the scale)")
    newt = ctx.gamma("newtonian")
    for r, fluid in enumerate(st.VISCOELASTIC):
        b = ctx.gamma(fluid)
        w = ctx.wi(fluid, HIGH)
        pts = stored(w)
        for c, column in enumerate(["tangential_stress", "normal_extra_stress"]):
            colours = st.sequence_colours(len(GAMMAS))
            profile(axes[r, c], newt, gamma_points(newt), colours, column, None, ls="--", lw=0.9)
            profile(axes[r, c], b, gamma_points(b), colours, column, "Gamma")
            profile_axes(axes[r, c], f"{st.fluid_label(fluid)}, Wi = 0.1 (Newtonian dashed)", column)
            profile(axes[r, c + 2], w, pts, st.sequence_colours(len(pts)), column, "Wi")
            profile_axes(axes[r, c + 2], f"{st.fluid_label(fluid)}, $\\Gamma$ = 4.95e-4", column)
    return ctx.save(fig, "fig16_interface_stresses")
