#!/usr/bin/env python3
"""`svr view` from the command line: it prints the URL it serves on loopback, answers there,
stops cleanly on Ctrl-C (exit 0, "svr view: stopped"), and refuses a bad --port before loading.
Off loopback (--host 0.0.0.0; every request here still goes to 127.0.0.1) it makes a token and
prints it in the URL, and refuses requests without it; --token sets it, --no-token turns it off
with a warning, and bad token flags are refused.

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
import urllib.error
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


def start(svr: str, scene: str, *extra: str):
    """svr view on any free port: the process, the match of the loopback URL (and its token) in
    its first line, and that line."""
    proc = subprocess.Popen([svr, "view", scene, "--port", "0", *extra], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    line = proc.stdout.readline()
    return proc, re.search(r"http://127\.0\.0\.1:(\d+)/(\?token=([0-9A-Za-z_-]+))?", line), line


def status(url: str, headers=None) -> int:
    try:
        with urllib.request.urlopen(urllib.request.Request(url, headers=headers or {}),
                                    timeout=30) as r:
            return r.status
    except urllib.error.HTTPError as e:
        return e.code


def stop(proc) -> tuple:
    proc.send_signal(signal.SIGINT)
    try:
        return proc.communicate(timeout=20)
    except subprocess.TimeoutExpired:
        proc.kill()
        return proc.communicate()


def check_tokens(svr: str, scene: str, problems: list) -> None:
    # Off loopback: a fresh 32-hex-digit token in the printed URL, needed by every request.
    proc, match, line = start(svr, scene, "--host", "0.0.0.0")
    if not match or not match.group(3) or len(match.group(3)) != 32:
        problems.append(f"--host 0.0.0.0: no token in the URL line {line!r}")
        stop(proc)
        return
    base, token = f"http://127.0.0.1:{match.group(1)}/", match.group(3)
    got = {"no token": status(base + "api/scene"), "wrong token": status(base + "api/scene?token=0"),
           "token": status(f"{base}api/scene?token={token}"),
           "cookie": status(base + "api/scene",
                            {"Cookie": f"svr-token-{match.group(1)}={token}"}),
           "foreign Host": status(f"{base}api/scene?token={token}",
                                  {"Host": f"attacker.example:{match.group(1)}"})}
    want = {"no token": 403, "wrong token": 403, "token": 200, "cookie": 200, "foreign Host": 403}
    if got != want:
        problems.append(f"--host 0.0.0.0: statuses {got}, expected {want}")
    stop(proc)
    # --token VALUE: that token, on loopback too.
    proc, match, line = start(svr, scene, "--token", "my-token-123")
    if not match or match.group(3) != "my-token-123":
        problems.append(f"--token my-token-123: URL line {line!r}")
    else:
        base = f"http://127.0.0.1:{match.group(1)}/"
        if (status(base + "api/scene"), status(base + "api/scene?token=my-token-123")) != (403, 200):
            problems.append("--token my-token-123 is not enforced")
    stop(proc)
    # --no-token off loopback: served without one, and said loudly.
    proc, match, line = start(svr, scene, "--host", "0.0.0.0", "--no-token")
    if not match or match.group(3):
        problems.append(f"--no-token: URL line {line!r}")
    elif status(f"http://127.0.0.1:{match.group(1)}/api/scene") != 200:
        problems.append("--no-token: /api/scene is not served without a token")
    _, err = stop(proc)
    if "WARNING: --no-token on 0.0.0.0: anyone who can reach port" not in err:
        problems.append(f"--no-token: no warning on stderr: {err!r}")
    for flags, message in [(["--token", "short"], "--token must be 8–128 letters"),
                           (["--token", "bad token!"], "--token must be 8–128 letters"),
                           (["--token", "abcdefgh1", "--no-token"], "exclude each other")]:
        bad = subprocess.run([svr, "view", scene, "--port", "0", *flags], capture_output=True,
                             text=True, timeout=60)
        if bad.returncode != 2 or message not in bad.stderr:
            problems.append(f"{flags}: exit {bad.returncode}, stderr {bad.stderr!r}")


def run(svr: str, scene: str) -> int:
    problems = []
    check_tokens(svr, scene, problems)
    bad = subprocess.run([svr, "view", scene, "--port", "70000"], capture_output=True, text=True,
                         timeout=60)
    if bad.returncode != 2 or "--port 70000 is outside 0..65535" not in bad.stderr:
        problems.append(f"--port 70000: exit {bad.returncode}, stderr {bad.stderr!r}")

    proc, match, line = start(svr, scene)
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
