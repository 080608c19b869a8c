#!/usr/bin/env bash
# The project's test command: builds everything (including the FMU shared objects), prepares
# the Python venv with FMPy used as the reference importer and the headless browser the
# report tests use, and runs every test.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
echo "== Python venv with FMPy (target/venv)"
bash tests/python/setup-venv.sh
echo "== headless Chromium for the report tests"
bash tests/browser/setup.sh
echo "== cargo build --release --workspace"
cargo build --release --workspace
echo "== cargo test --release --workspace"
cargo test --release --workspace
