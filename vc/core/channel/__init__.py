"""The channel (layer 2 of vc/core): NC start / stop / reset, the program run block by block
(seed 003 channel and program operation, DB21).

``channel``              the Channel: its commands (NC start, NC stop, reset, mode change) and its
                         IPO cycle; it owns the parts below and delegates to them
``program_run``          the channel and program state, the program and the block in progress: what
                         the parts share (ChannelState, ProgramState, BlockPhase, Mode)
``interface``            the DB21 signals: the PLC's requests and their edges, the states written back
``block_execution``      a block plan turned into motion, dwell, G74, the block change, program end
``spindle_functions``    the blocks' spindle, coupling and polygon commands and their interlocks
``thread_retract``       G33 thread blocks, fast retraction (LFON) and the channel's side of ESR
``stroke_limit_path``    stored stroke limits 2 and 3 on the channel's paths and in JOG
``channel_referencing``  channel-specific referencing (DB21.DBX1.0) in the order of MD34110
``referencing_control``  the channel's referencing order (MD34110) and the inclined-axis rule for it;
                         it uses the transform controls, so it lives above them

Imports: spindle, retraction, transforms, referencing, program, interpolation, kinematics, axis and
the base modules; never nck.
"""
