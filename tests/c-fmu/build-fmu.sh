#!/usr/bin/env bash
# Build one of the C FMUs of this folder (FMI 2.0 Co-Simulation, Linux x86-64) into an .fmu:
#
#   tests/c-fmu/build-fmu.sh sprung_mass vehicle.fmu     # the outside vehicle of docs/fmus.md
#   tests/c-fmu/build-fmu.sh oscillator oscillator.fmu
#
# Compiles MODEL.c with the C compiler ($CC, default cc) and packs modelDescription.xml
# (MODEL.xml) and binaries/linux64/MODEL.so with Python's zipfile. The FMUs share no code
# with the project's crates.
set -euo pipefail
if [ $# -ne 2 ]; then
    echo "usage: $0 MODEL OUT.fmu   (MODEL: sprung_mass, oscillator, counter)" >&2
    exit 2
fi
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
model="$1"
out="$2"
if [ ! -f "$here/$model.c" ] || [ ! -f "$here/$model.xml" ]; then
    echo "build-fmu.sh: no $model.c and $model.xml in $here" >&2
    exit 1
fi
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
"${CC:-cc}" -shared -fPIC -O2 -std=c99 -fvisibility=hidden -I "$here" "$here/$model.c" \
    -o "$tmp/$model.so" -lm
python3 - "$here/$model.xml" "$tmp/$model.so" "$model" "$tmp/out.fmu" <<'PY'
import sys
import zipfile

xml, so, model, out = sys.argv[1:]
with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
    z.write(xml, "modelDescription.xml")
    z.write(so, f"binaries/linux64/{model}.so")
PY
mv "$tmp/out.fmu" "$out"
echo "$out"
