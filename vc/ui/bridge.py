"""The NC's side of the operator page: an observer of the served simulation.

The NC runs in the main thread, the page's server in its own (``vc/ui/server.py``).  They meet
only here, in two one-way hand-overs, so the web server never touches the simulation and the NC
never waits for the web::

    page -> NC   a command (press a key, force, release, MDA, watch ...) is appended to
                 ``commands`` (a deque: appending and popping are atomic); after every IPO cycle
                 the NC thread takes what is there, does it as the operator's action
                 (:func:`vc.simulation.observed.perform`) and tells the recording, then hands the
                 answer (done, or the refusal and why) back to the server's event loop
    NC -> page   at most every ``update_period_s`` of the wall clock the NC thread composes a
                 snapshot (plain values) and hands it to the server's loop, which sends only the
                 latest to each page (coalesced: a slow page skips snapshots, it never queues them)

While no page is open and no command waits, the observer returns at once after each cycle; without
``--ui`` it does not exist.  Commands are checked against :class:`vc.ui.panel.Rules` here, where the
machine is known; a page gets its refusal as a sentence.
"""

from __future__ import annotations

import math
import time as wallclock
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from interfaces.image import Value
from interfaces.plant_io import PointOwner
from interfaces.signals import SignalRef, UnknownSignalError
from vc.simulation.lockstep import Simulation
from vc.simulation.observed import OperatorAction, SimulationObserver, perform, resolve
from vc.ui.connection import connection_state
from vc.ui.panel import Rules, lamps, panel_controls
from vc.ui.recording import PageRecording
from vc.ui.scope import Scope

UPDATE_PERIOD_S = 0.1  # what a person reads: 10 snapshots a second
MAX_WATCHED = 200  # signals in one page's watch table
MAX_MDA_CHARACTERS = 16_384  # an MDA program typed or pasted into the page

Reply = Callable[[bool, str], None]


@dataclass(slots=True)
class Command:
    """What a page asks of the NC; ``reply`` is called in the NC thread with (done, message)."""

    kind: str  # key, force, release, mda, acknowledge, handwheel, watch, record, scope, scope_copy, closed
    page: int
    peer: str  # the page's address (the force rules)
    arguments: dict[str, Any] = field(default_factory=dict)
    reply: Reply = lambda done, message: None


