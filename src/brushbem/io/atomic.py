"""Writing files safely: the case folder's file names, atomic replacement, temporaries, folder locks, free space.

`atomic_path` gives a temporary beside a target and moves it into place with
`os.replace`; `temporary_of` and `remove_stale_temporaries` recognise and
remove what a killed writer left; `exclusive_folder` holds an ``flock`` on a
folder (`FolderBusyError`, `UnsafeLockError`); `check_writable` and
`_check_free_space` refuse a folder that cannot take a file.
"""

from __future__ import annotations

import contextlib
import errno
import os
import re
import shutil
import stat
import tempfile
from collections.abc import Iterator
from pathlib import Path

SUMMARY_FILE = "summary.json"
DATASET_FILE = "result.nc"
CURVE_FILE = "curve.csv"

#: Free space kept beyond a file's own size when writing it (bytes).
_FREE_SPACE_MARGIN = 2**20


#: A temporary of `atomic_path` (``.<final name>.<random>.tmp``; `tempfile.mkstemp`'s random part is
#: lower-case letters, digits and underscores) or of `check_writable` (``.write-check.<random>.tmp``).
_TEMPORARY = re.compile(r"\.(?P<final>.+)\.[a-z0-9_]+\.tmp")
_WRITE_CHECK = "write-check"


def temporary_of(name: str) -> str | None:
    """The final name whose temporary ``name`` is (``".summary.json.x1y2.tmp"`` -> ``"summary.json"``), or None."""
    match = _TEMPORARY.fullmatch(name)
    return match["final"] if match else None


def remove_stale_temporaries(folder: str | Path,
                             names: tuple[str, ...] = (SUMMARY_FILE, DATASET_FILE, CURVE_FILE)) -> list[Path]:
    """Delete the temporary files that a killed writer left in ``folder`` (never a complete file).

    Only the names `atomic_path` creates for the files ``names``
    (``.<name>.<random>.tmp``) and those of `check_writable` are removed:
    nothing else in the folder, hidden ``*.tmp`` files of other programs
    included, is touched, nor a link of such a name.

    Returns
    -------
    list of Path
        The files removed.
    """
    removed = []
    finals = {*names, _WRITE_CHECK}
    for stale in Path(folder).glob(".*.tmp"):
        if temporary_of(stale.name) in finals and stale.is_file() and not stale.is_symlink():
            stale.unlink(missing_ok=True)
            removed.append(stale)
    return removed


class FolderBusyError(RuntimeError):
    """Another process holds a folder's lock (`exclusive_folder`)."""


class UnsafeLockError(OSError):
    """A lock file that brushbem will not write: a link, not a regular file, or not a lock it wrote.

    ``filename`` is the lock file, ``strerror`` what is wrong with it.
    """

    def __str__(self) -> str:
        return f"{self.filename}: {self.strerror}"


def _open_lock(path: Path) -> int:
    """Open the lock file ``path`` for reading and writing, creating it; never through a link.

    Raises `UnsafeLockError` (naming ``path``) when it is a symbolic link, not a
    regular file, or a file with other names (a hard link): writing it would
    change a file that the package did not create.
    """
    refusal = "the lock file is {}; brushbem never writes through it (remove it, or choose another folder)"
    try:
        before = os.lstat(path)
    except FileNotFoundError:
        before = None
    if before is not None and stat.S_ISLNK(before.st_mode):
        raise UnsafeLockError(errno.ELOOP, refusal.format("a symbolic link"), str(path))
    if before is not None and not stat.S_ISREG(before.st_mode):
        raise UnsafeLockError(errno.EINVAL, refusal.format("not a regular file"), str(path))
    flags = os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0)
    try:
        handle = os.open(path, flags, 0o644)
    except OSError as exc:  # replaced by a link or a folder since the check
        if exc.errno in (errno.ELOOP, errno.EISDIR, errno.ENXIO):
            raise UnsafeLockError(exc.errno, refusal.format("a symbolic link or not a regular file"),
                                  str(path)) from None
        raise
    opened = os.fstat(handle)
    if not stat.S_ISREG(opened.st_mode) or opened.st_nlink != 1:
        os.close(handle)
        what = "not a regular file" if not stat.S_ISREG(opened.st_mode) else "a hard link (a file with other names)"
        raise UnsafeLockError(errno.EINVAL, refusal.format(what), str(path))
    return handle


