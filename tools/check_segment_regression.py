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
    print("\nall checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
