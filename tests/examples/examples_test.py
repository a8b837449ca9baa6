#!/usr/bin/env python3
"""The scenes of examples/ as a user runs them: each solved on 2 ranks (fewer rays than the
default, so that the test is quick), rendered small, and checked for what can go wrong in a
hand-written scene.

Usage: examples_test.py RADIOSITY MPIEXEC EXAMPLES_DIR [NAME ...]
(mpiexec's flags from MPIEXEC_NUMPROC_FLAG, MPIEXEC_PREFLAGS and MPIEXEC_POSTFLAGS in the
environment, as tests/CMakeLists.txt sets them; NAME: room, office, furnace, all by default).

Every example: exit 0 from solve, render and export; no warning in the solve's log (a face
wound the wrong way, an MTL statement that is not read, a face without material all warn);
`radiosity info --json` counts patches > 0; no ray escaped (the scenes are closed: a gap or a room
wound inside out lets rays out; the solve warns only where nearly all of them leave). Then, per
example:
- room, office: the energy balance. In a closed scene every watt emitted is absorbed somewhere:
  sum A E = sum A (1 - rho) H over the groups, H = (B - E) / rho from each group's mean radiosity
  (`export --groups-csv`) and its material's rho and E (read from the MTL). Holds to the sampling
  error of F's columns: 1 % allowed at 64 rays (measured 0.1 %; a window pane laid over an
  uncut wall, two faces facing the same way in the same place, is 1-4 % off).
- office: contacts were cut: the patches under the cabinet, the desk's legs and the luminaires
  are hidden (`info` counts them) and make up about their footprints' share of the area.
- furnace: the analytic answer of furnace.obj's comments. The hearth's rate is exact whatever
  the sampling (everything it sees is black at 300 K, and its rows sum to 1): to 1e-4. The roof's
  and the walls' rates depend on the view factor hearth -> roof (a closed form): within 4
  estimated errors plus 0.5 %. The rates sum to 0 (the enclosure's balance).
Standard library only (the result is read through `radiosity info --json` and `radiosity export`).
"""
import csv
import json
import math
import os
import re
import shlex
import subprocess
import sys
import tempfile

SIGMA = 5.670374419e-8
RAYS = "64"


def parallel_rectangles(a, b, c):
    """View factor between two directly opposed parallel a x b rectangles c apart."""
    x, y = a / c, b / c
    return 2 / (math.pi * x * y) * (
        math.log(math.sqrt((1 + x * x) * (1 + y * y) / (1 + x * x + y * y)))
        + x * math.sqrt(1 + y * y) * math.atan(x / math.sqrt(1 + y * y))
        + y * math.sqrt(1 + x * x) * math.atan(y / math.sqrt(1 + x * x))
        - x * math.atan(x) - y * math.atan(y))


