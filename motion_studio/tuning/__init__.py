"""The tuning room: problem (parameters with units and bounds, constraints, objective) -> optimizer (CasADi/IPOPT
trust region, CMA-ES) -> rollout backend (this process, local processes, Ray, a real-server batch) -> run
folder (checkpoint, solver trace as JSON lines, plots drawn from the trace) -> one writer of tuned values into
``motions/params/*.toml`` with provenance. Every tuner is a problem definition on this skeleton.
"""

from motion_studio.tuning.backends import BACKENDS, Backend, BatchBackend, InProcess, make_backend
from motion_studio.tuning.cma_es import CMAES
from motion_studio.tuning.errors import TuningError
from motion_studio.tuning.problem import Constraint, CurveView, ModelSpec, Parameter, Problem, subset
from motion_studio.tuning.runner import Event, RunResult, run

__all__ = ["BACKENDS", "Backend", "BatchBackend", "CMAES", "Constraint", "CurveView", "Event", "InProcess",
           "ModelSpec", "Parameter", "Problem", "RunResult", "TuningError", "make_backend", "run", "subset"]
