"""The real-server kick rollout (motion_studio.realserver.rollout_kick) without the real server: truth from a
recorded real monitor stream, the kick measured from truth, the trainer commands' timing, the re-exec into the
private namespace, the kick tuner's backends (``--backend real|both``) and the two-server kick check on stand-in
rollouts."""

from __future__ import annotations

import gzip
import math
from pathlib import Path

import pytest

from motion_studio import tune_kick
from motion_studio.kick_rollout import KickRun, Placement
from motion_studio.realserver import rollout_kick
from motion_studio.realserver import session as real_session
from motion_studio.realserver.rollout_kick import CYCLE_S, frame_time_s, launch, measure, parse_truth
from motions.authoring.kick import kick_params, stance_params

#: The shipped kick (motions at ccc781a) on the real rcssserver3d 0.7.3 with the ball on its spot, recorded by
#: RealKickBench: the full state requested at the kick's start (game time 1.80 s), then one diff frame a cycle
#: up to 2.86 s. The whole run measured: contact 0.92 s after the kick's start, foot 2.51 m/s, ball 1.33 m/s
#: three cycles later, at most 3.6 cm up, rest 1.26 m away.
FIXTURE = Path(__file__).parent / "fixtures" / "real_0.7.3_kick_monitor.txt.gz"
KICK_START_S = 1.80
BALL_START_M = (-7.79463, -0.00210)


@pytest.fixture(scope="module")
def real_truth(tmp_path_factory):
    frames = gzip.open(FIXTURE).read().split(b"\n")
    return parse_truth([f for f in frames if f], tmp_path_factory.mktemp("frames"))


def test_monitor_frames_give_one_truth_per_cycle(real_truth):
    first = round(1.84 / CYCLE_S)
    assert sorted(real_truth) == list(range(first, round(2.86 / CYCLE_S) + 1))
    sample = real_truth[first]
    assert sample["ball"][:2] == pytest.approx(BALL_START_M, abs=1e-4)
    assert sample["torso"][2] == pytest.approx(0.332, abs=0.003)
    assert sample["up_z"] > 0.95 and abs(sample["heading_deg"]) < 1.0
    assert 10.0 < sample["pitch_deg"] < 16.0  # the stance leans forward
    assert sample["lfoot"][2] == pytest.approx(0.0093, abs=5e-4) and sample["rfoot"][1] < sample["lfoot"][1]


def test_the_real_strike_is_measured_as_ours(real_truth):
    run = measure(real_truth, "kick", Placement(), BALL_START_M, 0.0, KICK_START_S, 2.24)
    assert run.contact_s == pytest.approx(0.92)
    assert run.foot_speed_m_s == pytest.approx(2.51, abs=0.01)
    assert run.ball_speed_m_s == pytest.approx(1.33, abs=0.01)
    assert not run.fell and not run.trapped
    assert 0.03 < run.ball_max_height_m < 0.04
    assert launch(real_truth, run.contact_s, KICK_START_S)["launch_m_s"] == pytest.approx(1.4, abs=0.15)


def _sample(cycle: int, ball_x: float, foot_x: float = 0.0, up_z: float = 0.97) -> tuple[int, dict]:
    return cycle, {"time_s": cycle * CYCLE_S, "torso": (0.0, 0.0, 0.33), "up_z": up_z, "heading_deg": 0.0,
                   "pitch_deg": 13.0, "roll_deg": 0.0, "rfoot": (foot_x, -0.05, 0.02), "lfoot": (0.0, 0.05, 0.01),
                   "ball": (ball_x, 0.1 * (ball_x - 0.15), 0.042)}


def test_a_kick_measured_from_synthetic_truth():
    """The ball rests 2 m along a line 5.7 deg left of the aim; the foot moves 4 cm a cycle before the strike;
    the robot falls after the kick."""
    samples = dict(_sample(k, 0.15 + 0.05 * max(0, k - 110), 0.04 * (k - 100), 0.97 if k <= 140 else 0.3)
                   for k in range(101, 151))
    run = measure(samples, "kick", Placement(0.01), (0.15, 0.0), 0.0, 100 * CYCLE_S, 1.0)
    assert run.contact_s == pytest.approx(11 * CYCLE_S)
    assert run.foot_speed_m_s == pytest.approx(2.0)
    assert run.ball_speed_m_s == pytest.approx(2.5 * math.hypot(1.0, 0.1), rel=1e-6)
    assert run.distance_m == pytest.approx(math.hypot(2.0, 0.2))
    assert run.direction_error_deg == pytest.approx(math.degrees(math.atan(0.1)))
    assert run.fell and run.motion_s == 1.0 and len(run.truths) == 50


def test_no_truth_after_the_kick_is_an_error():
    with pytest.raises(ValueError, match="no monitor truth"):
        measure(dict([_sample(10, 0.15)]), "kick", Placement(), (0.15, 0.0), 0.0, 1.0, 1.0)


def test_frame_time():
    assert frame_time_s(b"((time 12.34)(play_mode 3))(RDS 0 1)()") == pytest.approx(12.34)
    assert frame_time_s(b"(RDS 0 1)()") is None


class _Monitor:
    def __init__(self, log: list) -> None:
        self.log = log

    def send(self, text: str) -> None:
        self.log.append(("monitor", text))


