"""What an ELF shared object or executable needs from the system: its libraries and glibc versions.

``objdump -T | grep GLIBC_`` and ``readelf -d`` without binutils: the export chooses with this
which extension modules of the standard library travel in the FMU (only those that need nothing
but glibc) and states the glibc floor of everything it bundles.  Only 64-bit little-endian ELF
(Linux x86-64, aarch64) is read.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from pathlib import Path

from interfaces.errors import VcError

_ELF_MAGIC = b"\x7fELF"
_SHT_DYNAMIC = 6
_SHT_GNU_VERNEED = 0x6FFFFFFE
_DT_NEEDED = 1
_HEADER = struct.Struct("<16sHHIQQQIHHHHHH")
_SECTION = struct.Struct("<IIQQQQIIQQ")
_DYNAMIC = struct.Struct("<qQ")
_VERNEED = struct.Struct("<HHIII")
_VERNAUX = struct.Struct("<IHHII")
GLIBC_LIBRARIES = frozenset({"libc.so.6", "libm.so.6", "libpthread.so.0", "libdl.so.2", "librt.so.1",
                             "libutil.so.1", "ld-linux-x86-64.so.2", "ld-linux-aarch64.so.1"})


class ElfError(VcError):
    """Not an ELF file this module reads."""


@dataclass(frozen=True, slots=True)
class Needs:
    libraries: tuple[str, ...]  # DT_NEEDED, in order
    versions: dict[str, frozenset[str]]  # per library: the symbol versions it must provide

    @property
    def glibc(self) -> tuple[int, ...]:
        """The newest GLIBC_x.y version needed: the oldest glibc the file runs with; () for none."""
        found = [tuple(int(part) for part in name.removeprefix("GLIBC_").split("."))
                 for names in self.versions.values() for name in names
                 if name.startswith("GLIBC_") and name.removeprefix("GLIBC_").replace(".", "").isdigit()]
        return max(found, default=())


def is_elf(data: bytes) -> bool:
    return data[:4] == _ELF_MAGIC


def needs(path: Path) -> Needs:
    return needs_of(path.read_bytes(), str(path))


def needs_of(data: bytes, name: str) -> Needs:
    """What the ELF file ``data`` (called ``name`` in messages) needs."""
    if not is_elf(data) or data[4] != 2 or data[5] != 1:
        raise ElfError(f"{name}: not a 64-bit little-endian ELF file")
    fields = _HEADER.unpack_from(data)
    section_offset, section_size, section_count = fields[6], fields[11], fields[12]
    sections = [_SECTION.unpack_from(data, section_offset + index * section_size) for index in range(section_count)]

    def string(table: int, offset: int) -> str:
        start = sections[table][4] + offset
        return data[start:data.index(b"\0", start)].decode()

    libraries: list[str] = []
    versions: dict[str, set[str]] = {}
    for kind, link, offset, size, entry_size in ((s[1], s[6], s[4], s[5], s[9]) for s in sections):
        if kind == _SHT_DYNAMIC:
            for position in range(offset, offset + size, entry_size or _DYNAMIC.size):
                tag, value = _DYNAMIC.unpack_from(data, position)
                if tag == _DT_NEEDED:
                    libraries.append(string(link, value))
        elif kind == _SHT_GNU_VERNEED:
            position = offset
            while True:
                _, count, file_name, aux, following = _VERNEED.unpack_from(data, position)
                names = versions.setdefault(string(link, file_name), set())
                aux_position = position + aux
                for _ in range(count):
                    _, _, _, version_name, aux_next = _VERNAUX.unpack_from(data, aux_position)
                    names.add(string(link, version_name))
                    aux_position += aux_next
                if not following:
                    break
                position += following
    return Needs(tuple(libraries), {library: frozenset(names) for library, names in versions.items()})
