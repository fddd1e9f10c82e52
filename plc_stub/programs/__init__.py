"""The built-in PLC programs, registered by name for the harness.

``REGISTRY`` is published through the ``vc_harness.plc_programs`` entry point; the
harness looks programs up there and never imports this package.
"""

from __future__ import annotations

from interfaces.plc import PlcEnvironment, PlcFactory, SoftPlc
from plc_stub.programs.basic_machine import BasicMachine
from plc_stub.programs.manual_retraction import ManualRetraction
from plc_stub.programs.polygon import Polygon
from plc_stub.programs.referencing import Referencing
from plc_stub.programs.retraction import Retraction
from plc_stub.programs.spindle import Spindle
from plc_stub.programs.sync_spindle import SyncSpindle
from plc_stub.runtime import ScanCycleRuntime


def _basic_machine(environment: PlcEnvironment) -> SoftPlc:
    return ScanCycleRuntime(environment, BasicMachine)


def _referencing(environment: PlcEnvironment) -> SoftPlc:
    return ScanCycleRuntime(environment, Referencing)


def _spindle(environment: PlcEnvironment) -> SoftPlc:
    return ScanCycleRuntime(environment, Spindle)


def _sync_spindle(environment: PlcEnvironment) -> SoftPlc:
    return ScanCycleRuntime(environment, SyncSpindle)


def _polygon(environment: PlcEnvironment) -> SoftPlc:
    return ScanCycleRuntime(environment, Polygon)


def _manual_retraction(environment: PlcEnvironment) -> SoftPlc:
    return ScanCycleRuntime(environment, ManualRetraction)


def _retraction(environment: PlcEnvironment) -> SoftPlc:
    return ScanCycleRuntime(environment, Retraction)


REGISTRY: dict[str, PlcFactory] = {
    "basic_machine": _basic_machine,
    "referencing": _referencing,
    "spindle": _spindle,
    "sync_spindle": _sync_spindle,
    "polygon": _polygon,
    "retraction": _retraction,
    "manual_retraction": _manual_retraction,
}
