"""The velocity components on threads: the same values, bit for bit, as one after the other."""

from __future__ import annotations

import dataclasses
import os
import threading

import numpy as np
import pytest

from solver.compiled.threads import (
    AUTO_MIN_SAMPLES,
    AUTO_THREADS,
    MAX_THREADS,
    BesideJob,
    quota_cores,
    run_beside,
    run_components,
    run_shared,
    thread_count,
    usable_cores,
)
from solver.grid import Grid
from solver.linalg import multigrid
from solver.probes import Probe
from solver.scenes.plan import explain
from solver.shapes import Box
from solver.simulation import Fluid, Simulation, SolverSettings


def _stirred(dim: int, threads: int, nu: float = 0.01, **settings) -> Simulation:
    """A spinning box crossing a small closed box of fluid."""
    n = 12
    grid = Grid.from_size((1.0,) * dim, (n,) * dim)
    centre = np.full(dim, 0.4)
    velocity = np.zeros(dim)
    velocity[0] = 0.6
    spin = 2.0 if dim == 2 else np.array([0.0, 0.0, 2.0])
    turn = 0.0 if dim == 2 else np.array([1.0, 0.0, 0.0, 0.0])
    probe = Probe("box", Box((0.25,) * dim), dim, centre, turn, velocity, spin)
    cfg = SolverSettings(threads=threads, **settings)
    return Simulation(grid, Fluid(1.0, nu), probes=[probe], settings=cfg)


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize(
    "settings",
    [
        {},
        {"nu": 0.0},  # inviscid: the pressure's hierarchy is still built beside
        {"advection": "maccormack"},
        {"viscosity_preconditioner": "multigrid"},
        {"viscosity_preconditioner": "multigrid", "warm_start": True},
        {"boundary_method": "staircase", "viscosity_preconditioner": "mic0"},
    ],
)
def test_components_on_threads_give_the_same_bits(dim, settings):
    one, two = _stirred(dim, 1, **settings), _stirred(dim, 2, **settings)
    assert (one.component_threads(), two.component_threads()) == (1, 2)
    for _ in range(6):
        a, b = one.step(0.02), two.step(0.02)
        assert [r.iterations for r in a.viscosity] == [r.iterations for r in b.viscosity]
    for x, y in zip(one.state.comps[:dim], two.state.comps[:dim], strict=True):
        assert np.array_equal(x, y)
    assert np.array_equal(one.state.pressure, two.state.pressure)
    assert np.array_equal(one.forces["box"].force, two.forces["box"].force)
    assert np.abs(one.state.comps[0]).max() > 0.1  # the box stirred the fluid


@pytest.mark.parametrize("settings", [{}, {"boundary_method": "staircase"}])
def test_the_pressure_solve_on_threads_gives_the_same_bits(settings, monkeypatch):
    """With every multigrid level on the parallel kernels (the threshold lowered to a cell)."""
    monkeypatch.setattr(multigrid, "PARALLEL_MIN_CELLS", 1)
    one, two = _stirred(3, 1, **settings), _stirred(3, 2, **settings)
    for _ in range(4):
        a, b = one.step(0.02), two.step(0.02)
        assert a.pressure == b.pressure
    assert np.array_equal(one.state.pressure, two.state.pressure)
    for x, y in zip(one.state.comps, two.state.comps, strict=True):
        assert np.array_equal(x, y)
    assert a.pressure.iterations > 0


def test_run_components_keeps_the_order_and_uses_other_threads():
    seen: dict[int, str] = {}

    def work(a: int) -> int:
        seen[a] = threading.current_thread().name
        return 10 * a

    assert run_components(work, 3, 2) == [0, 10, 20]
    here = threading.current_thread().name
    assert seen[0] == seen[2] == here  # this thread does the first and the last
    assert seen[1] != here
    assert run_components(work, 3, 1) == [0, 10, 20]


def test_a_failing_component_raises_after_the_others_finish():
    done = []

    def work(a: int) -> int:
        if a == 1:
            raise ValueError("component 1 failed")
        done.append(a)
        return a

    with pytest.raises(ValueError, match="component 1 failed"):
        run_components(work, 3, 2)
    assert sorted(done) == [0, 2]


@pytest.mark.parametrize("dim", [2, 3])
def test_auto_takes_two_threads_only_for_large_components(dim):
    least = AUTO_MIN_SAMPLES[dim]
    assert thread_count(0, least - 1, dim) == 1
    assert thread_count(0, least, dim) == min(AUTO_THREADS, usable_cores())
    assert thread_count(3, 10, dim) == 3
    for bad in (-1, MAX_THREADS + 1):
        with pytest.raises(ValueError, match="threads must be in"):
            thread_count(bad, 10, dim)


