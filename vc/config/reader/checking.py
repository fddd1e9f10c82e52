"""The rules across a machine as read, checked once its file and a scenario's overrides are read:
what relates one value to others (each value alone was checked as it was read).

* the IPO cycle (MD10050 x MD10070) is a whole number of microseconds;
* an axis: its spindle number (MD35000) is unique and makes a rotary axis, its software limits
  (MD36100 < MD36110), its master channel (MD30550), a gearbox (against MD35000, MD35090 and the
  I/O list), a chuck (against MD35000 and the I/O list), generator operation (against the DC
  link and the drive's parameters); gearbox and chuck I/O need their gearbox and chuck;
* a channel: the names of its channel axes (MD20080) and geometry axes (MD20060), the channel
  axis serving each geometry axis (MD20050), the synchronous spindle pair (MD21300) and its
  control parameters, the master spindle (MD20090);
* the ``can:`` section against the built machine (vc/config/can_config.py).

Each problem is reported at the value it is about: where it is written (the file or the
overrides), or, for a default, where its instance is declared.
"""

from __future__ import annotations

from collections.abc import Callable

from interfaces.plant_io import (
    chuck_axis,
    chuck_close,
    chuck_closed,
    chuck_release,
    gear_engaged,
    gear_shift,
    gearbox_point,
)
from vc.config import md_dictionary as mdd
from vc.config.can_config import check_against_machine
from vc.config.machine_data import MdDef
from vc.config.model import (
    DC_LINK_PER_SUPPLY_VOLT,
    PULSE_CANCELLATION_PER_SUPPLY_VOLT,
    SPEED_HYSTERESIS,
    MachineConfig,
    machine_ipo_cycle_us,
)
from vc.config.reader.located import NAME, AxisEntry, ChannelEntry, LocatedMachine, count
from vc.located_yaml import Problems

_REQUIRED_GEARBOX_KEYS = {"stages": "the number of gear stages",
                          "shift_time": "the seconds the shift actuator must push while the motor turns"}
# the control parameters LS and FS of a synchronous spindle pair must have alike (seed 003 L23736-23748)
COUPLED_LIKE_PARAMETERS = (mdd.FIPO_TYPE, mdd.AX_JERK_ENABLE, mdd.AX_JERK_MODE, mdd.AX_JERK_TIME, mdd.AX_JERK_FREQ,
                           mdd.AX_JERK_DAMP, mdd.JOG_AND_POS_JERK_ENABLE, mdd.JOG_AND_POS_MAX_JERK)


def check_machine(machine: LocatedMachine, problems: Problems) -> None:
    """Every rule across ``machine`` but CAN's (:func:`check_can` needs the built machine)."""
    _Checker(machine, problems).check()


def check_can(machine: LocatedMachine, config: MachineConfig, problems: Problems) -> None:
    """The ``can:`` section against the machine built from ``machine``; without a section the
    defaults fit every machine that gets this far."""
    if machine.can_mark is not None:
        check_against_machine(machine.can, machine_ipo_cycle_us(config), config.plc_cycle_ipo, config.layout,
                              machine.plant_io.area_sizes(), machine.can_mark, problems)


