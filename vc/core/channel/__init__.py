"""The channel (layer 2 of vc/core): NC start / stop / reset, the program run block by block
(seed 003 channel and program operation, DB21).

``channel``              the Channel: its state machines, the blocks it runs and the functions it drives
``referencing_control``  the channel's referencing order (MD34110) and the inclined-axis rule for it;
                         it uses the transform controls, so it lives above them

Imports: spindle, retraction, transforms, referencing, program, interpolation, kinematics, axis and
the base modules; never nck.
"""
