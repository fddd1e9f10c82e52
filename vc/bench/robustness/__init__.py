"""The robustness campaign (``bench/robustness.py``): the links and the real-time NC under abuse.

Each part starts the harness as a user would (``vc serve`` and ``python -m plc_stub`` in their
own processes, :mod:`vc.bench.robustness.processes`), abuses one link and returns one row of
the campaign's table (:mod:`vc.bench.robustness.campaign`): inputs tried, crashes, hangs,
tracebacks, false passes, lost requests, rule violations, RSS growth, overruns.

* :mod:`~vc.bench.robustness.modbus_fuzz`: frames of every kind on the Modbus server of a real-time
  NC whose PLC is connected: random bytes, wrong lengths, every function code, out-of-range counts
  and addresses, truncation, splits, pipelining, 200 connections, idle half-open connections;
* :mod:`~vc.bench.robustness.flood`: 50 connections reading back to back while the NC runs in
  real time: the overruns and the NC's share of real time;
* :mod:`~vc.bench.robustness.s7_probe`: S7 writes, block downloads, idle sessions, garbage;
* :mod:`~vc.bench.robustness.can_noise`: datagrams that are no frames, error frames and stray
  frames on the CAN bus of a lockstep scenario and of a real-time NC;
* :mod:`~vc.bench.robustness.control_characters`: scenario names with control characters through
  ``vc run``'s console, JUnit, CSV, VCD, GTKWave and HTML outputs;
* :mod:`~vc.bench.robustness.hostile_recordings`, :mod:`~vc.bench.robustness.hostile_expressions`,
  :mod:`~vc.bench.robustness.campaign_size`: the inputs of ``vc replay`` and ``vc run`` made
  hostile (recordings, conditions and placeholders, matrices and campaigns), each command in its
  own bounded process (:mod:`~vc.bench.robustness.one_shot`);
* :mod:`~vc.bench.robustness.soak`: ``vc serve --realtime`` with the built-in PLC over Modbus for
  minutes, the RSS of both processes sampled.

A short version of each runs in the test suite (tests/vc/bench/test_robustness.py).
"""
