"""The ``vc`` command line: run scenarios, print the signal map, measure the speed.

    vc run PATH... [-j N | --cluster ADDRESS|local:N [--cluster-files send|shared]] [--junit FILE]
           [--trace-dir DIR] [--report DIR] [--golden DIR [--update-golden]] [--link inprocess|modbus|can
           [--can-bus BUS]] [--coverage FILE] [--max-variants N] [-k EXPRESSION] [--shard I/N]
                                                      run scenario files, campaign files or directories
    vc run --plot SCENARIO [--plot-to FILE]           one scenario's timing diagram
    vc coverage report FILE... [--json OUT] [--html OUT] [--fail-under PCT] [--fail-under-function NAME=PCT]
                                                      the interface coverage of runs (docs/coverage.md)
    vc map --machine M [--format md|csv|json|dbc|guide]
                                                      the machine's expanded signal map, its CAN frames as a
                                                      DBC file, or the guide for connecting OpenPLC / CODESYS
                                                      over Modbus TCP
    vc map --machine M --format codesys|openplc|tia|s7|awlsim [--io-base N] [-o FILE]
                                                      the signal map for a PLC tool (docs/plc_tools.md)
    vc serve [--machine M] [--modbus HOST:PORT] [--s7 HOST:PORT] [--can BUS] [--realtime [--speed F]]
             [--scenario FILE [--junit FILE] [--keep-running]] [--duration S] [--record FILE [--record-limit MIB]]
             [--allow IP,...] [--allow-writers IP,...] [--plc-key-file FILE] [--max-clients N] [--idle-timeout S]
             [--cpu LIST] [--fifo PRIORITY] [--verbose]
                                                      the NC as a server (or CAN node) for a PLC in another
                                                      process; with a scenario the exit code is its result;
                                                      --record records the session
    vc replay FILE [--machine M] [--to-scenario OUT.yaml [--name NAME]]
                                                      replay a recorded session without the PLC and report the
                                                      first difference, or turn it into a scenario
                                                      (docs/recording.md)
    vc bench [--machine M] [--seconds S]              real-time factor and cost per IPO cycle, light and heavy
    vc bench --scaling [--machine M] [--seconds S]
                                                      the cost per IPO cycle by what moves, per machine
    vc bench --link modbus [--seconds S]              what the Modbus TCP link costs (bench/README.md)
    vc bench --link can [--seconds S]                 frames per second and cost per IPO cycle of the CAN link
    vc bench --link fmu [--seconds S] [--python host] FMU steps per second under FMPy against in process
    vc fmu export --machine M -o M.fmu [--fmi 3] [--python host]
                                                      the NC and the plant as an FMI co-simulation FMU,
                                                      self-contained (or lean: runs in the host's Python)

M is a machine file or the name of a machine the package ships (turn_mill, the default,
mill_3axis, mill_5axis, gantry_mill), found from any directory.

Problems in input files are reported with file, line and column and exit with code 2;
a failed scenario exits with 1.
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import platform
import sys
from collections.abc import Callable, Mapping, Sequence
from importlib import metadata
from typing import TYPE_CHECKING, Protocol

from interfaces.catalog import load_catalog
from interfaces.exports import EXPORTS, Export, ExportContext
from interfaces.links import INPROCESS, LINKS
from interfaces.links.modbus.access import DEFAULT_IDLE_TIMEOUT_S, DEFAULT_MAX_CLIENTS
from interfaces.links.modbus.codec import RegisterMap
from interfaces.signal_map import MapRow, map_rows
from interfaces.signals import expand
from vc.cli.map_formats import FORMATTERS
from vc.config.loader import load_machine
from vc.config.machine_files import DEFAULT_MACHINE, packaged_machines
from vc.input_limits import MAX_RECORDING_BYTES, MAX_RUN_VARIANTS
from vc.located_yaml import SourceError
from vc_build import status as build_status

if TYPE_CHECKING:
    from vc.harness.links.modbus import Endpoint
    from vc.simulation.observed import SimulationObserver
    from vc.ui.server import UiServer

GUIDE_FORMAT = "guide"  # vc map --format guide: docs/modbus.md for the machine
DBC_FORMAT = "dbc"  # vc map --format dbc: the CAN frames through cantools
DEFAULT_BENCH_SECONDS = 30.0  # simulated, in process, per workload
DEFAULT_UI_PORT = 8080  # vc serve --ui: the operator page
DEFAULT_RECORD_LIMIT_MIB = 256  # vc serve --record-limit: some 40 minutes of a busy PLC
DEFAULT_SCALING_SECONDS = 10.0  # simulated, per machine and load of --scaling
DEFAULT_REALTIME_BENCH_SECONDS = 60.0  # wall-clock, the real-time measurement of --link modbus
DEFAULT_FMU_BENCH_SECONDS = 20.0  # simulated, per workload of --link fmu
DEFAULT_CAN_BENCH_SECONDS = 10.0  # simulated, per bus of --link can
EXIT_PROBLEMS = 2
EXIT_FAILED = 1  # a scenario failed, a benchmark's workload did not move as it should


def _map(arguments: argparse.Namespace) -> int:
    machine = load_machine(arguments.machine)
    catalog = expand(load_catalog(), machine.layout)
    if arguments.format == GUIDE_FORMAT:
        from vc.cli.modbus_guide import modbus_guide  # it imports the NC core: only for this format
        from vc.simulation.commissioning import commissioning_of

        _write(modbus_guide(machine.name, machine.source, catalog, machine.plant_io,
                            commissioning_of(machine, catalog)), arguments.output)
        return 0
    can = machine.can
    if arguments.format == DBC_FORMAT:
        from interfaces.links.can.codec import CanLayout
        from interfaces.links.can.dbc import dbc_text
        from vc.config.model import machine_ipo_cycle_us

        ipo_us = machine_ipo_cycle_us(machine)
        layout = CanLayout.build(catalog, machine.plant_io.area_sizes(), can.settings)
        _write(dbc_text(layout, catalog, machine.plant_io,
                        nc_cycle_ms=round(can.period_cycles(ipo_us, machine.plc_cycle_ipo) * ipo_us / 1000),
                        plc_cycle_ms=round(machine.plc_cycle_ipo * ipo_us / 1000)), arguments.output)
        return 0
    from vc.simulation.commissioning import commissioning_of  # the facts need the NC's rules

    rows = map_rows(catalog, machine.plant_io, can.settings, commissioning_of(machine, catalog))
    if arguments.format in EXPORTS:
        return _export(EXPORTS[arguments.format], rows, ExportContext(
            machine.name, RegisterMap.build(catalog, machine.plant_io.area_sizes()), arguments.io_base or 0),
            arguments)
    if arguments.io_base is not None:
        print(f"vc map: --io-base applies to {', '.join(n for n, e in EXPORTS.items() if e.uses_io_base)}",
              file=sys.stderr)
        return EXIT_PROBLEMS
    _write(FORMATTERS[arguments.format](rows), arguments.output)
    return 0


def _export(export: Export, rows: Sequence[MapRow], context: ExportContext, arguments: argparse.Namespace) -> int:
    """One of the exports for PLC tools (interfaces/exports)."""
    if arguments.io_base is not None and not export.uses_io_base:
        print(f"vc map: --io-base does not apply to --format {export.name} (its addresses are the tool's own)",
              file=sys.stderr)
        return EXIT_PROBLEMS
    if export.binary and arguments.output is None:
        print(f"vc map: --format {export.name} writes a binary file: give -o FILE{export.suffix}", file=sys.stderr)
        return EXIT_PROBLEMS
    from interfaces.exports.tia import MissingExtra

    try:
        content = export.write(rows, context)
    except (MissingExtra, ValueError) as error:
        print(f"vc map: {error}", file=sys.stderr)
        return EXIT_PROBLEMS
    _write(content, arguments.output)
    return 0


def _write(content: str | bytes, output: str | None) -> None:
    """To the file ``output`` (text as written, line ends kept), else to standard output."""
    if output is not None:
        with open(output, "wb") as file:
            file.write(content if isinstance(content, bytes) else content.encode())
    elif isinstance(content, bytes):
        sys.stdout.buffer.write(content)
    else:
        sys.stdout.write(content)


def _bench(arguments: argparse.Namespace) -> int:
    if arguments.scaling:
        if arguments.link != "inprocess":
            print(f"vc bench: --scaling measures the simulation in process, not --link {arguments.link}",
                  file=sys.stderr)
            return EXIT_PROBLEMS
        return _bench_scaling(arguments)
    if arguments.machine is None:  # --scaling alone runs several machines
        arguments.machine = DEFAULT_MACHINE
    if arguments.link == "modbus":
        return _bench_modbus(arguments)
    if arguments.link == "fmu":
        return _bench_fmu(arguments)
    if arguments.link == "can":
        return _bench_can(arguments)
    from vc.bench.lockstep import BenchmarkError, run_light_and_heavy

    seconds = DEFAULT_BENCH_SECONDS if arguments.seconds is None else arguments.seconds
    try:
        light, heavy = run_light_and_heavy(arguments.machine, seconds)
    except BenchmarkError as error:
        print(f"vc bench: {error}", file=sys.stderr)
        return EXIT_FAILED
    print(f"vc {_version()}, {build_status().describe()}, Python {platform.python_version()}")
    print(f"machine {light.machine}, IPO cycle {light.ipo_cycle_us} us, {seconds:g} s simulated per workload")
    for name, result in (("light", light), ("heavy", heavy)):
        print(f"{name}: {result.plan.describe()}, built-in PLC {result.plc}: real-time factor"
              f" {result.realtime_factor:.1f}x, {result.us_per_cycle:.1f} us per IPO cycle"
              f" ({result.cycles} IPO cycles in {result.wall_s:.3f} s)")
    print(json.dumps({"realtime_factor": round(light.realtime_factor, 1),
                      "us_per_cycle": round(light.us_per_cycle, 2),
                      "heavy_realtime_factor": round(heavy.realtime_factor, 1),
                      "heavy_us_per_cycle": round(heavy.us_per_cycle, 2),
                      "build": _build_name()}))
    return 0


def _bench_scaling(arguments: argparse.Namespace) -> int:
    """The cost per IPO cycle of each machine idle, with two axes and with everything moving."""
    from vc.bench.lockstep import BenchmarkError
    from vc.bench.scaling import (
        SCALING_MACHINES,
        SCALING_PLC,
        row_figures,
        run_scaling,
        scaling_table,
    )

    seconds = DEFAULT_SCALING_SECONDS if arguments.seconds is None else arguments.seconds
    machines = SCALING_MACHINES if arguments.machine is None else (arguments.machine,)
    try:
        rows = run_scaling(machines, seconds)
    except BenchmarkError as error:
        print(f"vc bench: {error}", file=sys.stderr)
        return EXIT_FAILED
    print(f"vc {_version()}, {build_status().describe()}, Python {platform.python_version()}")
    print(f"built-in PLC {SCALING_PLC}, {seconds:g} s simulated per row")
    print(scaling_table(rows))
    print(json.dumps({"build": _build_name(), "scaling": [row_figures(row) for row in rows]}))
    return 0


def _build_name() -> str:
    return "compiled" if build_status().compiled else "pure"


class HasFigures(Protocol):
    def figures(self) -> Mapping[str, object]: ...


def _figures_of(run: Callable[[], HasFigures], errors: tuple[type[Exception], ...]) -> int:
    """Run a link benchmark and print its figures as one JSON line (its progress goes before)."""
    try:
        result = run()
    except errors as error:
        print(f"vc bench: {error}", file=sys.stderr)
        return EXIT_PROBLEMS
    print(json.dumps(result.figures()))
    return 0


def _say(text: str) -> None:
    print(text, flush=True)


def _bench_modbus(arguments: argparse.Namespace) -> int:
    from interfaces.links.errors import LinkError
    from vc.bench.modbus_link import run_link_benchmark

    seconds = DEFAULT_REALTIME_BENCH_SECONDS if arguments.seconds is None else arguments.seconds
    return _figures_of(lambda: run_link_benchmark(arguments.machine, realtime_seconds=seconds,
                                                  lockstep_seconds=arguments.lockstep_seconds,
                                                  exchanges=arguments.exchanges, say=_say),
                       (LinkError, ValueError))


def _bench_can(arguments: argparse.Namespace) -> int:
    from interfaces.links.errors import LinkError
    from vc.bench.can_link import run_can_benchmark

    seconds = DEFAULT_CAN_BENCH_SECONDS if arguments.seconds is None else arguments.seconds
    return _figures_of(lambda: run_can_benchmark(arguments.machine, seconds, frames=arguments.frames, say=_say),
                       (LinkError,))


def _bench_fmu(arguments: argparse.Namespace) -> int:
    from fmu.export import PythonRuntime
    from fmu.instance import FmuError
    from vc.bench.fmu_steps import FmuBenchmarkError, run_fmu_benchmark

    seconds = DEFAULT_FMU_BENCH_SECONDS if arguments.seconds is None else arguments.seconds
    python = PythonRuntime(arguments.python)
    return _figures_of(lambda: run_fmu_benchmark(arguments.machine, seconds, say=_say, python=python),
                       (FmuBenchmarkError, FmuError))


def _fmu_export(arguments: argparse.Namespace) -> int:
    from fmu.export import PythonRuntime, export_fmu
    from fmu.instance import FmuError

    try:
        result = export_fmu(arguments.machine, arguments.output, PythonRuntime(arguments.python), arguments.fmi)
    except FmuError as error:
        print(f"vc fmu export: {error}", file=sys.stderr)
        return EXIT_PROBLEMS
    print(result.summary())
    return 0


def _positive(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None
    if not value > 0:
        raise argparse.ArgumentTypeError(f"{text}: must be greater than 0")
    return value


def _shard(text: str) -> object:
    from vc.scenario.language.selection import SelectionError, Shard

    try:
        return Shard.parse(text)
    except SelectionError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def _whole(lowest: int, highest: int | None = None, unit: str = "") -> Callable[[str], int]:
    """An argument type: a whole number from ``lowest`` (to ``highest``, ``unit`` said after it)."""
    def whole(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"'{text}' is not a whole number") from None
        if value < lowest or (highest is not None and value > highest):
            raise argparse.ArgumentTypeError(f"{text}: at least {lowest}" if highest is None else
                                             f"{text}: from {lowest} to {highest}{unit}")
        return value
    return whole


def _jobs(text: str) -> int:
    from vc.scenario.distribution.parallel import MAX_WORKERS_PER_CORE, max_workers

    return _whole(1, max_workers(), f" ({MAX_WORKERS_PER_CORE} worker processes per core)")(text)


def _version() -> str:
    try:
        return metadata.version("vc-harness")
    except metadata.PackageNotFoundError:
        return "(not installed)"


def _byte_offset(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a byte number") from None
    if not 0 <= value <= 65535:
        raise argparse.ArgumentTypeError(f"{text}: a byte number 0..65535")
    return value


def _run(arguments: argparse.Namespace) -> int:
    from vc.harness.scenarios import run_scenario_files

    if arguments.update_golden and not arguments.golden:
        print("--update-golden needs --golden DIR", file=sys.stderr)
        return EXIT_PROBLEMS
    if arguments.can_bus is not None and arguments.link != "can":
        print("--can-bus needs --link can", file=sys.stderr)
        return EXIT_PROBLEMS
    from interfaces.links.errors import LinkError

    if arguments.link != INPROCESS and arguments.jobs not in (None, 1):
        print(f"vc run: -j runs scenarios in process; with --link {arguments.link} they run one after another"
              " behind one PLC process", file=sys.stderr)
    if arguments.cluster is not None and (arguments.link != INPROCESS or arguments.jobs is not None):
        print("vc run: --cluster runs the scenarios on the cluster's workers, with the PLC in process: it takes"
              " neither -j nor --link", file=sys.stderr)
        return EXIT_PROBLEMS
    if arguments.plot is not None:
        from vc.harness.scenarios import plot_scenario

        if arguments.paths:
            print("vc run --plot SCENARIO runs that one scenario; leave out the other paths", file=sys.stderr)
            return EXIT_PROBLEMS
        return plot_scenario(arguments.plot, arguments.plot_to)
    if not arguments.paths:
        print("vc run: name scenario files or directories (or --plot SCENARIO)", file=sys.stderr)
        return EXIT_PROBLEMS
    from vc.scenario.language.selection import Selection, SelectionError

    try:
        selection = Selection(arguments.keyword, arguments.shard) \
            if arguments.keyword is not None or arguments.shard is not None else None
    except SelectionError as error:
        print(f"vc run: {error}", file=sys.stderr)
        return EXIT_PROBLEMS
    collector = None
    if arguments.coverage is not None:
        from vc.coverage.collector import CoverageCollector

        collector = CoverageCollector()
    try:
        code = run_scenario_files(arguments.paths, junit=arguments.junit, trace_dir=arguments.trace_dir,
                                  golden=arguments.golden, update_golden=arguments.update_golden, link=arguments.link,
                                  can_bus=arguments.can_bus, jobs=arguments.jobs, cluster=arguments.cluster,
                                  cluster_files=arguments.cluster_files, report_dir=arguments.report,
                                  observe=collector.observe if collector else None,
                                  max_variants=arguments.max_variants, selection=selection)
    except LinkError as error:
        print(f"vc run: {error}", file=sys.stderr)
        return EXIT_PROBLEMS
    if collector is not None and collector.data.scenarios:
        from vc.coverage.report import build_report

        collector.data.save(arguments.coverage)
        total = build_report(collector.data).total
        print(f"interface coverage {total.percent:.1f} % ({total.covered} of {total.total} points) written to"
              f" {arguments.coverage} (vc coverage report {arguments.coverage} shows it)")
    return code


def _coverage_report(arguments: argparse.Namespace) -> int:
    from vc.coverage.command import coverage_report, parse_function_threshold

    try:
        thresholds = dict(parse_function_threshold(text) for text in arguments.fail_under_function)
    except ValueError as error:
        print(f"vc coverage report: {error}", file=sys.stderr)
        return EXIT_PROBLEMS
    return coverage_report(arguments.files, json_path=arguments.json, html_path=arguments.html,
                           fail_under=arguments.fail_under, fail_under_function=thresholds,
                           complain=lambda text: print(text, file=sys.stderr))


def _percent(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None
    if not 0 <= value <= 100:
        raise argparse.ArgumentTypeError(f"{text}: a percentage 0..100")
    return value


class _Given(argparse.Action):
    """Stores the value and that it was given (``<dest>_given``): a default is no choice of the user's."""

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace, values: object,
                 option_string: str | None = None) -> None:
        setattr(namespace, self.dest, values)
        setattr(namespace, f"{self.dest}_given", True)