class Runner:
    def __init__(self, radiosity, mpiexec, examples, work):
        self.radiosity, self.mpiexec, self.examples, self.work = radiosity, mpiexec, examples, work
        self.failures = 0

    def fail(self, name, message):
        print(f"FAIL: {name}: {message}", file=sys.stderr)
        self.failures += 1

    def run(self, args, ranks=None):
        command = [self.radiosity] + args
        if ranks:
            command = ([self.mpiexec, os.environ.get("MPIEXEC_NUMPROC_FLAG") or "-n", str(ranks)]
                       + shlex.split(os.environ.get("MPIEXEC_PREFLAGS", "")) + [self.radiosity]
                       + shlex.split(os.environ.get("MPIEXEC_POSTFLAGS", "")) + args)
        done = subprocess.run(command, capture_output=True, text=True, timeout=600)
        return done.returncode, done.stdout, done.stderr

    def solve(self, name, extra):
        """Solves examples/NAME.obj on 2 ranks and renders it; returns (result path, the solve's
        log, patches, hidden patches), or None if it failed."""
        result = os.path.join(self.work, name + ".h5")
        scene = os.path.join(self.examples, name + ".obj")
        code, _, log = self.run(["solve", scene, "--rays", RAYS, "-o", result] + extra, ranks=2)
        if code != 0:
            self.fail(name, f"solve: exit {code}\n{log}")
            return None
        warnings = [line for line in log.splitlines() if "warning" in line.lower()]
        if warnings:
            self.fail(name, "the solve warned:\n  " + "\n  ".join(warnings))
        code, info, err = self.run(["info", result, "--json"])
        if code != 0:
            self.fail(name, f"info: exit {code}\n{err}")
            return None
        summary = json.loads(info)["summary"]
        patches, hidden = summary["patches"], summary.get("hidden_patches", 0)
        print(f"{name}: {patches} patches")
        if patches <= 0:
            self.fail(name, f"{patches} patches")
        # A closed scene lets no ray out: a gap between faces, or a room wound inside out (every
        # face lit from outside), shows as rays that escaped.
        escaped = re.findall(r"(\d+) rays escaped", log)
        if not escaped or any(int(n) for n in escaped):
            self.fail(name, f"rays escaped the closed scene: {escaped}")
        code, _, err = self.run(["render", result, "--width", "96", "--height", "96",
                                 "-o", os.path.join(self.work, name + ".png")])
        if code != 0:
            self.fail(name, f"render: exit {code}\n{err}")
        return result, log, patches, hidden

    def groups(self, name, result):
        table = os.path.join(self.work, name + "-groups.csv")
        code, _, err = self.run(["export", result, "--groups-csv", table])
        if code != 0:
            self.fail(name, f"export: exit {code}\n{err}")
            return []
        with open(table, newline="") as f:
            return list(csv.DictReader(f))

    def materials(self, name):
        """The MTL's materials: name -> (rho, E), each three channels."""
        found, current = {}, None
        with open(os.path.join(self.examples, name + ".mtl")) as f:
            for line in f:
                words = line.split("#")[0].split()
                if not words:
                    continue
                if words[0] == "newmtl":
                    current = words[1]
                    found[current] = [[0.5] * 3, [0.0] * 3]
                elif words[0] in ("Kd", "Ke"):
                    values = [float(v) for v in words[1:]]
                    if len(values) == 1:  # "Kd 0.7": grey
                        values *= 3
                    found[current][0 if words[0] == "Kd" else 1] = values
        return found

    def energy_balance(self, name, result):
        """Emitted = absorbed, per channel, in a closed lit scene."""
        materials = self.materials(name)
        rows = self.groups(name, result)
        if not rows:
            return
        for c, channel in enumerate(("red", "green", "blue")):
            emitted = absorbed = 0.0
            for row in rows:
                material = row["name"].split(" (")[0]  # 'material (group g)'
                rho, e = materials[material][0][c], materials[material][1][c]
                area, b = float(row["area"]), float(row["radiosity_" + channel])
                emitted += area * e
                absorbed += area * (1 - rho) * (b - e) / rho
            defect = abs(absorbed - emitted) / emitted
            print(f"{name}: {channel}: emitted {emitted:.6g}, absorbed {absorbed:.6g} "
                  f"({100 * defect:.2f} % apart)")
            if not defect < 0.01:
                self.fail(name, f"{channel}: absorbed {absorbed:.6g} against emitted "
                                f"{emitted:.6g}: {100 * defect:.2f} % apart (1 % allowed)")

    def room(self):
        solved = self.solve("room", ["--length-unit", "m"])
        if solved:
            self.energy_balance("room", solved[0])

    def office(self):
        solved = self.solve("office", ["--length-unit", "m"])
        if not solved:
            return
        result, log, patches, hidden = solved
        self.energy_balance("office", result)
        # Hidden: the floor under the cabinet (0.55 m^2) and the legs (4 x 0.0025), the ceiling
        # over the luminaires (2 x 0.36) and the desk top's underside over the legs (4 x 0.0025):
        # 1.29 m^2 of the scene's 130.54 m^2, 0.988 %, exactly where the cuts follow the outlines.
        share = re.search(r"hidden: (\d+) patches \(([0-9.e+-]+) % of the area\)", log)
        if not share or hidden == 0:
            self.fail("office", "no hidden patches: the contacts under the furniture were not cut")
            return
        print(f"office: {hidden} hidden patches, {share.group(2)} % of the area (0.988 % expected)")
        if not abs(float(share.group(2)) - 0.988) < 0.005:
            self.fail("office", f"hidden: {share.group(2)} % of the area, not the footprints' "
                                f"0.988 %: the contacts were not cut along their outlines")

    def furnace(self):
        solved = self.solve("furnace", ["--thermal", os.path.join(self.examples, "furnace.toml")])
        if not solved:
            return
        rows = {row["name"]: row for row in self.groups("furnace", solved[0])}
        hearth = 0.85 * 0.6 * 0.4 * SIGMA * (1200.0 ** 4 - 300.0 ** 4)
        roof = -parallel_rectangles(0.6, 0.4, 0.5) * hearth
        expected = {"hearth": (hearth, 1e-4 * hearth), "roof": (roof, None),
                    "walls": (-hearth - roof, None)}
        total = 0.0
        for surface, (exact, tolerance) in expected.items():
            if surface not in rows:
                self.fail("furnace", f"no group '{surface}' in the groups table: {list(rows)}")
                continue
            rate, error = float(rows[surface]["heat_rate"]), float(rows[surface]["heat_rate_error"])
            total += rate
            allowed = tolerance if tolerance else 4 * error + 0.005 * abs(exact)
            print(f"furnace: {surface}: {rate:.2f} W +- {error:.2f} (exact {exact:.2f} W, "
                  f"{rate - exact:+.2f}, {allowed:.2f} allowed)")
            if not abs(rate - exact) <= allowed:
                self.fail("furnace", f"{surface}: {rate} W, exact {exact} W: off by "
                                     f"{rate - exact:+.3g} W, more than {allowed:.3g}")
        if not abs(total) <= 1e-6 * hearth:
            self.fail("furnace", f"the rates sum to {total} W, not 0")


def main():
    if len(sys.argv) < 4:
        print(__doc__, file=sys.stderr)
        return 2
    radiosity, mpiexec, examples = sys.argv[1:4]
    names = sys.argv[4:] or ["room", "office", "furnace"]
    with tempfile.TemporaryDirectory() as work:
        runner = Runner(radiosity, mpiexec, os.path.abspath(examples), work)
        for name in names:
            getattr(runner, name)()
    if runner.failures:
        print(f"{runner.failures} failure(s)", file=sys.stderr)
        return 1
    print("PASS")
    return 0


if __name__ == "__main__":
    sys.exit(main())
