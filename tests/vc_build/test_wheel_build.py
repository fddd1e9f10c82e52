"""setup.py's builds keep to their own manifest: a wheel built from a checkout leaves the editable
install's ``vc_build/compiled.json`` (and its extensions) as they are, and carries a manifest of
its own that says which build it is.  And the build says what it does on the terminal of whoever
runs ``pip -q`` (here a pseudo-terminal), which pip's own output would not show.

The checkout is a copy of this one with an editable build's manifest and extension shim in it; a
real ``pip wheel`` builds it.  The pure build runs as it is (``VC_BUILD=pure``).  The compiled build
would take minutes to compile: there a stand-in ``mypyc.build.mypycify`` that compiles nothing
(on ``PYTHONPATH`` ahead of the real one) lets setup.py take its compiled path in seconds - the
manifest handling around the compiler is what is tested, not mypyc."""

from __future__ import annotations

import fcntl
import json
import os
import shutil
import subprocess
import sys
import sysconfig
import termios
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("vc", "interfaces", "plc_stub", "fmu", "vc_build", "plc_awlsim", "awlsimhw_vcmodbus")
EDITABLE_MANIFEST = '{"format": 1, "opt_level": "3", "modules": {"vc.core.alarms": "an editable build"}}\n'
NO_COMPILER = "def mypycify(*args, **kwargs):\n    return []  # compiles nothing: the test is about the manifests\n"


@pytest.fixture
def checkout(tmp_path: Path) -> Path:
    """A copy of the sources as an editable compiled install leaves them: its manifest, a shim."""
    source = tmp_path / "checkout"
    source.mkdir()
    for name in ("pyproject.toml", "README.md", "setup.py"):
        shutil.copyfile(ROOT / name, source / name)
    for package in PACKAGES:
        shutil.copytree(ROOT / package, source / package,
                        ignore=shutil.ignore_patterns("__pycache__", "*.so", "compiled.json"))
    (source / "vc_build" / "compiled.json").write_text(EDITABLE_MANIFEST, encoding="utf-8")
    (source / "vc" / "core" / f"alarms{sysconfig.get_config_var('EXT_SUFFIX')}").write_bytes(b"a shim")
    return source


def _wheel(checkout: Path, tmp_path: Path, **environment: str) -> tuple[dict[str, object], str]:
    """``pip wheel -q --no-deps`` of the checkout run from a terminal (a pseudo-terminal as the
    session's controlling terminal, as an interactive shell has); the manifest the wheel carries
    and what the terminal showed."""
    wheels = tmp_path / "wheels"
    env = {**os.environ, **environment}
    master, slave = os.openpty()

    def controlling_terminal() -> None:  # in the child, after setsid (start_new_session)
        fcntl.ioctl(slave, termios.TIOCSCTTY, 0)

    try:
        done = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-build-isolation", "--no-deps", "-q",
                               "-w", str(wheels), str(checkout)], env=env, capture_output=True, text=True,
                              timeout=300, start_new_session=True, pass_fds=(slave,),
                              preexec_fn=controlling_terminal)  # one ioctl in the child, no locks taken
    finally:
        os.close(slave)
    terminal = _drain(master)
    assert done.returncode == 0, done.stderr
    (wheel,) = wheels.glob("vc_harness-*.whl")
    with zipfile.ZipFile(wheel) as archive:
        manifest: dict[str, object] = json.loads(archive.read("vc_build/compiled.json"))
    return manifest, terminal


def _drain(master: int) -> str:
    os.set_blocking(master, False)
    chunks = []
    while True:
        try:
            chunk = os.read(master, 4096)
        except (BlockingIOError, OSError):  # nothing more; EIO once every writer has closed it
            break
        if not chunk:
            break
        chunks.append(chunk)
    os.close(master)
    return b"".join(chunks).decode(errors="replace")


def _untouched(checkout: Path) -> None:
    assert (checkout / "vc_build" / "compiled.json").read_text(encoding="utf-8") == EDITABLE_MANIFEST
    assert (checkout / "vc" / "core" / f"alarms{sysconfig.get_config_var('EXT_SUFFIX')}").read_bytes() == b"a shim"


def test_a_pure_wheel_leaves_the_editable_manifest_and_says_why_it_is_pure(checkout: Path, tmp_path: Path) -> None:
    manifest, terminal = _wheel(checkout, tmp_path, VC_BUILD="pure")
    _untouched(checkout)
    assert manifest == {"format": 1, "modules": {}, "pure": "installed with VC_BUILD=pure"}
    assert "vc-harness: installing the pure-Python build (VC_BUILD=pure)" in terminal


def test_a_compiled_wheel_leaves_the_editable_manifest_and_says_it_compiles(checkout: Path, tmp_path: Path) -> None:
    if shutil.which((sysconfig.get_config_var("CC") or "cc").split()[0]) is None:
        if os.environ.get("VC_REQUIRE_GCC"):
            pytest.fail("no C compiler, and VC_REQUIRE_GCC is set")
        pytest.skip("no C compiler: setup.py takes the pure path")  # the pure test above covers that one
    stand_in = tmp_path / "stand_in" / "mypyc"
    stand_in.mkdir(parents=True)
    (stand_in / "__init__.py").write_text("")
    (stand_in / "build.py").write_text(NO_COMPILER)
    path = os.pathsep.join([str(stand_in.parent), os.environ.get("PYTHONPATH", "")])
    manifest, terminal = _wheel(checkout, tmp_path, PYTHONPATH=path, VC_BUILD="")
    _untouched(checkout)
    modules = manifest["modules"]
    assert isinstance(modules, dict) and "vc.core.alarms" in modules and "pure" not in manifest
    # said before mypyc starts, through pip -q
    assert f"vc-harness: compiling {len(modules)} modules with mypyc - about a minute" in terminal
