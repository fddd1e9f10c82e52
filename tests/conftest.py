"""Settings of the whole suite.

Property-based tests judge results, never time: Hypothesis's deadline per example and its
"too slow" health check measure the machine, not the code (a CI machine shared with other work took
292 ms for one example of the five-axis kinematics against the default deadline of 200 ms).  Both
are off for every test; a test's own ``@settings`` still sets its number of examples.
"""

from hypothesis import HealthCheck, settings

settings.register_profile("vc", deadline=None, suppress_health_check=[HealthCheck.too_slow])
settings.load_profile("vc")


# Test modules whose tests run for tens of seconds to minutes (the pure build's whole library, the
# robustness campaign's parts, the FMU exports and their validation, the ST program against vc serve).
# pytest-xdist hands each worker a contiguous part of the collected order and lets idle workers steal
# from the end of the others': one of these collected late ran alone at the end while the other
# worker was idle (the suite's wall time, not its work).  They go first; the thousands of short tests
# fill in around them.
LONG_FIRST = (
    "tests/scenarios/test_library_builds.py",
    "tests/vc/bench/test_robustness",
    "tests/fmu/test_fmu_export.py",
    "tests/plc_examples/test_turn_mill_st.py",
    "tests/vc/scenario/distribution/",
    "tests/vc/ui/test_operator_page.py",
)


def pytest_collection_modifyitems(items: list) -> None:  # type: ignore[type-arg]
    items.sort(key=lambda item: not item.nodeid.startswith(LONG_FIRST))  # stable: the rest keep their order
