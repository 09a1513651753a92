"""Bounded reading of the small text files a user names: stator files, parameter sets, studies.

Each is a few kB of TOML or JSON, yet the path can name anything: ``/dev/zero`` read whole
exhausts memory, a FIFO waits for ever, a 512 MB sparse file takes 1.1 GB. Here the path must be
a regular file, it is opened without blocking (a FIFO swapped in after the check opens at
once) and checked again on its descriptor, and at most one byte more than the cap is read, so
no path can make the read unbounded. The callers word the refusals in their own terms (the
option or the file kind the user knows).
"""

from __future__ import annotations

import os
import stat
from pathlib import Path


class NotRegularFile(ValueError):
    """The path is not a regular file; ``what`` says what it is ("a folder", "a FIFO (named
    pipe)", ...)."""

    def __init__(self, path: Path, what: str) -> None:
        super().__init__(f"{path}: is {what}, not a regular file")
        self.path, self.what = path, what


class FileTooLarge(ValueError):
    """The file has more than the cap's bytes; ``size`` is at least that (bytes)."""

    def __init__(self, path: Path, size: int, max_bytes: int) -> None:
        super().__init__(f"{path}: {size} bytes, above {max_bytes}")
        self.path, self.size, self.max_bytes = path, size, max_bytes


def kind_of(mode: int) -> str | None:
    """None for a regular file, else what the mode says the path is."""
    if stat.S_ISREG(mode):
        return None
    return next((name for test, name in (
        (stat.S_ISDIR, "a folder"), (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
        (stat.S_ISSOCK, "a socket")) if test(mode)), "not a regular file")


def read_small_text(path: str | Path, max_bytes: int) -> str:
    """The UTF-8 text (a byte-order mark dropped) of the regular file ``path`` of at most
    ``max_bytes`` bytes.

    Raises
    ------
    NotRegularFile
        If the path is a folder, a device, a FIFO, a socket.
    FileTooLarge
        If the file has more than ``max_bytes`` bytes (checked on what is read, not only on
        the size the file system reports).
    UnicodeDecodeError
        If the bytes are not UTF-8.
    OSError
        If the file does not exist or cannot be opened (``FileNotFoundError`` for the first).
    """
    path = Path(path)
    what = kind_of(os.stat(path).st_mode)  # before opening: opening a FIFO would block
    if what is not None:
        raise NotRegularFile(path, what)
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    with os.fdopen(fd, "rb") as fh:
        st = os.fstat(fh.fileno())
        what = kind_of(st.st_mode)  # the path may have been replaced since the stat
        if what is not None:
            raise NotRegularFile(path, what)
        if st.st_size > max_bytes:
            raise FileTooLarge(path, st.st_size, max_bytes)
        data = fh.read(max_bytes + 1)
    if len(data) > max_bytes:
        raise FileTooLarge(path, max(st.st_size, len(data)), max_bytes)
    return data.decode("utf-8-sig")


def link_loop(path) -> str | None:
    """The system's words when ``path`` does not resolve because of a loop of symbolic
    links (``Path.exists`` says False for it, which read as "not found"), else None."""
    import errno

    try:
        os.stat(path)
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            return exc.strerror or "Too many levels of symbolic links"
    return None
