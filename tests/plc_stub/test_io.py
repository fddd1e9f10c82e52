"""The PLC program's typed access to its image (plc_stub/io.py): a group of the NC's outputs read
whole, through the group's declaration in interfaces/signal_groups.py."""

from __future__ import annotations

import pytest

from interfaces.catalog import load_catalog
from interfaces.image import ProcessImage
from interfaces.plant_io import PlantIoMap
from interfaces.plc import PlcEnvironment
from interfaces.signal_groups import AxisRequests, AxisStatus, RetractionStatus
from interfaces.signals import InterfaceLayout, expand
from plc_stub.io import PlcIo


@pytest.fixture
def io() -> PlcIo:
    catalog = expand(load_catalog(), InterfaceLayout(channels=("CHAN1", "CHAN2"), axes=("X1", "Z1")))
    return PlcIo(PlcEnvironment(catalog, PlantIoMap.from_mapping({}, ("X1", "Z1")), 0.01, {}))


def write(io: PlcIo, image: ProcessImage, name: str) -> None:
    ref = io.environment.catalog.resolve(name)
    image.write(ref, 1)


def test_a_group_reads_the_nc_outputs_of_its_instance(io: PlcIo) -> None:
    channel_2 = io.input_group(RetractionStatus, "CHAN2")
    channel_1 = io.input_group(RetractionStatus, "CHAN1")
    write(io, io.image, "CHAN2.basic.in.jogRetractDataAvailable")
    write(io, io.image, "CHAN2.piService.in.retracError")
    assert channel_2.read() == RetractionStatus(data_available=True, active=False, done=False, error=True)
    assert channel_1.read() == RetractionStatus()


def test_a_group_reads_what_its_single_signals_read(io: PlcIo) -> None:
    status = io.input_group(AxisStatus, "Z1")
    for name in ("Z1.basic.in.posFineReached", "Z1.drive.in.enabled", "Z1.basic.in.enc2Synchronized"):
        write(io, io.image, name)
    read = status.read()
    assert (read.exact_fine, read.drive_enabled, read.referenced_2) == (True, True, True)
    assert read.exact_coarse == io.input("Z1.basic.in.posCoarseReached").value is False


def test_a_group_of_the_plc_outputs_is_not_an_input(io: PlcIo) -> None:
    with pytest.raises(TypeError, match="AxisRequests is an output of the PLC"):
        io.input_group(AxisRequests, "X1")
