#!/usr/bin/env python3
"""Checks the segment-mass tables articula embeds (src/model/anthropometry/tables.rs) against
their CSV files, and the Zatsiorsky-Seluyanov regression against de Leva's (1996) fractions.

1. `ZATSIORSKY_SELUYANOV` in tables.rs holds exactly the rows of
   data/reference/zatsiorsky_seluyanov_1983_mass_regression.csv (segment, articula segment,
   b0, b1, b2), and `DE_LEVA_1996` the mass fractions of ../shared/reference/de_leva_1996.csv
   (when that folder is there; otherwise the Rust table's own fractions are used below).
2. At de Leva's reference subject (male, 73.0 kg, 174.1 cm: the regression sample's mean), the
   regression's segment masses, as % of body mass, agree with de Leva's male fractions within
   TOL_REFERENCE_PCT per cent of each (the comparison table is printed).
3. Over a grid of 50-110 kg and 1.50-2.00 m, the raw regression (before articula rescales it to
   the body mass) sums to within TOL_SUM_PCT per cent of the body mass, and no row is below
   articula's floor (a quarter of its share at the mean subject); the worst case is printed.
4. The signs of the mass dependence: at 1.75 m, going from 60 to 100 kg raises the trunk's and
   the thighs' share of body mass and lowers the shanks' (printed per segment).
5. `ZATSIORSKY_SELUYANOV_INERTIA` holds exactly the rows of
   data/reference/zatsiorsky_seluyanov_1983_inertia_regression.csv and `TRUNK_PARTS` those of
   data/reference/de_leva_1996_trunk_parts.csv; every inertia row evaluated at the sample's mean
   subject gives Zatsiorsky's Table 4.4 mean moment (the CSV's mean_kg_cm2) within
   TOL_MEAN_PCT (a least-squares fit passes through the means).
6. At the mean subject, the regression's radius of gyration of each segment (the trunk's parts
   combined about the trunk's centre with the parts' positions) over de Leva's segment length
   (../shared/reference/de_leva_1996.csv; the head's, not in that file, from tables.rs's
   head row as de Leva's Table 4 gives it: 242.9 mm) agrees with de Leva's radii within
   TOL_RADIUS_PCT (the comparison table is printed).
7. The radii of gyration articula uses (de Leva's, times the regression's change of r/H from
   the mean subject; src/model/anthropometry/inertia.rs) for a 60 and a 100 kg man of 1.75 m
   (printed): the thigh's and trunk's grow with body mass.

Standard library only. Run from the repository root: python3 tools/check_segment_regression.py
Exits non-zero (an AssertionError) when a check fails; writes nothing.
"""

import csv
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CSV_REGRESSION = ROOT / "data/reference/zatsiorsky_seluyanov_1983_mass_regression.csv"
CSV_DE_LEVA = ROOT.parent / "shared/reference/de_leva_1996.csv"
RUST_TABLES = ROOT / "src/model/anthropometry/tables.rs"

TOL_REFERENCE_PCT = 2.0  # per segment, relative, at the reference subject
TOL_MEAN_PCT = 1.5  # each inertia row at the sample mean against Table 4.4's mean moment
TOL_RADIUS_PCT = 2.0  # the regression's radii at the mean subject against de Leva's
CSV_INERTIA = ROOT / "data/reference/zatsiorsky_seluyanov_1983_inertia_regression.csv"
CSV_TRUNK_PARTS = ROOT / "data/reference/de_leva_1996_trunk_parts.csv"
HEAD_LENGTH_MM = 242.9  # de Leva (1996) Table 4, male head (vertex-C7); not in the shared CSV
TOL_SUM_PCT = 0.5  # the raw regression's sum against the body mass, over the grid
FLOOR = 0.25  # model::anthropometry::REGRESSION_FLOOR
REFERENCE = (73.0, 174.1)  # kg, cm

# articula's Segment variants and the CSV names
SEGMENT = {
    "Head": "head",
    "Trunk": "trunk",
    "UpperArm": "upper_arm",
    "Forearm": "forearm",
    "Hand": "hand",
    "Thigh": "thigh",
    "Shank": "shank",
    "Foot": "foot",
}
LIMBS = {"upper_arm", "forearm", "hand", "thigh", "shank", "foot"}


def copies(segment):
    return 2 if segment in LIMBS else 1


def read_csv(path):
    lines = [l for l in path.read_text().splitlines() if l and not l.startswith("#")]
    return list(csv.DictReader(lines))


