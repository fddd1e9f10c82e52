"""retraction: the spindle program with the guard door, plus the PLC's part of extended stop and
retract (ESR), of fast retraction, and of manual retraction along the tool axis.

The NC reacts to ESR triggers that its part program sets up as static synchronized actions
(seed 003 L42180-42195); the PLC reaches them through the digital NCK inputs it sets in
DB10.DBB1 (``$A_IN[n]``).  Network 11 (after the door, network 10):

* ``$A_IN[1]`` (DB10.DBX1.0) = "retract now": the emergency-stop chain opened or the drive
  line-up reported a fault (``Drives.ready`` fell while the chain is closed).  A program with
  ``IDS=1 WHENEVER $A_IN[1]==1 DO $AC_ESR_TRIGGER=1`` retracts the tool.
* The emergency stop reaches the NC (DB10.DBX56.1) ``esr_time`` after the chain opened: the NC's
  e-stop brakes the axes and takes their enables, so the retraction must come first (a real
  machine's PLC delays it in the same way, with the safety relay's stop category 1 delay).
* A drive fault keeps the controller and pulse enables for ``esr_time`` (the DC link still holds
  the energy for the retraction), then they go as in ``basic_machine``.
* ``$A_IN[2]`` (DB10.DBX1.1) = "acknowledge ESR", one scan on the reset key's edge (the edge the
  guard door's network takes as well).  A program with
  ``IDS=5 EVERY $A_IN[2]==1 DO $AA_ESR_ENABLE[X]=0 $AN_ESR_TRIGGER=0`` and
  ``IDS=6 EVERY $A_IN[2]==0 DO $AA_ESR_ENABLE[X]=1`` gives the drives the enable edge 1 -> 0 -> 1
  that acknowledges their reaction (L41874-41907).

A lost PLC sign of life needs no network: the NC raises alarm 2000 and a synchronized action on
``$AC_ALARM_STAT B_AND 'H2000'`` triggers ESR in the NC.

A tool left in the thread after a reset or power failure is retracted by hand: networks 0 and 10
of ``manual_retraction`` (JOG when DB21.DBX377.5 rises, the PI service RETRAC) run here as well.

Parameters, besides those of ``spindle`` and the guard door (``guard_door``)::

    plc:
      esr_time: 0.3             # s from the trigger to the e-stop of the NC (and the end of the enables)
"""

from __future__ import annotations

from plc_stub.blocks import F_TRIG, TOF, TON
from plc_stub.io import PlcIo
from plc_stub.programs.guard_door import GuardedSpindle
from plc_stub.programs.manual_retraction import ManualRetractionNetworks
from plc_stub.programs.parameters import seconds

ESR_TIME_S = 0.3
RETRACT_INPUT = 1 << 0  # $A_IN[1]
ACKNOWLEDGE_INPUT = 1 << 1  # $A_IN[2]


class Retraction(GuardedSpindle):
    PROGRAM = "retraction"
    PARAMETERS = (*GuardedSpindle.PARAMETERS, "esr_time")

    def __init__(self, io: PlcIo):
        super().__init__(io)
        scan = io.environment.scan_time_s
        problems: list[str] = []
        esr_time = seconds(io.environment.parameters, "esr_time", ESR_TIME_S, problems)
        if problems:
            raise ValueError("\n".join(problems))
        # Network 11
        self.nck_inputs = io.output_byte("NC.basic.out.setDigitalInputs")
        self.emergency_stop_delay = TON(esr_time, scan)
        self.drive_fault_edge = F_TRIG()
        self.drive_fault_hold = TOF(esr_time, scan)
        self.drive_fault = False
        self.manual_retraction = ManualRetractionNetworks(io)  # networks 0 and 10 of manual_retraction

    def ob1(self) -> None:
        self.manual_retraction.mode(self)
        super().ob1()
        self.manual_retraction.selection(self)

    def process_networks(self, reset: bool) -> None:
        self.extended_stop_and_retract(reset)

    # Network 11 --------------------------------------------------------------------------
    def extended_stop_and_retract(self, reset: bool) -> None:
        """``reset``: the reset key's edge."""
        chain_ok = self.chain_ok.value if self.chain_ok is not None else True
        ready = self.drives_ready.value if self.drives_ready is not None else True
        if self.drive_fault_edge(ready) and chain_ok:
            self.drive_fault = True  # the line-up fell on its own: a drive fault
        if ready:
            self.drive_fault = False  # the line-up is back (after the operator's reset of the drives)
        retract = not chain_ok or self.drive_fault
        self.emergency_stop.value = self.emergency_stop_delay(not chain_ok)
        holding = self.drive_fault_hold(ready or not self.drive_fault)
        if self.drive_fault and holding:
            for axis in self.axes:  # the enables stay while the drives retract on the DC link's energy
                axis.controller_enable.value = True
                axis.pulse_enable.value = True
                axis.follow_up_mode.value = False
        self.nck_inputs.value = (RETRACT_INPUT if retract else 0) | (ACKNOWLEDGE_INPUT if reset else 0)
