"""Spindles (layer 3 of vc/core): a spindle on its own and spindles coupled to one another.

``spindle``      speed, position and axis mode of a spindle (seed 003 chapter 13, DB31)
``gear_change``  the gear stage change dialog with the PLC (DB31.DBX82.3, 16.3)
``coupling``     synchronous spindle coupling (seed 003 chapter 14, docs/sync_spindle.md)
``polygon``      GSK polygon turning G51.2 / G50.2 on the coupling engine (seed 002)

Imports: referencing, program (the commands it executes), interpolation, kinematics, axis and the
base modules; never its siblings retraction and transforms, never channel or nck.
"""
