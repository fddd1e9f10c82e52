"""Signal traces of a scenario run: recording, history queries, CSV and VCD files.

What is recorded, after every IPO cycle, when it changes (``record_all``, for traces, golden
traces and diagrams; otherwise only the names the scenario itself reads):

* every catalogue signal of type bool, bits, byte or word of every DB instance (double words
  and reals, which often change every cycle, only when a scenario names them), and the numbers
  of the alarms present in the alarm list of DB100 (``ALARMS.entry[1].in.number`` ..., double
  words that change only with the list),
* every plant I/O point,
* position and velocity of every machine axis (when they move by more than 1e-6),
* whatever else the scenario names (other axis quantities, raw addresses, double words, reals).

Cost per cycle (measured with the test machine: 3 axes, ~650 recorded signals, ~190 bytes;
``measure_sample_cost`` gives the figure for any target):

* a target that offers ``image_areas()`` (see :class:`ImageSource`) is watched through its
  bytes: each area is compared with its copy from the previous cycle (one ``memcmp``), and
  only the signals inside changed bytes are decoded.  A quiet cycle costs about 2 us, the
  six axis reads included; the whole runner (recorder, two invariants) about 4 us.
* any other target is read through :meth:`ScenarioTarget.read`, one raw byte per byte that
  holds bool/bits/byte signals (bits are decoded only when their byte changed) and each word
  on its own: about 120 us with a dict-backed target, over the 100 us budget.  The harness
  should offer ``image_areas()``.

Times in a trace count from the start of the scenario: cycle 0 holds the initial values.
"""

from __future__ import annotations

import csv
import heapq
import time as wallclock
from array import array
from collections import OrderedDict
from collections.abc import Callable, Collection, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol, runtime_checkable

from interfaces.address import Address
from interfaces.image import Value, decode
from interfaces.plant_io import PlantIoMap
from interfaces.signals import ALARMS_INSTANCE, Catalog, ExpandedCatalog, SignalRef, SignalType
from vc.escaping import csv_field, vcd
from vc.scenario.language.model import EdgeKind
from vc.scenario.language.quantities import Quantity, QuantityKind, axis_quantity, signal_quantity
from vc.scenario.language.target import ScenarioTarget

AXIS_DEADBAND = 1e-6
RECORDED_TYPES = (SignalType.BOOL, SignalType.BITS, SignalType.BYTE, SignalType.WORD)
RECORDED_AXIS_QUANTITIES = ("position", "velocity")


@runtime_checkable
class ImageSource(Protocol):
    """Optional fast path for recording: the live byte areas of the target.

    ``image_areas()`` returns the current bytes, keyed ``DB10``, ``DB11``, ``DB21``..,
    ``DB31``.., ``I`` and ``Q`` (as :attr:`interfaces.image.ProcessImage.areas`), showing
    exactly what :meth:`ScenarioTarget.read` would return (forces included).  The recorder
    only reads them; returning the live ``bytearray`` objects (no copy) is intended.
    """

    def image_areas(self) -> Mapping[str, bytes | bytearray]: ...


@dataclass(frozen=True, slots=True)
class _ByteRead:
    raw: SignalRef  # the whole byte
    scratch: bytearray  # the last value of every byte of the area that is read
    byte: int
    histories: list[History]


@dataclass(slots=True)
class History:
    """The recorded values of one name: ``values[i]`` holds from ``cycles[i]`` on."""

    quantity: Quantity
    cycles: array[int] = field(default_factory=lambda: array("q"))
    values: array[float] = field(default_factory=lambda: array("d"))
    last: float = 0.0

    def add(self, cycle: int, value: float) -> None:
        self.cycles.append(cycle)
        self.values.append(value)
        self.last = value

    def value(self, index: int) -> Value:
        value = self.values[index]
        return int(value) if self.quantity.is_integer else value

    def entries(self) -> Iterator[tuple[int, Value]]:
        for index, cycle in enumerate(self.cycles):
            yield cycle, self.value(index)

    def __len__(self) -> int:
        return len(self.cycles)


