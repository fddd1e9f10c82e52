"""The NCK's own signals, declared once: DB10 (seed 003, spec B.1) and what it reads of DB19.

:class:`NckInputs` is what the PLC gives the NCK (the emergency stop, its acknowledgement and the
NC's digital inputs $A_IN), decoded when DB10 changed; :class:`NckStatus` is what the NCK shows the
PLC, written with the other status signals.  The NC reads one bit of the operator panel's DB19:
which coordinates the keys traverse in (:data:`DISPLAY_WCS`).
"""

from __future__ import annotations

from dataclasses import dataclass

from interfaces.signal_group import signal

DISPLAY_WCS = "basic.out.displayWcsValues"  # DB19.DBX0.7: 1 WCS, 0 MCS


@dataclass(slots=True)
class NckInputs:
    emergency_stop: bool = signal("basic.out.emergencyStop")  # DB10.DBX56.1
    emergency_stop_ack: bool = signal("basic.out.emergencyStopAck")  # DB10.DBX56.2
    digital_inputs: int = signal("basic.out.setDigitalInputs", 0)  # $A_IN[1..8]


@dataclass(frozen=True, slots=True)
class NckStatus:
    emergency_stop_active: bool = signal("basic.in.emergencyStopActive")
    nc_ready: bool = signal("basic.in.ncReady")
    alarm_active: bool = signal("basic.in.alarmActive")
