"""pytest suite of the Python bindings and of floorcast's standard outputs read back by numpy.

Run by ctest (python_pytest) with Debian's /usr/bin/python3 and PYTHONPATH=<build>/python.
FLOORCAST_CLI names the command-line tool for the output-format tests.
"""
import json
import os
import shutil
import subprocess

import numpy as np
import pytest

import floorcast as fc

DATA = fc.data_dir()
OUT = os.environ.get("FLOORCAST_TEST_OUT", "/tmp/floorcast_pytest")
CLI = os.environ.get("FLOORCAST_CLI", "")
SMALL = {"geometry": {"width_px": 160, "height_px": 120}}


@pytest.fixture(scope="module")
def plan():
    return fc.load_plan(os.path.join(DATA, "floorplans", "buildings", "two_rooms.json"))


@pytest.fixture(scope="module")
def out_dir():
    os.makedirs(OUT, exist_ok=True)
    return OUT


def test_import_and_plan(plan):
    assert fc.__version__
    info = plan.info()
    assert info["walls"] > 0 and info["doors"] > 0
    xmin, ymin, xmax, ymax = info["bounds_m"]
    assert xmax > xmin and ymax > ymin
    assert len(plan.hash) == 16
    picture = plan.render(10.0)
    assert picture.dtype == np.uint8 and picture.ndim == 3 and picture.shape[2] == 3
    assert "kernel" in fc.matcher_names() and "ray" in fc.matcher_names()
    generated = fc.generate_plan("apartment", seed=2)
    assert generated.info()["walls"] > 10


def test_bad_input_raises_value_error(plan):
    with pytest.raises(ValueError, match="inside wall"):
        fc.simulate_scan(plan, (5.02, 2.0, 0.0))
    with pytest.raises(ValueError):
        fc.load_plan("/nonexistent/plan.json")


def test_simulate_scan_with_colour(plan):
    scan = fc.simulate_scan(plan, (2.0, 2.0, 30.0), sensor="perfect", rgb=True, params=SMALL)
    assert len(scan) == 6 and scan.truth["x_m"] == pytest.approx(2.0)
    previous = None
    for v in scan.views:
        assert v.depth.shape == (120, 160) and v.depth.dtype == np.float32
        assert (v.depth > 0).mean() > 0.99  # a closed building: every pixel sees a surface
        assert v.rgb.shape == (120, 160, 3) and v.rgb.dtype == np.uint8
        assert v.rgb.std() > 10.0  # not blank
        assert v.T_scan_camera.shape == (4, 4)
        assert v.intrinsics["width_px"] == 160
        if previous is not None:
            assert np.abs(v.rgb.astype(int) - previous.astype(int)).mean() > 5.0  # views differ
        previous = v.rgb


def test_observe_match_posterior_and_estimate(plan):
    scan = fc.simulate_scan(plan, (2.3, 1.7, 35.0), sensor="perfect", params=SMALL)
    obs = fc.observe(scan)
    assert obs.segments.ndim == 2 and obs.segments.shape[1] == 4 and len(obs.segments) > 0
    assert obs.truth["x_m"] == pytest.approx(2.3)
    res = fc.match(plan, obs, matcher="kernel")
    post = res.posterior
    grid = res.grid
    assert post.dtype == np.float32 and post.shape == tuple(grid["shape"])
    assert grid["axes"] == ("yaw", "y", "x")
    assert (post >= 0).all() and post.max() > 0
    est = res.estimate
    assert est["status"] == "ok"
    # The estimate is the posterior's argmax cell.
    s, r, c = np.unravel_index(np.argmax(post), post.shape)
    ox, oy = grid["origin_m"]
    assert est["x_m"] == pytest.approx(ox + (c + 0.5) * grid["resolution_m"], abs=1e-6)
    assert est["y_m"] == pytest.approx(oy + (r + 0.5) * grid["resolution_m"], abs=1e-6)
    assert "position_error_m" in est
    assert len(res.top_k) >= 1 and res.top_k[0]["score"] == pytest.approx(est["score"])
    assert res.parameters and res.matcher == "kernel"


def test_perfect_observation_localizes(plan):
    # With every door closed the two rooms are symmetric boxes (the estimate lands 1.2 m off, in the
    # mirrored spot); with the inner door open the spot sees into the second room, as in the CLI's
    # match_cli_localize_* tests.
    obs = fc.perfect_observation(plan, (2.3, 1.7, 35.0), rays=36, doors_open=True)
    assert len(obs.ray_ranges) == 36
    res = fc.match(plan, obs, matcher="ray", params={"doors_closed": False})
    assert res.estimate["position_error_m"] < 0.2
    assert abs((res.estimate["yaw_deg"] - 35.0 + 180.0) % 360.0 - 180.0) <= 5.0


