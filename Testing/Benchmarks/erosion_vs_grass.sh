#!/usr/bin/env bash
# Times our erosion filter, vtkTerroirErosion (CPU path), against GRASS GIS's SIMWE models
# r.sim.water and r.sim.sediment on the same synthetic DEM (terroir fractal, seed 1, 10 m
# cells), and prints seconds, cells x iterations per second and the ratio ours / GRASS (issue
# 27's speed target: at 1024^2, ours >= 10 x r.sim.sediment's cells x iterations per second).
#   Testing/Benchmarks/erosion_vs_grass.sh [BUILD_DIR] [SIZES] [STEPS]
# Defaults: build, "1024", 100 (our steps). Environment: MINUTES (r.sim.* niterations, minutes
# of simulated time, > 1; default 10, GRASS's default), WALKERS (walkers per cell; default 2,
# GRASS's default), THREADS (both sides; default nproc), REPEAT (timed rounds, best kept;
# default 2), PYTHON (default /usr/bin/python3). BUILD_DIR needs bin/terroir and the Python
# package (lib/python3/dist-packages/terroir). Not a CTest test (smoke.sh runs it at 64^2):
# about 4 min at 1024^2 on 2 cores, most of it r.sim.water.
#
# What an "iteration" is on each side, and how they are made comparable:
#  - ours: one erosion step = one hydraulic step of the virtual-pipe model on every cell (rain,
#    four-pipe fluxes, water height, velocity, capacity, erosion/deposition, semi-Lagrangian
#    sediment transport with Dunn's rescaling, evaporation) then one thermal (soil-slip) step:
#    the filter's defaults (Weiss's constants, dt 0.01 s, ThermalInterval 1), rain 50 mm/h (as
#    r.sim.water's), Boundary Sea at 0 m (below the DEM: the grid's edge drains, as GRASS's
#    walkers leave the region). A second figure: hydraulic steps alone (ThermalInterval 0),
#    since GRASS has no soil slip.
#  - GRASS: r.sim.* solve shallow overland flow and sediment continuity by path sampling
#    (Green's-function Monte Carlo, Mitas & Mitasova 1998): WALKERS x cells particles are
#    released and each iteration moves every live walker once (drift by the local velocity
#    times the time step plus a Gaussian diffusion jump) and adds its weight to the water depth
#    or sediment of its cell. The user gives the simulated time (niterations, in minutes) and
#    the walkers, not the iterations: GRASS sets its iteration count to the simulated time over
#    a time step of 0.25 cell / mean velocity (times 1.25 or 4) and prints it ("Number of
#    iterations"); r.sim.sediment then moves its walkers by a shorter step when 0.8 / (sigma_max
#    v_max) is shorter ("Time step used"), so its iterations cover less than the requested
#    time. The script reads the printed count and checks the progress counter reached 100 % (a
#    run whose walkers all leave stops early: flagged). There is no common grid step, so, as
#    the issue states, the unit is cells x iterations per second: nx * ny x (our steps, or
#    GRASS's printed iterations) / seconds. One GRASS iteration moves about WALKERS particles
#    per cell (fewer as they leave); one of ours updates every cell's whole state. The two
#    cover very different simulated times per iteration (ours 0.01 s; GRASS's dt is printed):
#    this compares throughput per iteration over the grid, NOT the time to a given physical
#    answer, and NOT accuracy or realism.
#  - Two figures each: "run" = the whole module or Update (input, setup, output included) and
#    "loop" = the iterations alone: ours (t(STEPS) - t(0 steps)) / STEPS; GRASS (t(MINUTES) -
#    t(1 minute)) / (iterations(MINUTES) - iterations(1 minute)), which removes reading the
#    input maps, GRASS's setup and writing its output map.
#  - r.sim.sediment needs r.sim.water's depth: r.sim.water runs first (timed and reported too:
#    our step includes the water flow), then r.sim.sediment on its depth. Inputs: dx, dy from
#    r.slope.aspect, Manning's n 0.1 and rain excess 50 mm/h (GRASS's defaults), detachment
#    0.001 s/m, transport 0.001 s, critical shear stress 0.01 Pa (constant maps, our choice: the
#    manual gives no table; they change the answer, little the time per iteration),
#    random_seed 1, nprocs = THREADS (OpenMP). r.slope.aspect leaves the 1-cell border null,
#    so GRASS computes (n-2)^2 of the n^2 cells; both sides are counted as n^2.
#  - Rounds: r.sim.water (1 minute, then MINUTES) and r.sim.sediment (1 minute) once, then
#    REPEAT rounds of r.sim.sediment (MINUTES) each followed by ours (0 steps x 3, STEPS steps,
#    STEPS hydraulic steps), best of the rounds kept, so that load from other users of the
#    machine hits both sides alike; the load average is printed.
#  - The fractal GeoTIFF has no CRS: it is placed on NAD83 / UTM 11N (EPSG:26911; upper-left
#    213980 E, 4373670 N) so that GRASS's location is projected, in metres. HOME and TMPDIR
#    point into a scratch folder (nothing is written to the user's GRASS settings).
# Ratios are ours / GRASS in cells x iterations per second (> 1: ours is faster).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=${1:-$here/build}
sizes=${2:-1024}
steps=${3:-100}
minutes=${MINUTES:-10}
walkers=${WALKERS:-2}
threads=${THREADS:-$(nproc)}
repeat=${REPEAT:-2}
terroir="$build/bin/terroir"
python=${PYTHON:-/usr/bin/python3}
package="$build/lib/python3/dist-packages"
command -v grass >/dev/null || { echo "grass not found (Debian grass-core)" >&2; exit 1; }
command -v gdal_translate >/dev/null ||
  { echo "gdal_translate not found (Debian gdal-bin)" >&2; exit 1; }
