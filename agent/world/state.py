"""Game and body state of the world model: what the server says about the game and the agent's own body."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from agent.protocol.perceptors import ForceResistance

#: Play modes in which beam is accepted (REFERENCE §3.7).
BEAM_MODES = frozenset({"BeforeKickOff", "Goal_Left", "Goal_Right"})
#: Force below which a foot counts as off the ground [N] (magmaChallenge uses a 0.01 vector length).
CONTACT_FORCE_N = 0.01


@dataclass
class GameInfo:
    """The game as the GS and time perceptors report it."""

    server_time_s: float = 0.0
    """Server clock [s] (runs in every play mode); the time base for every age in the world model."""
    game_time_s: float = 0.0
    """Game time [s] (frozen in BeforeKickOff and GameOver; 300-600 in the second half)."""
    play_mode: str = "unknown"
    """Play mode as the server spells it (REFERENCE §4.2)."""
    play_mode_since_s: float = 0.0
    """Server time of the last play-mode change [s]."""
    play_mode_cycles: int = 0
    """Cycles since the last play-mode change (0 in the cycle it is seen; before any change, since server time
    0): the team's shared clock for say slots (§7.9, ``agent.communication.slots``)."""
    side: str | None = None
    """``left`` / ``right`` once the first GS after init said so; None before."""
    unum: int | None = None
    """Own uniform number once the server confirmed it; None before."""
    score_left: int = 0
    """Goals of the left team."""
    score_right: int = 0
    """Goals of the right team."""
    cycles: int = 0
    """Sense messages received since connecting."""

    @property
    def score_own(self) -> int:
        """Goals of the agent's team (left's before the side is known)."""
        return self.score_right if self.side == "right" else self.score_left

    @property
    def score_opponent(self) -> int:
        """Goals of the other team."""
        return self.score_left if self.side == "right" else self.score_right

    @property
    def beam_allowed(self) -> bool:
        """Beam is accepted in this play mode."""
        return self.play_mode in BEAM_MODES


@dataclass(frozen=True, slots=True)
class FootContact:
    """One foot's pressure this cycle (FRP; REFERENCE §3.4)."""

    point_m: tuple[float, float, float]
    """Force-weighted contact point in foot coordinates, relative to the foot box centre [m]."""
    force_n: tuple[float, float, float]
    """Summed contact force in foot axes [N]."""

    @property
    def touching(self) -> bool:
        """The force is not negligible."""
        return math.hypot(*self.force_n) > CONTACT_FORCE_N


@dataclass
class BodyState:
    """The agent's own body this cycle."""

    joints_rad: dict[str, float] = field(default_factory=dict)
    """Wire joint name (``hj1`` ... ``rlj6``) -> angle [rad], SimSpark sign."""
    gyro_deg_s: tuple[float, float, float] = (0.0, 0.0, 0.0)
    """Torso angular rate about x (right), y (forward), z (up) [deg/s], as sent."""
    acc_m_s2: tuple[float, float, float] = (0.0, 0.0, 9.81)
    """Torso proper acceleration in torso axes [m/s²] (+9.81 z upright at rest)."""
    feet: dict[str, FootContact] = field(default_factory=dict)
    """FRP sensor (``lf``, ``rf``, ``lf1``, ``rf1``) -> contact, only for sensors touching this cycle."""
    pitch_forward_rad: float = 0.0
    """Torso lean forward, from the orientation filter [rad]."""
    roll_right_rad: float = 0.0
    """Torso lean to the right, from the orientation filter [rad]."""
    up_z: float = 1.0
    """z of the torso's up axis in the gravity frame (1 upright)."""
    camera_height_m: float = 0.54
    """Camera height above the lowest sole corner at the last vision frame [m] (0.54 standing, type 0)."""

    def set_feet(self, frp: dict[str, ForceResistance]) -> None:
        """Replace the foot contacts with this cycle's FRP perceptors."""
        self.feet = {name: FootContact(p.contact_m, p.force_n) for name, p in frp.items()}

    @property
    def on_ground(self) -> bool:
        """Some foot sensor touches the ground this cycle."""
        return any(contact.touching for contact in self.feet.values())

    @property
    def fallen(self) -> bool:
        """The torso's up axis is below 0.6 z (the benchmarks' fall criterion, REFERENCE §8.1)."""
        return self.up_z < 0.6