def rust_regression(src):
    rows = re.findall(
        r'zs\(\s*"(\w+)",\s*Segment::(\w+),\s*([-\d.]+),\s*([-\d.]+),\s*([-\d.]+),?\s*\)', src
    )
    return [(p, SEGMENT[s], float(b0), float(b1), float(b2)) for p, s, b0, b1, b2 in rows]


def rust_de_leva(src):
    rows = re.findall(r"row\(\s*Segment::(\w+),\s*Sex::(\w+),\s*([-\d.]+),", src)
    return {(SEGMENT[s], sex.lower()): float(pct) for s, sex, pct in rows}


def eval_row(row, mass, height_cm):
    _, _, b0, b1, b2 = row
    return b0 + b1 * mass + b2 * height_cm


def main():
    src = RUST_TABLES.read_text()

    # 1. the Rust tables equal the CSV files
    want = [
        (r["segment"], r["articula_segment"], float(r["b0_kg"]), float(r["b1_kg_per_kg"]),
         float(r["b2_kg_per_cm"]))
        for r in read_csv(CSV_REGRESSION)
    ]
    got = rust_regression(src)
    assert len(want) == 10, f"{CSV_REGRESSION}: {len(want)} rows, expected 10"
    assert got == want, f"tables.rs ZATSIORSKY_SELUYANOV differs from the CSV:\n{got}\n{want}"
    print(f"ZATSIORSKY_SELUYANOV: {len(got)} rows, equal to {CSV_REGRESSION.relative_to(ROOT)}")
    de_leva = rust_de_leva(src)
    assert len(de_leva) == 16, f"DE_LEVA_1996: {len(de_leva)} rows parsed, expected 16"
    if CSV_DE_LEVA.exists():
        shared = {
            (r["segment"], r["sex"]): float(r["mass_pct"])
            for r in read_csv(CSV_DE_LEVA)
            if r["endpoints"] not in ("vertex-midgonion", "suprasternale-midhip")
        }
        assert shared == de_leva, f"DE_LEVA_1996 mass_pct differs from {CSV_DE_LEVA}"
        print(f"DE_LEVA_1996 mass fractions: equal to {CSV_DE_LEVA}")
    else:
        print(f"({CSV_DE_LEVA} not found: de Leva's fractions taken from tables.rs)")

    # 2. the regression at de Leva's reference subject against his male fractions
    m0, h0 = REFERENCE
    seg = {}
    for row in got:
        seg[row[1]] = seg.get(row[1], 0.0) + eval_row(row, m0, h0)
    total = sum(copies(s) * kg for s, kg in seg.items())
    print(f"\nat de Leva's reference subject, male {m0} kg, {h0} cm "
          f"(the raw regression sums to {total:.3f} kg, {100 * total / m0:.2f} % of the body):")
    print(f"{'segment':<10} {'regression kg':>13} {'regression %':>12} {'de Leva %':>9} "
          f"{'difference':>10}")
    worst = 0.0
    for s in SEGMENT.values():
        pct = 100 * seg[s] / m0
        ref = de_leva[(s, "male")]
        diff = 100 * (pct / ref - 1)
        worst = max(worst, abs(diff))
        print(f"{s:<10} {seg[s]:>13.3f} {pct:>12.3f} {ref:>9.2f} {diff:>+9.2f}%")
        assert abs(diff) < TOL_REFERENCE_PCT, f"{s}: {diff:+.2f} % from de Leva's fraction"
    print(f"largest difference {worst:.2f} % (tolerance {TOL_REFERENCE_PCT} %)")

    # 3. the raw sum and the floor over a grid of bodies
    total0 = sum(copies(r[1]) * eval_row(r, m0, h0) for r in got)
    worst_sum = (0.0, None)
    for mass in range(50, 111, 5):
        for h in range(150, 201, 5):
            s = sum(copies(r[1]) * eval_row(r, mass, h) for r in got)
            dev = 100 * (s / mass - 1)
            if abs(dev) > abs(worst_sum[0]):
                worst_sum = (dev, (mass, h))
            for r in got:
                floor = FLOOR * eval_row(r, m0, h0) / total0 * mass
                assert eval_row(r, mass, h) >= floor, f"{r[0]} below its floor at {mass} kg, {h} cm"
    dev, (mass, h) = worst_sum
    print(f"\nraw regression sum over 50-110 kg x 150-200 cm: largest deviation from the body "
          f"mass {dev:+.3f} % (at {mass} kg, {h} cm; tolerance {TOL_SUM_PCT} %); no row below "
          f"its floor")
    assert abs(dev) < TOL_SUM_PCT

    # 4. the share of body mass per segment at 60 and 100 kg, 175 cm, after rescaling
    def shares(mass, h):
        seg = {}
        for r in got:
            seg[r[1]] = seg.get(r[1], 0.0) + eval_row(r, mass, h)
        tot = sum(copies(s) * kg for s, kg in seg.items())
        return {s: 100 * kg / tot for s, kg in seg.items()}

    light, heavy = shares(60, 175), shares(100, 175)
    print("\nshare of body mass (% per segment, one side), 175 cm, rescaled to the body mass:")
    print(f"{'segment':<10} {'60 kg':>7} {'100 kg':>7} {'de Leva':>7}")
    for s in SEGMENT.values():
        print(f"{s:<10} {light[s]:>7.3f} {heavy[s]:>7.3f} {de_leva[(s, 'male')]:>7.2f}")
    assert heavy["trunk"] > light["trunk"] and heavy["thigh"] > light["thigh"]
    assert heavy["shank"] < light["shank"] and heavy["head"] < light["head"]
    print("heavier at the same height: trunk and thighs up, head and shanks down")

    check_inertia(src, got, de_leva)
    print("\nall checks passed")
    return 0


