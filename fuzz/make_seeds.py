#!/usr/bin/env python3
"""Writes the seed corpora of the fuzz targets (scripts/fuzz.sh runs it): for each target
a folder of small inputs, from the shared data sets (cut to their first bytes where large)
and tiny valid files written here in every layout the reader takes, so that fuzzing starts
past the headers. Inputs follow the targets' conventions (see fuzz/fuzz_*.cpp): the points
target's first two bytes pick the format and colouring; multi-file formats are parts
joined by separator lines.

usage: make_seeds.py DATA_DIR OUT_DIR"""
import base64
import gzip
import pathlib
import struct
import sys
import zlib

data_dir, out_dir = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
CUT = 4096  # bytes kept of a large shared file: its header and first records


def seed(target, name, content):
    folder = out_dir / target
    folder.mkdir(parents=True, exist_ok=True)
    (folder / name).write_bytes(content.encode() if isinstance(content, str) else content)


def head(path, size=CUT):
    with open(path, "rb") as f:
        return f.read(size)


# ---- PLY meshes
ply_ascii = """ply
format ascii 1.0
comment a tetrahedron with normals, colours and texture coordinates
element vertex 4
property float x
property float y
property float z
property float nx
property float ny
property float nz
property uchar red
property uchar green
property uchar blue
property float u
property float v
element face 4
property list uchar int vertex_indices
end_header
0 0 0 0 0 1 255 0 0 0 0
1 0 0 0 0 1 0 255 0 1 0
0 1 0 0 0 1 0 0 255 0 1
0 0 1 0 0 1 255 255 255 1 1
3 0 1 2
3 0 1 3
4 0 1 2 3
3 1 2 3
"""
seed("ply", "ascii.ply", ply_ascii)


def binary_ply(little, quads=False):
    e = "<" if little else ">"
    header = ("ply\nformat binary_%s_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
              "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
              % ("little" if little else "big"))
    body = b"".join(struct.pack(e + "3f", *p) for p in [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0)])
    if quads:
        body += struct.pack(e + "B4i", 4, 0, 1, 3, 2) + struct.pack(e + "B3i", 3, 0, 1, 2)
    else:
        body += struct.pack(e + "B3i", 3, 0, 1, 2) + struct.pack(e + "B3i", 3, 1, 3, 2)
    return header.encode() + body


seed("ply", "binary_le.ply", binary_ply(True))
seed("ply", "binary_be_quads.ply", binary_ply(False, quads=True))
general = ("ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
           "property double z\nproperty list uchar float extra\nelement face 1\nproperty ushort flags\n"
           "property list ushort uint vertex_index\nproperty float red\nproperty float green\nproperty float blue\n"
           "element other 1\nproperty int w\nend_header\n").encode()
for p in [(0, 0, 0), (1, 0, 0), (0, 1, 0)]:
    general += struct.pack("<3dB", *p, 1) + struct.pack("<f", 0.5)
general += struct.pack("<HH3I3f", 7, 3, 0, 1, 2, 1, 0.5, 0) + struct.pack("<i", 5)
seed("ply", "general.ply", general)
for mesh in sorted((data_dir / "meshes").glob("*.ply")):
    # The header with its counts cut to what the first bytes hold: 20 vertices, no faces.
    data = head(mesh)
    end = data.find(b"\n", data.find(b"end_header")) + 1
    lines = [b"element vertex 20" if line.startswith(b"element vertex ")
             else b"element face 0" if line.startswith(b"element face ") else line
             for line in data[:end].split(b"\n")]
    seed("ply", mesh.name, b"\n".join(lines) + data[end:])

# ---- point clouds: byte 0 picks ply/xyz/xyzr/f32xyzr, byte 1 odd for the file's colours
points_ply = """ply
format ascii 1.0
element vertex 3
property float x
property float y
property float z
property float radius
property uchar red
property uchar green
property uchar blue
property float intensity
end_header
0 0 0 0.1 255 0 0 1
1 0 0 0.2 0 255 0 2
0 1 0 0.3 0 0 255 3
"""
seed("points", "ply", b"\x00\x01" + points_ply.encode())
seed("points", "ply_binary", b"\x00\x00" + binary_ply(True))
seed("points", "xyz", b"\x01\x00" + b"# x y z\n0 0 0\n1 2 3\n-1.5 2e3 +4\n")
seed("points", "xyzr", b"\x02\x00" + b"0 0 0 0.5\n1 2 3 0.25\n")
seed("points", "f32xyzr", b"\x03\x00" + struct.pack("<8f", 0, 0, 0, 1, 1, 2, 3, 0.5))
seed("points", "stars_head", b"\x00\x00" + head(data_dir / "meshes" / "footbones.ply", 1024))

