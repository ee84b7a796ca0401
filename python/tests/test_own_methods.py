"""Own methods in floorcast's engine from Python: a registered matcher and an external program
scored beside kernel and ray in one scenario (same numbers re-run, resumed and sharded), errors of
a misbehaving method kept to its units, matchers built once, scan views edited in place."""
import json
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

import floorcast as fc

DATA = fc.data_dir()
OUT = os.path.join(os.environ.get("FLOORCAST_TEST_OUT", "/tmp/floorcast_pytest"), "own_methods")
EXAMPLES = os.path.join(DATA, "examples", "own_matchers")
sys.path.insert(0, EXAMPLES)
import chamfer  # noqa: E402  (examples/own_matchers/chamfer.py)


def fresh(name):
    path = os.path.join(OUT, name)
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    return path


def prepare(plan, grid, params):
    return {"distance_m": plan.rasters(grid)["distance_m"], "grid": grid, "params": params}


def match(state, observation):
    return chamfer.chamfer_posterior(state["distance_m"], state["grid"], observation.segments, **state["params"])


fc.register_matcher("chamfer_py", prepare=prepare, match=match, params={"sigma_m": 0.2, "clearance_m": 0.2},
                    resolution_m=0.2)


def scenario(path, matchers_yaml, count=4):
    with open(path, "w") as f:
        f.write("name: own-methods\n"
                "buildings: [%s, %s]\n" % (os.path.join(DATA, "floorplans", "buildings", "apartment.json"),
                                           os.path.join(DATA, "floorplans", "buildings", "two_rooms.json")) +
                "sampling: {count: %d, seed: 3, clearance_m: 0.5, region: uniform}\n" % count +
                "observation: {source: perfect, max_range_m: 10, doors_closed: true, rays: 36}\n"
                "output: {heatmaps: 0}\n"
                "scoring: {bootstrap_resamples: 200}\n"
                "matchers:\n" + matchers_yaml)
    return path


FOUR = ("  kernel: {matcher: kernel}\n"
        "  ray: {matcher: ray}\n"
        "  chamfer_py: {matcher: chamfer_py}\n"
        "  chamfer_exe: {matcher: external, command: [%s, %s], resolution_m: 0.2, timeout_s: 120,"
        " params: {sigma_m: 0.2, clearance_m: 0.2}}\n" % (sys.executable, os.path.join(EXAMPLES, "external_matcher.py")))


def without_timing(summary):
    s = json.loads(json.dumps(summary))
    s.pop("timing", None)
    for c in s["cells"]:
        c.pop("timing_mean_s", None)
        for g in c["groups"].values():
            for m in g.values():
                # The metric sets of each matcher (and the rejection set within them, which times
                # negatives too) with their intervals.
                for ms in (m, m.get("rejection", {})):
                    for k in [k for k in ms if "time" in k]:
                        ms.pop(k)
                    for k in [k for k in ms.get("ci95", {}) if "time" in k]:
                        ms["ci95"].pop(k)
    return s


def test_own_matchers_beside_kernel_and_ray():
    yaml = scenario(fresh("four.yaml"), FOUR)
    run = fresh("four_run")
    summary = fc.run_scenario(yaml, run, jobs=2)
    assert summary["matchers"] == ["kernel", "ray", "chamfer_py", "chamfer_exe"]
    groups = summary["cells"][0]["groups"]["all"]
    for label in ("chamfer_py", "chamfer_exe"):
        assert groups[label]["count"] == 8
        # Perfect observations in small buildings: the true pose is among the chamfer matchers' top
        # five modes (the apartment's two identical halves make the first mode a coin toss).
        assert groups[label]["top5_recall_1m"] >= 0.75, (label, groups[label])
    assert "errors" not in summary["cells"][0]
    # The paired comparisons cover the new methods.
    paired = summary["cells"][0]["paired"]["all"]
    assert "kernel vs chamfer_py" in paired and "chamfer_py vs chamfer_exe" in paired
    assert paired["kernel vs chamfer_exe"]["recall_1m_30deg"]["p_value"] <= 1.0
    # The same numbers when run again: into a new folder, resumed, and in two shards.
    again = fc.run_scenario(yaml, fresh("four_again"), jobs=1)
    assert without_timing(again) == without_timing(summary)
    resumed = fc.run_scenario(yaml, run, jobs=2)
    assert without_timing(resumed) == without_timing(summary)
    sharded = fresh("four_shards")
    assert fc.run_scenario(yaml, sharded, shard="0/2") is None  # incomplete: no summary yet
    assert without_timing(fc.run_scenario(yaml, sharded, shard="1/2")) == without_timing(summary)
    with open(os.path.join(run, "summary.md")) as f:
        md = f.read()
    assert "| chamfer_py |" in md and "| chamfer_exe |" in md and "| kernel vs chamfer_py |" in md


def test_the_readme_external_program_route_from_the_cli():
    """README, "Your own matcher", route 2: the external program beside kernel, CLI only."""
    cli = os.environ.get("FLOORCAST_CLI", "")
    assert cli, "FLOORCAST_CLI is not set (ctest sets it)"
    run = fresh("readme_external")
    r = subprocess.run([cli, "run", os.path.join(EXAMPLES, "own_matchers_external.yaml"), "-o", run, "--quiet"],
                       capture_output=True, text=True, cwd=OUT)
    assert r.returncode == 0, r.stdout + r.stderr
    with open(os.path.join(run, "summary.json")) as f:
        summary = json.load(f)
    assert summary["matchers"] == ["kernel", "chamfer_exe"]
    groups = summary["cells"][0]["groups"]["all"]
    assert groups["chamfer_exe"]["count"] == 8 and "errors" not in summary["cells"][0]
    assert groups["chamfer_exe"]["top5_recall_1m"] >= 0.75


