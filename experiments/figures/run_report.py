#!/usr/bin/python3
"""One self-contained HTML page of a navaid full-device run (docs/run-report.md).

Reads the run folder that `navaid run --device` writes: summary.json (required), estimates.csv,
plans.csv, cues.csv, speech.wav, stages.csv, latency.csv and the figures topview.png,
map/topview.png, cues.png. Every figure and the audio are embedded as data URIs, so the page opens
anywhere without the folder. An inline script checks, once the page has loaded, that every image
decoded and the audio is playable, and records script errors: <body data-status="ok|failed"
data-figures="loaded/total" data-errors="N">, which the tests read in headless Chromium.
"""
import argparse
import base64
import csv
import html
import io
import json
import os
import sys
from decimal import Decimal, InvalidOperation

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

MODE_COLOURS = {"initializing": "tab:gray", "rgbd-vio": "tab:blue", "vio": "tab:orange",
                "imu-only": "tab:red", "lost": "black"}
OUTCOME_MARKERS = {"sent": ("o", "tab:blue"), "refreshed": (".", "tab:cyan"), "switched-off": ("x", "tab:gray"),
                   "spoken": ("s", "tab:green"), "interrupted": ("X", "tab:red"), "preempted": ("v", "tab:red"),
                   "rate-limited": ("|", "tab:orange"), "duplicate": ("_", "tab:orange"),
                   "expired": ("d", "tab:purple"), "finished": ("+", "tab:olive")}
STAGES = ["frontend_ms", "estimator_ms", "mapping_ms", "planning_ms", "interaction_ms"]
# Summary sections shown first and by name; every other object in summary.json follows generically.
LEAD_SECTIONS = ["device", "pipeline", "ate", "latency", "stages"]
MAX_SPOKEN_ROWS = 200

# Registered first in <head> so that an error in any later script is counted.
CHECK_SCRIPT = """
window.__errors = [];
window.addEventListener('error', function (e) {
  if (e instanceof ErrorEvent) window.__errors.push(String(e.message));  // a figure that fails to load is counted below
}, true);
window.addEventListener('unhandledrejection', function (e) { window.__errors.push(String(e.reason)); });
"""

# Media elements delay the document's load event until they have data or an error, so at `load`
# an <audio> without .error has decoded its source.
LOAD_SCRIPT = """
window.addEventListener('load', function () {
  var images = Array.prototype.slice.call(document.images);
  var audios = Array.prototype.slice.call(document.getElementsByTagName('audio'));
  var loaded = images.filter(function (i) { return i.complete && i.naturalWidth > 0; }).length;
  loaded += audios.filter(function (a) { return !a.error; }).length;
  var total = images.length + audios.length;
  var body = document.body;
  body.dataset.figures = loaded + '/' + total;
  body.dataset.errors = String(window.__errors.length);
  body.dataset.status = (loaded === total && window.__errors.length === 0) ? 'ok' : 'failed';
  var line = document.getElementById('check');
  if (line) line.textContent = 'page check: ' + body.dataset.status + ', figures ' + body.dataset.figures +
      ', script errors ' + body.dataset.errors;
});
"""

STYLE = """
body { font-family: sans-serif; margin: 1.5em auto; max-width: 1100px; color: #222; }
h1 { font-size: 1.5em; } h2 { font-size: 1.2em; margin-top: 1.6em; border-bottom: 1px solid #ccc; }
h3 { font-size: 1em; margin-bottom: 0.2em; }
table { border-collapse: collapse; margin: 0.5em 0; font-size: 0.9em; }
td, th { border: 1px solid #ccc; padding: 2px 6px; text-align: left; vertical-align: top; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
img { max-width: 100%; } figure { margin: 0.8em 0; } figcaption { font-size: 0.85em; color: #555; }
details { margin: 0.8em 0; } summary { cursor: pointer; color: #555; }
.note { color: #777; font-style: italic; } #check { color: #777; font-size: 0.8em; }
"""


class RunError(Exception):
    """A run folder the report cannot be made from; the message names the file."""


def read_csv(path):
    """The rows of `path` as dicts, or None when the file is absent. Quoted fields (cue texts with
    commas) are handled by the csv module; short rows leave their missing columns at None."""
    if not os.path.isfile(path):
        return None
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def number(text):
    """A finite float, or None for an empty, missing or non-numeric field."""
    try:
        v = float(text)
    except (TypeError, ValueError):
        return None
    return v if np.isfinite(v) else None


def integer(text):
    try:
        return int(text)
    except (TypeError, ValueError):
        return None


def figure_uri(fig):
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=100, bbox_inches="tight")
    plt.close(fig)
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")


def file_uri(path, mime):
    with open(path, "rb") as f:
        return "data:" + mime + ";base64," + base64.b64encode(f.read()).decode("ascii")


