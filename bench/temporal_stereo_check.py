#!/usr/bin/python3
"""What a longer baseline would give far surfaces on a real KITTI odometry sequence (temporal stereo).

A car moves ~1 m a frame against a 0.54 m stereo baseline, so matching a frame against one K frames back
could measure far surfaces over a baseline of several metres. This measures that potential, before any of it
is built: Shi-Tomasi corners of every 3rd left image that have a Velodyne depth (within one pixel, no depth
edge: the returns within one pixel agree to 2 %) are tracked with pyramidal KLT through the next K frames and
back (kept within 0.3 px), and triangulated from the two views with the sequence's poses (rays at least
--min-angle degrees apart: forward motion gives points near the focus of expansion no parallax). Each depth is
compared with the Velodyne's, beside the SGBM depth of the same pixels (OpenCV's StereoSGBM with semap's
matching parameters: 3-way, 128 disparities, 7 px blocks, uniqueness 5, speckle 100 / 2; without semap's row
alignment and gap filling), per range of Velodyne depth.

Usage: bench/temporal_stereo_check.py SEQUENCE_DIR POSES [--window K] [--min-angle DEG]
(SEQUENCE_DIR: a KITTI odometry sequence folder with image_2, image_3, velodyne and calib.txt with Tr;
POSES: its poses file.) Needs Debian's python3-opencv and python3-numpy.
"""
import argparse
import os

import cv2
import numpy as np

