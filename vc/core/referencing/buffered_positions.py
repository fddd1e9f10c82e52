"""What the control keeps of each measuring system across power-off, and what makes it forget
(seed 003 §4.9, §4.10, L2025-2043).

At power-off the NC buffers the actual value of every measuring system, whether it was
referenced or restored and whether the axis stood in exact stop fine (``buffer_at_power_off``);
an absolute encoder writes its reading to MD30250.  At power-on ``restore_at_power_on`` gives
each measuring system its reference state back by MD34210: an absolute encoder is referenced
when calibrated, an incremental one is referenced again (MD34210 = 2, stood in exact stop) or
only restored (MD34210 = 3).  An encoder that miscounts (``encoder_slip``) loses its reference,
an absolute one its calibration (``lose_calibration``, also after a gear stage with a new ratio).
"""

from __future__ import annotations

from vc.config import md_dictionary as MD
from vc.core.alarms import AlarmList
from vc.core.axis.axis import MachineAxis
from vc.core.axis.encoder import (
    ENC_STATE_CALIBRATED,
    ENC_STATE_CALIBRATION_ENABLED,
    ENC_STATE_NOT_CALIBRATED,
    ENC_STATE_RESTORE,
)
from vc.core.nc_memory import BufferedEncoder, NcMemory

ALARM_ZERO_MARK_MONITORING = 25020
ALARM_ENCODER_WARNING = 25022


def restore_at_power_on(axis: MachineAxis, memory: NcMemory, alarms: AlarmList) -> None:
    """The reference state of each measuring system when the control powers on (§4.9, §4.10).

    * absolute: calibrated (MD34210 = 2) means referenced at once, actual value = reading +
      MD34090; a different encoder serial number than MD34230 (a new encoder) takes the
      calibration away: MD34210 := 0 and alarm 25022 (L2028-2043);
    * incremental, MD34210 = 2 (referenced, automatic referencing): referenced with the
      buffered actual value if the axis stood in exact stop fine at switch-off, else not
      referenced and MD34210 back to 1;
    * incremental, MD34210 = 3: the buffered position is restored (DB31.DBX71.4/71.5), the
      axis is not referenced;
    * otherwise an incremental encoder starts at actual value 0, not referenced.
    """
    for encoder in axis.encoders:
        index = encoder.index
        base = axis.config.md
        md = memory.view(axis.name, base)
        physical = axis.physical
        if encoder.absolute:
            serial = (axis.config.sim.encoder_serial, axis.config.sim.encoder_serial_2)[index]
            if serial != md.int(MD.ENC_SERIAL_NUMBER, index):
                memory.write(axis.name, MD.ENC_SERIAL_NUMBER, serial, index, base)
                if md.int(MD.ENC_REFP_STATE, index) != ENC_STATE_NOT_CALIBRATED:
                    memory.write(axis.name, MD.ENC_REFP_STATE, ENC_STATE_NOT_CALIBRATED, index, base)
                    alarms.raise_alarm(ALARM_ENCODER_WARNING, 0, axis.name, index + 1, 0,
                                       channel=axis.channel, axis=axis.name)
                md = memory.view(axis.name, base)
            encoder.offset = encoder.calibrated_actual(physical, md.float(MD.REFP_MOVE_DIST_CORR, index)) - physical
            encoder.referenced = md.int(MD.ENC_REFP_STATE, index) == ENC_STATE_CALIBRATED
            continue
        buffered = memory.buffered.get((axis.name, index))
        state = md.int(MD.ENC_REFP_STATE, index)
        if state == ENC_STATE_CALIBRATED:
            if buffered is not None and buffered.referenced and buffered.exact_stop_fine:
                encoder.offset = buffered.actual - physical
                encoder.referenced = True
                continue
            memory.write(axis.name, MD.ENC_REFP_STATE, ENC_STATE_CALIBRATION_ENABLED, index, base)
        elif state == ENC_STATE_RESTORE and buffered is not None and (buffered.referenced or buffered.restored):
            encoder.offset = buffered.actual - physical
            encoder.restored = True
            continue
        encoder.offset = -physical
    axis.stand_at(axis.encoder.actual(axis.physical))


def buffer_at_power_off(axis: MachineAxis, memory: NcMemory) -> None:
    """What the control keeps of each measuring system when it is switched off."""
    in_exact_stop = axis.at_rest and abs(axis.distance_to_end_point) <= axis.dyn.fine_window
    for encoder in axis.encoders:
        memory.buffered[(axis.name, encoder.index)] = BufferedEncoder(
            encoder.actual(axis.physical), encoder.referenced, encoder.restored, in_exact_stop)
        if encoder.absolute:
            memory.write(axis.name, MD.ACT_POS_ABS, encoder.absolute_reading(axis.physical), encoder.index,
                         axis.config.md)


def encoder_slip(axis: MachineAxis, encoder_index: int, amount: float, memory: NcMemory, alarms: AlarmList) -> None:
    """The zero-mark monitoring sees the encoder count wrongly (a fault of the plant).

    The position is no longer trusted: an incremental encoder loses its reference; an
    absolute encoder loses its calibration (MD34210 := 0) with alarms 25020 and 25022
    (seed 003 L2028-2043).
    """
    encoder = axis.encoders[encoder_index]
    encoder.offset += amount
    encoder.lose_reference()
    alarms.raise_alarm(ALARM_ZERO_MARK_MONITORING, 0, axis.name, channel=axis.channel, axis=axis.name)
    if encoder.absolute:
        lose_calibration(axis, encoder_index, memory, alarms, 0)
    if encoder is axis.encoder:
        axis.shift(encoder.actual(axis.physical) - axis.actual)


def lose_calibration(axis: MachineAxis, encoder_index: int, memory: NcMemory, alarms: AlarmList, cycle: int) -> None:
    """The control sees that an absolute encoder must be calibrated again (a gear stage change with
    a new ratio, the zero-mark monitoring, a new serial number): MD34210 := 0 and alarm 25022
    "axis <axis> encoder <n> warning 0"; the axis is no longer referenced by it (seed 003
    L2025-2040)."""
    encoder = axis.encoders[encoder_index]
    encoder.lose_reference()
    memory.write(axis.name, MD.ENC_REFP_STATE, ENC_STATE_NOT_CALIBRATED, encoder_index, axis.config.md)
    alarms.raise_alarm(ALARM_ENCODER_WARNING, cycle, axis.name, encoder_index + 1, 0,
                       channel=axis.channel, axis=axis.name)
    axis.resting = False  # DB31.DBX60.4 / 60.5 change
