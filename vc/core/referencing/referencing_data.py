"""What a referencing procedure reads (seed 003 chapter 4): the referencing machine data of its
axis, taken when it starts, and what the NC tells it in each IPO cycle."""

from __future__ import annotations

from dataclasses import dataclass

from vc.config import md_dictionary as MD
from vc.config.machine_data import MachineData
from vc.core.axis.axis import MachineAxis


@dataclass(frozen=True, slots=True)
class ReferencingData:
    """The referencing machine data of one axis in internal units (per second)."""

    direction: int  # +1 / -1: MD34010 REFP_CAM_DIR_IS_MINUS
    with_cam: bool  # MD34000
    search_velocity: float  # MD34020
    max_cam_distance: float  # MD34030
    creep_velocity: float  # MD34040
    rising_edge: bool  # MD34050
    max_marker_distance: float  # MD34060
    positioning_velocity: float  # MD34070
    move_distance: float  # MD34080 + MD34090 (reference point distance + offset)
    cam_shift: float  # MD34092
    set_positions: tuple[float, ...]  # MD34100[0..3]
    sync_encoders: bool  # MD34102
    in_follow_up: bool  # MD34104
    velocity_tolerance: float  # MD35150 (phase 2 speed reached within this factor)
    hold_mode: bool  # MD11300
    stop_at_target: bool  # MD34330: 1 = no travel to the reference position

    @classmethod
    def of(cls, axis: MachineAxis, md: MachineData, hold_mode: bool, encoder: int) -> ReferencingData:
        unit = 6.0 if axis.config.is_rotary else 1.0 / 60.0
        return cls(
            direction=-1 if md.bool(MD.REFP_CAM_DIR_IS_MINUS) else 1,
            with_cam=md.bool(MD.REFP_CAM_IS_ACTIVE),
            search_velocity=md.float(MD.REFP_VELO_SEARCH_CAM) * unit,
            max_cam_distance=md.float(MD.REFP_MAX_CAM_DIST),
            creep_velocity=md.float(MD.REFP_VELO_SEARCH_MARKER) * unit,
            rising_edge=md.bool(MD.REFP_SEARCH_MARKER_REVERSE),
            max_marker_distance=md.float(MD.REFP_MAX_MARKER_DIST),
            positioning_velocity=md.float(MD.REFP_VELO_POS) * unit,
            move_distance=md.float(MD.REFP_MOVE_DIST) + md.float(MD.REFP_MOVE_DIST_CORR, encoder),
            cam_shift=md.float(MD.REFP_CAM_SHIFT),
            set_positions=md.floats(MD.REFP_SET_POS),
            sync_encoders=md.bool(MD.REFP_SYNC_ENCS),
            in_follow_up=md.bool(MD.REFP_PERMITTED_IN_FOLLOWUP),
            velocity_tolerance=md.float(MD.SPIND_DES_VELO_TOL),
            hold_mode=hold_mode,
            stop_at_target=md.bool(MD.REFP_STOP_AT_ABS_MARKER),
        )


@dataclass(slots=True)
class CycleConditions:
    """What the NC tells the referencing of one axis in this cycle."""

    feed_stop: bool  # channel feed disable or axis feed stop
    nc_stop: bool  # NC stop of the channel is held (latched in phases 1 and 3 until NC start)
    key_held: bool  # the traverse key of the started direction (hold mode)
