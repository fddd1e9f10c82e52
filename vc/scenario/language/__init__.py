"""The scenario language: files read, checked and built into :class:`~vc.scenario.language.model.Scenario`
objects, before anything runs.

The model (``model.py``) and its loader (``loader.py``), the step kinds as one table (``steps/``: each
kind's checker and the runner that says what it does), conditions and ``${...}`` placeholders
(``expressions.py``, ``placeholders.py``), ``vary:`` and campaign files (``variants.py``), names
(``quantities.py``), durations and expected values (``durations.py``, ``values.py``), and
:class:`~vc.scenario.language.target.ScenarioTarget` (``target.py``): the machine a step acts on, as a
protocol the composed machine implements.  Nothing here runs a scenario, writes a file or knows a
worker (the ``layers`` contract of ``vc.scenario`` in pyproject.toml).
"""
