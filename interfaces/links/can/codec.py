"""The interface as CAN frames: identifiers, frame layout and byte codecs (pure, no I/O).

Convention, stated once (``vc map --format dbc`` writes it as a DBC file, the tests check it both ways):

* **Frames.** CAN FD frames of up to 64 data bytes with 11-bit identifiers (``fd: false`` in the
  machine file's ``can:`` section: classic frames of 8 bytes).
* **Data frames.** Every byte range a link moves (:mod:`interfaces.exchange`: the plant area, then
  the data-block ranges of DB10, DB11, DB19, DB21.., DB31.., DB100, per direction) is cut into frames of up to P
  bytes, P = 63 (7 classic) with the checksum byte, 64 (8) without; a cut that would split a word
  or double word moves back to its first byte.  A frame carries its bytes from its byte 0 on; a
  range never shares a frame with another one.  A frame is
  as long as the smallest CAN FD length (0..8, 12, 16, 20, 24, 32, 48, 64) that holds its bytes and
  the checksum; the padding between them is 0.
* **Identifiers.** NC-to-PLC data frames count up from 0x200 in link order, PLC-to-NC data frames
  from 0x400; the three link frames are 0x100 (NC link), 0x101 (PLC link) and 0x102 (description).
  The machine file moves the three bases (``can: {ids: {link: .., nc_to_plc: .., plc_to_nc: ..}}``).
  For turn_mill (CHAN1; X1, Z1, Y1, SP1, SP2, SP3) with the checksum on::

      id     bytes                 length   id     bytes               length
      0x200  IB0..9                12       0x400  QB0..1              3
      0x201  DB10.DBB106..109      5        0x401  DB10.DBB1..56       64
      0x202  DB11.DBB6..7          3        0x402  DB11.DBB0..1        3
      0x203  DB19.DBB20            2        0x403  DB19.DBB0           2
      0x204  DB21.DBB32..93        64       0x404  DB21.DBB0..31       48
      ..     up to 63 bytes a frame         0x405  DB21.DBB321         2
      0x208  DB21.DBB280..318      48       0x406  DB21.DBB396         2
      0x209  DB21.DBB333..377      48       0x407  DB21.DBB398         2
      0x20A  DB21.DBB397           2        0x408  DB31.DBB0..43       48
      0x20B  DB31.DBB60..105       48       ..     one frame per axis
      ..     one frame per axis             0x40D  DB36.DBB0..43       48
      0x210  DB36.DBB60..105       48       0x40E  DB2.DBB180..187     12
      0x211  DB100.DBB0..59        64
      0x212  DB100.DBB60..67       12

  19 frames from the NC and 15 from the PLC per exchange (classic frames: 109 and 63).

* **Values.** Data-block words and double words are big-endian as in S7 (a DBC marks them
  Motorola, start bit = the most significant bit, frame byte x 8 + 7); a bit ``n.b`` or a byte
  sits at frame byte x 8 + b (Intel).
* **Checksum.** The last byte of a frame: CRC-8 SAE J1850 (polynomial 0x1D, initial value and final
  XOR 0xFF, the CRC of AUTOSAR E2E profile 1) over the identifier's two bytes (big-endian) and every
  other byte of the frame.  Data frames carry it unless ``checksum: false``; link and description
  frames always do.  A receiver drops a frame whose checksum or length is wrong: a protocol error is
  a value (``decode`` answers False or None), the time-out monitor sees the frame missing.
* **Link frames**, 8 bytes::

      NC link (0x100), NC -> PLC, after the NC's data frames and with every scan grant
        0     link version 1 (high nibble) | mode (low nibble): 1 lockstep, 2 free-running
        1     NC sign of life: counts every transmission, 0..255
        2..3  session: counts the harness's power-ons; a new one restarts the PLC program
        4..5  scan grant (lockstep: the scan the PLC may run, 1..65535; free-running 0)
        6     0
        7     checksum
      PLC link (0x101), PLC -> NC, after the PLC's data frames at the end of every scan
        0     link version 1 | flags: bit 0 = the PLC needs the description (no session running),
              bit 1 = the PLC's time-out monitor misses frames of the NC (it runs on substitute values 0)
        1     PLC sign of life: counts every scan, 0..255 (the NC watches it: alarm 2000)
        2..3  session ready: the session the PLC runs its program for
        4..5  scan done: the granted scan the PLC finished (lockstep)
        6     0
        7     checksum

* **Description** (0x102), NC -> PLC when the PLC asks for it: the interface description
  (:mod:`interfaces.links.description`) as a stream ``length (4 bytes) + CRC-32 (4) + UTF-8 JSON``,
  cut into frames of the full frame size: bytes 0..1 the segment number, then the stream's
  bytes, the last byte the checksum.

Lockstep, as a PLC implements it: when the NC link frame shows a new session, send the PLC link
frame with flag bit 0 until the description is complete, start the program, then send it with
the session in bytes 2..3.  When the NC link frame grants a scan other than the last one handled:
run one scan with the data frames received since, send the PLC-to-NC data frames, then the PLC
link frame with the grant in bytes 4..5 and the sign of life counted up.
"""

