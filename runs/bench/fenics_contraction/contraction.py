#!/usr/bin/python3
"""Measurement peer: steady creeping Oldroyd-B flow through the 4:1 planar contraction, legacy FEniCS.

Benchmark (Alves, Oliveira & Pinho, J. Non-Newtonian Fluid Mech. 110 (2003) 45-75; keller's
docs/contraction.md): upstream half-width H1 = 4, downstream half-width H2 = 1 (lengths in H2),
upper half (symmetry line y = 0), contraction plane x = 0 (re-entrant corner (0, 1), salient corner
(0, 4)), inflow at x = -upstream_length, outflow at x = downstream_length. beta = eta_s/eta0 = 1/9,
eta0 = 1, Re = 0, downstream mean velocity U2 = 1 (flow rate 1 through the half channel),
De = lambda U2 / H2 = lambda.

Geometry and meshes: keller's runs/geometries/contraction.geo (the same file, the same -setnumber
parameters; M1, M2, M3, M4 = f 1, 2, 4, 8), meshed by the Gmsh Python API into its first-order
quadrilaterals, each split here into 2 triangles along its shorter diagonal (--split 2: the same
vertices as keller's mesh, and P2 on them has the nodes of keller's Q2) or into 4 through its centre
(--split 4).

Discretisation (monolithic, exact Newton Jacobian from UFL, direct LU), as the cylinder peer:
  velocity u: P2, pressure p: P1, polymer stress tau: P1 (3 components), velocity-gradient
  projection G: P1 (4 components)  (Taylor-Hood + DEVSS-G / SUPG, stress form).
  momentum:     (2 eta_s D(u) + tau + alpha (grad u + grad u^T - G - G^T), grad v) - (p, div v) = 0
  continuity:   (div u, q) = 0
  projection:   (G - grad u, H) = 0
  constitutive: (tau + lam (u.grad tau - G tau - tau G^T) - eta_p (G + G^T), S + delta u.grad S) = 0
                delta = lam h / sqrt(h^2 + 4 lam^2 |u|^2),  alpha = eta_p,  h = cell circumdiameter.
Boundary conditions: inflow: parabolic u (mean U1 = 1/4 over the half-width 4) and the analytic
  fully developed Oldroyd-B stress (tau_xx = 2 eta_p lam gdot^2, tau_xy = eta_p gdot, tau_yy = 0);
  upstream_wall, step, downstream_wall: u = 0; symmetry: u_y = 0; outflow: u_y = 0 and
  (--outflow fd, default) the x-traction of the fully developed flow with p = 0 (2 eta_p lam gdot^2),
  or (--outflow natural) zero x-traction.

Observables at every converged De:
  X_R   = x_R / H2: distance from the salient corner to where the wall shear rate du_x/dy on the
          upstream wall y = 4 changes sign, found scanning from the inflow end towards x = 0 (so the
          Moffatt eddies in the corner are skipped): the first sign change of u_x(x, 4 - d),
          d = 1e-6 (the P2 polynomial of the wall element, so the element's own wall shear rate),
          at the wall's P2 nodes, then bisection.
  Psi_R = max of the stream function psi in x in [-4, 0], y in [1, 4] divided by the flow rate q = 1
          (Psi_salient: the same in y in [2.5, 4], the salient-corner vortex without a lip vortex);
          psi: P2, psi = 0 on the walls, grad psi = (-u_y, u_x) in the least-squares sense,
          maximum over the nodes then refined by Nelder-Mead on point values (positive: a vortex
          turning against the main flow; psi = -1 on the symmetry line).
  C     = (Delta p - Delta p_fd) / (2 tau_w), Delta p = mean p over inflow - mean p over outflow,
          Delta p_fd = 3 U1 / H1^2 L_up + 3 U2 / H2^2 L_down, tau_w = 3 eta0 U2 / H2.
  min eig c, c = I + lam tau / eta_p, over the vertices.

Usage:  /usr/bin/python3 contraction.py mesh  --mesh M2
        /usr/bin/python3 contraction.py solve --mesh M2 [--lu default|mumps|umfpack|superlu] [--de-max 3]
        /usr/bin/python3 contraction.py table              (markdown tables of results/*.json)
"""
import argparse
import json
import math
import os
import tempfile
import time

