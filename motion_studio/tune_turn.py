"""Fit the turn-gain curve (``[turn_gain]`` of ``motions/params/dynamic_elements.toml``) to the turn the turn
motions make on our simulator.

Measure: the turn per motion of ``turn_left`` and ``turn_right`` played back to back at a grid of gains
(``motion_studio.skill_bench.turn.gain_sweep``, truth heading). Fit: a straight line turn = a + b * gain
(least squares over both sides), which is the curve's model (``agent.motion.dynamic.TurnGain``):
``predicted_base_deg`` = the line at ``min_gain``, ``predicted_slope_deg`` = its rise from ``min_gain`` to 1,
and the request -> gain map is its inverse (``offset_deg`` = base, ``span_deg`` = slope). Only the
``[turn_gain]`` section is rewritten (the other sections and their comments stay as they are).

Run::

    python -m motion_studio.tune_turn --write
"""

from __future__ import annotations

import argparse
import datetime
import re
from dataclasses import fields
from pathlib import Path

import numpy as np

from agent.motion.dynamic import DEFAULT_PARAMS_PATH, TurnGain, load_dynamic_params
from motion_studio.skill_bench.turn import gain_sweep

#: Gains measured by default.
FIT_GAINS = (0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)
#: Smallest gain of the fitted curve: the turn motions scale from a step in place, so small gains still step
#: properly and turn a little (the seed agent's 0.3 would make ~12 deg the smallest turn).
MIN_GAIN = 0.05
MOTIONS = 6


def fit_turn_gain(rows: list[dict[str, float | bool]], min_gain: float = MIN_GAIN,
                  provenance: str = "") -> tuple[TurnGain, float]:
    """The curve fitted to sweep rows (gain, left_deg, right_deg); returns it and the fit's RMS residual [deg].

    Raises:
        ValueError: fewer than two gains, a fall in the sweep, or a line that does not rise with the gain.
    """
    if len(rows) < 2:
        raise ValueError(f"need at least two gains to fit a line, got {len(rows)}")
    fallen = [row["gain"] for row in rows if row.get("left_fell") or row.get("right_fell")]
    if fallen:
        raise ValueError(f"the robot fell at gains {fallen}; a curve fitted through falls would mislead")
    gains = np.array([float(row["gain"]) for row in rows for _ in (0, 1)])
    turns = np.array([float(row[side]) for row in rows for side in ("left_deg", "right_deg")])
    slope, intercept = np.polyfit(gains, turns, 1)
    if slope <= 0.0:
        raise ValueError(f"the turn does not grow with the gain (slope {slope:.3g} deg per unit gain)")
    residual = float(np.sqrt(np.mean((intercept + slope * gains - turns) ** 2)))
    base = float(intercept + slope * min_gain)
    rise = float(slope * (1.0 - min_gain))
    curve = TurnGain(min_gain=min_gain, offset_deg=round(base, 3), span_deg=round(rise, 3),
                     predicted_base_deg=round(base, 3), predicted_slope_deg=round(rise, 3), provenance=provenance)
    return curve, residual


def _toml(value: object) -> str:
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    return repr(float(value)) if isinstance(value, float) else str(value)


def section_text(curve: TurnGain) -> str:
    """The ``[turn_gain]`` section, with the formulas as comments."""
    values = {f.name: getattr(curve, f.name) for f in fields(curve)}
    lines = ["[turn_gain]", f"provenance = {_toml(values.pop('provenance'))}",
             "# gain = min_gain + (1 - min_gain) * min(span_deg, max(0, |turn_deg| - offset_deg)) / span_deg"]
    lines += [f"{key} = {_toml(values[key])}" for key in ("min_gain", "offset_deg", "span_deg")]
    lines.append("# Predicted turn of one turn motion at a gain: "
                 "base_deg + slope_deg * (gain - min_gain) / (1 - min_gain).")
    lines += [f"{key} = {_toml(values[key])}" for key in ("predicted_base_deg", "predicted_slope_deg")]
    return "\n".join(lines) + "\n"


def replace_section(text: str, name: str, section: str) -> str:
    """``text`` with TOML section ``[name]`` (up to the next section) replaced by ``section`` (appended if
    missing)."""
    pattern = re.compile(rf"^\[{re.escape(name)}\]\n.*?(?=^\[|\Z)", re.S | re.M)
    if pattern.search(text):
        following = pattern.search(text)
        assert following is not None
        tail = text[following.end():]
        return text[:following.start()] + section + ("\n" if tail else "") + tail
    return text.rstrip("\n") + "\n\n" + section


def write_curve(curve: TurnGain, path: Path = DEFAULT_PARAMS_PATH) -> None:
    """Rewrite the ``[turn_gain]`` section of ``path`` and check that the file still loads to ``curve``.

    Raises:
        ValueError: the rewritten file does not load back to the curve (the file is left unchanged).
    """
    old = path.read_text(encoding="utf-8")
    new = replace_section(old, "turn_gain", section_text(curve))
    path.write_text(new, encoding="utf-8")
    try:
        loaded = load_dynamic_params(path).turn_gain
        if loaded != curve:
            raise ValueError(f"{path}: [turn_gain] reads back as {loaded}, expected {curve}")
    except ValueError:
        path.write_text(old, encoding="utf-8")
        raise


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--min-gain", type=float, default=MIN_GAIN, help="smallest gain of the curve")
    parser.add_argument("--motions", type=int, default=MOTIONS, help="motions per gain and side")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--write", action="store_true", help="rewrite [turn_gain] of the parameter file")
    parser.add_argument("--params", type=Path, default=DEFAULT_PARAMS_PATH, help="dynamic elements file")
    args = parser.parse_args(argv)
    rows = gain_sweep(FIT_GAINS, args.motions, args.seed)
    for row in rows:
        print(f"gain {row['gain']:.2f}: left {row['left_deg']:6.2f} deg, right {row['right_deg']:6.2f} deg")
    table = ", ".join(f"{row['gain']:g}: {(float(row['left_deg']) + float(row['right_deg'])) / 2:.2f}"
                      for row in rows)
    provenance = (f"fitted on our simulator by python -m motion_studio.tune_turn on {datetime.date.today()}: "
                  f"turn per motion [deg] of turn_left/turn_right (mean of both, {args.motions} motions each, "
                  f"truth heading) at gain {table}; least-squares line; min_gain {args.min_gain}")
    curve, residual = fit_turn_gain(rows, args.min_gain, provenance)
    print(f"fit: {curve.predicted_base_deg} deg at gain {curve.min_gain}, +{curve.predicted_slope_deg} deg to gain 1,"
          f" RMS residual {residual:.2f} deg")
    if args.write:
        write_curve(curve, args.params)
        print(f"wrote [turn_gain] of {args.params}")


if __name__ == "__main__":
    main()


__all__ = ["FIT_GAINS", "MIN_GAIN", "fit_turn_gain", "replace_section", "section_text", "write_curve"]
