#!/usr/bin/python3
"""A mesh's accuracy by area, split by distance to the nearest camera (generated sequences).

Samples 100,000 points uniformly on the mesh's surface, measures each to the exact scene mesh and to the nearest
camera centre of the sequence, and prints, per range of camera distance, the share of the area and how much of
it lies within 0.2 m, 0.2-2 m and beyond 2 m of the truth. Says where the area that is off comes from: near
the cameras (a defect of the map) or far from every camera (where stereo depth is noisy: σ_z grows as z²).
Needs Debian's python3-open3d (as bench/tsdf_fuse.py).

Usage: bench/area_by_range.py MESH SCENE_MESH.ply GT_WORLD_FROM_CAM.txt
(GT_WORLD_FROM_CAM.txt: `gt_world_from_cam2.txt` of a `semap synth` drive, one 3×4 matrix per line.)
"""
import sys

import numpy as np
import open3d as o3d

SAMPLES = 100000
NEAR_M, FAR_M = 0.2, 2.0
RANGES_M = [(0, 5), (5, 10), (10, 15), (15, 20), (20, 30), (30, 40), (40, float("inf"))]


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    mesh = o3d.io.read_triangle_mesh(sys.argv[1])
    truth = o3d.io.read_triangle_mesh(sys.argv[2])
    if len(mesh.triangles) == 0 or len(truth.triangles) == 0:
        sys.exit("a mesh without triangles")
    cameras = np.loadtxt(sys.argv[3]).reshape(-1, 3, 4)[:, :, 3]
    points = np.asarray(mesh.sample_points_uniformly(SAMPLES).points)
    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(o3d.t.geometry.TriangleMesh.from_legacy(truth))
    error = scene.compute_distance(o3d.core.Tensor(points.astype(np.float32))).numpy()
    range_m = np.empty(len(points))
    for first in range(0, len(points), 10000):
        part = points[first:first + 10000]
        range_m[first:first + 10000] = np.min(np.linalg.norm(part[:, None, :] - cameras[None, :, :], axis=2), axis=1)
    print(f"all: {100 * np.mean(error <= NEAR_M):.1f} % of the area within {NEAR_M} m, "
          f"{100 * np.mean(error > FAR_M):.1f} % beyond {FAR_M} m")
    print("| from the nearest camera | share of the area | within 0.2 m | 0.2-2 m | beyond 2 m | off by > 0.2 m, share of all |")
    print("|---|---|---|---|---|---|")
    for lo, hi in RANGES_M:
        m = (range_m >= lo) & (range_m < hi)
        if not m.any():
            continue
        e = error[m]
        print(f"| {lo}-{hi:g} m | {100 * m.mean():.1f} % | {100 * np.mean(e <= NEAR_M):.1f} % | "
              f"{100 * np.mean((e > NEAR_M) & (e <= FAR_M)):.1f} % | {100 * np.mean(e > FAR_M):.1f} % | "
              f"{100 * np.sum(m & (error > NEAR_M)) / len(error):.1f} % |")


if __name__ == "__main__":
    main()
