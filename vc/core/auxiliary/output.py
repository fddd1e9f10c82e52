"""Auxiliary function output to the PLC: a channel's M, S, T, D, DL, H and F functions in DB21.

The blocks hand their functions over in batches, one batch per time of output (before, during,
after the motion: ``OutputTime``); a batch goes into the channel's output slots (DB21.DBB58 ff.)
with a change signal per function and waits for the PLC.  As on the real control, whose basic
program shows the functions to the user program for one OB1 cycle and acknowledges them to the
NC at the start of the next one (Basic Functions H2), the NC takes a batch as read after the
PLC's next cycle and as acknowledged after the cycle after that: by then the PLC's answer (a
read-in disable that holds the program for a tool change) is in the interface.  The output slots
as the PLC sees them::

    IDLE ──a batch is due (queued in the order of the blocks)──▶ OUTPUT: values, change signals,
                                                                 decoded M signals
    OUTPUT ──a PLC cycle: the PLC has read the batch──▶ READ: change signals 0 with the next NC cycle
    READ ──another batch queued──▶ OUTPUT (the earlier batch waits for its acknowledgement)
    READ ──a PLC cycle: its answer is in the interface──▶ IDLE: the batch is acknowledged
    any ──reset──▶ IDLE: the batches not acknowledged are dropped, the change signals 0

A normal function holds its block: before the motion until it is acknowledged, during the motion
and at the block end until it is acknowledged (``BlockExecution``); a quick one (QU) never holds
it.  The values stay in the slots until functions of the same type overwrite them.  Between two
blocks with auxiliary functions the unit does nothing at all: the channel asks it only when a
block brings functions and the NCK only while a batch is on its way.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass
from enum import Enum

from interfaces.bit_access import Bit
from interfaces.signal_groups import (
    AUX_FUNCTION,
    AUX_M_DECODED,
    AuxFeedFunction,
    AuxRealFunction,
    AuxWholeFunction,
    ProgramStopStatus,
)
from vc.core.interface_map import SignalTable
from vc.core.program.commands import AuxiliaryFunction, OutputTime
from vc.core.state_machine import Instance, StateMachine, states, transitions

SLOTS = {"M": 5, "S": 3, "T": 1, "D": 1, "DL": 1, "H": 3, "F": 1}  # output slots per type in DB21
DECODED_M = 100  # M00 .. M99 have a decoded signal (DB21.DBB194 .. 206)
_REAL_KINDS = ("S", "DL", "H")
_WHOLE_KINDS = ("M", "T", "D")


class OutputState(Enum):
    IDLE = "no auxiliary function on its way to the PLC"
    OUTPUT = "change signals set: the functions wait for the PLC's next cycle"
    READ = "the PLC has read them; its next cycle acknowledges them"


@dataclass(slots=True)
class Batch:
    """Functions of one block that go out together, and how far they are."""

    functions: tuple[AuxiliaryFunction, ...]
    read: bool = False
    acknowledged: bool = False

    @property
    def holds_block(self) -> bool:
        """The block waits for it: a normal function not yet acknowledged (quick ones never hold)."""
        return not self.acknowledged and any(not function.quick for function in self.functions)


@dataclass(slots=True)
class BlockBatches:
    """The batches of the block in progress, by the time they go out."""

    before: Batch | None = None
    during: Batch | None = None
    at_end: tuple[AuxiliaryFunction, ...] = ()  # go out once the motion is done
    end: Batch | None = None
    end_queued: bool = False


class AuxiliaryOutput:
    """The auxiliary function interface of one channel (see the module docstring)."""

    def __init__(self, table: SignalTable, area: bytearray):
        self._area = area
        self._whole = {kind: [table.codec(AuxWholeFunction, AUX_FUNCTION.format(kind=kind, number=number)).encode
                              for number in range(1, SLOTS[kind] + 1)] for kind in _WHOLE_KINDS}
        self._real_writers = {
            kind: [table.codec(AuxRealFunction, AUX_FUNCTION.format(kind=kind, number=number)).encode
                   for number in range(1, SLOTS[kind] + 1)] for kind in _REAL_KINDS}
        self._feed = table.codec(AuxFeedFunction, AUX_FUNCTION.format(kind="F", number=1)).encode
        decoded = [table.bit(AUX_M_DECODED.format(number=number)) for number in range(DECODED_M)]
        self._decoded: tuple[Bit, ...] = tuple(decoded)
        first, last = decoded[0].byte, decoded[-1].byte
        self._decoded_bytes = slice(first, last + 1)
        self._encode_stop = table.codec(ProgramStopStatus).encode
        self._values: dict[tuple[str, int], tuple[int, float]] = {}  # (kind, slot) -> (extension, value) shown
        # (kind, slot) -> (change, quick, extension, value) as last written: a slot is encoded again only
        # when it differs (a batch touches a few of the 15 slots)
        self._written: dict[tuple[str, int], tuple[bool, bool, int, float]] = {}
        self.state = OutputState.IDLE
        self._queue: deque[Batch] = deque()
        self._current: Batch | None = None  # the batch in the slots
        self._unacknowledged: list[Batch] = []  # read, waiting for the PLC's next cycle
        self.block = BlockBatches()
        self.dirty = False  # the slots or the stop status need writing in the outputs phase
        self.stopped_at_m0 = False  # DB21.DBX32.5
        self.ended_with_m30 = False  # DB21.DBX33.5
        self._stop_shown = (False, False)

    @property
    def busy(self) -> bool:
        """A batch is queued, in the slots or waiting for its acknowledgement."""
        return self.state is not OutputState.IDLE or bool(self._queue) or bool(self._unacknowledged)

    # ------------------------------------------------------------------ what the blocks hand over
    def block_started(self, functions: Sequence[AuxiliaryFunction]) -> None:
        """A block with auxiliary functions starts: the functions before and during its motion are
        queued now, those of its end when the motion is done (:meth:`block_end_reached`)."""
        before = tuple(function for function in functions if function.time is OutputTime.BEFORE_MOTION)
        during = tuple(function for function in functions if function.time is OutputTime.DURING_MOTION)
        at_end = tuple(function for function in functions if function.time is OutputTime.AT_BLOCK_END)
        self.block = BlockBatches(self._queued(before), self._queued(during), at_end)

    def block_end_reached(self) -> None:
        """The block's motion is done: its functions of the block end go out (once)."""
        block = self.block
        if not block.end_queued:
            block.end_queued = True
            block.end = self._queued(block.at_end)

    @property
    def motion_may_start(self) -> bool:
        """The functions before the motion are acknowledged (MD22200 = 0 ...)."""
        before = self.block.before
        return before is None or not before.holds_block

    @property
    def block_may_end(self) -> bool:
        """Every normal function of the block is acknowledged."""
        block = self.block
        return not any(batch is not None and batch.holds_block for batch in (block.before, block.during, block.end))

    def block_changed(self) -> None:
        self.block = BlockBatches()

    def _queued(self, functions: tuple[AuxiliaryFunction, ...]) -> Batch | None:
        if not functions:
            return None
        batch = Batch(functions)
        self._queue.append(batch)
        if self.state is not OutputState.OUTPUT:
            self._output_next()
        return batch

    # ------------------------------------------------------------------ the PLC's cycles
    def plc_cycle(self) -> None:
        """The PLC has run a cycle on the interface as the NC last wrote it (called after every
        PLC cycle while :attr:`busy`)."""
        for batch in self._unacknowledged:
            batch.acknowledged = True  # the PLC's answer to it is in the interface now
        self._unacknowledged.clear()
        if self.state is OutputState.OUTPUT:
            self._output()
        elif self.state is OutputState.READ:
            self._read()

    def _output(self) -> None:
        """OUTPUT: the PLC has read the batch in its cycle; the change signals go with the next NC
        cycle, unless the next batch takes the slots at once."""
        current = self._current
        assert current is not None
        current.read = True
        self._unacknowledged.append(current)
        self._current = None
        self.state = OutputState.READ
        self.dirty = True
        if self._queue:
            self._output_next()

    def _read(self) -> None:
        """READ: the batch is acknowledged (above); nothing is in the slots any more."""
        self.state = OutputState.IDLE

    def _output_next(self) -> None:
        """IDLE / READ: the next batch goes into the slots."""
        self._current = self._queue.popleft()
        self.state = OutputState.OUTPUT
        self.dirty = True

    # ------------------------------------------------------------------ reset
    def reset(self) -> None:
        """Reset: the functions not yet acknowledged are dropped, the change signals go."""
        if self.busy:
            self._queue.clear()
            self._unacknowledged.clear()
            self._current = None
            self.state = OutputState.IDLE
            self.dirty = True
        self.block = BlockBatches()
        self.stopped_at_m0 = False
        self.show_stop()

    def show_stop(self) -> None:
        """DB21.DBX32.5 / 33.5 follow ``stopped_at_m0`` / ``ended_with_m30`` (written when they change)."""
        if (self.stopped_at_m0, self.ended_with_m30) != self._stop_shown:
            self.dirty = True

    # ------------------------------------------------------------------ the outputs phase
    def write_outputs(self) -> None:
        """The slots as the state says: the batch with its change signals, or the change signals 0."""
        self.dirty = False
        area = self._area
        shown = self._current.functions if self.state is OutputState.OUTPUT and self._current is not None else ()
        area[self._decoded_bytes] = bytes(self._decoded_bytes.stop - self._decoded_bytes.start)
        used = dict.fromkeys(SLOTS, 0)
        changed: set[tuple[str, int]] = set()
        for function in shown:
            slot = used[function.kind]
            used[function.kind] = slot + 1
            self._values[(function.kind, slot)] = (function.extension, function.value)
            self._write_slot(function.kind, slot, True, function.quick)
            changed.add((function.kind, slot))
            if function.kind == "M" and function.extension == 0 and function.value < DECODED_M:
                self._decoded[int(function.value)].put(area, True)
        for kind, count in SLOTS.items():
            for slot in range(count):
                if (kind, slot) not in changed:
                    self._write_slot(kind, slot, False, False)
        stop = (self.stopped_at_m0, self.ended_with_m30)
        if stop != self._stop_shown:
            self._stop_shown = stop
            self._encode_stop(area, ProgramStopStatus(m00_m01_active=stop[0], m02_m30_active=stop[1]))

    def _write_slot(self, kind: str, slot: int, change: bool, quick: bool) -> None:
        extension, value = self._values.get((kind, slot), (0, 0.0))
        content = (change, quick, extension, value)
        if self._written.get((kind, slot)) == content:
            return  # the slot's bytes hold it already
        self._written[(kind, slot)] = content
        area = self._area
        if kind in _WHOLE_KINDS:
            self._whole[kind][slot](area, AuxWholeFunction(change=change, quick=quick, extended_address=extension,
                                                           value=int(value)))
        elif kind in _REAL_KINDS:
            self._real_writers[kind][slot](area, AuxRealFunction(change=change, quick=quick,
                                                                 extended_address=extension, value=float(value)))
        else:
            self._feed(area, AuxFeedFunction(change=change, extended_address=extension, value=float(value)))


AUX_OUTPUT_STATES: StateMachine[AuxiliaryOutput] = StateMachine(
    __name__, "auxiliary_output", "Auxiliary function output to the PLC (DB21.DBB58 ff.)", Instance.CHANNEL,
    states(*OutputState),
    transitions(("IDLE", "OUTPUT", "a block's functions are due"),
                ("OUTPUT", "READ", "a PLC cycle: the PLC has read them"),
                ("READ", "OUTPUT", "another batch queued"),
                ("READ", "IDLE", "a PLC cycle: acknowledged"),
                ("OUTPUT", "IDLE", "reset")),
    read=lambda output: output.state)