@dataclass(frozen=True, slots=True)
class RecordedData:
    """A :class:`Recording` as plain data, for another process or machine: per name its cycles and
    values as the bytes of their arrays.  The receiver names the quantities again
    (:meth:`Recording.from_data`), from the scenario it has itself."""

    ipo_cycle_us: int
    alarm_numbers: tuple[int, ...]
    histories: tuple[tuple[str, bytes, bytes], ...]  # (name, cycles: array("q"), values: array("d"))

    @property
    def size(self) -> int:
        """Bytes of the arrays (what dominates the transfer)."""
        return sum(len(cycles) + len(values) for _, cycles, values in self.histories)


class Recording:
    """What a run recorded: the history of every name, queried by the runner, the golden check
    and the trace writers.  A plain Recording (no target) is what a worker's data becomes again."""

    def __init__(self, ipo_cycle_us: int, histories: Iterable[History] = (), alarm_numbers: Iterable[int] = ()):
        self.ipo_cycle_us = ipo_cycle_us
        self._histories: dict[str, History] = {history.quantity.name: history for history in histories}
        self._alarm_numbers = tuple(alarm_numbers)

    def alarm_numbers(self) -> tuple[int, ...]:
        """The numbers of the alarms raised during the run, in order."""
        return self._alarm_numbers

    def data(self, names: Collection[str] | None = None) -> RecordedData:
        """The histories (of ``names`` only, when given) as plain data."""
        chosen = [history for name, history in self._histories.items() if names is None or name in names]
        return RecordedData(self.ipo_cycle_us, self.alarm_numbers(),
                            tuple((history.quantity.name, history.cycles.tobytes(), history.values.tobytes())
                                  for history in chosen))

    @classmethod
    def from_data(cls, data: RecordedData, quantities: Mapping[str, Quantity]) -> Recording:
        """The recording again, its names resolved by ``quantities`` (:func:`recorded_quantities`);
        raises KeyError for a name the receiver does not know."""
        histories = []
        for name, cycles, values in data.histories:
            history = History(quantities[name])
            history.cycles.frombytes(cycles)
            history.values.frombytes(values)
            history.last = history.values[-1] if len(history.values) else 0.0
            histories.append(history)
        return cls(data.ipo_cycle_us, histories, data.alarm_numbers)

    # -- queries ---------------------------------------------------------------------------

    @property
    def histories(self) -> list[History]:
        return list(self._histories.values())

    def history(self, quantity: Quantity) -> History | None:
        return self._histories.get(quantity.name)

    def time_of(self, cycle: int) -> float:
        """Seconds since the scenario started at ``cycle`` (a trace cycle)."""
        return cycle * self.ipo_cycle_us / 1e6

    def occurrences(self, quantity: Quantity, kind: EdgeKind) -> list[int]:
        """Cycles at which ``quantity`` rose (0 -> not 0), fell (not 0 -> 0) or changed."""
        history = self._histories.get(quantity.name)
        if history is None:
            return []
        found = []
        values = history.values
        for index in range(1, len(values)):
            before, after = values[index - 1], values[index]
            if kind is EdgeKind.CHANGES or (kind is EdgeKind.RISES and before == 0 and after != 0) \
                    or (kind is EdgeKind.FALLS and before != 0 and after == 0):
                found.append(history.cycles[index])
        return found

    def changes(self) -> Iterator[tuple[int, History, Value]]:
        """Every recorded value, ordered by cycle and then by name."""
        ordered = sorted(self._histories.values(), key=lambda h: h.quantity.name)
        streams = [_numbered(position, history) for position, history in enumerate(ordered)]
        for cycle, _, history, value in heapq.merge(*streams, key=lambda item: (item[0], item[1])):
            yield cycle, history, value


def is_alarm_number(quantity: Quantity) -> bool:
    """A number of DB100's alarm list (``ALARMS.entry[3].in.number``), recorded for the traces and the
    diagrams' alarm marks; the golden traces compare the alarms as the list of those raised."""
    ref = quantity.ref
    return (ref is not None and ref.type is SignalType.DWORD and ref.signal is not None
            and ref.signal.instance == ALARMS_INSTANCE)


def recorded_quantities(catalog: ExpandedCatalog, plant_io: PlantIoMap, axes: Iterable[str],
                        watched: Iterable[Quantity] = ()) -> dict[str, Quantity]:
    """What a :class:`Recorder` records on a machine by default, and ``watched`` (by name): every
    bool, bits, byte and word signal, every plant I/O point, position and velocity of every axis."""
    found: dict[str, Quantity] = {quantity.name: quantity for quantity in _default_quantities(catalog, plant_io, axes)}
    for quantity in watched:
        if quantity.kind is not QuantityKind.TIME:
            found.setdefault(quantity.name, quantity)
    return found


