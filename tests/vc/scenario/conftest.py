"""The scenario package's tests, one folder per subpackage of vc/scenario (language/, run/, outputs/,
distribution/; the tests of vc/scenario/command.py beside this file).

Loading this file puts tests/vc/scenario on ``sys.path`` (pytest's prepend import mode), so the tests
in every folder import the shared stand-in target as ``from scenario_fakes import ...``; the campaign
files several folders run are in campaign_files/.
"""
