"""The velocity components' independent work (advection, the viscosity solves) on threads.

Each component's advection and viscosity solve reads the shared fields and writes only arrays of
its own, and their kernels release the interpreter lock (``nogil``), so the components can run on
two threads at once with the same values, bit for bit, as one after the other.

``threads`` (``SolverSettings.threads``): 1 runs the components one after the other on the
calling thread; N >= 2 runs them on the calling thread and N - 1 pool threads; 0 (``auto``) takes
``min(AUTO_THREADS, the cores this process may run on)`` threads where a component has at
least ``AUTO_MIN_SAMPLES[dim]`` samples, and one thread below that, where handing work to a
sleeping thread costs more than it saves. The thresholds are where two threads began to pay on a
2-core machine (the solver benchmark's scene stepped on one thread and on two, alternating); a 2D
sample is less work, so 2D needs more of them.
"""

from __future__ import annotations

import functools
import itertools
import os
import threading
from collections.abc import Callable, Sequence
from concurrent.futures import Future, ThreadPoolExecutor
from typing import Any, Generic, TypeVar

AUTO_THREADS = 2
AUTO_MIN_SAMPLES = {2: 32768, 3: 8192}  # by the grid's dimension
MAX_THREADS = 64

T = TypeVar("T")

_pools: dict[int, ThreadPoolExecutor] = {}
_pools_lock = threading.Lock()


CGROUP_QUOTAS = (
    ("/sys/fs/cgroup/cpu.max", None),  # cgroup v2: "QUOTA PERIOD" or "max PERIOD"
    ("/sys/fs/cgroup/cpu/cpu.cfs_quota_us", "/sys/fs/cgroup/cpu/cpu.cfs_period_us"),  # v1
)


