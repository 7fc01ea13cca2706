"""Before a sweep is submitted to a dask cluster: does every worker have the scene's plugins, at
the versions of this client? And, after it ran: where did it run?

A worker missing a plugin would otherwise fail the first task with ``No module named ...``
written only to the scheduler's log, and the client would see a long traceback ending in "lost
dependencies". :func:`check_workers` asks every worker once (``client.run``; 44-56 ms for two
local workers, best and worst of ten calls) for the versions of the
distributions that provide the scene's plugins (``importlib.metadata``) and whether their
modules import, and raises one :class:`WorkerEnvironmentError` whose message is one line naming
the worker, the distribution and the module.
"""

from __future__ import annotations

import sys
from collections.abc import Iterable
from typing import Any

__all__ = ["WorkerEnvironmentError", "check_workers", "ran_on", "requirements"]


class WorkerEnvironmentError(ValueError):
    """A dask worker lacks one of the scene's plugins, or has another version of it than the
    client; ``str(error)`` is one line naming the worker, the distribution and its module.
    (A ValueError, so the command line reports it as one line.)"""


def requirements(records: Iterable[Any]) -> dict[str, tuple[str, str]]:
    """``{distribution: (version, top-level module)}`` of a resolved scene's plugin records
    (``ResolvedScene.plugin_records``: ``(record, name)`` pairs or bare records)."""
    out: dict[str, tuple[str, str]] = {}
    for item in records:
        record = item[0] if isinstance(item, tuple) else item
        module = str(record.get("class", "")).partition(":")[0].partition(".")[0]
        dist = str(record.get("distribution") or module)
        out.setdefault(dist, (str(record.get("version", "")), module))
    return out


def _installed(wanted: dict[str, tuple[str, str]]) -> dict[str, Any]:
    """On a worker: ``{distribution: (installed version or None, module importable)}``, and
    under ``MACHINE`` its host name and boot id (as :func:`xpersson.sweep._shm.machine`).

    Only the standard library: this function travels by value (see :func:`check_workers`), so
    it runs on a worker that lacks xpersson itself."""
    import importlib.util
    import socket
    from importlib import metadata

    try:
        with open("/proc/sys/kernel/random/boot_id") as f:
            boot = f.read().strip()
    except OSError:
        boot = ""
    out: dict[str, Any] = {MACHINE: (socket.gethostname(), boot)}
    for dist, (_, module) in wanted.items():
        try:
            version: str | None = metadata.version(dist)
        except metadata.PackageNotFoundError:
            version = None
        try:
            found = bool(module) and importlib.util.find_spec(module) is not None
        except (ImportError, ValueError):
            found = False
        out[dist] = (version, found)
    return out


def _problem(worker: str, wanted: dict[str, tuple[str, str]], have: dict[str, Any]) -> str:
    """The first mismatch of one worker, as words ("" when it has everything)."""
    for dist, (version, module) in wanted.items():
        got, found = have.get(dist, (None, False))
        if got is None:
            return (
                f"worker {worker} lacks the plugin module {module!r} (distribution {dist} "
                f"{version} on this client, not installed there)"
            )
        if not found:
            return (
                f"worker {worker} cannot import the plugin module {module!r} (distribution "
                f"{dist} {got} is installed there, its module is not on the worker's path)"
            )
        if got != version:
            return f"worker {worker} has {dist} {got}, this client {version}"
    return ""


#: The key of a worker's machine (host name, boot id) in :func:`_installed`'s answer.
MACHINE = " machine"


def check_workers(client: Any, records: Iterable[Any]) -> dict[str, tuple[str, str]]:
    """Raise :class:`WorkerEnvironmentError` (one line) unless every worker of ``client`` has
    the distributions of the scene's plugin ``records`` at the client's versions; returns
    each worker's machine (host name, boot id), in the same round trip.

    Parameters
    ----------
    client : distributed.Client
        The client the sweep is submitted through.
    records : iterable
        The resolved scene's ``plugin_records`` (distribution, version and class of each
        plugin; xpersson itself is one of them for the built-in plugins).
    """
    import cloudpickle

    wanted = requirements(records)
    module = sys.modules[__name__]
    cloudpickle.register_pickle_by_value(module)  # the probe runs where xpersson is missing
    try:
        answers = client.run(_installed, wanted)
    finally:
        cloudpickle.unregister_pickle_by_value(module)
    problems = [p for w, have in sorted(answers.items()) if (p := _problem(w, wanted, have))]
    if problems:
        more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
        raise WorkerEnvironmentError(
            f"{problems[0]}{more}: install the same xpersson and plugin versions on every "
            "worker (see the user guide's 'Running on a cluster')"
        )
    return {w: tuple(have[MACHINE]) for w, have in answers.items()}


def ran_on(asked: Any, scheduler: Any, n_workers: int) -> str:
    """Where a sweep ran: ``"serial"``, ``"threads (2)"``, ``"tcp://... (2 workers)"``, with
    what was asked when it differs. A sweep that did not run where it was asked (a small study
    asked for processes, a client or an address runs serially, a memory-bound one on threads
    of this process) stores this as its
    ``xpersson_scheduler`` attribute; a sweep that ran where asked does not (its result stays
    identical, attributes included, to the serial one)."""
    if scheduler in (None, "serial", "synchronous", "sync"):
        where = "serial"
    elif scheduler == "threads":
        where = f"threads ({n_workers})"
    elif isinstance(scheduler, str):
        where = f"{scheduler} ({n_workers} workers)"
    else:  # a Client
        address = getattr(getattr(scheduler, "scheduler", None), "address", "a dask client")
        where = f"{address} ({n_workers} workers)"
    here = scheduler in (None, "threads")
    if asked == "processes" and here:
        where += " (asked: processes; the study takes less than starting the workers)"
    elif asked not in (None, "serial", "synchronous", "sync", "threads") and here:
        asked_where = ran_on(None, asked, n_workers).rsplit(" (", 1)[0]
        where += f" (asked: {asked_where}; the workers would not pay for this study)"
    return where
