"""The ``paintapp`` program's exit: the command's status, its atexit handlers, its output."""

from __future__ import annotations

import subprocess
import sys

SCRIPT = """
import atexit, sys
atexit.register(lambda: print("atexit ran"))
print("buffered before the exit", end="")
sys.argv = ["paintapp", *sys.argv[1:]]
from paintapp.cli import console
console()
"""


def run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-c", SCRIPT, *args], capture_output=True, text=True, timeout=120
    )


def test_the_program_exits_with_the_command_s_status_after_its_atexit_handlers(tmp_path):
    done = run("demo", "--out", str(tmp_path / "a-file" / "inside"), "--strokes", "no.jsonl")
    assert done.returncode == 2
    assert "error" in done.stderr and "Traceback" not in done.stderr
    assert done.stdout.startswith("buffered before the exit")  # flushed before the end
    assert done.stdout.rstrip().endswith("atexit ran")


def test_argument_errors_keep_argparse_s_status():
    done = run("no-such-command")
    assert done.returncode == 2 and "invalid choice" in done.stderr
