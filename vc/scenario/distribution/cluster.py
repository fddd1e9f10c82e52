"""``vc run --cluster ADDRESS`` / ``--cluster local:N``: a run's scenarios and variants as tasks of
a Dask distributed cluster.

``ADDRESS`` is a scheduler started with Dask's own tools (``dask scheduler`` and, on every
machine, ``dask worker ADDRESS --nthreads 1``); ``local:N`` starts a ``LocalCluster`` of N
worker processes on this machine (127.0.0.1).  Every worker needs the same vc-harness installed
(``pip install 'vc-harness[cluster]'``): a worker whose harness or PLC program sources differ from
the client's refuses the task (:class:`~vc.scenario.distribution.tasks.Identity`), since the same variant
must give the same trace on any worker.

One task per scenario variant, :func:`run_task` (the task function of ``-j N`` too, see
:mod:`vc.scenario.distribution.tasks`).  The files a scenario reads reach the workers one of two ways
(``--cluster-files``):

* ``send`` (default): the scenario, campaign, machine and program files of the whole run go to
  every worker once (:class:`Bundle`, a task the others depend on), which writes them into a
  directory of its own and runs from there.  The recordings come back when traces or golden traces are asked for: the
  client writes the traces and compares the golden traces itself.
* ``shared``: the workers read the files at the client's paths (a shared file system mounted at
  the same place) and write the traces there themselves; only verdicts, and the recordings a
  golden comparison or a report needs, come back.

Results are reported in the scenarios' order, as the serial run reports them: the console
report, the JUnit file and the traces are those of ``-j 1``.  A worker that dies while it has a
task (killed, out of memory) loses nothing: the scheduler gives the task to another worker (up
to its ``allowed-failures``, after which the variant is reported as an error), and the run
names every such re-run after its summary.
"""

from __future__ import annotations

import atexit
import hashlib
import logging
import os
import shutil
import socket
import struct
import tempfile
import threading
import time as wallclock
import traceback
import urllib.parse
import uuid
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from interfaces.errors import VcError
from vc.scenario.distribution.parallel import MAX_WORKERS_PER_CORE, max_workers
from vc.scenario.distribution.tasks import (
    SEND_ALL,
    SEND_DIAGRAM,
    SEND_NOTHING,
    Identity,
    InOrder,
    RunSettings,
    ScenarioOutcome,
    ScenarioTask,
    ScenarioWorker,
    identity_of,
    rerun_lines,
)
from vc.scenario.language.model import Scenario
from vc.scenario.run.runner import RunInterrupted, RunObserver, ScenarioResult, finish, trace_names

LOCAL = "local:"
FILES_SEND = "send"
FILES_SHARED = "shared"
WORKER_WAIT_S = 60.0  # for the first worker to join the scheduler
CONNECT_TIMEOUT = "20s"
DEFAULT_SCHEDULER_PORT = 8786  # dask scheduler's
PROBE_TIMEOUT_S = 10.0  # for the scheduler to accept the connection and greet
MAX_GREETING_BYTES = 64 * 1024  # a scheduler's handshake has some 60 bytes
STARTED_TOPIC = "vc-task-started"  # the event a task logs when a worker starts it


class ClusterError(VcError):
    """The cluster cannot be used: Dask missing, no scheduler at the address, no worker joining."""


@dataclass(frozen=True, slots=True)
class ClusterSettings:
    address: str  # a scheduler address, or local:N
    files: str = FILES_SEND

    @property
    def local_workers(self) -> int | None:
        if not self.address.startswith(LOCAL):
            return None
        count = self.address[len(LOCAL):]
        most = max_workers()
        if not count.isdigit() or not 1 <= int(count) <= most:
            raise ClusterError(f"--cluster {self.address}: local:N starts N worker processes on this machine, from 1"
                               f" to {most} ({MAX_WORKERS_PER_CORE} per core), e.g. local:2")
        return int(count)

    def check(self) -> None:
        """Raise :class:`ClusterError` unless the address is local:N or a scheduler address (nothing connects)."""
        if self.local_workers is None:
            self.endpoint()

    def endpoint(self) -> tuple[str, int]:
        """The scheduler's host and port, from ``tcp://HOST:PORT`` or ``HOST:PORT`` (port 8786 when left
        out), checked before anything connects; raises :class:`ClusterError` for anything else."""
        address = self.address.strip()
        scheme, separator, rest = address.partition("://")
        if not separator:
            scheme, rest = "tcp", address
        scheme = scheme.lower()
        if scheme in ("http", "https"):
            raise ClusterError(f"--cluster {self.address}: a web address; the scheduler's address is"
                               f" tcp://HOST:{DEFAULT_SCHEDULER_PORT} ('Scheduler at:' when dask scheduler starts), the"
                               " dashboard's is http://HOST:8787")
        if scheme != "tcp":
            raise ClusterError(f"--cluster {self.address}: vc run reaches a scheduler over tcp:// only, not"
                               f" {scheme}://; give tcp://HOST:PORT, or local:N for a cluster on this machine")
        example = f"e.g. tcp://10.0.0.5:{DEFAULT_SCHEDULER_PORT}"
        try:
            parts = urllib.parse.urlsplit(f"tcp://{rest}")
            host, port = parts.hostname, parts.port
        except ValueError:
            raise ClusterError(f"--cluster {self.address}: the port is a number from 1 to 65535 ({example})") from None
        if not host or parts.path or parts.query or parts.fragment or parts.username is not None or port == 0:
            raise ClusterError(f"--cluster {self.address}: not a scheduler address: tcp://HOST:PORT ({example}),"
                               " or local:N")
        return host, port or DEFAULT_SCHEDULER_PORT


# ---------------------------------------------------------------------------------- files


@dataclass(frozen=True, slots=True)
class Bundle:
    """The files a run's scenarios read, as the client names them, with their contents."""

    cwd: str  # the client's working directory: what relative names are relative to
    files: tuple[tuple[str, bytes], ...]
    digest: str

    @classmethod
    def of(cls, scenarios: Sequence[Scenario], cwd: str | None = None) -> Bundle:
        paths = sorted({path for scenario in scenarios for path in scenario.sources})
        files = tuple((path, Path(path).read_bytes()) for path in paths)
        digest = hashlib.sha256()
        for path, content in files:
            digest.update(path.encode() + b"\0" + hashlib.sha256(content).digest())
        return cls(cwd or os.getcwd(), files, digest.hexdigest())

    @property
    def size(self) -> int:
        return sum(len(content) for _, content in self.files)


@dataclass(frozen=True, slots=True)
class SharedFiles:
    """The workers read the client's files where the client has them (a shared file system)."""

    cwd: str


_bundle_roots: dict[str, str] = {}  # this worker process's unpacked bundles: digest -> directory
_bundle_lock = threading.Lock()  # a worker may run tasks in several threads


def _locator(files: Bundle | SharedFiles) -> Callable[[str], str]:
    """Where a file the client names lies on this worker."""
    if isinstance(files, SharedFiles):
        return lambda path: os.path.normpath(os.path.join(files.cwd, path))
    with _bundle_lock:
        root = _bundle_roots.get(files.digest)
        if root is None:
            root = _unpack(files)
            _bundle_roots[files.digest] = root
    return lambda path: root + os.path.normpath(os.path.join(files.cwd, path))


def _unpack(bundle: Bundle) -> str:
    """The bundle's files under a directory of this process, at ``directory + absolute client path``:
    relative references between them (a scenario's ``../machines/x.yaml``) still hold."""
    root = tempfile.mkdtemp(prefix="vc-files-", dir=_scratch_space())
    atexit.register(shutil.rmtree, root, True)
    for path, content in bundle.files:
        target = Path(root + os.path.normpath(os.path.join(bundle.cwd, path)))
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(content)
    return root


def _scratch_space() -> str | None:
    """The Dask worker's own directory, which Dask removes with the worker (and, after a worker was
    killed, when the next one starts on the machine); None outside a worker: the system's temp."""
    try:
        from distributed import get_worker

        return str(get_worker().local_directory)
    except (ImportError, ValueError):
        return None


# ---------------------------------------------------------------------------------- worker


def _the_files(bundle: Bundle) -> Bundle:
    """The task that holds a run's bundle on the cluster (the tasks of the run depend on it)."""
    return bundle


_workers: dict[RunSettings, ScenarioWorker] = {}  # this process's worker state per run settings
_workers_lock = threading.Lock()


def run_task(task: ScenarioTask, settings: RunSettings, files: Bundle | SharedFiles,
             identity: Identity) -> ScenarioOutcome:
    """The cluster's task: one scenario variant, on whatever worker the scheduler chose."""
    address = _started()
    different = identity_of(name for name, _ in identity.programs).difference(identity)
    if different:
        return ScenarioOutcome(task.position, False, error=different, worker=address)
    with _workers_lock:
        worker = _workers.get(settings)
        if worker is None:
            worker = _workers[settings] = ScenarioWorker(settings)
    outcome = worker.run(task, _locator(files))
    return replace(outcome, worker=address) if address else outcome


def _started() -> str:
    """In a Dask worker: tell the client this worker holds the task now (so a worker that dies is
    charged only with what it held, not with the tasks queued for it); the worker's address."""
    try:
        from distributed import get_worker

        worker = get_worker()
    except (ImportError, ValueError):  # not on a Dask worker (a test calls the task itself)
        return ""
    worker.log_event(STARTED_TOPIC, {"key": str(worker.get_current_task()), "worker": worker.address})
    return str(worker.address)


# ---------------------------------------------------------------------------------- client


@dataclass(slots=True)
class ClusterRun:
    results: list[ScenarioResult]
    workers: int = 0  # worker processes when the run began
    reruns: dict[int, list[str]] = field(default_factory=dict)  # position -> workers that died while it had it
    ran_on: dict[int, str] = field(default_factory=dict)  # position -> the worker process that ran it
    submit_s: float = 0.0  # the client's time to prepare and hand over the tasks
    client_s: float = 0.0  # the client's time handling outcomes (unpickling, traces, golden, report)
    sent_bytes: int = 0  # the file bundle
    received_bytes: int = 0  # recordings sent back
    task_s: list[float] = field(default_factory=list)  # per task, its time on the worker
    run_s: list[float] = field(default_factory=list)  # per task, the run itself

    def rerun_lines(self, scenarios: Sequence[Scenario]) -> list[str]:
        """A sentence per re-run: which variant, which worker died, where it ran then."""
        return rerun_lines(scenarios, self.reruns, self.ran_on)


def worker_settings(settings: RunSettings, files: str, report: bool) -> RunSettings:
    """What the workers do of a client's settings: in ``send`` mode they write nothing and the
    client gets the recordings it needs; in ``shared`` mode they write the traces themselves."""
    if files == FILES_SHARED:
        send = SEND_ALL if settings.golden is not None else (SEND_DIAGRAM if report else SEND_NOTHING)
        return replace(settings, golden=None, send_back=send)
    wanted = settings.trace_dir is not None or settings.golden is not None
    return replace(settings, trace_dir=None, golden=None,
                   send_back=SEND_ALL if wanted else (SEND_DIAGRAM if report else SEND_NOTHING))


def run_on_cluster(scenarios: Sequence[Scenario], settings: RunSettings, cluster: ClusterSettings, *,
                   check: Callable[[ScenarioResult], None] | None = None, report: bool = False,
                   observer: RunObserver | None = None, say: Callable[[str], None] = lambda _: None) -> ClusterRun:
    """Run ``scenarios`` on the cluster; results in their order.  ``settings`` are the client's
    (its trace directory), ``check`` its golden comparison.  Raises :class:`ClusterError` when the
    cluster cannot be used, :class:`~vc.scenario.run.runner.RunInterrupted` with what finished after
    cancelling the tasks on Ctrl-C."""
    if cluster.files not in (FILES_SEND, FILES_SHARED):
        raise ClusterError(f"--cluster-files {cluster.files}: {FILES_SEND} or {FILES_SHARED}")
    began = wallclock.perf_counter()
    with _client(cluster, say) as client:
        from distributed import as_completed

        run = ClusterRun([], workers=len(client.scheduler_info().get("workers", {})))
        names = trace_names(scenarios)
        on_worker = worker_settings(settings, cluster.files, report)
        files: Bundle | SharedFiles = SharedFiles(os.getcwd())
        if cluster.files == FILES_SEND:
            bundle = Bundle.of(scenarios)
            run.sent_bytes = bundle.size
            files = bundle
        identity = identity_of({scenario.plc for scenario in scenarios if scenario.plc_program is not None})
        lost = _Losses()
        client.subscribe_topic("all", lost.event)
        client.subscribe_topic(STARTED_TOPIC, lost.started)
        token = uuid.uuid4().hex[:12]
        in_order = InOrder(scenarios, observer)
        futures: dict[Any, int] = {}
        try:
            # the bundle as a task of its own, not scattered: a worker that fetched it and died is no
            # loss, the scheduler has the bundle in the task and computes it again
            shipped: Any = files
            if isinstance(files, Bundle):
                shipped = client.submit(_the_files, files, key=f"vc-files-{token}", pure=False)
            for position, scenario in enumerate(scenarios):
                task = ScenarioTask.of(position, scenario, names[position])
                key = f"vc-scenario-{token}-{position}"
                futures[client.submit(run_task, task, on_worker, shipped, identity, key=key, pure=False)] = position
            run.submit_s = wallclock.perf_counter() - began
            trace_dir = Path(settings.trace_dir) if settings.trace_dir is not None else None
            # the results are fetched by the client's event loop as they come, not one call per future
            for future, value in as_completed(futures, with_results=True, raise_errors=False):
                handling = wallclock.perf_counter()
                position = futures.pop(future)
                outcome = _outcome_of(value, position)
                future.release()
                result = outcome.result_for(scenarios[position])
                if outcome.recording is not None:
                    run.received_bytes += outcome.recording.size
                if cluster.files == FILES_SEND:
                    finish(result, trace_dir, names[position], check)
                else:
                    written = list(outcome.trace_files)
                    finish(result, None, names[position], check)
                    if written and trace_dir is not None:
                        result.trace_files = [str(trace_dir / Path(path).name) for path in written]
                result.recorder = result.recorder if report else None
                if outcome.worker:
                    run.ran_on[position] = outcome.worker
                run.task_s.append(outcome.task_s)
                run.run_s.append(outcome.wall_s)
                in_order.put(position, result)
                run.client_s += wallclock.perf_counter() - handling
        except KeyboardInterrupt:
            client.cancel(list(futures), force=True)
            in_order.report_rest()
            raise RunInterrupted(in_order.finished()) from None
        finally:
            client.unsubscribe_topic("all")
            client.unsubscribe_topic(STARTED_TOPIC)
        run.results = in_order.finished()
        run.reruns = lost.reruns(token)
    return run


def _outcome_of(value: Any, position: int) -> ScenarioOutcome:
    """The task's outcome; for a task that failed, Dask's (type, exception, traceback)."""
    from distributed import KilledWorker

    if isinstance(value, ScenarioOutcome):
        return value
    error = value[1] if isinstance(value, tuple) and len(value) == 3 else value
    if isinstance(error, KilledWorker):
        return ScenarioOutcome(position, False, error=f"the workers running this scenario died again and again:"
                                                      f" {error}")
    if isinstance(error, BaseException):  # the task could not run, or its outcome could not come back
        return ScenarioOutcome(position, False, error="".join(traceback.format_exception(error)))
    return ScenarioOutcome(position, False, error=f"the cluster gave no outcome for this scenario: {value!r}")


class _Losses:
    """The scheduler's "remove-worker" events and the tasks' own "started" events: which task each
    lost worker held.  The scheduler counts every task it had assigned to the worker (a worker of
    one thread is given the next one before the first ends); only the one it ran is a re-run."""

    def __init__(self) -> None:
        self.lost: list[tuple[str, tuple[str, ...]]] = []  # (worker, keys it was processing)
        self.started_on: dict[str, set[str]] = {}  # key -> the workers that started it

    def event(self, event: tuple[float, Any]) -> None:
        _, message = event
        if isinstance(message, dict) and message.get("action") == "remove-worker" \
                and not message.get("expected", False):
            self.lost.append((str(message.get("worker", "?")), tuple(str(key) for key in
                                                                     message.get("processing-tasks", ()))))

    def started(self, event: tuple[float, Any]) -> None:
        _, message = event
        if isinstance(message, dict):
            self.started_on.setdefault(str(message.get("key")), set()).add(str(message.get("worker")))

    def reruns(self, token: str) -> dict[int, list[str]]:
        prefix = f"vc-scenario-{token}-"
        found: dict[int, list[str]] = {}
        for worker, keys in self.lost:
            ours = [key for key in keys if key.startswith(prefix)]
            held = [key for key in ours if worker in self.started_on.get(key, ())]
            if not held and len(ours) == 1:  # it died before its "started" reached us; it held only that one
                held = ours
            for key in held:
                found.setdefault(int(key[len(prefix):]), []).append(worker)
        return found


def check_scheduler(cluster: ClusterSettings) -> None:
    """Whether a Dask scheduler answers at the address, before Dask itself connects: Dask's client
    writes first and then takes the first 8 bytes it reads as the length of the answer, so an HTTP
    server's "HTTP/1.1" made it allocate exabytes, and a listener that says nothing kept it waiting
    for minutes.  A scheduler greets first: 8 bytes of length (little-endian) and its handshake of a
    few dozen bytes.  The check reads that within :data:`PROBE_TIMEOUT_S` and answers with the
    scheduler's own greeting, so the scheduler sees a complete handshake; anything else is a
    :class:`ClusterError` that says what answered."""
    host, port = cluster.endpoint()
    where = f"--cluster {cluster.address}"
    try:
        connection = socket.create_connection((host, port), timeout=PROBE_TIMEOUT_S)
    except socket.gaierror as error:
        raise ClusterError(f"{where}: no host {host} ({error.strerror})") from None
    except ConnectionRefusedError:
        raise ClusterError(f"{where}: nothing listens at {host}:{port} (start the scheduler there: dask scheduler)"
                           ) from None
    except OSError as error:  # a time-out, a network that cannot be reached
        reason = error.strerror or f"no answer within {PROBE_TIMEOUT_S:g} s"
        raise ClusterError(f"{where}: {host}:{port} cannot be reached ({reason})") from None
    with connection:
        try:
            head = _received(connection, 8)
            (length,) = struct.unpack("<Q", head)
            if not 0 < length <= MAX_GREETING_BYTES:
                raise ClusterError(f"{where}: something answers at {host}:{port}, but not a Dask scheduler (its"
                                   f" first bytes are {head!r})")
            connection.sendall(head + _received(connection, length))
        except TimeoutError:
            raise ClusterError(f"{where}: {host}:{port} accepts connections but sends no Dask greeting within"
                               f" {PROBE_TIMEOUT_S:g} s: not a Dask scheduler (a web server, the dashboard's port?)"
                               ) from None
        except (EOFError, OSError):
            raise ClusterError(f"{where}: {host}:{port} closed the connection without a Dask greeting: not a Dask"
                               " scheduler") from None


def _received(connection: socket.socket, count: int) -> bytes:
    data = b""
    while len(data) < count:
        chunk = connection.recv(count - len(data))
        if not chunk:
            raise EOFError
        data += chunk
    return data


@contextmanager
def _client(cluster: ClusterSettings, say: Callable[[str], None]) -> Iterator[Any]:
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise ClusterError("vc run --cluster needs Dask: pip install 'vc-harness[cluster]'") from None
    count = cluster.local_workers
    if count is not None:
        say(f"starting a Dask LocalCluster of {count} worker processes on 127.0.0.1")
        # no dashboard; the scheduler's HTTP routes (health, metrics) on an ephemeral loopback port, not 8787
        with LocalCluster(n_workers=count, threads_per_worker=1, processes=True, host="127.0.0.1",
                          dashboard_address=None, silence_logs=logging.ERROR,
                          scheduler_kwargs={"dashboard": False, "dashboard_address": "127.0.0.1:0"},
                          worker_dashboard_address="127.0.0.1:0") as local, Client(local) as client:
            yield client
        return
    check_scheduler(cluster)
    try:
        client = Client(cluster.address, timeout=CONNECT_TIMEOUT)
    except (OSError, ValueError) as error:  # gone since the check; a scheduler of another Dask version
        raise ClusterError(f"--cluster {cluster.address}: the Dask scheduler there cannot be used ({error})") from None
    with client:
        try:
            client.wait_for_workers(1, timeout=WORKER_WAIT_S)
        except TimeoutError:
            raise ClusterError(f"--cluster {cluster.address}: no worker joined the scheduler within"
                               f" {WORKER_WAIT_S:g} s (start them with: dask worker {cluster.address}"
                               " --nthreads 1)") from None
        say(f"Dask scheduler {cluster.address}, {len(client.scheduler_info().get('workers', {}))} workers")
        yield client