EDGES_M = [15.0, 25.0, 40.0]
EVERY_FRAMES = 3
MAX_CORNERS, CORNER_QUALITY, CORNER_SPACING_PX = 3000, 0.005, 5
KLT_WINDOW_PX, KLT_LEVELS, ROUND_TRIP_PX = 21, 3, 0.3
SMOOTH_SHARE = 0.02


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sequence")
    ap.add_argument("poses")
    ap.add_argument("--window", type=int, default=5, help="frames between the two views (default 5)")
    ap.add_argument("--min-angle", type=float, default=1.0, help="least angle between the two rays, degrees")
    args = ap.parse_args()
    seq = args.sequence
    cal = {l.split(":")[0]: np.array(l.split()[1:], float) for l in open(os.path.join(seq, "calib.txt")) if ":" in l}
    p2, p3 = cal["P2"].reshape(3, 4), cal["P3"].reshape(3, 4)
    velo_to_cam0 = np.vstack([cal["Tr"].reshape(3, 4), [0, 0, 0, 1]])
    f = p2[0, 0]
    baseline_m = (p2[0, 3] - p3[0, 3]) / f
    cam2_from_cam0 = np.eye(4)
    cam2_from_cam0[:3, 3] = p2[:, 3] / f
    poses = [np.vstack([np.array(l.split(), float).reshape(3, 4), [0, 0, 0, 1]]) for l in open(args.poses)]
    n = min(len(poses), len(os.listdir(os.path.join(seq, "image_2"))))
    world_from_cam2 = [p @ np.linalg.inv(cam2_from_cam0) for p in poses[:n]]
    colour = [cv2.imread(os.path.join(seq, "image_2", f"{i:06d}.png")) for i in range(n)]
    grey = [cv2.cvtColor(c, cv2.COLOR_BGR2GRAY) for c in colour]
    block = 7
    sgbm = cv2.StereoSGBM_create(0, 128, block, 8 * 3 * block * block, 32 * 3 * block * block, 1, 31, 5, 100, 2,
                                 cv2.STEREO_SGBM_MODE_SGBM_3WAY)
    k_matrix = p2[:, :3]
    errors = {"SGBM (one frame)": [], f"temporal, {args.window} frames": []}
    for i in range(0, n - args.window, EVERY_FRAMES):
        j = i + args.window
        velo = np.fromfile(os.path.join(seq, "velodyne", f"{i:06d}.bin"), np.float32).reshape(-1, 4)[:, :3]
        cam0 = (velo_to_cam0 @ np.c_[velo, np.ones(len(velo))].T)[:3]
        front = cam0[2] > 1.0
        uvw = p2 @ np.vstack([cam0[:, front], np.ones(front.sum())])
        z, u, v = uvw[2], uvw[0] / uvw[2], uvw[1] / uvw[2]
        lidar = np.zeros(grey[i].shape, np.float32)
        inside = (u >= 0) & (u < lidar.shape[1] - 0.5) & (v >= 0) & (v < lidar.shape[0] - 0.5)
        order = np.argsort(-z[inside])  # nearest last: it wins its pixel
        lidar[np.round(v[inside]).astype(int)[order], np.round(u[inside]).astype(int)[order]] = z[inside][order]
        right = cv2.imread(os.path.join(seq, "image_3", f"{i:06d}.png"))
        disparity = sgbm.compute(colour[i], right).astype(np.float32) / 16.0
        start = cv2.goodFeaturesToTrack(grey[i], MAX_CORNERS, CORNER_QUALITY, CORNER_SPACING_PX)
        ok = np.ones(len(start), bool)
        pts = start.copy()
        for k in range(i, j):
            pts, st, _ = cv2.calcOpticalFlowPyrLK(grey[k], grey[k + 1], pts, None, winSize=(KLT_WINDOW_PX,) * 2,
                                                  maxLevel=KLT_LEVELS)
            ok &= st.ravel() == 1
        back = pts.copy()
        for k in range(j, i, -1):
            back, st, _ = cv2.calcOpticalFlowPyrLK(grey[k], grey[k - 1], back, None, winSize=(KLT_WINDOW_PX,) * 2,
                                                   maxLevel=KLT_LEVELS)
            ok &= st.ravel() == 1
        ok &= np.linalg.norm((back - start).reshape(-1, 2), axis=1) < ROUND_TRIP_PX
        a, b = start.reshape(-1, 2)[ok], pts.reshape(-1, 2)[ok]
        b_from_a = np.linalg.inv(world_from_cam2[j]) @ world_from_cam2[i]
        x = cv2.triangulatePoints(k_matrix @ np.eye(3, 4), k_matrix @ b_from_a[:3], a.T.astype(float),
                                  b.T.astype(float))
        x = x[:3] / x[3]
        centre_b = -b_from_a[:3, :3].T @ b_from_a[:3, 3]
        for (ua, va), point in zip(a, x.T):
            ray_b = point - centre_b
            cosine = point @ ray_b / (np.linalg.norm(point) * np.linalg.norm(ray_b))
            if np.degrees(np.arccos(np.clip(cosine, -1, 1))) < args.min_angle:
                continue
            col, row = int(round(ua)), int(round(va))
            near = lidar[max(0, row - 1):row + 2, max(0, col - 1):col + 2]
            near = near[near > 0]
            if len(near) == 0 or np.ptp(near) > SMOOTH_SHARE * near.min():
                continue
            z_lidar = near.min()
            d = disparity[row, col]
            if not (EDGES_M[0] <= z_lidar < EDGES_M[-1]) or d <= 0:
                continue
            errors[f"temporal, {args.window} frames"].append((z_lidar, point[2] - z_lidar))
            errors["SGBM (one frame)"].append((z_lidar, f * baseline_m / d - z_lidar))
    print(f"{seq}: corners of every {EVERY_FRAMES}rd frame with a Velodyne depth, tracked {args.window} frames, "
          f"rays at least {args.min_angle}° apart; depth error against the Velodyne, m\n")
    print("| depth | SGBM or temporal | points | median \\|error\\| | bias | RMSE |\n|---|---|---:|---:|---:|---:|")
    for lo, hi in zip(EDGES_M[:-1], EDGES_M[1:]):
        for name, values in errors.items():
            e = np.array([err for z, err in values if lo <= z < hi])
            if len(e) == 0:
                continue
            print(f"| {lo:.0f}-{hi:.0f} m | {name} | {len(e)} | {np.median(np.abs(e)):.3f} | {np.mean(e):+.3f} | "
                  f"{np.sqrt(np.mean(e ** 2)):.3f} |")


if __name__ == "__main__":
    main()
