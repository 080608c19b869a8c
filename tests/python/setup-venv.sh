#!/usr/bin/env bash
# Create (once) the Python virtual environment with the pinned FMPy that the comparison
# tests run as the reference importer, the pinned libcosimpy (libcosim) the
# interoperability test runs the exported SSP in, and what the Python package's tests use
# (pandas, dask.distributed, pytest, and maturin, which builds the package from python/),
# and pythonfmu3, which builds an FMI 3.0 FMU from Python for the importer's tests.
#
#   tests/python/setup-venv.sh          # venv at "${TBI_VENV:-<repo>/target/venv}"
#
# Idempotent: when the venv already holds the pinned FMPy the script only checks it and
# exits. Prints the venv directory on its last line of standard output. Exits non-zero with
# a message on standard error when the venv cannot be created or FMPy cannot be installed.
set -euo pipefail

FMPY_VERSION="0.3.32"
LIBCOSIMPY_VERSION="0.0.6"
# The Python package's tests (tests/python/package) and its build.
PINS=("fmpy==$FMPY_VERSION" "libcosimpy==$LIBCOSIMPY_VERSION" "pandas==3.1.1"
    "dask==2026.8.0" "distributed==2026.8.0" "pytest==9.2.0" "maturin==1.16.0"
    "pythonfmu3==0.3.4")

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
VENV="${TBI_VENV:-$REPO/target/venv}"
PYTHON="${PYTHON:-python3}"

have_fmpy() {
    [ -x "$VENV/bin/python" ] && [ -x "$VENV/bin/fmpy" ] &&
        "$VENV/bin/python" -c "import sys, fmpy; sys.exit(0 if fmpy.__version__ == '$FMPY_VERSION' else 1)" \
            >/dev/null 2>&1 &&
        "$VENV/bin/python" - "${PINS[@]}" >/dev/null 2>&1 <<'PY'
import sys, importlib.metadata as m
for pin in sys.argv[1:]:
    name, version = pin.split("==")
    if m.version(name) != version:
        sys.exit(1)
PY
}

if have_fmpy; then
    echo "$VENV"
    exit 0
fi

# Serialise concurrent setups (parallel test binaries) on a lock next to the venv.
mkdir -p "$(dirname "$VENV")"
exec 9>"$VENV.lock"
if command -v flock >/dev/null 2>&1; then
    flock 9
fi
if have_fmpy; then
    echo "$VENV"
    exit 0
fi

if ! command -v "$PYTHON" >/dev/null 2>&1; then
    echo "setup-venv.sh: no '$PYTHON' interpreter on PATH (set PYTHON=... to choose one)" >&2
    exit 1
fi

if [ ! -x "$VENV/bin/python" ]; then
    echo "setup-venv.sh: creating venv at $VENV" >&2
    "$PYTHON" -m venv "$VENV" >&2 || {
        echo "setup-venv.sh: '$PYTHON -m venv $VENV' failed (on Debian: apt-get install python3-venv)" >&2
        exit 1
    }
fi

echo "setup-venv.sh: installing ${PINS[*]} into $VENV" >&2
"$VENV/bin/python" -m pip install --quiet --disable-pip-version-check "${PINS[@]}" >&2 || {
    echo "setup-venv.sh: pip could not install ${PINS[*]} into $VENV (libcosimpy needs Python >= 3.11 on x86_64 Linux)" >&2
    exit 1
}

if ! have_fmpy; then
    echo "setup-venv.sh: one of ${PINS[*]} is not importable from $VENV after installation" >&2
    exit 1
fi
echo "$VENV"
