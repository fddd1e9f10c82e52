"""Machine files: YAML -> a checked, frozen :class:`~vc.config.model.MachineConfig`.

A machine file describes one machine as its builder knows it: the control's machine data
with the manual's numbers and names, the channel and axis structure, where the switches
sit on the slides of the simulated machine, and the I/O list wired to the PLC::

    machine: turn_mill
    description: Turn-mill centre with counter spindle
    plc_cycle_ipo: 5               # OB1 period in IPO cycles (default 5)
    nck:                           # general machine data ($MN_)
      MD10050 SYSCLOCK_CYCLE_TIME: 0.002
    channels:                      # channel k -> interface DB(20 + k), in file order
      CHAN1:
        axes: [X1, Z1, Y1, SP1]    # machine axes of the channel, in channel axis order (MD20070)
        MD20080 AXCONF_CHANAX_NAME_TAB: [X, Z, Y, SP1]
        MD20050 AXCONF_GEOAX_ASSIGN_TAB: [1, 3, 2]
    axes:                          # machine axis n -> interface DB(30 + n), in file order (MD10000)
      X1:
        MD32000 MAX_AX_VELO: 30000
        MD34100 REFP_SET_POS: [0.0, 10.0]   # an array: items from index 0 ...
        MD34100[3]: 5.0                     # ... or one index
        sim: {start_position: 150.0, zero_mark_offset: 2.5}
        plant: {ref_cam: [280.0, 295.0], hw_limits: [-12.0, 312.0]}
      SP1:
        MD35090 NUM_GEAR_STEPS: 3
        plant: {gearbox: {stages: 3, shift_time: 0.4, engaged: 1}, chuck: {travel_time: 0.3, closed: true}}
    plant_io:                      # address: plant function (interfaces/plant_io.py)
      I0.0: MCP.auto
      I9.0: SP1.gearEngaged1       # one engaged sensor and one shift actuator per gear stage:
      Q2.0: SP1.gearShift1         # ... gearEngaged2, gearShift2, ... up to the gearbox's stages
      I9.4: SP1.chuckClosed        # the chuck's sensors (chuckOpen optional) and its valve
      Q2.4: SP1.chuckClose         # solenoids: clamp ...
      Q2.5: SP1.chuckRelease       # ... and unclamp
    plc:                           # parameters of the machine's PLC program (it checks them)
      referencing_order: [[Y1], [X1], [Z1]]

Rules:

* Machine data keys take any form of :func:`~vc.config.md_dictionary.parse_md_key`:
  ``MD32000``, ``MD32000 MAX_AX_VELO``, ``$MA_MAX_AX_VELO``, ``MAX_AX_VELO``, each optionally
  with ``[n]``.  General data ($MN_) go under ``nck:``, channel data ($MC_) under a channel,
  axis data ($MA_) under an axis.  An array is written as a list (items from index 0) or
  index by index; an array written as one scalar is refused as ambiguous.  Unwritten data
  and indices keep the default of the dictionary; ``MachineData`` holds only what was
  written (plus MD10000 and MD20070, which the ``axes:`` keys and the channels' axes lists
  state, so they are not written as machine data).
* ``sim`` holds what the control cannot know: ``start_position`` (where the slide stands at
  power-on), ``zero_mark_offset`` / ``zero_mark_offset_2`` (measuring system 1 / 2: physical
  position of one zero mark, of the first distance-coded mark, or of an absolute encoder's
  zero; see vc/core/axis/encoder.py) and ``encoder_serial`` / ``encoder_serial_2`` (the serial
  numbers of the mounted encoders, which the control compares with MD34230).  ``plant`` holds switches:
  ``ref_cam: [start, end]`` and ``hw_limits: [minus, plus]`` (``null`` = no switch there), and a
  spindle's load gearbox: ``gearbox: {stages: n, shift_time: s, engaged: k}`` with n = MD35090 gear
  stages, the seconds the shift actuator must push while the motor turns for the teeth to mesh, and
  the stage in mesh at power-on (default 1, 0 = neutral).  A gearbox needs its I/O: the shift
  actuators ``<spindle>.gearShift1..n`` and the engaged sensors ``<spindle>.gearEngaged1..n`` (the
  neutral sensor ``<spindle>.gearNeutral`` is optional); gearbox I/O without a gearbox is a mistake.
  A spindle's hydraulic chuck: ``chuck: {travel_time: s, closed: true|false}``, the seconds of its
  stroke and whether it is clamped at power-on (default true).  It needs its valve solenoids
  ``<spindle>.chuckClose`` and ``<spindle>.chuckRelease`` and its sensor ``<spindle>.chuckClosed``
  wired (``<spindle>.chuckOpen`` is optional); chuck I/O without a chuck is a mistake.
* An axis's ``drive:`` holds parameters of its drive that the NC does not write: ESR generator
  operation ``{p0888: 3, p0892: s, p1240: 2, p1248: V, p2161: rev/min, p0341: kg m^2, p0342: ratio}``
  (seed 003 L41700-41769); none of it without p0888 = 3 (1 and 2 are written by ESRS / ESRR from
  the program).  It needs the machine's ``dc_link: {supply_voltage: V (r0208), capacitance_uf: uF,
  load_power: W, precharge_time: s (optional)}`` (vc/core/retraction/dc_link.py).
* The machine's devices besides the axes go under a top-level ``plant:`` (``turret``, ``coolant``,
  ``tool_changer``, each with its I/O), the texts of the PLC user alarms its PLC program raises under
  ``plc_alarms:`` (``700000: "Turret: lock pin not pulled"``): vc/config/devices.py.
* Every machine axis belongs to exactly one channel.  A channel axis without a name in
  MD20080 is called by its machine axis name in part programs.
* Scenario overrides (``load_machine(..., overrides=...)``) are ``{instance: {key: value}}``
  with instance = an axis name, a channel name or ``NC``.  They are checked exactly like the
  file and replace the file's values index by index.  An axis may also carry ``sim:`` and
  ``plant:``; the keys written replace the file's (``hw_limits`` as a pair, ``gearbox`` and ``chuck`` key
  by key); ``NC`` may carry ``dc_link:``, whose keys replace the file's.

Every problem of the file and of the overrides is collected with ``file:line:column`` and
reported at once in one :class:`~vc.located_yaml.SourceError`; no half-checked configuration
is returned.  Pure apart from reading the one file.

The reader is :mod:`vc.config.reader`, one module per step: reading the file (each value alone
checked as it is read), reading the overrides over it, checking the rules across the machine,
building the frozen configuration.  This module runs the steps and keeps parsed files.
"""

