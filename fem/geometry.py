"""Geometry of the stator plate and of its four quadrant electrodes.

Coordinates (m): ``x`` across the width, centred (``-W/2 <= x <= W/2``); ``y`` along the
length (``0 <= y <= l``); ``z`` through the thickness, the poling direction (the 2D model is
in the x-y plane). The preload point is the centre of the end ``y = 0``, the contact tip the
centre of the end ``y = l``.

Electrodes on the top face, following Fig. 1 of the paper ("1 2" above "3 4")::

      y=0                      y=l
       +-----------+-----------+   x = +W/2
       |     1     |     2     |
       +-----------+-----------+   x = 0   (gap strips of width g along x=0 and y=l/2)
       |     3     |     4     |
       +-----------+-----------+   x = -W/2
    preload                   tip

Electrode 1: ``x > g/2, y < l/2 - g/2``; 2: ``x > g/2, y > l/2 + g/2``;
3: ``x < -g/2, y < l/2 - g/2``; 4: ``x < -g/2, y > l/2 + g/2``. The bottom face is one
grounded electrode. Driving one diagonal (1, 4) excites L1 and B2 together; the other
diagonal (2, 3) reverses the sign of the B2 forcing and hence the direction of motion.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from bounds import ParameterError

ELECTRODES = (1, 2, 3, 4)
"""Electrode numbers of the top face."""


MIN_GAP_M = 1e-6
"""Smallest non-zero electrode gap (m): 1 um, far below any printed or etched gap; a gap of
0 means touching quadrants (one conductor)."""


MAX_SIZE_M = 10.0
"""Largest plate dimension (m) the stator classes accept: ten times the CLI's 1000 mm, room
for a tuning's trial plates; millimetres typed as metres (``length_m=30``) are refused (a
30 m plate runs 29 s of FE into NaN)."""


@dataclass(frozen=True)
class PlateStator:
    """Rectangular piezoelectric stator plate with four quadrant electrodes.

    Attributes
    ----------
    length_m : float
        Length l along y (m); the paper's 30 mm.
    width_m : float
        Width b_s along x (m); the paper's 7.5 mm.
    thickness_m : float
        Thickness h_s along the poling axis z (m); the paper's 3 mm.
    electrode_gap_m : float
        Width of the unelectroded strips separating the quadrants (m), ``0 <= g < min(W, l)``.
    drive_electrodes : tuple of int
        Electrodes carrying the drive voltage (the others are grounded), numbers in 1..4.
    """

    length_m: float = 30e-3
    width_m: float = 7.5e-3
    thickness_m: float = 3e-3
    electrode_gap_m: float = 0.5e-3
    drive_electrodes: tuple[int, ...] = (1, 4)

    def __post_init__(self) -> None:
        for name in ("length_m", "width_m", "thickness_m", "electrode_gap_m"):
            value = getattr(self, name)
            # NumPy scalars are numbers (np.float32(0.03) too) and are stored as floats; a
            # bool is not a size (True would make a 1 m plate)
            if isinstance(value, (np.integer, np.floating)) and not isinstance(value, bool):
                object.__setattr__(self, name, float(value))
            elif isinstance(value, (bool, np.bool_)):
                raise ParameterError(name, value, unit="m",
                                     message=f"PlateStator.{name} must be a number (m), got "
                                     f"{value!r}")
        for name in ("length_m", "width_m", "thickness_m"):
            value = getattr(self, name)
            if not isinstance(value, (int, float)) or not np.isfinite(value) or value <= 0.0:
                raise ParameterError(name, value, 0.0, MAX_SIZE_M, "m", low_open=True,
                                     message=f"PlateStator.{name} must be a finite number > 0, "
                                     f"got {value!r}")
            if value > MAX_SIZE_M:  # millimetres typed as metres: a 30 m plate
                raise ParameterError(name, value, 0.0, MAX_SIZE_M, "m", low_open=True,
                                     message=f"PlateStator.{name} must lie in (0, "
                                     f"{MAX_SIZE_M:g}] m, got {value!r} (sizes are in metres: "
                                     "30 mm is 0.03)")
        gap = self.electrode_gap_m
        if not isinstance(gap, (int, float)) or not np.isfinite(gap) or gap < 0.0:
            raise ParameterError("electrode_gap_m", gap, 0.0, None, "m",
                                 message=f"PlateStator.electrode_gap_m must be >= 0, got {gap!r}")
        if 0.0 < gap < MIN_GAP_M:
            raise ParameterError(
                "electrode_gap_m", gap, MIN_GAP_M, None, "m",
                reason="or 0, touching quadrants",
                message=f"PlateStator.electrode_gap_m must be 0 (touching quadrants) or at least "
                f"{MIN_GAP_M:g} m, got {gap!r}: the gap's cross-section solve grades its mesh "
                "from a fraction of the gap to the plate's size")
        limit = min(self.width_m, self.length_m)
        if gap >= limit:
            raise ParameterError(
                "electrode_gap_m", gap, 0.0, limit, "m", high_open=True,
                reason="below the plate's width and length",
                message=f"PlateStator.electrode_gap_m must lie in [0, {limit!r}) m "
                f"(min of width and length), got {gap!r}: the gap leaves no electrode"
            )
        try:  # any sequence of numbers (a NumPy array too); an int is refused below
            drive = tuple(self.drive_electrodes)
        except TypeError:  # refused below, with the choices, not as "'int' object ..."
            drive = ()
        if len(drive) == 0 or any(
            isinstance(e, bool) or not isinstance(e, (int, np.integer)) or e not in ELECTRODES
            for e in drive
        ):
            raise ValueError(
                f"PlateStator.drive_electrodes must be a non-empty tuple of electrode numbers in "
                f"1..4, got {self.drive_electrodes!r}"
            )
        if len(set(drive)) != len(drive):
            raise ValueError(
                f"PlateStator.drive_electrodes must not repeat an electrode, got {drive!r}"
            )
        object.__setattr__(self, "drive_electrodes", tuple(int(e) for e in drive))

    @property
    def tip_point_m(self) -> tuple[float, float]:
        """Contact tip ``(x, y)``: centre of the end ``y = l`` (m)."""
        return (0.0, float(self.length_m))

    @property
    def preload_point_m(self) -> tuple[float, float]:
        """Preload point ``(x, y)``: centre of the end ``y = 0`` (m)."""
        return (0.0, 0.0)

    def electrode_of(self, x_m: np.ndarray, y_m: np.ndarray, tol_m: float = 0.0) -> np.ndarray:
        """Electrode number (1..4) above points ``(x, y)``, 0 in the gap strips; a point
        within ``tol_m`` (m) of an electrode's edge counts as on it (mesh nodes on the
        edge, a roundoff away)."""
        x = np.asarray(x_m, dtype=float)
        y = np.asarray(y_m, dtype=float)
        g2 = max(0.5 * self.electrode_gap_m - tol_m, 0.0)
        half = 0.5 * self.length_m
        upper = x > g2  # electrodes 1, 2
        lower = x < -g2  # electrodes 3, 4
        near = y < half - g2  # preload half: 1, 3
        far = y > half + g2  # tip half: 2, 4
        out = np.zeros(np.broadcast(x, y).shape, dtype=int)
        out[upper & near] = 1
        out[upper & far] = 2
        out[lower & near] = 3
        out[lower & far] = 4
        return out

    def reversed(self) -> PlateStator:
        """The same stator driven through the other diagonal (reverse direction of motion)."""
        return reverse_drive(self)


def reverse_drive(stator: PlateStator) -> PlateStator:
    """Copy of ``stator`` driven through the opposite diagonal (1 <-> 4 becomes 2 <-> 3).

    Each driven electrode is replaced by the electrode of the other diagonal in the same
    half-length: 1 -> 3, 4 -> 2, 2 -> 4, 3 -> 1, i.e. the x-mirror image, which keeps the L1
    forcing and reverses the B2 forcing.
    """
    mirror = {1: 3, 3: 1, 2: 4, 4: 2}
    drive = tuple(sorted(mirror[e] for e in stator.drive_electrodes))
    return replace(stator, drive_electrodes=drive)