[ -x "$terroir" ] || { echo "$terroir not found: build first" >&2; exit 1; }
[ -f "$package/terroir/__init__.py" ] || { echo "$package/terroir not found" >&2; exit 1; }
[ "$minutes" -gt 1 ] || { echo "MINUTES $minutes must be > 1 (1 minute is the setup)" >&2; exit 1; }
[ "$repeat" -ge 1 ] || { echo "REPEAT $repeat must be >= 1" >&2; exit 1; }
work=$(mktemp -d)
[ -d "$work" ] || { echo "mktemp -d failed" >&2; exit 1; }
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/home"

version=$(HOME="$work/home" grass --version 2>&1 | head -1 || true)
echo "$version; terroir: $build; $threads threads; our steps $steps;" \
  "r.sim.* niterations $minutes min, $walkers walkers per cell; best of $repeat rounds"

cat >"$work/ours.py" <<'PY'
"""One round of vtkTerroirErosion (CPU) timings on a DEM, appended as a JSON line to OUT: the
best of 3 runs of 0 steps (the setup), one run of STEPS steps (hydraulic + thermal) and one of
STEPS hydraulic steps alone (ThermalInterval 0)."""
import json
import sys
import time

import terroir
from vtkmodules.vtkCommonCore import vtkSMPTools
from vtkmodules.vtkCommonDataModel import vtkImageData

dem, steps, threads, out = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
vtkSMPTools.Initialize(threads)
reader = terroir.vtkTerroirDEMReader()
reader.SetFileName(dem)
reader.Update()
image = vtkImageData()
image.ShallowCopy(reader.GetOutput())


def run(n, thermal=1):
    """Seconds of one Update of a fresh filter for n steps (its step count checked)."""
    f = terroir.vtkTerroirErosion()
    f.SetInputData(image)
    f.SetBackendToCPU()
    f.SetSteps(n)
    f.SetThermalInterval(thermal)  # 1: a soil-slip step after every step (default); 0: none
    f.SetRainRate(50.0)  # mm/h, as r.sim.water's rain_value
    f.SetBoundary(f.Sea)  # sea level 0 m, below the DEM: the grid's edge drains
    t0 = time.perf_counter()
    f.Update()
    t = time.perf_counter() - t0
    done = f.GetOutput().GetFieldData().GetArray("ErosionSteps")
    if f.GetLastBackend() != 1 or done is None or done.GetValue(0) != n:
        sys.exit("vtkTerroirErosion did not run %d CPU steps" % n)
    return t


