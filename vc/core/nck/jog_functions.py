"""The machine functions of JOG of the machine axes (seed 003 §16.4.1, §16.5.1-16.5.2, L32700-32760,
L32860-33095).

The PLC selects per machine axis with DB31.DBX5.0..5.6 how its traverse keys command in JOG:
INC1 .. INC10000 (the fixed increments MD11330 JOG_INCR_SIZE_TAB[0..4]), INCvar (the variable
increment SD41010 JOG_VAR_INCR_SIZE) or continuous JOG; one increment travels the number of
increments x MD31090 JOG_INCR_WEIGHT of the axis (a negative weight reverses the keys'
direction, L33086-33088).  Several selected at once: the smallest increment counts, as for the
handwheels [control choice: the seed does not say]; none selected: continuous JOG, as the NC
always traversed [control choice], and nothing is reported.  The NC reports the machine function
it has active in JOG on DB31.DBX65.0..65.6 (L32733-32735, L33016-33040); outside JOG none.
MD11300 (increments) and SD41050 (continuous) say whether the keys command in jog or continuous
mode (``vc/core/axis/jog_keys.py``).  The handwheels take the same fixed increments and weight.
"""

from __future__ import annotations

from collections.abc import Sequence

from interfaces.image import ProcessImage
from interfaces.signal_groups import (
    ActiveGeometryJogMachineFunction,
    ActiveJogMachineFunction,
    GeometryJogMachineFunctions,
    HandwheelSelection,
    JogMachineFunctions,
)
from vc.config import md_dictionary as MD
from vc.config.machine_data import MachineData
from vc.core.axis.axis import MachineAxis
from vc.core.axis.handwheel import increment_of
from vc.core.axis.jog_keys import JogSelection
from vc.core.channel.channel import Channel
from vc.core.interface_map import SignalTable

_NOTHING_ACTIVE = ActiveJogMachineFunction()
_NOTHING_ACTIVE_GEOMETRY = ActiveGeometryJogMachineFunction()
HANDWHEEL_INCREMENTS = 5  # the handwheels take INC1 .. INC10000 (DB31.DBX5.0..5.4)


class JogFunctions:
    """The JOG machine function of every machine axis: what its keys command, what the NC reports."""

    def __init__(self, nck: MachineData, axis_table: SignalTable, channel_table: SignalTable, image: ProcessImage,
                 axes: Sequence[MachineAxis]):
        self._image = image
        self._read_geometry = channel_table.codec(GeometryJogMachineFunctions).read
        self._encode_geometry = channel_table.codec(ActiveGeometryJogMachineFunction).encode
        self._geometry_reported: dict[str, ActiveGeometryJogMachineFunction] = {}
        self._read = axis_table.codec(JogMachineFunctions).read
        self._encode = axis_table.codec(ActiveJogMachineFunction).encode
        self._increments = (*nck.floats(MD.JOG_INCR_SIZE_TAB), nck.float(MD.JOG_VAR_INCR_SIZE))
        continuous_held = nck.bool(MD.JOG_CONT_MODE_LEVELTRIGGRD)
        self._increment_held = nck.bool(MD.JOG_INC_MODE_LEVELTRIGGRD)
        self.continuous = JogSelection(0.0, continuous_held, self._increment_held)
        self._weight = {axis.name: axis.config.md.float(MD.JOG_INCR_WEIGHT, 0) for axis in axes}
        self._reported: dict[str, ActiveJogMachineFunction] = {axis.name: _NOTHING_ACTIVE for axis in axes}

    def selection(self, axis: MachineAxis) -> JogSelection:
        """How the traverse keys of ``axis`` command this cycle (DB31.DBX5.0..5.6)."""
        index = _selected(self._read(self._image.area(axis.area_key)))
        if index is None or index == len(self._increments):
            return self.continuous
        return JogSelection(self._increments[index] * self._weight[axis.name], self.continuous.continuous_held,
                            self._increment_held)

    def handwheel_increment(self, selection: HandwheelSelection, axis: MachineAxis) -> float:
        """The travel of ``axis`` per handwheel detent for the PLC's INC1 .. INC10000 (MD11330 x MD31090)."""
        return increment_of(selection, self._increments[:HANDWHEEL_INCREMENTS], self._weight[axis.name])

    def report(self, axis: MachineAxis, jog_mode: bool) -> None:
        """DB31.DBX65.0..65.6: the machine function active in JOG (the PLC's selection), none outside."""
        active = _NOTHING_ACTIVE
        if jog_mode and not axis.is_spindle:
            index = _selected(self._read(self._image.area(axis.area_key)))
            if index is not None:
                active = _ACTIVE[index]
        if active != self._reported[axis.name]:
            self._reported[axis.name] = active
            self._encode(self._image.area(axis.area_key), active)

    def report_geometry_axis(self, channel: Channel, jog_mode: bool) -> None:
        """DB21.DBX41.0..41.6: the machine function of geometry axis 1 active in JOG (DB21.DBX13.0..13.6,
        its handwheel's increment; L33011-33032, L34197-34205), none outside JOG or without the axis."""
        active = _NOTHING_ACTIVE_GEOMETRY
        area = self._image.area(channel.area_key)
        if jog_mode and channel.config.geometry_axes[0]:
            index = _selected(self._read_geometry(area))
            if index is not None:
                active = _ACTIVE_GEOMETRY[index]
        if active != self._geometry_reported.get(channel.name, _NOTHING_ACTIVE_GEOMETRY):
            self._geometry_reported[channel.name] = active
            self._encode_geometry(area, active)


# the feedback of each machine function, in the order of ``_selected``
_ACTIVE = (ActiveJogMachineFunction(inc1=True), ActiveJogMachineFunction(inc10=True),
           ActiveJogMachineFunction(inc100=True), ActiveJogMachineFunction(inc1000=True),
           ActiveJogMachineFunction(inc10000=True), ActiveJogMachineFunction(inc_var=True),
           ActiveJogMachineFunction(continuous=True))
_ACTIVE_GEOMETRY = (
    ActiveGeometryJogMachineFunction(inc1=True), ActiveGeometryJogMachineFunction(inc10=True),
    ActiveGeometryJogMachineFunction(inc100=True), ActiveGeometryJogMachineFunction(inc1000=True),
    ActiveGeometryJogMachineFunction(inc10000=True), ActiveGeometryJogMachineFunction(inc_var=True),
    ActiveGeometryJogMachineFunction(continuous=True))


def _selected(functions: JogMachineFunctions | GeometryJogMachineFunctions) -> int | None:
    """The machine function the NC takes: the smallest increment selected (0..4 fixed, 5 INCvar),
    6 continuous, None for none."""
    for index, on in enumerate((functions.inc1, functions.inc10, functions.inc100, functions.inc1000,
                                functions.inc10000, functions.inc_var, functions.continuous)):
        if on:
            return index
    return None
