"""A part clamped in two chucks: held, twisted beyond 1 degree once, free when a chuck opens."""

from __future__ import annotations

from dataclasses import dataclass

from vc.plant.chuck import Chuck
from vc.plant.workpiece import MAX_TWIST_DEG, ClampedPart


@dataclass
class _Spindle:
    physical: float


def _chuck(axis: str, clamped: bool) -> Chuck:
    return Chuck(axis, (0, 1), (0, 2), None, None, travel_cycles=10, stroke=10 if clamped else 0)


def _part(counter_clamped: bool) -> tuple[ClampedPart, _Spindle, _Spindle]:
    main, counter = _Spindle(370.0), _Spindle(12.0)
    return ClampedPart(_chuck("SP1", True), _chuck("SP2", counter_clamped), main, counter), main, counter


def test_the_relation_at_clamping_is_the_parts_and_a_small_twist_is_elastic() -> None:
    part, main, counter = _part(counter_clamped=False)
    main.physical += 500.0
    assert part.step() is False and part.twist == 0.0  # one chuck: no link
    part.counter.stroke = part.counter.travel_cycles
    assert part.step() is False and part.relation == 12.0 - 870.0
    main.physical += 90.0
    counter.physical += 90.0 + MAX_TWIST_DEG
    assert part.step() is False and abs(part.twist - MAX_TWIST_DEG) < 1e-9


def test_beyond_the_twist_the_part_blocks_the_counter_spindle_once_until_a_chuck_opens() -> None:
    part, main, _ = _part(counter_clamped=True)
    part.step()
    main.physical -= 1.01
    assert part.step() is True and part.twisted
    main.physical -= 5.0
    assert part.step() is False  # reported once
    part.main.stroke = 9  # the main chuck starts to open: the part is free
    assert part.step() is False and not part.twisted and part.twist == 0.0
