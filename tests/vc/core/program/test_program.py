"""Part-program text to blocks: every item form of the SINUMERIK syntax the sequences use."""

from __future__ import annotations

import pytest

from vc.core.program.program import (
    Assignment,
    Block,
    Call,
    Jump,
    Keyword,
    Label,
    ValueFunction,
    Word,
    jump_target,
    parse_program,
)


def single(text: str) -> Block:
    blocks = parse_program(text)
    assert len(blocks) == 1, blocks
    return blocks[0]


# ------------------------------------------------------------------------------ address words


def test_address_words_with_signed_and_fractional_numbers() -> None:
    block = single("G1  X100.5  Z-2  F.5")
    assert block.items == (Word("G", 1.0), Word("X", 100.5), Word("Z", -2.0), Word("F", 0.5))
    assert block.error == ""


def test_x1_is_the_address_x_with_the_value_1() -> None:
    # "X1" is address X = 1 (DIN 66025), not a name: the block moves X to 1.
    assert single("X1").items == (Word("X", 1.0),)


def test_x1_followed_by_equals_is_an_assignment_to_the_axis_x1() -> None:
    # "X1=5": the '=' makes X1 a name (an axis identifier with a digit), value 5.
    assert single("X1=5").items == (Assignment("X1", "", 5.0),)
    assert single("X1 = 5").items == (Assignment("X1", "", 5.0),)


def test_letters_are_case_insensitive() -> None:
    assert single("x1 g1 f100").items == (Word("X", 1.0), Word("G", 1.0), Word("F", 100.0))


def test_a_blank_between_address_and_number_is_allowed() -> None:
    assert single("X 10").items == (Word("X", 10.0),)


def test_explicit_plus_sign_and_leading_zeros() -> None:
    assert single("X+3 G01").items == (Word("X", 3.0), Word("G", 1.0))


# ------------------------------------------------------------------------------ block numbers


def test_block_number_is_taken_out_of_the_items() -> None:
    block = single("N10 G1 X10")
    assert block.number == 10
    assert block.label == "N10"
    assert block.items == (Word("G", 1.0), Word("X", 10.0))


def test_block_number_with_leading_zeros() -> None:
    assert single("N010 G0").number == 10


def test_block_without_number_is_labelled_with_its_line() -> None:
    blocks = parse_program("G0 X1\n\nG1 X2 F100")
    assert [b.number for b in blocks] == [None, None]
    assert [b.line for b in blocks] == [1, 3]
    assert blocks[1].label == "line 3"


def test_block_number_alone_is_an_empty_block() -> None:
    block = single("N5")
    assert block.number == 5
    assert block.items == ()
    assert block.error == ""


# ------------------------------------------------------------------------------ assignments


def test_assignments_to_names_with_digits() -> None:
    assert single("X1=100 DILF=10 M2=3").items == (
        Assignment("X1", "", 100.0), Assignment("DILF", "", 10.0), Assignment("M2", "", 3.0))


def test_assignment_with_numeric_index_and_value_function() -> None:
    assert single("SPOS[2]=IC(-90)").items == (Assignment("SPOS", "2", ValueFunction("IC", -90.0)),)


@pytest.mark.parametrize("function", ["AC", "IC", "DC", "ACP", "ACN"])
def test_every_value_function(function: str) -> None:
    assert single(f"SPOS={function}(45.5)").items == (Assignment("SPOS", "", ValueFunction(function, 45.5)),)


def test_assignment_indexed_by_a_name() -> None:
    assert single("FA[S2]=3600 POLF[X]=10").items == (
        Assignment("FA", "S2", 3600.0), Assignment("POLF", "X", 10.0))


def test_assignment_of_a_string_keeps_its_case() -> None:
    assert single('TEXT="Mixed Case"').items == (Assignment("TEXT", "", "Mixed Case"),)


# ------------------------------------------------------------------------------ calls, keywords, labels


def test_call_with_names_and_numbers() -> None:
    assert single("COUPON(S2,S1,77)").items == (Call("COUPON", ("S2", "S1", 77.0)),)


