"""The built-in PLC's end of a link to the harness in another process, one module per technology:
``modbus.py`` (a Modbus TCP client of ``vc serve`` / ``vc run --link modbus``) and ``can.py`` (a node
on the harness's CAN bus).  The harness's end is :mod:`vc.harness.links`; both meet only through
the protocol adapters of :mod:`interfaces.links`.
"""
