"""The channel's DB21 interface: the PLC's requests read every cycle, the states written back.

:meth:`ChannelInterface.decode_inputs` reads the PLC -> NC signals into :class:`ChannelInputs` and
their rising edges into :class:`Edges` (NC start, NC stop, reset, delete distance-to-go, channel
referencing); :meth:`ChannelInterface.write_status` and :meth:`ChannelInterface.write_axis_summary`
write the channel and program state (DB21.DBX35.x), the alarm bits and the axis summary.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from vc.core.axis.axis import MachineAxis
from vc.core.channel.program_run import ChannelState, ProgramRun, ProgramState
from vc.core.interface_map import SignalTable
from vc.core.overrides import OverrideCoding


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


class ChannelInterface:
    def __init__(self, signals: ChannelSignals, area: bytearray, feed_coding: OverrideCoding,
                 rapid_coding: OverrideCoding):
        self._signals = signals
        self._area = area
        self._feed_coding = feed_coding
        self._rapid_coding = rapid_coding
        self.inputs = ChannelInputs()
        self.edges = Edges()
        self._summary: tuple[bool, bool] | None = None

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

    def write_status(self, run: ProgramRun, reference_active: bool, alarm_present: bool, alarm_with_stop: bool) -> None:
        """Channel and program state and the alarm bits (written when they change)."""
        area, sig = self._area, self._signals
        state, program = run.state, run.program_state
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
        sig.reference_active.put(area, reference_active)

    def write_axis_summary(self, axes: Sequence[MachineAxis], needs_reference: Sequence[MachineAxis]) -> None:
        """All axes referenced / all axes stationary (written when they change); spindles count
        as axes only in axis mode."""
        summary = (all(axis.referenced for axis in needs_reference),
                   all(axis.at_rest and abs(axis.velocity) <= axis.dyn.standstill_velocity for axis in axes
                       if not axis.is_spindle or axis.axis_mode))
        if summary != self._summary:
            self._summary = summary
            self._signals.all_referenced.put(self._area, summary[0])
            self._signals.all_stationary.put(self._area, summary[1])
