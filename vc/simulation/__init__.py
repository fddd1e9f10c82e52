"""The composed machine: NC, plant and PLC in lockstep, below every user of it.

``lockstep``        :class:`Simulation`, one IPO cycle of NC, plant and PLC at a time
``observables``     the names a scenario, the FMU and a recording may read or inject
``observed``        the simulation with its operator actions seen by observers (recording, coverage)
``published``       what the NC publishes for observers: its state machines' states, its alarms
``link_faults``     faults of the wire between NC and PLC, the kinds a link may take
``commissioning``   the commissioning facts of a machine handed to the PLC program

The harness (links, serving, benchmarks), the scenario runner, the FMU, recording and coverage
build on it; it imports none of them.
"""
