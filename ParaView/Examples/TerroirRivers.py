"""Rivers in ParaView (pvpython or pvbatch): the water flow in its river-forming mode, and the
mapped rivers and the watershed burnt onto the same grid by the plugin's vector rasterizer, all
written to one .vti that `terroir validate`'s scoring rule can read (ParaView/Testing/
ScoreRivers.py scores it).

    pvpython TerroirRivers.py PLUGIN DEM RIVERS.geojson WATERSHED.geojson OUT.vti"""
import sys

from paraview.simple import LoadPlugin, XMLImageDataWriter


def main():
    plugin, dem, rivers, watershed, out = sys.argv[1:6]
    LoadPlugin(plugin, remote=False, ns=globals())
    reader = TerroirDEMReader(FileName=dem)  # noqa: F821 (the plugin defines them)
    flow = TerroirWaterFlow(Input=reader, Mode='Rivers')  # noqa: F821
    reference = TerroirVectorRasterizer(Input=flow, FileName=rivers,  # noqa: F821
                                        OutputArrayName='ReferenceRivers')
    area = TerroirVectorRasterizer(Input=reference, FileName=watershed,  # noqa: F821
                                   OutputArrayName='Watershed')
    XMLImageDataWriter(Input=area, FileName=out).UpdatePipeline()
    river = area.PointData['River'].GetRange()
    print('River', river, 'RiverStrength', area.PointData['RiverStrength'].GetRange())


if __name__ == '__main__':
    main()
