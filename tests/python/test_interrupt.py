# Ctrl-C during a render raises KeyboardInterrupt soon, not when the render would have ended,
# and leaves the module ready for the next render.
import signal
import subprocess
import sys
import textwrap

from conftest import SCENES

SCRIPT = textwrap.dedent("""
    import os, signal, sys, threading, time
    import svr
    scene = svr.Scene.load(sys.argv[1])
    scene.render(model="rgb", width=32, height=32)
    t0 = time.perf_counter()
    scene.render(model="rgb", width=768, height=768)
    full = time.perf_counter() - t0
    threading.Timer(0.1 * full, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
    t0 = time.perf_counter()
    try:
        scene.render(model="rgb", width=768, height=768)
        print("not interrupted"); sys.exit(3)
    except KeyboardInterrupt:
        stopped = time.perf_counter() - t0
    image = scene.render(model="rgb", width=32, height=32)
    assert image.relight("D65").shape == (32, 32, 3)
    print(f"full render {full:.3f} s, interrupted after {stopped:.3f} s")
    assert stopped < 0.6 * full, (full, stopped)
""")


def test_ctrl_c_stops_a_render():
    run = subprocess.run([sys.executable, "-c", SCRIPT, str(SCENES / "engine.json")],
                         capture_output=True, text=True, timeout=300)
    print(run.stdout, run.stderr)
    assert run.returncode == 0, run.stdout + run.stderr
