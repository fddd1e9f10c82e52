"""Setpoint switchover: one drive, several machine axes, one of them in control of it at a time
(seed 003 chapter 18, L38125-38453), e.g. a milling head's motor turning the tool or swivelling
the head through a mechanical changeover (figure 18-1).

The axes whose MD30110 CTRLOUT_MODULE_NR names the same drive share it (L38196-38202).  The PLC
requests the drive's control for one of them with DB31.DBX24.5, the NC shows which one has it in
DB31.DBX96.5 (L38226-38236)::

    STEADY ──exactly one axis requests the control, not the one that has it──▶ REQUESTED
    REQUESTED ──every axis of the drive at rest, none at a fixed stop or referencing──▶ STEADY:
               the control passes (96.5), the controller enables of both cancelled meanwhile
    REQUESTED ──the request withdrawn, or several axes request at once──▶ STEADY: the control
               stays with the axis that had it (L38303-38306)

At power-on the first axis of the drive (in machine axis order) has the control (L38308-38320).
Only the axis with the control is position controlled: the others run in follow-up, their
controller enable DBX2.1 does not act (L38157-38162, L38278-38290) - the seed prints
"followUpModeActive == 0" (L38290) where the real control shows 1 [DOC-ERR].  A switchover
refused for its conditions (an axis moving, L38137-38153) shows no message (L38452-38453): the
request waits until they are met.  The drive's status signals of the axes without the control are
not mirrored from the one with it (L38238-38255) [INF: each axis's DB31 shows its own drive's model],
nor do their drive control signals (DBX20.x, 21.x) wait for the control.
"""

from __future__ import annotations

from enum import Enum
from typing import TYPE_CHECKING

from interfaces.signal_groups import SetpointSwitchoverRequest, SetpointSwitchoverStatus
from vc.core.axis.owner import Owner
from vc.core.interface_map import SignalTable
from vc.core.state_machine import Instance, StateMachine, states, transitions

if TYPE_CHECKING:
    from vc.core.axis.axis import MachineAxis


class Switchover(Enum):
    STEADY = "one axis has the drive's control"
    REQUESTED = "another axis requests the control: waiting for every axis of the drive at rest"


SETPOINT_SWITCHOVER_STATES: StateMachine[SharedDrive] = StateMachine(
    __name__, "drive.setpoint_switchover", "Setpoint switchover of a shared drive (DB31.DBX24.5 / 96.5)",
    Instance.AXIS, states(*Switchover),
    transitions(("STEADY", "REQUESTED", "exactly one other axis requests the control (DBX24.5)"),
                ("REQUESTED", "STEADY", "every axis at rest: the control passes (DBX96.5); or the request"
                                        " withdrawn, several at once: the control stays")),
    read=lambda drive: drive.state)


class SharedDrive:
    """The axes of one drive (equal MD30110) and which of them has its control."""

    def __init__(self, number: int, axes: list[MachineAxis], table: SignalTable, areas: list[bytearray]):
        self.number = number
        self.axes = axes
        self._decode = table.codec(SetpointSwitchoverRequest).decode
        self._encode = table.codec(SetpointSwitchoverStatus).encode
        self._areas = areas
        self._requests = [SetpointSwitchoverRequest() for _ in axes]
        self.state: Switchover = Switchover.STEADY
        self.holder = axes[0]  # power-on without a request: the first axis of the drive (L38308-38320)
        self._requested: MachineAxis | None = None
        for axis in axes:
            axis.drive_control = axis is self.holder
        self.publish()

    @property
    def busy(self) -> bool:
        """A request waits for its conditions (the NCK ticks the drive only then)."""
        return self.state is Switchover.REQUESTED

    def decode(self) -> None:
        """The PLC changed an output of one of the drive's axes."""
        for request, area in zip(self._requests, self._areas, strict=True):
            self._decode(area, request)
        asking = [axis for axis, request in zip(self.axes, self._requests, strict=True) if request.request]
        if len(asking) == 1 and asking[0] is not self.holder:
            self._requested = asking[0]
            self.state = Switchover.REQUESTED
        else:
            self._requested = None  # none or several: the control stays (L38303-38306)
            self.state = Switchover.STEADY

    def cycle(self) -> None:
        """While a request waits: switch over once every axis of the drive is at rest."""
        new = self._requested
        if new is None or not all(self._at_rest(axis) for axis in self.axes):
            return
        old = self.holder
        old.drive_control = False
        new.drive_control = True
        old.resting = new.resting = False
        self.holder = new
        self._requested = None
        self.state = Switchover.STEADY
        self.publish()

    @staticmethod
    def _at_rest(axis: MachineAxis) -> bool:
        """At standstill and in none of the functions the switchover excludes (L38137-38153): the
        harness checks the motion, travel to fixed stop and referencing.  A program block that waits for
        the axis (it has no control yet) does not move it: the switchover may take place under it."""
        return axis.owner is not Owner.REF and axis.command_velocity == 0.0 \
            and abs(axis.velocity) <= axis.dyn.standstill_velocity and axis.torque_limit is None

    def publish(self) -> None:
        for axis, area in zip(self.axes, self._areas, strict=True):
            self._encode(area, SetpointSwitchoverStatus(active=axis is self.holder))

    @staticmethod
    def declare(table: SignalTable) -> None:
        """Every axis has the signals; an axis with a drive of its own shows DBX96.5 = 0 [INF]."""
        table.codec(SetpointSwitchoverRequest)
        table.codec(SetpointSwitchoverStatus)
