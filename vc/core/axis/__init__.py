"""Machine axes (layer 8 of vc/core, beside kinematics): one axis and what moves it
(seed 003 axes, DB31).

``axis``           the machine axis: owner, position control, monitoring, its DB31 signals
``motion``         ramps, jerk filter and braking distances
``encoder``        measuring systems and their reference marks
``stroke_limits``  software limits and the stored stroke limits 2 and 3
``handwheel``      the handwheels of the control (JOG)

Imports: the base modules only (alarms, interface_map, nc_memory, overrides); never kinematics.
"""
