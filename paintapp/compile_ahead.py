"""The first run's kernels compiled from both ends at once: a second process takes the far end.

numba compiles one kernel at a time in a process (its compiler lock), and a painting run needs
about 180 compilations (most of a minute on a cold cache, :mod:`paintapp.first_run`). numba's
disk cache is shared between processes, and a dispatcher looks for cached code every time it
meets a new signature, so a second process that compiles the same kernels *in the reverse
order* of the run's needs meets the run halfway: each kernel is compiled once, by whichever
process reaches it first, and the other loads it from the cache.

The run's needs, in their order, are a bundled list (:data:`MANIFEST`): every compilation a cold
``paintapp demo`` makes, as (module, qualified name, argument types), numba's own types pickled.
:func:`compiling_ahead` starts the second process on a cold cache (``python -m
paintapp.compile_ahead``, which compiles the list from its end) and stops it when the run is done;
on a warm cache, or without a readable list, it does nothing. A stale entry (a kernel renamed, its arguments changed) costs the second process one
useless compilation or is skipped; the run itself is never changed by it.

``NUMBA_CACHE_DIR=$(mktemp -d) python -m paintapp.compile_order`` writes the list again (after a
change to the kernels or their call order, :mod:`paintapp.compile_order`).
"""

from __future__ import annotations

import contextlib
import importlib
import os
import pickle
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from paintapp.resources import asset_path

#: The bundled list of a painting run's compilations.
MANIFEST = asset_path("kernels", "painting.pkl")
#: Seconds given to the second process to stop when asked, before it is killed.
STOP_WAIT_S = 2.0
#: Off with ``PAINTAPP_COMPILE_AHEAD=0`` in the environment, and while the list is recorded (it
#: must hold every compilation of the run itself).
ENABLED = os.environ.get("PAINTAPP_COMPILE_AHEAD", "1") != "0"

Entry = tuple[str, str, tuple[Any, ...]]


def load_manifest(path: Path = MANIFEST) -> list[Entry]:
    """The list at ``path`` (empty if missing or unreadable, e.g. pickled by a numba whose types
    have moved)."""
    try:
        with path.open("rb") as handle:
            data = pickle.load(handle)
    except Exception:  # missing, truncated, or numba's types moved: nothing to compile ahead
        return []
    if not isinstance(data, dict) or not isinstance(data.get("entries"), list):
        return []
    # Kept under another numba too: its types, where they still unpickle, name the same
    # signatures; one that no longer compiles is skipped (:func:`compile_from_the_end`).
    return [e for e in data["entries"] if isinstance(e, tuple) and len(e) == 3]


def resolve(module: str, qualname: str) -> Any:
    """The dispatcher ``module.qualname`` (None if gone)."""
    try:
        target: Any = importlib.import_module(module)
        for part in qualname.split("."):
            target = getattr(target, part)
    except (ImportError, AttributeError):
        return None
    return target if hasattr(target, "compile") and hasattr(target, "py_func") else None


def compile_from_the_end(entries: list[Entry]) -> int:
    """Compile ``entries`` last first (loading those already cached); returns how many were
    compiled or loaded. An entry that does not compile any more is skipped."""
    done = 0
    for module, qualname, args in reversed(entries):
        dispatcher = resolve(module, qualname)
        if dispatcher is None:
            continue
        try:
            dispatcher.compile(tuple(args))
        except Exception:  # a stale signature: the run compiles what it needs itself
            continue
        done += 1
    return done


@contextlib.contextmanager
def compiling_ahead(path: Path = MANIFEST) -> Iterator[bool]:
    """While entered, on a cold kernel cache (:func:`paintapp.first_run.kernels_cold`), a second
    process compiles the list at ``path`` from its end; yields whether one was started."""
    from paintapp.first_run import kernels_cold

    child: subprocess.Popen[bytes] | None = None
    if ENABLED and kernels_cold() and load_manifest(path):
        try:
            child = subprocess.Popen(
                [sys.executable, "-m", "paintapp.compile_ahead", str(path)],
                stdin=subprocess.DEVNULL,
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
            )
        except OSError:
            child = None
    try:
        yield child is not None
    finally:
        if child is not None:
            _stop(child)


def _stop(child: subprocess.Popen[bytes]) -> None:
    child.terminate()
    try:
        child.wait(STOP_WAIT_S)
    except subprocess.TimeoutExpired:
        child.kill()
        child.wait()


def main(argv: list[str] | None = None) -> int:
    """The second process: compile the list (the path given, or the bundled one) from its end."""
    args = sys.argv[1:] if argv is None else argv
    with contextlib.suppress(OSError, AttributeError):
        os.nice(5)  # the run in front comes first
    compile_from_the_end(load_manifest(Path(args[0]) if args else MANIFEST))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
