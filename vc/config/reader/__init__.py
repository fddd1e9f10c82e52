"""The machine reader in its parts, one responsibility a module (``vc.config.loader`` runs them)::

    YAML document --reading--> LocatedMachine --overrides--> LocatedMachine --checking--> problems
                   (reading.py, blocks.py)     (overrides.py)                 (checking.py)
                                                             --building--> MachineConfig (building.py)

* ``located``: the machine as read, before its rules are checked: every value with its mark.
* ``reading``: a machine file's document into a located machine: its top level, axes,
  channels and plant I/O.  Each value is checked alone as it is read (a key the reader does
  not know, a value of the wrong type or out of the manual's range): what cannot be read
  cannot be kept.
* ``blocks``: the blocks of one instance that the file and the overrides both write: machine
  data, an axis's ``sim:``, ``plant:`` and ``drive:``, the DC link's parameters.
* ``overrides``: a scenario's ``machine_data:`` over the located machine, index by index and
  key by key, with the scenario's marks.
* ``checking``: the rules that relate values to each other, after the overrides (spindle
  numbers, limits, gearboxes and chucks against their I/O, channel and geometry axes, the
  synchronous pair, the master spindle, generator operation, the IPO cycle, CAN).
* ``building``: the frozen :class:`~vc.config.model.MachineConfig` of a machine without problems.

Every problem goes to one :class:`~vc.located_yaml.Problems` with its ``file:line:column``.
"""
