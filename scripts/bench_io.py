# SPDX-License-Identifier: Apache-2.0
"""Readers (and the report-section writer) shared by scripts/speed_vs_error.py and scripts/render_hip.py.

Python 3 with numpy (Debian: python3-numpy). Formats are the ones the host writes
(see core/framework/reporter.* and core/framework/frame_geometry.*):
  outputs.sto   OpenSim storage: header lines, `endheader`, tab-separated labels and rows
  *.vtp         ASCII VTK XML PolyData (Points, Lines, Polys)
  *.rbf         rbfmuscle surface file; its `metrics {json}` line holds the fit figures
  model XML     <RBFMuscleModel> with <components>, <motion file=...>
"""
import json
import math
import os
import re
import sys
import xml.etree.ElementTree as ET

import numpy as np


def read_sto(path):
    """Returns (labels, rows as a 2-D float array, in_degrees) of an OpenSim .sto/.mot file."""
    in_degrees = False
    with open(path) as f:
        for line in f:
            text = line.strip()
            if text.lower().startswith("indegrees="):
                in_degrees = text.split("=", 1)[1].strip().lower() == "yes"
            if text == "endheader":
                break
        else:
            raise ValueError(f"{path}: no 'endheader' line (expected an OpenSim storage file)")
        labels = f.readline().rstrip("\n").split("\t")
        rows = [[float(v) for v in line.rstrip("\n").split("\t")] for line in f if line.strip()]
    data = np.array(rows, dtype=float).reshape(len(rows), len(labels))
    return labels, data, in_degrees


class Storage:
    """Columns of an outputs.sto by label: `s["glmax_r.volume_ratio"]` (1-D array)."""

    def __init__(self, path):
        self.path = path
        self.labels, self.data, self.in_degrees = read_sto(path)
        self.index = {label: k for k, label in enumerate(self.labels)}

    def has(self, label):
        return label in self.index

    def __getitem__(self, label):
        if label not in self.index:
            raise KeyError(f"{self.path}: no column '{label}'")
        return self.data[:, self.index[label]]

    def angle_deg(self, coordinate="hip_flexion_r"):
        """A coordinate in degrees (the host writes radians)."""
        values = self[coordinate]
        return values if self.in_degrees else np.degrees(values)


def read_rbf_metrics(path):
    """The `metrics {json}` line of a .rbf file as a dict ({} when absent)."""
    with open(path) as f:
        for line in f:
            if line.startswith("metrics "):
                return json.loads(line[len("metrics "):])
            if line.startswith("centres "):
                break
    return {}


def read_rbf_settings(path, without=("max_centres",)):
    """The fit settings of a .rbf file (its `settings k=v ...` line) as a dict, less `without`."""
    with open(path) as f:
        for line in f:
            if line.startswith("settings "):
                pairs = (w.split("=", 1) for w in line.split()[1:] if "=" in w)
                return {k: v for k, v in pairs if k not in without}
            if line.startswith("centres "):
                break
    return {}


def read_vtp(path):
    """(points N×3, triangles M×3 int, polylines list of int arrays) of an ASCII .vtp file."""
    root = ET.parse(path).getroot()
    piece = root.find("PolyData/Piece")
    if piece is None:
        raise ValueError(f"{path}: no PolyData/Piece element")

    def array(parent, name=None):
        if parent is None:
            return np.zeros(0)
        for a in parent.findall("DataArray"):
            if name is None or a.get("Name") == name:
                return np.array((a.text or "").split(), dtype=float)
        return np.zeros(0)

    points = array(piece.find("Points")).reshape(-1, 3)
    tri = array(piece.find("Polys"), "connectivity").astype(int).reshape(-1, 3)
    conn = array(piece.find("Lines"), "connectivity").astype(int)
    offsets = array(piece.find("Lines"), "offsets").astype(int)
    lines, start = [], 0
    for end in offsets:
        lines.append(conn[start:end])
        start = end
    return points, tri, lines


def frame_meshes(out, name):
    """[(frame, path)] of OUTDIR/meshes/NAME_#####.vtp in frame order, as a run with
    --frames-mesh writes them; exits with a message naming the directory when there are none."""
    directory = os.path.join(out, "meshes")
    pattern = re.compile(re.escape(name) + r"_(\d+)\.vtp")
    found = []
    if os.path.isdir(directory):
        found = sorted((int(m.group(1)), os.path.join(directory, f))
                       for f in os.listdir(directory) for m in [pattern.fullmatch(f)] if m)
    if not found:
        sys.exit(f"{directory}: no {name}_NNNNN.vtp (run with --frames-mesh; the muscle's name as in the model)")
    return found


