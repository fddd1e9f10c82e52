"""A channel: NC start / stop / reset and the program run block by block, with its DB21 signals.

Channel and program states (DB21.DBX35.x), ``program_run.py``::

    RESET / aborted ──NC start (AUTO: selected program, MDA: MDA buffer)──▶ ACTIVE / running
    ACTIVE / running ──NC stop, M0, alarm with interrupt──▶ INTERRUPTED / stopped
    INTERRUPTED / stopped ──mode change (e.g. to JOG)──▶ INTERRUPTED / interrupted
    INTERRUPTED ──NC start (in the mode the program was started in)──▶ ACTIVE / running
    any ──reset, M2, M30──▶ RESET / aborted

The :class:`Channel` takes the commands (NC start, NC stop, reset, mode change) and runs one IPO
cycle of its program; its parts, each in a module of its own, share one :class:`ProgramRun`:

``interface``            the DB21 signals: the PLC's requests and their edges, the states written back
``block_execution``      the block plan turned into motion, dwell, G74, block change, program end
``spindle_functions``    the blocks' spindle, coupling and polygon commands, their interlocks, and
                         ``cutting_speed`` (G96 / G961: the master spindle's speed from the radius)
``thread_retract``       G33, fast retraction (LFON) and the channel's side of ESR
``stroke_limit_path``    stored stroke limits 2 and 3 on the paths and in JOG
``channel_referencing``  channel-specific referencing (DB21.DBX1.0, MD34110 order)

Beside the program it keeps its command axes (``vc/core/axis/command_axis.py``): axes a
synchronized action moves on their own, which NC stop and program end leave alone and its reset stops;
the same axis interpolators move the program's positioning axes (POS / POSA), which NC stop holds,
and the PLC's axes (``vc/core/axis/plc_axis.py``: FC18, DB31.DBX28.7).

The channel owns its auxiliary function output (``vc/core/auxiliary``: the DB21 output slots, the
tool the program selects), which block execution fills and the NCK tells of the PLC's cycles.

NC stop goes through :meth:`Channel.stop` from every part: in G33 with LFON it lifts the tool.
"""

from __future__ import annotations

from vc.config import md_dictionary as MD
from vc.config.model import ChannelConfig
from vc.core.alarms import CHANNEL_INTERRUPT, NC_START_DISABLED, STOP_AXES, AlarmList, Clear
from vc.core.auxiliary.output import AuxiliaryOutput
from vc.core.auxiliary.tool_selection import ToolSelection
from vc.core.axis.axis import MachineAxis
from vc.core.axis.command_axis import CommandAxes
from vc.core.axis.jog import JogLimits
from vc.core.axis.owner import Owner
from vc.core.axis.plc_axis import PlcAxes
from vc.core.axis.stroke_limits import StrokeLimitControl
from vc.core.channel.block_execution import BlockExecution
from vc.core.channel.channel_referencing import ChannelReferencing
from vc.core.channel.cutting_speed import ConstantCuttingSpeed
from vc.core.channel.dry_run import DryRunFeed
from vc.core.channel.interface import ChannelInterface
from vc.core.channel.program_run import BlockPhase, ChannelState, Mode, ProgramRun, ProgramState
from vc.core.channel.referencing_control import ReferencingControl
from vc.core.channel.spindle_functions import SpindleFunctions
from vc.core.channel.stroke_limit_path import ChannelStrokeLimits
from vc.core.channel.thread_retract import ThreadRetract
from vc.core.fixed_stop.channel_fixed_stops import ChannelFixedStops
from vc.core.interface_map import SignalTable
from vc.core.interpolation.thread_cutting import ThreadSegment
from vc.core.overrides import OverrideCoding
from vc.core.program.block_plan import BlockPlan, ModalState
from vc.core.program.program import Block, parse_program
from vc.core.program.sync_actions import FIXED_STOP_WORDS, VariableWrite
from vc.core.retraction.esr import ChannelEsr
from vc.core.spindle.coupling import Couplings
from vc.core.spindle.polygon import PolygonTurning
from vc.core.spindle.spindle import Spindle
from vc.core.transforms.five_axis_control import FiveAxisControl
from vc.core.transforms.inclined_axis_control import InclinedAxisControl