def _serve(arguments: argparse.Namespace) -> int:
    if (arguments.junit or arguments.keep_running) and not arguments.scenario:
        print("--junit and --keep-running need --scenario", file=sys.stderr)
        return EXIT_PROBLEMS
    from interfaces.links.can.bus import BusSpec
    from interfaces.links.errors import LinkError
    from interfaces.links.modbus.access import ConnectionLimits, key_file
    from interfaces.links.scheduling import parse_cpus, parse_priority
    from vc.harness.links.modbus import Endpoint
    from vc.harness.serve import ServeOptions, serve

    recorder = None
    operator_page: UiServer | None = None
    if arguments.ui is not None:
        from vc.ui import missing_ui_extra

        missing = missing_ui_extra()
        if missing is not None:
            print(f"vc serve: {missing}", file=sys.stderr)
            return EXIT_PROBLEMS
    if arguments.verbose:
        logging.basicConfig(level=logging.INFO, format="%(name)s: %(message)s")
    try:
        if arguments.record is not None:
            from vc.recording.command import session_recorder

            link = "can" if arguments.can else "modbus" if arguments.modbus or not arguments.s7 else "s7"
            recorder = session_recorder(arguments.record, arguments.scenario, link, arguments.realtime,
                                        arguments.record_limit << 20, lambda text: print(text, file=sys.stderr))
        observer: SimulationObserver | None = recorder
        if arguments.ui is not None:
            operator_page = _operator_page(Endpoint.parse(arguments.ui, DEFAULT_UI_PORT),
                                           _addresses(arguments.allow_writers), recorder)
            observer = operator_page.bridge
        options = ServeOptions(
            machine_path=arguments.machine,
            machine_given=arguments.machine_given,
            plc_key=key_file(arguments.plc_key_file) if arguments.plc_key_file else None,
            cpus=parse_cpus(arguments.cpu) if arguments.cpu else None,
            fifo_priority=parse_priority(arguments.fifo) if arguments.fifo else None,
            modbus=Endpoint.parse(arguments.modbus, 5020) if arguments.modbus else None,
            s7=Endpoint.parse(arguments.s7, 102) if arguments.s7 else None,
            can=BusSpec.parse(arguments.can) if arguments.can else None,
            allow_remote=arguments.allow_remote,
            allowed_clients=_addresses(arguments.allow),
            allow_writers=_addresses(arguments.allow_writers),
            limits=ConnectionLimits(arguments.max_clients, arguments.idle_timeout),
            realtime=arguments.realtime,
            speed=None if arguments.speed == "max" else _speed(arguments.speed),
            program=arguments.program,
            scenario=arguments.scenario,
            keep_running=arguments.keep_running,
            junit=arguments.junit,
            duration_s=arguments.duration,
            stats_every_s=arguments.stats,
            say=lambda text: print(text, flush=True),
            observer=observer,
        )
        return serve(options)
    except (LinkError, ValueError) as error:
        print(f"vc serve: {error}", file=sys.stderr)
        return EXIT_PROBLEMS
    except OSError as error:  # the recording cannot be written
        print(f"vc serve: {error.filename}: {error.strerror}", file=sys.stderr)
        return EXIT_PROBLEMS
    finally:
        if operator_page is not None:
            operator_page.stop()
        if recorder is not None and recorder.writer is not None:
            recorder.close()
            print(f"session recorded in {arguments.record} (vc replay {arguments.record})", flush=True)


