#!/usr/bin/env python3
"""Peak memory of a 512³ float32 volume (512 MiB of voxels) through `svr render` (issue 9).

Renders it with raycast at 64×64, once loaded from a NRRD file and once generated procedurally,
measures each run's peak resident set (getrusage's ru_maxrss of the child), prints the figures
and checks them against the bound svr's design gives: the voxels once as loaded, plus what
classification keeps for the renderers (the values as float — one more copy of a float volume;
a scalar volume shades with the values themselves, so there is no second copy for the
gradients), plus a fixed margin for the program, its libraries, the spectrum tables and the
image. Under the test's 1 GiB budget the raycaster's precomputed gradients (8 bytes a voxel,
1 GiB here) do not fit, so it takes its on-the-fly path, as a user's render would. Also checks that a budget below the volume
refuses it before allocating (exit 2, the message, a small peak).

Usage: memory_512.py SVR_BINARY
"""
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

N = 512
VOLUME = N ** 3 * 4                      # bytes of voxels
MARGIN = 320 << 20                       # program, libraries, tables, image, block tables
BOUND = 2 * VOLUME + MARGIN              # voxels + classified values + margin
MIB = 1 << 20


def run(argv):
    """Runs svr; returns (exit status, stderr, peak RSS in bytes, seconds)."""
    start = time.monotonic()
    child = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    stderr = child.stderr.read().decode("utf-8", "replace")
    _, status, usage = os.wait4(child.pid, 0)
    child.stderr.close()
    code = os.waitstatus_to_exitcode(status)
    return code, stderr, usage.ru_maxrss * 1024, time.monotonic() - start


def write_volume(folder):
    """A 512³ float32 NRRD: a ball of radius 0.8 with a soft edge (values 0..1), x fastest."""
    axis = np.linspace(-1.0, 1.0, N, dtype=np.float32)
    yy, xx = np.meshgrid(axis, axis, indexing="ij")
    with open(os.path.join(folder, "ball.raw"), "wb") as raw:
        for z in axis:
            r = np.sqrt(xx * xx + yy * yy + z * z)
            raw.write(np.clip((0.8 - r) * 10.0, 0.0, 1.0).astype("<f4").tobytes())
    with open(os.path.join(folder, "ball.nhdr"), "w") as header:
        header.write(f"NRRD0004\ntype: float\ndimension: 3\nsizes: {N} {N} {N}\n"
                     "endian: little\nencoding: raw\ndata file: ball.raw\n")


def write_scene(folder, name, volume):
    with open(os.path.join(folder, name), "w") as scene:
        scene.write('{"volume": %s,\n'
                    ' "materials": {"m": {"reflectance": "ColorChecker/red", "opacity": 0.05}},\n'
                    ' "transfer_function": {"points": [[0, "m"], [1, "m"]],\n'
                    '                       "opacity": [[0, 0], [0.1, 0], [0.5, 1]]},\n'
                    ' "lights": ["D65"], "image": {"width": 64, "height": 64},\n'
                    ' "model": "rgb"}\n' % volume)
    return os.path.join(folder, name)


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    svr = os.path.abspath(sys.argv[1])
    failures = []
    print(f"bound: {BOUND / MIB:.0f} MiB = 2 × {VOLUME / MIB:.0f} MiB (voxels, classified values) "
          f"+ {MARGIN / MIB:.0f} MiB")
    with tempfile.TemporaryDirectory(prefix="svr_mem_") as folder:
        write_volume(folder)
        scenes = {"file": write_scene(folder, "file.json", '{"file": "ball.nhdr"}'),
                  "procedural": write_scene(folder, "procedural.json",
                                            '{"procedural": "sphere", "size": %d}' % N)}
        for name, scene in scenes.items():
            out = os.path.join(folder, "out_" + name)
            code, stderr, peak, seconds = run([svr, "render", scene, "--renderer", "raycast",
                                               "--memory-budget", "1G", "--out", out, "-q"])
            print(f"{name}: peak RSS {peak / MIB:.0f} MiB ({peak / VOLUME:.2f} × the voxels) "
                  f"in {seconds:.1f} s, exit {code}")
            if code != 0:
                failures.append(f"{name}: exit {code}: {stderr.strip()[-400:]}")
            elif peak > BOUND:
                failures.append(f"{name}: peak RSS {peak / MIB:.0f} MiB exceeds {BOUND / MIB:.0f} MiB")
            elif not os.path.exists(os.path.join(out, "D65.png")):
                failures.append(f"{name}: no D65.png written")
        # Over budget: refused from the header, before the voxels are allocated.
        code, stderr, peak, _ = run([svr, "render", scenes["file"], "--memory-budget", "256M",
                                     "--out", os.path.join(folder, "out_refused"), "-q"])
        print(f"refused: peak RSS {peak / MIB:.0f} MiB, exit {code}")
        expected = "ball.nhdr: 512×512×512 float32 needs 512.0 MiB, over the memory budget of 256.0 MiB"
        if code != 2 or expected not in stderr:
            failures.append(f"refused: exit {code}, stderr {stderr.strip()[-400:]!r}")
        elif peak > MARGIN:
            failures.append(f"refused: peak RSS {peak / MIB:.0f} MiB; the volume was allocated")
    for failure in failures:
        print("FAIL", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
