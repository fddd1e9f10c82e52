"""What can be read from and done to the simulated machine besides its interface signals.

The scenario language, the harness and the FMU share this vocabulary.
"""

from __future__ import annotations

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
}
AXIS_QUANTITIES = tuple(AXIS_QUANTITY_MEANINGS)

# Faults of the simulated machine a scenario can inject:
#   zero_marks_missing       the encoder's zero-mark track is not seen (dirty, broken)
#   reference_marks_missing  distance-coded reference marks missing between two positions
#   encoder_slip             the measuring system miscounts by an amount (zero-mark monitoring responds)
FAULTS = ("zero_marks_missing", "reference_marks_missing", "encoder_slip")
