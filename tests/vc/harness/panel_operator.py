"""The operator of the linked-PLC tests: JOG, REF and X1+ on the panel, and the images to compare."""

from __future__ import annotations

from vc.simulation.lockstep import Simulation


def operate(simulation: Simulation) -> None:
    """JOG, REF and the plus key of X1 from the panel: the PLC enables, selects and references.
    On a machine with an inclined Y1 the minus key of Y1 comes first: the orthogonal X1 may be
    referenced only while Y1 stands at its reference point (seed 000 L375)."""
    simulation.step(100)  # the drives come ready
    for key, cycles in (("MCP.jog", 20), ("MCP.ref", 20)):
        simulation.write(simulation.plant_io.resolve(key), 1)
        simulation.step(cycles)
        simulation.write(simulation.plant_io.resolve(key), 0)
    if any(channel.inclined is not None for channel in simulation.nck.channels):
        simulation.write(simulation.plant_io.resolve("MCP.minus.Y1"), 1)
        simulation.step(3000)  # Y1 references within 6 s
        simulation.write(simulation.plant_io.resolve("MCP.minus.Y1"), 0)
    simulation.write(simulation.plant_io.resolve("MCP.plus.X1"), 1)
    simulation.step(1500)


def images(simulation: Simulation) -> tuple[dict[str, bytes], dict[str, bytes], dict[str, bytes]]:
    return simulation.nck.image.snapshot(), simulation.interface.snapshot(), simulation.plant_image.snapshot()
