"""The figures of the reference study (Chakraborty and Prakash's collapsible channel), one
function each, drawn from the studies of runs/paper (make_all.py runs them first). Every figure
reads only keller's HDF5 files and writes FIGURES/figNN_name.png; docs/paper.md says what each
shows. M2, Pe = 0.04, t = 0.4, b = 100 unless a figure says otherwise."""

import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.colors import LogNorm
from matplotlib.lines import Line2D

import paper_style as st
from keller.plot.curves import draw_branch
from paper_data import Study

GAMMAS = [4.95e-5, 1.98e-4, 3.0e-4, 3.96e-4, 4.95e-4, 6.6e-4]
LOW, MID, HIGH = 4.95e-5, 1.98e-4, 4.95e-4
KINDS_DRAWN = (1, 2, 3, 6)  # start, requested value, event, end: the stored points a figure draws

# "Mesh converged" (figure 5): the largest Wi up to which two meshes agree in min m1 to
# CONVERGED_M1 (absolute: min m1 goes to zero at the limit; 5% of its value at rest) and in dP to
# CONVERGED_DP (relative). With 0.02 the corner of the bulged wall at Gamma = 6.6e-4, where min m1
# sits and falls with h, would fail from Wi = 0.09 on.
CONVERGED_M1, CONVERGED_DP = 0.05, 0.01


class Context:
    """Where the studies' folders are and where the figures go; the studies, read once."""

    def __init__(self, data, out):
        self.data, self.out, self._studies = data, out, {}
        self.inputs = []

    def study(self, name):
        if name not in self._studies:
            self._studies[name] = Study(f"{self.data}/{name}")
        return self._studies[name]

    def branch(self, study, **where):
        b = self.study(study).branch({k.replace("__", "."): v for k, v in where.items()})
        self.inputs.append(b.path)
        return b

    def gamma(self, fluid):
        return self.branch("gamma", fluid__model=fluid)

    def wi(self, fluid, Gamma, mesh="M2"):
        if mesh == "M3":
            if Gamma != LOW:
                raise ValueError("M3 runs only at Gamma = 4.95e-5")
            return self.branch("wi_m3", fluid__model=fluid)
        return self.branch("wi", fluid__model=fluid, parameters__Gamma=Gamma, mesh__name=mesh)

    def wi_thickness(self, fluid, t):
        return self.wi(fluid, HIGH) if t == 0.4 else self.branch("wi_thickness", fluid__model=fluid, parameters__t=t)

    def save(self, fig, name, rect=None):
        return st.save(fig, f"{self.out}/{name}.png", self.inputs, rect)


def stored(branch, upto=None, kinds=KINDS_DRAWN):
    """(parameter value, group, table row index) of the stored solutions of the kinds a figure
    draws, in branch order, up to a parameter value."""
    rows = {int(r): i for i, r in enumerate(branch["row"])}
    out = []
    for v, row, g in branch.saved:
        i = rows[row]
        if int(branch["kind"][i]) in kinds and (upto is None or v <= upto * (1 + 1e-9)):
            if not out or abs(out[-1][0] - v) > 1e-9 * abs(v):  # the event and the end at one Wi: once
                out.append((v, g, i))
    return out


def limiting(branch):
    """The located zero of min m1 on a Wi branch, or None: the first event, or the end where the
    branch's stop threshold on min m1 ended it (the engine reports that point once, as the end)."""
    ev = branch["kind"] == 3
    if ev.any():
        return float(branch[branch.parameter][ev][0])
    return float(branch.end(branch.parameter)) if "min_m1 < stop_below crossed" in branch.status else None


# --- figure 1 -------------------------------------------------------------------------------