from __future__ import annotations

import struct
import zlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from enum import IntEnum
from typing import NamedTuple

from interfaces.errors import VcError
from interfaces.exchange import exchange_ranges, link_direction
from interfaces.signals import Direction, ExpandedCatalog, SignalRef, SignalType

LINK_VERSION = 6  # raised with every change of the layout (tests/interfaces/test_link_versions.py)
DEFAULT_LINK_ID = 0x100
DEFAULT_NC_TO_PLC_ID = 0x200
DEFAULT_PLC_TO_NC_ID = 0x400
MAX_STANDARD_ID = 0x7FF
DEFAULT_TIMEOUT_US = 50_000  # a frame missing for longer: the receiver's time-out monitor reacts
FD_FRAME_BYTES = 64
CLASSIC_FRAME_BYTES = 8
LINK_FRAME_BYTES = 8
FD_LENGTHS = (0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 20, 24, 32, 48, 64)
class ControllerState(IntEnum):
    """A CAN controller's fault confinement state (ISO 11898-1), as a number for observers."""

    ERROR_ACTIVE = 0  # error counters below 128: takes part normally
    ERROR_PASSIVE = 1  # a counter at 128 or above: still sends, signals errors passively
    BUS_OFF = 2  # transmit error counter beyond 255: neither sends nor receives until restarted


NEEDS_DESCRIPTION = 0x01  # PLC link frame, byte 0, low nibble
MISSES_NC_FRAMES = 0x02  # PLC link frame, byte 0, low nibble
DESCRIPTION_HEADER_BYTES = 8  # stream: length (4), CRC-32 (4)
_SEGMENT_NUMBER = struct.Struct(">H")
_LINK = struct.Struct(">BBHHB")  # version|low nibble, life, session, grant/done, reserved


class CanMapError(VcError, ValueError):
    """The interface does not fit the identifiers (overlapping or beyond 0x7FF): every clash in
    ``problems``, joined in the message."""

    def __init__(self, problems: Sequence[str]):
        super().__init__("; ".join(problems))
        self.problems = tuple(problems)


class Frame(NamedTuple):
    """A CAN frame as the codec sees it: identifier, data bytes, FD format or classic."""

    can_id: int
    data: bytes
    fd: bool = True


def _crc8_table() -> tuple[int, ...]:
    table = []
    for value in range(256):
        crc = value
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1D) & 0xFF if crc & 0x80 else (crc << 1) & 0xFF
        table.append(crc)
    return tuple(table)


_CRC8 = _crc8_table()


def checksum(can_id: int, data: bytes | bytearray, length: int) -> int:
    """CRC-8 SAE J1850 over the identifier (two bytes, big-endian) and ``data[:length]``."""
    table = _CRC8
    crc = table[0xFF ^ (can_id >> 8 & 0xFF)]
    crc = table[crc ^ (can_id & 0xFF)]
    for byte in data[:length]:
        crc = table[crc ^ byte]
    return crc ^ 0xFF


def frame_length(used: int, fd: bool) -> int:
    """The bytes a frame needs on the bus for ``used`` bytes: the next CAN FD length (classic: as is)."""
    if not fd:
        return used
    for length in FD_LENGTHS:
        if length >= used:
            return length
    raise ValueError(f"{used} bytes do not fit one CAN FD frame")


