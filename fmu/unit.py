"""The NC and its machine plant as one co-simulation unit: variables, parameters, the step.

This is what the FMU exports, without any FMI library (``fmu/instance.py`` gives it the FMI
behaviour, ``fmu/worker.py`` and ``fmu/slave.py`` carry it), so it is tested like any other part
of the project.  The unit is the
simulation of ``vc run`` with the PLC left out: the PLC, wherever it runs, talks to the
unit through its variables.

Variables, each named as the rest of the project names it (FMI structured names)::

    inputs      every PLC->NC signal (``X1.basic.out.enableCtrl``) and every plant output Q
                (``SP1.gearShift2``); the NC reads them at the start of its next IPO cycle
    outputs     every NC->PLC signal (``X1.basic.in.enc1Synchronized``) and every plant input
                I (``X1.refCam``), as they are at the end of the last IPO cycle; and per axis
                and spindle the continuous quantities of ``vc.simulation.observables`` (``X1.position``,
                ``SP1.velocity`` in rev/min, ``SP1.physical`` = the spindle's angle), per spindle
                its coupling quantities (``SP2.syncDeviation``, 0 while it follows nobody), and
                on a machine with a DC link ``NC.dcLinkVoltage``
    parameters  ``ipoCycle`` (s) and per axis ``<axis>.startPosition`` (where the slide stands at
                power-on); they take effect when initialisation ends
    PLC.signOfLife  an input of the project's own: the PLC changes it every scan; once it has
                been written the NC watches it as it watches its PLC (alarm 2000 after MD10100)

Booleans are bits, integers the byte, word and bit-field signals (unsigned), reals the
S7 REAL signals (and double words, which fmi2Integer cannot hold) and the axis quantities.
Each description starts with the absolute address.  The operator's points of the plant I/O
(panel keys and switches, the emergency stop chain) are outputs too, at their power-on
position, and say so in their description: the operator acts at the PLC, so a master that
copies the plant inputs to its PLC leaves these out.

Time: a step of the host is a whole number of IPO cycles; the unit refuses any other step,
and a communication point that is not where the unit stands (the NC cannot jump or go back).
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass
from enum import Enum
from functools import partial
from typing import NoReturn

from interfaces.errors import VcError
from interfaces.image import ProcessImage, Value, ValueRangeError, decode
from interfaces.plant_io import PointOwner
from interfaces.signals import NCK_INSTANCE, Direction, SignalRef, SignalType
from vc.config.loader import load_machine
from vc.config.md_dictionary import IPO_SYSCLOCK_TIME_RATIO
from vc.config.model import MachineConfig
from vc.located_yaml import LocatedMap, SourceError, load_text
from vc.simulation.lockstep import Simulation
from vc.simulation.observables import AXIS_QUANTITY_MEANINGS, COUPLING_QUANTITY_MEANINGS, NCK_QUANTITY_MEANINGS

IPO_CYCLE = "ipoCycle"
PLC_SIGN_OF_LIFE = "PLC.signOfLife"
START_POSITION = "startPosition"
PARAMETERS_FILE = "<FMU parameters>"
_CYCLE_TOLERANCE = 1e-6  # of an IPO cycle: what a host's floating-point step may be off by


class Kind(Enum):
    BOOLEAN = "Boolean"
    INTEGER = "Integer"
    REAL = "Real"


class Causality(Enum):
    INPUT = "input"
    OUTPUT = "output"
    PARAMETER = "parameter"


class Variability(Enum):
    DISCRETE = "discrete"  # changes only at communication points (interface signals)
    CONTINUOUS = "continuous"  # axis quantities
    FIXED = "fixed"  # parameters: set before initialisation ends


@dataclass(frozen=True, slots=True)
class Variable:
    name: str
    kind: Kind
    causality: Causality
    variability: Variability
    description: str


class UnitError(VcError):
    """Something the host asked of the unit that it cannot do; the message says what and why."""


class NcUnit:
    """The machine of ``machine_path`` without its PLC, stepped by a co-simulation host."""

    def __init__(self, machine_path: str):
        self.machine_path = machine_path
        self.machine = _load(machine_path, None)
        self.simulation = Simulation(self.machine, plc=None)
        self.ipo_cycle_s = self.simulation.ipo_cycle_s
        self.plc_cycle_s = self.machine.plc_cycle_ipo * self.ipo_cycle_s
        self.variables: list[Variable] = []
        self._readers: list[Callable[[], float | int | bool]] = []
        self._writers: list[Callable[[float | int | bool], None] | None] = []
        self._defaults = self._parameter_defaults()
        self.parameters = dict(self._defaults)
        self._signals: dict[int, SignalRef] = {}  # variable index -> interface signal or plant point
        self._written: dict[int, float | int | bool] = {}  # inputs set by the host, kept over a new power-on
        self._sign_of_life = 0
        self.start_time = 0.0
        self._declare_variables()
        self._bind_signals()

    # ------------------------------------------------------------------ variables
    def _declare_variables(self) -> None:
        simulation = self.simulation
        for signal in simulation.catalog.signals:
            ref = signal.ref()
            meaning = signal.definition.meaning
            if ref.direction is Direction.PLC_TO_NC:
                self._declare_input(ref, f"{ref.address} {meaning}")
            else:
                self._declare_output(ref, f"{ref.address} {meaning}")
        for point in self.machine.plant_io.points:
            ref = point.ref()
            text = f"{point.address} {point.meaning}"
            if point.owner is PointOwner.OPERATOR:
                text += " (the operator's: its power-on position; the operator acts at the PLC)"
            if point.direction is Direction.PLC_TO_PLANT:
                self._declare_input(ref, text)
            else:
                self._declare_output(ref, text)
        for axis in self.machine.axes:
            units = ("deg", "rev/min") if axis.is_rotary else ("mm", "mm/min")
            for quantity, meaning in AXIS_QUANTITY_MEANINGS.items():
                unit = units[1] if quantity == "velocity" else units[0]
                self._add_quantity(axis.name, quantity, f"{meaning}, {unit}")
            if axis.is_spindle:
                for quantity, meaning in COUPLING_QUANTITY_MEANINGS.items():
                    self._add_quantity(axis.name, quantity, meaning)
        if self.machine.dc_link is not None:
            for quantity, meaning in NCK_QUANTITY_MEANINGS.items():
                self._add_quantity(NCK_INSTANCE, quantity, meaning)
        self._add(Variable(PLC_SIGN_OF_LIFE, Kind.INTEGER, Causality.INPUT, Variability.DISCRETE,
                           "the PLC's sign of life, a number it changes every scan; once written the NC watches"
                           " it: no change for MD10100 raises alarm 2000 [project variable]"),
                  self._read_sign_of_life, self._plc_sign_of_life)
        self._add(Variable(IPO_CYCLE, Kind.REAL, Causality.PARAMETER, Variability.FIXED,
                           "IPO cycle, s (MD10050 SYSCLOCK_CYCLE_TIME x MD10070 IPO_SYSCLOCK_TIME_RATIO)"),
                  partial(self.parameters.__getitem__, IPO_CYCLE), partial(self._set_parameter, IPO_CYCLE))
        for axis in self.machine.axes:
            name = f"{axis.name}.{START_POSITION}"
            unit = "deg" if axis.is_rotary else "mm"
            self._add(Variable(name, Kind.REAL, Causality.PARAMETER, Variability.FIXED,
                               f"where the slide stands at power-on (machine coordinates), {unit}"),
                      partial(self.parameters.__getitem__, name), partial(self._set_parameter, name))

    def _declare_input(self, ref: SignalRef, description: str) -> None:
        self._signals[len(self.variables)] = ref
        self._add(Variable(ref.name, _kind_of(ref), Causality.INPUT, Variability.DISCRETE, description),
                  _unbound, _unbound)

    def _declare_output(self, ref: SignalRef, description: str) -> None:
        self._signals[len(self.variables)] = ref
        self._add(Variable(ref.name, _kind_of(ref), Causality.OUTPUT, Variability.DISCRETE, description),
                  _unbound, None)

    def _add(self, variable: Variable, reader: Callable[[], float | int | bool],
             writer: Callable[[float | int | bool], None] | None) -> None:
        self.variables.append(variable)
        self._readers.append(reader)
        self._writers.append(writer)

    def _bind_signals(self) -> None:
        """Accessors of the signal variables straight on the bytes of the present simulation's
        images (new at every power-on).  A host exchanges every variable at every step; through
        ``Simulation.read``/``write`` that cost about 1 us a variable, most of an FMU step.  The
        unit forces nothing, so the images hold what the NC and the PLC see."""
        for index, ref in self._signals.items():
            image = self.simulation.image_of(ref)
            area = image.areas[ref.area_key]
            kind = self.variables[index].kind
            if kind is Kind.BOOLEAN:
                self._readers[index] = partial(_read_bit, area, ref.address.byte, 1 << ref.address.bit)
            else:
                self._readers[index] = partial(_read_number, area, ref, float if kind is Kind.REAL else int)
            if self._writers[index] is not None:
                self._writers[index] = partial(_write_value, image, ref)

    def _add_quantity(self, instance: str, quantity: str, description: str) -> None:
        self._add(Variable(f"{instance}.{quantity}", Kind.REAL, Causality.OUTPUT, Variability.CONTINUOUS, description),
                  partial(self._axis_quantity, instance, quantity), None)

    def _axis_quantity(self, axis: str, quantity: str) -> float:
        return self.simulation.axis_quantity(axis, quantity)

    def _read_sign_of_life(self) -> int:
        return self._sign_of_life

    def _plc_sign_of_life(self, value: float | int | bool) -> None:
        self._sign_of_life = int(value)
        self.simulation.nck.plc_sign_of_life(self._sign_of_life)

    def get(self, index: int) -> float | int | bool:
        return self._readers[index]()

    def set(self, index: int, value: float | int | bool) -> None:
        """Set an input or a parameter; raises :class:`UnitError` for an output or a bad value."""
        writer = self._writers[index]
        if writer is None:
            raise UnitError(f"{self.variables[index].name} is an output; only inputs and parameters can be set")
        writer(value)
        if self.variables[index].causality is Causality.INPUT:
            self._written[index] = value

    # ------------------------------------------------------------------ parameters
    def _parameter_defaults(self) -> dict[str, float]:
        defaults = {IPO_CYCLE: self.ipo_cycle_s}
        for axis in self.machine.axes:
            defaults[f"{axis.name}.{START_POSITION}"] = axis.sim.start_position
        return defaults

    def _set_parameter(self, name: str, value: float | int | bool) -> None:
        self.parameters[name] = float(value)

    def _overrides(self) -> LocatedMap | None:
        """The parameters that differ from the machine file, as machine-file overrides."""
        changed = {name: value for name, value in self.parameters.items() if value != self._defaults[name]}
        if not changed:
            return None
        document: dict[str, dict[str, object]] = {}
        if IPO_CYCLE in changed:
            ratio = self.machine.nck.int(IPO_SYSCLOCK_TIME_RATIO)
            document["NC"] = {"MD10050": changed.pop(IPO_CYCLE) / ratio}  # the system clock scales
        for name, value in changed.items():
            axis = name.removesuffix(f".{START_POSITION}")
            document.setdefault(axis, {})["sim"] = {"start_position": value}
        parsed, problems = load_text(json.dumps(document), PARAMETERS_FILE)
        if problems:
            raise SourceError(problems)
        assert isinstance(parsed, LocatedMap)
        return parsed

    # ------------------------------------------------------------------ the FMI life cycle
    def setup(self, start_time: float) -> None:
        self.start_time = start_time

    def initialize(self) -> None:
        """End of initialisation: power on with the parameters, keep the inputs the host set."""
        overrides = self._overrides()
        if overrides is None:
            return  # the power-on of the constructor is the one of the machine file
        self.machine = _load(self.machine_path, overrides)
        self.simulation = Simulation(self.machine, plc=None)
        self.ipo_cycle_s = self.simulation.ipo_cycle_s
        self._bind_signals()
        for index, value in self._written.items():
            writer = self._writers[index]
            assert writer is not None
            writer(value)

    @property
    def time(self) -> float:
        return self.start_time + self.simulation.cycle * self.ipo_cycle_s

    def step(self, current_time: float, step_size: float) -> None:
        """Advance from ``current_time`` by ``step_size`` (s): a whole number of IPO cycles."""
        cycle = self.ipo_cycle_s
        cycles = step_size / cycle
        whole = round(cycles)
        if step_size <= 0.0 or abs(cycles - whole) > _CYCLE_TOLERANCE * max(1, whole):
            raise UnitError(f"the communication step {step_size:g} s is not a whole number of IPO cycles of"
                            f" {cycle * 1e3:g} ms; use a multiple such as {max(1, whole) * cycle:g} s")
        if abs(current_time - self.time) > cycle / 2:
            raise UnitError(f"the communication point t = {current_time:g} s is not where the NC stands"
                            f" (t = {self.time:g} s); it can neither jump nor go back")
        self.simulation.step(whole)


def _unbound(*_: object) -> NoReturn:
    raise AssertionError("signal accessors are bound to the simulation's images")


def _read_bit(area: bytearray, byte: int, mask: int) -> bool:
    return bool(area[byte] & mask)


def _read_number(area: bytearray, ref: SignalRef, kind: Callable[[Value], float | int]) -> float | int:
    return kind(decode(area, ref))


def _write_value(image: ProcessImage, ref: SignalRef, value: float | int | bool) -> None:
    """Through the image, which counts the write: the NC takes over the PLC's bytes only when it changed."""
    try:
        image.write(ref, int(value) if isinstance(value, bool) else value)
    except ValueRangeError as error:
        raise UnitError(f"{error}; the value was not taken") from None


def _load(path: str, overrides: LocatedMap | None) -> MachineConfig:
    try:
        return load_machine(path, overrides, PARAMETERS_FILE)
    except SourceError as error:
        raise UnitError(f"the machine does not load:\n{error}") from None


def _kind_of(ref: SignalRef) -> Kind:
    if ref.type is SignalType.BOOL:
        return Kind.BOOLEAN
    if ref.type in (SignalType.REAL, SignalType.DWORD):
        return Kind.REAL  # a DWORD does not fit fmi2Integer (signed 32 bit); a double holds it exactly
    return Kind.INTEGER
