"""basic_machine: the basic machine control every machine needs, written like PLC code.

Networks (one method each, called in this order from OB1):

1. Emergency stop and drives: the e-stop chain (normally closed) drives DB10.DBX56.1;
   the infeed stays on for a short off delay after an e-stop so that the NC can brake the
   axes with the drives powered (stop category 1).  The reset key acknowledges the
   emergency stop (DB10.DBX56.2) once the chain is closed again.
2. Operating mode: the mode keys AUTO / MDA / JOG select the mode (one-hot in
   DB11.DBX0.0..0.2, held until another key); REF switches the machine function
   REF on (DB11.DBX1.2) and a mode key switches it off.
3. Channel: NC start / NC stop / reset keys to DB21.DBX7.1 / 7.3 / 7.7; feed stop and
   feed start keys latch the channel feed disable DB21.DBX6.0 (the stop key wins while both
   are pressed); the override switches to
   DB21.DBB4 (feed) and DBB5 (rapid) with their enables; the optional stop switch selects
   M01 (DB21.DBX0.5).
4. Axes: measuring system 1 selected (DB31.DBX1.5), controller and pulse enable once the
   drives are ready (follow-up mode while the enable is off), the axis override, the
   traverse keys to DB31.DBX4.6/4.7, the rapid traverse key, the reference cam to
   DB31.DBX12.7 and the hardware limit switches (normally closed) to DB31.DBX12.0/12.1.
   The machine functions of JOG (seed 003 §16.4.1, §16.5.1): the panel's keys INC1 .. INC10000,
   INCvar and continuous JOG (``MCP.inc1`` .. ``MCP.inc10000``, ``MCP.incVar``,
   ``MCP.jogContinuous``) select one of them, latched (the key last pressed; none after power-on,
   so the NC's traverse keys stay continuous) and written to DB31.DBX5.0..5.6 of every axis; each
   key's lamp (``Lamp.inc1`` .. ``Lamp.jogContinuous``) lights while the NC reports that machine
   function active on an axis (DB31.DBX65.0..65.6: in JOG).  A program that assigns handwheels
   (network 12 of ``manual_retraction``) gives the increment to the handwheels' axes instead.
5. JOG to a fixed point (seed 003 §16.9.1): the panel's keys ``MCP.fixedPoint1`` .. ``4`` select
   fixed point n of every axis (DB31.DBX13.0..13.2, binary), latched; the same key pressed again,
   or a mode other than JOG, withdraws it (0).  Each key's lamp (``Lamp.fixedPoint1`` ..) lights
   steadily while every axis with the selection acknowledged (DB31.DBX75.0..75.2 = n) stands on
   the fixed point (DB31.DBX75.3..75.5 = n) and flashes while one still has to travel there.  On
   a panel without these keys the program never writes DB31.DBX13.

Everything is derived from the machine's I/O list: an axis without a cam simply has no
cam network.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from plc_stub.blocks import R_TRIG, SR, TOF
from plc_stub.io import Bool, Byte, PlcIo

DRIVES_OFF_DELAY_S = 0.5  # infeed kept on after an e-stop: the NC brakes with powered drives
KEY_MODES = ("auto", "mda", "jog")
# the machine functions of JOG: the panel's key (and lamp) and the DB31 request, in the order of DBX5.0..5.6
JOG_FUNCTIONS = (("inc1", "inc1"), ("inc10", "inc10"), ("inc100", "inc100"), ("inc1000", "inc1000"),
                 ("inc10000", "inc10000"), ("incVar", "incVar"), ("jogContinuous", "contTravers"))
INCREMENT_KEYS = 5  # the first five are the fixed increments INC1 .. INC10000 (the handwheels' too)
FIXED_POINTS = 4  # MD30600 holds at most four fixed points per axis (seed 003 L34435)
FLASH_PERIOD_S = 0.5  # a fixed point's lamp flashes while an axis still travels there


@dataclass(slots=True)
class _AxisIo:
    measuring_system_1: Bool
    controller_enable: Bool
    pulse_enable: Bool
    follow_up_mode: Bool
    override_active: Bool
    override: Byte
    key_minus: Bool
    key_plus: Bool
    rapid: Bool
    panel_minus: Bool | None
    panel_plus: Bool | None
    cam_input: Bool | None
    cam_output: Bool
    limit_minus_input: Bool | None
    limit_plus_input: Bool | None
    limit_minus_output: Bool
    limit_plus_output: Bool


@dataclass(slots=True)
class _ChannelIo:
    nc_start: Bool
    nc_stop: Bool
    reset: Bool
    feed_disable: Bool
    feed_override_active: Bool
    feed_override: Byte
    rapid_override_active: Bool
    rapid_override: Byte
    activate_m01: Bool


class BasicMachine:
    # the machine file's plc: parameters the program reads (a class constant: mypyc reads it from the class)
    PARAMETERS: ClassVar[tuple[str, ...]] = ()

    def __init__(self, io: PlcIo):
        scan = io.environment.scan_time_s
        layout = io.environment.catalog.layout

        def optional_input(name: str) -> Bool | None:
            return io.input(name) if io.is_wired(name) else None

        def optional_byte(name: str) -> Byte | None:
            return io.input_byte(name) if io.is_wired(name) else None

        # Network 1
        self.chain_ok = optional_input("EStop.chainOk")
        self.drives_ready = optional_input("Drives.ready")
        self.drives_on = io.output("Drives.on") if io.is_wired("Drives.on") else None
        self.emergency_stop = io.output("NC.basic.out.emergencyStop")
        self.emergency_stop_ack = io.output("NC.basic.out.emergencyStopAck")
        self.drives_off_delay = TOF(DRIVES_OFF_DELAY_S, scan)
        # Network 2
        self.mode_keys = {mode: optional_input(f"MCP.{mode}") for mode in KEY_MODES}
        self.mode_key_edges = {mode: R_TRIG() for mode in KEY_MODES}
        self.mode_outputs = {
            "auto": io.output("MODEGROUP.basic.out.autoMode"),
            "mda": io.output("MODEGROUP.basic.out.mdaMode"),
            "jog": io.output("MODEGROUP.basic.out.jogMode"),
        }
        self.ref_key = optional_input("MCP.ref")
        self.ref_key_edge = R_TRIG()
        self.ref_output = io.output("MODEGROUP.basic.out.refPoint")
        self.selected_mode = "jog"
        self.reference_function = False
        # Network 3
        self.key_nc_start = optional_input("MCP.ncStart")
        self.key_nc_stop = optional_input("MCP.ncStop")
        self.key_reset = optional_input("MCP.reset")
        self.key_feed_stop = optional_input("MCP.feedStop")
        self.key_feed_start = optional_input("MCP.feedStart")
        self.feed_switch = optional_byte("MCP.feedOverride")
        self.rapid_switch = optional_byte("MCP.rapidOverride")
        self.key_rapid = optional_input("MCP.rapid")
        self.optional_stop_switch = optional_input("MCP.optionalStop")
        # the panel's NOZAGC switch goes to the inclined-axis control of every channel; without the
        # switch the program leaves the signal alone
        self.nozagc_switch = optional_input("MCP.noOrthogonalCompensation")
        self.nozagc_outputs = [io.output(f"{name}.inclinedAxis.out.noOrthogonalCompensation")
                               for name in layout.channels] if self.nozagc_switch is not None else []
        self.feed_stop_latch = SR()
        self.channels = [
            _ChannelIo(
                nc_start=io.output(f"{name}.basic.out.ncStart"),
                nc_stop=io.output(f"{name}.basic.out.ncStop"),
                reset=io.output(f"{name}.basic.out.reset"),
                feed_disable=io.output(f"{name}.basic.out.disableFeed"),
                feed_override_active=io.output(f"{name}.basic.out.pathFeedrateOvr"),
                feed_override=io.output_byte(f"{name}.basic.out.pathFeedrateOvrFactor"),
                rapid_override_active=io.output(f"{name}.basic.out.pathRapidTraversOvr"),
                rapid_override=io.output_byte(f"{name}.basic.out.pathRapidTraversOvrFactor"),
                activate_m01=io.output(f"{name}.basic.out.activateM01"),
            )
            for name in layout.channels
        ]
        # Network 4: the machine functions of JOG, where the panel has their keys
        self.jog_keys = [(index, io.input(f"MCP.{key}"), R_TRIG()) for index, (key, _) in enumerate(JOG_FUNCTIONS)
                         if io.is_wired(f"MCP.{key}")]
        self.jog_function: int | None = None  # the machine function last selected (index of JOG_FUNCTIONS)
        self.jog_requests = [tuple(io.output(f"{name}.basic.out.{signal}") for _, signal in JOG_FUNCTIONS)
                             for name in layout.axes] if self.jog_keys else []
        self.jog_feedback = [tuple(io.input(f"{name}.basic.in.{signal}Active") for _, signal in JOG_FUNCTIONS)
                             for name in layout.axes] if self.jog_keys else []
        self.jog_lamps = [(index, io.output(f"Lamp.{key}")) for index, (key, _) in enumerate(JOG_FUNCTIONS)
                          if io.is_wired(f"Lamp.{key}")]
        # Network 5: JOG to a fixed point, where the panel has its keys
        self.fixed_point_keys = [(number, io.input(f"MCP.fixedPoint{number}"), R_TRIG())
                                 for number in range(1, FIXED_POINTS + 1) if io.is_wired(f"MCP.fixedPoint{number}")]
        self.fixed_point = 0  # the fixed point selected on the panel, 0 none
        self.fixed_point_requests = [io.output_field(f"{name}.basic.out.jogFixedPointSelection")
                                     for name in layout.axes] if self.fixed_point_keys else []
        self.fixed_point_feedback = [(io.input_field(f"{name}.basic.in.jogFixedPointSelectedNumber"),
                                      io.input_field(f"{name}.basic.in.jogFixedPointReachedNumber"))
                                     for name in layout.axes] if self.fixed_point_keys else []
        self.fixed_point_lamps = [(number, io.output(f"Lamp.fixedPoint{number}"))
                                  for number in range(1, FIXED_POINTS + 1) if io.is_wired(f"Lamp.fixedPoint{number}")]
        self.flash_scans = max(1, round(FLASH_PERIOD_S / 2 / scan))
        self.flash_count = 0
        # Network 4
        self.axes = [
            _AxisIo(
                measuring_system_1=io.output(f"{name}.basic.out.enc1Activation"),
                controller_enable=io.output(f"{name}.basic.out.enableCtrl"),
                pulse_enable=io.output(f"{name}.drive.out.enablePulses"),
                follow_up_mode=io.output(f"{name}.basic.out.followUpMode"),
                override_active=io.output(f"{name}.basic.out.enableOvr"),
                override=io.output_byte(f"{name}.basic.out.feedrateOvrFactor"),
                key_minus=io.output(f"{name}.basic.out.traversKeyMinus"),
                key_plus=io.output(f"{name}.basic.out.traversKeyPlus"),
                rapid=io.output(f"{name}.basic.out.enableRapidTravers"),
                panel_minus=optional_input(f"MCP.minus.{name}"),
                panel_plus=optional_input(f"MCP.plus.{name}"),
                cam_input=optional_input(f"{name}.refCam"),
                cam_output=io.output(f"{name}.basic.out.refPointApproachCam"),
                limit_minus_input=optional_input(f"{name}.hwLimitMinus"),
                limit_plus_input=optional_input(f"{name}.hwLimitPlus"),
                limit_minus_output=io.output(f"{name}.basic.out.hwLimitSwitchMinus"),
                limit_plus_output=io.output(f"{name}.basic.out.hwLimitSwitchPlus"),
            )
            for name in layout.axes
        ]

    def ob1(self) -> None:
        self.emergency_stop_and_drives()
        self.operating_mode()
        self.channel_control()
        self.axis_control()
        self.jog_to_fixed_point()

    # Network 1 ---------------------------------------------------------------------------
    def emergency_stop_and_drives(self) -> None:
        chain_ok = self.chain_ok.value if self.chain_ok is not None else True
        self.emergency_stop.value = not chain_ok
        reset_pressed = pressed(self.key_reset)
        self.emergency_stop_ack.value = chain_ok and reset_pressed
        if self.drives_on is not None:
            self.drives_on.value = self.drives_off_delay(chain_ok)

    # Network 2 ---------------------------------------------------------------------------
    def operating_mode(self) -> None:
        for mode, key in self.mode_keys.items():
            if key is not None and self.mode_key_edges[mode](key.value):
                self.selected_mode = mode
                self.reference_function = False
        if self.ref_key is not None and self.ref_key_edge(self.ref_key.value):
            self.reference_function = True
            if self.selected_mode == "auto":
                self.selected_mode = "jog"  # REF is a machine function of JOG or MDA
        for mode, output in self.mode_outputs.items():
            output.value = mode == self.selected_mode
        self.ref_output.value = self.reference_function

    # Network 3 ---------------------------------------------------------------------------
    def channel_control(self) -> None:
        start = pressed(self.key_nc_start)
        stop = pressed(self.key_nc_stop)
        reset = pressed(self.key_reset)
        feed_stopped = self.feed_stop_latch(pressed(self.key_feed_stop), pressed(self.key_feed_start))
        feed = self.feed_switch.value if self.feed_switch is not None else 100
        rapid = self.rapid_switch.value if self.rapid_switch is not None else feed
        for channel in self.channels:
            channel.nc_start.value = start
            channel.nc_stop.value = stop
            channel.reset.value = reset
            channel.feed_disable.value = feed_stopped
            channel.feed_override_active.value = True
            channel.feed_override.value = feed
            channel.rapid_override_active.value = True
            channel.rapid_override.value = rapid
            channel.activate_m01.value = pressed(self.optional_stop_switch)
        for output in self.nozagc_outputs:
            output.value = pressed(self.nozagc_switch)

    # Network 4 ---------------------------------------------------------------------------
    def axis_control(self) -> None:
        ready = self.drives_ready.value if self.drives_ready is not None else True
        feed = self.feed_switch.value if self.feed_switch is not None else 100
        rapid = pressed(self.key_rapid)
        for axis in self.axes:
            axis.measuring_system_1.value = True
            axis.controller_enable.value = ready
            axis.pulse_enable.value = ready
            axis.follow_up_mode.value = not ready
            axis.override_active.value = True
            axis.override.value = feed
            axis.key_minus.value = pressed(axis.panel_minus)
            axis.key_plus.value = pressed(axis.panel_plus)
            axis.rapid.value = rapid
            if axis.cam_input is not None:
                axis.cam_output.value = axis.cam_input.value
            # Limit switches are normally closed: an open contact (0) means "actuated".
            if axis.limit_minus_input is not None:
                axis.limit_minus_output.value = not axis.limit_minus_input.value
            if axis.limit_plus_input is not None:
                axis.limit_plus_output.value = not axis.limit_plus_input.value
        self.jog_machine_functions()

    def jog_machine_functions(self) -> None:
        """Network 4, the machine functions of JOG: the key last pressed to every axis, the lamps
        from the NC's feedback."""
        for index, key, edge in self.jog_keys:
            if edge(key.value):
                self.jog_function = index
        for requests in self.jog_requests:
            for index, request in enumerate(requests):
                request.value = index == self.jog_function
        for index, lamp in self.jog_lamps:
            lamp.value = any(feedback[index].value for feedback in self.jog_feedback)

    # Network 5 ---------------------------------------------------------------------------
    def jog_to_fixed_point(self) -> None:
        """Network 5, JOG to a fixed point: the key last pressed to every axis (again: off; outside
        JOG: off), the lamps from the NC's feedback."""
        if not self.fixed_point_keys:
            return
        for number, key, edge in self.fixed_point_keys:
            if edge(key.value):
                self.fixed_point = 0 if self.fixed_point == number else number
        if self.selected_mode != "jog" or self.reference_function:
            self.fixed_point = 0
        for request in self.fixed_point_requests:
            request.value = self.fixed_point
        self.flash_count = (self.flash_count + 1) % (2 * self.flash_scans)
        flash_on = self.flash_count < self.flash_scans
        for number, lamp in self.fixed_point_lamps:
            selected = [reached.value == number for acknowledged, reached in self.fixed_point_feedback
                        if acknowledged.value == number]
            lamp.value = bool(selected) and (all(selected) or flash_on)

    @property
    def panel_increment(self) -> int | None:
        """The fixed increment (1 .. 10000) the panel selects, None for INCvar, continuous or none."""
        function = self.jog_function
        return 10 ** function if function is not None and function < INCREMENT_KEYS else None


def pressed(key: Bool | None) -> bool:
    """A panel key's state; a key the machine's panel lacks is never pressed."""
    return key.value if key is not None else False
