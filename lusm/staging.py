"""Staging folders: an output built aside, and what a run killed outright leaves of one.

An output (an output set, :mod:`lusm.output_set`; an export; a dataset) is built in a
fresh hidden folder beside its target, ``.NAME-partial-<12 hex>`` (:func:`staging_name`,
bounded by the file system's limit on a name), and moved in only when whole; the folder is
removed on leaving, whatever happened (:func:`staging`).

A run killed outright (``SIGKILL``, a power cut) cannot remove its staging folder. Every
staging folder therefore holds :data:`STAGING_LOCK`, on which its run holds an exclusive
``flock`` from the start, and which records that run's process, host, boot and the folder
(its random suffix, device and inode). The next run writing the same target removes such a
folder only when all of that says it is lusm's and dead: the record names this very folder
(not a copy), this host and this boot, the lock is free (the kernel released it when the run
died) and the recorded process is gone. Every other folder of that name laid out as lusm
makes one (a folder without the record, a copy, another host's or another boot's, one whose
process id lives again) is left where it is,
and named in one warning line; a folder whose lock is held is a run at work, and any other
entry of that name (a file, a folder of other content) may be the user's: both are left
unsaid (:func:`clear_stale_staging`).
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import shutil
import socket
import stat
import sys
import uuid
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

STAGING_LOCK = ".lusm-staging"
"""The file in every staging folder that its run holds an exclusive ``flock`` on, recording
``{"lusm": "staging", "token": <the folder's 12 hex>, "dev": ..., "ino": ..., "pid": ...,
"host": ..., "boot": ...}`` (``dev``, ``ino``: the folder's ``st_dev`` and ``st_ino``;
``boot``: Linux's boot id, or null)."""

_STAGED = "set"
"""The folder inside a staging folder that the output is built in (the lock file stays out of
the set: a new target is this folder, renamed)."""


def _name_max(folder: Path) -> int:
    """The longest file name, in bytes, that ``folder``'s file system takes (255 when it does
    not say, and never more: the common limit, which a wrong answer must not raise)."""
    try:
        limit = os.pathconf(folder, "PC_NAME_MAX")
    except (OSError, ValueError, AttributeError):  # not POSIX, or no such query here
        return 255
    return min(limit, 255) if isinstance(limit, int) and limit > 0 else 255


def staging_name(name: str, what: str, folder: Path) -> str:
    """A fresh hidden name for a ``what`` (``"partial"``, ``"probe"``) entry of ``name`` made
    in ``folder``: ``.NAME-WHAT-<12 hex>``.

    Parameters
    ----------
    name : str
        The name the user gave (a folder's or a file's); empty gives ``out``.
    what : str
        What the entry is for; it stays whole in the name, so ``.*-partial-*`` still finds
        every staging entry.
    folder : Path
        Where the entry is made; its file system's limit on a name bounds the result.

    Returns
    -------
    str
        The name, with ``NAME`` cut short (whole characters, from the end) so that the whole
        fits the limit: a 250-letter ``--plot`` name, which the file system takes, was refused
        because its staging name ``.NAME-partial-<hex>`` did not fit. The random suffix is
        always kept whole, so a cut name is still unique to this run.
    """
    suffix = f"-{what}-{uuid.uuid4().hex[:12]}"
    return f".{_staging_stem(name, suffix, folder)}{suffix}"


def _staging_stem(name: str, suffix: str, folder: Path) -> str:
    """The part of ``name`` that :func:`staging_name` keeps before ``suffix``: the suffix is
    ASCII of a fixed length, so a name's staging entries all share this stem."""
    limit = _name_max(folder)
    stem = name or "out"
    while stem and len(os.fsencode(f".{stem}{suffix}")) > limit:
        stem = stem[:-1]
    return stem


_STAGING_ENTRY = re.compile(r"\.(?P<stem>.*)-partial-(?P<token>[0-9a-f]{12})", re.DOTALL)


def _hold_staging(stage: Path) -> int | None:
    """Lock ``stage``'s :data:`STAGING_LOCK` for this run and record the run in it; the file
    descriptor (None where ``fcntl`` or ``flock`` is missing: no record is written then, and
    a later run only warns about a folder left behind). The kernel releases the lock when the
    process ends, however it ends; the record is written only once the lock is held, so a
    later run that finds it and takes the lock knows the run has ended."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not POSIX
        return None
    fd = os.open(stage / STAGING_LOCK, os.O_RDWR | os.O_CREAT | os.O_EXCL
                 | getattr(os, "O_NOFOLLOW", 0), 0o600)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)  # a fresh file: only this run has it
    except OSError:  # a file system without locks: the folder stays unrecorded
        os.close(fd)
        return None
    try:
        folder = os.stat(stage)
        record = {"lusm": "staging", "token": stage.name[-12:], "dev": folder.st_dev,
                  "ino": folder.st_ino, "pid": os.getpid(), "host": socket.gethostname(),
                  "boot": _boot_id()}
        os.write(fd, json.dumps(record).encode())
    except BaseException:
        os.close(fd)
        raise
    return fd


def _boot_id() -> str | None:
    """This boot of the machine (Linux's random boot id; None elsewhere): a process id and a
    lock mean something only to the kernel of the boot that recorded them."""
    try:
        with open("/proc/sys/kernel/random/boot_id") as f:
            return f.read().strip() or None
    except OSError:
        return None


def _gone(pid: int) -> bool:
    """Whether no process ``pid`` runs (one of another user's counts as running: it cannot
    be told apart from a live lusm)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    except OSError:  # EPERM: it exists
        return False
    return False


def _remove_if_dead(entry: Path) -> bool:
    """Remove the staging folder ``entry`` if it is certainly lusm's and its run is over:
    a folder of this user's (not a link), holding a :data:`STAGING_LOCK` whose lock this
    call takes (no process holds it) and whose record shows the run dead
    (:func:`_proves_dead`). Anything less leaves it untouched (False)."""
    try:
        st = os.lstat(entry)
    except OSError:
        return False
    if not os.path.isdir(entry) or os.path.islink(entry) or st.st_uid != os.geteuid():
        return False
    fd = _try_lock(entry, exclusive=True)
    if not isinstance(fd, int):  # no lock file (not lusm's, or an older lusm's), or held
        return False
    try:
        dead = _proves_dead(_record(fd), entry, st)
    except BaseException:
        os.close(fd)
        raise
    if not dead:
        os.close(fd)
        return False
    _remove_staging_folder(entry, fd)
    return not os.path.lexists(entry)


def _record(fd: int) -> object:
    """What the lock file open on ``fd`` records (None when it is not whole JSON: a run
    killed before its record was written whole)."""
    try:
        return json.loads(os.read(fd, 4096).decode())
    except (OSError, ValueError):
        return None


def _proves_dead(record: object, entry: Path, st: os.stat_result) -> bool:
    """Whether ``record``, read from the free lock of the staging folder ``entry`` (whose
    ``lstat`` is ``st``), shows a run of lusm's that has ended.

    It must name this very folder: its random suffix, device and inode (a copy, ``cp -a``,
    keeps the suffix and the record; it had been removed as the run's own). It must name this
    host and this boot, and its process must be gone here. A record of another boot is not
    taken as proof of death, though before a reboot every run of it ended: the record cannot
    tell an earlier boot of this machine from another machine of the same name sharing the
    folder over NFS, where locks may be local to each host (``local_lock=flock``), so a free
    lock and a process id unknown here prove nothing. Such a folder is named, not removed.
    """
    return (isinstance(record, dict) and record.get("lusm") == "staging"
            and record.get("token") == entry.name[-12:]
            and record.get("dev") == st.st_dev and record.get("ino") == st.st_ino
            and record.get("host") == socket.gethostname()
            and record.get("boot") == _boot_id()
            and isinstance(record.get("pid"), int) and _gone(record["pid"]))


def clear_stale_staging(name: str, folder: Path, option: str, target: Path) -> None:
    """Deal with the staging entries that runs killed outright left for ``name`` in
    ``folder`` (:func:`staging_name`'s ``.NAME-partial-<12 hex>``): remove those that are
    certainly lusm's and dead (:func:`_remove_if_dead`), saying so on stderr, and name the
    rest in one warning line (``option`` and ``target`` name what the user asked for). Only
    folders laid out as lusm makes them are considered (:func:`_laid_out_as_staging`).

    Each killed run had added one more hidden folder beside the target, which no later run
    removed or mentioned.
    """
    stem = _staging_stem(name, "-partial-" + "0" * 12, folder)
    try:
        entries = sorted(e.name for e in os.scandir(folder))
    except OSError:  # an unreadable folder: the staging mkdir there says why, if it fails
        return
    found = [folder / e for e in entries
             if (m := _STAGING_ENTRY.fullmatch(e)) is not None and m["stem"] == stem
             and _laid_out_as_staging(folder / e)]
    removed = [e for e in found if _remove_if_dead(e)]
    if removed:
        what = ("the staging folder of a lusm run killed before it finished (its lock free, "
                "its process gone)" if len(removed) == 1 else "the staging folders of lusm "
                "runs killed before they finished (their locks free, their processes gone)")
        print(f"lusm: removed {what}: {', '.join(map(str, removed))}", file=sys.stderr)
    left = [e for e in found if e not in removed and not _held(e)]  # held: a run at work
    if left:
        from lusm.messages import warn

        what = ("has the name and layout of a lusm staging folder; if an interrupted run left "
                "it, remove it" if len(left) == 1 else "have the names and layout of lusm "
                "staging folders; if interrupted runs left them, remove them")
        warn(f"{option} {target}: {', '.join(map(str, left))} {what} once no lusm run is "
             f"writing {target}")


def _laid_out_as_staging(entry: Path) -> bool:
    """Whether ``entry`` is laid out as :func:`staging` makes a staging folder: a folder
    (not a link) holding :data:`STAGING_LOCK` or the folder the output is built in. Only
    such an entry is named to the user: any entry of the name had been, even a file of the
    user's, as an earlier run's staging folder to remove."""
    if entry.is_symlink() or not entry.is_dir():
        return False
    built = entry / _STAGED
    return os.path.lexists(entry / STAGING_LOCK) or (built.is_dir() and not built.is_symlink())


def _held(entry: Path) -> bool:
    """Whether a running process holds ``entry``'s :data:`STAGING_LOCK` (a staging folder of
    a run in progress: not stale, not worth a word)."""
    return lock_held(entry / STAGING_LOCK)


_HELD = "held"
"""What :func:`_try_lock` returns for a lock that another process holds."""


def lock_held(lock: Path) -> bool:
    """Whether a running process holds an exclusive ``flock`` on the file ``lock``, tested
    without creating the file and without blocking (a missing file is held by no one).

    Parameters
    ----------
    lock : Path
        The lock file of a run (a staging folder's :data:`STAGING_LOCK`, an explore parts
        folder's ``.lock``).

    Returns
    -------
    bool
    """
    fd = _try_lock_file(lock, exclusive=False)
    if fd is None and os.path.isfile(lock) and not os.access(lock, os.W_OK):
        # another user's lock in a shared folder (explore's .lock is 0644): a shared lock
        # on a read-only open still tells (NFS too), where the read-write open had said
        # "not held" and the run was told it could remove a live study's folder (review)
        fd = _try_lock_file(lock, exclusive=False, flags=os.O_RDONLY)
    if isinstance(fd, int):
        os.close(fd)  # also releases the shared lock this call took
    return fd is _HELD


def _try_lock(entry: Path, exclusive: bool) -> int | str | None:
    """:func:`_try_lock_file` on the staging folder ``entry``'s :data:`STAGING_LOCK`."""
    return _try_lock_file(entry / STAGING_LOCK, exclusive)


def _try_lock_file(lock: Path, exclusive: bool, flags: int = os.O_RDWR) -> int | str | None:
    """Open the lock file ``lock`` (never through a link; ``flags`` the access, read-write by
    default) and take its ``flock`` without waiting, exclusive or shared.

    Returns
    -------
    int, str or None
        The file descriptor, holding the lock (the caller closes it); :data:`_HELD` when
        another process holds the lock; None when there is no lock to take (no such file,
        one that cannot be opened, no ``fcntl``, or a file system that refuses the lock).
    """
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not POSIX
        return None
    try:
        # open for writing too: NFS emulates flock with byte-range locks, and an exclusive
        # one on a file open only for reading fails (EBADF), which had read as "held"; a
        # FIFO of that name must not block the open
        fd = os.open(lock, flags | os.O_NONBLOCK | getattr(os, "O_NOFOLLOW", 0))
    except OSError:  # no lock file: a folder of an older lusm, or not lusm's at all
        return None
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):  # lusm's lock is a plain file
            os.close(fd)
            return None
        fcntl.flock(fd, (fcntl.LOCK_EX if exclusive else fcntl.LOCK_SH) | fcntl.LOCK_NB)
    except BlockingIOError:  # a run still writing
        os.close(fd)
        return _HELD
    except OSError:
        os.close(fd)
        return None
    return fd


@contextmanager
def staging(name: str, folder: Path, refuse: Callable[[OSError], Exception],
            option: str, target: Path) -> Iterator[Path]:
    """Yield a fresh empty folder to build an output named ``name`` in, inside a staging
    folder ``.NAME-partial-<12 hex>`` made in ``folder``; the staging folder is removed on
    leaving, whatever happened.

    Parameters
    ----------
    name : str
        The output's name (a folder's or a file's).
    folder : Path
        Where to stage: on the target's disk, so that moving the output in is a rename.
    refuse : callable
        Turns the ``OSError`` of making the staging folder into the exception to raise
        (naming the user's option and target, not the random name); nothing was made then.
    option, target : str, Path
        The option and target named in the warning about stale staging folders
        (:func:`clear_stale_staging`, run first).

    Notes
    -----
    The staging folder holds :data:`STAGING_LOCK`, locked for its whole life, so that a run
    killed outright (no ``finally`` runs) leaves a folder the next run can tell is dead.
    """
    folder = Path(folder)
    clear_stale_staging(name, folder, option, target)
    # The name is chosen before the folder exists, so a signal landing anywhere (even inside
    # the mkdir) still finds it in ``finally``.
    stage = folder / staging_name(name, "partial", folder)
    made = True  # until the mkdir says otherwise: a signal just after it still finds the folder
    fd = None
    try:
        try:
            os.mkdir(stage, 0o700)
        except OSError as exc:
            made = False  # an entry already there by that name is not ours to remove
            raise refuse(exc) from None
        fd = _hold_staging(stage)
        built = stage / _STAGED
        built.mkdir()  # the umask's mode: a new target is this folder, renamed
        yield built
    finally:
        if made:
            _remove_staging_folder(stage, fd)


def _remove_staging_folder(stage: Path, fd: int | None) -> None:
    """Remove the staging folder ``stage``, whose lock this process holds on ``fd`` (None:
    no lock), and close ``fd``.

    What it holds besides the lock file is removed first, with the lock still held, so that
    no other run takes the folder for dead meanwhile; the lock file goes only once ``fd`` is
    closed. NFS keeps a file unlinked while it is open as a hidden ``.nfsXXXX`` in its
    folder: removing the lock file before closing it left that folder non-empty, and every
    later run named it.
    """
    try:
        try:
            with os.scandir(stage) as entries:
                inside = [e.name for e in entries if e.name != STAGING_LOCK]
        except OSError:
            inside = []
        for name in inside:
            path = stage / name
            if path.is_dir() and not path.is_symlink():
                shutil.rmtree(path, ignore_errors=True)
            else:
                with contextlib.suppress(OSError):
                    os.unlink(path)
    finally:
        if fd is not None:
            os.close(fd)
    shutil.rmtree(stage, ignore_errors=True)
