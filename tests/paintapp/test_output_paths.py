"""Output paths checked before any work, and atomic writes that clean up after killed writers."""

from __future__ import annotations

import io
import os
import subprocess
import sys
import tempfile
import time

import pytest

from common.errors import InputError
from paintapp import atomic
from paintapp.atomic import WriteError, atomic_path, atomic_write_text, remove_stale_temps
from paintapp.output_paths import prepare_outputs


def test_a_missing_folder_is_created_and_said_so(tmp_path):
    log = io.StringIO()
    target = tmp_path / "new" / "sub" / "out.png"
    created = prepare_outputs([("--out", target)], log=log)
    assert created == [target.parent] and target.parent.is_dir()
    assert log.getvalue() == f"created folder {target.parent}\n"
    assert list(target.parent.iterdir()) == []  # the write check leaves nothing behind


def test_an_existing_folder_as_a_file_output_names_the_flag(tmp_path):
    with pytest.raises(InputError, match=r"--forces .*: is an existing folder"):
        prepare_outputs([("--out", tmp_path / "a.exr"), ("--forces", tmp_path)])


def test_a_file_in_the_way_of_a_folder(tmp_path):
    (tmp_path / "f.txt").write_text("x")
    with pytest.raises(InputError, match=r"f.txt is a file, not a folder"):
        prepare_outputs([("--out", tmp_path / "f.txt" / "deeper" / "out.exr")])
    with pytest.raises(InputError, match="is a file; expected a folder"):
        prepare_outputs(folders=[("--out", tmp_path / "f.txt")])


def test_nothing_is_created_unless_every_output_passes(tmp_path):
    with pytest.raises(InputError, match="--forces"):
        prepare_outputs([("--out", tmp_path / "new" / "a.exr"), ("--forces", tmp_path)])
    assert not (tmp_path / "new").exists()


def test_two_outputs_on_the_same_file(tmp_path):
    with pytest.raises(InputError, match="is also the --out output"):
        prepare_outputs([("--out", tmp_path / "a.png"), ("--preview", tmp_path / "a.png")])


def test_an_unwritable_folder_is_refused_before_any_work(tmp_path, monkeypatch):
    def denied(*args, **kwargs):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(tempfile, "mkstemp", denied)  # as root, chmod would not stop a write
    with pytest.raises(InputError, match=r"--json .*cannot write in folder .*Permission denied"):
        prepare_outputs([("--json", tmp_path / "r.json")])


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0, reason="root writes anywhere")
def test_a_read_only_folder_is_refused(tmp_path):
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o500)
    try:
        with pytest.raises(InputError, match="cannot write in folder"):
            prepare_outputs([("--out", folder / "x.png")])
    finally:
        folder.chmod(0o700)


def test_a_not_regular_file_is_refused():
    if not os.path.exists("/dev/null"):
        pytest.skip("no /dev/null")
    with pytest.raises(InputError, match="not a regular file"):
        prepare_outputs([("--out", "/dev/null")])


def test_a_failed_write_is_a_write_error_naming_the_target_not_the_temporary(tmp_path):
    target = tmp_path / "out.csv"

    def fail(tmp):
        raise OSError(28, "No space left on device")

    with pytest.raises(WriteError, match=r"cannot write .*out.csv: No space left on device"):
        atomic.atomic_write_with(target, fail)
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(WriteError, match="is a folder"):
        atomic_write_text(tmp_path, "x")


def test_stale_temporaries_of_dead_writers_are_removed_on_the_next_write(tmp_path):
    target = tmp_path / "canvas.exr"
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], text=True,
                          capture_output=True, check=True).stdout.strip()  # fmt: skip
    stale = tmp_path / f".canvas.exr.{dead}.abcd1234.tmp.exr"  # kill -9 left it
    old_style = tmp_path / ".canvas.exr.zyxw9876.tmp.exr"  # no pid: removed once old
    fresh_old_style = tmp_path / ".canvas.exr.qqqq1111.tmp.exr"
    live = tmp_path / f".canvas.exr.{os.getppid()}.efgh5678.tmp.exr"  # a running writer
    other = tmp_path / f".other.exr.{dead}.abcd1234.tmp.exr"
    for path in (stale, old_style, fresh_old_style, live, other):
        path.write_bytes(b"")
    hour_ago = time.time() - 3600
    os.utime(old_style, (hour_ago, hour_ago))
    atomic_write_text(target, "new")
    assert target.read_text() == "new"
    assert not stale.exists() and not old_style.exists()
    assert fresh_old_style.exists() and live.exists() and other.exists()
    assert remove_stale_temps(target) == []


def test_temporaries_carry_the_writers_pid(tmp_path):
    with atomic_path(tmp_path / "a.png") as tmp:
        assert tmp.name.startswith(f".a.png.{os.getpid()}.") and tmp.name.endswith(".tmp.png")
        tmp.write_bytes(b"png")
    assert (tmp_path / "a.png").read_bytes() == b"png"
