"""Labels of the figures: what each parameter and observable is (its axis label: its symbol and,
where it has one, its scaling), and what tells several files apart (the scene keys whose values
differ).

`quantity(name)` takes any name a figure may put on an axis: a branch column (`Gamma`, `dP`,
`min_m1`), a scene key (`parameters.Gamma`, `bratu.intervals`) or a study column (`end:min_m1`,
`event:min_m1`, `min_m1@0.1`, `dP@0.1#2`, `end_parameter`): no raw key reaches an axis."""

import os

from keller.files.h5 import scene_values

# What each parameter and observable is, with its scaling (model.md: lengths in W, pressures and
# stresses in G, velocities in G W / eta0; the rheometry problems in eta0, lambda and 1/s), as
# axis labels. Parameters of every problem (keller solve --help-scene), then the observables
# (docs/observables.md, docs/fluids.md, the test problems).
QUANTITIES = {
    # parameters
    "Wi": "Wi",
    "Gamma": r"$\Gamma = \eta_0 U_0 / (G W)$",
    "t": "wall thickness t / W",
    "Pe": r"external pressure $P_e / G$",
    "Re": "Re",
    "beta": r"$\beta = \eta_s / \eta_0$",
    "b": "b",
    "alpha": r"Giesekus mobility $\alpha$",
    "epsilon": r"PTT extensibility $\varepsilon$",
    "xi": r"PTT slip $\xi$",
    "inertia": r"wall inertia $\rho_s / \rho$",
    "lambda": r"$\lambda$",
    "mu": r"$\mu$",
    "r": "r",
    "log10_rate": r"$\log_{10}$ of the rate (1/s)",
    # the collapsible channel
    "dP": r"pressure drop across the wall $\Delta P / G$",
    "dP_inlet_outlet": r"pressure drop inlet to outlet $\Delta P_{io} / G$",
    "dx_max": r"x of the largest deflection from the centre / W",
    "dy_max": r"largest deflection $\delta y_{max} / W$",
    "gap_min": "narrowest gap / W",
    "min_m1": r"min $m_1$ (smallest eigenvalue of M)",
    "min_m1_x": r"x of min $m_1$ / W",
    "min_m1_y": r"y of min $m_1$ / W",
    "max_m3": r"max $m_3$ (largest eigenvalue of M)",
    "max_trM": "max tr M",
    "x_min_m1": r"x of min $m_1$ / W",
    "y_min_m1": r"y of min $m_1$ / W",
    "Q_in": r"flow rate in $Q_{in}$",
    "Q_out": r"flow rate out $Q_{out}$",
    "area_change": "relative change of the fluid's area",
    "mesh_quality": "mesh quality (min det J / generated)",
    "min_detF": r"min det F (solid)",
    # an event curve's pieces (docs/two_parameter.md)
    "place": "place of the minimum (node index)",
    "switch margin": "switch margin",
    # the cylinder
    "K": r"drag $K = F_x / (\eta_0 U)$",
    "drag": r"drag $K = F_x / (\eta_0 U)$",
    "K_surface": r"drag $K$ (surface integral)",
    "K_devss": r"drag $K$ (DEVSS)",
    # rheometry
    "eta": r"viscosity $\eta / \eta_0$",
    "eta_p": r"polymer viscosity $\eta_p / \eta_{p0}$",
    "eta_e": r"extensional viscosity $\eta_e / \eta_0$",
    "eta_e_p": r"polymer extensional viscosity $\eta_{e,p} / \eta_{p0}$",
    "N1": r"first normal stress difference $N_1$",
    "N2": r"second normal stress difference $N_2$",
    "psi1_p": r"$\Psi_{1,p} / (2 \eta_{p0} \lambda)$",
    "M_xx": r"$M_{xx}$",
    "M_xy": r"$M_{xy}$",
    "M_yy": r"$M_{yy}$",
    "M_zz": r"$M_{zz}$",
    "Wi_local": r"local Wi = $\lambda_0 \dot\gamma$",
    "rate": "rate (1/s)",
    # the test problems
    "u_mid": "u(1/2)",
    "u_max": "max u",
    "u_min": "min u",
    "u_mean": "mean u",
    "u_norm": r"$\|u\|$",
    "u_centre": "u at the centre",
    "u_quarter": "u(1/4)",
    "v_mean": "mean v",
    # the examples' observables (examples/)
    "u_corner": "u - a at the corner (0, 0)",
    "u_origin": "u(0, 0)",
    "u_mid_wall": "u - a at the middle of the bottom wall",
    "u_top": "u(0, Ly)",
    "u_range": "max u - min u",
    "nu": r"$\nu$",
    "vx_max": r"max $v_x$",
    # time series
    "deviation": "deviation from the steady state",
    "mode_amplitude": "amplitude along the eigenvector",
    "mode_re": "amplitude along the eigenvector, real part",
    "mode_im": "amplitude along the eigenvector, imaginary part",
    # study columns
    "unknowns": "unknowns",
    "seconds": "time of the run (s)",
    "points": "continuation points",
    "end_parameter": "parameter at the end of the branch",
}

# scene keys a study varies, by their meaning (the others: their last part, spaced)
KEYS = {
    "bratu.intervals": "intervals",
    "pitchfork.intervals": "intervals",
    "mesh.name": "mesh",
    "fluid.model": "fluid",
    "fluid.formulation": "formulation",
    "geometry.thickness": "wall thickness t / W",
}

