"""manual_retraction: the spindle program plus manual retraction along the tool axis.

After a tapping or thread block was aborted by a reset or by power failure, the NC shows
"retract data available" (DB21.DBX377.5, seed 003 §16.12).  The machine builder's PLC
operates the function from the panel, as the seed asks of the PLC user program (L35472-35494).
Networks after those of ``spindle`` (1-9):

0. Mode, before network 2 writes it: in its first scan the PLC keeps the mode the NC selected
   itself at power-on (MD10720, or JOG by MD10721 with retract data) instead of selecting JOG;
   when 377.5 rises (also: found at the first scan) it selects JOG (DB11.DBX0.2).

10. Manual retraction, per channel::

        377.5, JOG active, channel in reset (35.7), 377.4 = 0, and either the first chance
        since 377.5 rose or the NC start key ──▶ REQUEST: DB21.DBX396.0 = 1 (PI service RETRAC)
        REQUEST ──397.0 (done) or 397.1 (refused)──▶ request off

    The traverse keys of the panel go to the axes as in JOG (network 4): the NC lets only the
    tool axis move, in its plus direction unless MD10735 bit 8.  NC stop pauses the
    retraction and NC start continues it (network 3 passes the keys on).  RESET cancels it
    (network 3); the data stay, and the NC start key selects it again from where the tool
    stands.  Back in AUTOMATIC, the axes are referenced and NC start continues the program,
    which deletes the data (377.5 = 0).

11. Coordinate system of the operator panel: the MCS/WCS softkey (DB19.DBX20.7, rising edge)
    toggles DB19.DBX0.7 (1 = WCS); when 377.4 rises the PLC selects the WCS, in which the
    retraction traverses the tool axis (SEQ-MR step 7, L35486-35488).

12. Handwheels from the panel (``handwheel_selection.py``): each handwheel's axis selector
    assigns it to a machine axis (DB31.DBX4.0..4.2) or a geometry axis (DB21.DBX12.0..2 ff.), the
    increment keys select INC1 .. INC10000 for them; the retraction's tool axis takes the
    handwheel whether it is selected as machine axis or as geometry axis.

The selection through DB21.DBX396.0 / 397.0 / 397.1 stands in for FB4 with the PI service
"RETRAC" (REQ, DONE, ERROR): a project-specific location of this harness.  The networks are a
function block (``ManualRetractionNetworks``), so that ``retraction`` runs them as well.
"""

from __future__ import annotations

from dataclasses import dataclass

from interfaces.signal_groups import RetractionStatus
from plc_stub.blocks import R_TRIG
from plc_stub.io import Bool, GroupInput, PlcIo
from plc_stub.programs.basic_machine import BasicMachine, pressed
from plc_stub.programs.handwheel_selection import HandwheelSelection
from plc_stub.programs.spindle import Spindle

_ACTIVE_MODE_SIGNALS = (("auto", "MODEGROUP.basic.in.autoModeActive"), ("mda", "MODEGROUP.basic.in.mdaModeActive"),
                        ("jog", "MODEGROUP.basic.in.jogModeActive"))


@dataclass(slots=True)
class _RetractionChannel:
    status: GroupInput[RetractionStatus]  # DB21.DBX377.5 data available, 377.4 active, 397.0 done, 397.1 refused
    in_reset: Bool  # DB21.DBX35.7
    request: Bool  # DB21.DBX396.0: PI service RETRAC
    data_edge: R_TRIG
    active_edge: R_TRIG
    first_chance: bool = False  # 377.5 rose and no selection was tried since


class ManualRetractionNetworks:
    """Networks 0, 10, 11 and 12 as a function block, for any program built on ``basic_machine``:
    call ``mode`` before the program's network 2 and ``selection`` after its network 4."""

    def __init__(self, io: PlcIo):
        self.active_modes = {mode: io.input(name) for mode, name in _ACTIVE_MODE_SIGNALS}
        self.first_scan = True
        self.start_key_edge = R_TRIG()
        self.show_wcs = io.output("HMI.basic.out.displayWcsValues")  # DB19.DBX0.7
        self.mcs_wcs_softkey = io.input("HMI.basic.in.mcsWcsSwitched")  # DB19.DBX20.7
        self.softkey_edge = R_TRIG()
        self.handwheels = HandwheelSelection(io)
        self.channels = [
            _RetractionChannel(
                status=io.input_group(RetractionStatus, name),
                in_reset=io.input(f"{name}.basic.in.stateReset"),
                request=io.output(f"{name}.piService.out.retracRequest"),
                data_edge=R_TRIG(),
                active_edge=R_TRIG(),
            )
            for name in io.environment.catalog.layout.channels
        ]

    # Network 0 ---------------------------------------------------------------------------
    def mode(self, program: BasicMachine) -> None:
        if self.first_scan:
            self.first_scan = False
            for mode, active in self.active_modes.items():
                if active.value:
                    program.selected_mode = mode
        for channel in self.channels:
            if channel.data_edge(channel.status.read().data_available):
                program.selected_mode = "jog"
                program.reference_function = False
                channel.first_chance = True

    # Network 10 --------------------------------------------------------------------------
    def selection(self, program: BasicMachine) -> None:
        start = self.start_key_edge(pressed(program.key_nc_start))
        jog = self.active_modes["jog"].value and not program.reference_function
        for channel in self.channels:
            status = channel.status.read()
            if channel.request.value:
                channel.request.value = not (status.done or status.error)
                continue
            selectable = status.data_available and jog and channel.in_reset.value and not status.active
            if selectable and (channel.first_chance or start):
                channel.first_chance = False
                channel.request.value = True
        self.coordinate_system()
        self.handwheels(program.panel_increment)

    # Network 11 --------------------------------------------------------------------------
    def coordinate_system(self) -> None:
        if self.softkey_edge(self.mcs_wcs_softkey.value):
            self.show_wcs.value = not self.show_wcs.value
        for channel in self.channels:
            if channel.active_edge(channel.status.read().active):
                self.show_wcs.value = True


class ManualRetraction(Spindle):
    PROGRAM = "manual_retraction"

    def __init__(self, io: PlcIo):
        super().__init__(io)
        self.retraction_networks = ManualRetractionNetworks(io)

    def ob1(self) -> None:
        self.retraction_networks.mode(self)
        super().ob1()
        self.retraction_networks.selection(self)
