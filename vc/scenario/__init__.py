"""Scenarios: YAML files that drive a simulated machine headless and check what it does.

A scenario names a machine and a PLC, then lists steps that run one after the other.  Time
passes only in steps that take time (``press``, ``pulse``, ``wait``, ``power_cycle``); everything else happens
between two IPO cycles.  Every file of a run is checked completely before anything runs.
User documentation with examples: ``docs/scenarios.md``.

File grammar (``[...]`` = optional)::

    name: TEXT                        required
    [description: TEXT]
    machine: PATH                     required; machine file, relative to this file
    plc: PROGRAM | none               required; a built-in PLC program, or none = the steps act as the PLC
    [link: can]                       the PLC program behind the CAN link (a virtual bus in this process
                                      unless the run's link is CAN)
    [machine_data: {INSTANCE: {MD: VALUE}}]   INSTANCE = axis, channel or NC (checked like the machine file)
    [plc_parameters: {NAME: VALUE}]   over the machine file's plc: section; the PLC program checks them
    [timeout: DURATION]               limit of simulated time for the whole scenario, default 300 s
    [invariants: [CONDITION, ...]]    must hold after every IPO cycle
    steps: [STEP, ...]                required, at least one

    STEP, one kind per "-":
      press: KEYS | {key: KEYS, for: DURATION}           1, then DURATION (default 100 ms), then 0
      pulse: KEYS | {signal: KEYS, for: DURATION}        the same, for interface signals (plc: none)
      hold: KEYS                                         1 until released
      release: NAMES                                     ends a force; a key not forced goes back to 0
      set: {NAME: VALUE, ...}                            write once, as the signal's owner would
      force: {NAME: VALUE, ...}                          hold against the owner until release
      mda: TEXT | {text: TEXT, channel: CHANNEL}         load the MDA buffer (default: first channel)
      program: {name: NAME, text: TEXT | file: PATH, channel: CHANNEL}   select for AUTOMATIC
      wait: DURATION | {until: CONDITION, timeout: DURATION}   timeout default: the scenario's
      expect: CONDITION | {NAME: EXPECTED, ...}
      expect_alarm: NUMBER | {number: NUMBER, axis: AXIS | channel: CHANNEL, text: TEXT}   present now
      expect_no_alarm: NUMBER | all | {number: NUMBER, axis: AXIS | channel: CHANNEL}
      expect_order: [EVENT, EVENT, ...]                  two or more
      expect_timing: {from: EVENT, to: EVENT, min: DURATION, max: DURATION}    min, max or both
      power_cycle: DURATION | {off: DURATION}            machine off and on again (default 1 s off)
      fault: {axis: AXIS, kind: FAULT, [from: X, to: X], [by: X], [encoder: 1|2]}   vc.simulation.observables.FAULTS
      clear_faults: AXIS
      acknowledge: alarms                                the alarm cancel key: alarms cleared with it go
      link_fault: {kind: loss | delay | bus_off, for: DURATION, [direction: nc_to_plc | plc_to_nc | both],
                   [frames: NAMES], [by: DURATION], [every: N]}   a fault of the CAN bus (link: can)
      move_by_hand: {axis: AXIS, velocity: NUMBER}       the slide moved from outside (servo off); 0 stops

    KEYS, NAMES   a name or a list of names
    NAME          signal symbol (X1.basic.in.enc1Synchronized) or absolute address (DB31.DBX60.4,
                  DB21.DBB4, DB31.DBD88); plant I/O name (MCP.jog) or address (I0.3);
                  AXIS.QUANTITY (X1.position, see vc.simulation.observables.AXIS_QUANTITIES);
                  INSTANCE.MD<number>[<index>] (X1.MD34210: as the control holds it now);
                  CAN.QUANTITY (CAN.lostFromPlc, with link: can; vc.simulation.observables.LINK_QUANTITIES); time
    DURATION      20ms, 2s, 1.5 s, 1min, 500us, or a number of seconds
    VALUE         a number, true or false; checked against the signal's type
    EXPECTED      1, true (exact); 99.5 (within 1e-9); "100 +- 0.001" or "100 ± 0.001" (bounds
                  included); "< 5", "<= 5", "> 5", ">= 5", "!= 0", "== 3"
    EVENT         "NAME rises" (0 -> not 0), "NAME falls" (not 0 -> 0), "NAME changes", or
                  "when CONDITION" (the cycle it becomes true; at 0 s if it holds from the start)
    CONDITION     see vc.scenario.language.expressions: or, and, not, == != < <= > >=, + - * /, unary -,
                  ( ), numbers, true/false, names, abs(x), alarm(N), alarm(N, AXIS or CHANNEL)

Write rules (checked when the file is loaded):

* ``set``/``pulse``/``press``/``hold`` never write NC-to-PLC signals (the NC owns them), nor
  PLC-to-NC signals or plant outputs while a PLC program runs (the program owns them), nor
  plant inputs other than the operator's (panel ``MCP.*``, e-stop button ``EStop.chainOk``);
  the simulated machine drives cams, limit switches and drive ready.  ``force`` overrides any
  owner.
* ``press``, ``pulse``, ``hold`` and the ``release`` of an unforced name take bool signals.
* ``release`` of a name that no earlier step forces (and that is not a key) is refused.

Events and time: ``expect_order`` passes when each event occurs at or after the one before
(events of the same IPO cycle count as in order); ``expect_timing`` measures from the first
``from`` event to the first ``to`` event at or after it.  Both look at everything recorded
since the scenario started.  A value the scenario writes between two cycles belongs to the
cycle before it (a pulse written at 0 s rises at 0 s); ``time`` counts seconds since the
scenario started.

The package in layers, each importing only those below it (docs/architecture.md, "Scenarios"):
:mod:`vc.scenario.command` (``vc run``), :mod:`vc.scenario.distribution` (worker processes, a Dask
cluster), :mod:`vc.scenario.outputs` (golden traces, reports, timing diagrams), :mod:`vc.scenario.run`
(the runner, traces), :mod:`vc.scenario.language` (this grammar: model, loader, the step kinds).

Public functions (what ``vc run`` calls):

* :func:`run_command` - check, run, report; returns the exit code 0 / 1 / 2.
* :func:`load_scenarios` / :func:`load_scenario` - raise one :class:`~vc.located_yaml.SourceError`.
* :func:`run_scenarios` / :func:`run_scenario` - need a factory / a :class:`ScenarioTarget`.
* :func:`write_junit`, :func:`write_csv`, :func:`write_vcd`, :class:`ConsoleReport`.
"""

from vc.scenario.command import EXIT_FAILED, EXIT_PASSED, EXIT_PROBLEMS, run_command
from vc.scenario.language.loader import load_scenario, load_scenarios
from vc.scenario.language.model import Scenario
from vc.scenario.language.target import ScenarioTarget
from vc.scenario.outputs.report import ConsoleReport, write_junit
from vc.scenario.run.runner import ScenarioResult, run_scenario, run_scenarios
from vc.scenario.run.trace import ImageSource, Recorder, write_csv, write_vcd

__all__ = [
    "EXIT_FAILED",
    "EXIT_PASSED",
    "EXIT_PROBLEMS",
    "ConsoleReport",
    "ImageSource",
    "Recorder",
    "Scenario",
    "ScenarioResult",
    "ScenarioTarget",
    "load_scenario",
    "load_scenarios",
    "run_command",
    "run_scenario",
    "run_scenarios",
    "write_csv",
    "write_junit",
    "write_vcd",
]
