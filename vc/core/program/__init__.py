"""The part program (layer 5 of vc/core): from program text to what a block asks of the machine
(seed 003 programming, docs/sync_spindle.md and docs/retraction.md for the program words).

``program``            the program text parsed into blocks (words, calls, assignments, labels)
``interpreter``        the blocks decoded into block plans with the modal state
``sync_actions``       synchronized actions (WHEN / WHENEVER ... DO)
``five_axis_program``  the five-axis program words (G43.4, G68.2, G53.1)
``commands``           the interpreter's output vocabulary other packages consume: spindle,
                       coupling, polygon, drive ESR and retract commands

Imports: interpolation, kinematics, axis and the base modules; none of spindle, retraction,
transforms, referencing, channel, nck.
"""