_DEFAULTS_KEPT = 8  # machines whose default quantities a process keeps (a library has a handful)
_defaults: OrderedDict[tuple[int, object, PlantIoMap, tuple[str, ...]],
                       tuple[Catalog, tuple[Quantity, ...]]] = OrderedDict()


def _default_quantities(catalog: ExpandedCatalog, plant_io: PlantIoMap, axes: Iterable[str]) -> tuple[Quantity, ...]:
    """The default quantities of a machine, named once per catalogue, interface layout, plant I/O and
    axes: every scenario and variant on one machine records the same ~1,500 names."""
    names = tuple(axes)
    base = catalog.catalog
    key = (id(base), catalog.layout, plant_io, names)
    kept = _defaults.get(key)
    if kept is not None and kept[0] is base:  # the catalogue itself, not one at its address before
        _defaults.move_to_end(key)
        return kept[1]
    chosen = [signal_quantity(item.ref()) for item in catalog.signals
              if item.type in RECORDED_TYPES or (item.instance == ALARMS_INSTANCE and item.type is SignalType.DWORD)]
    chosen += [signal_quantity(point.ref()) for point in plant_io.points]
    chosen += [axis_quantity(axis, name) for axis in names for name in RECORDED_AXIS_QUANTITIES]
    unique: dict[str, Quantity] = {}
    for quantity in chosen:
        unique.setdefault(quantity.name, quantity)
    quantities = tuple(unique.values())
    _defaults[key] = (base, quantities)
    if len(_defaults) > _DEFAULTS_KEPT:
        _defaults.popitem(last=False)
    return quantities


