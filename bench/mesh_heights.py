#!/usr/bin/python3
"""Where a KITTI map's area lies in height: the share of a mesh's area above the cameras, and its sky vertices.

A ceiling over the street (surface closed over space no camera saw, or sky given depth) shows as area well
above the cameras. Reads a semap PLY (binary, with per-vertex labels) and the sequence's KITTI poses
(camera 0 frame of the first frame: y points down). Each triangle's height is that of its centroid above the
camera nearest to it horizontally (x, z), over the frames the run used.

Usage: bench/mesh_heights.py MESH.ply POSES.txt [--frames N]
Prints the area, the shares above 3 m and 6 m, the triangles over 5 m² and their share of the area, and the
number of vertices labelled Sky (semap class 11).
"""
import argparse
import sys

import numpy as np

SKY_LABEL = 11
HEIGHTS_M = (3.0, 6.0)
BIG_TRIANGLE_M2 = 5.0


def read_ply(path):
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline().decode("ascii").strip()
            header.append(line)
            if line == "end_header":
                break
        if "format binary_little_endian 1.0" not in header:
            sys.exit(f"{path}: not a binary little-endian PLY")
        vertex_props, n_vertices, n_faces, element = [], 0, 0, None
        for line in header:
            words = line.split()
            if words[:1] == ["element"]:
                element = words[1]
                if element == "vertex":
                    n_vertices = int(words[2])
                elif element == "face":
                    n_faces = int(words[2])
            elif words[:1] == ["property"] and element == "vertex":
                vertex_props.append((words[2], words[1]))
        types = {"float": "<f4", "double": "<f8", "uchar": "u1", "int": "<i4", "uint": "<u4"}
        vertex_dtype = np.dtype([(name, types[t]) for name, t in vertex_props])
        vertices = np.frombuffer(f.read(vertex_dtype.itemsize * n_vertices), dtype=vertex_dtype)
        face_dtype = np.dtype([("n", "u1"), ("i", "<i4", (3,))])
        faces = np.frombuffer(f.read(face_dtype.itemsize * n_faces), dtype=face_dtype)
        if n_faces and not np.all(faces["n"] == 3):
            sys.exit(f"{path}: only triangles are supported")
    xyz = np.stack([vertices["x"], vertices["y"], vertices["z"]], axis=1).astype(np.float64)
    labels = vertices["label"] if "label" in vertices.dtype.names else None
    return xyz, faces["i"], labels


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mesh")
    parser.add_argument("poses")
    parser.add_argument("--frames", type=int, default=0, help="poses used by the run (0 = all)")
    args = parser.parse_args()
    xyz, triangles, labels = read_ply(args.mesh)
    poses = np.loadtxt(args.poses).reshape(-1, 3, 4)
    if args.frames > 0:
        poses = poses[: args.frames]
    cameras = poses[:, :, 3]
    a, b, c = xyz[triangles[:, 0]], xyz[triangles[:, 1]], xyz[triangles[:, 2]]
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    centroid = (a + b + c) / 3.0
    # Nearest camera horizontally (x, z), in chunks to bound memory.
    height = np.empty(len(centroid))
    for first in range(0, len(centroid), 20000):
        part = centroid[first:first + 20000]
        d2 = (part[:, None, 0] - cameras[None, :, 0]) ** 2 + (part[:, None, 2] - cameras[None, :, 2]) ** 2
        nearest = np.argmin(d2, axis=1)
        height[first:first + 20000] = cameras[nearest, 1] - part[:, 1]  # y points down
    total = area.sum()
    print(f"mesh        {len(xyz)} vertices, {len(triangles)} triangles, {total:.0f} m2")
    for h in HEIGHTS_M:
        print(f"above {h:.0f} m   {100.0 * area[height > h].sum() / total:.1f} % of the area")
    big = area > BIG_TRIANGLE_M2
    print(f"big         {big.sum()} triangles over {BIG_TRIANGLE_M2:.0f} m2: {100.0 * area[big].sum() / total:.1f} % of the area")
    if labels is not None:
        print(f"sky         {int((labels == SKY_LABEL).sum())} vertices labelled Sky")


if __name__ == "__main__":
    main()