def test_bring_your_own_depth_in_python(plan):
    scan = fc.simulate_scan(plan, (2.3, 1.7, 35.0), sensor="mono", seed=4, params=SMALL)
    reference = fc.observe(scan, scale_alignment="none")
    # Feeding the same depth back reproduces the observation exactly.
    for v in scan.views:
        v.depth = v.depth.copy()
    again = fc.observe(scan, scale_alignment="none")
    np.testing.assert_array_equal(reference.segments, again.segments)
    # Another depth (here: twice as far) changes it.
    for v in scan.views:
        v.depth = 2.0 * v.depth
    assert not np.array_equal(reference.segments, fc.observe(scan, scale_alignment="none").segments)
    with pytest.raises(ValueError, match="shape"):
        scan.views[0].depth = np.zeros((10, 10), np.float32)


def test_posterior_npy_round_trip(plan, out_dir):
    obs = fc.perfect_observation(plan, (6.5, 4.0, 90.0))
    res = fc.match(plan, obs)
    path = os.path.join(out_dir, "posterior.npy")
    res.save_npy(path)
    back = np.load(path)
    np.testing.assert_array_equal(back, res.posterior)


def test_plane_matcher_on_perfect_planes(out_dir):
    plan = fc.load_plan(os.path.join(DATA, "floorplans", "buildings", "apartment.json"))
    obs = fc.perfect_observation(plan, (3.0, 6.7, 80.0))
    assert len(obs.planes) >= 5
    p = obs.planes[0]
    assert abs(np.linalg.norm(p["normal"]) - 1.0) < 1e-9 and p["offset_m"] <= 0.0 and p["cells_m"].shape[1] == 3
    res = fc.match(plan, obs, matcher="planes")
    assert "planes" in fc.matcher_names()
    assert res.localized and res.estimate["status"] == "ok"
    # A corridor looks the same turned by 180 degrees: the true pose is one of the best modes.
    assert any(t["position_error_m"] < 0.05 and t["yaw_error_deg"] < 1.0 for t in res.top_k[:3])
    assert res.counters["hypotheses_accepted"] > 0
    # A score threshold no pose reaches: not localized, every matcher.
    for m in ("kernel", "planes"):
        r = fc.match(plan, obs, matcher=m, params={"min_score": 1e9})
        assert not r.localized and r.estimate["x_m"] is None and r.top_k == []


def test_run_scenario(out_dir, capfd):
    scenario = os.path.join(out_dir, "tiny.yaml")
    with open(scenario, "w") as f:
        f.write("name: pytest-tiny\n"
                "buildings: [" + os.path.join(DATA, "floorplans", "buildings", "two_rooms.json") + "]\n"
                "sampling: {count: 3, seed: 5, clearance_m: 0.5}\n"
                "matchers: {kernel: {matcher: kernel}}\n"
                "output: {heatmaps: 0}\n")
    run_dir = os.path.join(out_dir, "tiny_run")
    shutil.rmtree(run_dir, ignore_errors=True)  # a folder of an older build's run would be refused
    summary = fc.run_scenario(scenario, run_dir, jobs=1)
    printed = capfd.readouterr()
    assert printed.out == "" and printed.err == "", "run_scenario(quiet=True) must print nothing"
    assert summary["complete"] is True and summary["units"] == 3
    assert "kernel" in summary["cells"][0]["groups"]["all"]


# ---- standard outputs of the command-line tool, read back with numpy only ----

def cli(*args):
    if not CLI:
        pytest.fail("FLOORCAST_CLI is not set (ctest sets it)")
    return subprocess.run([CLI, *args], check=True, capture_output=True, text=True)