def _operator_page(endpoint: Endpoint, allow_writers: tuple[str, ...],
                   recorder: SimulationObserver | None) -> UiServer:
    """The operator page's server, listening and running in its thread before the NC starts."""
    from interfaces.links.errors import LinkError
    from vc.ui.bridge import OperatorBridge
    from vc.ui.server import UiServer

    try:
        page = UiServer(OperatorBridge(allow_writers, recorder), endpoint.host, endpoint.port)
    except OSError as error:
        raise LinkError(f"--ui {endpoint}: {error.strerror or error}") from None
    page.start()
    token = " (the token in it is needed beyond loopback)" if page.token else ""
    print(f"operator panel: {page.url}{token}", flush=True)
    return page


def _replay(arguments: argparse.Namespace) -> int:
    from vc.recording.command import replay_command

    if arguments.name is not None and arguments.to_scenario is None:
        print("--name needs --to-scenario OUT.yaml", file=sys.stderr)
        return EXIT_PROBLEMS
    return replay_command(arguments.file, machine=arguments.machine, to_scenario_path=arguments.to_scenario,
                          name=arguments.name, complain=lambda text: print(text, file=sys.stderr))


def _addresses(texts: Sequence[str]) -> tuple[str, ...]:
    """``--allow 10.0.0.1,10.0.0.2 --allow 10.1.0.0/16`` as one list."""
    return tuple(item for text in texts for item in text.split(",") if item.strip())


