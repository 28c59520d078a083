"""sim.engine: the cycle order and its delays, connection sequence, beam, say/hear, bad input, determinism."""

from __future__ import annotations

import math
import re

import pytest

from agent.protocol.sense import parse_sense
from sim.engine import FrozenReferee, SimEngine
from sim.inprocess import InProcessHost
from tests.sim.scripted import SCENE, Scripted, engine, run_until

INIT = b"(init (unum 0)(teamname Mine))(syn)"


def hj(message: bytes, name: str) -> float:
    return parse_sense(message).joints[name]


def test_action_in_reply_to_message_k_first_shows_in_k_plus_2() -> None:
    sim = engine()
    host = InProcessHost(sim)
    agent = Scripted({0: INIT, 30: b"(he1 1.0)(syn)"})
    host.add(agent)
    run_until(host, agent, 40)
    angles = [hj(m, "hj1") for m in agent.received]
    assert abs(angles[31]) < 0.01 and angles[32] == pytest.approx(1.15, abs=0.01)   # 1 rad/s for one 20 ms step
    assert angles[33] - angles[32] == pytest.approx(math.degrees(0.02), abs=0.01)


def test_init_and_beam_delays_match_the_real_server() -> None:
    # Measured on 0.7.3 (tests/sim/fixtures/real_0.7.3_*.jsonl.gz): init in reply to 0 stops the fall in 2
    # (ACC z 29.42 = 3 g after two falling steps); beam in reply to 2 shows in ACC of 5 (19.61 = 2 g).
    sim = engine()
    host = InProcessHost(sim)
    agent = Scripted({0: b"(init (unum 1)(teamname Calib))(syn)", 2: b"(beam -5.0 0.0 0.0)(syn)"})
    host.add(agent)
    run_until(host, agent, 8)
    acc_z = [parse_sense(m).acc.acc_m_s2[2] for m in agent.received]  # type: ignore[union-attr]
    assert acc_z[0] == pytest.approx(0.0, abs=0.05)                   # free fall since the spawn
    assert acc_z[2] == pytest.approx(29.42, abs=0.1)
    assert acc_z[4] == pytest.approx(0.0, abs=0.05)
    assert acc_z[5] == pytest.approx(19.61, abs=0.1)


def test_connection_sequence_sides_numbers_and_init_spots() -> None:
    sim = engine()
    host = InProcessHost(sim)
    agents = [Scripted({0: b"(init (unum 0)(teamname Mine))(syn)"}),
              Scripted({0: b"(init (unum 0)(teamname Rivals))(syn)"}),
              Scripted({0: b"(init (unum 0)(teamname Mine))(syn)"}),
              Scripted({0: b"(init (unum 7)(teamname Others))(syn)"})]
    ids = [host.add(a) for a in agents]
    for agent in agents:
        run_until(host, agent, 3)
    links = [sim.agents[i] for i in ids]
    assert [(l.side, l.unum) for l in links] == [("left", 1), ("right", 1), ("left", 2), (None, None)]
    assert b"(GS (unum 1) (team right)" in agents[1].received[2]
    assert sim.errors[ids[3]] == 1                                    # a third team is refused
    positions = [sim.world.torso_position(i) for i in ids[:3]]
    assert positions[0][:2] == pytest.approx((-14.2, 9.2), abs=0.01)
    assert positions[1][:2] == pytest.approx((14.2, 9.2), abs=0.01)   # measured: right team at +x, +y
    assert positions[2][:2] == pytest.approx((-14.2, 8.0), abs=0.01)
    assert sim.world.heading_deg(ids[1]) == pytest.approx(180.0, abs=0.1) or \
        sim.world.heading_deg(ids[1]) == pytest.approx(-180.0, abs=0.1)


def test_beam_rules() -> None:
    sim = engine(seed=5)
    host = InProcessHost(sim)
    left = Scripted({0: b"(init (unum 0)(teamname A))(syn)", 2: b"(beam -3 2 90)(syn)", 60: b"(beam 5 -20 0)(syn)"})
    right = Scripted({0: b"(init (unum 0)(teamname B))(syn)", 2: b"(beam -3 2 90)(syn)"})
    a, b = host.add(left), host.add(right)
    run_until(host, left, 40)
    run_until(host, right, 40)
    pa, pb = sim.world.torso_position(a), sim.world.torso_position(b)
    assert pa[:2] == pytest.approx((-3.0, 2.0), abs=0.051)           # noise within ±5 cm
    assert pb[:2] == pytest.approx((3.0, -2.0), abs=0.051)           # the right team's frame is point-reflected
    assert sim.world.heading_deg(a) == pytest.approx(90.0, abs=10.01)
    assert sim.world.heading_deg(b) == pytest.approx(-90.0, abs=10.01)
    assert pa[2] < 0.4
    run_until(host, left, 100)
    assert sim.world.torso_position(a)[:2] == pytest.approx((0.0, -10.0), abs=0.051)   # clamped to own half


