"""A test bench that runs docs/plc_examples/turn_mill.st as its CODESYS setup would, against ``vc serve``.

* **Parsing**: blark (an IEC 61131-3 Structured Text grammar on lark) parses the program and the
  CODESYS global variable list of ``vc map --format codesys``; a program blark cannot parse fails.
* **Evaluating**: :class:`Program` runs the subset of ST the example uses, statement by statement
  from blark's tree: assignments, IF / ELSIF / ELSE, the standard function blocks TON, TOF and
  R_TRIG, NOT / AND / OR / XOR, comparisons, + - * MOD, the literals (TRUE, integers, 16#..,
  WORD#16#.., T#500MS) and the ``*_TO_*`` conversions of unsigned integers.  Anything else is an
  :class:`StError` naming its line: the bench never guesses.
* **Process image**: the located variables live in the I/O words of the CODESYS Modbus Slave
  Channels (:func:`interfaces.exports.client_setups.codesys_word`), little-endian as on every CODESYS
  Control for x86 and ARM: ``%IXn.m`` is bit m of byte n, ``%IBn`` byte n, ``%IWn`` bytes 2n, 2n + 1.
* **The master**: pyModbusTCP (an independent client) moves the channels, stepped by the lockstep
  handshake of docs/modbus.md instead of the channels' cycle: read the link block; on a grant read
  every input channel, run one scan with the PLC's clock at NC time (input registers 4..5 times 6),
  write the program's session ready and key (holding registers 1..5: its claim), the output
  channels, and last the program's scan done (holding register 0).  The program itself does the
  link's part (echoes the session, answers the grant, starts over in a new session): a program
  that does not is refused by the server or never granted another scan, and :class:`HandshakeError`
  says which.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any

from blark import parse
from blark import transform as tf
from pyModbusTCP.client import ModbusClient

from interfaces.exports.client_setups import codesys_channels, codesys_word
from interfaces.links.modbus.codec import LINK_REGISTERS, LINK_VERSION, LinkHolding, LinkInput, RegisterMap, Table

BITS = {"BOOL": 1, "BYTE": 8, "USINT": 8, "WORD": 16, "UINT": 16, "DWORD": 32, "UDINT": 32, "TIME": 32}
STUCK_S = 15.0  # no new grant for this long while the harness runs: it did not take the last scan


class StError(Exception):
    """A construct the bench does not run, or a name it does not know, with its line."""


class HandshakeError(Exception):
    """The program does not do the link's part (docs/modbus.md, lockstep with a third-party PLC)."""


def _line(node: Any) -> str:
    meta = getattr(node, "meta", None)
    return f"turn_mill.st:{getattr(meta, 'line', '?')}"


def _parsed(text: str, name: str) -> list[Any]:
    result = parse.parse_source_code(text, fn=name)
    if result.exception is not None:
        raise StError(f"{name}: blark cannot parse it: {result.exception}")
    return list(result.transform().items)


# ---------------------------------------------------------------------------------- process image


@dataclass(frozen=True, slots=True)
class Located:
    """A located variable: ``%IX386.4``, ``%QB33``, ``%IW193``."""

    area: str  # "I" or "Q"
    size: str  # "X", "B", "W"
    index: int  # byte (X, B) or word (W)
    bit: int  # X only
    type_name: str


class ChannelImage:
    """The I/O words of the CODESYS channels, in the order they are created (module docstring)."""

    def __init__(self, register_map: RegisterMap):
        self.register_map = register_map
        self.inputs = bytearray(2 * register_map.registers(Table.NC_TO_PLC))
        self.outputs = bytearray(2 * register_map.registers(Table.PLC_TO_NC))

    def _area(self, area: str) -> bytearray:
        return self.inputs if area == "I" else self.outputs

    def read(self, where: Located) -> int | bool:
        data = self._area(where.area)
        if where.size == "X":
            return bool(data[where.index] >> where.bit & 1)
        if where.size == "B":
            return data[where.index]
        return int.from_bytes(data[2 * where.index: 2 * where.index + 2], "little")

    def write(self, where: Located, value: int | bool) -> None:
        if where.area != "Q":
            raise StError(f"%I{where.size}{where.index} is an input: a program cannot write it")
        data = self.outputs
        if where.size == "X":
            data[where.index] = data[where.index] | 1 << where.bit if value else data[where.index] & ~(1 << where.bit)
        elif where.size == "B":
            data[where.index] = int(value) & 0xFF
        else:
            data[2 * where.index: 2 * where.index + 2] = (int(value) & 0xFFFF).to_bytes(2, "little")

    def load_inputs(self, registers: Sequence[int]) -> None:
        for register, value in enumerate(registers):
            word = codesys_word(self.register_map, Table.NC_TO_PLC, register)
            self.inputs[2 * word: 2 * word + 2] = value.to_bytes(2, "little")

    def output_registers(self) -> list[int]:
        return [int.from_bytes(self.outputs[2 * word: 2 * word + 2], "little")
                for word in (codesys_word(self.register_map, Table.PLC_TO_NC, register)
                             for register in range(self.register_map.registers(Table.PLC_TO_NC)))]


