"""The name rules for identifiers that files carry, one rule per kind of name.

- Pigments: lower-case identifiers, at most 48 characters (``[a-z][a-z0-9_]*``). They become EXR
  channel names (``pigment.<name>``) and file names of the pigment library, so a stroke file, a
  canvas file and the library all accept exactly the same names.
- Presets (brushes and other named files): letters, digits, ``_ . -``, at most 64 characters,
  no path separators and no ``..``, since they name files in an assets folder.
"""

from __future__ import annotations

import re
from typing import Any, TypeGuard

PIGMENT_NAME = re.compile(r"^[a-z][a-z0-9_]{0,47}$")
PRESET_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$")


def is_pigment_name(value: Any) -> TypeGuard[str]:
    """True when ``value`` is a valid pigment name."""
    return isinstance(value, str) and PIGMENT_NAME.match(value) is not None


def check_pigment_name(value: Any) -> str:
    """``value`` when it is a valid pigment name, else ValueError saying the rule."""
    if not is_pigment_name(value):
        raise ValueError(
            "expected a pigment name: a lower-case letter, then lower-case letters, digits or "
            f"'_' (at most 48 characters), got {value!r}"
        )
    return value


def is_preset_name(value: Any) -> bool:
    """True when ``value`` is a valid preset name."""
    return isinstance(value, str) and PRESET_NAME.match(value) is not None and ".." not in value


def check_preset_name(value: Any, what: str) -> str:
    """``value`` when it is a valid name of a ``what`` (e.g. "brush preset"), else ValueError."""
    if not is_preset_name(value):
        raise ValueError(
            f"expected a {what} name of letters, digits, '_', '.', '-' "
            f"(at most 64 characters, no path separators), got {value!r}"
        )
    return value
