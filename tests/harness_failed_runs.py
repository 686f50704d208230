#!/usr/bin/env python3
"""The harness keeps what worked (issue 49): a run that fails at render time (here splats
post-classifying a label map, which only a scalar volume allows) is recorded with its error in
report.json, the report page and sweep.json; the runs that worked are measured and reported
beside it; and the exit status is 2, as for any other error.

Usage: harness_failed_runs.py SVR_BINARY SCENE OUT_FOLDER
"""
import json
import math
import os
import shutil
import subprocess
import sys

EXPECTED = "splat.classification=post needs a scalar volume: a label map is classified at its voxels"


def run(*args):
    done = subprocess.run(list(args), capture_output=True, text=True)
    return done.returncode, done.stdout + done.stderr


def check_compare(svr, scene, out):
    status, text = run(svr, "compare", scene, "--renderers", "raycast,splat", "--models",
                       "rgb,factor:4", "--width", "24", "--height", "24", "--out", out, "-q")
    assert status == 2, (status, text)
    assert text.count(f"failed: {EXPECTED}") == 2, text
    with open(os.path.join(out, "report.json")) as f:
        report = json.load(f)
    assert not report["pass"], report["pass"]
    assert [r["label"] for r in report["runs"]] == ["raycast rgb", "raycast factor:4"], report["runs"]
    for r in report["runs"]:
        assert all(math.isfinite(l["de_mean"]) and l["pass"] for l in r["lights"]), r
    failed = report["failed"]
    assert [(f["renderer"], f["model_asked"], f["error"]) for f in failed] == \
        [("splat", "rgb", EXPECTED), ("splat", "factor:4", EXPECTED)], failed
    with open(os.path.join(out, "report.html")) as f:
        page = f.read()
    assert page.count("needs a scalar volume") == 2, "the report page names each failed run"


def check_sweep(svr, scene, out):
    status, text = run(svr, "sweep", scene, "--param", "azimuth=0:10:10", "--renderers",
                       "raycast,splat", "--model", "rgb", "--size", "24", "--out", out, "-q")
    assert status == 2, (status, text)
    assert "svr: error: splat at azimuth = 10 failed: " + EXPECTED in text, text
    with open(os.path.join(out, "sweep.json")) as f:
        sweep = json.load(f)
    raycast, splat = sweep["renderers"]
    assert all(v is not None and math.isfinite(v) for v in raycast["de_mean"] + raycast["ms"]), raycast
    assert raycast["errors"] == ["", ""], raycast
    assert splat["de_mean"] == [None, None] and splat["ms"] == [None, None], splat
    assert splat["errors"] == [EXPECTED, EXPECTED], splat
    assert splat["flags"] == [f"failed at {v}: {EXPECTED}" for v in (0, 10)], splat["flags"]
    assert os.path.exists(os.path.join(out, "sweep_azimuth.png"))


def main():
    svr, scene, out = sys.argv[1:4]
    shutil.rmtree(out, ignore_errors=True)
    check_compare(svr, scene, os.path.join(out, "compare"))
    check_sweep(svr, scene, os.path.join(out, "sweep"))
    print("failed runs recorded, the others reported, exit 2")


if __name__ == "__main__":
    main()
