"""The signal catalogue files (``db2_plc_alarms.yaml``, ``db10_nck.yaml`` ... ``db31_axis.yaml``,
``db100_alarms.yaml``) and their loader.

Reading the packaged YAML files is the only file access of ``interfaces`` outside
``links/``; everything else builds on the parsed :class:`~interfaces.signals.Catalog`.
"""

from __future__ import annotations

from functools import lru_cache
from importlib import resources

import yaml

from interfaces.signals import Catalog

# libyaml's parser where PyYAML has it (the same safe constructor; the files are ten times faster to read)
_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
CATALOG_FILES = ("db2_plc_alarms.yaml", "db10_nck.yaml", "db11_mode_group.yaml", "db19_hmi.yaml", "db21_channel.yaml",
                 "db31_axis.yaml", "db100_alarms.yaml")


@lru_cache(maxsize=1)
def load_catalog() -> Catalog:
    """The packaged catalogue, parsed and checked once per process."""
    package = resources.files(__name__)
    documents = []
    for name in CATALOG_FILES:
        text = package.joinpath(name).read_text(encoding="utf-8")
        documents.append((f"interfaces/catalog/{name}", yaml.load(text, Loader=_LOADER)))
    return Catalog.from_documents(documents)
