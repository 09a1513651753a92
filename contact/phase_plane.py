"""The transformed phase plane of Section 4.3: (y_tip, v_rel) with the lines L1 and L2.

L1 is ``y_tip = y_tip^min``, the smallest tip normal displacement of the steady state; L2 is
``y_tip = y_tip^c``, the displacement at which F_N reaches 0 (Eq. 21). The separation region S
between them exists only when ``y_tip^c > y_tip^min`` (Eq. 20).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from contact.model import normal_force_zero_tip_displacement
from contact.results import FrozenArrays
from contact.simulate import SimulationResult


@dataclass(frozen=True, eq=False)
class PhasePlane(FrozenArrays):
    """Steady-state trajectory on the transformed phase plane.

    Attributes
    ----------
    y_tip_m : ndarray
        Tip normal displacement (m), abscissa.
    v_rel_m_s : ndarray
        Relative tangential velocity (m/s), ordinate.
    phase : ndarray
        Phase code per point (see :class:`contact.results.Trace`).
    y_min_m : float
        Line L1 (m).
    y_c_m : float
        Line L2 (m), Eq. 21.
    """

    y_tip_m: np.ndarray
    v_rel_m_s: np.ndarray
    phase: np.ndarray
    y_min_m: float
    y_c_m: float

    @property
    def separation_region(self) -> bool:
        """Whether the region S between L1 and L2 exists (``y_c > y_min``)."""
        return self.y_c_m > self.y_min_m


def phase_plane(result: SimulationResult) -> PhasePlane:
    """Phase-plane trajectory of the stored steady-state window of a run.

    Raises
    ------
    ValueError
        The run stored no window at every step: only ``method="event"`` does.
    """
    w = result.window
    if w is None:  # say why, not an AttributeError on None
        raise ValueError(f"phase_plane needs the steady-state window at every step, which "
                         f"only method='event' stores; this run used method="
                         f"{result.method!r}")
    y_c = normal_force_zero_tip_displacement(result.params, result.op.preload_N)
    return PhasePlane(
        y_tip_m=w.y_tip_m,
        v_rel_m_s=w.v_rel_m_s,
        phase=w.phase,
        y_min_m=result.steady.y_tip_min_m,
        y_c_m=y_c,
    )
