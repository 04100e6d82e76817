#!/usr/bin/python3
"""Writes the seed corpus of FuzzDEMReader (Testing/Fuzz/corpus/DEMReader/) in the layout that
FuzzDEMReader.cxx documents: typical rasters (UTM, geographic, feet, integer with scale,
polar stereographic, a CRS given as WKT), edge cases (1 x 1, no georeference, NaN nodata,
huge pixel size, rotated geotransform, every cell no-data), and 64 x 64 crops of the bundled
Sagehen DEMs (UTM GeoTIFF and geographic NED .img) with their own georeference. Run with
/usr/bin/python3 (python3-gdal) from anywhere; rewrites the folder's seed_*.bin files."""
import os
import struct

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus", "DEMReader")
TYPES = ["Byte", "UInt16", "Int16", "UInt32", "Int32", "Float32", "Float64"]
FMT = {"Byte": "B", "UInt16": "H", "Int16": "h", "UInt32": "I", "Int32": "i", "Float32": "f",
       "Float64": "d"}


def seed(gt=None, nodata=None, scale=None, unit=None, crs=None, dtype="Float32", nx=4, ny=3,
         values=(100.0, 101.5, 99.0, 102.0)):
    flags = ((gt is not None) * 1 | (nodata is not None) * 2 | (scale is not None) * 4
             | (unit is not None) * 8 | (crs is not None) * 16)
    b = struct.pack("<BBBB", flags, TYPES.index(dtype), nx - 1, ny - 1)
    b += struct.pack("<6d", *(gt or (0, 1, 0, 0, 0, -1)))
    b += struct.pack("<d", nodata if nodata is not None else 0.0)
    s, o = scale or (1.0, 0.0)
    b += struct.pack("<dd", s, o)
    u = (unit or "").encode()
    b += struct.pack("<B", len(u)) + u
    if crs is not None:
        kind = crs[0]
        if kind == "epsg":
            b += struct.pack("<BH", 0, crs[1])
        elif kind == "built":
            _, a, invf, lin, proj, lat, lon = crs
            b += struct.pack("<BdddBdd", 1, a, invf, lin, proj, lat, lon)
        else:
            text = crs[1].encode()
            b += struct.pack("<BH", 2, len(text)) + text
    b += b"".join(struct.pack("<" + FMT[dtype], v) for v in values)
    return b


UTM = (734000, 10, 0, 4376000, 0, -10)
SEEDS = {
    "utm_float32_nodata": seed(gt=UTM, nodata=-9999.0, crs=("epsg", 32611),
                               values=(2100.0, -9999.0, 2101.0, 2099.5)),
    "geographic_nad83": seed(gt=(-120.3, 1 / 10800, 0, 39.47, 0, -1 / 10800),
                             crs=("epsg", 4269)),
    "state_plane_us_feet": seed(gt=(6e6, 30, 0, 2e6, 0, -30), unit="ft", crs=("epsg", 2227)),
    "int16_scale_offset": seed(gt=UTM, scale=(0.1, 1000.0), dtype="Int16",
                               values=(0, 10, -10, 32767), crs=("epsg", 32611)),
    "polar_stereographic": seed(gt=(0, 100, 0, 0, 0, -100), crs=("epsg", 3031)),
    "built_tm_odd_unit": seed(gt=UTM, crs=("built", 6378137.0, 298.257, 0.3048, 1, 0.0, -117.0)),
    "built_degenerate_ellipsoid": seed(gt=UTM, crs=("built", 1.0, 0.5, 1.0, 2, 90.0, 0.0)),
    "wkt_local_cs": seed(gt=UTM, crs=("wkt", 'LOCAL_CS["site",UNIT["metre",1]]')),
    "one_by_one": seed(gt=UTM, nx=1, ny=1, values=(5.0,)),
    "no_georeference": seed(values=(1.0, 2.0)),
    "nan_nodata_float64": seed(gt=UTM, nodata=float("nan"), dtype="Float64",
                               values=(float("nan"), 1.0, float("inf"), -3.4e38)),
    "huge_pixel_size": seed(gt=(0, 1e300, 0, 0, 0, -1e300), crs=("epsg", 32611)),
    "rotated": seed(gt=(0, 10, 2, 0, 1, -10)),
    "all_nodata": seed(gt=UTM, nodata=7.0, dtype="Byte", values=(7,)),
    "uint32_big_values": seed(gt=UTM, dtype="UInt32", values=(4294967295, 0, 1, 2)),
}

# Seeds cut from the bundled real DEMs (Data/): 64 x 64 corners with their own georeference.
DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Data",
                    "sagehen_creek_ca")
try:
    from osgeo import gdal
    for name, file, epsg in (("sagehen_utm_crop", "sagehen_dem_utm11n_10m.tif", 32611),
                             ("sagehen_ned_geographic_crop", "ned10m_nad83.img", 4269)):
        ds = gdal.Open(os.path.join(DATA, file))
        band = ds.GetRasterBand(1)
        values = band.ReadAsArray(0, 0, 64, 64).astype("float32").ravel().tolist()
        SEEDS[name] = seed(gt=ds.GetGeoTransform(), nodata=band.GetNoDataValue(),
                           crs=("epsg", epsg), nx=64, ny=64, values=values)
except ImportError:
    print("python3-gdal missing: seeds from Data/ not written")

os.makedirs(OUT, exist_ok=True)
for name, data in SEEDS.items():
    with open(os.path.join(OUT, "seed_" + name + ".bin"), "wb") as f:
        f.write(data)
print(f"{len(SEEDS)} seeds in {OUT}")
