"""The mode group (DB11): operating mode, machine function REF, mode-group reset.

The PLC selects a mode with level signals DB11.DBX0.0 (AUTOMATIC), 0.1 (MDA), 0.2 (JOG);
if several are set, JOG wins over MDA over AUTOMATIC, as on the control.  A mode change
is refused while a channel of the mode group is active (a program running); the
selection then waits until the channel is stopped or reset.  REF (DB11.DBX1.2) is a
machine function inside JOG or MDA.  DB11.DBX0.7 resets every channel of the group.

Published as one state machine (``MODE_GROUP_STATES``): the mode, with REF as a state of its own
inside JOG and MDA::

    JOG, MDA, AUTO ──DB11.DBX0.2 / 0.1 / 0.0, no channel active──▶ the mode selected
    JOG ──DB11.DBX1.2──▶ JOG REF ──DB11.DBX1.2 = 0──▶ JOG          (MDA and MDA REF alike)
    JOG REF ──MDA or AUTOMATIC selected: REF ends with JOG──▶ MDA, AUTO
"""

from __future__ import annotations

from interfaces.signal_groups import ModeGroupRequests, ModeGroupStatus
from vc.core.channel.program_run import Mode
from vc.core.interface_map import SignalTable
from vc.core.state_machine import Instance, StateMachine, states, transitions


class ModeGroup:
    def __init__(self, table: SignalTable, area: bytearray):
        self._decode = table.codec(ModeGroupRequests).decode
        self._encode = table.codec(ModeGroupStatus).encode
        self._inputs = ModeGroupRequests()
        self._area = area
        self.mode = Mode.JOG  # power-on default mode (MD10720, see power_on)
        self.reference_function = False
        self.requested = Mode.JOG
        self.reset_edge = False
        self._reset_level = False
        self._ref_requested = False

    def power_on(self, mode: Mode) -> None:
        """The mode the NC selects itself at power-on (MD10720, MD10721), until the PLC selects one."""
        self.mode = self.requested = mode

    def decode_inputs(self) -> None:
        inp = self._inputs
        self._decode(self._area, inp)
        if inp.jog:
            self.requested = Mode.JOG
        elif inp.mda:
            self.requested = Mode.MDA
        elif inp.auto:
            self.requested = Mode.AUTO
        self.reset_edge = inp.reset and not self._reset_level
        self._reset_level = inp.reset
        self._ref_requested = inp.ref

    def update(self, any_channel_active: bool) -> bool:
        """Apply the selection; returns True if the mode changed this cycle."""
        changed = False
        if self.requested is not self.mode and not any_channel_active:
            self.mode = self.requested
            changed = True
        self.reference_function = self._ref_requested and self.mode in (Mode.JOG, Mode.MDA)
        return changed

    def write_outputs(self, ready: bool) -> None:
        mode = self.mode
        self._encode(self._area, ModeGroupStatus(auto_active=mode is Mode.AUTO, mda_active=mode is Mode.MDA,
                                                 jog_active=mode is Mode.JOG, ready=ready,
                                                 ref_active=self.reference_function))


# the state of the mode group for observers: JOG, MDA, AUTO; JOG REF and MDA REF with the machine function REF
_STATE_NAMES = {(mode, ref): f"{mode.value} REF" if ref else mode.value for mode in Mode for ref in (False, True)}

MODE_GROUP_STATES: StateMachine[ModeGroup] = StateMachine(
    __name__, "mode_group", "Mode group: operating mode and machine function REF (DB11)", Instance.MODE_GROUP,
    states(("JOG", "JOG (DB11.DBX6.2)"), ("JOG REF", "JOG with the machine function REF (DB11.DBX7.2)"),
           ("MDA", "MDA (DB11.DBX6.1)"), ("MDA REF", "MDA with the machine function REF"),
           ("AUTO", "AUTOMATIC (DB11.DBX6.0)")),
    transitions(("JOG", "MDA", "DB11.DBX0.1"), ("MDA", "JOG", "DB11.DBX0.2"),
                ("JOG", "AUTO", "DB11.DBX0.0"), ("AUTO", "JOG", "DB11.DBX0.2"),
                ("MDA", "AUTO", "DB11.DBX0.0"), ("AUTO", "MDA", "DB11.DBX0.1"),
                ("JOG", "JOG REF", "DB11.DBX1.2 in JOG"), ("JOG REF", "JOG", "DB11.DBX1.2 = 0"),
                ("MDA", "MDA REF", "DB11.DBX1.2 in MDA"), ("MDA REF", "MDA", "DB11.DBX1.2 = 0"),
                ("JOG REF", "MDA", "DB11.DBX0.1: REF ends with JOG"),
                ("JOG REF", "AUTO", "DB11.DBX0.0: REF ends with JOG")),
    read=lambda group: _STATE_NAMES[(group.mode, group.reference_function)])
