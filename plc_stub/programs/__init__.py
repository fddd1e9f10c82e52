"""The built-in PLC programs, registered by name for the harness.

``REGISTRY`` maps each name to its program class; ``FACTORIES`` runs each class in the scan-cycle
runtime and is published through the ``vc_harness.plc_programs`` entry point (a mapping
``{name: PlcFactory}``); the harness looks programs up there and never imports this package.
"""

from __future__ import annotations

from functools import partial

from interfaces.plc import PlcFactory
from plc_stub.programs.basic_machine import BasicMachine
from plc_stub.programs.cams import Cams
from plc_stub.programs.coolant import Coolant
from plc_stub.programs.drive_lineup import DriveLineup
from plc_stub.programs.gantry import Gantry
from plc_stub.programs.magazine import Magazine
from plc_stub.programs.manual_retraction import ManualRetraction
from plc_stub.programs.polygon import Polygon
from plc_stub.programs.referencing import Referencing
from plc_stub.programs.retraction import Retraction
from plc_stub.programs.rotary_table import RotaryTable
from plc_stub.programs.spindle import Spindle
from plc_stub.programs.sync_spindle import SyncSpindle
from plc_stub.programs.tailstock import Tailstock
from plc_stub.programs.tool_change import ToolChange
from plc_stub.programs.turret import Turret
from plc_stub.runtime import ProgramClass, ScanCycleRuntime

REGISTRY: dict[str, ProgramClass] = {
    "basic_machine": BasicMachine,
    "referencing": Referencing,
    "spindle": Spindle,
    "sync_spindle": SyncSpindle,
    "polygon": Polygon,
    "retraction": Retraction,
    "manual_retraction": ManualRetraction,
    "coolant": Coolant,
    "turret": Turret,
    "tool_change": ToolChange,
    "tailstock": Tailstock,
    "magazine": Magazine,
    "rotary_table": RotaryTable,
    "drive_lineup": DriveLineup,
    "cams": Cams,
    "gantry": Gantry,
}


# partial, not a closure: a factory pickles (by the class's name) into worker processes
FACTORIES: dict[str, PlcFactory] = {name: partial(ScanCycleRuntime, program=program)
                                    for name, program in REGISTRY.items()}
