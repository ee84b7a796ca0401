"""Figures a paper can print, from a finished run directory (matplotlib).

    python3 -m floorcast.figures RUN_DIR [-o DIR] [--format pdf|svg|png] [--style paper|screen]
    floorcast figures RUN_DIR ...            (the CLI runs this file)
    floorcast.figures.render_run(run_dir, out_dir=None, fmt="pdf", style="paper") -> [paths]

Reads only the run's files (summary.json, units/**.json, resolved_config.json, plans/ and
heatmaps/ when the run kept them), so it needs matplotlib and numpy but not floorcast's compiled
module. Every figure is laid out for one column of a two-column paper (85 mm wide, 8 pt text;
``--style screen`` doubles the size), with titles and axes in words and units, recalls in percent
with their 95% bootstrap intervals drawn, error CDFs to the largest error (failures shown as the
part of the curve that never reaches 100%), trajectories with start and end markers, time
colouring and jumps drawn as jumps. The C++ PNGs in plots/ stay as quick looks.
"""
import argparse
import glob
import json
import math
import os
import sys

try:
    import numpy as np
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection
except ImportError as _e:  # a clear message, not a traceback, for the CLI
    if __name__ == "__main__":
        print("floorcast: error: figures need numpy and matplotlib (Debian: apt-get install python3-matplotlib): %s" % _e,
              file=sys.stderr)
        sys.exit(2)
    raise

COLUMN_WIDTH_IN = 85.0 / 25.4  # one column of a two-column paper

# Human names of matcher and tracker registry names and of the usual scenario labels; any other
# label is shown as the scenario wrote it.
METHOD_NAMES = {
    "kernel": "PALMS kernel",
    "ray": "F3Loc ray (36)",
    "ray36": "F3Loc ray (36)",
    "ray72": "F3Loc ray (72)",
    "ray180": "F3Loc ray (180)",
    "planes": "plane triplets",
    "bev": "semantic BEV",
    "pf": "particle filter",
    "pf_palms": "particle filter (PALMS init)",
    "pf_uniform": "particle filter (uniform init)",
    "pf_proportional": "particle filter (proportional init)",
    "hist": "histogram filter",
}

# Sweep keys: the last part of the key names the quantity; these read better than the key.
QUANTITY_NAMES = {
    "sensor": "sensor",
    "path": "observation path",
    "model": "depth network",
    "max_range_m": "maximum range",
    "scale_sigma_ln": "per-view scale error (log sigma)",
    "mask_glass": "glass masked",
    "setting": "views per scan",
    "scale_alignment": "scale alignment",
    "extractor": "plane extractor",
    "rays": "rays",
    "num_directions": "ray directions",
    "orientations": "orientations",
    "doors_closed": "doors closed",
    "range_m": "range",
    "count": "observation points",
    "steps": "walk length (steps)",
    "every_steps": "observation every (steps)",
}

VALUE_NAMES = {
    "depth_pro": "Depth Pro",
    "unidepth_v2": "UniDepth V2",
    "depth_anything_v2": "Depth Anything V2",
    "metric3d_v2": "Metric3D v2",
    "mono": "monocular",
    "lidar": "LiDAR",
    "phone": "phone",
    "perfect": "perfect",
    "palms+": "PALMS+",
    "palms": "PALMS",
}

UNIT_SUFFIXES = [("_m", "m"), ("_deg", "°"), ("_s", "s"), ("_px", "px"), ("_mps", "m/s"), ("_hz", "Hz")]


def method_name(label):
    return METHOD_NAMES.get(label, label.replace("_", " "))


def quantity_name(key):
    """'observation.sensor_params.sensor.max_range_m' -> ('maximum range', 'm')."""
    last = key.split(".")[-1]
    unit = ""
    for suffix, u in UNIT_SUFFIXES:
        if last.endswith(suffix):
            unit = u
            break
    if last in QUANTITY_NAMES:
        return QUANTITY_NAMES[last], unit
    base = last
    for suffix, u in UNIT_SUFFIXES:
        if base.endswith(suffix):
            base = base[: -len(suffix)]
            break
    return base.replace("_", " "), unit


def value_text(value, unit=""):
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (int, float)):
        text = ("%g" % value)
        return text + (" " + unit if unit and unit != "°" else unit)
    if isinstance(value, str):
        return VALUE_NAMES.get(value, value.replace("_", " "))
    return json.dumps(value)


