"""``python -m plc_awlsim``: an STL program in awlsim as the harness's PLC over Modbus TCP.

1. Connect to the harness and wait for its first session (the description of the machine).
2. The symbol table: the file given (``--symbols``: awlsim's ``.csv`` or STEP 7's ``.asc``), else
   the machine's own, made from the description as ``vc map --format awlsim`` makes it.
3. Load the program (English or German mnemonics, ``--mnemonics``), start the CPU (OB 100) and
   run OB 1 for every scan the harness grants (lockstep) or every PLC period (real time);
   :mod:`plc_awlsim.hardware` does the link's work, :mod:`plc_awlsim.clock` gives the CPU NC time.

Exit codes (as ``python -m plc_stub``): 0 stopped, 1 no harness, 2 the program cannot run (a
problem in the program or the symbol table, reported with file and line).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from interfaces.errors import VcError
from interfaces.exports.context import ExportContext
from interfaces.exports.symbol_tables import awlsim_csv
from interfaces.links.description import DescriptionError, LinkDescription, PlcSetupError
from interfaces.links.errors import LinkError
from interfaces.signal_map import map_rows
from plc_awlsim.awlsim_api import AwlParser, AwlSim, AwlSimError, AwlSource, S7CPUConfig, SymTabParser
from plc_awlsim.hardware import HardwareInterface

EXIT_STOPPED, EXIT_NO_HARNESS, EXIT_CANNOT_RUN = 0, 1, 2
MNEMONICS = {"en": S7CPUConfig.MNEMONICS_EN, "de": S7CPUConfig.MNEMONICS_DE}


class ProgramError(VcError):
    """The program or its symbol table cannot run; the message says where."""


def machine_symbols(description: bytes, io_base: int) -> str:
    """The machine's awlsim symbol table (``vc map --format awlsim``) from the harness's description."""
    try:
        link = LinkDescription.from_json(description)
        environment, register_map = link.environment()
    except DescriptionError as error:
        raise ProgramError(f"the harness's description: {error}") from None
    rows = map_rows(environment.catalog, environment.plant_io)
    return awlsim_csv(rows, ExportContext(link.machine, register_map, io_base))


def _symbol_table(text: str, mnemonics: Any, where: str) -> Any:
    try:
        return SymTabParser.parseText(text, autodetectFormat=True, mnemonics=mnemonics)
    except AwlSimError as error:
        raise ProgramError(f"{where}: {error.getReport(verbose=False).strip()}") from None


class AwlsimPlc:
    """An awlsim CPU with the bridge, loaded with one program."""

    def __init__(self, host: str, port: int, program: Path, symbols: Path | None = None, io_base: int = 0,
                 mnemonics: str = "en", connect_timeout_s: float = 30.0, log: Callable[[str], None] = print,
                 key_file: str | None = None):
        self.log = log
        self.sim = AwlSim()
        cpu = self.sim.getCPU()
        cpu.getConf().setConfiguredMnemonics(MNEMONICS[mnemonics])
        self.hardware: HardwareInterface = self.sim.registerHardwareClass(HardwareInterface, {
            "host": host, "port": str(port), "connectTimeout": str(connect_timeout_s), "keyFile": key_file or "",
            "inputAddressBase": str(io_base), "outputAddressBase": str(io_base)})
        self.hardware.log = log
        self.hardware.startup()  # connect and wait for the first session: it describes the machine
        session = self.hardware.session
        assert session is not None
        if symbols is not None:
            table = _symbol_table(symbols.read_text(encoding="latin-1"), MNEMONICS[mnemonics], str(symbols))
        else:
            table = _symbol_table(machine_symbols(session.description, io_base), MNEMONICS[mnemonics],
                                  "the machine's symbol table")
        try:
            self.sim.loadSymbolTable(table)
            parser = AwlParser()
            parser.parseSource(AwlSource(name=program.name, filepath=str(program),
                                         sourceBytes=program.read_bytes()))
            self.sim.load(parser.getParseTree())
            self.sim.startup()  # builds the blocks and runs OB 100
        except AwlSimError as error:
            raise ProgramError(f"{program}: {error.getReport(verbose=False).strip()}") from None
        self.log(f"session {session.number}: program {program.name},"
                 f" {'lockstep' if session.lockstep else 'real time'}")

    def run(self, should_stop: Callable[[], bool] = lambda: False) -> None:
        session = self.hardware.session
        while not should_stop():
            self.sim.runCycle()
            if self.hardware.session is not session:
                session = self.hardware.session
                assert session is not None
                self.log(f"session {session.number}: warm restart (OB 100)")


def run(host: str, port: int, program: Path, symbols: Path | None, io_base: int, mnemonics: str,
        connect_timeout_s: float, log: Callable[[str], None], key_file: str | None = None) -> int:
    """Run until stopped; the exit code of ``python -m plc_awlsim``."""
    plc: AwlsimPlc | None = None
    try:
        plc = AwlsimPlc(host, port, program, symbols, io_base, mnemonics, connect_timeout_s, log, key_file)
        plc.run()
    except LinkError as error:  # no harness, or it has gone (HarnessGone)
        log(str(error))
        return EXIT_NO_HARNESS
    except (ProgramError, PlcSetupError, OSError) as error:
        log(f"cannot run: {error}")
        return EXIT_CANNOT_RUN
    except AwlSimError as error:
        log(f"stopped: {error.getReport(verbose=False).strip()}")
        return EXIT_CANNOT_RUN
    finally:
        if plc is not None:
            plc.sim.shutdown()
    return EXIT_STOPPED
