"""Block decoding: modal G-code state, end points, dwell, program end, and the decode alarms.

The turn-mill's channel: geometry X = channel axis 1 (X1), Y = channel axis 3 (Y1),
Z = channel axis 2 (Z1) (MD20050 = [1, 3, 2]).  X1, Z1 and Y1 are absolute, calibrated
encoders here, so they are referenced and their software limits are active:
X1 -5 .. 305, Z1 -8 .. 608, Y1 -100 .. 100 (MD36100 / MD36110).
"""

from __future__ import annotations

import pytest
from core_rig import ABSOLUTE_XYZ, machine

from interfaces.catalog import load_catalog
from vc.config.model import ChannelConfig
from vc.core.axis.axis import MachineAxis
from vc.core.nck.nck import Nck
from vc.core.program.block_plan import (
    EXACT_STOP_COARSE,
    EXACT_STOP_FINE,
    INTERPOLATION_END,
    BlockPlan,
    DecodeAlarm,
    ModalState,
)
from vc.core.program.interpreter import decode
from vc.core.program.program import parse_program


class Decoder:
    """One channel's decoding context: its modal state persists from block to block."""

    def __init__(self, overrides: str = ABSOLUTE_XYZ):
        config = machine(overrides)
        nck = Nck(config, load_catalog())
        self.channel: ChannelConfig = config.channels[0]
        self.axes: dict[str, MachineAxis] = nck.channels[0].axes_by_name
        self.modal = ModalState()

    def __call__(self, text: str) -> tuple[BlockPlan, DecodeAlarm | None]:
        (block,) = parse_program(text)
        return decode(block, self.modal, self.channel, self.axes)

    def ok(self, text: str) -> BlockPlan:
        plan, alarm = self(text)
        assert alarm is None, alarm
        return plan


@pytest.fixture
def dec() -> Decoder:
    return Decoder()


# ------------------------------------------------------------------------------ motion blocks


def test_g1_block_gives_end_point_feed_and_fine_exact_stop(dec: Decoder) -> None:
    plan = dec.ok("G1 X100 F500")
    assert plan.targets == {"X1": 100.0}
    assert plan.rapid is False
    assert plan.feed == 500.0
    assert plan.block_end == EXACT_STOP_FINE  # G60/G601 is the reset setting


def test_g0_is_the_reset_setting_of_group_1(dec: Decoder) -> None:
    plan = dec.ok("X100")
    assert plan.rapid is True
    assert plan.targets == {"X1": 100.0}


def test_geometry_axis_names_map_to_machine_axes_per_md20050(dec: Decoder) -> None:
    plan = dec.ok("G0 X10 Y20 Z30")
    assert plan.targets == {"X1": 10.0, "Y1": 20.0, "Z1": 30.0}


def test_machine_axis_names_are_accepted_with_an_assignment(dec: Decoder) -> None:
    assert dec.ok("G0 X1=12 Z1=34").targets == {"X1": 12.0, "Z1": 34.0}


def test_g1_and_f_are_modal(dec: Decoder) -> None:
    dec.ok("G1 X10 F250")
    plan = dec.ok("X20")
    assert plan.rapid is False
    assert plan.feed == 250.0
    assert plan.targets == {"X1": 20.0}


def test_g91_adds_to_the_current_setpoint_and_g90_restores_absolute(dec: Decoder) -> None:
    # X1 stands at 150 (physical start = actual value, absolute encoder).
    assert dec.ok("G91 G0 X5").targets == {"X1": 155.0}
    assert dec.ok("G90 X5").targets == {"X1": 5.0}


def test_ic_and_ac_override_the_modal_dimension_for_one_value(dec: Decoder) -> None:
    # Z1 stands at 300, X1 at 150.
    assert dec.ok("G90 G0 Z=IC(10) X=AC(20)").targets == {"Z1": 310.0, "X1": 20.0}
    assert dec.ok("G91 X=AC(40) Z=IC(-5)").targets == {"X1": 40.0, "Z1": 295.0}


def test_g602_g603_and_g64_select_the_block_end(dec: Decoder) -> None:
    assert dec.ok("G602 G1 X1 F100").block_end == EXACT_STOP_COARSE
    assert dec.ok("G601 X2").block_end == EXACT_STOP_FINE
    assert dec.ok("G64 X3").block_end == INTERPOLATION_END
    assert dec.ok("G60 X4").block_end == EXACT_STOP_FINE


