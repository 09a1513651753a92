"""The resume store of an optimisation: one part file per evaluated design in ``<out>.parts/``.

The parts are explore's (:func:`studies.parts.write_part`: written aside and renamed in), one
per trial number, each holding the plate's outputs and the design's values
(``design_<variable>``); ``study.json`` names the problem (its fingerprint), the batch size
and the lusm version, and a :mod:`filelock` lock keeps a second run off the folder.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from studies.optimize.problem import Problem
from studies.parts import (
    LOCK_FILE,
    STUDY_FILE,
    part_path,
    parts_folder,
    read_part,
    remove_parts,
    write_part,
)
from studies.task import package_version

DESIGN_PREFIX = "design_"
"""Prefix of a part's design values (``design_length``: m)."""


@dataclass
class Record:
    """One evaluated design.

    Attributes
    ----------
    trial : int
    design : dict
        Variable -> value (SI, or the material's name).
    outputs : dict
        The plate's outputs (:func:`studies.task.compute_geometry`'s arrays).
    """

    trial: int
    design: dict[str, Any]
    outputs: dict[str, np.ndarray]


def part_of(record: Record) -> dict[str, np.ndarray]:
    """The arrays of ``record``'s part file."""
    data = dict(record.outputs)
    for k, v in record.design.items():
        data[DESIGN_PREFIX + k] = np.array(v)
    return data


def record_of(trial: int, data: dict[str, np.ndarray]) -> Record:
    """The :class:`Record` a part file holds."""
    design = {k[len(DESIGN_PREFIX):]: v.item() for k, v in data.items()
              if k.startswith(DESIGN_PREFIX)}
    outputs = {k: v for k, v in data.items() if not k.startswith(DESIGN_PREFIX)}
    return Record(trial, design, outputs)


class Store:
    """The parts folder of one run: opened (made, or checked as this problem's), locked,
    read; :meth:`add` writes a record, :meth:`remove` the folder once the dataset is in.

    Parameters
    ----------
    problem : Problem
    out : Path
        The run's ``--out``.
    resume : bool
        Continue from the parts there (refused without it).
    """

    def __init__(self, problem: Problem, out: Path, resume: bool) -> None:
        from filelock import FileLock, Timeout

        self.folder = parts_folder(Path(out))
        self.created = not self.folder.exists()
        if self.created:
            stamp = {"fingerprint": problem.fingerprint, "batch": None, "kind": "optimize",
                     "lusm_version": package_version()}
            try:
                self.folder.mkdir(parents=True)
                (self.folder / STUDY_FILE).write_text(json.dumps(stamp, indent=1))
            except OSError as exc:
                raise ValueError(f"--out {out}: cannot write its parts folder {self.folder} "
                                 f"({exc.strerror or exc})") from None
        elif not (self.folder / STUDY_FILE).is_file():
            raise ValueError(f"--out {out}: {self.folder} has no {STUDY_FILE}, so it is not "
                             "the parts folder of a lusm optimize run; move it away or choose "
                             "another --out")
        self.lock = FileLock(self.folder / LOCK_FILE)
        try:
            self.lock.acquire(timeout=0)
        except Timeout:
            raise ValueError(f"--out {out}: another lusm run is working on {self.folder}; "
                             "wait for it to finish, or choose another --out") from None
        try:
            self.stamp = json.loads((self.folder / STUDY_FILE).read_text())
            self._check(problem, out, resume)
        except BaseException:
            self.lock.release()
            raise
        self.records = self._read()

    @property
    def batch(self) -> int:
        """Designs asked at once (:meth:`set_batch`)."""
        return int(self.stamp["batch"])

    def set_batch(self, workers: int) -> None:
        """Ask ``workers`` designs at once, unless the folder's run chose its batch already
        (a resumed run keeps it, so it asks for the same designs)."""
        if self.stamp.get("batch") is None:
            self.stamp["batch"] = int(workers)
            (self.folder / STUDY_FILE).write_text(json.dumps(self.stamp, indent=1))

    def _check(self, problem: Problem, out: Path, resume: bool) -> None:
        """Refuse another problem's, another version's, or (without ``resume``) an earlier
        run's parts."""
        if self.created:
            return
        option = "--resume" if resume else f"--out {out}"
        if self.stamp.get("kind") != "optimize" or \
                self.stamp.get("fingerprint") != problem.fingerprint:
            raise ValueError(f"{option}: {self.folder} holds the parts of another study (the "
                             "study file or its stator file changed); remove that folder, or "
                             "restore the study")
        if self.stamp.get("lusm_version") != package_version():
            raise ValueError(f"{option}: {self.folder} was computed by lusm "
                             f"{self.stamp.get('lusm_version')} (this is lusm "
                             f"{package_version()}); remove that folder to start over")
        if not resume:
            raise ValueError(f"--out {out}: {self.folder} holds an unfinished run; pass "
                             "--resume to continue it, or remove that folder to start over")

    def _read(self) -> dict[int, Record]:
        """The readable parts, by trial number."""
        out = {}
        for path in sorted(self.folder.glob("g*.npz")):
            try:
                trial = int(path.stem[1:])
            except ValueError:
                continue
            data = read_part(self.folder, trial)
            if data is not None:
                out[trial] = record_of(trial, data)
        return out

    def add(self, record: Record) -> None:
        """Write ``record``'s part and keep it, as one step: a Ctrl-C between the two would
        leave a part this store does not know of (:meth:`remove` would then leave the folder
        without its ``study.json``, which ``--resume`` refuses); a signal lands after both."""
        from contact.deferred_signals import deferred_signals

        with deferred_signals():
            write_part(self.folder, record.trial, part_of(record))
            self.records[record.trial] = record

    def close(self) -> None:
        """Release the folder's lock."""
        self.lock.release()

    def __enter__(self) -> Store:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        """Release the lock; a run stopped before its first record leaves no trace (the
        folder goes again if this store made it)."""
        self.close()
        if exc_type is not None and self.created and not self.records:
            self.remove()

    def remove(self) -> None:
        """Remove the parts this store wrote and the folder (once the dataset is in)."""
        top = max(self.records, default=-1) + 1
        for i in range(top):
            part_path(self.folder, i).unlink(missing_ok=True)
        remove_parts(self.folder, 0)
