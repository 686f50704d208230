#!/usr/bin/env python3
"""svr-mpi end to end (issue 21, docs/distributed.md): `mpirun -np N svr-mpi render` writes the
light-independent image `svr render` writes, for N = 1..4, raycast and shearwarp, rgb and
factor:6, scalar and spectral transmittance, gzip (streamed) and raw (seeked) volume files;
each rank's peak memory is about 1/N of the volume plus ghosts; a rank that cannot read its
brick stops every rank with that rank's message and leaves no output.

Usage: mpi_render.py SVR SVR_MPI DATA_DIR
Images are compared with idiff (openimageio-tools) to 2e-5 absolute: the rounding of the
compositing order. Raycast bricks take the transmittance in front of them from the ranks in
front (renderers/render/front_transmittance.h), so they stop their rays where the whole render
does and its scenes keep early termination on; shear-warp bricks cannot see it and may go on
where the whole render stopped (within ε; Bricks.EarlyTerminationDiffersByAtMostItsThreshold
bounds that), so its scenes turn early termination off.
"""
import gzip
import json
import os
import shutil
import subprocess
import sys
import tempfile

SVR, SVR_MPI, DATA = sys.argv[1], sys.argv[2], os.path.abspath(sys.argv[3])
ENV = dict(os.environ, OMP_NUM_THREADS="1",
           # CI runs as root; Open MPI refuses root unless told.
           OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           # One machine, no network: shared memory and loopback only.
           OMPI_MCA_btl="self,vader", OMPI_MCA_btl_vader_single_copy_mechanism="none")
problems = []


def engine_scene(volume_file, early_termination):
    with open(os.path.join(DATA, "scenes", "engine.json")) as f:
        scene = json.load(f)
    scene["volume"] = {"file": volume_file}
    for m in scene["materials"].values():
        r = m["reflectance"]
        if isinstance(r, dict) and "csv" in r:
            r["csv"] = os.path.join(DATA, "scenes", r["csv"])
    scene["render"]["early_termination"] = early_termination
    scene["image"] = {"width": 72, "height": 64}
    return scene


def phantom_scene(early_termination):
    with open(os.path.join(DATA, "scenes", "phantom.json")) as f:
        scene = json.load(f)
    scene.setdefault("render", {})["early_termination"] = early_termination
    scene["image"] = {"width": 48, "height": 48}
    return scene


def cthead_scene():
    """16-bit big-endian CT (gzip) with a haemoglobin-like spectral absorber over a backdrop."""
    return {
        "volume": {"file": os.path.join(DATA, "volumes", "cthead_256x256x113_uint16be.nhdr")},
        "materials": {
            "tissue": {"reflectance": "ColorChecker/light skin", "opacity": 0.02,
                       "absorption": "ColorChecker/red"},
            "bone": {"reflectance": "ColorChecker/neutral 8 (.23 D)", "opacity": 1.5,
                     "specular": 0.3}},
        "transfer_function": {"type": "scalar",
                              "points": [[600, "tissue"], [1200, "tissue"], [1500, "bone"]],
                              "opacity": [[0, 0], [500, 0], [700, 1]]},
        "lights": ["D65", "A"],
        "background": "ColorChecker/white 9.5 (.05 D)",
        "camera": {"azimuth": -30, "elevation": 20},
        "image": {"width": 64, "height": 64},
        "render": {"step": 1.0, "early_termination": 0.01},
        "model": "rgb",
    }


def run(cmd, **kw):
    return subprocess.run(cmd, capture_output=True, text=True, env=ENV, timeout=600, **kw)


def mpirun(n, args):
    return run(["mpirun", "--oversubscribe", "-np", str(n), SVR_MPI, "render"] + args)


def same_image(a, b, what):
    r = run(["idiff", "-fail", "2e-5", "-warn", "2e-5", "-a",
             os.path.join(a, "light_independent.exr"), os.path.join(b, "light_independent.exr")])
    if r.returncode != 0:
        problems.append(f"{what}: differs from svr render:\n{r.stdout[-600:]}")
        return False
    return True