class OperatorBridge:
    """A :class:`~vc.simulation.observed.SimulationObserver` that serves the operator page (see the module
    docstring); ``recorder`` is the session recording (``--record``), told of every cycle and of the
    page's actions as of a scenario's."""

    def __init__(self, allow_writers: tuple[str, ...] = (), recorder: SimulationObserver | None = None,
                 update_period_s: float = UPDATE_PERIOD_S):
        self.allow_writers = allow_writers
        self.recorder = recorder
        self.recording = PageRecording(recorder)  # ended from the page, turned into a scenario
        self.scope = Scope()  # the live scope's lanes and samples (vc/ui/scope.py)
        self.update_period_s = update_period_s
        self.commands: deque[Command] = deque()
        self.pages = 0  # open pages, counted by the server
        self.publish: Callable[[dict[str, Any]], None] = lambda snapshot: None  # set by the server
        self.announce: Callable[[dict[str, Any]], None] = lambda description: None  # set by the server
        self.description: dict[str, Any] | None = None  # the machine's panel, for a page that opens
        self._rules: Rules | None = None
        self._watched: dict[int, dict[str, SignalRef]] = {}  # page -> name typed -> signal
        self._next_publish = 0.0
        self._power_ons = 0
        self._panel: list[tuple[str, SignalRef]] = []  # the panel's keys, switches and lamps

    # ------------------------------------------------------------------ the observer (NC thread)
    def attached(self, simulation: Simulation) -> None:
        self._power_ons += 1
        self._rules = Rules(simulation.plant_io, self.allow_writers)
        self._panel = [(point.name, point.ref()) for point in simulation.plant_io.points
                       if point.owner is PointOwner.OPERATOR or point.name.startswith("Lamp.")]
        self.description = describe(simulation, self._power_ons, bool(self.allow_writers))
        self.announce(self.description)
        self._next_publish = 0.0
        if self.recorder is not None:
            self.recorder.attached(simulation)

    def cycle_done(self, simulation: Simulation) -> None:
        if self.recorder is not None and not self.recording.ended:  # ended from the page: nothing more to diff
            self.recorder.cycle_done(simulation)
        if not self.pages and not self.commands:
            return  # nobody looks: nothing of the page runs
        self.scope.sample(simulation)
        commands = self.commands
        while commands:
            self._do(simulation, commands.popleft())
        now = wallclock.monotonic()
        if now >= self._next_publish and self.pages:
            self._next_publish = now + self.update_period_s
            self.publish(self.snapshot(simulation))

    def acted(self, simulation: Simulation, action: OperatorAction) -> None:
        if self.recorder is not None and not self.recording.ended:
            self.recorder.acted(simulation, action)

    # ------------------------------------------------------------------ the page's commands
    def _do(self, simulation: Simulation, command: Command) -> None:
        try:
            message = self._perform(simulation, command)
        except (KeyError, ValueError, UnknownSignalError) as error:
            command.reply(False, _text(error))
            return
        except Exception as error:  # the simulation refused (a step it cannot take): the page says why
            command.reply(False, f"{type(error).__name__}: {_text(error)}")
            return
        if message.startswith("refused: "):
            command.reply(False, message.removeprefix("refused: "))
        else:
            command.reply(True, message)

    def _perform(self, simulation: Simulation, command: Command) -> str:
        kind, arguments, rules = command.kind, command.arguments, self._rules
        assert rules is not None  # attached before the first cycle
        if kind == "closed":
            self._watched.pop(command.page, None)
            return "closed"
        if kind == "watch":
            return self._watch(simulation, command.page, arguments["names"])
        if kind == "key":
            name, value = str(arguments["name"]), float(arguments["value"])
            refusal = rules.key_refusal(name, value)
            if refusal:
                return f"refused: {refusal}"
            self._act(simulation, OperatorAction("write", (name, int(value))))
            return f"{name} = {int(value)}"
        if kind == "force":
            name, value = str(arguments["name"]), float(arguments["value"])
            ref = resolve(simulation, name)
            refusal = rules.force_refusal(ref, value, command.peer)
            if refusal:
                return f"refused: {refusal}"
            self._act(simulation, OperatorAction("force", (ref.name, _number(value))))
            return f"{ref.name} forced to {value:g}"
        if kind == "release":
            ref = resolve(simulation, str(arguments["name"]))
            if ref not in simulation.forced():
                return f"refused: {ref.name} is not forced"
            self._act(simulation, OperatorAction("release", (ref.name,)))
            return f"{ref.name} released"
        if kind == "mda":
            channel, text = str(arguments["channel"]), str(arguments["text"])
            if len(text) > MAX_MDA_CHARACTERS:
                return f"refused: the MDA program has more than {MAX_MDA_CHARACTERS} characters"
            if channel not in {item.name for item in simulation.machine.channels}:
                return f"refused: this machine has no channel '{channel}'"
            self._act(simulation, OperatorAction("mda", (channel, text)))
            return f"MDA program loaded into {channel}: select MDA and press NC START"
        if kind == "scope":
            return self.scope.pick(simulation, [str(name) for name in arguments["names"]], arguments["seconds"])
        if kind == "scope_copy":  # the server's VCD download: the ring copied between two cycles
            arguments["into"].append(self.scope.recording(simulation.ipo_cycle_us))
            return "copied"
        if kind == "record":
            return self.recording.command(str(arguments.get("action")))
        if kind == "acknowledge":
            self._act(simulation, OperatorAction("acknowledge", ()))
            return "alarms acknowledged (cancel key)"
        if kind == "handwheel":
            number, detents = int(arguments["number"]), int(arguments["detents"])
            if not 1 <= number <= 3 or not -1000 <= detents <= 1000:
                return "refused: handwheel 1..3, -1000..1000 detents at a time"
            self._act(simulation, OperatorAction("handwheel", (number, detents, max(1, abs(detents)))))
            return f"handwheel {number} turned {detents:+d} detents"
        return f"refused: unknown command '{kind}'"

    def _act(self, simulation: Simulation, action: OperatorAction) -> None:
        perform(simulation, action)
        self.acted(simulation, action)

    def _watch(self, simulation: Simulation, page: int, names: list[str]) -> str:
        if len(names) > MAX_WATCHED:
            return f"refused: at most {MAX_WATCHED} signals in one watch table"
        watched: dict[str, SignalRef] = {}
        unknown = []
        for name in names:
            try:
                watched[str(name)] = resolve(simulation, str(name))
            except (UnknownSignalError, KeyError, ValueError) as error:
                unknown.append(_text(error))
        self._watched[page] = watched
        if unknown:
            return "refused: " + "; ".join(unknown)
        return f"watching {len(watched)} signals"

    # ------------------------------------------------------------------ what the page shows
    def snapshot(self, simulation: Simulation) -> dict[str, Any]:
        """The machine as the page shows it now, as plain values."""
        forced = simulation.forced()
        watched = {name: ref for table in self._watched.values() for name, ref in table.items()}
        panel = {name: _plain(simulation.read(ref)) for name, ref in self._panel}
        return {
            "update": {
                "time_s": round(simulation.time_s, 6),
                "axes": [_axis(simulation, axis.name) for axis in simulation.machine.axes],
                "states": [[reading.machine, reading.instance, reading.state]
                           for reading in simulation.state_view()],
                "alarms": [{"number": alarm.number, "text": alarm.text, "channel": alarm.channel,
                            "axis": alarm.axis, "clear": str(alarm.clear)} for alarm in simulation.alarms()],
                "panel": panel,
                "watch": {name: {"symbol": ref.name, "address": str(ref.address), "value": _plain(simulation.read(ref)),
                                 "forced": ref in forced} for name, ref in watched.items()},
                "forces": {ref.name: _plain(value) for ref, value in forced.items()},
                "connection": connection_state(simulation),
                "recording": self.recording.state(),
                "scope": self.scope.take_unsent(simulation),
            }
        }


