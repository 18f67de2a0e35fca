#!/usr/bin/env python3
"""Loads articula's OpenSim outputs with OpenSim itself and checks them against articula's CSV.

For one take, writes with the articula binary:
  export states -o states.sto   and  -o states.csv
  id            -o id.sto       and  -o id.csv
  a session's   export id session_id.sto (`set consistent off`, as `id`'s default)
  export grf    -o grf.mot (+ grf.xml) and -o grf.csv
  export trc    -o markers.trc (mm) and markers_m.trc (--trc-units m), export positions -o positions.csv
then loads each with the `opensim` wheel (PyPI: `pip install opensim`):
  opensim.TimeSeriesTable(path)      for .sto / .mot,
  opensim.TimeSeriesTableVec3(path)  for .trc,
  opensim.ExternalLoads(xml, True)   for the XML (its forces' columns must exist in the .mot),
and checks the column labels, the row count, the times and every number against the CSV of the
same command: |sto - csv| <= RTOL * |csv| + ATOL (RTOL 1e-9: the OpenSim files carry 11
significant digits; ATOL 1e-9 in the file's unit, for values that are zero up to rounding).

Run (from the repository root, after `cargo build --release`):
  python3 -m venv /tmp/venv-osim && /tmp/venv-osim/bin/pip install opensim numpy
  /tmp/venv-osim/bin/python tools/check_opensim.py [TAKE.bvh] [--bin target/release/articula]
TAKE defaults to data/demo_walk.bvh. Exits 0 when every check passes, 1 on a failure, and 0 with
a "skipped" message when `opensim` cannot be imported.
"""

import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

RTOL = 1e-9
ATOL = 1e-9


def run(binary, args, may_fail_with=None):
    """Runs articula; a failure is fatal unless its message holds `may_fail_with` (then False)."""
    out = subprocess.run([binary] + args, capture_output=True, text=True)
    if out.returncode != 0:
        if may_fail_with and may_fail_with in out.stderr:
            return False
        sys.exit(f"articula {' '.join(args)} failed:\n{out.stderr}")
    return True


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header = rows[0]
    cols = {h: [float(r[i]) for r in rows[1:]] for i, h in enumerate(header)}
    return header, cols


class Checker:
    def __init__(self):
        self.failures = []
        self.checks = 0

    def close(self, what, got, want, scale=1.0):
        self.checks += 1
        want = want * scale
        if abs(got - want) > RTOL * abs(want) + ATOL:
            self.failures.append(f"{what}: {got!r} vs CSV {want!r}")
            return False
        return True

    def equal(self, what, got, want):
        self.checks += 1
        if got != want:
            self.failures.append(f"{what}: {got!r}, expected {want!r}")


def check_table(c, opensim, path, csv_path, mapping, expect_degrees):
    """mapping: sto label -> (csv column, scale) for every column of the .sto, in order."""
    t = opensim.TimeSeriesTable(path)
    header, cols = read_csv(csv_path)
    labels = list(t.getColumnLabels())
    c.equal(f"{path}: labels", labels, [m[0] for m in mapping])
    c.equal(f"{path}: rows", t.getNumRows(), len(cols["time"]))
    in_deg = t.getTableMetaDataAsString("inDegrees")
    c.equal(f"{path}: inDegrees", in_deg, "yes" if expect_degrees else "no")
    times = t.getIndependentColumn()
    bad = 0
    for i, tt in enumerate(times):
        bad += not c.close(f"{path}: time row {i}", tt, cols["time"][i])
    for j, (label, (col, scale)) in enumerate(mapping):
        data = t.getDependentColumnAtIndex(j).to_numpy()
        for i, x in enumerate(data):
            if not c.close(f"{path}: {label} row {i}", float(x), cols[col][i], scale):
                bad += 1
                if bad > 10:
                    return
    print(f"  {os.path.basename(path)}: {len(labels)} columns x {t.getNumRows()} rows, "
          f"inDegrees={in_deg}: loaded, labels and numbers match the CSV")


