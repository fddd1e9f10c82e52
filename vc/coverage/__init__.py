"""Interface coverage: what the scenario runs exercised of the NC/PLC interface, the NC's state
machines, its alarms and the plant I/O (``vc run --coverage FILE``, ``vc coverage report``).

``data`` the mergeable coverage data and its file, ``state_machines`` the declared state machines,
``probes`` reading them from a running NC, ``collector`` the observer of a run, ``report`` the
figures and gaps, ``html`` the standalone page, ``command`` the report command.  docs/coverage.md
explains the figures.
"""
