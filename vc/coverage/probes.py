"""Reading the states of a running NC's state machines, from outside, once per IPO cycle.

:func:`state_probes` builds one :class:`StateProbe` per instance of every state machine of
``vc.coverage.state_machines`` (the mode group, each channel, spindle and axis): a small function
that reads the state through the NC's public attributes, and the coverage it reports to.  Nothing
in the NC changes for it; a probe only reads.  :meth:`StateProbe.check` costs one read and one
comparison while the state stands, which is almost always.

Referencing is one state machine per variant: a procedure's variant is decided when it starts
(the first state after IDLE or DONE tells: P1 / P2 phases incremental, DC_SEARCH distance-coded,
TO_TARGET absolute, FOLLOW_UP follow-up mode) and kept until it ends.
"""

from __future__ import annotations

from collections.abc import Callable
from enum import Enum

from vc.config import md_dictionary as MD
from vc.core.axis.command_axis import CommandAxis
from vc.core.axis.encoder import DISTANCE_CODED_MODES
from vc.core.channel.channel import Channel
from vc.core.channel.program_run import Mode
from vc.core.nck.manual_retraction import ManualRetraction
from vc.core.nck.mode_group import ModeGroup
from vc.core.nck.nck import Nck
from vc.core.referencing.referencing import AxisReferencing
from vc.core.referencing.referencing import State as R
from vc.core.retraction.drive_esr import DriveEsr
from vc.core.retraction.esr import ChannelEsr
from vc.core.spindle.spindle import Spindle
from vc.coverage.data import CoverageData, FunctionCoverage

State = Enum | str


def _name(state: State) -> str:
    return state.name if isinstance(state, Enum) else state


class StateProbe:
    """One instance of a state machine: reads its state and reports what it enters."""

    __slots__ = ("function", "last", "read")

    def __init__(self, read: Callable[[], State], function: FunctionCoverage, instance: str):
        self.read = read
        self.function = function
        self.last = read()
        function.instances.add(instance)
        function.entered(_name(self.last))

    def check(self) -> None:
        state = self.read()
        if state is not self.last and state != self.last:
            self.function.took(_name(self.last), _name(state))
            self.last = state


class ReferencingProbe:
    """The referencing of one axis, recorded under the variant of each procedure (module docstring)."""

    __slots__ = ("data", "instance", "last", "referencing", "variant")

    def __init__(self, referencing: AxisReferencing, data: CoverageData, instance: str):
        self.referencing = referencing
        self.data = data
        self.instance = instance
        self.last = referencing.state
        self.variant = self._configured_variant()
        self._function().entered(self.last.name)

    def _function(self) -> FunctionCoverage:
        function = self.data.function(f"referencing.{self.variant}")
        function.instances.add(self.instance)
        return function

    def _configured_variant(self) -> str:
        encoder = self.referencing.encoder
        if encoder.mode in DISTANCE_CODED_MODES:
            return "distance_coded"
        if encoder.absolute:
            return "absolute"
        return "incremental_cam" if self.referencing.md.bool(MD.REFP_CAM_IS_ACTIVE) else "incremental_no_cam"

    def _variant_of_start(self, state: R) -> str:
        if state is R.FOLLOW_UP:
            return "follow_up"
        if state in (R.DC_SEARCH, R.DC_REVERSE, R.DC_BRAKE):
            return "distance_coded"
        if state is R.TO_TARGET or (state is R.DONE and self.referencing.encoder.absolute):
            return "absolute"
        if state in (R.P1_TO_CAM, R.P1_BRAKE, R.P2_LEAVE_CAM, R.P2_BRAKE_OFF_CAM, R.P2_RETURN_TO_CAM):
            return "incremental_cam"
        if state in (R.P2_ZERO_MARK, R.P3_STOP, R.P3_TO_POINT):
            return "incremental_cam" if self.referencing.md.bool(MD.REFP_CAM_IS_ACTIVE) else "incremental_no_cam"
        return self._configured_variant()

    def check(self) -> None:
        state = self.referencing.state
        if state is self.last:
            return
        before, self.last = self.last, state
        if before in (R.IDLE, R.DONE):
            self.variant = self._variant_of_start(state)
        self._function().took(before.name, state.name)


