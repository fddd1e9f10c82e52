"""The DB31 interface signals of one machine axis: where they are, what the PLC's outputs say,
and the status bits the axis writes back (seed 003 axes, DB31).

``AxisSignals`` holds the byte positions (from the signal table) and is the codec: ``read_inputs``
decodes the PLC-to-NC signals into ``AxisInputs`` when the PLC changed its outputs,
``write_status`` puts the NC-to-PLC status bits the axis computed each cycle.  It keeps no state.
"""

from __future__ import annotations

from dataclasses import dataclass

from vc.core.interface_map import SignalTable


class AxisSignals:
    """Byte positions of the DB31 signals an axis reads and writes."""

    def __init__(self, table: SignalTable):
        self.feed_override = table.field("basic.out.feedrateOvrFactor")
        self.disable = table.bit("basic.out.disable")
        self.follow_up_mode = table.bit("basic.out.followUpMode")
        self.override_active = table.bit("basic.out.enableOvr")
        self.controller_enable = table.bit("basic.out.enableCtrl")
        self.reset_movement = table.bit("basic.out.resetMovement")
        self.feed_stop = table.bit("basic.out.feedStopSpindleStop")
        self.rapid_key = table.bit("basic.out.enableRapidTravers")
        self.key_minus = table.bit("basic.out.traversKeyMinus")
        self.key_plus = table.bit("basic.out.traversKeyPlus")
        self.hw_limit_minus = table.bit("basic.out.hwLimitSwitchMinus")
        self.hw_limit_plus = table.bit("basic.out.hwLimitSwitchPlus")
        self.pulse_enable = table.bit("drive.out.enablePulses")
        self.ref_cam = table.bit("basic.out.refPointApproachCam")
        self.ref_point_selection = table.field("basic.out.refPointSelection")
        self.encoder_activation = (table.bit("basic.out.enc1Activation"), table.bit("basic.out.enc2Activation"))
        self.referenced = (table.bit("basic.in.enc1Synchronized"), table.bit("basic.in.enc2Synchronized"))
        self.frequency_exceeded = (table.bit("basic.in.enc1FreqLimitExceeded"),
                                   table.bit("basic.in.enc2FreqLimitExceeded"))
        self.restored = (table.bit("basic.in.enc1Restored"), table.bit("basic.in.enc2Restored"))
        self.exact_coarse = table.bit("basic.in.posCoarseReached")
        self.exact_fine = table.bit("basic.in.posFineReached")
        self.follow_up_active = table.bit("basic.in.followUpModeActive")
        self.stationary = table.bit("basic.in.isStationary")
        self.position_control = table.bit("basic.in.posCtrlActive")
        self.disabled = table.bit("basic.in.disabled")
        self.command_minus = table.bit("basic.in.traversMinusCommandActive")
        self.command_plus = table.bit("basic.in.traversPlusCommandActive")
        self.drive_enabled = table.bit("drive.in.enabled")

    def read_inputs(self, area: bytearray, inp: AxisInputs, encoder_count: int) -> None:
        """Decode the PLC's outputs for this axis into ``inp`` (DB31.DBX1.5 / 1.6 select measuring
        system 1 or 2, 2 only where the axis has it; neither: parked)."""
        inp.controller_enable = bool(area[self.controller_enable.byte] & self.controller_enable.mask)
        inp.pulse_enable = bool(area[self.pulse_enable.byte] & self.pulse_enable.mask)
        inp.disable = bool(area[self.disable.byte] & self.disable.mask)
        inp.follow_up_mode = bool(area[self.follow_up_mode.byte] & self.follow_up_mode.mask)
        inp.override_active = bool(area[self.override_active.byte] & self.override_active.mask)
        inp.override_raw = self.feed_override.get(area)
        inp.feed_stop = bool(area[self.feed_stop.byte] & self.feed_stop.mask)
        inp.rapid_key = bool(area[self.rapid_key.byte] & self.rapid_key.mask)
        inp.key_minus = bool(area[self.key_minus.byte] & self.key_minus.mask)
        inp.key_plus = bool(area[self.key_plus.byte] & self.key_plus.mask)
        inp.hw_limit_minus = bool(area[self.hw_limit_minus.byte] & self.hw_limit_minus.mask)
        inp.hw_limit_plus = bool(area[self.hw_limit_plus.byte] & self.hw_limit_plus.mask)
        inp.reset_movement = bool(area[self.reset_movement.byte] & self.reset_movement.mask)
        inp.ref_cam = bool(area[self.ref_cam.byte] & self.ref_cam.mask)
        inp.ref_point_selection = self.ref_point_selection.get(area)
        first, second = (bit.get(area) for bit in self.encoder_activation)
        inp.encoder_selected = 0 if first else (1 if second and encoder_count > 1 else None)

    def write_status(self, area: bytearray, status: tuple[bool, ...]) -> None:
        """Put the axis's status bits, in this order: exact stop coarse, fine, stationary, position
        control active, follow-up active, referenced 1 / 2, restored 1 / 2, limit frequency exceeded
        1 / 2, axis disabled, traverse command plus / minus, drive ready."""
        (coarse, fine, stationary, position_control, follow_up, referenced_1, referenced_2, restored_1, restored_2,
         frequency_1, frequency_2, disabled, plus, minus, drive_enabled) = status
        self.exact_coarse.put(area, coarse)
        self.exact_fine.put(area, fine)
        self.stationary.put(area, stationary)
        self.position_control.put(area, position_control)
        self.follow_up_active.put(area, follow_up)
        self.referenced[0].put(area, referenced_1)
        self.referenced[1].put(area, referenced_2)
        self.restored[0].put(area, restored_1)
        self.restored[1].put(area, restored_2)
        self.frequency_exceeded[0].put(area, frequency_1)
        self.frequency_exceeded[1].put(area, frequency_2)
        self.disabled.put(area, disabled)
        self.command_plus.put(area, plus)
        self.command_minus.put(area, minus)
        self.drive_enabled.put(area, drive_enabled)


@dataclass(slots=True)
class AxisInputs:
    """The PLC-to-NC signals of one axis, decoded when the PLC changed its outputs."""

    controller_enable: bool = False
    pulse_enable: bool = False
    disable: bool = False
    follow_up_mode: bool = False
    override_active: bool = False
    override_raw: int = 0
    feed_stop: bool = False
    rapid_key: bool = False
    key_minus: bool = False
    key_plus: bool = False
    hw_limit_minus: bool = False
    hw_limit_plus: bool = False
    reset_movement: bool = False
    ref_cam: bool = False  # DB31.DBX12.7: the reference cam as the PLC copied it
    ref_point_selection: int = 0  # DB31.DBX2.4..2.7: one bit per reference point value 1..4
    encoder_selected: int | None = None  # DB31.DBX1.5 / 1.6: 0 or 1; None = parked
