"""What a skill is: each cycle it reads the world model (and the motion controller's state) and asks the
motion controller for a motion. Skills hold their own state; ``reset`` starts them afresh."""

from __future__ import annotations

from agent.motion import MotionController, MotionRequest
from agent.world_model import WorldModel


class Skill:
    """Base class: ``step`` returns this cycle's MotionRequest; ``done`` says the skill reached its goal."""

    name = "skill"

    def __init__(self) -> None:
        self.done = False

    def reset(self) -> None:
        """Start again (called when the skill becomes active)."""
        self.done = False

    def step(self, world: WorldModel, motion: MotionController) -> MotionRequest:
        raise NotImplementedError


class PlayMotion(Skill):
    """Play one motion: once (``done`` after it ended), or for as long as the skill is active (``repeat``).

    Args:
        motion_name: the motion's name in the library.
        repeat: keep requesting it (cyclic motions such as walks; a finished motion starts again).
        then: the motion to request once it ended (default: none, the body holds still).
        request: extra request fields (lean, gain, turn_deg, head_deg).
    """

    def __init__(self, motion_name: str, repeat: bool = False, then: str | None = None,
                 **request: object) -> None:
        super().__init__()
        self.name = f"play {motion_name}"
        self.motion_name = motion_name
        self.repeat = repeat
        self.then = then
        self.request = request
        self._completed_before: int | None = None

    def reset(self) -> None:
        super().reset()
        self._completed_before = None

    def step(self, world: WorldModel, motion: MotionController) -> MotionRequest:
        if self._completed_before is None:
            self._completed_before = motion.completed[self.motion_name]
        if not self.repeat and motion.completed[self.motion_name] > self._completed_before:
            self.done = True
        if self.done:
            return MotionRequest(self.then)
        return MotionRequest(self.motion_name, **self.request)  # type: ignore[arg-type]
