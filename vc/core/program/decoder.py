"""The decoder of one block: the block, the modal state and the plan it fills, and what the word
handlers (``motion_words``, ``spindle_words``, ``retract_words``) share while they read the block.

A handler reports a faulty word with :meth:`BlockDecoder.fail`; the first alarm of a block is the
one raised.
"""

from __future__ import annotations

from collections.abc import Collection, Mapping

from vc.config import md_dictionary as MD
from vc.config.model import ChannelConfig
from vc.core.axis import rotary
from vc.core.axis.axis import MachineAxis
from vc.core.axis.indexing import ALARM_HIRTH_NOT_AN_INDEX_POSITION, ALARM_NOT_AN_INDEXING_AXIS, CODED_POSITIONS
from vc.core.axis.rotary import ROTARY_MODES
from vc.core.program.block_plan import BlockPlan, DecodeAlarm, ModalState
from vc.core.program.commands import SpindleCommand
from vc.core.program.five_axis_program import FIVE_AXIS_G_CODES, FiveAxisWords
from vc.core.program.program import Block, ValueFunction, Word

ALARM_WRONG_AXIS_TYPE = 14092  # [control] "axis %3 is wrong axis type": MD30460 bit 8 as a path axis
_END_POINT_FUNCTIONS = ("AC", "IC", *ROTARY_MODES)  # the value functions of an axis's end point
# DAC / DIC / RAC / RIC: one value of the transverse axis in diameter or radius, absolute or incremental,
# whatever DIAMON / DIAM90 / DIAMOF say (seed 003 L10336-10347): (mode, divisor)
DIAMETER_FUNCTIONS = {"DAC": ("AC", 2.0), "DIC": ("IC", 2.0), "RAC": ("AC", 1.0), "RIC": ("IC", 1.0)}
ALARM_NO_TRANSVERSE_AXIS = 16510  # DIAMON / DIAM90 / DAC ... without a transverse axis [control]


