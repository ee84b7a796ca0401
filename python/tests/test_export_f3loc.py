"""`floorcast export` read back the way F3Loc's public loaders read a dataset (issue 24).

F3Loc's conventions (its utils/data_utils.py GridSeqDataset, eval_observation.py,
utils/utils.get_ray_from_depth; /work/shared/reference/f3loc.md), re-implemented here from their
description: a dataset folder with split.yaml listing scene folders; per scene map.png (0.01 m per
pixel, 255 free), poses.txt ("x y theta", metres from the map centre, y down) and depth40.txt with
L + 1 = 4 lines per sample, images rgb/NNNNN-l.png with the reference frame last; a pose becomes a
map pixel as x / 0.01 + W / 2; rays come from a depth line as 11 rays at 10 degree steps over +-50
degrees, left to right, sampled at column tan(a) * W * F_W + (W - 1) / 2 with F_W = 3/8 and
divided by cos(a). With `--camera f3loc` those rays must agree with rays cast on map.png from the
pose; with the scenario's own camera the export must say that F3Loc's F_W differs.
"""
import os
import shutil
import subprocess

import numpy as np
import pytest
import yaml
import matplotlib.image as mpimg

import floorcast as fc

OUT = os.environ.get("FLOORCAST_TEST_OUT", "/tmp/floorcast_pytest")
CLI = os.environ.get("FLOORCAST_CLI", "")
L = 3            # F3Loc eval_observation.py: source frames per sample
F_W = 3.0 / 8.0  # F3Loc: focal length / image width
MAP_RES = 0.01   # F3Loc: metres per map pixel


def get_ray_from_depth(d, V=11, dv=10.0, F_W=F_W):
    """F3Loc's rule: V rays dv degrees apart, left to right, linear interpolation along the line."""
    W = d.shape[0]
    angles = np.radians((np.arange(V) - V // 2) * dv)
    cols = np.tan(angles) * W * F_W + (W - 1) / 2.0
    depth = np.interp(cols, np.arange(W), d)
    return depth / np.cos(angles), angles


def cast_on_map(occ, col, row, theta, max_m=15.0):
    """First non-free pixel along (cos theta, sin theta) in the map's (col, row) frame, metres."""
    step = 0.25
    c, s = np.cos(theta), np.sin(theta)
    t = step
    while t * MAP_RES < max_m:
        x, y = int(np.floor(col + t * c)), int(np.floor(row + t * s))
        if x < 0 or y < 0 or y >= occ.shape[0] or x >= occ.shape[1] or occ[y, x] < 0.5:
            return t * MAP_RES
        t += step
    return max_m


@pytest.fixture(scope="module")
def exported():
    if not CLI:
        pytest.fail("FLOORCAST_CLI is not set (ctest sets it)")
    root = os.path.join(OUT, "export_f3loc")
    shutil.rmtree(root, ignore_errors=True)
    os.makedirs(root)
    scenario = os.path.join(root, "export.yaml")
    with open(scenario, "w") as f:
        f.write("name: export-f3loc\n"
                "buildings: [%s]\n" % os.path.join(fc.data_dir(), "floorplans", "buildings", "apartment.json") +
                "sampling: {count: 3, seed: 4, clearance_m: 0.6}\n"
                "observation: {source: scan, sensor: lidar, setting: partial, seed: 2}\n"
                "matchers: {kernel: {matcher: kernel}}\n")
    matched = os.path.join(root, "f3loc")
    own = os.path.join(root, "scenario_camera")
    subprocess.run([CLI, "export", scenario, "--camera", "f3loc", "--quiet", "-o", matched], check=True,
                   capture_output=True, text=True)
    res = subprocess.run([CLI, "export", scenario, "--quiet", "--no-rgb", "-o", own], check=True,
                         capture_output=True, text=True)
    return matched, own, res.stderr


def test_f3loc_loader_conventions(exported):
    matched, _, _ = exported
    dataset = os.path.join(matched, "c000")
    with open(os.path.join(dataset, "split.yaml")) as f:
        split = yaml.safe_load(f)
    assert split["test"] == ["apartment"] and split["train"] == [] and split["val"] == []
    checked = 0
    for scene in split["test"]:
        scene_dir = os.path.join(dataset, scene)
        occ = mpimg.imread(os.path.join(scene_dir, "map.png"))
        assert occ.ndim == 2
        h, w = occ.shape
        with open(os.path.join(scene_dir, "poses.txt")) as f:
            poses = [np.array([float(v) for v in line.split(" ")], dtype=np.float32) for line in f.read().splitlines()]
        with open(os.path.join(scene_dir, "depth40.txt")) as f:
            depths = [np.array([float(v) for v in line.split(" ")], dtype=np.float32) for line in f.read().splitlines()]
        assert len(poses) == len(depths) and len(poses) % (L + 1) == 0
        samples = len(poses) // (L + 1)
        assert samples == 3
        errors = []
        for idx in range(samples):
            for l in range(L + 1):
                img = mpimg.imread(os.path.join(scene_dir, "rgb", str(idx).zfill(5) + "-" + str(l) + ".png"))
                assert img.ndim == 3 and img.shape[2] >= 3
            ref_pose = poses[idx * (L + 1) + L]
            ref_depth = depths[idx * (L + 1) + L]
            assert ref_depth.shape == (40,)
            col = ref_pose[0] / MAP_RES + w / 2.0
            row = ref_pose[1] / MAP_RES + h / 2.0
            assert occ[int(row), int(col)] > 0.5, "the camera stands on a blocked map pixel"
            rays, angles = get_ray_from_depth(ref_depth)
            for r, a in zip(rays, angles):
                # Left to right in the image is clockwise seen from above (y up): in the map's
                # y-down frame the ray at image angle a points along theta + a.
                cast = cast_on_map(occ, col, row, ref_pose[2] + a)
                if cast < 14.0:
                    errors.append(abs(cast - r))
            checked += 1
    errors = np.array(errors)
    assert checked == 3 and len(errors) > 20
    assert np.median(errors) < 0.05, np.median(errors)
    assert np.mean(errors < 0.25) > 0.9, np.sort(errors)[-10:]


def test_scenario_camera_mismatch_is_said(exported):
    _, own, stderr = exported
    readme = open(os.path.join(own, "README.md")).read()
    for text in (stderr, readme):
        assert "F_W = 3/8" in text and "--camera f3loc" in text
    # Without colour there are no images, but poses and depth lines are complete.
    scene = os.path.join(own, "c000", "apartment")
    assert len(open(os.path.join(scene, "poses.txt")).read().splitlines()) == 3 * (L + 1)
    assert len(open(os.path.join(scene, "depth160.txt")).read().splitlines()[0].split(" ")) == 160
