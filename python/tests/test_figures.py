"""`floorcast figures` and floorcast.figures: figures a paper can print, checked as a reader sees them.

A single-shot run (two buildings, kept heatmaps) and a sequential run (walks, three trackers) are
made with the CLI; every figure is rendered as PDF and then (poppler) rasterised at 300 dpi and
read back as words with their boxes: the page is one 85 mm column, no text is smaller than 6.5 pt,
titles and axes are words (no internal ids), intervals and the full error range are drawn.
"""
import json
import math
import os
import re
import shutil
import subprocess

import numpy as np
import pytest

OUT = os.environ.get("FLOORCAST_TEST_OUT", "/tmp/floorcast_pytest")
CLI = os.environ.get("FLOORCAST_CLI", "")
HERE = os.path.dirname(os.path.abspath(__file__))

from floorcast import figures  # noqa: E402

COLUMN_PT = 85.0 / 25.4 * 72.0


def data_dir():
    import floorcast
    return floorcast.data_dir()


def cli(*args):
    if not CLI:
        pytest.fail("FLOORCAST_CLI is not set (ctest sets it)")
    return subprocess.run([CLI, *args], check=True, capture_output=True, text=True)


def run_in_own_folder(name, yaml_text):
    """Runs a scenario (BUILDINGS in its text: the shipped buildings folder) into OUT/name/run."""
    root = os.path.join(OUT, name)
    shutil.rmtree(root, ignore_errors=True)
    os.makedirs(root)
    path = os.path.join(root, "scenario.yaml")
    with open(path, "w") as f:
        f.write(yaml_text.replace("BUILDINGS", os.path.join(data_dir(), "floorplans", "buildings")))
    run = os.path.join(root, "run")
    cli("run", path, "-o", run, "--quiet")
    return run


@pytest.fixture(scope="module")
def single_run():
    return run_in_own_folder("figures_single",
                             "name: figures-single\n"
                             "description: kernel and ray matchers on two shipped buildings\n"
                             "buildings: [BUILDINGS/two_rooms.json, BUILDINGS/apartment.json]\n"
                             "sampling: {count: 8, seed: 3, clearance_m: 0.5}\n"
                             "matchers: {kernel: {matcher: kernel}, ray: {matcher: ray}}\n"
                             "output: {heatmaps: 1}\n")


@pytest.fixture(scope="module")
def sequential_run():
    return run_in_own_folder("figures_sequential",
                             "name: figures-sequential\n"
                             "buildings: [BUILDINGS/apartment.json]\n"
                             "sampling: {count: 2, seed: 41, clearance_m: 0.5, region: uniform}\n"
                             "observation: {source: perfect, seed: 3}\n"
                             "matchers: {kernel: {matcher: kernel}, ray: {matcher: ray}}\n"
                             "walk: {steps: 40, seed: 5}\nodometry: {model: vio, seed: 6}\n"
                             "schedule: {initial: true, every_steps: 10}\n"
                             "trackers: {pf_palms: {tracker: pf, matcher: kernel, init: palms}, hist: {tracker: hist, matcher: ray}}\n"
                             "output: {heatmaps: 0}\n")


def pdf_text(pdf):
    """The PDF's page size (pt) and its texts with their font sizes (pt), as poppler's pdftohtml
    reads them (rotated labels included)."""
    xml = subprocess.run(["pdftohtml", "-xml", "-i", "-stdout", "-zoom", "1", pdf], check=True, capture_output=True,
                         text=True).stdout
    page = re.search(r'<page [^>]*height="([\d.]+)" width="([\d.]+)"', xml)
    sizes = {fid: float(size) for fid, size in re.findall(r'<fontspec id="(\d+)" size="([\d.]+)"', xml)}
    texts = [(sizes[fid], re.sub(r"<[^>]+>", "", t)) for fid, t in re.findall(r'<text [^>]*font="(\d+)"[^>]*>(.*?)</text>', xml)]
    return float(page.group(2)), float(page.group(1)), texts


def check_readable_pdf(pdf, png_dir):
    """One 85 mm column, no text below 7 pt, rasterised at 300 dpi without trouble."""
    width_pt, height_pt, texts = pdf_text(pdf)
    assert abs(width_pt - COLUMN_PT) < 1.5, "%s is %.1f pt wide, not one 85 mm column" % (pdf, width_pt)
    assert texts, pdf + ": no text"
    small = [(t, size) for size, t in texts if size < 7.0]
    assert not small, "%s: text below 7 pt: %s" % (pdf, small[:5])
    stem = os.path.join(png_dir, os.path.splitext(os.path.basename(pdf))[0])
    subprocess.run(["pdftoppm", "-r", "300", "-png", "-singlefile", pdf, stem], check=True)
    import matplotlib.image as mpimg
    img = mpimg.imread(stem + ".png")
    assert abs(img.shape[1] - 85.0 / 25.4 * 300) < 4, img.shape  # 1004 px at 300 dpi
    ink = (img[..., :3].mean(axis=2) < 0.5).mean()
    assert 0.002 < ink < 0.6, "%s: %.3f of the page is dark" % (pdf, ink)
    return " | ".join(t for _, t in texts)


