"""The step kinds of the scenario language, one module per family; the table of all of them is
:mod:`vc.scenario.language.steps.table` (``STEPS``)."""
