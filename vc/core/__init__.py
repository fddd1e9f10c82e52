"""The NC core: a deterministic simulated SINUMERIK-style NC, one package per NC function.

Layers, from the top; a package imports only packages below it (import-linter keeps it so):

1. ``nck``            the NCK, the mode group, manual retraction, the alarm area (DB100)
2. ``channel``        the channel and its referencing order
3. ``spindle`` | ``retraction`` | ``transforms`` | ``auxiliary`` | ``fixed_stop`` | ``gantry``   independent of one
   another
4. ``referencing``    the axis referencing state machine
5. ``program``        program text, interpreter, sync actions and the commands they produce
6. ``interpolation``  path, circle, tool path, thread cutting
7. ``kinematics`` | ``axis``   pure transform math; machine axes

The base modules beside the packages (``alarms``, ``interface_map``, ``nc_memory``,
``overrides``, ``state_machine``) import no package of vc/core.  ``state_machine`` is how a
function declares its state machine beside its State enum for observers; ``nck/state_view.py``
publishes every instance through ``Nck.state_view()``.
"""
