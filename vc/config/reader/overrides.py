"""A scenario's ``machine_data:`` over a machine as read: ``{instance: {key: value}}`` with instance
an axis name, a channel name or ``NC``.

The blocks are read as the machine file's are (vc/config/reader/blocks.py), with the scenario's
marks, and replace the file's values index by index.  An axis may also carry ``sim:``,
``plant:`` and ``drive:`` (the keys written replace the file's), ``NC`` the keys of the DC link
(``dc_link:``).  A scenario matrix's machine data settings (vc/scenario/language/variants.py) come here
as the overrides of each variant.  The rules across the machine are checked afterwards, on the
machine with its overrides (checking.py).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

from interfaces.signals import NCK_INSTANCE
from vc.config.machine_data import MdLevel, shown
from vc.config.reader.blocks import AXIS_EXTRA_KEYS, DC_LINK_KEYS, BlockReader
from vc.config.reader.located import Instance, LocatedMachine, Marks
from vc.located_yaml import Mark, Problems

NCK_EXTRA_KEYS = ("dc_link",)  # the NC's block of a scenario's overrides: its drive line-up's DC link too
_PLACE_IN_OVERRIDES = {MdLevel.NCK: "for NC", MdLevel.CHANNEL: "for a channel", MdLevel.AXIS: "for an axis"}


def apply_overrides(machine: LocatedMachine, overrides: Any, fallback: Mark, problems: Problems) -> None:
    """Read ``overrides`` over ``machine``; ``fallback`` is the mark of values without one (a
    mapping built in code)."""
    blocks = BlockReader(problems, Marks(fallback))
    marks = blocks.marks
    if not isinstance(overrides, dict):
        blocks.add(marks.of(overrides), f"machine_data: expected a mapping of axis, channel or NC names to"
                                        f" machine data, got {shown(overrides)}")
        return
    for name, raw in overrides.items():
        instance = machine.instance(name)
        if instance is None:
            known = ", ".join([*machine.axes, *machine.channels, NCK_INSTANCE])
            blocks.add(marks.key(overrides, name),
                       f"machine_data: {machine.name or 'the machine'} has no axis"
                       f" or channel '{name}' (it has {known})")
            continue
        if raw is not None and not isinstance(raw, dict):
            blocks.add(marks.value(overrides, name),
                       f"machine_data.{name}: expected a mapping of machine"
                       f" data, got {shown(raw)}")
            continue
        block: Mapping[str, Any] = raw or {}
        scratch = Instance(instance.level, name, marks.key(overrides, name))
        axis_entry = machine.axes.get(name)
        blocks.machine_data(block, scratch, _PLACE_IN_OVERRIDES,
                            extra_keys=AXIS_EXTRA_KEYS if axis_entry is not None
                            else NCK_EXTRA_KEYS if name == NCK_INSTANCE else ())
        if name == NCK_INSTANCE and "dc_link" in block:
            _override_dc_link(machine, blocks, block["dc_link"], marks.value(block, "dc_link"))
        if axis_entry is not None:
            # the slide and the switches of this one test: where the cam sits, where the
            # scale's first mark is, where the slide stands at power-on
            blocks.axis_extras(axis_entry, block, f"machine_data.{name}")
        for number, entries in scratch.written.items():
            instance.written.setdefault(number, {}).update(entries)


def _override_dc_link(machine: LocatedMachine, blocks: BlockReader, raw: Any, mark: Mark) -> None:
    """``NC: {dc_link: {...}}``: the keys written replace the machine file's."""
    values = blocks.parameters(raw, mark, "machine_data.NC.dc_link", DC_LINK_KEYS)
    if machine.dc_link is None:
        blocks.add(mark, f"machine_data.NC.dc_link: {machine.name or 'the machine'} has no dc_link: section")
    elif values:
        machine.dc_link = dataclasses.replace(machine.dc_link, **values)
