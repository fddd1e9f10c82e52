"""Auxiliary functions (layer 3 of vc/core): a channel's M, S, T, D, DL, H and F output to the PLC.

``output``          the output slots of DB21.DBB58 ff. and their handshake with the PLC (Basic
                    Functions H2; seed 003 L16391-16455, L16486, L17456-17490, L20662-20680)
``tool_selection``  the tool the program's T, D and M6 select (MD22550 / MD22560)

Imports: program (the functions a block hands over), the base modules and the machine data; never
its siblings spindle, retraction and transforms, never channel or nck.  The words themselves are
decoded in ``vc/core/program/aux_words.py``; docs/auxiliary_functions.md says what is modelled.
"""