def test_call_with_a_string_argument() -> None:
    assert single('MSG("Gear change")').items == (Call("MSG", ("Gear change",)),)


def test_call_with_an_empty_argument() -> None:
    assert single("WAITC(S2, ,S4)").items == (Call("WAITC", ("S2", "", "S4")),)


def test_keywords() -> None:
    assert single("LFON STOPRE").items == (Keyword("LFON"), Keyword("STOPRE"))


def test_a_keyword_with_an_index_takes_no_value() -> None:
    assert single("FINEA[X] POS[X]=10").items == (Keyword("FINEA", "X"), Assignment("POS", "X", 10.0))


def test_label() -> None:
    assert single("MM_THREAD:").items == (Label("MM_THREAD"),)


def test_mixed_block_keeps_the_written_order() -> None:
    block = single("N20 G1 X10 LFON COUPON(S2,S1) SPOS[2]=AC(0) F200")
    assert block.number == 20
    assert block.items == (Word("G", 1.0), Word("X", 10.0), Keyword("LFON"), Call("COUPON", ("S2", "S1")),
                           Assignment("SPOS", "2", ValueFunction("AC", 0.0)), Word("F", 200.0))


# ------------------------------------------------------------------------------ comments and lines


def test_comment_after_the_words_is_dropped_but_kept_in_the_text() -> None:
    block = single("G1 X10 ; comment X20")
    assert block.items == (Word("G", 1.0), Word("X", 10.0))
    assert block.text == "G1 X10 ; comment X20"


def test_blank_and_comment_lines_are_no_blocks_and_lines_count_from_one() -> None:
    blocks = parse_program("\n; header\n   \nN10 G0 X1\nN20 X2 ; back\n")
    assert [(b.line, b.number) for b in blocks] == [(4, 10), (5, 20)]


def test_block_number_with_only_a_comment() -> None:
    block = single("N10 ; nothing else")
    assert block.number == 10
    assert block.items == ()


# ------------------------------------------------------------------------------ syntax errors


@pytest.mark.parametrize("text", [
    "G1 X10 @",  # a character that is no part of the syntax
    "X1=",  # assignment without a value
    "COUPON(S2,S1",  # call without ')'
    "X100.5.3",  # a second decimal point
    "SPOS[2]=IC(-90, 3)",  # a value function takes one number
    "X[1",  # index without ']'
])
def test_syntax_error_is_kept_on_its_block_without_items(text: str) -> None:
    block = single(text)
    assert block.error != ""
    assert block.items == ()
    assert block.text == text


def test_syntax_error_does_not_stop_parsing_of_the_other_blocks() -> None:
    # The control raises alarm 12080 only when execution reaches the faulty block, so the
    # blocks before (and after) it must be there.
    blocks = parse_program("N10 G1 X10 F100\nN20 X=\nN30 X30")
    assert [b.line for b in blocks] == [1, 2, 3]
    assert blocks[0].error == "" and blocks[2].error == ""
    assert blocks[1].error != ""
    assert blocks[2].items == (Word("X", 30.0),)


def test_syntax_error_block_keeps_its_block_number() -> None:
    # Alarm 12080 "Channel %1 block %2 syntax error" names the block by its number (real control):
    # a block N20 with a syntax error is still block N20.
    blocks = parse_program("N10 G1 X10 F100\nN20 G1 X=")
    assert blocks[1].error != ""
    assert blocks[1].number == 20
    assert blocks[1].label == "N20"


@pytest.mark.parametrize("text", [
    "G1 X" + "9" * 308 + " F100",  # finite, but it overflowed the motion's arithmetic (OverflowError)
    "G1 X" + "9" * 5000,  # infinite as a double: NaN in the path interpolation (ValueError)
    "N" + "9" * 400 + " G1 X1",  # int(float(...)) of infinity (OverflowError)
    "R1=" + "9" * 400,
    "COUPON(S2,S1," + "9" * 400 + ")",
    "G1 X-1000000000000001",
])
def test_a_number_beyond_the_limit_is_a_syntax_error(text: str) -> None:
    block = single(text)
    assert block.items == () and block.error.endswith("beyond 1e+15")


