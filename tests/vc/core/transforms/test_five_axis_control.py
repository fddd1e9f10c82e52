"""The five-axis functions in the channel: G43.4, G43 / G49, G68.2 / G69, G53.1, the rotary ranges.

mill_5axis (table-table, seed 001 Pr3001 = 2): trunnion A1 about X through Y 250 / Z -380,
left-hand, range -120 .. +30 (MD63009 240 -> 30); table C1 about Z at X 300, left-hand,
endless.  All five axes have calibrated absolute encoders here (referenced at power-on);
tool H1 is 100 mm long, H2 50 mm (MD62950).  Hand-computed positions are in the comments.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import pytest
from core_rig import FIVE_AXIS, Rig, machine

from vc.core.channel.program_run import ChannelState

CHAIN = ("X1", "Y1", "Z1", "A1", "C1")
ABSOLUTE = "CHAN1: {MD20700: 0, MD62950: [100.0, 50.0]}\n" + "\n".join(
    f"{axis}: {{MD30240: [4], MD34210: [2]}}" for axis in CHAIN)
START = "G90 G0 X350 Y250 Z-180 A0 C0\n"  # spindle face; with H1 the tip stands at (350, 250, -280)


def _rig(overrides: str = ABSOLUTE) -> Rig:
    rig = Rig(machine(overrides, FIVE_AXIS))
    rig.ready_mda(*CHAIN)
    return rig


def _tip(rig: Rig) -> tuple[float, ...]:
    """CHAN1.toolTipX/Y/Z: the forward kinematics of the actual positions."""
    return tuple(rig.sim.axis_quantity("CHAN1", f"toolTip{axis}") for axis in "XYZ")


def _direction(rig: Rig) -> tuple[float, ...]:
    return tuple(rig.sim.axis_quantity("CHAN1", f"toolDir{axis}") for axis in "XYZ")


def _run_to_stop(rig: Rig, cycles: int = 20_000) -> None:
    """Until the program stops (M0, alarm) or ends, then let the servo loops settle."""
    rig.step(5)
    rig.run_until(lambda: rig.channel.state is not ChannelState.ACTIVE, cycles)
    rig.step(100)


def _positions(rig: Rig) -> dict[str, float]:
    return {name: rig.axis(name).actual for name in CHAIN}


def _largest_while_tcp_runs(rig: Rig, measure: Callable[[], float]) -> float:
    """The largest ``measure()`` over the cycles of the running program with G43.4 active."""
    largest = 0.0
    rig.step(5)
    while rig.channel.state is ChannelState.ACTIVE:
        rig.step()
        if rig.channel.modal.five_axis.tool_center_point:
            largest = max(largest, measure())
    rig.step(100)
    return largest


def test_g43_4_keeps_the_tool_tip_while_a_and_c_turn() -> None:
    rig = _rig()
    rig.mda(START + "G43.4 H1\nG1 A-30 C90 F2000\nM0")
    deviation = _largest_while_tcp_runs(rig, lambda: math.dist(_tip(rig), (350.0, 250.0, -280.0)))
    assert deviation < 0.005  # measured 0.0014 mm: the drives' lag while they accelerate
    # q - O2 = (50, 0, 100); R2 = Rz(-90) -> (0, -50, 100); + (O2 - O1) = (300, -50, 100);
    # R1 = Rx(30) -> (300, -93.301, 61.603); + O1 (0, 250, -380) -> (300, 156.699, -318.397); + L t0
    assert _positions(rig) == pytest.approx({"X1": 300.0, "Y1": 156.699, "Z1": -218.397, "A1": -30.0,
                                             "C1": 90.0}, abs=2e-3)
    # t_w = R2^T R1^T z = Rz(90) (0, 0.5, 0.866) = (-0.5, 0, 0.866)
    assert _direction(rig) == pytest.approx((-0.5, 0.0, 0.8660254), abs=1e-4)


def test_incremental_words_under_g43_4_count_from_the_tool_tip() -> None:
    rig = _rig()
    rig.mda(START + "G43.4 H1\nG91 G1 Z10 X-5 F1000\nM0")
    _run_to_stop(rig)
    assert _tip(rig) == pytest.approx((345.0, 250.0, -270.0), abs=1e-3)
    assert rig.axis("Z1").actual == pytest.approx(-170.0, abs=1e-3)


def test_a_fast_tcp_move_is_slowed_to_the_axis_limits() -> None:
    rig = _rig()
    rig.mda(START + "G43.4 H1\nG1 A-30 C90 F100000\nM0")
    rig.step(5)
    rig.run_until(lambda: rig.channel.modal.five_axis.tool_center_point, 5000)
    previous = {name: rig.axis(name).command_velocity for name in CHAIN}
    worst_velocity = worst_accel = 0.0
    while rig.channel.state is ChannelState.ACTIVE:
        rig.step()
        for name in CHAIN:
            axis = rig.axis(name)
            worst_velocity = max(worst_velocity, abs(axis.command_velocity) / axis.dyn.max_velocity)
            worst_accel = max(worst_accel, abs(axis.command_velocity - previous[name]) / 0.002 / axis.dyn.max_accel)
            previous[name] = axis.command_velocity
    assert worst_velocity <= 1.0 + 1e-9
    assert worst_velocity > 0.5  # F100000 is far above what the axes allow: slowed, not to a crawl
    assert worst_accel <= 1.0 + 1e-6


def test_a_move_leaving_the_rotary_range_is_refused_before_it_starts() -> None:
    rig = _rig()
    rig.mda(START + "G43.4 H1\nG1 A-130 C90 F2000\nM30")
    _run_to_stop(rig)
    assert rig.alarm_numbers() == [65852]
    assert rig.sim.alarms()[0].axis == "A1"
    assert _positions(rig)["A1"] == pytest.approx(0.0, abs=1e-6)
    assert rig.channel.modal.five_axis.tool_center_point  # the block before it switched G43.4 on
    rig.pulse("CHAN1.basic.out.reset")
    rig.step(2)
    assert rig.alarm_numbers() == [] and not rig.channel.modal.five_axis.tool_center_point


@pytest.mark.parametrize(("program", "alarm"), [
    ("G53.1", 65853),  # G53.1 must follow G68.2
    ("G68.2 X300 Y250 Z-380 I0 J-30 K0\nG53.1 P3", 65850),  # COR-149
    ("G68.2 X300 Y250 Z-380 I0 J125 K0\nG53.1", 65851),  # COR-153: A -125 / +125 outside -120 .. 30
    ("G43.4 H1 L3", 65853),  # L is 0 or 2
    ("G43.4 H1 E1", 65853),  # E belongs to L2
    ("G43.4 H11", 65853),  # offsets H0 .. H10
    ("G43.4 G91 Z1", 65853),  # incremental in the switching block
    ("G43 G49 H1", 65853),
    ("G68.2 I0 J-30\nG1 A-30 F1000", 65853),  # rotary axes with G68.2 only through G53.1
    ("G43.4 H1\nG1 A10 X1000 F1000", 10720),  # the path leaves the software limits
    ("G43.4 H1\nG49 G1 X1000 F1000", 10720),  # switched off in the block: an ordinary end point
    ("G68.2 X0 Y0 Z0 I0 J0 K0\nG69 G1 X1000 F1000", 10720),
])
def test_refused_five_axis_blocks(program: str, alarm: int) -> None:
    rig = _rig()
    rig.mda(program)
    _run_to_stop(rig, 500)
    assert rig.alarm_numbers() == [alarm]
    assert rig.get("CHAN1.basic.in.progStateStopped") == 1


def test_five_axis_words_on_a_machine_without_the_chain_raise_12550() -> None:
    rig = _rig(ABSOLUTE.replace("MD20700: 0,", "MD20700: 0, MD63001: 0,"))
    rig.mda("G43.4 H1")
    _run_to_stop(rig, 500)
    assert rig.alarm_numbers() == [12550]


def test_sto_g43_4_l2_is_refused_as_a_missing_function() -> None:
    """STO (seed 001 L42-46) is not part of this control: 12550 before the block does anything."""
    rig = _rig()
    rig.mda("G43.4 H1 L2 E0.2 R1")
    _run_to_stop(rig, 500)
    assert rig.alarm_numbers() == [12550]
    assert not rig.channel.modal.five_axis.tool_center_point
    assert any("G43.4 L2" in str(alarm) for alarm in rig.sim.alarms())
    rig.pulse("CHAN1.basic.out.reset")
    rig.step(2)
    rig.mda("G43.4 H1 L0\nM0")  # STO off: accepted, G43.4 on
    _run_to_stop(rig)
    assert rig.alarm_numbers() == [] and rig.channel.modal.five_axis.tool_center_point


def test_tilted_plane_g53_1_then_moves_in_the_plane() -> None:
    rig = _rig()
    rig.mda("G90 G0 X300 Y250 Z-100 A0 C0\nG68.2 X300 Y250 Z-380 I90 J-30 K0\nG53.1 P1\nG43 H1\n"
            "G1 X0 Y0 Z50 F2000\nX20\nM0")
    _run_to_stop(rig)
    # R = Rz(90) Rx(-30): plane Z = (-0.5, 0, 0.866), plane X = workpiece +Y; P1 turns A positive
    assert _positions(rig)["A1"] == pytest.approx(30.0, abs=1e-3)
    assert rig.axis("C1").shown(rig.axis("C1").actual) == pytest.approx(270.0, abs=1e-3)
    assert _direction(rig) == pytest.approx((-0.5, 0.0, 0.8660254), abs=1e-4)
    # tip = (300, 250, -380) + R (20, 0, 50) = (275, 270, -336.699)
    assert _tip(rig) == pytest.approx((275.0, 270.0, -336.699), abs=1e-3)
    assert _positions(rig)["X1"] == pytest.approx(280.0, abs=1e-3)
    rig.pulse("CHAN1.basic.out.reset")
    rig.step(2)
    assert rig.channel.modal.five_axis.plane is None  # Pr3014 = 0: not kept over reset


def test_g53_1_under_g43_4_keeps_the_tip() -> None:
    rig = _rig()
    rig.mda(START + "G43.4 H2\nG68.2 X350 Y250 Z-330 I0 J-20 K0\nG53.1\nM0")
    _run_to_stop(rig)
    assert _tip(rig) == pytest.approx((350.0, 250.0, -230.0), abs=2e-3)  # H2 = 50 mm below the face
    assert _direction(rig) == pytest.approx((0.0, math.sin(math.radians(20)), math.cos(math.radians(20))),
                                            abs=1e-4)


def test_g3_under_g43_4_keeps_the_tool_tip_on_the_arc_while_the_table_turns() -> None:
    # the tip from (350, 250, -280) about (330, 250) counter-clockwise to (330, 270), C1 0 -> 90 and
    # A1 0 -> -20 with it (Pr3054 = 0: the angles linear in the path parameter)
    rig = _rig()
    rig.mda(START + "G43.4 H1\nG3 X330 Y270 I-20 J0 A-20 C90 F1000\nM0")

    def off_the_arc() -> float:
        x, y, z = _tip(rig)
        return max(abs(math.hypot(x - 330.0, y - 250.0) - 20.0), abs(z + 280.0))

    off = _largest_while_tcp_runs(rig, off_the_arc)
    assert off < 0.001  # measured 0.00026 mm: the drives' lag while they accelerate
    assert _tip(rig) == pytest.approx((330.0, 270.0, -280.0), abs=1e-3)
    assert rig.axis("C1").actual == pytest.approx(90.0, abs=1e-3)
    assert rig.axis("A1").actual == pytest.approx(-20.0, abs=1e-3)
