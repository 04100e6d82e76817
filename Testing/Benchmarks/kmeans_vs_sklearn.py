#!/usr/bin/python3
"""Time per Lloyd iteration of vtkTerroirKMeans against scikit-learn and vtkKMeansStatistics.

  /usr/bin/python3 Testing/Benchmarks/kmeans_vs_sklearn.py [--build build] [--size 1024]
      [--json out.json] [--vtk-cells 65536] [--repeat 5] [--ks 2,5,10,20] [--compare-ks 5,10]

Input: a size x size vtkTerroirFractalTerrainSource terrain (seed 7) with 37 feature components
per cell, Long (2016)'s default features: Slope (1, the filter), Temperature (12, the filter) and
two synthetic 12-month fields named IlluminationHours and WeightedSoilHumidity (numpy, the same
formulas as `terroir bench`'s k-means stage; computing the real ones would dominate the run).
Weights 1, 1, 1, 0.1; CollapseConstantOffsets off, so all 37 components are features (on, the
Temperature would be one).

Time per iteration, for everyone the same way: (time of a run of 11 Lloyd iterations - time of a
run of 1) / 10, each run the best of --repeat (ours and scikit-learn in interleaved rounds, so
that a burst of load from another user does not hit all runs of one method), with tolerance 0
(so the iteration count is the maximum, checked) and the same initial centres (the diagonal seed
cells of KMeans.h):
- ours, CPU backend (vtkSMPTools, all threads) and GPU backend (the compute context's device,
  llvmpipe on machines without a GPU; a failure is reported, not fatal); each run a full
  Update, the difference removes the packing, feature preparation, seeding and the table;
- scikit-learn `KMeans(algorithm="lloyd", n_init=1, init=array, tol=0, max_iter=11 vs 1)` on
  the same prepared features (sqrt(w) * value) as a C-contiguous float32 matrix (all OpenMP
  threads);
- vtkKMeansStatistics (VTK's own, vtkmodules.vtkFiltersStatistics) on a subset of --vtk-cells
  cells (every n/subset-th cell), MaxNumIterations 11 vs 1, Tolerance 0, the initial centres on
  its LEARN_PARAMETERS port (first column "K", vtkIdType); its per-iteration time is scaled to
  the full size per cell (it is linear in the cells).
The table shows ms per iteration, ms per iteration per million cells, and the ratios
scikit-learn / ours and vtkKMeansStatistics / ours (ours = the CPU backend; > 1: ours is
faster). Then ours for each K of --ks. It is a benchmark, not a test: no assertion on times.
The machine's load is printed before, after each round and after; on a shared machine, run it
when it is quiet (about 2.5 minutes at --size 1024, 2 minutes of it vtkKMeansStatistics).

Measured when this was written (2 cores, TBB, quiet: load 0.9 before and 1.1 after, no other
process in `top`; build of merge 1ca0a7e; llvmpipe 22.3.6), --size 1024, ms per iteration:
  K = 5:  ours CPU 13.8, ours GPU (llvmpipe) 141.5, scikit-learn 38.2 (2.8x ours),
          vtkKMeansStatistics 36,759 scaled from 2,298 on 65,536 cells (2,656x ours)
  K = 10: ours CPU 17.8, GPU 168.9, scikit-learn 62.6 (3.5x), vtkKMeansStatistics 67,679 (3,800x)
  ours CPU for K = 2, 5, 10, 20: 9.7, 13.8, 17.8, 26.7
"""
import argparse
import glob
import json
import os
import platform
import sys
import time

import numpy as np


def find_package(build):
    """The folder that holds the built `terroir` package, under the build dir itself."""
    hits = sorted(glob.glob(os.path.join(build, "lib", "**", "terroir", "__init__.py"),
                            recursive=True))
    if not hits:
        hits = sorted(glob.glob(os.path.join(build, "**", "terroir", "__init__.py"),
                                recursive=True))
    if not hits:
        sys.exit("no terroir/__init__.py under %s: build first (or pass --build)" % build)
    return os.path.dirname(os.path.dirname(hits[0]))


def round_half_up(numerator, denominator):
    q, r = divmod(numerator, denominator)
    return q + (1 if 2 * r >= denominator else 0)


