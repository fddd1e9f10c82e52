"""Spindles (layer 3 of vc/core): a spindle on its own and spindles coupled to one another.

``spindle``           the modes of a spindle and their DB31 status (seed 003 chapter 13)
``gear_change``       the gear stages and the gear stage change dialog with the PLC (DB31.DBX82.3, 16.3)
``positioning``       the motion of SPOS / SPOSA / M19 (§13.2.5)
``speed_control``     speed limits, override, ramp, set speed and speed monitoring (§13.8, 83.x)
``zero_mark``         synchronisation of a turning spindle with its encoder's zero mark (§13.3)
``signals``           the DB31 spindle signals, the inputs as taken, the status shown
``coupling``          synchronous spindle coupling (seed 003 chapter 14, docs/sync_spindle.md): the
                      coupling table and the commands COUPDEF / COUPON / COUPOF
``coupling_state``    a pair, a coupled pair and its phases
``coupling_motion``   the coupling law and the overlaid motions of each coupled following spindle
``coupling_monitor``  fine / coarse synchronism, stage-2 monitoring, the coupling's system variables
``coupling_signals``  the DB31 coupling signals
``polygon``           GSK polygon turning G51.2 / G50.2 on the coupling engine (seed 002)

Imports: referencing, program (the commands it executes), interpolation, kinematics, axis and the
base modules; never its siblings retraction and transforms, never channel or nck.
"""
