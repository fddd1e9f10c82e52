"""``HOST:PORT`` of the server a PLC process connects to (``python -m plc_stub``, ``python -m plc_awlsim``)."""

from __future__ import annotations

from interfaces.links.errors import BadAddress


def parse_endpoint(text: str) -> tuple[str, int]:
    """``127.0.0.1:5020`` -> (host, port); an empty host is loopback.  :class:`BadAddress` (a ValueError)
    says what is wrong."""
    host, _, port = text.rpartition(":")
    try:
        number = int(port)
    except ValueError:
        raise BadAddress(f"'{text}' is not HOST:PORT (e.g. 127.0.0.1:5020)") from None
    if not 0 < number < 65536:
        raise BadAddress(f"'{text}': port {number} is outside 1..65535")
    return host or "127.0.0.1", number
