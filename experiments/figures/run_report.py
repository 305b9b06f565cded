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

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MODE_COLOURS = {"initializing": "tab:gray", "rgbd-vio": "tab:blue", "vio": "tab:orange",
                "imu-only": "tab:red", "lost": "black"}
OUTCOME_MARKERS = {"sent": ("o", "tab:blue"), "refreshed": (".", "tab:cyan"), "switched-off": ("x", "tab:gray"),
                   "spoken": ("s", "tab:green"), "interrupted": ("X", "tab:red"), "preempted": ("v", "tab:red"),
                   "rate-limited": ("|", "tab:orange"), "duplicate": ("_", "tab:orange"),
                   "expired": ("d", "tab:purple"), "finished": ("+", "tab:olive")}
STAGES = ["frontend_ms", "estimator_ms", "mapping_ms", "planning_ms", "interaction_ms"]

CHECK_SCRIPT = """
window.__errors = [];
window.addEventListener('error', function (e) {
  if (e instanceof ErrorEvent) window.__errors.push(String(e.message));  // a figure that fails to load is counted below
}, true);
window.addEventListener('unhandledrejection', function (e) { window.__errors.push(String(e.reason)); });
"""

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
table { border-collapse: collapse; margin: 0.5em 0; font-size: 0.9em; }
td, th { border: 1px solid #ccc; padding: 2px 6px; text-align: left; vertical-align: top; }
img { max-width: 100%; } .note { color: #777; font-style: italic; } #check { color: #777; font-size: 0.8em; }
"""


def read_csv(path):
    if not os.path.isfile(path):
        return None
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def number(text):
    try:
        return float(text)
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


def value_html(v):
    if isinstance(v, dict):
        return table_html(v)
    if isinstance(v, list):
        if len(v) > 12:
            return html.escape(", ".join(str(x) for x in v[:12])) + " &hellip; (%d)" % len(v)
        return html.escape(", ".join(str(x) for x in v))
    if isinstance(v, float):
        return "%.4g" % v
    return html.escape(str(v))


def table_html(obj):
    rows = "".join("<tr><th>%s</th><td>%s</td></tr>" % (html.escape(str(k)), value_html(v)) for k, v in obj.items())
    return "<table>%s</table>" % rows


def parse_path(text):
    points = []
    for pair in (text or "").split():
        x, _, y = pair.partition(":")
        if number(x) is not None and number(y) is not None:
            points.append((float(x), float(y)))
    return points


def trajectory_section(run):
    estimates = read_csv(os.path.join(run, "estimates.csv"))
    plans = read_csv(os.path.join(run, "plans.csv")) or []
    if not estimates:
        return note("no estimates.csv: no trajectory to draw")
    fig, ax = plt.subplots(figsize=(7, 5))
    for mode, colour in MODE_COLOURS.items():
        xs = [float(r["px"]) for r in estimates if r["mode"] == mode]
        ys = [float(r["py"]) for r in estimates if r["mode"] == mode]
        if xs:
            ax.plot(xs, ys, ".", ms=3, color=colour, label=mode)
    drawn = 0
    for p in plans:
        points = parse_path(p.get("path"))
        if len(points) >= 2:
            ax.plot([q[0] for q in points], [q[1] for q in points], "-", lw=0.6, color="tab:green", alpha=0.5,
                    label="plans" if drawn == 0 else None)
            drawn += 1
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x in W [m]")
    ax.set_ylabel("y in W [m]")
    ax.set_title("estimated trajectory by mode, with %d plans" % drawn)
    ax.legend(loc="best", fontsize=8)
    out = [image(figure_uri(fig), "Trajectory (W) coloured by estimator mode; the plans' paths in green")]
    if plans:
        found = sum(1 for p in plans if p.get("status") == "found")
        times = sorted(number(p.get("time_ms")) or 0.0 for p in plans)
        out.append(table_html({"plans": len(plans), "found": found, "not found": len(plans) - found,
                               "median planning time [ms]": times[len(times) // 2] if times else 0.0}))
    else:
        out.append(note("no plans.csv rows: this device's chain makes no plans"))
    return "".join(out)


def cue_section(run):
    cues = read_csv(os.path.join(run, "cues.csv"))
    if cues is None:
        return note("no cues.csv")
    out = []
    t0 = min(float(r["t_s"]) for r in cues) if cues else 0.0
    if cues:
        fig, ax = plt.subplots(figsize=(9, 3))
        for outcome, (marker, colour) in OUTCOME_MARKERS.items():
            rows = [r for r in cues if r["outcome"] == outcome]
            if rows:
                ax.plot([float(r["t_s"]) - t0 for r in rows], [number(r["priority"]) or 0 for r in rows], marker,
                        color=colour, ls="none", label=outcome)
        ax.set_xlabel("time from the first cue [s]")
        ax.set_ylabel("priority")
        ax.set_title("cue events by outcome")
        ax.legend(loc="upper right", fontsize=7, ncol=5)
        out.append(image(figure_uri(fig), "Cue timeline: every cue event by its priority and outcome"))
    else:
        out.append(note("no cue events"))
    spoken = [r for r in cues if r["outcome"] == "spoken"][:200]
    if spoken:
        rows = "".join("<tr><td>%.2f</td><td>%s</td></tr>" % (float(r["t_s"]) - t0, html.escape(r["text"])) for r in spoken)
        out.append("<table><tr><th>t [s]</th><th>spoken</th></tr>%s</table>" % rows)
    return "".join(out)


def timing_section(run):
    stages = read_csv(os.path.join(run, "stages.csv"))
    out = []
    if stages:
        t0 = int(stages[0]["t_ns"])
        t = [(int(r["t_ns"]) - t0) * 1e-9 for r in stages]
        fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 3.5), gridspec_kw={"width_ratios": [3, 1]})
        medians, p99s, names = [], [], []
        for name in STAGES:
            values = [number(r.get(name)) for r in stages]
            pairs = [(x, v) for x, v in zip(t, values) if v is not None]
            if not pairs:
                continue
            ax.plot([p[0] for p in pairs], [p[1] for p in pairs], lw=0.8, label=name[:-3])
            vs = sorted(p[1] for p in pairs)
            names.append(name[:-3])
            medians.append(vs[len(vs) // 2])
            p99s.append(vs[min(len(vs) - 1, int(0.99 * (len(vs) - 1) + 0.5))])
        ax.set_xlabel("time [s]")
        ax.set_ylabel("ms per frame")
        ax.set_title("time per frame by stage")
        ax.legend(fontsize=7)
        xs = range(len(names))
        bx.bar([x - 0.2 for x in xs], medians, width=0.4, label="median")
        bx.bar([x + 0.2 for x in xs], p99s, width=0.4, label="p99")
        bx.set_xticks(list(xs))
        bx.set_xticklabels(names, rotation=45, ha="right", fontsize=7)
        bx.legend(fontsize=7)
        out.append(image(figure_uri(fig), "Time per frame by stage; median and p99 per stage"))
    else:
        out.append(note("no stages.csv"))
    latency = read_csv(os.path.join(run, "latency.csv"))
    values = sorted(v for v in (number(r.get("latency_ms")) for r in latency or []) if v is not None)
    if values:
        p99 = values[min(len(values) - 1, int(0.99 * (len(values) - 1) + 0.5))]
        fig, ax = plt.subplots(figsize=(6, 3))
        ax.hist(values, bins=min(40, max(5, len(values) // 2)), color="tab:blue")
        ax.axvline(p99, color="tab:red", ls="--", label="p99 %.1f ms" % p99)
        ax.set_xlabel("sensor frame -> cue [ms]")
        ax.set_ylabel("cues")
        ax.legend(fontsize=8)
        out.append(image(figure_uri(fig), "Latency from a sensor frame's arrival to the cue it caused"))
    else:
        out.append(note("no cue reached the user: no latency to show"))
    return "".join(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", help="run folder of navaid run --device")
    parser.add_argument("--out", help="HTML file to write (default RUN/report.html)")
    args = parser.parse_args()
    summary_file = os.path.join(args.run, "summary.json")
    if not os.path.isfile(summary_file):
        print("run_report: %s not found: not a navaid run folder" % summary_file, file=sys.stderr)
        return 1
    with open(summary_file) as f:
        summary = json.load(f)
    out_file = args.out or os.path.join(args.run, "report.html")
    device = summary.get("device", {})
    title = "navaid run: %s on %s" % (device.get("name", "estimator"), os.path.basename(str(summary.get("recording", ""))))

    parts = ["<h2>Summary</h2>"]
    scalars = {k: v for k, v in summary.items() if not isinstance(v, (dict, list))}
    parts.append(table_html(scalars))
    for key in ("device", "pipeline", "ate", "latency", "guidance", "cues", "mapping"):
        if key in summary:
            parts.append("<h3>%s</h3>%s" % (html.escape(key), value_html(summary[key])))
    parts.append("<h2>Trajectory and plans</h2>" + trajectory_section(args.run))
    figures = [("topview.png", "Top view of the estimated track against ground truth"),
               (os.path.join("map", "topview.png"), "The map's top view")]
    parts.append("<h2>Map</h2>")
    shown = False
    for name, caption in figures:
        path = os.path.join(args.run, name)
        if os.path.isfile(path):
            parts.append(image(file_uri(path, "image/png"), caption))
            shown = True
    if not shown:
        parts.append(note("no map figure (run without figures, or a device that does not map)"))
    parts.append("<h2>Cues</h2>")
    if os.path.isfile(os.path.join(args.run, "cues.png")):
        parts.append(image(file_uri(os.path.join(args.run, "cues.png"), "image/png"), "Actuators, cues and speech"))
    parts.append(cue_section(args.run))
    wav = os.path.join(args.run, "speech.wav")
    if os.path.isfile(wav):
        parts.append('<p>Everything spoken:</p><audio controls preload="auto" src="%s"></audio>' % file_uri(wav, "audio/wav"))
    else:
        parts.append(note("no speech: the device speaks no messages (device.speech off or text)"))
    parts.append("<h2>Timing</h2>")
    if "stages" in summary:
        parts.append(value_html(summary["stages"]))
    parts.append(timing_section(args.run))

    page = ("<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>%s</title><script>%s</script>"
            "<style>%s</style></head><body><h1>%s</h1><p id=\"check\"></p>%s<script>%s</script></body></html>") % (
        html.escape(title), CHECK_SCRIPT, STYLE, html.escape(title), "".join(parts), LOAD_SCRIPT)
    with open(out_file, "w") as f:
        f.write(page)
    return 0


if __name__ == "__main__":
    sys.exit(main())
