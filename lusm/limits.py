"""Every limit of the ``lusm`` inputs in one place: validity ranges and work bounds.

Two kinds of limit (see ``docs/limits.md``):

* **validity ranges** where the model means something (a plate from 10 um to 1 m, a drive
  below the depoling field, a preload the contact can carry); beyond them the CLI refuses
  with exit code 2, and near them it warns on stderr;
* **work bounds** (time steps, map points, mesh refinement, frequency points, mesh cells),
  checked before any array is allocated. They keep a typo (``--dt 1e-13``) from starting a
  run of hours or tens of gigabytes. Ask for more on purpose with the environment variable
  ``LUSM_MAX_WORK=N``: every work bound is multiplied by ``N`` (a number >= 1).

Only the standard library is imported here, so that ``lusm --help`` stays fast.
"""

from __future__ import annotations

import math
import os

WORK_ENV = "LUSM_MAX_WORK"
"""Environment variable multiplying every work bound (e.g. ``LUSM_MAX_WORK=10``)."""

# --- validity ranges (user units) -------------------------------------------------------------
PLATE_MM = (0.1, 1000.0)
"""Plate length, width and thickness (mm): refused outside (and meshes outside it are taken
as a wrong unit, see ``fem.meshing.mesh_io``)."""
PLANE_STRESS_RATIO = 0.6
"""Warn when thickness / min(length, width) exceeds this (plane stress needs a thin plate).
B2's 2D frequency falls below the 3D model's as the plate thickens: on a 25 x 5 mm plate
with a 0.3 mm gap, -0.024 % at 3 mm thickness (0.6) and -0.081 % at 4 mm (0.8) against the
3D model at refine 5, layers 5 (``lusm modes --length-mm 25 --width-mm 5 --gap-mm 0.3
--thickness-mm H [--model 3d --refine 5 --layers 5]``); at 1.0 it is -0.19 %."""
VOLTAGE_V = (0.0, 2000.0)
"""Drive amplitude V0 (V): refused outside. The linear piezoelectric model and PZT-8's
polarisation do not survive fields of ~1 kV/mm; Table 2's motor runs at 50-450 V."""
VOLTAGE_WARN_V = 600.0
"""Warn above this drive amplitude (V): outside the paper's range, heating and nonlinearity."""
PRELOAD_N = (0.0, 1000.0)
"""Preload F_P (N): refused outside. Table 2's motor runs at 6-40 N."""
PRELOAD_WARN_N = 100.0
"""Warn above this preload (N)."""
FREQUENCY_HZ = (1.0, 10e6)
"""Drive frequency and frequency bands (Hz): refused outside."""
DURATION_S = (0.0, 10.0)
"""Simulated time (s), exclusive lower bound: refused outside (and bounded by the steps)."""
WORKERS = (1, 256)
"""Threads of ``lusm map``; processes of ``lusm explore``'s LocalCluster."""
WORKER_TIMEOUT_S = (1.0, 86400.0)
"""``lusm explore --worker-timeout-s`` (s): how long a study waits for a cluster with no
worker."""
TARGET_FREQUENCY_HZ = (1e3, 10e6)
"""``lusm tune --target-frequency`` (Hz)."""
ZETA = (0.0, 1.0)
"""Modal damping ratio of ``lusm admittance --zeta`` (-), exclusive bounds."""

