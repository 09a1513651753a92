"""The FE package's structured refusals, in a module that imports nothing heavy, so that the
command line recognises them by class without loading the FE code."""

from __future__ import annotations


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
