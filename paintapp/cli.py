"""The ``paintapp`` command line.

Each sub-command lives in its own module under :mod:`paintapp.commands` and exposes
``register(subparsers)``, which adds its parser and sets ``func`` (a callable taking the parsed
arguments and returning an exit status). Modules are discovered, so adding a command is adding a
file.

Errors are one line on stderr, never a traceback: bad input (:class:`InputError`) exits with status
2, a write that failed mid-run (an :class:`OSError`: disk full, ...) or running out of memory with 1.
"""

from __future__ import annotations

import argparse
import atexit
import importlib
import os
import pkgutil
import sys
from collections.abc import Sequence
from typing import NoReturn

import paintapp
import paintapp.commands
from common.errors import InputError


def build_parser() -> argparse.ArgumentParser:
    """Build the top-level parser with every discovered sub-command."""
    parser = argparse.ArgumentParser(
        prog="paintapp",
        description="Haptic fluid painting: simulate, paint, replay, measure.",
    )
    parser.add_argument("--version", action="version", version=f"paintapp {paintapp.__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for info in sorted(pkgutil.iter_modules(paintapp.commands.__path__), key=lambda m: m.name):
        if info.name.startswith("_"):
            continue
        module = importlib.import_module(f"paintapp.commands.{info.name}")
        module.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the process exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        return int(args.func(args) or 0)
    except InputError as exc:
        print(f"paintapp {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:  # a write that failed mid-run (disk full, ...): one line
        print(f"paintapp {args.command}: error: {exc}", file=sys.stderr)
        return 1
    except MemoryError:
        print(
            f"paintapp {args.command}: error: out of memory; try a smaller grid or canvas",
            file=sys.stderr,
        )
        return 1
    except KeyboardInterrupt:
        print(f"paintapp {args.command}: interrupted", file=sys.stderr)
        return 130


def console() -> NoReturn:
    """The ``paintapp`` program: :func:`main`, then the exit without the interpreter's teardown.

    Once the command has returned, its files are written and closed; what is left is the
    ``atexit`` handlers (run here) and the interpreter's teardown, a last collection over every
    object the run made and each module's clean-up: 0.3-0.4 s after a demo, for memory the
    process gives back as it ends. So the output streams are flushed and the process ends
    (``os._exit``) with the command's status. For the entry points only: a caller that goes on
    after :func:`main` calls :func:`main`."""
    status = main()
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe or stream: nothing more can reach it
            pass
    os._exit(status)
