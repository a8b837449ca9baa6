#!/usr/bin/env python3
"""Helper of bench/accuracy.sh: one row of the Cornell-box table, and its plot.

  accuracy_cornell.py row CSV LABEL ESTIMATOR RAYS RESULT.h5 VERIFY.log SECONDS...
      appends to CSV (header first if new) a row: the setting, the median wall time of the
      runs (SECONDS, one per run) and, per channel, what `radiosity verify` printed (measured,
      reference noise, measured with the noise taken out, the file's estimate, estimate /
      measured, coverage) and the solve's own headline from the result's attributes (whole
      estimate, sampling and discretisation parts, rays per patch reached).
  accuracy_cornell.py plot CSV SVG
      log-log SVG of the measured error (noise taken out, largest channel) against the median
      wall time, one curve per estimator, the default and --target-error runs as points.
Needs h5py (Debian's python3-h5py).
"""
import csv
import math
import re
import statistics
import sys

from csv_rows import append_row

CHANNELS = ("red", "green", "blue")
VERIFY_ROWS = {
    "measured (result against reference)": "measured",
    "reference noise": "noise",
    "measured, noise taken out": "corrected",
    "file's own estimate of its error": "estimate",
    "estimate / measured (noise taken out)": "ratio",
    "coverage: |B - B_ref| <= 2 sigma": "coverage",
}


def parse_verify(path):
    values = {}
    with open(path) as log:
        for line in log:
            for label, key in VERIFY_ROWS.items():
                if line.strip().startswith(label):
                    # one cell per channel: a number, or n/a / - where there is none
                    cells = line.strip()[len(label):].replace("%", "").split()[-3:]
                    numbers = [float(c) if re.match(r"^[-+0-9.eE]+$", c) else "" for c in cells]
                    if key == "coverage":
                        numbers = [x / 100 if x != "" else "" for x in numbers]
                    values[key] = numbers
    return values


def attributes(path):
    import h5py

    with h5py.File(path, "r") as f:
        a = dict(f.attrs)
    row = {"rays_reached": int(a["rays_per_patch"]),
           "estimator_used": re.search(r"estimator = (\w+)", a["options"].decode()).group(1),
           "seconds_formfactors": a.get("time_formfactors", ""),
           "seconds_solve": a.get("time_solve", "")}
    for c in CHANNELS:
        row[f"solve_estimate_{c}"] = a.get(f"solve_error_estimate_B_{c}", "")
        row[f"solve_sampling_{c}"] = a.get(f"solve_sampling_error_B_{c}", "")
        row[f"solve_discretisation_{c}"] = a.get(f"solve_discretisation_error_B_{c}", "")
    return row


def make_row(out, label, estimator, rays, result, verify_log, seconds):
    seconds = [float(s) for s in seconds]
    row = {"setting": label, "estimator": estimator, "rays": rays,
           "wall_seconds": statistics.median(seconds),
           "wall_seconds_runs": " ".join(f"{s:.2f}" for s in seconds)}
    row.update(attributes(result))
    verified = parse_verify(verify_log)
    for key in VERIFY_ROWS.values():
        found = verified.get(key, [])
        for c, x in zip(CHANNELS, found if len(found) == 3 else [""] * 3):
            row[f"{key}_{c}"] = x
    append_row(out, row)


