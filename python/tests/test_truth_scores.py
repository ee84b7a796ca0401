"""scripts/truth_scores.py on a small perfect-observation run: one row per point with the truth's score over the
posterior's maximum, and a paired comparison that gives identical outcomes against identical plans."""
import csv
import os
import shutil
import subprocess
import sys

import pytest

import floorcast as fc

OUT = os.environ.get("FLOORCAST_TEST_OUT", "/tmp/floorcast_pytest")
CLI = os.environ.get("FLOORCAST_CLI", "")
SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "truth_scores.py")


@pytest.fixture(scope="module")
def run_dir():
    if not CLI:
        pytest.fail("FLOORCAST_CLI is not set (ctest sets it)")
    root = os.path.join(OUT, "truth_scores")
    shutil.rmtree(root, ignore_errors=True)
    os.makedirs(root)
    plan = os.path.join(fc.data_dir(), "floorplans", "buildings", "apartment.json")
    run = os.path.join(root, "run")
    subprocess.run([CLI, "compare-matchers", plan, "--points", "8", "--seed", "1", "--rays", "36", "--uniform",
                    "--quiet", "-o", run], check=True, capture_output=True, text=True)
    return run


def test_rows_scores_and_pairing(run_dir):
    root = os.path.dirname(run_dir)
    same = os.path.join(root, "same_plans")
    shutil.copytree(os.path.join(run_dir, "plans"), same)
    table = os.path.join(root, "points.csv")
    res = subprocess.run([sys.executable, SCRIPT, run_dir, "--where", "all", "--against", same, "--csv", table],
                         check=True, capture_output=True, text=True)
    rows = list(csv.DictReader(open(table)))
    assert len(rows) == 8
    for r in rows:
        ratio = float(r["truth_over_best"])
        assert ratio != ratio or 0.0 <= ratio <= 1.0 + 1e-6, r  # NaN only for an all-zero posterior
        assert float(r["area_above_truth_m2"]) >= 0.0
        assert 0.0 <= float(r["heading_off_deg"]) <= 180.0
        # The apartment's walls run in two directions: PALMS+ always tests the true heading.
        assert float(r["heading_off_deg"]) <= 2.5, r
        # The same poses on the same plans: the same outcome, point by point.
        assert r["success_against"] == r["success"], r
    localised = sum(r["success"] == "True" for r in rows)
    assert "| apartment | 8 |" in res.stdout
    assert "%d / %d of 8 |" % (localised, localised) in res.stdout


def test_refuses_a_matcher_the_run_does_not_have(run_dir):
    res = subprocess.run([sys.executable, SCRIPT, run_dir, "--matcher", "no_such"], capture_output=True, text=True)
    assert res.returncode != 0
    assert "no matcher labelled no_such" in res.stderr