def _speed(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise ValueError(f"--speed {text}: a factor such as 0.5 or 2, or max") from None
    if not 0.01 <= value <= 100:
        raise ValueError(f"--speed {text}: between 0.01 and 100, or max")
    return value


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="vc", description="Virtual commissioning harness for CNC machines")
    parser.add_argument("--version", action="version", version=f"vc {_version()}, {build_status().describe()}")
    machines = f"a machine file, or the name of a packaged machine ({', '.join(packaged_machines())})"
    machine_help = f"{machines}; default {DEFAULT_MACHINE}"
    commands = parser.add_subparsers(dest="command", required=True)

    run = commands.add_parser("run", help="run scenarios with the built-in PLC")
    run.add_argument("paths", nargs="*", help="scenario files, campaign files or directories (searched recursively)")
    run.add_argument("--junit", metavar="FILE", help="write a JUnit XML report")
    run.add_argument("--trace-dir", metavar="DIR",
                     help="write a CSV and a VCD trace and a GTKWave save file (.gtkw) per scenario")
    run.add_argument("--report", metavar="DIR",
                     help="write an HTML report with a timing diagram per scenario to DIR/index.html (needs the report"
                          " extra: matplotlib)")
    run.add_argument("--plot", metavar="SCENARIO",
                     help="run one scenario (FILE, or a variant FILE[ARGUMENTS]) and show its timing diagram")
    run.add_argument("--plot-to", metavar="FILE", help="with --plot: write the diagram to FILE (.png or .svg)")
    run.add_argument("--cluster", metavar="ADDRESS",
                     help="run on a Dask cluster: a scheduler address (dask scheduler / dask worker) or local:N for a"
                          " LocalCluster of N worker processes (needs the cluster extra)")
    run.add_argument("--cluster-files", choices=("send", "shared"), default="send",
                     help="with --cluster: send the scenario, machine and program files to the workers (default), or"
                          " let them read the files and write the traces at the same paths (a shared file system)")
    run.add_argument("--golden", metavar="DIR",
                     help="compare each scenario with its golden trace in DIR (regression check)")
    run.add_argument("--update-golden", action="store_true", help="write the golden traces of --golden DIR anew")
    run.add_argument("--link", choices=(INPROCESS, *LINKS), default=INPROCESS,
                     help="where the PLC programs run: in this process (default) or in their own process over a"
                          " lockstep link: " + ", ".join(f"{name} ({kind.title})" for name, kind in LINKS.items()))
    run.add_argument("--can-bus", metavar="BUS",
                     help="with --link can: udp_multicast[:GROUP:PORT] (default: a channel of this run) or"
                          " socketcan[:INTERFACE]")
    run.add_argument("-j", "--jobs", type=_jobs, default=None, metavar="N",
                     help="run N scenario files at a time in worker processes (default: the number of cores;"
                          " -j 1 runs them one after another in this process); in process only")
    run.add_argument("--max-variants", type=_whole(1), default=MAX_RUN_VARIANTS, metavar="N",
                     help=f"the most variants the run's vary: matrices and campaigns may give together, counted before"
                          f" any is built (default {MAX_RUN_VARIANTS:,}; docs/scenarios.md)")
    run.add_argument("-k", dest="keyword", metavar="EXPRESSION",
                     help="run only the scenarios and variants whose file or name contains the expression's words,"
                          " combined with and, or, not and parentheses, as pytest -k (e.g. -k \"referencing and not"
                          " abort\", -k \"MD34050=1\")")
    run.add_argument("--shard", type=_shard, metavar="I/N",
                     help="run the I-th of N parts of the selected scenarios (every N-th from the I-th on): N CI"
                          " jobs run each scenario once, without a cluster")
    run.add_argument("--coverage", metavar="FILE",
                     help="write the interface coverage of the run (signals, state machines, alarms, plant I/O) to"
                          " FILE; vc coverage report FILE shows it (docs/coverage.md)")
    run.set_defaults(handler=_run)

    coverage = commands.add_parser("coverage", help="report the interface coverage of vc run --coverage")
    coverage_commands = coverage.add_subparsers(dest="coverage_command", required=True)
    report = coverage_commands.add_parser("report", help="merge coverage files, print the figures, write JSON and"
                                                         " HTML, check thresholds (docs/coverage.md)")
    report.add_argument("files", nargs="+", metavar="FILE", help="coverage files of vc run --coverage (merged)")
    report.add_argument("--json", metavar="OUT", help="write the figures and what was never exercised as JSON")
    report.add_argument("--html", metavar="OUT", help="write a standalone HTML page of what was never exercised")
    report.add_argument("--fail-under", type=_percent, metavar="PCT",
                        help="exit with 1 when the total coverage is below PCT percent")
    report.add_argument("--fail-under-function", action="append", default=[], metavar="NAME=PCT",
                        help="exit with 1 when a figure is below PCT: a state machine (gear_change), a group"
                             " (referencing), signals, functions, alarms, plant, DB10..DB31 (repeatable)")
    report.set_defaults(handler=_coverage_report)

    signal_map = commands.add_parser("map", help="print the expanded signal catalogue of a machine")
    signal_map.add_argument("--machine", required=True, help=machines)
    signal_map.add_argument("--format", choices=[*sorted(FORMATTERS), DBC_FORMAT, GUIDE_FORMAT, *EXPORTS],
                            default="md", help="md, csv, json: the map; dbc: the CAN frames; guide: docs/modbus.md;"
                            " codesys, openplc, tia, s7, awlsim: for a PLC tool (docs/plc_tools.md)")
    signal_map.add_argument("--io-base", type=_byte_offset, metavar="N",
                            help="s7, tia, awlsim: table byte t is input / output byte N + t (default 0)")
    signal_map.add_argument("-o", "--output", metavar="FILE", help="write to FILE instead of standard output")
    signal_map.set_defaults(handler=_map)

    serve = commands.add_parser("serve", help="serve the NC and the plant to a PLC over Modbus TCP and/or S7")
    serve.add_argument("--machine", default=DEFAULT_MACHINE, action=_Given,
                       help=f"{machine_help}; with --scenario only the scenario's machine")
    serve.add_argument("--modbus", nargs="?", const="127.0.0.1:5020", metavar="HOST:PORT",
                       help="serve Modbus TCP (default 127.0.0.1:5020; the default when no --s7 is given)")
    serve.add_argument("--s7", metavar="HOST:PORT", help="serve the data blocks over S7 (python-snap7)")
    serve.add_argument("--can", metavar="BUS", help="instead of the servers, a node on a CAN bus: udp_multicast"
                       "[:GROUP:PORT] or socketcan[:INTERFACE] (the machine file's can: settings; docs/can.md)")
    serve.add_argument("--allow-remote", action="store_true",
                       help="allow binding to an interface other than loopback")
    serve.add_argument("--allow", action="append", default=[], metavar="IP[,NET]",
                       help="only these clients may connect (addresses or networks, repeatable)")
    serve.add_argument("--allow-writers", action="append", default=[], metavar="IP[,NET]",
                       help="these clients may write besides the session's PLC, the one connection that wrote"
                            " the session into holding register 1 (a PLC with several connections, a tool;"
                            " repeatable)")
    serve.add_argument("--plc-key-file", metavar="FILE",
                       help="only a PLC that claims its session with the key in FILE writes into the NC (16"
                            " hexadecimal digits; made, readable by you alone, when missing; python -m plc_stub"
                            " --key-file FILE; docs/modbus.md)")
    serve.add_argument("--max-clients", type=int, default=DEFAULT_MAX_CLIENTS, metavar="N",
                       help=f"connections per server (default {DEFAULT_MAX_CLIENTS}); when full, the one idle"
                            " the longest makes room")
    serve.add_argument("--idle-timeout", type=_positive, default=DEFAULT_IDLE_TIMEOUT_S, metavar="S",
                       help=f"close a connection silent for S seconds (default {DEFAULT_IDLE_TIMEOUT_S:g})")
    serve.add_argument("--verbose", action="store_true",
                       help="log what the links and their libraries report (refused requests, server failures)")
    serve.add_argument("--realtime", action="store_true",
                       help="tie the IPO cycles to the wall clock; the PLC scans on its own clock")
    serve.add_argument("--cpu", metavar="LIST",
                       help="pin the server to these CPUs (1, 0,2, 2-3): with --fifo, what keeps the real-time NC's"
                            " period on a busy host (docs/modbus.md, bench/README.md)")
    serve.add_argument("--fifo", metavar="PRIORITY",
                       help="SCHED_FIFO real-time scheduling at PRIORITY 1..99 where permitted (root, CAP_SYS_NICE"
                            " or an rtprio limit); the statistics say what the server got")
    serve.add_argument("--speed", default="1", metavar="FACTOR",
                       help="real-time factor with --realtime: 0.5, 2 ... or max (default 1)")
    serve.add_argument("--program", default="basic_machine",
                       help="the PLC program a PLC that follows the harness runs (default basic_machine)")
    serve.add_argument("--scenario", metavar="FILE",
                       help="a scenario that plays the operator for the PLC on the link (its machine is used; its"
                            " plc: is optional and names what plc_stub runs); the server stops when it ends and"
                            " the exit code is its result: 0 passed, 1 failed, 2 a problem in the file")
    serve.add_argument("--junit", metavar="FILE", help="with --scenario: write its JUnit XML report")
    serve.add_argument("--keep-running", action="store_true",
                       help="with --scenario: keep the machine running after it (Ctrl-C or --duration ends)")
    serve.add_argument("--duration", type=float, metavar="S", help="stop after S simulated seconds")
    serve.add_argument("--stats", type=float, default=10.0, metavar="S",
                       help="print real-time statistics every S seconds (default 10)")
    serve.add_argument("--record", metavar="FILE",
                       help="record the session (the PLC's writes, the NC's outputs, the operator's actions, the"
                            " machine) for vc replay; FILE.gz is compressed (docs/recording.md)")
    serve.add_argument("--record-limit", type=_whole(1, MAX_RECORDING_BYTES >> 20, " MiB"),
                       default=DEFAULT_RECORD_LIMIT_MIB, metavar="MIB",
                       help=f"with --record: end the recording at MIB mebibytes (uncompressed; default"
                            f" {DEFAULT_RECORD_LIMIT_MIB}, at most {MAX_RECORDING_BYTES >> 20}); the session goes on")
    serve.add_argument("--ui", nargs="?", const=f"127.0.0.1:{DEFAULT_UI_PORT}", metavar="HOST:PORT",
                       help=f"serve the operator panel in the browser (default 127.0.0.1:{DEFAULT_UI_PORT}; beyond"
                            " loopback it asks for the token in the address it prints; needs the extra 'ui';"
                            " docs/ui.md)")
    serve.set_defaults(handler=_serve, machine_given=False)

    replay = commands.add_parser("replay", help="replay a session recorded by vc serve --record without the PLC")
    replay.add_argument("file", metavar="FILE", help="the recording")
    replay.add_argument("--machine", metavar="M.yaml",
                        help="replay on this machine file instead of the recorded one (what a change of machine data"
                             " does)")
    replay.add_argument("--to-scenario", metavar="OUT.yaml",
                        help="write the session as a scenario with plc: none instead of replaying it")
    replay.add_argument("--name", help="with --to-scenario: the scenario's name")
    replay.set_defaults(handler=_replay)

    bench = commands.add_parser("bench", help="measure the real-time factor of the simulation, the Modbus link"
                                              " or the FMU")
    bench.add_argument("--machine", default=None,
                       help=f"{machine_help} (with --scaling: the three packaged machines)")
    bench.add_argument("--scaling", action="store_true",
                       help="the cost per IPO cycle of each machine idle, with two axes and with every axis and"
                            " spindle moving, as a table (in process)")
    bench.add_argument("--link", choices=("inprocess", "modbus", "can", "fmu"), default="inprocess",
                       help="inprocess (default): the simulation with the PLC in this process; modbus: exchange"
                            " round trip against a bare pymodbus server, lockstep rate and real-time jitter with"
                            " plc_stub in its own process; fmu: steps per second of the exported FMU under FMPy"
                            " against the same unit in process, doStep only and with a full PLC exchange"
                            " (needs the test extra); can: frames per second and added cost per IPO cycle of the"
                            " CAN link on a virtual bus and on UDP multicast with plc_stub in its own process")
    bench.add_argument("--seconds", type=_positive, default=None,
                       help=f"inprocess: simulated seconds per workload (default {DEFAULT_BENCH_SECONDS:g});"
                            f" --scaling: simulated seconds per row (default {DEFAULT_SCALING_SECONDS:g});"
                            f" modbus: wall seconds of the real-time measurement"
                            f" (default {DEFAULT_REALTIME_BENCH_SECONDS:g}); fmu: simulated seconds per workload"
                            f" (default {DEFAULT_FMU_BENCH_SECONDS:g}); can: simulated seconds per bus"
                            f" (default {DEFAULT_CAN_BENCH_SECONDS:g})")
    bench.add_argument("--lockstep-seconds", type=_positive, default=10.0, metavar="S",
                       help="modbus: simulated seconds of the lockstep measurement (default 10)")
    bench.add_argument("--exchanges", type=int, default=2000, metavar="N",
                       help="modbus: full interface exchanges per server, in 10 rounds (default 2000)")
    bench.add_argument("--frames", type=int, default=20000, metavar="N",
                       help="can: frames of the throughput measurement per bus (default 20000)")
    bench.add_argument("--python", choices=("bundled", "host"), default="bundled",
                       help="fmu: the self-contained FMU (bundled, default) or the lean one (host)")
    bench.set_defaults(handler=_bench)

    fmu = commands.add_parser("fmu", help="export the NC and the plant as an FMU (FMI 2.0/3.0 co-simulation)")
    fmu_commands = fmu.add_subparsers(dest="fmu_command", required=True)
    export = fmu_commands.add_parser("export", help="build the FMU of a machine (docs/fmu.md)")
    export.add_argument("--machine", default=DEFAULT_MACHINE, help=machine_help)
    export.add_argument("-o", "--output", required=True, metavar="FILE.fmu", help="the FMU file to write")
    export.add_argument("--fmi", type=int, choices=(2, 3), default=2, help="FMI version (default 2: 2.0; 3: 3.0)")
    export.add_argument("--python", choices=("bundled", "host"), default="bundled",
                        help="bundled (default): a self-contained FMU with its own Python runtime, for any host;"
                             " host: the lean FMU (pythonfmu, FMI 2.0) that runs in the host's Python 3.11+"
                             " with PyYAML")
    export.set_defaults(handler=_fmu_export)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    arguments = build_parser().parse_args(argv)
    try:
        code: int = arguments.handler(arguments)
    except SourceError as error:
        for problem in error.problems:
            print(problem, file=sys.stderr)
        count = len(error.problems)
        print(f"{count} problem{'s' if count != 1 else ''} found; nothing was run.", file=sys.stderr)
        return EXIT_PROBLEMS
    except BrokenPipeError:
        return 0
    return code


def entry() -> None:
    """The ``vc`` command.  A run interrupted with Ctrl-C ends here at once: its worker processes
    were terminated, and one of them may have died in the middle of sending a result, which leaves
    the process pool's manager thread waiting for the rest of it; the interpreter's exit would
    join that thread for ever.  Everything to say has been said (and flushed) by then."""
    code = main()
    from vc.scenario.command import EXIT_INTERRUPTED

    if code == EXIT_INTERRUPTED:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    sys.exit(code)


if __name__ == "__main__":
    entry()