@dataclass(frozen=True, slots=True)
class CanSettings:
    """What both ends must agree on; the machine file's ``can:`` section sets it, the description
    carries it to the PLC."""

    link_id: int = DEFAULT_LINK_ID
    nc_to_plc_id: int = DEFAULT_NC_TO_PLC_ID
    plc_to_nc_id: int = DEFAULT_PLC_TO_NC_ID
    fd: bool = True
    checksum: bool = True

    @property
    def frame_bytes(self) -> int:
        return FD_FRAME_BYTES if self.fd else CLASSIC_FRAME_BYTES

    @property
    def data_bytes(self) -> int:
        """Area bytes a data frame carries."""
        return self.frame_bytes - (1 if self.checksum else 0)

    @property
    def nc_link_id(self) -> int:
        return self.link_id

    @property
    def plc_link_id(self) -> int:
        return self.link_id + 1

    @property
    def description_id(self) -> int:
        return self.link_id + 2

    def as_dict(self) -> dict[str, int | bool]:
        return {"link_id": self.link_id, "nc_to_plc_id": self.nc_to_plc_id, "plc_to_nc_id": self.plc_to_nc_id,
                "fd": self.fd, "checksum": self.checksum}

    @classmethod
    def from_dict(cls, document: Mapping[str, object]) -> CanSettings:
        """The settings of a description; raises ValueError, KeyError or TypeError when malformed."""
        numbers = {key: document[key] for key in ("link_id", "nc_to_plc_id", "plc_to_nc_id")}
        flags = {key: document[key] for key in ("fd", "checksum")}
        if not all(isinstance(value, int) and not isinstance(value, bool) for value in numbers.values()) or \
                not all(isinstance(value, bool) for value in flags.values()):
            raise TypeError(f"CAN settings of the wrong types: {dict(document)}")
        return cls(**numbers, **flags)  # type: ignore[arg-type]


@dataclass(frozen=True, slots=True)
class FrameSlot:
    """One data frame: area bytes ``start`` .. ``stop - 1`` under identifier ``can_id``."""

    can_id: int
    direction: Direction  # NC_TO_PLC or PLC_TO_NC
    area: str  # "DB31", "I", "Q"
    start: int
    stop: int
    length: int  # bytes on the bus: data, padding, checksum
    checksum: bool
    fd: bool

    @property
    def name(self) -> str:
        """The frame's name in a DBC file: sender, area, first and last byte (``NC_DB31_60_105``)."""
        sender = "NC" if self.direction is Direction.NC_TO_PLC else "PLC"
        return f"{sender}_{self.area}_{self.start}_{self.stop - 1}"

    def encode(self, areas: Mapping[str, bytearray]) -> Frame:
        payload = bytearray(self.length)
        payload[: self.stop - self.start] = areas[self.area][self.start: self.stop]
        if self.checksum:
            payload[-1] = checksum(self.can_id, payload, self.length - 1)
        return Frame(self.can_id, bytes(payload), self.fd)

    def decode(self, data: bytes, areas: Mapping[str, bytearray]) -> bool:
        """Copy the frame's bytes into the areas; False (nothing copied) for a wrong length or checksum."""
        if len(data) != self.length:
            return False
        if self.checksum and data[-1] != checksum(self.can_id, data, self.length - 1):
            return False
        areas[self.area][self.start: self.stop] = data[: self.stop - self.start]
        return True


@dataclass(frozen=True, slots=True)
class CanLocation:
    """Where a signal lies in the CAN frames, as a DBC file places it."""

    slot: FrameSlot
    start_bit: int  # DBC start bit: Intel = lowest bit, Motorola = most significant bit
    length: int  # bits
    big_endian: bool  # Motorola (S7 words, double words, reals)

    @property
    def can_id(self) -> int:
        return self.slot.can_id