def quota_cores(quota: str, period: str | None = None) -> int | None:
    """The whole cores a CPU quota allows (at least 1), from a cgroup v2 ``cpu.max`` line
    (``quota`` alone) or a v1 quota and period; None when there is no quota or it is unreadable."""
    fields = quota.split() if period is None else [quota.strip(), period.strip()]
    if len(fields) != 2 or fields[0] in ("max", "-1"):
        return None
    try:
        limit, length = float(fields[0]), float(fields[1])
    except ValueError:
        return None
    if not (limit > 0 and length > 0):
        return None
    return max(int(limit // length), 1)


def usable_cores() -> int:
    """The cores this process may run on: its affinity where the OS tells it, at most what a
    container's CPU quota allows (read once per process: a step asks several times)."""
    try:
        cores = max(len(os.sched_getaffinity(0)), 1)
    except (AttributeError, OSError):
        cores = max(os.cpu_count() or 1, 1)
    allowed = container_quota_cores()
    return cores if allowed is None else min(cores, allowed)


@functools.cache
def container_quota_cores() -> int | None:
    """The whole cores the first readable cgroup CPU quota allows, or None without one."""
    for quota_path, period_path in CGROUP_QUOTAS:
        try:
            with open(quota_path) as f:
                quota = f.read()
            period = None
            if period_path is not None:
                with open(period_path) as f:
                    period = f.read()
        except OSError:
            continue
        allowed = quota_cores(quota, period)
        if allowed is not None:
            return allowed
    return None


def thread_count(setting: int, samples_per_component: int, dim: int) -> int:
    """The threads a step uses for ``setting`` (0: auto) with components this large, on a
    ``dim``-D grid."""
    if setting < 0 or setting > MAX_THREADS:
        raise ValueError(f"threads must be in [0, {MAX_THREADS}] (0: auto), got {setting}")
    if setting > 0:
        return setting
    if samples_per_component < AUTO_MIN_SAMPLES[dim]:
        return 1
    return min(AUTO_THREADS, usable_cores())


def _pool(workers: int) -> ThreadPoolExecutor:
    with _pools_lock:
        pool = _pools.get(workers)
        if pool is None:
            pool = ThreadPoolExecutor(workers, thread_name_prefix="solver-component")
            _pools[workers] = pool
        return pool


def run_components(work: Callable[[int], T], count: int, threads: int) -> list[T]:
    """``[work(0), ..., work(count - 1)]`` on ``threads`` threads: this thread does the
    components ``a`` with ``a % threads == 0`` (on two threads and three components, the first
    and the last) while ``threads - 1`` pool threads do the others, so this thread keeps its
    caches and works instead of waiting. With one thread, all in order here. An exception (an
    interrupt too) stops this thread's share and is raised here once the pool's components have
    finished: none is left writing behind the caller's back."""
    if threads <= 1 or count <= 1:
        return [work(a) for a in range(count)]
    pool = _pool(threads - 1)
    futures = {a: pool.submit(work, a) for a in range(count) if a % threads}
    results: dict[int, T] = {}
    error: BaseException | None = None
    for a in range(0, count, threads):
        try:
            results[a] = work(a)
        except BaseException as exc:
            error = exc
            break
    for a, future in futures.items():
        try:
            results[a] = future.result()
        except BaseException as exc:
            error = error or exc
    if error is not None:
        raise error
    return [results[a] for a in range(count)]


def run_beside(
    own: Callable[[Callable[[int], object]], T], jobs: Sequence[Callable[[], object]]
) -> tuple[T, list[object]]:
    """Run ``jobs`` one after the other on one pool thread while this thread runs ``own``, which
    gets ``wait``: ``wait(i)`` returns job ``i``'s result once it has finished (an exception it
    raised is raised there). Returns ``own``'s result and the jobs'. As in
    :func:`run_components`, an exception is raised here only once every job has finished."""
    pool = _pool(1)
    futures = [pool.submit(job) for job in jobs]
    error: BaseException | None = None
    mine: T | None = None
    try:
        mine = own(lambda i: futures[i].result())
    except BaseException as exc:
        error = exc
    return mine, _finished(futures, error)  # type: ignore[return-value]


def run_shared(work: Callable[[int], object], count: int, threads: int, lead: Callable[[], T]) -> T:
    """``work(0)``, ..., ``work(count - 1)`` on ``threads`` threads while one pool thread first
    runs ``lead`` (work of another kind): every thread takes the next task no thread has taken
    yet, so the tasks even out what ``lead`` costs. The tasks and ``lead`` must write nothing
    another of them reads. Returns ``lead``'s result. With one thread, ``lead`` and then the
    tasks, in order, here. As in :func:`run_components`, an exception stops its thread's share
    (and every thread's next take) and is raised here once the others have finished. Neither
    ``lead`` nor a task may hand work to this module's threads and wait for it."""
    if threads <= 1:
        result = lead()
        for a in range(count):
            work(a)
        return result
    tasks = itertools.count()  # next() on it is atomic under the interpreter lock
    failed = threading.Event()

    def take() -> None:
        try:
            for a in tasks:
                if a >= count or failed.is_set():
                    return
                work(a)
        except BaseException:
            failed.set()
            raise

    def leading() -> T:
        try:
            result = lead()
        except BaseException:
            failed.set()
            raise
        take()
        return result

    pool = _pool(threads - 1)
    futures: list[Future[Any]] = [pool.submit(leading)]
    futures += [pool.submit(take) for _ in range(threads - 2)]
    error: BaseException | None = None
    try:
        take()
    except BaseException as exc:
        error = exc
    led: T = _finished(futures, error)[0]
    return led


def _finished(futures: Sequence[Future[Any]], error: BaseException | None) -> list[Any]:
    """The futures' results once every one has finished; raises ``error`` (this thread's own),
    else the first error a future raised."""
    results: list[Any] = []
    for future in futures:
        try:
            results.append(future.result())
        except BaseException as exc:
            error = error or exc
    if error is not None:
        raise error
    return results


class BesideJob(Generic[T]):
    """A job of the caller's that runs beside this thread's own work: started on a pool thread
    now when ``threads`` > 1; with one thread, run here when :meth:`result` asks for it. The
    job must not itself hand work to this module's threads and wait for it (the one pool thread
    would wait on itself); jobs started one after another run in that order."""

    def __init__(self, job: Callable[[], T], threads: int) -> None:
        self._job = job
        self._future = _pool(1).submit(job) if threads > 1 else None

    def result(self) -> T:
        """The job's result, once it has finished (an exception it raised is raised here)."""
        if self._future is None:
            return self._job()
        return self._future.result()

    def settle(self) -> None:
        """Wait until the job has finished, without its result or error: for a caller whose own
        work failed and raises its own error, so that nothing is left running behind it (with
        one thread the job never starts)."""
        if self._future is None:
            return
        try:
            self._future.result()
        except BaseException:  # the caller's own error is the one raised
            pass
