"""``vc run``: scenario files against the lockstep simulation with the built-in PLC programs.

The targets come from :mod:`vc.harness.targets` (in this process) and :mod:`vc.harness.external_plc`
(a PLC in its own process); this module only chooses among them.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from interfaces.links import INPROCESS, link_kind, load
from interfaces.links.inprocess import plc_programs
from vc.harness.external_plc import ChildPlcRun, ExternalPlcs
from vc.harness.targets import TargetFactory, simulation_for
from vc.input_limits import MAX_RUN_VARIANTS
from vc.scenario.command import plot_command, run_command
from vc.scenario.distribution.cluster import ClusterSettings
from vc.scenario.language.model import Scenario
from vc.scenario.language.selection import Selection
from vc.scenario.language.target import ScenarioTarget
from vc_build import status as build_status

# wraps the factory of a run, e.g. to observe each simulation (vc run --coverage)
Observe = Callable[[TargetFactory], Callable[[Scenario], ScenarioTarget]]


def run_scenario_files(paths: Sequence[str], *, junit: str | None = None, trace_dir: str | None = None,
                       golden: str | None = None, update_golden: bool = False, link: str = INPROCESS,
                       can_bus: str | None = None, jobs: int | None = None, observe: Observe | None = None,
                       cluster: str | None = None, cluster_files: str = "send", report_dir: str | None = None,
                       max_variants: int = MAX_RUN_VARIANTS, selection: Selection | None = None) -> int:
    """``link``: ``inprocess`` runs the PLC programs in lockstep in this process, or in ``jobs``
    worker processes (default one per core), or on the Dask ``cluster`` (an address or local:N;
    ``cluster_files``: send or shared); ``modbus`` runs them in a ``python -m plc_stub``
    process over a lockstep Modbus TCP link, ``can`` over a lockstep CAN link on ``can_bus``
    (default: a UDP multicast channel of this run): both with one PLC process, one scenario
    after the other.  A scenario with an external PLC (``plc: awlsim:FILE``) runs against that
    PLC in its own process, in every run.  ``observe`` wraps the run's factory of simulations
    (the interface coverage observes each one, in this process: such a run has no workers).
    ``report_dir`` gets the HTML report with the timing diagrams; ``max_variants`` is the ceiling on
    the variants of the run's matrices (vc run --max-variants); ``selection``: -k and --shard."""
    build = build_status().describe()

    def run(make_target: TargetFactory, workers: int | None = 1, on: ClusterSettings | None = None) -> int:
        with ExternalPlcs() as external:  # scenarios with plc: awlsim:FILE, whatever the link
            wrapped = external.wrap(make_target)
            target_factory: Callable[[Scenario], ScenarioTarget] = wrapped if observe is None else observe(wrapped)
            return run_command(paths, target_factory, plc_programs(), junit=junit, trace_dir=trace_dir,
                               golden=golden, update_golden=update_golden,
                               jobs=workers if observe is None else 1, build=build,
                               cluster=on if observe is None else None, report_dir=report_dir,
                               max_variants=max_variants, selection=selection)

    if link != INPROCESS:
        plc_process: Callable[[str | None], ChildPlcRun[Any]] = load(link_kind(link).plc_process)
        with plc_process(can_bus) as process:
            return run(process.target_factory())
    return run(simulation_for, jobs, ClusterSettings(cluster, cluster_files) if cluster else None)


def plot_scenario(spec: str, output: str | None = None) -> int:
    """``vc run --plot SCENARIO``: one scenario in this process, its timing diagram shown or written."""
    return plot_command(spec, simulation_for, plc_programs().keys(), output=output)