def fig01(ctx):
    """Steady-shear viscosity (polymer part) against the local Wi; inset against the rate."""
    ctx.study("steady_shear")  # MissingData where the study is not there
    fig, axes = st.figure(1, 1, width=7.8, height=4.6,
                          title="Steady-shear viscosity of the polymer: Owens and FENE-P ($\\lambda_0$ = 0.263 s)")
    ax = axes[0, 0]
    bs = [2.0, 5.0, 10.0, 20.0, 50.0, 100.0]
    colours = st.sequence_colours(len(bs), "viridis")
    owens = ctx.branch("steady_shear", fluid__model="owens")
    ax.loglog(owens["Wi_local"], owens["eta_p"], color=st.FLUID_COLOUR["owens"], lw=2.0, label="Owens")
    for b, c in zip(bs, colours):
        fp = ctx.branch("steady_shear", fluid__model="fene-p", parameters__b=b)
        ax.loglog(fp["Wi_local"], fp["eta_p"], color=c, label=f"FENE-P, b = {b:g}")
    ax.set_xlabel("local Wi = $\\lambda_0 \\dot\\gamma$")
    ax.set_ylabel("$\\eta_p / \\eta_{p0}$")
    ax.set_ylim(5e-3, 2)
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0))
    inset = ax.inset_axes([0.15, 0.17, 0.3, 0.3])
    fp2 = ctx.branch("steady_shear", fluid__model="fene-p", parameters__b=2.0)
    inset.loglog(owens["rate"], owens["eta_p"], color=st.FLUID_COLOUR["owens"], lw=2.0, label="Owens")
    inset.loglog(fp2["rate"], fp2["eta_p"], color=colours[0], label="FENE-P, b = 2")
    inset.set_xlabel("shear rate $\\dot\\gamma$ (1/s)", fontsize=7)
    inset.set_ylabel("$\\eta_p / \\eta_{p0}$", fontsize=7)
    inset.tick_params(labelsize=6)
    inset.legend(fontsize=6, loc="lower left")
    return ctx.save(fig, "fig01_shear_viscosity")


# --- figure 2 -------------------------------------------------------------------------------


def fig02(ctx):
    """The meshes M1, M2, M3 at t = 0.4 (reference configuration), whole and around the wall."""
    fig, axes = st.figure(3, 2, width=11.0, height=5.0,
                          title="Meshes M1, M2, M3, reference configuration (t = 0.4): fluid grey, solid brown",
                          gridspec_kw={"width_ratios": [2.2, 1]})
    for r, mesh in enumerate(["M1", "M2", "M3"]):
        b = ctx.wi("oldroyd-b", LOW, mesh)
        nodes, elements, groups = b.mesh()
        outline = [0, 1, 2, 5, 8, 7, 6, 3, 0]  # lexicographic 3 x 3 nodes
        segs = {"fluid": [], "solid": []}
        for el, g in zip(elements, groups):
            segs["solid" if g != "fluid" else "fluid"].append(nodes[el[outline]])
        n_fluid, n_solid = len(segs["fluid"]), len(segs["solid"])
        for c, (ax, xlim) in enumerate(zip(axes[r], [(0, 19), (6.5, 12.5)])):
            ax.add_collection(LineCollection(segs["fluid"], colors="0.45", linewidths=0.3))
            ax.add_collection(LineCollection(segs["solid"], colors="tab:brown", linewidths=0.3))
            ax.set_xlim(*xlim)
            ax.set_ylim(0, 1.45)
            ax.set_aspect("equal")
            ax.grid(False)
            ax.set_xlabel(st.label("x"))
            ax.set_ylabel(st.label("y"))
            if c == 0:
                ax.set_title(f"{mesh}: {n_fluid} fluid + {n_solid} solid elements, {len(nodes)} nodes, "
                             f"{int(b.attribute('problem', 'unknowns'))} unknowns (Oldroyd-B)")
            else:
                ax.set_title(f"{mesh} around the deformable wall")
    return ctx.save(fig, "fig02_meshes")


# --- figure 3 -------------------------------------------------------------------------------