def check_equal(name, scene_path, scratch, renderer, model, counts, balance="work"):
    single = os.path.join(scratch, f"{name}_{renderer}_{model}_single".replace(":", "_"))
    r = run([SVR, "render", scene_path, "--out", single, "--renderer", renderer,
             "--model", model, "-q"])
    if r.returncode != 0:
        problems.append(f"svr render {name} {renderer} {model}: {r.stderr}")
        return
    for n in counts:
        out = single.replace("_single", f"_np{n}")
        r = mpirun(n, [scene_path, "--out", out, "--renderer", renderer, "--model", model, "-q",
                       "--balance", balance])
        what = f"{name} {renderer} {model} np {n} balance {balance}"
        if r.returncode != 0:
            problems.append(f"{what}: exit {r.returncode}: {r.stderr[-800:]}")
            continue
        if same_image(single, out, what):
            with open(os.path.join(out, "render.json")) as f:
                report = json.load(f)
            per = report["distributed"]["per_process"]
            if len(per) != n:
                problems.append(f"{what}: render.json lists {len(per)} processes")
            print(f"ok: {what} (" + ", ".join(
                f"rank {p['rank']} x {p['own']['lo'][0]}–{p['own']['hi'][0]} "
                f"{p['render_ms']:.0f} ms" for p in per) + ")")
            if renderer == "raycast" and balance == "work" and n == 2 and name.startswith("engine"):
                # The view's work lies mostly in the brick nearer the eye (high x here): the
                # split gives that brick fewer voxels, within 1.25× of a half for the other.
                lo_x = [p["own"]["hi"][0] for p in per if p["own"]["lo"][0] == 0][0]
                if not 128 < lo_x <= 160:
                    problems.append(f"{what}: work balance split x at {lo_x}, expected 129–160")


def peaks(out):
    with open(os.path.join(out, "render.json")) as f:
        return [p["peak_resident_bytes"] for p in json.load(f)["distributed"]["per_process"]]


def check_memory(scratch):
    """frogtissue 500×470×136 (uint8, 30 MiB; 4 bytes a voxel more as float): every rank of
    four holds about a quarter, plus ghost layers. A tiny procedural scene measures what a
    process holds besides the volume."""
    frog = {"volume": {"file": os.path.join(DATA, "volumes", "frogtissue_500x470x136_uint8.nhdr")},
            "materials": {"t": {"reflectance": "ColorChecker/red", "opacity": 0.5}},
            "transfer_function": {"type": "scalar", "points": [[60, "t"]],
                                  "opacity": [[0, 0], [40, 0], [80, 1]]},
            "lights": ["D65"], "image": {"width": 32, "height": 32}, "model": "rgb",
            "render": {"early_termination": 0}}
    tiny = dict(frog, volume={"procedural": "sphere", "size": 8})
    paths = {}
    for name, scene in (("frog", frog), ("tiny", tiny)):
        paths[name] = os.path.join(scratch, name + ".json")
        with open(paths[name], "w") as f:
            json.dump(scene, f)
    results = {}
    for name, n, balance in (("tiny", 4, "voxels"), ("frog", 1, "voxels"), ("frog", 4, "voxels"),
                             ("frog", 4, "work")):
        out = os.path.join(scratch, f"mem_{name}_{n}_{balance}")
        r = mpirun(n, [paths[name], "--out", out, "-q", "--balance", balance])
        if r.returncode != 0:
            problems.append(f"memory run {name} np {n}: {r.stderr[-800:]}")
            return
        results[(name, n, balance)] = peaks(out)
    base = max(results[("tiny", 4, "voxels")])
    whole = results[("frog", 1, "voxels")][0] - base
    if whole < (100 << 20):
        problems.append(f"memory: the whole volume took only {whole} bytes beyond the base")
    # Own share plus ghost layers (2 voxels each side of each cut), and 16 MiB for allocator
    # and page-granularity slack; a work-balanced brick may hold 1.25× its share.
    for balance, share in (("voxels", 1.0), ("work", 1.25)):
        allowed = whole / 4 * share * 1.10 + (16 << 20)
        worst = max(results[("frog", 4, balance)]) - base
        print(f"memory: whole volume {whole / 2**20:.0f} MiB beyond a process's base; 4 ranks, "
              f"balance {balance}: at most {worst / 2**20:.0f} MiB each "
              f"(allowed {allowed / 2**20:.0f})")
        if worst > allowed:
            problems.append(f"memory: balance {balance}: a rank of 4 held {worst} bytes beyond "
                            f"its base, over {allowed:.0f} ({share} × 1/4 of {whole} plus ghosts)")


