"""``motion-studio tune kick --type N``: a robot type's own long kick (``motions.authoring.kick_types``) tuned
where it is played: the candidate is solved with the type's kinematics from its stance, a robot of that type
plays it, and --write goes to the type's override file (never to kick.toml, which type 0 plays)."""

from __future__ import annotations

import json
from dataclasses import replace

import pytest

from agent.motion import default_library
from motion_studio import tune_kick
from motions.authoring import kick_types
from motions.authoring.kick import PARAMS_PATH
from tests.motions.conftest import assert_shipped_as_generated


#: The files write angles to 0.01 deg (1.7e-4 rad); the tuner's candidate is solved afresh.
FILE_ROUNDING_RAD = 2e-4


@pytest.mark.parametrize("robot_type", sorted(kick_types.TYPE_KICKS))
def test_the_start_candidate_is_the_kick_the_type_plays(robot_type):
    stance, _ = kick_types.type_stance(robot_type)
    params, own, _ = kick_types.type_kick_params(robot_type, "kick_strong")
    assert own  # both types have values of their own
    candidate = tune_kick.library_for(params, stance, "kick_strong", robot_type=robot_type)
    shipped = default_library(robot_type, include_withheld=True)
    for name in ("kick_strong", "stand"):
        assert_shipped_as_generated(shipped.get(name), candidate.get(name), FILE_ROUNDING_RAD)
    # and it is not type 0's kick (the tuner would tune the wrong file)
    with pytest.raises(AssertionError):
        assert_shipped_as_generated(default_library(0).get("kick_strong"), candidate.get("kick_strong"),
                                    FILE_ROUNDING_RAD)


def test_writing_the_shipped_values_back_keeps_the_kick_and_its_history(tmp_path):
    target = tmp_path / "kick_type3.toml"
    target.write_text(kick_types.type_params_path(3).read_text(encoding="utf-8"), encoding="utf-8")
    params, own, before = kick_types.type_kick_params(3, "kick_strong")
    tune_kick.write_type_section(3, "kick_strong", params, "CMA-ES on here", "ours 5 m", target)
    again, own_again, provenance = kick_types.type_kick_params(3, "kick_strong", overrides_path=target)
    assert again == params
    # keys equal to kick.toml's section as type 3 solves it are not repeated (land_ms is 260 in both)
    assert own_again == {k: v for k, v in own.items() if k != "land_ms"}
    assert provenance.startswith("CMA-ES on here; started from the values of: ") and provenance.endswith(before)
    assert "measured = \"ours 5 m\"" in target.read_text(encoding="utf-8")


def test_a_new_type_file_gets_its_header(tmp_path):
    target = tmp_path / "kick_type1.toml"
    params, _, _ = kick_types.type_kick_params(1, "kick_strong")
    tune_kick.write_type_section(1, "kick_strong", params, "p", "m", target)
    text = target.read_text(encoding="utf-8")
    assert text.startswith("# Robot type 1's own kicks") and "python -m motions.authoring.kick_types 1" in text
    assert kick_types.type_kick_params(1, "kick_strong", overrides_path=target)[0] == params


def test_a_type_without_its_own_kick_is_one_line(capsys):
    assert tune_kick.main(["kick_strong", "--type", "2"]) == 2
    error = capsys.readouterr().err.strip()
    assert error.startswith("motion-studio tune kick: error: --type 2: no kick_strong of its own") and "\n" not in error


def test_a_short_run_on_our_simulator_plays_type_3_and_writes_its_file(tmp_path, capsys):
    """A real run: the start and two candidates of type 3's landing times, 13 placements each on our simulator
    by a type-3 robot; the shipped kick (the start) stands at every placement and moves the ball."""
    target = tmp_path / "kick_type3.toml"
    target.write_text(kick_types.type_params_path(3).read_text(encoding="utf-8"), encoding="utf-8")
    shipped_before = kick_types.type_params_path(3).read_text(encoding="utf-8")
    kick_before = PARAMS_PATH.read_text(encoding="utf-8")
    run = tmp_path / "run"
    assert tune_kick.main(["kick_strong", "--type", "3", "--generations", "1", "--popsize", "2",
                           "--only", "retract_ms,recover_ms", "--checkpoint", str(run), "--params", str(target),
                           "--write"]) == 0
    out = capsys.readouterr().out
    assert f"wrote {target}" in out and "type3/kick_strong.xml" not in out  # not the shipped file
    trace = [json.loads(line) for line in (run / "trace.jsonl").read_text().splitlines()]
    assert trace[0]["problem"] == "kick:kick_strong:type3" and "--only retract_ms,recover_ms --type 3" in trace[0]["command"]
    start = next(r for r in trace if r["kind"] == "evaluation" and r["iteration"] == -1)
    runs = start["result"]["runs"]
    assert len(runs) == len(tune_kick.PLACEMENTS) and not any(r["fell"] for r in runs)
    assert max(r["distance_m"] for r in runs) > 4.5
    assert "--type 3" in target.read_text(encoding="utf-8")
    assert kick_types.type_params_path(3).read_text(encoding="utf-8") == shipped_before
    assert PARAMS_PATH.read_text(encoding="utf-8") == kick_before


def _stopped_run(folder, command: str, values: dict) -> None:
    """A run folder's trace as the tuning room writes it: the start, then one generation, stopped."""
    runs = [{"distance_m": 7.9, "direction_error_deg": -4.0, "fell": False, "trapped": False, "backend": "real"}]
    rows = [{"kind": "run", "problem": "kick:kick_strong", "command": command},
            {"kind": "evaluation", "iteration": -1, "index": 0, "loss": -5.0, "values": {"retract_ms": 280},
             "result": {"runs": runs}},
            {"kind": "evaluation", "iteration": 0, "index": 0, "loss": -9.0, "values": values, "result": {"runs": runs}},
            {"kind": "iteration", "iteration": 0, "evaluations": 2, "best_loss": -9.0}]
    folder.mkdir()
    (folder / "trace.jsonl").write_text("".join(json.dumps(row) + "\n" for row in rows), encoding="utf-8")


def test_write_only_puts_a_stopped_run_s_best_into_a_copy_of_kick_toml(tmp_path, capsys):
    run, target = tmp_path / "run", tmp_path / "kick_candidate.toml"
    _stopped_run(run, "motion-studio tune kick kick_strong --backend real --only retract_ms", {"retract_ms": 340})
    kick_before = PARAMS_PATH.read_text(encoding="utf-8")
    assert tune_kick.main(["kick_strong", "--checkpoint", str(run), "--params", str(target), "--write-only"]) == 0
    out = capsys.readouterr().out
    assert f"wrote {target}" in out and "not the shipped file" in out and "kick_strong.xml" not in out
    assert PARAMS_PATH.read_text(encoding="utf-8") == kick_before
    from motions.authoring.kick import kick_params

    written = kick_params("kick_strong", target)
    assert written.retract_ms == 340
    assert written == replace(kick_params("kick_strong"), retract_ms=340)   # the rest: the shipped section
    assert kick_params("kick", target) == kick_params("kick")                # the other sections copied
    text = target.read_text(encoding="utf-8")
    assert ("motion-studio tune kick kick_strong --backend real --only retract_ms (best of generation 1 of a run of 1, "
            "written with --write-only)") in text
    assert "CMA-ES on the real rcssserver3d 0.7.3" in text and "distance 7.90-7.90 m" in text