def test_numbers_up_to_the_limit_are_read() -> None:
    assert single("G1 X1000000000000000 Z-1000000000000000").items == (
        Word("G", 1.0), Word("X", 1e15), Word("Z", -1e15))


@pytest.mark.parametrize("text", ["N" + "9" * 5000 + " G1 X1", "N" + "9" * 5000 + " GOTOF N1",
                                  "IDS=" + "9" * 5000 + " WHENEVER $A_IN[1]==1 DO $AC_ESR_TRIGGER=1"])
def test_block_and_action_numbers_of_thousands_of_digits_are_syntax_errors(text: str) -> None:
    """int() of more than 4,300 digits raised ValueError while the program was read."""
    assert single(text).error != ""


# ------------------------------------------------------------------------------ jumps


def test_conditional_and_plain_jumps() -> None:
    assert single("N69 IF $AC_LIFTFAST GOTOB MM_THREAD").items == (Jump("GOTOB", "MM_THREAD", "$AC_LIFTFAST"),)
    assert single("if $A_IN[1]==1 gotof n100").items == (Jump("GOTOF", "N100", "$A_IN[1]==1"),)
    assert single("GOTO END_1").items == (Jump("GOTO", "END_1"),)


def test_jump_destinations_by_direction() -> None:
    blocks = parse_program("START:\nN10 G1 X1\nGOTO START\nN20 G1 X2\nSTART:\nGOTOB N20\nGOTOF N10")
    assert jump_target(blocks, 2, Jump("GOTOB", "START")) == 0
    assert jump_target(blocks, 2, Jump("GOTOF", "START")) == 4
    assert jump_target(blocks, 2, Jump("GOTO", "START")) == 4  # forward first
    assert jump_target(blocks, 5, Jump("GOTO", "N10")) == 1  # then back
    assert jump_target(blocks, 5, Jump("GOTOB", "N20")) == 3
    assert jump_target(blocks, 6, Jump("GOTOF", "N10")) is None


def test_a_number_may_end_in_its_decimal_point() -> None:
    assert single("G0 Y100.").items == (Word("G", 0.0), Word("Y", 100.0))
    assert single("G1X10.Z-2. F500").items == (Word("G", 1.0), Word("X", 10.0), Word("Z", -2.0), Word("F", 500.0))
    assert single("X100.5 Y.5").items == (Word("X", 100.5), Word("Y", 0.5))
    assert single("LFON.").error  # a point after a name is no number


def test_chained_address_words_with_fractions() -> None:
    assert single("G1X10.5").items == (Word("G", 1.0), Word("X", 10.5))
    assert single("N10G1X10.5Z-2.25F.5").items == (Word("G", 1.0), Word("X", 10.5), Word("Z", -2.25),
                                                    Word("F", 0.5))
    assert single("G1X+.5Y100.").items == (Word("G", 1.0), Word("X", 0.5), Word("Y", 100.0))
    assert single("X1.5=2").error  # a name cannot hold a point
    assert single("X10ABC").items == (Keyword("X10ABC"),)  # goes on as a name: no address words
    assert single("FA[S2]=3600 COUPON(S2,S1,77)").items == (Assignment("FA", "S2", 3600.0),
                                                            Call("COUPON", ("S2", "S1", 77.0)))


def test_a_labelled_jump_block_carries_its_label_and_jumps_to_it() -> None:
    blocks = parse_program("N10 G1 X1\nMM: IF $AC_LIFTFAST GOTOB MM\nN20 GOTOB MM")
    assert blocks[1].items == (Label("MM"), Jump("GOTOB", "MM", "$AC_LIFTFAST"))
    assert jump_target(blocks, 2, Jump("GOTOB", "MM")) == 1
    assert jump_target(blocks, 1, Jump("GOTOB", "MM")) == 1  # its own label, before the jump
    assert jump_target(blocks, 1, Jump("GOTOF", "MM")) is None
    assert single("N5 LOOP_1: GOTOF END").items == (Label("LOOP_1"), Jump("GOTOF", "END"))
