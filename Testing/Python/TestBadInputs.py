#!/usr/bin/python3
"""The bad-input catalogue of Documentation/Reliability.md, checked row by row.

Each row of the catalogue's table names a case, the command a user types, the environment it
runs in, the exit status and the exact line the user reads on stderr. This test makes each
case's input (the functions below, keyed by the case id), runs the command with
/usr/bin/python3's subprocess (never through a shell), and asserts the exit status, the exact
message, and that no output and no temporary file was left behind (an earlier output that was
there stays byte for byte). Progress lines ("read: 50%") are not part of the message.

Placeholders in the table: {dir} the case's scratch folder, {dem} the bundled Sagehen DEM,
{ter} its Terragen twin. Environments: NAME=value, `ulimit -f KIB` (file-size limit: writes
past it fail as on a full disk), `no permission override` (when the tests run as root, the
command runs through util-linux's setpriv without root's CAP_DAC_OVERRIDE and
CAP_DAC_READ_SEARCH, so that file permissions apply to it as to any user).
"""
import os
import re
import resource
import shutil
import stat
import struct
import subprocess
import tempfile
import unittest

import numpy as np
from osgeo import gdal

gdal.UseExceptions()
BIN = os.path.join(os.environ.get("TERROIR_BIN_DIR", "build/bin"), "terroir")
DATA = os.environ.get("TERROIR_DATA_DIR", "Data")
DEM = os.path.join(DATA, "sagehen_creek_ca", "sagehen_dem_utm11n_10m.tif")
TER = os.path.join(DATA, "sagehen_creek_ca", "sagehen_dem_utm11n_10m.ter")
TEMP = os.environ.get("TERROIR_TEMP_DIR", tempfile.gettempdir())
CATALOGUE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                         "Documentation", "Reliability.md")


def write(path, data):
    with open(path, "wb" if isinstance(data, bytes) else "w") as f:
        f.write(data)


def geotiff(path, array, srs="EPSG:32611", gt=(734000, 10, 0, 4376000, 0, -10), nodata=None,
            dtype=gdal.GDT_Float32, options=()):
    ny, nx = array.shape
    ds = gdal.GetDriverByName("GTiff").Create(path, nx, ny, 1, dtype, list(options))
    ds.SetGeoTransform(gt)
    if srs:
        ds.SetProjection(srs)
    band = ds.GetRasterBand(1)
    if nodata is not None:
        band.SetNoDataValue(nodata)
    band.WriteArray(array)
    ds = None


def ascii_grid(path, rows, nodata=-9999):
    lines = [f"ncols {len(rows[0].split())}", f"nrows {len(rows)}", "xllcorner 0",
             "yllcorner 0", "cellsize 10", f"NODATA_value {nodata}"] + rows
    write(path, "\n".join(lines) + "\n")


