"""The loop both PLC transports share (interfaces/links/scan_loop.py): it follows the harness while no
session runs on the PLC's clock, scans on the clock when one does, and turns a PLC that cannot run
what the harness describes into exit code 2."""

from __future__ import annotations

from interfaces.links.description import PlcSetupError
from interfaces.links.scan_loop import EXIT_CANNOT_RUN, EXIT_STOPPED, exit_code, run_scans


class _Transport:
    """Lockstep for the first three rounds, then free-running with a period of 0 (no waiting)."""

    def __init__(self) -> None:
        self.calls: list[str] = []

    def free_running_period(self) -> float | None:
        return None if self.calls.count("follow") < 3 else 0.0

    def follow(self) -> None:
        self.calls.append("follow")

    def idle(self, seconds: float) -> None:
        self.calls.append("idle")

    def scan(self) -> None:
        self.calls.append("scan")


def test_the_loop_follows_the_harness_then_scans_on_the_clock() -> None:
    transport = _Transport()
    run_scans(transport, None, lambda: transport.calls.count("scan") == 2)
    assert transport.calls[:3] == ["follow"] * 3
    assert transport.calls.count("scan") == 2 and "follow" not in transport.calls[3:]


def test_a_plc_that_cannot_run_ends_with_code_2_and_says_why() -> None:
    said: list[str] = []

    def refuse() -> int:
        raise PlcSetupError("no PLC program 'lathe' (known: basic_machine)")

    assert exit_code(refuse, said.append) == EXIT_CANNOT_RUN
    assert said == ["cannot run: no PLC program 'lathe' (known: basic_machine)"]
    assert exit_code(lambda: EXIT_STOPPED, said.append) == EXIT_STOPPED and len(said) == 1
