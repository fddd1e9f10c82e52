"""Where a machine file is: a path, or the name of a machine the package ships.

The project's machines (turn_mill, mill_3axis, mill_5axis, gantry_mill) are package data of ``vc``
(``vc/machines/*.yaml``), so ``--machine turn_mill`` finds its file from any directory after a
plain ``pip install``.  That directory is their only home: the repository's scenario library
reaches the same files through the symbolic link ``scenarios/machines -> ../vc/machines``, so a
scenario's ``machine: ../machines/turn_mill.yaml`` keeps working.

A reference is taken as a path when a file of that name exists or when it looks like one (it
holds a directory separator or ends in ``.yaml`` / ``.yml``); otherwise as the name of a
packaged machine.
"""

from __future__ import annotations

import os
from importlib import resources
from importlib.abc import Traversable

DEFAULT_MACHINE = "turn_mill"
MACHINE_SUFFIXES = (".yaml", ".yml")
_PACKAGE = __name__.rsplit(".", 2)[0]  # "vc", also when an FMU bundles this module inside its own package


def _packaged() -> Traversable:
    return resources.files(_PACKAGE).joinpath("machines")


def packaged_machines() -> list[str]:
    """The names of the machines the package ships, sorted."""
    return sorted(entry.name.removesuffix(".yaml") for entry in _packaged().iterdir()
                  if entry.name.endswith(".yaml"))


def looks_like_a_path(reference: str) -> bool:
    return "/" in reference or os.sep in reference or reference.endswith(MACHINE_SUFFIXES)


def machine_file(reference: str) -> str | None:
    """The file ``reference`` names: a path as given, or the packaged machine of that name;
    None when it is neither an existing file, nor a path, nor a packaged machine."""
    if os.path.exists(reference) or looks_like_a_path(reference):
        return reference
    packaged = _packaged().joinpath(f"{reference}.yaml")
    return str(packaged) if packaged.is_file() else None


def unknown_machine(reference: str) -> str:
    """The message for a reference :func:`machine_file` cannot resolve."""
    return (f"no machine file '{reference}' and no packaged machine of that name (packaged:"
            f" {', '.join(packaged_machines())})")
