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
import importlib
import pkgutil
import sys
from collections.abc import Sequence

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
