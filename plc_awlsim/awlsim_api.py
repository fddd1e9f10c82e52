"""The parts of awlsim the bridge uses, imported in the order awlsim needs.

awlsim's modules star-import each other: its CPU core must be loaded before its STL compiler,
or the compiler's names are missing in the core (``NameError: RawAwlOB``).  Everything of
awlsim that this package (and its tests) uses comes from here.
"""
# isort: skip_file

from __future__ import annotations

import awlsim_loader.common  # awlsim's loader picks the pure-Python build
import awlsim_loader.core
import awlsim_loader.awlcompiler  # noqa: F401

from awlsim.common.cpuconfig import S7CPUConfig
from awlsim.common.exceptions import AwlSimError, MaintenanceRequest
from awlsim.common.sources import AwlSource
from awlsim.core.hardware import AbstractHardwareInterface
from awlsim.core.hardware_params import HwParamDesc_float, HwParamDesc_int, HwParamDesc_str
from awlsim.core.main import AwlSim
from awlsim.core.symbolparser import SymTabParser
from awlsim.awlcompiler import AwlParser

__all__ = ["AbstractHardwareInterface", "AwlParser", "AwlSim", "AwlSimError", "AwlSource", "HwParamDesc_float",
           "HwParamDesc_int", "HwParamDesc_str", "MaintenanceRequest", "S7CPUConfig", "SymTabParser"]