def test_modal_reset_restores_g0_g90_g601_and_no_feed(dec: Decoder) -> None:
    dec.ok("G91 G1 G602 X1 F100")
    dec.modal.reset()
    assert (dec.modal.rapid, dec.modal.absolute, dec.modal.block_end, dec.modal.feed) == (
        True, True, EXACT_STOP_FINE, None)


@pytest.mark.parametrize(("per_minute", "per_revolution"), [("G94", "G95"), ("G98", "G99")])
def test_g95_makes_f_a_feed_per_revolution_and_g94_a_feed_per_minute(dec: Decoder, per_minute: str,
                                                                    per_revolution: str) -> None:
    # G98 / G99: the ISO words of seed 002's polygon programs (L241)
    plan = dec.ok(f"{per_revolution} G1 X10 F0.2")
    assert (plan.feed, plan.feed_per_revolution) == (0.2, True)
    assert dec.ok("X20").feed_per_revolution  # modal
    plan = dec.ok(f"{per_minute} X30 F120")
    assert (plan.feed, plan.feed_per_revolution) == (120.0, False)
    dec.modal.reset()
    assert dec.modal.per_revolution is False  # G94 is the reset setting


def test_a_change_of_the_feed_type_wants_a_new_f(dec: Decoder) -> None:
    dec.ok("G1 X10 F300")
    _, alarm = dec("N20 G95 X20")
    assert alarm is not None and alarm.number == 10860
    assert dec.ok("G95 X20 F0.1").feed == 0.1  # the same type again keeps F
    assert dec.ok("G95 X30").feed == 0.1


# ------------------------------------------------------------------------------ dwell, program stop and end


def test_g4_f_is_a_dwell_in_seconds_and_keeps_the_modal_feed(dec: Decoder) -> None:
    dec.ok("G1 X10 F300")
    plan = dec.ok("G4 F2.5")
    assert plan.dwell == 2.5
    assert plan.targets == {}
    # The F of the dwell block is a time: the next G1 block still moves at F300.
    assert dec.ok("X20").feed == 300.0


@pytest.mark.parametrize(("text", "stop", "end"), [("M0", True, False), ("M30", False, True),
                                                    ("M2", False, True), ("M1", False, False)])
def test_program_stop_and_end(dec: Decoder, text: str, stop: bool, end: bool) -> None:
    plan = dec.ok(text)
    assert (plan.program_stop, plan.program_end) == (stop, end)


def test_block_number_only_does_nothing(dec: Decoder) -> None:
    plan = dec.ok("N10")
    assert plan.targets == {} and plan.dwell == 0.0 and not plan.program_end


# ------------------------------------------------------------------------------ decode alarms


def test_g1_without_any_feed_raises_10860(dec: Decoder) -> None:
    _, alarm = dec("N10 G1 X10")
    assert alarm is not None
    assert alarm.number == 10860
    assert alarm.parameters == ("CHAN1", "N10")


def test_g1_with_f0_raises_14800(dec: Decoder) -> None:
    _, alarm = dec("G1 X10 F0")
    assert alarm is not None and alarm.number == 14800


def test_g0_needs_no_feed(dec: Decoder) -> None:
    assert dec("G0 X10")[1] is None


def test_unknown_keyword_raises_12550_naming_it(dec: Decoder) -> None:
    _, alarm = dec("N30 G1 X10 F100 NOSUCHWORD")
    assert alarm is not None
    assert alarm.number == 12550
    assert alarm.parameters == ("CHAN1", "N30", "NOSUCHWORD")


def test_unknown_axis_name_raises_12550(dec: Decoder) -> None:
    # The turn-mill has no axis called A.
    _, alarm = dec("G0 A10")
    assert alarm is not None and alarm.number == 12550


def test_syntax_error_raises_12080_with_the_faulty_text(dec: Decoder) -> None:
    _, alarm = dec("G1 X=")
    assert alarm is not None
    assert alarm.number == 12080
    assert alarm.parameters[0] == "CHAN1"
    assert "X=" in str(alarm.parameters[2])


@pytest.mark.parametrize(("text", "axis", "sign"), [("G0 X305.001", "X1", "+"), ("G0 X-5.001", "X1", "-"),
                                                    ("G0 Z608.5", "Z1", "+"), ("G0 Y-100.5", "Y1", "-")])
def test_end_point_beyond_a_software_limit_raises_10720(dec: Decoder, text: str, axis: str,
                                                        sign: str) -> None:
    _, alarm = dec(text)
    assert alarm is not None
    assert alarm.number == 10720
    assert alarm.axis == axis
    assert sign in alarm.parameters


