#!/usr/bin/env bash
# Sets up the environment (browser included where it can be installed), then runs the whole test suite.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$ROOT/scripts/setup_env.sh"
bash "$ROOT/scripts/setup_browser.sh" || echo "note: headless Chromium could not be installed; browser tests will skip" >&2
cd "$ROOT"
exec .venv/bin/python -m pytest "$@"
