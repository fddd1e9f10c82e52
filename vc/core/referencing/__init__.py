"""Referencing (layer 4 of vc/core): the reference point approach of an axis and what the NC
memory keeps of it across power off (seed 003 referencing, DB31.DBX60.4/60.5).

``referencing``  the axis referencing state machine (incremental, distance-coded, absolute
                 encoders) and the loss of calibration

Imports: interpolation, kinematics, axis and the base modules (spindle uses ``lose_calibration``,
so it sits below spindle).
"""