def fig03(ctx):
    """min m1 and max m3 against Wi on M1-M3 at Gamma = 4.95e-5, per fluid."""
    fig, axes = st.figure(2, 3, width=11.5, height=6.2,
                          title="Conformation eigenvalues against Wi on M1, M2, M3 ($\\Gamma$ = 4.95e-5)")
    for c, fluid in enumerate(st.VISCOELASTIC):
        for mesh in ["M1", "M2", "M3"]:
            b = ctx.wi(fluid, LOW, mesh)
            lim = limiting(b)
            lab = f"{mesh}" + (f": limit Wi = {lim:.4g}" if lim else f": ended at Wi = {b.end('Wi'):.4g}")
            for r, obs in enumerate(["min_m1", "max_m3"]):
                st.branch_line(axes[r, c], b, "Wi", obs, ls=st.MESH_STYLE[mesh], color=st.FLUID_COLOUR[fluid], label=lab)
                if lim:
                    axes[r, c].plot([lim], [np.interp(lim, b["Wi"], b[obs])], "o", ms=3.5, color=st.FLUID_COLOUR[fluid])
        axes[0, c].axhline(0, color="k", lw=0.6)
        axes[0, c].set_title(st.fluid_label(fluid))
        axes[1, c].set_yscale("log")
        for r, obs in enumerate(["min_m1", "max_m3"]):
            axes[r, c].set_xlabel(st.label("Wi"))
            axes[r, c].set_ylabel(st.label(obs))
        axes[0, c].legend(loc="upper right")
    return ctx.save(fig, "fig03_eigenvalues_meshes")


# --- figure 4 -------------------------------------------------------------------------------


def fig04(ctx):
    """M_xx across the narrowest gap, height scaled by the gap, for several Wi (Gamma = 1.98e-4)."""
    fig, axes = st.figure(1, 3, width=11.5, height=3.6,
                          title="$M_{xx}$ across the narrowest gap for several Wi ($\\Gamma$ = 1.98e-4)")
    for c, fluid in enumerate(st.VISCOELASTIC):
        b = ctx.wi(fluid, MID)
        pts = stored(b)
        colours = st.sequence_colours(len(pts))
        for (v, g, i), col in zip(pts, colours):
            gp = b.array(g, "gap_profile")  # x, y, vx, vy, Mxx, bottom to top
            kind = " (limit)" if int(b["kind"][i]) in (3, 6) and i == len(b["kind"]) - 1 else ""
            ax = axes[0, c]
            ax.plot(gp[:, 1] / gp[-1, 1], gp[:, 4], color=col, label=f"Wi = {v:.3g}{kind}")
        axes[0, c].set_title(st.fluid_label(fluid))
        axes[0, c].set_xlabel("height across the gap, y / gap")
        axes[0, c].set_ylabel(st.label("Mxx"))
        axes[0, c].set_yscale("log")
        axes[0, c].set_ylim(top=30 * axes[0, c].get_ylim()[1])  # room for the legend above the curves
        axes[0, c].legend(ncol=2, loc="upper center")
    return ctx.save(fig, "fig04_mxx_across_gap")


# --- figure 5 -------------------------------------------------------------------------------


def converged_wi(coarse, fine):
    """The largest Wi up to which two branches agree in min m1 to CONVERGED_M1 and in dP to
    CONVERGED_DP, at that Wi and at every smaller one from the start, both interpolated linearly
    between their points on 1000 Wi up to the end of the shorter; None where they differ at the
    start already."""
    w = np.linspace(max(coarse["Wi"][0], fine["Wi"][0]), min(coarse.end("Wi"), fine.end("Wi")), 1000)

    def at(b, obs):
        return np.interp(w, b["Wi"], b[obs])

    bad = ((np.abs(at(coarse, "min_m1") - at(fine, "min_m1")) > CONVERGED_M1)
           | (np.abs(at(coarse, "dP") / at(fine, "dP") - 1) > CONVERGED_DP))
    if not bad.any():
        return w[-1]
    i = int(np.argmax(bad))
    return w[i - 1] if i > 0 else None