def cell_caption(cell):
    """What distinguishes a sweep cell, in words ('LiDAR, maximum range 5 m')."""
    axes = cell.get("axes") or {}
    parts = []
    for key, value in axes.items():
        name, unit = quantity_name(key)
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            parts.append("%s %s" % (name, value_text(value, unit)))
        else:
            parts.append(value_text(value, unit))
    return ", ".join(parts)


def threshold_text(name):
    """'recall_0p5m' style keys -> '0.5 m'."""
    return name.replace("p", ".").replace("m", " m")


def _style(style):
    scale = 2.0 if style == "screen" else 1.0
    plt.rcParams.update({
        "font.family": "DejaVu Sans",
        "font.size": 8 * scale,
        "axes.titlesize": 8 * scale,
        "axes.labelsize": 8 * scale,
        "xtick.labelsize": 7 * scale,
        "ytick.labelsize": 7 * scale,
        "legend.fontsize": 7 * scale,
        "lines.linewidth": 1.2 * scale,
        "axes.linewidth": 0.6 * scale,
        "grid.linewidth": 0.4 * scale,
        "grid.alpha": 0.5,
        "pdf.fonttype": 42,   # TrueType: the text stays text (searchable, editable)
        "ps.fonttype": 42,
        "svg.fonttype": "none",
        "savefig.bbox": "standard",
    })
    return scale


def _plain_log_ticks(axis):
    """Log-scale ticks as plain numbers (0.01, 0.1, 1, 10): no small superscript exponents."""
    from matplotlib.ticker import FuncFormatter, NullFormatter
    axis.set_major_formatter(FuncFormatter(lambda v, _: ("%g" % v)))
    axis.set_minor_formatter(NullFormatter())


def _figure(scale, aspect=0.72, layout=None):
    w = COLUMN_WIDTH_IN * scale
    return plt.figure(figsize=(w, w * aspect), layout=layout)


COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf"]


def _colour(i):
    return COLOURS[i % len(COLOURS)]


class Run:
    """A finished run directory: its summary, scenario and units."""

    def __init__(self, root):
        self.root = root
        summary_path = os.path.join(root, "summary.json")
        if not os.path.isfile(summary_path):
            raise ValueError("%s: no summary.json: not a finished run (run it to completion, or merge its shards)" % root)
        with open(summary_path) as f:
            self.summary = json.load(f)
        self.config = {}
        config_path = os.path.join(root, "resolved_config.json")
        if os.path.isfile(config_path):
            with open(config_path) as f:
                self.config = json.load(f)
        self.units = []
        for path in sorted(glob.glob(os.path.join(root, "units", "**", "*.json"), recursive=True)):
            with open(path) as f:
                self.units.append(json.load(f))
        self.matchers = list(self.summary.get("matchers", []))
        self.cells = self.summary.get("cells", [])
        self.name = self.summary.get("scenario", os.path.basename(os.path.normpath(root)))
        self.description = self.config.get("description", "")
        self.buildings = [b.get("label", "") for b in self.config.get("buildings", [])]

    def units_of(self, cell_index):
        return [u for u in self.units if u.get("cell") == cell_index]

    def errors(self, cell_index, label):
        """Position errors of one matcher in one cell (inf = no pose or failed observation)."""
        out = []
        for u in self.units_of(cell_index):
            e = math.inf
            for o in u.get("outcomes", []):
                if o.get("label") == label and o.get("ok", True) and u.get("observation_ok", True):
                    e = o["estimate"]["position_error_m"]
            out.append(e)
        return np.array(out, dtype=float)

    def plan(self, label):
        """The plan the run used for a building (plans/<label>.json), or None."""
        path = os.path.join(self.root, "plans", label + ".json")
        if not os.path.isfile(path):
            for b in self.config.get("buildings", []):
                if b.get("label") == label and b.get("file") and os.path.isfile(b["file"]):
                    path = b["file"]
                    break
            else:
                return None
        with open(path) as f:
            return json.load(f)


# ---------------------------------------------------------------------------------------------
# Single-shot figures