def describe(simulation: Simulation, power_on: int, writers_named: bool) -> dict[str, Any]:
    """The machine's panel and layout, sent to a page when it opens and after every power-on."""
    machine = simulation.machine
    return {
        "hello": {
            "machine": machine.name,
            "power_on": power_on,
            "controls": [{"name": control.name, "kind": str(control.kind), "group": control.group,
                          "label": control.label, "maximum": control.maximum}
                         for control in panel_controls(simulation.plant_io)],
            "lamps": lamps(simulation.plant_io),
            "axes": [axis.name for axis in machine.axes],
            "channels": [channel.name for channel in machine.channels],
            "writers_named": writers_named,
        }
    }


def _axis(simulation: Simulation, name: str) -> dict[str, Any]:
    quantity = simulation.axis_quantity
    return {"name": name, "spindle": bool(simulation.functions_of(name)),
            "position": _plain(quantity(name, "position")), "velocity": _plain(quantity(name, "velocity")),
            "following_error": _plain(quantity(name, "followingError")),
            "referenced": _referenced(simulation, name)}


def _referenced(simulation: Simulation, axis: str) -> bool:
    """Referenced / synchronized with either measuring system (DB31.DBX60.4 / 60.5)."""
    for signal in ("enc1Synchronized", "enc2Synchronized"):
        try:
            if simulation.read(simulation.catalog.resolve(f"{axis}.basic.in.{signal}")):
                return True
        except UnknownSignalError:
            continue
    return False


def _plain(value: Value) -> float | int | None:
    if isinstance(value, float):
        return round(value, 6) if math.isfinite(value) else None
    return value


def _number(value: float) -> float | int:
    return int(value) if value == int(value) else value


def _text(error: BaseException) -> str:
    return str(error.args[0]) if isinstance(error, KeyError) and error.args else str(error)
