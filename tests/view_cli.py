#!/usr/bin/env python3
"""`svr view` from the command line: it prints the URL it serves on loopback, answers there,
stops cleanly on Ctrl-C (exit 0, "svr view: stopped"), and refuses a bad --port before loading.

Usage: view_cli.py SVR_BINARY
Its scene is its own: a small procedural sphere with the rgb model, so that it starts in well
under a second even under the sanitizers (no model to train).
"""
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
import urllib.request

SCENE = {
    "volume": {"procedural": "sphere", "size": 24},
    "materials": {"red": {"reflectance": "ColorChecker/red", "opacity": 0.6}},
    "transfer_function": {"type": "scalar", "points": [[0.5, "red"]],
                          "opacity": [[0.0, 0.0], [0.2, 1.0]]},
    "lights": ["D65", "A"],
    "image": {"width": 32, "height": 32},
    "model": "rgb",
}


def main() -> int:
    with tempfile.TemporaryDirectory(prefix="svr_view_cli_") as scratch:
        scene = os.path.join(scratch, "sphere.json")
        with open(scene, "w") as f:
            json.dump(SCENE, f)
        return run(sys.argv[1], scene)


def run(svr: str, scene: str) -> int:
    problems = []
    bad = subprocess.run([svr, "view", scene, "--port", "70000"], capture_output=True, text=True,
                         timeout=60)
    if bad.returncode != 2 or "--port 70000 is outside 0..65535" not in bad.stderr:
        problems.append(f"--port 70000: exit {bad.returncode}, stderr {bad.stderr!r}")

    proc = subprocess.Popen([svr, "view", scene, "--port", "0"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    line = proc.stdout.readline()
    match = re.search(r"http://127\.0\.0\.1:(\d+)/", line)
    if not match:
        proc.kill()
        print(f"FAIL: no loopback URL in {line!r}; stderr {proc.stderr.read()!r}")
        return 1
    url = match.group(0)
    with urllib.request.urlopen(url + "api/scene", timeout=30) as r:
        info = json.load(r)
    if not info.get("lights"):
        problems.append(f"/api/scene has no lights: {info}")
    with urllib.request.urlopen(url, timeout=30) as r:
        if b"<canvas" not in r.read():
            problems.append("/ is not the page")
    t0 = time.monotonic()
    proc.send_signal(signal.SIGINT)
    try:
        out, err = proc.communicate(timeout=20)
    except subprocess.TimeoutExpired:
        proc.kill()
        print("FAIL: svr view did not stop within 20 s of SIGINT")
        return 1
    if proc.returncode != 0 or "svr view: stopped" not in out:
        problems.append(f"after SIGINT: exit {proc.returncode}, stdout {out!r}, stderr {err!r}")
    for p in problems:
        print("FAIL:", p)
    if not problems:
        print(f"ok: served {url}, stopped {time.monotonic() - t0:.2f} s after SIGINT")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