def image(uri, caption):
    return '<figure><img src="%s" alt="%s"><figcaption>%s</figcaption></figure>' % (
        uri, html.escape(caption, quote=True), html.escape(caption))


def note(text):
    return '<p class="note">%s</p>' % html.escape(text)


def scalar_html(v):
    if isinstance(v, bool) or v is None:
        return html.escape(str(v).lower() if isinstance(v, bool) else "null")
    if isinstance(v, float):
        return "%.4g" % v
    return html.escape(str(v))


def value_html(v):
    if isinstance(v, dict):
        return table_html(v) if v else note("empty")
    if isinstance(v, list):
        if any(isinstance(x, (dict, list)) for x in v):
            return "".join(value_html(x) for x in v[:12]) + (" &hellip; (%d)" % len(v) if len(v) > 12 else "")
        shown = ", ".join(scalar_html(x) for x in v[:12])
        return shown + (" &hellip; (%d)" % len(v) if len(v) > 12 else "") if v else "[]"
    return scalar_html(v)


def table_html(obj):
    rows = "".join("<tr><th>%s</th><td>%s</td></tr>" % (html.escape(str(k)), value_html(v)) for k, v in obj.items())
    return "<table>%s</table>" % rows


def matrix_html(obj):
    """An object of objects of scalars (summary.json's stages) as one table: a row per key."""
    columns = []
    for row in obj.values():
        columns += [c for c in row if c not in columns]
    head = "<tr><th></th>%s</tr>" % "".join("<th>%s</th>" % html.escape(c) for c in columns)
    body = "".join("<tr><th>%s</th>%s</tr>" % (html.escape(str(k)), "".join(
        '<td class="num">%s</td>' % value_html(row.get(c, "")) for c in columns)) for k, row in obj.items())
    return "<table>%s%s</table>" % (head, body)


def is_matrix(v):
    return isinstance(v, dict) and v and all(
        isinstance(r, dict) and r and not any(isinstance(x, (dict, list)) for x in r.values()) for r in v.values())


def summary_section(summary):
    scalars = {k: v for k, v in summary.items() if not isinstance(v, (dict, list))}
    parts = [table_html(scalars)] if scalars else []
    def section(key):
        v = summary[key]
        return "<h3>%s</h3>%s" % (html.escape(key), matrix_html(v) if is_matrix(v) else value_html(v))

    parts += [section(k) for k in LEAD_SECTIONS if k in summary]
    rest = [k for k, v in summary.items() if k not in LEAD_SECTIONS and isinstance(v, (dict, list))]
    if rest:
        # Folded, so that the figures stay near the top of a long summary.
        parts.append("<details><summary>more from summary.json: %s</summary>%s</details>" % (
            html.escape(", ".join(rest)), "".join(section(k) for k in rest)))
    return "".join(parts)


def parse_path(text):
    points = []
    for pair in (text or "").split():
        x, _, y = pair.partition(":")
        if number(x) is not None and number(y) is not None:
            points.append((float(x), float(y)))
    return points


def run_origin_ns(estimates, stages):
    """The run's first sensor time (ns): the common origin of every time axis in the page."""
    times = [integer(r.get("t_ns")) for r in (estimates or []) + (stages or [])]
    times = [t for t in times if t is not None]
    return min(times) if times else None


def seconds_since(t_s, origin_ns):
    """Cue time (decimal seconds on the sensor clock) relative to the origin, exactly."""
    try:
        return float(Decimal(t_s) - Decimal(origin_ns) / Decimal(10**9))
    except (InvalidOperation, TypeError, ValueError):
        return None