def fig05(ctx):
    """The limiting Wi (M1, M2; M3 at the smallest Gamma) and the largest mesh-converged Wi."""
    fig, axes = st.figure(1, 3, width=11.5, height=4.4,
                          title="Limiting Wi and largest mesh-converged Wi against $\\Gamma$ (t = 0.4)")
    for c, fluid in enumerate(st.VISCOELASTIC):
        ax = axes[0, c]
        col = st.FLUID_COLOUR[fluid]
        lim = {m: [] for m in ("M1", "M2")}
        conv = []
        for G in GAMMAS:
            bs = {m: ctx.wi(fluid, G, m) for m in ("M1", "M2")}
            for m in lim:
                lim[m].append(limiting(bs[m]) or np.nan)
            conv.append(converged_wi(bs["M1"], bs["M2"]))
        ax.plot(GAMMAS, lim["M2"], "o-", color=col, label="limiting Wi, M2")
        ax.plot(GAMMAS, lim["M1"], "o:", color=col, mfc="white", label="limiting Wi, M1")
        ax.plot(GAMMAS, [np.nan if v is None else v for v in conv], "s--", color="0.3", ms=4,
                label="mesh converged, M1 against M2")
        failed = [G for G, v in zip(GAMMAS, conv) if v is None]
        if failed:
            ax.plot(failed, [0] * len(failed), "x", color="0.3", ms=8, clip_on=False,
                    label="not converged at Wi = 0.01 (M1 against M2)")
        m3 = ctx.wi(fluid, LOW, "M3")
        ax.plot([LOW], [limiting(m3) or np.nan], "*", ms=10, color=col, label="limiting Wi, M3")
        conv3 = converged_wi(ctx.wi(fluid, LOW, "M2"), m3)
        ax.plot([LOW], [np.nan if conv3 is None else conv3], "P", ms=7, color="0.3",
                label="mesh converged, M2 against M3")
        ax.set_title(st.fluid_label(fluid))
        ax.set_xlabel(st.label("Gamma"))
        ax.set_ylabel("Wi")
        ax.set_ylim(bottom=0)
    handles, labels = axes[0, 2].get_legend_handles_labels()
    for ax in axes[0, :2]:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            if lab not in labels:
                handles.append(h)
                labels.append(lab)
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=7)
    fig.text(0.5, 0.165, f"mesh converged: min m1 within {CONVERGED_M1:g} and dP within {CONVERGED_DP:.0%} "
             "between the two meshes at every Wi up to it", ha="center", fontsize=7, color="0.3")
    return ctx.save(fig, "fig05_limiting_wi_gamma", rect=(0, 0.17, 1, 1))


# --- interface shapes: figures 6 and 9 --------------------------------------------------------


def shapes(ax, branch, pts, colours, fmt, **kw):
    for (v, g, _), col in zip(pts, colours):
        s = branch.array(g, "interface_shape")
        ax.plot(s[:, 0], s[:, 1], color=col, label=st.fmt_value(fmt, v), **kw)


def newtonian_shapes(ax, branch, values):
    for k, v in enumerate(values):
        s = branch.array(branch.solution(v), "interface_shape")
        ax.plot(s[:, 0], s[:, 1], color="0.35", ls="--", lw=0.9, label="Newtonian" if k == 0 else None)


def shape_axes(ax, title):
    ax.axhline(1, color="0.6", lw=0.6, ls=":")
    ax.set_xlim(st.WALL_START - 0.2, st.WALL_END + 0.2)
    ax.set_title(title)
    ax.set_xlabel(st.label("x"))
    ax.set_ylabel("interface y / W")
    # under the panel: inside it the legend would cover shapes (they fill the panel's width)
    ax.legend(ncol=4, fontsize=6, loc="upper center", bbox_to_anchor=(0.5, -0.2), frameon=False,
              columnspacing=1.0, handlelength=1.6)


def fig06(ctx):
    """Interface shapes: against Gamma at Wi = 0.1 (Newtonian dashed), against Wi at 4.95e-4."""
    fig, axes = st.figure(2, 3, width=11.5, height=8.4,
                          title="Interface shapes: top, Wi = 0.1 for six $\\Gamma$ (Newtonian dashed); "
                                "bottom, $\\Gamma$ = 4.95e-4 for several Wi up to the limit")
    newt = ctx.gamma("newtonian")
    for c, fluid in enumerate(st.VISCOELASTIC):
        b = ctx.gamma(fluid)
        pts = [(v, b.solution(v), None) for v in GAMMAS]
        newtonian_shapes(axes[0, c], newt, GAMMAS)
        shapes(axes[0, c], b, pts, st.sequence_colours(len(pts)), "Gamma")
        shape_axes(axes[0, c], f"{st.fluid_label(fluid)}, Wi = 0.1")
        w = ctx.wi(fluid, HIGH)
        pts = stored(w)
        shapes(axes[1, c], w, pts, st.sequence_colours(len(pts)), "Wi")
        shape_axes(axes[1, c], f"{st.fluid_label(fluid)}, $\\Gamma$ = 4.95e-4 (limit Wi = {limiting(w):.3g})")
    return ctx.save(fig, "fig06_interfaces")


