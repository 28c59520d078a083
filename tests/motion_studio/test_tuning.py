"""The tuning room's skeleton: problems refuse bad input in one line, a failing rollout is a failed candidate,
CMA-ES (pycma) and the CasADi trust region find minima in the box, a run killed with SIGKILL resumes to the
same result, and the plots are drawn from the trace."""

from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import casadi
import numpy as np
import pytest

from motion_studio.tuning import (CMAES, Constraint, CurveView, ModelSpec, Parameter, Problem, TuningError,
                                  make_backend, run, subset)
from motion_studio.tuning.run_folder import draw_plots
from motion_studio.tuning.trace import read_trace
from motion_studio.tuning.trust_region import TrustRegion

TARGET_DEG = np.array([5.0, 10.0, 20.0, 30.0])


def bowl(values: dict[str, float]) -> dict[str, float]:
    return {"loss": (values["a"] - 0.3) ** 2 + 2.0 * (values["b"] + 0.5) ** 2}


def bowl_problem() -> Problem:
    return Problem("bowl", (Parameter("a", -2.0, 2.0, unit="m"), Parameter("b", -2.0, 2.0, unit="deg")), bowl,
                   start={"a": 1.5, "b": 1.5})


def turns(values: dict[str, float]) -> dict[str, float]:
    """A stand-in turn-gain sweep: the turn per motion [deg] at each knot's gain, mildly nonlinear."""
    gains = np.array([values[f"g{i}"] for i in range(4)])
    turn = 40.0 * gains + 3.0 * np.sin(3.0 * gains)
    return {"loss": float(np.mean((turn - TARGET_DEG) ** 2)), **{f"turn_{i}": float(t) for i, t in enumerate(turn)}}


def turn_problem() -> Problem:
    def loss(figures, values):
        return sum((figures[f"turn_{i}"] - TARGET_DEG[i]) ** 2 for i in range(4)) / 4

    def monotone(values):
        return [(values[f"g{i + 1}"] - values[f"g{i}"], 0.01, casadi.inf) for i in range(3)]

    view = CurveView("gain", "turn [deg]", lambda v, result: ([v[f"g{i}"] for i in range(4)], list(TARGET_DEG)),
                     lambda r: ([0.1, 0.2, 0.3, 0.4], [r[f"turn_{i}"] for i in range(4)]))
    return Problem("toy_turn", tuple(Parameter(f"g{i}", 0.02, 1.0) for i in range(4)), turns,
                   start={f"g{i}": 0.5 for i in range(4)}, curve=view,
                   model=ModelSpec(tuple(f"turn_{i}" for i in range(4)), loss, monotone))


# ---- bad input: one line naming it -------------------------------------------------------------------
def test_a_bound_with_lower_above_upper_is_refused_naming_the_parameter():
    with pytest.raises(TuningError, match=r"parameter 'knee_deg': lower bound 5.0 > upper bound -5.0") as error:
        Parameter("knee_deg", 5.0, -5.0)
    assert "\n" not in str(error.value)


def test_an_unknown_parameter_is_refused_naming_it_and_the_known_ones():
    with pytest.raises(TuningError, match=r"unknown parameter 'c'.*known: a, b"):
        Problem("bowl", bowl_problem().parameters, bowl, start={"c": 1.0})
    with pytest.raises(TuningError, match=r"--only: unknown parameter 'strike_m'; known: a, b"):
        subset(bowl_problem().parameters, ["a", "strike_m"])


def test_a_nan_objective_stops_the_run_naming_the_problem_and_candidate(tmp_path):
    problem = Problem("nan", bowl_problem().parameters, lambda values: {"loss": math.nan})
    with pytest.raises(TuningError, match=r"problem 'nan': objective returned nan for a=0, b=0") as error:
        run(problem, lambda p: CMAES(p.x0(), 0.2, max_iterations=2), tmp_path)
    assert "\n" not in str(error.value)


