"""Collecting interface coverage while scenarios run: ``vc run --coverage FILE``.

:class:`CoverageCollector` wraps the factory that makes a scenario's simulation: each simulation
is observed (``vc.simulation.observed``) by a :class:`CoverageObserver`, which after every IPO cycle

* compares the bytes of the interface and the plant I/O with those of the cycle before (one
  ``memcmp`` per area) and, only where they differ, decodes the signals in the changed bytes;
* reads the state of every state machine instance the NC publishes (``vc.coverage.probes``);
* looks at the alarms when the alarm list has changed (raised: its history; cleared: its log of
  cleared alarms, which says by what; alarms present at a power cycle are cleared by power-on).

Everything goes into one :class:`~vc.coverage.data.CoverageData` per collector, which is plain
data: runs in other processes collect their own and the results merge.  Without ``--coverage``
none of this exists: the runner steps the plain simulation.

Signals that do not apply to their instance are counted apart (``NOT_APPLICABLE``): the spindle
and coupling signals of an axis that is not a spindle, the inclined-axis signals of a channel
without an inclined-axis control, the orientation-axis signals of a channel without five-axis
kinematics.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from interfaces.image import decode
from interfaces.signals import InstanceKind, SignalRef
from vc.coverage.data import CoverageData, MachineCoverage, ValueRecord
from vc.coverage.probes import StateProbe, state_probes
from vc.scenario.language.model import Scenario
from vc.simulation.lockstep import Simulation
from vc.simulation.observed import ObservedSimulation, OperatorAction
from vc.simulation.published import AlarmList, Clear, NcFunction

# Catalogue groups that mean nothing on some instances: (kind, symbol part, who has them)
NOT_APPLICABLE: tuple[tuple[InstanceKind, str, str], ...] = (
    (InstanceKind.AXIS, ".spindle.", "spindles"),
    (InstanceKind.AXIS, ".coupling.", "spindles"),
    (InstanceKind.CHANNEL, ".inclinedAxis.", "channels with an inclined-axis control"),
    (InstanceKind.CHANNEL, ".orientationAxis1.", "channels with five-axis kinematics"),
)
# the function an instance must have for the group of NOT_APPLICABLE to apply (by symbol part)
_NEEDS = {".spindle.": NcFunction.SPINDLE, ".coupling.": NcFunction.SPINDLE,
          ".inclinedAxis.": NcFunction.INCLINED_AXIS, ".orientationAxis1.": NcFunction.FIVE_AXIS}


def _applies(simulation: Simulation, kind: InstanceKind, instance: str, symbol: str) -> bool:
    for rule_kind, part, _ in NOT_APPLICABLE:
        if rule_kind is kind and part in symbol:
            return _NEEDS[part] in simulation.functions_of(instance)
    return True


@dataclass(slots=True)
class _Watched:
    ref: SignalRef
    record: ValueRecord


class _SignalIndex:
    """Every signal and plant point of one machine with its record, indexed by the bytes it occupies
    (built once per machine of a collector: the scenarios of a machine share it)."""

    def __init__(self, simulation: Simulation, machine: MachineCoverage):
        self.by_byte: dict[str, list[tuple[int, list[_Watched]]]] = {}
        index: dict[tuple[str, int], list[_Watched]] = {}
        refs: list[tuple[SignalRef, ValueRecord]] = []
        for item in simulation.catalog.signals:
            refs.append((item.ref(), machine.signals[item.symbol]))
        for point in simulation.plant_io.points:
            refs.append((point.ref(), machine.plant[point.name]))
        for ref, record in refs:
            watched = _Watched(ref, record)
            for byte in range(ref.address.byte, ref.address.byte + ref.address.size):
                index.setdefault((ref.area_key, byte), []).append(watched)
        for (key, byte), entries in sorted(index.items()):
            self.by_byte.setdefault(key, []).append((byte, entries))
        self.refs = refs


class _SignalWatch:
    """The signals of one simulation: their bytes after the last look, what changed since."""

    def __init__(self, index: _SignalIndex):
        self.index = index
        self.previous: dict[str, bytes] = {}

    def start(self, areas: dict[str, bytearray]) -> None:
        for ref, record in self.index.refs:
            record.saw(decode(areas[ref.area_key], ref))
        self.previous = {key: bytes(areas[key]) for key in self.index.by_byte}

    def sample(self, areas: dict[str, bytearray]) -> None:
        previous, by_byte = self.previous, self.index.by_byte
        for key, before in previous.items():
            now = areas[key]
            if now == before:
                continue
            done: set[int] = set()
            for byte, entries in by_byte[key]:
                if now[byte] == before[byte]:
                    continue
                for watched in entries:
                    ref = watched.ref
                    if ref.address.size > 1:
                        if id(watched) in done:
                            continue
                        done.add(id(watched))
                    old, new = decode(before, ref), decode(now, ref)
                    if old != new:
                        watched.record.changed(old, new)
            previous[key] = bytes(now)


class CoverageObserver:
    """Observes one simulation for a :class:`CoverageCollector` (see the module docstring)."""

    def __init__(self, data: CoverageData, indexes: dict[object, _SignalIndex] | None = None):
        self.data = data
        self.indexes = indexes if indexes is not None else {}  # by machine, shared with other observers
        self.probes: list[StateProbe] = []
        self.signals: _SignalWatch | None = None
        self.alarm_list: AlarmList | None = None
        self.alarm_version = -1
        self.raised_seen = 0
        self.cleared_seen = 0

    # ------------------------------------------------------------------ SimulationObserver
    def attached(self, simulation: Simulation) -> None:
        self.data.scenarios += 1
        machine = self._machine(simulation)
        config = simulation.machine
        key = (config.name, config.layout, config.plant_io)
        index = self.indexes.get(key)
        if index is None:
            index = self.indexes[key] = _SignalIndex(simulation, machine)
        self.signals = _SignalWatch(index)
        self.signals.start(simulation.image_areas())
        self._powered_on(simulation)

    def cycle_done(self, simulation: Simulation) -> None:
        self.data.cycles += 1
        assert self.signals is not None
        self.signals.sample(simulation.image_areas())
        for probe in self.probes:
            probe.check()
        alarms = self.alarm_list
        if alarms is not None and alarms.version != self.alarm_version:
            self._alarms(alarms)

    def acted(self, simulation: Simulation, action: OperatorAction) -> None:
        assert self.signals is not None
        if action.kind != "power_cycle":
            self.signals.sample(simulation.image_areas())  # a key released after the last cycle counts too
            return
        if self.alarm_list is not None:
            self._alarms(self.alarm_list)
            for alarm in self.alarm_list.present:
                self.data.alarm(alarm.number).cleared_by(Clear.POWER_ON.value)
        self._powered_on(simulation)
        self.signals.sample(simulation.image_areas())

    # ------------------------------------------------------------------ parts
    def _powered_on(self, simulation: Simulation) -> None:
        self.probes = state_probes(simulation.state_view(), self.data, simulation.machine.name)
        self.alarm_list = alarms = simulation.alarm_list
        self.alarm_version = -1
        self.raised_seen = self.cleared_seen = 0
        self._alarms(alarms)

    def _alarms(self, alarms: AlarmList) -> None:
        self.alarm_version = alarms.version
        data = self.data
        history, cleared = alarms.history, alarms.cleared
        for alarm in history[self.raised_seen:]:
            data.alarm(alarm.number).raised += 1
        for alarm, how in cleared[self.cleared_seen:]:
            data.alarm(alarm.number).cleared_by(how.value)
        self.raised_seen, self.cleared_seen = len(history), len(cleared)

    def _machine(self, simulation: Simulation) -> MachineCoverage:
        """The machine's entry in the data: every signal and plant point, exercised or not."""
        config = simulation.machine
        machine = self.data.machines.get(config.name)
        if machine is None:
            machine = self.data.machines[config.name] = MachineCoverage(source=config.source)
        layout = config.layout
        for instance_kind in InstanceKind:
            machine.instances.update(layout.instances(instance_kind))
        for item in simulation.catalog.signals:
            if item.symbol not in machine.signals:
                machine.signals[item.symbol] = ValueRecord()
                machine.types[item.symbol] = item.type.value
                kind = _kind_of(item.definition.address.db)
                if kind is not None and not _applies(simulation, kind, item.instance, item.symbol):
                    machine.not_applicable.add(item.symbol)
        for point in simulation.plant_io.points:
            if point.name not in machine.plant:
                machine.plant[point.name] = ValueRecord()
                machine.types[point.name] = point.type.value
        return machine


def _kind_of(db: int) -> InstanceKind | None:
    """The kind of a catalogue entry by the data block it is declared in (DB21 channel, DB31 axis)."""
    return {21: InstanceKind.CHANNEL, 31: InstanceKind.AXIS}.get(db)


class CoverageCollector:
    """Interface coverage over the scenario runs of this process (see the module docstring)."""

    def __init__(self, data: CoverageData | None = None):
        self.data = data if data is not None else CoverageData()
        self._indexes: dict[object, _SignalIndex] = {}

    def observe(self, make_target: Callable[[Scenario], Simulation]) -> Callable[[Scenario], ObservedSimulation]:
        """The factory ``make_target`` with each of its simulations observed for the coverage."""
        def make(scenario: Scenario) -> ObservedSimulation:
            return self.observed(make_target(scenario))
        return make

    def observed(self, simulation: Simulation) -> ObservedSimulation:
        return ObservedSimulation(simulation, [CoverageObserver(self.data, self._indexes)])

