"""Kinematics (layer 7 of vc/core): pure functions between programmed and machine positions.

``inclined_axis``  GSK 988TD inclined (angular) axis control (seed 000)
``five_axis``      Syntec five-axis mechanism chains, types 1-5, RTCP (seed 001)
``tilted_plane``   G68.2 tilted working plane and G53.1 tool alignment (seed 001)
``geometry``       the vectors and rotations they share

No state and no I/O: the NC core calls them with positions and parameters and acts on the
results, alarms included (``transform_alarm``).  Formulas, conventions and the choices the
seeds leave open are in docs/kinematics.md.  The channel-side controls that apply them live
in ``vc.core.transforms``.

Imports: the base modules of vc/core and vc.config only (no other package of vc/core).
"""