def trajectory_section(run):
    estimates = read_csv(os.path.join(run, "estimates.csv"))
    plans = read_csv(os.path.join(run, "plans.csv"))
    out = []
    if estimates is None:
        out.append(note("no estimates.csv: no trajectory to draw"))
    points = [(number(r.get("px")), number(r.get("py")), r.get("mode") or "?") for r in estimates or []]
    points = [p for p in points if p[0] is not None and p[1] is not None]
    if estimates is not None and not points:
        out.append(note("estimates.csv has no position rows: no trajectory to draw"))
    if points:
        fig, ax = plt.subplots(figsize=(7, 5))
        modes = list(MODE_COLOURS) + sorted({p[2] for p in points} - set(MODE_COLOURS))
        for mode in modes:
            xy = [(p[0], p[1]) for p in points if p[2] == mode]
            if xy:
                # Modes this script does not know still appear, in the default colour cycle.
                ax.plot([q[0] for q in xy], [q[1] for q in xy], ".", ms=4, color=MODE_COLOURS.get(mode), label=mode,
                        zorder=3)
        drawn = 0
        for p in plans or []:
            path = parse_path(p.get("path"))
            if len(path) >= 2:
                ax.plot([q[0] for q in path], [q[1] for q in path], "-", lw=0.6, color="tab:green", alpha=0.4,
                        label="plans" if drawn == 0 else None, zorder=1)  # under the track they were made from
                drawn += 1
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("x in W [m]")
        ax.set_ylabel("y in W [m]")
        ax.set_title("estimated trajectory by mode, with %d plans" % drawn)
        ax.legend(loc="best", fontsize=8)
        out.append(image(figure_uri(fig), "Trajectory (W) coloured by estimator mode; the plans' paths in green"))
    if plans:
        found = sum(1 for p in plans if p.get("status") == "found")
        times = [t for t in (number(p.get("time_ms")) for p in plans) if t is not None]
        out.append(table_html({"plans": len(plans), "found": found, "not found": len(plans) - found,
                               "median planning time [ms]": float(np.median(times)) if times else "-"}))
    elif plans is None:
        out.append(note("no plans.csv: this device's chain makes no plans"))
    else:
        out.append(note("plans.csv has no rows: no plan was made"))
    return "".join(out)


def cue_section(run, origin_ns):
    cues = read_csv(os.path.join(run, "cues.csv"))
    if cues is None:
        return note("no cues.csv: the run made no cues")
    if origin_ns is None:
        firsts = [Decimal(r["t_s"]) for r in cues if number(r.get("t_s")) is not None]
        origin_ns = int(min(firsts) * 10**9) if firsts else 0
    out = []
    timed = [(seconds_since(r.get("t_s"), origin_ns), r) for r in cues]
    timed = [(t, r) for t, r in timed if t is not None]
    if timed:
        fig, ax = plt.subplots(figsize=(9, 3))
        outcomes = list(OUTCOME_MARKERS) + sorted({r.get("outcome") or "?" for _, r in timed} - set(OUTCOME_MARKERS))
        for outcome in outcomes:
            rows = [(t, number(r.get("priority"))) for t, r in timed if (r.get("outcome") or "?") == outcome]
            if rows:
                marker, colour = OUTCOME_MARKERS.get(outcome, ("*", None))
                ax.plot([t for t, _ in rows], [p if p is not None else 0 for _, p in rows], marker, color=colour,
                        ls="none", label=outcome)
        ax.set_xlabel("time since the run's first frame [s]")
        ax.set_ylabel("priority")
        ax.set_title("cue events by outcome")
        ax.legend(loc="upper right", fontsize=7, ncol=5)
        out.append(image(figure_uri(fig), "Cue timeline: every cue event by its priority and outcome"))
    else:
        out.append(note("cues.csv has no cue events"))
    spoken = [(t, r) for t, r in timed if r.get("outcome") == "spoken"]
    if spoken:
        rows = "".join('<tr><td class="num">%.2f</td><td>%s</td></tr>' % (t, html.escape(r.get("text") or ""))
                       for t, r in spoken[:MAX_SPOKEN_ROWS])
        out.append("<h3>Spoken</h3><table><tr><th>t [s]</th><th>text</th></tr>%s</table>" % rows)
        if len(spoken) > MAX_SPOKEN_ROWS:
            out.append(note("the first %d of %d spoken messages" % (MAX_SPOKEN_ROWS, len(spoken))))
    elif timed:
        out.append(note("nothing was spoken"))
    return "".join(out)


def speech_section(run, summary):
    wav = os.path.join(run, "speech.wav")
    if os.path.isfile(wav):
        return '<p>Everything spoken:</p><audio controls preload="auto" src="%s"></audio>' % file_uri(wav, "audio/wav")
    device = summary.get("device") if isinstance(summary.get("device"), dict) else {}
    if "speech" in device:
        return note("no speech: run with device.speech %s" % device["speech"])
    return note("no speech: the run wrote no speech.wav")


def p99(values):
    return float(np.percentile(values, 99))


