"""Alarms of the simulated control: values with a number, a text, where, and a reaction.

A fault of the simulated machine is data, never an exception.  Each alarm number has a
definition (text with %1.. parameters, reaction, how it is cleared) in ``ALARM_TEXTS``;
the numbers and texts are those of the real control (the seed names few numbers; the
others are marked ``[control]``).  The :class:`AlarmList` is the NCK's alarm memory: the
NC core raises and clears alarms, the interface shows "alarm present" bits, scenarios
assert on them.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from enum import Flag, StrEnum, auto

from vc.config.model import PLC_USER_ALARMS


class Reaction(Flag):
    """What the control does while the alarm is present."""

    NONE = 0
    STOP_AXES = auto()  # brake the axes of the channel (interpolation stop)
    NC_START_DISABLED = auto()  # NC start is refused
    READ_IN_DISABLED = auto()  # no further block is decoded
    CHANNEL_INTERRUPT = auto()  # the running program is interrupted (NC stop)
    RAPID_STOP = auto()  # axes stop with the rapid-stop ramp, then controller enable is removed
    MODE_GROUP = auto()  # acts on every channel of the mode group


class Clear(StrEnum):
    """How the alarm goes away."""

    RESET = "reset"  # channel or mode-group reset
    CANCEL = "cancel"  # acknowledge key (or reset)
    SELF = "self"  # disappears when its cause is gone
    POWER_ON = "power_on"
    EMERGENCY_STOP_ACK = "emergency_stop_ack"  # e-stop released, acknowledged and reset


@dataclass(frozen=True, slots=True)
class AlarmDefinition:
    number: int
    text: str  # with %1.. placeholders as on the control
    reaction: Reaction
    clear: Clear
    source: str


@dataclass(frozen=True, slots=True)
class Alarm:
    """One present alarm."""

    number: int
    text: str  # the text with its parameters filled in
    reaction: Reaction
    clear: Clear
    channel: str = ""
    axis: str = ""
    raised_cycle: int = 0

    def __str__(self) -> str:
        return f"{self.number} {self.text}"


_STOP = Reaction.STOP_AXES | Reaction.NC_START_DISABLED | Reaction.CHANNEL_INTERRUPT

# Reaction bits as ints, for ``AlarmList.reactions`` in the cycle.
STOP_AXES = Reaction.STOP_AXES.value
NC_START_DISABLED = Reaction.NC_START_DISABLED.value
CHANNEL_INTERRUPT = Reaction.CHANNEL_INTERRUPT.value

ALARM_TEXTS: dict[int, AlarmDefinition] = {
    definition.number: definition
    for definition in (
        AlarmDefinition(2000, "PLC sign-of-life monitoring", Reaction.RAPID_STOP | _STOP | Reaction.MODE_GROUP,
                        Clear.RESET, "[control] number and text; the real control needs power-on, here a"
                        " reset clears it once the PLC shows its sign of life again"),
        AlarmDefinition(2001, "PLC has not started up", Reaction.RAPID_STOP | _STOP | Reaction.MODE_GROUP,
                        Clear.RESET, "[control] number and text; cleared by a reset once the PLC runs"),
        *(AlarmDefinition(number, f"Channel %1 block %2 axis %3 {sign} overtravel (stored stroke limit {limit}, "
                                  f"OT0{number})", _STOP, Clear.RESET,
                          "seed 000 L264-291, L414-429 (stored stroke limits 2 and 3 of the inclined-axis control;"
                          " the seed names no numbers); [control] FANUC / GSK OT0502-OT0505; block = JOG in JOG")
          for number, sign, limit in ((502, "+", 2), (503, "-", 2), (504, "+", 3), (505, "-", 3))),
        AlarmDefinition(3000, "Emergency stop", Reaction.RAPID_STOP | _STOP | Reaction.MODE_GROUP,
                        Clear.EMERGENCY_STOP_ACK, "[control]"),
        AlarmDefinition(10203, "Channel %1 NC start without reference point (action=%2)",
                        Reaction.NC_START_DISABLED, Clear.RESET, "seed 003 L2218-2231; [control] number"),
        AlarmDefinition(10621, "Channel %1 axis %2 rests on software limit switch %3",
                        Reaction.NONE, Clear.SELF, "[control]"),
        AlarmDefinition(10652, "Channel %1 axis %2 gantry warning limit exceeded", Reaction.NONE, Clear.SELF,
                        "seed 003 L14467-14476 (the message 'warning limit exceeded', gone below the limit);"
                        " [control] number and text"),
        AlarmDefinition(10653, "Channel %1 axis %2 error limit exceeded",
                        Reaction.RAPID_STOP | _STOP | Reaction.MODE_GROUP, Clear.RESET,
                        "seed 003 L14496-14501 (number and text; the whole grouping stops, L14588);"
                        " [control] reaction (the mode group stops) and reset"),
        AlarmDefinition(10654, "Channel %1 waiting for synchronization start of gantry group %2", Reaction.NONE,
                        Clear.SELF, "seed 003 L14725-14731 (the message 'waiting for gantry grouping X to start"
                        " synchronization'); [control] number"),
        AlarmDefinition(10655, "Channel %1 synchronization of gantry group %2 in progress", Reaction.NONE,
                        Clear.SELF, "seed 003 L14698-14705 (the message 'gantry grouping X synchronizing',"
                        " suppressed by MD37150 bit 2); [control] number"),
        AlarmDefinition(10720, "Channel %1 block %3 axis %2 software limit switch %4",
                        _STOP | Reaction.READ_IN_DISABLED, Clear.RESET, "[control]"),
        AlarmDefinition(10860, "Channel %1 block %2 feedrate not programmed", _STOP, Clear.RESET,
                        "seed 003 L7841-7858"),
        AlarmDefinition(10870, "Channel %1 block %2 facing axis for constant cutting speed not defined", _STOP,
                        Clear.RESET, "seed 003 L7846-7851 (G96 / G961 without a transverse axis in MD20100);"
                        " [control] text"),
        AlarmDefinition(10900, "Channel %1 block %2 no S value programmed for constant cutting speed", _STOP,
                        Clear.RESET, "seed 003 L7857-7858; [control] text"),
        AlarmDefinition(12080, "Channel %1 block %2 syntax error in text %3", _STOP, Clear.RESET, "[control]"),
        AlarmDefinition(12550, "Channel %1 block %2 name %3 not defined or option/function not available",
                        _STOP, Clear.RESET, "[control]"),
        AlarmDefinition(14040, "Channel %1 block %2 error in end point of circle: %3", _STOP, Clear.RESET,
                        "[control] number and text (G2/G3: end point off the circle beyond MD21000 / MD21010,"
                        " radius too small, full circle with a radius); the reason as %3"),
        AlarmDefinition(14080, "Channel %1 block %2 jump destination %3 not found", _STOP, Clear.RESET,
                        "[control]"),
        AlarmDefinition(14760, "Channel %1 block %2 auxiliary function of a group programmed repeatedly", _STOP,
                        Clear.RESET, "[control] number and text: two functions of one group (MD22000; M0, M1,"
                        " M2, M17, M30 are one) in a block"),
        AlarmDefinition(14770, "Channel %1 block %2 auxiliary function programmed incorrectly", _STOP, Clear.RESET,
                        "[control] number and text: more than 5 M, 3 S, 3 H or one T, D, DL, F in a block, a value"
                        " or extended address no auxiliary function takes"),
        AlarmDefinition(14800, "Channel %1 block %2 programmed path velocity is less than or equal to zero",
                        _STOP, Clear.RESET, "seed 003 L7841-7858"),
        AlarmDefinition(14092, "Channel %1 block %2 axis %3 is wrong axis type", _STOP, Clear.RESET,
                        "[control] number and text: an axis with MD30460 bit 8 (positioning axis / auxiliary"
                        " spindle only) as a path axis, or as the spindle of G33 / G331 (seed 003 L10843-10858)"),
        AlarmDefinition(14820, "Channel %1 block %2 negative maximum spindle speed programmed for constant"
                        " cutting speed", _STOP, Clear.RESET, "seed 003 L7853-7855 (LIMS < 0); [control] text"),
        AlarmDefinition(16510, "Channel %1 block %2 no transverse axis existing", _STOP, Clear.RESET,
                        "seed 003 L10283-10415, L10635-10645 (DIAMON / DIAM90 / DAC / DIC / RAC / RIC without"
                        " a transverse axis in MD20100); [control] number and text"),
        AlarmDefinition(16800, "Channel %1 block %2 traverse instruction DC not allowed for axis %3", _STOP,
                        Clear.RESET, "seed 003 L13164"),
        AlarmDefinition(16810, "Channel %1 block %2 traverse instruction ACP not allowed for axis %3", _STOP,
                        Clear.RESET, "seed 003 L13123"),
        AlarmDefinition(16820, "Channel %1 block %2 traverse instruction ACN not allowed for axis %3", _STOP,
                        Clear.RESET, "seed 003 L13123-13124"),
        AlarmDefinition(16830, "Channel %1 block %2 axis %3 incorrect modulo position programmed", _STOP,
                        Clear.RESET, "seed 003 L13150-13152"),
        AlarmDefinition(17810, "Channel %1 axis %2 not referenced", Reaction.NONE, Clear.RESET,
                        "seed 003 L34270, L34392-34394, L34624 (JOG to a fixed point / to a position of an axis"
                        " not referenced: it does not travel); [control] clearing"),
        AlarmDefinition(17812, "Channel %1 axis %2 JOG to fixed point: fixed point changed", Reaction.NONE,
                        Clear.RESET, "seed 003 L34338-34342 (the motion ends, a new JOG start travels on);"
                        " [control] clearing"),
        AlarmDefinition(17500, "Channel %1 block %2 axis %3 is not an indexing axis", _STOP, Clear.RESET,
                        "[control] number and text: CAC / CACP / CACN / CDC / CIC for an axis without MD30500"
                        " (seed 003 §11.4 names no alarm)"),
        AlarmDefinition(17501, "Channel %1 block %2 indexing axis %3 with Hirth joint is active", _STOP, Clear.RESET,
                        "[control] number and text: an end point of an axis with MD30505 = 1 that is no index"
                        " position (seed 003 L13740-13747: the Hirth joint locks it on its index positions only);"
                        " [INF] also PRESETON, G95, G43.4 and G68.2 on such an axis (L14064-14077)"),
        AlarmDefinition(17503, "Channel %1 block %2 indexing axis %3 with Hirth joint and axis not referenced", _STOP,
                        Clear.RESET, "[control] number and text: a motion of an axis with MD30505 = 1 before its"
                        " measuring system is referenced (seed 003 L13750-13757)"),
        AlarmDefinition(17510, "Channel %1 block %2 invalid index for indexing axis %3", _STOP, Clear.RESET,
                        "[control] number and text: a coded position that names no index position of the"
                        " axis (seed 003 L13868: 0 .. 59, an integer)"),
        AlarmDefinition(16105, "Channel %1 block %2 assigned spindle %3 does not exist", _STOP, Clear.RESET,
                        "seed 003 L20232-20235, L20328"),
        AlarmDefinition(16111, "Channel %1 block %2 spindle %3 no speed programmed", _STOP, Clear.RESET,
                        "seed 003 L23485-23488 (M3/M4 on a coupled FS without S)"),
        AlarmDefinition(16771, "Channel %1 following axis %2 overlaid motion not enabled", Reaction.NONE,
                        Clear.SELF, "seed 003 L23450-23456 (DB31.DBX26.4 missing; cleared by 26.4 or"
                        " decoupling)"),
        AlarmDefinition(16785, "Channel %1 block %2 identical axes/spindles %3", _STOP, Clear.RESET,
                        "[control] a coupling of a spindle with itself"),
        AlarmDefinition(16787, "Channel %1 block %2 coupling parameters may not be changed", _STOP, Clear.RESET,
                        "seed 003 L21986-21991 (MD21340 = 1; number unnamed in the seed) [control]"),
        AlarmDefinition(16792, "Channel %1 block %2 too many couplings for axis/spindle %3", _STOP, Clear.RESET,
                        "seed 003 L21749, L23018-23024 (more than 2 pairs, compound coupling; number"
                        " unnamed in the seed) [control]"),
        AlarmDefinition(16795, "Channel %1 block %2 string cannot be interpreted", _STOP, Clear.RESET,
                        "[control] COUPDEF / WAITC with an unknown block change or coupling type"),
        AlarmDefinition(16796, "Channel %1 block %2 coupling not defined", _STOP, Clear.RESET,
                        "[control] COUPON / COUPOF of a pair neither MD21300 nor COUPDEF defined"),
        AlarmDefinition(16797, "Channel %1 block %2 coupling is active", _STOP, Clear.RESET,
                        "seed 003 L22645, L22102-22104, L23465 (gear change, oscillation or a type change"
                        " while coupled; number from L22645) [control] reaction"),
        AlarmDefinition(20000, "Channel %1 axis %2 reference cam not reached", _STOP, Clear.RESET,
                        "seed 003 L1046-1048 (MD34030; number removed in the seed) [control]"),
        AlarmDefinition(20001, "Channel %1 axis %2 no cam signal", _STOP, Clear.RESET,
                        "phase 2 starts without the cam [control]"),
        AlarmDefinition(20002, "Channel %1 axis %2 zero mark missing", _STOP, Clear.RESET,
                        "seed 003 L1262-1264 (MD34060; number removed in the seed) [control], spec D.3"),
        AlarmDefinition(20003, "Channel %1 axis %2 fault in measuring system", _STOP, Clear.RESET,
                        "seed 003 L1550-1561"),
        AlarmDefinition(20004, "Channel %1 axis %2 reference mark missing", _STOP, Clear.RESET,
                        "seed 003 L1564-1568 (distance-coded marks within MD34060) [control]"),
        AlarmDefinition(20005, "Channel %1 axis %2 reference point approach aborted", _STOP, Clear.RESET,
                        "seed 003 L1252-1254 (override 0 % in phase 2) [control]"),
        AlarmDefinition(20090, "Axis %1 travel to fixed stop not possible", _STOP, Clear.RESET,
                        "seed 003 L38017-38019 (number and name); [control] cause: FXS on an axis without"
                        " MD37000, or FXS=1 while it is selected"),
        AlarmDefinition(20091, "Axis %1 has not reached fixed stop", Reaction.NONE, Clear.RESET,
                        "seed 003 L37963-37967 (the block changes); [control] reaction and clearing"),
        AlarmDefinition(20092, "Axis %1 travel to fixed stop still active", _STOP, Clear.RESET,
                        "seed 003 L37969-37972 (a motion or a new selection at the stop); [control] reaction"),
        AlarmDefinition(20093, "Axis %1 standstill monitoring at fixed stop has been triggered", _STOP, Clear.RESET,
                        "seed 003 L37335-37337, L37974-37984 (the axis left the window SD43520); [control]"
                        " reaction"),
        AlarmDefinition(20094, "Axis %1 travel to fixed stop has been aborted", _STOP, Clear.RESET,
                        "seed 003 L37986-37993 (pulses cancelled, or DB31.DBX3.1 taken away); [control] reaction"),
        AlarmDefinition(20141, "Channel %1 axis %2 motion-synchronized action: illegal axis type", _STOP,
                        Clear.RESET, "seed 003 L17574-17575 (POS on a spindle in speed control); text [control]; also"
                        " a POS on an axis another motion owns [control]"),
        AlarmDefinition(20143, "Channel %1 axis %2 command axis cannot be started, as it is controlled by the PLC",
                        _STOP, Clear.RESET, "seed 003 L11231-11235 (a synchronized action's command axis motion on a"
                        " PLC axis); text and reaction [control]"),
        AlarmDefinition(21610, "Channel %1 axis %2 encoder %3 frequency exceeded", _STOP | Reaction.RAPID_STOP,
                        Clear.RESET, "seed 003 L758-761 (re-reference after the encoder limit frequency);"
                        " [control] number and reaction"),
        AlarmDefinition(21612, "Channel %1 axis %2 VDI signal 'controller enable' reset during motion",
                        _STOP | Reaction.RAPID_STOP, Clear.RESET, "[control]"),
        AlarmDefinition(21614, "Channel %1 axis %2 hardware limit switch %3", _STOP, Clear.RESET, "[control]"),
        AlarmDefinition(22000, "Channel %1 block %2 spindle %3 gear stage change not possible", _STOP,
                        Clear.RESET, "seed 003 L18504-18508 (M40 without control mode)"),
        AlarmDefinition(22010, "Channel %1 block %2 spindle %3 actual gear stage %4 differs from set gear stage %5",
                        Reaction.NONE, Clear.CANCEL, "seed 003 L18401-18405; [control] text and reaction"),
        AlarmDefinition(22011, "Channel %1 block %2 spindle %3 cannot change to the programmed gear stage", _STOP,
                        Clear.RESET, "seed 003 L20050-20055 (MD35035 bit 2); [control] reaction"),
        AlarmDefinition(22020, "Channel %1 block %2 spindle %3 gear stage change position not reached",
                        _STOP | Reaction.READ_IN_DISABLED, Clear.RESET, "seed 003 L19697-19701"),
        AlarmDefinition(22025, "Channel %1 block %2 following axis/spindle %3 synchronism (2): fine tolerance"
                        " exceeded", Reaction.NONE, Clear.CANCEL, "seed 003 L29878-29888 (text; a display alarm the"
                        " operator clears, machining continues; block = the coupling's COUPON [control])"),
        AlarmDefinition(22026, "Channel %1 block %2 following axis/spindle %3 synchronism (2): coarse tolerance"
                        " exceeded", Reaction.NONE, Clear.CANCEL, "seed 003 L29878-29888 (text; a display alarm the"
                        " operator clears, machining continues; block = the coupling's COUPON [control])"),
        AlarmDefinition(22040, "Channel %1 block %2 spindle %3 is not referenced with zero mark", Reaction.NONE,
                        Clear.CANCEL, "seed 003 L22214-22231 (coupling activated unsynchronised: allowed,"
                        " with an alarm); L30398-30399 (CPMALARM bit 10: the same check of FS and LS)"
                        " [control] number and reaction"),
        AlarmDefinition(22100, "Channel %1 block %2 spindle %3 chuck speed exceeded", _STOP, Clear.RESET,
                        "seed 003 L20946-20969"),
        AlarmDefinition(25020, "Axis %1 zero mark monitoring of active encoder",
                        Reaction.NC_START_DISABLED | Reaction.STOP_AXES, Clear.RESET, "seed 003 L2041-2043"),
        AlarmDefinition(25022, "Axis %1 encoder %2 warning %3", Reaction.NONE, Clear.CANCEL,
                        "seed 003 L2038-2040"),
        AlarmDefinition(25040, "Axis %1 standstill monitoring", _STOP | Reaction.RAPID_STOP, Clear.RESET,
                        "[control]"),
        AlarmDefinition(26000, "Axis %1 clamping monitoring", _STOP | Reaction.RAPID_STOP, Clear.RESET,
                        "[control] number and text: the clamped axis (DB31.DBX2.3) left its position by more than"
                        " MD36050; the seed names DB31.DBX2.3 only (L15436, L15524)"),
        AlarmDefinition(25050, "Axis %1 contour monitoring", _STOP | Reaction.RAPID_STOP, Clear.RESET,
                        "[control]"),
        AlarmDefinition(25080, "Axis %1 positioning monitoring", _STOP | Reaction.RAPID_STOP, Clear.RESET,
                        "[control]"),
        AlarmDefinition(26075, "Channel %1 axis %2 not available for the NC program, as exclusively controlled"
                                " by the PLC", _STOP, Clear.RESET,
                        "seed 003 L12215-12217, L12516-12520 (MD30460 bit 4; a program or synchronized action"
                        " names the axis); text and reaction [control]"),
        AlarmDefinition(26076, "Channel %1 axis %2 not available for the NC program, as permanently assigned to"
                                " the PLC", _STOP, Clear.RESET,
                        "seed 003 L12217 (MD30460 bit 5); text and reaction [control]"),
        AlarmDefinition(207900, "Axis %1 drive: motor blocked", _STOP | Reaction.RAPID_STOP, Clear.RESET,
                        "[control] SINAMICS F07900 as the NC shows it; the seeds name no drive fault: a part"
                        " twisted between two chucks blocks the counter spindle (vc/plant/workpiece.py)"),
        AlarmDefinition(65830, "Channel %1 spindle %2 gear stage change not acknowledged within MD10192 = %3 s",
                        _STOP, Clear.RESET, "seed 003 L19127-19147 (MD10192; the seed names no number);"
                        " project alarm number"),
        AlarmDefinition(65840, "Channel %1 block %2 G51.2 argument out of range: %3", _STOP, Clear.RESET,
                        "seed 002 L29-31 (P 1..999, Q -999..999 not 0, R 0..9999999); project alarm number,"
                        " the seed names none"),
        AlarmDefinition(65841, "Channel %1 block %2 G51.2 while synchronous not allowed (ECN = 0)", _STOP,
                        Clear.RESET, "seed 002 L67-69, L204-208; project alarm number"),
        AlarmDefinition(65842, "Channel %1 block %2 G51.2 / G50.2 must stand in a block of its own", _STOP,
                        Clear.RESET, "seed 002 L21-23; project alarm number"),
        AlarmDefinition(65843, "Channel %1 block %2 axis %3 is synchronised by polygon turning", _STOP,
                        Clear.RESET, "seed 002 L128-131 (master and slave cannot be commanded, only the"
                        " master's speed and direction); project alarm number"),
        AlarmDefinition(65820, "Channel %1 axis %2 orthogonal axis: reference the inclined axis %3 first",
                        _STOP, Clear.RESET,
                        "seed 000 L62-66, L375, L381, L88-100 (inclined-axis control); project alarm number,"
                        " the seed names none"),
        AlarmDefinition(65821, "Channel %1 block %2 G28/G30 names the orthogonal axis %3 and the inclined axis %4"
                        " in one block: return the inclined axis first", _STOP, Clear.RESET,
                        "seed 000 L88-100; project alarm number, the seed names none"),
        AlarmDefinition(65822, "Channel %1 block %2 %3 cannot be used with inclined-axis control", _STOP,
                        Clear.RESET, "seed 000 L364-370 (rigid tapping on the inclined axis, feed axis synchronous"
                        " control, polygon turning, hypothetical axis, PMC axis, superimposed control); project"
                        " alarm number"),
        AlarmDefinition(65824, "Channel %1 inclined-axis control not possible: %2", Reaction.NC_START_DISABLED,
                        Clear.POWER_ON, "seed 000 L379-381 (linear axes of one increment system only; the"
                        " machine data take effect at power-on, L403-405); project alarm number"),
        AlarmDefinition(65870, "Channel %1 block %2 G33 thread cutting: master spindle %3 is at a standstill", _STOP,
                        Clear.RESET, "seed 003 L8211-8399 (G33 follows the master spindle; the seed names no"
                        " alarm); project alarm number"),
        AlarmDefinition(65850, "Channel %1 block %2 G53.1 P%3: P must be 0, 1 or 2 (COR-149)", _STOP, Clear.RESET,
                        "seed 001 L59 (Syntec COR-149); project alarm number"),
        AlarmDefinition(65851, "Channel %1 block %2 no solution for this tool direction within the rotary ranges"
                        " Pr3009-3012 (COR-153)", _STOP, Clear.RESET,
                        "seed 001 L59-60 (Syntec COR-153); project alarm number"),
        AlarmDefinition(65852, "Channel %1 block %2 rotary axis %3 would leave its five-axis range %4 (Pr3009-3012)",
                        _STOP, Clear.RESET,
                        "seed 001 L13-15 (travel protection while five-axis functions are active; the seed"
                        " names no alarm number); project alarm number"),
        AlarmDefinition(65853, "Channel %1 block %2 five-axis block not allowed: %3", _STOP, Clear.RESET,
                        "seed 001 L42-46 (G43.4 L2 E / R out of range: HSHP-3551 COR alarm), L59-60 (G53.1"
                        " after G68.2); project alarm number"),
    )
}


# The PLC's user alarms (DB2 user area 0, vc/core/nck/plc_alarms.py): their texts and reactions
# are the machine's (plc_alarms: of the machine file, MD14516), so they have no entry above.
READ_IN_DISABLED = Reaction.READ_IN_DISABLED.value


def known_alarm(number: int) -> bool:
    """An alarm the simulated control can show: one of ``ALARM_TEXTS`` or a PLC user alarm."""
    return number in ALARM_TEXTS or number in PLC_USER_ALARMS


def format_text(template: str, parameters: tuple[object, ...]) -> str:
    text = template
    for index, parameter in reversed(list(enumerate(parameters, start=1))):
        text = text.replace(f"%{index}", str(parameter))
    return text


@dataclass(slots=True)
class AlarmList:
    """The alarms present in the NCK, in the order they were raised."""

    present: list[Alarm] = field(default_factory=list)
    history: list[Alarm] = field(default_factory=list)  # every alarm ever raised, for reports
    cleared: list[tuple[Alarm, Clear]] = field(default_factory=list)  # every alarm cleared, and how, for reports
    version: int = 0  # counts changes of ``present``, so the interface is rewritten only on change
    _reactions: dict[str | None, int] = field(default_factory=dict)  # per channel, valid for ``version``
    _reactions_version: int = -1

    def raise_alarm(
        self, number: int, cycle: int, *parameters: object, channel: str = "", axis: str = ""
    ) -> Alarm:
        """Raise alarm ``number`` unless the same alarm is already present for the same place."""
        return self.raise_defined(ALARM_TEXTS[number], cycle, *parameters, channel=channel, axis=axis)

    def raise_defined(self, definition: AlarmDefinition, cycle: int, *parameters: object, channel: str = "",
                      axis: str = "") -> Alarm:
        """Raise the alarm of ``definition`` (one the machine defines: a PLC user alarm with its
        machine's text) unless the same alarm is already present for the same place."""
        number = definition.number
        for alarm in self.present:
            if alarm.number == number and alarm.channel == channel and alarm.axis == axis:
                return alarm
        alarm = Alarm(number, format_text(definition.text, parameters), definition.reaction,
                      definition.clear, channel, axis, cycle)
        self.present.append(alarm)
        self.history.append(alarm)
        self.version += 1
        return alarm

    def clear(self, number: int, *, channel: str | None = None, axis: str | None = None,
              how: Clear = Clear.SELF) -> None:
        """Clear alarm ``number`` (of ``channel`` / ``axis``); ``how``: what cleared it, for reports
        (by default its cause is gone)."""
        self._keep([
            alarm for alarm in self.present
            if not (alarm.number == number and (channel is None or alarm.channel == channel)
                    and (axis is None or alarm.axis == axis))
        ], how)

    def clear_on(self, kinds: tuple[Clear, ...], channel: str | None = None) -> None:
        """Clear every alarm whose clearing condition is one of ``kinds`` (reset, cancel ...); the
        first kind says what cleared them (a reset also clears what the cancel key would)."""
        self._keep([
            alarm for alarm in self.present
            if alarm.clear not in kinds or (channel is not None and alarm.channel not in ("", channel))
        ], kinds[0])

    def _keep(self, remaining: list[Alarm], how: Clear) -> None:
        if len(remaining) != len(self.present):
            self.cleared.extend((alarm, how) for alarm in self.present if alarm not in remaining)
            self.present = remaining
            self.version += 1

    def reactions(self, channel: str | None = None) -> int:
        """The combined reactions of the alarms acting on ``channel`` (all alarms for None).

        A plain int of ``Reaction`` bits: the cycle tests it with ``& STOP_AXES`` and the
        like, and int operations cost far less than ``Flag`` operations.
        """
        if self._reactions_version != self.version:
            self._reactions.clear()
            self._reactions_version = self.version
        cached = self._reactions.get(channel)
        if cached is not None:
            return cached
        result = 0
        for alarm in self.present:
            if channel is None or alarm.channel in ("", channel) or Reaction.MODE_GROUP in alarm.reaction:
                result |= alarm.reaction.value
        self._reactions[channel] = result
        return result

    def __iter__(self) -> Iterator[Alarm]:
        return iter(self.present)

    def __len__(self) -> int:
        return len(self.present)

    def is_present(self, number: int, axis: str | None = None) -> bool:
        return any(a.number == number and (axis is None or a.axis == axis) for a in self.present)
