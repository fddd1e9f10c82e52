"""The NCK (layer 1 of vc/core, the top): the whole control of one machine.

``nck``                the NCK itself: the IPO cycle as named phases, the NCK functions (emergency stop,
                       PLC sign of life), DB10 / DB11 / DB21 / DB31 exchange, power off
``power_on``           power on: every part of the NCK built from the machine data and wired
``manual_functions``   JOG, handwheels and DRF, referencing with the traverse keys
``alarm_reactions``    rapid stop and follow-up on alarms, the controller enable given back
``mode_group``         the mode group: operating mode and machine function REF (DB11)
``manual_retraction``  retraction of a tapping tool after a power failure or reset (G331 / G332 data
                       kept in the NC memory); it takes over the channel's axes, so it sits above the channel
``alarm_area``         the alarm list published for the PLC (DB100)

Imports: every package of vc/core below it (channel, spindle, retraction, transforms, referencing,
program, interpolation, kinematics, axis) and the base modules.  Nothing in vc/core imports it.
"""
