"""The machine-data dictionary: complete, consistent, and its key forms."""

from __future__ import annotations

import re

import pytest

from vc.config import md_dictionary as mdd
from vc.config.machine_data import MdDef, MdLevel, MdType, MdValueError, checked_value

# Every datum the referencing, spindle/gear, coupling and ESR specs need (spec A.2, B.2, 1.3, 2.3).
REQUIRED = (
    10000, 10050, 10070, 10192, 10720, 10721, 10735, 11300, 11410, 12000, 12010, 12020, 12030, 12040,
    12050, 12060, 12070, 12080, 12082, 12100,
    20050, 20060, 20070, 20080, 20090, 20092, 20094, 20110, 20112, 20700, 20850, 21200, 21300, 21310,
    21320, 21330, 21340, 21380, 21381,
    30240, 30242, 30250, 30270, 30300, 30310, 30330, 30340, 30455, 30550, 31000, 31020, 31030, 31040,
    31050, 31060, 31122, 31123, 32000, 32300, 32620, 32810, 32900, 32910,
    34000, 34010, 34020, 34030, 34040, 34050, 34060, 34070, 34080, 34090, 34092, 34093, 34100, 34102,
    34104, 34110, 34200, 34210, 34220, 34300, 34320, 34330,
    35000, 35010, 35012, 35014, 35020, 35030, 35035, 35040, 35090, 35092, 35100, 35110, 35112, 35120,
    35122, 35130, 35135, 35140, 35150, 35200, 35210, 35212, 35220, 35230, 35242, 35300, 35310, 35350,
    35400, 35410, 35430,
    35440, 35450, 35500, 35510, 35550, 35590, 36000, 36010, 36060, 36300, 36302,
    37200, 37202, 37210, 37212, 37220, 37230, 37500, 37510, 37511, 37550, 37560,
)

GEAR_STAGE_ARRAYS = (35012, 35110, 35112, 35120, 35122, 35130, 35135, 35140, 35200, 35210, 35212, 35300,
                     35310, 35550)


def test_numbers_and_names_are_unique() -> None:
    assert len(mdd.BY_NUMBER) == len(mdd.ALL_MACHINE_DATA)
    assert len(mdd.BY_NAME) == len(mdd.ALL_MACHINE_DATA)
    assert [md.number for md in mdd.ALL_MACHINE_DATA] == sorted(mdd.BY_NUMBER)


def test_every_required_datum_is_there() -> None:
    missing = [number for number in REQUIRED if number not in mdd.BY_NUMBER]
    assert missing == []


def test_module_constants_are_the_index() -> None:
    constants = {value for value in vars(mdd).values() if isinstance(value, MdDef)}
    assert constants == set(mdd.ALL_MACHINE_DATA)
    for name, value in vars(mdd).items():
        if isinstance(value, MdDef):
            assert name == value.name


@pytest.mark.parametrize("md", mdd.ALL_MACHINE_DATA, ids=lambda md: md.label)
def test_definition_is_consistent(md: MdDef) -> None:
    assert re.fullmatch(r"[A-Z][A-Z0-9_]*", md.name), "a name without the $Mx_ prefix"
    assert md.meaning
    assert re.search(r"seed 00[0-3] L", md.source) or "[control]" in md.source
    assert md.level.prefix == {"N": "$MN_", "C": "$MC_", "A": "$MA_"}[md.level.value]
    if md.minimum is not None and md.maximum is not None:
        assert md.minimum <= md.maximum
    if md.allowed:
        assert md.type is MdType.INT
    if md.is_array:
        assert isinstance(md.default, tuple) and len(md.default) == md.length
        items = list(md.default)
    else:
        assert not isinstance(md.default, tuple)
        items = [md.default]
    for index, item in enumerate(items):
        # the default passes the same check as a value written in a file
        assert checked_value(md, item, index if md.is_array else None) == item


def test_gear_stage_arrays_have_gear_stages_0_to_5() -> None:
    for number in GEAR_STAGE_ARRAYS:
        assert mdd.BY_NUMBER[number].length == 6, number
        assert mdd.BY_NUMBER[number].level is MdLevel.AXIS


def test_spec_ranges_and_defaults() -> None:
    assert mdd.REFP_SET_POS.length == 4
    assert (mdd.REFP_CYCLE_NR.minimum, mdd.REFP_CYCLE_NR.maximum) == (-1, 15)
    assert mdd.ENC_REFP_MODE.allowed == (0, 1, 2, 3, 4, 7, 8)
    assert (mdd.ENC_REFP_STATE.minimum, mdd.ENC_REFP_STATE.maximum) == (0, 3)
    assert (mdd.NUM_GEAR_STEPS.minimum, mdd.NUM_GEAR_STEPS.maximum) == (1, 5)
    assert mdd.COUPLE_AXIS_1.length == 2
    assert mdd.REFP_CAM_MARKER_DIST.read_only
    assert [md.number for md in mdd.ALL_MACHINE_DATA if md.read_only] == [34093]
    defaults = {34020: 5000.0, 34030: 10000.0, 34040: 300.0, 34060: 20.0, 34070: 10000.0, 34080: 2.0,
                35150: 0.1, 35400: 500.0, 35440: 1.0, 35450: 0.5, 10192: 10.0}
    for number, default in defaults.items():
        assert mdd.BY_NUMBER[number].default == default, number
    assert mdd.SPIND_POSCTRL_VELO.default == (500.0,) * 6
    assert mdd.SPIND_VELO_LIMIT.unit == "rev/min"
    assert mdd.REFP_NC_START_LOCK.default == 1


