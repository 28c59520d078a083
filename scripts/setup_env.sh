#!/usr/bin/env bash
# Creates .venv (Python 3.11) and installs the toolkit with the exact pins of constraints.txt.
# Idempotent: re-running only installs what changed. Sourced by scripts/main.sh and scripts/test.sh.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

find_python() {
    for candidate in python3.11 python3; do
        if command -v "$candidate" >/dev/null 2>&1 &&
           "$candidate" -c 'import sys; sys.exit(0 if sys.version_info[:2] == (3, 11) else 1)'; then
            echo "$candidate"; return 0
        fi
    done
    return 1
}

PYTHON="$(find_python)" || { echo "error: Python 3.11 is required (python3.11 not found)" >&2; exit 1; }

if [ ! -x .venv/bin/python ]; then
    echo "creating .venv with $PYTHON ..." >&2
    if ! "$PYTHON" -m venv .venv 2>/dev/null; then
        # Debian ships venv separately; install it when we are allowed to.
        if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
            apt-get update -qq && apt-get install -y -qq python3.11-venv >/dev/null
            rm -rf .venv && "$PYTHON" -m venv .venv
        else
            echo "error: '$PYTHON -m venv' failed; install python3.11-venv" >&2; exit 1
        fi
    fi
fi

STAMP=.venv/.installed-$(cat pyproject.toml constraints.txt | sha256sum | cut -c1-16)
if [ ! -f "$STAMP" ]; then
    # Quiet, with one progress line per step: pip's own output goes to a log, shown only if a step fails
    # (setuptools' build warnings about the editable install are noise to a new user).
    LOG=.venv/install.log
    : > "$LOG"
    step() {  # step N TEXT COMMAND...: run COMMAND with its output in the log, report its time
        local number="$1" text="$2"; shift 2
        local started=$SECONDS
        echo "[$number/2] $text ..." >&2
        if ! PIP_DISABLE_PIP_VERSION_CHECK=1 "$@" >>"$LOG" 2>&1; then
            echo "error: step $number ($text) failed; the last lines of $LOG:" >&2
            tail -n 25 "$LOG" >&2
            exit 1
        fi
        echo "[$number/2] $text: done in $((SECONDS - started)) s" >&2
    }
    step 1 "upgrading pip" .venv/bin/python -m pip install -q --upgrade pip
    step 2 "installing the toolkit and the $(grep -c '==' constraints.txt) pinned packages of constraints.txt (the first time: several minutes)" \
        .venv/bin/python -m pip install -q -c constraints.txt -e ".[dev]"
    rm -f .venv/.installed-* && touch "$STAMP"
fi
