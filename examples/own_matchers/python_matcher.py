#!/usr/bin/env python3
"""A matcher written in Python, scored by floorcast's engine beside kernel and ray.

    PYTHONPATH=build/python /usr/bin/python3 examples/own_matchers/python_matcher.py [OUT_DIR]

registers `chamfer_py` (chamfer.py on floorcast's plan rasters), then runs own_matchers.yaml, whose
matchers are kernel, ray, chamfer_py and chamfer_exe (the same idea as an external program), and
prints the summary table with the paired comparisons. Run it again: every unit is resumed, the
numbers are the same.
"""
import os
import sys

import floorcast as fc

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from chamfer import chamfer_posterior  # noqa: E402


def prepare(plan, grid, params):
    """Once per building: the distance from every grid cell to the nearest wall."""
    return {"distance_m": plan.rasters(grid)["distance_m"], "grid": grid, "params": params}


def match(state, observation):
    """Once per observation: scores (yaw, y, x) on the shared grid."""
    return chamfer_posterior(state["distance_m"], state["grid"], observation.segments, **state["params"])


fc.register_matcher("chamfer_py", prepare=prepare, match=match, params={"sigma_m": 0.2, "clearance_m": 0.2},
                    resolution_m=0.2, version="1")

if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "runs/own_matchers"
    here = os.path.dirname(os.path.abspath(__file__))
    summary = fc.run_scenario(os.path.join(here, "own_matchers.yaml"), out)
    print(open(os.path.join(out, "summary.md")).read())
