"""The reduced-order package's structured refusals, in a module that imports nothing of the
project, so that the command line recognises them by class and formats them from their
fields, not from their wording."""

from __future__ import annotations

import math


class UnreachableAmplitudeError(ValueError):
    """A damping fit whose target amplitude no damping reaches at the drive frequency: even
    undamped, the mode's response there is smaller (:func:`rom.damping.identify_damping`).

    Parameters
    ----------
    mode : str
        ``'L1'`` or ``'B2'``.
    target_m_per_V : float
        The amplitude per volt asked for (m/V).
    frequency_Hz : float
        The drive frequency of the fit (Hz).
    undamped_m_per_V : float
        The undamped mode's amplitude per volt there (m/V), the most any damping gives.
    natural_Hz : float
        The mode's natural frequency (Hz): a drive frequency nearer to it reaches more.
    remedy : str
        What the caller can change, the message's last clause.
    """

    def __init__(self, mode: str, target_m_per_V: float, frequency_Hz: float,
                 undamped_m_per_V: float, natural_Hz: float,
                 remedy: str = "identify at a drive frequency nearer to it") -> None:
        self.mode, self.target_m_per_V = mode, target_m_per_V
        self.frequency_Hz, self.undamped_m_per_V = frequency_Hz, undamped_m_per_V
        self.natural_Hz, self.remedy = natural_Hz, remedy
        super().__init__(
            f"no damping gives the {mode} amplitude {target_m_per_V:.4g} m/V at "
            f"{frequency_Hz:.6g} Hz: even undamped the mode reaches only "
            f"{undamped_m_per_V:.4g} m/V there (its natural frequency is {natural_Hz:.6g} Hz); "
            f"{remedy}")

    @classmethod
    def of_mode(cls, mode: str, target: float, omega: float, mass: float, stiffness: float,
                undamped: float) -> UnreachableAmplitudeError:
        """The error of ``mode`` from its angular frequency (rad/s), mass (kg) and stiffness
        (N/m)."""
        return cls(mode, target, omega / (2 * math.pi), undamped,
                   math.sqrt(stiffness / mass) / (2 * math.pi))


class NodalPointError(ValueError):
    """A point where the modal reduction normalises a mode that lies at (or next to) a node
    of it (:func:`rom.from_fem.fem_params`); a stator file moves it with ``key``.

    Parameters
    ----------
    message : str
        The library's words: the mode, the point, its share of the largest displacement.
    mode : str
        ``'L1'`` or ``'B2'``.
    point : str
        ``'preload'`` or ``'tip'``.
    share : float
        The mode's displacement there over its largest (-).
    key : str
        The stator file's key that places the point (``'[points] preload_mm'``).
    """

    def __init__(self, message: str, mode: str, point: str, share: float, key: str) -> None:
        super().__init__(message)
        self.mode, self.point, self.share, self.key = mode, point, share, key


class DesignFileError(ValueError):
    """A stator file whose motor tables make no valid parameter set or damping fit
    (:func:`rom.from_fem.design_base`, :func:`rom.from_fem.fem_params_from_design`).

    Parameters
    ----------
    path : str
        The file (or the design's name, for a design not read from a file).
    key : str
        The file's ``[table] key`` to blame, or ``''`` where it is not one key.
    reason : str
        What is wrong, in the file's terms.
    """

    def __init__(self, path: str, key: str, reason: str) -> None:
        self.path, self.key, self.reason = str(path), key, reason
        super().__init__(f"{self.path}: {f'{key}: ' if key else ''}{reason}")
