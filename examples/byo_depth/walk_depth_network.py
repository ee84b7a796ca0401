#!/usr/bin/env python3
"""A stand-in for a depth network run over a walk: reads the colour views of every observation of
a walk folder (`floorcast sim walk --sensor mono --rgb`) and writes one depth map per view where
`floorcast track --depth-dir` looks for it:

    DEPTH_DIR/observations/step_NNNN/view_KKK_rgb.npy     float32 metres, named after the colour image

Your network goes where `predict` is: it gets the colour image (uint8 H x W x 3, RGB) and returns
z-depth in metres (H x W). This stand-in has no network: it returns the depth the simulator
rendered for the same view (what a perfect network would say), optionally scaled and with
Gaussian noise, so that a test can check that depth written back gives the simulated depth's
track exactly, and that other depth changes it.

    PYTHONPATH=build/python /usr/bin/python3 examples/byo_depth/walk_depth_network.py WALK DEPTH [--scale S] [--noise-m M]
"""
import argparse
import json
import os

import numpy as np

import floorcast as fc


def predict(rgb, simulated_depth_m, scale, noise_m, rng):
    """Replace with your network: rgb (H, W, 3) uint8 -> z-depth (H, W) float32 metres."""
    depth = simulated_depth_m * scale
    if noise_m > 0:
        depth = depth + rng.normal(0.0, noise_m, depth.shape)
        depth[simulated_depth_m <= 0] = 0.0  # no return stays no return
    return np.maximum(depth, 0.0).astype(np.float32)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("walk", help="walk folder (floorcast sim walk ... --rgb -o WALK)")
    ap.add_argument("depth_dir", help="where the depth maps go")
    ap.add_argument("--scale", type=float, default=1.0, help="multiply the depth (a network's scale error)")
    ap.add_argument("--noise-m", type=float, default=0.0, help="Gaussian noise, metres")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    walk = fc.load_walk(args.walk)
    written = 0
    for i, obs in enumerate(walk.observations):
        if obs["kind"] != "scan":
            raise SystemExit("%s: observation at step %d is not a scan" % (args.walk, obs["step"]))
        scan = walk.scan(i, rgb=True)
        with open(os.path.join(obs["path"], "scan.json")) as f:
            entries = json.load(f)["views"]
        out = os.path.join(args.depth_dir, os.path.relpath(obs["path"], args.walk))
        os.makedirs(out, exist_ok=True)
        for view, entry in zip(scan.views, entries):
            if view.rgb.size == 0:
                raise SystemExit("%s: view %d has no colour image (simulate the walk with --rgb)" % (obs["path"], view.view_index))
            stem = os.path.splitext(entry["rgb"])[0]
            np.save(os.path.join(out, stem + ".npy"), predict(view.rgb, view.depth, args.scale, args.noise_m, rng))
            written += 1
    print("%d depth maps for %d observations -> %s" % (written, len(walk.observations), args.depth_dir))


if __name__ == "__main__":
    main()