H1, H2, BETA, ETA0, U2 = 4.0, 1.0, 1.0 / 9.0, 1.0, 1.0
U1 = U2 * H2 / H1
Q = U2 * H2  # flow rate through the half channel
ETA_S, ETA_P = BETA * ETA0, (1.0 - BETA) * ETA0
TAU_W = 3.0 * ETA0 * U2 / H2
NAMES = ["inflow", "outflow", "symmetry", "upstream_wall", "step", "downstream_wall"]
INFLOW, OUTFLOW, SYM, UPWALL, STEP, DOWNWALL = 1, 2, 3, 4, 5, 6
WALLS = (UPWALL, STEP, DOWNWALL)

MESHES = {"M1": 1, "M2": 2, "M3": 4, "M4": 8}
HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_GEO = os.path.normpath(os.path.join(HERE, "..", "..", "geometries", "contraction.geo"))
DEFAULT_WORK = os.environ.get("FENICS_CON_WORK", os.path.join(tempfile.gettempdir(), "fenics_contraction"))
D_WALL = 1e-6
# regions (x0, x1, y0, y1) for the stream function's maximum: the corner region of the benchmark, and
# its part above y = 2.5 (contraction.geo's salient block), which excludes a lip vortex at (0, 1)
PSI_REGIONS = {"corner": (-4.0, 0.0, H2, H1), "salient": (-4.0, 0.0, 0.5 * (H1 + H2), H1)}


def log(*a):
    print(*a, flush=True)


def loadavg():
    try:
        with open("/proc/loadavg") as fh:
            return " ".join(fh.read().split()[:3])
    except OSError:
        return "?"


# ----------------------------------------------------------------------------------------------
# mesh: contraction.geo -> gmsh (order 1 quads) -> triangles -> XDMF (cells + facet markers)
# ----------------------------------------------------------------------------------------------
def mesh_files(work, name, split, lup, ldown):
    base = os.path.join(work, "%s_s%d_L%g_%g" % (name, split, lup, ldown))
    return base + "_cells.xdmf", base + "_facets.xdmf"


def make_mesh(name, f, split, work, geo, lup, ldown):
    import gmsh
    import meshio
    import numpy as np

    cells_x, facets_x = mesh_files(work, name, split, lup, ldown)
    os.makedirs(work, exist_ok=True)
    t0 = time.perf_counter()
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.onelab.setNumber("f", [float(f)])
    gmsh.onelab.setNumber("upstream_length", [float(lup)])
    gmsh.onelab.setNumber("downstream_length", [float(ldown)])
    gmsh.open(geo)
    gmsh.option.setNumber("Mesh.ElementOrder", 1)
    gmsh.model.mesh.generate(2)
    tags, coords, _ = gmsh.model.mesh.getNodes()
    pts = np.asarray(coords).reshape(-1, 3)[:, :2]
    index = {int(t): i for i, t in enumerate(tags)}
    quads = []
    for _, stag in gmsh.model.getEntities(2):
        etypes, _, enodes = gmsh.model.mesh.getElements(2, stag)
        for et, en in zip(etypes, enodes):
            if et != 3:
                raise SystemExit("%s: expected 4-node quadrilaterals (type 3), got type %d" % (geo, et))
            quads.extend(np.asarray(en, dtype=np.int64).reshape(-1, 4).tolist())
    lines, markers = [], []
    for dim, ptag in gmsh.model.getPhysicalGroups(1):
        pname = gmsh.model.getPhysicalName(dim, ptag)
        if pname not in NAMES:
            raise SystemExit("%s: unexpected physical curve %r" % (geo, pname))
        for ctag in gmsh.model.getEntitiesForPhysicalGroup(dim, ptag):
            etypes, _, enodes = gmsh.model.mesh.getElements(1, ctag)
            for et, en in zip(etypes, enodes):
                for ln in np.asarray(en, dtype=np.int64).reshape(-1, 2):
                    lines.append([index[int(ln[0])], index[int(ln[1])]])
                    markers.append(NAMES.index(pname) + 1)
    gmsh.finalize()
    quads = np.array([[index[int(n)] for n in qd] for qd in quads], dtype=np.int64)
    tri = []
    pts = pts.tolist()
    for a, b, c, d in quads:
        if split == 4:
            centre = len(pts)
            pts.append([0.25 * (pts[a][0] + pts[b][0] + pts[c][0] + pts[d][0]),
                        0.25 * (pts[a][1] + pts[b][1] + pts[c][1] + pts[d][1])])
            tri += [[a, b, centre], [b, c, centre], [c, d, centre], [d, a, centre]]
        else:
            ac = math.dist(pts[a], pts[c])
            bd = math.dist(pts[b], pts[d])
            tri += [[a, b, c], [a, c, d]] if ac <= bd else [[a, b, d], [b, c, d]]
    pts = np.array(pts)
    tri = np.array(tri, dtype=np.int64)
    # counter-clockwise triangles
    e1 = pts[tri[:, 1]] - pts[tri[:, 0]]
    e2 = pts[tri[:, 2]] - pts[tri[:, 0]]
    neg = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0] < 0
    tri[neg] = tri[neg][:, [0, 2, 1]]
    meshio.write(cells_x, meshio.Mesh(points=pts, cells={"triangle": tri}))
    meshio.write(facets_x, meshio.Mesh(points=pts, cells={"line": np.array(lines, dtype=np.int64)},
                                       cell_data={"markers": [np.asarray(markers, dtype=np.int32)]}))
    t = time.perf_counter() - t0
    info = dict(name=name, f=f, split=split, quads=int(len(quads)), vertices=int(len(pts)),
                triangles=int(len(tri)), boundary_lines=len(lines), seconds=t, lup=lup, ldown=ldown, geo=geo)
    log("mesh %s (f = %d, split %d): %d quads -> %d triangles, %d vertices, %.2f s"
        % (name, f, split, len(quads), len(tri), len(pts), t))
    return info


