# Volumes from numpy render exactly as the same voxels read from a file, in every accepted dtype
# and layout; every bad array is a ValueError, never a crash.
import numpy as np
import pytest

from conftest import SCENES, read_nrrd_voxels, small_scene

SCALAR_TF = {"type": "scalar", "points": [[0.2, "soft"], [0.6, "hard"]],
             "opacity": [[0.0, 0.0], [0.15, 0.0], [0.3, 1.0]]}


def same_render(a, b):
    assert a.S.shape == b.S.shape and a.T.shape == b.T.shape
    assert np.array_equal(a.S, b.S) and np.array_equal(a.T, b.T)


@pytest.mark.parametrize("layout", ["C zyx", "Fortran xyz", "C xyz (transposed copy)"])
def test_engine_from_numpy_is_byte_identical_to_the_file(svr_module, layout):
    scene = svr_module.Scene.load(str(SCENES / "engine.json"))
    zyx, spacing = read_nrrd_voxels("engine_256x256x128_uint8.nhdr")
    if layout == "C zyx":
        volume = svr_module.Volume.from_numpy(zyx, spacing, axes="zyx")
    elif layout == "Fortran xyz":
        xyz = zyx.T  # a view: Fortran-contiguous, a[x, y, z]
        assert xyz.flags.f_contiguous
        volume = svr_module.Volume.from_numpy(xyz, spacing)
    else:
        xyz = np.ascontiguousarray(zyx.T)
        volume = svr_module.Volume.from_numpy(xyz, spacing)
    assert volume.dims == (256, 256, 128) and volume.dtype == "uint8"
    from_file = scene.render(width=64, height=64)
    from_numpy = scene.with_volume(volume).render(width=64, height=64)
    same_render(from_file, from_numpy)
    assert np.array_equal(from_file.relight("D65"), from_numpy.relight("D65"))


@pytest.mark.parametrize("file,tf_points", [
    ("headsq_64x64x93_int16.nhdr", [[400, "soft"], [1400, "hard"]]),
    ("cthead_256x256x113_uint16be.nhdr", [[600, "soft"], [1600, "hard"]]),
    ("hydrogen_orbital_64x64x64_float32.nhdr", [[0.05, "soft"], [0.4, "hard"]]),
])
def test_every_dtype_matches_its_file(svr_module, file, tf_points):
    zyx, spacing = read_nrrd_voxels(file)
    lo, hi = float(zyx.min()), float(zyx.max())
    tf = {"type": "scalar", "points": tf_points,
          "opacity": [[lo, 0.0], [lo + 0.1 * (hi - lo), 0.0], [lo + 0.3 * (hi - lo), 1.0]]}
    scene = svr_module.Scene.from_dict(small_scene(file, tf))
    volume = svr_module.Volume.from_numpy(zyx, spacing, axes="zyx")
    assert volume.dtype == {"i2": "int16", "u2": "uint16", "f4": "float32"}[zyx.dtype.str[1:]]
    assert volume.value_range == (lo, hi)
    same_render(scene.render(), scene.with_volume(volume).render())


def test_label_map_from_numpy(svr_module):
    labels = np.zeros((24, 24, 24), np.uint8)
    labels[4:20, 4:20, 4:20] = 1
    labels[9:15, 9:15, 9:15] = 2
    scene = svr_module.Scene.from_dict(small_scene(
        "nucleon_41x41x41_uint8.nhdr", {"type": "labels", "labels": {"1": "soft", "2": "hard"}}))
    image = scene.with_volume(svr_module.Volume.from_numpy(labels)).render()
    rgb = image.relight("D65")
    assert rgb.shape == (48, 48, 3) and rgb.dtype == np.uint8
    # The cube covers the middle of the frame and leaves its corners empty (black backdrop).
    assert rgb[24, 24].sum() > 0 and rgb[0, 0].sum() == 0
    assert float(image.T[0, 0, 0]) == 1.0 and float(image.T[24, 24, 0]) < 0.5


GOOD = np.zeros((8, 8, 8), np.float32)


@pytest.mark.parametrize("array,message", [
    (np.zeros((8, 8, 8), np.float64), "float64.* is not one of"),
    (np.zeros((8, 8, 8), np.int32), "int32.* is not one of"),
    (np.zeros((8, 8, 8), bool), "bool.* is not one of"),
    (np.zeros((8, 8), np.uint8), "3-D array; this one has 2"),
    (np.zeros((2, 8, 8, 8), np.uint8), "3-D array; this one has 4"),
    (np.zeros((8, 16, 8), np.uint8)[:, ::2, :], "not contiguous"),
    (np.where(np.arange(512).reshape(8, 8, 8) == 77, np.nan, GOOD).astype(np.float32), "NaN or Inf"),
    (np.where(np.arange(512).reshape(8, 8, 8) == 3, np.inf, GOOD).astype(np.float32), "NaN or Inf"),
    (np.zeros((0, 8, 8), np.uint8), "an axis of 0 voxels"),
    (np.zeros((8, 8, 8), ">u2"), "'>u2'.* native byte order"),
    ("volume.nrrd", "3-D array; this one has 0"),
    ([[[1, 2], [3, 4]]], "int64.* is not one of"),
])
def test_bad_arrays_raise_value_error(svr_module, array, message):
    with pytest.raises(ValueError, match=message):
        svr_module.Volume.from_numpy(array)


def test_bad_axes_and_spacing(svr_module):
    with pytest.raises(ValueError, match="axes 'yxz' is not"):
        svr_module.Volume.from_numpy(GOOD, axes="yxz")
    with pytest.raises(ValueError, match="spacing 1 is -1"):
        svr_module.Volume.from_numpy(GOOD, spacing=(1.0, -1.0, 1.0))


def test_array_over_the_memory_budget(svr_module):
    # 8 GiB of untouched zero pages: the check refuses it before a byte is copied.
    huge = np.zeros((2048, 2048, 2048), np.uint8)
    with pytest.raises(ValueError, match="over the memory budget"):
        svr_module.Volume.from_numpy(huge)
