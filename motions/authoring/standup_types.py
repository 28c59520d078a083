"""Stand-ups for the robot types whose feet differ from type 0, written to ``motions/files/type<N>/``.

Why: the crouch and rise keyframes of a stand-up put the whole-body CoM over the soles, and where the soles
are relative to the ankle differs by type (REFERENCE §2.5: type 4's foot box is 0.124 m long instead of
0.16 m, its centre 1.78 cm further back, a toe box making up the front; the sole site the CoM is put over
is the foot box's centre). Played with type 0's angles a type-4 robot rose and then tipped onto its front
at the stance (see below). Here the same parameters (``motions/params/standup.toml``) are solved with the
type's own kinematics (``standup.SagittalSolver(robot_type)``): ground phases keep their joint angles (same leg
lengths), crouch and rise put the CoM over that type's soles, and the last keyframe stays the shared
``stand`` pose (every type's walk starts there).

Measured on our simulator (6 lying trials per side as the stand-up benchmark draws them, robot type set;
time to stand [s]): type 4 with these files back 6/6 stood (3.1-3.5 s; with the back timings retuned
on 2026-11-23, 20 seed-0 draws: 19 in 2.42-2.90 s, one not up after 8 s and 3 attempts), front 6/6
(2.6-3.3 s); with type 0's files back 1/6, front 6/6 (5.6-6.2 s, after a retry). With the retuned back
timings, type 0's files get a type-4 robot up from its back too, but slower: of 10 back trials drawn as
the benchmark's (robot type 4), 6 within 3 s and two only after a retry (5.6, 6.6 s), against 10 of 10
within 3 s (2.5-2.9 s) with these files. Type 2 has type 0's
geometry and stood with type 0's files (back 6/6, front 6/6) until type 0's back stand-up was retimed.

Types 1, 2, 3 and 4 have parameter files of their own, ``motions/params/standup_type<N>.toml``
(:func:`type_params_path`; made from ``standup.toml`` and tuned per type with ``motion-studio tune standup
<section> --type N``, which solves and plays the candidates as this module writes them). Type 4's holds
``standup.toml``'s values from before type 0's back stand-up was retimed (2026-11-27): solved for type 4, the
retimed ones stood it up after the scripted fall onto its back in 4 of 10 real starts, these in 9 (its header
has the figures); it plays the shared ``roll_to_back`` (its own 300 ms three-phase roll until 2026-11-28). Type 3
keeps the three-phase roll the shared file had before that day (a ``[roll_to_back]`` of its own: with the one-keyframe
roll its side lies stood on ours 4 of 10; its provenance). Type 2's
back stand-up is ``standup.toml``'s again since 2026-11-30 (a copy of the section): from 2026-11-28 it played a retime
of its own, because type 0's retimed one stood a type-2 robot up within 3 s after 4 of 20 real scripted falls onto its
back; with every type lying flat first it stands it up after 20 of 20, 0.35 s sooner than that retime (its header and
provenance have the figures). Types 1
and 3 (longer legs): with type 0's
parameters neither got up from the front on either server (type 3: from the front on the real server only
after a retry, from the back on neither). What each section gave is in its provenance and measured keys.
On 2026-11-26 (``motion-studio real skills standup_back standup_front --type N``, stood up after the scripted
fall, real / ours): type 1 from its front 4.10 / 3.74 s, from its back 4.08 / 4.02 s; type 3 from its front
5.22 / 4.24 s, from its back 3.70 / 3.88 s. Our stand-up benchmark (``motion-studio bench skills --skill standup
--type 1,3``, 20 lying trials per side, within 3 s / stood at all), before -> after: type 1 back 10 / 10 ->
50 / 70 %, front 0 / 0 -> 75 / 100 %; type 3 back 5 / 5 -> 65 / 100 %, front 0 / 0 -> 90 / 100 %.

Run ``python -m motions.authoring.standup_types`` after ``python -m motions.authoring.standup``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from motions.authoring.common import FILES_DIR, PARAMS_DIR, write_xml_motions
from motions.authoring.gait_params import GAIT_PARAMS_PATH
from motions.authoring.standup import (PARAMS_PATH, ROLLS, STANDUPS, SagittalSolver, build_roll, build_standup,
                                       describe, ground_phases_comment, key_poses, load_standup_params, meta_comments,
                                       section_params, stance_params)
from motions.model import Motion

#: Types that get their own stand-ups (see the module docstring for the others).
TYPES = (1, 2, 3, 4)
COMMAND = "python -m motions.authoring.standup_types"


def type_params_path(robot_type: int) -> Path:
    """The stand-up parameter file of ``robot_type``: its own ``motions/params/standup_type<N>.toml`` (tuned for
    that type, e.g. types 1 and 3 with their longer legs) if there is one, else the shared ``standup.toml``."""
    own = PARAMS_DIR / f"standup_type{robot_type}.toml"
    return own if own.is_file() else PARAMS_PATH


def build_for_type(robot_type: int, path: Path | None = None, gait_path: Path = GAIT_PARAMS_PATH) -> dict[str, Motion]:
    """Both stand-ups for ``robot_type``: motion name -> Motion with a header saying how it was made; with them
    the rolls (``roll_to_back``, ``lie_flat``) whose section the type's own parameter file has (the others come
    from the shared files).

    ``path``: the parameter file (default :func:`type_params_path`).

    Raises:
        ValueError: a section missing from the parameter file, or a crouch/rise out of the type's reach.
    """
    path = type_params_path(robot_type) if path is None else Path(path)
    sections = load_standup_params(path)
    stance = stance_params(gait_path)
    solver = SagittalSolver(robot_type)
    own = path.resolve() != PARAMS_PATH.resolve()
    source = f"motions/params/{path.name}" if path.parent.resolve() == PARAMS_PATH.parent.resolve() else str(path)
    out = {}
    for name, side in STANDUPS.items():
        params = section_params(sections, path, name)
        poses = key_poses(params, side, stance, solver)
        ground = (f"type {robot_type}'s own parameters (provenance below)" if own else "ground phases as type 0's")
        comments = (f" Stand-up for robot type {robot_type}, generated by motions.authoring.standup_types "
                    f"(command: {COMMAND}) from [{name}] of {source}: {ground}, crouch and rise solved with "
                    f"type {robot_type}'s kinematics "
                    f"(CoM over its soles), last keyframe the shared stand pose. Do not edit by hand. ",
                    f" Lying on the {side}. Keyframes: ") + describe(poses)
        if own:
            comments += meta_comments(path, name)
        out[name] = build_standup(name, params, side, stance, comments, solver, poses)
    for name in ROLLS:
        if not own or name not in sections:
            continue
        params = sections[name]
        comments = (f" {name} for robot type {robot_type}, generated by motions.authoring.standup_types (command: "
                    f"{COMMAND}) from [{name}] of {source}: type {robot_type}'s own parameters (provenance below). "
                    f"Do not edit by hand. ", ground_phases_comment(params))
        comments += meta_comments(path, name)
        out[name] = build_roll(name, params, comments)
    return out


def write_all(out_dir: Path = FILES_DIR, types: tuple[int, ...] = TYPES) -> list[Path]:
    """Write ``type<N>/standup_front.xml`` and ``standup_back.xml`` (and the type's own rolls) for each type;
    returns the paths."""
    written = []
    for robot_type in types:
        written += write_xml_motions(build_for_type(robot_type), out_dir / f"type{robot_type}")
    return written


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=FILES_DIR, help="folder holding the type<N> folders")
    args = parser.parse_args(argv)
    for target in write_all(args.out):
        print(f"wrote {target}")


if __name__ == "__main__":
    main()
