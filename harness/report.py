#!/usr/bin/env python3
"""Charts and the HTML page of an `svr compare` (or `svr demo`) report folder.

  report.py DIR      DIR holds report.json (compare) or demo.json listing scene folders (demo)

Writes, per compare folder: a ΔE2000 heat map with a colour bar beside every error map
(maps/**/*.pfm → .png), speed_accuracy.png and speed_accuracy.json (time per frame against
mean ΔE2000, both log, Pareto front marked and its points labelled where the labels do not
overlap; one marker per backend and one colour per model across every chart), and report.html: one self-contained page (images
embedded) with the relit images side by side per light, the error maps, the chart and the tables.
A demo folder gets one report.html with a section per scene. Needs Debian's python3-matplotlib.
"""
import base64
import html
import json
import os
import sys
import zlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.transforms  # noqa: E402
import numpy as np  # noqa: E402


def read_pfm(path):
    with open(path, "rb") as f:
        if f.readline().strip() != b"Pf":
            raise ValueError(f"{path}: not a grey PFM")
        w, h = (int(v) for v in f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4").reshape(h, w)
    return np.flipud(data)


def heat_maps(folder, report):
    vmax = 1.0
    for run in report["runs"]:
        for light in run["lights"]:
            m = read_pfm(os.path.join(folder, light["error_map"]))
            if m.size and np.isfinite(m).all():
                vmax = max(vmax, float(np.percentile(m, 99.5)))
    for run in report["runs"]:
        for light in run["lights"]:
            path = os.path.join(folder, light["error_map"])
            m = read_pfm(path)
            fig, ax = plt.subplots(figsize=(4.2, 3.4), dpi=80)
            im = ax.imshow(m, cmap="magma", vmin=0, vmax=vmax, interpolation="nearest")
            ax.set_axis_off()
            ax.set_title(f"ΔE2000 {run['label']}\n{light['light']}: mean {light['de_mean']:.2f}",
                         fontsize=8)
            fig.colorbar(im, ax=ax, fraction=0.046, pad=0.04).set_label("ΔE2000", fontsize=8)
            fig.tight_layout()
            light["error_png"] = light["error_map"][:-4] + ".png"
            fig.savefig(os.path.join(folder, light["error_png"]))
            plt.close(fig)


def pareto(points):
    """Indices of points not dominated in (time, error), both minimised."""
    front = []
    for i, (t, e) in enumerate(points):
        if not any((t2 <= t and e2 <= e) and (t2 < t or e2 < e) for t2, e2 in points):
            front.append(i)
    return sorted(front, key=lambda i: points[i][0])


# One marker per backend and one colour per model, the same in every chart of every report, so
# that a point reads alike across scenes and runs. Names not listed get a marker and a colour
# from a stable hash of the name.
BACKEND_MARKERS = {"raycast": "o", "shearwarp": "s", "splat": "D", "gl": "^"}
MODEL_COLOURS = {"rgb": "#7f7f7f", "factor:3": "#bcbd22", "factor:4": "#ff7f0e",
                 "factor:6": "#1f77b4", "factor:8": "#2ca02c", "factor:6/projected": "#9467bd",
                 "spectral:31": "#d62728", "spectral:81": "#000000"}


def marker_of(backend):
    return BACKEND_MARKERS.get(backend) or "v<>p*hXP"[zlib.crc32(backend.encode()) % 8]


def colour_of(model):
    return MODEL_COLOURS.get(model) or plt.get_cmap("tab20")(zlib.crc32(model.encode()) % 20)


def place_labels(fig, ax, front_points, taken):
    """Labels for the Pareto points, each placed at the first of a ring of offsets around its
    point where its box overlaps no other label, no point and stays inside the axes."""
    renderer = fig.canvas.get_renderer()
    inside = ax.get_window_extent(renderer)
    for (x, y), text in front_points:
        placed = None
        for radius in (5, 12, 22, 34, 48, 64, 84):
            for dx, dy in ((1, 1), (1, -1), (-1, 1), (-1, -1), (1, 0), (-1, 0), (0, 1), (0, -1)):
                note = ax.annotate(
                    text, (x, y), xytext=(dx * radius, dy * radius), textcoords="offset points",
                    fontsize=7, ha="left" if dx > 0 else ("right" if dx < 0 else "center"),
                    va="bottom" if dy > 0 else ("top" if dy < 0 else "center"),
                    arrowprops=dict(arrowstyle="-", lw=0.5, color="0.4") if radius > 5 else None)
                box = note.get_window_extent(renderer).expanded(1.04, 1.15)
                if (inside.contains(box.x0, box.y0) and inside.contains(box.x1, box.y1)
                        and not any(box.overlaps(t) for t in taken)):
                    placed = box
                    break
                note.remove()
            if placed:
                break
        if placed:
            taken.append(placed)
        # A label with no free place is left out of the chart; the hover title and the table
        # still name the point.


def speed_accuracy(folder, report):
    runs, points = [], []
    for run in report["runs"]:
        errors = [l["de_mean"] for l in run["lights"] if l["de_mean"] is not None]
        if not errors:
            continue
        runs.append(run)
        points.append((max(run["render_ms"], 1e-3), max(float(np.mean(errors)), 1e-3)))
    labels = [run["label"] for run in runs]
    front = pareto(points)
    fig, ax = plt.subplots(figsize=(8.5, 5), dpi=90)
    for (t, e), run in zip(points, runs):
        ax.scatter(t, e, marker=marker_of(run["renderer"]), color=colour_of(run["model"]), s=40,
                   zorder=3)
    if front:
        ax.plot([points[i][0] for i in front], [points[i][1] for i in front], "k--", lw=1,
                zorder=2)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("render time per frame (ms)")
    ax.set_ylabel("mean ΔE2000 against spectral:81 reference")
    ax.set_title(os.path.basename(report["scene"]))
    # The legend keys the two channels apart: black markers for backends, squares for models.
    keys = [plt.Line2D([], [], ls="", marker=marker_of(b), color="k", label=b)
            for b in dict.fromkeys(run["renderer"] for run in runs)]
    keys += [plt.Line2D([], [], ls="", marker="s", color=colour_of(m), label=m)
             for m in dict.fromkeys(run["model"] for run in runs)]
    keys.append(plt.Line2D([], [], ls="--", color="k", lw=1, label="Pareto front"))
    # Beside the axes, where it covers no point.
    ax.legend(handles=keys, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.margins(0.1)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    # Pixel positions once the layout is final: for the labels, and for the page's hover titles.
    pixels = [ax.transData.transform(p) for p in points]
    taken = [matplotlib.transforms.Bbox.from_bounds(px - 5, py - 5, 10, 10) for px, py in pixels]
    place_labels(fig, ax, [(points[i], labels[i]) for i in front], taken)
    fig.savefig(os.path.join(folder, "speed_accuracy.png"))
    height = fig.get_size_inches()[1] * fig.dpi
    plt.close(fig)
    with open(os.path.join(folder, "speed_accuracy.json"), "w") as f:
        json.dump({"points": [{"run": l, "ms": p[0], "de_mean": p[1], "pareto": i in front,
                               "x": round(float(px[0]), 1), "y": round(float(height - px[1]), 1)}
                              for i, (l, p, px) in enumerate(zip(labels, points, pixels))]},
                  f, indent=1)


def chart_with_titles(folder, name):
    """The chart, with an image map whose circles give every point's run, time and error on
    hover (pixel positions from speed_accuracy.json)."""
    with open(os.path.join(folder, "speed_accuracy.json")) as f:
        points = json.load(f)["points"]
    areas = "".join(
        f"<area shape=circle coords='{p['x']:.0f},{p['y']:.0f},7' "
        f"title='{html.escape(p['run'])}: {p['ms']:.1f} ms, mean ΔE2000 {p['de_mean']:.3f}"
        f"{' (Pareto front)' if p['pareto'] else ''}'>" for p in points)
    return (f"<img src='{embed(folder, 'speed_accuracy.png')}' usemap='#{name}'>"
            f"<map name='{name}'>{areas}</map>")


def embed(folder, rel):
    with open(os.path.join(folder, rel), "rb") as f:
        return "data:image/png;base64," + base64.b64encode(f.read()).decode()


def slug(text):
    out = ""
    for c in text:
        if c.isalnum() or c in "-.":
            out += c
        elif out and out[-1] != "_":
            out += "_"
    return out.rstrip("_") or "x"


def section(folder, report):
    e = html.escape
    parts = [f"<h2>{e(report['scene'])}</h2>",
             f"<p>Reference: raycast {e(report['reference']['model'])}, "
             f"{report['reference']['render_ms']:.0f} ms. Overall: "
             f"<b>{'pass' if report['pass'] else 'FAIL'}</b></p>"]
    for miss in report.get("exceedances", []):
        parts.append(f"<p class=miss>{e(miss)}</p>")
    # A run that failed is reported with its error; the runs that worked are shown below.
    for failed in report.get("failed", []):
        parts.append(f"<p class=miss>{e(failed['label'])} failed: {e(failed['error'])}</p>")
    for note in report.get("skipped", []):
        parts.append(f"<p>{e(note)}</p>")
    # How each colour model was made (auto: which k and the palette error that justified it).
    described = {}
    for run in report["runs"]:
        described.setdefault(run.get("model_asked", run["model"]), run.get("model_description", ""))
    parts.append("<ul class=models>" + "".join(
        f"<li><b>{e(asked)}</b>: {e(text)}</li>" for asked, text in described.items()) + "</ul>")
    parts.append(chart_with_titles(folder, "chart-" + slug(report["scene"])))
    parts.append("<table><tr><th>run</th><th>model</th><th>ms/frame</th><th>first frame ms</th>"
                 "<th>relight fps</th>"
                 "<th>light</th><th>mean ΔE</th><th>p95</th><th>max</th>"
                 "<th title='the run against the same backend with spectral:81 at its own sampling'>"
                 "model</th><th title='that spectral:81 image against the reference'>sampling</th>"
                 "<th>vs raycast</th>"
                 "<th>ΔT</th><th>pass</th></tr>")
    for run in report["runs"]:
        for l in run["lights"]:
            fmt = lambda v: "–" if v is None else f"{v:.3f}"  # noqa: E731
            parts.append(
                f"<tr><td>{e(run['label'])}</td><td>{e(run['model'])}</td>"
                f"<td>{run['render_ms']:.1f}</td><td>{run.get('first_render_ms', run['render_ms']):.1f}</td>"
                f"<td>{run['relight_fps']:.0f}</td>"
                f"<td>{e(l['light'])}</td><td>{fmt(l['de_mean'])}</td><td>{fmt(l['de_p95'])}</td>"
                f"<td>{fmt(l['de_max'])}</td><td>{fmt(l.get('de_model_mean'))}</td>"
                f"<td>{fmt(l.get('de_sampling_mean'))}</td><td>{fmt(l['de_vs_raycast_mean'])}</td>"
                f"<td>{fmt(l['transmittance_error'])}</td>"
                f"<td class={'ok' if l['pass'] else 'miss'}>{'yes' if l['pass'] else 'NO'}</td></tr>")
    parts.append("</table>")
    for i, light in enumerate(report["lights"]):
        parts.append(f"<h3>{e(light)}</h3><div class=row>")
        parts.append(f"<figure><img src='{embed(folder, 'images/reference/' + slug(light) + '.png')}'>"
                     f"<figcaption>reference spectral:81</figcaption></figure>")
        # Each run's relit image with its ΔE2000 map beneath it, so the two read together.
        for run in report["runs"]:
            l = run["lights"][i]
            parts.append(f"<figure><img src='{embed(folder, l['image'])}'>"
                         f"<img class=map src='{embed(folder, l['error_png'])}'>"
                         f"<figcaption>{e(run['label'])}</figcaption></figure>")
        parts.append("</div>")
    return "\n".join(parts)


PAGE = """<!doctype html><html><head><meta charset=utf-8><title>svr report</title><style>
body{{font-family:sans-serif;margin:1em;background:#fafafa}} table{{border-collapse:collapse;font-size:12px}}
td,th{{border:1px solid #ccc;padding:2px 6px;text-align:right}} td:first-child{{text-align:left}}
.row{{display:flex;flex-wrap:wrap;gap:6px}} figure{{margin:0}} figure img{{width:192px;display:block}}
img.map{{width:192px}} ul.models{{font-size:12px}} figcaption{{font-size:11px;max-width:192px}} .miss{{color:#b00}} .ok{{color:#070}}
</style></head><body><h1>svr comparison report</h1>{body}</body></html>"""


def process(folder):
    with open(os.path.join(folder, "report.json")) as f:
        report = json.load(f)
    heat_maps(folder, report)
    speed_accuracy(folder, report)
    body = section(folder, report)
    with open(os.path.join(folder, "report.html"), "w") as f:
        f.write(PAGE.format(body=body))
    return body


def sweep(folder):
    with open(os.path.join(folder, "sweep.json")) as f:
        s = json.load(f)
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 6), dpi=90, sharex=True)
    for curve in s["renderers"]:
        de = [np.nan if v is None else v for v in curve["de_mean"]]
        a1.plot(s["values"], de, marker=".", label=curve["renderer"])
        ms = [np.nan if v is None else v for v in curve["ms"]]  # None: the run failed
        a2.plot(s["values"], ms, marker=".", label=curve["renderer"])
        for flag in curve["flags"]:
            if flag.startswith("jump at "):
                x = float(flag.split()[2])
                a1.axvline(x, color="r", lw=0.5, alpha=0.5)
    a1.set_ylabel("mean ΔE2000 vs reference")
    a1.set_yscale("log")
    a1.legend(fontsize=8)
    a1.grid(True, alpha=0.3)
    a2.set_ylabel("render ms")
    a2.set_xlabel(s["param"])
    a2.grid(True, alpha=0.3)
    a1.set_title(f"{os.path.basename(s['scene'])}: {s['model']}, red lines = flagged jumps")
    fig.tight_layout()
    fig.savefig(os.path.join(folder, f"sweep_{s['param']}.png"))
    plt.close(fig)


def main():
    folder = sys.argv[1]
    if os.path.exists(os.path.join(folder, "sweep.json")):
        sweep(folder)
    elif os.path.exists(os.path.join(folder, "demo.json")):
        with open(os.path.join(folder, "demo.json")) as f:
            demo = json.load(f)
        bodies = [process(os.path.join(folder, sub)) for sub in demo["scenes"]]
        with open(os.path.join(folder, "report.html"), "w") as f:
            f.write(PAGE.format(body="\n<hr>\n".join(bodies)))
    else:
        process(folder)


if __name__ == "__main__":
    main()
