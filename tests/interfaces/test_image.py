"""The process image's direction-wise copies: the bound copy a PLC scan repeats copies exactly the
ranges it was given, into the buffers the accessors hold, and counts as a write."""

from interfaces.image import ProcessImage, RangeCopy


def _images() -> tuple[ProcessImage, ProcessImage]:
    source = ProcessImage({"DB21": 8, "Q": 2})
    target = ProcessImage({"DB21": 8, "Q": 2})
    source.areas["DB21"][:] = bytes(range(1, 9))
    source.areas["Q"][:] = b"\xaa\x55"
    return target, source


def test_a_range_copy_copies_its_ranges_and_nothing_else() -> None:
    target, source = _images()
    held = target.areas["DB21"]  # an accessor bound before the copy keeps seeing the image
    RangeCopy(target, source, [("DB21", 2, 5), ("Q", 1, 2)]).run()
    assert bytes(held) == bytes([0, 0, 3, 4, 5, 0, 0, 0])
    assert bytes(target.areas["Q"]) == b"\x00\x55"


def test_a_range_copy_sees_every_later_change_of_its_source_and_counts_as_a_write() -> None:
    target, source = _images()
    copy = RangeCopy(target, source, [("DB21", 0, 8)])
    copy.run()
    version = target.version
    source.areas["DB21"][7] = 0xFF
    copy.run()
    assert target.areas["DB21"][7] == 0xFF
    assert target.version == version + 1


def test_a_range_copy_does_what_copy_from_does() -> None:
    ranges = [("DB21", 0, 3), ("DB21", 6, 8), ("Q", 0, 2)]
    target, source = _images()
    twin, _ = _images()
    RangeCopy(target, source, ranges).run()
    twin.copy_from(source, ranges)
    assert target.snapshot() == twin.snapshot()
