"""The FE package's structured refusals, in a module that imports nothing heavy, so that the
command line recognises them by class without loading the FE code."""

from __future__ import annotations

from bounds import ParameterError


class ShortedDriveError(ValueError):
    """A drive that puts two voltages on touching electrodes (one conductor).

    Parameters
    ----------
    message : str
        The library's words: the electrodes, how each is wired, why it shorts.
    electrodes : tuple of int
        The touching electrodes (1..4), one conductor.
    """

    def __init__(self, message: str, electrodes: tuple[int, ...] = ()) -> None:
        super().__init__(message)
        self.electrodes = tuple(int(e) for e in electrodes)


class FeatureError(ValueError):
    """A parametric stator whose features (tip, chamfers, holes, mesh size) do not fit its
    plate (:class:`fem.meshing.parametric.ParametricStator`): a sweep, a tuning or a study
    that varies the plate meets it on its own plates.

    Parameters
    ----------
    message : str
        The library's words, in SI units and the class's attribute names.
    file_text : str
        The same refusal in a stator file's terms (its ``[table] key``, mm, hole numbers),
        or ``''`` where the library's words are all there is; the message ends with it.
    """

    def __init__(self, message: str, file_text: str = "") -> None:
        super().__init__(f"{message}: {file_text}" if file_text else message)
        self.file_text = file_text


class GapValidityWarning(UserWarning):
    """The electrode gap is too wide for the 2D model; use the 3D model (``--model 3d``).

    The message is built from the fields, so a front end can word the comparison in its own
    terms (a stator file's keys) and keep the rest (:attr:`detail`).

    Parameters
    ----------
    gap_m : float
        The electrode gap (m): a meshed stator's from its mesh's gap strips.
    thickness_m : float
        The plate's thickness (m).
    limit_m : float
        The widest gap the 2D model is valid for, thickness / 6 (m).
    """

    def __init__(self, gap_m: float, thickness_m: float, limit_m: float) -> None:
        super().__init__(gap_m, thickness_m, limit_m)
        self.gap_m, self.thickness_m, self.limit_m = gap_m, thickness_m, limit_m

    @property
    def detail(self) -> str:
        """The words after the comparison: the plate's thickness, why, the remedy."""
        return (f" (a {self.thickness_m * 1e3:g} mm thick plate): the 2D model is outside "
                "its validity (the gap strip is no longer shorted by its neighbours); use "
                "the 3D model (lusm modes --model 3d, fem.solid3d)")

    def __str__(self) -> str:
        return (f"electrode gap {self.gap_m * 1e3:g} mm exceeds thickness/6 = "
                f"{self.limit_m * 1e3:.3g} mm{self.detail}")


class StatorFileError(ParameterError):
    """A stator file's refusal, named by the file's key, so that a caller tells which key
    failed (and what it allows) without reading the message
    (:func:`fem.stator_file.load_stator`). A :class:`bounds.ParameterError` whose
    :attr:`~bounds.ParameterError.name` is the file's key.

    Parameters
    ----------
    source : str
        The file as the message names it: its path, or the design's name.
    key : str
        The file's key (``'[plate] length_mm'``, ``'[[holes]] #2 diameter_mm'``), a table
        (``'[mesh]'``), or ``''`` for the file as a whole.
    value : object
        The value refused, as the file gives it; None where the key is missing.
    allowed : str
        What the key takes where that is not a range (``'[x, y] in mm'``); a range goes in
        ``low``, ``high`` and ``unit``, a few values in ``choices``.
    text : str, optional
        The refusal after ``'{source}: '`` where it is not ``'{key} must be {allowed}, got
        {value!r}'`` (a key missing, two keys that cannot be combined).
    **range_
        :class:`bounds.ParameterError`'s ``low``, ``high``, ``unit``, ``low_open``,
        ``high_open``, ``reason`` and ``choices``.
    """

    def __init__(self, source: object, key: str, value: object = None, allowed: str = "",
                 text: str | None = None, **range_: object) -> None:
        super().__init__(key, value, kind=allowed, message="", **range_)
        self.source = str(source)
        self.args = (f"{self.source}: {self.said(key) if text is None else text}",)

    @property
    def key(self) -> str:
        """The file's key (the parameter's :attr:`~bounds.ParameterError.name`)."""
        return self.name

    @property
    def allowed(self) -> str:
        """What the key takes, in words (``'in [0.1, 1000] mm'``, ``'[x, y] in mm'``)."""
        return self.range_text()