def check_failure(scratch):
    """Bad data in one brick: a float label map whose voxel (31, 31, 31) holds 2.5. Of two
    ranks (split across x at 16) only rank 1 holds that voxel; both stop, with its message, and
    nothing is written."""
    import struct
    n = 32
    values = [1.0 if (x - 15.5) ** 2 + (y - 15.5) ** 2 + (z - 15.5) ** 2 < 100 else 0.0
              for z in range(n) for y in range(n) for x in range(n)]
    values[-1] = 2.5
    with open(os.path.join(scratch, "labels.raw"), "wb") as f:
        f.write(struct.pack(f"<{len(values)}f", *values))
    scene = {"volume": {"file": os.path.join(scratch, "labels.raw"),
                        "raw": {"dims": [n, n, n], "type": "float32"}},
             "materials": {"ball": {"reflectance": "ColorChecker/red", "opacity": 0.5}},
             "transfer_function": {"type": "labels", "labels": {"1": "ball"}},
             "lights": ["D65"], "image": {"width": 16, "height": 16}, "model": "rgb"}
    path = os.path.join(scratch, "bad_labels.json")
    with open(path, "w") as f:
        json.dump(scene, f)
    out = os.path.join(scratch, "fail_out")
    r = mpirun(2, [path, "--out", out, "-q"])
    errors = [l for l in r.stderr.splitlines() if "svr-mpi: error" in l]
    if (r.returncode == 0 or len(errors) != 1 or "rank 1 of 2" not in errors[0]
            or "voxel (31, 31, 31) holds 2.5" not in errors[0]):
        problems.append(f"failing rank: exit {r.returncode}, stderr {r.stderr[-800:]!r}")
    elif os.path.exists(out):
        problems.append(f"failing rank: {out} was created")
    else:
        print(f"ok: bad data in one brick stops both ranks: {errors[0]}")


def main():
    with tempfile.TemporaryDirectory(prefix="svr_mpi_") as scratch:
        # The engine as shipped (gzip: streamed, each rank keeping its brick) and as raw
        # (each rank seeks to its rows).
        raw = os.path.join(scratch, "engine.raw")
        with gzip.open(os.path.join(DATA, "volumes", "engine_256x256x128_uint8.raw.gz")) as src, \
                open(raw, "wb") as dst:
            shutil.copyfileobj(src, dst)
        with open(os.path.join(scratch, "engine.nhdr"), "w") as f:
            f.write("NRRD0004\ntype: uint8\ndimension: 3\nsizes: 256 256 128\n"
                    "spacings: 1 1 1\nencoding: raw\ndata file: engine.raw\n")
        engine_gz = os.path.join(DATA, "volumes", "engine_256x256x128_uint8.nhdr")
        engine_raw = os.path.join(scratch, "engine.nhdr")
        scenes = {  # early termination on for raycast, off for shear-warp (above)
            "engine_gz": engine_scene(engine_gz, 0.01),
            "engine_raw": engine_scene(engine_raw, 0.01),
            "engine_gz_all": engine_scene(engine_gz, 0),
            "engine_raw_all": engine_scene(engine_raw, 0),
            "phantom": phantom_scene(0.01),
            "phantom_all": phantom_scene(0),
            "cthead": cthead_scene(),
        }
        paths = {}
        for name, scene in scenes.items():
            paths[name] = os.path.join(scratch, name + ".json")
            with open(paths[name], "w") as f:
                json.dump(scene, f)
        check_equal("engine_gz", paths["engine_gz"], scratch, "raycast", "rgb", [1, 2, 3, 4])
        check_equal("engine_raw", paths["engine_raw"], scratch, "raycast", "factor:6", [2, 3, 4])
        check_equal("engine_raw", paths["engine_raw"], scratch, "raycast", "rgb", [2, 4], "voxels")
        check_equal("engine_raw_all", paths["engine_raw_all"], scratch, "shearwarp", "rgb",
                    [1, 2, 3, 4])
        check_equal("engine_gz_all", paths["engine_gz_all"], scratch, "shearwarp", "factor:6",
                    [2, 4])
        check_equal("phantom", paths["phantom"], scratch, "raycast", "factor:6", [1, 2, 3, 4])
        check_equal("phantom_all", paths["phantom_all"], scratch, "shearwarp", "factor:6", [3, 4])
        check_equal("cthead", paths["cthead"], scratch, "raycast", "rgb", [3])
        r = mpirun(2, [paths["phantom_all"], "--out", os.path.join(scratch, "x"), "--renderer",
                       "splat", "-q"])
        if r.returncode == 0 or "cannot render one brick" not in r.stderr:
            problems.append(f"splat bricks: exit {r.returncode}, {r.stderr[-400:]!r}")
        check_memory(scratch)
        check_failure(scratch)
    for p in problems:
        print("FAIL:", p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
