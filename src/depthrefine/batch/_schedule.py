"""Frames as tasks of a Dask distributed client: recomputable, in order, each worker on its share of the cores.

A frame's arrays travel inside its task (``client.submit(f, arrays)``, not
``client.scatter``), so the scheduler holds everything needed to run the
task again: a worker lost mid-run has its frames recomputed on another
worker, with the same bits (the methods are deterministic on any number of
threads). A lost scheduler ends the run with :class:`ClusterLost`.

Each task caps the kernel threads of its worker process at the worker's
share of its machine's cores and keeps glibc's allocator from returning
every array to the system while it runs (:mod:`._worker`).
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
import threading
import time
from collections.abc import Callable, Hashable, Iterable, Iterator, Mapping, Sized
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._lazy import missing_dependency, missing_dependency_message
from ..methods.registry import DEFAULT_METHOD, get_method
from ._frame import FrameOutput, FramePlan, encode_files, solve_frame
from ._worker import task_settings, worker_share

__all__ = ["DEFAULT_CHUNK", "ClusterLost", "FrameResult", "refine_many", "run_frames", "local_client",
           "needed_keys"]

#: Frames per chunk with ``temporal``: each chunk's first frame starts cold.
DEFAULT_CHUNK = 32

Loader = Callable[[], tuple[np.ndarray, np.ndarray]]

#: Seconds to wait for a first worker of a remote cluster.
_WORKER_WAIT = 30
#: Without ``temporal``: frames per task by default, as many as hold about this many color pixels ...
TASK_PIXELS = 1 << 20
#: ... and at most this many (each task costs Dask a few milliseconds; small frames share one).
MAX_FRAMES_PER_TASK = 8


#: Dask settings of the local cluster, which serve only Dask's dashboard and its warnings (silenced here): the
#: servers' event-loop watchdog every second instead of every 20 ms, and no statistical profiler on the
#: workers (it walked the task thread's stack every 10 ms). Idle: 24 -> 14 ms CPU per second in this process
#: (scheduler, client, nannies), 18-20 -> 6-7 in each worker (``benchmarks/bench_batch.py --overheads``).
LOCAL_CLUSTER_CONFIG = {"distributed.admin.tick.interval": "1s", "distributed.worker.profile.enabled": False}


class ClusterLost(RuntimeError):
    """The connection to the Dask scheduler was lost during a run (the frames in flight are not done)."""


@dataclass
class FrameResult:
    """The outcome of one frame.

    Attributes
    ----------
    key : hashable
        The frame's key, as given.
    output : FrameOutput or None
        What the worker returned, or ``None`` if the frame failed or was
        only run to warm-start the next (``want`` false).
    seconds : float
        Time the worker spent on it (0 if it failed before reaching one).
    error : str or None
        Why it failed, one line.
    bad_input : bool
        Whether the failure is the input's (``ValueError``/``TypeError``,
        e.g. an unreadable file or shapes that do not belong together)
        rather than an internal error.
    """

    key: Hashable
    output: FrameOutput | None
    seconds: float = 0.0
    error: str | None = None
    bad_input: bool = False

    @property
    def depth_hr(self) -> np.ndarray | None:
        """The refined depth (float32), or ``None``."""
        return None if self.output is None else self.output.depth_hr


def refine_many(
    pairs: Mapping[Hashable, tuple[np.ndarray, np.ndarray]] | Iterable[tuple[Hashable, np.ndarray, np.ndarray]],
    *,
    method: str = DEFAULT_METHOD,
    params: Any = None,
    client: Any = None,
    temporal: bool = False,
    chunk: int = DEFAULT_CHUNK,
    workers: int | None = None,
    confidence: bool = False,
) -> Iterator[tuple[Hashable, np.ndarray]]:
    """Refine many depth + color pairs on Dask; yield ``(key, depth_hr)`` in input order.

    Parameters
    ----------
    pairs : mapping or iterable
        ``{key: (depth_lr, rgb_hr)}``, or an iterable of ``(key, depth_lr,
        rgb_hr)``; consumed lazily (a few frames per worker ahead). With a
        length (a mapping, a list), the last tasks are smaller, so that the
        workers finish together (:func:`run_frames`, ``total``).
    method, params
        As for :func:`depthrefine.refine`.
    client : dask.distributed.Client, optional
        Where to run. Default: a ``LocalCluster`` of ``workers`` processes
        (default: the number of cores), started for this call (a few
        seconds) and closed at the end; as its workers are new processes, a
        script that calls this must do so under ``if __name__ ==
        "__main__":``. Pass a client to reuse one cluster for many calls.
    temporal : bool
        Warm-start each frame from the previous one within chunks of
        ``chunk`` frames (see :mod:`depthrefine.batch`).
    confidence : bool
        Also make each frame's confidence map and yield ``(key, depth_hr,
        confidence)`` (:func:`depthrefine.refine_with_confidence`; with
        ``temporal``, :func:`depthrefine.methods.confidence.confidence_of`).

    Raises
    ------
    ValueError, TypeError
        The first frame (in input order) that is bad input, with its key.
    RuntimeError
        A frame that failed inside a worker for another reason.
    ClusterLost
        The scheduler went away.

    Examples
    --------
    >>> import numpy as np
    >>> from distributed import Client, LocalCluster
    >>> from depthrefine.batch import refine_many
    >>> frames = {i: (np.full((8, 8), 100 + i, np.uint8), np.zeros((32, 32, 3), np.uint8)) for i in range(3)}
    >>> with LocalCluster(n_workers=1, processes=False) as cluster, Client(cluster) as client:
    ...     [(k, float(d[0, 0])) for k, d in refine_many(frames, method="bilinear", client=client)]
    [(0, 100.0), (1, 101.0), (2, 102.0)]
    """
    plan = FramePlan(get_method(method), params, confidence=confidence)
    items = pairs.items() if isinstance(pairs, Mapping) else ((k, (d, c)) for k, d, c in pairs)
    tasks = ((key, _constant(value)) for key, value in items)
    with contextlib.ExitStack() as stack:
        if client is None:
            client = stack.enter_context(local_client(workers))
        total = len(pairs) if isinstance(pairs, Sized) else None
        for result in run_frames(tasks, plan=plan, client=client, temporal=temporal, chunk=chunk, total=total):
            if result.error is not None:
                kind = ValueError if result.bad_input else RuntimeError
                raise kind(f"frame {result.key!r}: {result.error}")
            yield (result.key, result.depth_hr, result.output.confidence) if confidence else (result.key, result.depth_hr)


def _constant(value: tuple[np.ndarray, np.ndarray]) -> Loader:
    return lambda: value


@contextlib.contextmanager
def local_client(workers: int | None = None, scheduler: str | None = None) -> Iterator[Any]:
    """A ``distributed.Client``: of the scheduler at ``scheduler``, else of a new ``LocalCluster``.

    The local cluster has ``workers`` processes (default: the number of
    cores) with one thread each and no dashboard; both are closed at the
    end. Dask's own log lines stay off the terminal (a lost worker or
    scheduler is the caller's to report).

    Raises
    ------
    OSError
        The scheduler cannot be reached (the message says how to start one).
    """
    from distributed import Client, LocalCluster

    with _quiet_dask() as silence:
        try:
            if scheduler:
                try:
                    _reachable(scheduler)
                    client = Client(scheduler, timeout="10s")
                except (OSError, TimeoutError) as exc:
                    raise OSError(f"cannot reach the Dask scheduler at {scheduler} ({' '.join(str(exc).split())}); "
                                  "start one with `dask scheduler` and workers with `dask worker ADDRESS`.") from None
                with _closing(client, silence):
                    try:
                        client.wait_for_workers(1, timeout=_WORKER_WAIT)
                    except TimeoutError:
                        raise OSError(f"the Dask scheduler at {scheduler} has no workers (waited {_WORKER_WAIT} s); "
                                      f"start some with `dask worker {scheduler}`.") from None
                    yield client
                return
            import logging

            import dask

            n = workers or os.cpu_count() or 1
            # the workers ignore Ctrl-C (this process stops them): no tracebacks of theirs
            with _sigint_ignored(), dask.config.set(LOCAL_CLUSTER_CONFIG):
                cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, host="127.0.0.1",
                                       dashboard_address=":0", silence_logs=logging.ERROR)
            # results come straight from the worker, not through the scheduler (which runs in this process)
            with _closing(cluster, silence), _closing(Client(cluster, direct_to_workers=True), silence) as client:
                yield client
        except BaseException:
            silence()  # what Dask logs while it is torn down after an error is not the user's news
            raise


@contextlib.contextmanager
def _quiet_dask() -> Iterator[Callable[[], None]]:
    """Dask's loggers at CRITICAL for the block; the callable given silences them fully (shutdown after a failure).

    Dask logs a lost connection or worker as a traceback; the batch reports
    what it means, in one line. Dask's configuration gives some of its
    loggers their own levels (``distributed.client``), so each is set.
    """
    import logging

    prefixes = ("distributed", "tornado", "asyncio")
    known = [name for name in logging.root.manager.loggerDict
             if name in prefixes or name.startswith(tuple(p + "." for p in prefixes))]
    loggers = [logging.getLogger(name) for name in sorted(set(known) | set(prefixes))]
    levels = [logger.level for logger in loggers]

    def quiet(level: int) -> None:
        for logger in loggers:
            logger.setLevel(level)

    quiet(logging.CRITICAL)
    try:
        yield lambda: quiet(logging.CRITICAL + 1)
    finally:
        for logger, level in zip(loggers, levels):
            logger.setLevel(level)


@contextlib.contextmanager
def _sigint_ignored() -> Iterator[None]:
    """SIGINT ignored while the block starts processes, which inherit it (in the main thread; else nothing).

    A Ctrl-C at a terminal reaches every process of the foreground group: the
    local workers, started with SIGINT ignored, leave it to this process,
    which stops them. A Ctrl-C while they start is ignored.
    """
    import signal

    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


@contextlib.contextmanager
def _closing(thing: Any, silence: Callable[[], None]) -> Iterator[Any]:
    """``thing`` (a client or cluster), closed at the end; within seconds and silently after a failure."""
    try:
        yield thing
    except BaseException:
        silence()
        with contextlib.suppress(BaseException):
            thing.close(timeout=2)
        raise
    thing.close()


def _reachable(address: str) -> None:
    """Fail at once (``OSError``) when nothing listens at a ``tcp://host:port`` address."""
    import socket

    from distributed.comm import parse_address, parse_host_port

    scheme, location = parse_address(address)
    if scheme != "tcp":
        return
    host, port = parse_host_port(location)
    with socket.create_connection((host, port), timeout=5):
        pass


