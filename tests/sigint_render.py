#!/usr/bin/env python3
"""Ctrl-C during `svr render` stops it cleanly: exit status 130, "svr: interrupted", and no
file (partial or whole) in the output folder.

Usage: sigint_render.py SVR_BINARY SCENE
"""
import os
import signal
import subprocess
import sys
import tempfile
import time


def main() -> int:
    svr, scene = os.path.abspath(sys.argv[1]), sys.argv[2]
    with tempfile.TemporaryDirectory(prefix="svr_sigint_") as scratch:
        out = os.path.join(scratch, "out")
        # Large enough that the render is still running when the signal comes.
        proc = subprocess.Popen([svr, "render", scene, "--out", out, "-q", "--width", "4096",
                                 "--height", "4096"], cwd=scratch, stderr=subprocess.PIPE)
        time.sleep(2.0)
        if proc.poll() is not None:
            print(f"FAIL: svr ended (status {proc.returncode}) before the signal was sent")
            return 1
        proc.send_signal(signal.SIGINT)
        try:
            _, stderr = proc.communicate(timeout=60)
        except subprocess.TimeoutExpired:
            proc.kill()
            print("FAIL: svr did not stop within 60 s of SIGINT")
            return 1
        message = stderr.decode("utf-8", "replace")
        left = [os.path.join(d, n) for d, _, names in os.walk(scratch) for n in names]
        problems = []
        if proc.returncode != 130:
            problems.append(f"exit status {proc.returncode}, expected 130")
        if "svr: interrupted" not in message:
            problems.append(f"no 'svr: interrupted' message in {message!r}")
        if left:
            problems.append(f"left files behind: {left}")
        for p in problems:
            print("FAIL:", p)
        if not problems:
            print("svr render stopped on SIGINT with status 130, nothing written")
        return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
