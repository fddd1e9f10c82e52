"""What can be read from and done to the simulated machine besides its interface signals.

The scenario language, the harness and the FMU share this vocabulary.
"""

from __future__ import annotations

from interfaces.errors import VcError
from interfaces.signals import NCK_INSTANCE
from vc.config.model import MachineConfig

# Quantities of an axis or spindle that can be read besides interface signals
# (mm and mm/min on a linear axis, degrees and rev/min on a rotary axis or spindle).
AXIS_QUANTITY_MEANINGS = {
    "position": "actual position the NC shows (machine coordinate system); a modulo rotary axis"
                " (MD30310) shows it inside its modulo range",
    "setpoint": "position setpoint of the interpolator, shown like the position",
    "velocity": "actual velocity",
    "followingError": "setpoint minus actual position",
    "physical": "true position of the slide in the simulated machine (plant); on a spindle its angle,"
                " counted on over the turns",
    "programPosition": "absolute position the NC shows in program coordinates: Cartesian for the axes of an"
                       " inclined-axis control (seed 000), else the position without the DRF offset",
    "drfOffset": "the DRF offset the handwheel set in AUTO / MDA (DB21.DBX0.3), in the machine coordinate"
                 " system; on a coupled following spindle the relation it moved",
}
# Quantities of a following spindle's coupling (0 while the spindle follows nobody), degrees.
COUPLING_QUANTITY_MEANINGS = {
    "couplingOffset": "$AA_COUP_OFFS: setpoint relation FS - k x LS, 0..360",
    "couplingOffsetActual": "$VA_COUP_OFFS: actual relation FS - k x LS, 0..360",
    "couplingOffsetProgrammed": "$P_COUP_OFFS: the last programmed offset",
    "couplingCorrection": "$AA_COUP_CORR: the synchronism correction (DB31.DBX31.6)",
    "syncDeviation": "synchronism deviation the monitoring compares with MD37200 / MD37210 (degrees;"
                     " rev/min for a VV coupling)",
    "couplingRelationError": "actual relation FS - k x LS minus the relation commanded now (setpoint relation"
                             " and applied correction), -180..180, signed; 0 until setpoint synchronism",
}
AXIS_QUANTITIES = tuple(AXIS_QUANTITY_MEANINGS) + tuple(COUPLING_QUANTITY_MEANINGS)

# The unit of every quantity, declared once: the diagrams, the CSV traces and the reports read it here
# (quantity_unit).  POSITION and VELOCITY stand for the axis's own units (AxisConfig.position_unit and
# velocity_unit: mm and mm/min on a linear axis, degrees and rev/min on a rotary axis or spindle).
# syncDeviation has none: degrees, or rev/min for a VV coupling.
POSITION, VELOCITY = "<position>", "<velocity>"
AXIS_QUANTITY_UNITS = {
    "position": POSITION, "setpoint": POSITION, "velocity": VELOCITY, "followingError": POSITION,
    "physical": POSITION, "programPosition": POSITION, "drfOffset": POSITION,
    "couplingOffset": "deg", "couplingOffsetActual": "deg", "couplingOffsetProgrammed": "deg",
    "couplingCorrection": "deg", "syncDeviation": "", "couplingRelationError": "deg",
}

# Quantities of a channel (CHAN1.toolTipX): the tool by the five-axis forward kinematics from the
# actual machine positions, in workpiece coordinates (mm; the direction as a unit vector).
CHANNEL_QUANTITY_MEANINGS = {
    "toolTipX": "tool tip X in workpiece coordinates, with the tool length of G43.4 / G43 in force"
                " (none: the spindle face)",
    "toolTipY": "tool tip Y in workpiece coordinates",
    "toolTipZ": "tool tip Z in workpiece coordinates",
    "toolDirX": "tool direction (tip towards holder) X component, in workpiece coordinates",
    "toolDirY": "tool direction Y component",
    "toolDirZ": "tool direction Z component",
    "tcpActive": "1 while tool centre point control G43.4 is active",
    "liftfast": "$AC_LIFTFAST: 1 after a fast retraction in G33, 0 when the program resets it",
    "tool": "the active tool ($P_TOOLNO): the last T (MD22550 = 0) or the tool M6 changed to (MD22550 = 1)",
    "toolPreselected": "the tool the last T selected (with MD22550 = 1 active after M6)",
    "toolOffset": "the active tool offset: the last D",
}
CHANNEL_QUANTITIES = tuple(CHANNEL_QUANTITY_MEANINGS)
CHANNEL_QUANTITY_UNITS = {"toolTipX": "mm", "toolTipY": "mm", "toolTipZ": "mm"}  # the others have none

