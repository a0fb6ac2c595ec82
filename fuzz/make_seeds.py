#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
"""Writes the seed corpora of the fuzz targets into fuzz/corpus/<target>/: small valid inputs
of every form each loader reads, taken from models/ and tests/ data or written here (a few KB
each; the meshes are a tetrahedron and a cube, not the subject's bones).

Usage: /usr/bin/python3 fuzz/make_seeds.py   (from anywhere; rewrites the corpora)
"""
import base64
import pathlib
import shutil
import struct
import zlib

ROOT = pathlib.Path(__file__).resolve().parent.parent
CORPUS = ROOT / "fuzz" / "corpus"

TETRA = [(0, 0, 0), (10, 0, 0), (0, 10, 0), (0, 0, 10)]
TETRA_FACES = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
CUBE = [(x, y, z) for z in (0, 10) for y in (0, 10) for x in (0, 10)]
CUBE_QUADS = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]


def write(target, name, data):
    folder = CORPUS / target
    folder.mkdir(parents=True, exist_ok=True)
    (folder / name).write_bytes(data if isinstance(data, bytes) else data.encode())


def copy(target, source, name=None):
    write(target, name or pathlib.Path(source).name, (ROOT / source).read_bytes())


def ply_ascii(vertices, faces):
    head = f"ply\nformat ascii 1.0\nelement vertex {len(vertices)}\nproperty float x\nproperty float y\n" \
           f"property float z\nelement face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
    body = "".join(f"{x} {y} {z}\n" for x, y, z in vertices)
    body += "".join(f"{len(f)} " + " ".join(map(str, f)) + "\n" for f in faces)
    return head + body


def ply_binary(vertices, faces, big_endian):
    order = ">" if big_endian else "<"
    head = f"ply\nformat binary_{'big' if big_endian else 'little'}_endian 1.0\ncomment seed\n" \
           f"element vertex {len(vertices)}\nproperty double x\nproperty double y\nproperty double z\n" \
           f"property uchar red\nelement face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
    body = b"".join(struct.pack(order + "dddB", *v, 7) for v in vertices)
    body += b"".join(struct.pack(order + "B" + "i" * len(f), len(f), *f) for f in faces)
    return head.encode() + body


def vtp_array_binary(values, kind, compressed):
    fmt = {"Float32": "f", "Float64": "d", "Int32": "i", "Int64": "q"}[kind]
    raw = struct.pack("<" + fmt * len(values), *values)
    if compressed:
        block = zlib.compress(raw)
        header = struct.pack("<IIII", 1, len(raw), len(raw), len(block))
        return base64.b64encode(header).decode() + base64.b64encode(block).decode()
    return base64.b64encode(struct.pack("<I", len(raw)) + raw).decode()


def vtp(vertices, faces, encoding):
    """A .vtp of one piece: encoding 'ascii', 'binary', 'zlib' (binary, compressed) or 'raw'
    (appended raw data)."""
    points = [c for v in vertices for c in v]
    connectivity = [i for f in faces for i in f]
    offsets, n = [], 0
    for f in faces:
        n += len(f)
        offsets.append(n)
    arrays = [("Points", "Float32", points, 3), ("connectivity", "Int32", connectivity, 1),
              ("offsets", "Int64", offsets, 1)]
    compressor = ' compressor="vtkZLibDataCompressor"' if encoding == "zlib" else ""
    text, appended, offset = [], b"", 0
    for name, kind, values, components in arrays:
        attributes = f'type="{kind}" Name="{name}" NumberOfComponents="{components}"'
        if encoding == "ascii":
            body = f'<DataArray {attributes} format="ascii">{" ".join(map(str, values))}</DataArray>'
        elif encoding == "raw":
            fmt = {"Float32": "f", "Int32": "i", "Int64": "q"}[kind]
            data = struct.pack("<" + fmt * len(values), *values)
            body = f'<DataArray {attributes} format="appended" offset="{offset}"/>'
            appended += struct.pack("<I", len(data)) + data
            offset += 4 + len(data)
        else:
            body = f'<DataArray {attributes} format="binary">{vtp_array_binary(values, kind, encoding == "zlib")}</DataArray>'
        text.append((name, body))
    bodies = dict(text)
    xml = (f'<?xml version="1.0"?>\n<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian"{compressor}>\n'
           f'<PolyData>\n<Piece NumberOfPoints="{len(vertices)}" NumberOfPolys="{len(faces)}">\n'
           f'<Points>{bodies["Points"]}</Points>\n'
           f'<Polys>{bodies["connectivity"]}{bodies["offsets"]}</Polys>\n</Piece>\n</PolyData>\n')
    if encoding == "raw":
        return xml.encode() + b'<AppendedData encoding="raw">_' + appended + b"</AppendedData>\n</VTKFile>\n"
    return (xml + "</VTKFile>\n").encode()