class CanLayout:
    """The data frames of one machine per direction, and the link frames' identifiers."""

    def __init__(self, settings: CanSettings, slots: Mapping[Direction, Sequence[FrameSlot]]):
        self.settings = settings
        self.slots = {direction: tuple(slots[direction]) for direction in (Direction.NC_TO_PLC,
                                                                            Direction.PLC_TO_NC)}
        self.by_id = {slot.can_id: slot for items in self.slots.values() for slot in items}

    @classmethod
    def build(cls, catalog: ExpandedCatalog, plant_sizes: Mapping[str, int], settings: CanSettings) -> CanLayout:
        """The layout of the module docstring; raises :class:`CanMapError` when identifiers clash."""
        per_frame = settings.data_bytes
        inside = _inside_values(catalog)
        slots: dict[Direction, list[FrameSlot]] = {}
        for direction, first_id in ((Direction.NC_TO_PLC, settings.nc_to_plc_id),
                                    (Direction.PLC_TO_NC, settings.plc_to_nc_id)):
            placed: list[FrameSlot] = []
            for area, start, stop in exchange_ranges(catalog, plant_sizes, direction):
                first = start
                while first < stop:
                    last = min(stop, first + per_frame)
                    while (area, last) in inside:  # a word or double word stays in one frame
                        last -= 1
                    used = last - first + (1 if settings.checksum else 0)
                    placed.append(FrameSlot(first_id + len(placed), direction, area, first, last,
                                            frame_length(used, settings.fd), settings.checksum, settings.fd))
                    first = last
            slots[direction] = placed
        _check_identifiers(settings, slots)
        return cls(settings, slots)

    def frames(self, direction: Direction, areas: Mapping[str, bytearray]) -> list[Frame]:
        return [slot.encode(areas) for slot in self.slots[direction]]

    def ids(self, direction: Direction) -> list[int]:
        return [slot.can_id for slot in self.slots[direction]]

    def slot_of(self, direction: Direction, area: str, byte: int) -> FrameSlot | None:
        for slot in self.slots[direction]:
            if slot.area == area and slot.start <= byte < slot.stop:
                return slot
        return None

    def location(self, ref: SignalRef) -> CanLocation | None:
        """Where ``ref`` lies, or None when its bytes are in no frame."""
        address = ref.address
        slot = self.slot_of(link_direction(ref.direction), ref.area_key, address.byte)
        if slot is None:
            return None
        frame_byte = address.byte - slot.start
        if ref.type in (SignalType.BOOL, SignalType.BITS):
            return CanLocation(slot, 8 * frame_byte + address.bit, ref.bits, False)
        if address.size == 1:
            return CanLocation(slot, 8 * frame_byte, 8, False)
        return CanLocation(slot, 8 * frame_byte + 7, 8 * address.size, True)


def _inside_values(catalog: ExpandedCatalog) -> set[tuple[str, int]]:
    """``(area, byte)`` where a frame must not begin: the second and later bytes of words and double words."""
    return {(item.address.area_key, item.address.byte + offset) for item in catalog.signals
            for offset in range(1, item.address.size)}


_SHOWN = {Direction.NC_TO_PLC: "NC-to-PLC", Direction.PLC_TO_NC: "PLC-to-NC"}


def _check_identifiers(settings: CanSettings, slots: Mapping[Direction, Sequence[FrameSlot]]) -> None:
    blocks = [("the link frames", settings.link_id, 3)]
    blocks += [(f"the {_SHOWN[direction]} data frames", items[0].can_id, len(items))
               for direction, items in slots.items() if items]
    problems = [f"{name} need identifiers 0x{first:03X}..0x{first + count - 1:03X}; standard identifiers end at"
                f" 0x{MAX_STANDARD_ID:03X}" for name, first, count in blocks
                if first < 0 or first + count - 1 > MAX_STANDARD_ID]
    for index, (name, first, count) in enumerate(blocks):
        for other, other_first, other_count in blocks[index + 1:]:
            if first < other_first + other_count and other_first < first + count:
                problems.append(f"{name} (0x{first:03X}..0x{first + count - 1:03X}) overlap {other}"
                                f" (0x{other_first:03X}..0x{other_first + other_count - 1:03X})")
    if problems:
        raise CanMapError(problems)


# ---------------------------------------------------------------------------------- link frames


def _pack_link(can_id: int, version: int, nibble: int, life: int, session: int, number: int, fd: bool) -> Frame:
    payload = bytearray(_LINK.pack(version << 4 | nibble & 0x0F, life & 0xFF, session & 0xFFFF, number & 0xFFFF, 0))
    payload.append(checksum(can_id, payload, len(payload)))
    return Frame(can_id, bytes(payload), fd)


class _LinkFields(NamedTuple):
    version: int
    nibble: int  # NC: the mode; PLC: the flags
    life: int
    session: int
    number: int  # NC: the grant; PLC: the scan done


def _unpack_link(can_id: int, data: bytes) -> _LinkFields | None:
    if len(data) != LINK_FRAME_BYTES or data[-1] != checksum(can_id, data, LINK_FRAME_BYTES - 1):
        return None
    head, life, session, number, _ = _LINK.unpack_from(data)
    return _LinkFields(head >> 4, head & 0x0F, life, session, number)


