"""The part program (layer 5 of vc/core): from program text to what a block asks of the machine
(seed 003 programming, docs/sync_spindle.md and docs/retraction.md for the program words).

``program``            the program text parsed into blocks (words, calls, assignments, labels)
``interpreter``        the blocks decoded into block plans with the modal state: the block-level
                       driver (which handler takes a word, what may stand together in a block)
``block_plan``         what a decoded block asks of the channel (BlockPlan), the modal state, the
                       software limit checks of end points
``decoder``            the decoder of one block, shared by the word handlers
``motion_words``       G words, F, circle, thread (G33), tapping (G331 / G332), G28 / G30, G22,
                       PRESETON, the argument words of a five-axis block
``spindle_words``      spindle M / S / SPOS words, SPCON, WAITS, the coupling calls, polygon turning
``retract_words``      fast retraction, ESR, system variables and synchronized actions of a block
``sync_actions``       synchronized actions (WHEN / WHENEVER ... DO)
``five_axis_program``  the five-axis program words (G43.4, G68.2, G53.1)
``commands``           the interpreter's output vocabulary other packages consume: spindle,
                       coupling, polygon, drive ESR and retract commands

Imports: interpolation, kinematics, axis and the base modules; none of spindle, retraction,
transforms, referencing, channel, nck.
"""