def fig09(ctx):
    """Interface shapes against the wall thickness (Gamma = 4.95e-4, Wi = 0.1), and at t = 0.1
    for several Wi."""
    fig, axes = st.figure(2, 3, width=11.5, height=8.0,
                          title="Interface shapes at $\\Gamma$ = 4.95e-4: top, Wi = 0.1 for t = 0.4, 0.2, 0.1 "
                                "(Newtonian dashed); bottom, t = 0.1 for several Wi")
    ts = [0.4, 0.2, 0.1]
    newt = ctx.branch("thickness", fluid__model="newtonian")
    for c, fluid in enumerate(st.VISCOELASTIC):
        b = ctx.branch("thickness", fluid__model=fluid)
        newtonian_shapes(axes[0, c], newt, ts)
        shapes(axes[0, c], b, [(t, b.solution(t), None) for t in ts], st.sequence_colours(3), "t")
        shape_axes(axes[0, c], f"{st.fluid_label(fluid)}, Wi = 0.1")
        w = ctx.wi_thickness(fluid, 0.1)
        pts = stored(w)
        shapes(axes[1, c], w, pts, st.sequence_colours(len(pts)), "Wi")
        lim = limiting(w)
        shape_axes(axes[1, c], f"{st.fluid_label(fluid)}, t = 0.1 ("
                   + (f"limit Wi = {lim:.3g})" if lim else f"ended at Wi = {w.end('Wi'):.3g})"))
    return ctx.save(fig, "fig09_thickness_interfaces")


# --- figure 7 -------------------------------------------------------------------------------


JUMP = 0.3  # a step of dx_max longer than this is the largest deflection moving to another extremum


def path_with_arrows(ax, b, colour, label):
    """The path (dx_max, dy_max) of a branch with arrows along it, smooth in the arclength between
    its points; where the largest deflection jumps from one extremum of the interface to another
    (a dip to a bulge), a thin dotted line."""
    s, x, y = b["s"], b["dx_max"], b["dy_max"]
    jumps = np.where(np.abs(np.diff(x)) > JUMP)[0]
    start = 0
    for j in list(jumps) + [len(x) - 1]:
        draw_branch(ax, s[start:j + 1], x[start:j + 1], y[start:j + 1], color=colour,
                    label=label if start == 0 else None)
        if j < len(x) - 1:
            ax.plot(x[j:j + 2], y[j:j + 2], ":", color=colour, lw=0.8)
        start = j + 1
    n = len(x)
    for k in np.linspace(0, n - 2, min(6, n - 1)).astype(int):
        if abs(x[k + 1] - x[k]) <= JUMP:
            # the head at the next point, pointing along the chord; a short shaft (a chord drawn
            # whole would show the polygon beside the smooth path)
            ax.annotate("", xy=(x[k + 1], y[k + 1]), xytext=(x[k + 1] - 0.05 * (x[k + 1] - x[k]),
                                                           y[k + 1] - 0.05 * (y[k + 1] - y[k])),
                        arrowprops={"arrowstyle": "-|>", "color": colour, "lw": 1.0, "mutation_scale": 10})
    ax.plot(x[:1], y[:1], "o", ms=4, color=colour)


def fig07(ctx):
    """The path of the point of largest deflection, against Gamma and against Wi."""
    fig, axes = st.figure(1, 2, width=10.0, height=4.2,
                          title="Point of largest deflection (dot: start; arrows: increasing parameter; "
                                "dotted: it jumps from the dip to the bulge)")
    for fluid in st.FLUIDS:
        b = ctx.gamma(fluid)
        path_with_arrows(axes[0, 0], b, st.FLUID_COLOUR[fluid], st.fluid_label(fluid))
    axes[0, 0].set_title("Wi = 0.1, $\\Gamma$ from 4.95e-5 to 6.6e-4")
    for fluid in st.VISCOELASTIC:
        b = ctx.wi(fluid, HIGH)
        path_with_arrows(axes[0, 1], b, st.FLUID_COLOUR[fluid],
                         f"{st.fluid_label(fluid)}, Wi 0.01 to {limiting(b):.3g}")
    axes[0, 1].set_title("$\\Gamma$ = 4.95e-4, Wi from 0.01 to the limiting Wi")
    for ax in axes[0]:
        ax.set_xlabel(st.label("dx_max"))
        ax.set_ylabel(st.label("dy_max"))
        ax.legend()
    return ctx.save(fig, "fig07_deflection_path")


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


