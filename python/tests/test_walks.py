"""Walks from Python and bring-your-own depth along a walk: sim_walk writes what `floorcast sim walk`
writes (same seed, same bytes), colour views for a depth network, depth maps written back by a
script standing in for the network give the simulated depth's track exactly (CLI and Python),
other depth changes it; track() with any tracker and any matcher (names, registered ones, a
Matcher built once), per-step errors as numpy."""
import csv
import json
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

import floorcast as fc

DATA = fc.data_dir()
CLI = os.environ.get("FLOORCAST_CLI", "")
OUT = os.path.join(os.environ.get("FLOORCAST_TEST_OUT", "/tmp/floorcast_pytest"), "walks")
PLAN = os.path.join(DATA, "floorplans", "buildings", "apartment.json")
NETWORK = os.path.join(DATA, "examples", "byo_depth", "walk_depth_network.py")
sys.path.insert(0, os.path.join(DATA, "examples", "own_matchers"))
import chamfer  # noqa: E402  (examples/own_matchers/chamfer.py)
TIMING = {"time_per_step_s", "init_s", "depth_dir", "depth_kind", "walk"}


def fresh(name):
    path = os.path.join(OUT, name)
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    return path


def cli(*args):
    assert CLI, "FLOORCAST_CLI is not set (ctest sets it)"
    r = subprocess.run([CLI, *args], capture_output=True, text=True)
    assert r.returncode == 0, "floorcast %s failed:\n%s%s" % (" ".join(args), r.stdout, r.stderr)
    return r.stdout


