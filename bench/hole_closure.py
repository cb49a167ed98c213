#!/usr/bin/python3
"""Holes in the seen surface closed offline: what filling them would give, measured on written meshes.

With map.drop_unseen_surface the map leaves out the surface triangles no view saw within the tolerance of
their plane; where a facade's vertices are noisy this leaves holes, and the cameras see through them. Given
the mesh of a run with the defaults (SEEN) and the mesh of the same run with map.drop_unseen_surface=false
(ALL: every surface triangle of the same triangulation, so SEEN's triangles are a subset of ALL's), this
groups the triangles that ALL has and SEEN lacks into components connected across edges, and writes SEEN plus
the components that are holes: none of their edges lies on ALL's open border (where Steiner triangles were
left out), and they have at most N triangles. `semap eval` of each written mesh then says what closing those
holes would give, and what it costs by area.

Usage: bench/hole_closure.py SEEN.ply ALL.ply --out DIR [--max-triangles N [N ...]]   (0 = no limit)
Writes DIR/closed_N.ply (closed_all.ply for 0) and prints the unseen components by size: count, triangles,
area, and how many of them are holes. Needs Debian's python3-numpy (run with /usr/bin/python3).
"""
import argparse
import os
import sys
from collections import defaultdict

import numpy as np

from mesh_heights import read_ply

SIZE_CLASSES = ((1, 1), (2, 2), (3, 4), (5, 8), (9, 16), (17, 64), (65, 256), (257, None))


def write_ply(path, xyz, triangles, labels):
    header = [
        "ply", "format binary_little_endian 1.0", "comment written by bench/hole_closure.py",
        f"element vertex {len(xyz)}", "property float x", "property float y", "property float z",
    ]
    fields = [("x", "<f4"), ("y", "<f4"), ("z", "<f4")]
    if labels is not None:
        header.append("property uchar label")
        fields.append(("label", "u1"))
    header += [f"element face {len(triangles)}", "property list uchar int vertex_indices", "end_header"]
    vertices = np.zeros(len(xyz), dtype=np.dtype(fields))
    for axis, name in enumerate("xyz"):
        vertices[name] = xyz[:, axis]
    if labels is not None:
        vertices["label"] = labels
    faces = np.zeros(len(triangles), dtype=np.dtype([("n", "u1"), ("i", "<i4", (3,))]))
    faces["n"] = 3
    faces["i"] = triangles
    with open(path, "wb") as f:
        f.write(("\n".join(header) + "\n").encode("ascii"))
        f.write(vertices.tobytes())
        f.write(faces.tobytes())


def triangle_keys(xyz, triangles):
    """Each triangle as the sorted tuple of its vertices' coordinates (float32, as written)."""
    points = [tuple(p) for p in xyz.astype(np.float32).tolist()]
    return [tuple(sorted((points[a], points[b], points[c]))) for a, b, c in triangles.tolist()]


def components(members, edge_triangles):
    """Components of the triangles in `members` connected across edges (union-find)."""
    parent = {t: t for t in members}

    def find(t):
        while parent[t] != t:
            parent[t] = parent[parent[t]]
            t = parent[t]
        return t

    for around in edge_triangles.values():
        inside = [t for t in around if t in parent]
        for t in inside[1:]:
            a, b = find(inside[0]), find(t)
            if a != b:
                parent[a] = b
    groups = defaultdict(list)
    for t in members:
        groups[find(t)].append(t)
    return list(groups.values())


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("seen", help="mesh.ply of a run with the defaults")
    parser.add_argument("all", help="mesh.ply of the same run with map.drop_unseen_surface=false")
    parser.add_argument("--out", required=True, help="folder for closed_N.ply")
    parser.add_argument("--max-triangles", type=int, nargs="+", default=[0],
                        help="write one mesh per limit on a hole's triangles (0 = no limit)")
    args = parser.parse_args()
    seen_xyz, seen_triangles, _ = read_ply(args.seen)
    xyz, triangles, labels = read_ply(args.all)
    seen_keys = set(triangle_keys(seen_xyz, seen_triangles))
    all_keys = triangle_keys(xyz, triangles)
    in_seen = np.array([k in seen_keys for k in all_keys])
    if in_seen.sum() != len(seen_keys):
        sys.exit(f"{args.seen}: {len(seen_keys) - in_seen.sum()} of its triangles are not in {args.all}: "
                 "not two runs of the same frames and options")
    edge_triangles = defaultdict(list)
    for t, (a, b, c) in enumerate(triangles.tolist()):
        for u, v in ((a, b), (b, c), (c, a)):
            edge_triangles[(min(u, v), max(u, v))].append(t)
    unseen = components(set(np.flatnonzero(~in_seen).tolist()), edge_triangles)
    a, b, c = xyz[triangles[:, 0]], xyz[triangles[:, 1]], xyz[triangles[:, 2]]
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)

    def is_hole(group):
        for t in group:
            x, y, z = triangles[t].tolist()
            for u, v in ((x, y), (y, z), (z, x)):
                if len(edge_triangles[(min(u, v), max(u, v))]) == 1:
                    return False  # on the open border of ALL
        return True

    holes = [is_hole(g) for g in unseen]
    print(f"ALL: {len(triangles)} triangles; SEEN: {len(seen_keys)}; unseen: {int((~in_seen).sum())} triangles, "
          f"{area[~in_seen].sum():.0f} m2, in {len(unseen)} components")
    for low, high in SIZE_CLASSES:
        pick = [i for i, g in enumerate(unseen) if len(g) >= low and (high is None or len(g) <= high)]
        name = f"{low}-{high}" if high is not None else f"{low}+"
        hole_area = sum(area[unseen[i]].sum() for i in pick if holes[i])
        print(f"  {name:>7} triangles: {len(pick):5d} components, {sum(len(unseen[i]) for i in pick):6d} triangles, "
              f"{sum(area[unseen[i]].sum() for i in pick):7.0f} m2; holes {sum(holes[i] for i in pick):5d}, "
              f"{hole_area:7.0f} m2")
    os.makedirs(args.out, exist_ok=True)
    for limit in args.max_triangles:
        keep = in_seen.copy()
        for group, hole in zip(unseen, holes):
            if hole and (limit <= 0 or len(group) <= limit):
                keep[group] = True
        name = "all" if limit <= 0 else str(limit)
        path = os.path.join(args.out, f"closed_{name}.ply")
        write_ply(path, xyz, triangles[keep], labels)
        print(f"{path}: {int(keep.sum())} triangles ({int(keep.sum() - in_seen.sum())} closing holes)")


if __name__ == "__main__":
    main()
