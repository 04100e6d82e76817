#!/usr/bin/python3
"""Writes the seed corpus of FuzzVectorRasterizer (Testing/Fuzz/corpus/VectorRasterizer/) in the
layout that FuzzVectorRasterizer.cxx documents: four option bytes, then a vector file. The files
cover polygons (with a hole), lines, points and multi-geometries in the harness's UTM 11N grid,
lon/lat features without a CRS member for the geographic grid, numeric, null and text
attributes, a layer named "rivers", the first bundled NHD flowlines moved into the grid, a
TopoJSON, an ESRI JSON, a GML and a KML file, and a few malformed files. Run with /usr/bin/python3
from anywhere; rewrites the folder's seed_*.bin files."""
import glob
import json
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "corpus", "VectorRasterizer")
NHD = os.path.join(HERE, "..", "..", "Data", "sagehen_creek_ca",
                   "sagehen_nhd_flowlines_utm11n.geojson")
UTM = {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::32611"}}

# Flag bits of the harness.
ALL_TOUCHED, ATTRIBUTE, GEOGRAPHIC, FILTER, LAYER = 1, 2, 4, 8, 16


def header(flags=0, burn=0, nx=16, ny=12):
    return struct.pack("<BBBB", flags, burn, nx - 1, ny - 1)


def collection(features, crs=UTM, name="soils"):
    doc = {"type": "FeatureCollection", "name": name}
    if crs:
        doc["crs"] = crs
    doc["features"] = [{"type": "Feature", "properties": p, "geometry": g} for p, g in features]
    return json.dumps(doc).encode()


def ring(x0, y0, x1, y1):
    return [[x0, y0], [x1, y0], [x1, y1], [x0, y1], [x0, y0]]


def nhd_moved(count=2):
    """The first bundled NHD flowlines (NAD83 / UTM 11N), moved into the harness's grid."""
    with open(NHD) as f:
        doc = json.load(f)
    features = []
    for feat in doc["features"][:count]:
        coords = [[500000 + (x - 214700) * 0.6, 4359700 + (y - 4368300) * 0.6]
                  for x, y in feat["geometry"]["coordinates"]]
        props = dict(feat["properties"], v=feat["properties"]["FCODE"])
        features.append((props, {"type": "LineString", "coordinates": coords}))
    return collection(features, name="rivers")


def seeds():
    square = {"type": "Polygon", "coordinates": [ring(500020, 4359900, 500090, 4359960)]}
    holed = {"type": "Polygon", "coordinates": [ring(500010, 4359890, 500150, 4359990),
                                                ring(500050, 4359920, 500100, 4359960)]}
    line = {"type": "LineString", "coordinates": [[500003, 4359885], [500157, 4359995]]}
    point = {"type": "Point", "coordinates": [500045, 4359935]}
    multi = {"type": "MultiPolygon", "coordinates": [[ring(500000, 4359880, 500030, 4359900)],
                                                     [ring(500100, 4359950, 500160, 4360000)]]}
    lonlat = {"type": "Polygon", "coordinates": [ring(-116.999, 35.991, -116.992, 35.998)]}
    yield "utm_polygon", header(), collection([({"v": 3}, square)])
    yield "utm_polygon_hole_all_touched", header(ALL_TOUCHED), collection([({"v": 2}, holed)])
    yield "utm_line_burn7", header(burn=1), collection([({"v": 1.5}, line)])
    yield "utm_point_fractional_burn", header(burn=2), collection([({"v": 4}, point)])
    yield "utm_multi_negative_burn", header(burn=3), collection([({"v": -2}, multi)])
    yield "attribute_overlap", header(ATTRIBUTE), collection(
        [({"v": 1}, holed), ({"v": 9.25}, square), ({"v": None}, point)])
    yield "attribute_filter", header(ATTRIBUTE | FILTER), collection(
        [({"v": -1}, holed), ({"v": 5}, line)])
    yield "attribute_text", header(ATTRIBUTE), collection([({"v": "clay"}, square)])
    yield "attribute_huge", header(ATTRIBUTE), collection([({"v": 1e300}, square)])
    yield "geographic_no_crs", header(GEOGRAPHIC, nx=10, ny=10), collection(
        [({"v": 1}, lonlat)], crs=None)
    yield "geographic_all_touched", header(GEOGRAPHIC | ALL_TOUCHED, nx=12, ny=9), collection(
        [({"v": 1}, {"type": "LineString", "coordinates": [[-117.0, 35.995], [-116.99, 35.999]]})],
        crs=None)
    yield "nhd_rivers_layer", header(LAYER | ATTRIBUTE | ALL_TOUCHED, nx=32, ny=32), nhd_moved()
    yield "layer_not_found", header(LAYER), collection([({"v": 1}, square)])
    yield "outside_terrain", header(), collection(
        [({"v": 1}, {"type": "Point", "coordinates": [600000, 4000000]})])
    yield "empty_collection", header(), collection([])
    yield "null_geometry", header(), b'{"type":"FeatureCollection","crs":' + json.dumps(UTM).encode() \
        + b',"features":[{"type":"Feature","properties":{"v":1},"geometry":null}]}'
    yield "geometry_collection", header(ALL_TOUCHED), collection([({"v": 1}, {
        "type": "GeometryCollection", "geometries": [point, line]})])
    yield "unknown_crs", header(), collection(
        [({"v": 1}, square)], crs={"type": "name", "properties": {"name": "EPSG:999999"}})
    yield "topojson", header(), json.dumps({
        "type": "Topology",
        "objects": {"soils": {"type": "GeometryCollection", "geometries": [
            {"type": "Polygon", "arcs": [[0]], "properties": {"v": 1}}]}},
        "arcs": [[[-116.998, 35.992], [-116.993, 35.992], [-116.993, 35.997], [-116.998, 35.997],
                  [-116.998, 35.992]]]}).encode()
    yield "esrijson", header(), json.dumps({
        "geometryType": "esriGeometryPolygon", "spatialReference": {"wkid": 32611},
        "fields": [{"name": "v", "type": "esriFieldTypeInteger"}],
        "features": [{"attributes": {"v": 1},
                      "geometry": {"rings": [ring(500020, 4359900, 500090, 4359960)]}}]}).encode()
    yield "gml", header(GEOGRAPHIC), (
        b'<?xml version="1.0"?><ogr:FeatureCollection xmlns:ogr="http://ogr.maptools.org/" '
        b'xmlns:gml="http://www.opengis.net/gml"><gml:featureMember><ogr:soils><ogr:geometryProperty>'
        b'<gml:Polygon srsName="EPSG:4326"><gml:outerBoundaryIs><gml:LinearRing><gml:coordinates>'
        b'-116.998,35.992 -116.993,35.992 -116.993,35.997 -116.998,35.992</gml:coordinates>'
        b'</gml:LinearRing></gml:outerBoundaryIs></gml:Polygon></ogr:geometryProperty>'
        b'<ogr:v>3</ogr:v></ogr:soils></gml:featureMember></ogr:FeatureCollection>')
    yield "kml", header(GEOGRAPHIC | ALL_TOUCHED), (
        b'<?xml version="1.0"?><kml xmlns="http://www.opengis.net/kml/2.2"><Document><Placemark>'
        b'<LineString><coordinates>-117.0,35.995 -116.99,35.999</coordinates></LineString>'
        b'</Placemark></Document></kml>')
    yield "truncated", header(), collection([({"v": 1}, square)])[:70]
    yield "not_json", header(), b"\x00\x01garbage\xff"
    yield "empty_file", header(), b""


def main():
    os.makedirs(OUT, exist_ok=True)
    for old in glob.glob(os.path.join(OUT, "seed_*.bin")):
        os.remove(old)
    for name, head, body in seeds():
        with open(os.path.join(OUT, "seed_%s.bin" % name), "wb") as f:
            f.write(head + body)


if __name__ == "__main__":
    main()
