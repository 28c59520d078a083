"""Tables, plots and the calibrated-parameter file of a calibration run."""

from __future__ import annotations

import datetime
import subprocess
from pathlib import Path

from motion_studio.calibration.agreement import Outcome
from motion_studio.calibration.fit import Evaluation
from motion_studio.figures import write_png


def ending(outcome: Outcome) -> str:
    """One word for how a skill trace ended: stood (never fell), rose (fell, standing at the end), down (fell,
    not standing at the end) or low (never fell but not standing at the end, e.g. crouched)."""
    if outcome.fell:
        return "rose" if outcome.standing else "down"
    return "stood" if outcome.standing else "low"


def _ending_column(result: Evaluation, name: str) -> str:
    """The real and our ending of ``name`` ("rose/down"), with a ``!`` where they differ; blank if scripted."""
    if name not in result.outcomes:
        return ""
    real, ours = result.outcomes[name]
    return f"{ending(real)}/{ending(ours)}" + ("!" if real != ours else "")


def agreement_table(before: Evaluation, after: Evaluation | None = None) -> str:
    """Per-trace score (0 = agrees) before and after, how the real run and our replay ended (a ``!`` marks a
    different ending: the transfer issue's fall/no-fall target), and each trace's worst measure."""
    lines = [f"{'trace':32s} {'before':>7s}" + (f" {'after':>7s}" if after else "")
             + f"  {'ends real/ours':15s} worst measure (real / ours)"]
    for name, score in before.scores.items():
        shown = after or before
        worst = max(shown.details[name], key=lambda m: m.error, default=None)
        text = (f"{worst.name} {worst.real:.3g} / {worst.ours:.3g} {worst.unit}" if worst else "-")
        line = f"{name:32s} {score:7.2f}" + (f" {after.scores[name]:7.2f}" if after else "")
        lines.append(f"{line}  {_ending_column(shown, name):15s} {text}")
    total = f"{'objective (mean + blow-ups)':32s} {before.objective:7.3f}" + (f" {after.objective:7.3f}" if after else "")
    lines.append(total)
    if before.outcomes:
        counts = " -> ".join(f"{e.same_outcomes()}" for e in (before, after) if e is not None)
        lines.append(f"same outcome as the real robot (fell or not, standing at the end or not): {counts} of "
                     f"{len(before.outcomes)} skill traces")
    return "\n".join(lines)


def measure_table(result: Evaluation) -> str:
    """Every measure of every trace: real, ours, unit, error."""
    lines = [f"{'trace':28s} {'measure':26s} {'real':>10s} {'ours':>10s} unit       error"]
    for name, found in result.details.items():
        for m in found:
            lines.append(f"{name:28s} {m.name:26s} {m.real:10.4g} {m.ours:10.4g} {m.unit:10s} {m.error:5.2f}")
    return "\n".join(lines)


def plot_agreement(before: Evaluation, after: Evaluation | None, path: Path) -> Path:
    """A bar chart of the per-trace scores before and after, as PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = list(before.scores)
    fig, ax = plt.subplots(figsize=(10, 0.35 * len(names) + 1.5))
    y = range(len(names))
    ax.barh([i + 0.2 for i in y], [before.scores[n] for n in names], height=0.4, label="before")
    if after:
        ax.barh([i - 0.2 for i in y], [after.scores[n] for n in names], height=0.4, label="after")
    ax.set_yticks(list(y), names)
    ax.invert_yaxis()
    ax.set_xlabel("disagreement with the real rcssserver3d (0 = same; 1 = noticeable for a skill)")
    ax.legend()
    return write_png(fig, path)


def _revision() -> str:
    try:
        return subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                              check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def write_physics_file(path: Path, after: Evaluation, before: Evaluation, command: str, traces: list[str]) -> None:
    """Write the fitted values as ``[physics]`` with a provenance header (command, date, revision, figures)."""
    lines = [
        "# Physical parameters of our MuJoCo world fitted to real rcssserver3d 0.7.3 recordings; they override",
        "# the defaults of sim/physics_params.py (see its docstring for what each means).",
        f"# Made by: {command}",
        f"# Date: {datetime.date.today().isoformat()}, revision {_revision()}",
        f"# Traces: {', '.join(traces)}",
        f"# Objective (mean per-trace disagreement, 0 = same): {before.objective:.3f} before, {after.objective:.3f} after",
        "",
        "[physics]",
    ]
    for name, value in _grouped(after.values).items():
        lines.append(f"{name} = {value!r}".replace("(", "[").replace(")", "]"))
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def _grouped(values: dict[str, float]) -> dict[str, object]:
    """``contact_solimp[0]`` etc. gathered into full tuples (missing elements from the defaults)."""
    from sim.physics_params import PhysicsParams

    out: dict[str, object] = {}
    defaults = PhysicsParams()
    for name, value in values.items():
        if name.endswith("]"):
            field, index = name[:-1].split("[")
            current = list(out.get(field, getattr(defaults, field)))  # type: ignore[arg-type]
            current[int(index)] = value
            out[field] = tuple(current)
        else:
            out[name] = value
    for field, value in list(out.items()):
        if field in ("contact_solimp", "ball_solimp"):
            solimp = list(value)  # type: ignore[arg-type]
            solimp[1] = max(solimp[0], solimp[1])
            out[field] = tuple(solimp)
    return out
