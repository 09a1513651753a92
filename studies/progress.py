"""The progress bar a study run shows on stderr while its tasks come back."""

from __future__ import annotations

import sys


def progress_bar(total: int, initial: int, enabled: bool, unit: str, desc: str):
    """A tqdm bar on stderr from ``initial`` (the parts a resumed run has) to ``total``.

    Parameters
    ----------
    total, initial : int
        Tasks of the whole run, and those done before it starts.
    enabled : bool
        Show the bar; tqdm still hides it when stderr is not a terminal.
    unit, desc : str
        What one task is (``'geometry'``, ``'design'``) and the bar's label (the command).

    Returns
    -------
    tqdm.tqdm
        Closed by the caller (it is left off the terminal when closed).
    """
    from tqdm import tqdm

    return tqdm(total=total, initial=initial, unit=unit, file=sys.stderr,
                disable=(not enabled) or None, desc=desc, leave=False)
