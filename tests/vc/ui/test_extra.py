"""Without the extra ``ui``, ``vc serve --ui`` says what to install before anything runs."""

from __future__ import annotations

import importlib.util

import pytest

from vc.cli.main import main
from vc.ui import missing_ui_extra


def test_a_missing_extra_is_named_before_anything_runs(monkeypatch: pytest.MonkeyPatch,
                                                      capsys: pytest.CaptureFixture[str]) -> None:
    assert missing_ui_extra() is None  # the test extras bring it
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *rest: None if name == "uvicorn" else real(name))
    said = missing_ui_extra()
    assert said is not None and "uvicorn" in said and "vc-harness[ui]" in said and "starlette" not in said
    assert main(["serve", "--machine", "turn_mill", "--modbus", "127.0.0.1:0", "--ui"]) == 2
    assert "pip install 'vc-harness[ui]'" in capsys.readouterr().err