def load_mesh(args):
    import dolfin as df
    cells_x, facets_x = mesh_files(args.work, args.mesh, args.split, args.lup, args.ldown)
    if not os.path.exists(facets_x) or args.remesh:
        make_mesh(args.mesh, args.f, args.split, args.work, args.geo, args.lup, args.ldown)
    mesh = df.Mesh()
    with df.XDMFFile(cells_x) as fh:
        fh.read(mesh)
    mvc = df.MeshValueCollection("size_t", mesh, 1)
    with df.XDMFFile(facets_x) as fh:
        fh.read(mvc, "markers")
    mf = df.cpp.mesh.MeshFunctionSizet(mesh, mvc)
    return mesh, mf


# ----------------------------------------------------------------------------------------------
# problem
# ----------------------------------------------------------------------------------------------
class Problem:
    def __init__(self, mesh, mf, lup, ldown, outflow="fd", qdeg=4, supg=1.0):
        import dolfin as df
        self.df = df
        self.mesh, self.mf, self.lup, self.ldown = mesh, mf, lup, ldown
        cell = mesh.ufl_cell()
        Ve = df.VectorElement("CG", cell, 2)
        Qe = df.FiniteElement("CG", cell, 1)
        Te = df.VectorElement("CG", cell, 1, dim=3)
        Ge = df.TensorElement("CG", cell, 1)
        W = df.FunctionSpace(mesh, df.MixedElement([Ve, Qe, Te, Ge]))
        self.W = W
        self.w = df.Function(W)
        self.lam = df.Constant(0.0)
        lam = self.lam
        eta_s, eta_p, alpha = df.Constant(ETA_S), df.Constant(ETA_P), df.Constant(ETA_P)

        u, p, t, G = df.split(self.w)
        v, q, s, Hh = df.TestFunctions(W)
        tau = df.as_tensor([[t[0], t[1]], [t[1], t[2]]])
        S = df.as_tensor([[s[0], s[1]], [s[1], s[2]]])
        gu = df.grad(u)
        hK = df.CellDiameter(mesh)
        delta = df.Constant(supg) * lam * hK / df.sqrt(hK * hK + 4.0 * lam * lam * df.dot(u, u))
        dx = df.Measure("dx", domain=mesh, metadata={"quadrature_degree": qdeg})
        ds = df.Measure("ds", domain=mesh, subdomain_data=mf)
        self.ds = ds
        I = df.Identity(2)

        sig_m = -p * I + eta_s * (gu + gu.T) + tau + alpha * (gu + gu.T - G - G.T)
        Rc = tau + lam * (df.dot(df.grad(tau), u) - df.dot(G, tau) - df.dot(tau, G.T)) - eta_p * (G + G.T)
        F = (df.inner(sig_m, df.grad(v)) * dx
             - q * df.div(u) * dx
             + df.inner(G - gu, Hh) * dx
             + df.inner(Rc, S + delta * df.dot(df.grad(S), u)) * dx)
        # fully developed shear rates: inflow (half-width H1, mean U1), outflow (H2, U2)
        g_in = df.Expression("-3.0*U*x[1]/(H*H)", U=U1, H=H1, degree=1)
        g_out = df.Expression("-3.0*U*x[1]/(H*H)", U=U2, H=H2, degree=1)
        if outflow == "fd":
            F -= 2.0 * eta_p * lam * g_out ** 2 * v[0] * ds(OUTFLOW)
        self.F = F
        self.J = df.derivative(F, self.w, df.TrialFunction(W))

        self.uin = df.Expression(("1.5*U*(1.0 - x[1]*x[1]/(H*H))", "0.0"), U=U1, H=H1, degree=2)
        self.tin = df.Expression(("2.0*etap*lam*g*g", "etap*g", "0.0"), etap=ETA_P, lam=0.0, g=g_in, degree=2)
        zero2 = df.Constant((0.0, 0.0))
        bcs = [df.DirichletBC(W.sub(0), self.uin, mf, INFLOW),
               df.DirichletBC(W.sub(2), self.tin, mf, INFLOW)]
        bcs += [df.DirichletBC(W.sub(0), zero2, mf, m) for m in WALLS]
        bcs += [df.DirichletBC(W.sub(0).sub(1), df.Constant(0.0), mf, SYM),
                df.DirichletBC(W.sub(0).sub(1), df.Constant(0.0), mf, OUTFLOW)]
        self.bcs = bcs
        self.bcs0 = [df.DirichletBC(b) for b in bcs]
        for b in self.bcs0:
            b.homogenize()
        self.A = df.PETScMatrix()
        self.b = df.PETScVector()
        self.ndofs = W.dim()

        # pressure means on inflow (length H1) and outflow (length H2)
        self.p_in = p / H1 * ds(INFLOW)
        self.p_out = p / H2 * ds(OUTFLOW)

        # stream function: P2, psi = 0 on the walls, (grad psi - (-u_y, u_x), grad phi) = 0
        P = df.FunctionSpace(mesh, "CG", 2)
        self.P = P
        psi_t, phi = df.TrialFunction(P), df.TestFunction(P)
        self.a_psi = df.inner(df.grad(psi_t), df.grad(phi)) * df.dx
        self.L_psi = df.inner(df.as_vector((-u[1], u[0])), df.grad(phi)) * df.dx
        self.bc_psi = [df.DirichletBC(P, df.Constant(0.0), mf, m) for m in WALLS]
        self.A_psi = df.assemble(self.a_psi)
        for bc in self.bc_psi:
            bc.apply(self.A_psi)
        self.psi_solver = df.LUSolver(self.A_psi, "default")
        self.psi = df.Function(P)
        xy = P.tabulate_dof_coordinates().reshape(-1, 2)
        self.psi_regions = {name: (box, [i for i in range(len(xy)) if box[0] - 1e-12 <= xy[i, 0] <= box[1] + 1e-12
                                         and box[2] - 1e-12 <= xy[i, 1] <= box[3] + 1e-12])
                            for name, box in PSI_REGIONS.items()}
        self.psi_xy = xy
        self.psi_dofs_sym = [i for i in range(len(xy)) if abs(xy[i, 1]) < 1e-12]
        # X_R scan points: x of the P2 nodes on the upstream wall, from the inflow to the corner
        xs = sorted(set(round(float(xy[i, 0]), 12) for i in range(len(xy)) if abs(xy[i, 1] - H1) < 1e-12))
        self.wall_xs = [x for x in xs if x < 0.0]
        self.wall_xs.append(0.0)

    def set_de(self, de):
        lam = de * H2 / U2
        self.lam.assign(lam)
        self.tin.lam = lam

    def couette(self):
        df = self.df
        pin, pout = df.assemble(self.p_in), df.assemble(self.p_out)
        dp = pin - pout
        dp_fd = 3.0 * ETA0 * U1 / H1 ** 2 * self.lup + 3.0 * ETA0 * U2 / H2 ** 2 * self.ldown
        return (dp - dp_fd) / (2.0 * TAU_W), dp, pin, pout

    def vortex_length(self):
        """X_R from the sign change of u_x(x, H1 - d) nearest the inflow; None without a vortex."""
        u = self.w.sub(0, deepcopy=False)
        y = H1 - D_WALL

        def g(x):
            return u(x, y)[0]

        xs = self.wall_xs
        prev_x, prev_g = xs[0], g(xs[0])
        for x in xs[1:]:
            gx = g(min(x, -1e-12))
            if prev_g > 0.0 and gx <= 0.0:
                a, b, ga = prev_x, x, prev_g
                for _ in range(60):
                    m = 0.5 * (a + b)
                    gm = g(m)
                    if (gm > 0.0) == (ga > 0.0):
                        a, ga = m, gm
                    else:
                        b = m
                return -0.5 * (a + b) / H2
            prev_x, prev_g = x, gx
        return None

    def stream_function(self):
        """psi on the symmetry line / q, and per region of PSI_REGIONS (max psi / q, where)."""
        import numpy as np
        from scipy.optimize import minimize
        df = self.df
        b = df.assemble(self.L_psi)
        for bc in self.bc_psi:
            bc.apply(b)
        self.psi_solver.solve(self.psi.vector(), b)
        vals = self.psi.vector().get_local()
        sym = float(np.mean(vals[self.psi_dofs_sym]))
        found = {}
        for name, (box, idx) in self.psi_regions.items():
            k = idx[int(np.argmax(vals[idx]))]
            x0 = self.psi_xy[k]
            best = (float(vals[k]), x0)
            if vals[k] > 0.0:
                def negpsi(z):
                    if not (box[0] <= z[0] <= box[1] and box[2] <= z[1] <= box[3]):
                        return 1.0
                    return -self.psi(z[0], z[1])
                r = minimize(negpsi, x0, method="Nelder-Mead",
                             options=dict(xatol=1e-7, fatol=1e-13, maxiter=400,
                                          initial_simplex=[x0, x0 + [0.02, 0.0], x0 + [0.0, 0.02]]))
                if -r.fun > best[0]:
                    best = (float(-r.fun), r.x)
            found[name] = (best[0] / Q, [float(best[1][0]), float(best[1][1])])
        return found, sym / Q

    def min_conformation_eig(self):
        import numpy as np
        lam = float(self.lam)
        if lam == 0.0:
            return 1.0
        t = self.w.split(deepcopy=True)[2].compute_vertex_values(self.mesh).reshape(3, -1)
        a = 1.0 + lam * t[0] / ETA_P
        c = lam * t[1] / ETA_P
        d = 1.0 + lam * t[2] / ETA_P
        return float(np.min(0.5 * (a + d) - np.sqrt(0.25 * (a - d) ** 2 + c * c)))

    def observables(self):
        t0 = time.perf_counter()
        C, dp, pin, pout = self.couette()
        xr = self.vortex_length()
        found, psisym = self.stream_function()
        return dict(X_R=xr, Psi_R=found["corner"][0], Psi_R_at=found["corner"][1],
                    Psi_salient=found["salient"][0], Psi_salient_at=found["salient"][1], psi_symmetry=psisym,
                    C=C, dp=dp, p_in=pin, p_out=pout,
                    min_eig_c=self.min_conformation_eig(), t_observables=time.perf_counter() - t0)


