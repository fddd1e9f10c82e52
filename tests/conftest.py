"""Settings of the whole suite.

Property-based tests judge results, never time: Hypothesis's deadline per example and its
"too slow" health check measure the machine, not the code (a CI machine shared with other work took
292 ms for one example of the five-axis kinematics against the default deadline of 200 ms).  Both
are off for every test; a test's own ``@settings`` still sets its number of examples.
"""

from hypothesis import HealthCheck, settings

settings.register_profile("vc", deadline=None, suppress_health_check=[HealthCheck.too_slow])
settings.load_profile("vc")
