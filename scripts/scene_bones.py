# SPDX-License-Identifier: Apache-2.0
"""The bones a scene's muscles must not lie in at rest, for `rbfmuscle fit --out-of`.

A scene moves each muscle mesh out of its skeleton's collision meshes before fitting it; a fit
run outside the scene gives the same surface when it is given the same meshes. Only URDF
skeletons whose meshes lie in the muscles' frame at rest (the hip scenes') are read here.
"""
import os
import xml.etree.ElementTree as ET


def out_of_argument(model_path):
    """['--out-of', 'A.ply,B.ply,…'] for the URDF collision meshes of `model_path`, or []."""
    directory = os.path.dirname(os.path.abspath(model_path))
    skeleton = ET.parse(model_path).getroot().find("skeleton")
    if skeleton is None or not skeleton.get("file", "").endswith(".urdf"):
        return []
    urdf = os.path.join(directory, skeleton.get("file"))
    meshes = [os.path.join(os.path.dirname(urdf), m.get("filename"))
              for c in ET.parse(urdf).getroot().iter("collision") for m in c.iter("mesh")]
    return ["--out-of", ",".join(meshes)] if meshes else []
