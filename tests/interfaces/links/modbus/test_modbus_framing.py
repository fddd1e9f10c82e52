"""Modbus TCP framing (interfaces/links/modbus/framing.py): the requests in the bytes a connection
received, whatever segments they came in, and the header no request has.  (The server that answers
them, with real clients: test_modbus_server.py.)"""

from __future__ import annotations

import itertools
import struct

from hypothesis import given, settings
from hypothesis import strategies as st

from interfaces.links.modbus.framing import Request, take_requests


def _frame(function: int, payload: bytes, transaction: int = 7, length: int | None = None) -> bytes:
    pdu = bytes([function]) + payload
    return struct.pack(">HHHB", transaction, 0, length if length is not None else len(pdu) + 1, 1) + pdu


def _read(transaction: int) -> bytes:
    return _frame(0x04, struct.pack(">HH", 0, 1), transaction=transaction)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 65535), st.integers(0, 255), st.binary(min_size=1, max_size=253)),
                min_size=1, max_size=12), st.lists(st.integers(1, 600), max_size=8))
def test_the_requests_of_a_stream_whatever_its_segments(requests: list[tuple[int, int, bytes]],
                                                        cuts: list[int]) -> None:
    stream = b"".join(struct.pack(">HHHB", transaction, 0, len(pdu) + 1, unit) + pdu
                      for transaction, unit, pdu in requests)
    received, found = bytearray(), []
    for start, stop in itertools.pairwise([0, *sorted(cut % (len(stream) + 1) for cut in cuts), len(stream)]):
        received += stream[start:stop]
        taken, problem = take_requests(received)
        assert problem is None
        found += taken
    assert found == [Request(transaction, unit, pdu) for transaction, unit, pdu in requests]
    assert received == b""


def test_a_header_no_request_has_is_named_after_the_requests_before_it() -> None:
    received = bytearray(_read(1) + _frame(0x04, b"\x00\x00\x00\x01", length=300) + _read(2))
    taken, problem = take_requests(received)
    assert [request.transaction for request in taken] == [1]
    assert problem == "a header with protocol identifier 0 and length 300"


def test_no_more_than_the_limit_is_taken_and_the_rest_waits_as_bytes() -> None:
    received = bytearray(b"".join(_read(transaction) for transaction in range(1, 6)))
    taken, problem = take_requests(received, 2)
    assert [request.transaction for request in taken] == [1, 2] and problem is None
    assert received == b"".join(_read(transaction) for transaction in range(3, 6))
