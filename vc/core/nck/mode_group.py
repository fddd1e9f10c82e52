"""The mode group (DB11): operating mode, machine function REF, mode-group reset.

The PLC selects a mode with level signals DB11.DBX0.0 (AUTOMATIC), 0.1 (MDA), 0.2 (JOG);
if several are set, JOG wins over MDA over AUTOMATIC, as on the control.  A mode change
is refused while a channel of the mode group is active (a program running); the
selection then waits until the channel is stopped or reset.  REF (DB11.DBX1.2) is a
machine function inside JOG or MDA.  DB11.DBX0.7 resets every channel of the group.
"""

from __future__ import annotations

from vc.core.channel.program_run import Mode
from vc.core.interface_map import SignalTable


class ModeGroupSignals:
    def __init__(self, table: SignalTable):
        self.auto = table.bit("basic.out.autoMode")
        self.mda = table.bit("basic.out.mdaMode")
        self.jog = table.bit("basic.out.jogMode")
        self.reset = table.bit("basic.out.reset")
        self.ref = table.bit("basic.out.refPoint")
        self.auto_active = table.bit("basic.in.autoModeActive")
        self.mda_active = table.bit("basic.in.mdaModeActive")
        self.jog_active = table.bit("basic.in.jogModeActive")
        self.ready = table.bit("basic.in.ready")
        self.ref_active = table.bit("basic.in.refPointActive")


class ModeGroup:
    def __init__(self, signals: ModeGroupSignals, area: bytearray):
        self._signals = signals
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
        area, sig = self._area, self._signals
        if sig.jog.get(area):
            self.requested = Mode.JOG
        elif sig.mda.get(area):
            self.requested = Mode.MDA
        elif sig.auto.get(area):
            self.requested = Mode.AUTO
        reset = sig.reset.get(area)
        self.reset_edge = reset and not self._reset_level
        self._reset_level = reset
        self._ref_requested = sig.ref.get(area)

    def update(self, any_channel_active: bool) -> bool:
        """Apply the selection; returns True if the mode changed this cycle."""
        changed = False
        if self.requested is not self.mode and not any_channel_active:
            self.mode = self.requested
            changed = True
        self.reference_function = self._ref_requested and self.mode in (Mode.JOG, Mode.MDA)
        return changed

    def write_outputs(self, ready: bool) -> None:
        area, sig, mode = self._area, self._signals, self.mode
        sig.auto_active.put(area, mode is Mode.AUTO)
        sig.mda_active.put(area, mode is Mode.MDA)
        sig.jog_active.put(area, mode is Mode.JOG)
        sig.ready.put(area, ready)
        sig.ref_active.put(area, self.reference_function)
