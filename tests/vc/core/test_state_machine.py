"""The NC's state machines as it publishes them (vc/core/state_machine.py, vc/core/nck/state_view.py):
each declared once beside its enum, every instance read through the NCK's one state view."""

from __future__ import annotations

from enum import Enum
from importlib import import_module
from typing import Any

import pytest
from core_rig import FIVE_AXIS, MILL, TURN_MILL, Rig, machine

from vc.core.nck.state_view import PUBLISHED, STATE_MACHINES
from vc.core.state_machine import StateMachine, StateReading, Variants, machines_of


@pytest.mark.parametrize("declared", STATE_MACHINES, ids=lambda machine: machine.name)
def test_a_declaration_names_its_states_and_transitions_between_them(declared: StateMachine[Any]) -> None:
    names = [state.name for state in declared.states]
    assert len(names) == len(set(names)), "a state declared twice"
    assert all(state.meaning for state in declared.states)
    for transition in declared.transitions:
        assert {transition.before, transition.after} <= set(names), transition
        assert transition.before != transition.after and transition.trigger
    pairs = [(t.before, t.after) for t in declared.transitions]
    assert len(pairs) == len(set(pairs)), "a transition declared twice"


@pytest.mark.parametrize("declared", STATE_MACHINES, ids=lambda machine: machine.name)
def test_a_state_of_an_enum_is_its_member_in_the_declaring_module(declared: StateMachine[Any]) -> None:
    module = import_module(declared.module)
    assert (declared.path.replace("/", ".")[:-3]) == declared.module
    for state in declared.states:
        if state.enum:
            enum = getattr(module, state.enum)
            assert issubclass(enum, Enum) and enum[state.name].value == state.meaning


def test_every_state_machine_has_its_own_name_and_the_variants_share_theirs() -> None:
    names = [machine.name for machine in STATE_MACHINES]
    assert len(names) == len(set(names)) == 28
    for row in PUBLISHED:
        if isinstance(row.declaration, Variants):
            assert all(machine.name.startswith(f"{row.declaration.name}.") for machine in machines_of(row.declaration))


@pytest.mark.parametrize("path", [TURN_MILL, MILL, FIVE_AXIS])
def test_the_view_holds_every_instance_of_every_state_machine(path: str) -> None:
    rig = Rig(machine(path=path))
    nck = rig.nck
    view = nck.state_view()
    axes = [axis for axis in nck.axes if not axis.is_spindle]
    esr_channels = [channel for channel in nck.channels if channel.esr is not None]
    # the mode group; channel, program, auxiliary function output, constant cutting speed and manual
    # retraction of each channel, its two ESR state machines; mode, gear change and coupling of each
    # spindle; the drive's ESR and data sets of every axis, the referencing, the command axis, the PLC
    # axis type, the FC18 job, the traverse keys in JOG and JOG to a fixed point / position of every
    # axis that is no spindle (no machine has software cams or a shared drive here)
    assert not nck.software_cams.of
    assert not nck.shared_drives
    assert len(view.instances) == (1 + 5 * len(nck.channels) + 2 * len(esr_channels) + 3 * len(nck.spindles)
                                   + 2 * len(nck.axes) + 6 * len(axes))
    for reading in view:
        assert isinstance(reading, StateReading)
        declared = next(machine for machine in STATE_MACHINES if machine.name == reading.machine)
        assert declared.state(reading.state) is not None, reading
    assert view.state("mode_group", "MODEGROUP") == "JOG"
    assert view.state("gear_change", "X1") is None  # X1 is no spindle
    assert nck.state_view() is view


def test_the_view_follows_the_mode_group_and_the_referencing_procedure() -> None:
    rig = Rig(machine("CHAN1: {MD62800: 0}"))  # no inclined-axis control: X1 may reference first
    view = rig.nck.state_view()
    referencing = next(each for each in view.instances if each.name == "referencing" and each.instance == "X1")
    assert (referencing.machine().name, referencing.state()) == ("referencing.incremental_cam", "IDLE")
    rig.enable_axes("X1")
    rig.set("X1.basic.out.enc1Activation", 0)
    rig.set("X1.basic.out.enc2Activation", 1)  # the distance-coded scale
    rig.set("MODEGROUP.basic.out.jogMode", 1)
    rig.set("MODEGROUP.basic.out.refPoint", 1)
    rig.step(60)  # the drive is ready after 100 ms
    assert view.state("mode_group", "MODEGROUP") == "JOG REF"
    assert referencing.machine().name == "referencing.incremental_cam"  # no procedure started yet
    rig.set("X1.basic.out.traversKeyPlus", 1)
    rig.step(2)
    assert (referencing.machine().name, referencing.state()) == ("referencing.distance_coded", "DC_SEARCH")
    assert referencing.reading() == StateReading("referencing.distance_coded", "X1", "DC_SEARCH")
