"""Many frames at once: scheduling on Dask distributed, in order, with an optional warm start.

The same code path serves one machine and a cluster: frames (or, with
``temporal``, chunks of consecutive frames) are tasks of a
``dask.distributed`` client, which is either given (``client=``, e.g.
``Client("tcp://scheduler:8786")``) or a :class:`distributed.LocalCluster`
started for the run (processes with one thread each, one per core).

Images travel to the workers as arrays and results come back as arrays: the
workers need the package but no access to the files (the caller, e.g. the
``depthrefine batch`` command, reads and writes them through
:mod:`depthrefine.io`).

Without ``temporal`` each frame is refined on its own, exactly as
:func:`depthrefine.refine` refines it (bit for bit). With ``temporal`` the
frames of a chunk run in order on one worker and each warm-starts from the
state the method left after the previous one (the thesis method: its
k-means starts from the previous frame's means, so cluster labels do not
flicker); a method without :attr:`Method.refine_stateful` runs each frame on
its own. Chunks are cut from the whole sequence at fixed positions
(``chunk`` frames each), so the result does not depend on the number of
workers or on a restart.

Dask is imported only when a batch runs.
"""

from __future__ import annotations

import contextlib
import os
import time
from collections.abc import Callable, Hashable, Iterable, Iterator, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._lazy import missing_dependency, missing_dependency_message
from .methods.registry import DEFAULT_METHOD, Method, check_call, get_method

__all__ = ["refine_many", "FrameResult", "run_frames", "local_client", "DEFAULT_CHUNK"]

#: Frames per chunk with ``temporal``: each chunk's first frame starts cold.
DEFAULT_CHUNK = 32

Loader = Callable[[], tuple[np.ndarray, np.ndarray]]

#: Seconds to wait for a first worker of a remote cluster.
_WORKER_WAIT = 30