# --- work bounds (multiplied by LUSM_MAX_WORK) ------------------------------------------------
MAX_STEPS = 20_000_000
"""Time steps of one simulation (the default run takes 500 000, ~0.1 s)."""
MAX_WINDOW_STEPS = 2_000_000
"""Steps stored at full resolution (the last periods, 10 doubles each: 160 MB)."""
MAX_MAP_STEPS = 400_000_000
"""Time steps of a whole stick-slip map (points x steps; the default map takes 4e7), and of
a transient ``lusm explore`` study (geometries x drive points x steps)."""
MAX_STEADY_POINTS = 10_000
"""Points of a steady-engine map (``lusm map --method steady``; up to ~0.5 s each, the
default 9 x 9 map has 81)."""
MAX_STEADY_WORK = 500_000
"""Steady solves x steps per drive period of one command (a steady map's points, a
characteristic's loads x voltages, a steady ``lusm explore`` study's geometries x drive points
x their solves, :func:`studies.study.steady_solves`): a point costs in proportion to its
steps per period (25 at 40 kHz, 10 000 points allowed; 14 923 at 20 Hz, where a point takes
1.5 s: 33 allowed)."""
MAX_CALIBRATION_SPEEDS = 500
"""Speed rows of one ``lusm calibrate`` (each a steady solve per model evaluation, about a
hundred evaluations a start: 30 rows take about a minute with three starts and profiles)."""
MAX_UNCERTAINTY_SAMPLES = 4096
"""Monte Carlo draws of ``--uncertainty`` (each a whole prediction; the steady work of all
draws is bounded by :data:`MAX_STEADY_WORK` too)."""
MAX_GRID_POINTS = 2000
"""Points of a ``start:stop:step`` grid (``--voltages``, ``--preloads``, sweep ranges)."""
MAX_SWEEP_POINTS = 200
"""FE solves of one ``lusm sweep``."""
MAX_REFINE_2D = 48
"""``--refine`` of the 2D model (default 4; 48 gives ~1e5 unknowns)."""
MAX_REFINE_3D = 12
"""``--refine`` of the 3D model (default 3)."""
MAX_FE_CELLS_2D = 20_000
"""Elements of a generated 2D plate mesh (the default plate at --refine 48 has 9 700); long,
narrow plates need many elements at a given --refine."""
MAX_FE_CELLS_3D = 3_000
"""Bricks of a generated 3D mesh (planform elements x layers; the uniform ``--quick`` mesh has
195, the default pair's fine mesh 720 on the paper's plate's quarter). The solve grows about
as the square of the bricks (1 050: 19 s; 3 000 with --edge-grading 6: over 150 s); 3 000
admits the default graded meshes of a 35-45 mm stator with a tip (2 140 bricks, its planform
extruded in graded layers), whose solve stays within a minute or two of CPU."""
MAX_FE_WORK_2D = 100_000
"""Elements x FE solves of one command that solves many plates (a sweep, a tuning): ten
solves at --refine 48 (about 3 minutes), 1 100 of the default plate."""
MAX_FE_WORK_3D = 20_000
"""Bricks x FE solves of a 3D tuning (its 3D solves after the 2D start,
:data:`fem.tuning.MAX_3D_SOLVES`, of a 35-45 mm stator with a tip fit)."""
TUNE_SOLVES = 15
"""FE solves a tuning is counted as before it starts (the paper's plate to 40 kHz takes 14)."""
MAX_LAYERS = 16
"""``--layers`` of the 3D model (default 3)."""
MAX_EDGE_GRADING = 6
"""``--edge-grading`` of the 3D model (default 0): levels of lines at ``g 2^-k`` from the
electrode edges; the brick count is bounded separately, before anything is built."""
MAX_ADMITTANCE_MODES = 800
"""Modes ``lusm admittance`` computes below 6 x --f-max (the default band needs ~50; 730 took
2 s, 2 500 took 70 s: ARPACK's work grows as their square)."""
MAX_FREQUENCY_POINTS = 200_000
"""``lusm admittance --points``."""
MAX_MESH_CELLS = 200_000
"""Surface cells of an imported stator mesh (after splitting triangles into quads)."""


MAX_WORK_FACTOR = 1e6
"""Largest ``LUSM_MAX_WORK``: a million times the default bounds is already years of work, and
beyond it the bounds stop being integers a check can compare (1e308 overflowed)."""


def work_factor() -> float:
    """The ``LUSM_MAX_WORK`` multiplier (1 when unset).

    Raises
    ------
    ValueError
        If the variable is set but not a number in [1, :data:`MAX_WORK_FACTOR`].
    """
    text = os.environ.get(WORK_ENV, "").strip()
    if not text:
        return 1.0
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and 1.0 <= value <= MAX_WORK_FACTOR):
        raise ValueError(f"{WORK_ENV} must be a number in [1, {MAX_WORK_FACTOR:.0f}] "
                         f"(multiplies the work bounds), got {text!r}")
    return value


def work_bound(limit: float) -> int:
    """``limit`` times :func:`work_factor`, as an integer."""
    return int(limit * work_factor())


def more_work_hint() -> str:
    """The sentence telling the user how to raise a work bound on purpose."""
    return f"set {WORK_ENV}=N to allow N times more"


MEASURED_THICK_RATIO = 1.3
"""The largest thickness over in-plane size at which the 2D model was measured against 3D
(:func:`lusm.options.warn_thin_plate`)."""
