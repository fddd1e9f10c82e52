"""The NC core's tests, one folder per package of vc/core (tests/vc/core/<package>/test_<module>.py).

Loading this file puts tests/vc/core on ``sys.path`` (pytest's prepend import mode), so the tests
in every package folder import the shared rig as ``from core_rig import ...``.
"""
