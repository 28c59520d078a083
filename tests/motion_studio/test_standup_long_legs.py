"""Robot types 1 and 3 (longer legs, REFERENCE §2.5) stand up on our simulator with their own shipped stand-ups
(``motions/files/type1/``, ``type3/``; ``motions/params/standup_type<N>.toml``), from both sides: the StandUp
skill after the scripted fall of ``motion-studio real skills standup_back`` / ``standup_front`` (transfer start
0 is that case as shipped) and after one more seeded fall. With type 0's stand-ups these robots did not get up
from one side or the other (module docstring of ``motions.authoring.standup_types``)."""

from __future__ import annotations

import pytest

from agent.motion import default_library
from motion_studio.realserver.rollout_standup import SimWorld, StandUpBench, transfer_starts

#: From the stand-up's start (the fall detected) to standing for good [s]; the shipped files take 2.2-2.7 s.
LIMIT_S = 3.5


@pytest.fixture(scope="module", params=[1, 3])
def typed_bench(request):
    robot_type = request.param
    bench = StandUpBench(lambda behavior: SimWorld(behavior, robot_type=robot_type), default_library(robot_type),
                         robot_type)
    yield robot_type, bench
    bench.close()


@pytest.mark.parametrize("side", ["back", "front"])
@pytest.mark.parametrize("start", [0, 1])
def test_a_long_legged_robot_stands_up_from_its_side(typed_bench, side, start):
    robot_type, bench = typed_bench
    library = default_library(robot_type)
    name = f"standup_{side}"
    assert library.get(name) != default_library(0).get(name)  # its own file, not type 0's
    outcome = bench.rollout({}, name, transfer_starts(side, start + 1)[start], use_skill=True)
    assert outcome.lying_up_z < 0.5  # it was down when the stand-up began (the skill starts as the fall ends)
    assert outcome.time_s is not None and outcome.time_s < LIMIT_S, (robot_type, side, start, outcome.time_s)
