"""svr: spectral volume rendering (Bergner et al., IEEE Vis 2002) from Python.

    import svr
    scene = svr.Scene.load("data/scenes/engine.json")
    image = scene.render(model="factor:6", width=256, height=256)
    rgb = image.relight("D65")                 # H × W × 3 uint8 sRGB
    image.S.shape                               # (256, 256, 6): the light-independent image

See docs/python.md. Everything here is the C++ library (the extension svr._svr): no second
implementation of anything.
"""

from ._svr import (  # noqa: F401  (the package's API)
    Error,
    Image,
    Scene,
    Volume,
    __version__,
    backends,
    compare,
    library,
)

__all__ = ["Error", "Image", "Scene", "Volume", "backends", "compare", "library", "__version__"]
