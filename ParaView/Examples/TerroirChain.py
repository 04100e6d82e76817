"""The chain of `terroir run` as a ParaView pipeline of the Terroir plugin (pvpython or pvbatch):
DEM -> slope -> monthly sun hours -> temperature -> infiltration -> soil humidity -> water flow
(Rivers mode) -> ecological zones (k-means), every filter at its defaults but the water flow's
mode, then the terrain with every array written as a .vti.

    pvbatch TerroirChain.py PLUGIN DEM OUT.vti

Documentation/ParaView.md explains the set-up (Scripts/setup.sh paraview)."""
import sys

from paraview.simple import (LoadPlugin, XMLImageDataWriter)


def build_chain(plugin, dem):
    """The proxies of the chain, by stage name (the last one is the zones)."""
    LoadPlugin(plugin, remote=False, ns=globals())
    stages = {}
    stages['dem'] = TerroirDEMReader(FileName=dem)  # noqa: F821 (the plugin defines them)
    stages['slope'] = TerroirSlope(Input=stages['dem'])  # noqa: F821
    stages['sun'] = TerroirSolarIllumination(Input=stages['slope'])  # noqa: F821
    stages['temperature'] = TerroirTemperature(Input=stages['sun'])  # noqa: F821
    stages['infiltration'] = TerroirInfiltration(Input=stages['temperature'])  # noqa: F821
    stages['humidity'] = TerroirSoilHumidity(Input=stages['infiltration'])  # noqa: F821
    stages['water'] = TerroirWaterFlow(Input=stages['humidity'], Mode='Rivers')  # noqa: F821
    stages['zones'] = TerroirKMeans(Input=stages['water'])  # noqa: F821
    return stages


def main():
    plugin, dem, out = sys.argv[1:4]
    stages = build_chain(plugin, dem)
    writer = XMLImageDataWriter(Input=stages['zones'], FileName=out)
    writer.UpdatePipeline()
    info = stages['zones'].GetDataInformation()
    print('points', info.GetNumberOfPoints())
    print('arrays', ' '.join(sorted(stages['zones'].PointData.keys())))


if __name__ == '__main__':
    main()
