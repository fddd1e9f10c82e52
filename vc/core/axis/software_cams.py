"""Software cams (seed 003 chapter 21, L40894-41520): position-dependent switching signals of the
machine axes, output to the PLC in DB10.DBB110-117.

A cam pair n (1..32) belongs to the machine axis MD10450[n-1] names (0: the pair does not act; an axis
may have several pairs, L41117-41131).  Its minus and plus cam positions are SD41500-41507 in the
machine coordinate system (L41054-41073).  The NC compares the axis's actual position with them every
IPO cycle (L40963, L41236) and sets the pair's signals:

    signal   linear axis (L40928-40963)           modulo rotary axis (L40974-40999)
    minus    1 at positions <= the minus cam       toggles with every rising edge of the plus signal
    plus     1 at positions >= the plus cam        1 from the minus cam to the plus cam; inverted when
                                                   plus - minus >= 180 degrees or minus > plus, unless
                                                   MD10485 bit 1 (L41043-41047)

Each signal is output earlier by its lead time, MD10460 / MD10461 plus SD41520-41527 (a negative time
delays it, L41133-41196): the cam is judged at the position the axis reaches after that time at its
actual velocity.

Activation of an axis's cams (published as ``SOFTWARE_CAM_STATES``)::

    OFF ──DB31.DBX2.0 = 1 and a measuring system selected──▶ ACTIVE: DB31.DBX62.0 = 1 (L41202-41230)
    ACTIVE ──2.0 = 0, or no measuring system──▶ OFF: 62.0 and the axis's cam signals 0 (L41250-41254)

Reset and emergency stop leave the cams active (L40907).  Only the axes whose cams are active are
evaluated, so a machine that uses none pays nothing in its cycle.  Not modelled: the NC I/O outputs and
their timer (MD10470-10480, L41276-41448), the path-time cams (MD10485 bit 2, L41450-41516), writing
the setting data from the PLC (FB2 / FB3) or the part program.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from interfaces.bit_access import Bit
from interfaces.signal_groups import SoftwareCamRequests, SoftwareCamStatus
from vc.config import md_dictionary as MD
from vc.config.machine_data import MachineData
from vc.core.axis.axis import MachineAxis
from vc.core.interface_map import SignalTable
from vc.core.state_machine import Instance, StateMachine, states, transitions

NO_INVERSION = 1 << 1  # MD10485 bit 1: the plus cam signal of a wide modulo cam is not inverted
HALF_TURN = 180.0


class CamState(Enum):
    OFF = "off"  # DB31.DBX2.0 = 0 or no measuring system: the axis's signals and 62.0 are 0
    ACTIVE = "active"  # the signals follow the axis's actual position, 62.0 = 1


@dataclass(slots=True)
class CamPair:
    """One cam pair of an axis: its positions, lead times and signals."""

    number: int  # 1..32
    minus: float  # SD41500 ff., machine coordinates
    plus: float  # SD41501 ff.
    minus_lead: float  # s: MD10460 + SD41520 ff.
    plus_lead: float  # s: MD10461 + SD41521 ff.
    minus_bit: Bit
    plus_bit: Bit
    inverted: bool  # a modulo cam whose plus signal is inverted (L40997-40999)
    minus_signal: bool = False
    plus_signal: bool = False
    plus_raw: bool = False  # a modulo cam's plus range before the inversion, for the minus toggle


class AxisCams:
    """The cam pairs of one machine axis and their activation."""

    def __init__(self, axis: MachineAxis, pairs: list[CamPair], table: SignalTable, area: bytearray,
                 nck_area: bytearray):
        self.axis = axis
        self.pairs = pairs
        self.state = CamState.OFF
        self._area = area
        self._nck_area = nck_area
        self._requests = SoftwareCamRequests()
        self._decode = table.codec(SoftwareCamRequests).decode
        self._encode = table.codec(SoftwareCamStatus).encode

    def decode_inputs(self) -> None:
        self._decode(self._area, self._requests)

    @property
    def requested(self) -> bool:
        """DB31.DBX2.0."""
        return self._requests.activate

    @property
    def wanted(self) -> bool:
        """DB31.DBX2.0 with a measuring system selected (L41250)."""
        return self._requests.activate and self.axis.active_encoder is not None

    def activate(self, on: bool) -> None:
        self.state = CamState.ACTIVE if on else CamState.OFF
        self._encode(self._area, SoftwareCamStatus(active=on))
        for pair in self.pairs:
            pair.minus_signal = pair.plus_signal = pair.plus_raw = False
            pair.minus_bit.put(self._nck_area, False)
            pair.plus_bit.put(self._nck_area, False)
        if on:
            self.cycle(first=True)

    def cycle(self, first: bool = False) -> None:
        """The signals at the actual position (each cam shifted by its lead time)."""
        axis, area = self.axis, self._nck_area
        modulo = axis.modulo_range
        for pair in self.pairs:
            minus_at = axis.actual + axis.velocity * pair.minus_lead
            plus_at = axis.actual + axis.velocity * pair.plus_lead
            if modulo is None:
                minus, plus = minus_at <= pair.minus, plus_at >= pair.plus
            else:
                minus, plus = self._modulo(pair, axis.shown(minus_at), axis.shown(plus_at), first)
            if minus != pair.minus_signal:
                pair.minus_signal = minus
                pair.minus_bit.put(area, minus)
            if plus != pair.plus_signal:
                pair.plus_signal = plus
                pair.plus_bit.put(area, plus)

    @staticmethod
    def _modulo(pair: CamPair, minus_at: float, plus_at: float, first: bool) -> tuple[bool, bool]:
        """A modulo axis: the plus signal is the range from the minus to the plus cam (inverted for a
        wide cam); the minus signal changes its level at every rising edge of that range, judged with
        the minus cam's lead time [INF]; at the activation it starts at 0 [INF]."""
        entered = _in_range(pair, minus_at)
        rising = entered and not pair.plus_raw and not first
        pair.plus_raw = entered
        minus = not pair.minus_signal if rising else pair.minus_signal
        return minus, _in_range(pair, plus_at) != pair.inverted


