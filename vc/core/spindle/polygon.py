"""Polygon turning G51.2 / G50.2 (seed 002, GSK980TDi) on the coupling engine.

The workpiece spindle is the master (MD62900, GSK parameter 0197), the driven tool the slave
(MD62901, 0198); the seed's parameter table calls them the other way round, its definitions
(L15-17, L55-57) hold here.  ``G51.2 P Q`` couples the slave to the master with the ratio
``n_slave = n_master x Q / P`` (L63-65): Q > 0 turns the slave with the master, Q < 0 against it
(L33-37).  R shifts the relation by R degrees of master angle before the synchronisation
(relative, L21-51: the slave is set back by Q/P x R, which is the same relation as the master
turning R first) [INF]; A couples the geometry Z axis with A mm per master revolution (a lead,
right-hand for A > 0, L49).  The master's S is signed while synchronous (the interpreter).

Synchronisation follows the master from the start: interpolation mode (0201 SNTP = 0) couples
to the master's setpoint (DV), follow mode (SNTP = 1) to its actual position (AV, the master may
be a spindle with only an encoder, L9-19).  While synchronous: master and slave take no other
command than the master's speed and direction (alarm 65843, L128-131); G51.2 again resynchronises
with the new P/Q if ECN = 1, else alarm 65841 (L67-69); reset ends it unless HBR = 1; the
emergency stop ends it; program and user alarms keep it, other alarms end it (L134-138).
G50.2 ends it and the helix axis's travel becomes part of its programmed position (L77-81).
"""

from __future__ import annotations

from vc.config import md_dictionary as MD
from vc.config.model import ChannelConfig
from vc.core.alarms import Alarm, Reaction
from vc.core.axis.axis import MachineAxis
from vc.core.program.commands import BlockChange, Kind, PolygonCommand
from vc.core.spindle.coupling import Couplings
from vc.core.spindle.spindle import RPM, Spindle

ALARM_NOT_AVAILABLE = 12550  # no master / slave configured: the function is not available
ALARM_RESYNC_NOT_ALLOWED = 65841
ALARM_AXIS_SYNCHRONISED = 65843
ERV, HBR, ECN, SNTP = 1 << 2, 1 << 3, 1 << 4, 1 << 7  # bits of parameter 0201 (spec 7.3 [INF])


def keeps_synchronism(alarm: Alarm) -> bool:
    """Program alarms (the NC program's 10000..19999) and user alarms (60000..69999) keep the
    synchronisation; every other alarm ends it (seed 002 L136-137) [INF: the SINUMERIK number
    ranges stand for the GSK alarm classes].  A warning without any reaction (22040, coupled
    without zero mark) keeps it too: the GSK control has no such alarm to end it with [INF]."""
    return 10000 <= alarm.number < 20000 or 60000 <= alarm.number < 70000 or alarm.reaction is Reaction.NONE


class PolygonTurning:
    """G51.2 / G50.2 of one channel."""

    def __init__(self, channel: ChannelConfig, couplings: Couplings, spindles: dict[str, Spindle],
                 axes: dict[str, MachineAxis]):
        self._channel = channel
        self._couplings = couplings
        md = channel.md
        master, slave = md.int(MD.POLYGON_MASTER_AXIS), md.int(MD.POLYGON_SLAVE_AXIS)
        names = channel.axes
        self.master = names[master - 1] if 0 < master <= len(names) and names[master - 1] in spindles else ""
        self.slave = names[slave - 1] if 0 < slave <= len(names) and names[slave - 1] in spindles else ""
        self._spindles = spindles
        helix_axis = channel.geometry_axes[2] if len(channel.geometry_axes) > 2 else ""
        self._helix_axis = axes.get(helix_axis) if helix_axis else None
        self._mask = md.int(MD.POLYGON_FUNCTION_MASK)
        self.active = False

    @property
    def configured(self) -> bool:
        return bool(self.master and self.slave and self.master != self.slave)

    def commanded_axes(self) -> tuple[str, ...]:
        return (self.master, self.slave) if self.active else ()

    def start(self, command: PolygonCommand) -> int:
        """G51.2: couple the slave to the master.  Returns an alarm number or 0."""
        if not self.configured:
            return ALARM_NOT_AVAILABLE
        if self.active:
            if not self._mask & ECN:
                return ALARM_RESYNC_NOT_ALLOWED
            self._couplings.decouple(self.slave, stop=False)
        kind = Kind.AV if self._mask & SNTP else Kind.DV
        name = self._channel.name
        self._couplings.define(name, self.slave, self.master, command.q, command.p, BlockChange.NOC, kind)
        alarm = self._couplings.couple(name, self.slave, self.master, None, False, 0, "")
        if alarm:
            return alarm
        coupling = self._couplings.active[self.slave]
        coupling.pending_shift = -command.q / command.p * command.r
        coupling.jog_allowed = False  # the relation holds in manual operation too (L63-65)
        if command.a and self._helix_axis is not None:
            coupling.helix = (self._helix_axis, command.a)
        self._master_ramp(on=True)
        self.active = True
        return 0

    def _master_ramp(self, on: bool) -> None:
        """0162 / 0163: the master's ramp while synchronous (start speed to MD32000 in the time constant)."""
        master = self._spindles[self.master]
        time = self._channel.md.float(MD.POLYGON_MASTER_ACC_TIME) / 1000.0
        if not on or time <= 0.0:
            master.speed_control.acceleration_override = None
            return
        start = self._channel.md.float(MD.POLYGON_MASTER_ACC_START_VELO) / 60.0  # deg/min -> deg/s
        top = master.md.float(MD.MAX_AX_VELO) * RPM
        master.speed_control.acceleration_override = max(top - start, 0.0) / time

    def revolution_speed(self) -> float | None:
        """While synchronous: the speed (rev/min) G99 takes its feed from, by 0201 ERV (seed 002
        L187-196): 0 = the encoder's feedback speed, 1 = the slave's theoretical speed.  The seed
        names no spindle for the encoder; G99 counts the revolutions of the workpiece, the master,
        so its actual speed [INF].  The theoretical speed is the slave's setpoint speed."""
        if not self.active:
            return None
        if self._mask & ERV:
            return abs(self._spindles[self.slave].axis.command_velocity) / RPM
        return abs(self._spindles[self.master].axis.velocity) / RPM

    def cancel(self) -> None:
        """G50.2, the emergency stop, a reset without HBR or an alarm that ends it."""
        if not self.active:
            return
        self.active = False
        # the GSK slave is a servo axis turned by the synchronisation alone: it stops with it
        # (seed 002 L51, L77-81 say only "cancel") [INF]
        self._couplings.delete(self.slave, stop=True)
        self._master_ramp(on=False)

    def reset(self) -> str | None:
        """Reset and program end: HBR = 0 ends the synchronisation, HBR = 1 keeps it, whatever the
        coupling engine's reset masks say (seed 002 L137, L198-202).  Returns the slave it keeps."""
        if not self._mask & HBR:
            self.cancel()
            return None
        return self.kept()

    def kept(self) -> str | None:
        """The slave while synchronous: its coupling is the polygon's, which only G50.2, the emergency
        stop, a reset without HBR and the alarms of L134-138 end; the coupling engine's masks for
        programmed pairs at NC start and reset (MD20112, MD20110) leave it alone."""
        return self.slave if self.active else None

    def alarms_raised(self, alarms: list[Alarm]) -> None:
        if self.active and not all(keeps_synchronism(alarm) for alarm in alarms):
            self.cancel()
