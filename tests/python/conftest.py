# Shared by the Python module's tests (ctest python.*; docs/python.md). The module comes from
# PYTHONPATH (build/<preset>/python), the svr binary from SVR_BIN.
import gzip
import os
import pathlib

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = ROOT / "data"
SCENES = DATA / "scenes"
VOLUMES = DATA / "volumes"


def read_nrrd_voxels(name):
    """The voxels of one of data/volumes' gzip NRRDs as a C-ordered [z, y, x] array in native
    byte order, read with numpy alone (the header's sizes, type, endian and spacings)."""
    header = {}
    for line in (VOLUMES / name).read_text().splitlines():
        if ":" in line and not line.startswith("#"):
            key, value = line.split(":", 1)
            header[key.strip()] = value.strip()
    sizes = [int(s) for s in header["sizes"].split()]
    kind = {"uint8": "u1", "int16": "i2", "uint16": "u2", "float": "f4"}[header["type"]]
    order = ">" if header.get("endian") == "big" else "<"
    raw = gzip.decompress((VOLUMES / header["data file"]).read_bytes())
    a = np.frombuffer(raw, dtype=order + kind).reshape(sizes[::-1])
    spacing = tuple(float(s) for s in header["spacings"].split())
    return a.astype(a.dtype.newbyteorder("=")), spacing


@pytest.fixture(scope="session")
def svr_module():
    import svr

    return svr


@pytest.fixture(scope="session")
def svr_bin():
    path = os.environ.get("SVR_BIN")
    if not path:
        pytest.skip("SVR_BIN names the svr binary (ctest sets it)")
    return path


def small_scene(volume_file, tf, lights=("D65", "F11"), size=48, **extra):
    """A scene dict over one of data/volumes, for renders of a few milliseconds."""
    scene = {
        "volume": {"file": str(VOLUMES / volume_file)},
        "materials": {
            "soft": {"reflectance": "Munsell/5R 6/10", "opacity": 0.6},
            "hard": {"reflectance": "Munsell/5PB 6/8", "opacity": 4.0, "specular": 0.3},
        },
        "transfer_function": tf,
        "lights": list(lights),
        "image": {"width": size, "height": size},
        "model": "factor:4",
    }
    scene.update(extra)
    return scene