def _in_range(pair: CamPair, position: float) -> bool:
    """From the minus cam (included) to the plus cam, on a modulo axis (over the range end if minus > plus)."""
    low, high = pair.minus, pair.plus
    return low <= position < high if low <= high else (position >= low or position < high)


class SoftwareCams:
    """Every cam pair of the NCK, by axis; the NCK runs the active axes' cams each IPO cycle."""

    def __init__(self, nck: MachineData, axes: list[MachineAxis], nck_table: SignalTable,
                 axis_table: SignalTable, nck_area: bytearray, axis_areas: dict[str, bytearray]):
        # every signal is resolved, the cams of every pair: the NC models them whether or not a pair is assigned
        minus_bits = [nck_table.bit(f"basic.in.swCams[0].minus{n}") for n in range(1, MD.SW_CAM_PAIRS + 1)]
        plus_bits = [nck_table.bit(f"basic.in.swCams[0].plus{n}") for n in range(1, MD.SW_CAM_PAIRS + 1)]
        axis_table.codec(SoftwareCamRequests)
        axis_table.codec(SoftwareCamStatus)
        by_number = {axis.config.number: axis for axis in axes}
        no_inversion = bool(nck.int(MD.SW_CAM_MODE) & NO_INVERSION)
        pairs: dict[str, list[CamPair]] = {}
        for index in range(MD.SW_CAM_PAIRS):
            axis = by_number.get(nck.int(MD.SW_CAM_ASSIGN_TAB, index))
            if axis is None:
                continue
            table, entry = divmod(index, 8)
            minus = nck.float(MD.SW_CAM_MINUS_POS_TABS[table], entry)
            plus = nck.float(MD.SW_CAM_PLUS_POS_TABS[table], entry)
            wide = plus - minus >= HALF_TURN or minus > plus
            pairs.setdefault(axis.name, []).append(CamPair(
                index + 1, minus, plus,
                nck.float(MD.SW_CAM_MINUS_LEAD_TIME, index) + nck.float(MD.SW_CAM_MINUS_TIME_TABS[table], entry),
                nck.float(MD.SW_CAM_PLUS_LEAD_TIME, index) + nck.float(MD.SW_CAM_PLUS_TIME_TABS[table], entry),
                minus_bits[index], plus_bits[index], axis.modulo_range is not None and wide and not no_inversion))
        self.of: dict[str, AxisCams] = {
            name: AxisCams(next(axis for axis in axes if axis.name == name), axis_pairs, axis_table,
                           axis_areas[name], nck_area)
            for name, axis_pairs in pairs.items()}
        self.active: list[AxisCams] = []  # the axes whose cams are evaluated
        self.waiting: list[AxisCams] = []  # DB31.DBX2.0 set, but no measuring system selected
        self.busy = False  # an axis is active or waiting: the NCK runs cycle()

    def decode_inputs(self, cams: AxisCams) -> None:
        """The axis's DB31.DBX2.0 or its measuring system selection changed: the cams on or off."""
        cams.decode_inputs()
        self._update(cams)

    def _update(self, cams: AxisCams) -> None:
        requested, wanted = cams.requested, cams.wanted
        if requested and not wanted and cams not in self.waiting:
            self.waiting.append(cams)
        elif (wanted or not requested) and cams in self.waiting:
            self.waiting.remove(cams)
        if wanted != (cams.state is CamState.ACTIVE):
            cams.activate(wanted)
            if wanted:
                self.active.append(cams)
            else:
                self.active.remove(cams)
        self.busy = bool(self.active or self.waiting)

    def cycle(self) -> None:
        """Every active axis's cams on its new actual position (after position control); an axis whose
        measuring system was deselected goes off, one selected again on (L41250-41254)."""
        for cams in list(self.waiting):
            self._update(cams)
        for cams in list(self.active):
            if cams.axis.active_encoder is None:
                self._update(cams)
            else:
                cams.cycle()


SOFTWARE_CAM_STATES: StateMachine[AxisCams] = StateMachine(
    __name__, "software_cams", "Software cams of an axis (DB31.DBX2.0 / 62.0)", Instance.AXIS,
    states(*CamState),
    transitions(("OFF", "ACTIVE", "DB31.DBX2.0 = 1 with a measuring system"),
                ("ACTIVE", "OFF", "DB31.DBX2.0 = 0, no measuring system")),
    read=lambda cams: cams.state)
