"""Labels of the figures: what each parameter and observable is (its axis label), and what
tells several files apart (the scene keys whose values differ)."""

import os

from keller.files.h5 import scene_values

# What each parameter and observable is, with its scaling (model.md: lengths in W, pressures and
# stresses in G, velocities in G W / eta0), for axis labels.
QUANTITIES = {
    "Wi": "Wi (inlet Weissenberg number)",
    "Gamma": r"$\Gamma = \eta_0 U_0 / (G W)$",
    "t": "wall thickness t / W",
    "Pe": "external pressure Pe / G",
    "Re": "Re",
    "beta": r"$\beta = \eta_s / \eta_0$",
    "dP": "pressure drop across the wall, dP / G",
    "dP_inlet_outlet": "pressure drop inlet to outlet, dP_inlet_outlet / G",
    "eta": "viscosity eta / eta0",
    "eta_p": "polymer viscosity eta_p / eta_p0",
    "Wi_local": "local Wi = lambda_0 gdot",
    "rate": "shear rate (1/s)",
    "log10_rate": "log10 of the shear rate (1/s)",
    "dx_max": "x of largest deflection from the centre, dx_max / W",
    "dy_max": "largest deflection dy_max / W",
    "gap_min": "narrowest gap / W",
    "min_m1": "min m1 (smallest eigenvalue of M)",
    "max_m3": "max m3 (largest eigenvalue of M)",
    "max_trM": "max tr M",
    "drag": r"drag K = $F_x / (\eta_0 U)$",
    "u_mid": "u(1/2)",
    "u_max": "max u",
    "u_quarter": "u(1/4)",
    "lambda": r"$\lambda$",
}


def quantity(name):
    """The axis label of a parameter or observable (its name when it is not a known one); a
    multi-mode fluid's mode times time_<mode> are labelled by their mode."""
    if name not in QUANTITIES and name.startswith("time_") and len(name) > 5:
        return rf"$\lambda_k / \lambda$ of mode {name[5:]}"
    return QUANTITIES.get(name, name)


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
