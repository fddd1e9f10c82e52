"""Session recording and replay: ``vc serve --record FILE`` records what an external PLC wrote and
what the NC answered, ``vc replay FILE`` replays it without the PLC and reports the first
difference, ``vc replay FILE --to-scenario OUT.yaml`` turns it into a scenario.

``format`` the file (docs/recording.md), ``recorder`` the observer of a served simulation,
``replay`` the replay, ``to_scenario`` the conversion, ``command`` the commands.
"""
