#!/usr/bin/env bash
# Install (once) the headless browser the report tests open report.html in: Debian's
# Chromium. Idempotent: when /usr/bin/chromium runs, the script only prints its path.
#
#   tests/browser/setup.sh        # prints the browser's path on its last line
#
# Needs root (apt-get) on a machine without Chromium; exits non-zero with a message when
# it cannot be installed.
set -euo pipefail
BROWSER="${TBI_BROWSER:-/usr/bin/chromium}"
if [ -x "$BROWSER" ] && "$BROWSER" --version >/dev/null 2>&1; then
    echo "$BROWSER"
    exit 0
fi
if ! command -v apt-get >/dev/null 2>&1; then
    echo "setup.sh: no $BROWSER and no apt-get to install Debian's chromium (set TBI_BROWSER)" >&2
    exit 1
fi
SUDO=""
if [ "$(id -u)" != 0 ]; then
    SUDO="sudo"
fi
echo "setup.sh: installing Debian's chromium" >&2
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq >&2
$SUDO apt-get install -y -qq --no-install-recommends chromium >&2 || {
    echo "setup.sh: apt-get could not install chromium" >&2
    exit 1
}
"$BROWSER" --version >&2
echo "$BROWSER"