Probe = StateProbe | ReferencingProbe


def _mode_group_state(mode_group: ModeGroup) -> Callable[[], State]:
    """JOG, MDA, AUTO; JOG REF and MDA REF with the machine function REF."""
    names = {(mode, ref): f"{mode.value} REF" if ref else mode.value for mode in Mode for ref in (False, True)}
    return lambda: names[(mode_group.mode, mode_group.reference_function)]


def _gear_state(spindle: Spindle) -> Callable[[], State]:
    def read() -> State:
        state = spindle.gear_change.state
        return "NONE" if state is None else state
    return read


def _coupling_state(nck: Nck, spindle: str) -> Callable[[], State]:
    active = nck.couplings.active

    def read() -> State:
        coupling = active.get(spindle)
        return "UNCOUPLED" if coupling is None else coupling.phase
    return read


def _retract_state(esr: ChannelEsr) -> Callable[[], State]:
    return lambda: "IDLE" if esr.motion is None else "RETRACTING"


def _stop_state(nck: Nck, esr: ChannelEsr) -> Callable[[], State]:
    def read() -> State:
        deadlines = esr.stop_deadlines
        if deadlines is None:
            return "IDLE"
        return "RUNNING_ON" if nck.cycle < deadlines[0] else "BRAKING"
    return read


def _manual_retraction_state(retraction: ManualRetraction) -> Callable[[], State]:
    return lambda: "ACTIVE" if retraction.active else "NO_DATA" if retraction.data is None else "DATA"


def _channel_probes(nck: Nck, channel: Channel, data: CoverageData, instance: str) -> list[Probe]:
    probes: list[Probe] = [
        StateProbe(lambda: channel.state, data.function("channel"), instance),
        StateProbe(lambda: channel.program_state, data.function("program"), instance),
        StateProbe(_manual_retraction_state(nck.retractions[channel.name]), data.function("manual_retraction"),
                   instance),
    ]
    esr = channel.esr
    if esr is not None:
        probes.append(StateProbe(_retract_state(esr), data.function("esr.retract"), instance))
        probes.append(StateProbe(_stop_state(nck, esr), data.function("esr.stop"), instance))
    machine = instance.rpartition("/")[0]
    for name, command in channel.command_axes.by_name.items():
        def command_state(command: CommandAxis = command) -> State:
            return command.state
        probes.append(StateProbe(command_state, data.function("command_axis"), f"{machine}/{name}"))
    return probes


def state_probes(nck: Nck, data: CoverageData, machine: str) -> list[Probe]:
    """A probe for every instance of every state machine of ``nck`` (a power-on of ``machine``)."""
    mode_group = nck.mode_group
    probes: list[Probe] = [StateProbe(_mode_group_state(mode_group), data.function("mode_group"),
                                      f"{machine}/MODEGROUP")]
    for channel in nck.channels:
        probes.extend(_channel_probes(nck, channel, data, f"{machine}/{channel.name}"))
    for spindle in nck.spindles:
        instance = f"{machine}/{spindle.name}"

        def mode(spindle: Spindle = spindle) -> State:
            return spindle.mode
        probes.append(StateProbe(mode, data.function("spindle_mode"), instance))
        probes.append(StateProbe(_gear_state(spindle), data.function("gear_change"), instance))
        probes.append(StateProbe(_coupling_state(nck, spindle.name), data.function("coupling"), instance))
    for axis in nck.axes:
        instance = f"{machine}/{axis.name}"
        def reaction(drive: DriveEsr = nck.esr.drives[axis.name]) -> State:
            return drive.reaction
        probes.append(StateProbe(reaction, data.function("esr.drive"), instance))
        if not axis.is_spindle:
            probes.append(ReferencingProbe(nck.referencing.of[axis.name], data, instance))
    return probes
