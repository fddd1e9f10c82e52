"""awlsim's name for the bridge (awlsim loads hardware module ``NAME`` as ``awlsimhw_NAME``): add the
hardware module ``vcmodbus`` to an awlsim project (awlsim-gui, awlsim-server) to run it against the harness."""

from plc_awlsim.hardware import HardwareInterface as HardwareInterface
