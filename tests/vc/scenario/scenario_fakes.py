"""A small stand-in for the harness: implements ScenarioTarget over a ProcessImage.

It is not an NC: a test gives it a ``behaviour`` that runs once per cycle.  ``SimpleNc`` is
the behaviour most runner tests use: NC start runs the MDA block ``G1 X<pos> F<feed>``
on X1 and reports "exact stop fine" when X1 arrives.
"""

from __future__ import annotations

import re
import shutil
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

from interfaces.catalog import load_catalog
from interfaces.image import ProcessImage, Value
from interfaces.signals import SignalRef, expand
from vc.config.loader import load_machine
from vc.config.model import MachineConfig
from vc.core.alarms import ALARM_TEXTS, Alarm, Clear
from vc.scenario.language.loader import load_scenario
from vc.scenario.language.model import Scenario

HERE = Path(__file__).parent
CORPUS = HERE / "language" / "bad_scenarios"
MACHINE_FILE = CORPUS / "machines" / "mini.yaml"
KNOWN_PROGRAMS = ("basic_machine", "referencing")

Behaviour = Callable[["FakeTarget"], None]


def machine() -> MachineConfig:
    return load_machine(str(MACHINE_FILE))


def write_scenario(directory: Path, text: str, name: str = "scenario.yaml") -> Path:
    """Write a scenario next to a copy of the test machine (``machines/mini.yaml``)."""
    (directory / "machines").mkdir(exist_ok=True)
    shutil.copy(MACHINE_FILE, directory / "machines" / "mini.yaml")
    path = directory / name
    path.write_text(text, encoding="utf-8")
    return path


def scenario(directory: Path, text: str, name: str = "scenario.yaml") -> Scenario:
    return load_scenario(str(write_scenario(directory, text, name)), KNOWN_PROGRAMS)


class FakeTarget:
    def __init__(self, config: MachineConfig, behaviour: Behaviour | None = None, ipo_cycle_us: int = 2000):
        self.machine = config
        self.catalog = expand(load_catalog(), config.layout)
        self.plant_io = config.plant_io
        self.image = ProcessImage({**self.catalog.area_sizes, **self.plant_io.area_sizes()})
        self.behaviour = behaviour
        self._cycle = 0
        self._ipo_cycle_us = ipo_cycle_us
        self.forces: dict[SignalRef, Value] = {}
        self.axes: dict[str, dict[str, float]] = {
            axis.name: dict.fromkeys(("position", "setpoint", "velocity", "followingError", "physical"), 0.0)
            for axis in config.axes
        }
        self.present: list[Alarm] = []
        self.raised: list[Alarm] = []
        self.mda: dict[str, str] = {}
        self.programs: dict[str, tuple[str, str]] = {}
        self.writes: list[tuple[int, str, Value]] = []

    @property
    def cycle(self) -> int:
        return self._cycle

    @property
    def ipo_cycle_us(self) -> int:
        return self._ipo_cycle_us

    def step(self, cycles: int = 1) -> None:
        for _ in range(cycles):
            self._cycle += 1
            if self.behaviour is not None:
                self.behaviour(self)
            for ref, value in self.forces.items():
                self.image.write(ref, value)

    def read(self, ref: SignalRef) -> Value:
        return self.image.read(ref)

    def write(self, ref: SignalRef, value: Value) -> None:
        self.writes.append((self._cycle, ref.name, value))
        self.image.write(ref, value)

    def force(self, ref: SignalRef, value: Value) -> None:
        self.forces[ref] = value
        self.image.write(ref, value)

    def release(self, ref: SignalRef) -> None:
        self.forces.pop(ref, None)

    def axis_quantity(self, axis: str, quantity: str) -> float:
        return self.axes[axis][quantity]

    def alarms(self) -> Sequence[Alarm]:
        return list(self.present)

    def alarm_history(self) -> Sequence[Alarm]:
        return list(self.raised)

    def load_mda(self, channel: str, text: str) -> None:
        self.mda[channel] = text

    def select_program(self, channel: str, name: str, text: str) -> None:
        self.programs[channel] = (name, text)

    # helpers for behaviours

    def get(self, name: str) -> Value:
        return self.image.read(self._ref(name))

    def set(self, name: str, value: Value) -> None:
        self.image.write(self._ref(name), value)

    def _ref(self, name: str) -> SignalRef:
        try:
            return self.catalog.resolve(name)
        except KeyError:
            return self.plant_io.resolve(name)

    def raise_alarm(self, number: int, axis: str = "") -> None:
        definition = ALARM_TEXTS[number]
        alarm = Alarm(number, definition.text, definition.reaction, definition.clear, "CHAN1", axis,
                      self._cycle)
        self.present.append(alarm)
        self.raised.append(alarm)

    def acknowledge_alarms(self) -> None:
        self.present = [alarm for alarm in self.present if alarm.clear is not Clear.CANCEL]


class ImageFakeTarget(FakeTarget):
    """The same, offering the recorder's fast path."""

    def image_areas(self) -> Mapping[str, bytearray]:
        return self.image.areas


class CachingImageFakeTarget(FakeTarget):
    """Offers images composed once per cycle (as the harness does): writes between two cycles
    show in them only after the next cycle."""

    def __init__(self, config: MachineConfig, behaviour: Behaviour | None = None):
        super().__init__(config, behaviour)
        self._composed: dict[str, bytearray] = {}
        self._composed_cycle = -1

    def image_areas(self) -> Mapping[str, bytearray]:
        if self._composed_cycle != self.cycle:
            self._composed_cycle = self.cycle
            self._composed = {key: bytearray(area) for key, area in self.image.areas.items()}
        return self._composed


class SimpleNc:
    """NC start (CHAN1.basic.out.ncStart rising) runs ``G1 X<pos> F<feed>`` from the MDA buffer on X1."""

    def __init__(self) -> None:
        self.start_before = 0
        self.target_position: float | None = None
        self.feed = 0.0

    def __call__(self, target: FakeTarget) -> None:
        start = target.get("CHAN1.basic.out.ncStart")
        if start and not self.start_before:
            match = re.match(r"G1 X(?P<x>-?[0-9.]+) F(?P<f>[0-9.]+)", target.mda.get("CHAN1", ""))
            if match:
                self.target_position = float(match.group("x"))
                self.feed = float(match.group("f"))
                target.set("X1.basic.in.posFineReached", 0)
                target.set("CHAN1.basic.in.stateReset", 0)
        self.start_before = int(start)
        axis = target.axes["X1"]
        if self.target_position is None:
            axis["velocity"] = 0.0
            return
        if axis["position"] == self.target_position:  # arrived in the cycle before: at standstill now
            axis["velocity"] = 0.0
            target.set("X1.basic.in.posFineReached", 1)
            target.set("CHAN1.basic.in.stateReset", 1)
            self.target_position = None
            return
        step = self.feed / 60.0 * target.ipo_cycle_us / 1e6  # mm per cycle
        distance = self.target_position - axis["position"]
        move = max(-step, min(step, distance))
        axis["position"] = self.target_position if abs(distance) <= step + 1e-9 else axis["position"] + move
        axis["setpoint"] = axis["position"]
        axis["velocity"] = abs(move) / (target.ipo_cycle_us / 1e6) * 60.0
