"""The operator panel in the browser for ``vc serve --ui``: the machine control panel, the machine,
MDA and a watch and force table, served by Starlette and uvicorn (the optional extra ``ui``).

``panel``    what the page may show and do, from the machine file: its keys and switches (the plant's
             operator points), which signals may be forced by whom (pure, no I/O)
``bridge``   the NC's side: an observer of the served simulation that takes the page's commands
             between two IPO cycles and publishes what the page shows, rate-limited, only while a
             page is open
``server``   the page's side: the web server in its own thread and event loop
``static``   the page itself (HTML, CSS and JavaScript in one file, shipped in the wheel: no CDN)
"""

from __future__ import annotations

UI_EXTRA_MODULES = ("starlette", "uvicorn", "websockets")


def missing_ui_extra() -> str | None:
    """What is missing for ``--ui`` (None: nothing), said before anything runs."""
    import importlib.util

    missing = [name for name in UI_EXTRA_MODULES if importlib.util.find_spec(name) is None]
    if not missing:
        return None
    return (f"--ui needs the optional extra 'ui' ({', '.join(missing)} not installed):"
            " pip install 'vc-harness[ui]'")
