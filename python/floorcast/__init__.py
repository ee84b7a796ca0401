"""floorcast: floor-plan-based indoor localization test-bed (PALMS / PALMS+ family).

    import floorcast as fc
    plan = fc.load_plan(fc.data_dir() + "/floorplans/buildings/office.json")
    scan = fc.simulate_scan(plan, (12.0, 6.0, 30.0), sensor="mono", rgb=True)
    obs = fc.observe(scan)
    result = fc.match(plan, obs, matcher="kernel")
    result.posterior      # numpy float32 (yaw, y, x)
    result.estimate       # {'x_m': ..., 'y_m': ..., 'yaw_deg': ..., 'score': ..., 'status': 'ok', ...}

Bring your own depth: replace each view's depth by your network's (float32 metres, shape (H, W))
before observing: ``scan.views[k].depth = my_net(scan.views[k].rgb)`` (views are the scan's own
pixels: in-place edits such as ``scan.views[k].depth[mask] = 0`` change the scan too).

Your own matcher, scored by the same engine as kernel and ray (examples/own_matchers/):

    def prepare(plan, grid, params):          # once per building
        return plan.rasters(grid)["distance_m"]
    def match(distance, observation):         # once per observation
        return scores                         # float (yaw, y, x) on grid, or [{x_m, y_m, yaw_deg, score}]
    fc.register_matcher("mine", prepare=prepare, match=match, params={"sigma_m": 0.2})
    fc.run_scenario("my_scenario.yaml", "runs/mine")   # matchers: {mine: {matcher: mine}, kernel: ...}
"""
import atexit as _atexit
import os as _os


def _find_data_dir():
    # The shipped data (buildings, scenarios): FLOORCAST_DATA_DIR, else the source tree above this
    # package (the build tree lives inside it), else an installed share/floorcast.
    if _os.environ.get("FLOORCAST_DATA_DIR"):
        return
    here = _os.path.dirname(_os.path.abspath(__file__))
    d = here
    for _ in range(6):
        if _os.path.isfile(_os.path.join(d, "scenarios", "quickstart.yaml")) and _os.path.isdir(
                _os.path.join(d, "floorplans", "buildings")):
            _os.environ["FLOORCAST_DATA_DIR"] = d
            return
        for share in (_os.path.join(d, "share", "floorcast"),):
            if _os.path.isfile(_os.path.join(share, "scenarios", "quickstart.yaml")):
                _os.environ["FLOORCAST_DATA_DIR"] = share
                return
        d = _os.path.dirname(d)


_find_data_dir()

from ._floorcast import *  # noqa: E402,F401,F403
from ._floorcast import __version__  # noqa: E402,F401
from ._floorcast import _unregister_python_matchers  # noqa: E402

# Matchers registered from Python hold Python functions: drop them while the interpreter still runs.
_atexit.register(_unregister_python_matchers)
