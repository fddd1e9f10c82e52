"""The drive's data sets and speed controller integrator as the PLC selects them:
DB31.DBX21.0-21.6 -> DBX93.0-93.6 (seed 003 §18.2, L38337-38361).

The seed prints the signals only; the procedure is the real drive's (SINAMICS with the 840D sl,
the control's list manual) [control]::

    STEADY ──DBX21.0-21.2 (drive data set) changes──▶ SWITCHING: the drive changes over
    STEADY ──DBX21.3-21.4 (motor data set) changes──▶ SWITCHING: the pulses cancelled
    SWITCHING ──the switchover time──▶ STEADY: DBX93.0-93.2 show the new drive data set
    SWITCHING ──the switchover time, a new motor──▶ WAIT_MOTOR: DBX93.3-93.4 show the new motor,
                                                   the pulses stay cancelled
    WAIT_MOTOR ──the PLC switched the motor's contactors: DBX21.5 "motor changeover done"──▶ STEADY:
                                                   the pulses come back

A drive data set changes over while the drive runs; a motor data set (a second motor, star / delta
of one) only without pulses: during the changeover the drive cancels them, the axis leaves position
control as with DBX21.7 taken away (DB31.DBX92.7 = 0, 21612 if it moved: the PLC changes the motor
of an axis at rest) and returns to it once the PLC confirms the motor with DBX21.5 (a PLC that holds
DBX21.5 at 1 gets the pulses back with the new motor at once).  The changeover ends with what the
PLC selects by then.  The drive answers the integrator disable DBX21.6 in DBX93.6 in the next cycle.

What a data set holds (motor and encoder data, the speed controller's parameters) and what the
integrator does to the speed controller are not modelled: the harness's drive is the lag of
MD32810 (vc/core/axis/position_loop.py) in every data set [INF].  The switchover time is 4 ms, two
of SINAMICS' 2 ms sampling cycles [INF].
"""

from __future__ import annotations

from enum import Enum

from interfaces.signal_groups import DriveDataSetRequest, DriveDataSetStatus
from vc.core.interface_map import SignalTable
from vc.core.state_machine import Instance, StateMachine, states, transitions

SWITCHOVER_TIME = 0.004  # s: the drive's data set changeover [INF]
DRIVE_DATA_SETS = 8  # DBX21.0-21.2: A..C, a 3-bit number
MOTOR_DATA_SETS = 4  # DBX21.3-21.4: A..B, a 2-bit number


class Changeover(Enum):
    STEADY = "the selected data sets act"
    SWITCHING = "the drive changes its data set over"
    WAIT_MOTOR = "the new motor is active, the pulses wait for the PLC's DBX21.5"


DRIVE_DATA_SET_STATES: StateMachine[DriveDataSets] = StateMachine(
    __name__, "drive.data_sets", "Drive and motor data set changeover (DB31.DBX21.0-21.5 / 93.0-93.4)",
    Instance.AXIS, states(*Changeover),
    transitions(("STEADY", "SWITCHING", "DBX21.0-21.2 or 21.3-21.4 changes"),
                ("SWITCHING", "STEADY", "the switchover time (a drive data set)"),
                ("SWITCHING", "WAIT_MOTOR", "the switchover time (a motor data set): the pulses stay cancelled"),
                ("WAIT_MOTOR", "STEADY", "DBX21.5 motor changeover done")),
    read=lambda drive: drive.state)


class DriveDataSets:
    """One axis's drive: its active data sets, the changeover, the integrator's answer."""

    def __init__(self, table: SignalTable, area: bytearray, dt: float):
        self._decode = table.codec(DriveDataSetRequest).decode
        self._encode = table.codec(DriveDataSetStatus).encode
        self._area = area
        self._switch_cycles = max(1, round(SWITCHOVER_TIME / dt))
        self._request = DriveDataSetRequest()
        self.state: Changeover = Changeover.STEADY
        self.drive_data_set = 0  # active: power-on with data set A
        self.motor_data_set = 0
        self.integrator_disabled = False
        self._integrator_pending = False
        self._remaining = 0  # cycles of the changeover still to go
        # the changeover under way changes the motor: its pulses are cancelled until the PLC confirms
        # the new motor (a plain attribute: the axis asks several times an IPO cycle)
        self.pulses_cancelled = False

    @property
    def busy(self) -> bool:
        """The drive has something to do in the coming cycles (the NCK ticks it only then)."""
        return self.state is not Changeover.STEADY or self._integrator_pending

    def decode(self) -> None:
        """The PLC changed its outputs."""
        self._decode(self._area, self._request)
        request = self._request
        self._integrator_pending = request.integrator_disable != self.integrator_disabled
        if self.state is Changeover.STEADY:
            self._start_if_selected()
        elif self.state is Changeover.WAIT_MOTOR and request.motor_changeover_done:
            self.pulses_cancelled = False
            self.state = Changeover.STEADY
            self._start_if_selected()

    def _start_if_selected(self) -> None:
        request = self._request
        motor = request.motor_data_set % MOTOR_DATA_SETS
        if request.drive_data_set % DRIVE_DATA_SETS == self.drive_data_set and motor == self.motor_data_set:
            return
        self.pulses_cancelled = motor != self.motor_data_set
        self._remaining = self._switch_cycles
        self.state = Changeover.SWITCHING

    def cycle(self) -> None:
        """One IPO cycle while busy: the integrator's answer, the changeover's time."""
        if self._integrator_pending:
            self._integrator_pending = False
            self.integrator_disabled = self._request.integrator_disable
            self.publish()
        if self.state is not Changeover.SWITCHING:
            return
        self._remaining -= 1
        if self._remaining > 0:
            return
        request = self._request
        self.drive_data_set = request.drive_data_set % DRIVE_DATA_SETS
        self.motor_data_set = request.motor_data_set % MOTOR_DATA_SETS
        self.publish()
        if self.pulses_cancelled and not request.motor_changeover_done:
            self.state = Changeover.WAIT_MOTOR
            return
        self.pulses_cancelled = False
        self.state = Changeover.STEADY
        self._start_if_selected()  # the PLC selected again meanwhile

    def publish(self) -> None:
        self._encode(self._area, DriveDataSetStatus(drive_data_set=self.drive_data_set,
                                                    motor_data_set=self.motor_data_set,
                                                    integrator_disabled=self.integrator_disabled))