def test_end_point_exactly_on_the_software_limit_is_allowed(dec: Decoder) -> None:
    assert dec.ok("G0 X305 Z-8").targets == {"X1": 305.0, "Z1": -8.0}


def test_incremental_end_point_beyond_the_limit_raises_10720(dec: Decoder) -> None:
    # X1 at 150: 150 + 160 = 310 > 305.
    _, alarm = dec("G91 G0 X160")
    assert alarm is not None and alarm.number == 10720


def test_unreferenced_axis_has_no_software_limit_check() -> None:
    # Incremental encoders (the file's default): not referenced, software limits inactive.
    dec = Decoder("CHAN1: {MD20700: 0}")
    assert dec("G0 X1000")[1] is None


# ------------------------------------------------------------------------------ G74 and PRESETON


def test_g74_names_the_axes_to_reference_and_stands_alone(dec: Decoder) -> None:
    assert dec.ok("G74 X1=0 Z=0").reference_axes == ("X1", "Z1")
    for text in ("G74 G1 X1=0", "G74 X1=0 F100", "G74", "G74 X1=0 M30"):
        _, alarm = dec(text)
        assert alarm is not None and alarm.number == 12080, text


def test_preseton_gives_machine_axes_their_new_actual_values(dec: Decoder) -> None:
    plan = dec.ok("PRESETON(X1, 10.5, Y, -2)")  # machine or program names
    assert plan.preset == {"X1": 10.5, "Y1": -2.0}
    assert plan.targets == {}


@pytest.mark.parametrize("text", [
    "PRESETON()",
    "PRESETON(X1)",  # a value missing
    "PRESETON(X1, 1, Z1)",
    "PRESETON(Q7, 1)",  # no such axis in the channel
    "PRESETON(SP1, 0)",  # a spindle
    "PRESETON(X1, 1) G1 X20 F100",  # a block of its own
    "PRESETON(X1, 1) M30",
])
def test_preseton_is_refused_with_a_syntax_alarm_when_it_does_not_fit(dec: Decoder, text: str) -> None:
    _, alarm = dec(text)
    assert alarm is not None and alarm.number == 12080


# ------------------------------------------------------------------------------ spindle words


def test_s_and_m3_address_the_master_spindle_and_extensions_another(dec: Decoder) -> None:
    plan = dec.ok("M3 S500 S2=800 M2=4")
    first, second = plan.spindles["SP1"], plan.spindles["SP2"]
    assert (first.speed, first.direction, first.m_function) == (500.0, 3, 3)
    assert (second.speed, second.direction, second.m_function) == (800.0, 4, 4)


@pytest.mark.parametrize(("text", "mode", "value", "wait"), [
    ("SPOS=90", "DC", 90.0, True),  # plain = DC (L16335-16349)
    ("SPOS=AC(45)", "AC", 45.0, True),
    ("SPOS[1]=IC(-720)", "IC", -720.0, True),
    ("SPOSA=ACP(10)", "ACP", 10.0, False),
    ("SPOSA[2]=ACN(350)", "ACN", 350.0, False),
    ("M19", "DC", 0.0, True),
])
def test_spindle_positioning_forms(dec: Decoder, text: str, mode: str, value: float, wait: bool) -> None:
    plan = dec.ok(text)
    (command,) = plan.spindles.values()
    assert command.position == (mode, value)
    assert command.wait_for_position is wait


def test_gear_stages_and_axis_mode(dec: Decoder) -> None:
    assert dec.ok("M40 S1200").spindles["SP1"].gear == 40
    assert dec.ok("M1=43").spindles["SP1"].gear == 43
    assert dec.ok("M70").spindles["SP1"].axis_mode
    implicit = dec.ok("SP1=90")  # the axis name of a spindle: an implicit M70 (L17421-17462)
    assert implicit.spindles["SP1"].axis_mode and implicit.targets == {"SP1": 90.0}


@pytest.mark.parametrize("text", ["S7=100", "M9=3", "SPOS[9]=0"])
def test_a_spindle_number_that_does_not_exist_raises_16105(dec: Decoder, text: str) -> None:
    _, alarm = dec(text)
    assert alarm is not None and alarm.number == 16105


def test_spindle_words_are_refused_beside_g74_and_preseton(dec: Decoder) -> None:
    for text in ("G74 X1=0 M3", "PRESETON(X1, 1) S100"):
        _, alarm = dec(text)
        assert alarm is not None and alarm.number == 12080, text


# ------------------------------------------------------------------------------ circles G2 / G3


