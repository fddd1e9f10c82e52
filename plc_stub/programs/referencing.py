"""referencing: basic_machine plus the machine builder's referencing logic.

Network 5, referencing (in JOG-REF or MDA-REF, started with NC start on the panel):

* without a ``referencing_order`` parameter, NC start sets DB21.DBX1.0 and the NC references
  the channel's axes in its own order (MD34110);
* with ``referencing_order`` (the machine file's ``plc:`` section), the PLC chooses the order:
  group by group it holds the traverse key of each axis in its referencing direction
  (``referencing_direction``, per axis ``plus`` or ``minus``, default ``plus``; it must match
  MD34010) until the axis reports DB31.DBX60.4 (or 60.5), then the next group.  The key is
  held all the time, so referencing also works in hold mode (MD11300 = 1).
* RESET ends the PLC's sequence; the NC aborts its referencing on the same reset.

Parameters (machine file)::

    plc:
      referencing_order: [[Y1, Z1], [X1]]        # inclined and Z first, then the orthogonal X
      referencing_direction: {Y1: minus}
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from plc_stub.blocks import R_TRIG
from plc_stub.io import Bool, PlcIo
from plc_stub.programs.basic_machine import BasicMachine, pressed


@dataclass(slots=True)
class _SequencedAxis:
    key: Bool  # the traverse key of the referencing direction
    referenced: tuple[Bool, Bool]  # DB31.DBX60.4, 60.5


class Referencing(BasicMachine):
    PARAMETERS = (*BasicMachine.PARAMETERS, "referencing_order", "referencing_direction")

    def __init__(self, io: PlcIo):
        super().__init__(io)
        layout = io.environment.catalog.layout
        order, directions = _parameters(io.environment.parameters, layout.axes)
        self.start_key = R_TRIG()
        self.reset_key = R_TRIG()
        self.channel_reference_starts = [io.output(f"{name}.basic.out.refPointApproach") for name in layout.channels]
        self.ref_active = io.input("MODEGROUP.basic.in.refPointActive")
        self.groups: list[list[_SequencedAxis]] = [[self._sequenced(io, axis, directions) for axis in group]
                                                    for group in order]
        self.step = -1  # -1 = no sequence running, else the group being referenced

    @staticmethod
    def _sequenced(io: PlcIo, axis: str, directions: Mapping[str, str]) -> _SequencedAxis:
        key = "traversKeyMinus" if directions.get(axis) == "minus" else "traversKeyPlus"
        referenced = (io.input(f"{axis}.basic.in.enc1Synchronized"), io.input(f"{axis}.basic.in.enc2Synchronized"))
        return _SequencedAxis(io.output(f"{axis}.basic.out.{key}"), referenced)

    def ob1(self) -> None:
        super().ob1()
        self.referencing()

    # Network 5 ---------------------------------------------------------------------------
    def referencing(self) -> None:
        start = self.start_key(pressed(self.key_nc_start))
        reset = self.reset_key(pressed(self.key_reset))
        in_ref = self.ref_active.value
        if reset or not in_ref:
            self.step = -1
        for output in self.channel_reference_starts:
            output.value = start and in_ref and not self.groups
        if start and in_ref and self.groups and self.step < 0:
            self.step = 0
        if self.step < 0:
            return
        group = self.groups[self.step]
        done = True
        for axis in group:
            referenced = axis.referenced[0].value or axis.referenced[1].value
            axis.key.value = not referenced
            done = done and referenced
        if done:
            self.step += 1
            if self.step == len(self.groups):
                self.step = -1


def _parameters(parameters: Mapping[str, Any], axes: tuple[str, ...]) -> tuple[list[list[str]], dict[str, str]]:
    """Check the program's parameters; a mistake is a clear error when the PLC starts."""
    order = parameters.get("referencing_order", [])
    directions = parameters.get("referencing_direction", {})
    if not isinstance(order, list) or not all(isinstance(group, list) for group in order):
        raise ValueError("plc: referencing_order must be a list of groups of axes, e.g. [[Y1, Z1], [X1]]")
    for group in order:
        for axis in group:
            if axis not in axes:
                raise ValueError(f"plc: referencing_order names {axis}, which the machine lacks")
    if not isinstance(directions, Mapping) or any(value not in ("plus", "minus") for value in directions.values()):
        raise ValueError("plc: referencing_direction maps axes to plus or minus, e.g. {Y1: minus}")
    for axis in directions:
        if axis not in axes:
            raise ValueError(f"plc: referencing_direction names {axis}, which the machine lacks")
    return [list(group) for group in order], dict(directions)
