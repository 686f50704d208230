#!/usr/bin/env python3
"""The peer table from the JSON files bench/peers/run leaves in its output folder: every peer
time beside ours on the same view, size and thread count, and ours/peer (< 1: we are faster).

  python3 bench/peers/table.py out/peers              (prints; writes out/peers/peers.json)
  python3 bench/peers/table.py out/peers --markdown   (the same as markdown, for docs/performance*)
  python3 bench/peers/table.py out/peers --chart docs/performance/peers_ratios.png   (and a bar chart)

Inputs (any may be missing; its rows are then left out):
  volpack_t1.json, volpack_t2.json   svr_volpack_bench (Google Benchmark JSON); VolPack is
                                     single-threaded, so its time is the t1 run's in both
  raycast_t<N>.json                  svr_raycast_peer_bench at OMP_NUM_THREADS=N
  vtk_t<N>.json                      vtk_bench.py --threads N
  glraycast.json, vtk_gpu.json       svr_raycast_peer_bench's GlRaycast rows and vtk_bench.py
                                     --mapper gpu, both on llvmpipe (threads: its own, one per core)
"""
import glob
import json
import math
import os
import re
import sys


def bench_times(path):
    """name -> ms per frame, without Google Benchmark's /min_time:…/real_time suffixes: the
    median of the repetitions where the bench repeats (Repetitions + ReportAggregatesOnly), else
    the single run."""
    out = {}
    for b in json.load(open(path))["benchmarks"]:
        aggregate = b.get("run_type", "iteration") == "aggregate"
        if aggregate and b.get("aggregate_name") != "median":
            continue
        name = b["run_name"] if aggregate else b["name"]
        name = "/".join(p for p in name.split("/")
                        if p != "real_time" and not p.startswith(("min_time:", "iterations:",
                                                                   "repeats:")))
        scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[b["time_unit"]]
        out[name] = b["real_time"] * scale
    return out


def threads_of(path):
    return int(re.search(r"_t(\d+)\.json$", path).group(1))