# Inputs of each case, made in the case's folder `d`.
def make_truncated_tif(d):
    with open(DEM, "rb") as f:
        data = f.read()
    write(os.path.join(d, "cut.tif"), data[: len(data) // 2])


def make_truncated_ter(d):
    with open(TER, "rb") as f:
        data = f.read()
    write(os.path.join(d, "cut.ter"), data[:100000])


def make_oversized_tif(d):
    # A valid GeoTIFF header claiming 100000 x 100000 cells (sparse: a few hundred bytes).
    ds = gdal.GetDriverByName("GTiff").Create(os.path.join(d, "huge.tif"), 100000, 100000, 1,
                                              gdal.GDT_Float32, ["SPARSE_OK=TRUE", "TILED=YES"])
    ds.SetGeoTransform((0, 10, 0, 0, 0, -10))
    ds = None


def make_large_tif(d):
    # 40000 x 40000 cells: within the reader's cell limit, but 7.5 GiB to hold.
    ds = gdal.GetDriverByName("GTiff").Create(os.path.join(d, "large.tif"), 40000, 40000, 1,
                                              gdal.GDT_Float32, ["SPARSE_OK=TRUE", "TILED=YES"])
    ds.SetGeoTransform((0, 10, 0, 0, 0, -10))
    ds = None


def make_oversized_ter(d):
    head = b"TERRAGENTERRAIN " + b"SIZE" + struct.pack("<hh", 32766, 0)
    head += b"XPTS" + struct.pack("<hh", 32767, 0) + b"YPTS" + struct.pack("<hh", 32767, 0)
    write(os.path.join(d, "huge.ter"), head + b"ALTW" + struct.pack("<hh", 1, 0) + b"\0" * 64)


def make_wrong_magic_ter(d):
    with open(TER, "rb") as f:
        data = bytearray(f.read(4096))
    data[0:16] = b"TERRAGENTERRAIM "
    write(os.path.join(d, "bad.ter"), bytes(data))


def make_empty(d):
    write(os.path.join(d, "empty.tif"), b"")
    write(os.path.join(d, "empty.ter"), b"")


def make_text(d):
    write(os.path.join(d, "notes.tif"), "elevation: high\n")


def make_nan_only(d):
    geotiff(os.path.join(d, "nan.tif"), np.full((20, 30), np.nan, dtype=np.float32))


def make_river_case(d):
    # A 30 x 20 DEM (UTM 11N, 10 m) with a no-data hole, a line across it, and a polygon 100 km
    # away, for `terroir validate`.
    z = np.fromfunction(lambda j, i: 2000.0 + i + j, (20, 30)).astype(np.float32)
    z[10, 15] = np.nan
    geotiff(os.path.join(d, "hole.tif"), z)
    crs = '"crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::32611"}}'
    write(os.path.join(d, "line.geojson"),
          '{"type": "FeatureCollection", ' + crs + ', "features": [{"type": "Feature", '
          '"properties": {}, "geometry": {"type": "LineString", '
          '"coordinates": [[734005, 4375905], [734295, 4375905]]}}]}')
    write(os.path.join(d, "cover.geojson"),
          '{"type": "FeatureCollection", ' + crs + ', "features": [{"type": "Feature", '
          '"properties": {}, "geometry": {"type": "Polygon", "coordinates": [[[734000, 4376000], '
          '[734300, 4376000], [734300, 4375800], [734000, 4375800], [734000, 4376000]]]}}]}')
    write(os.path.join(d, "far.geojson"),
          '{"type": "FeatureCollection", ' + crs + ', "features": [{"type": "Feature", '
          '"properties": {}, "geometry": {"type": "Polygon", "coordinates": [[[834000, 4376000], '
          '[835000, 4376000], [835000, 4377000], [834000, 4376000]]]}}]}')


def make_nodata_everywhere(d):
    ascii_grid(os.path.join(d, "nodata.asc"), ["-9999 -9999 -9999", "-9999 -9999 -9999"])


def make_mismatched_crs(d):
    # Metre coordinates (UTM-sized) under a geographic CRS: latitudes of millions of degrees.
    geotiff(os.path.join(d, "utm_as_degrees.tif"), np.ones((20, 30), dtype=np.float32),
            srs="EPSG:4269")


def make_rotated(d):
    geotiff(os.path.join(d, "rotated.tif"), np.ones((20, 30), dtype=np.float32),
            gt=(734000, 10, 2, 4376000, 1, -10))


def make_degenerate_ellipsoid(d):
    ascii_grid(os.path.join(d, "ok.asc"), ["1 2 3", "4 5 6"])
    write(os.path.join(d, "odd.vrt"),
          '<VRTDataset rasterXSize="3" rasterYSize="2"><SRS>GEOGCS["odd",DATUM["odd",'
          'SPHEROID["odd",1,0.5]],PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433]]</SRS>'
          '<GeoTransform>10, 0.001, 0, 40, 0, -0.001</GeoTransform><VRTRasterBand '
          'dataType="Float32" band="1"><SimpleSource><SourceFilename relativeToVRT="1">ok.asc'
          '</SourceFilename><SourceBand>1</SourceBand></SimpleSource></VRTRasterBand>'
          '</VRTDataset>\n')


def make_directory(d):
    os.mkdir(os.path.join(d, "folder.tif"))


def make_fifo(d):
    os.mkfifo(os.path.join(d, "pipe.tif"))


def make_unreadable(d):
    shutil.copy(DEM, os.path.join(d, "secret.tif"))
    os.chmod(os.path.join(d, "secret.tif"), 0)


def make_remote_vrt(d):
    write(os.path.join(d, "remote.vrt"),
          '<VRTDataset rasterXSize="3" rasterYSize="2"><GeoTransform>0, 10, 0, 20, 0, -10'
          '</GeoTransform><VRTRasterBand dataType="Float32" band="1"><SimpleSource>'
          '<SourceFilename relativeToVRT="0">/vsicurl/http://127.0.0.1:9/dem.tif</SourceFilename>'
          '<SourceBand>1</SourceBand><SourceProperties RasterXSize="3" RasterYSize="2" '
          'DataType="Float32" BlockXSize="3" BlockYSize="1"/></SimpleSource></VRTRasterBand>'
          '</VRTDataset>\n')


def make_wms(d):
    write(os.path.join(d, "tiles.xml"),
          '<GDAL_WMS><Service name="TMS"><ServerUrl>http://127.0.0.1:9/${z}/${x}/${y}.png'
          '</ServerUrl></Service><DataWindow><UpperLeftX>-20037508.34</UpperLeftX><UpperLeftY>'
          '20037508.34</UpperLeftY><LowerRightX>20037508.34</LowerRightX><LowerRightY>'
          '-20037508.34</LowerRightY><TileLevel>1</TileLevel><TileCountX>1</TileCountX>'
          '<TileCountY>1</TileCountY><YOrigin>top</YOrigin></DataWindow><Projection>EPSG:3857'
          '</Projection><BlockSizeX>256</BlockSizeX><BlockSizeY>256</BlockSizeY><BandsCount>1'
          '</BandsCount></GDAL_WMS>\n')


def make_existing_output(d):
    write(os.path.join(d, "slope.tif"), "an earlier result")


def make_earlier_result(d):
    # An earlier slope of a small DEM; replacing it with the bundled DEM's slope needs more room
    # than `ulimit -f` leaves.
    geotiff(os.path.join(d, "small.tif"), np.arange(64, dtype=np.float32).reshape(8, 8))
    for out in ("slope.tif", "slope.vti"):
        subprocess.run([BIN, "slope", os.path.join(d, "small.tif"), os.path.join(d, out)],
                       check=True, capture_output=True)


def make_climate_missing_month(d):
    write(os.path.join(d, "climate.csv"),
          "month,temperature_c\n" + "".join(f"{m},{m}\n" for m in range(1, 12)))


def make_climate_negative_rain(d):
    write(os.path.join(d, "climate.json"),
          '{"precipitation_mm": [80, 70, -5, 60, 50, 40, 20, 20, 40, 60, 70, 80]}\n')


def make_view_script(d):
    write(os.path.join(d, "s.txt"), "overlay slope\nmonth 13\nquit\n")


def make_nothing(d):
    pass


SETUP = {name[len("make_"):]: f for name, f in globals().items() if name.startswith("make_")}


def parse_catalogue():
    """Rows of the catalogue table: (id, command, environment, exit, message)."""
    rows = []
    with open(CATALOGUE) as f:
        text = f.read()
    # Only the table of the "Bad-input catalogue" section.
    section = text.split("## Bad-input catalogue", 1)[1].split("\n## ", 1)[0]
    unquote = lambda c: c.strip("`").strip() if c.startswith("`") else c
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) != 6 or not cells[0].startswith("`"):
            continue
        rows.append(dict(id=unquote(cells[0]), what=cells[1], command=unquote(cells[2]),
                         env=unquote(cells[3]), exit=int(cells[4]), message=unquote(cells[5])))
    return rows


def run_case(row, folder):
    fill = lambda s: s.replace("{dir}", folder).replace("{dem}", DEM).replace("{ter}", TER)
    args = fill(row["command"]).split(" ")
    assert args[0] == "terroir", row["command"]
    env = dict(os.environ)
    env.pop("TERROIR_MEMORY_LIMIT", None)
    preexec = None
    prefix = []
    spec = fill(row["env"])
    if spec.startswith("ulimit -f "):
        kib = int(spec.split()[2])
        preexec = lambda: resource.setrlimit(resource.RLIMIT_FSIZE, (kib * 1024, kib * 1024))
    elif spec == "no permission override":
        if os.geteuid() == 0:
            prefix = ["setpriv", "--bounding-set=-dac_override,-dac_read_search"]
    elif spec not in ("", "-"):
        key, value = spec.split("=", 1)
        env[key] = value
    return subprocess.run(prefix + [BIN] + args[1:], capture_output=True, text=True, env=env,
                          preexec_fn=preexec, timeout=300)


def snapshot(folder):
    """Every file of the folder with its bytes (FIFOs and folders by name only)."""
    out = {}
    for name in sorted(os.listdir(folder)):
        path = os.path.join(folder, name)
        mode = os.lstat(path).st_mode
        if stat.S_ISREG(mode) and os.access(path, os.R_OK):
            with open(path, "rb") as f:
                out[name] = f.read()
        else:
            out[name] = None
    return out


class BadInputCatalogue(unittest.TestCase):
    def test_every_row_gives_its_exact_message_and_leaves_nothing(self):
        rows = parse_catalogue()
        self.assertGreaterEqual(len(rows), 30, "catalogue table not found or too short")
        self.assertEqual(sorted({r["id"] for r in rows}), sorted(SETUP),
                         "every case has one input maker and at least one row")
        root = tempfile.mkdtemp(prefix="bad-inputs-", dir=TEMP)
        os.chmod(root, 0o755)
        try:
            for k, row in enumerate(rows):
                with self.subTest(case=row["id"], command=row["command"]):
                    folder = os.path.join(root, f"{k:02d}_{row['id']}")
                    os.mkdir(folder)
                    SETUP[row["id"]](folder)
                    before = snapshot(folder)
                    r = run_case(row, folder)
                    lines = [l for l in r.stderr.splitlines()
                             if l.strip() and not re.fullmatch(r"\w+: \d+%", l)]
                    expected = row["message"].replace("{dir}", folder).replace(
                        "{dem}", DEM).replace("{ter}", TER)
                    self.assertEqual(r.returncode, row["exit"], r.stderr)
                    self.assertEqual(lines, [expected])
                    self.assertEqual(snapshot(folder), before, "output or temporary left behind")
        finally:
            for dirpath, dirnames, filenames in os.walk(root):
                for n in filenames:
                    p = os.path.join(dirpath, n)
                    if not os.path.islink(p):
                        os.chmod(p, 0o644)
            shutil.rmtree(root, ignore_errors=True)


if __name__ == "__main__":
    unittest.main(verbosity=2)