def test_beam_refused_when_the_referee_forbids_it() -> None:
    class PlayOn(FrozenReferee):
        play_mode = "PlayOn"

        def allows_beam(self) -> bool:
            return False

    sim = engine(referee=PlayOn())
    host = InProcessHost(sim)
    agent = Scripted({0: INIT, 2: b"(beam -3 2 0)(syn)"})
    key = host.add(agent)
    run_until(host, agent, 10)
    assert sim.world.torso_position(key)[:2] == pytest.approx((-14.2, 9.2), abs=0.05)


def test_say_and_hear_rules() -> None:
    sim = engine()
    host = InProcessHost(sim)
    long_message = b"(say " + b"x" * 21 + b")(syn)"
    mine = Scripted({0: b"(init (unum 0)(teamname Mine))(syn)", 2: b"(beam -3 0 0)(syn)",
                     20: b"(say hello)(syn)", 21: b"(say again)(syn)", 22: b"(say third)(syn)", 30: long_message})
    mate = Scripted({0: b"(init (unum 0)(teamname Mine))(syn)", 2: b"(beam -3 3 0)(syn)"})
    rival = Scripted({0: b"(init (unum 0)(teamname Rivals))(syn)", 2: b"(beam -3 0 0)(syn)",
                      21: b"(say rival1)(syn)"})
    ids = [host.add(a) for a in (mine, mate, rival)]
    run_until(host, mine, 40)
    run_until(host, rival, 40)

    def hears(agent: Scripted, index: int) -> list[str]:
        return re.findall(r"\(hear [^)]*\)", agent.received[index].decode())

    assert hears(mine, 22) == ["(hear Mine 0.00 self hello)"]          # said in reply to 20: heard in 22
    assert len(hears(mate, 22)) == 1 and hears(mate, 22)[0].endswith(" hello)")
    direction = float(hears(mate, 22)[0].split()[3])
    assert direction == pytest.approx(-90.0, abs=2.0)                 # the speaker is 3 m to the mate's right
    # Capacity: one message per team per two cycles; "again" (next cycle) is lost, "third" arrives.
    assert "again" not in "".join(hears(mate, 23))
    assert "third" in "".join(hears(mate, 24))
    # Own message first, then the other team's (labelled with the speaker's team name).
    assert hears(mine, 23)[0] == "(hear Mine 0.00 self again)"
    assert re.fullmatch(r"\(hear Rivals 0\.00 -?\d+\.\d\d rival1\)", hears(mine, 23)[1])
    # The rival listens in its own frame: the speaker at world (-3, 0), itself at world (3, 0) -> straight ahead.
    rival_hears = [h for h in hears(rival, 22) if "hello" in h]
    assert len(rival_hears) == 1 and abs(float(rival_hears[0].split()[3])) < 2.0
    assert all("xxxx" not in m.decode() for m in mine.received)       # longer than 20 characters: dropped
    assert sim.errors[ids[0]] >= 1


def test_hearing_range_is_50_m() -> None:
    sim = engine()
    host = InProcessHost(sim)
    near = Scripted({0: INIT})
    far = Scripted({0: INIT, 5: b"(say far)(syn)"})
    a, b = host.add(near), host.add(far)
    run_until(host, near, 3)
    sim.world.place_robot(a, -24.0, -24.0, 0.0)
    sim.world.place_robot(b, 24.0, 24.0, 0.0)   # 68 m apart, inside the walls
    run_until(host, far, 10)
    run_until(host, near, 10)
    assert b"far" in far.received[7]
    assert all(b"hear" not in m for m in near.received)


def test_bad_input_is_counted_and_never_raises() -> None:
    sim = engine()
    key = sim.connect()
    for payload in (b"(he1 1.0)", b"(init (unum 1)(teamname X))", b"((((", b"\xff\x00", b"(foo 1)",
                    b"(scene rsg/agent/nao/unknown.rsg)", b"(beam 1)", b"(say a b)"):
        sim.receive(key, payload)
    sim.step()
    before = sim.errors[key]
    assert before >= 6
    sim.receive(key, b"(scene rsg/agent/nao/nao_hetero.rsg 0)")
    sim.step()
    sim.receive(key, b"(scene rsg/agent/nao/nao.rsg)(he1 nan)(he1 inf)(lle7 1.0)(beam 0 0 0)(syn)")
    sim.step()
    assert sim.errors[key] >= before + 4                      # second scene, NaN, Inf, lle7 on type 0, beam
    sim.receive(999, b"(syn)")                                 # unknown id
    sim.disconnect(999)
    out = sim.step()
    assert key in out and out[key].startswith(b"(time (now ")


