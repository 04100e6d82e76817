"""A ParaView render of a Terroir overlay (pvbatch): the slope of a DEM, top-down, in a grey
colour map from 0 to 60 degrees with its legend, saved as a PNG for the image test.
    pvbatch RenderOverlay.py PLUGIN DEM OUT.png"""
import sys

from paraview.simple import (ColorBy, CreateView, GetColorTransferFunction, GetScalarBar,
                             LoadPlugin, SaveScreenshot, Show)

plugin, dem, out = sys.argv[1:4]
LoadPlugin(plugin, remote=False, ns=globals())
slope = TerroirSlope(Input=TerroirDEMReader(FileName=dem))  # noqa: F821 (the plugin's)
view = CreateView('RenderView')
view.ViewSize = [480, 400]
view.OrientationAxesVisibility = 0
view.Background = [1.0, 1.0, 1.0]
view.UseColorPaletteForBackground = 0
display = Show(slope, view)
display.Representation = 'Slice'
ColorBy(display, ('POINTS', 'Slope'))
lut = GetColorTransferFunction('Slope')
lut.ApplyPreset('Grayscale', True)
lut.RescaleTransferFunction(0.0, 60.0)
lut.AutomaticRescaleRangeMode = 'Never'
bar = GetScalarBar(lut, view)
bar.Title = 'Slope (deg)'
bar.ComponentTitle = ''
bar.TitleColor = bar.LabelColor = [0.0, 0.0, 0.0]
display.SetScalarBarVisibility(view, True)
view.InteractionMode = '2D'
view.ResetCamera()
SaveScreenshot(out, view, ImageResolution=[480, 400])
print('wrote', out)
