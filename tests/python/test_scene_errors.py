# Scenes from files and dicts get svr's own checks and messages: file, key and value.
import json
import subprocess

import pytest

from conftest import SCENES, small_scene


def test_missing_file(svr_module):
    with pytest.raises(svr_module.Error, match="no_such_scene.json"):
        svr_module.Scene.load("no_such_scene.json")


def test_dict_with_a_bad_key_names_it(svr_module):
    scene = small_scene("nucleon_41x41x41_uint8.nhdr", {"type": "scalar", "points": [[10, "soft"]]})
    scene["camera"] = {"azimuth": "east"}
    with pytest.raises(svr_module.Error, match=r"camera\.azimuth: expected a number, got \"east\""):
        svr_module.Scene.from_dict(scene)
    del scene["camera"]
    scene["colour"] = 1
    with pytest.raises(svr_module.Error, match="colour"):
        svr_module.Scene.from_dict(scene)


def test_same_message_as_the_command_line(svr_module, svr_bin, tmp_path):
    scene = json.loads((SCENES / "engine.json").read_text())
    scene["volume"] = {"file": str(SCENES.parent / "volumes/engine_256x256x128_uint8.nhdr")}
    scene["image"] = {"width": 0, "height": 64}
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(scene))
    cli = subprocess.run([svr_bin, "render", str(path), "--out", str(tmp_path / "out")],
                         capture_output=True, text=True)
    assert cli.returncode != 0
    with pytest.raises(svr_module.Error) as raised:
        svr_module.Scene.load(str(path))
    assert str(raised.value) in cli.stderr


def test_unknown_backend_and_model(svr_module):
    scene = svr_module.Scene.load(str(SCENES / "engine.json"))
    with pytest.raises(svr_module.Error, match="raytrace"):
        scene.render(renderer="raytrace", width=16, height=16)
    with pytest.raises(svr_module.Error, match="factor:99|99"):
        scene.render(model="factor:99", width=16, height=16)
    with pytest.raises(svr_module.Error, match="negative"):
        scene.render(width=-4, height=16)