AXES = {"SAGITTAL": "sagittal", "TRANSVERSE": "transverse", "LONGITUDINAL": "longitudinal"}


def rust_inertia(src):
    rows = re.findall(
        r'zi\(\s*"(\w+)",\s*Segment::(\w+),\s*(\w+),\s*([-\d.]+),\s*([-\d.]+),\s*([-\d.]+),'
        r'\s*([-\d.]+),?\s*\)',
        src,
    )
    return [(p, SEGMENT[s], AXES[a], float(b0), float(b1), float(b2), float(mean))
            for p, s, a, b0, b1, b2, mean in rows]


def rust_trunk_parts(src):
    rows = re.findall(
        r'TrunkPart\s*\{\s*part:\s*"(\w+)",\s*length_mm:\s*([-\d.]+),\s*com_pct:\s*([-\d.]+),?\s*\}',
        src,
    )
    return [(p, float(l), float(c)) for p, l, c in rows]


def radii_cm(mass_rows, inertia_rows, parts, mass, h_cm):
    """Radius of gyration (cm) of each segment about its three axes at (mass kg, h_cm cm):
    the parts' moments about their own centres, plus m d^2 across the trunk for the two
    transverse axes (no floors: the grid here stays inside the sample)."""
    k = h_cm / REFERENCE[1]
    along, top = {}, 0.0
    for p, length, com in parts:
        along[p] = (top + com / 100 * length) / 10 * k  # cm from suprasternale
        top += length
    out = {}
    for seg in SEGMENT.values():
        ps = [r for r in mass_rows if r[1] == seg]
        m = {r[0]: eval_row(r, mass, h_cm) for r in ps}
        total = sum(m.values())
        centre = sum(m[p] * along.get(p, 0.0) for p in m) / total
        spread = sum(m[p] * (along.get(p, 0.0) - centre) ** 2 for p in m)
        r = []
        for axis in ("sagittal", "transverse", "longitudinal"):
            i = sum(b0 + b1 * mass + b2 * h_cm
                    for p, s, a, b0, b1, b2, _ in inertia_rows if p in m and a == axis)
            if axis != "longitudinal":
                i += spread
            r.append((i / total) ** 0.5)
        out[seg] = r
    return out