# short symbols, for names inside a longer label (the study's columns, a point's label)
SYMBOLS = {
    "Gamma": r"$\Gamma$", "beta": r"$\beta$", "alpha": r"$\alpha$", "epsilon": r"$\varepsilon$", "xi": r"$\xi$",
    "lambda": r"$\lambda$", "mu": r"$\mu$", "Pe": r"$P_e$", "dP": r"$\Delta P$", "min_m1": r"min $m_1$",
    "max_m3": r"max $m_3$", "dP_inlet_outlet": r"$\Delta P_{io}$", "gap_min": "narrowest gap",
    "K": "K", "dy_max": r"$\delta y_{max}$", "dx_max": r"$x_{max}$", "eta_p": r"$\eta_p$",
    "eta": r"$\eta$", "log10_rate": r"$\log_{10}$ rate", "psi1_p": r"$\Psi_{1,p}$", "inertia": r"$\rho_s / \rho$",
    "t": "t", "fold": "the fold", "bp": "the branch point", "hopf": "the Hopf point",
}


def symbol(name):
    """The short form of a parameter or observable (its symbol), for use inside a label."""
    name = name[len("parameters."):] if name.startswith("parameters.") else name
    return SYMBOLS.get(name, name)


def quantity(name, parameter=None):
    """The axis label of a parameter, observable, scene key or study column (`parameters.Gamma`,
    `end:min_m1`, `event:min_m1`, `min_m1@0.1`); `parameter`, the branch's parameter where it is
    known, names the value of `event:` and `@` columns. A name keller does not know is its own
    label (a user's observable); a scene key it does not know, its last part."""
    if name in QUANTITIES:
        return QUANTITIES[name]
    if name in KEYS:
        return KEYS[name]
    if name.startswith("parameters."):
        return quantity(name[len("parameters."):])
    if name.startswith("monitor:"):
        return quantity(name[len("monitor:"):])
    if name.startswith("time_") and len(name) > 5:  # a multi-mode fluid's mode time, by its mode
        return rf"$\lambda_k / \lambda$ of mode {name[5:]}"
    if name.startswith("end:"):
        return f"{symbol(name[4:])} at the end of the branch"
    par = symbol(parameter) if parameter else "parameter"
    if name.startswith("event:"):
        what = name[len("event:"):]
        return f"{par} at {SYMBOLS[what]}" if what in ("fold", "bp", "hopf") else f"{par} where {symbol(what)} = 0"
    if name == "end_parameter" and parameter:
        return f"{par} at the end of the branch"
    if "@" in name:
        obs, _, at = name.partition("@")
        at, _, crossing = at.partition("#")
        return f"{symbol(obs)} at {par} = {at}" + (f" (crossing {crossing})" if crossing else "")
    if name.startswith("sigma") and name.endswith(("_re", "_im")):
        part = "Re" if name.endswith("_re") else "Im"
        return rf"{part} $\sigma_{{{name[5:-3]}}}$"
    if "." in name:
        return name.rsplit(".", 1)[1].replace("_", " ")
    return name


FLUID_NAMES = {"newtonian": "Newtonian", "oldroyd-b": "Oldroyd-B", "fene-p": "FENE-P", "owens": "Owens",
               "giesekus": "Giesekus", "ptt-linear": "linear PTT", "ptt-exponential": "exponential PTT",
               "fene-cr": "FENE-CR"}


def readable(label):
    """A label of distinguishing_labels as a reader writes it: 'model = giesekus, alpha = 0.3' as
    'Giesekus, $\\alpha$ = 0.3' (the law by its name, a parameter by its symbol, a key by its
    meaning)."""
    parts = []
    given = label.split(", ")
    # the law first: 'Giesekus, alpha = 0.1, log-conformation', not sorted by key
    given = [p for p in given if p.startswith("model = ")] + [p for p in given if not p.startswith("model = ")]
    for part in given:
        key, eq, value = part.partition(" = ")
        if not eq:
            parts.append(part)
        elif key == "name":  # mesh.name
            parts.append(f"mesh {value.strip(chr(34))}")
        elif key == "formulation":
            parts.append(value.strip('"'))
        elif key == "model":
            parts.append(FLUID_NAMES.get(value.strip('"'), value.strip('"')))
        elif key in SYMBOLS or key in QUANTITIES:
            parts.append(f"{symbol(key)} = {value.strip(chr(34))}")
        else:
            parts.append(f"{key.replace('_', ' ')} = {value.strip(chr(34))}")
    return ", ".join(parts)


# The constants of the constitutive laws (docs/fluids.md): a scene lists each with its default
# whatever the law, so it tells files apart only where the file's fluid.model uses it.
LAW_CONSTANTS = {
    "parameters.b": ("fene-p", "fene-cr"),
    "parameters.alpha": ("giesekus",),
    "parameters.epsilon": ("ptt-linear", "ptt-exponential"),
    "parameters.xi": ("ptt-linear", "ptt-exponential"),
}


def _without_unused_constants(scene):
    model = scene.get("fluid.model", "").strip('"')
    return {k: v for k, v in scene.items() if k not in LAW_CONSTANTS or model in LAW_CONSTANTS[k]}


def distinguishing_labels(paths, ignore=()):
    """A label per file from the scene keys whose values differ between the files (for example
    'fluid.model = owens, mesh.name = M3'); the file names when the scenes agree. A law's
    constant counts only for the files whose law has it."""
    scenes = [_without_unused_constants(scene_values(p)) for p in paths]
    keys = sorted({k for s in scenes for k in s})
    differing = [k for k in keys if len({s.get(k) for s in scenes}) > 1 and not k.startswith("continuation.")
                 and k not in ignore and not k.startswith("output.")]
    if not differing or len(paths) == 1:
        return [os.path.basename(p) for p in paths]
    # a law's constant the file's law does not have is left out of its label, not shown as '-'
    return [", ".join(f"{k.split('.', 1)[1]} = {s.get(k, '-')}" for k in differing
                      if k in s or k not in LAW_CONSTANTS) for s in scenes]
