"""The tool the channel works with, as the program's T, D and tool change M function select it.

MD22550 TOOL_CHANGE_MODE = 0: the T word changes the tool (a turret indexes to it); 1: T only
preselects it and the M function of MD22560 (M6) changes it (a magazine prepares the tool while
the program machines, the changer swaps it at M6) [control].  The NC keeps no tool offsets: it
knows the numbers; the PLC does the mechanics with the functions it is given.
"""

from __future__ import annotations

from collections.abc import Sequence

from vc.config import md_dictionary as MD
from vc.config.machine_data import MachineData
from vc.core.program.commands import AuxiliaryFunction


class ToolSelection:
    def __init__(self, md: MachineData):
        self.change_with_m = md.int(MD.TOOL_CHANGE_MODE) == 1
        self.change_code = md.int(MD.TOOL_CHANGE_M_CODE)
        self.tool = 0  # the active tool (T0: none)
        self.preselected = 0  # the tool the last T selected
        self.offset = 0  # the active tool offset (D)

    def block(self, functions: Sequence[AuxiliaryFunction]) -> None:
        """Take a block's T, D and M functions, in the block's order."""
        for function in functions:
            if function.kind == "T":
                self.preselected = int(function.value)
                if not self.change_with_m:
                    self.tool = self.preselected
            elif function.kind == "D":
                self.offset = int(function.value)
            elif self.change_with_m and function.kind == "M" and function.extension == 0 \
                    and function.value == self.change_code:
                self.tool = self.preselected
