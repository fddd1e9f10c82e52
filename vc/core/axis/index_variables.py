"""The system variables of indexing axes (seed 003 §11.3.3, L13779-13820), read by part-program
conditions and synchronized actions as the other $AA_ variables are::

    $AA_PROG_INDEX_AX_POS_NO[ax]   the number of the index position a motion of the axis goes to:
                                   POS / POSA (coded or onto an index position), FC18, a synchronized
                                   action's POS; kept while the axis stands there, 0 once another
                                   owner (the path, JOG, a brake) takes the axis [INF: the seed says
                                   "0: not travelling to an index position"]; 0 for no indexing axis
    $AA_ACT_INDEX_AX_POS_NO[ax]    the number of the index position last reached or passed, where it
                                   changes as MD10940 INDEX_AX_MODE bit 0 says (IndexPositions.reached);
                                   0 for no indexing axis

The seed warns that the second says nothing about being in position (L13683-13700): DB31.DBX76.6 or
DBX60.7 do.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

from vc.config.model import ChannelConfig
from vc.core.axis.axis import MachineAxis

PROGRAMMED = "$AA_PROG_INDEX_AX_POS_NO"
ACTUAL = "$AA_ACT_INDEX_AX_POS_NO"
INDEX_VARIABLES = (PROGRAMMED, ACTUAL)
HALFWAY = 1  # MD10940 bit 0

Reader = Callable[[str, str], float]


def index_variable_reader(config: ChannelConfig, axes: Mapping[str, MachineAxis], index_mode: int,
                          others: Reader) -> Reader:
    """The channel's reader of system variables with the two above in front of ``others``; an axis
    name the channel does not know is a KeyError (12550 for the program), as for the others."""
    halfway = bool(index_mode & HALFWAY)

    def read(name: str, index: str) -> float:
        if name not in INDEX_VARIABLES:
            return others(name, index)
        machine_axis = config.axis_for_program_name(index)
        axis = axes.get(machine_axis) if machine_axis is not None else None
        if axis is None:
            raise KeyError(f"{name}[{index}]")
        if axis.index is None:
            return 0.0
        if name == PROGRAMMED:
            return float(axis.programmed_index)
        return float(axis.index.reached(axis.actual, axis.dyn.fine_window, halfway))
    return read