def make_solver(df, method):
    if method == "default":
        return df.PETScLUSolver("default")
    ksp = df.PETScKrylovSolver()
    pre = "lu_%s_" % method
    ksp.set_options_prefix(pre)
    df.PETScOptions.set(pre + "ksp_type", "preonly")
    df.PETScOptions.set(pre + "pc_type", "lu")
    df.PETScOptions.set(pre + "pc_factor_mat_solver_type", method)
    ksp.set_from_options()
    return ksp


def solver_name(solver):
    try:
        return solver.ksp().getPC().getFactorSolverType()
    except Exception as e:  # noqa
        return "?(%s)" % e


def newton(prob, solver, maxit=15, rtol=1e-9, atol=1e-10, div=1e4, verbose=True):
    """Exact Newton; returns (converged, iterations, list of (assembly s, solve s), residuals)."""
    df = prob.df
    w, A, b = prob.w, prob.A, prob.b
    for bc in prob.bcs:
        bc.apply(w.vector())
    dw = df.Function(prob.W)
    times, res = [], []
    r0 = None
    for it in range(maxit + 1):
        t0 = time.perf_counter()
        df.assemble(prob.J, tensor=A)
        df.assemble(prob.F, tensor=b)
        for bc in prob.bcs0:
            bc.apply(A, b)
        ta = time.perf_counter() - t0
        r = b.norm("l2")
        res.append(r)
        if r0 is None:
            r0 = max(r, 1e-300)
        if verbose:
            log("      it %2d  |F| = %.3e" % (it, r))
        if not math.isfinite(r) or r > div * r0:
            times.append((ta, 0.0))
            return False, it, times, res
        if r < atol or r < rtol * r0 and it > 0:
            times.append((ta, 0.0))
            return True, it, times, res
        if it == maxit:
            times.append((ta, 0.0))
            return False, it, times, res
        t1 = time.perf_counter()
        b *= -1.0
        try:
            solver.set_operator(A)
            solver.solve(dw.vector(), b)
        except Exception as e:  # noqa  (factorisation failure)
            log("      linear solve failed: %s" % str(e).splitlines()[0][:200])
            times.append((ta, time.perf_counter() - t1))
            return False, it, times, res
        times.append((ta, time.perf_counter() - t1))
        w.vector().axpy(1.0, dw.vector())
    return False, maxit, times, res


