"""Reading the states of a running NC's state machines, from outside, once per IPO cycle.

:func:`state_probes` builds one :class:`StateProbe` per instance the NC publishes in its state
view (``vc.simulation.published``: the mode group, each channel, spindle and axis), with the
coverage it reports to.  Nothing in the NC changes for it; a probe only reads.
:meth:`StateProbe.check` costs one read and one comparison while the state stands, which is
almost always.

A transition counts for the state machine the instance is in after it: referencing is one state
machine per procedure, and an axis is in the procedure it started last.
"""

from __future__ import annotations

from vc.coverage.data import CoverageData, FunctionCoverage
from vc.simulation.published import InstanceState, StateView


class StateProbe:
    """One instance of a state machine: reads its state and reports what it enters."""

    __slots__ = ("data", "instance", "last", "source")

    def __init__(self, source: InstanceState, data: CoverageData, instance: str):
        self.source = source
        self.data = data
        self.instance = instance
        self.last = source.state()
        self._function().entered(self.last)

    def _function(self) -> FunctionCoverage:
        function = self.data.function(self.source.machine().name)
        function.instances.add(self.instance)
        return function

    def check(self) -> None:
        state = self.source.state()
        if state is self.last or state == self.last:
            return
        before, self.last = self.last, state
        self._function().took(before, state)


def state_probes(view: StateView, data: CoverageData, machine: str) -> list[StateProbe]:
    """A probe for every instance of every state machine of ``view`` (a power-on of ``machine``)."""
    return [StateProbe(source, data, f"{machine}/{source.instance}") for source in view.instances]
