#!/usr/bin/env bash
# Pinocchio golden data for the URDF that `articula export urdf` writes for a take (issue 3 §2c).
#
#   PY=$(bash ../shared/oracle/setup.sh)
#   tools/take_urdf_fixtures.sh "$PY" data/demo_walk.bvh demo_walk
#   tools/take_urdf_fixtures.sh "$PY" ../shared/data/bvh/cmu_01_01.bvh cmu_01_01
#
# Writes tests/fixtures/pinocchio/take_<name>/{states,rnea,crba,aba}.csv: 6 seeded random states
# (Pinocchio's own `template`), then Pinocchio 4.1's RNEA, CRBA and ABA (τ = the RNEA result,
# so ABA must give back a) on the exported URDF with the take's gravity (Y-up: 0,-9.81,0).
# The take is exported with de Leva's fixed fractions (--segments fractions), as the committed
# fixtures were: the check is of the model, URDF and algorithms, whatever the segment table.
# The URDF itself is not committed for real takes (it is re-exported by the real-take suite
# from ../shared/data/bvh); for the project's own demo walk it is committed as model.urdf.
set -euo pipefail
PY="$1"; TAKE="$2"; NAME="$3"
ORACLE="$(dirname "$0")/../../shared/oracle/pin_ref.py"
[ -f "$ORACLE" ] || ORACLE=../shared/oracle/pin_ref.py
OUT="tests/fixtures/pinocchio/take_$NAME"
mkdir -p "$OUT"
TMP="$(mktemp -d)"; trap 'rm -rf "$TMP"' EXIT
cargo run -q --release -- export urdf "$TAKE" --segments fractions -o "$TMP/model.urdf"
G=0,-9.81,0
"$PY" "$ORACLE" template --urdf "$TMP/model.urdf" --gravity "$G" --rows 6 --seed 7 --out "$OUT/states.csv"
"$PY" "$ORACLE" rnea --urdf "$TMP/model.urdf" --gravity "$G" --states "$OUT/states.csv" --out "$OUT/rnea.csv"
"$PY" "$ORACLE" crba --urdf "$TMP/model.urdf" --gravity "$G" --states "$OUT/states.csv" --out "$OUT/crba.csv"
# ABA with τ = RNEA(q, v, a): join the two tables column-wise
python3 - "$OUT/states.csv" "$OUT/rnea.csv" "$TMP/sa.csv" <<'PYEOF'
import csv, sys
s = list(csv.reader(open(sys.argv[1]))); t = list(csv.reader(open(sys.argv[2])))
keep = [i for i, h in enumerate(s[0]) if not h.startswith("tau:")]
tcols = [i for i, h in enumerate(t[0]) if h.startswith("tau:")]
with open(sys.argv[3], "w", newline="") as f:
    w = csv.writer(f)
    for rs, rt in zip(s, t):
        w.writerow([rs[i] for i in keep] + [rt[i] for i in tcols])
PYEOF
"$PY" "$ORACLE" aba --urdf "$TMP/model.urdf" --gravity "$G" --states "$TMP/sa.csv" --out "$OUT/aba.csv"
if [ "$NAME" = demo_walk ]; then cp "$TMP/model.urdf" "$OUT/model.urdf"; fi
echo "wrote $OUT"
