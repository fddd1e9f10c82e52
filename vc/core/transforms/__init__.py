"""Transform controls (layer 3 of vc/core): the channel-side controls that apply the kinematics
to a channel's axes (docs/kinematics.md).

``inclined_axis_control``  GSK 988TD inclined (angular) axis control (seed 000)
``five_axis_control``      Syntec five-axis functions G43.4, G68.2, G53.1 (seed 001)

The pure math they call is in ``vc.core.kinematics``.

Imports: program (block plans), interpolation, kinematics, axis and the base modules; never its
siblings spindle and retraction, never referencing, channel or nck.
"""
