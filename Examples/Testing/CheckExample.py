#!/usr/bin/python3
"""Runs one example and checks what it printed and drew; compares the C++ and Python twins.

  CheckExample.py run NAME OUTDIR COMMAND...   runs COMMAND --data $TERROIR_DATA_DIR --out OUTDIR
                                               in an emptied OUTDIR, keeps its stdout in
                                               OUTDIR/stdout.txt and checks it (CHECKS below)
  CheckExample.py compare NAME DIR_A DIR_B     both runs printed the same report: the same lines,
                                               numbers equal to the last digit printed (and for
                                               RiversFromRain, the scores of `terroir validate`)

Pictures: every PNG an example must write is checked (size, not blank) and compared with the
user guide's copy, Documentation/images/examples/<file>, by the rendering tests' rule
(Testing/Python/TerroirImages.py: every pixel within 8 levels of a pixel within one pixel of it,
both ways, at most 16 pixels otherwise). On a difference the fresh image stays in OUTDIR; to
accept a new picture, look at it, then
  /usr/bin/python3 Testing/Rendering/CompactBaseline.py OUTDIR/<file> \\
      Documentation/images/examples/<file>
Environment: TERROIR_DATA_DIR (the bundled data), TERROIR_BIN_DIR (for `terroir validate`).
"""
import hashlib
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "Testing", "Python"))
from TerroirImages import DIFFERING_PIXELS, LEVELS, compare_images, read_rgb  # noqa: E402
GUIDE_IMAGES = os.path.normpath(os.path.join(HERE, "..", "..", "Documentation", "images",
                                             "examples"))
DATA = os.environ.get("TERROIR_DATA_DIR", os.path.join(HERE, "..", "..", "Data"))
SAGEHEN_CELLS = 786 * 720  # the bundled DEM has no no-data cell

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)


def numbers(line):
    return [float(x) for x in re.findall(r"-?\d+\.?\d*(?:e-?\d+)?", line)]


def line_with(text, prefix):
    for line in text.splitlines():
        if line.startswith(prefix):
            return line
    check(False, f"no line starting with {prefix!r}")
    return ""


def check_picture(out, name, size):
    """The PNG exists, has `size`, is not blank, and matches the guide's image."""
    path = os.path.join(out, name)
    if not os.path.isfile(path):
        check(False, f"{name}: not written")
        return
    pixels = read_rgb(path)
    height, width = pixels.shape[:2]
    check((width, height) == size, f"{name}: {width} x {height} pixels, expected {size}")
    rgb = pixels.reshape(-1, 3)
    colours = len(np.unique(rgb, axis=0))
    check(colours >= 16, f"{name}: only {colours} distinct colours (blank?)")
    check(rgb.astype(float).mean(axis=1).std() > 10.0, f"{name}: almost uniform (blank?)")
    baseline = os.path.join(GUIDE_IMAGES, name)
    if not os.path.isfile(baseline):
        check(False, f"{name}: no guide image {baseline}; look at {path} and copy it there")
        return
    differing, worst = compare_images(pixels, read_rgb(baseline))
    check(differing <= DIFFERING_PIXELS,
          f"{name}: differs from {baseline}: {differing} pixels more than {LEVELS} levels from "
          f"every pixel within one pixel (largest {worst}); see {path}")


def sun_declination(day_of_year):
    """Cooper (1969), degrees: good to about a degree, enough to catch a wrong date."""
    return 23.44 * math.sin(math.radians(360.0 * (284 + day_of_year) / 365.0))


def day_length(latitude, declination):
    """Hours between sunrise and sunset of the sun's centre, no refraction."""
    x = -math.tan(math.radians(latitude)) * math.tan(math.radians(declination))
    return 2.0 * math.degrees(math.acos(max(-1.0, min(1.0, x)))) / 15.0


# ---- one check per example: what would be wrong if the example were wrong --------------------

