"""Power-on wiring: every part of the NCK built complete from the machine data."""

from __future__ import annotations

from core_rig import machine

from interfaces.catalog import load_catalog
from interfaces.image import ProcessImage
from interfaces.signals import expand
from vc.core.alarms import AlarmList
from vc.core.nc_memory import NcMemory
from vc.core.nck.power_on import power_on


def test_every_channel_gets_its_spindles_esr_couplings_and_polygon_turning() -> None:
    config = machine()
    catalog = load_catalog()
    image = ProcessImage(expand(catalog, config.layout).area_sizes)
    used: set[str] = set()
    parts = power_on(config, catalog, image, NcMemory(), AlarmList(), 0.002, None, used)
    assert [axis.name for axis in parts.axes] == [axis.name for axis in config.axes]
    (channel,) = parts.channels
    assert sorted(channel.spindles) == ["SP1", "SP2", "SP3"] == sorted(parts.spindle_of)
    assert channel.esr is not None and channel.couplings is parts.couplings
    assert channel.polygon is not None and parts.polygons == [channel.polygon]
    assert set(parts.esr.drives) == {axis.name for axis in parts.axes}
    assert parts.inclined_axes == ([channel.inclined] if channel.inclined is not None else [])
    assert set(parts.retractions) == {"CHAN1"}
    # every signal looked up is a catalogue symbol of the NC's own data blocks
    assert "<Axis>.basic.in.enc1Synchronized" in used and "<Nc>.basic.out.emergencyStop" in used