@dataclass(frozen=True, slots=True)
class NcLink:
    """The NC link frame: mode, the NC's sign of life, session and scan grant."""

    mode: int
    life: int
    session: int
    grant: int
    version: int = LINK_VERSION

    def encode(self, settings: CanSettings) -> Frame:
        return _pack_link(settings.nc_link_id, self.version, self.mode, self.life, self.session, self.grant,
                          settings.fd)

    @classmethod
    def decode(cls, can_id: int, data: bytes) -> NcLink | None:
        fields = _unpack_link(can_id, data)
        return None if fields is None else cls(fields.nibble, fields.life, fields.session, fields.number,
                                               fields.version)


@dataclass(frozen=True, slots=True)
class PlcLink:
    """The PLC link frame: the PLC's sign of life, session ready, scan done, description wanted,
    the NC's frames missing."""

    life: int
    session_ready: int
    scan_done: int
    needs_description: bool = False
    misses_nc_frames: bool = False
    version: int = LINK_VERSION

    def encode(self, settings: CanSettings, fd: bool) -> Frame:
        flags = (NEEDS_DESCRIPTION if self.needs_description else 0) | \
            (MISSES_NC_FRAMES if self.misses_nc_frames else 0)
        return _pack_link(settings.plc_link_id, self.version, flags, self.life, self.session_ready, self.scan_done,
                          fd)

    @classmethod
    def decode(cls, can_id: int, data: bytes) -> PlcLink | None:
        fields = _unpack_link(can_id, data)
        return None if fields is None else cls(fields.life, fields.session, fields.number,
                                               bool(fields.nibble & NEEDS_DESCRIPTION),
                                               bool(fields.nibble & MISSES_NC_FRAMES), fields.version)


# ---------------------------------------------------------------------------------- description


def description_frames(settings: CanSettings, text: bytes) -> list[Frame]:
    """The description as segments (module docstring); the last one as short as CAN FD allows."""
    stream = struct.pack(">II", len(text), zlib.crc32(text)) + text
    chunk = settings.frame_bytes - 3  # segment number (2), checksum (1)
    frames = []
    for number, first in enumerate(range(0, len(stream), chunk)):
        part = stream[first: first + chunk]
        length = frame_length(len(part) + 3, settings.fd)
        payload = bytearray(length)
        _SEGMENT_NUMBER.pack_into(payload, 0, number)
        payload[2: 2 + len(part)] = part
        payload[-1] = checksum(settings.description_id, payload, length - 1)
        frames.append(Frame(settings.description_id, bytes(payload), settings.fd))
    return frames


class DescriptionAssembler:
    """Collects description segments; ``add`` returns the text once every segment is there and the
    CRC-32 matches (a wrong CRC starts over: the PLC asks again)."""

    def __init__(self, can_id: int):
        self.can_id = can_id
        self._segments: dict[int, bytes] = {}
        self._chunk = 0

    def reset(self) -> None:
        self._segments.clear()
        self._chunk = 0

    def add(self, data: bytes) -> bytes | None:
        if len(data) < 4 or data[-1] != checksum(self.can_id, data, len(data) - 1):
            return None
        (number,) = _SEGMENT_NUMBER.unpack_from(data)
        self._segments[number] = data[2:-1]
        if number == 0:
            self._chunk = len(data) - 3  # every segment but the last is as long as the first
        chunk = self._chunk
        if not chunk:
            return None
        head = self._joined(-(-DESCRIPTION_HEADER_BYTES // chunk))
        if head is None or len(head) < DESCRIPTION_HEADER_BYTES:
            return None
        length, crc = struct.unpack_from(">II", head)
        total = DESCRIPTION_HEADER_BYTES + length
        stream = self._joined(-(-total // chunk))
        if stream is None:
            return None
        self.reset()
        text = stream[DESCRIPTION_HEADER_BYTES: total]
        return text if len(text) == length and zlib.crc32(text) == crc else None

    def _joined(self, count: int) -> bytes | None:
        """Segments 0 .. count - 1 one after the other, or None while one is missing."""
        if any(index not in self._segments for index in range(count)):
            return None
        return b"".join(self._segments[index] for index in range(count))
