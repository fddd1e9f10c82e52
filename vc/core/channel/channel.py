"""A channel: program execution, NC start/stop/reset, block change, and its DB21 signals.

Channel and program states (DB21.DBX35.x)::

    RESET / aborted ──NC start (AUTO: selected program, MDA: MDA buffer)──▶ ACTIVE / running
    ACTIVE / running ──NC stop, M0, alarm with interrupt──▶ INTERRUPTED / stopped
    INTERRUPTED / stopped ──mode change (e.g. to JOG)──▶ INTERRUPTED / interrupted
    INTERRUPTED ──NC start (in the mode the program was started in)──▶ ACTIVE / running
    any ──reset, M2, M30──▶ RESET / aborted

Block execution, one phase at a time::

    DECODE ──motion block──▶ INTERPOLATE ──path at its end──▶ BLOCK_END (exact stop window)
    DECODE ──G4──▶ DWELL ──time elapsed──▶ next block
    DECODE ──G74──▶ REFERENCE ──the programmed axes referenced──▶ BLOCK_END
    DECODE ──spindle gear change or M70 in the block──▶ SPINDLE ──done──▶ (motion, dwell, BLOCK_END)
    BLOCK_END ──window reached, read-in not disabled──▶ DECODE (next block)
    INTERPOLATE ──an axis braked off the path (e-stop, limit switch)──▶ CONTOUR_LOST ──RESET──▶ DECODE
    INTERPOLATE ──the path ended on a stored stroke limit 2 / 3 (G22)──▶ CONTOUR_LOST

A block is decoded only when it is about to run, so a faulty block raises its alarm when
execution reaches it, and a software limit switch in the block stops the program before
the block moves.

Channel-specific referencing (seed 003 §4.3): DB21.DBX1.0 in JOG-REF or MDA-REF references
the channel's axes in the order of MD34110 (ascending; equal numbers together; 0 and -1
take no part) and reports DB21.DBX33.0 while it runs.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass
from enum import Enum

from vc.config import md_dictionary as MD
from vc.config.model import ChannelConfig
from vc.core.alarms import CHANNEL_INTERRUPT, NC_START_DISABLED, STOP_AXES, AlarmList, Clear
from vc.core.axis.axis import FREE_JOG, JogLimits, MachineAxis, Owner
from vc.core.axis.stroke_limits import BOUNDARY, StrokeLimitControl, StrokeStop
from vc.core.channel.referencing_control import ReferencingControl
from vc.core.interface_map import SignalTable
from vc.core.interpolation.path import PathSegment
from vc.core.interpolation.thread_cutting import THREAD_SPINDLE_STANDS, ThreadSegment
from vc.core.interpolation.tool_path import ToolPathSegment
from vc.core.overrides import OverrideCoding
from vc.core.program.commands import BlockChange, CouplingCommand, SpindleCommand, block_change_of, kind_of
from vc.core.program.block_plan import (
    EXACT_STOP_COARSE,
    EXACT_STOP_FINE,
    BlockPlan,
    DecodeAlarm,
    ModalState,
    software_limit_alarm,
)
from vc.core.program.interpreter import decode
from vc.core.program.program import Block, Jump, jump_target, parse_program
from vc.core.program.sync_actions import SyncActionError, VariableWrite, parse_condition
from vc.core.referencing.referencing import Source, State
from vc.core.retraction.esr import ChannelEsr
from vc.core.spindle.coupling import ALARM_COUPLING_ACTIVE, Couplings
from vc.core.spindle.polygon import ALARM_AXIS_SYNCHRONISED, PolygonTurning
from vc.core.spindle.spindle import RPM, SUPPRESS_IN_DRY_RUN, SUPPRESS_IN_PROGRAM_TEST, Spindle, SpindleMode
from vc.core.transforms.five_axis_control import FiveAxisControl
from vc.core.transforms.inclined_axis_control import InclinedAxisControl


class ChannelState(Enum):
    RESET = "reset"
    ACTIVE = "active"
    INTERRUPTED = "interrupted"


class ProgramState(Enum):
    ABORTED = "aborted"
    RUNNING = "running"
    WAITING = "waiting"
    STOPPED = "stopped"
    INTERRUPTED = "interrupted"


class Phase(Enum):
    DECODE = "decode"
    INTERPOLATE = "interpolate"
    BLOCK_END = "block_end"
    DWELL = "dwell"
    REFERENCE = "reference"  # G74: waiting until the programmed axes are referenced
    SPINDLE = "spindle"  # the block's gear change, M70, or the spindle speed before machining
    CONTOUR_LOST = "contour_lost"  # an axis was braked off the path: NC start cannot continue


class Mode(Enum):
    AUTO = "AUTO"
    MDA = "MDA"
    JOG = "JOG"


class ChannelSignals:
    def __init__(self, table: SignalTable):
        self.nc_start_disable = table.bit("basic.out.disableNcStart")
        self.nc_start = table.bit("basic.out.ncStart")
        self.nc_stop = table.bit("basic.out.ncStop")
        self.nc_stop_all = table.bit("basic.out.ncStopAxesAndSpindles")
        self.reset = table.bit("basic.out.reset")
        self.feed_disable = table.bit("basic.out.disableFeed")
        self.read_in_disable = table.bit("basic.out.disableReadIn")
        self.delete_distance_to_go = table.bit("basic.out.deleteDistanceToGo")
        self.reference_start = table.bit("basic.out.refPointApproach")
        self.reference_active = table.bit("basic.in.refActive")
        self.feed_override = table.field("basic.out.pathFeedrateOvrFactor")
        self.feed_override_active = table.bit("basic.out.pathFeedrateOvr")
        self.rapid_override = table.field("basic.out.pathRapidTraversOvrFactor")
        self.rapid_override_active = table.bit("basic.out.pathRapidTraversOvr")
        self.running = table.bit("basic.in.progStateRunning")
        self.waiting = table.bit("basic.in.progStateWaiting")
        self.stopped = table.bit("basic.in.progStateStopped")
        self.interrupted = table.bit("basic.in.progStateInterrupted")
        self.aborted = table.bit("basic.in.progStateAborted")
        self.state_active = table.bit("basic.in.stateActive")
        self.state_interrupted = table.bit("basic.in.stateInterrupted")
        self.state_reset = table.bit("basic.in.stateReset")
        self.dry_run = table.bit("basic.out.dryRunFeedrate")
        self.program_test = table.bit("basic.out.progTest")
        self.all_referenced = table.bit("basic.in.allAxesReferenced")
        self.all_stationary = table.bit("basic.in.allAxesStationary")
        self.alarm_active = table.bit("basic.in.alarmActive")
        self.alarm_with_stop = table.bit("basic.in.alarmWithStopActive")


@dataclass(slots=True)
class ChannelInputs:
    nc_start_disable: bool = False
    nc_start: bool = False
    nc_stop: bool = False
    nc_stop_all: bool = False
    reset: bool = False
    reference_start: bool = False
    feed_disable: bool = False
    read_in_disable: bool = False
    delete_distance_to_go: bool = False
    feed_override: float = 1.0
    rapid_override: float = 1.0
    dry_run: bool = False
    program_test: bool = False


@dataclass(slots=True)
class Edges:
    nc_start: bool = False
    nc_stop: bool = False
    reset: bool = False
    delete_distance_to_go: bool = False
    reference_start: bool = False


class Channel:
    def __init__(
        self,
        config: ChannelConfig,
        signals: ChannelSignals,
        area: bytearray,
        axes: list[MachineAxis],
        alarms: AlarmList,
        feed_coding: OverrideCoding,
        rapid_coding: OverrideCoding,
        dt: float,
        referencing: ReferencingControl,
    ):
        self.config = config
        self.name = config.name
        self.area_key = f"DB{config.db}"
        self._signals = signals
        self._area = area
        self.axes = axes
        self.axes_by_name = {axis.name: axis for axis in axes}
        self.five_axis = FiveAxisControl(config, self.axes_by_name)  # G43.4, G43, G68.2, G53.1 (seed 001)
        self.stroke_limits = StrokeLimitControl(self.axes_by_name,  # G22 / G23, stroke limit 3 (seed 000)
                                                not config.md.bool(MD.STROKE2_OUTSIDE_FORBIDDEN))
        self._stroke_stop: StrokeStop | None = None  # the running block ends on a stroke limit boundary
        self.inclined: InclinedAxisControl | None = None  # inclined-axis control (seed 000), given by the NCK
        self._alarms = alarms
        self._feed_coding = feed_coding
        self._rapid_coding = rapid_coding
        self._dt = dt
        self._referencing = referencing
        self.reference_groups: list[list[str]] = []  # channel referencing: groups still to do, MD34110 order
        self._group_started = False
        self._g74_axes: list[str] = []
        self.inputs = ChannelInputs()
        self.edges = Edges()
        self.state = ChannelState.RESET
        self.program_state = ProgramState.ABORTED
        self.modal = ModalState()
        self.mda_text = ""
        self.selected_program: tuple[str, str] | None = None
        self.started_in: Mode | None = None
        self._blocks: tuple[Block, ...] = ()
        self._block_index = 0
        self._leaving_thread_chain = False  # after a fast retraction: skip the chain's other G33 blocks
        self.current_block: Block | None = None
        self._phase = Phase.DECODE
        self._plan: BlockPlan | None = None
        self._segment: PathSegment | ToolPathSegment | None = None
        # G95 / G99: the segment's F (mm/rev, per second) and the velocity its axes allow
        self._feed_per_revolution: tuple[float, float] | None = None
        self._dwell_cycles = 0
        self._stop_after_block = False
        self._stopping = False  # braking on the path after NC stop / an alarm
        self._aborting = False  # braking on the path after a reset
        self._geometry = set(axis for axis in config.geometry_axes if axis)
        self._summary: tuple[bool, bool] | None = None
        self._needs_reference = [
            axis for axis in axes
            if not axis.is_spindle and axis.config.md.int(MD.REFP_CYCLE_NR) != -1
        ]
        self.spindles: dict[str, Spindle] = {}  # machine axis -> spindle, given by the NCK
        self.couplings: Couplings | None = None  # given by the NCK
        self.polygon: PolygonTurning | None = None
        self._coupling_feeds: dict[str, float] = {}  # FA[Sn], deg/min (modal)
        self._waits: list[tuple[str, BlockChange | None]] = []  # COUPON / WAITC block-change conditions
        self._dwell_degrees = 0.0  # G4 S: degrees the counted spindle still has to turn
        self._dwell_spindle = ""  # G4 S: the spindle whose revolutions count
        self.esr: ChannelEsr | None = None  # fast retraction and ESR, given by the NCK
        self._thread_segment: ThreadSegment | None = None  # the running G33 block
        self._thread_chain: float | None = None  # spindle position where the last G33 block ended
        self._thread_interrupted = False  # an ESR trigger retracted from the running G33 block (LFON)
        self.esr_run_on_spindle: str | None = None  # the master spindle of a thread in the ESR's MD21380

    # ------------------------------------------------------------------ inputs
    def decode_inputs(self) -> None:
        area, sig, inp, edges = self._area, self._signals, self.inputs, self.edges
        nc_start = sig.nc_start.get(area)
        nc_stop = sig.nc_stop.get(area)
        nc_stop_all = sig.nc_stop_all.get(area)
        reset = sig.reset.get(area)
        delete = sig.delete_distance_to_go.get(area)
        reference_start = sig.reference_start.get(area)
        edges.reference_start = reference_start and not inp.reference_start
        inp.reference_start = reference_start
        edges.nc_start = nc_start and not inp.nc_start
        edges.nc_stop = (nc_stop and not inp.nc_stop) or (nc_stop_all and not inp.nc_stop_all)
        edges.reset = reset and not inp.reset
        edges.delete_distance_to_go = delete and not inp.delete_distance_to_go
        inp.nc_start, inp.nc_stop, inp.nc_stop_all, inp.reset = nc_start, nc_stop, nc_stop_all, reset
        inp.delete_distance_to_go = delete
        inp.nc_start_disable = sig.nc_start_disable.get(area)
        inp.feed_disable = sig.feed_disable.get(area)
        inp.read_in_disable = sig.read_in_disable.get(area)
        inp.dry_run = sig.dry_run.get(area)
        inp.program_test = sig.program_test.get(area)
        inp.feed_override = self._feed_coding.factor(sig.feed_override.get(area), sig.feed_override_active.get(area))
        inp.rapid_override = self._rapid_coding.factor(sig.rapid_override.get(area),
                                                       sig.rapid_override_active.get(area))

    def clear_edges(self) -> None:
        edges = self.edges
        edges.nc_start = edges.nc_stop = edges.reset = edges.delete_distance_to_go = edges.reference_start = False

    # ------------------------------------------------------------------ commands
    @property
    def is_active(self) -> bool:
        return self.state is ChannelState.ACTIVE

    def reset(self, cycle: int) -> None:
        """Channel or mode-group reset: abort the program, brake, clear reset alarms."""
        self._alarms.clear_on((Clear.RESET, Clear.CANCEL), channel=self.name)
        if self._segment is not None and not self._segment.finished:
            self._aborting = True
        self._end_thread_functions()
        self._end_program()
        if self.inclined is not None:
            self.inclined.reset()
        self._stroke_stop = None
        self.reference_groups = []
        for axis in self.axes:
            if axis.owner is Owner.JOG:
                axis.brake()
            if axis.at_software_limit:
                self._alarms.clear(10621, axis=axis.name)  # its monitor only clears what it still sees
            axis.at_software_limit = 0
        self._reset_couplings()
        for spindle in self.spindles.values():
            spindle.reset(program_end=False)

    def _end_thread_functions(self) -> None:
        """Reset or program end: a running thread block stops, the modal synchronized actions end."""
        if self._thread_segment is not None:
            for axis in self._thread_segment.axes:
                axis.brake()
            self._thread_segment = None
        self._thread_chain = None
        self._thread_interrupted = False
        if self.esr is not None:
            self.esr.program_ended()

    def _reset_couplings(self) -> None:
        """Reset and program end: the couplings as MD21330 / MD20110 say, polygon turning as HBR."""
        kept = self.polygon.reset() if self.polygon is not None else None
        if self.couplings is not None:
            self.couplings.reset(self.name, kept_by_polygon=kept)
        self._waits = []
    def _end_program(self) -> None:
        self.state = ChannelState.RESET
        self.program_state = ProgramState.ABORTED
        self.started_in = None
        self._blocks = ()
        self._block_index = 0
        self._leaving_thread_chain = False
        self.current_block = None
        self._phase = Phase.DECODE
        self._plan = None
        self._stop_after_block = False
        self._stopping = False
        self.modal.reset()

    @property
    def block_in_progress(self) -> BlockPlan | None:
        """The block being executed, also while the program is stopped in it (None in reset)."""
        return self._plan if self.state is not ChannelState.RESET else None

    def nc_start(self, cycle: int, mode: Mode, reference_function: bool) -> None:
        """NC start edge from the PLC."""
        inp = self.inputs
        if inp.nc_start_disable or inp.nc_stop or inp.nc_stop_all or inp.reset:
            return
        if self._alarms.reactions(self.name) & NC_START_DISABLED:
            return
        if mode is Mode.JOG or reference_function:
            return
        if self.state is ChannelState.INTERRUPTED:
            if self.started_in is mode and self._phase is not Phase.CONTOUR_LOST:
                self.state = ChannelState.ACTIVE
                self.program_state = ProgramState.RUNNING
                self._stopping = False
            return
        if self.state is not ChannelState.RESET:
            return
        if not self._references_allow_start(cycle, mode):
            return
        text = self.mda_text if mode is Mode.MDA else (self.selected_program[1] if self.selected_program else "")
        self._blocks = parse_program(text)
        self._block_index = 0
        self._leaving_thread_chain = False
        self._phase = Phase.DECODE
        self.modal.reset()
        if self.couplings is not None:
            self.couplings.nc_start(self.name, kept_by_polygon=self.polygon.kept() if self.polygon else None)
        if self.polygon is not None:
            self.modal.polygon = self.polygon.active
        for spindle in self.spindles.values():
            spindle.program_start()
        self.started_in = mode
        self.state = ChannelState.ACTIVE
        self.program_state = ProgramState.RUNNING

    def _references_allow_start(self, cycle: int, mode: Mode) -> bool:
        """MD20700 REFP_NC_START_LOCK: no program start with unreferenced axes (seed 003 L2218-2231);
        with 2, restored positions count as well in MDA (L2726-2752)."""
        lock = self.config.md.int(MD.REFP_NC_START_LOCK)
        if lock == 0:
            return True
        restored_allowed = lock == 2 and mode is Mode.MDA
        if all(axis.referenced or (restored_allowed and axis.encoder.restored) for axis in self._needs_reference):
            return True
        self._alarms.raise_alarm(10203, cycle, self.name, 1, channel=self.name)
        return False

    def stop(self) -> None:
        """NC stop: brake on the path, the program is stopped and can continue with NC start.
        In G33 the thread block runs to its end, or with LFON the tool retracts at once (L8215-8221)."""
        if self.state is ChannelState.ACTIVE and self._thread_segment is not None and self.modal.retract.enabled:
            self._lift_fast(None)
        if self.state is ChannelState.ACTIVE:
            self.state = ChannelState.INTERRUPTED
            self.program_state = ProgramState.STOPPED
            self._stopping = True

    def mode_changed(self) -> None:
        """Leaving the mode of a stopped program interrupts it (DB21.DBX35.3)."""
        if self.state is ChannelState.INTERRUPTED:
            self.program_state = ProgramState.INTERRUPTED

    # ------------------------------------------------------------------ cycle
    def program_cycle(self, cycle: int) -> None:
        """Interpolation and block change for one IPO cycle."""
        if self.reference_groups:
            self._channel_referencing(cycle)
        esr = self.esr
        path_runs_on = False
        if esr is not None and esr.running:
            esr.cycle(cycle, self._thread_segment or self._segment)
            path_runs_on = esr.path_runs_on(cycle)  # MD21380: the stop axes' path goes on
        # a thread's run-on needs its spindle turning through the alarms' interpolation stop [control]
        thread = self._thread_segment
        self.esr_run_on_spindle = thread.spindle.name if path_runs_on and thread is not None else None
        reactions = self._alarms.reactions(self.name)
        if reactions & CHANNEL_INTERRUPT and self.state is ChannelState.ACTIVE:
            self.stop()
        if self._aborting:
            self._brake_segment()
            return
        if self.state is ChannelState.RESET:
            return
        hold = (self.state is not ChannelState.ACTIVE or bool(reactions & STOP_AXES)) and not path_runs_on
        if self._phase is Phase.INTERPOLATE:
            self._interpolate(hold, cycle)
        elif self._phase is Phase.REFERENCE:
            self._g74(cycle)
        elif self._phase is Phase.SPINDLE and not hold:
            if self._spindles_ready():
                self._start_block_body(cycle)
        elif self._phase is Phase.DWELL and not hold:
            self._dwell_cycle()
        elif self._phase is Phase.BLOCK_END:
            self._block_end()
        if self._phase is Phase.DECODE and self.state is ChannelState.ACTIVE and not hold:
            self._decode_next(cycle)

    def _dwell_cycle(self) -> None:
        if self._dwell_degrees > 0.0:
            counted = self.spindles.get(self._dwell_spindle)
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
        self._phase = Phase.BLOCK_END
        self._block_end()

    @property
    def thread_in_progress(self) -> ThreadSegment | None:
        """The G33 block's thread while it runs."""
        return self._thread_segment

    @staticmethod
    def _planned_feed(plan: BlockPlan) -> float:
        """Path velocity per second to plan with; under G95 / G99 the axes' limit, which the speed of
        the spindle lowers in every cycle (``_revolution_speed``)."""
        return math.inf if plan.feed_per_revolution else plan.feed / 60.0

    def _revolution_speed(self) -> float:
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

    def _brake_segment(self) -> None:
        segment = self._segment
        if segment is None or segment.finished or segment.velocity == 0.0 or \
                any(axis.owner is not Owner.PATH for axis in segment.axes):
            self._release_segment()
            self._aborting = False
            return
        segment.cycle(1.0, True, self._dt)
        if segment.velocity == 0.0:
            self._release_segment()
            self._aborting = False

    def _release_segment(self) -> None:
        if self._segment is not None:
            for axis in self._segment.axes:
                if axis.owner is Owner.PATH:
                    axis.release()
        self._segment = None

    def _interpolate(self, hold: bool, cycle: int) -> None:
        if self._thread_segment is not None:
            self._thread_cycle()
            return
        segment = self._segment
        assert segment is not None and self._plan is not None
        axes_hold = False
        inclined = self.inclined
        carried = inclined.orthogonal if inclined is not None and inclined.orthogonal_only_carried else None
        for axis in segment.axes:
            if axis.owner is not Owner.PATH:
                # A reaction (rapid stop, limit switch) braked an axis off the path: the contour is
                # lost, the block cannot be finished; the program stops and only RESET ends it.
                self._release_segment()
                self._phase = Phase.CONTOUR_LOST
                self.stop()
                return
            # Feed disable, an axis feed stop or a missing enable hold the path; the program
            # keeps its state "running" (only read-in disable makes it "waiting").
            interlocked = axis.inputs.feed_stop and axis is not carried
            axes_hold = axes_hold or interlocked or not axis.drive_ready
        blocked = hold or self.inputs.feed_disable or axes_hold
        override = self.inputs.rapid_override if segment.rapid else self.inputs.feed_override
        if self._feed_per_revolution is not None:
            feed, limit = self._feed_per_revolution
            # the spindle's turning sets the path velocity; a standing spindle holds the path (no alarm)
            segment.command_velocity = min(limit, feed * self._revolution_speed())
        segment.cycle(override, blocked, self._dt)
        if segment.finished:
            self._release_segment()
            if self._stroke_stop is not None:
                self._phase = Phase.CONTOUR_LOST  # the block cannot go on; RESET ends it
                self._raise_stroke_alarm(self._stroke_stop, cycle)
                return
            if self._leg_finished():
                return
            self._phase = Phase.BLOCK_END
            self._block_end()

    def _leg_finished(self) -> bool:
        """A motion of the block has arrived.  G28 / G30 at the intermediate point: True, the axes
        go on to their reference points in a second motion."""
        plan = self._plan
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
        plan = self._plan
        assert plan is not None
        if any(self.spindles[name].holds_block_end for name in plan.spindles):
            return  # SPOS / M19: the block ends when the spindle is in position (L16475-16496)
        if any(not self.spindles[name].positioned_or_stopped() for name in plan.spindle_waits):
            return  # WAITS
        couplings = self.couplings
        if couplings is not None and (
                any(couplings.holds_block(name, criterion) for name, criterion in self._waits)
                or any(couplings.overlay_holds_block(name) for name in plan.spindles)):
            return  # COUPON's block-change condition, WAITC, SPOS on a coupled FS (L22583-22592)
        if plan.block_end in (EXACT_STOP_FINE, EXACT_STOP_COARSE):
            fine = plan.block_end == EXACT_STOP_FINE
            for name in plan.targets:
                axis = self.axes_by_name[name]
                window = axis.dyn.fine_window if fine else axis.dyn.coarse_window
                if abs(axis.distance_to_end_point) > window:
                    return
        if self.inputs.read_in_disable:
            self.program_state = ProgramState.WAITING
            return
        if self.program_state is ProgramState.WAITING:
            self.program_state = ProgramState.RUNNING
        self._next_block()

    def _next_block(self) -> None:
        plan = self._plan
        self._phase = Phase.DECODE
        self._plan = None
        self._block_index += 1
        if plan is not None and plan.program_end:
            self._reset_couplings()
            self._end_thread_functions()
            for spindle in self.spindles.values():
                spindle.reset(program_end=True)
            self._end_program()
        elif plan is not None and plan.program_stop:
            self.stop()

    def _decode_next(self, cycle: int) -> None:
        if self._block_index >= len(self._blocks):
            self._end_program()  # a program without M30 ends after its last block
            return
        block = self._blocks[self._block_index]
        self.current_block = block
        jump = next((item for item in block.items if isinstance(item, Jump)), None)
        if jump is not None:  # alone, or after its label ("MM: IF ... GOTOB MM")
            self._jump(jump, block, cycle)
            return
        positions = self.five_axis.program_positions(self.modal.five_axis)
        pair: tuple[str, ...] = ()
        if self.inclined is not None:
            positions.update(self.inclined.program_positions())
            pair = self.inclined.machine_axes
        plan, alarm = decode(block, self.modal, self.config, self.axes_by_name, positions, pair)
        if self._leaving_thread_chain and alarm is None:
            if plan.thread is not None:
                self._block_index += 1  # a G33 block of the interrupted chain: not cut from the retract position
                return
            self._leaving_thread_chain = False
        if alarm is None:
            alarm = self.five_axis.apply(plan, self.modal.five_axis, block.label, pair)
        if alarm is None and self.inclined is not None:
            alarm = self.inclined.plan(plan, block.label)  # the inclined Y1 slide (seed 000)
        if alarm is not None:
            self._alarms.raise_alarm(alarm.number, cycle, *alarm.parameters, channel=self.name, axis=alarm.axis)
            self.stop()
            return
        self._plan = plan
        self._waits = []
        if plan.stroke_limit is not None:
            self.stroke_limits.apply(plan.stroke_limit)
        if not self._coupling_functions(plan, cycle, block):
            self.stop()
            return
        self._retract_functions(plan, cycle)
        for name, value in plan.preset.items():
            self.axes_by_name[name].preset_actual(value)
        if plan.delete_drf:
            for axis in self.axes:
                axis.delete_drf_offset()
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
        catching_up = False
        for spindle in self.spindles.values():
            if spindle.suppressed_gear is not None and not suppress(spindle):
                spindle.catch_up_gear(cycle, self._alarms, block.label)
                catching_up = catching_up or spindle.change is not None
        if plan.spindles or plan.targets or catching_up or self._waits:
            self._phase = Phase.SPINDLE
            if not self._spindles_ready():
                return
        self._start_block_body(cycle)

    # ------------------------------------------------------------------ couplings, polygon turning
    def _jump(self, jump: Jump, block: Block, cycle: int) -> None:
        """IF <condition> GOTOx <target>, evaluated when the block is reached: a condition on $A...
        variables stops the preprocessing until then on the control [control].  A jump block takes
        its IPO cycle.  An unreadable condition raises 12080, an unknown variable 12550, a missing
        destination 14080 (GOTOC: the program goes on after the block)."""
        self._leaving_thread_chain = False  # a jump leaves the thread chain: a G33 block at its target is cut
        holds = True
        if jump.condition:
            assert self.esr is not None
            try:
                holds = bool(parse_condition(jump.condition)(self.esr.read))
            except SyncActionError as error:
                self._raise(12080, cycle, block, str(error) or jump.condition)
                self.stop()
                return
            except KeyError as unknown:
                self._raise(12550, cycle, block, unknown.args[0])
                self.stop()
                return
        target = jump_target(self._blocks, self._block_index, jump) if holds else self._block_index + 1
        if target is None and jump.direction != "GOTOC":
            self._raise(14080, cycle, block, jump.target)
            self.stop()
            return
        self._block_index = self._block_index + 1 if target is None else target

    def _raise(self, number: int, cycle: int, block: Block, *parameters: object, axis: str = "") -> None:
        self._alarms.raise_alarm(number, cycle, self.name, block.label, *parameters, channel=self.name, axis=axis)

    def _coupling_functions(self, plan: BlockPlan, cycle: int, block: Block) -> bool:
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
                self._waits.append((following, None))
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
        self._waits.append((following, criterion))
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
            self.stop()
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
                self.stop()
        return True

    def _gear_change_suppressed(self, spindle: Spindle) -> bool:
        """MD35035 bits 0 / 1: no gear change in dry run / program test (L19956-19993)."""
        mask = spindle.md.int(MD.SPIND_FUNCTION_MASK)
        return (self.inputs.dry_run and bool(mask & SUPPRESS_IN_DRY_RUN)) or \
            (self.inputs.program_test and bool(mask & SUPPRESS_IN_PROGRAM_TEST))

    def _spindles_ready(self) -> bool:
        """Block change interlocks of the spindles (L18540-18548, L16517-16540): the block's gear
        change and M70 first; a machining block (not G0) starts only with every turning spindle at
        its speed (DB31.DBX83.5) when MD35500 asks for it."""
        plan = self._plan
        assert plan is not None
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

    def _start_block_body(self, cycle: int = 0) -> None:
        """After the spindle interlocks: referencing, dwell, motion or the block end."""
        plan = self._plan
        assert plan is not None
        if plan.reference_axes:
            self._g74_axes = list(plan.reference_axes)
            self._phase = Phase.REFERENCE
            for name in self._g74_axes:
                if not self._referencing.start(name, Source.G74, 0, cycle):
                    self._alarms.raise_alarm(20005, cycle, self.name, name, channel=self.name, axis=name)
                    self.stop()
                    return
            return
        if plan.dwell > 0.0:
            self._phase = Phase.DWELL
            self._dwell_cycles = max(1, math.ceil(plan.dwell / self._dt - 1e-9))
            return
        if plan.dwell_revolutions > 0.0:
            self._phase = Phase.DWELL
            self._dwell_degrees = plan.dwell_revolutions * 360.0
            self._dwell_spindle = plan.dwell_spindle
            return
        # G43.4 / G68.2 / G53.1: the path in program coordinates, or a refusal before anything moves
        tool_path = self.five_axis.plan(plan, self.modal.five_axis, self.current_block.label
                                        if self.current_block is not None else "")
        if tool_path is not None and not isinstance(tool_path, ToolPathSegment):
            self._alarms.raise_alarm(tool_path.number, cycle, *tool_path.parameters, channel=self.name,
                                     axis=tool_path.axis)
            self.stop()
            return
        if not plan.targets:
            self._phase = Phase.BLOCK_END
            self._block_end()
            return
        if plan.thread is not None:
            self._start_thread(cycle)
            return
        if plan.tapping is not None and not self._plan_tapping(plan, cycle):
            return
        axes = [self.axes_by_name[name] for name in plan.targets]
        if tool_path is None and plan.arc is not None:
            arc_path = self._arc_path(plan, axes)
            if isinstance(arc_path, DecodeAlarm):
                self._alarms.raise_alarm(arc_path.number, cycle, *arc_path.parameters, channel=self.name,
                                         axis=arc_path.axis)
                self.stop()
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
        stop = self.stroke_limits.path_stop(self._segment_point(segment), isinstance(segment, PathSegment),
                                            self._stroke_point)
        if stop is not None and stop.fraction <= BOUNDARY:
            self._raise_stroke_alarm(stop, cycle)  # starts in a forbidden area or at its boundary towards it
            return
        if stop is not None:
            segment = self._shortened(segment, stop.fraction, plan.path_length)
        self._stroke_stop = stop
        self._segment = segment
        per_revolution = plan.feed_per_revolution and not plan.rapid
        self._feed_per_revolution = (plan.feed / 60.0, segment.command_velocity) if per_revolution else None
        for axis in axes:
            axis.take(Owner.PATH)
        self._phase = Phase.INTERPOLATE
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
        label = self.current_block.label if self.current_block is not None else ""
        for sample in segment.samples:
            for axis, position in zip(axes, sample, strict=True):
                alarm = None if axis.name in checked_elsewhere else \
                    software_limit_alarm(self.name, label, axis, position)
                if alarm is not None:
                    return alarm
        return segment

    # ------------------------------------------------------------------ stored stroke limits 2 and 3
    def _stroke_point(self, limit: int, machine: dict[str, float]) -> dict[str, float]:
        """Machine positions in the coordinates stroke limit ``limit`` is checked in."""
        return self.inclined.stroke_point(limit, machine) if self.inclined is not None else machine

    @staticmethod
    def _segment_point(segment: PathSegment | ToolPathSegment) -> Callable[[float], dict[str, float]]:
        """The machine positions of the segment's axes at a fraction of its path."""
        names = [axis.name for axis in segment.axes]
        if isinstance(segment, PathSegment):
            starts, ends = list(segment.starts), list(segment.ends)
            return lambda fraction: {name: start + (end - start) * fraction
                                     for name, start, end in zip(names, starts, ends, strict=True)}
        positions_at = segment.positions_at
        return lambda fraction: dict(zip(names, positions_at(fraction), strict=True))

    def _shortened(self, segment: PathSegment | ToolPathSegment, fraction: float,
                   program_length: float | None) -> PathSegment | ToolPathSegment:
        """The same path up to ``fraction``: it decelerates onto the stroke limit's boundary."""
        if isinstance(segment, PathSegment):
            point = self._segment_point(segment)(fraction)
            return PathSegment.plan(segment.axes, [point[axis.name] for axis in segment.axes],
                                    [axis.name in self._geometry for axis in segment.axes],
                                    segment.command_velocity, segment.rapid,
                                    program_length * fraction if program_length else None)
        positions_at = segment.positions_at
        return ToolPathSegment.plan(segment.axes, lambda part: positions_at(part * fraction),
                                    segment.length * fraction, segment.command_velocity, segment.rapid)

    def _raise_stroke_alarm(self, stop: StrokeStop, cycle: int) -> None:
        label = self.current_block.label if self.current_block is not None else ""
        self._stroke_stop = None
        self._alarms.raise_alarm(stop.number, cycle, self.name, label, stop.axis, channel=self.name, axis=stop.axis)
        self.stop()

    def stroke_jog_limits(self, axis: MachineAxis, cycle: int) -> JogLimits:
        """JOG stops on the boundary of stored stroke limits 2 and 3; held against it, the key raises
        the limit's alarm (docstring of ``vc/core/axis/stroke_limits.py``)."""
        keys = axis.inputs
        if not (keys.key_plus or keys.key_minus or axis.owner is Owner.JOG):
            return FREE_JOG
        inclined = self.inclined
        travel = inclined.jog_travel(axis) if inclined is not None else {axis.name: 1.0}
        room = self.stroke_limits.jog_room(travel, self._stroke_point)
        if room is None:
            return FREE_JOG
        low, high, low_number, high_number, reached = room
        pressed = 1 if keys.key_plus and not keys.key_minus else -1 if keys.key_minus and not keys.key_plus else 0
        if axis.command_velocity == 0.0 and ((pressed > 0 and high <= BOUNDARY) or (pressed < 0 and low >= -BOUNDARY)):
            self._alarms.raise_alarm(high_number if pressed > 0 else low_number, cycle, self.name, "JOG", reached,
                                     channel=self.name, axis=reached)
        window = (axis.setpoint + low, axis.setpoint + high)
        if axis.software_limits_active and (inclined is None or axis.name not in inclined.machine_axes):
            window = (max(window[0], axis.dyn.limit_minus), min(window[1], axis.dyn.limit_plus))
        return JogLimits(plus=high > BOUNDARY, minus=low < -BOUNDARY, window=window)

    def _plan_tapping(self, plan: BlockPlan, cycle: int) -> bool:
        """G331 / G332: the spindle's end point from the drilling travel and the pitch, and the path
        feed F = S x |pitch| with the last programmed S (seed 003 L8573-8581, L17679-17680).
        False: no spindle speed, alarm 14800 stops the program [control]."""
        tapping = plan.tapping
        assert tapping is not None and self.current_block is not None
        speed = self.spindles[tapping.spindle].speed
        if speed <= 0.0:
            self._raise(14800, cycle, self.current_block)
            self.stop()
            return False
        spindle = self.axes_by_name[tapping.spindle]
        travel = plan.targets[tapping.axis] - self.axes_by_name[tapping.axis].setpoint
        plan.tapping = dataclasses.replace(tapping, travel=travel)
        plan.targets[tapping.spindle] = spindle.setpoint + tapping.spindle_degrees(travel)
        plan.feed = speed * abs(tapping.pitch)
        return True

    # ------------------------------------------------------------------ G33, fast retraction, ESR
    def _retract_functions(self, plan: BlockPlan, cycle: int) -> None:
        """The block's system variables, synchronized actions, POLFA and ESRS / ESRR, in this order."""
        esr = self.esr
        if plan.thread is None:
            self._thread_chain = None
        if esr is None:
            return
        esr.add_actions(plan.sync_actions)
        for axis, kind, value in plan.single_axis_retract:
            esr.single_axis_retract_command(axis, kind, value)
        for command in plan.drive_esr:
            drive = esr.nck.drives.get(command.axis)
            if drive is not None:
                drive.configure(command)  # [control] the drive acknowledges within the block
        for write in plan.variables:
            esr.write(write, cycle)
        self.esr_trigger(cycle)

    def esr_trigger(self, cycle: int) -> None:
        """React to a rising $AC_ESR_TRIGGER: fast retraction in G33 with LFON, else the ESR reaction."""
        esr = self.esr
        if esr is None or not esr.channel_trigger_pending:
            return
        esr.channel_trigger_pending = False
        if self._thread_segment is not None and self.modal.retract.enabled and not self._thread_interrupted:
            self._lift_fast(cycle)
            return
        interpolation = (self._thread_segment or self._segment) if self._phase is Phase.INTERPOLATE else None
        esr.start_channel_reaction(cycle, [axis.name for axis in self.axes], interpolation, self.modal.retract,
                                   self._esr_delays(), self.inclined)
        if self._thread_segment is not None:
            # G33 without LFON: the retract axes have left the thread, the others follow the spindle on
            # for MD21380; the block is dropped when the ESR has braked them [control]
            if self._thread_segment.axes:
                self._thread_interrupted = True
            else:
                self._drop_thread_block()
        if self.state is ChannelState.ACTIVE:
            self.state = ChannelState.INTERRUPTED
            self.program_state = ProgramState.STOPPED
            self._stopping = True

    def _esr_delays(self) -> tuple[float, float]:
        md = self.config.md
        return md.float(MD.ESR_DELAY_TIME1), md.float(MD.ESR_DELAY_TIME2)

    def _lift_fast(self, esr_cycle: int | None) -> None:
        """G33 with LFON interrupted: retract; the thread axes that stay stop at once, or after an ESR
        trigger in ``esr_cycle`` when MD21380 / MD21381 say.  The rest of the thread block and the
        G33 blocks chained to it are dropped, so NC start goes on after the thread, where the seed's
        example tests ``IF $AC_LIFTFAST GOTOB MM_THREAD`` (L8356-8385) [INF]."""
        thread, esr = self._thread_segment, self.esr
        assert thread is not None and esr is not None
        esr.start_liftfast(self.modal.retract, self.modal.plane, thread, self.config.md.float(MD.LIFTFAST_DIST),
                           self.inclined, None if esr_cycle is None else (esr_cycle, self._esr_delays()))
        if esr_cycle is None or not thread.axes:
            self._drop_thread_block()
        else:
            self._thread_interrupted = True  # the thread runs on until the ESR brakes it
        self.state = ChannelState.INTERRUPTED
        self.program_state = ProgramState.STOPPED

    def _drop_thread_block(self) -> None:
        self._thread_segment = None
        self._thread_chain = None
        self._thread_interrupted = False
        self._plan = None
        self._phase = Phase.DECODE
        self._block_index += 1
        self._leaving_thread_chain = True

    def _start_thread(self, cycle: int) -> None:
        """G33: the axes follow the master spindle; a standing spindle cannot cut a thread (alarm 65870)."""
        plan, block = self._plan, self.current_block
        assert plan is not None and plan.thread is not None and block is not None
        master_name = self.master_spindle()
        master = self.spindles.get(master_name or "")
        if master is None or (master.axis.velocity == 0.0 and self._thread_chain is None):
            self._raise(THREAD_SPINDLE_STANDS, cycle, block, master_name or "-")
            self.stop()
            return
        axes = [self.axes_by_name[name] for name in plan.targets]
        lead_axis = self.axes_by_name.get(plan.thread.lead_axis)
        lead_delta = plan.targets[lead_axis.name] - lead_axis.setpoint if lead_axis and lead_axis.name in plan.targets \
            else 0.0
        self._thread_segment = ThreadSegment.plan(axes, [plan.targets[axis.name] for axis in axes], lead_delta,
                                                  plan.thread, master.axis, self._thread_chain)
        self._phase = Phase.INTERPOLATE
        self._thread_cycle()

    def _thread_cycle(self) -> None:
        thread = self._thread_segment
        assert thread is not None
        if any(axis.owner is not Owner.PATH for axis in thread.axes):
            if self._thread_interrupted:
                self._drop_thread_block()  # the ESR braked the thread axes after MD21380
                return
            for axis in thread.axes:
                if axis.owner is Owner.PATH:
                    axis.brake()  # braked off the thread (rapid stop): the others stop too, the contour is lost
            self._thread_segment = None
            self._phase = Phase.CONTOUR_LOST
            self.stop()
            return
        thread.cycle(self._dt)
        if thread.finished:
            for axis in thread.axes:
                axis.release()
            if self._thread_interrupted:
                self._drop_thread_block()  # ended in the ESR's run-on: the chain is left all the same
                return
            self._thread_segment = None
            self._thread_interrupted = False
            self._thread_chain = thread.end_position
            self._phase = Phase.BLOCK_END
            self._block_end()

    # ------------------------------------------------------------------ referencing
    @property
    def reference_active(self) -> bool:
        return bool(self.reference_groups)

    def start_channel_referencing(self, cycle: int) -> None:
        """DB21.DBX1.0: reference the channel's axes in the order of MD34110 (seed 003 L667-683)."""
        if self.state is not ChannelState.RESET or self.reference_groups:
            return
        numbers: dict[int, list[str]] = {}
        for axis in self.axes:
            number = axis.config.md.int(MD.REFP_CYCLE_NR)
            if not axis.is_spindle and number > 0:
                numbers.setdefault(number, []).append(axis.name)
        self.reference_groups = [numbers[number] for number in sorted(numbers)]
        self._group_started = False

    def _channel_referencing(self, cycle: int) -> None:
        group = self.reference_groups[0]
        procedures = [self._referencing.of[name] for name in group]
        if not self._group_started:
            for name, procedure in zip(group, procedures, strict=True):
                if not procedure.active and not self._referencing.start(name, Source.CHANNEL, 0, cycle):
                    if self._alarms.reactions(self.name) & STOP_AXES:
                        self.reference_groups = []  # the order rule (or another alarm) ends it
                    return  # wait for the enables
            self._group_started = True
            return
        if any(procedure.state is State.IDLE for procedure in procedures):
            self.reference_groups = []  # aborted (alarm or reset): the channel referencing ends
            return
        if all(procedure.state is State.DONE for procedure in procedures):
            self.reference_groups.pop(0)
            self._group_started = False

    def _g74(self, cycle: int) -> None:
        """G74: the block ends when every programmed axis is referenced (seed 003 §4.4)."""
        procedures = [self._referencing.of[name] for name in self._g74_axes]
        if any(procedure.state is State.IDLE for procedure in procedures):
            self.stop()  # aborted with an alarm: the program stops
            self._phase = Phase.CONTOUR_LOST
            return
        if all(procedure.state is State.DONE for procedure in procedures):
            self._phase = Phase.BLOCK_END
            self._block_end()

    # ------------------------------------------------------------------ outputs
    def write_status(self, alarm_present: bool, alarm_with_stop: bool) -> None:
        """Channel and program state and the alarm bits (written when they change)."""
        area, sig = self._area, self._signals
        state, program = self.state, self.program_state
        sig.running.put(area, program is ProgramState.RUNNING)
        sig.waiting.put(area, program is ProgramState.WAITING)
        sig.stopped.put(area, program is ProgramState.STOPPED)
        sig.interrupted.put(area, program is ProgramState.INTERRUPTED)
        sig.aborted.put(area, program is ProgramState.ABORTED)
        sig.state_active.put(area, state is ChannelState.ACTIVE)
        sig.state_interrupted.put(area, state is ChannelState.INTERRUPTED)
        sig.state_reset.put(area, state is ChannelState.RESET)
        sig.alarm_active.put(area, alarm_present)
        sig.alarm_with_stop.put(area, alarm_with_stop)
        sig.reference_active.put(area, self.reference_active)

    def write_axis_summary(self) -> None:
        """All axes referenced / all axes stationary (written when they change); spindles count
        as axes only in axis mode."""
        summary = (all(axis.referenced for axis in self._needs_reference),
                   all(axis.at_rest and abs(axis.velocity) <= axis.dyn.standstill_velocity for axis in self.axes
                       if not axis.is_spindle or axis.axis_mode))
        if summary != self._summary:
            self._summary = summary
            self._signals.all_referenced.put(self._area, summary[0])
            self._signals.all_stationary.put(self._area, summary[1])
