"""Size, memory and nesting limits that every file reader checks before it trusts a file.

A file can claim far more than it holds: a compressed ``.npz`` member that inflates to gigabytes,
an array header or a grid extent of 100000 x 100000, a text "file" such as ``/dev/zero`` that
never ends, brackets nested a thousand deep. The readers ask these functions first, so that such
a file is refused with one :class:`~common.errors.InputError` naming the file and the field before
any memory is spent on it.
"""

from __future__ import annotations

import math
import re
import struct
import zipfile
import zlib
from pathlib import Path

import numpy as np

from common.errors import InputError

#: Most bytes the arrays read from one data file may take in memory.
MEMORY_BUDGET_BYTES = 4 * 1024**3
#: Most bytes of a scene, painting-scene or pigment TOML file.
MAX_TOML_BYTES = 4 * 1024**2
#: Deepest nesting of brackets and braces in TOML or JSON text.
MAX_NESTING = 64
#: What ``zipfile`` and ``numpy.load`` raise for a damaged or foreign archive: unsupported
#: compression or flags, encryption, a bad stream, a short file.
ARCHIVE_ERRORS = (
    ValueError,
    OSError,
    EOFError,
    zipfile.BadZipFile,
    NotImplementedError,
    RuntimeError,
    zlib.error,
    struct.error,
)


def brief(exc: BaseException, limit: int = 160) -> str:
    """A library's exception text on one line of at most ``limit`` characters (a message about
    a hostile file may quote the file's bytes)."""
    text = " ".join(str(exc).split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


def read_bytes_capped(path: str | Path, max_bytes: int, what: str) -> bytes:
    """The bytes of ``path``, read no further than ``max_bytes`` + 1.

    Raises :class:`InputError` (naming the file and the cap) for a longer file; an unreadable file
    raises the ``OSError`` of ``open`` so that each reader can word it its own way.
    """
    with open(path, "rb") as fh:
        raw = fh.read(max_bytes + 1)
    if len(raw) > max_bytes:
        raise InputError(f"the {what} is larger than {max_bytes} bytes, the most read", str(path))
    return raw


def read_text_capped(
    path: str | Path, max_bytes: int, what: str, encoding: str = "utf-8-sig"
) -> str:
    """The text of ``path`` (at most ``max_bytes`` bytes; see :func:`read_bytes_capped`).

    ``UnicodeDecodeError`` is passed on for the reader to word.
    """
    return read_bytes_capped(path, max_bytes, what).decode(encoding)


def check_nesting(
    text: str, source: str, *, toml: bool, max_depth: int = MAX_NESTING, key: str | None = None
) -> None:
    """Refuse text whose brackets and braces nest deeper than ``max_depth``.

    A cheap scan before parsing (``tomllib`` and ``json`` recurse once per level and would raise
    ``RecursionError``). Quoted strings are skipped, and for TOML ``'`` strings and ``#`` comments.
    """
    depth = 0
    quote = ""
    skip = 0  # characters before this index are escaped or in a comment
    for found in (_TOML_SPECIAL if toml else _JSON_SPECIAL).finditer(text):
        i = found.start()
        if i < skip:
            continue
        c = text[i]
        if quote:
            if c == "\\" and quote == '"':
                skip = i + 2
            elif c == quote:
                quote = ""
        elif c in "\"'":
            quote = c
        elif c == "#":
            end = text.find("\n", i)
            skip = len(text) if end < 0 else end
        elif c in "[{":
            depth += 1
            if depth > max_depth:
                line = text.count("\n", 0, i) + 1
                raise InputError(
                    f"brackets nested more than {max_depth} levels deep", source, key, line
                )
        elif c in "]}":
            depth -= 1


_TOML_SPECIAL = re.compile(r"[\"'#\[\]{}\\]")
_JSON_SPECIAL = re.compile(r"[\"\[\]{}\\]")


def check_elements(
    count: int, bytes_each: int, source: str, key: str | None, budget: int = MEMORY_BUDGET_BYTES
) -> None:
    """Refuse ``count`` values of ``bytes_each`` bytes that would exceed the memory budget."""
    if count < 0 or count * bytes_each > budget:
        raise InputError(
            f"claims {count} values ({count * bytes_each} bytes); at most {budget} bytes are read",
            source,
            key,
        )


def npz_headers(
    path: str | Path, budget: int = MEMORY_BUDGET_BYTES
) -> dict[str, tuple[tuple[int, ...], np.dtype]]:
    """The shape and dtype of each array in an ``.npz`` file, read from the ``.npy`` headers only.

    Nothing is inflated beyond the headers. Refused with an :class:`InputError` naming the file
    and the member: a file that is not a zip archive, a member that is not a ``.npy`` array, a
    pickled (object) array, a member compressed other than by deflate (zipfile would inflate it
    unbounded), and members whose stated or claimed sizes exceed ``budget`` together.
    Raises ``FileNotFoundError`` for a missing file; a file that cannot be read is refused too.
    """
    source = str(path)
    out: dict[str, tuple[tuple[int, ...], np.dtype]] = {}
    total = 0
    try:
        archive = zipfile.ZipFile(path)
    except FileNotFoundError:
        raise
    except ARCHIVE_ERRORS:
        raise InputError(
            "not a readable .npz file (not a zip archive of .npy arrays)", source
        ) from None
    with archive:
        for info in archive.infolist():
            name = info.filename.removesuffix(".npy")
            if not info.filename.endswith(".npy"):
                raise InputError("not a .npy array in the .npz archive", source, info.filename)
            if info.compress_type not in (zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED):
                # zipfile inflates other methods (bzip2, lzma) without a bound on the output of
                # a read, so even a header read could inflate the whole member
                raise InputError(
                    f"compressed with zip method {info.compress_type}; expected stored or deflate "
                    "members (as numpy's savez and savez_compressed write)",
                    source,
                    name,
                )
            total += info.file_size
            if total > budget:
                raise InputError(
                    f"the arrays inflate to more than {budget} bytes, the most read", source, name
                )
            try:
                with archive.open(info) as fh:
                    version = np.lib.format.read_magic(fh)
                    if version == (1, 0):
                        shape, _, dtype = np.lib.format.read_array_header_1_0(fh)
                    elif version == (2, 0):
                        shape, _, dtype = np.lib.format.read_array_header_2_0(fh)
                    else:
                        raise ValueError(f"unsupported .npy version {version}")
            except ARCHIVE_ERRORS as exc:
                raise InputError(
                    f"not a readable .npy header ({brief(exc)})", source, name
                ) from None
            if dtype.hasobject:
                raise InputError(
                    "not a readable plain array: it holds Python objects (refused)", source, name
                )
            count = math.prod(shape)
            check_elements(count, max(dtype.itemsize, 1), source, name, budget)
            out[name] = (tuple(shape), dtype)
    return out
