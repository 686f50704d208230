# Renders from Python equal `svr render`'s: the relit PNGs pixel for pixel, and save() writes the
# same files; every way of naming a light gives the same light.
import json
import subprocess

import numpy as np
import pytest
from PIL import Image as PilImage

from conftest import SCENES

SIZE = 64


@pytest.fixture(scope="module")
def engine(svr_module):
    return svr_module.Scene.load(str(SCENES / "engine.json"))


@pytest.fixture(scope="module")
def image(engine):
    return engine.render(width=SIZE, height=SIZE)


@pytest.fixture(scope="module")
def cli_render(svr_bin, tmp_path_factory):
    out = tmp_path_factory.mktemp("cli")
    subprocess.run([svr_bin, "render", str(SCENES / "engine.json"), "--out", str(out),
                    "--width", str(SIZE), "--height", str(SIZE), "--quiet"], check=True)
    return out


def png(path):
    return np.asarray(PilImage.open(path).convert("RGB"))


def test_relight_equals_svr_render_pngs(image, cli_render):
    report = json.loads((cli_render / "render.json").read_text())
    assert [i["light"] for i in report["images"]] == image.lights == ["F11", "D65", "half_and_half"]
    for entry in report["images"]:
        assert np.array_equal(image.relight(entry["light"]), png(cli_render / entry["file"])), entry


def test_save_writes_what_svr_render_writes(image, cli_render, tmp_path):
    image.save(str(tmp_path))
    for name in ["F11.png", "D65.png", "mix_half_and_half.png", "light_independent.model.json"]:
        assert (tmp_path / name).read_bytes() == (cli_render / name).read_bytes(), name
    ours = json.loads((tmp_path / "render.json").read_text())
    theirs = json.loads((cli_render / "render.json").read_text())
    for key in ["renderer", "model", "k", "t_channels", "width", "height", "step_world", "images"]:
        assert ours[key] == theirs[key], key
    # The same model chosen the same way; "cached" says only which of the two renders trained it
    # first on a cold cache.
    def choice(report):
        return {k: v for k, v in report["model_choice"].items() if k != "cached"}
    assert choice(ours) == choice(theirs)


def test_image_views_and_model(image):
    S, T = image.S, image.T
    assert S.shape == (SIZE, SIZE, 6) and S.dtype == np.float32
    assert T.shape == (SIZE, SIZE, 1) and not S.flags.writeable and not T.flags.writeable
    assert np.isfinite(S).all() and ((T >= 0) & (T <= 1)).all()
    with pytest.raises(ValueError):
        S[0, 0, 0] = 1.0
    model = image.model
    assert model["model"] == "factor:6" and model["k"] == 6 and model["asked"] == "factor:6"
    assert model["light_matrix"] == "full"
    assert image.renderer == "raycast" and (image.width, image.height) == (SIZE, SIZE)
    t = image.timings
    assert set(t) == {"setup_ms", "model_ms", "classify_ms", "render_ms"}
    assert t["setup_ms"] >= t["model_ms"] + t["classify_ms"] and t["render_ms"] > 0


def test_views_outlive_the_image(engine):
    S = engine.render(width=16, height=16).S  # the Image object is gone; the view keeps it
    assert S.shape == (16, 16, 6) and np.isfinite(S).all()


def test_every_way_of_naming_a_light(svr_module, image):
    by_name = image.relight("D65")
    assert np.array_equal(image.relight({"D65": 1.0}), by_name)
    assert np.array_equal(image.relight(svr_module.library.spectrum("D65")), by_name)
    assert np.array_equal(image.relight(list(svr_module.library.spectrum("D65") * 3.0)), by_name)
    mix = image.relight({"F11": 0.5, "D65": 0.5})
    assert np.array_equal(mix, image.relight("half_and_half"))


def test_linear_relight_and_out(image):
    linear = image.relight("F11", linear=True)
    assert linear.shape == (SIZE, SIZE, 3) and linear.dtype == np.float32
    assert np.isfinite(linear).all() and linear.max() > 0
    out = np.empty((SIZE, SIZE, 3), np.uint8)
    result = image.relight("F11", out=out)
    assert result is out or np.shares_memory(result, out)
    assert np.array_equal(out, image.relight("F11"))
    with pytest.raises(ValueError, match="out must be a writeable C-contiguous uint8"):
        image.relight("F11", out=np.empty((SIZE, SIZE, 3), np.float32))


def test_bad_lights(svr_module, image):
    with pytest.raises(svr_module.Error, match="unknown spectrum 'D66'|D66"):
        image.relight("D66")
    with pytest.raises(ValueError, match="81 values"):
        image.relight(np.ones(40))
    with pytest.raises(ValueError, match="finite and ≥ 0"):
        image.relight(np.full(81, np.nan))
    with pytest.raises(svr_module.Error, match="weight -1"):
        image.relight({"D65": -1.0})


def test_repr_png_shows_the_first_light(image):
    import io
    data = image._repr_png_()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert np.array_equal(np.asarray(PilImage.open(io.BytesIO(data)).convert("RGB")),
                          image.relight("F11"))


def test_progress_is_called_and_rises(engine):
    seen = []
    engine.render(width=SIZE, height=SIZE, progress=seen.append)
    assert seen and seen[-1] == 1.0 and seen == sorted(seen)


def test_progress_exception_stops_the_render(engine):
    class Stop(Exception):
        pass

    def stop(fraction):
        raise Stop()

    with pytest.raises(Stop):
        engine.render(width=256, height=256, progress=stop)


def test_backends_models_and_options(svr_module, engine):
    names = [b["name"] for b in svr_module.backends()]
    assert names[:3] == ["raycast", "shearwarp", "splat"]
    splat = next(b for b in svr_module.backends() if b["name"] == "splat")
    assert any(o["key"] == "mode" and o["kind"] == "choice" for o in splat["options"])
    for renderer in ["raycast", "shearwarp", "splat"]:
        for model in ["rgb", "factor:6", "spectral:31"]:
            im = engine.render(renderer=renderer, model=model, width=32, height=32)
            assert im.S.shape[2] == {"rgb": 3, "factor:6": 6, "spectral:31": 31}[model]
            assert im.relight("D65").shape == (32, 32, 3)
    direct = engine.render(renderer="splat", width=32, height=32, options={"splat.mode": "direct"})
    nested = engine.render(renderer="splat", width=32, height=32, options={"splat": {"mode": "direct"}})
    assert np.array_equal(direct.S, nested.S)
    with pytest.raises(svr_module.Error, match="mode"):
        engine.render(renderer="splat", width=32, height=32, options={"splat.mode": "wobbly"})


def test_library(svr_module):
    nm = svr_module.library.wavelengths()
    assert nm[0] == 380 and nm[-1] == 780 and len(nm) == 81
    lights = svr_module.library.names("light")
    assert {"D65", "A", "F11"} <= set(lights)
    assert "D65" not in svr_module.library.names("reflectance")
    d65 = svr_module.library.spectrum("D65")
    assert d65.shape == (81,) and abs(d65[36] - 100.0) < 0.5  # D65 is 100 at 560 nm
    with pytest.raises(ValueError, match="kind 'lamp'"):
        svr_module.library.names("lamp")
