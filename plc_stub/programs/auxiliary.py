"""The PLC's side of the auxiliary functions, shared by the programs coolant, turret and tool_change.

The NC outputs a block's M, S, T, D, DL, H and F functions to DB21 (DBB58 ff.); a change signal
says which slot holds a new function, for exactly one PLC cycle, and the NC takes the functions
as acknowledged one cycle later (vc/core/auxiliary/output.py).  A machine builder's program reads
them once per scan at its start (network 10 here), like the user part of the real control's
basic program, and its networks act on them.  A network that must hold the program - the turret
indexing to its station, the coolant pressure building up - sets the read-in disable DB21.DBX6.1
in the scan in which it sees the function: the NC ends the block once it has the acknowledgement,
and the next block waits until the PLC releases 6.1 (the program shows "waiting").  Faults are
the control's PLC user alarms: a bit of DB2 (user area 0, 700000 + n), cleared by the program when
the operator presses the reset key and the cause is gone.

:class:`AuxiliaryMachine` is the program ``spindle`` plus, after its networks 1-9:

10. Read the functions of this cycle (first channel): the M functions with their extended
    address, the T, D and H functions; collect the holds of the networks after it.
... the networks of the subclass ...
Last: DB21.DBX6.1 = OR of every network's hold, DB21.DBX6.0 (feed disable) also on a network's
    feed hold, the PLC alarm bits; the reset key acknowledges the faults (each network).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from interfaces.signal_groups import AUX_FUNCTION, AuxFeedFunction, AuxRealFunction, AuxWholeFunction
from plc_stub.io import Bool, PlcIo
from plc_stub.programs.basic_machine import pressed
from plc_stub.programs.spindle import Spindle

PLC_ALARM = "PLCALARMS.userArea0.out.alarm{number}"  # DB2: alarm 700000 + n is DB2.DBX180.0 + n


@dataclass(frozen=True, slots=True)
class Function:
    """One auxiliary function as the PLC reads it: M8 is ("M", 0, 8), M2=10 ("M", 2, 10)."""

    kind: str
    extension: int
    value: float


Slot = AuxWholeFunction | AuxRealFunction | AuxFeedFunction
_SLOTS: tuple[tuple[str, int, type[Slot]], ...] = (
    ("M", 5, AuxWholeFunction), ("S", 3, AuxRealFunction), ("T", 1, AuxWholeFunction), ("D", 1, AuxWholeFunction),
    ("DL", 1, AuxRealFunction), ("H", 3, AuxRealFunction), ("F", 1, AuxFeedFunction))


class AuxiliaryInputs:
    """The channel's output slots as the PLC reads them: every slot whose change signal is 1, in
    the order of the slots (the NC fills them in the order of the block)."""

    def __init__(self, io: PlcIo, channel: str):
        self._slots: list[tuple[str, Bool, Callable[[], Slot]]] = []
        for kind, count, group in _SLOTS:
            for number in range(1, count + 1):
                prefix = AUX_FUNCTION.format(kind=kind, number=number)
                self._slots.append((kind, io.input(f"{channel}.{prefix}change"),
                                    io.input_group(group, channel, prefix).read))

    def read(self) -> list[Function]:
        functions = []
        for kind, change, read in self._slots:
            if change.value:
                values = read()
                functions.append(Function(kind, values.extended_address, values.value))
        return functions


class AuxiliaryMachine(Spindle):
    PROGRAM = "auxiliary"

    def __init__(self, io: PlcIo):
        super().__init__(io)
        channel = io.environment.catalog.layout.channels[0]
        self.channel = channel
        self.inputs = AuxiliaryInputs(io, channel)
        self.functions: list[Function] = []  # network 10: what the NC output in this cycle
        self.read_in_disable = io.output(f"{channel}.basic.out.disableReadIn")
        self.feed_disable = io.output(f"{channel}.basic.out.disableFeed")
        self.program_ended = io.input(f"{channel}.basic.in.m02M30Active")
        self.channel_reset = io.input(f"{channel}.basic.in.stateReset")
        self.emergency_stop_active = io.input("NC.basic.in.emergencyStopActive")
        self.hold_read_in = False  # this scan: a network holds the program
        self.hold_feed = False  # this scan: a network holds the slides
        self._io = io

    def plc_alarm(self, number: int) -> Bool:
        """The DB2 bit of PLC user alarm ``number`` (700000 ..)."""
        return self._io.output(PLC_ALARM.format(number=number))

    @property
    def reset_pressed(self) -> bool:
        return pressed(self.key_reset)

    def ob1(self) -> None:
        super().ob1()
        self.read_functions()
        self.hold_read_in = False
        self.hold_feed = False
        self.auxiliary_networks()
        self.holds()

    # Network 10 --------------------------------------------------------------------------
    def read_functions(self) -> None:
        self.functions = self.inputs.read()

    def auxiliary_networks(self) -> None:
        """The networks of the machine's auxiliary functions (the subclasses')."""

    # Last network ------------------------------------------------------------------------
    def holds(self) -> None:
        self.read_in_disable.value = self.hold_read_in
        if self.hold_feed:
            self.feed_disable.value = True  # with network 3's feed stop latch

    def m_function(self, value: int, extension: int = 0) -> bool:
        """The NC output M<value> (with that extended address) in this cycle."""
        return any(f.kind == "M" and f.value == value and f.extension == extension for f in self.functions)

    def last(self, kind: str) -> Function | None:
        """The last function of ``kind`` output in this cycle (T, D ...)."""
        found = [f for f in self.functions if f.kind == kind]
        return found[-1] if found else None