class _Checker:
    def __init__(self, machine: LocatedMachine, problems: Problems):
        self.machine = machine
        self.add = problems.add

    def check(self) -> None:
        self._check_ipo_cycle()
        spindles: dict[int, str] = {}
        channel_numbers = {name: number for number, name in enumerate(self.machine.channels, start=1)}
        for axis in self.machine.axes.values():
            self._check_axis(axis, spindles, channel_numbers)
        self._check_gearbox_io()
        self._check_chuck_io()
        for channel in self.machine.channels.values():
            self._check_channel(channel)

    def _check_ipo_cycle(self) -> None:
        nck = self.machine.nck
        clock = float(nck.value(mdd.SYSCLOCK_CYCLE_TIME))
        microseconds = clock * int(nck.value(mdd.IPO_SYSCLOCK_TIME_RATIO)) * 1e6
        if abs(microseconds - round(microseconds)) > 1e-6:
            mark = nck.mark_of(mdd.SYSCLOCK_CYCLE_TIME)
            if not nck.is_written(mdd.SYSCLOCK_CYCLE_TIME):
                mark = nck.mark_of(mdd.IPO_SYSCLOCK_TIME_RATIO)
            self.add(mark, f"the IPO cycle MD10050 SYSCLOCK_CYCLE_TIME x MD10070 IPO_SYSCLOCK_TIME_RATIO ="
                           f" {microseconds:g} us is not a whole number of microseconds")

    # ------------------------------------------------------------------ axes

    def _check_axis(self, entry: AxisEntry, spindles: dict[int, str], channel_numbers: dict[str, int]) -> None:
        data = entry.data
        spindle = entry.spindle_number
        if spindle:
            mark = data.mark_of(mdd.SPIND_ASSIGN_TO_MACHAX)
            if spindle in spindles:
                self.add(mark,
                         f"{entry.name}: spindle number {spindle} (MD35000 SPIND_ASSIGN_TO_MACHAX) is"
                         f" already the number of {spindles[spindle]}")
            else:
                spindles[spindle] = entry.name
            if not data.value(mdd.IS_ROT_AX):
                self.add(mark,
                         f"{entry.name}: MD35000 SPIND_ASSIGN_TO_MACHAX = {spindle} makes it a spindle,"
                         " which needs MD30300 IS_ROT_AX = 1")
        minus, plus = data.value(mdd.POS_LIMIT_MINUS), data.value(mdd.POS_LIMIT_PLUS)
        assert isinstance(minus, float) and isinstance(plus, float)
        # on a modulo rotary axis the limits are modulo positions: minus above plus leaves the gap
        # between them forbidden (seed 003 L12900-12905)
        modulo = bool(data.value(mdd.IS_ROT_AX)) and bool(data.value(mdd.ROT_IS_MODULO))
        if minus >= plus and not (modulo and minus != plus):
            self.add(data.mark_of(mdd.POS_LIMIT_MINUS if data.is_written(mdd.POS_LIMIT_MINUS)
                                  else mdd.POS_LIMIT_PLUS),
                     f"{entry.name}: MD36100 POS_LIMIT_MINUS ({minus}) must be below"
                     f" MD36110 POS_LIMIT_PLUS ({plus})")
        minus_2, plus_2 = data.value(mdd.POS_LIMIT_MINUS2), data.value(mdd.POS_LIMIT_PLUS2)
        assert isinstance(minus_2, float) and isinstance(plus_2, float)
        if minus_2 >= plus_2 and not (modulo and minus_2 != plus_2):
            self.add(data.mark_of(mdd.POS_LIMIT_MINUS2 if data.is_written(mdd.POS_LIMIT_MINUS2)
                                  else mdd.POS_LIMIT_PLUS2),
                     f"{entry.name}: MD36120 POS_LIMIT_MINUS2 ({minus_2}) must be below"
                     f" MD36130 POS_LIMIT_PLUS2 ({plus_2})")
        master = int(data.value(mdd.AXCONF_ASSIGN_MASTER_CHAN))
        if master and entry.channel and master != channel_numbers[entry.channel]:
            self.add(data.mark_of(mdd.AXCONF_ASSIGN_MASTER_CHAN),
                     f"{entry.name}: MD30550 AXCONF_ASSIGN_MASTER_CHAN = {master}, but {entry.name} is an"
                     f" axis of channel {channel_numbers[entry.channel]} ({entry.channel})")
        self._check_gearbox(entry, spindle)
        self._check_chuck(entry, spindle)
        self._check_generator(entry)
        self._check_indexing(entry)

    def _check_indexing(self, entry: AxisEntry) -> None:
        """An indexing axis (MD30500): its table has positions, ascending, each different, inside a
        modulo axis's range (L13578-13603); equidistant ones a spacing; a Hirth joint only on a rotary axis
        with equidistant positions (L13740-13767)."""
        data, nck = entry.data, self.machine.nck
        assignment = int(data.value(mdd.INDEX_AX_ASSIGN_POS_TAB))
        if data.value(mdd.HIRTH_IS_ACTIVE) and (assignment != 3 or not data.value(mdd.IS_ROT_AX)):
            # L13740-13767: a rotary axis with equidistant index positions
            self.add(data.mark_of(mdd.HIRTH_IS_ACTIVE),
                     f"{entry.name}: MD30505 HIRTH_IS_ACTIVE = 1, the Hirth joint, needs a rotary axis (MD30300"
                     f" IS_ROT_AX = 1) with equidistant index positions (MD30500 = 3), here MD30500 = {assignment}")
        gantry = int(data.value(mdd.GANTRY_AXIS_TYPE))
        if data.value(mdd.HIRTH_IS_ACTIVE) and gantry // 10 == 1:
            # L14083-14093: a Hirth axis is never the following axis of a coupling, nor of a gantry grouping
            self.add(data.mark_of(mdd.HIRTH_IS_ACTIVE),
                     f"{entry.name}: MD30505 HIRTH_IS_ACTIVE = 1, the Hirth joint, on a synchronized axis of gantry"
                     f" grouping {gantry % 10} (MD37100 GANTRY_AXIS_TYPE = {gantry}): a Hirth axis cannot follow"
                     " another axis (L14083-14093)")
        if not assignment:
            return
        mark = data.mark_of(mdd.INDEX_AX_ASSIGN_POS_TAB)
        if entry.is_spindle:
            self.add(mark, f"{entry.name}: a spindle cannot be an indexing axis (MD30500 = {assignment})")
        modulo = bool(data.value(mdd.IS_ROT_AX)) and bool(data.value(mdd.ROT_IS_MODULO))
        if assignment == 3:
            if not modulo and not float(data.value(mdd.INDEX_AX_NUMERATOR)):
                self.add(data.mark_of(mdd.INDEX_AX_NUMERATOR),
                         f"{entry.name}: equidistant indexing (MD30500 = 3) on an axis without modulo needs"
                         " MD30501 INDEX_AX_NUMERATOR above 0")
            return
        length_md, table_md = (mdd.INDEX_AX_LENGTH_POS_TAB_1, mdd.INDEX_AX_POS_TAB_1) if assignment == 1 else \
            (mdd.INDEX_AX_LENGTH_POS_TAB_2, mdd.INDEX_AX_POS_TAB_2)
        length = int(nck.value(length_md))
        if not length:
            self.add(mark, f"{entry.name}: MD30500 = {assignment} assigns index position table {assignment},"
                           f" but {length_md.label} is 0")
            return
        positions = [float(nck.value(table_md, n)) for n in range(length)]
        for n in range(1, length):
            if positions[n] <= positions[n - 1]:
                self.add(nck.mark_of(table_md, n),
                         f"{table_md.label}[{n}] = {positions[n]:g}: the index positions must ascend and differ"
                         f" (L13578-13580), [{n - 1}] is {positions[n - 1]:g}")
                return
        if modulo:
            start = float(data.value(mdd.MODULO_RANGE_START))
            end = start + float(data.value(mdd.MODULO_RANGE))
            outside = next((n for n, position in enumerate(positions) if not start <= position < end), None)
            if outside is not None:
                self.add(nck.mark_of(table_md, outside),
                         f"{table_md.label}[{outside}] = {positions[outside]:g}: {entry.name} is a modulo axis,"
                         f" its index positions lie in {start:g} <= p < {end:g} (L13586)")

    def _check_generator(self, entry: AxisEntry) -> None:
        """Generator operation needs the DC link it buffers, the Vdc_min controller on, a threshold
        between where the pulses go and where the supply holds the link, the motor's inertia and a
        minimum speed the drive can tell from standstill."""
        drive, mark, dc_link = entry.drive, entry.drive_mark, self.machine.dc_link
        if not drive.generator or mark is None:
            return
        where = f"{entry.name}: drive p0888 = 3 (generator operation)"
        if dc_link is None:
            self.add(mark, f"{where} needs the DC link it buffers: a dc_link: section")
        else:
            lowest = PULSE_CANCELLATION_PER_SUPPLY_VOLT * dc_link.supply_voltage
            highest = DC_LINK_PER_SUPPLY_VOLT * dc_link.supply_voltage
            if not lowest < drive.p1248 < highest:
                self.add(mark, f"{where}: p1248 = {drive.p1248:g} V must lie between the pulse cancellation"
                               f" at {lowest:g} V and the link's {highest:g} V on the supply")
        if drive.p1240 != 2:
            self.add(mark, f"{where} needs p1240 = 2 (the Vdc_min controller brakes the motor under ESR)")
        if drive.p0341 <= 0:
            self.add(mark, f"{where} needs p0341, the motor's moment of inertia (kg m^2), above 0")
        if drive.p2161 <= SPEED_HYSTERESIS:
            self.add(mark, f"{where} needs p2161, the minimum generator speed, above the speed comparison's"
                           f" hysteresis {SPEED_HYSTERESIS:g} rev/min (got {drive.p2161:g})")

    def _check_gearbox(self, entry: AxisEntry, spindle: int) -> None:
        """The axis's gearbox against its machine data and the I/O list."""
        declared = entry.gearbox_mark
        if declared is None:
            return
        written = entry.gearbox
        missing = [f"{key} ({meaning})" for key, meaning in _REQUIRED_GEARBOX_KEYS.items()
                   if key not in entry.gearbox_keys]
        if missing:
            self.add(declared, f"{entry.name}: plant.gearbox lacks {' and '.join(missing)}")
        if not spindle:
            self.add(declared, f"{entry.name}: plant.gearbox on an axis that is not a spindle"
                               " (MD35000 SPIND_ASSIGN_TO_MACHAX = 0); only a spindle changes gear stages")
        if "stages" not in written:
            return
        stages = int(written["stages"].value)
        configured = int(entry.data.value(mdd.NUM_GEAR_STEPS))
        if spindle and stages != configured:
            # at MD35090 where it is written (a scenario may change it), else at the stages
            if entry.data.is_written(mdd.NUM_GEAR_STEPS):
                mark, default = entry.data.mark_of(mdd.NUM_GEAR_STEPS), ""
            else:
                mark, default = written["stages"].mark, " (the default)"
            self.add(mark, f"{entry.name}: plant.gearbox.stages = {stages}, but MD35090 NUM_GEAR_STEPS ="
                           f" {configured}{default}")
        engaged = written.get("engaged")
        if engaged is not None and int(engaged.value) > stages:
            self.add(engaged.mark, f"{entry.name}: plant.gearbox.engaged = {engaged.value}: the gearbox has"
                                   f" {count(stages, 'stage', 'stages')} (0 = neutral)")
        needed = [*(gear_shift(entry.name, stage) for stage in range(1, stages + 1)),
                  *(gear_engaged(entry.name, stage) for stage in range(1, stages + 1))]
        unwired = [name for name in needed if name not in self.machine.plant_io_names]
        if unwired:
            self.add(declared, f"{entry.name}: the gearbox's I/O is not wired in plant_io: {', '.join(unwired)}")

    def _check_gearbox_io(self) -> None:
        """Gearbox I/O needs a gearbox with that stage: a sensor no gearbox drives reads 0 for ever."""
        for name, (key, mark) in self.machine.plant_io_names.items():
            point = gearbox_point(name)
            if point is None or point.axis not in self.machine.axes:
                continue  # not gearbox I/O, or an unknown axis (the I/O list check reports it)
            entry = self.machine.axes[point.axis]
            if entry.gearbox_mark is None:
                self.add(mark, f"plant_io {key}: {name} needs a gearbox on {point.axis}"
                               " (plant: {gearbox: {stages: n, shift_time: s}})")
                continue
            stages = entry.gearbox.get("stages")
            if stages is not None and point.stage > int(stages.value):
                self.add(mark, f"plant_io {key}: {name}: the gearbox of {point.axis} has"
                               f" {count(int(stages.value), 'stage', 'stages')}")

    def _check_chuck(self, entry: AxisEntry, spindle: int) -> None:
        """The spindle's chuck against the I/O list."""
        declared = entry.chuck_mark
        if declared is None:
            return
        if not spindle:
            self.add(declared, f"{entry.name}: plant.chuck on an axis that is not a spindle"
                               " (MD35000 SPIND_ASSIGN_TO_MACHAX = 0)")
        unwired = [name for name in (chuck_close(entry.name), chuck_release(entry.name), chuck_closed(entry.name))
                   if name not in self.machine.plant_io_names]
        if unwired:
            self.add(declared, f"{entry.name}: the chuck's I/O is not wired in plant_io: {', '.join(unwired)}")
        if "travel_time" not in entry.chuck:
            self.add(declared, f"{entry.name}: plant.chuck lacks travel_time (the seconds of the chuck's stroke)")

    def _check_chuck_io(self) -> None:
        """Chuck I/O needs a chuck: its sensors would read 0 for ever."""
        axes = self.machine.axes
        for name, (key, mark) in self.machine.plant_io_names.items():
            axis = chuck_axis(name)
            if axis is not None and axis in axes and axes[axis].chuck_mark is None:
                self.add(mark, f"plant_io {key}: {name} needs a chuck on {axis} (plant: {{chuck: {{travel_time: s}}}})")

    # ------------------------------------------------------------------ channels

    def _check_channel(self, entry: ChannelEntry) -> None:
        geometry_names = entry.geometry_names()
        self._check_names(entry, mdd.AXCONF_GEOAX_NAME_TAB, geometry_names,
                          lambda name: f"geometry axis {name} is named twice")
        if entry.axes:  # a channel without a readable axes list has been reported already
            program_names = entry.program_names()
            self._check_program_names(entry, program_names)
            self._check_geometry_axes(entry, geometry_names, program_names)
            self._check_coupling(entry)
            self._check_master_spindle(entry)

    def _check_program_names(self, entry: ChannelEntry, program_names: tuple[str, ...]) -> None:
        md = mdd.AXCONF_CHANAX_NAME_TAB
        written = entry.data.written.get(md.number, {})
        for index, item in sorted(written.items(), key=lambda pair: pair[0] or 0):
            assert index is not None
            if index >= len(entry.axes) and item.value:
                self.add(item.mark, f"{md.label}[{index}] = '{item.value}': {entry.name} has only"
                                    f" {count(len(entry.axes), 'axis', 'axes')}")
        self._check_names(entry, md, program_names,
                          lambda name: f"{entry.name} already has a channel axis named {name}")

    def _check_names(self, entry: ChannelEntry, md: MdDef, names: tuple[str, ...],
                     twice: Callable[[str], str]) -> None:
        """Item ``index`` of ``names`` is item ``index`` of ``md``: each must be a name, and none may
        come twice (``twice(name)`` says what that means)."""
        seen: set[str] = set()
        for index, name in enumerate(names):
            mark = entry.data.mark_of(md, index)
            if not NAME.match(name):
                self.add(mark,
                         f"{md.label}[{index}] = '{name}' is not a name (a letter, then letters, digits, _)")
            elif name in seen:
                self.add(mark, f"{md.label}[{index}]: {twice(name)}")
            seen.add(name)

    def _check_geometry_axes(self, entry: ChannelEntry, geometry_names: tuple[str, ...],
                             program_names: tuple[str, ...]) -> None:
        md = mdd.AXCONF_GEOAX_ASSIGN_TAB
        used: dict[int, str] = {}
        for index, geometry_name in enumerate(geometry_names):
            channel_axis = int(entry.data.value(md, index))
            mark = entry.data.mark_of(md, index)
            label = f"{md.label}[{index}] = {channel_axis}"
            if channel_axis == 0:
                continue
            if channel_axis > len(entry.axes):
                default = "" if entry.data.is_written(md) else " (the default)"
                self.add(mark,
                         f"{label}{default}: geometry axis {geometry_name} names channel axis {channel_axis},"
                         f" but {entry.name} has {count(len(entry.axes), 'axis', 'axes')}")
                continue
            machine_axis = entry.axes[channel_axis - 1]
            if channel_axis in used:
                self.add(mark,
                         f"{label}: geometry axes {used[channel_axis]} and {geometry_name} both use channel"
                         f" axis {channel_axis} ({machine_axis})")
            used[channel_axis] = geometry_name
            if self.machine.axes[machine_axis].is_spindle:
                self.add(mark, f"{label}: geometry axis {geometry_name} would be the spindle {machine_axis}")
            elif int(self.machine.axes[machine_axis].data.value(mdd.BASE_FUNCTION_MASK)) & 0x100:
                self.add(mark, f"{label}: geometry axis {geometry_name} would be {machine_axis}, a positioning"
                               " axis only (MD30460 BASE_FUNCTION_MASK bit 8, L10846-10849)")
            if geometry_name in program_names and program_names.index(geometry_name) != channel_axis - 1:
                self.add(mark, f"{label}: geometry axis {geometry_name} is channel axis {channel_axis}"
                               f" ({machine_axis}), but MD20080 gives the name {geometry_name} to channel"
                               f" axis {program_names.index(geometry_name) + 1}")

    def _check_coupling(self, entry: ChannelEntry) -> None:
        md = mdd.COUPLE_AXIS_1
        machine_axes = list(self.machine.axes)
        for index in range(md.length):
            number = int(entry.data.value(md, index))
            if number and (number > len(machine_axes) or machine_axes[number - 1] not in entry.axes):
                self.add(entry.data.mark_of(md, index),
                         f"{md.label}[{index}] = {number}: machine axis {number} is not an axis of"
                         f" {entry.name}")
        numbers = [int(entry.data.value(md, index)) for index in range(md.length)]
        if all(numbers) and max(numbers) <= len(machine_axes):
            self._check_coupled_control_parameters(*(self.machine.axes[machine_axes[number - 1]]
                                                     for number in numbers))

    def _check_coupled_control_parameters(self, following: AxisEntry, leading: AxisEntry) -> None:
        """LS and FS of the configured pair need like control parameters (L23736-23748).  The seed
        names no alarm; the control does not check them [control], this loader refuses the machine
        so that the pair does not run with unlike setpoints."""
        for md in COUPLED_LIKE_PARAMETERS:
            fs_value, ls_value = following.data.value(md), leading.data.value(md)
            if fs_value != ls_value:
                self.add(following.data.mark_of(md),
                         f"{md.label} = {fs_value} on {following.name}, {ls_value} on {leading.name}: the"
                         f" synchronous spindle pair of MD21300 needs the same value on both (seed 003 L23736-23748)")

    def _check_master_spindle(self, entry: ChannelEntry) -> None:
        md = mdd.SPIND_DEF_MASTER_SPIND
        master = int(entry.data.value(md))
        numbers = [self.machine.axes[name].spindle_number for name in entry.axes]
        spindles = sorted({number for number in numbers if number > 0})
        if master == 0 and spindles:
            self.add(entry.data.mark_of(md),
                     f"{md.label} = 0: {entry.name} has spindles ({', '.join(str(number) for number in spindles)});"
                     " S, M3, M4 and M5 without a spindle number address the master spindle, so it needs one")
            return
        if master == 0 or master in spindles or not (spindles or entry.data.is_written(md)):
            return
        default = "" if entry.data.is_written(md) else " (the default)"
        own = ", ".join(str(number) for number in spindles) or "none"
        self.add(entry.data.mark_of(md),
                 f"{md.label} = {master}{default}: {entry.name} has no spindle {master}"
                 f" (its spindles: {own})")