def check_slope_temperature(out, text):
    check(line_with(text, "grid:").startswith("grid: 786 x 720 cells of 10.0 m"), "grid line")
    zmin, zmax = numbers(line_with(text, "elevation:"))
    mean_slope, max_slope = numbers(line_with(text, "slope:"))
    tmin, tmean, tmax = numbers(line_with(text, "july temperature:"))
    check(1800 < zmin < zmax < 2800, f"elevation range {zmin}..{zmax} m (Sagehen: 1910..2676)")
    check(0 < mean_slope < max_slope < 90, f"slope mean {mean_slope}, max {max_slope}")
    # July at sea level 20 degC, 6.4 degC/km: the warmest cell is the lowest, the coldest the
    # highest.
    check(abs(tmax - (20 - 6.4 * zmin / 1000)) < 0.002, f"July max {tmax} vs lowest cell {zmin}")
    check(abs(tmin - (20 - 6.4 * zmax / 1000)) < 0.002, f"July min {tmin} vs highest cell {zmax}")
    check(tmin < tmean < tmax, "July mean inside its range")
    check_picture(out, "slope_map.png", (400, 400))
    check_picture(out, "temperature_july_relief.png", (400, 400))


def check_sun_hours(out, text):
    latitude = numbers(line_with(text, "valley:"))[2]
    check(39.3 < latitude < 39.6, f"valley latitude {latitude} (Sagehen Creek: 39.43 N)")
    rows = [numbers(line) for line in text.splitlines()
            if re.match(r"^(Jan|Feb|Mar|Apr|May|Jun|Jul|Aug|Sep|Oct|Nov|Dec) ", line)]
    check(len(rows) == 12, f"{len(rows)} month rows, expected 12")
    if len(rows) != 12:
        return
    mean = [r[0] for r in rows]
    insolation = [r[3] for r in rows]
    for m, (mu, low, high, _) in enumerate(rows):
        check(0 <= low <= mu <= high <= 24, f"month {m + 1}: min <= mean <= max")
    # Northern hemisphere, 15th of each month: more sun every month to June, less after.
    for series, what in ((mean, "mean hours"), (insolation, "insolation")):
        check(all(a < b for a, b in zip(series[:6], series[1:6])), f"{what} rise Jan..Jun")
        check(all(a > b for a, b in zip(series[5:], series[6:])), f"{what} fall Jun..Dec")
    for label, month, day_of_year in (("15 June", 6, 166), ("15 March", 3, 74),
                                      ("15 December", 12, 349)):
        steps, highest = numbers(line_with(text, f"sun path {label}:"))[1:3]
        decl = sun_declination(day_of_year)
        check(abs(highest - (90 - latitude + decl)) < 1.5,
              f"{label}: highest sun {highest} deg, noon elevation {90 - latitude + decl:.2f}")
        hours_up = steps * 10 / 60
        check(abs(hours_up - day_length(latitude, decl)) < 0.4,
              f"{label}: sun up {hours_up:.2f} h, day length {day_length(latitude, decl):.2f} h")
        # No cell can have more sun than the sky has.
        check(rows[month - 1][2] <= hours_up + 1e-3, f"{label}: max hours over the day length")
    check_picture(out, "sun_hours_december.png", (400, 400))
    check_picture(out, "sun_path.png", (480, 360))


def check_zones(out, text):
    k = int(numbers(line_with(text, "k-means:"))[0])
    rows = [line for line in text.splitlines() if re.match(r"^\s+\d+\s+#[0-9a-f]{6}\s", line)]
    check(k == 5 and len(rows) == k, f"{len(rows)} table rows, {k} zones, expected 5")
    cells = [int(line.split()[2]) for line in rows]
    shares = [float(line.split()[3]) for line in rows]
    colours = [line.split()[1] for line in rows]
    total_cells, total_share = numbers(line_with(text, "total "))
    check(sum(cells) == total_cells == SAGEHEN_CELLS,
          f"zone cells sum to {sum(cells)}, total {total_cells}, DEM {SAGEHEN_CELLS}")
    check(abs(sum(shares) - 100.0) < 0.003 and abs(total_share - 100.0) < 0.001,
          f"shares sum to {sum(shares)} %")
    for c, s in zip(cells, shares):
        check(abs(100.0 * c / SAGEHEN_CELLS - s) < 0.0006, f"share {s} % of {c} cells")
    check(len(set(colours)) == k, "every zone has its own colour")
    for line in rows:
        values = [float(x) for x in line.split()[4:]]
        slope, t_jan, t_jul = values[0], values[1], values[2]
        check(0 <= slope < 90, f"zone slope {slope}")
        # Every cell is 18 degC warmer in July than in January (sea level 20 and 2 degC).
        check(abs((t_jul - t_jan) - 18.0) < 0.002, f"zone July - January = {t_jul - t_jan}")
    check_picture(out, "zones_map.png", (400, 400))


