#!/usr/bin/env bash
# Record the reference results that tests/tests/golden.rs compares against:
# summary.json of every scenario (the embedded default and master/tests/data/*.toml) with
# both solvers, without wall_time_s and steps_ahead (both depend on timing), and the
# exported modelDescription.xml files without their generationDateAndTime, and the SSP's
# SystemStructure.ssd.
#
#   tests/golden/record.sh [TBI_BINARY]      # default: target/release/tbi
#
# Re-record only when a change is meant to change results (say why in the commit).
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
TBI="${1:-$REPO/target/release/tbi}"
OUT="$REPO/tests/golden"
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT

scenarios=("default:")
for f in "$REPO"/master/tests/data/*.toml; do
    scenarios+=("$(basename "$f" .toml):$f")
done
for entry in "${scenarios[@]}"; do
    name="${entry%%:*}"
    file="${entry#*:}"
    for solver in monolithic cosim; do
        "$TBI" run ${file:+"$file"} --solver "$solver" --out "$WORK/$name-$solver" --quiet >/dev/null
        python3 - "$WORK/$name-$solver/summary.json" "$OUT/$name-$solver.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
s.pop("wall_time_s", None)
s.pop("steps_ahead", None)
json.dump(s, open(sys.argv[2], "w"), indent=1, sort_keys=True)
open(sys.argv[2], "a").write("\n")
PY
    done
    "$TBI" export ${file:+"$file"} --out "$WORK/$name-fmus" >/dev/null
    for fmu in bridge train; do
        unzip -p "$WORK/$name-fmus/$fmu.fmu" modelDescription.xml |
            sed -E 's/ generationDateAndTime="[^"]*"//' >"$OUT/$name-$fmu.xml"
    done
    unzip -p "$WORK/$name-fmus/system.ssp" SystemStructure.ssd >"$OUT/$name-system.ssd"
done
echo "recorded into $OUT"
