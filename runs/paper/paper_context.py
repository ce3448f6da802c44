"""What the figures of runs/paper share: the values of Gamma the studies run, the kinds of stored
points a figure draws, where the studies are (Context: the studies read once, the branch files a
figure read, for costs.md), and the stored points and the limiting Wi of a branch."""

import paper_style as st
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
