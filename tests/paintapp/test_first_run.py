"""The first run's kernel warm-up: cold and warm caches, terminals and redirected output.

Nothing here compiles more than a one-line kernel: the replay is a fake that compiles one.
"""

from __future__ import annotations

import io
import sys
import types

import pytest
from numba import njit

from paintapp import first_run
from paintapp.commands import paint as paint_command
from paintapp.commands.replay import replay_with_progress
from paintapp.first_run import MESSAGE, CompileProgress, kernels_cold, warm_up
from paintapp.resources import asset_path
from paintapp.strokes.files import read_strokes


class Terminal(io.StringIO):
    """A stream that says it is a terminal."""

    def isatty(self) -> bool:
        return True


def compile_one_kernel() -> None:
    """Make numba compile a fresh kernel (a new function each call: never cached)."""

    def twice(x):
        return 2 * x

    assert njit(twice)(1.5) == 3.0


class FakeIndex:
    def __init__(self, entries: dict) -> None:
        self._cache_file = types.SimpleNamespace(_load_index=lambda: entries)


def fake_kernels(monkeypatch: pytest.MonkeyPatch, **cached: bool) -> tuple[tuple[str, str], ...]:
    """A module of fake cached kernels, ``name=True`` for one with code in the cache."""
    module = types.ModuleType("fake_kernels")
    for name, warm in cached.items():
        setattr(module, name, types.SimpleNamespace(_cache=FakeIndex({"sig": 1} if warm else {})))
    monkeypatch.setitem(sys.modules, "fake_kernels", module)
    return tuple(("fake_kernels", name) for name in cached)


@pytest.fixture(autouse=True)
def no_second_process(monkeypatch: pytest.MonkeyPatch) -> None:
    """The caches here are cold by pretence only: no process compiles ahead."""
    monkeypatch.setattr("paintapp.compile_ahead.ENABLED", False)


@pytest.fixture
def strokes():
    return read_strokes(asset_path("strokes", "example_short.jsonl"))


@pytest.fixture
def replays(monkeypatch: pytest.MonkeyPatch) -> list:
    """Calls of the playback's replay, which compiles one kernel and returns None."""
    calls: list = []

    def fake_replay(strokes, scene=None, **kwargs):
        calls.append((strokes, scene, kwargs))
        compile_one_kernel()

    monkeypatch.setattr("paintapp.session.playback.replay", fake_replay)
    return calls


def set_cold(monkeypatch: pytest.MonkeyPatch, cold: bool) -> None:
    monkeypatch.setattr(first_run, "kernels_cold", lambda: cold)


def test_a_kernel_without_cached_code_makes_the_cache_cold(monkeypatch):
    assert kernels_cold(fake_kernels(monkeypatch, a=True, b=False))
    assert not kernels_cold(fake_kernels(monkeypatch, a=True, b=True))


def test_what_is_no_caching_dispatcher_counts_as_warm(monkeypatch):
    module = types.ModuleType("plain_functions")
    module.f = lambda: None  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "plain_functions", module)
    assert not kernels_cold((("plain_functions", "f"), ("no_such_module_here", "g")))


def test_the_bundled_sentinels_are_cached_kernels():
    for module, name in first_run.SENTINELS:
        dispatcher = getattr(__import__(module, fromlist=[name]), name)
        assert isinstance(dispatcher._cache._cache_file._load_index(), dict)


def test_compiling_shows_the_message_and_counts_on_a_terminal():
    stream = Terminal()
    with CompileProgress(stream) as progress:
        compile_one_kernel()
    assert progress.kernels == 1
    assert progress.seconds > 0.0
    assert MESSAGE in stream.getvalue()
    assert "1 kernels" in stream.getvalue()


def test_compiling_says_nothing_on_a_redirected_stream():
    stream = io.StringIO()
    with CompileProgress(stream) as progress:
        compile_one_kernel()
    assert progress.kernels == 1
    assert stream.getvalue() == ""


def test_a_cold_cache_on_a_terminal_replays_the_first_records(monkeypatch, strokes, replays):
    set_cold(monkeypatch, True)
    stream = Terminal()
    assert warm_up(strokes, None, "draft", "3dof", stream=stream, records=5)
    ((head, scene, kwargs),) = replays
    assert head.records == strokes.records[:5]
    assert head.header == strokes.header
    assert scene is None
    assert kwargs == {"fidelity": "draft", "device": "3dof"}
    assert MESSAGE in stream.getvalue()


def test_a_warm_cache_does_nothing(monkeypatch, strokes, replays):
    set_cold(monkeypatch, False)
    stream = Terminal()
    assert not warm_up(strokes, stream=stream)
    assert not replays
    assert stream.getvalue() == ""


def test_a_cold_cache_off_a_terminal_does_nothing(monkeypatch, strokes, replays):
    set_cold(monkeypatch, True)
    stream = io.StringIO()
    assert not warm_up(strokes, stream=stream)
    assert not replays
    assert stream.getvalue() == ""


def test_the_replay_command_prints_nothing_extra_on_a_warm_cache(monkeypatch, strokes, replays):
    set_cold(monkeypatch, False)
    stream = Terminal()
    monkeypatch.setattr(sys, "stderr", stream)
    replay_with_progress(strokes, None)
    assert len(replays) == 1  # the replay itself, no warm-up before it
    assert MESSAGE not in stream.getvalue()


def test_the_replay_command_warms_up_first_on_a_cold_cache(monkeypatch, strokes, replays):
    set_cold(monkeypatch, True)
    stream = Terminal()
    monkeypatch.setattr(sys, "stderr", stream)
    replay_with_progress(strokes, None, "draft")
    assert len(replays) == 2
    assert len(replays[0][0].records) == min(first_run.WARM_UP_RECORDS, len(strokes.records))
    assert replays[0][2]["fidelity"] == "draft"
    assert MESSAGE in stream.getvalue()


def test_the_painting_window_is_announced_on_a_terminal_on_a_cold_cache(monkeypatch):
    for cold, stream, said in (
        (True, Terminal(), True),
        (True, io.StringIO(), False),
        (False, Terminal(), False),
    ):
        set_cold(monkeypatch, cold)
        assert paint_command.announce_compilation(stream) is said
        assert (MESSAGE in stream.getvalue()) is said
