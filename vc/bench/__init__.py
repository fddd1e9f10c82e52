"""The benchmarks and the robustness campaign: figures printed, never asserted.

``lockstep``      ``vc bench``: how fast the lockstep simulation runs (and what the others share)
``workloads``     what moves in a benchmark: the MDA programs written from the machine
``scaling``       ``vc bench --scaling``: the cost of an IPO cycle against what moves
``modbus_link``   ``vc bench --link modbus``: the Modbus TCP link on loopback
``can_link``      ``vc bench --link can``: the CAN link on a virtual bus and on UDP multicast
``fmu_steps``     ``vc bench --link fmu``: the FMU under FMPy against the unit in process
``builds``        the pure-Python and the compiled build side by side (bench/compare_builds.py)
``robustness/``   the robustness campaign (bench/robustness.py, bench/robustness_files.py)

Only the CLI (``vc bench``) and the scripts in bench/ import this package.
"""