def global_variables(gvl: str) -> dict[str, Located]:
    """The located variables of a CODESYS global variable list (``vc map --format codesys``)."""
    found = {}
    for block in _parsed(gvl, "codesys.gvl"):
        for item in block.items:
            location = item.spec.location
            index = int(str(location.location))
            size = location.size_prefix.value if location.size_prefix is not None else "X"
            bit = int(str(location.bits[-1])) if location.bits else 0  # %QX59.1: location 59, bits [1]
            type_name = str(item.init.spec.type)
            for name in item.spec.variables:
                found[str(name)] = Located(location.location_prefix.value, size, index, bit, type_name)
    return found


# ---------------------------------------------------------------------------------- function blocks


@dataclass(slots=True)
class Ton:
    """IEC 61131-3 on-delay: Q once IN has been TRUE for PT (the fields are the standard's names)."""

    IN: bool = False
    PT: int = 0
    Q: bool = False
    ET: int = 0
    _start: int | None = None

    def run(self, now_ms: int) -> None:
        if not self.IN:
            self._start, self.Q, self.ET = None, False, 0
            return
        if self._start is None:
            self._start = now_ms
        self.ET = min(now_ms - self._start, self.PT)
        self.Q = self.ET >= self.PT


@dataclass(slots=True)
class Tof:
    """IEC 61131-3 off-delay: Q with IN, and for PT after IN fell."""

    IN: bool = False
    PT: int = 0
    Q: bool = False
    ET: int = 0
    _fell: int | None = None

    def run(self, now_ms: int) -> None:
        if self.IN:
            self._fell, self.Q, self.ET = None, True, 0
            return
        if not self.Q:
            return
        if self._fell is None:
            self._fell = now_ms
        self.ET = min(now_ms - self._fell, self.PT)
        self.Q = self.ET < self.PT


@dataclass(slots=True)
class RTrig:
    """IEC 61131-3 rising edge: Q for one call after CLK rose."""

    CLK: bool = False
    Q: bool = False
    _memory: bool = False

    def run(self, now_ms: int) -> None:
        self.Q = self.CLK and not self._memory
        self._memory = self.CLK


BLOCKS: dict[str, Callable[[], Ton | Tof | RTrig]] = {"TON": Ton, "TOF": Tof, "R_TRIG": RTrig}


# ---------------------------------------------------------------------------------- the evaluator


@dataclass(slots=True)
class _Local:
    type_name: str
    value: int | bool