def read_ply(path):
    """(vertices N×3, triangles M×3) of an ASCII or binary little-endian PLY triangle mesh."""
    with open(path, "rb") as f:
        header, fmt = [], "ascii"
        while True:
            line = f.readline().decode("ascii", "replace").strip()
            header.append(line)
            if line.startswith("format"):
                fmt = line.split()[1]
            if line == "end_header":
                break
        n_vertex = n_face = 0
        vertex_props, face_list = [], None
        current = None
        for line in header:
            words = line.split()
            if words[:1] == ["element"]:
                current = words[1]
                if current == "vertex":
                    n_vertex = int(words[2])
                elif current == "face":
                    n_face = int(words[2])
            elif words[:1] == ["property"] and current == "vertex":
                vertex_props.append(words[1])
            elif words[:2] == ["property", "list"] and current == "face":
                face_list = (words[2], words[3])
        if fmt == "ascii":
            values = f.read().decode().split()
            nv = len(vertex_props)
            v = np.array(values[: n_vertex * nv], dtype=float).reshape(n_vertex, nv)[:, :3]
            rest = np.array(values[n_vertex * nv:], dtype=float).astype(int)
            tri = rest.reshape(n_face, -1)[:, 1:4] if n_face else np.zeros((0, 3), int)
            return v, tri
        if fmt != "binary_little_endian":
            raise ValueError(f"{path}: PLY format {fmt} not supported")
        types = {"float": "<f4", "float32": "<f4", "double": "<f8", "float64": "<f8", "uchar": "u1",
                 "uint8": "u1", "int": "<i4", "int32": "<i4", "uint": "<u4", "uint32": "<u4",
                 "char": "i1", "short": "<i2", "ushort": "<u2"}
        vtype = np.dtype([(f"p{k}", types[t]) for k, t in enumerate(vertex_props)])
        vdata = np.frombuffer(f.read(vtype.itemsize * n_vertex), dtype=vtype)
        v = np.stack([vdata["p0"], vdata["p1"], vdata["p2"]], axis=1).astype(float)
        count_t, index_t = types[face_list[0]], types[face_list[1]]
        ftype = np.dtype([("n", count_t), ("i", index_t, (3,))])
        fdata = np.frombuffer(f.read(ftype.itemsize * n_face), dtype=ftype)
        if n_face and np.any(fdata["n"] != 3):
            raise ValueError(f"{path}: only triangle faces are supported")
        return v, fdata["i"].astype(int)


def read_model(path):
    """The model file: {'motion': path, 'directory': dir, 'muscles': [{name, mesh, surface,
    centres, properties}]} for every RBFMuscle component (paths resolved)."""
    root = ET.parse(path).getroot()
    directory = os.path.dirname(os.path.abspath(path))
    motion = root.find("motion")
    model = {"directory": directory, "muscles": [],
             "motion": os.path.normpath(os.path.join(directory, motion.get("file"))) if motion is not None else None,
             "skeleton": os.path.normpath(os.path.join(directory, root.find("skeleton").get("file")))}
    components = root.find("components")
    for element in (components if components is not None else []):
        if element.tag != "RBFMuscle":
            continue
        props = {child.tag: (child.text or "").strip() for child in element}
        resolve = lambda p: p if not p or os.path.isabs(p) else os.path.normpath(os.path.join(directory, p))
        model["muscles"].append({"name": element.get("name"), "mesh": resolve(props.get("mesh_file", "")),
                                 "surface": resolve(props.get("surface_file", "")),
                                 "centres": int(props.get("centres", 1000)), "properties": props})
    return model


def urdf_hip_rotation(urdf_path, flexion_deg, adduction_deg=0.0, rotation_deg=0.0):
    """(R 3×3, c 3) with p_ground(q) = c + R (p_rest − c) for a point fixed on the femur:
    the hip joints of hip_r.urdf (flexion about z, adduction about x, rotation about y of
    the joint frame, chained at the hip centre; URDF rpy = Rz(yaw) Ry(pitch) Rx(roll)).
    Lengths in the URDF are metres; c is returned in mm."""
    root = ET.parse(urdf_path).getroot()
    joints = {j.get("name"): j for j in root.findall("joint")}
    origin = joints["hip_flexion_r"].find("origin")
    c = np.array([float(v) for v in origin.get("xyz").split()]) * 1000.0
    roll, pitch, yaw = (float(v) for v in origin.get("rpy").split())

    def rot(axis, a):
        ca, sa = math.cos(a), math.sin(a)
        if axis == "x":
            return np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
        if axis == "y":
            return np.array([[ca, 0, sa], [0, 1, 0], [-sa, 0, ca]])
        return np.array([[ca, -sa, 0], [sa, ca, 0], [0, 0, 1]])

    R_J = rot("z", yaw) @ rot("y", pitch) @ rot("x", roll)
    q = rot("z", math.radians(flexion_deg)) @ rot("x", math.radians(adduction_deg)) @ rot("y", math.radians(rotation_deg))
    return R_J @ q @ R_J.T, c


def replace_marked_section(path, begin, end, block, preamble):
    """Puts `block` (text that starts with `begin` and ends with `end`) into the Markdown
    file `path`: in place of the text between the markers when both are there, else
    appended; a missing file starts with `preamble`. The file is written beside and
    renamed into place, so it is never left half written."""
    text = open(path).read() if os.path.exists(path) else preamble
    if begin in text and end in text:
        text = text[:text.index(begin)] + block + text[text.index(end) + len(end):]
    else:
        text = text.rstrip("\n") + "\n\n" + block + "\n"
    partial = path + ".partial"
    with open(partial, "w") as f:
        f.write(text)
    os.replace(partial, path)
