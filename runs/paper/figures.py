"""The figures of the reference study (Chakraborty and Prakash's collapsible channel), one
function each, drawn from the studies of runs/paper (make_all.py runs them first). Every figure
reads only keller's HDF5 files and writes FIGURES/figNN_name.png; docs/paper.md says what each
shows. M2, Pe = 0.04, t = 0.4, b = 100 unless a figure says otherwise. The figures of fields
(contours, profiles along the interface) are in figures_fields.py."""

import numpy as np
from matplotlib.collections import LineCollection

import paper_style as st
from figures_fields import fig08, fig11, fig12, fig14, fig15, fig16
from keller.plot.curves import draw_branch
from paper_context import CONVERGED_DP, CONVERGED_M1, GAMMAS, HIGH, LOW, MID, limiting, stored

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