def run_solve(args):
    import dolfin as df
    df.parameters["form_compiler"]["optimize"] = True
    df.parameters["form_compiler"]["cpp_optimize"] = True
    df.parameters["form_compiler"]["cpp_optimize_flags"] = "-O3 -march=native"
    df.parameters["allow_extrapolation"] = True
    df.set_log_level(df.LogLevel.WARNING)
    T0 = time.perf_counter()
    mesh, mf = load_mesh(args)
    t_mesh = time.perf_counter() - T0
    t1 = time.perf_counter()
    prob = Problem(mesh, mf, args.lup, args.ldown, outflow=args.outflow, qdeg=args.qdeg, supg=args.supg)
    solver = make_solver(df, args.lu)
    # first assembly compiles the forms (JIT, cached in ~/.cache/dijitso afterwards)
    df.assemble(prob.J, tensor=prob.A)
    df.assemble(prob.F, tensor=prob.b)
    prob.couette()
    df.assemble(prob.L_psi)
    t_setup = time.perf_counter() - t1
    log("mesh %s (f = %d, split %d): %d vertices, %d cells, %d unknowns (hmin %.4f hmax %.4f); setup+JIT %.1f s; LU %s"
        % (args.mesh, args.f, args.split, mesh.num_vertices(), mesh.num_cells(), prob.ndofs, mesh.hmin(),
           mesh.hmax(), t_setup, args.lu))

    out = dict(problem="4:1 planar contraction, Oldroyd-B, beta = 1/9, Re = 0", mesh=args.mesh, f=args.f,
               split=args.split, lup=args.lup, ldown=args.ldown, vertices=mesh.num_vertices(),
               cells=mesh.num_cells(), unknowns=prob.ndofs, lu=args.lu, outflow=args.outflow, supg=args.supg,
               qdeg=args.qdeg, dde=args.dde, openblas_threads=os.environ.get("OPENBLAS_NUM_THREADS", "unset"),
               load_before=loadavg(), t_mesh_load=t_mesh, t_setup_jit=t_setup, points=[], failures=[])
    backup = df.Function(prob.W)
    de, dde = 0.0, args.dde
    first = True
    t_cont = time.perf_counter()
    while True:
        prob.set_de(de)
        ts = time.perf_counter()
        log("  De = %.5f" % de)
        ok, its, times, res = newton(prob, solver, maxit=args.maxit, verbose=not args.quiet)
        if first:
            out["lu_backend_used"] = solver_name(solver)
        first = False
        ta = sum(t[0] for t in times)
        tsv = sum(t[1] for t in times)
        nsol = sum(1 for t in times if t[1] > 0)
        if ok:
            obs = prob.observables()
            dt = time.perf_counter() - ts
            pt = dict(De=de, newton_its=its, residuals=res, t_step=dt, t_assembly=ta, t_solve=tsv,
                      n_assembly=len(times), n_solve=nsol, **obs)
            out["points"].append(pt)
            log("  De = %.5f  X_R = %s  Psi_R = %.6e  C = %.5f  min eig c %.3g  its %d  %.2f s "
                "(asm %.2f s/%d, LU %.2f s/%d, obs %.2f s)"
                % (de, "%.5f" % obs["X_R"] if obs["X_R"] is not None else "-", obs["Psi_R"], obs["C"],
                   obs["min_eig_c"], its, dt, ta, len(times), tsv, nsol, obs["t_observables"]))
            backup.vector()[:] = prob.w.vector()
            if de >= args.de_max - 1e-12:
                out["stopped"] = "De max %g" % args.de_max
                break
            if time.perf_counter() - t_cont > args.time_limit:
                out["stopped"] = "time limit %.0f s" % args.time_limit
                break
            # after a halving, double the step again, but land on the grid of --dde
            dde = min(2.0 * dde, args.dde) if dde < args.dde else dde
            nxt = math.floor(de / args.dde + 1e-9) * args.dde + args.dde
            de = round(min(de + dde, nxt, args.de_max), 10)
        else:
            dt = time.perf_counter() - ts
            out["failures"].append(dict(De=de, newton_its=its, residuals=res, t_step=dt, t_assembly=ta,
                                        t_solve=tsv, n_assembly=len(times), n_solve=nsol))
            log("  De = %.5f FAILED after %d its (%.2f s)" % (de, its, dt))
            prob.w.vector()[:] = backup.vector()
            de_prev = out["points"][-1]["De"] if out["points"] else 0.0
            dde = (de - de_prev) / 2.0
            if dde < args.dde_min or not out["points"]:
                out["stopped"] = "step below %g (Newton failed at De = %g)" % (args.dde_min, de)
                break
            de = round(de_prev + dde, 10)
    out["t_continuation"] = time.perf_counter() - t_cont
    out["load_after"] = loadavg()
    out["t_total"] = time.perf_counter() - T0
    out["de_max_reached"] = out["points"][-1]["De"] if out["points"] else None
    allt = out["points"] + out["failures"]
    na = sum(p["n_assembly"] for p in allt)
    ns = sum(p["n_solve"] for p in allt)
    out["newton_iterations"] = ns
    out["t_assembly"] = sum(p["t_assembly"] for p in allt)
    out["t_solve"] = sum(p["t_solve"] for p in allt)
    out["t_observables"] = sum(p["t_observables"] for p in out["points"])
    out["s_per_assembly"] = out["t_assembly"] / max(na, 1)
    out["s_per_solve"] = out["t_solve"] / max(ns, 1)
    log("summary %s: unknowns %d, De max %s (%s), %d Newton its, %.3f s/assembly, %.3f s/LU, observables %.1f s, "
        "continuation %.1f s, total %.1f s"
        % (args.mesh, prob.ndofs, out["de_max_reached"], out.get("stopped"), ns, out["s_per_assembly"],
           out["s_per_solve"], out["t_observables"], out["t_continuation"], out["t_total"]))
    if args.save:
        xf = df.XDMFFile(os.path.join(args.work, "%s_s%d_sol.xdmf" % (args.mesh, args.split)))
        xf.parameters["functions_share_mesh"] = True
        for i, fn in enumerate(prob.w.split(deepcopy=True)):
            name = ["u", "p", "tau", "G"][i]
            fn.rename(name, name)
            xf.write(fn, 0.0)
        prob.psi.rename("psi", "psi")
        xf.write(prob.psi, 0.0)
        xf.close()
    os.makedirs(args.results, exist_ok=True)
    tag = args.tag or "%s_s%d_%s_%s" % (args.mesh, args.split, args.lu, args.outflow)
    fn = os.path.join(args.results, tag + ".json")
    with open(fn, "w") as fh:
        json.dump(compact(out), fh, separators=(",", ":"))
    log("wrote", fn)
    return out


