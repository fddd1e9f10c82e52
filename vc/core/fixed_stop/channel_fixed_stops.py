"""The fixed stops of a channel's axes, as its block execution sees them.

A block's FXS / FXST / FXSW words go to the axes' :class:`FixedStop` when the block starts (the
setting data SD43500-43520 are written block-synchronously, L37807-37811); the block's motion waits
while one of its axes waits for the PLC; the path ends where an axis found its stop (its rest is
deleted, L37306); at the end point an axis still approaching has not reached its stop (20091); the
block changes once every fixed stop allows it.  A machine without the function has no entries and
the channel asks nothing.

A synchronized action's FXS / FXST / FXSW (L37125-37131, the examples L38047-38110) act in the IPO
cycle the action is done in: on an axis the path moves, the running block's path then ends at the
stop as for a programmed FXS.  On an axis that moves on its own (a synchronized action's POS, the
program's POSA: vc/core/axis/command_axis.py) the function follows that motion and the program's
blocks do not wait for it (L37775-37778).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

from vc.config.model import ChannelConfig
from vc.core.alarms import AlarmList
from vc.core.axis.axis import MachineAxis
from vc.core.fixed_stop.fixed_stop import NOT_POSSIBLE, STILL_ACTIVE, FixedStop, State
from vc.core.program.block_plan import BlockPlan
from vc.core.program.commands import FixedStopWords
from vc.core.program.sync_actions import VariableWrite

FIXED_STOP_VARIABLES = ("$AA_FXS", "$VA_FXS", "$VA_FXS_INFO")


def _set_values(fixed_stop: FixedStop, words: FixedStopWords) -> None:
    """FXST / FXSW of the block into the axis's setting data SD43510 / SD43520."""
    if words.torque is not None:
        fixed_stop.set_torque(words.torque)
    if words.window is not None:
        fixed_stop.set_window(words.window)


class ChannelFixedStops:
    def __init__(self, channel: str, alarms: AlarmList):
        self.channel = channel
        self._alarms = alarms
        self.of: dict[str, FixedStop] = {}  # by machine axis: the axes whose MD37000 allows it
        self.selected_by_action = False  # an action selected FXS: the running block looks at its axes again

    def add(self, fixed_stop: FixedStop) -> None:
        self.of[fixed_stop.name] = fixed_stop

    def apply(self, plan: BlockPlan, cycle: int) -> bool:
        """The block's words, and 20092 for a motion of an axis held at its stop.  False: refused
        with an alarm (20090 on an axis without the function, 20092); the program stops."""
        for name, words in plan.fixed_stop.items():
            fixed_stop = self.of.get(name)
            if fixed_stop is None:
                self._alarms.raise_alarm(NOT_POSSIBLE, cycle, name, channel=self.channel, axis=name)
                return False
            if words.switch == 1 and not fixed_stop.busy:
                # the block's FXST / FXSW act from its start: the selection takes them (L37237-37247)
                _set_values(fixed_stop, words)
            if words.switch == 1 and not fixed_stop.select(cycle):
                return False
        for name in (*plan.targets, *plan.positioning):  # a path or a POS / POSA motion
            fixed_stop = self.of.get(name)
            written = plan.fixed_stop.get(name)
            if fixed_stop is not None and fixed_stop.at_stop and (written is None or written.switch != 0):
                self._alarms.raise_alarm(STILL_ACTIVE, cycle, name, channel=self.channel, axis=name)
                return False
        for name, words in plan.fixed_stop.items():
            fixed_stop = self.of[name]
            if words.switch != 1:
                _set_values(fixed_stop, words)
            if words.switch == 0:
                fixed_stop.deselect()
        return True

    def write(self, write: VariableWrite, cycle: int) -> None:
        """A synchronized action's ``FXS[ax]=0|1``, ``FXST[ax]=``, ``FXSW[ax]=`` (checked when its block
        was decoded): at once into the axis's setting data.  FXS=1 on an axis without MD37000 raises
        20090, on one still selected 20092 (the seed's example guards it with $AA_FXS==0, L38099-38103)."""
        fixed_stop = self.of.get(write.index)
        if fixed_stop is None:
            self._alarms.raise_alarm(NOT_POSSIBLE, cycle, write.index, channel=self.channel, axis=write.index)
        elif write.name == "FXST":
            fixed_stop.set_torque(write.value)
        elif write.name == "FXSW":
            fixed_stop.set_window(write.value)
        elif not write.value:
            fixed_stop.deselect()
        elif fixed_stop.select(cycle):
            self.selected_by_action = True

    def _busy_of(self, axes: Iterable[MachineAxis]) -> list[FixedStop]:
        return [fixed_stop for axis in axes if (fixed_stop := self.of.get(axis.name)) is not None and fixed_stop.busy]

    def holds_motion(self, axes: Iterable[MachineAxis]) -> bool:
        """An axis of the block waits for the PLC (its enable, a deselection's acknowledgement)."""
        return any(fixed_stop.holds_motion for fixed_stop in self._busy_of(axes))

    def path_ended(self, axes: Iterable[MachineAxis], approaching: set[str]) -> bool:
        """An axis that approached its stop in this block found it or failed: the rest is deleted."""
        return any(fixed_stop.motion_ended and fixed_stop.name in approaching for fixed_stop in self._busy_of(axes))

    def approaching(self, axes: Iterable[MachineAxis]) -> set[str]:
        return {fixed_stop.name for fixed_stop in self._busy_of(axes)
                if fixed_stop.state in (State.WAIT_ENABLE, State.APPROACH)}

    def motion_finished(self, axes: Iterable[MachineAxis], cycle: int) -> None:
        for fixed_stop in self._busy_of(axes):
            fixed_stop.motion_finished(cycle)

    @property
    def block_may_change(self) -> bool:
        """Every fixed stop allows the block change; one on an axis moving on its own does not hold
        the program's blocks (L37775-37778)."""
        return all(fixed_stop.block_may_change or fixed_stop.single_axis for fixed_stop in self.of.values())

    def standing_at_stop(self, name: str) -> bool:
        """The axis stands at its stop (or failed at it): its end point is no exact-stop target."""
        fixed_stop = self.of.get(name)
        return fixed_stop is not None and fixed_stop.busy

    def reset(self) -> None:
        for fixed_stop in self.of.values():
            fixed_stop.reset()

    def reader(self, config: ChannelConfig, others: Callable[[str, str], float]) -> Callable[[str, str], float]:
        """The channel's reader of system variables with $AA_FXS[ax], $VA_FXS[ax] (the same outside
        a block search, L37592-37594) and $VA_FXS_INFO[ax] (L37867-37915) in front of ``others``:
        ``IF $AA_FXS[W]==2 GOTOF ...`` as in L37928-37941; an axis without the function reads 0."""
        def read(name: str, index: str) -> float:
            if name not in FIXED_STOP_VARIABLES:
                return others(name, index)
            axis = config.axis_for_program_name(index)
            if axis is None:
                raise KeyError(f"{name}[{index}]")
            fixed_stop = self.of.get(axis)
            if fixed_stop is None:
                return 0.0
            return float(fixed_stop.info if name == "$VA_FXS_INFO" else fixed_stop.aa_fxs)
        return read
