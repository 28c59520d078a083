"""``motion-studio bench sim --repeat``: the figures are the median run's, and every run's factor is listed."""

from __future__ import annotations

import json
import subprocess
import sys


def test_repeat_reports_the_median_run_and_lists_every_run():
    out = subprocess.run([sys.executable, "-m", "motion_studio", "bench", "sim", "--robots", "1", "--cycles", "20",
                          "--repeat", "3", "--json"], capture_output=True, text=True, timeout=300, check=True)
    figures = json.loads(out.stdout)
    runs = figures["runs_realtime_factor"]
    assert len(runs) == 3 and runs == sorted(runs)
    assert round(figures["realtime_factor"], 2) == runs[1]
    assert figures["cycles"] == 20 and figures["robots"] == 1 and figures["agents_parse"] is True


def test_one_run_has_no_list():
    out = subprocess.run([sys.executable, "-m", "motion_studio", "bench", "sim", "--robots", "1", "--cycles", "20",
                          "--json"], capture_output=True, text=True, timeout=300, check=True)
    assert "runs_realtime_factor" not in json.loads(out.stdout)
