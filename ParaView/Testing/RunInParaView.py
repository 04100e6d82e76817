"""Runs a script in pvpython or pvbatch with ParaView's own Python modules first on sys.path:
    pvpython RunInParaView.py SCRIPT ARGS...
The prefix of ParaView/MakePrefix.sh holds python3-paraview's modules (TERROIR_PARAVIEW_SITE);
pvpython puts /usr/lib/python3/dist-packages (Debian's VTK 9.1 `vtkmodules`, from python3-vtk9)
ahead of PYTHONPATH, and importing paraview.simple there crashes. Numpy and the other Debian
modules stay reachable after ParaView's."""
import os
import runpy
import sys

site = os.environ['TERROIR_PARAVIEW_SITE']
sys.path[:] = [site] + [p for p in sys.path if p != site]
script = sys.argv[1]
sys.argv = sys.argv[1:]
runpy.run_path(script, run_name='__main__')