def network(walk, depth, *extra):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    r = subprocess.run([sys.executable, NETWORK, walk, depth, *extra], capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stdout + r.stderr
    return r.stdout


def metrics(folder):
    with open(os.path.join(folder, "metrics.json")) as f:
        return {k: v for k, v in json.load(f).items() if k not in TIMING}


def errors(folder):
    with open(os.path.join(folder, "errors.csv")) as f:
        return [{k: v for k, v in row.items() if k != "time_s"} for row in csv.DictReader(f)]


@pytest.fixture(scope="module")
def mono_walk():
    """A walk with three monocular scans (colour views rendered), from the CLI."""
    walk = fresh("mono_walk")
    cli("sim", "walk", PLAN, "--pose", "4.0,3.0,20", "--steps", "50", "--scan-every", "20", "--sensor", "mono",
        "--rgb", "--seed", "3", "-o", walk)
    return walk


def test_sim_walk_renders_the_colour_views_of_every_observation(mono_walk):
    w = fc.load_walk(mono_walk)
    assert [o["step"] for o in w.observations] == [0, 20, 40]
    for i, o in enumerate(w.observations):
        with open(os.path.join(o["path"], "scan.json")) as f:
            views = json.load(f)["views"]
        assert len(views) > 1
        for v in views:
            assert os.path.getsize(os.path.join(o["path"], v["rgb"])) > 1000, v
        scan = w.scan(i)
        rgb = scan.views[0].rgb
        assert rgb.dtype == np.uint8 and rgb.shape[2] == 3
        assert len(np.unique(rgb.reshape(-1, 3), axis=0)) > 50  # a rendered picture, not a blank
        assert scan.truth is not None
        assert np.allclose(w.truth[o["step"], :2], [scan.truth["x_m"], scan.truth["y_m"]])


def test_depth_written_back_by_a_network_script_gives_the_simulated_depths_track(mono_walk):
    base = fresh("byo")
    depth = os.path.join(base, "depth")
    assert "depth maps for 3 observations" in network(mono_walk, depth)
    cli("track", PLAN, mono_walk, "--quiet", "-o", os.path.join(base, "sim"))
    cli("track", PLAN, mono_walk, "--depth-dir", depth, "--quiet", "-o", os.path.join(base, "byo"))
    m_sim, m_byo = metrics(os.path.join(base, "sim")), metrics(os.path.join(base, "byo"))
    assert m_sim["started"] and m_sim["observations_used"] == 3
    assert m_byo == m_sim
    assert errors(os.path.join(base, "byo")) == errors(os.path.join(base, "sim"))
    with open(os.path.join(base, "byo", "metrics.json")) as f:
        assert json.load(f)["depth_dir"] == depth

    # The same through Python, with the step's folder named flat (DEPTH/step_NNNN) instead.
    flat = os.path.join(base, "flat")
    os.makedirs(flat)
    for o in fc.load_walk(mono_walk).observations:
        name = os.path.basename(o["path"])
        shutil.copytree(os.path.join(depth, "observations", name), os.path.join(flat, name))
    r = fc.track(fc.load_plan(PLAN), mono_walk, depth_dir=flat)
    assert {k: v for k, v in r.metrics.items() if k not in TIMING} == {
        k: v for k, v in m_sim.items() if k not in {"started", "tracker", "matcher", "tracker_parameters",
                                                      "matcher_parameters", "plan", "notes"}}
    sim_rows = errors(os.path.join(base, "sim"))
    assert np.allclose(r.position_error_m, [float(x["position_error_m"]) for x in sim_rows], atol=5e-5)
    assert list(r.step) == [int(x["step"]) for x in sim_rows]

    # The network's depth matters: noisy depth gives another track.
    noisy = os.path.join(base, "noisy")
    network(mono_walk, noisy, "--noise-m", "0.4", "--seed", "1")
    cli("track", PLAN, mono_walk, "--depth-dir", noisy, "--quiet", "-o", os.path.join(base, "noisy_track"))
    assert errors(os.path.join(base, "noisy_track")) != errors(os.path.join(base, "sim"))


def test_depth_dir_refusals_name_what_is_missing(mono_walk):
    base = fresh("byo_refusals")
    depth = os.path.join(base, "depth")
    network(mono_walk, depth)
    shutil.rmtree(os.path.join(depth, "observations", "step_0020"))
    with pytest.raises(Exception) as e:
        fc.track(fc.load_plan(PLAN), mono_walk, depth_dir=depth)
    assert "no depth maps for the observation at step 20" in str(e.value)
    r = subprocess.run([CLI, "track", PLAN, mono_walk, "--depth-dir", depth, "--quiet", "-o", os.path.join(base, "t")],
                       capture_output=True, text=True)
    assert r.returncode == 2 and "step_0020" in r.stderr, r.stderr
    # Perfect observations have no depth to replace.
    perfect = fc.sim_walk(fc.load_plan(PLAN), fresh("perfect_for_refusal"), steps=10, start=(4.0, 3.0, 20.0))
    with pytest.raises(Exception) as e:
        fc.track(fc.load_plan(PLAN), perfect, depth_dir=depth)
    assert "perfect observation" in str(e.value)


def test_python_sim_walk_writes_the_same_bytes_as_the_cli():
    a, b = fresh("cli_walk"), fresh("py_walk")
    cli("sim", "walk", PLAN, "--steps", "40", "--scan-every", "10", "--seed", "5", "--odometry", "pdr", "-o", a)
    w = fc.sim_walk(fc.load_plan(PLAN), b, steps=40, scan_every=10, seed=5, odometry="pdr")
    for f in ("walk.json", "steps.csv", "truth.tum", "odometry.tum", "observations/step_0010/observation.json"):
        with open(os.path.join(a, f), "rb") as x, open(os.path.join(b, f), "rb") as y:
            assert x.read() == y.read(), f
    assert len(w) == 40 and w.truth.shape == (40, 3) and w.odometry.shape == (40, 3)
    assert np.allclose(w.odometry[0], w.truth[0])  # chained from the true start
    assert not np.allclose(w.odometry[-1], w.truth[-1])  # pdr drifts
    assert w.summary["length_m"] > 0
    assert repr(w).startswith("<floorcast.Walk ")
    with pytest.raises(Exception):
        fc.load_walk(os.path.join(OUT, "no_such_walk"))


def test_track_any_tracker_any_matcher_per_step_errors_as_numpy():
    plan = fc.load_plan(PLAN)
    walk = fc.sim_walk(plan, fresh("perfect_walk"), steps=60, scan_every=15, seed=2, start=(4.0, 3.0, 20.0),
                       odometry="exact")
    pf = fc.track(plan, walk)  # pf with kernel, as `floorcast track`
    cli("track", PLAN, walk.dir, "--quiet", "-o", fresh("perfect_walk_cli"))
    assert {k: v for k, v in pf.metrics.items() if k not in TIMING} == {
        k: v for k, v in metrics(os.path.join(OUT, "perfect_walk_cli")).items()
        if k not in {"started", "tracker", "matcher", "tracker_parameters", "matcher_parameters", "plan"}}
    assert pf.started and pf.tracker == "pf" and pf.matcher == "kernel"
    n = len(pf.step)
    for a in (pf.t_s, pf.distance_m, pf.position_error_m, pf.yaw_error_deg, pf.stage, pf.updated):
        assert isinstance(a, np.ndarray) and a.shape == (n,)
    assert pf.estimate.shape == (n, 3) and pf.truth.shape == (n, 3)
    assert np.allclose(np.hypot(*(pf.estimate[:, :2] - pf.truth[:, :2]).T), pf.position_error_m)
    assert pf.updated.dtype == bool and pf.updated.sum() == pf.observations_used == 4
    # Perfect observations and exact odometry in a small apartment: ambiguous at first (its halves
    # look alike), on the true pose by the end (measured: last-10 RMSE 0.19 m, end error 0.26 m).
    assert pf.metrics["converged"] and pf.metrics["rmse_last_m"] < 0.5

    # hist with ray; a Matcher built once gives what its name gives.
    hist = fc.track(plan, walk, tracker="hist")
    assert hist.tracker == "hist" and hist.matcher == "ray" and hist.started
    assert hist.metrics["rmse_last_m"] < 0.5
    kernel = fc.Matcher(plan, "kernel")
    again = fc.track(plan, walk, matcher=kernel)
    assert np.array_equal(again.position_error_m, pf.position_error_m)
    with pytest.raises(Exception):
        fc.track(plan, walk, matcher=kernel, matcher_params={"alpha": 1})

    # A matcher registered from Python (examples/own_matchers/chamfer.py) tracks like a built-in one.
    calls = []

    def prepare(p, grid, params):
        return {"distance_m": p.rasters(grid)["distance_m"], "grid": grid, "params": params}

    def match(state, observation):
        calls.append(1)
        return chamfer.chamfer_posterior(state["distance_m"], state["grid"], observation.segments, **state["params"])

    fc.register_matcher("chamfer_track", prepare=prepare, match=match, params={"sigma_m": 0.2, "clearance_m": 0.2},
                        resolution_m=0.2)
    try:
        mine = fc.track(plan, walk, tracker="hist", matcher="chamfer_track")
        assert mine.started and mine.matcher == "chamfer_track" and len(calls) == 4
        assert np.all(np.isfinite(mine.position_error_m))
    finally:
        fc.unregister_matcher("chamfer_track")
    with pytest.raises(Exception) as e:
        fc.track(plan, walk, tracker="nosuchtracker")
    assert "nosuchtracker" in str(e.value)
