"""Block execution: a block plan turned into motion, one phase at a time, and the block change.

Block execution, one phase at a time::

    DECODE ──motion block──▶ INTERPOLATE ──path at its end──▶ BLOCK_END (exact stop window)
    DECODE ──G4──▶ DWELL ──time elapsed──▶ next block
    DECODE ──G74──▶ REFERENCE ──the programmed axes referenced──▶ BLOCK_END
    DECODE ──spindle gear change or M70 in the block──▶ SPINDLE ──done──▶ (motion, dwell, BLOCK_END)
    (SPINDLE) ──functions output before the motion──▶ AUXILIARY ──acknowledged──▶ (motion, dwell, BLOCK_END)
    BLOCK_END ──window reached, auxiliary functions acknowledged, read-in not disabled──▶ DECODE (next block)
    INTERPOLATE ──an axis braked off the path (e-stop, limit switch)──▶ CONTOUR_LOST ──RESET──▶ DECODE
    INTERPOLATE ──the path ended on a stored stroke limit 2 / 3 (G22)──▶ CONTOUR_LOST

A block is decoded only when it is about to run, so a faulty block raises its alarm when
execution reaches it, and a software limit switch in the block stops the program before
the block moves.  M0 (M1 with "activate M01") stops the program at the block end, M2 / M17 / M30
end it; IF ... GOTO jumps.  The block's auxiliary functions go to the PLC before, during or after
its motion, and a normal one holds the block until the PLC has acknowledged it (seed 003 L16486,
``vc/core/auxiliary/output.py``).
The block's spindle and coupling functions go to the channel's :class:`SpindleFunctions`, its
G33 thread and retraction words to its :class:`ThreadRetract`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

from vc.config.model import ChannelConfig
from vc.core.alarms import READ_IN_DISABLED, AlarmList
from vc.core.auxiliary.output import AuxiliaryOutput
from vc.core.auxiliary.tool_selection import ToolSelection
from vc.core.axis.axis import MachineAxis
from vc.core.axis.command_axis import CommandAxes
from vc.core.axis.dynamics import fixed_feed
from vc.core.axis.owner import Owner
from vc.core.axis.plc_axis import PlcAxes
from vc.core.axis.stroke_limits import BOUNDARY, StrokeStop
from vc.core.channel.dry_run import DryRunFeed
from vc.core.channel.interface import ChannelInputs
from vc.core.channel.program_run import BlockPhase, ChannelState, ProgramRun, ProgramState, raise_block_alarm
from vc.core.channel.referencing_control import ReferencingControl
from vc.core.channel.spindle_functions import SpindleFunctions
from vc.core.channel.stroke_limit_path import ChannelStrokeLimits
from vc.core.channel.thread_retract import ThreadRetract
from vc.core.fixed_stop.channel_fixed_stops import ChannelFixedStops
from vc.core.interpolation.path import PathSegment
from vc.core.interpolation.tool_path import ToolPathSegment
from vc.core.program.block_plan import EXACT_STOP_COARSE, EXACT_STOP_FINE, BlockPlan, DecodeAlarm, software_limit_alarm
from vc.core.program.interpreter import decode
from vc.core.program.positioning_words import named_axes
from vc.core.program.program import Block, Jump, jump_target
from vc.core.program.sync_actions import SyncActionError, parse_condition
from vc.core.referencing.referencing import Source, State
from vc.core.transforms.five_axis_control import FiveAxisControl
from vc.core.transforms.inclined_axis_control import InclinedAxisControl


class BlockExecution:
    def __init__(self, run: ProgramRun, config: ChannelConfig, axes: Sequence[MachineAxis],
                 axes_by_name: dict[str, MachineAxis], inputs: ChannelInputs, alarms: AlarmList, dt: float,
                 referencing: ReferencingControl, five_axis: FiveAxisControl, stroke: ChannelStrokeLimits,
                 spindles: SpindleFunctions, threads: ThreadRetract, stop: Callable[[], None],
                 aux: AuxiliaryOutput, tools: ToolSelection, fixed_stops: ChannelFixedStops,
                 positioning: CommandAxes, plc_axes: PlcAxes, dry_run: DryRunFeed,
                 permanent_feeds: tuple[float, ...]):
        self.run = run
        self.config = config
        self.name = config.name
        self.axes = axes
        self.axes_by_name = axes_by_name
        self.inputs = inputs
        self._alarms = alarms
        self._dt = dt
        self._referencing = referencing
        self.five_axis = five_axis
        self._stroke = stroke
        self._spindles = spindles
        self._threads = threads
        self._stop = stop  # the channel's NC stop
        self._aux = aux  # the auxiliary functions to the PLC
        self._tools = tools
        self._fixed_stops = fixed_stops  # FXS / FXST / FXSW (seed 003 chapter 17)
        self._approaching: set[str] = set()  # the block's axes that travel to their fixed stop
        self._deleting = False  # DB21.DBX6.2: the path brakes and the block ends where it stops
        self._positioning = positioning  # the axis interpolators of POS / POSA (vc/core/axis/command_axis.py)
        self._plc_axes = plc_axes  # the axes the PLC holds or has for good (vc/core/axis/plc_axis.py)
        self.inclined: InclinedAxisControl | None = None  # inclined-axis control (seed 000), given by the NCK
        self.stroke_stop: StrokeStop | None = None  # the running block ends on a stroke limit boundary
        self._g74_axes: list[str] = []
        # G95 / G99: the segment's F (mm/rev, per second) and the velocity its axes allow
        self._feed_per_revolution: tuple[float, float] | None = None
        self._dwell_cycles = 0
        self._dwell_degrees = 0.0  # G4 S: degrees the counted spindle still has to turn
        self._dwell_spindle = ""  # G4 S: the spindle whose revolutions count
        self._geometry = set(axis for axis in config.geometry_axes if axis)
        self.dry_run = dry_run  # DB21.DBX0.6, SD42100 (``dry_run.py``)
        self._permanent_feeds = permanent_feeds  # MD12202: the path's fixed feedrates 1-4, mm/min

    def _raise(self, number: int, cycle: int, block: Block, *parameters: object, axis: str = "") -> None:
        raise_block_alarm(self._alarms, self.name, number, cycle, block, *parameters, axis=axis)

    def cycle(self, hold: bool, cycle: int) -> None:
        """Interpolation and block change for one IPO cycle; ``hold``: the path may not move."""
        run = self.run
        if run.phase is BlockPhase.INTERPOLATE:
            self._interpolate(hold, cycle)
        elif run.phase is BlockPhase.REFERENCE:
            self._g74(cycle)
        elif run.phase is BlockPhase.SPINDLE and not hold:
            plan = run.plan
            assert plan is not None
            if self._spindles.spindles_ready(plan):
                self._start_block_body(cycle)
        elif run.phase is BlockPhase.AUXILIARY and not hold:
            if self._aux.motion_may_start:
                self._start_block_body(cycle)
        elif run.phase is BlockPhase.DWELL and not hold:
            self._dwell_cycle()
        elif run.phase is BlockPhase.BLOCK_END:
            self._block_end()
        if run.phase is BlockPhase.DECODE and run.state is ChannelState.ACTIVE and not hold:
            self._decode_next(cycle)

    def _dwell_cycle(self) -> None:
        if self._dwell_degrees > 0.0:
            counted = self._spindles.spindles.get(self._dwell_spindle)
            if counted is not None:
                self._dwell_degrees -= abs(counted.axis.velocity) * self._dt
            if self._dwell_degrees <= 1e-9 or counted is None:
                self._dwell_degrees = 0.0
                self._end_dwell()
            return
        self._dwell_cycles -= 1
        if self._dwell_cycles <= 0:
            self._end_dwell()

    def _end_dwell(self) -> None:
        # The dwell block ends like any other: read-in disable and WAITC still hold it.
        self.run.phase = BlockPhase.BLOCK_END
        self._block_end()

    def _planned_feed(self, plan: BlockPlan) -> float:
        """Path velocity per second to plan with; under G95 / G99 the axes' limit, which the speed of
        the spindle lowers in every cycle (``SpindleFunctions.revolution_speed``); under dry run the
        dry-run feed per minute (``dry_run.py``)."""
        fixed = self._fixed_feed(plan)
        if fixed > 0.0:
            return fixed / 60.0
        if self.dry_run.active and not plan.rapid:
            return self.dry_run.feed(plan.feed, plan.feed_per_revolution, self._spindles.revolution_speed) / 60.0
        return math.inf if plan.feed_per_revolution else plan.feed / 60.0

    def _fixed_feed(self, plan: BlockPlan) -> float:
        """DB21.DBX29.0-29.3: the fixed feedrate MD12202 (mm/min, always per minute) in place of F for a
        machining block, before the dry-run feed [INF]; 0.0 without one (seed 003 L9692-9722)."""
        selection = self.inputs.path_fixed_feed
        if not selection or plan.rapid or plan.tapping is not None:
            return 0.0
        return fixed_feed(self._permanent_feeds, selection)

    def brake_segment(self) -> None:
        segment = self.run.segment
        if segment is None or segment.finished or segment.velocity == 0.0 or \
                any(axis.owner is not Owner.PATH for axis in segment.axes):
            self._release_segment()
            self.run.aborting = False
            return
        segment.cycle(1.0, True, self._dt)
        if segment.velocity == 0.0:
            self._release_segment()
            self.run.aborting = False

    def delete_distance_to_go(self) -> None:
        """DB21.DBX6.2's rising edge: the path axes of the running block brake on their ramp and the
        block ends where they stand; the next block starts from there (path axes only, not the
        positioning axes, seed 003 L12160-12164; the Basic Functions manual's behaviour [control]).
        A thread (G33, G331) and a travel to fixed stop are not interrupted [control]."""
        run = self.run
        if run.phase is BlockPhase.INTERPOLATE and run.segment is not None and not self._approaching \
                and self._threads.thread_segment is None:
            self._deleting = True

    def _release_segment(self) -> None:
        self._deleting = False
        if self.run.segment is not None:
            for axis in self.run.segment.axes:
                if axis.owner is Owner.PATH:
                    axis.release()
        self.run.segment = None

    def _interpolate(self, hold: bool, cycle: int) -> None:
        if self._threads.thread_segment is not None:
            if self._threads.thread_cycle():
                self._block_end()
            return
        run = self.run
        segment = run.segment
        assert segment is not None and run.plan is not None
        if self._fixed_stops.selected_by_action:  # a synchronized action selected FXS during the block
            self._fixed_stops.selected_by_action = False
            self._approaching = self._fixed_stops.approaching(segment.axes)
        if self._approaching and self._fixed_stops.path_ended(segment.axes, self._approaching):
            self._approaching = set()
            self._release_segment()  # the stop is found: the rest of the path is deleted (L37306)
            run.phase = BlockPhase.BLOCK_END
            self._block_end()
            return
        axes_hold = bool(self._approaching) and self._fixed_stops.holds_motion(segment.axes)
        inclined = self.inclined
        carried = inclined.orthogonal if inclined is not None and inclined.orthogonal_only_carried else None
        for axis in segment.axes:
            if axis.owner is not Owner.PATH:
                # A reaction (rapid stop, limit switch) braked an axis off the path: the contour is
                # lost, the block cannot be finished; the program stops and only RESET ends it.
                self._release_segment()
                run.phase = BlockPhase.CONTOUR_LOST
                self._stop()
                return
            # Feed disable, an axis feed stop or a missing enable hold the path; the program
            # keeps its state "running" (only read-in disable makes it "waiting").
            interlocked = axis.inputs.feed_stop and axis is not carried
            axes_hold = axes_hold or interlocked or not axis.drive_ready
        blocked = hold or self.inputs.feed_disable or axes_hold or self._deleting
        override = self.inputs.rapid_override if segment.rapid else self.inputs.feed_override
        if self._feed_per_revolution is not None:
            feed, limit = self._feed_per_revolution
            # the spindle's turning sets the path velocity; a standing spindle holds the path (no alarm)
            segment.command_velocity = min(limit, feed * self._spindles.revolution_speed())
        segment.cycle(override, blocked, self._dt)
        if self._deleting and segment.velocity == 0.0:
            self._release_segment()  # the rest of the block's path is deleted
            run.plan.return_targets = {}  # G28 / G30: the second motion too
            if self.inclined is not None:
                self.inclined.reset()  # the leg is not finished: as after a RESET on the way
            run.phase = BlockPhase.BLOCK_END
            self._block_end()
            return
        if segment.finished:
            if self._approaching:
                self._fixed_stops.motion_finished(segment.axes, cycle)  # no stop before the end point: 20091
                self._approaching = set()
            self._release_segment()
            if self.stroke_stop is not None:
                run.phase = BlockPhase.CONTOUR_LOST  # the block cannot go on; RESET ends it
                self._raise_stroke_alarm(self.stroke_stop, cycle)
                return
            if self._leg_finished():
                return
            run.phase = BlockPhase.BLOCK_END
            self._block_end()

    def _leg_finished(self) -> bool:
        """A motion of the block has arrived.  G28 / G30 at the intermediate point: True, the axes
        go on to their reference points in a second motion."""
        plan = self.run.plan
        assert plan is not None
        if self.inclined is not None:
            self.inclined.leg_finished()
        if not plan.return_targets:
            return False
        plan.targets, plan.return_targets = plan.return_targets, {}
        plan.path_length = None
        self._start_block_body()
        return True

    def _block_end(self) -> None:
        plan = self.run.plan
        assert plan is not None
        if self._spindles.holds_block_end(plan):
            return  # SPOS / M19, WAITS, COUPON's block-change condition, WAITC
        fixed_stops = self._fixed_stops
        if fixed_stops.of and not fixed_stops.block_may_change:
            return  # the PLC's acknowledgement of the fixed stop (MD37060)
        if (plan.positioning or plan.positioning_waits or plan.program_end) and self._positioning_holds(plan):
            return  # POS, WAITP, the program end wait for their positioning axes
        if plan.block_end in (EXACT_STOP_FINE, EXACT_STOP_COARSE):
            fine = plan.block_end == EXACT_STOP_FINE
            for name in plan.targets:
                if fixed_stops.of and fixed_stops.standing_at_stop(name):
                    continue  # it stands at its stop, not at the end point
                axis = self.axes_by_name[name]
                window = axis.dyn.fine_window if fine else axis.dyn.coarse_window
                if abs(axis.distance_to_end_point) > window:
                    return
        if plan.aux_functions:
            self._aux.block_end_reached()  # the functions of the block end go out now
            if not self._aux.block_may_end:
                return  # normal functions not yet acknowledged by the PLC (seed 003 L16486)
        if self.inputs.read_in_disable:
            self.run.program_state = ProgramState.WAITING
            return
        if self._alarms.reactions(self.name) & READ_IN_DISABLED:
            return  # an alarm disables the read-in (a PLC user alarm with MD14516 bit 1): no block change
        if self.run.program_state is ProgramState.WAITING:
            self.run.program_state = ProgramState.RUNNING
        self._next_block()

    def _positioning_holds(self, plan: BlockPlan) -> bool:
        """The block waits for its POS axes, WAITP's axes and at the program end for every positioning
        axis (L11832-11845, L11771-11792); a motion an alarm took from an axis loses the block."""
        waited = [name for name, motion in plan.positioning.items() if motion.wait]
        waited.extend(plan.positioning_waits)
        if plan.program_end:
            waited.extend(name for name in self._positioning.by_name if self._positioning.positioning(name))
        if self._positioning.lost(waited):
            self.run.phase = BlockPhase.CONTOUR_LOST  # the block cannot be finished; RESET ends it
            self._stop()
            return True
        return not self._positioning.motion_ended(waited)

    def _next_block(self) -> None:
        plan = self.run.plan
        self.run.phase = BlockPhase.DECODE
        self.run.plan = None
        self.run.block_index += 1
        if plan is None:
            return
        if plan.aux_functions:
            self._aux.block_changed()
        if plan.program_end:
            self._spindles.reset_couplings()
            self._threads.end_thread_functions()
            self._spindles.reset_spindles(program_end=True)
            self.run.end()
            self._aux.ended_with_m30 = True  # DB21.DBX33.5 until the next NC start
            self._aux.show_stop()
        elif plan.program_stop or (plan.optional_stop and self.inputs.activate_m01):
            self._stop()  # M0, or M1 with DB21.DBX0.5: interrupted until NC start
            self._aux.stopped_at_m0 = True
            self._aux.show_stop()

    def _decode_next(self, cycle: int) -> None:
        if self.run.block_index >= len(self.run.blocks):
            self.run.end()  # a program without M30 ends after its last block
            return
        block = self.run.blocks[self.run.block_index]
        if self._positioning.any_positioning() and \
                any(self._positioning.positioning(name) for name in named_axes(block, self.config)):
            return  # a POSA axis is programmed again only once it has arrived: the implicit WAITP
        if self._plc_axes.restricted:
            refusal = self._plc_axes.block_refusal(named_axes(block, self.config))
            if refusal is not None:
                name, number = refusal
                if not number:
                    return  # the PLC has the axis: the block waits until it gives it back (implicit GET) [control]
                self._alarms.raise_alarm(number, cycle, self.name, name, channel=self.name, axis=name)
                self._stop()  # 26075 / 26076 (seed 003 L12215-12217)
                return
        self.run.current_block = block
        jump = next((item for item in block.items if isinstance(item, Jump)), None)
        if jump is not None:  # alone, or after its label ("MM: IF ... GOTOB MM")
            self._jump(jump, block, cycle)
            return
        positions = self.five_axis.program_positions(self.run.modal.five_axis)
        pair: tuple[str, ...] = ()
        if self.inclined is not None:
            positions.update(self.inclined.program_positions())
            pair = self.inclined.machine_axes
        plan, alarm = decode(block, self.run.modal, self.config, self.axes_by_name, positions, pair)
        if self.run.leaving_thread_chain and alarm is None:
            if plan.thread is not None:
                self.run.block_index += 1  # a G33 block of the interrupted chain: not cut from the retract position
                return
            self.run.leaving_thread_chain = False
        if alarm is None:
            alarm = self.five_axis.apply(plan, self.run.modal.five_axis, block.label, pair)
        if alarm is None and self.inclined is not None:
            alarm = self.inclined.plan(plan, block.label)  # the inclined Y1 slide (seed 000)
        if alarm is not None:
            self._alarms.raise_alarm(alarm.number, cycle, *alarm.parameters, channel=self.name, axis=alarm.axis)
            self._stop()
            return
        self.run.plan = plan
        self._spindles.waits = []
        if (plan.fixed_stop or self._fixed_stops.of) and not self._fixed_stops.apply(plan, cycle):
            self._stop()
            return
        if plan.stroke_limit is not None:
            self._stroke.control.apply(plan.stroke_limit)
        if not self._spindles.coupling_functions(plan, cycle, block):
            self._stop()
            return
        self._threads.retract_functions(plan, cycle)
        for name, value in plan.preset.items():
            self.axes_by_name[name].preset_actual(value)
        if plan.delete_drf:
            for axis in self.axes:
                axis.delete_drf_offset()
        for name, condition in plan.motion_ends.items():
            self._positioning.set_motion_end(name, condition)
        for name, feed in plan.axis_feeds.items():
            self._positioning.set_feed(name, feed)
        if plan.aux_functions:
            self._tools.block(plan.aux_functions)
            self._aux.block_started(plan.aux_functions)
        catching_up = self._spindles.program_spindles(plan, cycle, block)
        if plan.spindles or plan.targets or plan.positioning or catching_up or self._spindles.waits:
            self.run.phase = BlockPhase.SPINDLE
            if not self._spindles.spindles_ready(plan):
                return
        self._start_block_body(cycle)

    def _jump(self, jump: Jump, block: Block, cycle: int) -> None:
        """IF <condition> GOTOx <target>, evaluated when the block is reached: a condition on $A...
        variables stops the preprocessing until then on the control [control].  A jump block takes
        its IPO cycle.  An unreadable condition raises 12080, an unknown variable 12550, a missing
        destination 14080 (GOTOC: the program goes on after the block)."""
        self.run.leaving_thread_chain = False  # a jump leaves the thread chain: a G33 block at its target is cut
        holds = True
        if jump.condition:
            esr = self._threads.esr
            assert esr is not None
            try:
                holds = bool(parse_condition(jump.condition)(esr.read))
            except SyncActionError as error:
                self._raise(12080, cycle, block, str(error) or jump.condition)
                self._stop()
                return
            except KeyError as unknown:
                self._raise(12550, cycle, block, unknown.args[0])
                self._stop()
                return
        target = jump_target(self.run.blocks, self.run.block_index, jump) if holds else self.run.block_index + 1
        if target is None and jump.direction != "GOTOC":
            self._raise(14080, cycle, block, jump.target)
            self._stop()
            return
        self.run.block_index = self.run.block_index + 1 if target is None else target

    def _start_block_body(self, cycle: int = 0) -> None:
        """After the spindle interlocks and the functions output before the motion: referencing,
        dwell, motion or the block end."""
        plan = self.run.plan
        assert plan is not None
        if plan.aux_functions and not self._aux.motion_may_start:
            self.run.phase = BlockPhase.AUXILIARY
            return
        if plan.reference_axes:
            self._g74_axes = list(plan.reference_axes)
            self.run.phase = BlockPhase.REFERENCE
            for name in self._g74_axes:
                if not self._referencing.start(name, Source.G74, 0, cycle):
                    self._alarms.raise_alarm(20005, cycle, self.name, name, channel=self.name, axis=name)
                    self._stop()
                    return
            return
        if plan.dwell > 0.0:
            self.run.phase = BlockPhase.DWELL
            self._dwell_cycles = max(1, math.ceil(plan.dwell / self._dt - 1e-9))
            return
        if plan.dwell_revolutions > 0.0:
            self.run.phase = BlockPhase.DWELL
            self._dwell_degrees = plan.dwell_revolutions * 360.0
            self._dwell_spindle = plan.dwell_spindle
            return
        # G43.4 / G68.2 / G53.1: the path in program coordinates, or a refusal before anything moves
        tool_path = self.five_axis.plan(plan, self.run.modal.five_axis, self.run.current_block.label
                                        if self.run.current_block is not None else "")
        if tool_path is not None and not isinstance(tool_path, ToolPathSegment):
            self._alarms.raise_alarm(tool_path.number, cycle, *tool_path.parameters, channel=self.name,
                                     axis=tool_path.axis)
            self._stop()
            return
        for name, motion in plan.positioning.items():
            self._positioning.program_position(name, motion.target)  # each on its own interpolator (L11195)
        if not plan.targets:
            self.run.phase = BlockPhase.BLOCK_END
            self._block_end()
            return
        self.dry_run.take(self.inputs.dry_run)  # DB21.DBX0.6 takes effect at a block's start (MD10704)
        if plan.thread is not None:
            if self._threads.start_thread(cycle):
                self._block_end()
            return
        if plan.tapping is not None:
            block = self.run.current_block
            assert block is not None
            if not self._spindles.plan_tapping(plan, cycle, block):
                return
        axes = [self.axes_by_name[name] for name in plan.targets]
        if tool_path is None and plan.arc is not None:
            arc_path = self._arc_path(plan, axes)
            if isinstance(arc_path, DecodeAlarm):
                self._alarms.raise_alarm(arc_path.number, cycle, *arc_path.parameters, channel=self.name,
                                         axis=arc_path.axis)
                self._stop()
                return
            tool_path = arc_path
        for axis in axes:
            if axis.owner is not Owner.NONE and axis.owner is not Owner.PATH:
                axis.brake()
        segment = tool_path if tool_path is not None else PathSegment.plan(
            axes,
            [plan.targets[axis.name] for axis in axes],
            [axis.name in self._geometry for axis in axes],
            self._planned_feed(plan),
            plan.rapid,
            plan.path_length,
        )
        stop = self._stroke.path_stop(segment)
        if stop is not None and stop.fraction <= BOUNDARY:
            self._raise_stroke_alarm(stop, cycle)  # starts in a forbidden area or at its boundary towards it
            return
        if stop is not None:
            segment = self._stroke.shortened(segment, stop.fraction, plan.path_length)
        self.stroke_stop = stop
        self.run.segment = segment
        per_revolution = plan.feed_per_revolution and not plan.rapid and not self.dry_run.active \
            and self._fixed_feed(plan) <= 0.0
        self._feed_per_revolution = (plan.feed / 60.0, segment.command_velocity) if per_revolution else None
        for axis in axes:
            axis.take(Owner.PATH)
        self._approaching = self._fixed_stops.approaching(axes) if self._fixed_stops.of else set()
        self._fixed_stops.selected_by_action = False
        self.run.phase = BlockPhase.INTERPOLATE
        self._interpolate(False, cycle)

    def _arc_path(self, plan: BlockPlan, axes: list[MachineAxis]) -> ToolPathSegment | DecodeAlarm:
        """G2 / G3: the arc is interpolated in program coordinates and every IPO cycle its point goes
        to the machine axes, through the inclined-axis mapping for the pair (seed 000 L194-204); the
        end is the block's machine end point.  The software limits of the other axes are checked
        along the arc before it moves (the pair's where its AOT bit says, when it was planned)."""
        arc = plan.arc
        assert arc is not None
        names = [axis.name for axis in axes]
        inclined = self.inclined

        def positions_at(fraction: float) -> list[float]:
            if fraction >= 1.0:
                return [plan.targets[name] for name in names]
            point = arc.point(fraction)
            if inclined is not None:
                point = inclined.path_positions(point)
            return [point[name] for name in names]

        segment = ToolPathSegment.plan(axes, positions_at, arc.length, self._planned_feed(plan), plan.rapid)
        checked_elsewhere = inclined.machine_axes if inclined is not None else ()
        label = self.run.current_block.label if self.run.current_block is not None else ""
        for sample in segment.samples:
            for axis, position in zip(axes, sample, strict=True):
                alarm = None if axis.name in checked_elsewhere else \
                    software_limit_alarm(self.name, label, axis, position)
                if alarm is not None:
                    return alarm
        return segment

    def _raise_stroke_alarm(self, stop: StrokeStop, cycle: int) -> None:
        label = self.run.current_block.label if self.run.current_block is not None else ""
        self.stroke_stop = None
        self._alarms.raise_alarm(stop.number, cycle, self.name, label, stop.axis, channel=self.name, axis=stop.axis)
        self._stop()

    def _g74(self, cycle: int) -> None:
        """G74: the block ends when every programmed axis is referenced (seed 003 §4.4)."""
        procedures = [self._referencing.of[name] for name in self._g74_axes]
        if any(procedure.state is State.IDLE for procedure in procedures):
            self._stop()  # aborted with an alarm: the program stops
            self.run.phase = BlockPhase.CONTOUR_LOST
            return
        if all(procedure.state is State.DONE for procedure in procedures):
            self.run.phase = BlockPhase.BLOCK_END
            self._block_end()
