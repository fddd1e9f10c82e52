"""The channel's DB21 interface: the PLC's requests read every cycle, the states written back.

:meth:`ChannelInterface.decode_inputs` reads the PLC -> NC signals into :class:`ChannelInputs` and
their rising edges into :class:`Edges` (NC start, NC stop, reset, delete distance-to-go, channel
referencing); :meth:`ChannelInterface.write_status` and :meth:`ChannelInterface.write_axis_summary`
write the channel and program state (DB21.DBX35.x), the alarm bits and the axis summary.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from interfaces.signal_groups import AxisSummary, ChannelRequests, ChannelStatus, FeedTypeStatus
from vc.core.axis.axis import MachineAxis
from vc.core.channel.program_run import ChannelState, ProgramRun, ProgramState
from vc.core.interface_map import SignalTable
from vc.core.overrides import OverrideCoding


@dataclass(slots=True)
class ChannelInputs(ChannelRequests):
    """The PLC-to-NC signals of a channel, and the override factors they give."""

    feed_override: float = 1.0  # the factors of the override switches, through their coding
    rapid_override: float = 1.0


@dataclass(slots=True)
class Edges:
    nc_start: bool = False
    nc_stop: bool = False
    reset: bool = False
    delete_distance_to_go: bool = False
    reference_start: bool = False


class ChannelInterface:
    def __init__(self, table: SignalTable, area: bytearray, feed_coding: OverrideCoding,
                 rapid_coding: OverrideCoding):
        self._decode = table.codec(ChannelInputs).decode
        self._encode_status = table.codec(ChannelStatus).encode
        self._encode_summary = table.codec(AxisSummary).encode
        self._encode_feed_type = table.codec(FeedTypeStatus).encode
        self._area = area
        self._feed_coding = feed_coding
        self._rapid_coding = rapid_coding
        self.inputs = ChannelInputs()
        self.edges = Edges()
        self._summary: tuple[bool, bool] | None = None

    def decode_inputs(self) -> None:
        inp, edges = self.inputs, self.edges
        before = (inp.nc_start, inp.nc_stop, inp.nc_stop_all, inp.reset, inp.delete_distance_to_go,
                  inp.reference_start)
        self._decode(self._area, inp)
        nc_start, nc_stop, nc_stop_all, reset, delete, reference_start = before
        edges.reference_start = inp.reference_start and not reference_start
        edges.nc_start = inp.nc_start and not nc_start
        edges.nc_stop = (inp.nc_stop and not nc_stop) or (inp.nc_stop_all and not nc_stop_all)
        edges.reset = inp.reset and not reset
        edges.delete_distance_to_go = inp.delete_distance_to_go and not delete
        inp.feed_override = self._feed_coding.factor(inp.feed_override_raw, inp.feed_override_active)
        inp.rapid_override = self._rapid_coding.factor(inp.rapid_override_raw, inp.rapid_override_active)

    def clear_edges(self) -> None:
        edges = self.edges
        edges.nc_start = edges.nc_stop = edges.reset = edges.delete_distance_to_go = edges.reference_start = False

    def write_status(self, run: ProgramRun, reference_active: bool, alarm_present: bool, alarm_with_stop: bool) -> None:
        """Channel and program state and the alarm bits (written when they change)."""
        state, program = run.state, run.program_state
        self._encode_status(self._area, ChannelStatus(
            running=program is ProgramState.RUNNING, waiting=program is ProgramState.WAITING,
            stopped=program is ProgramState.STOPPED, interrupted=program is ProgramState.INTERRUPTED,
            aborted=program is ProgramState.ABORTED, state_active=state is ChannelState.ACTIVE,
            state_interrupted=state is ChannelState.INTERRUPTED, state_reset=state is ChannelState.RESET,
            alarm_active=alarm_present, alarm_with_stop=alarm_with_stop, reference_active=reference_active))

    def write_feed_type(self, revolution_feed: bool) -> None:
        """DB21.DBX33.2: F per revolution (G95, G96, G97) in the channel's modal state (L7640-7651)."""
        self._encode_feed_type(self._area, FeedTypeStatus(revolution_feed=revolution_feed))

    def write_axis_summary(self, axes: Sequence[MachineAxis], needs_reference: Sequence[MachineAxis]) -> None:
        """All axes referenced / all axes stationary (written when they change); spindles count
        as axes only in axis mode."""
        all_referenced = all(axis.referenced for axis in needs_reference)
        all_stationary = all(axis.at_rest and abs(axis.velocity) <= axis.dyn.standstill_velocity for axis in axes
                             if not axis.is_spindle or axis.axis_mode)
        summary = (all_referenced, all_stationary)
        if summary != self._summary:
            self._summary = summary
            self._encode_summary(self._area, AxisSummary(all_referenced=all_referenced, all_stationary=all_stationary))
