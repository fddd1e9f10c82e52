# The compiled build runs only where it matches the sources (vc_build's guard, before any module).
from vc_build import install as _install_build_guard

_install_build_guard()