def test_trainer_commands_go_out_before_the_agent_answers(monkeypatch):
    """In sync mode the server waits for the answer, so a command sent before it is applied in the next cycle,
    always the same one."""
    log: list = []
    session = object.__new__(rollout_kick._Session)
    session.monitor, session._commands, session.game_time_s = _Monitor(log), [], 0.0
    session.sock = None
    session.agent = type("A", (), {"step": lambda self, payload: b"(lle1 0.5)(syn)"})()
    sense = b"(time (now 3.1))(GS (sl 0)(sr 0)(t 1.24)(pm PlayOn))"
    monkeypatch.setattr(real_session, "read_frame", lambda sock: sense)
    monkeypatch.setattr(real_session, "write_frame", lambda sock, payload: log.append(("agent", payload)))
    session.command("(playMode PlayOn)")
    session.step()
    session.step(think=False)
    assert log == [("monitor", "(playMode PlayOn)"), ("agent", b"(lle1 0.5)(syn)"), ("agent", b"(syn)")]
    assert session.game_time_s == pytest.approx(1.24)


def test_the_bench_reruns_itself_in_the_private_namespace(monkeypatch, tmp_path):
    (tmp_path / "server.sh").write_text("")
    (tmp_path / "netns.sh").write_text("")
    calls = []
    monkeypatch.setattr(rollout_kick, "reexec_in_netns", lambda scripts, argv: calls.append((scripts, argv)))
    rollout_kick.ensure_private_network("motion_studio.tune_kick", ["kick", "--backend", "real"], tmp_path)
    assert calls == [(tmp_path.resolve(), [rollout_kick.sys.executable, "-m", "motion_studio.tune_kick", "kick",
                                           "--backend", "real"])]


def _fake_run(distance_m: float, placement: Placement, fell: bool = False) -> KickRun:
    return KickRun("kick", placement, (0.0, 0.0), (distance_m, 0.0), 0.0, 0.9, 2.2, fell, False, 0.0, 2.5, 3.0)


def test_backends_add_their_weighted_losses_and_label_their_runs():
    stance, params = stance_params(), kick_params("kick")
    seen = []

    def real(library, motion, placement, seed):
        seen.append(("real", motion, placement))
        return _fake_run(3.0, placement)

    def ours(library, motion, placement, seed):
        seen.append(("ours", motion, placement))
        return _fake_run(6.0, placement)

    objective = tune_kick.Objective()
    result = tune_kick.evaluate_backends(params, stance, objective, [
        tune_kick.Backend("real", real, tune_kick.REAL_PLACEMENTS),
        tune_kick.Backend("mujoco", ours, tune_kick.OURS_CHECK_PLACEMENTS, weight=0.5, cap_m=4.0)])
    assert result["losses"] == {"real": -4.5, "mujoco": -6.0}  # -(mean + 0.5 min); ours capped at 4 m
    assert result["loss"] == pytest.approx(-4.5 - 0.5 * 6.0)
    assert [r["backend"] for r in result["runs"]] == (["real"] * len(tune_kick.REAL_PLACEMENTS)
                                                      + ["mujoco"] * len(tune_kick.OURS_CHECK_PLACEMENTS))
    assert [s[2] for s in seen] == list(tune_kick.REAL_PLACEMENTS + tune_kick.OURS_CHECK_PLACEMENTS)
    assert {s[1] for s in seen} == {"kick"}
    note = tune_kick.measured_note(result["runs"])
    assert note.startswith("real rcssserver3d 0.7.3, tuning placements: distance 3.00-3.00 m (mean 3.00)")
    assert "our simulator, tuning placements: distance 6.00-6.00 m" in note


def test_tuning_on_a_backend_checkpoints_and_resumes(tmp_path):
    """Two generations with a stand-in rollout whose distance grows with the strike's height: the checkpoint
    keeps every evaluation and the best, and a second call resumes without evaluating again."""
    stance, base = stance_params(), kick_params("kick")

    def rollout(library, motion, placement, seed):
        height = library.get(motion).constants["ball_forward_m"]
        return _fake_run(10.0 * height, placement)

    backends = [tune_kick.Backend("real", rollout, tune_kick.REAL_PLACEMENTS[:2])]
    dimension = [d for d in tune_kick.SPACE if d.name == "ball_ahead_m"]
    checkpoint = tmp_path / "kick"
    data = tune_kick.tune("kick", base, stance, dimension, tune_kick.Objective(), 2, checkpoint, popsize=4,
                          progress=lambda text: None, backends=backends)
    assert len(data["evaluations"]) == 8 and (checkpoint / "checkpoint.pkl").is_file()
    assert data["best"]["loss"] <= min(e["result"]["loss"] for e in data["evaluations"])
    assert all(r["backend"] == "real" for e in data["evaluations"] for r in e["result"]["runs"])
    again = tune_kick.tune("kick", base, stance, dimension, tune_kick.Objective(), 2, checkpoint, popsize=4,
                           progress=lambda text: None, backends=backends)
    assert len(again["evaluations"]) == 8


def test_kick_check_measures_every_motion_offset_and_server():
    from motion_studio.realserver import kick_check

    distances = {"real": 1.0, "ours": 4.0}
    servers = {name: (lambda lib, motion, placement, name=name: _fake_run(distances[name] + placement.forward_m * 10,
                                                                         placement, fell=name == "real"))
               for name in distances}
    rows = kick_check.measure_kicks(None, ["kick"], [-0.02, 0.0, 0.02], servers)
    expected = [(offset, server) for offset in (-0.02, 0.0, 0.02) for server in ("real", "ours")]
    assert [(r["offset_m"], r["server"]) for r in rows] == expected
    figures = kick_check.summary(rows)["kick"]
    assert figures["real"] == {"mean_m": 1.0, "min_m": 0.8, "direction_mean_deg": 0.0, "direction_max_deg": 0.0,
                               "falls": 3, "kicks": 3}
    assert figures["ours"]["mean_m"] == 4.0 and figures["ours"]["falls"] == 0
    text = kick_check.table(rows)
    assert "kick on real: mean 1.00 m, min 0.80 m" in text and "kick on ours: mean 4.00 m, min 3.80 m" in text
