"""The step kinds of the scenario language, one module per family; the table of all of them is
:mod:`vc.scenario.steps.table` (``STEPS``)."""
