"""Software cams (seed 003 chapter 21) in the NC core, the test acting as the PLC.

Turn-mill Z1 (machine axis 2) with an absolute encoder standing at 300 mm; cam pairs by MD10450."""

from __future__ import annotations

from core_rig import Rig, spindle_rig

from vc.core.axis.software_cams import CamState

BASE = ("CHAN1: {MD20700: 0}\nX1: {MD30240: [4], MD34210: [2]}\nZ1: {MD30240: [4], MD34210: [2]}\n"
        "Y1: {MD30240: [4], MD34210: [2]}")


def rig(nck: str) -> Rig:
    return spindle_rig("", base=f"{BASE}\nNC: {{{nck}}}")


def cam(rig: Rig, kind: str, number: int) -> int:
    return int(rig.get(f"NC.basic.in.swCams[0].{kind}{number}"))


def test_a_machine_without_cam_pairs_runs_nothing_for_them() -> None:
    plain = spindle_rig("", base=BASE)
    cams = plain.nck.software_cams
    assert (cams.of, cams.busy) == ({}, False)
    plain.set("Z1.basic.out.swCams", 1)
    plain.step(3)
    assert int(plain.get("Z1.basic.in.swCamsActive")) == 0  # no pair on Z1: nothing to switch on


def test_the_cams_switch_on_with_2_0_and_follow_the_actual_position() -> None:
    machine = rig("MD10450: [2, 0, 2], MD41500: [250, 0, 400], MD41501: [290, 0, 100]")
    cams = machine.nck.software_cams.of["Z1"]
    assert [pair.number for pair in cams.pairs] == [1, 3]
    assert cam(machine, "plus", 1) == 0 and cams.state is CamState.OFF
    machine.set("Z1.basic.out.swCams", 1)
    machine.step(2)
    assert int(machine.get("Z1.basic.in.swCamsActive")) == 1
    # Z1 at 300: >= 290 (plus 1), not <= 250 (minus 1); pair 3 with plus < minus: both signals (L40955)
    assert (cam(machine, "minus", 1), cam(machine, "plus", 1)) == (0, 1)
    assert (cam(machine, "minus", 3), cam(machine, "plus", 3)) == (1, 1)
    machine.mda("G1 Z240 F6000\n")
    machine.run_until(lambda: machine.axis("Z1").actual < 240.001, 2000, step=10)
    assert (cam(machine, "minus", 1), cam(machine, "plus", 1)) == (1, 0)
    machine.set("Z1.basic.out.swCams", 0)
    machine.step(2)
    assert int(machine.get("Z1.basic.in.swCamsActive")) == 0 and cam(machine, "minus", 1) == 0
    assert not machine.nck.software_cams.busy


def test_a_lead_time_switches_earlier_by_velocity_times_time() -> None:
    machine = rig("MD10450: [2], MD41500: [0], MD41501: [350], MD10461: [0.1]")
    machine.set("Z1.basic.out.swCams", 1)
    machine.mda("G1 Z400 F6000\n")  # 100 mm/s: 10 mm earlier
    machine.run_until(lambda: cam(machine, "plus", 1) == 1, 3000)
    assert 339.0 < machine.axis("Z1").actual < 341.0