def test_g2_with_i_j_gives_the_arc_from_the_program_position(dec: Decoder) -> None:
    # X1 stands at 150, Y1 at 0: centre (150 - 20, 0), end (130, 20): a quarter, counter-clockwise
    plan = dec.ok("G3 X130 Y20 I-20 J0 F500")
    assert plan.arc is not None and not plan.rapid and plan.feed == 500.0
    assert plan.arc.plane_axes == ("X1", "Y1")
    assert plan.arc.centre == pytest.approx((130.0, 0.0))
    assert plan.arc.sweep == pytest.approx(1.5707963)
    assert plan.targets == {"X1": 130.0, "Y1": 20.0}
    assert dec.modal.circle == "G3" and not dec.modal.rapid


def test_a_full_circle_puts_the_plane_axes_into_the_block(dec: Decoder) -> None:
    plan = dec.ok("G2 I-20 F500")
    assert plan.targets == {"X1": 150.0, "Y1": 0.0}
    assert plan.arc is not None and plan.arc.sweep == pytest.approx(-6.2831853)


def test_g18_is_the_z_x_plane_with_k_and_i(dec: Decoder) -> None:
    # Z1 at 300, X1 at 150: G18 G3 Z280 X170 K-20 turns about (Z 280, X 150) from +Z towards +X (normal Y)
    plan = dec.ok("G18 G3 Z280 X170 K-20 F500")
    assert plan.arc is not None and plan.arc.plane_axes == ("Z1", "X1")
    assert plan.arc.centre == pytest.approx((280.0, 150.0))
    assert plan.arc.sweep == pytest.approx(1.5707963)


def test_the_helix_axis_and_cr_radius(dec: Decoder) -> None:
    plan = dec.ok("G2 X130 Y20 Z290 CR=20 F500")
    assert plan.arc is not None and plan.arc.linear == (("Z1", 300.0, 290.0),)
    assert plan.arc.centre == pytest.approx((150.0, 20.0))  # G2 R+: the short way, clockwise


def test_g1_and_g0_end_circular_interpolation(dec: Decoder) -> None:
    dec.ok("G2 X130 Y20 R20 F500")
    assert dec.ok("G1 X100").arc is None and dec.modal.circle == ""
    dec.ok("G3 X130 Y20 R20")
    assert dec.ok("G0 X100").arc is None and dec.modal.circle == ""


@pytest.mark.parametrize(("text", "number", "detail"), [
    ("G3 X130 Y20 I-20 J5 F500", 14040, "radius at the end point"),
    ("G3 X150 Y0 R20 F500", 14040, "full circle programmed with a radius"),
    ("G2 X100 Y0 R20 F500", 14040, "radius 20 too small"),
    ("G2 X130 Y20 F500", 12080, "G2: centre I J K or radius CR= / R"),
    ("G2 X130 Y20 R20 I-20 F500", 12080, "G2: centre I J K or radius CR= / R"),
    ("G2 X130 Y20 K5 F500", 12080, "K is no centre word of the plane"),
    ("G1 X130 R20 F500", 12550, "R"),
])
def test_circle_alarms(dec: Decoder, text: str, number: int, detail: str) -> None:
    _, alarm = dec(text)
    assert alarm is not None and alarm.number == number
    assert detail in str(alarm.parameters[-1])


def test_an_arc_without_feed_raises_10860(dec: Decoder) -> None:
    _, alarm = dec("G2 I-20")
    assert alarm is not None and alarm.number == 10860


# ------------------------------------------------------------------------------ constant cutting speed G96 / G961


@pytest.fixture
def lathe() -> Decoder:
    return Decoder(ABSOLUTE_XYZ.replace("CHAN1: {MD20700: 0}", "CHAN1: {MD20700: 0, MD20100: X}"))


def test_g96_takes_s_as_the_cutting_speed_and_f_per_revolution(lathe: Decoder) -> None:
    plan = lathe.ok("G96 S230 M3 G1 X10 F0.2")
    assert (plan.constant_cutting, plan.cutting_speed, plan.feed_per_revolution) == ("G96", 230.0, True)
    command = plan.spindles["SP1"]
    assert (command.speed, command.direction) == (None, 3)  # S is no spindle speed under G96
    assert [(aux.kind, aux.value) for aux in plan.aux_functions if aux.kind == "S"] == [("S", 230.0)]
    assert lathe.ok("X20").constant_cutting == "G96"  # modal