@pytest.mark.parametrize("key", ["MD32000", "MD32000 MAX_AX_VELO", "32000", "$MA_MAX_AX_VELO", "MAX_AX_VELO",
                                 "md32000  max_ax_velo", "MD32000 $MA_MAX_AX_VELO", " MAX_AX_VELO "])
def test_lookup_forms(key: str) -> None:
    assert mdd.lookup(key) is mdd.MAX_AX_VELO


@pytest.mark.parametrize("key", ["MD99999", "MD32000 JOG_VELO", "$MC_MAX_AX_VELO", "NOT_A_DATUM", "",
                                 "MD34100[1]", "max velocity"])
def test_lookup_refuses(key: str) -> None:
    assert mdd.lookup(key) is None


@pytest.mark.parametrize(("key", "number", "index"), [
    ("MD34100[2]", 34100, 2),
    ("MD34100 REFP_SET_POS[3]", 34100, 3),
    ("$MA_REFP_SET_POS[0]", 34100, 0),
    ("REFP_SET_POS [1]", 34100, 1),
    ("MD34100", 34100, None),
    ("MD20700", 20700, None),
])
def test_parse_md_key_returns_the_index_separately(key: str, number: int, index: int | None) -> None:
    parsed = mdd.parse_md_key(key)
    assert (parsed.md.number, parsed.index) == (number, index)


@pytest.mark.parametrize(("key", "message"), [
    ("MD99999", "unknown machine datum MD99999"),
    ("MAX_AXE_VELO", "unknown machine datum MAX_AXE_VELO"),
    ("MD32000 JOG_VELO", "MD32000 is MAX_AX_VELO, not JOG_VELO (JOG_VELO is MD32020)"),
    ("MD32000 FOO", "MD32000 is MAX_AX_VELO, not FOO"),
    ("$MC_MAX_AX_VELO", "MD32000 MAX_AX_VELO is axis data ($MA_), not $MC_"),
    ("MD34100[7]", "MD34100 REFP_SET_POS has 4 values; index 7 is out of range"),
    ("MD32000[1]", "MD32000 MAX_AX_VELO is not an array; write it without [1]"),
    ("MD34100[-1]", "MD34100 REFP_SET_POS[-1]: the index must be a whole number 0..3"),
    ("fast feed", "'fast feed' is not a machine datum (write " + mdd.KEY_FORMS + ")"),
])
def test_parse_md_key_errors(key: str, message: str) -> None:
    with pytest.raises(mdd.MdKeyError) as error:
        mdd.parse_md_key(key)
    assert str(error.value) == message


@pytest.mark.parametrize(("md", "raw", "value"), [
    (mdd.MAX_AX_VELO, 30000, 30000.0),
    (mdd.MAX_AX_VELO, "1e4", 10000.0),
    (mdd.REFP_CAM_IS_ACTIVE, 1, True),
    (mdd.REFP_CAM_IS_ACTIVE, False, False),
    (mdd.REFP_CYCLE_NR, -1, -1),
    (mdd.REFP_CYCLE_NR, 3.0, 3),
    (mdd.AXCONF_GEOAX_NAME_TAB, "X", "X"),
])
def test_checked_value_converts(md: MdDef, raw: object, value: object) -> None:
    converted = checked_value(md, raw)
    assert converted == value and type(converted) is type(value)


@pytest.mark.parametrize(("md", "raw", "message"), [
    (mdd.MAX_AX_VELO, -5, "MD32000 MAX_AX_VELO = -5: below the minimum 0.0 mm/min"),
    (mdd.MAX_AX_VELO, "fast", "MD32000 MAX_AX_VELO: expected a number, got 'fast'"),
    (mdd.MAX_AX_VELO, True, "MD32000 MAX_AX_VELO: expected a number, got true"),
    (mdd.MAX_AX_VELO, float("nan"), "MD32000 MAX_AX_VELO: expected a number, got nan"),
    (mdd.REFP_CAM_IS_ACTIVE, 2, "MD34000 REFP_CAM_IS_ACTIVE: expected true/false (or 1/0), got 2"),
    (mdd.REFP_CYCLE_NR, 16, "MD34110 REFP_CYCLE_NR = 16: above the maximum 15"),
    (mdd.REFP_CYCLE_NR, 1.5, "MD34110 REFP_CYCLE_NR: expected a whole number, got 1.5"),
    (mdd.ENC_REFP_MODE, 5, "MD34200 ENC_REFP_MODE = 5: not allowed; allowed are 0, 1, 2, 3, 4, 7, 8"),
    (mdd.AXCONF_GEOAX_NAME_TAB, 1, "MD20060 AXCONF_GEOAX_NAME_TAB: expected a name, got 1"),
])
def test_checked_value_messages(md: MdDef, raw: object, message: str) -> None:
    with pytest.raises(MdValueError) as error:
        checked_value(md, raw)
    assert str(error.value) == message
