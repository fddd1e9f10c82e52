"""Network 12 of ``manual_retraction``: the handwheels' axes and the increment from the panel.

The machine control panel has an axis selector per handwheel (``MCP.handwheel1`` .. ``3``, a byte
coded as the HMI's handwheel byte DB10.DBB100 / 101 of seed 003 L33180-33197: bits 0..4 the axis
number, bit 7 = 1 a machine axis, 0 a geometry axis of channel 1, 0 = no axis) and the increment
keys ``MCP.inc1`` .. ``MCP.inc10000`` (latched by network 4 of ``basic_machine``).  The PLC user
program assigns the handwheels through the NC/PLC interface, as L33162-33164 leave it to the PLC:

* a machine axis: its DB31.DBX4.0..4.2 (bit n-1 = handwheel n, MD11324 = 0);
* a geometry axis: DB21.DBX12.0..2 / 16.0..2 / 20.0..2 of channel 1;

and writes the increment last pressed (latched; none after power-on [control]) to the machine
functions of every axis that has a handwheel (DB31.DBX5.0..5.4, DB21.DBX13.0..13.4 / 17.x / 21.x),
nothing to the others, whose traverse keys stay continuous JOG.  On a machine without the
selectors the network does nothing (a scenario forces the assignment instead).
"""

from __future__ import annotations

from plc_stub.io import BitField, Bool, Byte, PlcIo

HANDWHEELS = 3
GEOMETRY_AXES = 3
INCREMENTS = (1, 10, 100, 1000, 10000)
MACHINE_AXIS_BIT = 0x80  # bit 7 of the selector: a machine axis (DB10.DBX100.7, L33193-33195)
AXIS_NUMBER_MASK = 0x1F  # bits 0..4: the axis number (DB10.DBX100.0-4, L33184-33186)


class _HandwheelTarget:
    """A machine axis or a geometry axis of channel 1: its handwheel selection and increments."""

    def __init__(self, io: PlcIo, prefix: str):
        self.selection: BitField = io.output_field(f"{prefix}handwheelSelection")
        self.increments: tuple[Bool, ...] = tuple(io.output(f"{prefix}inc{size}") for size in INCREMENTS)

    def write(self, handwheels: int, increment: int | None) -> None:
        self.selection.value = handwheels
        for size, output in zip(INCREMENTS, self.increments, strict=True):
            output.value = bool(handwheels) and size == increment


class HandwheelSelection:
    """Network 12 as a function block; ``wired`` is False on a machine without the selectors."""

    def __init__(self, io: PlcIo):
        self.selectors: list[Byte | None] = [io.input_byte(f"MCP.handwheel{number}")
                                             if io.is_wired(f"MCP.handwheel{number}") else None
                                             for number in range(1, HANDWHEELS + 1)]
        self.wired = any(selector is not None for selector in self.selectors)
        layout = io.environment.catalog.layout
        self.machine_axes = [_HandwheelTarget(io, f"{axis}.basic.out.") for axis in layout.axes] if self.wired else []
        self.geometry_axes = [_HandwheelTarget(io, f"{layout.channels[0]}.geoAxis{number}.out.")
                              for number in range(1, GEOMETRY_AXES + 1)] if self.wired and layout.channels else []

    def __call__(self, increment: int | None) -> None:
        """``increment``: the panel's increment key last pressed (1 .. 10000), None for none."""
        if not self.wired:
            return
        machine = [0] * len(self.machine_axes)
        geometry = [0] * len(self.geometry_axes)
        for bit, selector in enumerate(self.selectors):
            code = selector.value if selector is not None else 0
            number = code & AXIS_NUMBER_MASK
            targets = machine if code & MACHINE_AXIS_BIT else geometry
            if 1 <= number <= len(targets):
                targets[number - 1] |= 1 << bit
        for target, handwheels in zip(self.machine_axes, machine, strict=True):
            target.write(handwheels, increment)
        for target, handwheels in zip(self.geometry_axes, geometry, strict=True):
            target.write(handwheels, increment)
