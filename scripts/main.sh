#!/usr/bin/env bash
# The main job: sets up the environment, then runs the most complete thing the toolkit does.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$ROOT/scripts/setup_env.sh"
cd "$ROOT"
exec .venv/bin/motion-studio demo "$@"
