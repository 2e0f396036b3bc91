"""Atomic writes of user files: write a temporary file beside the target, then rename over it.

A crash (or an exception) at any point leaves either the old file or the new one, never a
half-written file under the target name. Temporary files are named
``.<name>.<pid>.<random>.tmp<suffix>`` (the suffix is kept so format-sniffing writers such as
OpenImageIO pick the right format). A process killed mid-write (``kill -9``) leaves its temporary
file behind; the next write to the same target removes the ones whose process is gone (or, for
names without a process id, that are older than :data:`STALE_AGE_S`).

Any :class:`OSError` while writing (disk full, permission, a folder in the way) is raised as a
:class:`WriteError` naming the target, which the command line prints in one line.
"""

from __future__ import annotations

import contextlib
import os
import re
import tempfile
import time
from collections.abc import Callable, Iterator
from pathlib import Path

_UMASK = os.umask(0o022)
os.umask(_UMASK)

#: A temporary file without a process id in its name is stale once this old (s).
STALE_AGE_S = 600.0
#: A temporary file of a live process is still stale once this old (s): its id was reused.
STALE_LIVE_AGE_S = 86400.0
_TEMP_MIDDLE = re.compile(r"(?:(\d+)\.)?[a-z0-9_]{8}")


class WriteError(OSError):
    """A file could not be written; the message names the target and the reason."""


def temp_prefix(target: Path) -> str:
    """The name prefix of this process's temporary files for ``target``."""
    return f".{target.name}.{os.getpid()}."


def _process_alive(pid: int) -> bool:
    if os.name != "posix":
        return True  # no cheap check: rely on the age alone
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # it exists but belongs to someone else
        return True
    return True


def remove_stale_temps(target: str | Path) -> list[Path]:
    """Remove the temporary files of ``target`` left by writers that died; returns them."""
    target = Path(target)
    directory = target.parent if str(target.parent) else Path(".")
    prefix, suffix = f".{target.name}.", f".tmp{target.suffix}"
    removed: list[Path] = []
    try:
        entries = list(os.scandir(directory))
    except OSError:
        return removed
    now = time.time()
    for entry in entries:
        name = entry.name
        if not (name.startswith(prefix) and name.endswith(suffix)):
            continue
        match = _TEMP_MIDDLE.fullmatch(name[len(prefix) : len(name) - len(suffix)])
        if match is None:
            continue
        try:
            age = now - entry.stat(follow_symlinks=False).st_mtime
        except OSError:
            continue
        pid = match.group(1)
        if pid is None:
            stale = age > STALE_AGE_S
        else:
            stale = int(pid) != os.getpid() and (
                not _process_alive(int(pid)) or age > STALE_LIVE_AGE_S
            )
        if stale:
            with contextlib.suppress(OSError):
                os.unlink(entry.path)
                removed.append(Path(entry.path))
    return removed


def _fsync_path(path: Path, directory: bool = False) -> None:
    flags = os.O_RDONLY | (getattr(os, "O_DIRECTORY", 0) if directory else 0)
    try:
        fd = os.open(path, flags)
    except OSError:
        if directory:  # some platforms cannot open directories; durability is best effort there
            return
        raise
    try:
        os.fsync(fd)
    except OSError:
        if not directory:
            raise
    finally:
        os.close(fd)


@contextlib.contextmanager
def atomic_path(target: str | Path) -> Iterator[Path]:
    """Yield a temporary path to write; on success it is flushed to disk and renamed to ``target``.

    On an exception the temporary file is removed and ``target`` is untouched.
    """
    target = Path(target)
    directory = target.parent if str(target.parent) else Path(".")
    try:
        if target.is_dir():
            raise IsADirectoryError(21, "is a folder, expected a file name")
        directory.mkdir(parents=True, exist_ok=True)
        remove_stale_temps(target)
        fd, name = tempfile.mkstemp(
            prefix=temp_prefix(target), suffix=f".tmp{target.suffix}", dir=directory
        )
        os.close(fd)
        tmp = Path(name)
        # mkstemp makes the file private (0600); give the result a plain open()'s permissions.
        mode = target.stat().st_mode & 0o777 if target.exists() else 0o666 & ~_UMASK
        os.chmod(tmp, mode)
    except OSError as exc:
        raise _write_error(target, exc) from exc
    try:
        yield tmp
        _fsync_path(tmp)
        os.replace(tmp, target)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            tmp.unlink()
        if isinstance(exc, OSError) and not isinstance(exc, WriteError):
            raise _write_error(target, exc, tmp) from exc
        raise
    _fsync_path(directory, directory=True)


def _write_error(target: Path, exc: OSError, tmp: Path | None = None) -> WriteError:
    """One line naming ``target`` (not the temporary file) and why the write failed."""
    reason = exc.strerror or str(exc)
    if tmp is not None:
        reason = reason.replace(str(tmp), str(target))
    reason = re.sub(r"^cannot (?:write|open) \S+(?: for writing)?: ", "", reason)
    error = WriteError(f"cannot write {target}: {reason}")
    error.errno = exc.errno
    return error


def atomic_write_text(path: str | Path, text: str) -> None:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8") as fh:
        fh.write(text)


def atomic_write_with(path: str | Path, writer: Callable[[Path], None]) -> None:
    """Let ``writer`` write a temporary file, then move it onto ``path`` atomically."""
    with atomic_path(path) as tmp:
        writer(tmp)
