"""Gantry axes (layer 3 of vc/core, seed 003 chapter 12).

``gantry``  the groupings of MD37100: a leading axis and its synchronized followers, the referencing of
            the grouping and its synchronization run, the warning and trip limits, the signals
            DB31.DBX29.4 / 29.5 / 101.2-101.7; its state machine ``GANTRY_STATES``

Imports: referencing (the procedures of the grouping's axes), axis, the base modules and the machine
data; never its siblings spindle, retraction, transforms, auxiliary and fixed_stop, never channel or nck
(the channel's referencing control is handed in as a function).  docs/gantry.md says what is modelled.
"""
