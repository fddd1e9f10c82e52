"""The links between the NC and a PLC in another process: one package per technology, and the one
registry of link kinds every place that chooses a link reads (as python-can's ``can.interfaces``
registry names each backend by its module and class).

=============================  =====================================================================
``modbus/``                    Modbus TCP (pymodbus) with S7 (python-snap7) as a second server of the
                               same link: codec, framing, tables, server, client, s7, access, plc_end
``can/``                       CAN (python-can): codec, bus, dbc, plc_end
``description.py``             the interface description the harness hands every PLC at a power-on
``errors.py``                  the one error every link raises
``endpoint.py``                ``HOST:PORT`` of a server
``scan_loop.py``               the loop of a PLC in its own process, whatever carries the interface
``scheduling.py``              where a link's process runs (CPU pinning, SCHED_FIFO)
``inprocess.py``               the in-process link and the registry of PLC programs
=============================  =====================================================================

A technology's package never imports another's; only this registry knows them all, by name, and
loads what a row names when that link is chosen (:func:`load`), so that choosing one never imports
the libraries of the others.  Each row names:

* ``plc_end``: the function that runs soft PLC programs as a PLC process on the link, ``python -m
  plc_stub --NAME ADDRESS`` (:data:`~interfaces.links.scan_loop.PlcEndRunner`);
* ``harness``: the harness's end for ``vc serve`` (a function of the serve options that gives a
  ``vc.harness.links.Link``; the harness's ends live in ``vc/harness/links/`` because they drive the
  simulation, which ``interfaces`` never imports);
* ``plc_process``: ``vc run --link NAME``: the run's PLC process and its link, of the run's address
  (``--can-bus``; None: the technology's default);
* ``in_process``: a scenario's ``link: NAME``: its PLC program behind the link inside the harness's
  process (None: the technology offers none).

A new link is its folder here, its harness end in ``vc/harness/links/<technology>.py`` and its row in
:data:`LINKS` (docs/architecture.md, "Where to add").
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from interfaces.errors import VcError

INPROCESS = "inprocess"  # ``vc run --link inprocess``: the PLC programs in the harness's process


@dataclass(frozen=True, slots=True)
class LinkKind:
    """One row of the registry: a technology and where each end of it lives ("module:name")."""

    name: str  # vc run --link NAME, a scenario's link: NAME, python -m plc_stub --NAME ADDRESS
    title: str  # in words, for the command line's help
    package: str  # interfaces.links.<technology>
    address: str  # what python -m plc_stub --NAME is given, as its help shows it
    address_help: str  # what that address names, for the help
    plc_end: str  # python -m plc_stub --NAME: soft PLC programs as the PLC's end (a PlcEndRunner)
    harness: str  # vc serve: the harness's end, of the serve options
    plc_process: str  # vc run --link NAME: the run's PLC process and its link, of the run's address
    in_process: str | None = None  # a scenario's link: NAME, its PLC behind the link in this process


LINKS: Mapping[str, LinkKind] = {
    kind.name: kind for kind in (
        LinkKind("modbus", "a Modbus TCP link", "interfaces.links.modbus", "HOST:PORT",
                 "the harness's Modbus TCP server (vc serve, vc run --link modbus)",
                 plc_end="interfaces.links.modbus.plc_end:run_plc",
                 harness="vc.harness.links.modbus:serving",
                 plc_process="vc.harness.external_plc:PlcProcess.for_run"),
        LinkKind("can", "a CAN link", "interfaces.links.can", "BUS",
                 "the CAN bus the harness is on (vc run --link can): udp_multicast[:GROUP:PORT] or"
                 " socketcan[:INTERFACE]",
                 plc_end="interfaces.links.can.plc_end:run_plc",
                 harness="vc.harness.links.can:serving",
                 plc_process="vc.harness.external_plc:CanPlcProcess.for_run",
                 in_process="vc.harness.links.can:virtual_can_simulation"),
    )
}


class UnknownLink(VcError, LookupError):
    pass


def link_kind(name: str) -> LinkKind:
    try:
        return LINKS[name]
    except KeyError:
        raise UnknownLink(f"no link '{name}' (known: {', '.join(LINKS)})") from None


def load(reference: str) -> Any:
    """What a row names, ``module:name`` or ``module:Class.name``, imported now."""
    module, _, path = reference.partition(":")
    found: Any = importlib.import_module(module)
    for part in path.split("."):
        found = getattr(found, part)
    return found


def in_process_links() -> tuple[str, ...]:
    """The links a scenario may put its PLC behind (``link: NAME``)."""
    return tuple(name for name, kind in LINKS.items() if kind.in_process is not None)