def river_rows(text):
    rows = {}
    for line in text.splitlines():
        parts = line.split()
        if parts and parts[0] in ("waterflow", "D8") and len(parts) == 8:
            rows[parts[0]] = [float(x) for x in parts[1:]]
    return rows


def check_rivers(out, text):
    iterations = numbers(line_with(text, "water flow:"))[0]
    check(iterations == 150 and "MaximumIterations" in text, "150 water-flow iterations")
    reference = numbers(line_with(text, "reference:"))[0]
    check(reference > 1000, f"{reference} reference cells")
    rows = river_rows(text)
    check(set(rows) == {"waterflow", "D8"}, f"methods {sorted(rows)}")
    for name, (threshold, p30, r30, f30, p60, r60, f60) in rows.items():
        check(threshold > 0, f"{name}: threshold {threshold}")
        for p, r, f in ((p30, r30, f30), (p60, r60, f60)):
            check(0 <= p <= 1 and 0 <= r <= 1, f"{name}: scores in [0, 1]")
            check(abs(f - 2 * p * r / (p + r)) < 2e-4, f"{name}: F1 {f} from P {p} and R {r}")
        check(p60 >= p30 and r60 >= r30, f"{name}: a wider tolerance finds more")
    if "D8" in rows:
        check(rows["D8"][6] >= 0.75, "D8 F1@60 >= 0.75 (Documentation/validation.md: 0.782)")
    check_picture(out, "rivers_comparison.png", (400, 400))


def check_sweep(out, text):
    rows = [numbers(line) for line in text.splitlines() if re.match(r"^\s+\d+\s+\d", line)]
    latitudes = [int(r[0]) for r in rows]
    check(latitudes == list(range(0, 61, 10)), f"latitudes {latitudes}")
    hours = [r[1] for r in rows]
    insolation = [r[2] for r in rows]
    # 21 December: days shorten and the sun sinks as the valley moves north.
    check(all(a > b for a, b in zip(hours, hours[1:])), f"mean hours fall with latitude: {hours}")
    check(all(a > b for a, b in zip(insolation, insolation[1:])),
          f"mean insolation falls with latitude: {insolation}")
    for latitude, h in zip(latitudes, hours):
        limit = day_length(latitude, -23.44)
        check(0 <= h <= limit + 0.2, f"{latitude} N: {h} h of sun, day length {limit:.2f} h")
    digests = set()
    for latitude in range(0, 61, 10):
        name = f"sweep_lat{latitude:02d}.png"
        check_picture(out, name, (300, 300))
        if os.path.isfile(os.path.join(out, name)):
            with open(os.path.join(out, name), "rb") as f:
                digests.add(hashlib.sha256(f.read()).hexdigest())
    check(len(digests) == 7, f"{len(digests)} distinct sweep images, expected 7")


def check_numpy(out, text):
    header = line_with(text, f"{SAGEHEN_CELLS} cells of 0.01 ha")
    check("(565920, 12)" in header, "Temperature seen by numpy as (cells, 12)")
    classes = [numbers(line)[-2:] for line in text.splitlines()
               if re.match(r"^(gentle|moderate|steep|very steep)", line)]
    check(len(classes) == 4, f"{len(classes)} slope classes")
    total_area, total_share = numbers(line_with(text, "total "))
    check(abs(sum(a for a, _ in classes) - total_area) < 0.03, "class areas sum to the total")
    check(abs(total_area - SAGEHEN_CELLS * 0.01) < 0.005, f"total area {total_area} ha")
    check(abs(total_share - 100.0) < 1e-3, f"total share {total_share}")
    zones = [numbers(line) for line in text.splitlines() if re.match(r"^\s+\d+\s+\d+\s+-?\d", line)]
    check(len(zones) == 4, f"{len(zones)} zones, expected 4")
    check(sum(int(z[1]) for z in zones) == SAGEHEN_CELLS, "zone cells sum to the DEM")
    for z in zones:
        check(abs(z[2] - z[3]) < 2e-4, f"zone {int(z[0])}: numpy mean {z[2]} vs table {z[3]}")
    low, high = numbers(line_with(text, "growing degree-days"))[:2]
    check(0 <= low < high, f"degree-days {low}..{high}")


CHECKS = {
    "SlopeTemperatureMaps": check_slope_temperature,
    "SunHoursAndSunPath": check_sun_hours,
    "EcologicalZones": check_zones,
    "RiversFromRain": check_rivers,
    "LatitudeSweep": check_sweep,
    "NumpyZoneStatistics": check_numpy,
}


