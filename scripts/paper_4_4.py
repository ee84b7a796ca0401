#!/usr/bin/env python3
"""Runs the PALMS+ sec. 4.4 ingredient study (issue 20; results/paper_4_4.md).

scenarios/paper_4_4.yaml (one matcher label per paper-faithful ingredient) and
scenarios/paper_4_4_protocol.yaml (where the 10 m range applies; its cells 1 and 2 as runs of their
own, paired with the ingredient run's points by `floorcast compare-runs`) and
scenarios/paper_4_4_combinations.yaml (F3Loc's code with the strongest ingredients) on the calibrated generated
buildings as written, and on the real development plans (imported by scripts/import_realplans.sh)
with the same matchers; plus the transitional-space definitions (transitional with 0.5 m and
1.0 m clearance, uniform) on the protocol's matchers. Every run is an ordinary run directory
(resumable: run the same command again). Two large real levels are run, one per directory (one
of them alone holds ~5 GB of matcher precomputation); paper_4_4_report.py pools them.

Usage: scripts/paper_4_4.py --plans out/realplans [--out out/paper_4_4] [--bin build/bin/floorcast]
       [--jobs N] [--only generated,real_small,real_large,protocol,regions,combinations]
The parts run in the order --only names them; OUT/commit.txt records the source commit of each run.
"""
import argparse
import copy
import os
import subprocess
import sys
import time

import yaml

REAL_SMALL = ["tum_studitum_L1", "tum_studitum_L2", "rwth_plt_L0", "rwth_plt_L1", "spbstu_no3_L2", "spbstu_no3_L4"]
# Two of the six large levels (one of each building): each costs ~5 GB and several CPU minutes of
# precomputation alone.
REAL_LARGE = ["spbstu_main_L1", "grenoble_mall_L0"]
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def with_buildings(text, files, count=None, sampling=None):
    """The scenario text with its buildings (and optionally its point count or its whole sampling
    block) replaced; the description says which buildings."""
    scenario = yaml.safe_load(text)
    scenario["buildings"] = list(files)
    if sampling is not None:
        scenario["sampling"] = sampling
    elif count is not None:
        scenario["sampling"]["count"] = count
    names = ", ".join(os.path.splitext(os.path.basename(f))[0] for f in files)
    scenario["description"] = scenario["description"].split(", on the calibrated")[0].rstrip(".") + "; on " + names + "."
    return yaml.safe_dump(scenario, sort_keys=False, width=1000)


def source_commit():
    """HEAD of the source tree, with "-dirty" when it has uncommitted changes to tracked files."""
    head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True).stdout.strip()
    dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=ROOT, capture_output=True,
                           text=True).stdout.strip()
    return (head or "unknown") + ("-dirty" if dirty else "")


def sweep_cells(text):
    """The scenario's sweep cells as single-cell scenario texts (cell k: the k-th value of every
    swept key applied, no sweep). Each runs as a run of its own, so its units keep the ids of the
    ingredient run's units and `floorcast compare-runs` pairs them point by point."""
    scenario = yaml.safe_load(text)
    sweep = scenario.pop("sweep")
    if len(sweep) != 1:
        sys.exit("sweep_cells: one sweep axis expected, %d found" % len(sweep))
    axis = sweep[0]
    n = len(next(iter(axis.values())))
    cells = []
    for k in range(n):
        s = copy.deepcopy(scenario)
        for key, values in axis.items():
            node = s
            parts = key.split(".")
            for part in parts[:-1]:
                node = node[part]
            node[parts[-1]] = values[k]
        cells.append(yaml.safe_dump(s, sort_keys=False, width=1000))
    return cells


