#!/usr/bin/env bash
# Build the wheel of the Python package tbi from the local sources (python/, by maturin) into
# target/wheels, and install it into the test venv; check it imports.
#
#   tests/python/install-package.sh     # after tests/python/setup-venv.sh
#
# The wheel carries its FMU libraries (tbi/_lib/libbridge.so, libtrain.so, libwind.so), built
# by python/build.rs: nothing prebuilt is used and nothing of the checkout is read at run time.
# maturin prints cargo's progress.
set -euo pipefail

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
VENV="${TBI_VENV:-$REPO/target/venv}"
cd "$REPO"

rm -rf target/wheels
# maturin and the package's dependencies are pinned in the venv (setup-venv.sh): build with
# them, not with a fresh download.
PATH="$VENV/bin:$PATH" "$VENV/bin/maturin" build --release --manifest-path python/Cargo.toml \
    --out target/wheels >&2 || {
    echo "install-package.sh: maturin could not build the wheel of ./python" >&2
    exit 1
}
WHEEL="$(ls target/wheels/tbi-*.whl)"
"$VENV/bin/python" -m pip install --quiet --disable-pip-version-check --no-deps \
    --force-reinstall "$WHEEL" >&2 || {
    echo "install-package.sh: pip could not install $WHEEL into $VENV" >&2
    exit 1
}
"$VENV/bin/python" -c "import tbi, sys; sys.exit(0 if tbi.default_scenario()['name'] else 1)" || {
    echo "install-package.sh: the installed package tbi does not import from $VENV" >&2
    exit 1
}
echo "install-package.sh: $WHEEL installed into $VENV" >&2
