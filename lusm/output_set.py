"""Output sets: built aside, moved in complete, and never at the cost of a user's file.

Every command that writes more than one file (a report, a folder of figures, an export) writes
them into a staging folder beside the target, and only when all of them exist moves them in.
A folder that lusm wrote carries a marker, :data:`MARKER`, listing the files it wrote with the
SHA-256 of each as written; a new output set may replace those files, as long as they are still
what lusm wrote, and nothing else.

The rules, for a target folder ``DIR``:

* ``DIR`` does not exist: the set is moved in, with its marker. ``DIR`` is empty: its files
  are moved into it (the folder, its owner and mode stay the user's).
* ``DIR`` holds a marker of the same kind: a file it lists that the new set writes again is
  replaced if its content is still what lusm wrote; if the user edited it (or the marker has no
  hash for it) it is kept as ``NAME.bak-N``. Files of the earlier set that the new one does not
  write stay where they are (a second ``lusm sweep`` over another axis keeps the first one's
  figure), and stay listed as lusm's. Files the user added beside them are left as they are. A
  user file standing where the new set wants to write is refused (or, with ``force``, kept
  under a ``.bak-N`` name).
* ``DIR`` is non-empty and has no marker of this kind: refused, unless ``force``; with
  ``force`` the set is written beside the user's files, and any of them whose name the set
  needs is renamed to ``NAME.bak-N`` first.

Nothing is ever deleted but lusm's own staging folders. A marker is only trusted for plain
relative names inside ``DIR``: an entry such as ``../x`` or ``/home/u/x`` (a hand-edited or
planted marker) is ignored, so no file outside the folder is ever touched.

A failure or interruption at any point before the move leaves ``DIR`` exactly as it was, and
the staging folder is removed.

A run killed outright (``SIGKILL``, a power cut) cannot remove its staging folder; the next
run writing the same target deals with it (:mod:`lusm.staging`).
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from lusm.staging import staging, staging_name

MARKER = ".lusm-output.json"
"""File name of the marker that lists what lusm wrote into a folder."""


class OutputError(ValueError):
    """An output folder that cannot be written without harming what is already there."""


def _read_marker(folder: Path) -> dict | None:
    path = folder / MARKER
    if path.is_symlink() or not path.is_file():  # a link is the user's, never lusm's marker
        return None
    try:
        doc = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    if not isinstance(doc, dict) or not isinstance(doc.get("files"), list):
        return None
    return doc


def _safe_name(folder: Path, name: object) -> bool:
    """Whether a marker entry is a plain relative path that stays inside ``folder``.

    Rejects absolute paths, ``..`` parts, empty or ``.`` parts, the marker itself, and names
    that a symlinked folder inside ``folder`` would lead outside it.
    """
    if not isinstance(name, str) or not name or "\\" in name or "\x00" in name:
        return False
    parts = name.split("/")
    if name.startswith("/") or any(p in ("", ".", "..") for p in parts) or name == MARKER:
        return False
    root = folder.resolve()
    parent = (folder / name).parent.resolve()
    return parent == root or root in parent.parents


def _digest(path: Path) -> str | None:
    """SHA-256 of a regular file's content; None for a symlink, folder or unreadable file."""
    if path.is_symlink() or not path.is_file():
        return None
    try:
        with path.open("rb") as f:
            return hashlib.file_digest(f, "sha256").hexdigest()
    except OSError:
        return None


def _sets(marker: dict | None) -> dict[str, dict]:
    """The file sets a marker records, by the command kind that wrote each: ``{kind: {"files":
    [...], "sha256": {...}}}``. A marker written before several sets were kept (one
    ``kind``, its ``files`` and ``sha256``) is the set of its kind."""
    if marker is None:
        return {}
    sets = marker.get("sets")
    if isinstance(sets, dict):
        return {k: v for k, v in sets.items() if isinstance(k, str) and isinstance(v, dict)
                and isinstance(v.get("files"), list)}
    kind = marker.get("kind")
    return {kind: {"files": marker["files"], "sha256": marker.get("sha256")}} \
        if isinstance(kind, str) else {}


def _ours(folder: Path, kind: str) -> dict[str, str | None]:
    """Files the marker in ``folder`` lists for ``kind``, each with its hash as written.

    Unsafe entries are dropped; an entry without a recorded hash maps to None (a marker
    written before hashes were kept), so it is never taken as unchanged.
    """
    entry = _sets(_read_marker(folder)).get(kind)
    if entry is None:
        return {}
    hashes = entry.get("sha256")
    hashes = hashes if isinstance(hashes, dict) else {}
    return {f: (hashes.get(f) if isinstance(hashes.get(f), str) else None)
            for f in entry["files"] if _safe_name(folder, f)}


