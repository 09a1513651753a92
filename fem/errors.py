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
