"""``lusm optimize``: the best stator for a motor objective, searched on dask.

:func:`optimize` asks optuna's TPE sampler for designs in batches of the cluster's workers,
evaluates each as the one-geometry explore study of its values (:func:`studies.task.
compute_geometry`), keeps every evaluation as a part for ``--resume``, and writes one dataset
row per evaluation. The study file's ``[optimize]`` table is read by :func:`load_problem`.
See docs/optimize.md.
"""

from studies.optimize.problem import Problem, load_problem, problem_from_dict
from studies.optimize.result import OptimizeResult
from studies.optimize.search import optimize

__all__ = ["OptimizeResult", "Problem", "load_problem", "optimize", "problem_from_dict"]