@dataclass
class FrameResult:
    """The outcome of one frame.

    Attributes
    ----------
    key : hashable
        The frame's key, as given.
    depth_hr : ndarray or None
        The refined depth (float32), or ``None`` if the frame failed or was
        only run to warm-start the next (``want`` false).
    seconds : float
        Time the worker spent on it (0 if it failed before reaching one).
    error : str or None
        Why it failed, one line.
    bad_input : bool
        Whether the failure is the input's (``ValueError``/``TypeError``,
        e.g. an unreadable file or shapes that do not belong together)
        rather than an internal error.
    confidence : ndarray or None
        The confidence map (float32 in [0, 1]) when it was asked for
        (:func:`run_frames` ``confidence=True``).
    """

    key: Hashable
    depth_hr: np.ndarray | None
    seconds: float = 0.0
    error: str | None = None
    bad_input: bool = False
    confidence: np.ndarray | None = None


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
        rgb_hr)``; consumed lazily (a few frames per worker ahead).
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
        ``chunk`` frames (see the module's notes).
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
    entry = get_method(method)
    items = pairs.items() if isinstance(pairs, Mapping) else ((k, (d, c)) for k, d, c in pairs)
    tasks = ((key, _constant(value)) for key, value in items)
    with contextlib.ExitStack() as stack:
        if client is None:
            client = stack.enter_context(local_client(workers))
        for result in run_frames(tasks, entry=entry, params=params, client=client, temporal=temporal,
                                 chunk=chunk, confidence=confidence):
            if result.error is not None:
                kind = ValueError if result.bad_input else RuntimeError
                raise kind(f"frame {result.key!r}: {result.error}")
            yield (result.key, result.depth_hr, result.confidence) if confidence else (result.key, result.depth_hr)


def _constant(value: tuple[np.ndarray, np.ndarray]) -> Loader:
    return lambda: value


@contextlib.contextmanager
def local_client(workers: int | None = None, scheduler: str | None = None) -> Iterator[Any]:
    """A ``distributed.Client``: of the scheduler at ``scheduler``, else of a new ``LocalCluster``.

    The local cluster has ``workers`` processes (default: the number of
    cores) with one thread each and no dashboard; both are closed at the end.

    Raises
    ------
    OSError
        The scheduler cannot be reached (the message says how to start one).
    """
    import logging

    from distributed import Client, LocalCluster

    quiet = logging.getLogger("distributed")
    level = quiet.level
    quiet.setLevel(logging.ERROR)  # no start/stop chatter on the terminal
    try:
        if scheduler:
            try:
                _reachable(scheduler)
                client = Client(scheduler, timeout="10s")
            except (OSError, TimeoutError) as exc:
                raise OSError(f"cannot reach the Dask scheduler at {scheduler} ({' '.join(str(exc).split())}); "
                              "start one with `dask scheduler` and workers with `dask worker ADDRESS`.") from None
            with client:
                try:
                    client.wait_for_workers(1, timeout=_WORKER_WAIT)
                except TimeoutError:
                    raise OSError(f"the Dask scheduler at {scheduler} has no workers (waited {_WORKER_WAIT} s); "
                                  f"start some with `dask worker {scheduler}`.") from None
                yield client
            return
        n = workers or os.cpu_count() or 1
        with LocalCluster(n_workers=n, threads_per_worker=1, processes=True, host="127.0.0.1",
                          dashboard_address=":0", silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
            yield client
    finally:
        quiet.setLevel(level)


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
    entry: Method,
    params: Any,
    client: Any,
    temporal: bool = False,
    chunk: int = DEFAULT_CHUNK,
    want: Callable[[Hashable], bool] | None = None,
    ahead: int | None = None,
    confidence: bool = False,
) -> Iterator[FrameResult]:
    """Run frames on ``client``; yield one :class:`FrameResult` per frame, in input order.

    Parameters
    ----------
    tasks : iterable of (key, loader)
        ``loader()`` returns ``(depth_lr, rgb_hr)``; it runs here, in the
        caller's process, just before its frame is sent (so files are read a
        few frames ahead, never all at once). A ``ValueError`` or
        ``TypeError`` it raises (or an exception given instead of a loader)
        fails that frame as bad input.
    entry : Method
        The method's registry entry (sent to the workers, so methods
        registered at run time work too).
    temporal, chunk
        Warm start within chunks of ``chunk`` consecutive frames.
    want : callable, optional
        ``want(key)`` false: the frame is yielded without ``depth_hr`` and,
        without ``temporal``, not even loaded or computed; with ``temporal``
        it still runs when a later frame of its chunk is wanted (to
        warm-start it). Used to resume a batch.
    ahead : int, optional
        Tasks in flight (default: twice the workers' threads).
    confidence : bool
        Also make each wanted frame's confidence map (:attr:`FrameResult.confidence`).
    """
    from distributed import wait

    chunk = max(1, int(chunk)) if temporal else 1
    if ahead is None:
        ahead = 2 * max(1, sum(client.nthreads().values()))
    want = want or (lambda key: True)
    groups = _chunks(iter(tasks), chunk)
    pending: dict[Any, tuple[int, list[tuple[int, Hashable]]]] = {}  # future -> (chunk number, its frames)
    known: dict[int, list[tuple[int, FrameResult]]] = {}   # results settled before sending
    done: dict[int, list[tuple[int, FrameResult]]] = {}    # chunks finished, not yet yielded
    next_submit = next_yield = 0
    exhausted = False
    try:
        while True:
            while not exhausted and len(pending) + len(done) < ahead:
                group = next(groups, None)
                if group is None:
                    exhausted = True
                    break
                settled, future, frames = _submit(client, group, entry, params, temporal, want, confidence)
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
                finished, _ = wait(list(pending), return_when="FIRST_COMPLETED")
                for future in finished:
                    number, frames = pending.pop(future)
                    done[number] = known.pop(number) + _collect(future, frames)
                    future.release()
    finally:
        for future in pending:
            future.cancel()


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


def _chunks(tasks: Iterator, size: int) -> Iterator[list[tuple[int, Hashable, Any]]]:
    index = 0
    while True:
        group = []
        for key, loader in tasks:
            group.append((index, key, loader))
            index += 1
            if len(group) == size:
                break
        if not group:
            return
        yield group


def _submit(client, group, entry, params, temporal, want, confidence=False):
    """Load a chunk's frames here and send them: (results settled now, future or None, its frames)."""
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
            depth_lr, rgb_hr = loader()
        except (ValueError, TypeError, MemoryError) as exc:
            settled.append((order, FrameResult(key, None, error=_one_line(exc), bad_input=True)))
            continue
        items.append((order, key, depth_lr, rgb_hr, is_wanted))
    if not items:
        return settled, None, []
    [data] = client.scatter([items], hash=False)
    future = client.submit(_solve_chunk, entry, params, temporal, data, confidence, pure=False)
    return settled, future, [(order, key) for order, key, *_ in items]


def _collect(future, frames: list[tuple[int, Hashable]]) -> list[tuple[int, FrameResult]]:
    try:
        rows = future.result()
    except Exception as exc:  # noqa: BLE001 - a worker died or the task could not run
        message = f"internal error: the worker failed: {type(exc).__name__}: {_one_line(exc)}"
        return [(order, FrameResult(key, None, error=message)) for order, key in frames]
    return [(order, FrameResult(key, depth, seconds, error, bad, conf))
            for order, key, depth, seconds, error, bad, conf in rows]


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split()) or type(exc).__name__


def _solve_chunk(entry: Method, params: Any, temporal: bool, items: list, confidence: bool = False) -> list[tuple]:
    """On a worker: refine a chunk's frames in order (warm-starting them with ``temporal``), with their
    confidence maps when asked."""
    from .methods.confidence import confidence_of, method_with_confidence

    stateful = temporal and entry.refine_stateful is not None
    state = None
    rows = []
    for order, key, depth_lr, rgb_hr, is_wanted in items:
        start = time.perf_counter()
        try:
            check_call(entry, depth_lr, rgb_hr, params)
            conf = None
            if stateful:
                depth_hr, state = entry.refine_stateful(depth_lr, rgb_hr, params=params, state=state)
                if confidence and is_wanted:
                    conf = confidence_of(entry, depth_lr, rgb_hr, depth_hr, params=params)
            elif confidence and is_wanted:
                depth_hr, conf = method_with_confidence(entry, depth_lr, rgb_hr, params=params)
            else:
                depth_hr = entry.func(depth_lr, rgb_hr, params=params, progress=None)
        except (ValueError, TypeError, MemoryError) as exc:
            rows.append((order, key, None, time.perf_counter() - start, _one_line(exc), True, None))
            continue
        except Exception as exc:  # noqa: BLE001 - reported per frame as an internal error
            package = missing_dependency(exc)  # e.g. numba for the thesis method: the user can fix it
            message = (missing_dependency_message(package, exc) if package
                       else f"internal error: {type(exc).__name__}: {_one_line(exc)}")
            rows.append((order, key, None, time.perf_counter() - start, message, False, None))
            continue
        rows.append((order, key, depth_hr if is_wanted else None, time.perf_counter() - start, None, False, conf))
    return rows
