"""floorcast: floor-plan-based indoor localization test-bed (PALMS / PALMS+ family).

    import floorcast as fc
    plan = fc.load_plan(fc.data_dir() + "/floorplans/buildings/office.json")
    scan = fc.simulate_scan(plan, (12.0, 6.0, 30.0), sensor="mono", rgb=True)
    obs = fc.observe(scan)
    result = fc.match(plan, obs, matcher="kernel")
    result.posterior      # numpy float32 (yaw, y, x)
    result.estimate       # {'x_m': ..., 'y_m': ..., 'yaw_deg': ..., 'score': ..., 'status': 'ok', ...}

Bring your own depth: replace each view's depth by your network's (float32 metres, shape (H, W))
before observing: ``scan.views[k].depth = my_net(scan.views[k].rgb)``.
"""
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
