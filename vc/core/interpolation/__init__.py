"""Interpolation (layer 6 of vc/core): the path of a block cycle by cycle (seed 003 path
interpolation, docs/kinematics.md section 7).

``path``            linear path interpolation of the machine axes
``circle``          G2 / G3 arcs in the working plane
``tool_path``       a path in program coordinates through a transform
``thread_cutting``  G33 thread cutting with the spindle

Imports: kinematics, axis and the base modules.
"""
