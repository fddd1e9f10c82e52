"""The root of every exception the project raises: ``except VcError`` catches them all.

Each package's exceptions derive from :class:`VcError`; one that also is a kind of a standard
exception keeps that base as well (``class SourceError(VcError, ValueError)``), so callers that
catch ``ValueError`` or ``KeyError`` catch it as before.  This module lies in the lowest layer
(interfaces) so that every package may import it.
"""

from __future__ import annotations


class VcError(Exception):
    """An error of the harness, the NC, the PLC stub, the FMU or a PLC bridge."""
