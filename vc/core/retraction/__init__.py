"""Retraction (layer 3 of vc/core): fast retraction and extended stop and retract
(seed 003 LIFTFAST and ESR, docs/retraction.md).

``esr``             NC-controlled ESR and fast retraction of a channel, the NCK's ESR trigger
``drive_esr``       the drive-autonomous ESR of an axis (p0888, p0892, DB31.DBX95.2)
``retract_motion``  the retract motion at maximum dynamics (S-curve, LFTXT / LFWP / LFPOS targets)
``dc_link``         the drive line-up's DC link that a power failure drains

Imports: program (sync actions, the commands), interpolation, kinematics, axis and the base modules;
never its siblings spindle and transforms, never referencing, channel or nck.
"""
