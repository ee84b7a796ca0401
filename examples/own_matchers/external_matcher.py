#!/usr/bin/env python3
"""A floorcast matcher as an external program: any language works, this one is Python + numpy.

floorcast runs `COMMAND... REQUEST_JSON` once per observation (protocol floorcast-matcher/1,
localization/match/include/floorcast/match/external.hpp): the request names the plan, the
observation and the shared grid; the program writes output_dir/posterior.npy (yaw, y, x) scores,
or output_dir/top_k.json with poses. A scenario names it like any matcher:

    matchers:
      chamfer_exe:
        matcher: external
        command: [python3, examples/own_matchers/external_matcher.py]
        timeout_s: 60
        resolution_m: 0.2
        params: {sigma_m: 0.2}      # handed to this program verbatim
"""
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from chamfer import chamfer_posterior, wall_distance_from_plan_json  # noqa: E402


def distance_field(request):
    """The plan's distance field, computed once per plan and grid: cached beside plan.json (the
    folder floorcast keeps for this matcher), written atomically as calls may run in parallel."""
    grid = request["grid"]
    cache = os.path.join(os.path.dirname(request["plan"]),
                         "distance_%g_%dx%d.npy" % (grid["resolution_m"], grid["width_px"], grid["height_px"]))
    if os.path.exists(cache):
        return np.load(cache)
    with open(request["plan"]) as f:
        distance = wall_distance_from_plan_json(json.load(f), grid)
    tmp = "%s.%d.tmp.npy" % (cache, os.getpid())
    np.save(tmp, distance)
    os.replace(tmp, cache)
    return distance


def main():
    with open(sys.argv[1]) as f:
        request = json.load(f)
    if request.get("protocol") != "floorcast-matcher/1":
        sys.exit("unsupported protocol %r" % request.get("protocol"))
    with open(request["observation"]) as f:
        observation = json.load(f)
    params = request["params"]
    posterior = chamfer_posterior(distance_field(request), request["grid"], observation["segments_m"],
                                  sigma_m=params.get("sigma_m", 0.2), clearance_m=params.get("clearance_m", 0.2))
    np.save(os.path.join(request["output_dir"], "posterior.npy"), posterior)


if __name__ == "__main__":
    main()