def run(binary, yaml_text, name, out, jobs):
    path = os.path.join(out, "scenarios", name + ".yaml")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(yaml_text)
    d = os.path.join(out, name)
    if os.path.exists(os.path.join(d, "summary.json")):
        print("%s: done already" % name, flush=True)
        return
    t0 = time.time()
    commit = source_commit()  # the source the binary is expected to match, taken as the run starts
    cmd = [binary, "run", path, "-o", d, "--quiet"]
    if jobs:
        cmd += ["--jobs", str(jobs)]
    r = subprocess.run(cmd, cwd=ROOT)
    if r.returncode != 0:
        sys.exit("%s: floorcast run failed (%d)" % (name, r.returncode))
    with open(os.path.join(out, "commit.txt"), "a") as f:
        f.write("%s %s\n" % (name, commit))
    print("%s: %.0f s" % (name, time.time() - t0), flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--plans", required=True, help="folder of the imported real plans (scripts/import_realplans.sh)")
    ap.add_argument("--out", default="out/paper_4_4")
    ap.add_argument("--bin", default="build/bin/floorcast")
    ap.add_argument("--points", type=int, default=20, help="observation points per real level (default 20)")
    ap.add_argument("--large", default=",".join(REAL_LARGE), help="large real levels to run (default: %(default)s)")
    ap.add_argument("--jobs", type=int, default=0, help="concurrent work units per run (default: all cores)")
    ap.add_argument("--only", default="generated,real_small,real_large,protocol,regions,combinations",
                    help="parts to run, in this order")
    a = ap.parse_args()
    binary = os.path.abspath(a.bin)
    out = os.path.abspath(a.out)
    plans = os.path.abspath(a.plans)
    only = a.only.split(",")
    ingredients = open(os.path.join(ROOT, "scenarios", "paper_4_4.yaml")).read()
    protocol = open(os.path.join(ROOT, "scenarios", "paper_4_4_protocol.yaml")).read()
    combinations = open(os.path.join(ROOT, "scenarios", "paper_4_4_combinations.yaml")).read()
    small = [os.path.join(plans, p + ".json") for p in REAL_SMALL]
    large = [p for p in a.large.split(",") if p]
    for f in small + [os.path.join(plans, p + ".json") for p in large]:
        if not os.path.exists(f):
            sys.exit("missing %s: import the real plans first (scripts/import_realplans.sh)" % f)
    generated = ["floorplans/buildings/office_calibrated.json", "floorplans/buildings/angled_calibrated.json",
                 "floorplans/buildings/campus_calibrated.json"]

    def protocol_cells():
        # Cell 0 (10 m on both sides) is the ingredient run's defaults: only cells 1 and 2 run.
        for k, name in ((1, "obs_only"), (2, "f3loc_eval")):
            cell = sweep_cells(protocol)[k]
            run(binary, cell, "generated_protocol_" + name, out, a.jobs)
            run(binary, with_buildings(cell, small, count=a.points), "real_small_protocol_" + name, out, a.jobs)

    def regions():
        base = sweep_cells(protocol)[0]
        for name, sampling in [("clear1", {"count": 30, "seed": 1, "clearance_m": 1.0}),
                               ("uniform", {"count": 30, "seed": 1, "clearance_m": 0.5, "region": "uniform"})]:
            run(binary, with_buildings(base, generated, sampling=sampling), "generated_region_" + name, out, a.jobs)
            run(binary, with_buildings(base, small, sampling=dict(sampling, count=a.points)),
                "real_small_region_" + name, out, a.jobs)

    parts = {
        "generated": lambda: run(binary, ingredients, "generated", out, a.jobs),
        "real_small": lambda: run(binary, with_buildings(ingredients, small, count=a.points), "real_small", out, a.jobs),
        "real_large": lambda: [run(binary, with_buildings(ingredients, [os.path.join(plans, p + ".json")], count=a.points),
                                   "real_large_" + p, out, a.jobs) for p in large],
        "protocol": protocol_cells,
        "regions": regions,
        "combinations": lambda: (run(binary, combinations, "generated_combinations", out, a.jobs),
                                 run(binary, with_buildings(combinations, small, count=a.points),
                                     "real_small_combinations", out, a.jobs)),
    }
    for part in only:
        if part not in parts:
            sys.exit("--only: unknown part %r (known: %s)" % (part, ", ".join(parts)))
        parts[part]()


if __name__ == "__main__":
    main()
