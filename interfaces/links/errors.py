"""The one error every link raises: a link that cannot be set up, or a peer that does not answer
as the protocol says.  Each adapter module translates its library's exceptions into it."""

from __future__ import annotations

from interfaces.errors import VcError


class LinkError(VcError):
    """A link could not be set up or a peer did not answer as the protocol says."""


class RequestRefused(LinkError):
    """The peer answered a request with a refusal (a Modbus exception response): the link itself stands."""


class BadAddress(LinkError, ValueError):
    """An address that has not the form the link's technology asks for (``HOST:PORT``, a bus)."""