def error_cdf(run, cell, scale):
    """Share of observations within an error, to the largest finite error (log x)."""
    fig = _figure(scale)
    ax = fig.add_subplot(111)
    largest = 0.0
    n_total = 0
    for i, label in enumerate(run.matchers):
        e = run.errors(cell["_index"], label)
        n_total = max(n_total, len(e))
        finite = np.sort(e[np.isfinite(e)])
        if len(e) == 0:
            continue
        failed = len(e) - len(finite)
        if len(finite):
            largest = max(largest, finite[-1])
            x = np.concatenate([[max(finite[0], 1e-3)], finite])
            y = np.concatenate([[0.0], np.arange(1, len(finite) + 1) / len(e)]) * 100.0
            name = method_name(label) + (" (no pose: %d)" % failed if failed else "")
            ax.step(x, y, where="post", color=_colour(i), label=name)
    ax.set_xscale("log")
    _plain_log_ticks(ax.xaxis)
    lo = 0.01
    ax.set_xlim(lo, max(largest * 1.3, 1.0))
    ax.set_ylim(0, 100)
    for t in (0.5, 1.0, 5.0):
        if t < largest * 1.3:
            ax.axvline(t, color="0.6", linewidth=0.6 * scale, linestyle=":")
    ax.set_xlabel("position error (m, log scale)")
    ax.set_ylabel("observations within (%)")
    title = "Position error, " + (cell_caption(cell) or "all buildings")
    ax.set_title(title + " (n = %d)" % n_total)
    ax.grid(True, which="major")
    ax.legend(loc="upper left", frameon=False)
    fig.tight_layout(pad=0.3)
    return fig


def recall_bars(run, cell, scale):
    """Recall at each threshold per method with its 95% bootstrap interval."""
    groups = cell.get("groups", {}).get("all", {})
    keys = []
    for label in run.matchers:
        for k in groups.get(label, {}):
            if k.startswith("recall_") and k not in keys:
                keys.append(k)
    if not keys:
        return None
    fig = _figure(scale)
    ax = fig.add_subplot(111)
    n = len(run.matchers)
    width = 0.8 / max(n, 1)
    x = np.arange(len(keys))
    for i, label in enumerate(run.matchers):
        g = groups.get(label, {})
        ci = g.get("ci95", {})
        vals = np.array([100.0 * (g.get(k) if g.get(k) is not None else np.nan) for k in keys])
        lo = np.array([100.0 * ci[k][0] if k in ci and ci[k][0] is not None else np.nan for k in keys])
        hi = np.array([100.0 * ci[k][1] if k in ci and ci[k][1] is not None else np.nan for k in keys])
        err = np.vstack([np.clip(vals - lo, 0, None), np.clip(hi - vals, 0, None)])
        ax.bar(x + (i - (n - 1) / 2) * width, vals, width * 0.92, color=_colour(i), label=method_name(label),
               yerr=np.nan_to_num(err), capsize=1.5 * scale, error_kw={"elinewidth": 0.6 * scale})
    names = []
    for k in keys:
        t = k[len("recall_"):]
        if t.endswith("deg"):
            m, d = t.split("_")
            names.append("%s, %s°" % (threshold_text(m), d[:-3]))
        else:
            names.append(threshold_text(t))
    ax.set_xticks(x)
    ax.set_xticklabels(names)
    ax.set_ylim(0, 100)
    ax.set_xlabel("error threshold (position, position and heading)")
    ax.set_ylabel("recall (%), 95% interval")
    ax.set_title("Recall, " + (cell_caption(cell) or "all buildings"))
    ax.grid(True, axis="y")
    ax.legend(loc="upper left", frameon=False)
    fig.tight_layout(pad=0.3)
    return fig