class BlockDecoder:
    def __init__(self, block: Block, modal: ModalState, channel: ChannelConfig, axes: dict[str, MachineAxis],
                 program_positions: Mapping[str, float], limits_checked_elsewhere: Collection[str]):
        self.block = block
        self.modal = modal
        self.channel = channel
        self.axes = axes
        self.program_positions = program_positions  # where a transform puts an axis in program coordinates
        self.limits_checked_elsewhere = limits_checked_elsewhere  # a transform checks their software limits
        if any(isinstance(item, Word) and item.address == "G" and item.value == 53 for item in block.items):
            self.program_positions = {}  # G53: machine coordinates; incremental words count from the setpoint
        self.plan = BlockPlan()
        self.alarm: DecodeAlarm | None = None
        self.dwell_requested = False
        self.reference_requested = False  # G74
        self.other_g_words = False  # G words besides G74 (a G74 block stands alone)
        self.dwell_value: float | None = None
        self.feed_word: float | None = None
        self.polygon_block = any(isinstance(item, Word) and item.address == "G" and round(item.value * 10) in (512, 502)
                                 for item in block.items)
        self.polygon_words: dict[str, float] = {}
        self.five_axis_codes = {round(item.value * 10) / 10 for item in block.items
                                if isinstance(item, Word) and item.address == "G"} & FIVE_AXIS_G_CODES
        if self.five_axis_codes:
            self.plan.five_axis = FiveAxisWords()
        self.pitch_words: dict[str, float] = {}  # I / J / K: thread pitch (G33, G331) or circle centre (G2, G3)
        self.radius_word: float | None = None  # R / CR=: circle radius (G2, G3)
        self.start_angle: float | None = None  # SF= of a G33 block

    def fail(self, number: int, *parameters: object, axis: str = "") -> None:
        if self.alarm is None:
            self.alarm = DecodeAlarm(number, parameters, axis)

    def unknown(self, text: str) -> None:
        self.fail(12550, self.channel.name, self.block.label, text)

    def spindle(self, number: int | None) -> SpindleCommand | None:
        """The command of spindle ``number`` (None: the channel's master spindle, MD20090)."""
        if number is None:
            number = self.channel.md.int(MD.SPIND_DEF_MASTER_SPIND)
        for name, axis in self.axes.items():
            if axis.config.spindle_number == number:
                return self.plan.spindles.setdefault(name, SpindleCommand())
        self.fail(16105, self.channel.name, self.block.label, number)
        return None

    def spindle_axis(self, text: object) -> str | None:
        """The machine axis of ``S<n>`` (or of a spindle's axis name) in a coupling call."""
        name = str(text).strip().upper()
        if len(name) > 1 and name[0] == "S" and name[1:].isdigit():
            command_count = len(self.plan.spindles)
            found = self.spindle(int(name[1:]))
            if found is None:
                return None
            axis = next(a for a, c in self.plan.spindles.items() if c is found)
            if len(self.plan.spindles) > command_count and found == SpindleCommand():
                del self.plan.spindles[axis]  # only looked up: no spindle function in the block
            return axis
        machine_axis = self.machine_axis(name)
        if machine_axis is not None and self.axes[machine_axis].is_spindle:
            return machine_axis
        self.fail(16105, self.channel.name, self.block.label, name)
        return None

    def transverse_axis(self) -> str | None:
        """The machine axis of the channel's transverse axis (MD20100: a geometry axis name), or None."""
        axis = self.channel.transverse_axis()
        return axis if axis in self.axes else None

    def machine_axis(self, name: str) -> str | None:
        """The machine axis of this channel that ``name`` (geometry, channel or machine axis name) means."""
        machine_axis = self.channel.axis_for_program_name(name)
        return machine_axis if machine_axis in self.axes else None

    def positioning_only(self, machine_axis: str) -> bool:
        """MD30460 bit 8 (seed 003 L10843-10858): a positioning axis or auxiliary spindle only."""
        return self.axes[machine_axis].positioning_only

    def refuse_positioning_only(self, machine_axis: str, name: str) -> bool:
        """14092 [control] for an axis of MD30460 bit 8 as a path axis or the spindle of a thread."""
        if not self.positioning_only(machine_axis):
            return False
        self.fail(ALARM_WRONG_AXIS_TYPE, self.channel.name, self.block.label, name, axis=machine_axis)
        return True

    def refuse_hirth(self, machine_axis: str, name: str) -> bool:
        """17501 [control] for an indexing axis with a Hirth joint in a function it must not be used
        with (seed 003 §11.5 L14064-14073: PRESETON, G95): the joint locks it on its positions."""
        index = self.axes[machine_axis].index
        if index is None or not index.hirth:
            return False
        self.fail(ALARM_HIRTH_NOT_AN_INDEX_POSITION, self.channel.name, self.block.label, name, axis=machine_axis)
        return True

    def axis_value(self, name: str, value: object) -> None:
        machine_axis = self.machine_axis(name)
        if machine_axis is None:
            self.unknown(name)
            return
        if self.refuse_positioning_only(machine_axis, name):
            return  # no path axis (L10846-10849)
        axis = self.axes[machine_axis]
        if axis.is_spindle and not axis.axis_mode:
            # the axis name of a spindle switches it to axis mode: an implicit M70 (L17421-17462)
            self.plan.spindles.setdefault(machine_axis, SpindleCommand()).axis_mode = True
        end = self.end_point(machine_axis, name, value, self.plan.targets)
        if end is not None:
            self.plan.targets[machine_axis] = end

    def end_point(self, machine_axis: str, name: str, value: object, given: Mapping[str, float]) -> float | None:
        """The machine end point of ``name=value``: AC( ) / IC( ) / DC( ) / ACP( ) / ACN( ) or the modal
        G90 / G91, by the rules of rotary axes with and without modulo (``vc/core/axis/rotary.py``);
        it counts from ``given`` (an end point already in the block), the program position or the
        setpoint.  Under a five-axis transform the values are program coordinates, taken as written;
        a spindle's axis words keep their own rules (SPOS, ``spindle_words``)."""
        if isinstance(value, ValueFunction) and value.name in CODED_POSITIONS:
            return self._coded_end_point(machine_axis, name, value, given)
        if isinstance(value, ValueFunction) and value.name in _END_POINT_FUNCTIONS:
            mode, number = value.name, value.value
        elif isinstance(value, ValueFunction) and value.name in DIAMETER_FUNCTIONS:
            if machine_axis != self.transverse_axis():
                self.fail(ALARM_NO_TRANSVERSE_AXIS, self.channel.name, self.block.label, name, axis=machine_axis)
                return None
            mode, divisor = DIAMETER_FUNCTIONS[value.name]
            number = value.value / divisor
        elif isinstance(value, float):
            mode, number = "G90" if self.modal.absolute else "IC", value
        else:
            self.unknown(f"{name}={value}")
            return None
        if self.modal.diameter != "DIAMOF" and isinstance(value, (float, ValueFunction)) and \
                not (isinstance(value, ValueFunction) and value.name in DIAMETER_FUNCTIONS) and \
                machine_axis == self.transverse_axis() and (mode != "IC" or self.modal.diameter == "DIAMON"):
            number /= 2.0  # DIAMON: every end point in diameter; DIAM90: the absolute ones (L10360-10415)
        if mode == "IC" and self.plan.five_axis is not None:
            self.plan.five_axis.incremental_axes = True
        axis = self.axes[machine_axis]
        start = given.get(machine_axis, self.program_positions.get(machine_axis, axis.setpoint))
        if (axis.is_spindle or self.plan.five_axis is not None or self.modal.five_axis.transformed) and \
                mode in ("AC", "G90", "IC"):
            return start + number if mode == "IC" else number  # a spindle in axis mode counts on [control]
        end, alarm = rotary.end_point(axis.config, start, mode, number)
        if not alarm and axis.index is not None:
            alarm = axis.index.hirth_refusal(end, axis.referenced)
        if alarm:
            self.fail(alarm, self.channel.name, self.block.label, name, axis=machine_axis)
            return None
        return end

    def _coded_end_point(self, machine_axis: str, name: str, value: ValueFunction,
                         given: Mapping[str, float]) -> float | None:
        """``CAC(i)``, ``CACP(i)``, ``CACN(i)``, ``CDC(i)``, ``CIC(i)`` of an indexing axis (seed 003
        §11.4, ``vc/core/axis/indexing.py``): the end point of index position i; 17500 on an axis
        that is no indexing axis, 17510 for a number that names no index position."""
        axis = self.axes[machine_axis]
        if axis.index is None:
            self.fail(ALARM_NOT_AN_INDEXING_AXIS, self.channel.name, self.block.label, name, axis=machine_axis)
            return None
        start = given.get(machine_axis, axis.setpoint)
        end, alarm = axis.index.coded_end_point(axis.config, start, value.name, value.value, axis.dyn.fine_window)
        if not alarm:
            alarm = axis.index.hirth_refusal(end, axis.referenced)
        if alarm:
            self.fail(alarm, self.channel.name, self.block.label, name, axis=machine_axis)
            return None
        return end
