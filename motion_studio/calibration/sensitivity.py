"""How firmly an open-loop replay's outcome holds: the same recording replayed with its joint commands perturbed far
below anything a server could tell apart, and the share of those replays that end as the real run did.

Why: `agreement.outcomes` compares one replay's ending (fell or not, standing at the end or not) with the real
run's. Many recordings are marginal: a stand-up that just makes it, a walk replayed open loop whose real corrections
drift on ours. Changing one contact parameter (dampratio 1 -> 2) flipped 16 of the 69 skill traces' outcomes, 8 each
way, the count staying at 44. A single replay cannot say whether a mismatch is the physics' (ours ends otherwise
in every perturbed replay) or the recording's chance (ours ends either way): the share here does.

The perturbation: every joint velocity the real agent sent gets N(0, ``sd_rad_s``) added, drawn per command from a
seeded generator, and is written in the agent's spelling (4 decimals); replies that are not plain joint commands
(scene, init, beam, say) stay as recorded. The default 1e-4 rad/s is the last digit the wire format carries: most
commands change by that one digit or not at all, 1.1e-4 deg of joint travel per cycle (2e-6 rad), a ninetieth of the
HJ perceptor's last digit (0.01 deg). Unperturbed (0) the replays repeat to the bit.

Measured on the defaults (2026-11-29, ``motion-studio calibrate --spread 8 --workers 2``, 69 skill traces, 8 min on 2
cores): 44 end as the real run unperturbed; 36 hold, 17 are marginal, 16 differ in every perturbed replay; 45.1 are
expected to end as the real run. The 16 that differ are our physics': the forward walks (walk_forward, walk_20m,
walk_fast_20m, the 13 cm candidate) and the dribbles (3), kick_3m, the 8 m candidate and type 3's long kick, and the
front stand-up's recording and its starts 1, 2, 3, 6 and 7. The back and side stand-ups' mismatches are marginal.
The candidates of sim/physics_candidates the same way (unperturbed same / holds / marginal / differs / expected):
foot_slip 51 / 35 / 18 / 16 / 45.1, body_slip 46 / 31 / 23 / 15 / 44.2, slip_fit_2026-11-29 48 / 40 / 13 / 16 / 47.5:
foot_slip's lead in the single replay (51 against 44) is the recordings' chance, slip_fit's is partly real.
"""

from __future__ import annotations

import hashlib
import random
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any

from agent.protocol.effectors import split_joint_commands
from agent.protocol.numbers import format_agent_float
from motion_studio.calibration.agreement import Outcome, Replay, outcomes
from motion_studio.realserver.fixtures import Fixture
from motion_studio.realserver.replay import replay_states
from sim.physics_params import PhysicsParams

#: Standard deviation of the command perturbation [rad/s] (see the module docstring).
SD_RAD_S = 1e-4
#: Perturbed replays per trace by default.
REPLAYS = 8


def perturbed_replies(fixture: Fixture, sd_rad_s: float, rng: random.Random) -> dict[int, bytes]:
    """``fixture``'s replies with N(0, sd_rad_s) added to each joint velocity, in the agent's spelling
    (`format_agent_float`) and order; a reply that is not plain joint commands (+ ``(syn)``) is kept as recorded."""
    out: dict[int, bytes] = {}
    for index, reply in fixture.replies.items():
        split = split_joint_commands(reply.decode("ascii", "replace"))
        if split is None or not split[0]:
            out[index] = reply
            continue
        names, values, syn = split
        text = "".join(f"({name} {format_agent_float(value + sd_rad_s * rng.gauss(0.0, 1.0))})"
                       for name, value in zip(names, values))
        out[index] = (text + ("(syn)" if syn else "")).encode("ascii")
    return out


@dataclass(frozen=True)
class OutcomeSpread:
    """One trace: the real outcome, ours unperturbed, and ours in each perturbed replay."""

    trace: str
    real: Outcome
    ours: Outcome
    perturbed: tuple[Outcome, ...]

    @property
    def same_share(self) -> float:
        """Share of the perturbed replays that end as the real run did (0-1)."""
        return sum(o == self.real for o in self.perturbed) / max(1, len(self.perturbed))

    @property
    def kind(self) -> str:
        """"holds" (every perturbed replay ends as the real run), "differs" (none does) or "marginal"."""
        share = self.same_share
        return "holds" if share == 1.0 else "differs" if share == 0.0 else "marginal"