def _write_marker(folder: Path, kind: str, hashes: dict[str, str | None]) -> None:
    """Record ``hashes`` as ``kind``'s files in ``folder``'s marker, keeping the sets other
    commands wrote there (``--force`` of a characteristic into a report's folder had kept the
    report's list aside as a ``.bak`` file, and a later report took its own files for the
    user's)."""
    files = sorted(hashes)
    own = {"files": files, "sha256": {f: hashes[f] for f in files if hashes[f] is not None}}
    path = folder / MARKER
    sets: dict[str, dict] = {}
    if path.is_symlink() or (path.exists() and not path.is_file()):
        # never write through a link (into whatever it points at): keep it aside
        keep_aside(path, "it is not lusm's marker")
    elif path.exists():
        earlier = _read_marker(folder)
        if earlier is None:  # a file of the user's by that name (--force into their folder)
            keep_aside(path, "it is not lusm's marker")
        else:
            # the other commands' sets stay, less the files this set now owns
            for k, entry in _sets(earlier).items():
                if k == kind:
                    continue
                rest = [f for f in entry["files"] if f not in hashes]
                old = entry.get("sha256") if isinstance(entry.get("sha256"), dict) else {}
                if rest:
                    sets[k] = {"files": rest, "sha256": {f: old[f] for f in rest if f in old}}
    sets[kind] = own
    doc = {"kind": kind, **own, "sets": sets}
    path.write_text(json.dumps(doc, indent=1))


def _files_below(folder: Path) -> list[str]:
    """Relative POSIX paths of every file (not folder) below ``folder``, sorted."""
    return sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*")
                  if p.is_file() or p.is_symlink())


def backup_name(path: Path) -> Path:
    """The first free ``NAME.bak-N`` beside ``path`` (N = 1, 2, ...)."""
    n = 1
    while True:
        candidate = path.with_name(f"{path.name}.bak-{n}")
        if not candidate.exists() and not candidate.is_symlink():
            return candidate
        n += 1


def keep_aside(path: Path, why: str) -> Path:
    """Rename ``path`` (a file or a link, never followed) to its :func:`backup_name` and say
    so on stderr, with ``why``; returns the new name."""
    backup = backup_name(path)
    os.replace(path, backup)
    print(f"lusm: kept {path} as {backup.name} ({why})", file=sys.stderr)
    return backup


def check_target(target: Path, kind: str, option: str = "--out", force: bool = False) -> None:
    """Refuse, before any work, a target the output set could not be moved into.

    Raises
    ------
    OutputError
        ``target`` is a file, sits below a file, or is a non-empty folder that lusm did not
        write as a ``kind`` (and ``force`` is not set). The message names ``option``.
    """
    target = Path(target)
    if target.is_symlink() and not target.exists():
        raise OutputError(f"{option} {target} is a link to {os.readlink(target)}, which does "
                          "not exist; name a folder")
    for parent in [target, *target.parents]:
        if parent.exists() and not parent.is_dir():
            what = "is a file" if parent == target else f"sits below the file {parent}"
            raise OutputError(f"{option} must be a folder, but {target} {what}")
        if parent.exists():
            break
    if target.is_dir() and any(target.iterdir()) and not force:
        marker = _read_marker(target)
        others = [p for p in target.iterdir() if p.name != MARKER]
        if marker is None or kind not in _sets(marker) or (others and not _ours(target, kind)):
            # no marker of ours, or one that lists nothing usable (hand-edited, planted)
            other = marker.get("kind") if marker is not None else None
            whose = (f"holds the output of lusm {other}, not of lusm {kind}"
                     if isinstance(other, str) and other != kind and other.isidentifier()
                     else f"is a non-empty folder that lusm {kind} did not write")
            # '.' alone does not say which folder was refused
            named = f"{target} (the current folder)" if str(target) == "." else str(target)
            raise OutputError(
                f"{option} {named} {whose}; choose a new or empty folder, or pass --force "
                "to write beside its files (nothing of yours is deleted)")


def _resolved_target(target: Path) -> Path:
    """The folder a set named ``target`` goes into: a link's folder, the current folder by its
    absolute name."""
    if target.is_symlink():  # a link to a folder: the set goes into the folder it names
        target = target.resolve()
    if str(target) in ("", "."):
        # the current folder: stage beside it, not inside it (inside, the staging folder
        # made it non-empty and the finished set was refused)
        target = Path(os.path.abspath(target))
    return target