# Quantities of the NCK and the drive line-up (NC.dcLinkVoltage).
NCK_QUANTITY_MEANINGS = {
    "dcLinkVoltage": "voltage of the drive line-up's DC link, V (only on a machine with dc_link:)",
}
NCK_QUANTITIES = tuple(NCK_QUANTITY_MEANINGS)
NCK_QUANTITY_UNITS = {"dcLinkVoltage": "V"}


def quantity_unit(machine: MachineConfig, instance: str, quantity: str) -> str:
    """The unit of ``instance.quantity`` on ``machine`` (``SP1.velocity``: rev/min); "" for none."""
    if instance == NCK_INSTANCE:
        return NCK_QUANTITY_UNITS.get(quantity, "")
    axis = next((axis for axis in machine.axes if axis.name == instance), None)
    if axis is None:
        return CHANNEL_QUANTITY_UNITS.get(quantity, "")
    unit = AXIS_QUANTITY_UNITS.get(quantity, "")
    return axis.position_unit if unit == POSITION else axis.velocity_unit if unit == VELOCITY else unit

# Faults of the simulated machine a scenario can inject:
#   zero_marks_missing       the encoder's zero-mark track is not seen (dirty, broken)
#   reference_marks_missing  distance-coded reference marks missing between two positions
#   encoder_slip             the measuring system miscounts by an amount (zero-mark monitoring responds)
#   load_disturbance         a load the drive holds against: the slide lags by amount (rev/min, mm/min)
#                            over the position controller's gain until the fault is cleared
#   workpiece_clamp          a part clamped in a following spindle and its leading spindle locks the
#                            FS to the LS, twisted by amount (degrees), until the fault is cleared
#   motor_temperature        the motor's temperature rises to amount (degC, ``to:``) until the fault is
#                            cleared (an axis whose drive reports its messages: DB31.DBX94.0 above p0604)
#   mains_failure            the line supply of the drive line-up fails (no axis; a machine with dc_link:):
#                            Drives.ready falls, the DC link is on its own until the fault is cleared
#                            (clear_faults: mains)
# Faults of a device of the machine (its plant:; no axis), repaired with clear_faults: <device>:
#   turret_sensor_missing    the wire of Turret.unlocked is broken: it reads 0 with the pin pulled
#   turret_lock_jammed       the lock pin does not engage: Turret.locked never comes
#   turret_drive_stalled     the indexing drive runs, the disk does not turn
#   coolant_pressure_lost    the pressure switch stays open while the pump runs (clogged filter, dry tank)
#   magazine_stalled         the magazine's drive runs, the magazine does not turn
#   tool_arm_stuck           the tool changer arm does not move
#   stop_lost                the part in the tailstock slips away: the quill's fixed stop is gone
#   no_part                  no part in the tailstock: the quill finds no fixed stop
#   axis_magazine_lock_sensor  the axis magazine's "locked" sensor wire is broken: it reads 0
#   axis_magazine_drive_fault  the axis magazine's drive reports not ready
#   clamp_not_closing        the axis clamp does not close: Clamp.closed never comes
#   clamp_opening            the closed axis clamp gives way under the load, which pushes the axis
#   brake_not_opening        an axis's holding brake does not release: DB31.DBX92.5 never comes
#   brake_not_closing        an axis's holding brake does not engage once released: DBX92.5 stays 1
DEVICE_FAULTS = {"turret_sensor_missing": "Turret", "turret_lock_jammed": "Turret", "turret_drive_stalled": "Turret",
                 "coolant_pressure_lost": "Coolant", "magazine_stalled": "Magazine", "tool_arm_stuck": "ToolArm",
                 "stop_lost": "Tailstock", "no_part": "Tailstock", "axis_magazine_lock_sensor": "AxisMagazine",
                 "axis_magazine_drive_fault": "AxisMagazine", "clamp_not_closing": "Clamp", "clamp_opening": "Clamp",
                 "brake_not_opening": "Brake", "brake_not_closing": "Brake"}