def run_frames(
    tasks: Iterable[tuple[Hashable, Loader | BaseException]],
    *,
    plan: FramePlan,
    client: Any,
    temporal: bool = False,
    chunk: int = DEFAULT_CHUNK,
    want: Callable[[Hashable], bool] | None = None,
    ahead: int | None = None,
    frames_per_task: int | None = None,
    total: int | None = None,
) -> Iterator[FrameResult]:
    """Run frames on ``client``; yield one :class:`FrameResult` per frame, in input order.

    Parameters
    ----------
    tasks : iterable of (key, loader)
        ``loader()`` returns ``(depth, rgb)``, or ``(depth, rgb, suffixes)``
        for a frame whose files the worker encodes (:func:`encode_files`:
        ``{"depth": ".png", ...}``; the result's ``output.files``); it runs
        here, in the caller's process, just before its frame is sent (so
        files are read a few frames ahead, never all at once). A
        ``ValueError`` or ``TypeError`` it raises (or an exception given
        instead of a loader) fails that frame as bad input.
    plan : FramePlan
        What the workers do with each frame (sent with every task).
    temporal, chunk
        Warm start within chunks of ``chunk`` consecutive frames.
    want : callable, optional
        ``want(key)`` false: the frame is yielded without output and,
        without ``temporal``, not even loaded or computed; with ``temporal``
        it still runs when a later frame of its chunk is wanted (to
        warm-start it). Used to resume a batch.
    ahead : int, optional
        Tasks in flight (default: twice the workers' threads).
    frames_per_task : int, optional
        Without ``temporal``: consecutive frames sent to a worker as one task
        (each refined on its own). Default: one for the first task, then as
        many as hold about :data:`TASK_PIXELS` color pixels of the first
        frame's size, at most :data:`MAX_FRAMES_PER_TASK` (small frames share
        a task, so that Dask's cost per task stays small beside the work);
        with ``total``, toward the end at most the frames left over twice the
        workers' Dask threads, so that the last tasks are small and the
        workers finish together.
    total : int, optional
        The number of ``tasks``, if known (see ``frames_per_task``).

    Raises
    ------
    ClusterLost
        The scheduler went away; the frames not yielded yet are not done.
    """
    from distributed import wait

    size = [max(1, int(chunk)) if temporal else (frames_per_task or 1)]  # frames of the next task
    threads = _check_running(client, client.nthreads)
    slots = max(1, sum(threads.values()))
    if ahead is None:
        ahead = 2 * slots
    share = _host_threads(threads)
    want = want or (lambda key: True)
    groups = _chunks(iter(tasks), size)
    pending: dict[Any, tuple[int, list[tuple[int, Hashable]]]] = {}  # future -> (chunk number, its frames)
    known: dict[int, list[tuple[int, FrameResult]]] = {}   # results settled before sending
    done: dict[int, list[tuple[int, FrameResult]]] = {}    # chunks finished, not yet yielded
    next_submit = next_yield = submitted = 0
    largest = size[0]  # frames per task before the end
    exhausted = False
    try:
        while True:
            while not exhausted and len(pending) + len(done) < ahead:
                group = next(groups, None)
                if group is None:
                    exhausted = True
                    break
                settled, future, frames, pixels = _submit(client, group, plan, temporal, want, share)
                submitted += len(group)
                if not temporal and frames_per_task is None:
                    if pixels:
                        largest = max(1, min(MAX_FRAMES_PER_TASK, TASK_PIXELS // pixels))
                    size[0] = largest if total is None else _task_size(largest, total - submitted, slots)
                if future is None:
                    done[next_submit] = settled
                else:
                    pending[future] = (next_submit, frames)
                    known[next_submit] = settled
                next_submit += 1
            while next_yield in done:
                for _, result in sorted(done.pop(next_yield), key=lambda pair: pair[0]):
                    yield result
                next_yield += 1
            if exhausted and not pending:
                return
            if pending:
                finished, _ = _check_running(client, wait, list(pending), return_when="FIRST_COMPLETED")
                for future in finished:
                    number, frames = pending.pop(future)
                    done[number] = known.pop(number) + _collect(client, future, frames)
                    future.release()
    finally:
        if pending and client.status == "running":
            with contextlib.suppress(Exception):
                client.cancel(list(pending))


def _task_size(largest: int, left: int, slots: int) -> int:
    """Frames of the next task: ``largest``, but at most the ``left`` frames over twice the ``slots``, at least 1.

    Each of the workers' ``slots`` threads holds about two tasks at once
    (one running, one queued); toward the end tasks get smaller, so that no
    worker finishes long after the others.

    Examples
    --------
    >>> [_task_size(8, left, 2) for left in (47, 39, 31, 23, 17, 12, 9, 6, 3, 1)]
    [8, 8, 8, 6, 5, 3, 3, 2, 1, 1]
    """
    return max(1, min(largest, -(-left // (2 * slots))))


def _check_running(client: Any, call: Callable, *args, **kwargs) -> Any:
    """``call(*args, **kwargs)``, raising :class:`ClusterLost` when the client lost its scheduler meanwhile."""
    from concurrent.futures import CancelledError

    try:
        result = call(*args, **kwargs)
    except (CancelledError, OSError, TimeoutError):
        if client.status != "running":
            raise ClusterLost(_lost_message(client)) from None
        raise
    if client.status != "running":
        raise ClusterLost(_lost_message(client))
    return result


def _lost_message(client: Any) -> str:
    address = getattr(client.scheduler, "address", None) or "the scheduler"
    return f"lost the connection to the Dask scheduler at {address}"


def needed_keys(keys: Iterable[Hashable], want: Callable[[Hashable], bool], *, temporal: bool = False,
                chunk: int = DEFAULT_CHUNK) -> set[Hashable]:
    """The keys :func:`run_frames` will load: the wanted ones and, with ``temporal``, those before them in
    their chunk (they warm-start the wanted ones).

    Examples
    --------
    >>> sorted(needed_keys(range(6), lambda k: k in (1, 4), temporal=True, chunk=3))
    [0, 1, 3, 4]
    """
    keys = list(keys)
    size = max(1, int(chunk)) if temporal else 1
    need: set[Hashable] = set()
    for start in range(0, len(keys), size):
        group = keys[start:start + size]
        last = max((i for i, key in enumerate(group) if want(key)), default=-1)
        need.update(group[:last + 1])
    return need


def _chunks(tasks: Iterator, size: list[int]) -> Iterator[list[tuple[int, Hashable, Any]]]:
    """Consecutive ``(index, key, loader)`` in groups of ``size[0]`` (read as each group starts)."""
    index = 0
    while True:
        group = []
        for key, loader in tasks:
            group.append((index, key, loader))
            index += 1
            if len(group) >= size[0]:
                break
        if not group:
            return
        yield group


def _host_threads(threads: Mapping[str, int]) -> dict[str, int]:
    """Dask threads per machine (host name) of the workers ``{address: nthreads}``.

    Examples
    --------
    >>> _host_threads({"tcp://10.0.0.1:4001": 1, "tcp://10.0.0.1:4002": 1, "tcp://10.0.0.2:4001": 4})
    {'10.0.0.1': 2, '10.0.0.2': 4}
    """
    from distributed.comm import get_address_host

    out: dict[str, int] = {}
    for address, n in threads.items():
        host = get_address_host(address)
        out[host] = out.get(host, 0) + int(n)
    return out


def _submit(client, group, plan, temporal, want, share):
    """Load a chunk's frames here and send them: (results settled now, future or None, its frames, color pixels)."""
    wanted = [want(key) for _, key, _ in group]
    last = max((i for i, w in enumerate(wanted) if w), default=-1)
    settled: list[tuple[int, FrameResult]] = []
    items = []
    for position, ((order, key, loader), is_wanted) in enumerate(zip(group, wanted)):
        if position > last or (not is_wanted and not temporal):
            settled.append((order, FrameResult(key, None)))
            continue
        try:
            if isinstance(loader, BaseException):
                raise loader
            depth, rgb, *files = loader()
        except (ValueError, TypeError, MemoryError) as exc:
            settled.append((order, FrameResult(key, None, error=_one_line(exc), bad_input=True)))
            continue
        items.append((order, key, depth, rgb, is_wanted, files[0] if files else None))
    if not items:
        return settled, None, [], 0
    import dask

    # the arrays go inside the task (no scatter): the scheduler can run it again if its worker is lost (and
    # Dask's advice against large tasks, "Sending large graph", is what this trades for that)
    with dask.config.set({"distributed.admin.large-graph-warning-threshold": "1TiB"}):
        future = _check_running(client, client.submit, _solve_chunk, plan, temporal, items, share, pure=False)
    pixels = max(int(np.prod(np.shape(item[3])[:2])) for item in items)
    return settled, future, [(order, key) for order, key, *_ in items], pixels


def _collect(client, future, frames: list[tuple[int, Hashable]]) -> list[tuple[int, FrameResult]]:
    try:
        rows = _check_running(client, future.result)
    except ClusterLost:
        raise
    except Exception as exc:  # noqa: BLE001 - the task could not run (e.g. it killed every worker it ran on)
        message = f"internal error: the worker failed: {type(exc).__name__}: {_one_line(exc)}"
        return [(order, FrameResult(key, None, error=message)) for order, key in frames]
    return [(order, FrameResult(key, output, seconds, error, bad))
            for order, key, output, seconds, error, bad in rows]


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split()) or type(exc).__name__


def _solve_chunk(plan: FramePlan, temporal: bool, items: list, share: Mapping[str, int]) -> list[tuple]:
    """On a worker: solve a chunk's frames in order (warm-starting them with ``temporal``), encode their files."""
    stateful = temporal and plan.method.refine_stateful is not None
    # A frame run only to warm-start the next needs no confidence map.
    unconfident = dataclasses.replace(plan, confidence=False, min_confidence=None)
    state = None
    rows = []
    with task_settings(worker_share(share)):
        for order, key, depth, rgb, is_wanted, files in items:
            start = time.perf_counter()
            try:
                frame_plan = plan if is_wanted or not plan.confidence else unconfident
                output, state = solve_frame(frame_plan, depth, rgb, state, stateful=stateful)
                if is_wanted and files:
                    output = encode_files(plan, output, files, input_dtype=depth.dtype, key=key)
            except (ValueError, TypeError, MemoryError) as exc:
                rows.append((order, key, None, time.perf_counter() - start, _one_line(exc), True))
                continue
            except Exception as exc:  # noqa: BLE001 - reported per frame as an internal error
                package = missing_dependency(exc)  # e.g. numba for the thesis method: the user can fix it
                message = (missing_dependency_message(package, exc) if package
                           else f"internal error: {type(exc).__name__}: {_one_line(exc)}")
                rows.append((order, key, None, time.perf_counter() - start, message, False))
                continue
            rows.append((order, key, output if is_wanted else None, time.perf_counter() - start, None, False))
    return rows
