"""Scores the rivers of ParaView/Examples/TerroirRivers.py (/usr/bin/python3): the plugin's
RiverStrength against the plugin's burnt reference rivers inside its burnt watershed, by the
independent re-derivation of `terroir validate`'s rule (Testing/Python/
TestRiverScoresIndependent.py: channel cells, length-matching threshold, distance matching),
and checks the counts against `terroir validate --json` of the standalone build, exactly, and
the F1 at 60 m against validation.md's level (floor 0.81).
    ScoreRivers.py PLUGIN_RIVERS.vti TERROIR_BIN WORK_DIR"""
import json
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..',
                                'Testing', 'Python'))
from TestRiverScoresIndependent import read_vti_array, score_measure  # noqa: E402


def main():
    vti, terroir_bin, work = sys.argv[1:4]
    os.makedirs(work, exist_ok=True)
    scores_json = os.path.join(work, 'scores.json')
    subprocess.run([terroir_bin, 'validate', '--json', scores_json, '--backend', 'cpu',
                    '--overwrite'], check=True, capture_output=True, timeout=900)
    with open(scores_json) as f:
        program = {m['name']: m for m in json.load(f)['methods']}['terroir waterflow rivers']
    strength = read_vti_array(vti, 'RiverStrength')
    reference = read_vti_array(vti, 'ReferenceRivers') > 0
    area = read_vti_array(vti, 'Watershed') > 0
    valid = np.isfinite(read_vti_array(vti, 'Elevation'))
    dx = dy = 10.0
    t, mine = score_measure(strength, reference & valid, area & valid, dx, dy)
    status = 0
    for a, b in zip(mine, program['scores']):
        for key in ('simulated_cells', 'reference_cells', 'simulated_hits', 'reference_hits'):
            if a[key] != b[key]:
                print('@%g m: %s %d from the plugin, %d by terroir validate'
                      % (b['tolerance_m'], key, a[key], b[key]))
                status = 1
    print('plugin rivers: threshold %.6g F1@30 %.4f F1@60 %.4f (P %.4f, R %.4f)'
          % (t, mine[0]['f1'], mine[1]['f1'], mine[1]['precision'], mine[1]['recall']))
    if mine[1]['f1'] < 0.81:
        print('F1 at 60 m %.4f is below 0.81 (0.820 in validation.md)' % mine[1]['f1'])
        status = 1
    return status


if __name__ == '__main__':
    sys.exit(main())
