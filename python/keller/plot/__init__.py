"""keller's figures, one module per kind, each a command (`python3 -m keller.plot KIND ...`,
`python3 -m keller.plot --help` lists them) and a function `main(argv)` to call from Python:

    branch       a bifurcation diagram of branch files (any observable against the parameter)
    collapsible  a collapsible-channel branch: diagram, interface shapes, path, wall profile, fields
    field        one component of a field of a stored solution over the mesh, files side by side
    flow         the mesh and the flow (speed and streamlines) of a run on a mesh
    evolve       a time series against time (with --log, the eigenvalue's rate)
    orbits       an orbit branch: amplitude and period against the parameter, its stability, the normal form
    study        a collected study value against a varied key, a curve per value of another
    rheometry    shear and extensional viscosities of a law's homogeneous-flow branches
    interfaces   interface shapes of Gamma branches, one panel per fluid
    cylinder_drag, cylinder_deviation   the confined cylinder's drag against the published table

They read only keller's files (keller.open) and write their figures the way keller writes every
file (keller.outputs: never over an input, under a temporary name until complete). The commands
draw with matplotlib's Agg backend (the figures are files, no display is needed); importing the
package leaves the backend alone, so a notebook that calls its functions keeps its inline figures."""

KINDS = ("branch", "collapsible", "field", "flow", "evolve", "orbits", "study", "rheometry", "interfaces", "cylinder_drag",
         "cylinder_deviation")