def test_a_simulation_refuses_a_thread_count_out_of_range():
    grid = Grid.from_size((1.0, 1.0), (8, 8))
    with pytest.raises(ValueError, match="threads must be in"):
        Simulation(grid, Fluid(1.0, 0.01), settings=SolverSettings(threads=-1))


def test_the_plan_says_how_many_threads_and_why():
    small = _stirred(3, 0)
    d = {x.topic: x for x in explain(small, 0.02)}["threads"]
    assert "one thread" in d.chosen and "auto" in d.reason
    set_two = _stirred(3, 0)
    set_two.settings = dataclasses.replace(set_two.settings, threads=2)
    d = {x.topic: x for x in explain(set_two, 0.02)}["threads"]
    assert "2 threads" in d.chosen and "threads = 2" in d.reason
    assert "pressure" not in d.chosen  # 12³: below the parallel levels' size
    grid = Grid.from_size((1.0,) * 3, (32,) * 3)
    large = Simulation(grid, Fluid(1.0, 0.01), settings=SolverSettings(threads=2))
    assert large.pressure_on_threads()
    d = {x.topic: x for x in explain(large, 0.02)}["threads"]
    assert "the pressure solve's levels of 32768+ cells on 2" in d.chosen
    assert not large.pressure_threads_adaptive()  # set threads: always on them
    auto = Simulation(grid, Fluid(1.0, 0.01), settings=SolverSettings(threads=0))
    two_cores = usable_cores() >= 2
    assert auto.pressure_on_threads() == two_cores  # auto: may, as measured
    assert auto.pressure_threads_adaptive() == two_cores
    if two_cores:
        d = {x.topic: x for x in explain(auto, 0.02)}["threads"]
        assert "on 2 threads or one, whichever has cost less" in d.chosen
    flat = Simulation(Grid.from_size((1.0,) * 2, (256,) * 2), Fluid(1.0, 0.01),
                      settings=SolverSettings(threads=2))  # fmt: skip
    assert not flat.pressure_on_threads()  # 2D levels are one plane


def test_a_failure_on_this_thread_stops_its_share_and_waits_for_the_pool():
    done = []

    def work(a: int) -> int:
        if a == 0:
            raise KeyboardInterrupt
        done.append(a)
        return a

    with pytest.raises(KeyboardInterrupt):
        run_components(work, 3, 2)
    assert done == [1]  # the pool's component finished; this thread's next one never began


def test_run_beside_runs_the_jobs_in_order_on_another_thread_and_waits_for_one():
    order: list[str] = []
    here = threading.current_thread().name
    first_done = threading.Event()

    def job(name: str, event: threading.Event | None = None):
        def run() -> str:
            if event is not None:
                event.wait(5.0)
            order.append(name)
            assert threading.current_thread().name != here
            return name.upper()

        return run

    def own(wait):
        first_done.set()  # the second job may start only after the first: it waits for this
        got = wait(0)
        order.append("own")
        return got

    mine, results = run_beside(own, [job("a"), job("b", first_done), job("c")])
    assert mine == "A" and results == ["A", "B", "C"]
    assert order.index("a") < order.index("own")  # own waited for job 0
    assert [n for n in order if n != "own"] == ["a", "b", "c"]


def test_run_beside_raises_after_every_job_has_finished():
    done: list[int] = []

    def failing() -> None:
        raise ValueError("job failed")

    def own(wait):
        wait(0)  # raises the job's error here
        done.append(-1)

    with pytest.raises(ValueError, match="job failed"):
        run_beside(own, [failing, lambda: done.append(1)])
    assert done == [1]  # the next job still ran to its end; own stopped at the wait

    def own_fails(wait):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_beside(own_fails, [lambda: done.append(2)])
    assert done == [1, 2]


def test_a_container_s_cpu_quota_caps_the_cores():
    assert quota_cores("max 100000\n") is None  # cgroup v2, no quota
    assert quota_cores("150000 100000\n") == 1  # one and a half cores: one whole
    assert quota_cores("400000 100000") == 4
    assert quota_cores("50000 100000") == 1  # at least one
    assert quota_cores("-1", "100000") is None  # cgroup v1, no quota
    assert quota_cores("200000", "100000\n") == 2
    for bad in ("", "garbage", "1 2 3", "0 100000", "nan 100000", "100000 0"):
        assert quota_cores(bad) is None
    assert 1 <= usable_cores() <= (os.cpu_count() or 1)