def test_single_shot_figures_read_at_column_width(single_run):
    out = os.path.join(single_run, "figures")
    res = cli("figures", single_run, "--format", "pdf")
    assert "figures:" in res.stdout
    pdfs = sorted(p for p in os.listdir(out) if p.endswith(".pdf"))
    assert "error_cdf.pdf" in pdfs and "recall.pdf" in pdfs
    assert any(p.startswith("heatmap_") for p in pdfs)
    png_dir = os.path.join(os.path.dirname(single_run), "png300")
    os.makedirs(png_dir, exist_ok=True)
    for p in pdfs:
        text = check_readable_pdf(os.path.join(out, p), png_dir)
        assert "c000" not in text, p + ": an internal cell id in the text"
        if p == "error_cdf.pdf":
            assert "Position error" in text and "position error (m" in text and "observations within (%)" in text
            assert "PALMS kernel" in text and "F3Loc ray (36)" in text
        if p == "recall.pdf":
            assert "recall (%), 95% interval" in text
        if p.startswith("heatmap_"):
            assert "x (m)" in text and "y (m)" in text and "true pose" in text


def test_cdf_reaches_the_largest_error_and_intervals_are_drawn(single_run):
    figures._style("paper")
    run = figures.Run(single_run)
    cell = dict(run.cells[0], _index=0)
    fig = figures.error_cdf(run, cell, 1.0)
    ax = fig.axes[0]
    largest = max(np.max(run.errors(0, m)[np.isfinite(run.errors(0, m))]) for m in run.matchers)
    assert ax.get_xlim()[1] >= largest
    for line in ax.get_lines()[: len(run.matchers)]:
        x = line.get_xdata()
        assert x.max() >= 0.999 * min(largest, x.max())
    fig = figures.recall_bars(run, cell, 1.0)
    # Error bars: one whisker collection per method.
    assert len([c for c in fig.axes[0].containers if hasattr(c, "errorbar") and c.errorbar is not None]) == len(run.matchers)


def test_svg_keeps_text_as_text(single_run):
    out = os.path.join(os.path.dirname(single_run), "svg")
    cli("figures", single_run, "--format", "svg", "-o", out)
    svg = open(os.path.join(out, "error_cdf.svg")).read()
    assert "<text" in svg and "position error (m" in svg


def test_sequential_figures_trajectories_and_jumps(sequential_run):
    out = os.path.join(sequential_run, "figures")
    cli("figures", sequential_run, "--format", "pdf")
    pdfs = sorted(p for p in os.listdir(out) if p.endswith(".pdf"))
    assert "tracking_error.pdf" in pdfs and "tracking_success.pdf" in pdfs
    walks = [p for p in pdfs if p.startswith("walk_")]
    assert len(walks) == 4, pdfs  # 2 walks x 2 trackers
    png_dir = os.path.join(os.path.dirname(sequential_run), "png300")
    os.makedirs(png_dir, exist_ok=True)
    for p in pdfs:
        text = check_readable_pdf(os.path.join(out, p), png_dir)
        if p.startswith("walk_"):
            for word in ("start", "true end", "estimated end", "time since the first observation (s)"):
                assert word in text, (p, word)
        if p == "tracking_success.pdf":
            assert "walks within 1 m (%), 95% interval" in text
    # The HTML report draws the same walks (one figure per walk and tracker).
    html_path = os.path.join(os.path.dirname(sequential_run), "report.html")
    cli("report", sequential_run, "-o", html_path)
    html = open(html_path).read()
    walks_section = html[html.index('<section id="walks">'):]
    walks_section = walks_section[:walks_section.index("</section>")]
    assert walks_section.count("<img") == 4 and "end error" in walks_section
    # Units carry what the trajectories need.
    unit = json.load(open(os.path.join(sequential_run, "units", "c000", "apartment", "0000.json")))
    assert len(unit["walk"]["truth_xy"]) == 40  # walk steps: 40 samples
    assert len(unit["tracks"][0]["estimate_xy"]) == len(unit["tracks"][0]["position_error_m"])


def test_jumps_are_split_not_drawn_through_walls():
    xy = np.array([[0, 0], [0.5, 0], [1.0, 0], [9.0, 4.0], [9.4, 4.0]], dtype=float)
    pieces, jumps = figures.split_at_jumps(xy, 1.5)
    assert pieces == [(0, 3), (3, 5)] and jumps == [(2, 3)]
    pieces, jumps = figures.split_at_jumps(xy[:3], 1.5)
    assert pieces == [(0, 3)] and jumps == []


def test_human_labels_for_sweep_keys():
    assert figures.quantity_name("observation.sensor_params.sensor.max_range_m") == ("maximum range", "m")
    assert figures.quantity_name("observation.sensor_params.sensor.mono.scale_sigma_ln")[0].startswith("per-view scale")
    assert figures.cell_caption({"axes": {"observation.sensor_params.sensor.mono.model": "depth_pro",
                                          "observation.sensor_params.sensor.max_range_m": 5}}) == \
        "Depth Pro, maximum range 5 m"
    assert figures.method_name("ray180") == "F3Loc ray (180)"


def test_not_a_run_is_a_usage_error(tmp_path):
    res = subprocess.run([CLI, "figures", str(tmp_path)], capture_output=True, text=True)
    assert res.returncode == 2 and "not a finished run" in res.stderr
