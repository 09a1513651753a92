"""Reduced-order parameter sets: the one meeting point of the FE stator and the contact model.

Importing this package (or :mod:`rom.table2`) never imports scikit-fem or pyvista; the FE-based
reduction lives in its own module and imports the ``fem`` stage lazily.
"""

from rom.params import GRAVITY_M_S2, MotorParams
from rom.table2 import table2

__all__ = ["GRAVITY_M_S2", "MotorParams", "table2"]
