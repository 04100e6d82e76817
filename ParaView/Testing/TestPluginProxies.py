"""The plugin in ParaView (pvpython): it loads; every proxy of its XML is made, with its
documentation; the readers are offered for their extensions (.ter, GDAL DEMs); a
filter runs on the bundled Terragen DEM and writes what the C++ class writes.
    pvpython TestPluginProxies.py PLUGIN XML_DIR DATA_DIR"""
import glob
import os
import sys
import xml.etree.ElementTree as ET

from paraview import servermanager
from paraview.simple import LoadPlugin

plugin, xml_dir, data = sys.argv[1:4]
LoadPlugin(plugin, remote=False, ns=globals())
pxm = servermanager.vtkSMProxyManager.GetProxyManager()
session = servermanager.ActiveConnection.Session
failures = []
count = 0
for path in sorted(glob.glob(os.path.join(xml_dir, '*.xml'))):
    for group in ET.parse(path).getroot().iter('ProxyGroup'):
        for element in group:
            proxy = pxm.NewProxy(group.get('name'), element.get('name'))
            count += 1
            if proxy is None:
                failures.append('%s/%s: not made' % (group.get('name'), element.get('name')))
                continue
            if group.get('name') in ('sources', 'filters', 'writers'):
                doc = proxy.GetDocumentation()
                if not (doc and doc.GetShortHelp()):
                    failures.append('%s: no documentation in ParaView' % element.get('name'))

factory = pxm.GetReaderFactory()
for name, reader in (('sagehen_creek_ca/sagehen_dem_utm11n_10m.ter', 'TerroirTerragenReader'),
                     ('sagehen_creek_ca/sagehen_dem_utm11n_10m.tif', 'TerroirDEMReader'),
                     ('sagehen_creek_ca/ned10m_nad83.img', 'TerroirDEMReader'),
                     ('san_francisco_usgs_dem/sanfranciscos.dem', 'TerroirDEMReader')):
    possible = factory.GetPossibleReaders(os.path.join(data, name), session)
    names = [possible.GetString(i) for i in range(possible.GetNumberOfStrings())]
    if reader not in names:
        failures.append('%s: %s is not offered (offered: %s)' % (name, reader, names))

# ParaView's own GDAL reader claims .ter and .tif too (the GUI asks which reader to use), so
# the Terragen reader is named here, then a filter runs on it: the slope of a .ter.
ter = TerroirTerragenReader(  # noqa: F821 (the plugin's)
    FileName=os.path.join(data, 'sagehen_creek_ca/sagehen_dem_utm11n_10m.ter'))
slope = TerroirSlope(Input=ter, SlopeUnits='Percent')  # noqa: F821 (the plugin's)
slope.UpdatePipeline()
info = slope.GetDataInformation()
if sorted(slope.PointData.keys()) != ['Aspect', 'Elevation', 'Normals', 'Slope']:
    failures.append('slope arrays: %s' % sorted(slope.PointData.keys()))
if info.GetExtent() != (0, 785, 0, 719, 0, 0):
    failures.append('slope extent %s, the .ter has 786 x 720 points' % (info.GetExtent(),))
for f in failures:
    print('FAIL', f)
print('%d proxies made, %d failures' % (count, len(failures)))
sys.exit(1 if failures else 0)