def outcome_spread(fixture: Fixture, physics: PhysicsParams | None = None, replays: int = REPLAYS,
                   sd_rad_s: float = SD_RAD_S, seed: int = 0) -> OutcomeSpread | None:
    """Replay ``fixture`` once as recorded and ``replays`` times perturbed (seeds ``seed``..); None for a scripted
    trace (no real outcome)."""
    base = Replay(fixture, replay_states(fixture, physics))
    ended = outcomes(base)
    if ended is None:
        return None
    perturbed = []
    for k in range(replays):
        varied = replace(fixture, replies=perturbed_replies(fixture, sd_rad_s, random.Random(seed + k)))
        replay = Replay(varied, replay_states(varied, physics))
        result = outcomes(replay)
        assert result is not None   # the same truth as the unperturbed replay
        perturbed.append(result[1])
    return OutcomeSpread(fixture.name, ended[0], ended[1], tuple(perturbed))


def physics_id(physics: PhysicsParams | None) -> str:
    """A short digest of the physics parameters, so that a checkpoint row is reused only for the same world."""
    return hashlib.sha1(repr(physics).encode()).hexdigest()[:12]


def spread_key(trace: str, physics: PhysicsParams | None, replays: int, seed: int,
               sd_rad_s: float = SD_RAD_S) -> str:
    """The checkpoint key of one trace's spread: the same trace, world, replay count, seed and perturbation."""
    return f"{trace}|{physics_id(physics)}|{replays}|{seed}|{sd_rad_s:g}"


def spread_row(spread: OutcomeSpread, key: str) -> dict[str, Any]:
    """One finished spread as a JSON-able checkpoint row."""
    return {"key": key, "trace": spread.trace, "real": asdict(spread.real), "ours": asdict(spread.ours),
            "perturbed": [asdict(o) for o in spread.perturbed]}


def spread_from_row(row: dict[str, Any]) -> OutcomeSpread:
    """The spread a checkpoint row holds (`spread_row`'s inverse)."""
    return OutcomeSpread(row["trace"], Outcome(**row["real"]), Outcome(**row["ours"]),
                         tuple(Outcome(**o) for o in row["perturbed"]))


def plot_spread(spreads: list[OutcomeSpread], path: Path) -> Path:
    """One bar per trace: the share of its perturbed replays that end as the real run, coloured by kind, the
    unperturbed mismatches marked; as PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from motion_studio.figures import write_png

    colours = {"holds": "tab:green", "marginal": "tab:orange", "differs": "tab:red"}
    fig, ax = plt.subplots(figsize=(9, 0.22 * len(spreads) + 1.5))
    rows = range(len(spreads))
    # a trace that differs in every replay has a share of 0: a sliver of red keeps it visible
    ax.barh(list(rows), [max(s.same_share, 0.015) for s in spreads], color=[colours[s.kind] for s in spreads])
    ax.set_yticks(list(rows), [s.trace + (" !" if s.ours != s.real else "") for s in spreads], fontsize=7)
    ax.invert_yaxis()
    ax.set_xlim(0, 1)
    ax.set_xlabel("share of perturbed replays ending as the real run ('!': the unperturbed replay does not)")
    ax.set_title("open-loop replays on ours: " + ", ".join(
        f"{kind} {sum(s.kind == kind for s in spreads)}" for kind in colours))
    ax.grid(axis="x", alpha=0.3)
    return write_png(fig, path)


def _outcome_text(outcome: Outcome) -> str:
    return ("fell" if outcome.fell else "up") + ("/standing" if outcome.standing else "/down")


def spread_table(spreads: list[OutcomeSpread]) -> str:
    """One row per trace (real outcome, ours unperturbed, share of perturbed replays ending as the real run, kind),
    then the counts of each kind."""
    lines = [f"{'trace':38s} {'real':14s} {'ours':14s} {'same':>6s}  kind"]
    for s in spreads:
        mark = "" if s.ours == s.real else "!"
        lines.append(f"{s.trace:38s} {_outcome_text(s.real):14s} {_outcome_text(s.ours) + mark:14s} "
                     f"{s.same_share:6.2f}  {s.kind}")
    counts = {kind: sum(s.kind == kind for s in spreads) for kind in ("holds", "marginal", "differs")}
    same = sum(s.ours == s.real for s in spreads)
    expected = sum(s.same_share for s in spreads)
    lines.append(f"unperturbed: {same} of {len(spreads)} end as the real run; perturbed "
                 f"({len(spreads[0].perturbed) if spreads else 0} each): holds {counts['holds']}, marginal "
                 f"{counts['marginal']}, differs {counts['differs']}; expected to end as the real run: {expected:.1f}")
    return "\n".join(lines)


__all__ = ["OutcomeSpread", "REPLAYS", "SD_RAD_S", "outcome_spread", "perturbed_replies", "physics_id", "plot_spread",
           "spread_from_row", "spread_key", "spread_row", "spread_table"]
