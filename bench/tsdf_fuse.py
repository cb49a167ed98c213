#!/usr/bin/env python3
"""Fuses the depth maps written by `semap depth --all` with Open3D's ScalableTSDFVolume and writes the mesh as OFF.

Part of bench/tsdf_compare.sh (the TSDF baseline of issue #17): the same SGBM depth maps and poses as semap,
fused by a voxel TSDF. Input folder (from `semap depth --all`):
  depth/NNNNNN.png  16-bit depth in mm (camera-frame z), 0 = none
  poses.txt         per line: frame id, then world_from_cam as 3x4 row-major
  camera.txt        width_px height_px fx_px fy_px cx_px cy_px
Prints one line of JSON with the timings (reading, integration, mesh extraction, writing; seconds) and sizes.
"""
import argparse
import json
import sys
import time

try:
    import numpy as np
    import open3d as o3d
except ImportError as e:  # the caller (tsdf_compare.sh) checks first; this is for direct use
    sys.exit(f"tsdf_fuse.py: {e}: install Debian's python3-open3d (apt-get install python3-open3d)")

# Open3D reads 16-bit depth PNGs as integers; semap writes millimetres.
DEPTH_PNG_UNITS_PER_METRE = 1000.0


def read_camera(path):
    with open(path) as f:
        fields = f.read().split()
    if len(fields) != 6:
        sys.exit(f"{path}: expected 'width height fx fy cx cy', got {len(fields)} fields")
    width, height = int(fields[0]), int(fields[1])
    fx, fy, cx, cy = (float(v) for v in fields[2:])
    return o3d.camera.PinholeCameraIntrinsic(width, height, fx, fy, cx, cy)


def read_poses(path):
    poses = []
    with open(path) as f:
        for number, line in enumerate(f, 1):
            fields = line.split()
            if not fields:
                continue
            if len(fields) != 13:
                sys.exit(f"{path}:{number}: expected a frame id and 12 numbers, got {len(fields)} fields")
            world_from_cam = np.eye(4)
            world_from_cam[:3, :4] = np.array([float(v) for v in fields[1:]]).reshape(3, 4)
            poses.append((int(fields[0]), world_from_cam))
    return poses


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("depth_folder", help="output folder of `semap depth --all`")
    parser.add_argument("--voxel-m", type=float, required=True, help="voxel size (m)")
    parser.add_argument("--sdf-trunc-voxels", type=float, default=4.0,
                        help="truncation distance of the signed distance, in voxels (default 4)")
    parser.add_argument("--depth-trunc-m", type=float, required=True,
                        help="depths beyond this are ignored (m): semap's depth.max_depth_m")
    parser.add_argument("--out", required=True, help="mesh file to write (.off)")
    args = parser.parse_args()
    if args.voxel_m <= 0 or args.sdf_trunc_voxels <= 0 or args.depth_trunc_m <= 0:
        sys.exit("tsdf_fuse.py: --voxel-m, --sdf-trunc-voxels and --depth-trunc-m must be > 0")

    start = time.perf_counter()
    intrinsic = read_camera(f"{args.depth_folder}/camera.txt")
    poses = read_poses(f"{args.depth_folder}/poses.txt")
    if not poses:
        sys.exit(f"{args.depth_folder}/poses.txt: no frame")
    volume = o3d.pipelines.integration.ScalableTSDFVolume(
        voxel_length=args.voxel_m,
        sdf_trunc=args.sdf_trunc_voxels * args.voxel_m,
        color_type=o3d.pipelines.integration.TSDFVolumeColorType.NoColor)
    # No colour is fused (OFF stores none); Open3D's RGBD image still wants one: a constant image.
    blank = o3d.geometry.Image(np.zeros((intrinsic.height, intrinsic.width, 3), dtype=np.uint8))
    read_s = integrate_s = 0.0
    for frame_id, world_from_cam in poses:
        t0 = time.perf_counter()
        depth = o3d.io.read_image(f"{args.depth_folder}/depth/{frame_id:06d}.png")
        rgbd = o3d.geometry.RGBDImage.create_from_color_and_depth(
            blank, depth, depth_scale=DEPTH_PNG_UNITS_PER_METRE, depth_trunc=args.depth_trunc_m,
            convert_rgb_to_intensity=False)
        t1 = time.perf_counter()
        volume.integrate(rgbd, intrinsic, np.linalg.inv(world_from_cam))
        t2 = time.perf_counter()
        read_s += t1 - t0
        integrate_s += t2 - t1
    t0 = time.perf_counter()
    mesh = volume.extract_triangle_mesh()
    t1 = time.perf_counter()
    if not o3d.io.write_triangle_mesh(args.out, mesh, write_ascii=True):
        sys.exit(f"{args.out}: cannot write the mesh")
    t2 = time.perf_counter()
    print(json.dumps({
        "frames": len(poses),
        "voxel_m": args.voxel_m,
        "sdf_trunc_m": args.sdf_trunc_voxels * args.voxel_m,
        "depth_trunc_m": args.depth_trunc_m,
        "read_s": read_s,
        "integrate_s": integrate_s,
        "extract_s": t1 - t0,
        "write_s": t2 - t1,
        "total_s": t2 - start,
        "vertices": len(mesh.vertices),
        "triangles": len(mesh.triangles),
        "open3d": o3d.__version__,
    }))


if __name__ == "__main__":
    main()
