#!/usr/bin/env bash
# Build the Python package tbi from the local sources (python/, by maturin) into the test venv,
# with the FMU libraries of this checkout bundled (tbi/lib), and check it imports.
#
#   tests/python/install-package.sh     # after tests/python/setup-venv.sh and cargo build --release
#
# Nothing prebuilt is used: maturin compiles python/ (and the crates it depends on) here.
set -euo pipefail

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
VENV="${TBI_VENV:-$REPO/target/venv}"
cd "$REPO"

for lib in libbridge.so libtrain.so libwind.so; do
    if [ ! -f "target/release/$lib" ]; then
        echo "install-package.sh: target/release/$lib is missing; run cargo build --release first" >&2
        exit 1
    fi
done
mkdir -p python/tbi/lib
cp target/release/libbridge.so target/release/libtrain.so target/release/libwind.so python/tbi/lib/

# maturin and the package's dependencies are pinned in the venv (setup-venv.sh): build with
# them, not with a fresh download.
PATH="$VENV/bin:$PATH" "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check \
    --no-build-isolation --no-deps --force-reinstall ./python >&2 || {
    echo "install-package.sh: pip could not build and install ./python into $VENV" >&2
    exit 1
}
"$VENV/bin/python" -c "import tbi, sys; sys.exit(0 if tbi.default_scenario()['name'] else 1)" || {
    echo "install-package.sh: the installed package tbi does not import from $VENV" >&2
    exit 1
}
echo "install-package.sh: tbi installed into $VENV" >&2
