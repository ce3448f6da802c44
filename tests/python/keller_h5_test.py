"""runs/scripts/keller_h5 on files written by keller: a branch of the collapsible channel (coarse
mesh) with the fields of its stored solutions, a time series of the Brusselator perturbed along
its critical mode, and a study of Bratu branches. What the package reads is compared with what
keller prints of the same file (`keller export --csv` and the study's CSV table, every number to
all its digits) and with known values.

Run by ctest (tests/CMakeLists.txt) as
    PYTHONPATH=runs/scripts python3 tests/python/keller_h5_test.py --keller build/bin/keller \\
        --source . --scratch DIR"""

import argparse
import csv
import math
import os
import shutil
import subprocess
import sys
import unittest

import numpy as np

import keller_h5

ARGS = None


def keller(*words, cwd):
    """Runs keller; fails the test with its output where it does not exit 0."""
    p = subprocess.run([ARGS.keller, *words], cwd=cwd, capture_output=True, text=True)
    if p.returncode != 0:
        raise AssertionError(f"keller {' '.join(words)}: exit {p.returncode}\n{p.stdout}\n{p.stderr}")


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def scratch(name):
    path = os.path.join(ARGS.scratch, name)
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(path)
    return path


def scene(name):
    return os.path.join(ARGS.source, "runs", "scenes", name)