def accuracy_vs_axis(run, scale):
    """Sweeps: recall @1 m 30 deg per cell, with intervals, against the cells' values."""
    if len(run.cells) < 2:
        return None
    keys = [k for k in run.cells[0].get("groups", {}).get("all", {}).get(run.matchers[0], {}) if
            k.startswith("recall_") and k.endswith("deg")]
    if not keys:
        return None
    key = keys[0]
    fig = _figure(scale, aspect=0.8)
    ax = fig.add_subplot(111)
    x = np.arange(len(run.cells))
    for i, label in enumerate(run.matchers):
        vals, lo, hi = [], [], []
        for c in run.cells:
            g = c.get("groups", {}).get("all", {}).get(label, {})
            v = g.get(key)
            ci = g.get("ci95", {}).get(key, [None, None])
            vals.append(100.0 * v if v is not None else np.nan)
            lo.append(100.0 * ci[0] if ci[0] is not None else np.nan)
            hi.append(100.0 * ci[1] if ci[1] is not None else np.nan)
        vals, lo, hi = map(np.array, (vals, lo, hi))
        ax.fill_between(x, lo, hi, color=_colour(i), alpha=0.18, linewidth=0)
        ax.plot(x, vals, marker="o", markersize=3 * scale, color=_colour(i), label=method_name(label))
    # The axis: the cells' values in words (one line per swept quantity that varies).
    labels = [cell_caption(c) for c in run.cells]
    ax.set_xticks(x)
    ax.set_xticklabels([l.replace(", ", "\n") for l in labels], rotation=0)
    m, d = key[len("recall_"):].split("_")
    swept = []
    for k in (run.cells[0].get("axes") or {}):
        name, unit = quantity_name(k)
        swept.append(name + (" (%s)" % unit if unit else ""))
    ax.set_xlabel(", ".join(swept))
    ax.set_ylabel("recall @%s, %s° (%%), 95%% interval" % (threshold_text(m), d[:-3]))
    ax.set_ylim(0, 100)
    ax.set_title("Recall vs " + ", ".join(s.split(" (")[0] for s in swept))
    ax.grid(True, axis="y")
    ax.legend(loc="best", frameon=False)
    fig.tight_layout(pad=0.3)
    return fig


# ---------------------------------------------------------------------------------------------
# Sequential figures

def _tracks(run, cell_index):
    """tracker label -> list of (unit, track) of one cell."""
    out = {}
    for u in run.units_of(cell_index):
        for t in u.get("tracks", []):
            out.setdefault(t["label"], []).append((u, t))
    return out


def _wilson(k, n, z=1.96):
    if n == 0:
        return (np.nan, np.nan)
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return (c - h, c + h)


def tracking_error(run, cell, scale):
    tracks = _tracks(run, cell["_index"])
    if not tracks:
        return None
    fig = _figure(scale)
    ax = fig.add_subplot(111)
    top, bottom = 1.0, 0.05
    for i, (label, items) in enumerate(sorted(tracks.items())):
        steps = max(len(t.get("position_error_m", [])) for _, t in items)
        if steps == 0:
            continue
        e = np.full((len(items), steps), np.inf)
        for r, (_, t) in enumerate(items):
            v = [x if x is not None else np.inf for x in t.get("position_error_m", [])]
            e[r, :len(v)] = v
        med = np.median(e, axis=0)
        q25, q75 = np.percentile(e, 25, axis=0), np.percentile(e, 75, axis=0)
        k = np.arange(steps)
        ok = np.isfinite(med)
        ax.fill_between(k[ok], q25[ok], np.where(np.isfinite(q75[ok]), q75[ok], np.nan), color=_colour(i), alpha=0.15,
                        linewidth=0)
        ax.plot(k[ok], med[ok], color=_colour(i), label=method_name(label))
        if ok.any():
            top = max(top, np.nanmax(np.where(np.isfinite(q75), q75, np.nan)))
            positive = q25[np.isfinite(q25) & (q25 > 0)]
            if len(positive):
                bottom = min(bottom, max(1e-3, 0.8 * positive.min()))
    ax.set_yscale("log")
    _plain_log_ticks(ax.yaxis)
    ax.set_ylim(bottom, top * 1.5)
    ax.set_xlabel("step since the first observation")
    ax.set_ylabel("position error (m, log scale)")
    ax.set_title("Tracking error, median and quartiles over %d walks" % len(run.units_of(cell["_index"])))
    ax.grid(True)
    ax.legend(loc="best", frameon=False)
    fig.tight_layout(pad=0.3)
    return fig


