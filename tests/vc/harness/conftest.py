"""The harness's tests, mirroring vc/harness (tests/vc/harness/links/test_<technology>.py for
vc/harness/links/).

Loading this file puts tests/vc/harness on ``sys.path`` (pytest's prepend import mode), so the tests
in links/ import the shared operator panel as ``from panel_operator import ...``.
"""