def staging_parent(target: Path) -> Path:
    """The folder in which :func:`output_set` builds the set for ``target``: the nearest
    existing ancestor of its parent, so the final move is a rename on one disk."""
    target = _resolved_target(Path(target))
    return next(p for p in [target.parent, *target.parent.parents] if p.exists())


def check_writable(target: Path, option: str) -> None:
    """Refuse, before any work, a ``target`` whose set could not be staged: a folder is made
    and removed where :func:`output_set` stages it, its name bounded the same way. Permission
    bits do not tell (root passes them everywhere, and ``/proc`` or ``/sys`` take no new
    folder): ``explore --plot /proc/maps`` ran the whole study before the maps were refused."""
    try:
        parent = staging_parent(target)
        probe = parent / staging_name(target.name, "probe", parent)
        probe.mkdir(mode=0o700)
        probe.rmdir()  # only reached when the mkdir made it: never an entry that was there
    except OSError as exc:
        raise OutputError(f"{option} {target}: cannot write there ({exc.strerror or exc})") \
            from None


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
    target = _resolved_target(target)
    created: list[Path] = []  # parent folders this call made, removed again on failure
    for parent in reversed([target, *target.parents]):
        if not parent.exists():
            created.append(parent)
    def refuse(exc: OSError) -> Exception:  # the user's folder and option, not the stage's
        from lusm.errors import LusmError

        return LusmError(f"{option} {target}: cannot write there ({exc.strerror or exc})",
                         option)

    done = False
    try:
        with staging(target.name, staging_parent(target), refuse, option, target) as stage:
            yield stage
            _commit(stage, target, kind, force, option)
            done = True
    finally:
        if not done:
            for folder in reversed(created):
                try:
                    folder.rmdir()  # only if still empty: never remove what is not ours
                except OSError:
                    pass


def _commit(stage: Path, target: Path, kind: str, force: bool, option: str = "--out") -> None:
    from lusm.interrupts import checkpoint

    checkpoint()  # a Ctrl-C / SIGTERM that Python swallowed: nothing is moved in
    new_files = _files_below(stage)
    new_hashes = {f: _digest(stage / f) for f in new_files}
    if not target.exists():
        target.parent.mkdir(parents=True, exist_ok=True)
        _write_marker(stage, kind, new_hashes)
        os.replace(stage, target)  # the staging folder around it is removed by the caller
        return
    # an existing folder, empty or not, is the user's: the files move into it (replacing
    # an empty one by the staging folder lost its owner, group, mode and the shell's
    # current folder)
    ours = _ours(target, kind)
    # Re-check now that the work is done: the folder may have changed meanwhile.
    if not ours and not force:
        check_target(target, kind, option, force=False)
    collisions = [f for f in new_files
                  if (target / f).exists() or (target / f).is_symlink()]
    # A folder in the way of a new file, or a file in the way of a new folder, collides too.
    for f in new_files:
        for parent in Path(f).parents:
            p = target / parent
            if str(parent) != "." and (p.is_symlink() or (p.exists() and not p.is_dir())):
                collisions.append(parent.as_posix())
    # lusm's own earlier file, unchanged since it was written, is simply replaced; one the
    # user edited (or whose hash the marker lacks) is kept aside like any user file.
    replace = {f for f in collisions if f in new_hashes
               and f in ours and ours[f] is not None and _digest(target / f) == ours[f]}
    edited = sorted({f for f in collisions if f in ours} - replace)
    foreign = sorted(set(collisions) - set(ours))
    if foreign and not force:
        raise OutputError(f"{option} {target} already holds {foreign[0]!r}, which lusm did not "
                          "write; move it away or pass --force (it is kept as a .bak file)")
    aside = sorted({*edited, *foreign})
    # a folder (or a link to one) kept aside takes its contents with it: a file below it is
    # not kept aside again (figures/ as a link: figures/a.png then no longer existed, the
    # move failed halfway and the new report was lost)
    aside = [f for f in aside if not any(Path(f).is_relative_to(g) for g in aside if g != f)]
    for f in aside:
        keep_aside(target / f, "it is not what lusm wrote there")
    for f in new_files:
        dst = target / f
        dst.parent.mkdir(parents=True, exist_ok=True)
        os.replace(stage / f, dst)
    # Earlier files the new set did not rewrite stay, and stay lusm's.
    kept = {f: h for f, h in ours.items() if f not in new_hashes and f not in edited
            and f not in foreign and (target / f).is_file()}
    _write_marker(target, kind, {**kept, **new_hashes})
