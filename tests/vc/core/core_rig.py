"""Test rig for the NC core: a :class:`Simulation` of a shipped machine with helpers.

The rig runs the real NCK, plant and (optionally) the built-in PLC in lockstep.  With
``plc=None`` the test is the PLC: it writes PLC->NC signals into the interface itself
(``rig.set("CHAN1.basic.out.ncStart", 1)``), and :meth:`Rig.enable_axes` gives the
enables a basic PLC program would give.  With ``plc="basic_machine"`` the test is the
operator and presses panel keys (``rig.press("MCP.jog")``).

Machine data overrides follow the scenario rules: ``{instance: {MDxxxxx: value}}`` in
YAML text.  ``ABSOLUTE_X1`` makes X1 an absolute, calibrated encoder (MD30240 = 4,
MD34210 = 2): X1 is referenced at power-on and its actual value equals the physical
position (MD34090 = 0).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from functools import lru_cache
from pathlib import Path

from interfaces.image import Value
from vc.config.loader import load_machine
from vc.config.model import MachineConfig
from vc.core.axis.axis import MachineAxis
from vc.core.channel.channel import Channel
from vc.located_yaml import load_text
from vc.simulation.lockstep import Simulation

ROOT = Path(__file__).resolve().parents[3]
TURN_MILL = str(ROOT / "scenarios" / "machines" / "turn_mill.yaml")
MILL = str(ROOT / "scenarios" / "machines" / "mill_3axis.yaml")
FIVE_AXIS = str(ROOT / "scenarios" / "machines" / "mill_5axis.yaml")

DT = 0.002  # s, IPO cycle of both shipped machines (MD10050 x MD10070)
# No NC start lock, X1 with a calibrated absolute encoder: referenced at power-on.
ABSOLUTE_X1 = "CHAN1: {MD20700: 0}\nX1: {MD30240: [4], MD34210: [2]}"
ABSOLUTE_XYZ = ("CHAN1: {MD20700: 0}\nX1: {MD30240: [4], MD34210: [2]}\nZ1: {MD30240: [4], MD34210: [2]}\n"
                "Y1: {MD30240: [4], MD34210: [2]}")


@lru_cache(maxsize=32)
def machine(overrides: str = "", path: str = TURN_MILL) -> MachineConfig:
    """A shipped machine with machine data overrides given as YAML text."""
    if not overrides:
        return load_machine(path)
    document, problems = load_text(overrides, "<test>")
    assert not problems, problems
    return load_machine(path, document, "<test>")


def with_start_position(config: MachineConfig, axis: str, position: float) -> MachineConfig:
    """The same machine with the slide of ``axis`` standing at ``position`` at power-on."""
    axes = tuple(
        dataclasses.replace(item, sim=dataclasses.replace(item.sim, start_position=position))
        if item.name == axis else item
        for item in config.axes
    )
    return dataclasses.replace(config, axes=axes)


class Rig:
    def __init__(self, config: MachineConfig, plc: str | None = None):
        self.sim = Simulation(config, plc=plc)
        self.nck = self.sim.nck

    # ------------------------------------------------------------------ signals
    def get(self, name: str) -> Value:
        """An interface signal as the NC shows it (NC->PLC) or as the PLC wrote it (PLC->NC)."""
        return self.sim.read(self.sim.catalog.resolve(name))

    def set(self, name: str, value: Value) -> None:
        """Write a PLC->NC signal (the test acts as the PLC)."""
        self.sim.write(self.sim.catalog.resolve(name), value)

    def io(self, name: str) -> Value:
        return self.sim.read(self.sim.plant_io.resolve(name))

    def press(self, name: str, value: Value = 1) -> None:
        """Operator: press (or set) a panel key or switch."""
        self.sim.write(self.sim.plant_io.resolve(name), value)

    def release(self, name: str) -> None:
        self.sim.write(self.sim.plant_io.resolve(name), 0)

    # ------------------------------------------------------------------ time
    def step(self, cycles: int = 1) -> None:
        self.sim.step(cycles)

    def run_until(self, condition: Callable[[], bool], max_cycles: int, step: int = 1) -> int:
        """Step until ``condition`` holds; return the cycles it took (fails after ``max_cycles``)."""
        taken = 0
        while not condition():
            assert taken < max_cycles, f"condition not reached within {max_cycles} cycles"
            self.sim.step(step)
            taken += step
        return taken

    def tap(self, name: str, scans: int = 2) -> None:
        """Operator: press a panel key long enough for the PLC to see it, then let go."""
        period = self.sim.plc_period
        self.press(name)
        self.step(scans * period)
        self.release(name)
        self.step(scans * period)

    def pulse(self, name: str, cycles: int = 1) -> None:
        """PLC (the test): set an edge-triggered PLC->NC signal for ``cycles`` IPO cycles."""
        self.set(name, 1)
        self.step(cycles)
        self.set(name, 0)

    # ------------------------------------------------------------------ the test as PLC
    def enable_axes(self, *axes: str, override: int = 100) -> None:
        """Measuring system 1, controller and pulse enable, axis override active at ``override`` percent."""
        for axis in axes or tuple(a.name for a in self.nck.axes):
            self.set(f"{axis}.basic.out.enc1Activation", 1)
            self.set(f"{axis}.basic.out.enableCtrl", 1)
            self.set(f"{axis}.drive.out.enablePulses", 1)
            self.set(f"{axis}.basic.out.enableOvr", 1)
            self.set(f"{axis}.basic.out.feedrateOvrFactor", override)

    def channel_overrides(self, feed: int = 100, rapid: int = 100, channel: str = "CHAN1") -> None:
        self.set(f"{channel}.basic.out.pathFeedrateOvr", 1)
        self.set(f"{channel}.basic.out.pathFeedrateOvrFactor", feed)
        self.set(f"{channel}.basic.out.pathRapidTraversOvr", 1)
        self.set(f"{channel}.basic.out.pathRapidTraversOvrFactor", rapid)

    def select_mode(self, mode: str) -> None:
        """``mode`` = auto / mda / jog: one-hot DB11.DBX0.0..0.2."""
        for name in ("auto", "mda", "jog"):
            self.set(f"MODEGROUP.basic.out.{name}Mode", int(name == mode))

    def ready_mda(self, *axes: str, feed: int = 100, rapid: int = 100) -> None:
        """Enables, overrides and MDA selected; steps until the NC shows MDA."""
        self.enable_axes(*axes)
        self.channel_overrides(feed, rapid)
        self.select_mode("mda")
        self.step(2)
        assert self.get("MODEGROUP.basic.in.mdaModeActive") == 1

    def mda(self, text: str, channel: str = "CHAN1") -> None:
        """Load ``text`` into the MDA buffer and give NC start (edge)."""
        self.sim.load_mda(channel, text)
        self.pulse(f"{channel}.basic.out.ncStart")

    # ------------------------------------------------------------------ NC state
    def axis(self, name: str) -> MachineAxis:
        return self.nck.axes_by_name[name]

    @property
    def channel(self) -> Channel:
        return self.nck.channels[0]

    def alarm_numbers(self) -> list[int]:
        return [alarm.number for alarm in self.sim.alarms()]

    def history_numbers(self) -> list[int]:
        return [alarm.number for alarm in self.sim.alarm_history()]

    def program_state(self, channel: str = "CHAN1") -> dict[str, Value]:
        """DB21.DBX35.0..35.7 by name."""
        names = ("progStateRunning", "progStateWaiting", "progStateStopped", "progStateInterrupted",
                 "progStateAborted", "stateActive", "stateInterrupted", "stateReset")
        return {name: self.get(f"{channel}.basic.in.{name}") for name in names}


def spindle_rig(extra: str = "", base: str = ABSOLUTE_XYZ) -> Rig:
    """The machine (``base`` machine data, then ``extra``) in MDA with the overrides at 100 %; the PLC
    reports SP1's gearbox in stage 1 (16.0-16.2), which the NC takes over in reset state."""
    rig = Rig(machine(base + ("\n" + extra if extra else "")))
    rig.ready_mda()
    for name in ("SP1", "SP2"):
        rig.set(f"{name}.spindle.out.ovrFactor", 100)
    rig.set("SP1.spindle.out.gearStageSelection", 1)
    rig.step(12)
    return rig