def test_a_diverging_rollout_is_a_failed_candidate_and_the_run_goes_on(tmp_path):
    def evaluate(values):
        if values["a"] > 0.5:
            raise FloatingPointError("simulation diverged: qacc is nan")
        return bowl(values)

    problem = Problem("diverge", bowl_problem().parameters, evaluate, start={"a": 1.5, "b": 1.5}, fail_loss=50.0)
    result = run(problem, lambda p: CMAES(p.x0(), 0.3, seed=2, max_iterations=10), tmp_path)
    failed = [r for r in result.records if r["kind"] == "evaluation" and r["failed"]]
    assert failed and all(r["loss"] == 50.0 for r in failed)
    assert failed[0]["result"]["failed"] == "FloatingPointError: simulation diverged: qacc is nan"
    assert result.best["values"]["a"] <= 0.5 and result.best["loss"] < 1.0


def test_a_checkpoint_of_another_problem_is_refused(tmp_path):
    run(bowl_problem(), lambda p: CMAES(p.x0(), 0.3, max_iterations=1), tmp_path)
    other = Problem("other", bowl_problem().parameters, bowl)
    with pytest.raises(TuningError, match="checkpoint of problem 'bowl'"):
        run(other, lambda p: CMAES(p.x0(), 0.3, max_iterations=1), tmp_path)


# ---- optimizers -------------------------------------------------------------------------------------
def test_cmaes_finds_the_minimum_of_a_shifted_bowl_inside_the_box(tmp_path):
    seen = []

    def evaluate(values):
        seen.append(values)
        return bowl(values)

    problem = Problem("bowl", bowl_problem().parameters, evaluate, start={"a": 1.5, "b": 1.5})
    result = run(problem, lambda p: CMAES(p.x0(), 0.3, seed=1, max_iterations=40), tmp_path)
    assert result.best["values"] == pytest.approx({"a": 0.3, "b": -0.5}, abs=0.01)
    assert all(-2.0 <= v["a"] <= 2.0 and -2.0 <= v["b"] <= 2.0 for v in seen)
    assert result.evaluations == len(seen) and result.iterations == 40


def test_a_finished_run_resumed_with_more_iterations_goes_on_where_it_stopped(tmp_path):
    """Resuming takes the new call's budget: the 5 more iterations continue the first 5 (the same candidates as
    one run of 10), where the pickled budget of 5 ended the resumed run at once."""
    short = run(bowl_problem(), lambda p: CMAES(p.x0(), 0.3, seed=2, max_iterations=5), tmp_path / "a")
    extended = run(bowl_problem(), lambda p: CMAES(p.x0(), 0.3, seed=2, max_iterations=10), tmp_path / "a")
    whole = run(bowl_problem(), lambda p: CMAES(p.x0(), 0.3, seed=2, max_iterations=10), tmp_path / "b")
    assert short.iterations == 5 and extended.iterations == 10
    assert extended.best["loss"] == whole.best["loss"] < short.best["loss"]
    xs = [r["x"] for r in read_trace(tmp_path / "a" / "trace.jsonl") if r["kind"] == "evaluation"]
    assert xs == [r["x"] for r in read_trace(tmp_path / "b" / "trace.jsonl") if r["kind"] == "evaluation"]


def test_steps_and_bounds_map_to_and_from_the_box():
    duration = Parameter("shift_ms", 300, 700, step=20, unit="ms")
    assert duration.from_unit(0.37) == 440 and isinstance(duration.from_unit(0.37), int)
    height = Parameter("torso_height_m", 0.30, 0.36, unit="m")
    assert height.from_unit(height.to_unit(0.3333)) == pytest.approx(0.3333)
    assert height.from_unit(-1.0) == 0.30 and height.from_unit(2.0) == 0.36


def test_the_trust_region_keeps_its_constraints_and_needs_far_fewer_rollouts_than_cmaes(tmp_path):
    problem = turn_problem()
    region = run(problem, lambda p: TrustRegion(p, p.x0(), 0.2, 1e-3, max_iterations=25), tmp_path / "tr")
    cma = run(problem, lambda p: CMAES(p.x0(), 0.2, seed=0, max_iterations=40), tmp_path / "cma")
    assert region.best["loss"] < 0.01 and region.best["loss"] < cma.best["loss"]
    assert region.evaluations < cma.evaluations / 5
    gains = [region.best["values"][f"g{i}"] for i in range(4)]
    assert all(b - a >= 0.01 - 1e-6 for a, b in zip(gains, gains[1:]))  # monotone as constrained
    plots = draw_plots(region, problem)
    assert [p.name for p in plots] == ["objective.png", "curve.png"] and all(p.stat().st_size > 5000 for p in plots)


