"""agent.motion: the motion controller (XML phase and Webots playback), its library and dynamic elements.

``MotionController.request(MotionRequest(...))`` then ``update(joint_angles_deg, time_s) -> {effector: rad/s}``
once per cycle; see :mod:`agent.motion.controller`.
"""

from agent.motion.controller import ControllerConfig, MotionController, MotionEvent, MotionRequest
from agent.motion.dynamic import (DEFAULT_PARAMS_PATH, DynamicParams, Slowdown, TurnGain, WalkBalance,
                                  WalkLean, load_dynamic_params, save_dynamic_params)
from agent.motion.library import DEFAULT_MOTION_DIR, MotionLibrary, WebotsTiming, default_library

__all__ = [
    "ControllerConfig", "DEFAULT_MOTION_DIR", "DEFAULT_PARAMS_PATH", "DynamicParams", "MotionController",
    "MotionEvent", "MotionLibrary", "MotionRequest", "Slowdown", "TurnGain", "WalkBalance", "WalkLean",
    "WebotsTiming", "default_library", "load_dynamic_params", "save_dynamic_params",
]
