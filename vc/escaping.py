"""Text from files and simulations made safe for each kind of output, one function per kind.

A scenario's name, a file's path, a varied value or a value echoed in a message is written by
whoever wrote the file: it may hold control characters.  Passed on raw they repaint a terminal
(``\\x1b[2K\\x1b[1G`` turns a FAIL line into a PASS line, ``\\r`` overwrites it, a line break starts
a line that looks like the tool's own), make a JUnit file ill-formed XML (XML 1.0 has no
``\\x1b``, not even as ``&#27;``), and break the lines of CSV, VCD and GTKWave files.

Every output writes such text through its kind's function here, and nowhere else:

=============  =====================  ============================================================
output         function               what it keeps
=============  =====================  ============================================================
terminal       :func:`terminal`       nothing: one line (``lines=True``: the line breaks of a
                                      text of several lines, such as a traceback)
JUnit XML      :func:`junit`          line breaks and tabs (ElementTree escapes ``<``, ``&``)
CSV            :func:`csv_field`      nothing (the csv module quotes the field)
VCD, GTKWave   :func:`vcd`            nothing: a name or a comment is one line
HTML           :func:`html_text`      line breaks (inside ``<pre>``), with ``<``, ``&``, quotes
                                      escaped as entities
diagrams       :func:`image_text`     nothing: one line drawn (a font has no glyph for ``\x1b``)
=============  =====================  ============================================================

A character taken out is written as its Python escape (``\\x1b``, ``\\n``, ``\\u202e``), so what was
there stays readable.  Taken out: the C0 controls, DEL and the C1 controls, the line and
paragraph separators, and the bidirectional overrides and isolates (they reorder what a
terminal or a browser shows: "Trojan source").  Text without any of them is returned as it is;
escaping twice changes nothing.
"""

from __future__ import annotations

import html
import re

# C0, DEL, C1; the line and paragraph separators; the bidi embeddings, overrides and isolates
_ANY = re.compile("[\x00-\x1f\x7f-\x9f\u2028\u2029\u202a-\u202e\u2066-\u2069]")
_BUT_LINE_BREAKS = re.compile("[\x00-\x09\x0b-\x1f\x7f-\x9f\u2028\u2029\u202a-\u202e\u2066-\u2069]")
_BUT_LINE_BREAKS_AND_TABS = re.compile("[\x00-\x08\x0b-\x1f\x7f-\x9f\u2028\u2029\u202a-\u202e\u2066-\u2069]")


_SHORT = {"\t": "\\t", "\n": "\\n", "\r": "\\r"}


def _shown(match: re.Match[str]) -> str:
    character = match.group()
    code = ord(character)
    return _SHORT.get(character) or (f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}")


def terminal(text: str, lines: bool = False) -> str:
    """For the console: one line, or (``lines``) the text's own lines and nothing else."""
    return (_BUT_LINE_BREAKS if lines else _ANY).sub(_shown, text)


def junit(text: str) -> str:
    """For a JUnit file's attributes and texts: what XML 1.0 can hold and a CI page shows as written."""
    return _BUT_LINE_BREAKS_AND_TABS.sub(_shown, text)


def csv_field(text: str) -> str:
    """For a field of a CSV trace: one line."""
    return _ANY.sub(_shown, text)


def vcd(text: str) -> str:
    """For a name or comment of a VCD file or a GTKWave save file: one line."""
    return _ANY.sub(_shown, text)


def html_text(text: str) -> str:
    """For an HTML page's text and attribute values (quoted): entities for markup, escapes for controls."""
    return html.escape(_BUT_LINE_BREAKS.sub(_shown, text), quote=True)


def image_text(text: str) -> str:
    """For text drawn into a timing diagram: one line, every character one a font can draw."""
    return _ANY.sub(_shown, text)