setup = min(run(0) for _ in range(3))
record = {"steps": steps, "setup": setup, "seconds": run(steps), "hydraulic": run(steps, 0),
          "threads": vtkSMPTools.GetEstimatedNumberOfThreads(), "smp": vtkSMPTools.GetBackend()}
with open(out, "a") as f:
    f.write(json.dumps(record) + "\n")
PY

cat >"$work/table.py" <<'PY'
"""The table of one size from the logs of its GRASS session and our rounds."""
import json
import os
import re
import sys

logs, n, minutes = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
cells = n * n
seconds = dict((l.split()[0], float(l.split()[1])) for l in open(os.path.join(logs, "times.txt")))
rounds = [json.loads(l) for l in open(os.path.join(logs, "ours.jsonl")) if l.strip()]
sediment_rounds = sorted(k for k in seconds if k.startswith("sediment_r"))
nan = float("nan")


def iterations(label):
    """GRASS's printed iteration count, its time step, the last progress percentage."""
    text = open(os.path.join(logs, label + ".log")).read()
    m = re.search(r"Number of iterations\s*=\s*(\d+)", text)
    if not m:
        sys.exit("no 'Number of iterations' in the %s log:\n%s" % (label, text))
    dt = re.search(r"Time step used\s*=\s*([\d.]+)", text) or \
        re.search(r"Time step\s*=\s*([\d.]+)", text)
    progress = re.findall(r"^\d+(?:\.\.\d+)*\s*$", text[m.end():], re.M)  # "1..3..5..100"
    last = int(progress[0].split("..")[-1]) if progress else None
    return int(m.group(1)), float(dt.group(1)) if dt else nan, last


def rate(its, s):
    return cells * its / s if s > 0 else nan


steps = rounds[0]["steps"]
setup = min(r["setup"] for r in rounds)
full = min(r["seconds"] for r in rounds)
hydraulic = min(r["hydraulic"] for r in rounds)
rows = [("ours: vtkTerroirErosion CPU", "%d steps" % steps, full, setup, rate(steps, full),
         rate(steps, full - setup), "hydraulic + thermal step (the default)"),
        ("ours: hydraulic steps alone", "%d steps" % steps, hydraulic, setup,
         rate(steps, hydraulic), rate(steps, hydraulic - setup), "ThermalInterval 0")]
warnings = []
for module, best in (("sediment", min(sediment_rounds, key=seconds.get)), ("water", "water")):
    its, dt, last = iterations(best)
    its1, _, last1 = iterations(module + "_1")
    t, t1 = seconds[best], seconds[module + "_1"]
    if last != 100 or last1 != 100:
        warnings.append("r.sim.%s stopped early (progress %s %% and %s %%): it ran fewer "
                        "iterations than it printed, its rates are too high"
                        % (module, last, last1))
    loop = cells * (its - its1) / (t - t1) if its > its1 and t > t1 else nan
    rows.append(("GRASS r.sim.%s, %d min" % (module, minutes), "%d it, dt %.2f s" % (its, dt),
                 t, t1, rate(its, t), loop, "setup = its 1-min run (%d it)" % its1))

print("%-30s %17s %8s %8s %11s %11s %7s %7s" % ("", "iterations", "run s", "setup s",
      "cell.it/s", "cell.it/s", "ratio", "ratio"))
print("%-30s %17s %8s %8s %11s %11s %7s %7s" % ("", "", "", "", "run", "loop", "run", "loop"))
ours = rows[0]
for what, its, t, t0, r_run, r_loop, note in rows:
    grass = what.startswith("GRASS")
    print(("%-30s %17s %8.3f %8.3f %11.3g %11.3g %7s %7s  %s" % (
        what, its, t, t0, r_run, r_loop, "%.2f" % (ours[4] / r_run) if grass else "",
        "%.2f" % (ours[5] / r_loop) if grass else "", note)).rstrip())
print("ours hydraulic alone / r.sim.sediment (loop): %.2f" % (rows[1][5] / rows[2][5]))
print("r.slope.aspect (dx, dy for both r.sim.*): %.2f s; r.sim.sediment rounds: %s s; ours "
      "rounds: %s s (%d threads, %s)" % (
          seconds["slope"], ", ".join("%.2f" % seconds[k] for k in sediment_rounds),
          ", ".join("%.2f" % r["seconds"] for r in rounds), rounds[0]["threads"],
          rounds[0]["smp"]))
