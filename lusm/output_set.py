"""Outputs built aside and moved in complete, never at the cost of a user's file.

Every output (a folder of figures, a report, an export, a dataset) is written into a hidden
staging folder beside its target (:func:`staging`) and moved in with :func:`os.replace` once
complete; the staging folder is removed whatever happens, so a failure, Ctrl-C or SIGTERM
leaves the target as it was (SIGKILL or a power cut can leave the hidden folder behind).

A folder lusm wrote carries :data:`MARKER`, the SHA-256 of each file it wrote. An output set
(:func:`output_set`) goes into a folder ``DIR``: whole if ``DIR`` does not exist, else file by
file. A file already there is replaced if the marker lists it with its present content; one
the user edited is kept as ``NAME.bak-N``; any other is refused, or with ``force`` kept as
``NAME.bak-N``. A non-empty ``DIR`` without a marker is refused before any work unless
``force``, and so is a folder whose marker names other commands than the one writing (the
marker lists the commands that wrote there): ``lusm map --plot figs`` does not write into
``lusm simulate``'s ``figs`` unless ``force``. Nothing is deleted; files the set does not
write stay, and stay listed.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import sys
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path, PurePosixPath

MARKER = ".lusm-output.json"
"""File name of the marker that lists what lusm wrote into a folder, with the SHA-256 of each
file as written."""


class OutputError(ValueError):
    """An output that cannot be written without harming what is already there."""


def _stem(name: str) -> str:
    """``name`` cut short from its end so that ``.NAME-partial-`` and the 8 random characters
    of :func:`tempfile.mkdtemp` fit a 255-byte file name (a long name the file system takes
    must not fail for its staging folder)."""
    stem = name or "out"
    while len(os.fsencode(f".{stem}-partial-12345678")) > 255:
        stem = stem[:-1]
    return stem


@contextmanager
def staging(folder: Path, name: str, option: str, target: Path) -> Iterator[Path]:
    """Yield a fresh empty folder ``.NAME-partial-XXXXXXXX`` in ``folder`` (the target's
    disk: moving out of it is a rename), removed with its content on leaving; an
    :class:`OutputError` naming ``option`` and ``target`` if it cannot be made."""
    try:
        stage = Path(tempfile.mkdtemp(prefix=f".{_stem(name)}-partial-", dir=folder))
    except OSError as exc:
        raise OutputError(f"{option} {target}: cannot write there ({exc.strerror or exc})") \
            from None
    try:
        yield stage
    finally:
        shutil.rmtree(stage, ignore_errors=True)


def backup_name(path: Path) -> Path:
    """The first free ``NAME.bak-N`` beside ``path`` (N = 1, 2, ...)."""
    n = 1
    while os.path.lexists(candidate := path.with_name(f"{path.name}.bak-{n}")):
        n += 1
    return candidate


def keep_aside(path: Path, why: str) -> Path:
    """Rename ``path`` (a file or a link, never followed) to its :func:`backup_name` and say
    so on stderr, with ``why``; returns the new name."""
    backup = backup_name(path)
    os.replace(path, backup)
    print(f"lusm: kept {path} as {backup.name} ({why})", file=sys.stderr)
    return backup


def _marker(folder: Path) -> dict[str, str] | None:
    """The files the marker in ``folder`` lists, with the SHA-256 each had as written; None
    when there is no marker (a link or a file that is not one is the user's)."""
    path = folder / MARKER
    try:
        hashes = json.loads(path.read_text()).get("sha256") if path.is_file() \
            and not path.is_symlink() else None
    except (OSError, ValueError, AttributeError):
        hashes = None
    return {f: h for f, h in hashes.items() if isinstance(h, str)} \
        if isinstance(hashes, dict) else None


def _commands(folder: Path) -> set[str]:
    """The ``lusm`` commands the marker in ``folder`` says wrote there (empty: none named)."""
    path = folder / MARKER
    try:
        doc = json.loads(path.read_text()) if path.is_file() and not path.is_symlink() else None
    except (OSError, ValueError):
        doc = None
    names = doc.get("commands") if isinstance(doc, dict) else None
    return {n for n in names if isinstance(n, str)} if isinstance(names, list) else set()


def _digest(path: Path) -> str | None:
    """SHA-256 of a regular file's content; None for a link, a folder or an unreadable file."""
    if path.is_symlink() or not path.is_file():
        return None
    try:
        with path.open("rb") as f:
            return hashlib.file_digest(f, "sha256").hexdigest()
    except OSError:
        return None


def check_target(target: Path, option: str = "--out", force: bool = False,
                 command: str | None = None) -> None:
    """Refuse (:class:`OutputError`, naming ``option``), before any work, a ``target`` that
    is a link to nothing, a file, below a file, or (unless ``force``) a non-empty folder
    without lusm's marker or one whose marker names other commands than ``command``."""
    target = Path(target)
    if target.is_symlink() and not target.exists():
        raise OutputError(f"{option} {target} is a link to {os.readlink(target)}, which does "
                          "not exist; name a folder")
    parent = next((p for p in [target, *target.parents] if p.exists()), None)
    if parent is not None and not parent.is_dir():
        what = "is a file" if parent == target else f"sits below the file {parent}"
        raise OutputError(f"{option} must be a folder, but {target} {what}")
    if not force and target.is_dir() and any(target.iterdir()) and not _marker(target):
        named = f"{target} (the current folder)" if str(target) == "." else str(target)
        raise OutputError(f"{option} {named} is a non-empty folder that lusm did not write; "
                          "choose a new or empty folder, or pass --force to write beside its "
                          "files (nothing of yours is deleted)")
    others = _commands(target) if command is not None and not force and target.is_dir() \
        else set()
    if others and command not in others:
        raise OutputError(f"{option} {target} holds the output of lusm "
                          f"{' and lusm '.join(sorted(others))}; choose another folder, or pass "
                          f"--force to write lusm {command}'s files beside it (nothing is "
                          "deleted)")


def _staging_parent(real: Path) -> Path:
    """The nearest existing folder above ``real`` (an absolute path without links): the set is
    built there, so that moving it in is a rename on one disk."""
    return next((p for p in real.parents if p.is_dir()), real.parent)


def check_writable(target: Path, option: str) -> None:
    """Refuse, before any work, a ``target`` whose set could not be staged, by making and
    removing a staging folder where :func:`output_set` makes it (permission bits do not tell:
    root passes them, and ``/proc`` takes no new folder)."""
    real = Path(os.path.realpath(target))
    with staging(_staging_parent(real), real.name, option, target):
        pass


@contextmanager
def output_set(target: Path, option: str = "--out", force: bool = False,
               command: str | None = None) -> Iterator[Path]:
    """Yield a staging folder; on a clean exit move its files into ``target``.

    Parameters
    ----------
    target : Path
        The folder the user named (a link to a folder: that folder; ``.``: the current one).
    option : str
        The command-line option that named ``target``, for messages.
    force : bool
        Write into a non-empty folder lusm did not write, keeping the user's files that the
        set would replace as ``NAME.bak-N``, or a folder of other commands.
    command : str, optional
        The ``lusm`` command writing the set, recorded in the marker; a folder another
        command wrote is refused unless ``force``.
    """
    target = Path(target)
    check_target(target, option, force, command)
    real = Path(os.path.realpath(target))
    # staged in the nearest existing folder: the target's missing parents are made only
    # when the set is complete
    with staging(_staging_parent(real), real.name, option, target) as stage:
        built = stage / "set"
        built.mkdir()  # the umask's mode: a new target is this folder, renamed
        yield built
        _commit(built, real, option, force, command)


def _commit(stage: Path, target: Path, option: str, force: bool,
            command: str | None = None) -> None:
    """Move the files of ``stage`` into ``target`` by the rules of the module docstring."""
    from lusm.interrupts import checkpoint

    checkpoint()  # a Ctrl-C / SIGTERM that Python swallowed: nothing is moved in
    new = {p.relative_to(stage).as_posix(): _digest(p)
           for p in sorted(stage.rglob("*")) if p.is_file() or p.is_symlink()}
    if not target.exists():
        target.parent.mkdir(parents=True, exist_ok=True)
        _write_marker(stage, new, {command} - {None})
        os.replace(stage, target)
        return
    ours = _marker(target) or {}
    if not force:  # checked again: the folder may have changed meanwhile
        check_target(target, option, command=command)
    in_way = {f for f in new if os.path.lexists(target / f)}
    for f in new:  # a file or link where the set needs a folder
        in_way |= {p.as_posix() for p in PurePosixPath(f).parents if str(p) != "."
                   and ((target / p).is_symlink() or (target / p).exists()
                        and not (target / p).is_dir())}
    edited = {f for f in in_way if f in ours and _digest(target / f) != ours[f]}
    foreign = sorted(in_way - set(ours))
    if foreign and not force:
        raise OutputError(f"{option} {target} already holds {foreign[0]!r}, which lusm did not "
                          "write; move it away or pass --force (it is kept as a .bak file)")
    aside = sorted(edited | set(foreign))
    for f in aside:  # a folder kept aside takes what is below it along
        if not any(PurePosixPath(f).is_relative_to(g) for g in aside if g != f):
            keep_aside(target / f, "it is not what lusm wrote there")
    for f in new:
        (target / f).parent.mkdir(parents=True, exist_ok=True)
        os.replace(stage / f, target / f)
    kept = {f: h for f, h in ours.items() if (target / f).is_file()}
    _write_marker(target, {**kept, **new}, _commands(target) | ({command} - {None}))


def _write_marker(folder: Path, hashes: dict[str, str | None], commands: set[str]) -> None:
    """Write ``folder``'s marker listing ``hashes`` and the ``commands`` that wrote them; a
    link or a file of the user's by that name is kept aside first, never written through or
    over."""
    path = folder / MARKER
    if path.is_symlink() or (os.path.lexists(path) and _marker(folder) is None):
        keep_aside(path, "it is not lusm's marker")
    doc = {"sha256": {f: h for f, h in sorted(hashes.items()) if h is not None},
           "commands": sorted(commands)}
    path.write_text(json.dumps(doc, indent=1))