def diagonal_seed_cells(nx, ny, k):
    """KMeans.h, KMeansDiagonalSeedCells, every cell valid."""
    length = max(nx, ny)
    diagonal = []
    for t in range(length):
        i = 0 if length == 1 else round_half_up(t * (nx - 1), length - 1)
        j = 0 if length == 1 else round_half_up(t * (ny - 1), length - 1)
        diagonal.append(j * nx + i)
    m = len(diagonal)
    return [diagonal[(2 * i + 1) * m // (2 * k)] for i in range(k)]


def best_of(repeat, fn):
    """Best wall time of `repeat` calls and the last call's result."""
    best, result = float("inf"), None
    for _ in range(repeat):
        t0 = time.perf_counter()
        result = fn()
        best = min(best, time.perf_counter() - t0)
    return best, result


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--build", default=os.path.join(here, "..", "..", "build"))
    parser.add_argument("--size", type=int, default=1024, help="terrain cells per side")
    parser.add_argument("--json", help="write the results here as JSON")
    parser.add_argument("--vtk-cells", type=int, default=65536,
                        help="cells of the vtkKMeansStatistics subset (0: skip it)")
    parser.add_argument("--repeat", type=int, default=5, help="rounds of runs (best kept)")
    parser.add_argument("--vtk-repeat", type=int, default=1,
                        help="runs per vtkKMeansStatistics measurement (slow: seconds each)")
    parser.add_argument("--ks", default="2,5,10,20", help="K values for ours (growth with K)")
    parser.add_argument("--compare-ks", default="5,10", help="K values compared with the peers")
    parser.add_argument("--long", type=int, default=11, help="iterations of the long run")
    args = parser.parse_args()

    sys.path.insert(0, find_package(os.path.abspath(args.build)))
    from vtkmodules.util.misc import calldata_type
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkCommonCore import VTK_STRING, vtkIdTypeArray, vtkLogger
    from vtkmodules.vtkCommonCore import vtkSMPTools
    from vtkmodules.vtkCommonDataModel import vtkImageData, vtkTable
    from vtkmodules.vtkFiltersStatistics import vtkKMeansStatistics, vtkStatisticsAlgorithm
    import sklearn
    from sklearn.cluster import KMeans
    import terroir

    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_WARNING)  # no per-filter backend lines
    long_iters, short_iters = args.long, 1
    span = long_iters - short_iters
    ks = [int(k) for k in args.ks.split(",") if k]
    compare_ks = [int(k) for k in args.compare_ks.split(",") if k]
    load_before = os.getloadavg()
    print("kmeans_vs_sklearn: %s, %d CPUs, load average %.2f %.2f %.2f; vtkSMPTools %s, %d "
          "threads; scikit-learn %s, numpy %s"
          % (platform.node(), os.cpu_count(), *load_before, vtkSMPTools.GetBackend(),
             vtkSMPTools.GetEstimatedNumberOfThreads(), sklearn.__version__, np.__version__))

    # 1. The terrain and its 37 feature components.
    t0 = time.perf_counter()
    n_side = args.size
    source = terroir.vtkTerroirFractalTerrainSource()
    source.SetDimensions(n_side, n_side)
    source.SetSeed(7)
    slope = terroir.vtkTerroirSlope()
    slope.SetInputConnection(source.GetOutputPort())
    slope.SetBackendToCPU()
    temperature = terroir.vtkTerroirTemperature()
    temperature.SetInputConnection(slope.GetOutputPort())
    temperature.SetBackendToCPU()
    temperature.Update()
    image = vtkImageData()
    image.ShallowCopy(temperature.GetOutput())
    nx, ny, _ = image.GetDimensions()
    n = nx * ny
    pd = image.GetPointData()
    z = vtk_to_numpy(pd.GetArray("Elevation")).astype(np.float64)
    s = vtk_to_numpy(pd.GetArray("Slope")).astype(np.float64)
    x = (np.arange(n) % nx) / nx
    season = np.cos(2.0 * np.pi * (np.arange(12) - 5.5) / 12.0)
    synthetic = {
        "IlluminationHours": 10.0 + 3.0 * season[None, :] - 0.05 * s[:, None] + x[:, None],
        "WeightedSoilHumidity": 80.0 - 40.0 * season[None, :] + 0.02 * z[:, None]
        - 20.0 * x[:, None],
    }
    for name, values in synthetic.items():
        array = numpy_to_vtk(values.astype(np.float32), deep=True)
        array.SetName(name)
        pd.AddArray(array)
    features = [("Slope", 1.0), ("Temperature", 1.0), ("IlluminationHours", 1.0),
                ("WeightedSoilHumidity", 0.1)]
    columns = []
    for name, weight in features:
        values = vtk_to_numpy(pd.GetArray(name)).reshape(n, -1).astype(np.float64)
        columns.append(values * np.sqrt(weight))
    X = np.ascontiguousarray(np.hstack(columns).astype(np.float32))
    if not np.all(np.isfinite(X)):
        sys.exit("non-finite feature values: the benchmark expects every cell to take part")
    print("terrain: %d x %d = %.3f M cells, %d features (%.1f s to build)"
          % (nx, ny, n / 1e6, X.shape[1], time.perf_counter() - t0))

    results = {"machine": {"host": platform.node(), "cpus": os.cpu_count(),
                           "load_before": load_before,
                           "smp_backend": vtkSMPTools.GetBackend(),
                           "smp_threads": vtkSMPTools.GetEstimatedNumberOfThreads()},
               "versions": {"sklearn": sklearn.__version__, "numpy": np.__version__},
               "size": n_side, "cells": n, "features": int(X.shape[1]),
               "iterations": [short_iters, long_iters], "repeat": args.repeat,
               "vtk_repeat": args.vtk_repeat,
               "method": "(best time of %d iterations - best time of %d) / %d"
                         % (long_iters, short_iters, span),
               "ours": {}, "ours_gpu": {}, "sklearn": {}, "vtk": {}}

    # 2. Ours.
    def run_ours(k, iterations, backend):
        f = terroir.vtkTerroirKMeans()
        f.SetInputData(image)
        f.SetNumberOfClusters(k)
        f.SetSeedingToDiagonal()
        f.SetTolerance(0.0)
        f.SetMaximumIterations(iterations)
        f.SetCollapseConstantOffsets(False)
        for name, weight in features:
            f.AddFeature(name, weight)
        if backend == "gpu":
            f.SetBackendToGPU()
        else:
            f.SetBackendToCPU()
        errors = []

        @calldata_type(VTK_STRING)
        def on_error(_obj, _event, message):
            errors.append(str(message).strip())

        f.AddObserver("ErrorEvent", on_error)
        f.GetExecutive().AddObserver("ErrorEvent", on_error)

        def update():
            f.Modified()
            f.Update()
            fd = f.GetOutput().GetFieldData()
            its = fd.GetArray("KMeansIterations")
            if its is None:
                # The filter's own message (the first), without VTK's "ERROR: In file" header.
                message = errors[0] if errors else "no KMeansIterations in the output"
                lines = [line for line in message.splitlines() if line.strip()]
                text = lines[1] if len(lines) > 1 else lines[0]
                raise RuntimeError(text.split("): ", 1)[-1])
            return int(its.GetValue(0))

        return update

    def per_iteration(make, k, repeat=None):
        """One method at one K on its own: best of `repeat` long runs and short runs."""
        repeat = repeat or args.repeat
        t_long, it_long = best_of(repeat, make(k, long_iters))
        t_short, it_short = best_of(repeat, make(k, short_iters))
        return summarize(k, t_long, it_long, t_short, it_short)

    def summarize(k, t_long, it_long, t_short, it_short):
        if (it_long, it_short) != (long_iters, short_iters):
            print("  warning: K = %d ran %d and %d iterations, not %d and %d"
                  % (k, it_long, it_short, long_iters, short_iters))
        return {"long_s": t_long, "short_s": t_short, "iterations": [it_short, it_long],
                "ms_per_iteration": 1e3 * (t_long - t_short) / (it_long - it_short)}

    # 3. scikit-learn, float32, the same features and initial centres.
    def run_sklearn(k, iterations):
        init = X[diagonal_seed_cells(nx, ny, k)].copy()

        def fit():
            km = KMeans(n_clusters=k, init=init, n_init=1, algorithm="lloyd", tol=0.0,
                        max_iter=iterations)
            km.fit(X)
            return int(km.n_iter_)

        return fit

    # Ours (CPU) and scikit-learn measured in interleaved rounds: each round runs every
    # (method, K) once long and once short, and the best of the rounds is kept, so that a burst
    # of load from another user hits one round of everyone rather than all runs of one method.
    jobs = [("ours", k, lambda kk, it: run_ours(kk, it, "cpu"))
            for k in sorted(set(ks) | set(compare_ks))]
    # The GPU backend joins the rounds when it runs at all (one probe run first).
    ctx = terroir.vtkTerroirComputeContext
    gpu = (ctx.GetRenderer() + ", " + ctx.GetVersion()) if ctx.IsAvailable() \
        else "unavailable: " + ctx.GetUnavailableReason()
    results["machine"]["gpu"] = gpu
    print("compute context:", gpu)
    try:
        run_ours(compare_ks[0], short_iters, "gpu")()
        jobs += [("ours_gpu", k, lambda kk, it: run_ours(kk, it, "gpu")) for k in compare_ks]
    except RuntimeError as e:
        print("ours GPU: failed: %s" % e)
        for k in compare_ks:
            results["ours_gpu"][str(k)] = {"error": str(e)}
    jobs += [("sklearn", k, run_sklearn) for k in compare_ks]
    runs = {(name, k): [make(k, long_iters), make(k, short_iters)] for name, k, make in jobs}
    best = {key: [float("inf"), float("inf"), None, None] for key in runs}
    round_loads = []
    for r in range(args.repeat):
        for key, (long_run, short_run) in runs.items():
            for slot, run in ((0, long_run), (1, short_run)):
                t0 = time.perf_counter()
                its = run()
                dt = time.perf_counter() - t0
                if dt < best[key][slot]:
                    best[key][slot] = dt
                    best[key][2 + slot] = its
        round_loads.append(os.getloadavg()[0])
        print("round %d of %d done, load average %.2f" % (r + 1, args.repeat, round_loads[-1]))
    results["machine"]["load_after_each_round"] = round_loads
    for (name, k), (t_long, t_short, it_long, it_short) in best.items():
        res = summarize(k, t_long, it_long, t_short, it_short)
        results[name][str(k)] = res
        label = {"ours": "ours CPU", "ours_gpu": "ours GPU", "sklearn": "scikit-learn float32"}
        print("%-22s K = %2d: %8.1f ms per iteration (%d its %.3f s, %d it %.3f s)"
              % (label[name], k, res["ms_per_iteration"], long_iters, t_long, short_iters,
                 t_short))

    # 4. vtkKMeansStatistics on a subset, scaled to the full size per cell.
    if args.vtk_cells > 0:
        stride = max(1, n // args.vtk_cells)
        subset = np.arange(0, n, stride)[: args.vtk_cells]
        data = vtkTable()
        names = ["f%02d" % f for f in range(X.shape[1])]
        for f, name in enumerate(names):
            column = numpy_to_vtk(X[subset, f].astype(np.float64), deep=True)
            column.SetName(name)
            data.AddColumn(column)

        def run_vtk(k, iterations):
            seeds = X[diagonal_seed_cells(nx, ny, k)].astype(np.float64)
            initial = vtkTable()
            run_k = vtkIdTypeArray()
            run_k.SetName("K")
            for _ in range(k):
                run_k.InsertNextValue(k)
            initial.AddColumn(run_k)
            for f, name in enumerate(names):
                column = numpy_to_vtk(seeds[:, f].copy(), deep=True)
                column.SetName(name)
                initial.AddColumn(column)
            stats = vtkKMeansStatistics()
            stats.SetInputData(vtkStatisticsAlgorithm.INPUT_DATA, data)
            stats.SetInputData(vtkStatisticsAlgorithm.LEARN_PARAMETERS, initial)
            for name in names:
                stats.SetColumnStatus(name, 1)
            stats.RequestSelectedColumns()
            stats.SetLearnOption(True)
            stats.SetDeriveOption(False)
            stats.SetAssessOption(False)
            stats.SetTestOption(False)
            stats.SetTolerance(0.0)
            stats.SetMaxNumIterations(iterations)

            def update():
                stats.Modified()
                stats.Update()
                model = stats.GetOutputDataObject(vtkStatisticsAlgorithm.OUTPUT_MODEL)
                table = model.GetBlock(0)
                for c in range(table.GetNumberOfColumns()):
                    if "Iteration" in (table.GetColumnName(c) or ""):
                        return int(table.GetValue(0, c).ToDouble())
                return iterations

            return update

        for k in compare_ks:
            r = per_iteration(run_vtk, k, args.vtk_repeat)
            r["cells"] = int(len(subset))
            r["ms_per_iteration_subset"] = r["ms_per_iteration"]
            r["ms_per_iteration"] = r["ms_per_iteration_subset"] * n / len(subset)
            results["vtk"][str(k)] = r
            print("vtkKMeansStatistics, K = %2d: %8.1f ms per iteration on %d cells, %.1f scaled"
                  % (k, r["ms_per_iteration_subset"], len(subset), r["ms_per_iteration"]))

    # 5. The table.
    mcells = n / 1e6
    rows = []
    print()
    print("%d x %d cells (%.3f M), %d features, per Lloyd iteration; %s"
          % (nx, ny, mcells, X.shape[1], results["method"]))
    print("%-40s %4s %12s %14s %14s %12s" % ("method", "K", "ms/iter", "ms/iter/Mcell",
                                             "sklearn/ours", "vtk/ours"))
    for k in compare_ks:
        ours = results["ours"][str(k)]["ms_per_iteration"]
        entries = [("ours CPU (%d threads)" % vtkSMPTools.GetEstimatedNumberOfThreads(),
                    results["ours"][str(k)])]
        entries.append(("ours GPU", results["ours_gpu"].get(str(k), {})))
        entries.append(("scikit-learn lloyd float32", results["sklearn"][str(k)]))
        if str(k) in results["vtk"]:
            entries.append(("vtkKMeansStatistics (%dk cells, scaled)"
                            % (results["vtk"][str(k)]["cells"] // 1024), results["vtk"][str(k)]))
        sk = results["sklearn"][str(k)]["ms_per_iteration"]
        vt = results["vtk"].get(str(k), {}).get("ms_per_iteration")
        for label, r in entries:
            if "ms_per_iteration" not in r:
                print("%-40s %4d %12s   %s" % (label, k, "failed", r.get("error", "")[:60]))
                rows.append({"method": label, "K": k, "error": r.get("error")})
                continue
            ms = r["ms_per_iteration"]
            first = label.startswith("ours CPU")
            print("%-40s %4d %12.1f %14.1f %14s %12s"
                  % (label, k, ms, ms / mcells,
                     "%.2f" % (sk / ours) if first else "",
                     ("%.1f" % (vt / ours)) if first and vt else ""))
            rows.append({"method": label, "K": k, "ms_per_iteration": ms,
                         "ms_per_iteration_per_mcell": ms / mcells})
        results.setdefault("ratios", {})[str(k)] = {
            "sklearn_over_ours": sk / ours, "vtk_over_ours": (vt / ours) if vt else None}
    print()
    print("ours CPU, growth with K:")
    print("%4s %12s %14s %14s" % ("K", "ms/iter", "ms/iter/Mcell", "ms/iter/K"))
    for k in ks:
        ms = results["ours"][str(k)]["ms_per_iteration"]
        print("%4d %12.1f %14.1f %14.2f" % (k, ms, ms / mcells, ms / k))
    results["table"] = rows
    results["machine"]["load_after"] = os.getloadavg()
    print("\nload average before %.2f %.2f %.2f, after %.2f %.2f %.2f"
          % (*load_before, *results["machine"]["load_after"]))
    print("ratios > 1: ours is faster")
    if args.json:
        with open(args.json, "w") as out:
            json.dump(results, out, indent=2)
        print("wrote", args.json)


if __name__ == "__main__":
    main()