def tracking_success(run, cell, scale, within_m=1.0):
    tracks = _tracks(run, cell["_index"])
    if not tracks:
        return None
    fig = _figure(scale)
    ax = fig.add_subplot(111)
    for i, (label, items) in enumerate(sorted(tracks.items())):
        steps = max(len(t.get("position_error_m", [])) for _, t in items)
        if steps == 0:
            continue
        n = len(items)
        inside = np.zeros(steps)
        for _, t in items:
            v = np.array([x if x is not None else np.inf for x in t.get("position_error_m", [])], dtype=float)
            inside[:len(v)] += v <= within_m
        lo, hi = zip(*[_wilson(k, n) for k in inside])
        k = np.arange(steps)
        ax.fill_between(k, 100 * np.array(lo), 100 * np.array(hi), color=_colour(i), alpha=0.15, linewidth=0)
        ax.plot(k, 100.0 * inside / n, color=_colour(i), label=method_name(label))
    ax.set_ylim(0, 100)
    ax.set_xlabel("step since the first observation")
    ax.set_ylabel("walks within %g m (%%), 95%% interval" % within_m)
    ax.set_title("Walks tracked within %g m" % within_m)
    ax.grid(True)
    ax.legend(loc="best", frameon=False)
    fig.tight_layout(pad=0.3)
    return fig


# ---------------------------------------------------------------------------------------------
# Plans, trajectories and heatmaps

def _xy(d, key):
    v = d.get(key)
    if v is None:
        v = d.get(key + "_m")
    return np.array(v, dtype=float)


def draw_plan(ax, plan, scale, colour="black"):
    """The plan as vectors: walls split at their openings (open doors are gaps), glass and windows
    blue, closed doors orange, obstacles grey."""
    openings = {}
    for kind in ("doors", "windows"):
        for d in plan.get(kind, []):
            openings.setdefault(d.get("wall") or d.get("wall_id"), []).append((kind, d))
    solid, glass, closed = [], [], []
    for w in plan.get("walls", []):
        a, b = _xy(w, "a"), _xy(w, "b")
        length = float(np.linalg.norm(b - a))
        if length <= 0:
            continue
        u = (b - a) / length
        spans = []
        for kind, d in openings.get(w.get("id"), []):
            t = float(np.dot(_xy(d, "center") - a, u))
            half = 0.5 * float(d.get("width_m", d.get("width", 0.9)))
            spans.append((max(0.0, t - half), min(length, t + half), kind, bool(d.get("closed", False))))
        spans.sort()
        body = glass if w.get("material") == "glass" else solid
        cursor = 0.0
        for t0, t1, kind, is_closed in spans:
            if t0 > cursor:
                body.append([a + cursor * u, a + t0 * u])
            if kind == "windows":
                glass.append([a + t0 * u, a + t1 * u])
            elif is_closed:
                closed.append([a + t0 * u, a + t1 * u])
            cursor = max(cursor, t1)
        if cursor < length:
            body.append([a + cursor * u, b])
    ax.add_collection(LineCollection(solid, colors=colour, linewidths=0.8 * scale, zorder=3))
    if glass:
        ax.add_collection(LineCollection(glass, colors="#1f77b4", linewidths=0.8 * scale, zorder=3))
    if closed:
        ax.add_collection(LineCollection(closed, colors="#ff7f0e", linewidths=1.0 * scale, zorder=3))
    for o in plan.get("obstacles", []):
        c = _xy(o, "center")
        size = np.array(o.get("size_m", o.get("size", [0.5, 0.5])), dtype=float)
        if o.get("kind") == "pillar":
            ax.add_patch(plt.Circle(c, size[0] / 2, color="0.7", zorder=2, linewidth=0))
        else:
            ax.add_patch(plt.Rectangle(c - size / 2, size[0], size[1], angle=math.degrees(o.get("yaw_rad", 0.0)),
                                       rotation_point="center", color="0.8", zorder=2, linewidth=0))
    pts = np.array([p for s in solid + glass for p in s]) if solid or glass else np.zeros((1, 2))
    ax.set_xlim(pts[:, 0].min() - 1, pts[:, 0].max() + 1)
    ax.set_ylim(pts[:, 1].min() - 1, pts[:, 1].max() + 1)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")


def split_at_jumps(xy, max_step_m):
    """Pieces of a trajectory between jumps (consecutive points farther apart than max_step_m),
    and the jumps themselves: a histogram filter's estimate teleports, it does not walk through
    walls."""
    pieces, jumps = [], []
    start = 0
    for k in range(1, len(xy)):
        if np.linalg.norm(xy[k] - xy[k - 1]) > max_step_m:
            pieces.append((start, k))
            jumps.append((k - 1, k))
            start = k
    pieces.append((start, len(xy)))
    return pieces, jumps