# ---- .obj with .mtl and a .pfm texture
obj = """# a quad and a triangle
mtllib f.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1 0.5 0.5 0.5
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 0 1
o quad
usemtl red
f 1/1/1 2/2/1 3/3/1 4/4/1
o tri
usemtl textured
f -5//1 -4//1 -1//1
g group
s 1
l 1 2
"""
mtl = """newmtl red
Kd 1 0 0
Ks 0.5 0.5 0.5
Ns 20
d 1
newmtl textured
Kd 1 1 1
Tr 0.2
map_Kd t.pfm
map_d -clamp on t.pfm
bump t.pfm
"""
pfm = b"PF\n2 1\n-1.0\n" + struct.pack("<6f", 0, 0.5, 1, 1, 0.5, 0)
seed("obj", "obj_mtl_pfm", obj.encode() + b"\n#@mtl\n" + mtl.encode() + b"\n#@pfm\n" + pfm)
seed("obj", "obj_only", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
seed("obj", "grey_pfm", obj.encode() + b"\n#@mtl\n" + mtl.encode() + b"\n#@pfm\nPf\n1 1\n1.0\n\x00\x00\x80\x3f")

# ---- PDB
pdb = """HEADER    TEST
ATOM      1  N   ALA A   1      11.104   6.134  -6.504  1.00  0.00           N
ATOM      2  CA  ALA A   1      11.639   6.071  -5.147  1.00  0.00           C
ATOM      3  C   ALA A   1      13.149   5.970  -5.154  1.00  0.00
ATOM      4  O  AALA A   1      13.741   5.590  -6.164  1.00  0.00           O
ATOM      5  O  BALA A   1      13.741   5.590  -6.164  1.00  0.00           O
HETATM    6 FE   HEM A   2      10.000  10.000  10.000  1.00  0.00          FE
HETATM    7  O   HOH A   3       0.000   0.000   0.000  1.00  0.00           O
CONECT    1    2
CONECT    2    1    3
ENDMDL
ATOM      8  N   ALA A   1      11.104   6.134  -6.504  1.00  0.00           N
END
"""
seed("pdb", "tiny.pdb", pdb)
for molecule in sorted((data_dir / "molecules").glob("*.pdb")):
    # Its first records of each kind: a few header lines, atoms, hetero atoms and bonds.
    kept, count = [], {}
    for line in molecule.read_bytes().splitlines(keepends=True):
        kind = line[:6].strip()
        kind = kind if kind in (b"ATOM", b"HETATM", b"CONECT", b"ENDMDL", b"END") else b"other"
        count[kind] = count.get(kind, 0) + 1
        if count[kind] <= {b"ATOM": 60, b"HETATM": 20, b"CONECT": 10, b"other": 10}.get(kind, 1):
            kept.append(line)
    seed("pdb", molecule.name, b"".join(kept))

# ---- raw volumes: sidecar JSON, separator, voxels
seed("volume_raw", "uint8", '{"dims": [2, 2, 2], "type": "uint8", "spacing": [1, 2, 3], "origin": [0, 0, -1], '
     '"range": [0, 7]}\n#@raw\n' + "".join(chr(i) for i in range(8)))
seed("volume_raw", "float32",
     b'{"dims": [2, 1, 1], "type": "float32"}\n#@raw\n' + struct.pack("<2f", 0.5, -1))
seed("volume_raw", "uint16", b'{"dims": [1, 1, 3], "type": "uint16", "x": {"a": [true, false, null, "\\u00e9\\n"]}}'
     b"\n#@raw\n" + struct.pack("<3H", 1, 2, 3))
for sidecar in sorted((data_dir / "volumes").glob("*.json")):
    seed("volume_raw", sidecar.name, head(sidecar) + b"\n#@raw\n" + head(sidecar.with_suffix(".raw"), 256))

# ---- NRRD: attached raw, attached gzip, detached
voxels = bytes(range(8))
seed("nrrd", "raw.nrrd", b"NRRD0004\n# comment\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
     b"spacings: 1 1 -2\ncenters: cell cell cell\nkey:=value\n\n" + voxels)
seed("nrrd", "gzip.nrrd", b"NRRD0005\ntype: short\ndimension: 3\nsizes: 2 1 1\nencoding: gzip\nendian: big\n"
     b"space dimension: 3\nspace directions: (1,0,0) (0,-1,0) (0,0,2.5)\nspace origin: (0,1,2)\n\n"
     + gzip.compress(struct.pack(">2h", -5, 7)))
seed("nrrd", "detached.nrrd", b"NRRD0004\ntype: float\ndimension: 3\nsizes: 1 1 2\nencoding: raw\nendian: little\n"
     b"data file: d.raw\nline skip: 1\nbyte skip: -1\n\n#@data\nskipped line\n" + struct.pack("<2f", 1, 2))

# ---- VTK XML: every data layout (ascii, base64, appended raw and base64, zlib blocks)
def vtk_block(values_bytes, compressed, header64=False):
    word = "<Q" if header64 else "<I"
    if not compressed:
        return struct.pack(word, len(values_bytes)) + values_bytes
    packed = zlib.compress(values_bytes)
    return struct.pack(word, 1) + struct.pack(word, len(values_bytes)) + struct.pack(word, len(values_bytes)) + \
        struct.pack(word, len(packed)) + packed


def b64_block(values_bytes, compressed, header64=False):
    if not compressed:
        return base64.b64encode(vtk_block(values_bytes, False, header64)).decode()
    word = "<Q" if header64 else "<I"
    packed = zlib.compress(values_bytes)
    header = struct.pack(word, 1) + struct.pack(word, len(values_bytes)) * 2 + struct.pack(word, len(packed))
    return base64.b64encode(header).decode() + base64.b64encode(packed).decode()


def vtk_file(kind, body, compressed=False, header64=False, appended=b"", encoding="raw"):
    attributes = f'type="{kind}" version="1.0" byte_order="LittleEndian" header_type="{"UInt64" if header64 else "UInt32"}"'
    if compressed:
        attributes += ' compressor="vtkZLibDataCompressor"'
    text = f'<?xml version="1.0"?>\n<VTKFile {attributes}>\n{body}\n'.encode()
    if appended:
        text += f'<AppendedData encoding="{encoding}">_'.encode() + appended + b"\n</AppendedData>\n"
    return text + b"</VTKFile>\n"


tetra_points = struct.pack("<12f", 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1)
vtu_ascii = """<UnstructuredGrid><Piece NumberOfPoints="4" NumberOfCells="1">
<PointData Scalars="s"><DataArray type="Float32" Name="s" format="ascii">0 1 2 3</DataArray></PointData>
<CellData><DataArray type="Float64" Name="v" NumberOfComponents="3" format="ascii">1 2 3</DataArray></CellData>
<Points><DataArray type="Float32" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0 0 0 1</DataArray></Points>
<Cells><DataArray type="Int64" Name="connectivity" format="ascii">0 1 2 3</DataArray>
<DataArray type="Int64" Name="offsets" format="ascii">4</DataArray>
<DataArray type="UInt8" Name="types" format="ascii">10</DataArray></Cells>
</Piece></UnstructuredGrid>"""
seed("vtu", "ascii.vtu", vtk_file("UnstructuredGrid", vtu_ascii))


def vtu_binary(compressed, header64):
    arrays = [("Float32", "s", 1, struct.pack("<4f", 0, 1, 2, 3), "PointData"),
              ("Float32", None, 3, tetra_points, "Points"),
              ("Int32", "connectivity", 1, struct.pack("<4i", 0, 1, 2, 3), "Cells"),
              ("Int32", "offsets", 1, struct.pack("<i", 4), "Cells"),
              ("UInt8", "types", 1, bytes([10]), "Cells")]
    sections = {}
    for type_, name, components, data, section in arrays:
        named = f' Name="{name}"' if name else ""
        sections.setdefault(section, []).append(
            f'<DataArray type="{type_}"{named} NumberOfComponents="{components}" format="binary">'
            f"{b64_block(data, compressed, header64)}</DataArray>")
    body = '<UnstructuredGrid><Piece NumberOfPoints="4" NumberOfCells="1">' + "".join(
        f"<{s}>{''.join(a)}</{s}>" for s, a in sections.items()) + "</Piece></UnstructuredGrid>"
    return vtk_file("UnstructuredGrid", body, compressed, header64)


seed("vtu", "binary.vtu", vtu_binary(False, False))
seed("vtu", "binary_zlib64.vtu", vtu_binary(True, True))


def vtu_appended(compressed, encoding):
    blobs = [struct.pack("<4f", 0, 1, 2, 3), tetra_points, struct.pack("<4q", 0, 1, 2, 3), struct.pack("<q", 4),
             bytes([10])]
    offsets, appended = [], b""
    for blob in blobs:
        offsets.append(len(appended))
        appended += b64_block(blob, compressed).encode() if encoding == "base64" else vtk_block(blob, compressed)
    body = f"""<UnstructuredGrid><Piece NumberOfPoints="4" NumberOfCells="1">
<PointData><DataArray type="Float32" Name="s" format="appended" offset="{offsets[0]}"/></PointData>
<Points><DataArray type="Float32" NumberOfComponents="3" format="appended" offset="{offsets[1]}"/></Points>
<Cells><DataArray type="Int64" Name="connectivity" format="appended" offset="{offsets[2]}"/>
<DataArray type="Int64" Name="offsets" format="appended" offset="{offsets[3]}"/>
<DataArray type="UInt8" Name="types" format="appended" offset="{offsets[4]}"/></Cells>
</Piece></UnstructuredGrid>"""
    return vtk_file("UnstructuredGrid", body, compressed, appended=appended, encoding=encoding)


seed("vtu", "appended_raw.vtu", vtu_appended(False, "raw"))
seed("vtu", "appended_zlib_base64.vtu", vtu_appended(True, "base64"))
for grid in sorted((data_dir / "unstructured").glob("*.vtu")):
    seed("vtu", grid.name, head(grid))

vti = """<ImageData WholeExtent="0 1 0 1 0 1" Origin="0 0 0" Spacing="1 1 2" Direction="1 0 0 0 1 0 0 0 1">
<Piece Extent="0 1 0 1 0 0"><PointData Scalars="d"><DataArray type="UInt8" Name="d" format="ascii">0 1 2 3</DataArray></PointData></Piece>
<Piece Extent="0 1 0 1 1 1"><PointData Scalars="d"><DataArray type="UInt8" Name="d" format="ascii">4 5 6 7</DataArray></PointData></Piece>
</ImageData>"""
seed("vti", "pieces.vti", vtk_file("ImageData", vti))
vti_cells = f"""<ImageData WholeExtent="0 2 0 1 0 1" Origin="1 2 3" Spacing="0.5 0.5 0.5">
<Piece Extent="0 2 0 1 0 1"><CellData Scalars="c"><DataArray type="Float64" Name="c" format="binary">{b64_block(struct.pack("<2d", 1.5, -2), True)}</DataArray>
<DataArray type="Int16" Name="n" format="binary">{b64_block(struct.pack("<2h", 1, 2), False)}</DataArray></CellData></Piece>
</ImageData>"""
seed("vti", "cells_zlib.vti", vtk_file("ImageData", vti_cells, compressed=True))

vtp = f"""<PolyData><Piece NumberOfPoints="4" NumberOfVerts="1" NumberOfLines="1" NumberOfStrips="1" NumberOfPolys="1">
<PointData Scalars="s" Normals="n" TCoords="t"><DataArray type="Float32" Name="s" format="ascii">0 1 2 3</DataArray>
<DataArray type="Float32" Name="n" NumberOfComponents="3" format="ascii">0 0 1 0 0 1 0 0 1 0 0 1</DataArray>
<DataArray type="Float32" Name="t" NumberOfComponents="2" format="ascii">0 0 1 0 1 1 0 1</DataArray></PointData>
<CellData><DataArray type="Int32" Name="id" format="ascii">0 1 2 3</DataArray></CellData>
<Points><DataArray type="Float64" NumberOfComponents="3" format="binary">{b64_block(struct.pack("<12d", 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0), False)}</DataArray></Points>
<Verts><DataArray type="Int32" Name="connectivity" format="ascii">0</DataArray><DataArray type="Int32" Name="offsets" format="ascii">1</DataArray></Verts>
<Lines><DataArray type="Int32" Name="connectivity" format="ascii">0 1</DataArray><DataArray type="Int32" Name="offsets" format="ascii">2</DataArray></Lines>
<Strips><DataArray type="Int32" Name="connectivity" format="ascii">0 1 3 2</DataArray><DataArray type="Int32" Name="offsets" format="ascii">4</DataArray></Strips>
<Polys><DataArray type="Int64" Name="connectivity" format="ascii">0 1 2 3</DataArray><DataArray type="Int64" Name="offsets" format="ascii">4</DataArray></Polys>
</Piece></PolyData>"""
seed("vtp", "all_cells.vtp", vtk_file("PolyData", vtp))
seed("vtp", "stars_head.vtp", head(data_dir / "points" / "stars.vtp"))

# ---- legacy VTK
seed("legacy_vtk", "structured_points.vtk", """# vtk DataFile Version 3.0
a volume
ASCII
DATASET STRUCTURED_POINTS
DIMENSIONS 2 2 2
ORIGIN 0 0 0
SPACING 1 1 1
POINT_DATA 8
SCALARS density float 1
LOOKUP_TABLE default
0 1 2 3 4 5 6 7
CELL_DATA 1
FIELD extra 1
f 1 1 double
2.5
""")
seed("legacy_vtk", "unstructured_v5.vtk", """# vtk DataFile Version 5.1
a tetrahedron
ASCII
DATASET UNSTRUCTURED_GRID
POINTS 4 float
0 0 0 1 0 0 0 1 0 0 0 1
CELLS 2 4
OFFSETS vtktypeint64
0 4
CONNECTIVITY vtktypeint64
0 1 2 3
CELL_TYPES 1
10
POINT_DATA 4
SCALARS s double
LOOKUP_TABLE default
0 1 2 3
VECTORS v float
1 0 0 0 1 0 0 0 1 1 1 1
""")
polydata = b"""# vtk DataFile Version 4.2
polygons
BINARY
DATASET POLYDATA
POINTS 4 float
""" + struct.pack(">12f", 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0) + b"""
POLYGONS 1 5
""" + struct.pack(">5i", 4, 0, 1, 2, 3) + b"""
TRIANGLE_STRIPS 1 5
""" + struct.pack(">5i", 4, 0, 1, 3, 2) + b"""
POINT_DATA 4
NORMALS n float
""" + struct.pack(">12f", *([0, 0, 1] * 4)) + b"""
TEXTURE_COORDINATES t 2 float
""" + struct.pack(">8f", 0, 0, 1, 0, 1, 1, 0, 1) + b"""
COLOR_SCALARS c 3
""" + bytes(range(12)) + b"\n"
seed("legacy_vtk", "polydata_binary.vtk", polydata)
seed("legacy_vtk", "polydata_ascii.vtk", """# vtk DataFile Version 2.0
points and lines
ASCII
DATASET POLYDATA
POINTS 3 double
0 0 0 1 0 0 0 1 0
VERTICES 1 2
1 0
LINES 1 3
2 1 2
CELL_DATA 2
SCALARS id int 1
LOOKUP_TABLE default
0 1
""")

# ---- the tool's JSON: materials and lights; transfer functions
for i, json in enumerate([
        '{"type": "principled", "baseColor": [0.8, 0.1, 0.1], "roughness": 0.3, "metallic": 0}',
        '{"type": "obj", "kd": 0.5, "ks": [0.1, 0.2, 0.3], "ns": 10, "d": 1}',
        '{"type": "mix", "material1": {"type": "obj"}, "material2": {"type": "metal", "roughness": 0.1}, "factor": 0.3}',
        '{"type": "carPaint", "flakeColor": [1, 1, 1], "flakeDensity": 0.5}',
        '{"type": "glass", "eta": 1.5}',
        '{"type": "sphere", "position": [0, 2, 0], "radius": 0.2, "intensity": 10, "color": [1, 1, 1]}',
        '{"type": "distant", "direction": [0, -1, 0], "angularDiameter": 0.5}',
        '{"type": "spot", "position": [0, 0, 0], "direction": [0, 0, 1], "openingAngle": 30, "penumbraAngle": 5}',
        '{"type": "quad", "position": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0]}',
        '{"type": "ambient", "intensity": 0.2, "visible": true}']):
    seed("shading_json", f"{i}.json", json)
seed("transfer_function", "tf.json", '{"colors": [[0, 0, 1], [1, 1, 1], [1, 0, 0]], "opacities": [0, 0.5, 1], '
     '"range": [-1, 2.5]}')
seed("transfer_function", "no_range.json", '{"colors": [[0.5, 0.5, 0.5]], "opacities": [1]}')
