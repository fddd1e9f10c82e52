"""The soak part: ``vc serve --realtime`` with the built-in PLC over Modbus for minutes.

The resident memory (RSS) of the server and of the PLC is sampled every :data:`SAMPLE_S` after a
warm-up (the first tenth of the run, at most a minute); the growth is the last sample against the
first, for the larger of the two.  The row also gives the overruns of the whole run and the
alarms raised (none are due: the PLC scans throughout).
"""

from __future__ import annotations

import time as wallclock

from vc.bench.robustness.campaign import CampaignSettings, Row, Say
from vc.bench.robustness.processes import ServedNc, final_pacing, growth_pct

SAMPLE_S = 10.0
WARM_UP_MAX_S = 60.0


def run_soak(settings: CampaignSettings, say: Say) -> Row:
    """The part's row (module docstring)."""
    seconds = 60 * settings.soak_minutes
    warm_up = min(WARM_UP_MAX_S, seconds / 10)
    sample_s = min(SAMPLE_S, max(0.5, seconds / 20))
    samples: list[tuple[int, int]] = []
    with ServedNc(["--realtime", "--stats", "60"]) as served:
        began = wallclock.monotonic()
        wallclock.sleep(warm_up)
        while wallclock.monotonic() - began < seconds and not served.crashes():
            samples.append(served.rss_kb())
            wallclock.sleep(min(sample_s, max(0.0, seconds - (wallclock.monotonic() - began))))
        samples.append(served.rss_kb())
        crashes = served.crashes()
    first, last = samples[0], samples[-1]
    server, plc = growth_pct(first[0], last[0]), growth_pct(first[1], last[1])
    pacing = final_pacing(served.serve)
    if pacing is None:  # it printed no statistics at its end: count it as a crash
        crashes += 1
    alarms = sorted({line.split("alarm ")[1].split()[0] for line in served.serve.lines if "  alarm " in line})
    say(f"  soak: {len(samples)} samples; server RSS {first[0]} -> {last[0]} kB ({server:+.2f} %), PLC {first[1]} ->"
        f" {last[1]} kB ({plc:+.2f} %); {pacing}; alarms: {', '.join(alarms) or 'none'}")
    return Row(f"Soak (vc serve --realtime, plc_stub over Modbus, {settings.soak_minutes:g} min)",
               inputs=pacing.cycles if pacing else 0, crashes=crashes, tracebacks=served.tracebacks(),
               rss_growth_pct=max(server, plc, key=abs), overruns=str(pacing) if pacing else "-",
               notes=f"RSS server {first[0]} -> {last[0]} kB ({server:+.2f} %), PLC {first[1]} -> {last[1]} kB"
                     f" ({plc:+.2f} %); NC at {pacing.share_pct if pacing else 0:.1f} % of real time; alarms:"
                     f" {', '.join(alarms) or 'none'}")
