"""The self-contained FMU's worker: one FMU instance in a process of the Python bundled in the FMU.

The FMU's binary (``fmu/native``) starts this script as ``vc_nc_worker.py`` with the runtime in
``resources/runtime`` at ``fmi2Instantiate`` / ``fmi3InstantiateCoSimulation``::

    python -I -S -B vc_nc_worker.py FD RESOURCES INSTANCE_NAME TOKEN FMI_VERSION

and speaks to it over the socket ``FD``.  The worker loads the machine, answers with the kinds
of the variables, then serves one request after another until the binary frees the instance
or the socket closes (the host ended).  Each message is preceded by the length of its body as a
little-endian uint32::

    request  uint8 operation, then its arguments:
             SETUP f64 start | ENTER_INITIALIZATION | EXIT_INITIALIZATION
             | SET u8 kind, u32 n, n x u32 reference, n x f64 value | GET u8 kind, u32 n, n x u32 reference
             | STEP f64 time, f64 step, u32 n, n x u32 reference (read after the step)
             | TERMINATE | RESET | FREE (no answer)
    answer   i32 status, u32 n, n x (i32 status, u32 length, UTF-8 message), u32 m, m x f64 value,
             then for the first answer one byte per variable: its kind (0 Real, 1 Integer, 2 Boolean)

Values cross as doubles: every Boolean and 32-bit integer is exact in one.  The instance's
behaviour, errors included, is ``fmu/instance.py``'s.
"""

from __future__ import annotations

import os
import signal
import struct
import sys
from collections.abc import Callable
from enum import IntEnum
from pathlib import Path

from fmu.instance import FmuError, NcInstance, Status
from fmu.unit import Kind

KIND_CODES = {Kind.REAL: 0, Kind.INTEGER: 1, Kind.BOOLEAN: 2}
KINDS = {code: kind for kind, code in KIND_CODES.items()}
_LENGTH = struct.Struct("<I")
_STATUS_AND_COUNT = struct.Struct("<iI")
_F64 = struct.Struct("<d")
_KIND_AND_COUNT = struct.Struct("<BI")
_STEP = struct.Struct("<ddI")
_CONVERT: dict[Kind, Callable[[float], float | int | bool]] = {
    Kind.REAL: float, Kind.INTEGER: int, Kind.BOOLEAN: bool}


class Operation(IntEnum):
    SETUP = 1
    ENTER_INITIALIZATION = 2
    EXIT_INITIALIZATION = 3
    SET = 4
    GET = 5
    STEP = 6
    TERMINATE = 7
    RESET = 8
    FREE = 9


class Link:
    """The worker's end of the socket: requests in, answers (with the messages logged meanwhile) out."""

    def __init__(self, fd: int):
        self.fd = fd
        self._reader = open(fd, "rb", buffering=1 << 16, closefd=False)  # noqa: SIM115 - lives as long as the worker
        self.messages: list[tuple[Status, str]] = []

    def log(self, status: Status, message: str) -> None:
        self.messages.append((status, message))

    def receive(self) -> bytes | None:
        """The next request's body; None when the binary closed the socket."""
        header = self._reader.read(_LENGTH.size)
        if len(header) < _LENGTH.size:
            return None
        (length,) = _LENGTH.unpack(header)
        body = self._reader.read(length)
        return body if len(body) == length else None

    def answer(self, status: Status, values: list[float] | tuple[float, ...] = (), rest: bytes = b"") -> None:
        parts = [_STATUS_AND_COUNT.pack(int(status), len(self.messages))]
        for message_status, message in self.messages:
            text = message.encode("utf-8", "replace")
            parts.append(_STATUS_AND_COUNT.pack(int(message_status), len(text)))
            parts.append(text)
        self.messages.clear()
        parts.append(_LENGTH.pack(len(values)))
        parts.append(struct.pack(f"<{len(values)}d", *values))
        parts.append(rest)
        body = b"".join(parts)
        data = memoryview(_LENGTH.pack(len(body)) + body)
        while data:
            written = os.write(self.fd, data)
            data = data[written:]


class Worker:
    """Serves the requests of one instance."""

    def __init__(self, link: Link, instance: NcInstance):
        self.link = link
        self.instance = instance

    def serve(self) -> None:
        link = self.link
        while (body := link.receive()) is not None:
            operation = body[0]
            if operation == Operation.FREE:
                return
            try:
                self._handle(operation, memoryview(body)[1:])
            except FmuError as error:
                link.log(Status.FATAL, str(error))
                link.answer(Status.FATAL)
            except Exception as error:  # a bug must reach the host as a message, not as a hung host
                link.log(Status.FATAL, f"{self.instance.name}: internal error {error!r}")
                link.answer(Status.FATAL)

    def _handle(self, operation: int, arguments: memoryview) -> None:
        instance, link = self.instance, self.link
        if operation == Operation.STEP:
            time, step_size, count = _STEP.unpack_from(arguments)
            references = struct.unpack_from(f"<{count}I", arguments, _STEP.size)
            status = instance.step(time, step_size)
            get = instance.unit.get  # the binary asked for them before: their kinds were checked then
            link.answer(status, [get(reference) for reference in references])
        elif operation == Operation.SET:
            kind_code, count = _KIND_AND_COUNT.unpack_from(arguments)
            references = struct.unpack_from(f"<{count}I", arguments, _KIND_AND_COUNT.size)
            values = struct.unpack_from(f"<{count}d", arguments, _KIND_AND_COUNT.size + 4 * count)
            kind = KINDS[kind_code]
            convert = _CONVERT[kind]
            instance.take(kind, references, [convert(value) for value in values])
            link.answer(Status.ERROR if link.messages else Status.OK)
        elif operation == Operation.GET:
            kind_code, count = _KIND_AND_COUNT.unpack_from(arguments)
            references = struct.unpack_from(f"<{count}I", arguments, _KIND_AND_COUNT.size)
            link.answer(Status.OK, instance.values(KINDS[kind_code], references))
        elif operation == Operation.SETUP:
            (start_time,) = _F64.unpack_from(arguments)
            instance.setup(start_time)
            link.answer(Status.OK)
        elif operation == Operation.EXIT_INITIALIZATION:
            instance.exit_initialization()
            link.answer(Status.OK)
        elif operation == Operation.RESET:
            instance.reset()
            link.answer(Status.OK)
        elif operation in (Operation.ENTER_INITIALIZATION, Operation.TERMINATE):
            link.answer(Status.OK)
        else:
            raise FmuError(f"{instance.name}: unknown request {operation} from the FMU's binary")


def main(arguments: list[str]) -> int:
    fd_text, resources, name, token, fmi_version = arguments
    fd = int(fd_text)
    os.closerange(fd + 1, 1 << 16)  # the host's descriptors that were not close-on-exec
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the host decides when the instance ends
    link = Link(fd)
    try:
        instance = NcInstance(Path(resources), name, link.log)
        expected = instance.manifest.get("token")
        if token != expected:
            raise instance.fatal(f"the instantiation token {token!r} is not this FMU's ({expected!r}): the host read"
                                 " another FMU's modelDescription.xml")
        if int(fmi_version) not in instance.manifest.get("fmi", (2, 3)):
            raise instance.fatal(f"this FMU was exported for FMI {instance.manifest.get('fmi')}, not {fmi_version}")
    except FmuError as error:
        link.log(Status.FATAL, str(error))
        link.answer(Status.FATAL)
        return 1
    link.answer(Status.OK, rest=bytes(KIND_CODES[variable.kind] for variable in instance.unit.variables))
    Worker(link, instance).serve()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
