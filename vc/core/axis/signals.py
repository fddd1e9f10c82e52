"""The DB31 interface signals of one machine axis, declared once (seed 003 axes, DB31).

:class:`AxisInputs` is what the PLC asks of the axis, decoded when the PLC changed its outputs;
:class:`AxisStatus` is what the axis shows the PLC, written when it changed.  Each field names its
catalogue symbol; the NCK compiles both groups once for every axis (:mod:`interfaces.signal_group`).
"""

from __future__ import annotations

from dataclasses import dataclass

from interfaces.signal_group import signal


@dataclass(slots=True)
class AxisInputs:
    """The PLC-to-NC signals of one axis."""

    controller_enable: bool = signal("basic.out.enableCtrl")
    pulse_enable: bool = signal("drive.out.enablePulses")
    disable: bool = signal("basic.out.disable")
    follow_up_mode: bool = signal("basic.out.followUpMode")
    override_active: bool = signal("basic.out.enableOvr")
    override_raw: int = signal("basic.out.feedrateOvrFactor", 0)
    feed_stop: bool = signal("basic.out.feedStopSpindleStop")
    rapid_key: bool = signal("basic.out.enableRapidTravers")
    key_minus: bool = signal("basic.out.traversKeyMinus")
    key_plus: bool = signal("basic.out.traversKeyPlus")
    hw_limit_minus: bool = signal("basic.out.hwLimitSwitchMinus")
    hw_limit_plus: bool = signal("basic.out.hwLimitSwitchPlus")
    reset_movement: bool = signal("basic.out.resetMovement")
    ref_cam: bool = signal("basic.out.refPointApproachCam")  # DB31.DBX12.7: the cam as the PLC copied it
    ref_point_selection: int = signal("basic.out.refPointSelection", 0)  # DBX2.4..2.7: reference point 1..4
    encoder_1_activation: bool = signal("basic.out.enc1Activation")  # DBX1.5
    encoder_2_activation: bool = signal("basic.out.enc2Activation")  # DBX1.6
    encoder_selected: int | None = None  # 0 or 1 from DBX1.5 / 1.6; None = parked (see select_encoder)

    def select_encoder(self, encoder_count: int) -> None:
        """Measuring system 1 or 2 from DB31.DBX1.5 / 1.6 (1 wins; 2 only where the axis has it;
        neither: parked)."""
        if self.encoder_1_activation:
            self.encoder_selected = 0
        else:
            self.encoder_selected = 1 if self.encoder_2_activation and encoder_count > 1 else None


@dataclass(frozen=True, slots=True)
class AxisStatus:
    """The NC-to-PLC status bits of one axis (the axis builds them, in this order, every cycle
    and writes them when they changed)."""

    exact_coarse: bool = signal("basic.in.posCoarseReached")
    exact_fine: bool = signal("basic.in.posFineReached")
    stationary: bool = signal("basic.in.isStationary")
    position_control: bool = signal("basic.in.posCtrlActive")
    follow_up_active: bool = signal("basic.in.followUpModeActive")
    referenced_1: bool = signal("basic.in.enc1Synchronized")
    referenced_2: bool = signal("basic.in.enc2Synchronized")
    restored_1: bool = signal("basic.in.enc1Restored")
    restored_2: bool = signal("basic.in.enc2Restored")
    frequency_exceeded_1: bool = signal("basic.in.enc1FreqLimitExceeded")
    frequency_exceeded_2: bool = signal("basic.in.enc2FreqLimitExceeded")
    disabled: bool = signal("basic.in.disabled")
    command_plus: bool = signal("basic.in.traversPlusCommandActive")
    command_minus: bool = signal("basic.in.traversMinusCommandActive")
    drive_enabled: bool = signal("drive.in.enabled")