def plot(table, svg):
    rows = list(csv.DictReader(open(table)))
    points = []
    for r in rows:
        if any(r[f"corrected_{c}"] in ("", None) for c in CHANNELS):
            continue
        error = max(float(r[f"corrected_{c}"]) for c in CHANNELS)
        if not error > 0:
            continue  # within the reference's noise: nothing to put on a log axis
        points.append((r["setting"], r["estimator_used"], float(r["wall_seconds"]), error,
                       int(r["rays_reached"])))
    xs = [p[2] for p in points]
    ys = [p[3] for p in points]
    x0, x1 = 10 ** math.floor(math.log10(min(xs))), 10 ** math.ceil(math.log10(max(xs)))
    y0, y1 = 10 ** math.floor(math.log10(min(ys))), 10 ** math.ceil(math.log10(max(ys)))
    W, H, L, R, T, B = 640, 420, 70, 20, 30, 50

    def px(x):
        return L + (W - L - R) * (math.log10(x) - math.log10(x0)) / (math.log10(x1) - math.log10(x0))

    def py(y):
        return H - B - (H - T - B) * (math.log10(y) - math.log10(y0)) / (math.log10(y1) - math.log10(y0))

    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" '
           f'font-family="sans-serif" font-size="12">',
           f'<rect width="{W}" height="{H}" fill="white"/>',
           f'<text x="{W / 2}" y="18" text-anchor="middle">Cornell box: measured error of B '
           f'(worst channel) against wall time</text>']
    d = x0
    while d <= x1 * 1.0001:
        out.append(f'<line x1="{px(d):.1f}" y1="{T}" x2="{px(d):.1f}" y2="{H - B}" stroke="#ddd"/>')
        out.append(f'<text x="{px(d):.1f}" y="{H - B + 16}" text-anchor="middle">{d:g}</text>')
        d *= 10
    d = y0
    while d <= y1 * 1.0001:
        out.append(f'<line x1="{L}" y1="{py(d):.1f}" x2="{W - R}" y2="{py(d):.1f}" stroke="#ddd"/>')
        out.append(f'<text x="{L - 6}" y="{py(d) + 4:.1f}" text-anchor="end">{d:g}</text>')
        d *= 10
    out.append(f'<line x1="{L}" y1="{py(0.01):.1f}" x2="{W - R}" y2="{py(0.01):.1f}" '
               f'stroke="#999" stroke-dasharray="4 3"/>')
    out.append(f'<text x="{W / 2}" y="{H - 12}" text-anchor="middle">wall time of the solve (s, '
               f'median of the runs)</text>')
    out.append(f'<text transform="translate(16 {H / 2}) rotate(-90)" text-anchor="middle">'
               f'verify: measured, noise taken out</text>')
    colours = {"hemisphere": "#E69F00", "mis": "#0072B2"}
    for k, estimator in enumerate(("hemisphere", "mis")):
        curve = sorted((p for p in points if p[0] == estimator), key=lambda p: p[2])
        if curve:
            path = " ".join(f"{px(p[2]):.1f},{py(p[3]):.1f}" for p in curve)
            out.append(f'<polyline points="{path}" fill="none" stroke="{colours[estimator]}" '
                       f'stroke-width="2"/>')
            for p in curve:
                out.append(f'<circle cx="{px(p[2]):.1f}" cy="{py(p[3]):.1f}" r="3" '
                           f'fill="{colours[estimator]}"/>')
                out.append(f'<text x="{px(p[2]) + 5:.1f}" y="{py(p[3]) - 5:.1f}" '
                           f'font-size="10">{p[4]}</text>')
        out.append(f'<line x1="{W - 170}" y1="{T + 14 + 16 * k}" x2="{W - 150}" '
                   f'y2="{T + 14 + 16 * k}" stroke="{colours[estimator]}" stroke-width="2"/>')
        out.append(f'<text x="{W - 145}" y="{T + 18 + 16 * k}">{estimator} (rays marked)</text>')
    for p in points:
        if p[0] not in ("hemisphere", "mis"):
            out.append(f'<rect x="{px(p[2]) - 4:.1f}" y="{py(p[3]) - 4:.1f}" width="8" '
                       f'height="8" fill="#009E73"/>')
            out.append(f'<text x="{px(p[2]) + 6:.1f}" y="{py(p[3]) + 14:.1f}" '
                       f'font-size="10">{p[0]}</text>')
    out.append("</svg>")
    with open(svg, "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    if sys.argv[1] == "row":
        make_row(*sys.argv[2:8], sys.argv[8:])
    elif sys.argv[1] == "plot":
        plot(sys.argv[2], sys.argv[3])
    else:
        sys.exit(__doc__)
