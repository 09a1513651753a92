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
