"""Writing :mod:`paintapp.compile_ahead`'s list: the compilations of a cold ``paintapp demo``, in
their order.

Run after a change to the kernels or to the order a painting run calls them in, on an empty
kernel cache: ``NUMBA_CACHE_DIR=$(mktemp -d) python -m paintapp.compile_order`` (writes
``assets/kernels/painting.pkl``; a path argument writes it elsewhere).
"""

from __future__ import annotations

import pickle
import sys
import tempfile
from pathlib import Path

from paintapp import compile_ahead
from paintapp.compile_ahead import Entry
from paintapp.first_run import kernels_cold

#: Where the list is kept in the source tree.
SOURCE_MANIFEST = Path(__file__).resolve().parent.parent / "assets" / "kernels" / "painting.pkl"


def record(out: Path) -> int:
    """Run ``paintapp demo`` on the (empty) kernel cache, noting each compilation as it starts,
    and write the list to ``out``; returns the number of entries."""
    from numba.core import event as numba_event

    from paintapp.cli import main as paintapp_main

    entries: list[Entry] = []

    class Listener(numba_event.Listener):
        def on_start(self, event: numba_event.Event) -> None:
            dispatcher = event.data["dispatcher"]
            func = getattr(dispatcher, "py_func", None)
            module = getattr(func, "__module__", "") or ""
            if module.split(".")[0] not in ("solver", "brushes", "paintapp", "common"):
                return
            args = tuple(event.data["args"])
            try:
                pickle.dumps(args)
            except Exception:
                return
            entry = (module, str(getattr(func, "__qualname__", "")), args)
            if entry not in entries:
                entries.append(entry)

        def on_end(self, event: numba_event.Event) -> None:
            pass

    listener = Listener()
    enabled = compile_ahead.ENABLED
    numba_event.register("numba:compile", listener)
    compile_ahead.ENABLED = False
    try:
        with tempfile.TemporaryDirectory() as folder:
            paintapp_main(["demo", "--out", str(Path(folder) / "demo")])
    finally:
        compile_ahead.ENABLED = enabled
        numba_event.unregister("numba:compile", listener)
    import numba

    out.parent.mkdir(parents=True, exist_ok=True)
    with out.open("wb") as handle:
        pickle.dump({"numba": numba.__version__, "entries": entries}, handle, protocol=4)
    return len(entries)


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    if not kernels_cold():
        print("the kernel cache is warm: run with NUMBA_CACHE_DIR=$(mktemp -d)", file=sys.stderr)
        return 2
    out = Path(args[0]) if args else SOURCE_MANIFEST
    print(f"wrote {out}: {record(out)} compilations")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
