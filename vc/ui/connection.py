"""The PLC connection as the operator page shows it: what ``vc serve --stats`` prints, as values.

Read in the NC thread between two IPO cycles (the bridge composes it into every snapshot), from
what the served simulation was built with: its connector is the link of ``vc serve``
(:class:`vc.harness.links.Link`: where it listens, its session, the PLC's side in
``peer_state``) and its pacer paces real time (:class:`vc.harness.pacer.RealtimePacer`: cycles
and overruns).  A simulation without a link (the PLC in this process) says so.
"""

from __future__ import annotations

from typing import Any

from vc.core.nck.nck import PLC_NOT_STARTED_ALARM, PLC_SIGN_OF_LIFE_ALARM
from vc.harness.pacer import RealtimePacer
from vc.simulation.lockstep import Simulation


def connection_state(simulation: Simulation) -> dict[str, Any]:
    """The link, its session, the PLC peer, the sign of life and the pacing, as plain values."""
    link: Any = simulation.connector
    realtime = _realtime_pacer(simulation)
    state: dict[str, Any] = {
        "link": "; ".join(_banner(link, simulation)) or "the PLC runs in this process",
        "mode": "real time" if realtime is not None else "lockstep",
        "session": getattr(link, "session", None),
        "peer": link.peer_state(simulation) if hasattr(link, "peer_state") else "",
        "sign_of_life": _sign_of_life(simulation, realtime is not None),
        "sign_of_life_lost": _lost(simulation),
        "cycles": None, "overruns": None, "link_overruns": None, "pacing": "",
    }
    if realtime is not None:
        stats = realtime.stats()
        state.update(cycles=stats.cycles, overruns=stats.overruns, link_overruns=stats.link_overruns,
                     pacing=str(stats))
    return state


def _banner(link: Any, simulation: Simulation) -> list[str]:
    if not hasattr(link, "banner"):
        return []
    return [line.split(" (")[0] for line in link.banner(simulation.machine)]  # the address, not the hints


def _realtime_pacer(simulation: Simulation) -> RealtimePacer | None:
    """The real-time pacer of ``vc serve --realtime``: the simulation's pacer itself or the one it
    reports for (``vc serve`` wraps it to print ``--stats``); None in lockstep."""
    pacer: Any = simulation.pacer
    for candidate in (pacer, getattr(pacer, "pacer", None)):
        if isinstance(candidate, RealtimePacer):
            return candidate
    return None


def _lost(simulation: Simulation) -> int | None:
    """The sign-of-life alarm present (2000 lost, 2001 never started), or None."""
    present = {alarm.number for alarm in simulation.alarms()}
    for number in (PLC_SIGN_OF_LIFE_ALARM, PLC_NOT_STARTED_ALARM):
        if number in present:
            return number
    return None


def _sign_of_life(simulation: Simulation, realtime: bool) -> str:
    lost = _lost(simulation)
    if lost == PLC_SIGN_OF_LIFE_ALARM:
        return "lost: alarm 2000 (no change for longer than MD10100; RESET clears it once the PLC scans again)"
    if lost == PLC_NOT_STARTED_ALARM:
        return "not started: alarm 2001 (no change within MD10120 of power-on)"
    if realtime:
        return "ok: the PLC's sign of life changes (watched against MD10100)"
    return "lockstep: the NC waits for every scan of the PLC"