def compact(out):
    """The results made small: first and last residual of each step, 7 significant digits (4 for times)."""
    def rnd(v, key=""):
        if isinstance(v, float):
            return float(("%.4g" if key.startswith("t_") else "%.7g") % v)
        if isinstance(v, list):
            return [rnd(x, key) for x in v]
        if isinstance(v, dict):
            return {k: rnd(x, k) for k, x in v.items()}
        return v
    for p in out["points"] + out["failures"]:
        p["residuals"] = [p["residuals"][0], p["residuals"][-1]]
        p.pop("p_in", None)
        p.pop("p_out", None)
    return rnd(out)


def run_table(args):
    """Markdown tables from the continuation results in --results (no FEniCS needed)."""
    import glob
    runs = []
    for fn in sorted(glob.glob(os.path.join(args.results, "*.json"))):
        d = json.load(open(fn))
        if "points" in d and d["points"]:
            runs.append((os.path.basename(fn)[:-5], d))
    print("| run | unknowns | LU | De max reached | stopped by | failed attempts (De) | Newton its (LU solves) "
          "| s/assembly | s/LU | setup+JIT s | continuation s | total s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, d in runs:
        print("| %s | %d | %s | %s | %s | %s | %d | %.3f | %.3f | %.1f | %.1f | %.1f |"
              % (name, d["unknowns"], d["lu_backend_used"], d["de_max_reached"], d.get("stopped", "-"),
                 " ".join("%g" % f["De"] for f in d["failures"]) or "-", d["newton_iterations"],
                 d["s_per_assembly"], d["s_per_solve"], d["t_setup_jit"], d["t_continuation"], d["t_total"]))
    print()
    des = sorted(set(round(p["De"], 6) for _, d in runs for p in d["points"]))
    print("| De | " + " | ".join("%s X_R / Psi_R (Psi_salient) / C / min eig c" % n for n, _ in runs) + " |")
    print("|---|" + "---|" * len(runs))
    for de in des:
        row = ["%.4g" % de]
        for _, d in runs:
            k = [p for p in d["points"] if abs(p["De"] - de) < 1e-9]
            if k:
                p = k[0]
                sal = "" if p["Psi_salient"] == p["Psi_R"] else " (%.4e)" % p["Psi_salient"]
                row.append("%s / %.4e%s / %.4f / %.3g" % ("%.4f" % p["X_R"] if p["X_R"] is not None else "-",
                                                          p["Psi_R"], sal, p["C"], p["min_eig_c"]))
            else:
                row.append("")
        print("| " + " | ".join(row) + " |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("cmd", choices=["mesh", "solve", "table"])
    ap.add_argument("--mesh", default="M1", help="M1, M2, M3, M4 (f = 1, 2, 4, 8) or f<N> for any whole N")
    ap.add_argument("--split", type=int, default=2, choices=[2, 4], help="triangles per quadrilateral")
    ap.add_argument("--geo", default=DEFAULT_GEO, help="keller's contraction.geo (default %(default)s)")
    ap.add_argument("--work", default=DEFAULT_WORK, help="mesh / solution folder (default %(default)s)")
    ap.add_argument("--remesh", action="store_true", help="mesh again even if the mesh files exist")
    ap.add_argument("--results", default=os.path.join(HERE, "results"))
    ap.add_argument("--lup", type=float, default=80.0, help="upstream_length: inflow at x = -lup")
    ap.add_argument("--ldown", type=float, default=50.0, help="downstream_length: outflow at x = +ldown")
    ap.add_argument("--lu", default="default", help="default | mumps | umfpack | superlu")
    ap.add_argument("--outflow", default="fd", choices=["natural", "fd"])
    ap.add_argument("--qdeg", type=int, default=4)
    ap.add_argument("--supg", type=float, default=1.0)
    ap.add_argument("--dde", type=float, default=0.25, help="continuation step in De (and its grid)")
    ap.add_argument("--dde-min", type=float, default=0.25 / 32)
    ap.add_argument("--de-max", type=float, default=3.0)
    ap.add_argument("--maxit", type=int, default=15)
    ap.add_argument("--time-limit", type=float, default=1e9, help="stop continuing after this many seconds (checked after each converged point)")
    ap.add_argument("--save", action="store_true", help="write the last solution and psi to XDMF in --work")
    ap.add_argument("--quiet", action="store_true")
    ap.add_argument("--tag", default="")
    args = ap.parse_args()
    if args.mesh in MESHES:
        args.f = MESHES[args.mesh]
    elif args.mesh.startswith("f") and args.mesh[1:].isdigit() and int(args.mesh[1:]) >= 1:
        args.f = int(args.mesh[1:])
    else:
        ap.error("--mesh: %r is not M1, M2, M3, M4 or f<N>" % args.mesh)
    if args.cmd == "mesh":
        print(json.dumps(make_mesh(args.mesh, args.f, args.split, args.work, args.geo, args.lup, args.ldown)))
    elif args.cmd == "solve":
        run_solve(args)
    else:
        run_table(args)


if __name__ == "__main__":
    main()
