#!/usr/bin/env bash
# The project's test command: checks the formatting and clippy's lints (warnings are errors),
# builds everything (including the FMU shared objects), prepares
# the Python venv with FMPy used as the reference importer and the headless browser the
# report tests use, runs every test, then builds the Python package and runs its tests.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
echo "== Python venv with FMPy (target/venv)"
bash tests/python/setup-venv.sh
echo "== headless Chromium for the report tests"
bash tests/browser/setup.sh
# The Python package (python/) is built by maturin below, from the same sources.
echo "== cargo fmt --check"
cargo fmt --all --check
echo "== cargo build --release --workspace"
cargo build --release --workspace --exclude tbi-python
echo "== cargo clippy --release --workspace --all-targets -- -D warnings"
cargo clippy --release --workspace --exclude tbi-python --all-targets -- -D warnings
echo "== cargo test --release --workspace"
cargo test --release --workspace --exclude tbi-python
echo "== the Python package tbi, built from python/ into the venv, and its tests (pytest)"
bash tests/python/install-package.sh
"$(bash tests/python/setup-venv.sh)/bin/python" -m pytest -q -p no:cacheprovider tests/python/package
