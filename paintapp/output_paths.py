"""Checking a command's output paths before it does any work.

Every command that writes files calls :func:`prepare_outputs` on all its output paths after
reading its inputs and before its run, so a bad ``--out`` costs seconds, not a whole run, and
never leaves some outputs written and others not. A path is refused (an :class:`InputError`
naming the flag and the path, exit status 2) when it is an existing folder or not a regular file,
when a file stands where a folder should be, when two outputs name the same file, or when its
folder cannot be created or written (checked by creating and removing a temporary file there). A
missing folder is created and said so on stderr (``created folder X``), so a typo in a path does
not go unnoticed. The module imports nothing heavy.
"""

from __future__ import annotations

import contextlib
import os
import sys
import tempfile
from collections.abc import Iterable
from pathlib import Path
from typing import TextIO

from common.errors import InputError
from paintapp.atomic import temp_prefix

Outputs = Iterable[tuple[str, str | Path | None]]
"""(flag, path) pairs; a None path (an option not given) is skipped."""


def _fail(flag: str, path: Path, message: str) -> InputError:
    return InputError(f"{flag} {path}: {message}")


def _existing_ancestor(folder: Path) -> Path:
    """The nearest folder above (or at) ``folder`` that exists (possibly a file in the way)."""
    current = folder
    while not current.exists() and current != current.parent:
        current = current.parent
    return current


def _check_folder_path(flag: str, path: Path, folder: Path) -> bool:
    """Raise unless ``folder`` is, or can become, a folder; True when it must be created."""
    if folder.is_dir():
        return False
    if folder.exists():
        raise _fail(flag, path, f"{folder} is a file, not a folder")
    above = _existing_ancestor(folder)
    if not above.is_dir():
        raise _fail(flag, path, f"{above} is a file, not a folder")
    return True


def _probe(flag: str, path: Path, folder: Path, target: Path) -> None:
    """Create and remove a temporary file in ``folder`` (as the atomic write will)."""
    try:
        fd, name = tempfile.mkstemp(
            prefix=temp_prefix(target), suffix=f".tmp{target.suffix}", dir=folder
        )
    except OSError as exc:
        raise _fail(flag, path, f"cannot write in folder {folder}: {exc.strerror or exc}") from None
    os.close(fd)
    with contextlib.suppress(OSError):
        os.unlink(name)


def _create(flag: str, path: Path, folder: Path, log: TextIO) -> None:
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise _fail(flag, path, f"cannot create folder {folder}: {exc.strerror or exc}") from None
    print(f"created folder {folder}", file=log)


def prepare_outputs(
    files: Outputs = (), folders: Outputs = (), *, log: TextIO | None = None
) -> list[Path]:
    """Check every output (``files``: files to write; ``folders``: folders to write into), then
    create the missing folders (one line each on ``log``, default stderr) and check that each
    can be written. Raises :class:`InputError` naming the flag and the path; returns the folders
    it created. Nothing is created unless every path passed the first checks."""
    log = log if log is not None else sys.stderr
    targets: list[tuple[str, Path, Path, Path]] = []  # flag, path, folder, probe target
    seen: dict[Path, str] = {}
    for flag, value in folders:
        if value is None:
            continue
        path = Path(value)
        if path.exists() and not path.is_dir():
            raise _fail(flag, path, "is a file; expected a folder for the outputs")
        targets.append((flag, path, path, path / "output"))
    for flag, value in files:
        if value is None:
            continue
        path = Path(value)
        if path.is_dir():
            raise _fail(flag, path, "is an existing folder; expected a file name")
        if path.exists() and not path.is_file():
            raise _fail(flag, path, "exists and is not a regular file")
        key = Path(os.path.abspath(path))
        if key in seen:
            raise _fail(
                flag, path, f"is also the {seen[key]} output; give each output its own file"
            )
        seen[key] = flag
        targets.append((flag, path, path.parent if str(path.parent) else Path("."), path))
    missing = []
    for flag, path, folder, _ in targets:
        if _check_folder_path(flag, path, folder):
            missing.append((flag, path, folder))
    created: list[Path] = []
    for flag, path, folder in missing:
        if not folder.is_dir():
            _create(flag, path, folder, log)
            created.append(folder)
    for flag, path, folder, target in targets:
        _probe(flag, path, folder, target)
    return created