def read_ply(path):
    """A PLY reader written for this test (binary little-endian float xyz + uchar rgb)."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().splitlines()
    assert header[0] == "ply" and header[1] == "format binary_little_endian 1.0"
    count = [int(l.split()[2]) for l in header if l.startswith("element vertex")][0]
    props = [l.split()[1:] for l in header if l.startswith("property")]
    types = {"float": "<f4", "uchar": "u1"}
    dtype = np.dtype([(name, types[t]) for t, name in props])
    return np.frombuffer(data, dtype=dtype, count=count, offset=end)


def read_tum_like_evo(path):
    """evo's file_interface.read_tum_trajectory_file rules: '#' comments, 8 whitespace-separated
    columns (timestamp tx ty tz qx qy qz qw), unit quaternions."""
    raw = np.loadtxt(path, comments="#", ndmin=2)
    assert raw.shape[1] == 8, "TUM lines must have 8 columns"
    stamps, xyz, quat = raw[:, 0], raw[:, 1:4], raw[:, 4:8]
    np.testing.assert_allclose(np.linalg.norm(quat, axis=1), 1.0, atol=1e-9)
    assert np.all(np.diff(stamps) >= 0)
    return stamps, xyz, quat


def test_cli_outputs_read_by_numpy(out_dir):
    plan_path = os.path.join(DATA, "floorplans", "buildings", "two_rooms.json")
    scan_dir = os.path.join(out_dir, "cli_scan")
    cli("sim", "scan", plan_path, "--pose", "2.3,1.7,35", "--sensor", "mono", "--setting", "partial", "-o", scan_dir)
    clouds = os.path.join(out_dir, "cli_clouds")
    obs = os.path.join(out_dir, "cli_obs")  # a folder: observation.json + observation.diagnostics.json
    cli("observe", scan_dir, "--clouds", clouds, "-o", obs)
    assert os.path.isfile(os.path.join(obs, "observation.json"))
    assert os.path.isfile(os.path.join(obs, "observation.diagnostics.json"))
    for name in ("back_projected.ply", "scaled.ply", "slice.ply"):
        pts = read_ply(os.path.join(clouds, name))
        assert len(pts) > 100
        assert np.isfinite(pts["x"]).all() and np.isfinite(pts["z"]).all()
    sliced = read_ply(os.path.join(clouds, "slice.ply"))
    assert np.abs(sliced["z"]).max() < 1e-6  # the slice is 2D (observer frame, z = 0)
    loc = os.path.join(out_dir, "cli_loc")
    cli("localize", plan_path, obs, "--posterior", "npy", "-o", loc)
    post = np.load(os.path.join(loc, "posterior.npy"))
    with open(os.path.join(loc, "posterior_grid.json")) as f:
        grid = json.load(f)
    assert list(post.shape) == grid["shape"] and grid["axes"] == ["yaw", "y", "x"]
    assert len(grid["yaw_deg"]) == post.shape[0]
    with open(os.path.join(loc, "estimate.json")) as f:
        est = json.load(f)
    s, r, c = np.unravel_index(np.argmax(post), post.shape)
    assert est["x_m"] == pytest.approx(grid["origin_m"][0] + (c + 0.5) * grid["resolution_m"], abs=1e-6)
    assert est["y_m"] == pytest.approx(grid["origin_m"][1] + (r + 0.5) * grid["resolution_m"], abs=1e-6)
    walk = os.path.join(out_dir, "cli_walk")
    cli("sim", "walk", plan_path, "--pose", "2,2,0", "--steps", "30", "--odometry", "vio", "--scan-every", "10",
        "--sensor", "perfect", "--seed", "3", "-o", walk)
    track = os.path.join(out_dir, "cli_track")
    subprocess.run([CLI, "track", plan_path, walk, "--filter", "hist", "-o", track], capture_output=True, text=True)
    for name in (os.path.join(walk, "truth.tum"), os.path.join(walk, "odometry.tum"), os.path.join(track, "estimate.tum")):
        if name.endswith("estimate.tum") and not os.path.exists(name):
            continue  # no track (exit 3) is a reported state, not a format failure
        stamps, xyz, quat = read_tum_like_evo(name)
        assert len(stamps) >= 2
        np.testing.assert_allclose(xyz[:, 2], 0.0)


def _yaw_of(quat_xyzw):
    x, y, z, w = quat_xyzw.T
    return np.arctan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def test_walk_tum_files_in_the_frames_their_names_say(out_dir):
    """truth.tum is the world (plan) frame; odometry.tum is the odometry's own frame, starting at
    the identity, as evo expects of an odometry source. Read as evo reads TUM files; with exact
    odometry the odometry trajectory is the truth seen from the start pose."""
    plan_path = os.path.join(DATA, "floorplans", "buildings", "apartment.json")
    walk = os.path.join(out_dir, "tum_frames_walk")
    cli("sim", "walk", plan_path, "--pose", "5.25,8.75,30", "--steps", "40", "--odometry", "exact", "--seed", "4",
        "-o", walk)
    t_stamps, t_xyz, t_quat = read_tum_like_evo(os.path.join(walk, "truth.tum"))
    o_stamps, o_xyz, o_quat = read_tum_like_evo(os.path.join(walk, "odometry.tum"))
    np.testing.assert_array_equal(t_stamps, o_stamps)
    # World frame: the walk starts where --pose says.
    np.testing.assert_allclose(t_xyz[0, :2], [5.25, 8.75], atol=1e-9)
    assert np.degrees(_yaw_of(t_quat[:1]))[0] == pytest.approx(30.0, abs=1e-6)
    # Odometry frame: the identity first.
    np.testing.assert_allclose(o_xyz[0], 0.0, atol=1e-12)
    np.testing.assert_allclose(o_quat[0], [0.0, 0.0, 0.0, 1.0], atol=1e-12)
    # Exact odometry = the truth expressed in the start frame: T_start^-1 T_world_body.
    yaw0 = _yaw_of(t_quat[:1])[0]
    c, s = np.cos(yaw0), np.sin(yaw0)
    d = t_xyz[:, :2] - t_xyz[0, :2]
    in_start = np.stack([c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1]], axis=1)
    np.testing.assert_allclose(o_xyz[:, :2], in_start, atol=1e-6)
    dyaw = np.angle(np.exp(1j * (_yaw_of(o_quat) - (_yaw_of(t_quat) - yaw0))))
    np.testing.assert_allclose(dyaw, 0.0, atol=1e-6)
    assert np.max(np.linalg.norm(o_xyz[:, :2], axis=1)) > 1.0  # the walk went somewhere


def test_posterior_outputs_none_npz_f16_top_k(out_dir):
    """--posterior: none writes no volume (same estimate), npz-f16 is the volume in float16,
    top-k its best cells in descending order; numpy reads each as written."""
    plan_path = os.path.join(DATA, "floorplans", "buildings", "apartment.json")
    obs = os.path.join(out_dir, "post_obs")
    cli("sim", "perfect", plan_path, "--pose", "5.25,8.75,20", "-o", obs)
    runs = {}
    for mode in ("npy", "none", "npz-f16", "top-k"):
        d = os.path.join(out_dir, "post_" + mode)
        cli("localize", plan_path, obs, "--posterior", mode, "--posterior-cells", "500", "-o", d)
        with open(os.path.join(d, "estimate.json")) as f:
            runs[mode] = (d, json.load(f))
    for mode in ("none", "npz-f16", "top-k"):
        assert runs[mode][1]["x_m"] == runs["npy"][1]["x_m"] and runs[mode][1]["yaw_deg"] == runs["npy"][1]["yaw_deg"]
    assert not any(f.startswith("posterior.n") or f.startswith("posterior_") for f in os.listdir(runs["none"][0]))
    assert os.path.isfile(os.path.join(runs["none"][0], "posterior.png"))
    full = np.load(os.path.join(runs["npy"][0], "posterior.npy"))
    with np.load(os.path.join(runs["npz-f16"][0], "posterior.npz")) as z:
        half = z["posterior"]
    assert half.dtype == np.float16 and half.shape == full.shape
    np.testing.assert_allclose(half.astype(np.float32), full, rtol=1e-3, atol=1e-3 * full.max())
    assert os.path.getsize(os.path.join(runs["npz-f16"][0], "posterior.npz")) < 0.5 * full.nbytes
    with np.load(os.path.join(runs["top-k"][0], "posterior_top.npz")) as z:
        index, score, x = z["index"], z["score"], z["x_m"]
    assert index.shape == (500, 3) and np.all(np.diff(score) <= 0)
    np.testing.assert_array_equal(score, full[index[:, 0], index[:, 1], index[:, 2]])
    assert score[0] == full.max()
    with open(os.path.join(runs["top-k"][0], "posterior_grid.json")) as f:
        grid = json.load(f)
    np.testing.assert_allclose(x, grid["origin_m"][0] + (index[:, 2] + 0.5) * grid["resolution_m"], atol=1e-4)


def test_bev_matcher(plan):
    """The semantic BEV matcher: perfect BEVs, a simulated predictor on a scan, a BEV of one's own."""
    assert "bev" in fc.matcher_names()
    pose = (2.35, 1.75, 30.0)
    obs = fc.perfect_observation(plan, pose, doors_open=True, bev_columns=72)
    assert [b["classes"] for b in obs.bev] == ["semantic", "occupancy"]
    sem = obs.bev[0]
    assert sem["probabilities"].shape == (72, 32, 4)
    assert np.allclose(sem["probabilities"].sum(axis=2), 1.0)
    r = fc.match(plan, obs, matcher="bev")
    assert r.estimate["x_m"] == pytest.approx(pose[0], abs=0.15)
    # A simulated scan with column semantics through the perfect predictor.
    scan = fc.simulate_scan(plan, pose, sensor="perfect", setting="single", doors_open=True, semantics=True, params=SMALL)
    o = fc.observe(scan, bev="perfect")
    assert len(o.bev) == 2 and o.bev[0]["probabilities"].shape[0] > 5
    # A BEV of one's own: the perfect one's columns, as a network would output them.
    own = fc.bev_observation(sem["probabilities"], hfov_deg=360.0)
    r2 = fc.match(plan, own, matcher="bev", params={"doors_closed": False})
    assert r2.estimate["x_m"] == pytest.approx(pose[0], abs=0.15)
    with pytest.raises(ValueError):
        fc.bev_observation(np.zeros((4, 8, 3), np.float32))
