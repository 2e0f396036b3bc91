"""Running a command-line tool whose output may go to a pipe that closes early (``| head``)."""

from __future__ import annotations

import os
import sys
from collections.abc import Callable
from typing import NoReturn


def run_tool(main: Callable[[list[str]], int], argv: list[str]) -> NoReturn:
    """Exit with ``main(argv)``; when the reader of standard output has closed the pipe, exit 1
    quietly instead of with a BrokenPipeError traceback."""
    try:
        code = main(argv)
        sys.stdout.flush()
    except BrokenPipeError:  # the reader (e.g. head) closed the pipe: nothing more to say
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        sys.exit(1)
    sys.exit(code)