class Channel:
    def __init__(
        self,
        config: ChannelConfig,
        table: SignalTable,
        area: bytearray,
        axes: list[MachineAxis],
        alarms: AlarmList,
        feed_coding: OverrideCoding,
        rapid_coding: OverrideCoding,
        dt: float,
        referencing: ReferencingControl,
        permanent_feeds: tuple[float, ...] = (),
    ):
        self.config = config
        self.name = config.name
        self.area_key = f"DB{config.db}"
        self.axes = axes
        self.axes_by_name = {axis.name: axis for axis in axes}
        self.five_axis = FiveAxisControl(config, self.axes_by_name)  # G43.4, G43, G68.2, G53.1 (seed 001)
        self.stroke_limits = StrokeLimitControl(self.axes_by_name,  # G22 / G23, stroke limit 3 (seed 000)
                                                not config.md.bool(MD.STROKE2_OUTSIDE_FORBIDDEN))
        self._alarms = alarms
        self._interface = ChannelInterface(table, area, feed_coding, rapid_coding)
        self.aux = AuxiliaryOutput(table, area)  # the M, S, T, D, DL, H and F functions to the PLC
        self.tools = ToolSelection(config.md)
        self.inputs = self._interface.inputs
        self.edges = self._interface.edges
        self.run = ProgramRun()
        self.mda_text = ""
        self.selected_program: tuple[str, str] | None = None
        self._needs_reference = [
            axis for axis in axes
            if not axis.is_spindle and axis.config.md.int(MD.REFP_CYCLE_NR) != -1
        ]
        geometry = set(axis for axis in config.geometry_axes if axis)
        self._stroke = ChannelStrokeLimits(self.name, self.stroke_limits, geometry, alarms)
        self._channel_referencing = ChannelReferencing(self.name, axes, referencing, alarms)
        self._spindles = SpindleFunctions(config, self.axes_by_name, self.inputs, alarms, self.stop)
        self._threads = ThreadRetract(self.run, config, axes, self.axes_by_name, self._spindles, alarms, dt, self.stop)
        self.fixed_stops = ChannelFixedStops(self.name, alarms)  # travel to fixed stop, filled at power-on
        # POS[ax]= of synchronized actions, POS / POSA of the program: the axis interpolators
        self.command_axes = CommandAxes(self.name, axes, alarms, dt)
        self.plc_axes = PlcAxes()  # FC18 and DB31.DBX28.7 (vc/core/axis/plc_axis.py), filled at power-on
        self.dry_run = DryRunFeed(config.md, table, area)  # the dry-run feed, DB21.DBX0.6 -> 318.6
        self._execution = BlockExecution(self.run, config, axes, self.axes_by_name, self.inputs, alarms, dt,
                                         referencing, self.five_axis, self._stroke, self._spindles, self._threads,
                                         self.stop, self.aux, self.tools, self.fixed_stops, self.command_axes,
                                         self.plc_axes, self.dry_run, permanent_feeds)
        self._inclined: InclinedAxisControl | None = None
        self._revolution_feed_shown = False  # DB21.DBX33.2 as written
        self.transverse_axis = config.transverse_axis()  # MD20100: diameter programming, G96's radius

    # ------------------------------------------------------------------ what the NCK gives the channel
    @property
    def inclined(self) -> InclinedAxisControl | None:
        """The inclined-axis control (seed 000), given by the NCK."""
        return self._inclined

    @inclined.setter
    def inclined(self, control: InclinedAxisControl | None) -> None:
        self._inclined = control
        self._stroke.inclined = control
        self._threads.inclined = control
        self._execution.inclined = control

    @property
    def esr(self) -> ChannelEsr | None:
        """Fast retraction and ESR, given by the NCK."""
        return self._threads.esr

    @esr.setter
    def esr(self, esr: ChannelEsr | None) -> None:
        self._threads.esr = esr

    @property
    def spindles(self) -> dict[str, Spindle]:
        """Machine axis -> spindle, filled by the NCK."""
        return self._spindles.spindles

    @property
    def couplings(self) -> Couplings | None:
        return self._spindles.couplings

    @couplings.setter
    def couplings(self, couplings: Couplings | None) -> None:
        self._spindles.couplings = couplings

    @property
    def polygon(self) -> PolygonTurning | None:
        return self._spindles.polygon

    @polygon.setter
    def polygon(self, polygon: PolygonTurning | None) -> None:
        self._spindles.polygon = polygon

    # ------------------------------------------------------------------ state
    @property
    def state(self) -> ChannelState:
        return self.run.state

    @property
    def program_state(self) -> ProgramState:
        return self.run.program_state

    @property
    def modal(self) -> ModalState:
        return self.run.modal

    @property
    def started_in(self) -> Mode | None:
        return self.run.started_in

    @property
    def current_block(self) -> Block | None:
        return self.run.current_block

    @property
    def is_active(self) -> bool:
        return self.run.state is ChannelState.ACTIVE

    @property
    def block_in_progress(self) -> BlockPlan | None:
        """The block being executed, also while the program is stopped in it (None in reset)."""
        return self.run.plan if self.run.state is not ChannelState.RESET else None

    @property
    def thread_in_progress(self) -> ThreadSegment | None:
        """The G33 block's thread while it runs."""
        return self._threads.thread_segment

    def shown_position(self, axis: str, position: float) -> float:
        """A position as the channel shows it in program coordinates: the transverse axis in diameter
        under DIAMON and DIAM90 (seed 003 L10360-10396)."""
        if axis == self.transverse_axis and self.run.modal.diameter != "DIAMOF":
            return 2.0 * position
        return position

    @property
    def cutting_speed(self) -> ConstantCuttingSpeed:
        """G96 / G961 of the channel (``cutting_speed.py``)."""
        return self._spindles.cutting_speed

    @property
    def esr_run_on_spindle(self) -> str | None:
        """The master spindle of a thread in the ESR's MD21380."""
        return self._threads.esr_run_on_spindle

    # ------------------------------------------------------------------ inputs
    def decode_inputs(self) -> None:
        self._interface.decode_inputs()
        if self.run.state is not ChannelState.ACTIVE:
            self.dry_run.take(self.inputs.dry_run)  # no block runs: the selection is taken at once (L9434-9442)

    def clear_edges(self) -> None:
        self._interface.clear_edges()

    # ------------------------------------------------------------------ commands
    def reset(self, cycle: int) -> None:
        """Channel or mode-group reset: abort the program, brake, clear reset alarms."""
        run = self.run
        self._alarms.clear_on((Clear.RESET, Clear.CANCEL), channel=self.name)
        if run.segment is not None and not run.segment.finished:
            run.aborting = True
        self._threads.end_thread_functions()
        run.end()
        if self._inclined is not None:
            self._inclined.reset()
        self._execution.stroke_stop = None
        self._channel_referencing.cancel()
        for axis in self.axes:
            if axis.owner is Owner.JOG:
                axis.brake()
            if axis.at_software_limit:
                self._alarms.clear(10621, axis=axis.name)  # its monitor only clears what it still sees
            axis.at_software_limit = 0
        self._spindles.reset_couplings()
        self._spindles.reset_spindles(program_end=False)
        self.command_axes.reset()
        self.plc_axes.reset()
        self.aux.reset()
        self.fixed_stops.reset()

    def nc_start(self, cycle: int, mode: Mode, reference_function: bool) -> None:
        """NC start edge from the PLC."""
        inp, run = self.inputs, self.run
        if inp.nc_start_disable or inp.nc_stop or inp.nc_stop_all or inp.reset:
            return
        if self._alarms.reactions(self.name) & NC_START_DISABLED:
            return
        self.plc_axes.start()  # NC start lets a PLC axis held by NC stop go on (L12320-12330)
        if mode is Mode.JOG or reference_function:
            return
        if run.state is ChannelState.INTERRUPTED:
            if run.started_in is mode and run.phase is not BlockPhase.CONTOUR_LOST:
                run.state = ChannelState.ACTIVE
                run.program_state = ProgramState.RUNNING
                run.stopping = False
                if self.aux.stopped_at_m0:
                    self.aux.stopped_at_m0 = False  # DB21.DBX32.5: the program goes on after M0 / M1
                    self.aux.show_stop()
            return
        if run.state is not ChannelState.RESET:
            return
        if not self._references_allow_start(cycle, mode):
            return
        text = self.mda_text if mode is Mode.MDA else (self.selected_program[1] if self.selected_program else "")
        run.blocks = parse_program(text)
        run.block_index = 0
        run.leaving_thread_chain = False
        run.phase = BlockPhase.DECODE
        run.modal.reset()
        self._spindles.program_start(run.modal)
        run.started_in = mode
        run.state = ChannelState.ACTIVE
        run.program_state = ProgramState.RUNNING
        if self.aux.ended_with_m30:
            self.aux.ended_with_m30 = False  # DB21.DBX33.5: a new program run
            self.aux.show_stop()

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
        run = self.run
        if run.state is ChannelState.ACTIVE and self._threads.thread_segment is not None and run.modal.retract.enabled:
            self._threads.lift_fast(None)
        run.interrupt()
        self.plc_axes.stop()

    def mode_changed(self) -> None:
        """Leaving the mode of a stopped program interrupts it (DB21.DBX35.3)."""
        if self.run.state is ChannelState.INTERRUPTED:
            self.run.program_state = ProgramState.INTERRUPTED

    def esr_trigger(self, cycle: int) -> None:
        """React to a rising $AC_ESR_TRIGGER: fast retraction in G33 with LFON, else the ESR reaction."""
        self._threads.esr_trigger(cycle)

    # ------------------------------------------------------------------ cycle
    def program_cycle(self, cycle: int) -> None:
        """Interpolation and block change for one IPO cycle, then the feed type it leaves."""
        self._run_program(cycle)
        if self.run.modal.per_revolution is not self._revolution_feed_shown:
            self._revolution_feed_shown = self.run.modal.per_revolution
            self._interface.write_feed_type(self._revolution_feed_shown)  # DB21.DBX33.2: G95 / G96 / G97

    def _run_program(self, cycle: int) -> None:
        if self._channel_referencing.groups:
            self._channel_referencing.cycle(cycle)
        path_runs_on = self._threads.esr_cycle(cycle)
        run = self.run
        if self.plc_axes.active:
            if self.edges.delete_distance_to_go:
                self.plc_axes.delete_distance_to_go()  # DB21.DBX6.2 ends their motions (L11339-11343)
            # the PLC's requests and FC18 jobs, before the axis interpolators run (L12145-12565)
            self.plc_axes.cycle(self.inputs.feed_disable, bool(self._alarms.reactions(self.name) & STOP_AXES))
        if self.command_axes.active:
            # a command axis independent of the program's state (L11215-11227); a positioning axis of
            # the program held by NC stop, a stopping alarm and the feed disable (L11044-11066)
            self.command_axes.cycle(run.state is not ChannelState.ACTIVE or self.inputs.feed_disable
                                    or bool(self._alarms.reactions(self.name) & STOP_AXES),
                                    self.inputs.feed_override == 0.0)
        reactions = self._alarms.reactions(self.name)
        if reactions & CHANNEL_INTERRUPT and run.state is ChannelState.ACTIVE:
            self.stop()
        if run.aborting:
            self._execution.brake_segment()
            return
        if run.state is ChannelState.RESET:
            return
        hold = (run.state is not ChannelState.ACTIVE or bool(reactions & STOP_AXES)) and not path_runs_on
        if self.edges.delete_distance_to_go:
            self._execution.delete_distance_to_go()  # DB21.DBX6.2
        self._execution.cycle(hold, cycle)
        if self._spindles.cutting_speed.following:
            self._spindles.cutting_speed.cycle()  # G96 / G961: the speed of the transverse axis's new position

    # ------------------------------------------------------------------ spindles and couplings
    def master_spindle(self) -> str | None:
        return self._spindles.master_spindle()

    def spindle_indices(self) -> dict[str, str]:
        """How a program names this channel's spindles as a variable's index: S<n> (MD35000) or the
        machine axis name."""
        return self._spindles.spindle_indices()

    def write_other_variable(self, write: VariableWrite, cycle: int) -> None:
        """``$AA_COUP_CORR[Sn]=...`` of a program or a synchronized action, or a synchronized action's
        ``FXS[ax]=`` / ``FXST[ax]=`` / ``FXSW[ax]=`` (index: the machine axis)."""
        if write.name in FIXED_STOP_WORDS:
            self.fixed_stops.write(write, cycle)
        else:
            self._spindles.write_coupling_variable(write)

    # ------------------------------------------------------------------ stored stroke limits 2 and 3
    def stroke_jog_limits(self, axis: MachineAxis, cycle: int) -> JogLimits:
        """JOG stops on the boundary of stored stroke limits 2 and 3 (``stroke_limit_path.py``)."""
        return self._stroke.jog_limits(axis, cycle)

    # ------------------------------------------------------------------ referencing
    @property
    def reference_active(self) -> bool:
        return self._channel_referencing.active

    def start_channel_referencing(self, cycle: int) -> None:
        """DB21.DBX1.0: reference the channel's axes in the order of MD34110 (seed 003 L667-683)."""
        if self.run.state is not ChannelState.RESET:
            return
        self._channel_referencing.start()

    # ------------------------------------------------------------------ outputs
    def write_status(self, alarm_present: bool, alarm_with_stop: bool) -> None:
        """Channel and program state and the alarm bits (written when they change)."""
        self._interface.write_status(self.run, self.reference_active, alarm_present, alarm_with_stop)

    def write_axis_summary(self) -> None:
        """All axes referenced / all axes stationary (written when they change); spindles count
        as axes only in axis mode."""
        axes = self.axes
        if self.plc_axes.any_left_out:  # MD30460 bit 7 (L12199-12213)
            axes = [axis for axis in axes if not self.plc_axes.left_out(axis.name)]
        self._interface.write_axis_summary(axes, self._needs_reference)
