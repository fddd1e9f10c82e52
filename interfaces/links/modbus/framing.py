"""Modbus TCP framing: the requests in the bytes a connection received (MBAP header, then the PDU).

Every complete request in what arrives is taken, once and in its order: ten requests in one TCP
segment, a request split over segments (pymodbus's own framer keeps only the first request of a
segment and drops a split one when it answers in between).  A header no request has (protocol
identifier other than 0, a length outside 2..254) is reported: a byte stream cannot be
resynchronised, so the server ends the connection after answering the requests before it.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

MBAP = struct.Struct(">HHHB")  # transaction, protocol (0), length (unit id and PDU), unit id
MAX_PDU_BYTES = 253  # the protocol's limit: an ADU of 260 bytes


@dataclass(frozen=True, slots=True)
class Request:
    """One request as it came: MBAP transaction and unit id, and the PDU (function code first)."""

    transaction: int
    unit: int
    pdu: bytes


def take_requests(received: bytearray, limit: int | None = None) -> tuple[list[Request], str | None]:
    """The complete requests at the start of ``received`` (at most ``limit``), removed from it (what
    stays is the beginning of the next one, or the requests beyond the limit), and what is wrong
    with the header that follows them, if anything."""
    requests: list[Request] = []
    offset = 0
    problem = None
    while len(received) - offset >= MBAP.size and (limit is None or len(requests) < limit):
        transaction, protocol, length, unit = MBAP.unpack_from(received, offset)
        if protocol != 0 or not 2 <= length <= MAX_PDU_BYTES + 1:
            problem = f"a header with protocol identifier {protocol} and length {length}"
            break
        end = offset + 6 + length
        if end > len(received):
            break
        requests.append(Request(transaction, unit, bytes(received[offset + MBAP.size: end])))
        offset = end
    del received[:offset]
    return requests, problem

