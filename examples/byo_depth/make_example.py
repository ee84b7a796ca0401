#!/usr/bin/env python3
"""Regenerates this example folder (run from the repository root after building):

    PYTHONPATH=build/python /usr/bin/python3 examples/byo_depth/make_example.py

scan/  two colour views of the shipped apartment with intrinsics and poses, and no depth;
depth/ one depth map per view "from a depth network": here the simulator's monocular model
       (per-view scale error, smooth warp, noise, flying pixels), saved the way a network script
       saves it: float32 metres, .npy for view 0 and float TIFF for view 1.
"""
import os
import shutil

import floorcast as fc

HERE = os.path.dirname(os.path.abspath(__file__))
POSE = (4.0, 3.0, 20.0)  # x_m, y_m, yaw_deg in floorplans/buildings/apartment.json

plan = fc.load_plan(os.path.join(fc.data_dir(), "floorplans", "buildings", "apartment.json"))
geometry = {"num_views": 2, "view_step_deg": 120.0, "width_px": 320, "height_px": 240}
scan = fc.simulate_scan(plan, POSE, sensor="mono", seed=7, rgb=True, params={"geometry": geometry})

for d in ("scan", "depth"):
    shutil.rmtree(os.path.join(HERE, d), ignore_errors=True)
os.makedirs(os.path.join(HERE, "depth"))
fc.write_depth(os.path.join(HERE, "depth", "view_000_rgb.npy"), scan.views[0].depth)
fc.write_depth(os.path.join(HERE, "depth", "view_001_rgb.tif"), scan.views[1].depth)
for v in scan.views:
    v.depth = None  # colour, intrinsics and poses only: the depth comes from elsewhere
scan.save(os.path.join(HERE, "scan"))
print("truth:", scan.truth)
