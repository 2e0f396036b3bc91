"""Autosave and crash recovery.

While the app runs it writes the canvas to ``autosave.exr`` in the recovery folder at a set
interval (only when the canvas changed since the last autosave), with ``autosave.json`` beside
it: when it was written, the process id, the canvas file being edited and the stroke journal. Both
are written atomically. A clean exit deletes them; so if they are there when the app starts, the
previous run ended without closing, and the app offers to recover the canvas (the journal named
in the note holds every stroke, including those after the last autosave).

The recovery folder is ``$PAINTAPP_RECOVERY_DIR`` if set, else ``$XDG_STATE_HOME/paintapp/recovery``
(``~/.local/state/paintapp/recovery``), or the ``--recovery-dir`` option.
"""

from __future__ import annotations

import json
import os
import threading
import time
from dataclasses import dataclass
from pathlib import Path

from common.errors import InputError
from paintapp.atomic import atomic_write_text
from paintapp.canvas.exr import read_canvas_exr, write_canvas_exr
from paintapp.canvas.model import Canvas
from paintapp.pigments.library import PigmentLibrary

CANVAS_NAME = "autosave.exr"
NOTE_NAME = "autosave.json"


def default_recovery_dir() -> Path:
    """Where autosaves go (see the module docstring)."""
    env = os.environ.get("PAINTAPP_RECOVERY_DIR")
    if env:
        return Path(env)
    state = os.environ.get("XDG_STATE_HOME") or str(Path.home() / ".local" / "state")
    return Path(state) / "paintapp" / "recovery"


@dataclass(frozen=True)
class RecoveryNote:
    """What an autosave left behind: its canvas file and what was being edited."""

    canvas_path: Path
    saved_at: float
    pid: int
    document: str | None
    journal: str | None

    def describe(self) -> str:
        """One paragraph for the recovery question."""
        when = time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(self.saved_at))
        lines = [f"An autosave from {when} was left by a session that did not close."]
        if self.document:
            lines.append(f"It was editing {self.document}.")
        if self.journal:
            lines.append(f"Its strokes are journalled in {self.journal}.")
        return " ".join(lines)


class Recovery:
    """Autosaves for one running app (see the module docstring).

    Args:
        folder: the recovery folder (created when first needed).
        library: pigments for the autosave's colour picture.
    """

    def __init__(self, folder: Path, library: PigmentLibrary | None = None) -> None:
        self.folder = Path(folder)
        self.library = library
        self.saved_version = 0
        self.last_error: str | None = None
        self._thread: threading.Thread | None = None

    @property
    def canvas_path(self) -> Path:
        """The autosave canvas file."""
        return self.folder / CANVAS_NAME

    @property
    def note_path(self) -> Path:
        """The autosave note."""
        return self.folder / NOTE_NAME

    def pending(self) -> RecoveryNote | None:
        """The note of an autosave left by a previous run, or None."""
        try:
            data = json.loads(self.note_path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return None
        if not self.canvas_path.is_file() or not isinstance(data, dict):
            return None
        if data.get("pid") == os.getpid():
            return None
        return RecoveryNote(
            self.canvas_path,
            float(data.get("saved_at", 0.0)),
            int(data.get("pid", 0)),
            data.get("document"),
            data.get("journal"),
        )

    def load(self) -> Canvas:
        """The autosaved canvas (InputError if it cannot be read)."""
        return read_canvas_exr(self.canvas_path)

    def busy(self) -> bool:
        """Whether an autosave is being written now."""
        return self._thread is not None and self._thread.is_alive()

    def save_async(
        self, canvas: Canvas, version: int, document: str | None, journal: str | None
    ) -> bool:
        """Write ``canvas`` (a private copy) in a background thread; False if one is running."""
        if self.busy():
            return False

        def target() -> None:
            self.save(canvas, version, document, journal)

        self._thread = threading.Thread(target=target, name="autosave", daemon=True)
        self._thread.start()
        return True

    def save(self, canvas: Canvas, version: int, document: str | None, journal: str | None) -> None:
        """Write the autosave canvas, then its note (both atomically)."""
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
            write_canvas_exr(self.canvas_path, canvas, library=self.library)
            note = {
                "saved_at": time.time(),
                "pid": os.getpid(),
                "document": document,
                "journal": journal,
            }
            atomic_write_text(self.note_path, json.dumps(note, indent=1, allow_nan=False) + "\n")
            self.saved_version = version
            self.last_error = None
        except (OSError, InputError, ValueError, RuntimeError) as exc:
            self.last_error = f"autosave failed: {exc}"

    def wait(self, timeout_s: float = 10.0) -> None:
        """Wait for a running autosave to finish."""
        if self._thread is not None:
            self._thread.join(timeout_s)

    def discard(self) -> None:
        """Delete the autosave (after a clean exit, or when recovery is declined)."""
        self.wait()
        for path in (self.note_path, self.canvas_path):
            try:
                path.unlink()
            except FileNotFoundError:
                pass
            except OSError as exc:
                self.last_error = f"cannot remove {path}: {exc}"
