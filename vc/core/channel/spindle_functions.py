"""What the channel's blocks ask of its spindles, couplings and polygon turning.

The channel hands each block's spindle commands to its spindles (or, for a coupled spindle, to
the couplings: SPOS on the following spindle is an offset change, M3 / M4 S a differential speed),
runs the block's SPCON / SPCOF, FA[Sn], COUP... calls, WAITC and G51.2 / G50.2 in their order, and
holds the block where a spindle or a coupling says: the block's gear change and M70 before it
moves, the spindle speed before machining (MD35500 / MD35510), SPOS / M19 / WAITS / COUPON /
WAITC at its end.  G95 / G99 and G331 / G332 take the master spindle's speed from here
(docs/sync_spindle.md); G96 / G961 set it (``cutting_speed.py``, docs/feedrates.md).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

from vc.config import md_dictionary as MD
from vc.config.model import ChannelConfig
from vc.core.alarms import AlarmList
from vc.core.axis.axis import MachineAxis
from vc.core.channel.cutting_speed import ConstantCuttingSpeed, CuttingSpeedState
from vc.core.channel.interface import ChannelInputs
from vc.core.channel.program_run import raise_block_alarm
from vc.core.program.block_plan import BlockPlan, ModalState
from vc.core.program.commands import BlockChange, CouplingCommand, SpindleCommand, block_change_of, kind_of
from vc.core.program.program import Block
from vc.core.program.sync_actions import VariableWrite
from vc.core.spindle.coupling import ALARM_COUPLING_ACTIVE, Couplings
from vc.core.spindle.polygon import ALARM_AXIS_SYNCHRONISED, PolygonTurning
from vc.core.spindle.spindle import RPM, SUPPRESS_IN_DRY_RUN, SUPPRESS_IN_PROGRAM_TEST, Spindle, SpindleMode


class SpindleFunctions:
    def __init__(self, config: ChannelConfig, axes_by_name: dict[str, MachineAxis], inputs: ChannelInputs,
                 alarms: AlarmList, stop: Callable[[], None]):
        self.config = config
        self.name = config.name
        self.axes_by_name = axes_by_name
        self._inputs = inputs
        self._alarms = alarms
        self._stop = stop  # the channel's NC stop
        self.spindles: dict[str, Spindle] = {}  # machine axis -> spindle, given by the NCK
        self.couplings: Couplings | None = None  # given by the NCK
        self.polygon: PolygonTurning | None = None
        self._coupling_feeds: dict[str, float] = {}  # FA[Sn], deg/min (modal)
        self.waits: list[tuple[str, BlockChange | None]] = []  # COUPON / WAITC block-change conditions
        self.cutting_speed = ConstantCuttingSpeed(config, axes_by_name, self.spindles)  # G96 / G961

    def _raise(self, number: int, cycle: int, block: Block, *parameters: object, axis: str = "") -> None:
        raise_block_alarm(self._alarms, self.name, number, cycle, block, *parameters, axis=axis)

    # ------------------------------------------------------------------ program start and end
    def program_start(self, modal: ModalState) -> None:
        """NC start from reset: the couplings as MD21330 says, polygon turning modal, the spindles."""
        if self.couplings is not None:
            self.couplings.nc_start(self.name, kept_by_polygon=self.polygon.kept() if self.polygon else None)
        if self.polygon is not None:
            modal.polygon = self.polygon.active
        for spindle in self.spindles.values():
            spindle.program_start()

    def reset_couplings(self) -> None:
        """Reset and program end: the couplings as MD21330 / MD20110 say, polygon turning as HBR."""
        kept = self.polygon.reset() if self.polygon is not None else None
        if self.couplings is not None:
            self.couplings.reset(self.name, kept_by_polygon=kept)
        self.waits = []

    def reset_spindles(self, program_end: bool) -> None:
        """Reset and program end: G96 / G961 end first, so that the spindle's reset keeps (MD35040 = 1)
        the speed they set (L16209-16211)."""
        self.cutting_speed.end()
        for spindle in self.spindles.values():
            spindle.reset(program_end=program_end)

    # ------------------------------------------------------------------ a block's spindle commands
    def program_spindles(self, plan: BlockPlan, cycle: int, block: Block) -> bool:
        """The block's command to each spindle; True: a gear stage suppressed in dry run / program
        test is being caught up (the block waits for it)."""
        suppress = self._gear_change_suppressed
        for name, command in plan.spindles.items():
            if command.position is not None and self.couplings is not None \
                    and self.couplings.feedforward_withdrawn(name):
                # MD32620 = 0 in the coupling: SPOS, M19 and SPOSA have no effect on FS or LS
                # (L23004-23005); ignored without an alarm, as the seed says [control]
                command = dataclasses.replace(command, position=None)
            if self._coupled_spindle_command(name, command, cycle, block):
                continue
            self.spindles[name].program(command, cycle, self._alarms, block.label, suppress(self.spindles[name]))
        if plan.constant_cutting or plan.spindle_limits or self.cutting_speed.state is not CuttingSpeedState.OFF:
            self.cutting_speed.block(plan, self.master_spindle())
        catching_up = False
        for spindle in self.spindles.values():
            if spindle.suppressed_gear is not None and not suppress(spindle):
                spindle.catch_up_gear(cycle, self._alarms, block.label)
                catching_up = catching_up or spindle.change is not None
        return catching_up

    def holds_block_end(self, plan: BlockPlan) -> bool:
        """The block ends only when its spindles and couplings allow it."""
        if any(self.spindles[name].holds_block_end for name in plan.spindles):
            return True  # SPOS / M19: the block ends when the spindle is in position (L16475-16496)
        if any(not self.spindles[name].positioned_or_stopped() for name in plan.spindle_waits):
            return True  # WAITS
        couplings = self.couplings
        # COUPON's block-change condition, WAITC, SPOS on a coupled FS (L22583-22592)
        return couplings is not None and (
            any(couplings.holds_block(name, criterion) for name, criterion in self.waits)
            or any(couplings.overlay_holds_block(name) for name in plan.spindles))

    def revolution_speed(self) -> float:
        """rev/min that G95 / G99 multiply F with: the master spindle's (MD20090) actual speed, so the
        feed follows its override, ramps and stops [control]; while polygon turning as 0201 ERV says."""
        speed = self.polygon.revolution_speed() if self.polygon is not None else None
        if speed is not None:
            return speed
        master = self.spindles.get(self.master_spindle() or "")
        return abs(master.axis.velocity) / RPM if master is not None else 0.0

    def master_spindle(self) -> str | None:
        number = self.config.md.int(MD.SPIND_DEF_MASTER_SPIND)
        return next((name for name, spindle in self.spindles.items() if spindle.number == number), None)

    def plan_tapping(self, plan: BlockPlan, cycle: int, block: Block) -> bool:
        """G331 / G332: the spindle's end point from the drilling travel and the pitch, and the path
        feed F = S x |pitch| with the last programmed S (seed 003 L8573-8581, L17679-17680).
        False: no spindle speed, alarm 14800 stops the program [control]."""
        tapping = plan.tapping
        assert tapping is not None
        speed = self.spindles[tapping.spindle].speed
        if speed <= 0.0:
            self._raise(14800, cycle, block)
            self._stop()
            return False
        spindle = self.axes_by_name[tapping.spindle]
        travel = plan.targets[tapping.axis] - self.axes_by_name[tapping.axis].setpoint
        plan.tapping = dataclasses.replace(tapping, travel=travel)
        plan.targets[tapping.spindle] = spindle.setpoint + tapping.spindle_degrees(travel)
        plan.feed = speed * abs(tapping.pitch)
        return True

    def coupling_functions(self, plan: BlockPlan, cycle: int, block: Block) -> bool:
        """SPCON / SPCOF, FA[Sn], the COUP... calls and G51.2 / G50.2 of the block, in their order.
        False: an alarm stops the program."""
        couplings = self.couplings
        for name, on in plan.position_control.items():
            spindle = self.spindles[name]
            if on and couplings is not None and couplings.feedforward_withdrawn(name) \
                    and spindle.axis.command_velocity != 0.0:
                continue  # MD32620 = 0 in the coupling: SPCON cannot switch position control on in motion (L23003)
            spindle.program_position_control(on)
        self._coupling_feeds.update(plan.feeds)
        polygon = self.polygon
        if polygon is not None and polygon.active:
            busy = set(plan.targets) & set(polygon.commanded_axes())
            slave = plan.spindles.get(polygon.slave)
            master = plan.spindles.get(polygon.master)
            if busy or slave is not None or (master is not None and (master.position is not None or master.gear
                                                                      or master.axis_mode)):
                self._raise(ALARM_AXIS_SYNCHRONISED, cycle, block, sorted(busy)[0] if busy else polygon.slave)
                return False
        if plan.polygon is not None:
            if polygon is None:
                self._raise(12550, cycle, block, "G51.2")
                return False
            if plan.polygon.start:
                alarm = polygon.start(plan.polygon)
                if alarm:
                    self._raise(alarm, cycle, block, "G51.2")
                    return False
            else:
                polygon.cancel()
        if couplings is None:
            return not plan.couplings
        for following, thresholds in plan.coupling_thresholds.items():
            couplings.program_thresholds(following, thresholds)  # before a COUPON of the same block
        for command in plan.couplings:
            alarm = self._coupling_call(couplings, command, cycle, block)
            if alarm:
                self._raise(alarm, cycle, block, command.following, axis=command.following)
                return False
        return True

    def _coupling_call(self, couplings: Couplings, command: CouplingCommand, cycle: int, block: Block) -> int:
        function, following, leading = command.function, command.following, command.leading
        if function == "COUPDEF":
            return couplings.define(self.name, following, leading, command.numerator, command.denominator,
                                    block_change_of(command.block_change) if command.block_change else None,
                                    kind_of(command.kind) if command.kind else None)
        if function in ("COUPON", "COUPONC"):
            alarm = couplings.couple(self.name, following, leading, command.offset, function == "COUPONC", cycle,
                                     block.label)
            if not alarm:
                self.waits.append((following, None))
            return alarm
        if function in ("COUPOF", "COUPOFS"):
            return couplings.decouple(following, stop=function == "COUPOFS")
        if function == "COUPDEL":
            return couplings.delete(following)
        if function == "COUPRES":
            return couplings.restore(following)
        # WAITC: no effect on a spindle that is not a coupled FS (L22659-22690)
        criterion = (block_change_of(command.block_change) if command.block_change
                     else couplings.waitc_criterion(following))
        self.waits.append((following, criterion))
        return 0

    def spindle_indices(self) -> dict[str, str]:
        """How a program names this channel's spindles as a variable's index: S<n> (MD35000) or the
        machine axis name."""
        indices = {name: name for name in self.spindles}
        indices.update({f"S{spindle.axis.config.spindle_number}": name for name, spindle in self.spindles.items()})
        return indices

    def write_coupling_variable(self, write: VariableWrite) -> None:
        """``$AA_COUP_CORR[Sn]=...`` of a program or a synchronized action (index: the machine axis)."""
        if self.couplings is not None and write.name == "$AA_COUP_CORR":
            self.couplings.write_correction(write.index, write.value)

    def _coupled_spindle_command(self, name: str, command: SpindleCommand, cycle: int, block: Block) -> bool:
        """What a block asks of a coupled spindle: the FS takes SPOS as offset change and M3/M4 S as
        differential speed; gear change and oscillation are refused on FS and LS (L22102-22104).
        True: handled here."""
        couplings = self.couplings
        if couplings is None or not couplings.involved(name):
            return False
        if self.spindles[name].needs_gear_change(command):
            self._raise(ALARM_COUPLING_ACTIVE, cycle, block, axis=name)
            self._stop()
            return True
        if couplings.coupled(name) is None:
            return False  # the LS: speed, direction and stop act as usual, the FS follows
        if command.position is not None:
            mode, value = command.position
            couplings.position_following(name, mode, value, self._coupling_feeds.get(name, 0.0),
                                         command.wait_for_position)
        if command.direction is not None or command.speed is not None:
            alarm = couplings.program_differential(name, command.direction, command.speed, cycle, block.label)
            if alarm:
                self._raise(alarm, cycle, block, name, axis=name)
                self._stop()
        return True

    def _gear_change_suppressed(self, spindle: Spindle) -> bool:
        """MD35035 bits 0 / 1: no gear change in dry run / program test (L19956-19993)."""
        mask = spindle.md.int(MD.SPIND_FUNCTION_MASK)
        return (self._inputs.dry_run and bool(mask & SUPPRESS_IN_DRY_RUN)) or \
            (self._inputs.program_test and bool(mask & SUPPRESS_IN_PROGRAM_TEST))

    def spindles_ready(self, plan: BlockPlan) -> bool:
        """Block change interlocks of the spindles (L18540-18548, L16517-16540): the block's gear
        change and M70 first; a machining block (not G0) starts only with every turning spindle at
        its speed (DB31.DBX83.5) when MD35500 asks for it."""
        if any(spindle.holds_motion for spindle in self.spindles.values()):
            return False  # the block's own change, M70, or a stage caught up after dry run
        if plan.targets and not plan.rapid:
            for spindle in self.spindles.values():
                # MD35500 compares set and actual speed in control mode only (L20840-20858): a
                # synchronous FS turns at what its LS dictates and does not hold the block
                if spindle.md.int(MD.SPIND_ON_SPEED_AT_IPO_START) and spindle.direction and \
                        spindle.mode is SpindleMode.CONTROL and not spindle.speed_reached():
                    return False
                if spindle.md.bool(MD.SPIND_STOPPED_AT_IPO_START) and not spindle.direction and \
                        spindle.mode is SpindleMode.CONTROL and not spindle.stationary():
                    return False  # MD35510: after M5 the path waits until the spindle stands (L20792-20798)
        return True