def test_a_misbehaving_python_matcher_errs_only_on_its_units():
    def flaky(state, observation):
        n = len(observation.segments)
        if n % 3 == 0:
            raise RuntimeError("my network ran out of memory (%d segments)" % n)
        if n % 3 == 1:
            return np.zeros((2, 2, 2), np.float32)  # wrong shape
        return [{"x_m": 1.0, "y_m": 1.0, "yaw_deg": 0.0, "score": 1.0}]

    fc.register_matcher("flaky", match=flaky)
    try:
        yaml = scenario(fresh("flaky.yaml"), "  kernel: {matcher: kernel}\n  flaky: {matcher: flaky}\n")
        run = fresh("flaky_run")
        summary = fc.run_scenario(yaml, run)
        cell = summary["cells"][0]
        units = []
        for root, _, files in os.walk(os.path.join(run, "units")):
            for f in files:
                with open(os.path.join(root, f)) as fh:
                    units.append(json.load(fh))
        assert len(units) == 8
        errors = [u for u in units if u["outcomes"][1].get("error")]
        assert cell.get("errors", {}).get("flaky", {}).get("units", 0) == len(errors)
        for u in units:
            assert u["outcomes"][0]["ok"]  # kernel never lost
            o = u["outcomes"][1]
            if o.get("error"):
                assert ("my network ran out of memory" in o["failure"]) or ("returned an array of shape (2, 2, 2)" in o["failure"])
        assert summary["cells"][0]["groups"]["all"]["kernel"]["count"] == 8
    finally:
        fc.unregister_matcher("flaky")


def test_matcher_built_once_and_bad_registrations():
    calls = {"prepare": 0, "match": 0}

    def counting_prepare(plan, grid, params):
        calls["prepare"] += 1
        assert grid["width_px"] > 0 and len(grid["yaw_deg"]) == 8
        return plan.rasters(grid)["distance_m"]

    def counting_match(distance, observation):
        calls["match"] += 1
        return [{"x_m": 2.0, "y_m": 2.0, "yaw_deg": 30.0, "score": 2.0}]

    fc.register_matcher("counting", prepare=counting_prepare, match=counting_match, yaw_bins=8, resolution_m=0.25)
    try:
        plan = fc.load_plan(os.path.join(DATA, "floorplans", "buildings", "two_rooms.json"))
        m = fc.Matcher(plan, "counting")
        obs = fc.perfect_observation(plan, (2.3, 1.7, 35.0))
        for _ in range(3):
            r = m.match(obs)
        assert calls == {"prepare": 1, "match": 3}
        assert r.estimate["x_m"] == pytest.approx(2.0) and r.estimate["yaw_deg"] == pytest.approx(30.0)
        assert r.posterior.shape[0] == 8 and r.posterior.sum() == pytest.approx(2.0)
        assert m.parameters["yaw_bins"] == 8 and m.name == "counting"
        # Built-in matchers too: prepared once, matched often.
        k = fc.Matcher(plan, "kernel")
        assert k.match(obs).estimate["status"] == "ok" and k.precompute_s >= 0.0
        with pytest.raises(ValueError, match="unknown parameter \"sigma\""):
            fc.Matcher(plan, "counting", params={"sigma": 1})
    finally:
        fc.unregister_matcher("counting")
    with pytest.raises(ValueError, match="built-in"):
        fc.register_matcher("kernel", match=counting_match)
    with pytest.raises(ValueError, match="unknown matcher"):
        fc.Matcher(fc.load_plan(os.path.join(DATA, "floorplans", "buildings", "two_rooms.json")), "counting")


def test_posterior_grid_and_rasters():
    plan = fc.load_plan(os.path.join(DATA, "floorplans", "buildings", "two_rooms.json"))
    grid = fc.posterior_grid(plan, resolution_m=0.2, yaw_bins=12)
    assert len(grid["yaw_deg"]) == 12 and grid["yaw_deg"][1] == pytest.approx(30.0)
    r = plan.rasters(grid)
    assert r["distance_m"].shape == (grid["height_px"], grid["width_px"]) and r["distance_m"].dtype == np.float32
    assert r["occupancy"].max() == 255 and r["valid"].max() == 255
    assert r["distance_m"][r["occupancy"] == 255].max() == 0.0


def test_scan_views_edit_in_place_or_raise():
    plan = fc.load_plan(os.path.join(DATA, "floorplans", "buildings", "two_rooms.json"))
    scan = fc.simulate_scan(plan, (2.3, 1.7, 35.0), sensor="perfect", rgb=True,
                            params={"geometry": {"width_px": 80, "height_px": 60}})
    v = scan.views[0]
    v.depth[:10, :] = 0.0
    assert (scan.views[0].depth[:10, :] == 0.0).all() and (scan.views[0].depth[10:, :] > 0).any()
    v.rgb[0, 0] = (255, 0, 0)
    assert tuple(scan.views[0].rgb[0, 0]) == (255, 0, 0)
    # An in-place edit reaches the observation module.
    before = fc.observe(scan)
    for view in scan.views:
        view.depth[:] = 0.0
    assert len(fc.observe(scan).segments) == 0 < len(before.segments)
    with pytest.raises(ValueError):
        v.T_scan_camera[0, 3] = 1.0
    with pytest.raises(TypeError):
        v.intrinsics["fx_px"] = 1.0
    with pytest.raises(ValueError):
        before.segments[0, 0] = 1.0