# --- figure 10, 13 ---------------------------------------------------------------------------


def fig10(ctx):
    """The limiting Wi against the wall thickness at Gamma = 4.95e-4."""
    fig, axes = st.figure(1, 1, width=5.6, height=4.2, title="Limiting Wi against the wall thickness ($\\Gamma$ = 4.95e-4, M2)")
    ax = axes[0, 0]
    ts = [0.1, 0.2, 0.3, 0.4]
    for fluid in st.VISCOELASTIC:
        lims = [limiting(ctx.wi_thickness(fluid, t)) or np.nan for t in ts]
        ax.plot(ts, lims, "-", marker=st.FLUID_MARKER[fluid], color=st.FLUID_COLOUR[fluid], label=st.fluid_label(fluid))
    ax.set_xlabel(st.label("t"))
    ax.set_ylabel(st.label("limiting_wi"))
    ax.set_ylim(bottom=0)
    ax.legend()
    return ctx.save(fig, "fig10_limiting_wi_thickness")


def fig13(ctx):
    """Pressure drops (inlet to outlet, and across the wall) against Gamma and against Wi."""
    fig, axes = st.figure(1, 3, width=13.5, height=4.2,
                          title="Pressure drop: inlet to outlet (solid) and across the wall, x = 7 to 12 (dashed)")
    for fluid in st.FLUIDS:
        b = ctx.gamma(fluid)
        col = st.FLUID_COLOUR[fluid]
        st.branch_line(axes[0, 0], b, "Gamma", "dP_inlet_outlet", color=col, label=st.fluid_label(fluid))
        st.branch_line(axes[0, 0], b, "Gamma", "dP", ls="--", color=col)
        if fluid == "newtonian":
            i = int(np.argmin(abs(b["Gamma"] - HIGH)))
            for c, (key, ls) in enumerate((("dP_inlet_outlet", "-"), ("dP", "--"))):
                axes[0, c + 1].axhline(b[key][i], color=col, ls=ls, lw=0.9, label=st.fluid_label(fluid))
            continue
        w = ctx.wi(fluid, HIGH)
        for c, (key, ls) in enumerate((("dP_inlet_outlet", "-"), ("dP", "--"))):
            st.branch_line(axes[0, c + 1], w, "Wi", key, ls=ls, color=col, label=st.fluid_label(fluid))
            axes[0, c + 1].plot(w["Wi"][-1:], w[key][-1:], "x", color=col, ms=7)
    axes[0, 0].set_title("Wi = 0.1")
    axes[0, 0].set_xlabel(st.label("Gamma"))
    axes[0, 0].set_ylabel("pressure drop / G")
    for c, key in ((1, "dP_inlet_outlet"), (2, "dP")):
        axes[0, c].set_title(f"{st.fmt_value('Gamma', HIGH)} (x: the limiting Wi)")
        axes[0, c].set_xlabel(st.label("Wi"))
        axes[0, c].set_xscale("log")
        axes[0, c].set_ylabel(st.label(key))
    for ax in axes[0]:
        ax.legend()
    return ctx.save(fig, "fig13_pressure_drop")


ALL = [fig01, fig02, fig03, fig04, fig05, fig06, fig07, fig08, fig09, fig10, fig11, fig12, fig13, fig14, fig15, fig16]
# the studies (runs/paper/NAME.toml) each figure reads
STUDIES = {
    "fig01": ["steady_shear"], "fig02": ["wi", "wi_m3"], "fig03": ["wi", "wi_m3"], "fig04": ["wi"],
    "fig05": ["wi", "wi_m3"], "fig06": ["gamma", "wi"], "fig07": ["gamma", "wi"], "fig08": ["gamma", "wi"],
    "fig09": ["thickness", "wi", "wi_thickness"], "fig10": ["wi", "wi_thickness"], "fig11": ["gamma", "wi"],
    "fig12": ["gamma", "wi"], "fig13": ["gamma", "wi"], "fig14": ["gamma", "wi"], "fig15": ["gamma"],
    "fig16": ["gamma", "wi"],
}
