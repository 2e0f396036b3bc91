"""Whether running some code loads a module: checked in a fresh interpreter."""

from __future__ import annotations

import subprocess
import sys


def loads_module(code: str, module: str) -> bool:
    """Whether ``module`` is in ``sys.modules`` after a fresh interpreter runs ``code``."""
    probe = f"{code}\nimport sys\nprint({module!r} in sys.modules)"
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    return done.stdout.strip().splitlines()[-1] == "True"
