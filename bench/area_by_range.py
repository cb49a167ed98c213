#!/usr/bin/python3
"""A mesh's accuracy (by area) and completeness, split by distance from the cameras (generated sequences).

Accuracy: 100,000 points sampled uniformly on the mesh's surface, each measured to the exact scene mesh and
to the nearest camera centre; per range of camera distance, the share of the area and how much of it lies
within 0.2 m, 0.2-2 m and beyond 2 m of the truth. Completeness: the exact depth maps of every 5th frame
back-projected (every 3rd pixel, reference depth 1-40 m as `semap eval`), each point measured to the mesh;
per range of reference depth, the share within 0.2 m (and 1 m) of the mesh. Says where what is off or
missing lies: near the cameras (a defect of the map) or far (where stereo depth is noisy: σ_z grows as z²).
Needs Debian's python3-open3d (as bench/tsdf_fuse.py).

Usage: bench/area_by_range.py MESH DRIVE
(DRIVE: the drive folder of a `semap synth` sequence, `SEQ/DATE/DATE_drive_0001_sync`, with scene_mesh.ply,
gt_world_from_cam2.txt, depth/data/*.png and ../calib_cam_to_cam.txt.)
"""
import os
import sys

import numpy as np
import open3d as o3d

SAMPLES = 100000
NEAR_M, FAR_M, LOOSE_M = 0.2, 2.0, 1.0
MIN_DEPTH_M, MAX_DEPTH_M = 1.0, 40.0
FRAME_STEP, PIXEL_STEP = 5, 3
RANGES_M = [(0, 5), (5, 10), (10, 15), (15, 20), (20, 30), (30, 40), (40, float("inf"))]


def distances_to(mesh, points):
    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(o3d.t.geometry.TriangleMesh.from_legacy(mesh))
    return scene.compute_distance(o3d.core.Tensor(points.astype(np.float32))).numpy()


def intrinsics(drive):
    with open(os.path.join(drive, "..", "calib_cam_to_cam.txt")) as f:
        for line in f:
            if line.startswith("P_rect_02:"):
                p = np.array(line.split()[1:], dtype=float).reshape(3, 4)
                return p[0, 0], p[1, 1], p[0, 2], p[1, 2]
    sys.exit(f"{drive}/../calib_cam_to_cam.txt: no P_rect_02")


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    mesh = o3d.io.read_triangle_mesh(sys.argv[1])
    drive = sys.argv[2]
    truth = o3d.io.read_triangle_mesh(os.path.join(drive, "scene_mesh.ply"))
    if len(mesh.triangles) == 0 or len(truth.triangles) == 0:
        sys.exit("a mesh without triangles")
    world_from_cam = np.loadtxt(os.path.join(drive, "gt_world_from_cam2.txt")).reshape(-1, 3, 4)
    cameras = world_from_cam[:, :, 3]

    points = np.asarray(mesh.sample_points_uniformly(SAMPLES).points)
    error = distances_to(truth, points)
    range_m = np.empty(len(points))
    for first in range(0, len(points), 10000):
        part = points[first:first + 10000]
        range_m[first:first + 10000] = np.min(np.linalg.norm(part[:, None, :] - cameras[None, :, :], axis=2), axis=1)
    print(f"accuracy: {100 * np.mean(error <= NEAR_M):.1f} % of the area within {NEAR_M} m, "
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

    fx, fy, cx, cy = intrinsics(drive)
    truth_points, depths = [], []
    for frame in range(0, len(world_from_cam), FRAME_STEP):
        path = os.path.join(drive, "depth", "data", f"{frame:010d}.png")
        depth = np.asarray(o3d.io.read_image(path)).astype(np.float64) / 1000.0
        v, u = np.mgrid[0:depth.shape[0]:PIXEL_STEP, 0:depth.shape[1]:PIXEL_STEP]
        z = depth[v, u]
        valid = (z >= MIN_DEPTH_M) & (z <= MAX_DEPTH_M)
        cam = np.stack([(u[valid] - cx) / fx * z[valid], (v[valid] - cy) / fy * z[valid], z[valid]], axis=1)
        truth_points.append(cam @ world_from_cam[frame][:, :3].T + world_from_cam[frame][:, 3])
        depths.append(z[valid])
    truth_points, depths = np.concatenate(truth_points), np.concatenate(depths)
    gap = distances_to(mesh, truth_points)
    print(f"\ncompleteness: {100 * np.mean(gap <= NEAR_M):.1f} % of {len(gap)} true points within {NEAR_M} m of the mesh")
    print("| reference depth | share of the points | within 0.2 m | within 1 m | missing (> 0.2 m), share of all |")
    print("|---|---|---|---|---|")
    for lo, hi in RANGES_M:
        m = (depths > lo) & (depths <= hi)
        if not m.any():
            continue
        print(f"| {lo}-{hi:g} m | {100 * m.mean():.1f} % | {100 * np.mean(gap[m] <= NEAR_M):.1f} % | "
              f"{100 * np.mean(gap[m] <= LOOSE_M):.1f} % | {100 * np.sum(m & (gap > NEAR_M)) / len(gap):.1f} % |")


if __name__ == "__main__":
    main()
