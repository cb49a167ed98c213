#!/usr/bin/python3
"""Where ENet's forward pass spends its time: OpenCV's per-layer timings, summed by layer type.

One KITTI frame scaled to ENet's 1024x512 input (as `semantics.enet_keep_aspect: false` would), one OpenCV
thread, one warm-up pass, then one timed pass (process CPU time, and OpenCV's own per-layer profile).
semap's segmenter computes the last layer (the full-resolution deconvolution) only on the image's rows (the
fused head), so its cost a keyframe is about this total less that layer.

Usage: bench/enet_layers.py MODEL.net IMAGE.png [--top N]   (Debian's python3-opencv)
"""
import argparse
import time

import cv2

ENET_INPUT = (1024, 512)
ENET_SCALE = 1.0 / 255.0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("model")
    ap.add_argument("image")
    ap.add_argument("--top", type=int, default=5, help="slowest single layers to list")
    args = ap.parse_args()
    cv2.setNumThreads(1)
    net = cv2.dnn.readNetFromTorch(args.model)
    image = cv2.imread(args.image)
    blob = cv2.dnn.blobFromImage(cv2.resize(image, ENET_INPUT), ENET_SCALE, ENET_INPUT, 0, swapRB=True, crop=False)
    net.setInput(blob)
    net.forward()
    start = time.process_time()
    net.setInput(blob)
    net.forward()
    cpu_ms = 1000.0 * (time.process_time() - start)
    total, timings = net.getPerfProfile()
    ms_per_tick = 1000.0 / cv2.getTickFrequency()
    names = net.getLayerNames()
    by_type = {}
    for name, ticks in zip(names, timings.ravel()):
        kind = net.getLayer(name).type
        by_type[kind] = by_type.get(kind, 0.0) + float(ticks) * ms_per_tick
    print(f"forward pass: {cpu_ms:.0f} ms CPU, OpenCV's profile {total * ms_per_tick:.0f} ms\n")
    print("| layer type | ms | share |\n|---|---:|---:|")
    whole = sum(by_type.values())
    for kind, ms in sorted(by_type.items(), key=lambda kv: -kv[1]):
        if ms >= 0.5:
            print(f"| {kind} | {ms:.1f} | {100.0 * ms / whole:.1f} % |")
    print("\nslowest layers:")
    for ticks, name in sorted(zip(timings.ravel(), names), reverse=True)[: args.top]:
        print(f"  {name}: {float(ticks) * ms_per_tick:.1f} ms")


if __name__ == "__main__":
    main()
