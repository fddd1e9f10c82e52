"""Limits of what the harness reads from files, stated once.

Scenario files, machine files and part programs come from people and from generators.  An
input beyond one of these limits is refused as a problem with its location
(``file:line:column``), like any other mistake in a file: no input may make a run hang, fill
the memory, end in a traceback or pass a check that cannot fail.  Every limit lies far above
what a real file needs (the shipped files are quoted) and far below what would hurt.

======================  ===========  ==========================================================
limit                   value        why
======================  ===========  ==========================================================
MAX_FILE_BYTES          1 MiB        a YAML file or a part program; the largest shipped file has
                                     14 KB, and a megabyte of YAML takes the parser some 5 s.
                                     Only regular files are read (not /dev/zero, a FIFO, ...)
MAX_NESTING             64           collections inside one another in a YAML file; shipped
                                     files nest 6 deep, the parser recurses once per level
MAX_VALUES              100,000      values of a YAML file with every alias expanded; shipped
                                     files hold 617 at most, a "billion laughs" holds 10^9
MAX_INTEGER_DIGITS      20           digits of a whole number (a 64-bit value has up to 20);
                                     Python refuses to convert more than 4,300 anyway
MAX_MAGNITUDE           1e15         largest number the harness takes where no narrower range
                                     applies (expected values, conditions, values written,
                                     positions of the plant): below 2^53 every whole number is
                                     exact in a double, and no quantity of a machine (mm, deg,
                                     rev/min, s) comes near it
MIN_MD_MAGNITUDE        1e-12        smallest machine datum other than 0: nothing a control
                                     sets is finer, and dividing by 1e-320 gives infinity
MAX_DURATION_S          86,400 s     longest time in a scenario (one simulated day; the
                                     longest shipped one is 120 s)
MAX_EXPRESSION_CHARACTERS
                        4,096        characters of one condition or ``${...}`` placeholder; the
                                     longest shipped one has 221
MAX_EXPRESSION_NESTING  32           parentheses, brackets, ``not``, signs and ``abs`` inside one
                                     another in a condition or a placeholder; shipped ones nest
                                     3 deep
MAX_EXPRESSION_DEPTH    100          operators a value passes through from a leaf of a condition
                                     or a placeholder to its result (``a and b and c`` is 2 deep):
                                     the checker, the compiler and every evaluation recurse once
                                     per level; shipped conditions are 9 deep
MAX_RUN_VARIANTS        100,000      variants of one run (``vary:`` matrices and campaigns),
                                     counted before any is built; ``vc run --max-variants N``
                                     raises it.  The shipped campaign has 1,000; beyond this a
                                     typo (a long list in a product) is likelier than intent
MAX_RECORDING_BYTES     1 GiB        a session recording, decompressed: ``vc serve --record``
                                     stops there (``--record-limit`` lowers it; a busy PLC
                                     writes some 110 kB/s, an idle one a few), ``vc replay``
                                     refuses more (a gzip file of 2 MB may hold 2 GB)
MAX_RECORDING_LINE      8 MiB        one line of a recording: the header holds the machine and
                                     scenario files (1 MiB each at most), a row a program text
MAX_RECORDED_SECONDS    7 days       the cycle of a row, at the recording's IPO cycle: a replay
                                     runs every cycle up to it (10^30 would never end)
MAX_AREA_BYTES          65,536       bytes of one data block or I/O area in a recording's header
                                     (the largest shipped one has 400; DB numbers address 64 KiB)
MAX_JSON_NESTING        8            arrays and objects inside one another in a line of a
                                     recording or a coverage file's value; their readers'
                                     documents nest 5 deep
======================  ===========  ==========================================================

Conditions and placeholders share one reader (:mod:`vc.scenario.language.expressions`) and so these
bounds; the value of every step of a placeholder's arithmetic stays within ``MAX_MAGNITUDE``.

Numbers must also be finite everywhere: a YAML file holds no ``.inf`` or ``.nan``, and a
number written as text (``"1e400"``) that overflows is refused where it is read.
"""

from __future__ import annotations

MAX_FILE_BYTES = 1 << 20
MAX_NESTING = 64
MAX_VALUES = 100_000
MAX_INTEGER_DIGITS = 20
MAX_MAGNITUDE = 1e15
MIN_MD_MAGNITUDE = 1e-12
MAX_DURATION_S = 86_400
MAX_EXPRESSION_CHARACTERS = 4096
MAX_EXPRESSION_NESTING = 32
MAX_EXPRESSION_DEPTH = 100
MAX_RUN_VARIANTS = 100_000
MAX_RECORDING_BYTES = 1 << 30
MAX_RECORDING_LINE = 8 << 20
MAX_RECORDED_SECONDS = 7 * 86_400
MAX_AREA_BYTES = 65_536
MAX_JSON_NESTING = 8