class KellerH5Test(unittest.TestCase):
    def assert_same_numbers(self, values, cells, what):
        """values (floats) are the numbers written as cells (all digits: equal, NaN as nan)."""
        self.assertEqual(len(values), len(cells), what)
        for i, (v, c) in enumerate(zip(values, cells)):
            x = float(c)
            self.assertTrue(v == x or (math.isnan(v) and math.isnan(x)), f"{what}, row {i}: {v!r} against {c}")

    def test_a_branch_its_fields_and_mesh(self):
        d = scratch("branch")
        keller("trace", scene("collapsible_newtonian_thickness.toml"), "-o", "c.h5", "--set", "mesh.name=custom",
               "--set", "mesh.nx_upstream=5", "--set", "mesh.nx_deformable=10", "--set", "mesh.nx_downstream=5",
               "--set", "mesh.ny_fluid=4", "--set", "mesh.ny_solid=2", cwd=d)
        keller("export", "c.h5", "--csv", "c.csv", cwd=d)
        path = os.path.join(d, "c.h5")
        parameter, cols, status = keller_h5.read_branch(path)
        self.assertEqual(parameter, "t")
        self.assertEqual(status, "reached the lower bound t = 0.1")
        header, rows = read_csv(os.path.join(d, "c.csv"))
        self.assertEqual(list(cols), header)
        # every column as keller exports it; the kinds by their names there
        names = {"point": 0, "start": 1, "stop": 2, "event": 3, "fold": 4, "bp": 5, "end": 6, "hopf": 7}
        for j, c in enumerate(header):
            cells = [str(names[r[j]]) if c == "kind" else r[j] for r in rows]
            self.assert_same_numbers(cols[c], cells, c)
        kinds = [keller_h5.KINDS[int(k)] for k in cols["kind"]]
        self.assertEqual((kinds[0], kinds[-1]), ("start", "end"))

        # the fields of every stored solution (the last point's always), at the table's parameter value
        saved = keller_h5.saved_solutions(path)
        stored_rows = [row for _, row, _ in saved]
        self.assertEqual(stored_rows, sorted(stored_rows))
        for i in np.flatnonzero(cols["saved_slot"] >= 0):
            self.assertIn(int(cols["row"][i]), stored_rows)
        self.assertEqual(stored_rows[-1], int(cols["row"][-1]))
        for v, row, _ in saved:
            self.assertEqual(v, cols[parameter][list(cols["row"]).index(row)])

        # the mesh: 20 x 4 fluid elements of 9 nodes, each split into 8 triangles, none inverted
        elements, groups, group_names = keller_h5.read_mesh(path)
        self.assertEqual(elements.shape[1], 9)
        fluid = group_names.index("fluid")
        self.assertEqual(int(np.sum(groups == fluid)), 80)
        _, _, g = saved[-1]
        tri, fluid_elements, pos = keller_h5.triangulation(path, g)
        self.assertEqual(len(fluid_elements), 80)
        self.assertEqual(tri.triangles.shape, (640, 3))
        x, y = pos[tri.triangles, 0], pos[tri.triangles, 1]
        area = 0.5 * ((x[:, 1] - x[:, 0]) * (y[:, 2] - y[:, 0]) - (x[:, 2] - x[:, 0]) * (y[:, 1] - y[:, 0]))
        self.assertGreater(area.min(), 0.0)
        # the pressure at an element's centre node is its centre value; NaN off the fluid
        pressure = keller_h5.read_array(path, g, "pressure")
        nodal = keller_h5.nodal_pressure(path, g, pos)
        for e in np.flatnonzero(groups == fluid):
            self.assertEqual(nodal[elements[e, 4]], pressure[e, 0])
        off_fluid = np.setdiff1d(np.arange(len(pos)), elements[groups == fluid].ravel())
        self.assertGreater(len(off_fluid), 0)
        self.assertTrue(np.all(np.isnan(nodal[off_fluid])))
        self.assertIsNone(keller_h5.read_array(path, g, "no such field"))
        self.assertEqual(keller_h5.scene_values(path)["problem.type"], "collapsible-channel")

    def test_labels_name_only_the_constants_a_law_has(self):
        # every scene lists every law constant with its default; a label names those of its own law
        d = scratch("labels")
        files = []
        for name, sets in (("g", ["fluid.model=\"giesekus\"", "parameters.alpha=0.3"]), ("p", []),
                           ("o", ["fluid.model=\"oldroyd-b\""])):
            words = ["trace", scene("steady_shear_ptt.toml"), "-o", name + ".h5", "--set", "output.xdmf=false"]
            for s in sets:
                words += ["--set", s]
            keller(*words, cwd=d)
            files.append(os.path.join(d, name + ".h5"))
        self.assertEqual(keller_h5.distinguishing_labels(files),
                         ["model = giesekus, alpha = 0.3", "model = ptt-linear, epsilon = 0.25, xi = 0.0",
                          "model = oldroyd-b"])
        # a multi-mode fluid's mode times are labelled by their mode, other names by themselves
        self.assertEqual(keller_h5.quantity("time_fast"), r"$\lambda_k / \lambda$ of mode fast")
        self.assertEqual(keller_h5.quantity("time_"), "time_")
        # plot_rheometry.py draws them, and measured points from a CSV (bad CSV: exit 2, no figure)
        script = os.path.join(ARGS.source, "runs", "scripts", "plot_rheometry.py")
        with open(os.path.join(d, "m.csv"), "w") as f:
            f.write("rate,eta_p\n1,0.99\n100,0.5\n")
        with open(os.path.join(d, "bad.csv"), "w") as f:
            f.write("rate,eta_p\n1,x\n")
        env = dict(os.environ, PYTHONPATH=os.path.join(ARGS.source, "runs", "scripts"))
        ok = subprocess.run([sys.executable, script, *files, "--rate", "--data", "m.csv", "-o", "r.png"], cwd=d,
                            env=env, capture_output=True, text=True)
        self.assertEqual(ok.returncode, 0, ok.stderr)
        self.assertGreater(os.path.getsize(os.path.join(d, "r.png")), 10000)
        bad = subprocess.run([sys.executable, script, *files, "--rate", "--data", "bad.csv", "-o", "b.png"], cwd=d,
                             env=env, capture_output=True, text=True)
        self.assertEqual(bad.returncode, 2)
        self.assertIn("bad.csv", bad.stderr)
        self.assertFalse(os.path.exists(os.path.join(d, "b.png")))

    def test_a_time_series_and_its_mode(self):
        d = scratch("time_series")
        keller("evolve", scene("brusselator1d_evolve.toml"), "--set", "evolve.t_end=3", "-o", "e.h5", cwd=d)
        keller("export", "e.h5", "--csv", "e.csv", cwd=d)
        cols, status, mode = keller_h5.read_time_series(os.path.join(d, "e.h5"))
        self.assertEqual(status, "reached t_end")
        header, rows = read_csv(os.path.join(d, "e.csv"))
        self.assertEqual(list(cols), header)
        for j, c in enumerate(header):
            self.assert_same_numbers(cols[c], [r[j] for r in rows], c)
        self.assertEqual(cols["t"][-1], 3.0)
        # the k = 0 mode of the uniform state: sigma = -(b - 1 - a^2) / 2 -+ i sqrt(a^2 - (b - 1 - a^2)^2 / 4)
        # (the scene's header), to the eigensolver's tolerance
        self.assertAlmostEqual(mode[0], -0.1, delta=1e-9)
        self.assertAlmostEqual(abs(mode[1]), math.sqrt(4.0 - 0.01), delta=1e-9)

    def test_a_study_table(self):
        d = scratch("study")
        with open(os.path.join(d, "s.toml"), "w") as f:
            f.write(f'[study]\nscene = "{scene("bratu1d_fold.toml")}"\n\n[set]\n"output.xdmf" = false\n\n'
                    '[grid]\n"bratu.intervals" = [16, 32]\n\n[collect]\nevents = ["fold"]\nend = ["u_mid"]\n')
        keller("study", "s.toml", "--jobs", "1", "-o", "st", cwd=d)
        cols, order = keller_h5.read_study(os.path.join(d, "st", "s.h5"))
        header, rows = read_csv(os.path.join(d, "st", "s.csv"))
        self.assertEqual(order, header)
        for j, c in enumerate(header):
            if cols[c].dtype.kind == "U":
                self.assertEqual(list(cols[c]), [r[j] for r in rows], c)
            else:
                self.assert_same_numbers(cols[c], [r[j] for r in rows], c)
        self.assertEqual(list(cols["status"]), ["done", "done"])
        # the fold of the discrete Bratu problem converges to 3.513830719125 at second order
        for n, fold in zip(cols["bratu.intervals"], cols["event:fold"]):
            self.assertTrue(keller_h5.same_value(n, int(n)))
            self.assertAlmostEqual(fold, 3.513830719125, delta=2.0 / float(n) ** 2)


def main():
    global ARGS
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--keller", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--scratch", required=True)
    ARGS, rest = ap.parse_known_args()
    ARGS.keller, ARGS.source, ARGS.scratch = map(os.path.abspath, (ARGS.keller, ARGS.source, ARGS.scratch))
    os.makedirs(ARGS.scratch, exist_ok=True)
    unittest.main(argv=[sys.argv[0]] + rest, verbosity=2)


if __name__ == "__main__":
    main()