def check_grf(c, opensim, p):
    header, _ = read_csv(p("grf.csv"))
    feet = []
    for h in header[1:]:
        foot = h.split(":")[1]
        if foot not in feet:
            feet.append(foot)
    mapping = []
    for f in feet:
        for stem, what in [("ground_force_v", "grf"), ("ground_force_p", "cop"),
                           ("ground_torque_", "moment")]:
            for ax in "xyz":
                mapping.append((f"{f}_{stem}{ax}", (f"{what}:{f}:{ax}", 1.0)))
    check_table(c, opensim, p("grf.mot"), p("grf.csv"), mapping, False)
    loads = opensim.ExternalLoads(p("grf.xml"), True)
    labels = set(opensim.TimeSeriesTable(p("grf.mot")).getColumnLabels())
    c.equal("grf.xml: forces", loads.getSize(), len(feet))
    c.equal("grf.xml: datafile", loads.getDataFileName(), "grf.mot")
    for i in range(loads.getSize()):
        ef = loads.get(i)
        for ident in (ef.getForceIdentifier(), ef.getPointIdentifier(), ef.getTorqueIdentifier()):
            for ax in "xyz":
                c.equal(f"grf.xml: {ef.getName()} column {ident}{ax} in grf.mot",
                        ident + ax in labels, True)
        c.equal(f"grf.xml: {ef.getName()} force expressed in", ef.getForceExpressedInBodyName(), "ground")
        c.equal(f"grf.xml: {ef.getName()} point expressed in", ef.getPointExpressedInBodyName(), "ground")
    print(f"  grf.xml: ExternalLoads with {loads.getSize()} ExternalForce "
          f"({', '.join(loads.get(i).getName() + ' on ' + loads.get(i).getAppliedToBodyName() for i in range(loads.getSize()))}), "
          "their force, point and torque columns found in grf.mot")


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(here)
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("take", nargs="?", default=os.path.join(root, "data", "demo_walk.bvh"))
    ap.add_argument("--bin", default=None, help="articula binary (default: target/release)")
    ap.add_argument("--keep", default=None, help="write the files into this folder and keep them")
    a = ap.parse_args()
    try:
        import opensim
    except ImportError as e:
        print(f"skipped: the `opensim` Python package is not importable ({e}); "
              "install it with `pip install opensim` (PyPI wheel) to run these checks")
        return 0
    binary = a.bin or os.path.join(
        os.environ.get("CARGO_TARGET_DIR", os.path.join(root, "target")), "release", "articula")
    if not os.path.exists(binary):
        sys.exit(f"{binary}: no such binary; run `cargo build --release` or give --bin")
    out = a.keep or tempfile.mkdtemp(prefix="articula-opensim-")
    os.makedirs(out, exist_ok=True)
    p = lambda name: os.path.join(out, name)
    take = a.take
    print(f"opensim {opensim.__version__}; take {take}; files in {out}")
    c = Checker()

    # states: q, v, a; rotations in degrees in the .sto
    run(binary, ["export", "states", take, "-o", p("states.sto")])
    run(binary, ["export", "states", take, "-o", p("states.csv")])
    header, _ = read_csv(p("states.csv"))
    t = opensim.TimeSeriesTable(p("states.sto"))
    units = t.getTableMetaDataAsString("units")
    mapping = []
    for h in header[1:]:
        kind, coord = h.split(":", 1)
        suffix = {"q": "", "v": "_u", "a": "_dudt"}[kind]
        rot = "rotation" in coord or ":w" in coord
        mapping.append((coord + suffix, (h, 180.0 / math.pi if rot else 1.0)))
    check_table(c, opensim, p("states.sto"), p("states.csv"), mapping, True)
    print(f"    units: {units}")

    # inverse dynamics: <coord>_moment (N m) / <coord>_force (N)
    run(binary, ["id", take, "-o", p("id.sto")])
    run(binary, ["id", take, "-o", p("id.csv")])
    header, _ = read_csv(p("id.csv"))
    coords = [h for h in header[1:] if h.startswith("tau:")]
    mapping = [(f"{h[4:]}_{'force' if 'position' in h else 'moment'}", (h, 1.0)) for h in coords]
    check_table(c, opensim, p("id.sto"), p("id.csv"), mapping, False)
    # with ground contact the header says the take's consistency, kept as the table's metadata
    # (the same figures the CSV's sidecar holds under "consistency")
    with open(p("id.csv") + ".json") as f:
        consistency = json.load(f).get("consistency")
    keys = list(opensim.TimeSeriesTable(p("id.sto")).getTableMetaDataKeys())
    c.equal("id.sto metadata `residuals` present iff the take has contact",
            "residuals" in keys, consistency is not None)
    if "residuals" in keys:
        line = opensim.TimeSeriesTable(p("id.sto")).getTableMetaDataAsString("residuals")
        print(f"    residuals: {line}")
    # the session's twin of `id -o id.sto`: the same writer, the same numbers
    with open(p("id.session"), "w") as f:
        f.write(f"load {take}\nset consistent off\nexport id {p('session_id.sto')}\n")
    run(binary, ["run", p("id.session")])
    check_table(c, opensim, p("session_id.sto"), p("id.csv"), mapping, False)

    # ground reactions: external loads .mot and its XML (a take that never stands has none)
    if run(binary, ["export", "grf", take, "-o", p("grf.mot")], "no ground contact"):
        run(binary, ["export", "grf", take, "-o", p("grf.csv")])
        check_grf(c, opensim, p)
    else:
        print("  grf.mot: skipped, the take never stands on a floor (no ground reactions)")

    # markers: joint centres, mm and m, against export positions (m)
    run(binary, ["export", "positions", take, "-o", p("positions.csv")])
    header, cols = read_csv(p("positions.csv"))
    joints = []
    for h in header[1:]:
        j = h[len("pos:"):].rsplit(":", 1)[0]
        if j not in joints:
            joints.append(j)
    for name, flags, unit, scale in [("markers.trc", [], "mm", 1000.0),
                                     ("markers_m.trc", ["--trc-units", "m"], "m", 1.0)]:
        run(binary, ["export", "trc", take, "-o", p(name)] + flags)
        t = opensim.TimeSeriesTableVec3(p(name))
        c.equal(f"{name}: markers", list(t.getColumnLabels()), joints)
        c.equal(f"{name}: rows", t.getNumRows(), len(cols["time"]))
        c.equal(f"{name}: Units", t.getTableMetaDataAsString("Units"), unit)
        times = t.getIndependentColumn()
        bad = 0
        for i in range(t.getNumRows()):
            bad += not c.close(f"{name}: time row {i}", times[i], cols["time"][i])
            row = t.getRowAtIndex(i)
            for m, j in enumerate(joints):
                v = row[m]
                for k, ax in enumerate("xyz"):
                    bad += not c.close(f"{name}: {j}.{ax} row {i}", v.get(k), cols[f"pos:{j}:{ax}"][i], scale)
            if bad > 10:
                break
        print(f"  {name}: {len(joints)} markers x {t.getNumRows()} rows in {unit}: loaded, "
              "positions match export positions")

    if c.failures:
        print(f"FAILED: {len(c.failures)} of {c.checks} checks")
        for f in c.failures[:30]:
            print("  " + f)
        return 1
    print(f"ok: {c.checks} checks passed (numbers within {RTOL:g} relative + {ATOL:g} absolute)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
