"""Every exception class the project defines derives from the one root, ``interfaces.errors.VcError``."""

from __future__ import annotations

import importlib
import inspect
import pkgutil

import pytest

from interfaces.errors import VcError

PACKAGES = ("interfaces", "vc", "plc_stub", "fmu", "vc_build", "plc_awlsim", "awlsimhw_vcmodbus")
NOT_PYTHON = {"fmu._vc_fmi"}  # the FMU's C binary: it travels with the package and is never imported
# BaseExceptions on purpose: the wall-clock bound of the file campaign must pass every
# ``except Exception`` of the code under test, and so must Ctrl-C (a KeyboardInterrupt that carries
# the results of the scenarios that finished).
NOT_AN_ERROR = {"vc.bench.robustness.files._Hang", "vc.scenario.run.runner.RunInterrupted"}


def _modules() -> list[str]:
    names = []
    for package_name in PACKAGES:
        package = importlib.import_module(package_name)
        names.append(package_name)
        names.extend(info.name for info in pkgutil.walk_packages(package.__path__, package_name + ".")
                     if info.name not in NOT_PYTHON)
    return names


def _exception_classes() -> dict[str, type[BaseException]]:
    found: dict[str, type[BaseException]] = {}
    for name in _modules():
        try:
            module = importlib.import_module(name)
        except ModuleNotFoundError as missing:  # a module of an optional extra that is not installed
            if (missing.name or "").split(".")[0] in PACKAGES:
                raise
            continue
        for class_name, value in vars(module).items():
            if inspect.isclass(value) and issubclass(value, BaseException) and value.__module__ == name:
                found[f"{name}.{class_name}"] = value
    return found


@pytest.fixture(scope="module")
def exception_classes() -> dict[str, type[BaseException]]:
    return _exception_classes()


def test_every_exception_class_derives_from_the_root(exception_classes: dict[str, type[BaseException]]) -> None:
    assert len(exception_classes) > 30  # the walk found the project's exceptions
    without = {name for name, cls in exception_classes.items() if not issubclass(cls, VcError)}
    assert without == NOT_AN_ERROR


def test_a_standard_base_is_kept_beside_the_root(exception_classes: dict[str, type[BaseException]]) -> None:
    """``except ValueError`` (or KeyError, LookupError ...) still catches what it caught before."""
    from interfaces.signals import UnknownSignalError
    from vc.located_yaml import InputLimitError

    assert issubclass(exception_classes["interfaces.address.AddressError"], ValueError)
    assert issubclass(UnknownSignalError, KeyError) and issubclass(UnknownSignalError, VcError)
    assert str(UnknownSignalError("DB99")) == "DB99"  # its own message, not KeyError's quoted key
    assert issubclass(exception_classes["interfaces.links.inprocess.UnknownPlcProgram"], LookupError)
    import yaml

    assert issubclass(InputLimitError, yaml.YAMLError)


def test_an_unknown_signal_writes_its_suggestion_only_when_it_is_read() -> None:
    import pickle

    from interfaces.catalog import load_catalog
    from interfaces.signals import InterfaceLayout, UnknownSignalError, expand

    written = []

    def message() -> str:
        written.append(1)
        return "unknown signal 'X1.x'; did you mean X1.y?"

    error = UnknownSignalError(message)
    assert written == []
    assert str(error) == error.message == "unknown signal 'X1.x'; did you mean X1.y?" and written == [1]
    again = pickle.loads(pickle.dumps(error))
    assert str(again) == str(error) and isinstance(again, KeyError)
    catalog = expand(load_catalog(), InterfaceLayout(("CHAN1",), ("X1", "Z1")))
    with pytest.raises(UnknownSignalError) as caught:
        catalog.resolve("X1.basic.in.enc1Synchronised")
    assert "did you mean X1.basic.in.enc1Synchronized" in str(caught.value)
