"""Output sets: built aside, moved in complete, and never at the cost of a user's file.

Every command that writes more than one file (a report, a folder of figures, an export) writes
them into a staging folder beside the target, and only when all of them exist moves them in.
A folder that lusm wrote carries a marker, :data:`MARKER`, listing the files it wrote; a new
output set may replace those files and nothing else.

The rules, for a target folder ``DIR``:

* ``DIR`` does not exist, or is empty: the set is moved in, with its marker.
* ``DIR`` holds a marker of the same kind: the files that marker lists are replaced; files the
  user added beside them are left as they are. A user file standing where the new set wants to
  write is refused (or, with ``force``, kept under a ``.bak-N`` name).
* ``DIR`` is non-empty and has no marker of this kind: refused, unless ``force``; with
  ``force`` the set is written beside the user's files, and any of them whose name the set
  needs is renamed to ``NAME.bak-N`` first. Nothing is ever deleted that lusm did not write.

A failure or interruption at any point before the move leaves ``DIR`` exactly as it was, and
the staging folder is removed.
"""

from __future__ import annotations

import json
import os
import shutil
import uuid
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

MARKER = ".lusm-output.json"
"""File name of the marker that lists what lusm wrote into a folder."""


class OutputError(ValueError):
    """An output folder that cannot be written without harming what is already there."""


def _read_marker(folder: Path) -> dict | None:
    path = folder / MARKER
    try:
        doc = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    if not isinstance(doc, dict) or not isinstance(doc.get("files"), list):
        return None
    return doc


def _files_below(folder: Path) -> list[str]:
    """Relative POSIX paths of every file (not folder) below ``folder``, sorted."""
    return sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*")
                  if p.is_file() or p.is_symlink())


def _backup_name(path: Path) -> Path:
    n = 1
    while True:
        candidate = path.with_name(f"{path.name}.bak-{n}")
        if not candidate.exists() and not candidate.is_symlink():
            return candidate
        n += 1


def check_target(target: Path, kind: str, option: str = "--out", force: bool = False) -> None:
    """Refuse, before any work, a target the output set could not be moved into.

    Raises
    ------
    OutputError
        ``target`` is a file, sits below a file, or is a non-empty folder that lusm did not
        write as a ``kind`` (and ``force`` is not set). The message names ``option``.
    """
    target = Path(target)
    if str(target) in ("", "."):
        if not force and target.resolve().exists() and any(target.resolve().iterdir()):
            raise OutputError(f"{option} must name a folder, got {str(target)!r} "
                              "(the current folder, which is not empty)")
    for parent in [target, *target.parents]:
        if parent.exists() and not parent.is_dir():
            what = "is a file" if parent == target else f"sits below the file {parent}"
            raise OutputError(f"{option} must be a folder, but {target} {what}")
        if parent.exists():
            break
    if target.is_dir() and any(target.iterdir()) and not force:
        marker = _read_marker(target)
        if marker is None or marker.get("kind") != kind:
            raise OutputError(
                f"{option} {target} is a non-empty folder that lusm {kind} did not write; "
                "choose a new or empty folder, or pass --force to write beside its files "
                "(nothing of yours is deleted)")


@contextmanager
def output_set(target: Path, kind: str, option: str = "--out",
               force: bool = False) -> Iterator[Path]:
    """Yield a staging folder; on a clean exit move its files into ``target``.

    Parameters
    ----------
    target : Path
        The folder the user named.
    kind : str
        What writes it (``"report"``, ``"figures"``, ...); a marker of another kind does not
        allow replacing.
    option : str
        The command-line option that named ``target``, for messages.
    force : bool
        Write into a non-empty folder lusm did not write, keeping colliding user files under
        ``.bak-N`` names.
    """
    target = Path(target)
    check_target(target, kind, option, force)
    created: list[Path] = []  # parent folders this call made, removed again on failure
    for parent in reversed([target, *target.parents]):
        if not parent.exists():
            created.append(parent)
    stage_parent = next(p for p in [target.parent, *target.parent.parents] if p.exists())
    # Stage inside the nearest existing ancestor so the final move is a rename on one disk.
    # The name is chosen before the folder exists, so a signal landing anywhere (even inside
    # the mkdir) still finds it in ``finally``.
    stage = stage_parent / f".{target.name or 'out'}-partial-{uuid.uuid4().hex[:12]}"
    done = False
    try:
        stage.mkdir()
        yield stage
        _commit(stage, target, kind, force)
        done = True
    finally:
        shutil.rmtree(stage, ignore_errors=True)
        if not done:
            for folder in reversed(created):
                try:
                    folder.rmdir()  # only if still empty: never remove what is not ours
                except OSError:
                    pass


def _commit(stage: Path, target: Path, kind: str, force: bool) -> None:
    from validation.interrupts import checkpoint

    checkpoint()  # a Ctrl-C / SIGTERM that Python swallowed: nothing is moved in
    new_files = _files_below(stage)
    if not target.exists() or (target.is_dir() and not any(target.iterdir())):
        target.parent.mkdir(parents=True, exist_ok=True)
        (stage / MARKER).write_text(json.dumps({"kind": kind, "files": new_files}, indent=1))
        if target.exists():
            target.rmdir()  # empty: nothing of the user's is in it
        os.replace(stage, target)
        stage.mkdir()  # so the caller's cleanup has something to remove
        return
    marker = _read_marker(target)
    ours = set(marker["files"]) if marker and marker.get("kind") == kind else set()
    # Re-check now that the work is done: the folder may have changed meanwhile.
    if not ours and not force:
        check_target(target, kind, force=False)
    collisions = [f for f in new_files if (target / f).exists() and f not in ours]
    # A folder in the way of a new file, or a file in the way of a new folder, collides too.
    for f in new_files:
        for parent in Path(f).parents:
            p = target / parent
            if str(parent) != "." and p.exists() and not p.is_dir():
                collisions.append(parent.as_posix())
    if collisions and not force:
        raise OutputError(f"--out {target} already holds {collisions[0]!r}, which lusm did not "
                          "write; move it away or pass --force (it is kept as a .bak file)")
    for f in sorted(set(collisions)):
        os.replace(target / f, _backup_name(target / f))
    for f in ours:  # lusm's own earlier files: replaced by the new set
        p = target / f
        if p.is_file() or p.is_symlink():
            p.unlink()
    for f in new_files:
        dst = target / f
        dst.parent.mkdir(parents=True, exist_ok=True)
        os.replace(stage / f, dst)
    _prune_empty(target, {str(Path(f).parent) for f in ours})
    (target / MARKER).write_text(json.dumps({"kind": kind, "files": new_files}, indent=1))


def _prune_empty(target: Path, folders: set[str]) -> None:
    """Remove folders an earlier set of ours left empty (deepest first; never the target)."""
    for rel in sorted(folders, key=lambda s: -len(Path(s).parts)):
        if rel in ("", "."):
            continue
        p = target / rel
        while p != target:
            try:
                p.rmdir()
            except OSError:
                break
            p = p.parent
