"""cams: the auxiliary-function program plus the way lubrication of a slide on a software cam.

Networks after those of ``auxiliary`` (1-10), for the axis ``cam_axis`` (docs/software_cams.md):

11. Software cams on (seed 003 §21.3.1, L41202-41230): DB31.DBX2.0 of the cam axis while it is
    referenced (DB31.DBX60.4 / 60.5), as the seed suggests tying the activation to referencing (L41219).  The
    NC answers with DB31.DBX62.0; when that does not come within ``cams_timeout`` (the axis parked,
    no measuring system, no cam pair assigned to it in MD10450) the PLC raises alarm 700030 and
    disables the feed until the reset key.  While 62.0 is missing the lubrication does not run.
12. Way lubrication, a step chain: every rising edge of the plus cam signal of pair ``lube_cam``
    (DB10.DBB114 ff.: the slide passed the plus cam going plus, L40950-40951) gives a pulse of oil
    ``lube_pulse`` long on ``Lube.pump``; an edge during a pulse does not prolong it::

        IDLE ──rising edge of the plus cam, cams active (62.0)──▶ PULSE: Lube.pump on
        PULSE ──lube_pulse elapsed──▶ IDLE: Lube.pump off

    The pulses count in ``strokes`` (the PLC's lubrication counter).  A machine without ``Lube.pump``
    wired has no lubrication: networks 11 and 12 do nothing.

Parameters (the machine file's ``plc:`` section or the scenario's ``plc_parameters:``), besides those of
``auxiliary``::

    plc:
      cam_axis: Z1          # the machine axis whose cams the program switches on (default: the first axis)
      lube_cam: 1           # the cam pair whose plus cam gives the pulse, 1..32
      lube_pulse: 0.5       # s of oil per pulse
      cams_timeout: 0.5     # s from DB31.DBX2.0 to DB31.DBX62.0 before alarm 700030
"""

from __future__ import annotations

from enum import Enum

from plc_stub.blocks import R_TRIG, TON
from plc_stub.io import Bool, PlcIo
from plc_stub.programs.auxiliary import AuxiliaryMachine
from plc_stub.programs.parameters import seconds

LUBE_PUMP = "Lube.pump"
CAMS_NOT_ACTIVE = 700030
CAM_PAIRS = 32
LUBE_PULSE_S = 0.5
CAMS_TIMEOUT_S = 0.5


class LubeStep(Enum):
    IDLE = "pump off, waiting for the slide to pass the cam"
    PULSE = "pump on for one pulse of oil"


class Cams(AuxiliaryMachine):
    PROGRAM = "cams"
    PARAMETERS = (*AuxiliaryMachine.PARAMETERS, "cam_axis", "lube_cam", "lube_pulse", "cams_timeout")

    def __init__(self, io: PlcIo):
        super().__init__(io)
        parameters = io.environment.parameters
        problems: list[str] = []
        axes = io.environment.catalog.layout.axes
        axis = parameters.get("cam_axis", axes[0] if axes else "")
        if axis not in axes:
            problems.append(f"plc: cam_axis is a machine axis of this machine ({', '.join(axes)}), got {axis!r}")
        cam = parameters.get("lube_cam", 1)
        if isinstance(cam, bool) or not isinstance(cam, int) or not 1 <= cam <= CAM_PAIRS:
            problems.append(f"plc: lube_cam is a cam pair 1..{CAM_PAIRS}, got {cam!r}")
        pulse = seconds(parameters, "lube_pulse", LUBE_PULSE_S, problems)
        timeout = seconds(parameters, "cams_timeout", CAMS_TIMEOUT_S, problems)
        if problems:
            raise ValueError("\n".join(problems))
        scan = io.environment.scan_time_s
        self.lube_pump: Bool | None = io.output(LUBE_PUMP) if io.is_wired(LUBE_PUMP) else None
        # Network 11
        self.cams_on = io.output(f"{axis}.basic.out.swCams")
        self.cams_active = io.input(f"{axis}.basic.in.swCamsActive")
        self.referenced = (io.input(f"{axis}.basic.in.enc1Synchronized"),
                           io.input(f"{axis}.basic.in.enc2Synchronized"))
        self.cams_alarm = self.plc_alarm(CAMS_NOT_ACTIVE)
        self.cams_watchdog = TON(timeout, scan)
        self.cams_fault = False
        # Network 12
        self.plus_cam = io.input(f"NC.basic.in.swCams[0].plus{cam}")
        self.passed = R_TRIG()
        self.lube_step = LubeStep.IDLE
        self.pulse = TON(pulse, scan)
        self.strokes = 0

    def auxiliary_networks(self) -> None:
        super().auxiliary_networks()
        self.software_cams()
        self.lubrication()

    # Network 11 --------------------------------------------------------------------------
    def software_cams(self) -> None:
        if self.lube_pump is None:
            return
        wanted = self.referenced[0].value or self.referenced[1].value
        self.cams_on.value = wanted
        if self.cams_watchdog(wanted and not self.cams_active.value):
            self.cams_fault = True  # the NC does not switch the cams on: no lubrication on them
        if self.cams_fault and self.reset_pressed:
            self.cams_fault = False
        self.cams_alarm.value = self.cams_fault
        self.hold_feed = self.hold_feed or self.cams_fault

    # Network 12 --------------------------------------------------------------------------
    def lubrication(self) -> None:
        pump = self.lube_pump
        if pump is None:
            return
        passed = self.passed(self.plus_cam.value)
        step = self.lube_step
        if step is LubeStep.IDLE and passed and self.cams_active.value:
            step = LubeStep.PULSE
            self.strokes += 1
        if self.pulse(step is LubeStep.PULSE):
            step = LubeStep.IDLE
        self.lube_step = step
        pump.value = step is LubeStep.PULSE