def check_inertia(src, mass_rows, de_leva_mass):
    # 5. the Rust tables equal the CSV files; each row passes through Table 4.4's mean
    want = [
        (r["segment"], r["articula_segment"], r["axis"], float(r["b0_kg_cm2"]),
         float(r["b1_kg_cm2_per_kg"]), float(r["b2_kg_cm2_per_cm"]), float(r["mean_kg_cm2"]))
        for r in read_csv(CSV_INERTIA)
    ]
    got = rust_inertia(src)
    assert len(want) == 30, f"{CSV_INERTIA}: {len(want)} rows, expected 30"
    assert got == want, f"tables.rs ZATSIORSKY_SELUYANOV_INERTIA differs from the CSV:\n{got}\n{want}"
    print(f"\nZATSIORSKY_SELUYANOV_INERTIA: {len(got)} rows, equal to {CSV_INERTIA.relative_to(ROOT)}")
    parts_csv = [(r["segment"], float(r["length_mm"]), float(r["com_pct"]))
                 for r in read_csv(CSV_TRUNK_PARTS)]
    parts = rust_trunk_parts(src)
    assert parts == parts_csv, f"tables.rs TRUNK_PARTS differs from the CSV:\n{parts}\n{parts_csv}"
    print(f"TRUNK_PARTS: equal to {CSV_TRUNK_PARTS.relative_to(ROOT)}")
    m0, h0 = REFERENCE
    print(f"each row at the sample mean ({m0} kg, {h0} cm) against Table 4.4's mean moment (kg*cm^2):")
    worst = 0.0
    for p, s, a, b0, b1, b2, mean in got:
        v = b0 + b1 * m0 + b2 * h0
        dev = 100 * (v / mean - 1)
        worst = max(worst, abs(dev))
        assert abs(dev) < TOL_MEAN_PCT, f"{p} {a}: {v:.1} vs {mean} ({dev:+.2f} %)"
    print(f"  largest difference {worst:.2f} % over 30 rows (tolerance {TOL_MEAN_PCT} %)")

    # 6. the regression's radii at the mean subject against de Leva's
    shared = {}
    if CSV_DE_LEVA.exists():
        for r in read_csv(CSV_DE_LEVA):
            if r["sex"] == "male" and r["endpoints"] not in ("vertex-midgonion", "suprasternale-midhip"):
                length = float(r["length_mm"]) if r["length_mm"] else HEAD_LENGTH_MM
                shared[r["segment"]] = (length, [float(r["r_sag_pct"]), float(r["r_trans_pct"]),
                                                 float(r["r_long_pct"])])
    else:
        print(f"({CSV_DE_LEVA} not found: radii against de Leva skipped)")
    r0 = radii_cm(mass_rows, got, parts, m0, h0)
    if shared:
        print("radii of gyration at the mean subject, % of de Leva's segment length "
              "(regression / de Leva):")
        print(f"{'segment':<10} {'sagittal':>15} {'transverse':>15} {'longitudinal':>15}")
        worst = 0.0
        for s in SEGMENT.values():
            length, dl = shared[s]
            cells = []
            for a in range(3):
                pct = 100 * r0[s][a] / (length / 10)
                dev = 100 * (pct / dl[a] - 1)
                worst = max(worst, abs(dev))
                cells.append(f"{pct:6.2f}/{dl[a]:5.1f}")
                assert abs(dev) < TOL_RADIUS_PCT, f"{s} axis {a}: {pct:.2f} vs {dl[a]}"
            print(f"{s:<10} " + " ".join(f"{c:>15}" for c in cells))
        print(f"largest difference {worst:.2f} % (tolerance {TOL_RADIUS_PCT} %)")
        # the trunk's centre from its parts against de Leva's suprasternale-mid-hip trunk
        top, z, mt = 0.0, 0.0, 0.0
        for p, length, com in parts:
            mp = sum(eval_row(r, m0, h0) for r in mass_rows if r[0] == p)
            z += mp * (top + com / 100 * length)
            mt += mp
            top += length
        supr = [r for r in read_csv(CSV_DE_LEVA)
                if r["endpoints"] == "suprasternale-midhip" and r["sex"] == "male"][0]
        dl_centre = float(supr["com_pct"]) / 100 * top
        print(f"trunk centre from suprasternale: parts {z / mt:.1f} mm, de Leva {dl_centre:.1f} mm "
              f"(of {top:.1f} mm)")
        assert abs(z / mt - dl_centre) < 5.0

    # 7. the radii articula uses for a 60 and a 100 kg man of 1.75 m
    print("\nradii of gyration articula uses (% of the segment length), man of 175 cm:")
    print(f"{'segment':<10} {'60 kg sag/trans/long':>24} {'100 kg sag/trans/long':>24}")
    dl = {s: v[1] for s, v in shared.items()} if shared else None
    use = {}
    for mass in (60, 100):
        rn = radii_cm(mass_rows, got, parts, mass, 175.0)
        use[mass] = {s: [(dl[s][a] if dl else 100.0) * rn[s][a] / r0[s][a] * h0 / 175.0
                         for a in range(3)] for s in SEGMENT.values()}
    for s in SEGMENT.values():
        fmt = lambda v: "/".join(f"{x:.2f}" for x in v)
        print(f"{s:<10} {fmt(use[60][s]):>24} {fmt(use[100][s]):>24}")
    assert use[100]["thigh"][1] > use[60]["thigh"][1] and use[100]["trunk"][1] > use[60]["trunk"][1]
    print("heavier at the same height: the thighs' and trunk's radii grow")


if __name__ == "__main__":
    sys.exit(main())