def timing_section(run, origin_ns):
    stages = read_csv(os.path.join(run, "stages.csv"))
    out = []
    series = []
    for name in STAGES:
        pairs = [(integer(r.get("t_ns")), number(r.get(name))) for r in stages or []]
        pairs = [(t, v) for t, v in pairs if t is not None and v is not None]
        if pairs:
            series.append((name[:-len("_ms")], pairs))
    if series:
        origin = origin_ns if origin_ns is not None else min(t for _, pairs in series for t, _ in pairs)
        fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 3.5), gridspec_kw={"width_ratios": [3, 1]})
        for name, pairs in series:
            ax.plot([(t - origin) * 1e-9 for t, _ in pairs], [v for _, v in pairs], lw=0.8, label=name)
        ax.set_xlabel("time since the run's first frame [s]")
        ax.set_ylabel("ms per frame")
        ax.set_title("time per frame by stage")
        ax.legend(fontsize=7)
        xs = np.arange(len(series))
        bx.bar(xs - 0.2, [float(np.median([v for _, v in p])) for _, p in series], width=0.4, label="median")
        bx.bar(xs + 0.2, [p99([v for _, v in p]) for _, p in series], width=0.4, label="p99")
        bx.set_xticks(xs)
        bx.set_xticklabels([name for name, _ in series], rotation=45, ha="right", fontsize=7)
        bx.set_ylabel("ms")
        bx.legend(fontsize=7)
        out.append(image(figure_uri(fig), "Time per frame by stage; median and p99 per stage"))
    elif stages is None:
        out.append(note("no stages.csv: no per-frame timing"))
    else:
        out.append(note("stages.csv has no timed frames"))
    latency = read_csv(os.path.join(run, "latency.csv"))
    values = [v for v in (number(r.get("latency_ms")) for r in latency or []) if v is not None]
    if values:
        top = p99(values)
        fig, ax = plt.subplots(figsize=(6, 3))
        ax.hist(values, bins=min(40, max(5, len(values) // 2)), color="tab:blue")
        ax.axvline(top, color="tab:red", ls="--", label="p99 %.1f ms" % top)
        ax.set_xlabel("sensor frame -> cue [ms]")
        ax.set_ylabel("cues")
        ax.set_title("frame-to-cue latency (%d cues)" % len(values))
        ax.legend(fontsize=8)
        out.append(image(figure_uri(fig), "Latency from a sensor frame's arrival to the cue it caused"))
    elif latency is None:
        out.append(note("no latency.csv: no frame-to-cue latency"))
    else:
        out.append(note("no cue reached the user: no latency to show"))
    return "".join(out)


def load_summary(run):
    path = os.path.join(run, "summary.json")
    if not os.path.isfile(path):
        raise RunError("%s not found: not a navaid run folder" % path)
    try:
        with open(path) as f:
            summary = json.load(f)
    except (OSError, UnicodeDecodeError, ValueError) as e:
        raise RunError("%s: not readable JSON: %s" % (path, e))
    if not isinstance(summary, dict):
        raise RunError("%s: expected a JSON object at the top level" % path)
    return summary


def report(run, summary):
    estimates = read_csv(os.path.join(run, "estimates.csv"))
    stages = read_csv(os.path.join(run, "stages.csv"))
    origin_ns = run_origin_ns(estimates, stages)
    device = summary.get("device") if isinstance(summary.get("device"), dict) else {}
    title = "navaid run: %s on %s" % (device.get("name", "estimator"),
                                      os.path.basename(str(summary.get("recording", ""))) or "?")

    parts = ["<h2>Summary</h2>", summary_section(summary)]
    parts.append("<h2>Trajectory and plans</h2>" + trajectory_section(run))
    parts.append("<h2>Map</h2>")
    shown = False
    for name, caption in [("topview.png", "Top view of the estimated track against ground truth"),
                          (os.path.join("map", "topview.png"), "The map's top view")]:
        path = os.path.join(run, name)
        if os.path.isfile(path):
            parts.append(image(file_uri(path, "image/png"), caption))
            shown = True
    if not shown:
        parts.append(note("no topview.png or map/topview.png (run without figures, or a device that does not map)"))
    parts.append("<h2>Cues</h2>")
    if os.path.isfile(os.path.join(run, "cues.png")):
        parts.append(image(file_uri(os.path.join(run, "cues.png"), "image/png"), "Actuators, cues and speech"))
    parts.append(cue_section(run, origin_ns))
    parts.append(speech_section(run, summary))
    parts.append("<h2>Timing</h2>")
    parts.append(timing_section(run, origin_ns))

    return ("<!DOCTYPE html><html><head><meta charset=\"utf-8\"><script>%s</script><title>%s</title>"
            "<style>%s</style></head><body><h1>%s</h1><p id=\"check\"></p>%s<script>%s</script></body></html>") % (
        CHECK_SCRIPT, html.escape(title), STYLE, html.escape(title), "".join(parts), LOAD_SCRIPT)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", help="run folder of navaid run --device")
    parser.add_argument("--out", help="HTML file to write (default RUN/report.html)")
    args = parser.parse_args()
    try:
        summary = load_summary(args.run)
    except RunError as e:
        print("run_report: %s" % e, file=sys.stderr)
        return 1
    out_file = args.out or os.path.join(args.run, "report.html")
    page = report(args.run, summary)
    if os.path.dirname(out_file):
        os.makedirs(os.path.dirname(out_file), exist_ok=True)
    with open(out_file, "w") as f:
        f.write(page)
    return 0


if __name__ == "__main__":
    sys.exit(main())