def trajectory(run, unit, track, scale, max_step_m=1.5):
    """One walk: the plan, the true path, the estimate coloured by time, start and end marked,
    jumps drawn as jumps."""
    truth = track.get("truth_xy") or unit.get("walk", {}).get("truth_xy")
    est = track.get("estimate_xy")
    if not truth or not est:
        return None
    building = run.buildings[unit["building"]] if unit.get("building", -1) < len(run.buildings) else ""
    plan = run.plan(building)
    fig = _figure(scale, aspect=0.9, layout="constrained")
    ax = fig.add_subplot(111)
    if plan:
        draw_plan(ax, plan, scale)
    truth = np.array(truth, dtype=float)
    est = np.array(est, dtype=float)
    t = np.array(track.get("t_s") or np.arange(len(est)), dtype=float)
    ax.plot(truth[:, 0], truth[:, 1], color="0.35", linewidth=1.6 * scale, label="true path", zorder=4)
    pieces, jumps = split_at_jumps(est, max_step_m)
    norm = plt.Normalize(t.min() if len(t) else 0, t.max() if len(t) else 1)
    lc = None
    for a, b in pieces:
        if b - a < 2:
            continue
        segs = np.stack([est[a:b - 1], est[a + 1:b]], axis=1)
        lc = LineCollection(segs, cmap="viridis", norm=norm, linewidths=1.2 * scale, zorder=5)
        lc.set_array(t[a + 1:b])
        ax.add_collection(lc)
    for a, b in jumps:
        ax.annotate("", xy=est[b], xytext=est[a], zorder=5,
                    arrowprops={"arrowstyle": "->", "color": "#d62728", "linestyle": (0, (2, 2)),
                                "linewidth": 0.7 * scale, "shrinkA": 0, "shrinkB": 0})
    if jumps:
        ax.plot([], [], color="#d62728", linestyle=(0, (2, 2)), linewidth=0.7 * scale, label="estimate jumps")
    ax.scatter(est[:, 0], est[:, 1], c=t, cmap="viridis", norm=norm, s=2.5 * scale, zorder=6)
    ax.plot(*truth[0], marker="o", color="#2ca02c", markersize=5 * scale, linestyle="none", label="start", zorder=7)
    ax.plot(*truth[-1], marker="s", color="black", markersize=5 * scale, linestyle="none", label="true end", zorder=7)
    ax.plot(*est[-1], marker="X", color="#d62728", markersize=5 * scale, linestyle="none", label="estimated end",
            zorder=7)
    sm = plt.cm.ScalarMappable(cmap="viridis", norm=norm)
    cb = fig.colorbar(sm, ax=ax, fraction=0.04, pad=0.02)
    cb.set_label("time since the first observation (s)")
    err = track.get("position_error_m") or [math.inf]
    end = err[-1] if err[-1] is not None else math.inf
    ax.set_title("%s, %s: end error %s" % (building.replace("_", " "), method_name(track["label"]),
                                          "%.2f m" % end if math.isfinite(end) else "no track"))
    ax.legend(loc="best", frameon=True, framealpha=0.85)
    return fig


def heatmap(run, stem, scale):
    """A kept posterior (heatmaps/<stem>.npy + .json): the raster max over heading, the plan drawn
    over it as vectors, the true pose and the estimate."""
    base = os.path.join(run.root, "heatmaps", stem)
    with open(base + ".json") as f:
        meta = json.load(f)
    post = np.load(base + ".npy").astype(np.float32)
    g = meta["grid"]
    x0, y0, res = g["origin_m"][0], g["origin_m"][1], g["resolution_m"]
    h, w = post.shape
    fig = _figure(scale, aspect=0.85, layout="constrained")
    ax = fig.add_subplot(111)
    shown = np.ma.masked_less_equal(post, 0.0)
    im = ax.imshow(shown, origin="lower", extent=(x0, x0 + w * res, y0, y0 + h * res), cmap="magma_r",
                   interpolation="nearest", zorder=1)
    plan = run.plan(meta.get("building", ""))
    if plan:
        draw_plan(ax, plan, scale)
    ax.set_xlim(x0, x0 + w * res)
    ax.set_ylim(y0, y0 + h * res)
    cb = fig.colorbar(im, ax=ax, fraction=0.04, pad=0.02)
    cb.set_label("score at the best heading")
    tr = meta.get("truth")
    if tr:
        ax.plot(tr["x_m"], tr["y_m"], marker="o", color="#2ca02c", markersize=5 * scale, linestyle="none",
                label="true pose", zorder=6)
        ax.arrow(tr["x_m"], tr["y_m"], 0.8 * math.cos(tr["yaw_rad"]), 0.8 * math.sin(tr["yaw_rad"]), color="#2ca02c",
                 width=0.05 * scale, zorder=6, length_includes_head=True)
    es = meta.get("estimate")
    if es:
        ax.plot(es["x_m"], es["y_m"], marker="X", color="#1f77b4", markersize=5 * scale, linestyle="none",
                label="estimate", zorder=6)
    ax.legend(loc="best", frameon=True, framealpha=0.85)
    err = meta.get("position_error_m")
    ax.set_title("%s, %s: %s" % (meta.get("building", "").replace("_", " "), method_name(meta.get("matcher", "")),
                                 "error %.2f m" % err if err is not None else "no pose"))
    return fig