def test_a_figure_constraint_is_a_penalty_for_cmaes():
    problem = Problem("c", bowl_problem().parameters, bowl, constraints=(Constraint("a small", "loss", high=0.5),))
    assert problem.penalised_loss({"loss": 1.5}) == pytest.approx(1.5 + 10.0 * 1.0)
    assert problem.penalised_loss({"loss": 0.2}) == 0.2


# ---- backends ---------------------------------------------------------------------------------------
def test_local_processes_give_the_in_process_result(tmp_path):
    problem = bowl_problem()
    here = run(problem, lambda p: CMAES(p.x0(), 0.3, seed=5, max_iterations=3), tmp_path / "here")
    backend = make_backend("processes", workers=2)
    try:
        there = run(problem, lambda p: CMAES(p.x0(), 0.3, seed=5, max_iterations=3), tmp_path / "there", backend)
    finally:
        backend.close()
    assert there.best == here.best and there.evaluations == here.evaluations


def test_an_unknown_backend_is_named():
    with pytest.raises(TuningError, match="unknown rollout backend 'gpu'; known: inprocess, processes, ray"):
        make_backend("gpu")


# ---- kill -9 and resume -----------------------------------------------------------------------------
SCRIPT = textwrap.dedent('''
    import json, sys, time
    from pathlib import Path
    from motion_studio.tuning import CMAES, Parameter, Problem, run

    def evaluate(values):
        time.sleep(0.03)
        with open(sys.argv[2], "a") as log:
            log.write(json.dumps(values) + "\\n")
        return {"loss": (values["a"] - 0.3) ** 2 + 0.5 * (values["b"] + 0.2) ** 2 + 0.1 * values["a"] * values["b"]}

    problem = Problem("bowl", (Parameter("a", -1, 1, unit="m"), Parameter("b", -1, 1, unit="deg")), evaluate,
                      start={"a": 0.8, "b": 0.8})
    result = run(problem, lambda p: CMAES(p.x0(), 0.3, popsize=6, seed=4, max_iterations=8), Path(sys.argv[1]))
    print(json.dumps({"best": result.best, "evaluations": result.evaluations}))
''')


def _evaluations(run_dir: Path) -> list[tuple]:
    records = [r for r in read_trace(run_dir / "trace.jsonl") if r["kind"] == "evaluation"]
    return sorted((r["iteration"], r["index"], json.dumps(r["values"]), r["loss"]) for r in records)


def test_a_run_killed_with_sigkill_resumes_and_ends_as_an_uninterrupted_run(tmp_path):
    script = tmp_path / "tune_bowl.py"
    script.write_text(SCRIPT)
    whole = subprocess.run([sys.executable, str(script), str(tmp_path / "whole"), str(tmp_path / "whole.log")],
                           capture_output=True, text=True, timeout=120, check=True)
    killed_dir, log = tmp_path / "killed", tmp_path / "killed.log"
    process = subprocess.Popen([sys.executable, str(script), str(killed_dir), str(log)], stdout=subprocess.PIPE)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        trace = killed_dir / "trace.jsonl"
        if trace.is_file() and trace.read_text().count('"kind": "evaluation"') >= 22:
            break
        time.sleep(0.01)
    os.kill(process.pid, signal.SIGKILL)
    process.wait()
    finished_before = len(log.read_text().splitlines())
    assert 22 <= finished_before < 49  # killed mid-run, inside an iteration
    resumed = subprocess.run([sys.executable, str(script), str(killed_dir), str(log)],
                             capture_output=True, text=True, timeout=120, check=True)
    assert json.loads(resumed.stdout) == json.loads(whole.stdout)
    assert _evaluations(killed_dir) == _evaluations(tmp_path / "whole")
    # no finished rollout was run again (one in flight at the kill may be)
    assert len(log.read_text().splitlines()) <= 49 + 1