class Recorder(Recording):
    """Records a target's signals after every cycle and answers questions about their history.

    ``record_all``: every signal and axis of the machine (:func:`recorded_quantities`), for traces,
    golden traces and diagrams; otherwise only what :meth:`watch` names (a scenario's own names).
    ``axis_values``: where :meth:`sample` leaves the axis quantities it read in a cycle, by name, for
    the scenario's conditions to read instead of asking the target again (the runner empties it)."""

    def __init__(self, target: ScenarioTarget, watch: Iterable[Quantity] = (), record_all: bool = True,
                 axis_values: dict[str, float] | None = None):
        super().__init__(target.ipo_cycle_us)
        self.target = target
        self.start_cycle = 0
        self.cycle = 0  # cycles since the start of the scenario
        self.record_all = record_all
        self.axis_values = axis_values
        self._images = target if isinstance(target, ImageSource) else None
        self._previous: dict[str, bytes] = {}
        self._signals: list[History] = []
        self._axes: list[History] = []
        self._data: list[History] = []
        self._byte_index: dict[str, list[tuple[int, list[History]]]] = {}
        self._byte_reads: list[_ByteRead] = []
        self._word_reads: list[History] = []
        self._by_byte: dict[tuple[str, int], list[History]] = {}
        if record_all:
            axes = (axis.name for axis in target.machine.axes)
            for quantity in _default_quantities(target.catalog, target.plant_io, axes):
                self._add(quantity)
        self.watch(watch)

    def alarm_numbers(self) -> tuple[int, ...]:
        return tuple(alarm.number for alarm in self.target.alarm_history())

    def watch(self, quantities: Iterable[Quantity]) -> None:
        """Record these too (call before :meth:`start`); ``time`` is never recorded."""
        for quantity in quantities:
            self._add(quantity)
        self._byte_index, self._byte_reads, self._word_reads = {}, [], []
        if self._images is not None and self._by_byte:
            self._index_bytes()
        else:
            self._plan_reads()

    def _add(self, quantity: Quantity) -> None:
        kind = quantity.kind
        if kind is QuantityKind.TIME or quantity.name in self._histories:
            return
        history = self._histories[quantity.name] = History(quantity)
        if kind is QuantityKind.SIGNAL:
            self._signals.append(history)
            ref = quantity.ref
            assert ref is not None
            key, first = ref.area_key, ref.address.byte
            for byte in range(first, first + ref.address.size):
                self._by_byte.setdefault((key, byte), []).append(history)
        elif kind is QuantityKind.AXIS:
            self._axes.append(history)
        elif kind in (QuantityKind.MACHINE_DATUM, QuantityKind.LINK):
            self._data.append(history)

    def _index_bytes(self) -> None:
        self._byte_index = {}
        for (key, byte), histories in sorted(self._by_byte.items()):
            self._byte_index.setdefault(key, []).append((byte, histories))

    def _plan_reads(self) -> None:
        """Without images: one read of a raw byte per byte that holds bool/bits/byte signals."""
        groups: dict[tuple[str, int], list[History]] = {}
        self._word_reads = []
        for history in self._signals:
            ref = history.quantity.ref
            assert ref is not None
            if ref.address.size == 1:
                groups.setdefault((ref.area_key, ref.address.byte), []).append(history)
            else:
                self._word_reads.append(history)
        sizes: dict[str, int] = {}
        for key, byte in groups:
            sizes[key] = max(sizes.get(key, 0), byte + 1)
        scratch = {key: bytearray(size) for key, size in sizes.items()}
        self._byte_reads = []
        for (key, byte), histories in sorted(groups.items()):
            first = histories[0].quantity.ref
            assert first is not None
            address = Address(first.address.area, first.address.db, byte, -1, "B")
            raw = SignalRef(str(address), address, SignalType.BYTE, 8, first.direction)
            self._byte_reads.append(_ByteRead(raw, scratch[key], byte, histories))

    # -- recording -------------------------------------------------------------------------

    def start(self) -> None:
        """Take the initial values (cycle 0 of the trace)."""
        self.start_cycle = self.target.cycle
        self.cycle = 0
        areas = self._images.image_areas() if self._byte_index and self._images is not None else None
        for history in self._histories.values():
            history.cycles = array("q")
            history.values = array("d")
            ref = history.quantity.ref
            if areas is not None and ref is not None:  # what read() gives, without a call per signal
                history.add(0, float(decode(areas[ref.area_key], ref)))
            else:
                history.add(0, float(self._read(history.quantity)))
        if areas is not None:
            self._previous = {key: bytes(areas[key]) for key in self._byte_index}
        for group in self._byte_reads:
            group.scratch[group.byte] = int(self.target.read(group.raw))

    def sample(self) -> None:
        """Record what changed in the cycle that just completed."""
        cycle = self.target.cycle - self.start_cycle
        self.cycle = cycle
        if self._byte_index:
            assert self._images is not None
            self._sample_images(cycle, self._images.image_areas())
        elif self._byte_reads or self._word_reads:
            self._sample_reads(cycle)
        axis_value, values = self.target.axis_quantity, self.axis_values
        for history in self._axes:
            quantity = history.quantity
            value = axis_value(quantity.axis, quantity.quantity)
            if values is not None:
                values[quantity.name] = value
            if abs(value - history.last) > AXIS_DEADBAND:
                history.add(cycle, value)
        for history in self._data:
            value = self._read(history.quantity)
            if value != history.last or not len(history):
                history.add(cycle, value)

    def note_writes(self, quantities: Iterable[Quantity]) -> None:
        """Record, at the current cycle, what the scenario wrote between two cycles: every
        recorded signal in the bytes of ``quantities``, read through the target (a target may
        compose its images once per cycle, so they need not show such writes yet)."""
        done: set[str] = set()
        read = self.target.read
        for quantity in quantities:
            ref = quantity.ref
            if ref is None:
                continue
            for byte in range(ref.address.byte, ref.address.byte + ref.address.size):
                for history in self._by_byte.get((ref.area_key, byte), ()):
                    name = history.quantity.name
                    if name in done:
                        continue
                    done.add(name)
                    assert history.quantity.ref is not None
                    value = read(history.quantity.ref)
                    if value != history.last:
                        history.add(self.cycle, value)

    def _sample_reads(self, cycle: int) -> None:
        read = self.target.read
        for group in self._byte_reads:
            value = read(group.raw)
            scratch, byte = group.scratch, group.byte
            if value == scratch[byte]:
                continue
            scratch[byte] = int(value)
            for history in group.histories:
                ref = history.quantity.ref
                assert ref is not None
                decoded = decode(scratch, ref)
                if decoded != history.last:
                    history.add(cycle, decoded)
        for history in self._word_reads:
            ref = history.quantity.ref
            assert ref is not None
            value = read(ref)
            if value != history.last:
                history.add(cycle, value)

    def _sample_images(self, cycle: int, areas: Mapping[str, bytes | bytearray]) -> None:
        previous = self._previous
        for key, before in previous.items():
            now = areas[key]
            if now == before:
                continue
            for byte, histories in self._byte_index[key]:
                if now[byte] != before[byte]:
                    for history in histories:
                        ref = history.quantity.ref
                        assert ref is not None
                        value = decode(now, ref)
                        if value != history.last:
                            history.add(cycle, value)
            previous[key] = bytes(now)

    def _read(self, quantity: Quantity) -> Value:
        if quantity.kind is QuantityKind.AXIS:
            return self.target.axis_quantity(quantity.axis, quantity.quantity)
        if quantity.kind is QuantityKind.MACHINE_DATUM:
            return self.target.machine_datum(quantity.axis, int(quantity.quantity), quantity.index)
        if quantity.kind is QuantityKind.LINK:
            return self.target.link_quantity(quantity.quantity)
        assert quantity.ref is not None
        return self.target.read(quantity.ref)

    # -- queries ---------------------------------------------------------------------------

    def recent(self, quantity: Quantity, limit: int = 10, window_s: float = 5.0) -> list[tuple[int, Value]]:
        """The last ``limit`` changes within the last ``window_s`` seconds (at least the value now)."""
        history = self._histories.get(quantity.name)
        if history is None or not len(history):
            return []
        window = int(window_s * 1e6 // self.ipo_cycle_us)
        first = self.cycle - window
        entries = [(c, history.value(i)) for i, c in enumerate(history.cycles) if c >= first]
        if not entries:
            entries = [(history.cycles[-1], history.value(len(history) - 1))]
        return entries[-limit:]


def _numbered(position: int, history: History) -> Iterator[tuple[int, int, History, Value]]:
    for cycle, value in history.entries():
        yield cycle, position, history, value


# ---------------------------------------------------------------------------------- writers

CSV_HEADER = ("cycle", "time_s", "name", "value", "address", "unit")
Units = Callable[[Quantity], str]  # the unit of a quantity's values (vc.scenario.language.quantities.unit_of)


def write_csv(recorder: Recording, path: str | Path, units: Units | None = None) -> None:
    """Long format, one row per change: ``cycle,time_s,name,value,address,unit`` sorted by cycle and name."""
    columns: dict[str, tuple[str, str, str]] = {}  # name -> its name, address and unit as written
    for history in recorder.histories:
        quantity = history.quantity
        columns[quantity.name] = (csv_field(quantity.name), csv_field(quantity.address),
                                  csv_field(units(quantity)) if units is not None else "")
    with open(path, "w", encoding="utf-8", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(CSV_HEADER)
        for cycle, history, value in recorder.changes():
            name, address, unit = columns[history.quantity.name]
            writer.writerow((cycle, f"{recorder.time_of(cycle):.6f}", name, _csv_value(value), address, unit))


def _csv_value(value: Value) -> str:
    return str(value) if isinstance(value, int) else repr(value)


def vcd_scope_and_name(quantity: Quantity) -> tuple[str, str]:
    """Where a quantity appears in a VCD file: ``("X1", "basic.in.enc1Synchronized")``."""
    scope = quantity.scope
    prefix = scope + "."
    name = quantity.name
    if quantity.kind is QuantityKind.SIGNAL and scope != "PLANT" and name.startswith(prefix):
        name = name[len(prefix):]
    return vcd(scope), vcd(name)


def write_vcd(recorder: Recording, path: str | Path, date: str | None = None) -> None:
    """A VCD file for GTKWave: one scope per DB instance, ``PLANT`` and ``AXES``; timescale 1 us."""
    from vcd import VCDWriter

    histories = sorted(recorder.histories, key=lambda h: vcd_scope_and_name(h.quantity))
    with open(path, "w", encoding="utf-8") as handle, \
            VCDWriter(handle, timescale="1 us", date=date or "", version="vc-harness") as writer:
        variables = {}
        for history in histories:
            if not len(history):
                continue
            scope, name = vcd_scope_and_name(history.quantity)
            ref = history.quantity.ref
            initial = history.value(0)
            if ref is None or ref.type is SignalType.REAL:
                variables[history.quantity.name] = writer.register_var(
                    scope, name, "real", init=float(initial))
            else:
                variables[history.quantity.name] = writer.register_var(
                    scope, name, "wire", size=_vcd_width(ref), init=int(initial))
        step = recorder.ipo_cycle_us
        initial_done: set[str] = set()
        for cycle, history, value in recorder.changes():
            if history.quantity.name not in initial_done:  # the initial value, given at registration
                initial_done.add(history.quantity.name)
                continue
            variable = variables[history.quantity.name]
            writer.change(variable, cycle * step, value if history.quantity.is_integer else float(value))


def _vcd_width(ref: SignalRef) -> int:
    return ref.bits if ref.type in (SignalType.BOOL, SignalType.BITS) else 8 * ref.address.size


def gtkwave_name(quantity: Quantity) -> str:
    """The name GTKWave gives a quantity of our VCD files: ``X1.\\basic.in.enc1Synchronized``.  GTKWave
    reads a dot as the step into a scope, so a VCD name that holds dots is an escaped identifier to it
    (a backslash before it); a signal of several bits carries its range, ``NC.\\basic.out.x[7:0]``.
    A save file must name them so, or it shows nothing."""
    scope, name = vcd_scope_and_name(quantity)
    escaped = "\\" + name if "." in name else name
    ref = quantity.ref
    width = _vcd_width(ref) if ref is not None and ref.type is not SignalType.REAL else 1
    return f"{scope}.{escaped}" + (f"[{width - 1}:0]" if width > 1 else "")


def write_gtkw(recording: Recording, shown: Sequence[Quantity], path: str | Path, vcd_name: str,
               title: str = "") -> None:
    """A GTKWave save file for the VCD ``vcd_name`` beside it that opens with ``shown`` in view
    (the names the scenario itself uses), digital signals as traces and reals and axis
    quantities as analog steps.  The dump and save file are named relative to each other, so
    GTKWave finds the VCD wherever the two are moved together (``gtkwave DIR/x.gtkw``)."""
    from vcd.gtkw import GTKWFlag, GTKWSave

    save_name = Path(path).name
    with open(path, "w", encoding="utf-8") as handle:
        save = GTKWSave(handle)
        save.comment(vcd(f"vc-harness: {title}") if title else "vc-harness")
        save.dumpfile(vcd_name, abspath=False)
        save.savefile(save_name, abspath=False)
        save.timestart(0)
        save.signals_width(320)
        save.sst_expanded(True)
        for quantity in shown:
            history = recording.history(quantity)
            if history is None or not len(history):
                continue
            ref = quantity.ref
            if ref is None or ref.type is SignalType.REAL:
                save.trace(gtkwave_name(quantity), datafmt="real", extraflags=GTKWFlag.analog_step)
                save.blank(analog_extend=True)
                save.blank(analog_extend=True)
            else:
                save.trace(gtkwave_name(quantity), datafmt="hex" if _vcd_width(ref) == 1 else "dec")


def write_traces(recording: Recording, shown: Sequence[Quantity], directory: Path, name: str,
                 title: str = "", units: Units | None = None) -> list[str]:
    """``directory/name.csv``, ``.vcd`` and the GTKWave save file ``.gtkw``; the files written."""
    directory.mkdir(parents=True, exist_ok=True)
    csv_path, vcd_path, gtkw_path = (directory / f"{name}{suffix}" for suffix in (".csv", ".vcd", ".gtkw"))
    write_csv(recording, csv_path, units)
    write_vcd(recording, vcd_path)
    write_gtkw(recording, shown, gtkw_path, vcd_path.name, title)
    return [str(csv_path), str(vcd_path), str(gtkw_path)]


# ---------------------------------------------------------------------------------- cost


def measure_sample_cost(target: ScenarioTarget, cycles: int = 1000) -> float:
    """Microseconds one :meth:`Recorder.sample` costs on ``target`` (stepping excluded)."""
    recorder = Recorder(target)
    recorder.start()
    spent = 0.0
    for _ in range(cycles):
        target.step(1)
        begin = wallclock.perf_counter()
        recorder.sample()
        spent += wallclock.perf_counter() - begin
    return spent / cycles * 1e6
