#!/usr/bin/python3
"""Steps per second of the live erosion in `terroir view` (issue 27: 1024^2 interactively, at
least 10 steps/s, on the CPU path) against the same steps run by vtkTerroirErosion in this
script, on a seeded fractal of N x N cells (10 m). The viewer's rate is the one its status line
shows (steps over the wall time since the start, frames and the window's redraws included:
the window draws on the same 2 cores); the filter's is (time of S steps - time of 0 steps) / S.
Speed is reported, never asserted. Needs an X display (xvfb-run -a).

  xvfb-run -a /usr/bin/python3 Testing/Benchmarks/viewer_erosion.py [--build build]
      [--size 1024] [--steps 100] [--json OUT.json]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
RAIN = 50.0  # mm/h on every cell, so that the run has water to move without a brush


def filter_rate(build, dem, steps):
    """Steps per second of vtkTerroirErosion (ThermalInterval 1, the viewer's settings)."""
    sys.path.insert(0, os.path.join(build, "lib", "python3", "dist-packages"))
    import terroir  # noqa: E402 (the build's module)
    reader = terroir.vtkTerroirDEMReader()
    reader.SetFileName(dem)
    reader.Update()

    def run(n):
        f = terroir.vtkTerroirErosion()
        f.SetInputConnection(reader.GetOutputPort())
        f.SetSteps(n)
        f.SetInitialWater(0.0)
        f.SetRainRate(RAIN)
        t = time.perf_counter()
        f.Update()
        return time.perf_counter() - t

    run(1)  # warm up
    return steps / max(1e-9, run(steps) - run(0))


def viewer_rate(build, dem, steps, folder):
    """The viewer's `erosion-rate` after `steps` steps of a run with RAIN mm/h."""
    script = os.path.join(folder, "erosion.txt")
    with open(script, "w") as f:
        f.write("erosion-rain %g\nerosion start\nwait-erosion %d\nstate\nerosion stop\nquit\n"
                % (RAIN, steps))
    proc = subprocess.run([os.path.join(build, "bin", "terroir"), "view", dem, "--script",
                           script], capture_output=True, text=True, timeout=3600, cwd=folder)
    if proc.returncode != 0:
        sys.exit("terroir view failed: " + proc.stderr.strip())
    for line in proc.stdout.splitlines():
        if line.startswith("state "):
            words = line.split()
            d = dict(zip(words[1::2], words[2::2]))
            return float(d["erosion-rate"]), int(float(d["erosion-steps"]))
    sys.exit("no state line from terroir view")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--size", type=int, default=1024)
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--json")
    a = ap.parse_args()
    if not os.environ.get("DISPLAY"):
        sys.exit("no DISPLAY: run under xvfb-run -a")
    build = os.path.abspath(a.build)
    with tempfile.TemporaryDirectory() as folder:
        dem = os.path.join(folder, "fractal.tif")
        subprocess.run([os.path.join(build, "bin", "terroir"), "fractal", "--size", str(a.size),
                        "--seed", "1", "--spacing", "10", dem], check=True,
                       capture_output=True)
        load = os.getloadavg()[0]
        viewer, done = viewer_rate(build, dem, a.steps, folder)
        filt = filter_rate(build, dem, a.steps)
    cells = a.size * a.size
    result = {"size": a.size, "steps": done, "load_average": load,
              "viewer_steps_per_s": viewer, "filter_steps_per_s": filt,
              "viewer_over_filter": viewer / filt,
              "viewer_mcells_steps_per_s": viewer * cells / 1e6,
              "target_steps_per_s": 10.0}
    print("%d^2, %d steps, load %.1f: viewer %.2f steps/s, filter %.2f steps/s (%.2fx), "
          "viewer %.1f Mcells x steps/s; target 10 steps/s"
          % (a.size, done, load, viewer, filt, viewer / filt, viewer * cells / 1e6))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(result, f, indent=1)


if __name__ == "__main__":
    main()
