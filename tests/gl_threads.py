#!/usr/bin/env python3
"""gl.mode=raycast gives identical pixels with 1 and 2 llvmpipe threads (LP_NUM_THREADS, read
once per process when llvmpipe's screen is made, hence one `svr render` per thread count), on
both platforms: every pixel is its own ray, so no thread count can change a sum.

Usage: gl_threads.py SVR_BINARY SCENE
"""
import os
import subprocess
import sys
import tempfile


def same_pixels(a, b):
    """Bit-identical pixels (the EXR header also holds the time it was written)."""
    return subprocess.run(["idiff", "-q", "-fail", "0", "-warn", "0", a, b]).returncode == 0


def main():
    svr, scene = sys.argv[1], sys.argv[2]
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        for platform in ("osmesa", "egl"):
            images = []
            for threads in ("1", "2"):
                out = os.path.join(tmp, f"{platform}_{threads}")
                env = dict(os.environ, LP_NUM_THREADS=threads)
                subprocess.run([svr, "render", scene, "--renderer", "gl", "--option",
                                f"gl.platform={platform}", "--out", out, "-q", "--width", "96",
                                "--height", "96"], check=True, env=env)
                images.append(os.path.join(out, "light_independent.exr"))
            if not same_pixels(*images):
                failures.append(f"{platform}: 1 and 2 llvmpipe threads differ")
    for f in failures:
        print(f"gl_threads: {f}", file=sys.stderr)
    print("gl_threads: identical pixels with 1 and 2 llvmpipe threads on osmesa and egl"
          if not failures else "gl_threads: FAILED")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