@dataclass
class Program:
    """One PROGRAM of ST over a :class:`ChannelImage` (module docstring)."""

    source: str
    globals: dict[str, Located]
    image: ChannelImage
    now_ms: int = 0
    locals: dict[str, _Local] = field(default_factory=dict)
    blocks: dict[str, Ton | Tof | RTrig] = field(default_factory=dict)

    def __post_init__(self) -> None:
        (program,) = _parsed(self.source, "turn_mill.st")
        if not isinstance(program, tf.Program):
            raise StError(f"turn_mill.st holds a {type(program).__name__}, not a PROGRAM")
        self.body = program.body.statements
        for block in program.declarations:
            for item in block.items:
                self._declare(item)

    def _declare(self, item: Any) -> None:
        names = [str(declared.variable.name) for declared in item.variables]
        if isinstance(item, tf.StructuredVariableInitDeclaration):  # TON := (PT := T#5S)
            for name in names:
                self.blocks[name] = self._block(str(item.init.name), item)
                for element in item.init.init.elements:
                    setattr(self.blocks[name], str(element.name), self.value(element.value))
            return
        type_name = str(item.init.spec.type)
        for name in names:
            if type_name in BLOCKS:
                self.blocks[name] = self._block(type_name, item)
            elif type_name in BITS:
                initial = self.value(item.init.value) if item.init.value is not None else 0
                self.locals[name] = _Local(type_name, bool(initial) if type_name == "BOOL" else int(initial))
            else:
                raise StError(f"{_line(item)}: the bench does not run variables of type {type_name}")

    @staticmethod
    def _block(type_name: str, item: Any) -> Ton | Tof | RTrig:
        if type_name not in BLOCKS:
            raise StError(f"{_line(item)}: the bench does not run function block {type_name}")
        return BLOCKS[type_name]()

    def scan(self, now_ms: int) -> None:
        self.now_ms = now_ms
        self.run(self.body)

    # ------------------------------------------------------------------ statements
    def run(self, statements: Sequence[Any]) -> None:
        for statement in statements:
            if isinstance(statement, tf.AssignmentStatement):
                value = self.value(statement.expression)
                for target in statement.variables:
                    self.assign(target, value)
            elif isinstance(statement, tf.IfStatement):
                self._if(statement)
            elif isinstance(statement, tf.FunctionCallStatement):
                self._call_block(statement)
            else:
                raise StError(f"{_line(statement)}: the bench does not run {type(statement).__name__}")

    def _if(self, statement: Any) -> None:
        branches = [(statement.if_expression, statement.statements),
                    *((clause.if_expression, clause.statements) for clause in statement.else_ifs)]
        for condition, body in branches:
            if self.value(condition):
                self.run(body.statements if body is not None else [])
                return
        if statement.else_clause is not None and statement.else_clause.statements is not None:
            self.run(statement.else_clause.statements.statements)

    def _call_block(self, statement: Any) -> None:
        name = str(statement.name.name)
        block = self.blocks.get(name)
        if block is None:
            raise StError(f"{_line(statement)}: {name} is no function block instance")
        for parameter in statement.parameters:
            setattr(block, str(parameter.name.name), self.value(parameter.value))
        block.run(self.now_ms)

    def assign(self, target: Any, value: int | bool) -> None:
        if not isinstance(target, tf.SimpleVariable):
            raise StError(f"{_line(target)}: the bench assigns to plain variables only")
        name = str(target.name)
        if name in self.locals:
            local = self.locals[name]
            local.value = bool(value) if local.type_name == "BOOL" else int(value) & (1 << BITS[local.type_name]) - 1
        elif name in self.globals:
            self.image.write(self.globals[name], value)
        else:
            raise StError(f"{_line(target)}: {name} is not declared (program or global variable list)")

    # ------------------------------------------------------------------ expressions
    def value(self, node: Any) -> Any:
        """The value of an expression, by the method named after blark's class of it (_BinaryOperation ...)."""
        handler = getattr(self, f"_{type(node).__name__}", None)
        if handler is None:
            raise StError(f"{_line(node)}: the bench does not evaluate {type(node).__name__}")
        return handler(node)

    def _SimpleVariable(self, node: Any) -> int | bool:
        name = str(node.name)
        if name in self.locals:
            return self.locals[name].value
        if name in self.globals:
            return self.image.read(self.globals[name])
        raise StError(f"{_line(node)}: {name} is not declared (program or global variable list)")

    def _MultiElementVariable(self, node: Any) -> int | bool:
        block = self.blocks.get(str(node.name.name))
        if block is None or len(node.elements) != 1 or not isinstance(node.elements[0], tf.FieldSelector):
            raise StError(f"{_line(node)}: the bench reads the outputs of function blocks only")
        return getattr(block, str(node.elements[0].field.name))  # type: ignore[no-any-return]

    def _ParenthesizedExpression(self, node: Any) -> Any:
        return self.value(node.expr)

    def _Boolean(self, node: Any) -> bool:
        return str(node.value).upper() == "TRUE"

    def _Integer(self, node: Any) -> int:
        return int(str(node.value))

    def _HexInteger(self, node: Any) -> int:
        return int(str(node.value), 16)

    def _HexBitString(self, node: Any) -> int:
        return int(str(node.value), 16)

    def _Duration(self, node: Any) -> int:
        parts = ((node.days, 86_400_000), (node.hours, 3_600_000), (node.minutes, 60_000), (node.seconds, 1000),
                 (node.milliseconds, 1))
        return sum(int(float(str(amount)) * scale) for amount, scale in parts if amount is not None)

    def _UnaryOperation(self, node: Any) -> Any:
        operand, operator = self.value(node.expr), str(node.op).upper()
        if operator == "NOT":
            return not operand if isinstance(operand, bool) else ~operand & 0xFFFF_FFFF
        if operator == "-":
            return -operand
        raise StError(f"{_line(node)}: the bench does not evaluate the operator {operator}")

    def _BinaryOperation(self, node: Any) -> Any:
        left, right, operator = self.value(node.left), self.value(node.right), str(node.op).upper()
        operations: dict[str, Callable[[Any, Any], Any]] = {
            "AND": lambda a, b: a and b if isinstance(a, bool) else a & b, "&": lambda a, b: a and b,
            "OR": lambda a, b: a or b if isinstance(a, bool) else a | b,
            "XOR": lambda a, b: a != b if isinstance(a, bool) else a ^ b,
            "=": lambda a, b: a == b, "<>": lambda a, b: a != b, "<": lambda a, b: a < b, ">": lambda a, b: a > b,
            "<=": lambda a, b: a <= b, ">=": lambda a, b: a >= b, "+": lambda a, b: a + b,
            "-": lambda a, b: a - b, "*": lambda a, b: a * b, "MOD": lambda a, b: a % b}
        if operator not in operations:
            raise StError(f"{_line(node)}: the bench does not evaluate the operator {operator}")
        return operations[operator](left, right)

    def _FunctionCall(self, node: Any) -> int:
        name = str(node.name.name).upper()
        source, _, target = name.partition("_TO_")
        if source not in BITS or target not in BITS or len(node.parameters) != 1:
            raise StError(f"{_line(node)}: the bench calls the conversions of unsigned integers only, not {name}")
        return int(self.value(node.parameters[0].value)) & (1 << BITS[target]) - 1


