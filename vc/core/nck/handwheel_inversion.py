"""The handwheel's direction of rotation inverted by the PLC (seed 003 §16.6.1 L33280-33333).

Where the handwheel's direction does not match the axis's (one handwheel for several axes), the PLC
inverts it per machine axis (DB31.DBX7.0) or for geometry axis 1 (DB21.DBX15.0); the NC
acknowledges it (DB31.DBX67.0, DB21.DBX43.0) and the handwheel's pulses travel the other way.
The inversion may change only while the axis stands (L33331-33333): a change while the axis still
travels a handwheel's distance is taken once that distance is done [INF: the seed's alarm for a
refused change has no number here, and the axis is not braked: the change waits instead].  It acts
on JOG with the handwheel; DRF keeps the handwheel's own direction [INF: the seed does not say].
The signals are read only when the PLC changed the data block (or a change waits), so an axis
whose PLC never inverts costs nothing.
"""

from __future__ import annotations

from collections.abc import Sequence

from interfaces.group_codec import GroupCodec
from interfaces.image import ProcessImage
from interfaces.signal_groups import (
    HANDWHEEL_INVERSION_OF_GEOMETRY_AXIS_1,
    HANDWHEEL_INVERSION_OF_MACHINE_AXIS,
    HandwheelInversionRequest,
    HandwheelInversionStatus,
)
from vc.core.axis.axis import MachineAxis
from vc.core.channel.channel import Channel
from vc.core.interface_map import SignalTable


class HandwheelInversion:
    """Which machine axes and which channels' geometry axis 1 have the handwheel inverted."""

    def __init__(self, axis_table: SignalTable, channel_table: SignalTable, image: ProcessImage):
        self._image = image
        self._read_axis = axis_table.codec(HandwheelInversionRequest, HANDWHEEL_INVERSION_OF_MACHINE_AXIS).read
        self._axis_status = axis_table.codec(HandwheelInversionStatus, HANDWHEEL_INVERSION_OF_MACHINE_AXIS)
        self._read_geometry = channel_table.codec(HandwheelInversionRequest,
                                                  HANDWHEEL_INVERSION_OF_GEOMETRY_AXIS_1).read
        self._geometry_status = channel_table.codec(HandwheelInversionStatus, HANDWHEEL_INVERSION_OF_GEOMETRY_AXIS_1)
        self.axes: set[str] = set()  # machine axes with the handwheel inverted
        self.geometry_axis_1: set[str] = set()  # channels whose geometry axis 1 has it inverted
        self._waiting: set[str] = set()  # channels where a change waits for its axis to stand

    def follow(self, channel: Channel, axes: Sequence[MachineAxis], latched: set[str] | None, refresh: bool) -> None:
        """Take the PLC's inversion of the channel's axes and geometry axis 1 when it changed (or waits)."""
        again = refresh or channel.name in self._waiting
        if not again and latched is None:
            return
        waiting = False
        for axis in axes:
            if again or (latched is not None and axis.area_key in latched):
                wanted = self._read_axis(self._image.area(axis.area_key)).invert
                waiting |= self._take(self.axes, axis.name, wanted, axis, axis.area_key, self._axis_status)
        geometry = channel.config.geometry_axes[0]
        if geometry and (again or (latched is not None and channel.area_key in latched)):
            wanted = self._read_geometry(self._image.area(channel.area_key)).invert
            waiting |= self._take(self.geometry_axis_1, channel.name, wanted, channel.axes_by_name[geometry],
                                  channel.area_key, self._geometry_status)
        if waiting:
            self._waiting.add(channel.name)
        else:
            self._waiting.discard(channel.name)

    def _take(self, inverted: set[str], name: str, wanted: bool, axis: MachineAxis, area_key: str,
              status: GroupCodec[HandwheelInversionStatus]) -> bool:
        """The new state once ``axis`` stands (True: the change waits), acknowledged to the PLC."""
        if wanted == (name in inverted):
            return False
        if axis.handwheel_rest != 0.0:
            return True  # only at standstill (L33331-33333)
        if wanted:
            inverted.add(name)
        else:
            inverted.discard(name)
        status.encode(self._image.area(area_key), HandwheelInversionStatus(inverted=wanted))
        return False