def test_usual_joint_messages_set_targets_as_the_general_path() -> None:
    # Joint-only messages take a cached fast path; odd ones (a joint the type lacks, a name twice, two messages
    # in one cycle) must give what the general rules give: known joints applied, the last value wins.
    sim = engine()
    key = sim.connect()
    sim.receive(key, SCENE)
    sim.step()
    motors = sim.world.motors
    start = motors.blocks[key].start
    index = {j.effector: start + i for i, j in enumerate(sim.world.by_key[key].spec.joints)}
    sim.receive(key, b"(he1 1.5)(lae1 -0.5)(syn)")
    sim.step()
    assert motors.target[index["he1"]] == 1.5 and motors.target[index["lae1"]] == -0.5
    errors = sim.errors[key]
    sim.receive(key, b"(he1 0.25)(lle7 1.0)(syn)")               # type 0 has no toes
    sim.step()
    assert motors.target[index["he1"]] == 0.25 and sim.errors[key] == errors + 1
    sim.receive(key, b"(he2 0.5)(he1 1.0)(he2 -0.75)")           # a name twice: the last value
    sim.step()
    assert motors.target[index["he2"]] == -0.75 and motors.target[index["he1"]] == 1.0
    sim.receive(key, b"(he1 0.5)(lae2 0.5)")                     # two messages in one cycle: the later wins
    sim.receive(key, b"(he1 -0.5)(syn)")
    sim.step()
    assert motors.target[index["he1"]] == -0.5 and motors.target[index["lae2"]] == 0.5
    assert sim.errors[key] == errors + 1


def test_disconnect_frees_the_number_and_removes_the_robot() -> None:
    sim = engine()
    host = InProcessHost(sim)
    first = Scripted({0: INIT})
    key = host.add(first)
    run_until(host, first, 3)
    host.remove(key)
    assert key not in sim.world.by_key and not sim.world.robots()
    second = Scripted({0: INIT})
    other = host.add(second)
    run_until(host, second, 3)
    assert sim.agents[other].unum == 1


def test_same_seed_same_bytes() -> None:
    def transcript(seed: int) -> list[tuple[int, int, bytes]]:
        sim = SimEngine(seed=seed)      # the real referee, noise on
        host = InProcessHost(sim, record=True)
        host.add(Scripted({0: b"(init (unum 0)(teamname A))(syn)", 2: b"(beam -2 1 0)(syn)",
                           10: b"(he1 2.0)(lae1 -1.5)(say hi)(syn)"}))
        host.add(Scripted({0: b"(init (unum 0)(teamname B))(syn)", 2: b"(beam -2 1 0)(syn)"}))
        host.run(40)
        return host.stats.transcript
    assert transcript(11) == transcript(11)
    assert transcript(11) != transcript(12)


def test_spelled_and_printf_numbers_write_the_same_messages(monkeypatch: pytest.MonkeyPatch) -> None:
    # Few robots' numbers go to printf templates, many robots' are spelled by look-up (sim.fixed2).
    import sim.engine
    import sim.vision

    def transcript(spell_min_values: int) -> list[tuple[int, int, bytes]]:
        monkeypatch.setattr(sim.engine, "SPELL_MIN_VALUES", spell_min_values)
        monkeypatch.setattr(sim.vision, "SPELL_MIN_VALUES", spell_min_values)
        host = InProcessHost(SimEngine(seed=5), record=True)
        for team in "AB":
            host.add(Scripted({0: b"(init (unum 0)(teamname %s))(syn)" % team.encode(),
                               3: b"(he1 2.0)(lae1 -1.5)(say hi)(syn)"}))
        host.run(30)
        return host.stats.transcript
    spelled = transcript(0)
    assert len(spelled) > 50 and spelled == transcript(10 ** 9)


def test_sync_readiness() -> None:
    sim = engine()
    key = sim.connect()
    sim.receive(key, b"(scene rsg/agent/nao/nao_hetero.rsg 1)")
    for _ in range(6):
        sim.step()
    assert not sim.ready()             # past its first 4 perceptor cycles and no (syn) yet
    sim.receive(key, b"(syn)")
    assert sim.ready()