def main():
    args = sys.argv[1:]
    markdown = "--markdown" in args
    args = [a for a in args if a != "--markdown"]
    chart = None
    if "--chart" in args:
        at = args.index("--chart")
        if at + 1 >= len(args):
            sys.exit("table: --chart needs a PNG path")
        chart = args[at + 1]
        del args[at:at + 2]
    if len(args) != 1:
        sys.exit(__doc__)
    folder = args[0]
    rows = []
    # VolPack against our shear-warp: VolPack's own time always comes from the 1-thread run.
    vp1 = os.path.join(folder, "volpack_t1.json")
    if os.path.exists(vp1):
        peer = bench_times(vp1)
        for path in sorted(glob.glob(os.path.join(folder, "volpack_t*.json"))):
            ours, threads = bench_times(path), threads_of(path)
            for name, ms in ours.items():
                if not name.startswith(("Shearwarp/", "ShearwarpPre/")):
                    continue
                row, model, size, view = name.split("/")
                ours_name = "shearwarp pre" if row == "ShearwarpPre" else "shearwarp"
                pairs = [("rgb", "VolPack rgb")] + ([("grey", "VolPack grey")] if model == "rgb" else [])
                for colour, label in pairs:
                    p = peer.get(f"VolPack/{colour}/{size}/{view}")
                    if p:
                        rows.append(dict(peer=label, peer_threads=1, ours=ours_name, model=model,
                                         size=int(size), view=view, threads=threads,
                                         peer_ms=p, ours_ms=ms, ratio=ms / p))
    # VTK's fixed-point ray caster against our raycaster and splats, at equal threads.
    for path in sorted(glob.glob(os.path.join(folder, "vtk_t*.json"))):
        threads = threads_of(path)
        ours_path = os.path.join(folder, f"raycast_t{threads}.json")
        if not os.path.exists(ours_path):
            continue
        ours = bench_times(ours_path)
        for rec in json.load(open(path))["runs"]:
            _, _, size, view = rec["name"].split("/")
            for model in ("rgb", "factor:6"):
                for row, label in (("Raycast", "raycast"), ("SplatSheet", "splat sheet"),
                                   ("SplatDirect", "splat direct")):
                    ms = ours.get(f"{row}/{model}/{size}/{view}")
                    if ms:
                        rows.append(dict(peer="VTK fixed-point", peer_threads=threads,
                                         ours=label, model=model, size=int(size), view=view,
                                         threads=threads, peer_ms=rec["ms"], ours_ms=ms,
                                         ratio=ms / rec["ms"]))
    # VTK's GPU ray caster against our gl.mode=raycast, both on llvmpipe.
    gpu_path, gl_path = os.path.join(folder, "vtk_gpu.json"), os.path.join(folder, "glraycast.json")
    if os.path.exists(gpu_path) and os.path.exists(gl_path):
        ours = bench_times(gl_path)
        gpu = json.load(open(gpu_path))
        for rec in gpu["runs"]:
            _, _, size, view = rec["name"].split("/")
            for model in ("rgb", "factor:6"):
                ms = ours.get(f"GlRaycast/{model}/{size}/{view}")
                if ms:
                    rows.append(dict(peer="VTK GPU (llvmpipe)", peer_threads=gpu["threads"],
                                     ours="gl raycast", model=model, size=int(size), view=view,
                                     threads=gpu["threads"], peer_ms=rec["ms"], ours_ms=ms,
                                     ratio=ms / rec["ms"]))
    # Our own gl splats against our gl ray caster at 256² (issue 18: at least 3× faster).
    if os.path.exists(gl_path):
        ours = bench_times(gl_path)
        for model in ("rgb", "factor:6"):
            ms, splat = ours.get(f"GlRaycast/{model}/256/az-60"), ours.get(f"GlSplat/{model}/256/az-60")
            if ms and splat:
                rows.append(dict(peer="gl splat (ours)", peer_threads=os.cpu_count(),
                                 ours="gl raycast", model=model, size=256, view="az-60",
                                 threads=os.cpu_count(), peer_ms=splat, ours_ms=ms,
                                 ratio=ms / splat))
    if not rows:
        sys.exit(f"table: no peer results in {folder}")

    gm = lambda xs: math.exp(sum(math.log(x) for x in xs) / len(xs))
    groups = {}
    for r in rows:
        key = (r["peer"], r["ours"], r["model"], r["size"], r["peer_threads"], r["threads"])
        groups.setdefault(key, []).append(r)
    summary = [dict(peer=peer, ours=ours, model=model, size=size, peer_threads=pt, threads=t,
                    peer_ms=gm([r["peer_ms"] for r in rs]), ours_ms=gm([r["ours_ms"] for r in rs]),
                    ratio=gm([r["ratio"] for r in rs]), views=len(rs))
               for (peer, ours, model, size, pt, t), rs in groups.items()]
    cols = ["peer", "ours", "model", "size", "view", "threads", "peer ms", "ours ms", "ratio"]
    cell = lambda r: [r["peer"], r["ours"], r["model"], f"{r['size']}²", r.get("view", "all"),
                      f"{r['peer_threads']}/{r['threads']}", f"{r['peer_ms']:.1f}",
                      f"{r['ours_ms']:.1f}", f"{r['ratio']:.2f}"]
    load = " ".join(f"{x:.1f}" for x in os.getloadavg())
    if markdown:
        for title, table in (("Geometric mean over the views", summary), ("Every view", rows)):
            print(f"**{title}** (threads: peer/ours; ratio = ours / peer, < 1: ours is faster)\n")
            print("| " + " | ".join(cols) + " |")
            print("|" + "---|" * 5 + "---:|" * 4)
            for r in table:
                print("| " + " | ".join(cell(r)) + " |")
            print()
        print(f"Load average when the table was made: {load}.")
    else:
        widths = [18, 13, 9, 6, 6, 7, 9, 9, 6]
        line = lambda vals: " ".join(f"{v:<{w}}" if i < 3 else f"{v:>{w}}"
                                     for i, (v, w) in enumerate(zip(vals, widths)))
        for title, table in (("Every view", rows), ("Geometric mean over the views", summary)):
            print(f"\n{title}")
            print(line(cols))
            for r in table:
                print(line(cell(r)))
        print("(threads: peer/ours; ratio = ours / peer, < 1 means ours is faster; "
              f"load average {load})")
    with open(os.path.join(folder, "peers.json"), "w") as f:
        json.dump({"rows": rows, "summary": summary, "load_average": os.getloadavg()}, f, indent=1)
    if chart:
        plot(summary, chart)


def plot(summary, path):
    """The geometric-mean ratios as horizontal bars, parity (1) and issue 16's goal (0.5) marked."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    labels = [f"{r['ours']} {r['model']} vs {r['peer']}, {r['size']}², {r['peer_threads']}/{r['threads']} thr"
              for r in summary]
    ratios = [r["ratio"] for r in summary]
    fig, ax = plt.subplots(figsize=(8, 0.32 * len(summary) + 1.2))
    colours = ["tab:green" if x <= 1 else "tab:red" for x in ratios]
    ax.barh(range(len(summary)), ratios, color=colours)
    ax.set_yticks(range(len(summary)), labels, fontsize=7)
    ax.invert_yaxis()
    ax.axvline(1.0, color="black", lw=1)
    ax.axvline(0.5, color="grey", lw=1, ls="--")
    for i, x in enumerate(ratios):
        ax.text(x, i, f" {x:.2f}", va="center", fontsize=7)
    ax.set_xlabel("ours / peer, time per frame (geometric mean over the views; < 1: ours faster)")
    ax.set_title("bench/peers/run: geometric mean over the views", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()