def test_a_beside_job_runs_on_another_thread_at_once_or_here_when_asked():
    here = threading.current_thread().name
    started = threading.Event()
    where: list[str] = []

    def job() -> int:
        where.append(threading.current_thread().name)
        started.set()
        return 42

    beside = BesideJob(job, 2)
    assert started.wait(5.0)  # it began without being asked
    assert beside.result() == 42 and where == [where[0]] and where[0] != here
    alone = BesideJob(job, 1)
    assert len(where) == 1  # one thread: not yet
    assert alone.result() == 42 and where[1] == here


def test_a_beside_job_s_error_is_raised_by_result_and_swallowed_by_settle():
    def failing() -> None:
        raise ValueError("job failed")

    with pytest.raises(ValueError, match="job failed"):
        BesideJob(failing, 2).result()
    finished = threading.Event()
    gate = threading.Event()

    def slow() -> None:
        gate.wait(5.0)
        finished.set()
        raise ValueError("also failed")

    job = BesideJob(slow, 2)
    gate.set()
    job.settle()  # waits for the end, raises nothing
    assert finished.is_set()
    never: list[int] = []
    BesideJob(lambda: never.append(1), 1).settle()
    assert never == []  # with one thread a settled job never runs


@pytest.mark.parametrize("threads", [1, 2])
def test_a_step_runs_its_beside_job_once_with_the_step_s_geometry(threads):
    """The job sees the labels and probe of the step (the probe already moved) and leaves the
    step's values as they were without it."""
    plain, with_job = _stirred(3, threads), _stirred(3, threads)
    seen: list[tuple[np.ndarray, np.ndarray]] = []

    def look() -> None:
        seen.append((with_job.state.label.copy(), with_job.probes[0].centre_m.copy()))

    for _ in range(3):
        plain.step(0.02)
        stats = with_job.step(0.02, beside=look)
        assert stats.substep_ms["beside"] >= 0.0
        label, centre = seen[-1]
        assert np.array_equal(label, with_job.state.label)
        np.testing.assert_array_equal(centre, with_job.probes[0].centre_m)
    assert len(seen) == 3
    assert not np.array_equal(seen[0][0], seen[-1][0])  # the box moved across cells
    for x, y in zip(plain.state.comps, with_job.state.comps, strict=True):
        assert np.array_equal(x, y)
    assert "beside" not in plain.step(0.02).substep_ms


@pytest.mark.parametrize("threads", [1, 2])
def test_a_failing_beside_job_raises_from_the_step_after_it_is_done(threads):
    sim = _stirred(3, threads)

    def failing() -> None:
        raise ValueError("the caller's job failed")

    plain = _stirred(3, threads)
    with pytest.raises(ValueError, match="the caller's job failed"):
        sim.step(0.02, beside=failing)
    plain.step(0.02)
    assert sim.time_s == plain.time_s  # the step itself was done and counted
    assert np.array_equal(sim.state.pressure, plain.state.pressure)
    sim.step(0.02)  # and the next runs as usual
    plain.step(0.02)
    assert np.array_equal(sim.state.comps[0], plain.state.comps[0])


def test_run_shared_runs_every_task_once_and_the_lead_on_a_pool_thread():
    here = threading.current_thread().name
    lead_running = threading.Event()
    release = threading.Event()
    done: dict[int, str] = {}

    def lead() -> str:
        lead_running.set()
        release.wait(5.0)
        return threading.current_thread().name

    def work(a: int) -> None:
        if a == 0:
            assert lead_running.wait(5.0)  # the lead started beside the first task
        done[a] = threading.current_thread().name
        if a == 5:
            release.set()  # the lead ends once this thread has taken six tasks

    lead_thread = run_shared(work, 12, 2, lead)
    assert lead_thread != here
    assert sorted(done) == list(range(12))
    assert all(done[a] == here for a in range(6))  # this thread took them while the lead ran
    order: list[str] = []
    assert run_shared(lambda a: order.append(f"t{a}"), 2, 1, lambda: order.append("lead")) is None
    assert order == ["lead", "t0", "t1"]  # one thread: the lead first, here


def test_run_shared_raises_once_every_thread_has_stopped():
    lead_done: list[int] = []

    def lead() -> None:
        threading.Event().wait(0.05)
        lead_done.append(1)

    def work(a: int) -> None:
        if a == 0:
            raise ValueError("task 0 failed")

    with pytest.raises(ValueError, match="task 0 failed"):
        run_shared(work, 4, 2, lead)
    assert lead_done == [1]  # raised only once the lead had finished
    taken: list[int] = []

    def failing_lead() -> None:
        raise RuntimeError("the lead failed")

    def slow(a: int) -> None:
        taken.append(a)
        threading.Event().wait(0.01)

    with pytest.raises(RuntimeError, match="the lead failed"):
        run_shared(slow, 1000, 2, failing_lead)
    assert len(taken) < 1000  # the lead's failure stopped the takes