def test_g961_is_the_cutting_speed_with_f_per_minute_and_g97_g971_end_it(lathe: Decoder) -> None:
    plan = lathe.ok("G961 S100 G1 X10 F300")
    assert (plan.constant_cutting, plan.feed_per_revolution, plan.feed) == ("G961", False, 300.0)
    plan = lathe.ok("G97 S800 X20 F0.1")
    assert (plan.constant_cutting, plan.feed_per_revolution, plan.spindles["SP1"].speed) == ("", True, 800.0)
    plan = lathe.ok("G971 X30 F200")
    assert (plan.constant_cutting, plan.feed_per_revolution) == ("", False)


def test_g96_selected_again_keeps_the_last_cutting_speed_and_reset_forgets_it(lathe: Decoder) -> None:
    lathe.ok("G96 S180")
    lathe.ok("G97")
    assert lathe.ok("G96").cutting_speed == 180.0  # L7666-7668
    lathe.modal.reset()
    _, alarm = lathe("N10 G96")
    assert alarm is not None and alarm.number == 10900


def test_g4_s_under_g96_counts_revolutions(lathe: Decoder) -> None:
    lathe.ok("G96 S180")
    plan = lathe.ok("G4 S3")
    assert (plan.dwell_revolutions, plan.cutting_speed) == (3.0, 180.0)


@pytest.mark.parametrize(("text", "number"), [("G96 S100", 10870), ("G961 S100", 10870)])
def test_g96_without_a_transverse_axis_raises_10870(dec: Decoder, text: str, number: int) -> None:
    _, alarm = dec(f"N10 {text}")
    assert alarm is not None and alarm.number == number


def test_lims_limits_the_master_spindle_or_spindle_n_and_a_negative_value_raises_14820(lathe: Decoder) -> None:
    assert lathe.ok("LIMS=2500").spindle_limits == {"SP1": 2500.0}
    assert lathe.ok("LIMS[2]=1200").spindle_limits == {"SP2": 1200.0}
    _, alarm = lathe("N10 G96 S100 LIMS=-1")
    assert alarm is not None and alarm.number == 14820
    _, alarm = lathe("N20 LIMS[7]=100")
    assert alarm is not None and alarm.number == 16105


# ------------------------------------------------------------------------------ transverse axis: DIAMON / DIAM90


def test_diamon_halves_absolute_and_incremental_end_points_of_the_transverse_axis_only(lathe: Decoder) -> None:
    plan = lathe.ok("DIAMON G1 X200 Z100 F100")
    assert (plan.targets["X1"], plan.targets["Z1"]) == (100.0, 100.0)
    assert lathe.ok("G91 X-20").targets["X1"] == pytest.approx(lathe.axes["X1"].setpoint - 10.0)


def test_diam90_takes_absolute_values_as_diameters_and_incremental_ones_as_radii(lathe: Decoder) -> None:
    assert lathe.ok("DIAM90 G1 X200 F100").targets["X1"] == 100.0
    assert lathe.ok("G91 X-20").targets["X1"] == pytest.approx(lathe.axes["X1"].setpoint - 20.0)
    assert lathe.ok("X=IC(-20)").targets["X1"] == pytest.approx(lathe.axes["X1"].setpoint - 20.0)
    assert lathe.ok("G90 X=AC(60)").targets["X1"] == 30.0


def test_dac_dic_rac_ric_act_for_one_value_whatever_the_mode(lathe: Decoder) -> None:
    start = lathe.axes["X1"].setpoint
    assert lathe.ok("G1 X=DAC(100) F100").targets["X1"] == 50.0
    assert lathe.ok("X=DIC(-10)").targets["X1"] == pytest.approx(start - 5.0)
    assert lathe.ok("DIAMON X=RAC(40)").targets["X1"] == 40.0
    assert lathe.ok("X=RIC(4)").targets["X1"] == pytest.approx(start + 4.0)


def test_diamof_and_the_reset_value_are_radius(lathe: Decoder) -> None:
    lathe.ok("DIAMON")
    assert lathe.ok("DIAMOF G1 X80 F100").targets["X1"] == 80.0
    lathe.ok("DIAMON")
    lathe.modal.reset()
    assert lathe.modal.diameter == "DIAMOF"


@pytest.mark.parametrize("text", ["DIAMON", "DIAM90", "G1 X=DAC(10) F100"])
def test_diameter_programming_without_a_transverse_axis_raises_16510(dec: Decoder, text: str) -> None:
    _, alarm = dec(f"N10 {text}")
    assert alarm is not None and alarm.number == 16510


def test_dac_on_another_axis_raises_16510(lathe: Decoder) -> None:
    _, alarm = lathe("N10 G1 Z=DAC(10) F100")
    assert alarm is not None and (alarm.number, alarm.axis) == (16510, "Z1")
