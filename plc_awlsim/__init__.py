"""awlsim, the S7-compatible soft PLC, as the harness's PLC over the Modbus TCP link.

* :mod:`plc_awlsim.hardware`: an awlsim hardware module that is the harness's Modbus client: it
  copies the NC-to-PLC table into the input process image and the output process image into
  the PLC-to-NC table (table byte t = IB / QB t, from the module's ``inputAddressBase`` /
  ``outputAddressBase``), follows the lockstep protocol (one OB 1 per granted scan) or scans
  every PLC period in real time, and answers a new session with a warm restart (OB 100).
* :mod:`plc_awlsim.clock`: the CPU's clock follows the NC: S7 timers, clock memory and
  TIME_TCK count NC time, not the wall clock.
* :mod:`plc_awlsim.runner` (``python -m plc_awlsim``): loads an STL program and its symbols
  (by default the machine's ``vc map --format awlsim`` table, from the harness's description)
  and runs it.

awlsim is an optional dependency (``pip install 'vc-harness[awlsim]'``); this package imports it,
``interfaces`` and nothing of ``vc``: like plc_stub, it meets the harness only through the link.
"""