for w in warnings:
    print("WARNING: " + w)
if n == 1024:
    r = ours[5] / rows[2][5]
    print("issue 27 target (1024^2, ours >= 10 x r.sim.sediment, loop): %.2f x, %s"
          % (r, "met" if r >= 10 else "NOT met"))
PY

for n in $sizes; do
  echo
  echo "== $n x $n =="
  raw="$work/fractal_$n.tif"
  dem="$work/fractal_${n}_utm.tif"
  "$terroir" fractal "$raw" --size "$n" --seed 1 --spacing 10 --overwrite >/dev/null 2>&1
  gdal_translate -q -a_srs EPSG:26911 \
    -a_ullr 213980 4373670 $((213980 + 10 * n)) $((4373670 - 10 * n)) "$raw" "$dem"
  rm -f "$raw"
  logs="$work/logs_$n"
  mkdir -p "$logs"
  nwalk=$((walkers * n * n))
  cat >"$work/grass_$n.sh" <<EOF
set -e
tm() { # tm LABEL command...: runs it, its messages to LABEL.log, "LABEL seconds" to times.txt
  local label=\$1; shift
  local t0 t1; t0=\$(date +%s.%N); "\$@" 2>"$logs/\$label.log"; t1=\$(date +%s.%N)
  awk -v l="\$label" -v a="\$t0" -v b="\$t1" 'BEGIN{ printf "%s %.3f\n", l, b - a }' \\
    >>"$logs/times.txt"
}
r.in.gdal -o input="$dem" output=dem --quiet
g.region raster=dem
tm slope r.slope.aspect elevation=dem dx=dx dy=dy --quiet
r.mapcalc "det = 0.001" --quiet
r.mapcalc "tran = 0.001" --quiet
r.mapcalc "tau = 0.01" --quiet
common="elevation=dem dx=dx dy=dy man_value=0.1 nwalkers=$nwalk random_seed=1 nprocs=$threads"
tm water_1 r.sim.water \$common rain_value=50 depth=depth1 niterations=1
tm water r.sim.water \$common rain_value=50 depth=depth niterations=$minutes
sed="water_depth=depth detachment_coeff=det transport_coeff=tran shear_stress=tau"
tm sediment_1 r.sim.sediment \$common \$sed erosion_deposition=erdep1 niterations=1
for r in \$(seq 1 $repeat); do
  echo "round \$r: \$(cut -d' ' -f1-3 /proc/loadavg)" >>"$logs/load.txt"
  tm sediment_r\$r r.sim.sediment \$common \$sed erosion_deposition=erdep_\$r \\
    niterations=$minutes
  env -u LD_LIBRARY_PATH PYTHONPATH="$package" "$python" "$work/ours.py" "$dem" "$steps" \\
    "$threads" "$logs/ours.jsonl" >>"$logs/ours.log" 2>&1 || { cat "$logs/ours.log"; exit 1; }
done
echo "end: \$(cut -d' ' -f1-3 /proc/loadavg)" >>"$logs/load.txt"
EOF
  echo "load average (1, 5, 15 min) at start: $(cut -d' ' -f1-3 /proc/loadavg)"
  env -u GISRC -u GISBASE HOME="$work/home" TMPDIR="$work" LC_ALL=C GRASS_MESSAGE_FORMAT=plain \
    grass --tmp-location "$dem" --exec bash "$work/grass_$n.sh" >"$logs/session.log" 2>&1 || true
  if [ "$(wc -l <"$logs/times.txt" 2>/dev/null || echo 0)" != $((4 + repeat)) ] ||
    [ ! -s "$logs/ours.jsonl" ]; then
    cat "$logs/session.log" >&2
    echo "the run failed at $n x $n" >&2
    exit 1
  fi
  echo "load average (1, 5, 15 min): $(tr '\n' ' ' <"$logs/load.txt")"
  "$python" "$work/table.py" "$logs" "$n" "$minutes"
done
echo
echo "ratio = ours (hydraulic + thermal) / GRASS in cells x iterations per second (> 1: ours is"
echo "faster); run = the whole module or Update, loop = the iterations alone (script header)"