# ---------------------------------------------------------------------------------------------

def _slug(text):
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in text)


def render_run(run_dir, out_dir=None, fmt="pdf", style="paper", walks=4):
    """Renders every figure of a run into out_dir (default RUN/figures); returns the paths."""
    if fmt not in ("pdf", "svg", "png"):
        raise ValueError("format must be pdf, svg or png, not %r" % fmt)
    run = Run(run_dir)
    out_dir = out_dir or os.path.join(run_dir, "figures")
    os.makedirs(out_dir, exist_ok=True)
    scale = _style(style)
    written = []

    def save(fig, name):
        if fig is None:
            return
        path = os.path.join(out_dir, name + "." + fmt)
        fig.savefig(path, dpi=300 if fmt == "png" else None)
        plt.close(fig)
        written.append(path)

    many = len(run.cells) > 1
    for i, cell in enumerate(run.cells):
        cell["_index"] = i
        suffix = ("_" + cell["id"]) if many else ""
        if any(u.get("outcomes") for u in run.units_of(i)):
            save(error_cdf(run, cell, scale), "error_cdf" + suffix)
            save(recall_bars(run, cell, scale), "recall" + suffix)
        save(tracking_error(run, cell, scale), "tracking_error" + suffix)
        save(tracking_success(run, cell, scale), "tracking_success" + suffix)
        # Per-walk trajectories: the first walks of each building (every tracker).
        shown = {}
        for u in run.units_of(i):
            for t in u.get("tracks", []):
                key = (u["building"], t["label"])
                if shown.get(key, 0) >= walks:
                    continue
                fig = trajectory(run, u, t, scale)
                if fig is not None:
                    shown[key] = shown.get(key, 0) + 1
                    save(fig, "walk_" + _slug(u["id"].replace("/", "_")) + "_" + _slug(t["label"]))
    save(accuracy_vs_axis(run, scale), "accuracy_vs_sweep")
    for meta in sorted(glob.glob(os.path.join(run.root, "heatmaps", "*.json"))):
        stem = os.path.splitext(os.path.basename(meta))[0]
        if os.path.isfile(os.path.join(run.root, "heatmaps", stem + ".npy")):
            save(heatmap(run, stem, scale), "heatmap_" + stem)
    return written


def main(argv=None):
    p = argparse.ArgumentParser(prog="floorcast figures", description=__doc__.split("\n\n")[0])
    p.add_argument("run_dir", metavar="RUN_DIR")
    p.add_argument("-o", "--output", default=None, help="output folder (default RUN_DIR/figures)")
    p.add_argument("--format", default="pdf", choices=["pdf", "svg", "png"])
    p.add_argument("--style", default="paper", choices=["paper", "screen"],
                   help="paper: one 85 mm column, 8 pt text; screen: twice the size")
    p.add_argument("--walks", type=int, default=4, help="trajectory figures per building and tracker")
    a = p.parse_args(argv)
    try:
        paths = render_run(a.run_dir, a.output, a.format, a.style, a.walks)
    except (ValueError, OSError) as e:
        print("floorcast: error: %s" % e, file=sys.stderr)
        return 2
    for path in paths:
        print(path)
    print("figures: %d %s files -> %s" % (len(paths), a.format, a.output or os.path.join(a.run_dir, "figures")))
    return 0


if __name__ == "__main__":
    sys.exit(main())