def run(name, out, command):
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    start = time.monotonic()
    result = subprocess.run(command + ["--data", DATA] +
                            (["--out", out] if name != "NumpyZoneStatistics" else []),
                            stdout=subprocess.PIPE, text=True, timeout=300)
    seconds = time.monotonic() - start
    with open(os.path.join(out, "stdout.txt"), "w") as f:
        f.write(result.stdout)
    print(result.stdout)
    print(f"{name}: exit code {result.returncode}, {seconds:.2f} s")
    check(result.returncode == 0, f"{name} exited with {result.returncode}")
    if result.returncode == 0:
        CHECKS[name](out, result.stdout)


def same_report(text_a, text_b, label):
    """Same lines; numbers equal up to one unit of the last digit printed."""
    lines_a, lines_b = text_a.splitlines(), text_b.splitlines()
    check(len(lines_a) == len(lines_b), f"{label}: {len(lines_a)} vs {len(lines_b)} lines")
    for a, b in zip(lines_a, lines_b):
        tokens_a, tokens_b = a.split(), b.split()
        same = len(tokens_a) == len(tokens_b)
        for x, y in zip(tokens_a, tokens_b):
            try:
                fx, fy = float(x), float(y)
            except ValueError:
                same = same and x == y
                continue
            digits = max(len(t.split(".")[1]) if "." in t else 0 for t in (x, y))
            same = same and abs(fx - fy) <= 1.01 * 10.0 ** -digits
        check(same, f"{label}: {a!r} vs {b!r}")


def compare(name, dir_a, dir_b):
    texts = []
    for d in (dir_a, dir_b):
        with open(os.path.join(d, "stdout.txt")) as f:
            texts.append(f.read())
    same_report(texts[0], texts[1], f"{name}: {dir_a} vs {dir_b}")
    if name != "RiversFromRain":
        return
    # The scores of `terroir validate` on the same input and settings.
    work = tempfile.mkdtemp(prefix="validate-")
    try:
        path = os.path.join(work, "scores.json")
        binary = os.path.join(os.environ.get("TERROIR_BIN_DIR", "build/bin"), "terroir")
        sagehen = os.path.join(DATA, "sagehen_creek_ca")
        command = [binary, "validate", os.path.join(sagehen, "sagehen_dem_utm11n_10m.tif"),
                   "--reference", os.path.join(sagehen, "sagehen_nhd_flowlines_utm11n.geojson"),
                   "--mask", os.path.join(sagehen, "sagehen_watershed_utm11n.geojson"),
                   "--mode", "pulse", "--max-iterations", "150", "--json", path]
        result = subprocess.run(command, capture_output=True, text=True, timeout=300)
        check(result.returncode == 0, f"terroir validate failed: {result.stderr}")
        if result.returncode != 0:
            return
        with open(path) as f:
            scores = json.load(f)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    check(scores["water_flow"]["iterations"] == 150, "terroir validate ran 150 iterations")
    for text, d in zip(texts, (dir_a, dir_b)):
        check(numbers(line_with(text, "reference:"))[0] == scores["reference_cells"],
              f"{d}: reference cells vs terroir validate's {scores['reference_cells']}")
        rows = river_rows(text)
        for method, key in zip(scores["methods"], ("waterflow", "D8")):
            printed = rows.get(key, [math.nan] * 7)
            check(abs(printed[0] - method["threshold"]) <= 0.0005 + 1e-9,
                  f"{d}: {key} threshold {printed[0]} vs {method['threshold']}")
            expected = [s[k] for s in method["scores"] for k in ("precision", "recall", "f1")]
            for got, want, what in zip(printed[1:], expected,
                                       ("P@30", "R@30", "F1@30", "P@60", "R@60", "F1@60")):
                check(abs(got - want) <= 0.00005 + 1e-9,
                      f"{d}: {key} {what} {got} vs terroir validate's {want:.6f}")


def main():
    if len(sys.argv) >= 5 and sys.argv[1] == "run" and sys.argv[2] in CHECKS:
        run(sys.argv[2], sys.argv[3], sys.argv[4:])
    elif len(sys.argv) == 5 and sys.argv[1] == "compare" and sys.argv[2] in CHECKS:
        compare(*sys.argv[2:])
    else:
        sys.exit(__doc__)
    if failures:
        print(f"{len(failures)} check(s) failed")
        sys.exit(1)
    print("all checks passed")


if __name__ == "__main__":
    main()