def strip_vtp():
    """Triangle strips and lines, ASCII."""
    return ('<?xml version="1.0"?>\n<VTKFile type="PolyData" version="0.1">\n<PolyData>\n'
            '<Piece NumberOfPoints="4" NumberOfStrips="1" NumberOfLines="1">\n'
            '<Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">'
            '0 0 0 10 0 0 0 10 0 10 10 0</DataArray></Points>\n'
            '<Strips><DataArray type="Int32" Name="connectivity" format="ascii">0 1 2 3</DataArray>'
            '<DataArray type="Int32" Name="offsets" format="ascii">4</DataArray></Strips>\n'
            '<Lines><DataArray type="Int32" Name="connectivity" format="ascii">0 3</DataArray>'
            '<DataArray type="Int32" Name="offsets" format="ascii">2</DataArray></Lines>\n'
            '</Piece>\n</PolyData>\n</VTKFile>\n')


def small_rbf(source, centres):
    lines = (ROOT / source).read_text().splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("centres "))
    head = lines[:start] + [f"centres {centres}"]
    body = [line for line in lines[start + 1:] if not line.startswith("#")][:centres]
    head = [("metrics {}" if line.startswith("metrics ") else line) for line in head]
    return "\n".join(head + body) + "\n"


def first_rows(source, rows):
    lines = (ROOT / source).read_text().splitlines()
    end = next(i for i, line in enumerate(lines) if line.strip() == "endheader")
    kept = lines[:end + 2 + rows]
    return "\n".join(line.replace(f"nRows={len(lines) - end - 2}", f"nRows={rows}") for line in kept) + "\n"


def main():
    if CORPUS.exists():
        shutil.rmtree(CORPUS)
    write("fuzz_ply", "tetrahedron_ascii.ply", ply_ascii(TETRA, TETRA_FACES))
    write("fuzz_ply", "cube_quads_ascii.ply", ply_ascii(CUBE, CUBE_QUADS))
    write("fuzz_ply", "tetrahedron_little.ply", ply_binary(TETRA, TETRA_FACES, False))
    write("fuzz_ply", "cube_big.ply", ply_binary(CUBE, CUBE_QUADS, True))
    copy("fuzz_ply", "models/shapes/tetrahedron.ply", "tetrahedron_trimesh.ply")
    copy("fuzz_ply", "models/shapes/block.ply")
    for encoding in ("ascii", "binary", "zlib", "raw"):
        write("fuzz_vtp", f"tetrahedron_{encoding}.vtp", vtp(TETRA, TETRA_FACES, encoding))
    write("fuzz_vtp", "cube_quads_zlib.vtp", vtp(CUBE, CUBE_QUADS, "zlib"))
    write("fuzz_vtp", "strip_lines_ascii.vtp", strip_vtp())
    write("fuzz_rbf", "gluteus_3.rbf", small_rbf("models/hip/surfaces/gluteus_maximus_r.rbf", 3))
    write("fuzz_rbf", "psoas_8.rbf", small_rbf("models/hip/surfaces/psoas_major_r.rbf", 8))
    for xml in ("models/hip/hip_gait.xml", "models/hip/skeleton_flexion_osim.xml",
                "tests/integration/host/data/femur_point.xml", "tests/integration/host/data/bad_property_type.xml",
                "tests/integration/host/data/bad_reporter_pattern.xml"):
        copy("fuzz_model_xml", xml)
    copy("fuzz_urdf", "models/hip/hip_r.urdf")
    copy("fuzz_urdf", "tests/integration/host/data/missing_mesh.urdf")
    for osim in ("three_bodies_v4.osim", "geometry_transform.osim", "two_coordinates.osim", "unknown_joint.osim"):
        copy("fuzz_osim", f"tests/unit/model/data/osim/{osim}")
    copy("fuzz_motion", "models/hip/motions/hip_flexion_0_80_step10.mot")
    copy("fuzz_motion", "models/hip/motions/hip_adduction_0_30.mot")
    write("fuzz_motion", "gait_12_rows.mot", first_rows("models/hip/motions/gait_cycle.mot", 12))
    copy("fuzz_motion", "tests/integration/host/data/unknown_coordinate.mot")
    write("fuzz_motion", "states_v4.sto",
          "states\nversion=1\nnRows=3\nnColumns=3\ninDegrees=no\nendheader\n"
          "time\t/jointset/hip_r/hip_flexion_r/value\t/jointset/hip_r/hip_flexion_r/speed\n"
          "0\t0.1\t0\n0.1\t0.2\t1\n0.2\t0.3\t1\n")
    write("fuzz_motion", "simm_datarows.mot",
          "hip\ndatacolumns 2\ndatarows 2\nrange 0 1\nendheader\ntime hip_adduction_r\n0 5\n1 10\n")


if __name__ == "__main__":
    main()
