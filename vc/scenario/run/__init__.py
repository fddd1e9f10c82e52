"""Running checked scenarios: the run loop (``runner.py``) against a
:class:`~vc.scenario.language.target.ScenarioTarget` and what it records (``trace.py``: the recorder,
its history queries and the trace files a run writes as it finishes).  It imports the language and
nothing of the outputs or the distribution.
"""