from __future__ import annotations

import os
from collections import OrderedDict
from typing import Any

from vc.config.machine_files import machine_file, unknown_machine
from vc.config.model import MachineConfig
from vc.config.reader.building import build_machine
from vc.config.reader.checking import check_can, check_machine
from vc.config.reader.overrides import apply_overrides
from vc.config.reader.reading import read_machine
from vc.located_yaml import LocatedMap, Mark, Problem, Problems, SourceError, load_file, load_text


def load_machine(reference: str, overrides: LocatedMap | None = None, overrides_file: str = "") -> MachineConfig:
    """Load and check a machine file, with a scenario's ``machine_data:`` overrides.

    ``reference`` is the file's path or the name of a packaged machine (``turn_mill``, see
    :mod:`vc.config.machine_files`); the configuration's ``source`` is the reference as given.
    ``overrides_file`` names the scenario file for problems that have no mark of their own
    (an override mapping built in code); the marks of a located mapping are used otherwise.
    Raises :class:`SourceError` listing every problem of both.
    """
    path = machine_file(reference)
    if path is None:
        raise SourceError([Problem(Mark(reference, 1, 1), unknown_machine(reference))])
    document, parse_problems = _parsed(path)
    return _machine_of(document, parse_problems, path, reference, overrides, overrides_file)


def load_machine_text(text: str, name: str, overrides: LocatedMap | None = None,
                      overrides_file: str = "") -> MachineConfig:
    """``load_machine`` for the text of a machine file kept elsewhere (a session recording holds
    the one it ran with); problems are located in ``name``."""
    document, parse_problems = load_text(text, name)
    return _machine_of(document, parse_problems, name, name, overrides, overrides_file)


def _machine_of(document: Any, parse_problems: list[Problem], path: str, reference: str,
                overrides: LocatedMap | None, overrides_file: str) -> MachineConfig:
    problems = Problems()
    problems.extend(parse_problems)
    if document is None:
        problems.raise_if_any()
    machine = read_machine(document, path, problems)
    if overrides is not None:
        apply_overrides(machine, overrides, Mark(overrides_file or "<machine_data>", 1, 1), problems)
    check_machine(machine, problems)
    problems.raise_if_any()  # no half-checked configuration is built
    config = build_machine(machine, reference)
    check_can(machine, config, problems)
    problems.raise_if_any()
    return config


_PARSED: OrderedDict[tuple[str, int, int, int], tuple[Any, list[Problem]]] = OrderedDict()
_PARSED_FILES = 16


def _parsed(path: str) -> tuple[Any, list[Problem]]:
    """The parsed machine file, parsed once while the file stays as it is: the variants of a
    scenario matrix load one machine file with hundreds of override sets (the reader only reads it)."""
    try:
        status = os.stat(path)
    except OSError:
        return load_file(path)  # it reports the file it cannot read
    key = (os.path.abspath(path), status.st_ino, status.st_mtime_ns, status.st_size)
    if key not in _PARSED:
        _PARSED[key] = load_file(path)
        if len(_PARSED) > _PARSED_FILES:
            _PARSED.popitem(last=False)
    _PARSED.move_to_end(key)
    return _PARSED[key]