@contextlib.contextmanager
def _locked(path: Path, folder: str | Path) -> Iterator[None]:
    """Hold an ``flock`` on the lock file ``path`` (its holder's pid written in it)."""
    import fcntl

    handle = _open_lock(path)
    try:
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.pread(handle, 64, 0).decode("ascii", "replace").strip() or "unknown"
            raise FolderBusyError(f"{folder}: another brushbem process (pid {holder}) is writing into "
                                  "this folder") from None
        content = os.pread(handle, 64, 0).strip()
        if content and not content.isdigit():
            # Not a process id: a file of that name that brushbem did not write.
            raise UnsafeLockError(errno.EEXIST, "the lock file holds something other than a process id; "
                                  "brushbem does not overwrite it (remove it, or choose another folder)", str(path))
        os.ftruncate(handle, 0)
        os.pwrite(handle, str(os.getpid()).encode(), 0)
        yield
    finally:
        os.close(handle)


@contextlib.contextmanager
def exclusive_folder(folder: str | Path, lock_name: str = ".brushbem.lock") -> Iterator[None]:
    """Hold an exclusive lock on ``folder`` while writing into it.

    The lock is an ``flock`` on ``folder/lock_name`` (POSIX; elsewhere no
    lock is taken): the kernel releases it when the holder ends, killed or
    not, so a stale lock never blocks a rerun.  The lock file is opened
    without following links (``O_NOFOLLOW``) and written (the holder's pid)
    only if it is a regular file of one name that is empty or holds a pid:
    a lock file that is a link, or any other file, is refused and left as it
    is.

    Raises
    ------
    FolderBusyError
        When another process holds the lock (its pid in the message).
    UnsafeLockError
        When the lock file is a symbolic or hard link, not a regular file, or
        holds something other than a pid (its path in the message).
    """
    try:
        import fcntl  # noqa: F401 - only whether it exists
    except ImportError:  # not on POSIX: no lock
        yield
        return
    with _locked(Path(folder) / lock_name, folder):
        yield


def check_writable(folder: str | Path) -> None:
    """Raise ``OSError`` unless a file can be created (and removed) in ``folder``."""
    handle, name = tempfile.mkstemp(dir=folder, prefix=".write-check.", suffix=".tmp")
    os.close(handle)
    os.unlink(name)


def _check_free_space(folder: Path, needed: int) -> None:
    """Raise ``OSError(ENOSPC)`` when ``folder``'s file system has less than ``needed`` bytes free."""
    free = shutil.disk_usage(folder).free
    if free < needed + _FREE_SPACE_MARGIN:
        raise OSError(errno.ENOSPC, f"no space left on device: writing needs {needed / 2**20:.2f} MiB and "
                      f"{_FREE_SPACE_MARGIN / 2**20:g} MiB to spare, {free / 2**20:.2f} MiB free", str(folder))


@contextlib.contextmanager
def atomic_path(target: str | Path) -> Iterator[Path]:
    """Give a temporary path beside ``target``; move it onto ``target`` on success.

    The temporary file lives in the same folder so that `os.replace` is an
    atomic rename on the same file system.  On an exception it is removed and
    ``target`` is left as it was.

    Parameters
    ----------
    target : path
        The file finally written.

    Yields
    ------
    Path
        Where the caller writes the complete content.
    """
    target = Path(target)
    handle, name = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".tmp")
    os.close(handle)
    temporary = Path(name)
    try:
        yield temporary
        # mkstemp creates the file private (0600); results are ordinary files.
        os.chmod(temporary, 0o644)
        os.replace(temporary, target)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise
