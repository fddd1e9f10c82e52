"""``vc run --cluster``: a Dask LocalCluster and a cluster started with Dask's own CLI (``dask scheduler``,
``dask worker``) give the report, the JUnit file and the traces of ``-j 1``; a worker killed in the middle of
the run loses no variant and its re-run is reported."""

from __future__ import annotations

import contextlib
import http.server
import io
import json
import os
import re
import signal
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path

import pytest
from rich.console import Console

from interfaces.links.inprocess import plc_programs
from vc.harness.targets import simulation_for
from vc.scenario.command import EXIT_FAILED, EXIT_PASSED, EXIT_PROBLEMS, run_command
from vc.scenario.distribution import cluster as cluster_module
from vc.scenario.distribution.cluster import (
    STARTED_TOPIC,
    Bundle,
    ClusterError,
    ClusterSettings,
    SharedFiles,
    check_scheduler,
    run_task,
)
from vc.scenario.distribution.parallel import MAX_WORKERS_PER_CORE, max_workers
from vc.scenario.distribution.tasks import SEND_ALL, Identity, RunSettings, ScenarioTask, identity_of
from vc.scenario.language.loader import load_scenarios
from vc.scenario.run.runner import trace_names

ROOT = Path(__file__).resolve().parents[4]
FILES = Path(__file__).resolve().parents[1] / "campaign_files"
CAMPAIGN = str((FILES / "jog_campaign.yaml").relative_to(ROOT))  # 20 variants, 5 of them fail
DWELL_CAMPAIGN = str((FILES / "jog_dwell_campaign.yaml").relative_to(ROOT))
WALL_TIME = re.compile(r"\d+\.\d+ s wall")
DASK = Path(sys.executable).parent / "dask"
START_TIMEOUT_S = 120.0
RUN_TIMEOUT_S = 600.0


@pytest.fixture(autouse=True)
def _in_repository(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)


def _run(paths: list[str], out: Path, traces: bool = True, **options: object) -> tuple[int, str]:
    output = io.StringIO()
    code = run_command(paths, simulation_for, plc_programs().keys(),  # type: ignore[arg-type]
                       console=Console(file=output, width=400), junit=out / "junit.xml",
                       trace_dir=out / "traces" if traces else None, **options)
    return code, output.getvalue()


def _same(text: str, directory: Path) -> str:
    """Without what differs between two runs of the same scenarios: wall times, the output directory."""
    text = WALL_TIME.sub("WALL", re.sub(r'time="[0-9.]+"', 'time="T"', text)).replace(str(directory), "OUT")
    return "\n".join(line for line in text.splitlines()
                     if not line.startswith(("starting a Dask", "Dask scheduler", "report:")))


def _assert_same_run(serial: Path, serial_report: str, other: Path, other_report: str) -> None:
    assert _same(other_report, other) == _same(serial_report, serial)
    assert _same((other / "junit.xml").read_text(), other) == _same((serial / "junit.xml").read_text(), serial)
    traces = sorted(path.name for path in (serial / "traces").iterdir())
    assert len(traces) == 3 * 20  # CSV, VCD and GTKWave save file of every variant
    assert traces == sorted(path.name for path in (other / "traces").iterdir())
    for name in traces:
        assert (other / "traces" / name).read_bytes() == (serial / "traces" / name).read_bytes(), name


@pytest.fixture(scope="module")
def serial_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    """The campaign with -j 1 in this process, its golden traces written first."""
    out = tmp_path_factory.mktemp("serial")
    os.chdir(ROOT)
    _run([CAMPAIGN], out, golden=str(out / "golden"), update_golden=True)
    code, report = _run([CAMPAIGN], out, golden=str(out / "golden"))
    assert code == EXIT_FAILED and "15 passed, 5 failed, 0 errors of 20 scenarios" in report, report
    return out, report


def test_a_local_cluster_gives_the_serial_report_junit_and_traces(serial_run: tuple[Path, str],
                                                                  tmp_path: Path) -> None:
    serial, serial_report = serial_run
    code, report = _run([CAMPAIGN], tmp_path, golden=str(serial / "golden"), cluster=ClusterSettings("local:2"))
    assert code == EXIT_FAILED
    assert "starting a Dask LocalCluster of 2 worker processes on 127.0.0.1" in report
    _assert_same_run(serial, serial_report, tmp_path, report)


def test_workers_on_a_shared_path_write_the_traces_themselves(serial_run: tuple[Path, str], tmp_path: Path,
                                                              dask_cli_cluster: str) -> None:
    check_scheduler(ClusterSettings(dask_cli_cluster))  # a real scheduler greets as one, and takes the answer
    serial, serial_report = serial_run
    code, report = _run([CAMPAIGN], tmp_path, golden=str(serial / "golden"),
                        cluster=ClusterSettings(dask_cli_cluster, "shared"))
    assert code == EXIT_FAILED
    _assert_same_run(serial, serial_report, tmp_path, report)


# ---------------------------------------------------------------------------------- the Dask CLI


class _Processes:
    def __init__(self) -> None:
        self.started: list[subprocess.Popen[bytes]] = []

    def start(self, *arguments: str, log: Path) -> subprocess.Popen[bytes]:
        handle = log.open("wb")
        process = subprocess.Popen([str(DASK), *arguments], stdout=handle, stderr=subprocess.STDOUT, cwd=log.parent)
        handle.close()
        self.started.append(process)
        return process

    def stop(self) -> None:
        for process in self.started:
            if process.poll() is None:
                process.kill()
        for process in self.started:
            process.wait(timeout=30)


def _wait_for(condition: object, what: str, timeout_s: float = START_TIMEOUT_S) -> None:
    deadline = time.monotonic() + timeout_s
    while not condition():  # type: ignore[operator]
        if time.monotonic() > deadline:
            raise AssertionError(f"{what} within {timeout_s:g} s")
        time.sleep(0.1)


@pytest.fixture(scope="module")
def dask_cli_cluster(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    """``dask scheduler`` and two ``dask worker`` processes on 127.0.0.1, ephemeral ports; the address."""
    from distributed import Client

    directory = tmp_path_factory.mktemp("dask")
    processes = _Processes()
    scheduler_file = directory / "scheduler.json"
    try:
        processes.start("scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard", "--dashboard-address",
                        "127.0.0.1:0", "--scheduler-file", str(scheduler_file), log=directory / "scheduler.log")
        _wait_for(lambda: scheduler_file.exists() and scheduler_file.stat().st_size > 0, "the scheduler started")
        address = json.loads(scheduler_file.read_text())["address"]
        for number in (1, 2):
            processes.start("worker", address, "--nthreads", "1", "--no-nanny", "--no-dashboard",
                            "--dashboard-address", "127.0.0.1:0", "--host", "127.0.0.1", "--name", f"w{number}",
                            log=directory / f"worker{number}.log")
        with Client(address, timeout="30s") as client:
            client.wait_for_workers(2, timeout=START_TIMEOUT_S)
        yield address
    finally:
        processes.stop()


def test_a_worker_killed_mid_run_loses_no_variant(dask_cli_cluster: str, tmp_path: Path) -> None:
    """The dwell campaign (each variant 15 s longer, 20 variants) through the vc command line on the CLI
    cluster; one worker is killed while it runs a variant: the JUnit file equals the serial run's and the
    re-run is named."""
    from distributed import Client

    serial = tmp_path / "serial"
    code, _ = _run([DWELL_CAMPAIGN], serial, traces=False)
    assert code == EXIT_FAILED
    vc = Path(sys.executable).parent / "vc"
    junit = tmp_path / "cluster" / "junit.xml"
    command = [str(vc), "run", DWELL_CAMPAIGN, "--cluster", dask_cli_cluster, "--junit", str(junit)]
    with Client(dask_cli_cluster, timeout="30s") as client:
        pids = client.run(os.getpid)
        since = time.time()
        run = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, cwd=ROOT)
        try:
            victim = ""

            def running_a_variant() -> bool:
                """A worker started a variant of this run (the task's own event; the scheduler also
                counts the next task it queued for the worker as processing)."""
                nonlocal victim
                for stamp, message in client.get_events(STARTED_TOPIC):
                    if stamp >= since and str(message["key"]).startswith("vc-scenario-") \
                            and message["worker"] in pids:
                        victim = message["worker"]
                        return True
                return False

            _wait_for(running_a_variant, "a worker ran a variant")
            os.kill(pids[victim], signal.SIGKILL)  # inside the variant: each takes 0.3 s and more
            output, _ = run.communicate(timeout=RUN_TIMEOUT_S)
        finally:
            if run.poll() is None:
                run.kill()
                run.wait(timeout=30)
    text = output.decode()
    assert run.returncode == EXIT_FAILED, text
    assert "15 passed, 5 failed, 0 errors of 20 scenarios" in text
    # one line: the variant the killed worker ran, not the one queued for it; both workers named by address
    reruns = [line for line in text.splitlines() if line.startswith("re-run: ")]
    assert len(reruns) == 1, text
    assert re.fullmatch(rf"re-run: JOG of X1 .*\[.*\]: the worker {re.escape(victim)} died while it had this task;"
                        r" it ran again on tcp://127\.0\.0\.1:\d+", reruns[0]), text
    assert _same(junit.read_text(), junit.parent) == _same((serial / "junit.xml").read_text(), serial)


# ---------------------------------------------------------------------------------- the task itself


def test_a_task_runs_from_its_sent_files_and_names_the_clients_files_again(tmp_path: Path) -> None:
    scenarios = load_scenarios([CAMPAIGN], plc_programs().keys())
    bundle = Bundle.of(scenarios, cwd=str(ROOT))
    assert {path for path, _ in bundle.files} == {CAMPAIGN, str((FILES / "jog_variants.yaml").relative_to(ROOT)),
                                                  "scenarios/machines/turn_mill.yaml"}
    settings = RunSettings(tuple(plc_programs()), simulation_for, send_back=SEND_ALL)
    failing = 19  # 40000 mm/min at 100 %: stopped by the limit switch
    names = trace_names(scenarios)
    task = ScenarioTask.of(failing, scenarios[failing], names[failing])
    os.chdir(tmp_path)  # nothing is read from the client's directory
    outcome = run_task(task, settings, bundle, identity_of(["basic_machine"]))
    assert not outcome.passed and outcome.mark is not None
    assert outcome.mark.file == str((FILES / "jog_variants.yaml").relative_to(ROOT))  # the client's name
    assert outcome.recording is not None and outcome.step_cycles
    result = outcome.result_for(scenarios[failing])
    assert result.failure is not None and result.failure.step is scenarios[failing].steps[5]
    assert result.recorder is not None and len(result.recorder.histories) > 1000


def test_a_worker_with_other_code_refuses_the_task() -> None:
    scenarios = load_scenarios([CAMPAIGN], plc_programs().keys())
    task = ScenarioTask.of(0, scenarios[0], "x")
    settings = RunSettings(tuple(plc_programs()), simulation_for)
    mine = identity_of(["basic_machine"])
    outcome = run_task(task, settings, SharedFiles(str(ROOT)), replace(mine, harness="0" * 64))
    assert not outcome.passed and "this worker runs other harness sources than the client" in outcome.error
    other = replace(mine, programs=(("basic_machine", "f" * 64),))
    outcome = run_task(task, settings, SharedFiles(str(ROOT)), other)
    assert "this worker's PLC program basic_machine differs from the client's" in outcome.error
    assert Identity(mine.harness, mine.programs).difference(mine) == ""


def test_a_cluster_that_cannot_be_used_is_a_clear_problem(tmp_path: Path) -> None:
    with pytest.raises(ClusterError, match="local:N starts N worker processes on this machine, from 1 to"):
        _ = ClusterSettings("local:0").local_workers
    code, report = _run([CAMPAIGN], tmp_path, cluster=ClusterSettings("local:x"))
    assert code == EXIT_PROBLEMS and "vc run: --cluster local:x: local:N starts N worker processes" in report
    assert EXIT_PASSED == 0


@pytest.mark.parametrize(("address", "message"), [
    ("garbage", "no host garbage"),
    ("http://", "a web address; the scheduler's address is tcp://HOST:8786"),
    ("https://127.0.0.1:8787/status", "a web address; the scheduler's address is tcp://HOST:8786"),
    ("tls://127.0.0.1:8786", "vc run reaches a scheduler over tcp:// only, not tls://"),
    ("ucx://127.0.0.1:8786", "vc run reaches a scheduler over tcp:// only, not ucx://"),
    ("tcp://", "not a scheduler address: tcp://HOST:PORT"),
    ("tcp://127.0.0.1:99999", "the port is a number from 1 to 65535"),
    ("127.0.0.1:1", "nothing listens at 127.0.0.1:1"),
    ("local:100000", f"from 1 to {max_workers()} ({MAX_WORKERS_PER_CORE} per core)"),
], ids=["garbage", "http", "https", "tls", "ucx", "no-host", "port", "nothing-listens", "local-100000"])
def test_an_address_that_names_no_scheduler_is_a_problem_before_the_run(address: str, message: str,
                                                                         tmp_path: Path) -> None:
    began = time.monotonic()
    code, report = _run([CAMPAIGN], tmp_path, traces=False, cluster=ClusterSettings(address))
    assert code == EXIT_PROBLEMS, report
    assert report.strip().startswith(f"vc run: --cluster {address}: ") and message in report, report
    assert "Traceback" not in report and time.monotonic() - began < 30


class _Banner(threading.Thread):
    """A service that greets every connection with a line of its own and closes it (an SSH server)."""

    def __init__(self, listener: socket.socket):
        super().__init__(daemon=True)
        self.listener = listener

    def run(self) -> None:
        with contextlib.suppress(OSError):
            while True:
                connection, _ = self.listener.accept()
                with connection:
                    connection.sendall(b"SSH-2.0-OpenSSH_9.2p1 Debian-2\r\n")


@pytest.mark.parametrize(("service", "message"), [
    ("http", "accepts connections but sends no Dask greeting within 1 s: not a Dask scheduler"),
    ("silent", "accepts connections but sends no Dask greeting within 1 s: not a Dask scheduler"),
    ("banner", "something answers at 127.0.0.1:{port}, but not a Dask scheduler (its first bytes are b'SSH-2.0-'"),
])
def test_a_service_that_is_no_dask_scheduler_is_refused_within_the_probe_time(
        service: str, message: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Dask itself tried to allocate 3.07 EiB on an HTTP server's answer and waited more than 200 s on a silent
    listener: the address is probed first, for as long as PROBE_TIMEOUT_S (1 s here)."""
    monkeypatch.setattr(cluster_module, "PROBE_TIMEOUT_S", 1.0)
    with contextlib.ExitStack() as stack:
        if service == "http":
            server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), http.server.SimpleHTTPRequestHandler)
            stack.callback(server.server_close)
            threading.Thread(target=server.serve_forever, daemon=True).start()
            stack.callback(server.shutdown)
            port = server.server_address[1]
        else:
            listener = stack.enter_context(socket.create_server(("127.0.0.1", 0)))
            port = listener.getsockname()[1]
            if service == "banner":
                _Banner(listener).start()
        began = time.monotonic()
        code, report = _run([CAMPAIGN], tmp_path, traces=False, cluster=ClusterSettings(f"tcp://127.0.0.1:{port}"))
    assert code == EXIT_PROBLEMS, report
    assert message.format(port=port) in report, report
    assert "Traceback" not in report and time.monotonic() - began < 20
