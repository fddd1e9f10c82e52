"""Referencing (layer 4 of vc/core): the reference point approach of an axis and what the NC
memory keeps of it across power off (seed 003 referencing, DB31.DBX60.4/60.5).

``referencing``         the axis referencing state machine (incremental, distance-coded, absolute
                        encoders), one state machine per procedure for observers
``referencing_data``    what a procedure reads: its axis's referencing machine data, the NC's
                        conditions of the cycle
``distance_coded``      distance-coded marks: the position they give, the passive scale that
                        references itself by crossing them
``buffered_positions``  power-off buffering and power-on restore of the measuring systems, the
                        loss of a reference (encoder slip) or of a calibration

Imports: interpolation, kinematics, axis and the base modules (spindle uses ``lose_calibration``,
so it sits below spindle).
"""
