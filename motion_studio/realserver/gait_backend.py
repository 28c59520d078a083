"""The gait tuner's judge on the real rcssserver3d 0.7.3 (``motion-studio tune gait MOTION --backend real``),
optionally with our simulator's loss as well (``--backend both``).

Why a judge of whole candidates: the real server runs one walk at a time in this process (the brief of the
machine: one real server, one worker), so the tuner hands each candidate here (``tuning.InProcess``), which
plays it on the real server (``rollout_walk.RealWalkBench``) in the real trials and, with ``both``, on ours
(``tune_gait.evaluate``: its own trials, pushes and transition trials included). A trial's score is
``tune_gait.trial_score`` on either server (speed along the walk, falls, drift, heading; a lean trial's
curvature); the real loss is minus the mean score over the real trials, and with ``both`` the candidate's
loss is the mean of the real and our loss.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from kinematics.errors import IKError
from motions.authoring.gait import GaitParams

#: Backends of the gait tuner besides the default in-process MuJoCo one.
BACKENDS = ("real", "both")


def real_trials(motion: str, lean: bool, quick: bool = False) -> tuple:
    """The tuner's trials (``tune_gait.default_trials``) the real server can play: all but the pushed ones (its
    trainer moves a robot but cannot push one)."""
    from motion_studio.tune_gait import default_trials

    return tuple(trial for trial in default_trials(motion, quick, lean) if not trial.pushes)


def real_loss(scores: Sequence[dict[str, float]]) -> float:
    """Minus the mean trial score (``tune_gait.trial_score``) over the real trials."""
    return -float(np.mean([score["score"] for score in scores]))


def combined_loss(real: float, ours: float | None) -> float:
    """The candidate's loss: the real loss alone, or with ours the mean of both."""
    return real if ours is None else (real + ours) / 2.0


@dataclass
class RealJudge:
    """Judges whole gait candidates of ``motion`` on the real server (and on ours with ``ours_trials``).

    Args:
        bench: the real walk bench (a ``RealWalkBench`` or anything with its ``walk``).
        motion: the walk tuned.
        trials: the real trials (:func:`real_trials`).
        ours_trials: our simulator's trials (None: the real server alone).
        robust: our transition trials (``tune_gait.Robust``), with ``ours_trials`` only.
    """

    bench: object
    motion: str
    trials: tuple
    ours_trials: tuple | None = None
    robust: object = None

    def __call__(self, params: GaitParams) -> dict[str, object]:
        """Loss and figures of one candidate: ``real`` (trials, loss) and with ours ``ours`` (its evaluation)."""
        from motion_studio.tune_gait import (DIRECTIONS, FAIL_LOSS, candidate_library, evaluate, trial_place,
                                             trial_score)

        try:
            library = candidate_library(self.motion, params)
        except IKError as error:
            return {"loss": FAIL_LOSS, "error": str(error)[:200], "trials": []}
        direction = DIRECTIONS[self.motion]
        scores = []
        for trial in self.trials:
            run = self.bench.walk(library, self.motion, trial.duration_s, lean=trial.lean,
                                  **trial_place(trial, direction))
            scores.append(trial_score(run, direction))
        real = {"loss": real_loss(scores), "trials": [{"lean": trial.lean, **{k: round(v, 4) for k, v in s.items()}}
                                                      for trial, s in zip(self.trials, scores)]}
        out: dict[str, object] = {"real": real}
        ours = None
        if self.ours_trials is not None:
            out["ours"] = evaluate(self.motion, params, self.ours_trials, self.robust)
            ours = float(out["ours"]["loss"])
        out["loss"] = combined_loss(float(real["loss"]), ours)
        return out


def real_note(result: dict) -> str:
    """The real trials' figures of a judged candidate for the parameter file's provenance."""
    trials = result.get("real", {}).get("trials", [])
    parts = [f"{'lean %+g' % t['lean'] if t.get('lean') else 'plain'} {t['along_m']:.2f} m in {t['time_s']:.0f} s, "
             f"heading {t['heading_deg']:+.0f} deg{', FELL' if t['fell'] else ''}"
             f"{', fell stopping' if t['fell_stopping'] else ''}" for t in trials]
    return "real rcssserver3d 0.7.3 trials: " + ", ".join(parts) if parts else ""


__all__ = ["BACKENDS", "RealJudge", "combined_loss", "real_loss", "real_note", "real_trials"]
