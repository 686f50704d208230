#!/usr/bin/env python3
"""Ratios from one Google Benchmark JSON run.

  relight bench: relight time / streaming-read time per size/k/storage, and frames per second
    build/release/bench/svr_relight_bench --benchmark_out=relight.json --benchmark_out_format=json
    python3 bench/ratios.py relight.json
  raycast bench: time per frame of every model, and its ratio to rgb at the same size
    build/release/bench/svr_raycast_bench --benchmark_out=raycast.json --benchmark_out_format=json
    python3 bench/ratios.py raycast.json
  splat bench: every CPU backend's time per frame, and its ratio to raycast with the same model
    build/release/bench/svr_splat_bench --benchmark_out=splat.json --benchmark_out_format=json
    python3 bench/ratios.py splat.json
"""
import json
import sys

def config(name):
    """The benchmark's own name, without Google Benchmark's /min_time:…/real_time suffixes."""
    return "/".join(p for p in name.split("/") if p != "real_time" and not p.startswith(("min_time:", "iterations:")))


runs = {config(b["name"]): b for b in json.load(open(sys.argv[1]))["benchmarks"]
        if b.get("run_type", "iteration") == "iteration"}


def ratio_table(prefix, baseline, width):
    """Time per frame of every run named PREFIX/…/X, and its ratio to PREFIX/…/BASELINE."""
    table = {n: b for n, b in runs.items() if n.startswith(prefix)}
    if not table:
        return False
    print(f"{'run':<{width}} {'ms/frame':>9} {'/ ' + baseline:>9}")
    for name, b in table.items():
        base = runs.get("/".join(name.split("/")[:-1] + [baseline]))
        ratio = b["real_time"] / base["real_time"] if base else float("nan")
        print(f"{name:<{width}} {b['real_time']:9.1f} {ratio:9.2f}")
    return True


if ratio_table("Frame/", "raycast", 44) or ratio_table("Raycast/", "rgb", 34):
    sys.exit(0)
print(f"{'config':<18} {'relight fps':>12} {'stream fps':>12} {'relight/stream':>15}  {'GB/s relight':>12}")
for name, b in runs.items():
    if not name.startswith("Relight/"):
        continue
    cfg = name[len("Relight/"):]
    s = runs.get("StreamRead/" + cfg)
    if not s:
        continue
    t, ts = b["real_time"], s["real_time"]
    print(f"{cfg:<18} {1e6 / t:12.0f} {1e6 / ts:12.0f} {t / ts:15.2f}  {b['bytes_per_second'] / 1e9:12.1f}")