# ---------------------------------------------------------------------------------- the master


@dataclass
class LockstepMaster:
    """The program's Modbus TCP master, stepped by the lockstep handshake (module docstring)."""

    client: ModbusClient
    program: Program
    register_map: RegisterMap
    scans: int = 0
    sessions: list[int] = field(default_factory=list)

    def _read(self, first: int, count: int) -> list[int] | None:
        values = self.client.read_input_registers(first, count)
        return list(values) if values is not None else None

    def _write(self, first: int, values: Sequence[int], what: str) -> None:
        if not self.client.write_multiple_registers(first, list(values)):
            raise HandshakeError(f"the server refused {what} (holding registers {first}..{first + len(values) - 1},"
                                 f" exception {self.client.last_except}): the program must claim its session,"
                                 " LINK_sessionReady := LINK_session")

    def steps(self) -> Iterator[int]:
        """Serve the harness until it ends (its server closes); yields every scan run."""
        session: tuple[int, int] | None = None
        last_grant, granted_at = 0, time.monotonic()
        while True:
            head = self._read(0, LINK_REGISTERS)
            if head is None:
                return  # the harness has ended
            if head[LinkInput.VERSION] == 0:
                time.sleep(0.01)
                continue
            if head[LinkInput.VERSION] != LINK_VERSION:
                raise HandshakeError(f"the harness speaks link version {head[LinkInput.VERSION]}, the bench"
                                     f" {LINK_VERSION}")
            if (head[LinkInput.SESSION], head[LinkInput.BOOT_ID]) != session:
                session = head[LinkInput.SESSION], head[LinkInput.BOOT_ID]
                self.sessions.append(session[0])
                last_grant, granted_at = 0, time.monotonic()
            grant = head[LinkInput.SCAN_GRANT]
            if grant == 0 or grant == last_grant:
                if time.monotonic() - granted_at > STUCK_S:
                    raise HandshakeError(f"the harness has not granted a scan after scan {last_grant} for"
                                         f" {STUCK_S:g} s: it did not take that scan; the program must answer the"
                                         " grant, LINK_scanDone := LINK_scanGrant in lockstep")
                time.sleep(0.0005)
                continue
            self._scan()
            last_grant, granted_at = grant, time.monotonic()
            self.scans += 1
            yield self.scans

    def _scan(self) -> None:
        inputs: list[int] = []
        for channel in codesys_channels(self.register_map):
            if channel.table is Table.NC_TO_PLC:
                values = self._read(channel.offset, channel.length)
                if values is None:
                    raise HandshakeError(f"the server did not answer the read of channel {channel.name}")
                inputs += values
        self.program.image.load_inputs(inputs)
        cycles = inputs[LinkInput.NC_CYCLE_HIGH] << 16 | inputs[LinkInput.NC_CYCLE_LOW]
        self.program.scan(cycles * inputs[LinkInput.IPO_CYCLE_US] // 1000)  # the PLC's clock: NC time
        outputs = self.program.image.output_registers()
        claim = slice(LinkHolding.SESSION_READY, LinkHolding.SESSION_KEY + 4)
        self._write(claim.start, outputs[claim], "the program's session ready and key")
        for channel in codesys_channels(self.register_map):
            if channel.table is Table.PLC_TO_NC and channel.offset >= LINK_REGISTERS:
                self._write(channel.offset, outputs[channel.offset: channel.stop], f"channel {channel.name}")
        self._write(LinkHolding.SCAN_DONE, outputs[LinkHolding.SCAN_DONE: LinkHolding.SCAN_DONE + 1],
                    "the program's scan done")
