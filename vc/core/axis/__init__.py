"""Machine axes (layer 7 of vc/core, beside kinematics): one axis and what moves it
(seed 003 axes, DB31).

``axis``           the machine axis: setpoint, drive, encoder, monitoring, commands (owns the pieces below)
``owner``          who moves the axis: the motion owners
``dynamics``       limits and loop parameters from the machine data, the jerk filter they ask for
``position_loop``  the position control loop: Kv, feedforward and symmetrising, the drive's lag
``signals``        the DB31 signals: decoding the PLC's outputs, writing the status bits
``jog``            JOG with the traverse keys and the handwheel, the software limits JOG keeps
``drf``            the DRF offset (handwheel in AUTO / MDA)
``motion``         ramps, jerk filter and braking distances
``encoder``        measuring systems and their reference marks
``stroke_limits``  software limits and the stored stroke limits 2 and 3
``handwheel``      the handwheels of the control (JOG)
``command_axis``   command axes: POS[ax]= of a synchronized action, a single axis (§9.3.2)

Imports: the base modules only (alarms, interface_map, nc_memory, overrides); never kinematics.
"""
