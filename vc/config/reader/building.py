"""The frozen :class:`~vc.config.model.MachineConfig` of a machine as read, once it has no problem
(vc/config/reader/checking.py found none): machine data per level instance, the axes in machine
axis order (interface DB31..), the channels in file order (DB21..), a spindle's gearbox and chuck.

Building reports nothing: every value it takes has been checked, and what it derives from
several values (a channel's axis names, a gearbox) is what checking checked.
"""

from __future__ import annotations

import dataclasses

from interfaces.signals import NCK_INSTANCE
from vc.config import md_dictionary as mdd
from vc.config.machine_data import MachineData
from vc.config.model import AxisConfig, ChannelConfig, ChuckPlant, GearboxPlant, IndexDivision, MachineConfig
from vc.config.reader.located import AxisEntry, ChannelEntry, Instance, LocatedMachine


def build_machine(machine: LocatedMachine, source: str) -> MachineConfig:
    """``machine`` as the configuration the harness runs; ``source`` is how its file was named."""
    return MachineConfig(
        name=machine.name,
        source=source,
        nck=MachineData(NCK_INSTANCE, machine.nck.values()),
        channels=tuple(_channel(number, entry) for number, entry in enumerate(machine.channels.values(), start=1)),
        axes=tuple(_axis(number, entry, machine.nck) for number, entry in enumerate(machine.axes.values(), start=1)),
        plant_io=machine.plant_io,
        plc_parameters=machine.plc_parameters,
        plc_cycle_ipo=machine.plc_cycle_ipo,
        dc_link=machine.dc_link,
        can=machine.can.config,
        plant=machine.plant,
        plc_alarms=machine.plc_alarms,
    )


def _axis(number: int, entry: AxisEntry, nck: Instance) -> AxisConfig:
    plant = dataclasses.replace(entry.plant, gearbox=_gearbox(entry), chuck=_chuck(entry))
    return AxisConfig(entry.name, number, MachineData(entry.name, entry.data.values()),
                      bool(entry.data.value(mdd.IS_ROT_AX)), entry.spindle_number, entry.sim, plant, entry.drive,
                      index_division(entry.data, nck))


def index_division(data: Instance, nck: Instance) -> IndexDivision | None:
    """The index positions MD30500 assigns the axis (seed 003 L13546-13605, §11.3.2), None for no
    indexing axis; checking has made sure they ascend and lie in a modulo axis's range."""
    assignment = int(data.value(mdd.INDEX_AX_ASSIGN_POS_TAB))
    if assignment in (1, 2):
        length, table = (mdd.INDEX_AX_LENGTH_POS_TAB_1, mdd.INDEX_AX_POS_TAB_1) if assignment == 1 else \
            (mdd.INDEX_AX_LENGTH_POS_TAB_2, mdd.INDEX_AX_POS_TAB_2)
        return IndexDivision(table=tuple(float(nck.value(table, n)) for n in range(int(nck.value(length)))))
    if assignment == 3:
        denominator = int(data.value(mdd.INDEX_AX_DENOMINATOR))
        modulo = bool(data.value(mdd.IS_ROT_AX)) and bool(data.value(mdd.ROT_IS_MODULO))
        numerator = float(data.value(mdd.MODULO_RANGE if modulo else mdd.INDEX_AX_NUMERATOR))  # L14210-14216
        return IndexDivision(offset=float(data.value(mdd.INDEX_AX_OFFSET)), spacing=numerator / denominator,
                             count=denominator if modulo else 0)
    return None


def _gearbox(entry: AxisEntry) -> GearboxPlant | None:
    if entry.gearbox_mark is None:
        return None
    written = entry.gearbox  # stages and shift_time: checking reports a gearbox without them
    engaged = written.get("engaged")
    return GearboxPlant(int(written["stages"].value), float(written["shift_time"].value),
                        int(engaged.value) if engaged is not None else 1)


def _chuck(entry: AxisEntry) -> ChuckPlant | None:
    if entry.chuck_mark is None:
        return None
    closed = entry.chuck.get("closed")  # travel_time: checking reports a chuck without it
    return ChuckPlant(float(entry.chuck["travel_time"].value), bool(closed.value) if closed is not None else True)


def _channel(number: int, entry: ChannelEntry) -> ChannelConfig:
    geometry_names = entry.geometry_names()
    return ChannelConfig(entry.name, number, MachineData(entry.name, entry.data.values()), tuple(entry.axes),
                         entry.program_names(), geometry_names,
                         tuple([entry.geometry_axis(index) for index in range(len(geometry_names))]))
