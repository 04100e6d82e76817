#!/usr/bin/python3
"""The whole pipeline, from a DEM to ecological zones, with the zone table printed.

Pipeline: vtkTerroirDEMReader -> vtkTerroirSlope -> vtkTerroirTemperature ->
vtkTerroirSolarIllumination (monthly hours of sun) -> vtkTerroirInfiltration ->
vtkTerroirSoilHumidity -> vtkTerroirKMeans (K = 5 zones on slope, temperature, sun hours and
weighted soil humidity, Long (2016)'s features and weights).
Prints the zone table (port 1 of vtkTerroirKMeans) and maps the zones.

Run under an X display (or xvfb-run -a):
  PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 \
      Examples/Python/EcologicalZones.py --data Data --out example-output
It runs on the whole bundled DEM (786 x 720 cells) in about 3 s on two cores. On a large DEM
try a window first (vtkExtractVOI after the reader, as in SunHoursAndSunPath.py). `terroir run`
runs the same stages and also writes the table as CSV and JSON.
"""
import argparse
import os
import sys

import terroir

repository_data = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Data")
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--data", default=os.environ.get("TERROIR_DATA_DIR", repository_data),
                    help="bundled data folder (default: $TERROIR_DATA_DIR, else Data/)")
parser.add_argument("--out", default="example-output", help="folder for the PNG")
parser.add_argument("--zones", type=int, default=5, help="number of zones K (default 5)")
args = parser.parse_args()
os.makedirs(args.out, exist_ok=True)

reader = terroir.vtkTerroirDEMReader()
reader.SetFileName(os.path.join(args.data, "sagehen_creek_ca", "sagehen_dem_utm11n_10m.tif"))

# Each stage passes its input's arrays through and adds its own.
slope = terroir.vtkTerroirSlope()  # Slope, Aspect, Normals
slope.SetInputConnection(reader.GetOutputPort())
temperature = terroir.vtkTerroirTemperature()  # Temperature (12 months)
temperature.SetInputConnection(slope.GetOutputPort())
sun = terroir.vtkTerroirSolarIllumination()  # IlluminationHours, Insolation (12 months)
sun.SetInputConnection(temperature.GetOutputPort())
sun.SetModeToMonthly()
infiltration = terroir.vtkTerroirInfiltration()  # InfiltrationRate (mm/h)
infiltration.SetInputConnection(sun.GetOutputPort())
infiltration.AddFill(15.0)  # loam everywhere ...
infiltration.AddSlopeRule(30.0)  # ... but slopes over 30 degrees shed the rain
humidity = terroir.vtkTerroirSoilHumidity()  # SoilHumidity, WeightedSoilHumidity, ...
humidity.SetInputConnection(infiltration.GetOutputPort())

zones = terroir.vtkTerroirKMeans()  # ClusterId, and the zone table on port 1
zones.SetInputConnection(humidity.GetOutputPort())
zones.SetNumberOfClusters(args.zones)
zones.AddFeature("Slope", 1.0)
zones.AddFeature("Temperature", 1.0)
zones.AddFeature("IlluminationHours", 1.0)
zones.AddFeature("WeightedSoilHumidity", 0.1)
zones.Update()
terrain = zones.GetOutput()
table = zones.GetClusterTable()
if terrain.GetNumberOfPoints() == 0 or table.GetNumberOfRows() == 0:
    sys.exit("EcologicalZones: the pipeline failed (see the error above)")

fields = terrain.GetFieldData()
print(f"k-means: {table.GetNumberOfRows()} zones, "
      f"{int(fields.GetArray('KMeansIterations').GetValue(0))} iterations "
      f"({fields.GetAbstractArray('KMeansStopReason').GetValue(0)})")

# The zone table: one row per zone, the mean of every feature in its own units.
columns = [("Slope", "slope_deg"), ("Temperature_Jan", "T_jan_C"), ("Temperature_Jul", "T_jul_C"),
           ("IlluminationHours_Dec", "sun_dec_h"), ("IlluminationHours_Jun", "sun_jun_h"),
           ("WeightedSoilHumidity_Jul", "soil_jul_mm")]
print("zone  colour     cells  share_%  " + "  ".join(f"{title:>11}" for _, title in columns))
total_cells = 0
total_share = 0.0
for row in range(table.GetNumberOfRows()):
    cells = table.GetValueByName(row, "Cells").ToInt()
    share = table.GetValueByName(row, "Share").ToDouble() * 100.0
    total_cells += cells
    total_share += share
    means = "  ".join(f"{table.GetValueByName(row, name).ToDouble():11.3f}" for name, _ in columns)
    print(f"{table.GetValueByName(row, 'ClusterId').ToInt():4d}  "
          f"{table.GetValueByName(row, 'Color').ToString()}  {cells:8d}  {share:7.3f}  {means}")
print(f"total {total_cells} cells, {total_share:.3f} %")

view = terroir.vtkTerroirOverlayView()
view.SetInputData(terrain)
view.SetArrayName("ClusterId")  # the Clusters preset; the legend shows each zone's share
view.SetModeToMap()
view.SetTitle("Ecological zones")
view.SetWidth(400)
view.SetHeight(400)
if not view.WritePNG(os.path.join(args.out, "zones_map.png")):
    sys.exit(f"EcologicalZones: {view.GetLastError()}")
print("wrote zones_map.png")
