"""The machine data the harness knows, with the manual's numbers and names.

``source`` cites the seed line (``seed 003 L1003``) where the seed gives the datum; where
the seed is silent the real control's meaning, unit and default are used and marked
``[control]``.  Units are those of the control's display: mm, mm/min, m/s^2, s; rotary
axes and spindles use degrees and rev/min where the control does.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from interfaces.errors import VcError
from vc.config.machine_data import MdDef, MdLevel, MdType

N, C, A = MdLevel.NCK, MdLevel.CHANNEL, MdLevel.AXIS
BOOL, INT, FLOAT, STR = MdType.BOOL, MdType.INT, MdType.FLOAT, MdType.STR


def _repeat(value: float, count: int) -> tuple[float, ...]:
    return (value,) * count


# Override switch tables for Gray-coded switches, 31 switch positions.  The seed says the
# factors must be entered in MD12010/12030/12050/12070 but prints no table (spec B.4.17
# [GAP]); these are the control's delivery values.
_FEED_GRAY = (0.0, 0.01, 0.02, 0.04, 0.06, 0.08, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.75, 0.8, 0.85,
              0.9, 0.95, 1.0, 1.05, 1.1, 1.15, 1.2, 1.2, 1.2, 1.2, 1.2, 1.2, 1.2, 1.2, 1.2)
_RAPID_GRAY = (0.0, 0.01, 0.02, 0.04, 0.06, 0.08, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.75, 0.8, 0.85,
               0.9, 0.95, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0)
_SPINDLE_GRAY = (0.5, 0.55, 0.6, 0.65, 0.7, 0.75, 0.8, 0.85, 0.9, 0.95, 1.0, 1.05, 1.1, 1.15, 1.2, 1.2,
                 1.2, 1.2, 1.2, 1.2, 1.2, 1.2, 1.2, 1.2, 1.2, 1.2, 1.2, 1.2, 1.2, 1.2, 1.2)

# ---------------------------------------------------------------------------------- NCK
AXCONF_MACHAX_NAME_TAB = MdDef(10000, "AXCONF_MACHAX_NAME_TAB", N, STR, tuple(f"AX{n}" for n in range(1, 32)),
                               "machine axis names (also used in G74 <axis>); the loader sets it from the"
                               " order of the axes: section",
                               "seed 003 L779-780; [control] generic names AX<n>",
                               length=31)
SYSCLOCK_CYCLE_TIME = MdDef(10050, "SYSCLOCK_CYCLE_TIME", N, FLOAT, 0.002, "basic system clock cycle",
                            "seed 003 L2518-2535; [control] default chosen for a 2 ms IPO cycle", "s",
                            0.000125, 0.031)
IPO_SYSCLOCK_TIME_RATIO = MdDef(10070, "IPO_SYSCLOCK_TIME_RATIO", N, INT, 1,
                                "IPO cycle as a multiple of the system clock cycle",
                                "seed 003 L2518-2535; [control] default 1 gives IPO = 2 ms", "", 1, 100)
PLC_CYCLIC_TIMEOUT = MdDef(10100, "PLC_CYCLIC_TIMEOUT", N, FLOAT, 0.1,
                           "longest time without a sign of life of the PLC before alarm 2000",
                           "[control] number, name and default (not in the seeds)", "s", 0.0, 100.0,
                           nonzero="no PLC answers within 0 s: alarm 2000 would stop the machine at once")
PLC_RUNNINGUP_TIMEOUT = MdDef(10120, "PLC_RUNNINGUP_TIMEOUT", N, FLOAT, 50.0,
                              "longest time from power-on to the PLC's first scan before alarm 2001",
                              "[control] number, name and default (not in the seeds)", "s", 0.0, 1000.0,
                              nonzero="no PLC starts within 0 s: alarm 2001 would come at every power-on")
GEAR_CHANGE_WAIT_TIME = MdDef(10192, "GEAR_CHANGE_WAIT_TIME", N, FLOAT, 10.0,
                              "longest wait for the PLC's gear-change acknowledgement",
                              "seed 003 L19127-19147; [control] default", "s", 0.0, 1.0e5)
OPERATING_MODE_DEFAULT = MdDef(10720, "OPERATING_MODE_DEFAULT", N, INT, (7,) * 10,
                               "operating mode of each mode group after power-on: 0 = AUTOMATIC, 3 = MDA,"
                               " 7 = JOG (further values for the sub-modes REPOS, REF, TEACH IN)",
                               "seed 003 L35366-35368; [control] coding and default 7 = JOG", "", 0, 12, 10)
OPERATING_MODE_EXTENDED = MdDef(10721, "OPERATING_MODE_EXTENDED", N, INT, (0,) * 10,
                                "after power-on: 0 = mode from MD10720, 1 = JOG if retract data exist"
                                " (DB21.DBX377.5)", "seed 003 L35370-35378; [control] default", "", 0, 1, 10,
                                allowed=(0, 1))
JOG_MODE_MASK = MdDef(10735, "JOG_MODE_MASK", N, INT, 0,
                      "JOG settings (bit mask); bit 2 = 1: JOG to a fixed point / to a position may travel"
                      " away from it (0 = towards it only); bit 8 = 1: manual retraction in both directions"
                      " (0 = plus only)",
                      "seed 003 L34322-34330, L34426-34432, L34711-34716, L35390-35400, L35547-35549;"
                      " [control] default", "", 0, 0xFFFF)
JOG_INC_MODE_LEVELTRIGGRD = MdDef(11300, "JOG_INC_MODE_LEVELTRIGGRD", N, BOOL, True,
                                  "INC and REF in hold mode: the key must be held (default)",
                                  "seed 003 L558-565, L33093-33095")
JOG_INCR_SIZE_TAB = MdDef(11330, "JOG_INCR_SIZE_TAB", N, FLOAT, (1.0, 10.0, 100.0, 1000.0, 10000.0),
                          "the fixed increments of INC1 .. INC10000 (DB31.DBX5.0..5.4), in units of MD31090",
                          "seed 003 L33068-33070, L35978; [control] defaults 1 / 10 / 100 / 1000 / 10000",
                          "", 0.0, 1.0e8, 5)
JOG_VAR_INCR_SIZE = MdDef(41010, "JOG_VAR_INCR_SIZE", N, FLOAT, 0.0,
                          "setting datum SD41010 $SN_JOG_VAR_INCR_SIZE: the variable increment INCvar"
                          " (DB31.DBX5.5), in units of MD31090",
                          "seed 003 L33074-33076, L35982; [control] default 0", "", 0.0, 1.0e8)
JOG_CONT_MODE_LEVELTRIGGRD = MdDef(41050, "JOG_CONT_MODE_LEVELTRIGGRD", N, BOOL, True,
                                   "setting datum SD41050 $SN_JOG_CONT_MODE_LEVELTRIGGRD: continuous JOG in jog"
                                   " mode (1: the axis runs while the key is held) or continuous mode (0: a press"
                                   " starts it, a second press stops it)",
                                   "seed 003 L32787-32791, L13422, L13436; [control] default 1 (L32791 names the"
                                   " continuous mode the default, L13420 calls jog mode the usual one)")
SUPPRESS_ALARM_MASK = MdDef(11410, "SUPPRESS_ALARM_MASK", N, INT, 0, "suppress specific alarms (bit mask)",
                            "seed 003 L18401-18405", "", 0, 0xFFFFFFFF)
OVR_AX_IS_GRAY_CODE = MdDef(12000, "OVR_AX_IS_GRAY_CODE", N, BOOL, False,
                            "axis feed override switch is Gray coded", "seed 003 L9133-9158")
OVR_FACTOR_AX_SPEED = MdDef(12010, "OVR_FACTOR_AX_SPEED", N, FLOAT, _FEED_GRAY,
                            "axis override factor per Gray switch position",
                            "seed 003 L9154-9158; [control] values",
                            "", 0.0, 2.0, 31)
OVR_FEED_IS_GRAY_CODE = MdDef(12020, "OVR_FEED_IS_GRAY_CODE", N, BOOL, False,
                              "path feed override switch is Gray coded", "seed 003 L9040-9067")
OVR_FACTOR_FEEDRATE = MdDef(12030, "OVR_FACTOR_FEEDRATE", N, FLOAT, _FEED_GRAY,
                            "path feed override factor per Gray switch position",
                            "seed 003 L9065-9067; [control] values", "", 0.0, 2.0, 31)
OVR_RAPID_IS_GRAY_CODE = MdDef(12040, "OVR_RAPID_IS_GRAY_CODE", N, BOOL, False,
                               "rapid traverse override switch is Gray coded", "seed 003 L9048, L9067")
OVR_FACTOR_RAPID_TRA = MdDef(12050, "OVR_FACTOR_RAPID_TRA", N, FLOAT, _RAPID_GRAY,
                             "rapid override factor per Gray switch position",
                             "seed 003 L9067; [control] values", "", 0.0, 2.0, 31)
OVR_SPIND_IS_GRAY_CODE = MdDef(12060, "OVR_SPIND_IS_GRAY_CODE", N, BOOL, False,
                               "spindle override switch is Gray coded", "seed 003 L9177-9198")
OVR_FACTOR_SPIND_SPEED = MdDef(12070, "OVR_FACTOR_SPIND_SPEED", N, FLOAT, _SPINDLE_GRAY,
                               "spindle override factor per Gray switch position",
                               "seed 003 L9196-9198; [control] values", "", 0.0, 2.0, 31)
OVR_REFERENCE_IS_PROG_FEED = MdDef(12080, "OVR_REFERENCE_IS_PROG_FEED", N, BOOL, False,
                                   "spindle override refers to the programmed speed"
                                   " (0 = to the limited speed)",
                                   "seed 003 L8644, L9208-9214; [control] default")
OVR_REFERENCE_IS_MIN_FEED = MdDef(12082, "OVR_REFERENCE_IS_MIN_FEED", N, BOOL, False,
                                  "path feed override refers to the limited feed where it is below the"
                                  " programmed feed", "seed 003 L8651, L9119-9123; [control] default")
OVR_FACTOR_LIMIT_BIN = MdDef(12100, "OVR_FACTOR_LIMIT_BIN", N, FLOAT, 1.2,
                             "upper limit of binary-coded override (path, axis, spindle)",
                             "seed 003 L9216-9220; [control] default", "", 0.0, 2.0)


PERMANENT_FEED = MdDef(12202, "PERMANENT_FEED", N, FLOAT, (0.0,) * 4,
                       "fixed feedrates 1-4 of linear axes: the path feed with DB21.DBX29.0-29.3 (AUTO / MDA) and"
                       " an axis's JOG velocity with DB31.DBX3.2-3.5; 0 = the value is not set [INF]",
                       "seed 003 L9692-9734", "mm/min", 0.0, 1.0e6, 4)
PERMANENT_ROT_AX_FEED = MdDef(12204, "PERMANENT_ROT_AX_FEED", N, FLOAT, (0.0,) * 4,
                              "fixed feedrates 1-4 of rotary axes (JOG with DB31.DBX3.2-3.5); 0 = not set [INF]",
                              "seed 003 L9716-9723; [control] unit as MD32000", "rev/min", 0.0, 1.0e6, 4)
USER_DATA_PLC_ALARM = MdDef(14516, "USER_DATA_PLC_ALARM", N, INT, (0,) * 64,
                            "reaction of PLC user alarm 700000 + n (user area 0, DB2.DBX180.0 ..), bits: 0 NC start"
                            " disabled, 1 read-in disabled, 2 feed disabled (the axes of every channel stop)",
                            "[control] number and name; [INF] the bit meanings as the project reads them, the"
                            " seed names no PLC alarms (docs/auxiliary_functions.md)", "", 0, 0xFF, 64)


# ------------------------------------------------------------ NCK: software cams (seed 003 chapter 21)
SW_CAM_PAIRS = 32  # cam pairs 1..32, eight to a setting datum of positions and times (L40925, L41054-41073)
SW_CAM_ASSIGN_TAB = MdDef(10450, "SW_CAM_ASSIGN_TAB", N, INT, (0,) * SW_CAM_PAIRS,
                          "machine axis number of cam pair n+1 (0 = not assigned: the pair does not act); an axis"
                          " may have several pairs, a pair one axis",
                          "seed 003 L41117-41131", "", 0, 31, SW_CAM_PAIRS)
SW_CAM_MINUS_LEAD_TIME = MdDef(10460, "SW_CAM_MINUS_LEAD_TIME", N, FLOAT, (0.0,) * SW_CAM_PAIRS,
                               "lead (> 0) or delay (< 0) time of the minus cam signal of pair n+1, added to"
                               " SD41520 ff.", "seed 003 L41133-41160; [control] range", "s", -10.0, 10.0,
                               SW_CAM_PAIRS)
SW_CAM_PLUS_LEAD_TIME = MdDef(10461, "SW_CAM_PLUS_LEAD_TIME", N, FLOAT, (0.0,) * SW_CAM_PAIRS,
                              "lead (> 0) or delay (< 0) time of the plus cam signal of pair n+1, added to"
                              " SD41521 ff.", "seed 003 L41133-41160; [control] range", "s", -10.0, 10.0,
                              SW_CAM_PAIRS)
SW_CAM_MODE = MdDef(10485, "SW_CAM_MODE", N, INT, 0,
                    "behaviour of the software cams (bits): 1 = the plus cam signal of a modulo axis is not"
                    " inverted when plus - minus >= 180 degrees or minus > plus (bits 0 and 2, the timer and"
                    " path-time cams, are not modelled)",
                    "seed 003 L40997-40999, L41043-41047; [control] range", "", 0, 7)

SW_CAM_MINUS_POS_TAB_1 = MdDef(41500, "SW_CAM_MINUS_POS_TAB_1", N, FLOAT, (0.0,) * 8,
    "setting datum SD41500: positions of the minus cams 1-8 in the machine coordinate system",
    "seed 003 L41054-41073", "mm / deg", -1.0e9, 1.0e9, 8)

SW_CAM_PLUS_POS_TAB_1 = MdDef(41501, "SW_CAM_PLUS_POS_TAB_1", N, FLOAT, (0.0,) * 8,
    "setting datum SD41501: positions of the plus cams 1-8 in the machine coordinate system",
    "seed 003 L41054-41073", "mm / deg", -1.0e9, 1.0e9, 8)

SW_CAM_MINUS_POS_TAB_2 = MdDef(41502, "SW_CAM_MINUS_POS_TAB_2", N, FLOAT, (0.0,) * 8,
    "setting datum SD41502: positions of the minus cams 9-16 in the machine coordinate system",
    "seed 003 L41054-41073", "mm / deg", -1.0e9, 1.0e9, 8)

SW_CAM_PLUS_POS_TAB_2 = MdDef(41503, "SW_CAM_PLUS_POS_TAB_2", N, FLOAT, (0.0,) * 8,
    "setting datum SD41503: positions of the plus cams 9-16 in the machine coordinate system",
    "seed 003 L41054-41073", "mm / deg", -1.0e9, 1.0e9, 8)

SW_CAM_MINUS_POS_TAB_3 = MdDef(41504, "SW_CAM_MINUS_POS_TAB_3", N, FLOAT, (0.0,) * 8,
    "setting datum SD41504: positions of the minus cams 17-24 in the machine coordinate system",
    "seed 003 L41054-41073", "mm / deg", -1.0e9, 1.0e9, 8)

SW_CAM_PLUS_POS_TAB_3 = MdDef(41505, "SW_CAM_PLUS_POS_TAB_3", N, FLOAT, (0.0,) * 8,
    "setting datum SD41505: positions of the plus cams 17-24 in the machine coordinate system",
    "seed 003 L41054-41073", "mm / deg", -1.0e9, 1.0e9, 8)

SW_CAM_MINUS_POS_TAB_4 = MdDef(41506, "SW_CAM_MINUS_POS_TAB_4", N, FLOAT, (0.0,) * 8,
    "setting datum SD41506: positions of the minus cams 25-32 in the machine coordinate system",
    "seed 003 L41054-41073", "mm / deg", -1.0e9, 1.0e9, 8)

SW_CAM_PLUS_POS_TAB_4 = MdDef(41507, "SW_CAM_PLUS_POS_TAB_4", N, FLOAT, (0.0,) * 8,
    "setting datum SD41507: positions of the plus cams 25-32 in the machine coordinate system",
    "seed 003 L41054-41073", "mm / deg", -1.0e9, 1.0e9, 8)

SW_CAM_MINUS_TIME_TAB_1 = MdDef(41520, "SW_CAM_MINUS_TIME_TAB_1", N, FLOAT, (0.0,) * 8,
    "setting datum SD41520: lead (> 0) or delay (< 0) time of the minus cams 1-8, added to MD10460",
    "seed 003 L41161-41196; [control] range", "s", -10.0, 10.0, 8)

SW_CAM_PLUS_TIME_TAB_1 = MdDef(41521, "SW_CAM_PLUS_TIME_TAB_1", N, FLOAT, (0.0,) * 8,
    "setting datum SD41521: lead (> 0) or delay (< 0) time of the plus cams 1-8, added to MD10461",
    "seed 003 L41161-41196; [control] range", "s", -10.0, 10.0, 8)

SW_CAM_MINUS_TIME_TAB_2 = MdDef(41522, "SW_CAM_MINUS_TIME_TAB_2", N, FLOAT, (0.0,) * 8,
    "setting datum SD41522: lead (> 0) or delay (< 0) time of the minus cams 9-16, added to MD10460",
    "seed 003 L41161-41196; [control] range", "s", -10.0, 10.0, 8)

SW_CAM_PLUS_TIME_TAB_2 = MdDef(41523, "SW_CAM_PLUS_TIME_TAB_2", N, FLOAT, (0.0,) * 8,
    "setting datum SD41523: lead (> 0) or delay (< 0) time of the plus cams 9-16, added to MD10461",
    "seed 003 L41161-41196; [control] range", "s", -10.0, 10.0, 8)

SW_CAM_MINUS_TIME_TAB_3 = MdDef(41524, "SW_CAM_MINUS_TIME_TAB_3", N, FLOAT, (0.0,) * 8,
    "setting datum SD41524: lead (> 0) or delay (< 0) time of the minus cams 17-24, added to MD10460",
    "seed 003 L41161-41196; [control] range", "s", -10.0, 10.0, 8)

SW_CAM_PLUS_TIME_TAB_3 = MdDef(41525, "SW_CAM_PLUS_TIME_TAB_3", N, FLOAT, (0.0,) * 8,
    "setting datum SD41525: lead (> 0) or delay (< 0) time of the plus cams 17-24, added to MD10461",
    "seed 003 L41161-41196; [control] range", "s", -10.0, 10.0, 8)

SW_CAM_MINUS_TIME_TAB_4 = MdDef(41526, "SW_CAM_MINUS_TIME_TAB_4", N, FLOAT, (0.0,) * 8,
    "setting datum SD41526: lead (> 0) or delay (< 0) time of the minus cams 25-32, added to MD10460",
    "seed 003 L41161-41196; [control] range", "s", -10.0, 10.0, 8)

SW_CAM_PLUS_TIME_TAB_4 = MdDef(41527, "SW_CAM_PLUS_TIME_TAB_4", N, FLOAT, (0.0,) * 8,
    "setting datum SD41527: lead (> 0) or delay (< 0) time of the plus cams 25-32, added to MD10461",
    "seed 003 L41161-41196; [control] range", "s", -10.0, 10.0, 8)

SW_CAM_MINUS_POS_TABS = (SW_CAM_MINUS_POS_TAB_1, SW_CAM_MINUS_POS_TAB_2, SW_CAM_MINUS_POS_TAB_3,
                         SW_CAM_MINUS_POS_TAB_4)
SW_CAM_PLUS_POS_TABS = (SW_CAM_PLUS_POS_TAB_1, SW_CAM_PLUS_POS_TAB_2, SW_CAM_PLUS_POS_TAB_3, SW_CAM_PLUS_POS_TAB_4)
SW_CAM_MINUS_TIME_TABS = (SW_CAM_MINUS_TIME_TAB_1, SW_CAM_MINUS_TIME_TAB_2, SW_CAM_MINUS_TIME_TAB_3,
                          SW_CAM_MINUS_TIME_TAB_4)
SW_CAM_PLUS_TIME_TABS = (SW_CAM_PLUS_TIME_TAB_1, SW_CAM_PLUS_TIME_TAB_2, SW_CAM_PLUS_TIME_TAB_3,
                         SW_CAM_PLUS_TIME_TAB_4)


# ---------------------------------------------------------------------------------- channel
AXCONF_GEOAX_ASSIGN_TAB = MdDef(20050, "AXCONF_GEOAX_ASSIGN_TAB", C, INT, (1, 2, 3),
                                "channel axis number serving each geometry axis (0 = none)",
                                "[control]", "", 0, 20, 3)
AXCONF_GEOAX_NAME_TAB = MdDef(20060, "AXCONF_GEOAX_NAME_TAB", C, STR, ("X", "Y", "Z"),
                              "names of the geometry axes in the channel", "[control]", length=3)
AXCONF_MACHAX_USED = MdDef(20070, "AXCONF_MACHAX_USED", C, INT, (1, 2, 3, 4) + (0,) * 16,
                           "machine axis number of each channel axis (0 = none); the loader sets it from"
                           " the channel's axes list", "seed 003 L22075-22082; [control] default", "",
                           0, 31, 20)
AXCONF_CHANAX_NAME_TAB = MdDef(20080, "AXCONF_CHANAX_NAME_TAB", C, STR, ("",) * 20,
                               "names of the channel axes used in part programs; empty = the machine axis"
                               " name (project convention)", "[control]", length=20)
SPIND_DEF_MASTER_SPIND = MdDef(20090, "SPIND_DEF_MASTER_SPIND", C, INT, 1,
                               "default master spindle of the channel", "seed 003 L20340-20345", "", 0, 20)
SPIND_ASSIGN_TAB_ENABLE = MdDef(20092, "SPIND_ASSIGN_TAB_ENABLE", C, BOOL, False,
                                "enable the logical-to-physical spindle converter (SD42800)",
                                "seed 003 L20190-20198; [control] default")
SPIND_RIGID_TAPPING_M_NR = MdDef(20094, "SPIND_RIGID_TAPPING_M_NR", C, INT, 70,
                                 "M function that switches the spindle to axis mode",
                                 "seed 003 L17177-17181; [control] default M70", "", 0, 2_147_483_647)
DIAMETER_AX_DEF = MdDef(20100, "DIAMETER_AX_DEF", C, STR, "",
                        "geometry axis with transverse-axis function: the radius G96 / G961 compute the"
                        " spindle speed from (\"\" = none: G96 raises alarm 10870)",
                        "seed 003 L7728-7731, L7846-7851, L10635-10645", "")
RESET_MODE_MASK = MdDef(20110, "RESET_MODE_MASK", C, INT, 0x1,
                        "basic settings after reset / program end (bit mask); bit 0 = 1: reset behaviour"
                        " of the other bits active, bit 10: programmed coupling kept (1) or cancelled (0)",
                        "seed 003 L22968-22981; [control] default", "", 0, 0x7FFFFFFF)
START_MODE_MASK = MdDef(20112, "START_MODE_MASK", C, INT, 0x400,
                        "basic settings at NC start (bit mask); bit 10: programmed coupling cancelled (1) or"
                        " kept (0)", "seed 003 L22954-22956; [control] default", "", 0, 0x7FFFFFFF)
REFP_NC_START_LOCK = MdDef(20700, "REFP_NC_START_LOCK", C, INT, 1,
                           "NC start disabled without reference point: 0 = allowed, 1 = disabled,"
                           " 2 = allowed with restored positions in MDA and overstore",
                           "seed 003 L2218-2231, L2726-2752; [control] default 1", "", 0, 2,
                           allowed=(0, 1, 2))
DRY_RUN_FEED = MdDef(42100, "DRY_RUN_FEED", C, FLOAT, 5000.0,
                     "setting datum SD42100 $SC_DRY_RUN_FEED: the dry-run feed, always mm/min (G94) (kept here"
                     " with the channel's machine data)", "seed 003 L9395-9402, L9429-9433; [control] default",
                     "mm/min", 0.0, 1.0e6)
DRY_RUN_FEED_MODE = MdDef(42101, "DRY_RUN_FEED_MODE", C, INT, 0,
                          "setting datum SD42101: 0 = the larger of F and SD42100, 1 = the smaller, 2 = SD42100"
                          " alone; 10 / 11 / 12 as 0 / 1 / 2 but threads and tapping keep F",
                          "seed 003 L9447-9470", "", 0, 12, allowed=(0, 1, 2, 10, 11, 12))
ALLOW_G0_IN_G96 = MdDef(20750, "ALLOW_G0_IN_G96", C, BOOL, False,
                        "G0 logic in G96 / G961: 0 = the spindle speed stays as it is during a rapid block"
                        " (G96 acts where F acts), 1 = the speed of the rapid block's end point is set at"
                        " its start, so the spindle reaches it while the axes travel",
                        "seed 003 L7748-7753; [control] the meaning of the two values")
SPOS_TO_VDI = MdDef(20850, "SPOS_TO_VDI", C, INT, 0,
                    "bit 0 = 1: SPOS/SPOSA output the auxiliary function M19 to the PLC",
                    "seed 003 L16406-16420; [control] default", "", 0, 1)
CIRCLE_ERROR_CONST = MdDef(21000, "CIRCLE_ERROR_CONST", C, FLOAT, 0.01,
                           "G2/G3: the end point's radius may differ from the start radius by this or by"
                           " MD21010 x the start radius, whichever is larger (else alarm 14040)",
                           "[control] number, name and default (not in the seeds)", "mm", 0.0, 1.0e3)
CIRCLE_ERROR_FACTOR = MdDef(21010, "CIRCLE_ERROR_FACTOR", C, FLOAT, 0.001,
                            "G2/G3: radius difference allowed at the end point as a share of the start radius",
                            "[control] number, name and default (not in the seeds)", "", 0.0, 1.0)
LIFTFAST_DIST = MdDef(21200, "LIFTFAST_DIST", C, FLOAT, 0.1,
                      "default retract distance of fast retraction (LFON); DILF overrides it until reset",
                      "seed 003 L8266-8273, L8398; [control] default", "mm", 0.0, 1.0e6)
COUPLE_AXIS_1 = MdDef(21300, "COUPLE_AXIS_1", C, INT, (0, 0),
                      "machine axis numbers of the configured synchronous spindle pair: [0] = following,"
                      " [1] = leading spindle; 0 = no configured pair",
                      "seed 003 L22869-22881, L21887-21893; [control] default", "", 0, 31, 2)
COUPLING_MODE_1 = MdDef(21310, "COUPLING_MODE_1", C, INT, 1,
                        "coupling type of the configured pair: 0 = actual value (AV), 1 = setpoint (DV),"
                        " 2 = velocity (VV)", "seed 003 L22900-22906; [control] coding and default", "", 0, 2,
                        allowed=(0, 1, 2))
COUPLE_BLOCK_CHANGE_CTRL_1 = MdDef(21320, "COUPLE_BLOCK_CHANGE_CTRL_1", C, INT, 1,
                                   "block change after COUPON: 0 = immediately, 1 = synchronism fine,"
                                   " 2 = synchronism coarse, 3 = setpoint synchronism (IPOSTOP)",
                                   "seed 003 L22883-22897; [control] coding and default", "", 0, 3,
                                   allowed=(0, 1, 2, 3))
COUPLE_RESET_MODE_1 = MdDef(21330, "COUPLE_RESET_MODE_1", C, INT, 0x1,
                            "configured pair at NC start / reset (bit mask): bit 0 cancel at NC start,"
                            " bit 1 cancel at reset, bit 5/6 activate configured data, bit 9 activate at"
                            " NC start",
                            "seed 003 L22908-22912, L22946-22975; [control] default", "", 0, 0x3FF)
COUPLE_IS_WRITE_PROT_1 = MdDef(21340, "COUPLE_IS_WRITE_PROT_1", C, BOOL, False,
                               "COUPDEF may not change ratio, type and block change of the configured pair",
                               "seed 003 L21986-21991; [control] default")
COUPLE_RATIO_1 = MdDef(42300, "COUPLE_RATIO_1", C, FLOAT, (1.0, 1.0),
                       "setting datum SD42300 $SC_COUPLE_RATIO_1: speed ratio of the configured pair, [0] ="
                       " numerator (FS), [1] = denominator (LS); COUPDEF changes the active ratio, not this"
                       " value (kept here with the channel's machine data)",
                       "seed 003 L22923-22936, L21919-21926; [control] default", "", -1.0e6, 1.0e6, 2,
                       nonzero="a ratio of 0 couples nothing, a denominator of 0 divides by 0 [control]")
ESR_DELAY_TIME1 = MdDef(21380, "ESR_DELAY_TIME1", C, FLOAT, 0.0,
                        "NC-controlled stop: time the path interpolation continues after the ESR trigger",
                        "seed 003 L42152-42154; [control] default", "s", 0.0, 1.0e3)
ESR_DELAY_TIME2 = MdDef(21381, "ESR_DELAY_TIME2", C, FLOAT, 0.04,
                        "NC-controlled stop: braking time after MD21380",
                        "seed 003 L42156; [control] default",
                        "s", 0.0, 1.0e3)


# ------------------------------------------------------------ channel: auxiliary function output (H2)
# The seed points at the control's "auxiliary function output to the PLC" (seed 003 L7390-7395,
# L8893-8897, L16391-16455, L17456-17490); the data below are the real control's, marked [control].
AUXFU_ASSIGN_ENTRIES = 32  # entries of MD22000 .. MD22035 here (the control sizes them with MD11100)
AUXFU_ASSIGN_GROUP = MdDef(22000, "AUXFU_ASSIGN_GROUP", C, INT, (0,) * AUXFU_ASSIGN_ENTRIES,
                           "auxiliary function group of the user-defined auxiliary function n (0 = entry unused):"
                           " one function of a group per block (alarm 14760)",
                           "seed 003 L16399-16404 (example); [control] meaning and default", "", 0, 64,
                           AUXFU_ASSIGN_ENTRIES)
AUXFU_ASSIGN_TYPE = MdDef(22010, "AUXFU_ASSIGN_TYPE", C, STR, ("",) * AUXFU_ASSIGN_ENTRIES,
                          "type of the user-defined auxiliary function n: M, S, T, D, DL, H or F",
                          "seed 003 L16399-16404 (example); [control]", length=AUXFU_ASSIGN_ENTRIES)
AUXFU_ASSIGN_EXTENSION = MdDef(22020, "AUXFU_ASSIGN_EXTENSION", C, INT, (0,) * AUXFU_ASSIGN_ENTRIES,
                               "extended address of the user-defined auxiliary function n (-1 = every extension)",
                               "seed 003 L16399-16404 (example); [control]", "", -1, 99, AUXFU_ASSIGN_ENTRIES)
AUXFU_ASSIGN_VALUE = MdDef(22030, "AUXFU_ASSIGN_VALUE", C, INT, (0,) * AUXFU_ASSIGN_ENTRIES,
                           "value of the user-defined auxiliary function n (-1 = every value of its type and"
                           " extension)", "seed 003 L16399-16404 (example); [control]", "", -1, 2_147_483_647,
                           AUXFU_ASSIGN_ENTRIES)
AUXFU_ASSIGN_SPEC = MdDef(22035, "AUXFU_ASSIGN_SPEC", C, INT, (0x121,) * AUXFU_ASSIGN_ENTRIES,
                          "output behaviour of the user-defined auxiliary function n, bits: 0 acknowledgement"
                          " normal (one PLC cycle), 1 quick (the block does not wait), 3 no output to the PLC,"
                          " 5 output before the motion, 6 during the motion, 7 at the block end (none of 5..7:"
                          " the type's MD22200 ..); the other bits are not modelled",
                          "[control] number, bits and default 0x121 (docs/auxiliary_functions.md)", "", 0, 0xFFFFF,
                          AUXFU_ASSIGN_ENTRIES)
_SYNC_TYPE = ("when the {what} go to the PLC: 0 before the motion of the block (the motion starts once they"
              " are acknowledged), 1 during the motion, 2 at the block end, 3 not at all")
AUXFU_M_SYNC_TYPE = MdDef(22200, "AUXFU_M_SYNC_TYPE", C, INT, 1, _SYNC_TYPE.format(what="M functions"),
                          "[control] number, coding and default (docs/auxiliary_functions.md)", "", 0, 3,
                          allowed=(0, 1, 2, 3))
AUXFU_S_SYNC_TYPE = MdDef(22210, "AUXFU_S_SYNC_TYPE", C, INT, 1, _SYNC_TYPE.format(what="S functions"),
                          "[control] number, coding and default", "", 0, 3, allowed=(0, 1, 2, 3))
AUXFU_T_SYNC_TYPE = MdDef(22220, "AUXFU_T_SYNC_TYPE", C, INT, 1, _SYNC_TYPE.format(what="T functions"),
                          "[control] number, coding and default", "", 0, 3, allowed=(0, 1, 2, 3))
AUXFU_H_SYNC_TYPE = MdDef(22230, "AUXFU_H_SYNC_TYPE", C, INT, 1, _SYNC_TYPE.format(what="H functions"),
                          "[control] number, coding and default", "", 0, 3, allowed=(0, 1, 2, 3))
AUXFU_F_SYNC_TYPE = MdDef(22240, "AUXFU_F_SYNC_TYPE", C, INT, 3, _SYNC_TYPE.format(what="F functions") +
                          "; 3 by default: an F output in continuous-path mode could cause velocity jumps",
                          "seed 003 L8893-8897 (default 3); [control] coding", "", 0, 3, allowed=(0, 1, 2, 3))
AUXFU_D_SYNC_TYPE = MdDef(22250, "AUXFU_D_SYNC_TYPE", C, INT, 1, _SYNC_TYPE.format(what="D functions"),
                          "[control] number, coding and default", "", 0, 3, allowed=(0, 1, 2, 3))
AUXFU_DL_SYNC_TYPE = MdDef(22252, "AUXFU_DL_SYNC_TYPE", C, INT, 1, _SYNC_TYPE.format(what="DL functions"),
                           "[control] number, coding and default", "", 0, 3, allowed=(0, 1, 2, 3))
TOOL_CHANGE_MODE = MdDef(22550, "TOOL_CHANGE_MODE", C, INT, 0,
                         "0 = T changes the tool (a turret: the T word selects and activates it), 1 = T preselects,"
                         " the M function of MD22560 changes", "[control] number, coding and default", "", 0, 1,
                         allowed=(0, 1))
TOOL_CHANGE_M_CODE = MdDef(22560, "TOOL_CHANGE_M_CODE", C, INT, 6,
                           "M function of the tool change with MD22550 = 1", "[control] number and default M6", "",
                           0, 2_147_483_647)

# ---------------------------------------------------------------------------------- axis
IS_ROT_AX = MdDef(30300, "IS_ROT_AX", A, BOOL, False, "rotary axis / spindle", "[control]")
ROT_IS_MODULO = MdDef(30310, "ROT_IS_MODULO", A, BOOL, False, "modulo conversion for a rotary axis",
                      "seed 003 L2826-2827")
MODULO_RANGE = MdDef(30330, "MODULO_RANGE", A, FLOAT, 360.0, "size of the modulo range",
                     "seed 003 L1662-1663",
                     "deg", 1.0, 360000.0)
MODULO_RANGE_START = MdDef(30340, "MODULO_RANGE_START", A, FLOAT, 0.0, "start of the modulo range",
                           "seed 003 L1662-1663; [control] default", "deg", -360000.0, 360000.0)
ENC_TYPE = MdDef(30240, "ENC_TYPE", A, INT, (1,) * 2, "encoder type: 0 = simulated, 1 = incremental, 4 = absolute",
                 "seed 003 L2363-2365, L5881-5883", "", 0, 4, allowed=(0, 1, 4), length=2)
ENC_RESOL = MdDef(31020, "ENC_RESOL", A, INT, (2048,) * 2, "encoder lines per revolution", "seed 003 L2533", "",
                  1, 10_000_000, length=2)
LEADSCREW_PITCH = MdDef(31030, "LEADSCREW_PITCH", A, FLOAT, 10.0,
                        "leadscrew pitch: travel per leadscrew revolution", "[control]", "mm",
                        0.001, 10_000.0)
ENC_IS_DIRECT = MdDef(31040, "ENC_IS_DIRECT", A, BOOL, (False,) * 2,
                      "encoder mounted directly on the machine (0 = motor encoder)", "seed 003 L16884-16888", length=2)
DRIVE_AX_RATIO_DENOM = MdDef(31050, "DRIVE_AX_RATIO_DENOM", A, INT, (1,) * 6,
                             "load gearbox denominator (load revolutions) per parameter set",
                             "seed 003 L19022-19034", "", -2_147_000_000, 2_147_000_000, 6,
                             nonzero="the seed says 0 cannot be entered, L19032")
DRIVE_AX_RATIO_NUMERA = MdDef(31060, "DRIVE_AX_RATIO_NUMERA", A, INT, (1,) * 6,
                              "load gearbox numerator (motor revolutions) per parameter set",
                              "seed 003 L19022-19034", "", -2_147_000_000, 2_147_000_000, 6,
                              nonzero="the seed says 0 cannot be entered, L19032")
JOG_INCR_WEIGHT = MdDef(31090, "JOG_INCR_WEIGHT", A, FLOAT, (0.001, 0.00254),
                        "the travel of one increment in incremental JOG and per handwheel detent ([0] metric,"
                        " [1] inch); a negative value reverses the traverse keys' direction of an increment",
                        "seed 003 L5476-5488, L33080-33088, L33143", "mm", -1.0e3, 1.0e3, 2)
MAX_AX_VELO = MdDef(32000, "MAX_AX_VELO", A, FLOAT, 10000.0, "maximum axis velocity",
                    "seed 003 L8340-8349, L21166-21168; [control] default", "mm/min", 0.0, 1.0e7,
                    nonzero="the axis could never move, and its rapid-stop ramp is scaled by it")
JOG_VELO_RAPID = MdDef(32010, "JOG_VELO_RAPID", A, FLOAT, 10000.0, "rapid traverse in JOG", "[control]",
                       "mm/min", 0.0, 1.0e7)
POS_AX_VELO = MdDef(32060, "POS_AX_VELO", A, FLOAT, 10000.0, "initial setting of the positioning axis velocity",
                    "seed 003 L11592-11594 (a command axis without FA); [control] default", "mm/min", 0.0, 1.0e7)
JOG_VELO = MdDef(32020, "JOG_VELO", A, FLOAT, 2000.0, "JOG velocity", "[control]", "mm/min", 0.0, 1.0e7)
HANDWH_VELO_OVERLAY_FACTOR = MdDef(32090, "HANDWH_VELO_OVERLAY_FACTOR", A, FLOAT, 0.5,
                                   "handwheel velocity of the DRF offset per JOG velocity",
                                   "seed 003 L36517-36519; [control] default", "", 0.0, 1.0)
POSCTRL_GAIN = MdDef(32200, "POSCTRL_GAIN", A, FLOAT, _repeat(16.667, 6),
                     "servo gain factor Kv per parameter set (16.667/s = 1 (m/min)/mm)", "[control]",
                     "1/s", 0.0, 2000.0, 6)
MAX_AX_ACCEL = MdDef(32300, "MAX_AX_ACCEL", A, FLOAT, _repeat(1.0, 5), "maximum axis acceleration",
                     "seed 003 L8340-8349; [control] default", "m/s^2", 0.001, 1000.0, 5)
AX_JERK_ENABLE = MdDef(32400, "AX_JERK_ENABLE", A, BOOL, False,
                       "axial jerk limitation: filter on the position setpoint", "[control]")
AX_JERK_MODE = MdDef(32402, "AX_JERK_MODE", A, INT, 2,
                     "kind of axial jerk filter: 1 = 2nd order filter, 2 = moving average", "[control]", "",
                     1, 2, allowed=(1, 2))
AX_JERK_TIME = MdDef(32410, "AX_JERK_TIME", A, FLOAT, 0.016, "time constant of the axial jerk filter",
                     "[control]", "s", 0.0, 0.2)
# like on LS and FS of a synchronous spindle pair (L23736-23748); the core's filter reads only 32400-32410
AX_JERK_FREQ = MdDef(32412, "AX_JERK_FREQ", A, FLOAT, 10.0, "blocking frequency of the axial jerk filter",
                     "seed 003 L23744; [control] default", "Hz", 0.0, 1000.0)
AX_JERK_DAMP = MdDef(32414, "AX_JERK_DAMP", A, FLOAT, 0.0, "damping of the axial jerk filter",
                     "seed 003 L23745; [control] default", "", 0.0, 1.0)
JOG_AND_POS_JERK_ENABLE = MdDef(32420, "JOG_AND_POS_JERK_ENABLE", A, BOOL, False,
                                "jerk limitation in JOG and positioning", "seed 003 L23746; [control] default")
JOG_AND_POS_MAX_JERK = MdDef(32430, "JOG_AND_POS_MAX_JERK", A, FLOAT, 1000.0, "axial jerk in JOG and positioning",
                             "seed 003 L23747; [control] default", "m/s^3", 0.001, 1.0e6)
FIPO_TYPE = MdDef(33000, "FIPO_TYPE", A, INT, 2, "fine interpolator type: 1 differential, 2 cubic, 3 cubic"
                  " optimised", "seed 003 L23740; [control] default", "", 1, 3, allowed=(1, 2, 3))
MAX_AX_JERK = MdDef(32431, "MAX_AX_JERK", A, FLOAT, _repeat(1000.0, 5),
                    "maximum axial jerk for path motion with SOFT", "seed 003 L8340-8349; [control] default",
                    "m/s^3", 0.001, 1.0e6, 5)
VELO_FFW_WEIGHT = MdDef(32610, "VELO_FFW_WEIGHT", A, FLOAT, _repeat(1.0, 6),
                        "feedforward weighting factor", "[control]", "", 0.0, 1.2, 6)
FFW_MODE = MdDef(32620, "FFW_MODE", A, INT, 1, "feedforward: 0 = off, 1 = speed feedforward,"
                 " 3 = speed feedforward with symmetrising", "seed 003 L17265-17268, L22997-23006",
                 "", 0, 4, allowed=(0, 1, 2, 3, 4))
EQUIV_SPEEDCTRL_TIME = MdDef(32810, "EQUIV_SPEEDCTRL_TIME", A, FLOAT, _repeat(0.004, 6),
                             "equivalent time constant of the closed speed control loop",
                             "seed 003 L23700-23721; [control] default", "s", 0.0, 1.0, 6)
DYN_MATCH_ENABLE = MdDef(32900, "DYN_MATCH_ENABLE", A, BOOL, False,
                         "dynamic-response matching: the position setpoint is delayed by MD32910",
                         "seed 003 L23706-23719; [control] default")
DYN_MATCH_TIME = MdDef(32910, "DYN_MATCH_TIME", A, FLOAT, _repeat(0.0, 6),
                       "time constant of dynamic-response matching: the slowest axis's equivalent time"
                       " MD32810 less this axis's", "seed 003 L23706-23719; [control] default", "s", 0.0, 1.0, 6)
SPIND_ASSIGN_TO_MACHAX = MdDef(35000, "SPIND_ASSIGN_TO_MACHAX", A, INT, 0,
                               "spindle number of the machine axis (0 = not a spindle)",
                               "seed 003 L20186-20188", "", 0, 20)
STOP_LIMIT_COARSE = MdDef(36000, "STOP_LIMIT_COARSE", A, FLOAT, 0.04, "exact stop coarse window",
                          "seed 003 L21210-21240; [control] default", "mm", 0.0, 1.0e6)
# JOG to a fixed point (seed 003 §16.9.2) and to a position (§16.10.2)
FIX_POINT_POS = MdDef(30600, "FIX_POINT_POS", A, FLOAT, (0.0,) * 4,
                      "the fixed points 1..4 of JOG to fixed point (DB31.DBX13.0..13.2), machine coordinates",
                      "seed 003 L34435-34437, L34563-34569", "mm", -1.0e8, 1.0e8, 4)
NUM_FIX_POINT_POS = MdDef(30610, "NUM_FIX_POINT_POS", A, INT, 0,
                          "how many of MD30600's fixed points are valid (0 = none)",
                          "seed 003 L34435, L34441-34446; [control] default 0", "", 0, 4)
JOG_POSITION = MdDef(43320, "JOG_POSITION", A, FLOAT, 0.0,
                     "setting datum SD43320 $SA_JOG_POSITION: the position of JOG to position (DB31.DBX13.3),"
                     " machine coordinates",
                     "seed 003 L34644-34646, L34800-34802, L34858; [control] default 0", "mm", -1.0e8, 1.0e8)
STOP_LIMIT_FINE = MdDef(36010, "STOP_LIMIT_FINE", A, FLOAT, 0.01, "exact stop fine window",
                        "seed 003 L21210-21240; [control] default", "mm", 0.0, 1.0e6)
POSITIONING_TIME = MdDef(36020, "POSITIONING_TIME", A, FLOAT, 1.0,
                         "delay for exact stop fine at the end of a motion (then alarm 25080)",
                         "[control]", "s", 0.0, 1.0e5)
STANDSTILL_POS_TOL = MdDef(36030, "STANDSTILL_POS_TOL", A, FLOAT, 0.2, "standstill tolerance (alarm 25040)",
                           "[control]", "mm", 0.0, 1.0e6)
STANDSTILL_DELAY_TIME = MdDef(36040, "STANDSTILL_DELAY_TIME", A, FLOAT, 0.4,
                              "delay before standstill monitoring starts", "[control]", "s", 0.0, 1.0e5)
CLAMP_POS_TOL = MdDef(36050, "CLAMP_POS_TOL", A, FLOAT, 0.5,
                      "clamping tolerance: how far a clamped axis (DB31.DBX2.3) may leave its position (alarm 26000)",
                      "seed 003 L15436, L15524 (DB31.DBX2.3); [control] number, meaning and default", "mm",
                      0.0, 1.0e6)
STANDSTILL_VELO_TOL = MdDef(36060, "STANDSTILL_VELO_TOL", A, FLOAT, 0.2,
                            "maximum velocity for 'axis/spindle stationary'", "seed 003 L20780-20787;"
                            " [control] default", "mm/min", 0.0, 1.0e6)
POS_LIMIT_MINUS = MdDef(36100, "POS_LIMIT_MINUS", A, FLOAT, -1.0e8, "1st software limit switch minus",
                        "[control]", "mm", -1.0e9, 1.0e9)
POS_LIMIT_PLUS = MdDef(36110, "POS_LIMIT_PLUS", A, FLOAT, 1.0e8, "1st software limit switch plus",
                       "[control]", "mm", -1.0e9, 1.0e9)
POS_LIMIT_MINUS2 = MdDef(36120, "POS_LIMIT_MINUS2", A, FLOAT, -1.0e8,
                         "2nd software limit switch minus: in force instead of MD36100 while DB31.DBX12.2 = 1",
                         "seed 003 L12835-12843, L12940; [control] default and the switchover", "mm", -1.0e9, 1.0e9)
POS_LIMIT_PLUS2 = MdDef(36130, "POS_LIMIT_PLUS2", A, FLOAT, 1.0e8,
                        "2nd software limit switch plus: in force instead of MD36110 while DB31.DBX12.3 = 1",
                        "seed 003 L12835-12843, L12941; [control] default and the switchover", "mm", -1.0e9, 1.0e9)
CONTOUR_TOL = MdDef(36400, "CONTOUR_TOL", A, FLOAT, 1.0, "tolerance band of contour monitoring (alarm 25050)",
                    "[control]", "mm", 0.0, 1.0e6)
BRAKE_MODE_CHOICE = MdDef(36600, "BRAKE_MODE_CHOICE", A, INT, 0,
                          "braking at a hardware limit switch: 0 = braking ramp, 1 = rapid stop", "[control]",
                          "", 0, 1, allowed=(0, 1))
AX_EMERGENCY_STOP_TIME = MdDef(36610, "AX_EMERGENCY_STOP_TIME", A, FLOAT, 0.05,
                               "braking ramp time for error states (rapid stop)", "[control]", "s",
                               0.0, 1.0e3)
SERVO_DISABLE_DELAY_TIME = MdDef(36620, "SERVO_DISABLE_DELAY_TIME", A, FLOAT, 0.1,
                                 "delay before the controller enable is removed after a rapid stop",
                                 "[control]", "s", 0.0, 1.0e3)

# ---------------------------------------------------------------------------------- axis: encoder
# Encoder-specific data (the control's [n] = measuring system 1/2) are modelled for measuring
# system 1 only, as scalars, like MD30240 ENC_TYPE above.
ENC_IS_INDEPENDENT = MdDef(30242, "ENC_IS_INDEPENDENT", A, INT, (0,) * 2,
                           "encoder independence: 0 = not independent, 1 = independent, 2 = passive encoder"
                           " compensated from the active one, 3 = passive distance-coded encoder referenced"
                           " automatically", "seed 003 L1757-1762, L5931-5943; [control] default", "", 0, 3,
                           allowed=(0, 1, 2, 3), length=2)
ACT_POS_ABS = MdDef(30250, "ACT_POS_ABS", A, FLOAT, (0.0,) * 2,
                    "absolute encoder position at switch-off (internal encoder position, normally written"
                    " by the control)", "seed 003 L2022, L2366, L2462; [control] default", "", -1.0e9, 1.0e9, length=2)
ENC_ABS_BUFFERING = MdDef(30270, "ENC_ABS_BUFFERING", A, INT, 0,
                          "absolute encoder traversing range extension: 0 = active (default), 1 = off",
                          "seed 003 L2377-2378, L2464", "", 0, 1, allowed=(0, 1))
MISC_FUNCTION_MASK = MdDef(30455, "MISC_FUNCTION_MASK", A, INT, 0,
                           "axis functions (bit mask): bit 1 modulo mapping of distance-coded reference,"
                           " bit 4 feed stop acts on the FS only, bit 5 FS control parameters, bit 6 uniform"
                           " FA/OVRA/ACC, bit 7 edge-triggered synchronism measurement",
                           "seed 003 L1665-1672, L22391-22401, L23756-23797, L31462-31476; [control] default",
                           "", 0, 0xFFFF)
BASE_FUNCTION_MASK = MdDef(30460, "BASE_FUNCTION_MASK", A, INT, 0,
                           "axis functions (bit mask) of a PLC axis: bit 4 the axis is controlled by the PLC"
                           " only (26075), bit 5 it is assigned to the PLC for good and starts as a neutral"
                           " axis (26076), bit 6 the channel's feed disable DB21.DBX6.0 does not act on it while"
                           " the PLC moves it, bit 7 DB21.DBX36.3 leaves it out while the PLC moves it, bit 8"
                           " a positioning axis / auxiliary spindle only (no path or geometry axis, no thread:"
                           " 14092)",
                           "seed 003 L12181-12218, L12499-12540, L10843-10858; bits 0-3 (bit 2 diameter"
                           " programming, L10481) [control] are accepted and not built",
                           "", 0, 0x1FF)
AXCONF_ASSIGN_MASTER_CHAN = MdDef(30550, "AXCONF_ASSIGN_MASTER_CHAN", A, INT, 0,
                                  "master channel of the axis (0 = the channel whose axes list holds it);"
                                  " axis-specific referencing runs in it",
                                  "seed 003 L616-620, L22082; [control] default", "", 0, 10)
ENC_IS_LINEAR = MdDef(31000, "ENC_IS_LINEAR", A, BOOL, (False,) * 2, "the measuring system is a linear scale",
                      "seed 003 L2422-2424, L6291", length=2)
BERO_DELAY_TIME_PLUS = MdDef(31122, "BERO_DELAY_TIME_PLUS", A, FLOAT, 0.000110,
                             "BERO signal delay compensation, plus direction (spindle)",
                             "seed 003 L18045-18068; [control] delivery value", "s", 0.0, 1.0)
BERO_DELAY_TIME_MINUS = MdDef(31123, "BERO_DELAY_TIME_MINUS", A, FLOAT, 0.000078,
                              "BERO signal delay compensation, minus direction (spindle)",
                              "seed 003 L18045-18068; [control] delivery value", "s", 0.0, 1.0)

# ---------------------------------------------------------------------------------- axis: referencing
REFP_CAM_IS_ACTIVE = MdDef(34000, "REFP_CAM_IS_ACTIVE", A, BOOL, True,
                           "axis with reference cam (0 = one zero mark in the whole range / per revolution)",
                           "seed 003 L1022-1035, L1621-1633; [control] default")
REFP_CAM_DIR_IS_MINUS = MdDef(34010, "REFP_CAM_DIR_IS_MINUS", A, BOOL, False,
                              "reference point approach in minus direction (0 = plus): the traverse key that"
                              " starts referencing and the phase-1 direction",
                              "seed 003 L539-551, L1001-1003, L1092-1097; [control] default")
REFP_VELO_SEARCH_CAM = MdDef(34020, "REFP_VELO_SEARCH_CAM", A, FLOAT, 5000.0,
                             "reference point approach velocity (phase 1)",
                             "seed 003 L1003, L1137; [control] default", "mm/min", 0.0, 1.0e7)
REFP_MAX_CAM_DIST = MdDef(34030, "REFP_MAX_CAM_DIST", A, FLOAT, 10000.0,
                          "maximum distance to the reference cam; the axis stops if no cam is found",
                          "seed 003 L1046-1048; [control] default", "mm", 0.0, 1.0e8)
REFP_VELO_SEARCH_MARKER = MdDef(34040, "REFP_VELO_SEARCH_MARKER", A, FLOAT, 300.0,
                                "reference point creep velocity (phase 2 zero-mark search; BERO mode 7)",
                                "seed 003 L1126, L1148, L1512-1513, L18062-18064; [control] default",
                                "mm/min", 0.0, 1.0e7)
REFP_SEARCH_MARKER_REVERSE = MdDef(34050, "REFP_SEARCH_MARKER_REVERSE", A, BOOL, False,
                                   "direction reversal on the cam: 0 = sync on the falling cam edge,"
                                   " 1 = on the rising edge", "seed 003 L1086-1107; [control] default")
REFP_MAX_MARKER_DIST = MdDef(34060, "REFP_MAX_MARKER_DIST", A, FLOAT, 20.0,
                             "maximum distance to the zero mark (phase 2); the axis stops if none is found",
                             "seed 003 L1262-1264, L1566-1568, L16912-16915, L2446; [control] default",
                             "mm", 0.0, 1.0e8)
REFP_VELO_POS = MdDef(34070, "REFP_VELO_POS", A, FLOAT, 10000.0,
                      "reference point positioning velocity (phase 3)",
                      "seed 003 L1303-1305, L1605; [control] default", "mm/min", 0.0, 1.0e7)
REFP_MOVE_DIST = MdDef(34080, "REFP_MOVE_DIST", A, FLOAT, 2.0,
                       "reference point distance: zero mark to reference point"
                       " (distance-coded: target point)",
                       "seed 003 L1307-1311, L18020; [control] default", "mm", -1.0e8, 1.0e8)
REFP_MOVE_DIST_CORR = MdDef(34090, "REFP_MOVE_DIST_CORR", A, FLOAT, (0.0,) * 2,
                            "reference point offset; absolute encoder: machine zero to encoder zero",
                            "seed 003 L1311, L1400-1444, L2066-2068; [control] default", "mm", -1.0e9, 1.0e9, length=2)
REFP_CAM_SHIFT = MdDef(34092, "REFP_CAM_SHIFT", A, FLOAT, 0.0,
                       "electronic reference cam shift in zero-mark search direction (only with MD34000 = 1)",
                       "seed 003 L1159-1189, L15747; [control] default", "mm", 0.0, 1.0e6)
REFP_CAM_MARKER_DIST = MdDef(34093, "REFP_CAM_MARKER_DIST", A, FLOAT, (0.0,) * 2,
                             "measured distance from leaving the cam to the zero mark (the control writes it"
                             " during referencing)", "seed 003 L1239-1246", "mm", read_only=True, length=2)
REFP_SET_POS = MdDef(34100, "REFP_SET_POS", A, FLOAT, _repeat(0.0, 4),
                     "reference point value n, selected by DB31.DBX2.4..2.7",
                     "seed 003 L1316-1322, L2132, L2271-2274; [control] default", "mm", -1.0e9, 1.0e9, 4)
REFP_SYNC_ENCS = MdDef(34102, "REFP_SYNC_ENCS", A, BOOL, False,
                       "compensate the other measuring system after referencing",
                       "seed 003 L1709-1713, L1749; [control] default")
REFP_PERMITTED_IN_FOLLOWUP = MdDef(34104, "REFP_PERMITTED_IN_FOLLOWUP", A, BOOL, False,
                                   "referencing permitted in follow-up mode",
                                   "seed 003 L1843-1845; [control] default")
REFP_CYCLE_NR = MdDef(34110, "REFP_CYCLE_NR", A, INT, 1,
                      "order in channel-specific referencing: -1 = not needed for NC start, 0 = does not take"
                      " part, 1..15 = sequence number (equal numbers together)",
                      "seed 003 L667-683, L2750; [control] default", "", -1, 15)
ENC_REFP_MODE = MdDef(34200, "ENC_REFP_MODE", A, INT, (1,) * 2,
                      "referencing mode: 0 = take over the reference value (absolute encoder), 1 = zero mark,"
                      " 2/7 = spindle BERO, 3 = distance-coded, 4 = [GAP], 8 = distance-coded with 4 marks",
                      "seed 003 L928-930, L1448-1462, L18060-18070, L2379-2380; [control] default", "", 0, 8,
                      allowed=(0, 1, 2, 3, 4, 7, 8), length=2)
ENC_REFP_STATE = MdDef(34210, "ENC_REFP_STATE", A, INT, (0,) * 2,
                       "absolute encoder: 0 = not calibrated, 1 = calibration enabled, 2 = calibrated;"
                       " incremental: 1..3 = automatic referencing / restoring (see seed)",
                       "seed 003 L1970-1978, L2653-2742; [control] default", "", 0, 3, length=2)
ENC_ABS_TURNS_MODULO = MdDef(34220, "ENC_ABS_TURNS_MODULO", A, INT, (4096,) * 2,
                             "absolute encoder modulo range in revolutions (e.g. EQN 1325: 4096)",
                             "seed 003 L2390-2392, L2814-2836; [control] default", "", 1, 100_000, length=2)
ENC_REFP_MARKER_DIST = MdDef(34300, "ENC_REFP_MARKER_DIST", A, FLOAT, (20.0,) * 2,
                             "reference mark spacing of a distance-coded scale",
                             "seed 003 L1550-1561; [control] default", "mm", 0.0, 1.0e6, length=2,
                             nonzero="marks 0 mm apart are no scale; the mark layout divides by it")
ENC_INVERS = MdDef(34320, "ENC_INVERS", A, BOOL, (False,) * 2,
                   "length measuring system runs opposite to the machine coordinate system; the actual"
                   " value is MD34090 + (or, inverted, -) the scale's distance from its first mark, so the"
                   " calibration is MD34090 = measured - displayed in both orientations [control]: the"
                   " seed's table (same: measured + displayed) fits no additive offset",
                   "seed 003 L1404-1407, L1431-1437; [control] default", length=2)
REFP_STOP_AT_ABS_MARKER = MdDef(34330, "REFP_STOP_AT_ABS_MARKER", A, BOOL, True,
                                "distance-coded / absolute: 0 = travel to the reference position MD34100,"
                                " 1 = referencing ends without travel",
                                "seed 003 L1591-1599, L2331-2343; [control] default")

# ---------------------------------------------------------------------------------- axis: spindle
# Gear-stage arrays have 6 indices as on the control: index n = gear stage n, index 0 = gear
# stage 0 / axis mode.  Speeds in rev/min, accelerations in rev/s^2, positions in degrees.
GEAR_STEP_CHANGE_ENABLE = MdDef(35010, "GEAR_STEP_CHANGE_ENABLE", A, INT, 0,
                                "gear-stage change (bits): 0 = fixed ratio of gear stage 1; bit 0 = up to 5"
                                " stages, change with oscillation; bit 1 = change at the position MD35012;"
                                " bit 3 = simulate the NC/PLC gear-change dialog; bit 5 = 2nd data set for"
                                " G331/G332", "seed 003 L18245-18276, L19537, L19803", "", 0, 0x3F)
GEAR_STEP_CHANGE_POSITION = MdDef(35012, "GEAR_STEP_CHANGE_POSITION", A, FLOAT, _repeat(0.0, 6),
                                  "gear-change position per gear stage (approached with the current gear)",
                                  "seed 003 L18219, L19661-19664; [control] default", "deg", 0.0, 360.0, 6)
GEAR_STEP_USED_IN_AXISMODE = MdDef(35014, "GEAR_STEP_USED_IN_AXISMODE", A, INT, 0,
                                   "gear stage engaged on M70: 0 = keep the current gear,"
                                   " 1..5 = change to it",
                                   "seed 003 L19007-19017, L19886-19891", "", 0, 5)
SPIND_DEFAULT_MODE = MdDef(35020, "SPIND_DEFAULT_MODE", A, INT, 0,
                           "spindle initial setting: 0 = speed control without position control, 1 = speed"
                           " control with position control, 2 = positioning mode, 3 = axis mode",
                           "seed 003 L17577-17598; [control] default", "", 0, 3, allowed=(0, 1, 2, 3))
SPIND_DEFAULT_ACT_MASK = MdDef(35030, "SPIND_DEFAULT_ACT_MASK", A, INT, 0,
                               "when MD35020 takes effect: 0 = power-on, 1 = also at program start,"
                               " 2 = also at reset (M2/M30)", "seed 003 L17600-17608; [control] default",
                               "", 0, 2, allowed=(0, 1, 2))
SPIND_FUNCTION_MASK = MdDef(35035, "SPIND_FUNCTION_MASK", A, INT, 0,
                            "spindle functions (bits): 0/1 suppress gear change in dry run / program test,"
                            " 2 catch up in REPOS, 4/5/8/10 setting data use, 12 override in zero-mark"
                            " search,"
                            " 19/20 implicit M19/M70 output, 22 invertM3M4 off for G331/G332",
                            "seed 003 L19956-19993, L20100-20172, L16421-16430, L17465-17475;"
                            " [control] default",
                            "", 0, 0x7FFFFF)
SPIND_ACTIVE_AFTER_RESET = MdDef(35040, "SPIND_ACTIVE_AFTER_RESET", A, INT, 0,
                                 "own spindle reset: 0 = brake at reset/M2/M30, 1 = keep speed and direction",
                                 "seed 003 L16196-16214; [control] default", "", 0, 1, allowed=(0, 1))
SPIND_MAX_VELO_LIMS = MdDef(43230, "SPIND_MAX_VELO_LIMS", A, FLOAT, 0.0,
                            "setting datum SD43230 $SA_SPIND_MAX_VELO_LIMS: spindle speed limit while G96 /"
                            " G961 / G97 are active, the start value of LIMS (0 = no limit but the gear"
                            " stage's; kept here with the spindle's machine data)",
                            "seed 003 L7773-7797; default 0 [project]", "rev/min", 0.0, 1.0e6)
NUM_GEAR_STEPS = MdDef(35090, "NUM_GEAR_STEPS", A, INT, 5, "number of gear stages",
                       "seed 003 L18205-18211; [control] default", "", 1, 5)
NUM_GEAR_STEPS2 = MdDef(35092, "NUM_GEAR_STEPS2", A, INT, 0, "gear stages of the 2nd data set (0 = off)",
                        "seed 003 L18422-18427", "", 0, 5)
SPIND_VELO_LIMIT = MdDef(35100, "SPIND_VELO_LIMIT", A, FLOAT, 10000.0,
                         "maximum spindle speed (chuck protection), monitored on the actual value",
                         "seed 003 L20932-20963; [control] default", "rev/min", 0.0, 1.0e6)
GEAR_STEP_MAX_VELO = MdDef(35110, "GEAR_STEP_MAX_VELO", A, FLOAT,
                           (500.0, 500.0, 1000.0, 2000.0, 4000.0, 8000.0),
                           "upper switching threshold of automatic gear selection (M40) per gear stage",
                           "seed 003 L18221, L21285-21288; [control] defaults", "rev/min", 0.0, 1.0e6, 6)
GEAR_STEP_MAX_VELO2 = MdDef(35112, "GEAR_STEP_MAX_VELO2", A, FLOAT,
                            (500.0, 500.0, 1000.0, 2000.0, 4000.0, 8000.0),
                            "as MD35110 for the 2nd gear-stage data set",
                            "seed 003 L18444; [control] defaults",
                            "rev/min", 0.0, 1.0e6, 6)
GEAR_STEP_MIN_VELO = MdDef(35120, "GEAR_STEP_MIN_VELO", A, FLOAT, (50.0, 50.0, 400.0, 800.0, 1500.0, 3000.0),
                           "lower switching threshold of automatic gear selection (M40) per gear stage",
                           "seed 003 L18222, L21292-21306; [control] defaults", "rev/min", 0.0, 1.0e6, 6)
GEAR_STEP_MIN_VELO2 = MdDef(35122, "GEAR_STEP_MIN_VELO2", A, FLOAT,
                            (50.0, 50.0, 400.0, 800.0, 1500.0, 3000.0),
                            "as MD35120 for the 2nd gear-stage data set",
                            "seed 003 L18445; [control] defaults",
                            "rev/min", 0.0, 1.0e6, 6)
GEAR_STEP_MAX_VELO_LIMIT = MdDef(35130, "GEAR_STEP_MAX_VELO_LIMIT", A, FLOAT,
                                 (500.0, 500.0, 1000.0, 2000.0, 4000.0, 8000.0),
                                 "maximum speed of the gear stage (setpoint clamped, DB31.DBX83.1)",
                                 "seed 003 L18224, L20903-20910; [control] defaults", "rev/min",
                                 0.0, 1.0e6, 6)
GEAR_STEP_PC_MAX_VELO_LIMIT = MdDef(35135, "GEAR_STEP_PC_MAX_VELO_LIMIT", A, FLOAT, _repeat(0.0, 6),
                                    "maximum speed of the gear stage in position control"
                                    " (0: 90 % of MD35130 and of the encoder limit)",
                                    "seed 003 L18226-18228; [control] default", "rev/min", 0.0, 1.0e6, 6)
GEAR_STEP_MIN_VELO_LIMIT = MdDef(35140, "GEAR_STEP_MIN_VELO_LIMIT", A, FLOAT,
                                 (5.0, 5.0, 10.0, 20.0, 40.0, 80.0),
                                 "minimum speed of the gear stage (setpoint raised, DB31.DBX83.2)",
                                 "seed 003 L18230, L20875-20900; [control] defaults", "rev/min",
                                 0.0, 1.0e6, 6)
SPIND_DES_VELO_TOL = MdDef(35150, "SPIND_DES_VELO_TOL", A, FLOAT, 0.1,
                           "spindle speed tolerance factor for 'speed reached' (0.1 = +-10 %, 0 = always)",
                           "seed 003 L20840-20858, L1109-1115; [control] default", "", 0.0, 1.0)
GEAR_STEP_SPEEDCTRL_ACCEL = MdDef(35200, "GEAR_STEP_SPEEDCTRL_ACCEL", A, FLOAT, _repeat(30.0, 6),
                                  "acceleration in speed-control mode per gear stage",
                                  "seed 003 L16175, L18232; [control] default", "rev/s^2", 0.001, 1.0e5, 6)
GEAR_STEP_POSCTRL_ACCEL = MdDef(35210, "GEAR_STEP_POSCTRL_ACCEL", A, FLOAT, _repeat(30.0, 6),
                                "acceleration in position-control mode per gear stage",
                                "seed 003 L16192, L18234; [control] default", "rev/s^2", 0.001, 1.0e5, 6)
GEAR_STEP_POSCTRL_ACCEL2 = MdDef(35212, "GEAR_STEP_POSCTRL_ACCEL2", A, FLOAT, _repeat(30.0, 6),
                                 "as MD35210 for the 2nd gear-stage data set",
                                 "seed 003 L18447-18449; [control] default", "rev/s^2", 0.001, 1.0e5, 6)
ACCEL_REDUCTION_SPEED_POINT = MdDef(35220, "ACCEL_REDUCTION_SPEED_POINT", A, FLOAT, 1.0,
                                    "kinked acceleration characteristic: speed above which the acceleration falls,"
                                    " as a share of the gear stage's MD35130",
                                    "seed 003 L23797-23810; [control] reference speed and default", "", 0.0, 1.0)
ACCEL_REDUCTION_FACTOR = MdDef(35230, "ACCEL_REDUCTION_FACTOR", A, FLOAT, 0.0,
                               "kinked acceleration characteristic: the acceleration falls by this share up to the"
                               " gear stage's MD35130 (0 = no reduction)",
                               "seed 003 L23797-23810; [control] default and range", "", 0.0, 0.95)
ACCEL_REDUCTION_TYPE = MdDef(35242, "ACCEL_REDUCTION_TYPE", A, INT, 1,
                             "kinked acceleration characteristic above the speed point: 0 = constant,"
                             " 1 = hyperbolic, 2 = linear", "seed 003 L23801-23803 (hyperbolic without it);"
                             " [control] coding", "", 0, 2, allowed=(0, 1, 2))
SPIND_POSCTRL_VELO = MdDef(35300, "SPIND_POSCTRL_VELO", A, FLOAT, _repeat(500.0, 6),
                           "position-control activation speed = maximum positioning speed per gear stage",
                           "seed 003 L16639-16645, L18239, L2541-2545; [control] default", "rev/min",
                           0.0, 1.0e6, 6)
SPIND_POSIT_DELAY_TIME = MdDef(35310, "SPIND_POSIT_DELAY_TIME", A, FLOAT, (0.0, 0.05, 0.1, 0.2, 0.4, 0.8),
                               "positioning delay per gear stage (wait at the gear-change position)",
                               "seed 003 L18241, L19666-19675; [control] defaults", "s", 0.0, 1.0e3, 6)
SPIND_POSITIONING_DIR = MdDef(35350, "SPIND_POSITIONING_DIR", A, INT, 3,
                              "direction when positioning an unsynchronized spindle from standstill:"
                              " 3 = M3 (clockwise), 4 = M4",
                              "seed 003 L16904-16906, L19687-19689; [control] coding and default", "", 3, 4,
                              allowed=(3, 4))
SPIND_OSCILL_DES_VELO = MdDef(35400, "SPIND_OSCILL_DES_VELO", A, FLOAT, 500.0, "oscillation speed",
                              "seed 003 L19222; [control] default", "rev/min", 0.0, 1.0e6)
SPIND_OSCILL_ACCEL = MdDef(35410, "SPIND_OSCILL_ACCEL", A, FLOAT, 16.0, "oscillation acceleration",
                           "seed 003 L19218; [control] default", "rev/s^2", 0.001, 1.0e5)
SPIND_OSCILL_START_DIR = MdDef(35430, "SPIND_OSCILL_START_DIR", A, INT, 0,
                               "oscillation start direction: 0..2 = opposite to the last direction of"
                               " rotation, 3 = M3, 4 = M4", "seed 003 L19220; [control] coding and default",
                               "", 0, 4)
SPIND_OSCILL_TIME_CW = MdDef(35440, "SPIND_OSCILL_TIME_CW", A, FLOAT, 1.0, "oscillation time in M3 direction",
                             "seed 003 L19226; [control] default", "s", 0.0, 1.0e3)
SPIND_OSCILL_TIME_CCW = MdDef(35450, "SPIND_OSCILL_TIME_CCW", A, FLOAT, 0.5,
                              "oscillation time in M4 direction",
                              "seed 003 L19224; [control] default", "s", 0.0, 1.0e3)
SPIND_ON_SPEED_AT_IPO_START = MdDef(35500, "SPIND_ON_SPEED_AT_IPO_START", A, INT, 1,
                                    "feed enable only with the spindle at speed: 0 = off, 1 = path starts"
                                    " when the set speed is reached, 2 = also stops at the last G0",
                                    "seed 003 L16517-16540; [control] default", "", 0, 2, allowed=(0, 1, 2))
SPIND_STOPPED_AT_IPO_START = MdDef(35510, "SPIND_STOPPED_AT_IPO_START", A, BOOL, False,
                                   "with M5 the path feed waits until the spindle is stationary",
                                   "seed 003 L16538-16540, L20792-20798; [control] default")
DRILL_VELO_LIMIT = MdDef(35550, "DRILL_VELO_LIMIT", A, FLOAT, _repeat(10000.0, 6),
                         "maximum speed for rigid tapping per gear stage",
                         "seed 003 L18243, L18474-18477; [control] default", "rev/min", 0.0, 1.0e6, 6)
PARAMSET_CHANGE_ENABLE = MdDef(35590, "PARAMSET_CHANGE_ENABLE", A, INT, 0,
                               "parameter set selection: 0 = internal, 1 = internal and external"
                               " (DB31.DBX9.0-2),"
                               " 2 = external only", "seed 003 L18927-18958; [control] default", "", 0, 2,
                               allowed=(0, 1, 2))
ENC_FREQ_LIMIT = MdDef(36300, "ENC_FREQ_LIMIT", A, FLOAT, (300000.0,) * 2,
                       "encoder limit frequency, per measuring system",
                       "seed 003 L2485-2499, L16733-16736; [control] default", "Hz", 0.0, 1.0e8, length=2)
ENC_FREQ_LIMIT_LOW = MdDef(36302, "ENC_FREQ_LIMIT_LOW", A, FLOAT, (99.9,) * 2,
                           "encoder limit frequency for resynchronisation, in percent of MD36300",
                           "seed 003 L2440-2443, L16733-16736; [control] unit and default", "%", 0.0, 100.0,
                           length=2)

# ---------------------------------------------------------------------------------- axis: coupling
COUPLE_POS_TOL_COARSE = MdDef(37200, "COUPLE_POS_TOL_COARSE", A, FLOAT, 1.0,
                              "threshold 'synchronism coarse' of AV/DV couplings (default of CPSYNCOP)",
                              "seed 003 L22447-22452, L29651; [control] default", "deg", 0.0, 1.0e6)
COUPLE_POS_TOL_COARSE_2 = MdDef(37202, "COUPLE_POS_TOL_COARSE_2", A, FLOAT, 0.0,
                                "second coarse threshold (0 = monitoring off)", "seed 003 L29801-29808",
                                "deg",
                                0.0, 1.0e6)
COUPLE_POS_TOL_FINE = MdDef(37210, "COUPLE_POS_TOL_FINE", A, FLOAT, 0.5,
                            "threshold 'synchronism fine' of AV/DV couplings (default of CPSYNFIP)",
                            "seed 003 L22454-22457, L29696; [control] default", "deg", 0.0, 1.0e6)
COUPLE_POS_TOL_FINE_2 = MdDef(37212, "COUPLE_POS_TOL_FINE_2", A, FLOAT, 0.0,
                              "second fine threshold (0 = monitoring off)", "seed 003 L29801-29808", "deg",
                              0.0, 1.0e6)
COUPLE_VELO_TOL_COARSE = MdDef(37220, "COUPLE_VELO_TOL_COARSE", A, FLOAT, 1.0,
                               "velocity tolerance 'coarse' of VV couplings (default of CPSYNCOV)",
                               "seed 003 L22452, L29711; [control] default", "rev/min", 0.0, 1.0e6)
COUPLE_VELO_TOL_FINE = MdDef(37230, "COUPLE_VELO_TOL_FINE", A, FLOAT, 0.5,
                             "velocity tolerance 'fine' of VV couplings (default of CPSYNFIV)",
                             "seed 003 L22457, L29726; [control] default", "rev/min", 0.0, 1.0e6)
EG_VEL_WARNING = MdDef(37550, "EG_VEL_WARNING", A, FLOAT, 90.0,
                       "velocity/acceleration warning threshold of the following axis in percent of"
                       " MD32000/MD32300 (DB31.DBX98.5/98.6)", "seed 003 L26518-26523; [control] default",
                       "%", 0.0, 100.0)
EG_ACC_TOL = MdDef(37560, "EG_ACC_TOL", A, FLOAT, 25.0,
                   "acceleration threshold of the following axis in percent of MD32300 (DB31.DBX99.3)",
                   "seed 003 L26525-26527; [control] default", "%", 0.0, 100.0)

# ---------------------------------------------------------------------------------- axis: travel to fixed stop
FIXED_STOP_MODE = MdDef(37000, "FIXED_STOP_MODE", A, INT, 0,
                        "travel to fixed stop: 0 = not available (FXS raises 20090), bit 0 = from the part"
                        " program (FXS / FXST / FXSW); bit 1 (by the PLC in JOG) is not modelled",
                        "seed 003 L37117-37160; [control] number, bits and default", "", 0, 3)
FIXED_STOP_CONTROL = MdDef(37002, "FIXED_STOP_CONTROL", A, INT, 0,
                           "bit 0: pulses cancelled at the stop: 0 = the function is aborted (20094), 1 = it is"
                           " interrupted and the torque returns with the pulses; bit 1: the torque returns"
                           " 0 = at once, 1 = on the ramp MD37012", "seed 003 L37461-37480; [control] default",
                           "", 0, 3)
FIXED_STOP_TORQUE_DEF = MdDef(37010, "FIXED_STOP_TORQUE_DEF", A, FLOAT, 5.0,
                              "clamping torque when no FXST is programmed, percent of the drive's maximum torque",
                              "seed 003 L37252-37255, L37850-37852; [control] default and range", "%", 0.0, 800.0)
FIXED_STOP_TORQUE_RAMP_TIME = MdDef(37012, "FIXED_STOP_TORQUE_RAMP_TIME", A, FLOAT, 0.0,
                                    "time in which a new torque limit is reached linearly (0: at once)",
                                    "seed 003 L37168-37176; [control] default and range", "s", 0.0, 1.0e5)
FIXED_STOP_WINDOW_DEF = MdDef(37020, "FIXED_STOP_WINDOW_DEF", A, FLOAT, 1.0,
                              "monitoring window at the fixed stop when no FXSW is programmed",
                              "seed 003 L37329-37337, L37853-37855; [control] default and range", "mm", 0.0, 1.0e8)
FIXED_STOP_THRESHOLD = MdDef(37030, "FIXED_STOP_THRESHOLD", A, FLOAT, 2.0,
                             "following error above which the fixed stop counts as reached (MD37040 = 0 / 2)",
                             "seed 003 L37277-37283; [control] default and range", "mm", 0.0, 1.0e8)
FIXED_STOP_BY_SENSOR = MdDef(37040, "FIXED_STOP_BY_SENSOR", A, INT, 0,
                             "fixed stop detection: 0 = following error above MD37030, 1 = the sensor"
                             " DB31.DBX1.2, 2 = either", "seed 003 L37275-37290; [control] default", "", 0, 2)
FIXED_STOP_ALARM_MASK = MdDef(37050, "FIXED_STOP_ALARM_MASK", A, INT, 1,
                              "fixed stop alarms: bit 0 = 0 suppresses 20091 (not reached), bit 1 = 1"
                              " suppresses 20094 (aborted); bits 3 / 4 (FOC, brake test) are not modelled",
                              "seed 003 L37375-37391, L37995-38013; [control] bit reading and default", "", 0, 31)
FIXED_STOP_ACKN_MASK = MdDef(37060, "FIXED_STOP_ACKN_MASK", A, INT, 0,
                             "PLC acknowledgements: bit 0 = 1 the motion waits for DB31.DBX3.1, bit 1 = 1 the"
                             " block change waits for DB31.DBX1.1", "seed 003 L37187-37196, L37226-37232,"
                             " L37311-37320; [control] default", "", 0, 3)

# ---------------------------------------------------------------------------------- axis: gantry axes
GANTRY_AXIS_TYPE = MdDef(37100, "GANTRY_AXIS_TYPE", A, INT, 0,
                         "gantry axis: tens digit 0 = leading axis, 1 = synchronized (following) axis; units"
                         " digit = the gantry grouping 1..8; 0 = no gantry axis (01 leads grouping 1, 11"
                         " follows in it)", "seed 003 L14407-14428; [control] 0 = no gantry axis", "", 0, 18,
                         allowed=(0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 12, 13, 14, 15, 16, 17, 18))
GANTRY_POS_TOL_WARNING = MdDef(37110, "GANTRY_POS_TOL_WARNING", A, FLOAT, 0.0,
                               "gantry warning limit of the actual-value difference (DB31.DBX101.3, alarm 10652);"
                               " also the largest difference for which the synchronization run starts by itself;"
                               " 0: no warning and no automatic synchronization run",
                               "seed 003 L14465-14481, L14698-14731, L15240-15250; [control] default", "mm",
                               0.0, 1.0e8)
GANTRY_POS_TOL_ERROR = MdDef(37120, "GANTRY_POS_TOL_ERROR", A, FLOAT, 0.0,
                             "gantry trip (cut-off) limit of a synchronized grouping (DB31.DBX101.2, alarm 10653,"
                             " the grouping stops); 0: not monitored",
                             "seed 003 L14486-14501, L15098-15101; [control] default", "mm", 0.0, 1.0e8)
GANTRY_POS_TOL_REF = MdDef(37130, "GANTRY_POS_TOL_REF", A, FLOAT, 0.0,
                           "gantry trip (cut-off) limit while the grouping is not synchronized (referencing);"
                           " 0: not monitored", "seed 003 L14493-14496, L15101; [control] default", "mm",
                           0.0, 1.0e8)
GANTRY_ACT_POS_TOL_ERROR = MdDef(37135, "GANTRY_ACT_POS_TOL_ERROR", A, FLOAT, 0.0,
                                 "the actual-value difference the extended monitoring (MD37150 bit 0) found beyond"
                                 " the trip limit, written by the control; while it is not 0 alarm 10653 comes"
                                 " back at every reset", "seed 003 L14531-14547; [control] default", "mm",
                                 -1.0e8, 1.0e8)
GANTRY_BREAK_UP = MdDef(37140, "GANTRY_BREAK_UP", A, BOOL, False,
                        "break up the gantry grouping: its axes travel on their own, nothing is monitored,"
                        " DB31.DBX101.5 = 0", "seed 003 L14590-14612, L14636-14638; [control] default")
GANTRY_FUNCTION_MASK = MdDef(37150, "GANTRY_FUNCTION_MASK", A, INT, 0,
                             "bit 0: extended monitoring (also in follow-up and broken up, once referenced);"
                             " bit 1: the follower searches its zero mark in the leading axis's direction;"
                             " bit 2: no 'synchronization in progress' message (alarm 10655)",
                             "seed 003 L14517-14547, L14703-14705, L14848-14856; [control] default", "", 0, 7)

# ---------------------------------------------------------------------------------- axis: ESR
ESR_REACTION = MdDef(37500, "ESR_REACTION", A, INT, 0,
                     "extended stop and retract of the axis: 0 = none, 21 = NC-controlled retract,"
                     " 22 = NC-controlled stop, 10/11/12 = drive-autonomous retract/stop/generator",
                     "seed 003 L42144-42150, L11536-11552; [control] values 0, 10..12 and default", "", 0, 22,
                     allowed=(0, 10, 11, 12, 21, 22))
AX_ESR_DELAY_TIME1 = MdDef(37510, "AX_ESR_DELAY_TIME1", A, FLOAT, 0.0,
                           "single-axis ESR: delay before braking (single axes only)",
                           "seed 003 L11497-11503, L11544; [control] default", "s", 0.0, 1.0e3)
AX_ESR_DELAY_TIME2 = MdDef(37511, "AX_ESR_DELAY_TIME2", A, FLOAT, 0.04, "single-axis ESR: braking time",
                           "seed 003 L11501-11503, L11545; [control] default", "s", 0.0, 1.0e3)

# ---------------------------------------------------------------------------------- setpoint switchover
CTRLOUT_MODULE_NR = MdDef(30110, "CTRLOUT_MODULE_NR", A, INT, 0,
                          "setpoint assignment: the logical drive number; axes with the same number share one"
                          " drive (setpoint switchover, DB31.DBX24.5 / 96.5); 0: the axis's own drive",
                          "seed 003 L38196-38202, L38308-38320; [INF] default 0 (the harness numbers no drives)",
                          "", 0, 64)

# ---------------------------------------------------------------------------------- measuring systems
NUM_ENCS = MdDef(30200, "NUM_ENCS", A, INT, 1, "number of measuring systems of the axis (1 or 2)",
                 "seed 003 L1685-1785 (two measuring systems); [control] default", "", 0, 2)
ENC_GRID_POINT_DIST = MdDef(31010, "ENC_GRID_POINT_DIST", A, FLOAT, (0.01,) * 2,
                            "grid spacing of a linear scale", "[control] default", "mm", 0.00001, 100.0, length=2)
ENC_SERIAL_NUMBER = MdDef(34230, "ENC_SERIAL_NUMBER", A, INT, (0,) * 2,
                          "encoder serial number; a new encoder (other number) needs recalibration",
                          "seed 003 L2394-2397, L2028-2043", "", 0, 2_147_483_647, length=2)
ENC_MARKER_INC = MdDef(34310, "ENC_MARKER_INC", A, FLOAT, (0.02,) * 2,
                       "interval increment of a distance-coded scale: the distances between adjacent reference"
                       " marks differ by multiples of it", "seed 003 L1376-1384; [control] default", "mm",
                       0.0001, 1000.0, length=2)

# ---------------------------------------------------------------------------------- inclined axis (GSK 988TD)
# The inclined-axis control of seed 000 is configured by GSK parameters 8200-8212; the
# SINUMERIK has no such data, so they are machine data of the project in the OEM range
# (62800..) that say which GSK parameter each one carries.
INCL_AXIS_ENABLE = MdDef(62800, "INCL_AXIS_ENABLE", C, BOOL, False,
                         "inclined-axis control on (GSK parameter 8200 #0 AAC); project machine datum",
                         "seed 000 L400-409")
INCL_AXIS_REF_ORTHO_STILL = MdDef(62801, "INCL_AXIS_REF_ORTHO_STILL", C, BOOL, False,
                                  "referencing the inclined axis does not move the orthogonal axis (GSK 8200 #2"
                                  " AZR); project machine datum", "seed 000 L52-53, L410-412")
INCL_AXIS_LIMITS_CARTESIAN = MdDef(62802, "INCL_AXIS_LIMITS_CARTESIAN", C, BOOL, (False,) * 3,
                                   "stroke limits 1, 2, 3 in Cartesian (1) or inclined (0) coordinates (GSK 8201"
                                   " #0 AOT, #1 AO2, #2 AO3); project machine datum", "seed 000 L414-429",
                                   length=3)
INCL_AXIS_G28_CARTESIAN = MdDef(62803, "INCL_AXIS_G28_CARTESIAN", C, BOOL, False,
                                "G28/G30 from the intermediate point in Cartesian (1) or inclined (0) motion"
                                " (GSK 8209 #0 ARF); project machine datum", "seed 000 L431-441")
INCL_AXIS_ANGLE = MdDef(62804, "INCL_AXIS_ANGLE", C, FLOAT, 0.0,
                        "inclination angle theta (GSK 8210, there in 0.001 degree); project machine datum",
                        "seed 000 L443-449", "deg", -180.0, 180.0)
INCL_AXIS_INCLINED = MdDef(62805, "INCL_AXIS_INCLINED", C, INT, 0,
                           "channel axis number of the inclined axis (GSK 8211); project machine datum",
                           "seed 000 L451", "", 0, 20)
INCL_AXIS_ORTHOGONAL = MdDef(62806, "INCL_AXIS_ORTHOGONAL", C, INT, 0,
                             "channel axis number of the orthogonal axis (GSK 8212); project machine datum",
                             "seed 000 L454-464, L45-49", "", 0, 20)
# The seed contradicts itself on 8211/8212 that are 0, equal or beyond the axis count:
# L45-49 picks the axes from the M/T series table, L460 makes the function invalid.  The
# choice is configured here (spec 9.2), not hard-coded; the default follows the parameter
# table L460 and the referencing order check of vc/core/channel/referencing_control.py.
INCL_AXIS_FALLBACK = MdDef(62807, "INCL_AXIS_FALLBACK", C, INT, 0,
                           "MD62805/62806 unusable (0, equal or beyond the channel's axes): 0 = inclined-axis"
                           " control invalid (L460), 1 = M-series table: inclined = geometry axis Y, orthogonal"
                           " = Z, 2 = T-series table: inclined = X, orthogonal = Z (L45-49; GSK parameter 1022"
                           " is MD20050 here); project machine datum", "seed 000 L45-49, L460-464",
                           "", 0, 2, allowed=(0, 1, 2))
INCL_AXIS_ORTHO_DIAMETER = MdDef(62808, "INCL_AXIS_ORTHO_DIAMETER", C, BOOL, False,
                                 "the orthogonal axis is programmed in diameter: coefficient C = 2 in"
                                 " Xa = Xp - C Yp tan(theta) (0: radius, C = 1); project machine datum",
                                 "seed 000 L20-22")

# Stored stroke limits 2 (G22 / G23) and 3, which seed 000 L264-291, L414-429 names for the
# inclined-axis control with the FANUC / GSK convention but without their parameters: the
# control's parameters 1300 #0, 1310 #0 / #1 and 1322-1325 as project machine data (62810..),
# each saying which parameter it carries (vc/core/axis/stroke_limits.py).
STROKE2_OUTSIDE_FORBIDDEN = MdDef(62810, "STROKE2_OUTSIDE_FORBIDDEN", C, BOOL, False,
                                  "stored stroke limit 2: 0 = the inside of its box is forbidden, 1 = the outside"
                                  " (FANUC / GSK parameter 1300 #0 OUT); project machine datum",
                                  "seed 000 L264-291 (G22/G23); [control] parameter")
STROKE2_CHECK = MdDef(62811, "STROKE2_CHECK", A, BOOL, False,
                      "the axis is checked by stored stroke limit 2 (FANUC / GSK parameter 1310 #0 OT2x); project"
                      " machine datum", "seed 000 L264-291; [control] parameter")
STROKE2_LIMIT_PLUS = MdDef(62812, "STROKE2_LIMIT_PLUS", A, FLOAT, 0.0,
                           "stored stroke limit 2, upper bound of the axis (FANUC / GSK parameter 1322; G22 sets"
                           " it); project machine datum", "seed 000 L264-291; [control] parameter", "mm",
                           -1.0e9, 1.0e9)
STROKE2_LIMIT_MINUS = MdDef(62813, "STROKE2_LIMIT_MINUS", A, FLOAT, 0.0,
                            "stored stroke limit 2, lower bound of the axis (FANUC / GSK parameter 1323; G22 sets"
                            " it); project machine datum", "seed 000 L264-291; [control] parameter", "mm",
                            -1.0e9, 1.0e9)
STROKE3_CHECK = MdDef(62814, "STROKE3_CHECK", A, BOOL, False,
                      "the axis is checked by stored stroke limit 3, inside forbidden (FANUC / GSK parameter 1310"
                      " #1 OT3x); project machine datum", "seed 000 L264-291, L427-429; [control] parameter")
STROKE3_LIMIT_PLUS = MdDef(62815, "STROKE3_LIMIT_PLUS", A, FLOAT, 0.0,
                           "stored stroke limit 3, upper bound of the axis (FANUC / GSK parameter 1324); project"
                           " machine datum", "seed 000 L264-291; [control] parameter", "mm", -1.0e9, 1.0e9)
STROKE3_LIMIT_MINUS = MdDef(62816, "STROKE3_LIMIT_MINUS", A, FLOAT, 0.0,
                            "stored stroke limit 3, lower bound of the axis (FANUC / GSK parameter 1325); project"
                            " machine datum", "seed 000 L264-291; [control] parameter", "mm", -1.0e9, 1.0e9)

# ---------------------------------------------------------------------------------- five-axis kinematics (Syntec)
# The five-axis mechanism chain of seed 001 (Syntec parameters of chain group 1) as machine
# data of the project: MD630nn carries Syntec Pr30nn; a parameter triple (x, y, z) or pair
# (start, end) is one array datum at the number of its first parameter.  Values are in the
# units of the display, degrees and mm: the Syntec BLU is 0.001 degree (290 degrees =
# 290000, seed 001 L15) and, by the same rule, 0.001 mm.  The seed's Pr3017 = 50000 for a
# 30 degree origin offset (L20) is read as a misprint of 30000 (spec 9.2).
FIVE_AXIS_ROTARY_AXES = MdDef(63000, "FIVE_AXIS_ROTARY_AXES", C, INT, (0, 0),
                              "channel axis numbers of the 1st (master) and 2nd (slave) rotary axis of the"
                              " five-axis chain (0 = none); Syntec names them by axis letter, so this is a"
                              " project machine datum", "seed 001 L6-8", "", 0, 20, 2)
FIVE_AXIS_TYPE = MdDef(63001, "FIVE_AXIS_TYPE", C, INT, 0,
                       "five-axis mechanism type (Syntec Pr3001): 0 = not set, 1 = spindle (head-head), 2 = table"
                       " (table-table), 3 = mixed (head-table), 4 = single rotary spindle, 5 = single rotary table",
                       "seed 001 L8-9", "", 0, 5)
FIVE_AXIS_TOOL_DIR = MdDef(63002, "FIVE_AXIS_TOOL_DIR", C, INT, 0,
                           "tool direction (tip towards holder) with all rotary axes at 0 (Syntec Pr3002):"
                           " 0 = not set, 1 = +X, 2 = +Y, 3 = +Z", "seed 001 L9", "", 0, 3)
FIVE_AXIS_TOOL_TILT_RA = MdDef(63003, "FIVE_AXIS_TOOL_TILT_RA", C, FLOAT, 0.0,
                               "tool tilt angle RA, turned first (Syntec Pr3003): Pr3002 = 1 about Z, 2 about X,"
                               " 3 about Y, right-hand", "seed 001 L9-10", "deg", 0.0, 360.0)
FIVE_AXIS_TOOL_TILT_RB = MdDef(63004, "FIVE_AXIS_TOOL_TILT_RB", C, FLOAT, 0.0,
                               "tool tilt angle RB, turned after RA (Syntec Pr3004): Pr3002 = 1 about X, 2 about"
                               " Y, 3 about Z, right-hand", "seed 001 L11", "deg", 0.0, 360.0)
FIVE_AXIS_ROT1_AXIS = MdDef(63005, "FIVE_AXIS_ROT1_AXIS", C, INT, 0,
                            "1st rotary axis parallel to (Syntec Pr3005): 0 = not set, 1 = X, 2 = Y, 3 = Z",
                            "seed 001 L12-13", "", 0, 3)
FIVE_AXIS_ROT2_AXIS = MdDef(63006, "FIVE_AXIS_ROT2_AXIS", C, INT, 0,
                            "2nd rotary axis parallel to (Syntec Pr3006): 0 = not set, 1 = X, 2 = Y, 3 = Z",
                            "seed 001 L12-13", "", 0, 3)
FIVE_AXIS_ROT1_DIR = MdDef(63007, "FIVE_AXIS_ROT1_DIR", C, INT, 0,
                           "rotation direction of the 1st rotary axis (Syntec Pr3007): 0 = not set,"
                           " 1 = right-hand rule, 2 = left-hand rule", "seed 001 L13-14", "", 0, 2)
FIVE_AXIS_ROT2_DIR = MdDef(63008, "FIVE_AXIS_ROT2_DIR", C, INT, 0,
                           "rotation direction of the 2nd rotary axis (Syntec Pr3008): 0 = not set,"
                           " 1 = right-hand rule, 2 = left-hand rule", "seed 001 L13-14", "", 0, 2)
FIVE_AXIS_ROT1_RANGE = MdDef(63009, "FIVE_AXIS_ROT1_RANGE", C, FLOAT, (0.0, 0.0),
                             "travel range [start, end] of the 1st rotary axis with five-axis functions active,"
                             " from machine 0 in the axis's positive direction (Syntec Pr3009, Pr3010);"
                             " start = end: no limit", "seed 001 L14-15", "deg", 0.0, 360.0, 2)
FIVE_AXIS_ROT2_RANGE = MdDef(63011, "FIVE_AXIS_ROT2_RANGE", C, FLOAT, (0.0, 0.0),
                             "travel range [start, end] of the 2nd rotary axis (Syntec Pr3011, Pr3012);"
                             " start = end: no limit", "seed 001 L14-15", "deg", 0.0, 360.0, 2)
FIVE_AXIS_HOLDER_LENGTH = MdDef(63013, "FIVE_AXIS_HOLDER_LENGTH", C, FLOAT, 0.0,
                                "tool holder length: spindle-side rotary axis centre (control point) to the"
                                " spindle face, types 1, 3, 4 (Syntec Pr3013)", "seed 001 L17", "mm",
                                0.0, 999999.999)
FIVE_AXIS_ROT1_TILT = MdDef(63015, "FIVE_AXIS_ROT1_TILT", C, FLOAT, (0.0, 0.0, 0.0),
                            "tilt vector of the 1st rotary axis, A/B/C components (Syntec Pr3015-3017): the"
                            " deviations of the axis about the two other axes and, about its own axis, the"
                            " origin offset; right-hand", "seed 001 L19-20", "deg", -360.0, 360.0, 3)
FIVE_AXIS_ROT2_TILT = MdDef(63018, "FIVE_AXIS_ROT2_TILT", C, FLOAT, (0.0, 0.0, 0.0),
                            "tilt vector of the 2nd rotary axis, A/B/C components (Syntec Pr3018-3020)",
                            "seed 001 L19-20", "deg", -360.0, 360.0, 3)
FIVE_AXIS_TOOL_TO_ROT2 = MdDef(63021, "FIVE_AXIS_TOOL_TO_ROT2", C, FLOAT, (0.0, 0.0, 0.0),
                               "type 1: offset (a, b, c) from the tool axis at the holder face to the 2nd rotary"
                               " axis (Syntec Pr3021-3023)", "seed 001 L21-22", "mm", -999999.999, 999999.999, 3)
FIVE_AXIS_ROT2_TO_ROT1 = MdDef(63024, "FIVE_AXIS_ROT2_TO_ROT1", C, FLOAT, (0.0, 0.0, 0.0),
                               "type 1: offset (d, e, f) from the 2nd to the 1st rotary axis (Syntec"
                               " Pr3024-3026)", "seed 001 L23-24", "mm", -999999.999, 999999.999, 3)
FIVE_AXIS_ROT1_TO_ROT2 = MdDef(63031, "FIVE_AXIS_ROT1_TO_ROT2", C, FLOAT, (0.0, 0.0, 0.0),
                               "type 2: offset (a, b, c) from the 1st to the 2nd rotary axis (Syntec"
                               " Pr3031-3033)", "seed 001 L25-26", "mm", -999999.999, 999999.999, 3)
FIVE_AXIS_ORIGIN_TO_ROT1 = MdDef(63034, "FIVE_AXIS_ORIGIN_TO_ROT1", C, FLOAT, (0.0, 0.0, 0.0),
                                 "type 2 (and 5, project choice): machine coordinates (d, e, f) of a point on the"
                                 " 1st rotary axis (Syntec Pr3034-3036)", "seed 001 L27-28", "mm",
                                 -999999.999, 999999.999, 3)
FIVE_AXIS_TOOL_TO_ROT1 = MdDef(63041, "FIVE_AXIS_TOOL_TO_ROT1", C, FLOAT, (0.0, 0.0, 0.0),
                               "type 3 (and 4, project choice): offset (a, b, c) from the tool axis at the holder"
                               " face to the 1st (spindle-side) rotary axis (Syntec Pr3041-3043)",
                               "seed 001 L28-29", "mm", -999999.999, 999999.999, 3)
FIVE_AXIS_ORIGIN_TO_ROT2 = MdDef(63044, "FIVE_AXIS_ORIGIN_TO_ROT2", C, FLOAT, (0.0, 0.0, 0.0),
                                 "type 3: machine coordinates (d, e, f) of a point on the 2nd (table) rotary axis"
                                 " (Syntec Pr3044-3046)", "seed 001 L29-30", "mm", -999999.999, 999999.999, 3)
FIVE_AXIS_ROTARY_REFERENCE = MdDef(63055, "FIVE_AXIS_ROTARY_REFERENCE", C, INT, 0,
                                   "reference of the table rotary axes in the transformation (Syntec Pr3055):"
                                   " 0 = rotary origin of the machine coordinates, 1 = rotary origin of the work"
                                   " offset (e.g. G54 C15)", "seed 001 L33-34, L41", "", 0, 1)
# G43.4 H_ / G43 H_ select a tool length by its offset number (seed 001 L31, L42).  The control
# keeps tool offsets in its tool offset memory, not in machine data; this core has none, so the
# lengths of the offset numbers H1 .. H10 are one project machine datum of the channel.
TOOL_LENGTH_OFFSETS = MdDef(62950, "TOOL_LENGTH_OFFSETS", C, FLOAT, (0.0,) * 10,
                            "tool length (length + wear) of the tool offsets H1 .. H10 for G43.4 and G43; H0 is"
                            " length 0; project machine datum in place of the tool offset memory",
                            "seed 001 L31, L42 (G43.4 H_); [control] the offset memory", "mm",
                            -9999.999, 9999.999, 10)

# ------------------------------------------------------------ polygon turning (GSK980TDi parameters)
# Seed 002 prints the GSK parameter numbers; they become channel machine data with project numbers.
POLYGON_MASTER_AXIS = MdDef(62900, "POLYGON_MASTER_AXIS", C, INT, 0,
                            "master (workpiece) axis of polygon turning: channel axis number of a spindle"
                            " (GSK parameter 0197; the seed's table labels it the tool axis, its definitions"
                            " the workpiece: the definitions hold); project machine datum",
                            "seed 002 L165-174, L55-57", "", 0, 20)
POLYGON_SLAVE_AXIS = MdDef(62901, "POLYGON_SLAVE_AXIS", C, INT, 0,
                           "slave (tool) axis of polygon turning: channel axis number of a spindle (GSK"
                           " parameter 0198); project machine datum", "seed 002 L176-185, L15-17", "", 0, 20)
POLYGON_FUNCTION_MASK = MdDef(62902, "POLYGON_FUNCTION_MASK", C, INT, 0,
                              "GSK parameter 0201: bit 2 ERV (G99 feed from the slave's theoretical speed), bit 3"
                              " HBR (1 = reset keeps the synchronisation), bit 4 ECN (1 = G51.2 while synchronous"
                              " resynchronises, 0 = alarm), bit 7 SNTP (1 = follow mode on the actual master"
                              " position); bit positions read from the seed's table layout; project machine datum",
                              "seed 002 L187-214", "", 0, 0xFF)
POLYGON_MASTER_ACC_START_VELO = MdDef(62903, "POLYGON_MASTER_ACC_START_VELO", C, FLOAT, 0.0,
                                      "master's acceleration start speed while synchronous (GSK parameter 0162);"
                                      " project machine datum", "seed 002 L143-152", "deg/min", 0.0, 4000.0)
POLYGON_MASTER_ACC_TIME = MdDef(62904, "POLYGON_MASTER_ACC_TIME", C, FLOAT, 0.0,
                                "master's acceleration time constant while synchronous, from the start speed to"
                                " MD32000 (GSK parameter 0163); 0 = the gear stage's ramp; project machine datum",
                                "seed 002 L154-163", "ms", 0.0, 10000.0)

# ---------------------------------------------------------------------------------- indexing axes (chapter 11)
# Two index position tables of the NC (L13560-13605) and the axis's assignment to one of them or to
# equidistant indexing (MD30500 = 3, L13548-13560, §11.3.2).  The table's positions ascend and differ
# (L13578-13580); on a modulo axis they lie in 0 <= p < 360 (L13586); the loader checks both.
INDEX_AX_LENGTH_POS_TAB_1 = MdDef(10900, "INDEX_AX_LENGTH_POS_TAB_1", N, INT, 0,
                                  "number of index positions of table 1 (entries beyond it do not count)",
                                  "seed 003 L13594-13603; [control] default", "", 0, 60)
INDEX_AX_POS_TAB_1 = MdDef(10910, "INDEX_AX_POS_TAB_1", N, FLOAT, (0.0,) * 60,
                           "index position table 1: ascending positions in mm or degrees",
                           "seed 003 L13562-13586, example L14131-14142", "mm", -1.0e8, 1.0e8, 60)
INDEX_AX_LENGTH_POS_TAB_2 = MdDef(10920, "INDEX_AX_LENGTH_POS_TAB_2", N, INT, 0,
                                  "number of index positions of table 2 (entries beyond it do not count)",
                                  "seed 003 L13594-13603; [control] default", "", 0, 60)
INDEX_AX_POS_TAB_2 = MdDef(10930, "INDEX_AX_POS_TAB_2", N, FLOAT, (0.0,) * 60,
                           "index position table 2: ascending positions in mm or degrees",
                           "seed 003 L13562-13586, example L14170-14183", "mm", -1.0e8, 1.0e8, 60)
INDEX_AX_MODE = MdDef(10940, "INDEX_AX_MODE", N, INT, 0,
                      "bit 0: the index position shown changes at the exact stop fine window of the next"
                      " position (0) or half-way to it (1)", "seed 003 L13634-13680; [control] default",
                      "", 0, 1)
INDEX_AX_ASSIGN_POS_TAB = MdDef(30500, "INDEX_AX_ASSIGN_POS_TAB", A, INT, 0,
                                "indexing axis: 0 = none, 1 / 2 = index position table 1 / 2,"
                                " 3 = equidistant index positions", "seed 003 L13546-13557; [control] default",
                                "", 0, 3, allowed=(0, 1, 2, 3))
INDEX_AX_NUMERATOR = MdDef(30501, "INDEX_AX_NUMERATOR", A, FLOAT, 0.0,
                           "equidistant indexing: numerator of the spacing (ignored on a modulo axis: MD30330)",
                           "seed 003 L14210-14216, L14290; [control] default", "mm", 0.0, 1.0e8)
INDEX_AX_DENOMINATOR = MdDef(30502, "INDEX_AX_DENOMINATOR", A, INT, 1,
                             "equidistant indexing: the spacing is numerator / denominator; on a modulo axis"
                             " the number of index positions", "seed 003 L14220-14224; [control] default",
                             "", 1, 999_999_999)
INDEX_AX_OFFSET = MdDef(30503, "INDEX_AX_OFFSET", A, FLOAT, 0.0,
                        "equidistant indexing: the first index position", "seed 003 L13557-13560, L14225",
                        "mm", -1.0e8, 1.0e8)
HIRTH_IS_ACTIVE = MdDef(30505, "HIRTH_IS_ACTIVE", A, BOOL, False,
                        "indexing axis with Hirth joint: only on a rotary axis with equidistant index positions"
                        " (MD30500 = 3)", "seed 003 L13740-13767")

# ---------------------------------------------------------------------------------- index

ALL_MACHINE_DATA: tuple[MdDef, ...] = tuple(
    sorted((value for value in globals().values() if isinstance(value, MdDef)), key=lambda md: md.number)
)
BY_NUMBER: dict[int, MdDef] = {md.number: md for md in ALL_MACHINE_DATA}
BY_NAME: dict[str, MdDef] = {md.name: md for md in ALL_MACHINE_DATA}

_LEVEL_TEXT = {MdLevel.NCK: "general data", MdLevel.CHANNEL: "channel data", MdLevel.AXIS: "axis data"}


def level_text(level: MdLevel) -> str:
    """``channel data ($MC_)`` and the like, as messages describe a level."""
    return f"{_LEVEL_TEXT[level]} ({level.prefix})"


class MdKeyError(VcError, ValueError):
    """A text that does not name a machine datum; the message says why."""


@dataclass(frozen=True, slots=True)
class MdKey:
    """A machine datum as a file names it, with the array index if one was written."""

    md: MdDef
    index: int | None  # None = the whole datum (all indices of an array)

    @property
    def label(self) -> str:
        return self.md.label if self.index is None else f"{self.md.label}[{self.index}]"


_KEY = re.compile(
    r"^(?:MD(?P<number>\d+)(?: (?:\$M(?P<number_level>[NCA])_)?(?P<number_name>[A-Z0-9_]+))?"
    r"|(?P<bare_number>\d+)"
    r"|(?:\$M(?P<level>[NCA])_)?(?P<name>[A-Z_][A-Z0-9_]*))"
    r"(?: ?\[ ?(?P<index>[^\]]*?) ?\])?$"
)

KEY_FORMS = "MD32000, MD32000 MAX_AX_VELO, $MA_MAX_AX_VELO or MAX_AX_VELO, with [n] for one index of an array"


def parse_md_key(key: str) -> MdKey:
    """Resolve a machine datum key as machine and scenario files write it.

    Accepted (case-insensitive): ``MD32000``, ``MD32000 MAX_AX_VELO``, ``MD32000 $MA_MAX_AX_VELO``,
    ``32000``, ``$MA_MAX_AX_VELO``, ``MAX_AX_VELO``; each optionally followed by ``[n]`` to name
    one index of an array datum.  Number and name must agree, a ``$Mx_`` prefix must match
    the datum's level and an index must lie inside the array; otherwise :class:`MdKeyError`
    says what is wrong.
    """
    normalized = re.sub(r"\s+", " ", str(key).strip())
    match = _KEY.match(normalized.upper())
    if match is None:
        raise MdKeyError(f"'{key}' is not a machine datum (write {KEY_FORMS})")
    number_text = match["number"] or match["bare_number"]
    name = match["number_name"] or match["name"]
    level = match["number_level"] or match["level"]
    if number_text is not None:
        md = BY_NUMBER.get(int(number_text))
        if md is None:
            raise MdKeyError(f"unknown machine datum MD{int(number_text)}")
        if name is not None and name != md.name:
            other = BY_NAME.get(name)
            where = f" ({name} is MD{other.number})" if other is not None else ""
            raise MdKeyError(f"MD{md.number} is {md.name}, not {name}{where}")
    else:
        assert name is not None
        found = BY_NAME.get(name)
        if found is None:
            raise MdKeyError(f"unknown machine datum {name}")
        md = found
    if level is not None and level != md.level.value:
        raise MdKeyError(f"{md.label} is {level_text(md.level)}, not $M{level}_")
    index_text = None if match["index"] is None else normalized[match.start("index"):match.end("index")]
    return MdKey(md, _index(md, index_text))


def _index(md: MdDef, text: str | None) -> int | None:
    if text is None:
        return None
    if not md.is_array:
        raise MdKeyError(f"{md.label} is not an array; write it without [{text}]")
    if not text.isdigit():
        raise MdKeyError(f"{md.label}[{text}]: the index must be a whole number 0..{md.length - 1}")
    index = int(text)
    if index >= md.length:
        raise MdKeyError(f"{md.label} has {md.length} values; index {index} is out of range")
    return index


def lookup(key: str) -> MdDef | None:
    """The machine datum a key names, or None.

    Takes every form of :func:`parse_md_key` *without* an index: a key with ``[n]`` gives None
    here; use :func:`parse_md_key` where an index may be written (it returns the index
    separately).
    """
    try:
        parsed = parse_md_key(key)
    except MdKeyError:
        return None
    return parsed.md if parsed.index is None else None
