"""Travel to fixed stop (layer 3 of vc/core, seed 003 chapter 17).

``fixed_stop``           one axis's function: its states, the PLC handshake DB31.DBX3.1 / 1.1 / 1.2 /
                         62.4 / 62.5, detection, the torque limit, the window, alarms 20090-20094
``channel_fixed_stops``  a channel's FXS / FXST / FXSW words applied to its axes, and what its
                         block execution asks of them (hold the motion, end the path, the block change)

Imports: program (the words a block hands over), axis, the base modules and the machine data; never
its siblings spindle, retraction, transforms and auxiliary, never channel or nck.  The words are
decoded in ``vc/core/program/fixed_stop_words.py``; docs/fixed_stop_and_drives.md says what is modelled.
"""
