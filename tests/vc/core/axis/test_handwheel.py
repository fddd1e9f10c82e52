"""The handwheels' pulses (vc/core/axis/handwheel.py): detents spread evenly over the turn."""

from __future__ import annotations

import pytest

from vc.core.axis.handwheel import Handwheels


def test_the_detents_arrive_evenly_and_the_wheel_turns_until_its_time_is_over() -> None:
    wheels = Handwheels()
    wheels.turn(1, 3, 6)
    wheels.turn(2, -2, 4)
    seen = [wheels.pulses() for _ in range(6)]
    assert [step.get(1) for step in seen] == [0, 1, 0, 1, 0, 1]
    assert [step.get(2) for step in seen] == [0, -1, 0, -1, None, None]
    assert not wheels.any_turning and wheels.pulses() == {}


def test_only_handwheels_1_to_3_exist() -> None:
    with pytest.raises(ValueError, match=r"handwheels 1\.\.3"):
        Handwheels().turn(4, 1, 1)
