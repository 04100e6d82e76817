"""Tables of scaling_mpi.sh's runs: OUT_DIR/runs.txt (kind, DEM, ranks, recipe, launcher wall
seconds) and each run's rank<R>.json (DistributedChain.py: seconds per stage, output KiB,
peak resident KiB, piece and read extents).
    scaling_summary.py OUT_DIR
Per run: the slowest rank's seconds per stage and for the whole pipeline update, the speed-up
and efficiency against the same DEM and recipe at 1 rank (strong) or against 1 rank at the
same cells per rank (weak), seconds per million cells of a rank's piece, and memory per rank."""
import glob
import json
import os
import sys

SHORT = {'vtkTerroirDEMReader': 'read', 'vtkTerroirSlope': 'slope',
         'vtkTerroirTemperature': 'temp', 'vtkTerroirInfiltration': 'infil',
         'vtkTerroirSoilHumidity': 'humid', 'vtkTerroirKMeans': 'kmeans',
         'vtkTerroirWaterFlow': 'flow', 'vtkTerroirFloodFill': 'lakes'}


def load(out):
    rows = []
    for line in open(os.path.join(out, 'runs.txt')):
        kind, dem, np_, recipe, wall = line.split()
        ranks = []
        for path in sorted(glob.glob(os.path.join(out, '%s-%s-np%s-%s' % (kind, dem, np_, recipe),
                                                  'rank*.json'))):
            ranks.append(json.load(open(path)))
        rows.append(dict(kind=kind, dem=dem, np=int(np_), recipe=recipe, wall=float(wall),
                         ranks=ranks))
    return rows


def main():
    out = sys.argv[1]
    rows = load(out)
    base = {}
    for r in rows:
        rk = r['ranks']
        pieces = [x['piece_extent'] for x in rk]
        r['cells'] = sum((p[1] - p[0] + 1) * (p[3] - p[2] + 1) for p in pieces)
        r['piece_cells'] = max((p[1] - p[0] + 1) * (p[3] - p[2] + 1) for p in pieces)
        r['pipeline'] = max(x['pipeline_seconds'] for x in rk)
        stages = {}
        for x in rk:
            for name, s in x['stage_seconds'].items():
                stages[SHORT.get(name, name)] = max(stages.get(SHORT.get(name, name), 0.0), s)
        r['stages'] = stages
        r['rss_mib'] = max(x['max_rss_kib'] for x in rk) / 1024.0
        r['out_mib'] = max(x['output_kib'] for x in rk) / 1024.0
        r['read_cells'] = max((x['read_extent'][1] - x['read_extent'][0] + 1) *
                              (x['read_extent'][3] - x['read_extent'][2] + 1) for x in rk)
        if r['np'] == 1:
            base[(r['kind'], r['dem'] if r['kind'] == 'strong' else '', r['recipe'])] = r
    print('%-6s %-12s %2s %-5s %9s %9s %8s %6s %5s %8s %8s  %s' % (
        'kind', 'DEM', 'np', 'chain', 'Mcells', 'piece M', 'pipe s', 'speedup', 'eff',
        'RSS MiB', 'out MiB', 'slowest rank s per stage (s per Mcell of its piece)'))
    for r in rows:
        b = base.get((r['kind'], r['dem'] if r['kind'] == 'strong' else '', r['recipe']))
        speedup = b['pipeline'] / r['pipeline'] if b else float('nan')
        if r['kind'] == 'strong':
            eff = speedup / r['np']
        else:  # weak: the same time at N times the cells is 100 %
            eff = (b['pipeline'] / r['pipeline']) if b else float('nan')
        stages = ' '.join('%s %.2f (%.2f)' % (k, v, v / (r['piece_cells'] / 1e6))
                          for k, v in sorted(r['stages'].items()))
        print('%-6s %-12s %2d %-5s %9.2f %9.2f %8.2f %6.2f %4.0f%% %8.0f %8.0f  %s' % (
            r['kind'], r['dem'], r['np'], r['recipe'], r['cells'] / 1e6, r['piece_cells'] / 1e6,
            r['pipeline'], speedup, 100 * eff, r['rss_mib'], r['out_mib'], stages))


if __name__ == '__main__':
    main()
