"""Calibration of a motor model to measurements of a prototype (``lusm calibrate``).

A measurement file (TOML, :mod:`calibration.measurements`) names CSV files of free tip
amplitudes, of the free stator's admittance and of steady speeds, each column with its unit
and uncertainty, and the parameters to fit with their start values and bounds
(:mod:`calibration.parameters`). :mod:`calibration.model` predicts every measured value from a
parameter set (the linear free response, the two-mode admittance, the steady engine),
:mod:`calibration.fit` fits them by weighted least squares from several starts and reports
the covariance, correlations, profile-likelihood intervals and which parameters the data
cannot fix, and :mod:`calibration.output` writes the calibrated stator or parameter file
with the fit in machine-readable form. :mod:`calibration.uncertainty` reads that back and
carries the covariance to any prediction by Monte Carlo (``--uncertainty``;
:mod:`calibration.bands`: the steady speed, stall force and map).
The package sits above ``contact`` and below the command line (``docs/calibration.md``).
"""

from calibration.fit import CalibrationResult, calibrate
from calibration.measurements import MeasurementError, Measurements, load_measurements

__all__ = ["CalibrationResult", "MeasurementError", "Measurements", "calibrate",
           "load_measurements"]
