"""The auxiliary functions a block outputs to the PLC (vc/core/program/aux_words.py).

The turn-mill's channel, main spindle 1 (MD20090), machine data at their defaults: M, S, T, H, D
and DL during the motion (MD22200 .. MD22252 = 1), F not at all (MD22240 = 3).
"""

from __future__ import annotations

import pytest
from core_rig import ABSOLUTE_XYZ, machine

from interfaces.catalog import load_catalog
from vc.core.nck.nck import Nck
from vc.core.program.block_plan import BlockPlan, DecodeAlarm, ModalState
from vc.core.program.commands import AuxiliaryFunction, OutputTime
from vc.core.program.interpreter import decode
from vc.core.program.program import parse_program

DURING = OutputTime.DURING_MOTION
# MD22000 .. MD22035 entry 0: M8 in group 2, quick, before the motion; entry 1: M9 in group 2
USER_FUNCTIONS = ABSOLUTE_XYZ.replace(
    "CHAN1: {MD20700: 0}",
    "CHAN1: {MD20700: 0, MD22000: [2, 2], MD22010: [M, M], MD22020: [0, 0], MD22030: [8, 9],"
    " MD22035: [0x23, 0x121]}")


class Decoder:
    def __init__(self, overrides: str = ABSOLUTE_XYZ):
        config = machine(overrides)
        nck = Nck(config, load_catalog())
        self.channel = config.channels[0]
        self.axes = nck.channels[0].axes_by_name
        self.modal = ModalState()

    def __call__(self, text: str) -> tuple[BlockPlan, DecodeAlarm | None]:
        (block,) = parse_program(text)
        return decode(block, self.modal, self.channel, self.axes)

    def functions(self, text: str) -> list[AuxiliaryFunction]:
        plan, alarm = self(text)
        assert alarm is None, alarm
        return plan.aux_functions

    def alarm(self, text: str) -> int | None:
        return None if (alarm := self(text)[1]) is None else alarm.number


@pytest.fixture
def dec() -> Decoder:
    return Decoder()


def test_functions_go_out_in_the_order_of_the_block_with_their_extended_address(dec: Decoder) -> None:
    assert dec.functions("M8 M2=10 T5 D1 H3=5.5 DL=2") == [
        AuxiliaryFunction("M", 0, 8, DURING, False), AuxiliaryFunction("M", 2, 10, DURING, False),
        AuxiliaryFunction("T", 0, 5, DURING, False), AuxiliaryFunction("D", 0, 1, DURING, False),
        AuxiliaryFunction("H", 3, 5.5, DURING, False), AuxiliaryFunction("DL", 0, 2, DURING, False)]


def test_spindle_functions_carry_the_spindle_number_and_still_drive_the_spindle(dec: Decoder) -> None:
    plan, alarm = dec("M3 S1000")
    assert alarm is None
    assert plan.aux_functions == [AuxiliaryFunction("M", 1, 3, DURING, False),
                                  AuxiliaryFunction("S", 1, 1000, DURING, False)]
    assert plan.spindles  # the spindle command is there as before
    assert dec.functions("M2=4 S2=50")[0] == AuxiliaryFunction("M", 2, 4, DURING, False)


def test_qu_makes_a_function_quick(dec: Decoder) -> None:
    assert dec.functions("M=QU(8) H=QU(7)") == [AuxiliaryFunction("M", 0, 8, DURING, True),
                                                AuxiliaryFunction("H", 0, 7, DURING, True)]


@pytest.mark.parametrize(("text", "flag"), [("M0", "program_stop"), ("M1", "optional_stop"),
                                            ("M2", "program_end"), ("M17", "program_end"), ("M30", "program_end")])
def test_program_flow_functions_go_out_at_the_block_end(dec: Decoder, text: str, flag: str) -> None:
    plan, alarm = dec(text)
    assert alarm is None and getattr(plan, flag)
    assert plan.aux_functions == [AuxiliaryFunction("M", 0, int(text[1:]), OutputTime.AT_BLOCK_END, False)]


def test_f_goes_out_only_when_md22240_asks(dec: Decoder) -> None:
    assert dec.functions("G1 X10 F500") == []  # MD22240 = 3: not output
    other = Decoder(ABSOLUTE_XYZ.replace("MD20700: 0", "MD20700: 0, MD22240: 0"))
    assert other.functions("G1 X10 F500") == [AuxiliaryFunction("F", 0, 500, OutputTime.BEFORE_MOTION, False)]


@pytest.mark.parametrize("text", ["M1 M2 M3 M4 M5 M6", "T1 T2", "H1 H2 H3 H4", "M1.5", "T-1", "D1.5"])
def test_too_many_or_malformed_functions_raise_14770(dec: Decoder, text: str) -> None:
    assert dec.alarm(text) == 14770


def test_two_program_flow_functions_in_one_block_raise_14760(dec: Decoder) -> None:
    assert dec.alarm("M0 M30") == 14760


def test_md22000_groups_and_md22035_timing() -> None:
    dec = Decoder(USER_FUNCTIONS)
    assert dec.functions("M8") == [AuxiliaryFunction("M", 0, 8, OutputTime.BEFORE_MOTION, True)]
    assert dec.functions("M9") == [AuxiliaryFunction("M", 0, 9, OutputTime.BEFORE_MOTION, False)]
    assert dec.alarm("M8 M9") == 14760
    assert dec.functions("M10")[0].time == DURING  # in no entry: MD22200


def test_an_m19_assigned_to_a_group_does_not_position_the_spindle() -> None:
    plan, alarm = Decoder()("M19")
    assert alarm is None and plan.spindles
    user = Decoder(ABSOLUTE_XYZ.replace("MD20700: 0", "MD20700: 0, MD22000: [4], MD22010: [M], MD22030: [19]"))
    plan, alarm = user("M19")
    assert alarm is None and not plan.spindles
    # MD22035 at its default 0x121: acknowledged normally, before the motion
    assert plan.aux_functions == [AuxiliaryFunction("M", 0, 19, OutputTime.BEFORE_MOTION, False)]
