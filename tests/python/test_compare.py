# svr.compare is `svr compare`: the same report for the same scene, apart from timings.
import json
import subprocess

import pytest

from conftest import SCENES

ARGS = dict(renderers=["raycast", "shearwarp"], models=["rgb", "factor:4"], width=48, height=48)


def strip_timings(value):
    if isinstance(value, dict):
        # Times, and whether a model came from the disk cache (the first run trained it).
        return {k: strip_timings(v) for k, v in value.items()
                if not (k.endswith(("_ms", "_fps")) or k == "cached")}
    if isinstance(value, list):
        return [strip_timings(v) for v in value]
    return value


def test_compare_equals_the_command(svr_module, svr_bin, tmp_path):
    scene_file = str(SCENES / "engine.json")
    ours = svr_module.compare(svr_module.Scene.load(scene_file), **ARGS)
    subprocess.run([svr_bin, "compare", scene_file, "--out", str(tmp_path), "--renderers",
                    "raycast", "shearwarp", "--models", "rgb", "factor:4", "--width", "48",
                    "--height", "48", "--quiet"], check=True)
    theirs = json.loads((tmp_path / "report.json").read_text())
    assert [r["renderer"] + " " + r["model"] for r in ours["runs"]] == \
        ["raycast rgb", "raycast factor:4", "shearwarp rgb", "shearwarp factor:4"]
    assert strip_timings(ours) == strip_timings(theirs)


def test_compare_keeps_its_folder_when_asked(svr_module, tmp_path):
    report = svr_module.compare(svr_module.Scene.load(str(SCENES / "engine.json")),
                                renderers=["raycast"], models=["rgb"], width=32, height=32,
                                out=str(tmp_path))
    assert (tmp_path / "report.json").exists() and report["runs"][0]["model"] == "rgb"