FAULTS = ("zero_marks_missing", "reference_marks_missing", "encoder_slip", "load_disturbance", "workpiece_clamp",
          "motor_temperature", "mains_failure", *DEVICE_FAULTS)
MACHINE_FAULTS = ("mains_failure", *DEVICE_FAULTS)  # faults of the whole machine or a device: no axis


def machine_devices(machine: MachineConfig) -> tuple[str, ...]:
    """The devices of ``machine`` a fault can be injected into (clear_faults names them)."""
    plant = machine.plant
    return tuple(name for name, present in (("Turret", plant.turret), ("Coolant", plant.coolant),
                                            ("Magazine", plant.tool_changer), ("ToolArm", plant.tool_changer),
                                            ("Tailstock", plant.tailstock), ("AxisMagazine", plant.axis_magazine),
                                            ("Clamp", plant.clamp), ("Brake", plant.holding_brake))
                 if present is not None)
MAINS = "mains"  # clear_faults: mains - the supply is back

# Faults of the bus between the NC and the PLC a scenario can inject (link_fault step; the scenario
# runs its PLC behind the CAN link, link: can):
#   loss     frames are lost (with every: n, every n-th of them)
#   delay    frames arrive later (by: the delay); nothing overtakes them
#   bus_off  a disturbance of the bus drives the NC's CAN controller bus-off; it restarts after
#            can.restart once the bus is quiet again
LINK_FAULTS = ("loss", "delay", "bus_off")
LINK_DIRECTIONS = ("nc_to_plc", "plc_to_nc")
LINK_AREA = "link"  # the link frames (NC link, PLC link) among a fault's frames

# Quantities of the CAN link (CAN.lostFromPlc) of a scenario whose PLC sits behind it (link: can),
# counted from the power-on (the session).
LINK_INSTANCE = "CAN"
LINK_QUANTITY_MEANINGS = {
    "framesSent": "frames the NC's controller put on the bus",
    "framesTaken": "frames of the PLC the NC took (after the faults)",
    "lostToPlc": "frames of the NC lost to a fault or to the controller (bus-off)",
    "lostFromPlc": "frames of the PLC lost to a fault or to the controller (bus-off)",
    "delayedToPlc": "frames of the NC a delay held back",
    "delayedFromPlc": "frames of the PLC a delay held back",
    "plcFrameAge": "seconds since the oldest of the PLC's frames arrived (the time-out monitor: can.timeout)",
    "timedOut": "1 while one of the PLC's frames is older than can.timeout: the NC gets no new sign of life",
    "plcSignOfLife": "the PLC's sign of life as the NC watches it (MD10100, alarm 2000)",
    "plcMissesNcFrames": "1 while the PLC's time-out monitor misses frames of the NC (its link frame says so)",
    "busState": "the NC's CAN controller: 0 error active, 1 error passive, 2 bus-off",
    "transmitErrors": "the transmit error counter of the NC's CAN controller",
    "busOffs": "times the NC's CAN controller went bus-off",
}
LINK_QUANTITIES = tuple(LINK_QUANTITY_MEANINGS)


class StepRefused(VcError):
    """What a step asks cannot be done in the state the machine is in now (a workpiece clamped in a
    spindle that follows none): the step fails with this message, as a check does.  Here, below the
    simulation and the scenario runner, so that the simulation (and the FMU that carries it) needs
    nothing of the scenario package."""

