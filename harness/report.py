#!/usr/bin/env python3
"""Charts and the HTML page of an `svr compare` (or `svr demo`) report folder.

  report.py DIR      DIR holds report.json (compare) or demo.json listing scene folders (demo)

Writes, per compare folder: a ΔE2000 heat map with a colour bar beside every error map
(maps/**/*.pfm → .png), speed_accuracy.png and speed_accuracy.json (time per frame against
mean ΔE2000, both log, Pareto front marked), and report.html: one self-contained page (images
embedded) with the relit images side by side per light, the error maps, the chart and the tables.
A demo folder gets one report.html with a section per scene. Needs Debian's python3-matplotlib.
"""
import base64
import html
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
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


def speed_accuracy(folder, report):
    labels, points = [], []
    for run in report["runs"]:
        errors = [l["de_mean"] for l in run["lights"] if l["de_mean"] is not None]
        if not errors:
            continue
        labels.append(run["label"])
        points.append((max(run["render_ms"], 1e-3), max(float(np.mean(errors)), 1e-3)))
    front = pareto(points)
    fig, ax = plt.subplots(figsize=(7, 5), dpi=90)
    renderers = sorted({l.split(" ")[0] for l in labels})
    markers = dict(zip(renderers, "osD^v<>p*h"))
    colours = {r: f"C{i}" for i, r in enumerate(renderers)}
    for (t, e), label in zip(points, labels):
        r = label.split(" ")[0]
        ax.scatter(t, e, marker=markers[r], color=colours[r], s=40, label=r)
        ax.annotate(label[len(r) + 1:], (t, e), fontsize=7, xytext=(4, 3), textcoords="offset points")
    if front:
        ax.plot([points[i][0] for i in front], [points[i][1] for i in front], "k--", lw=1,
                label="Pareto front")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("render time per frame (ms)")
    ax.set_ylabel("mean ΔE2000 against spectral:81 reference")
    ax.set_title(os.path.basename(report["scene"]))
    handles, names = ax.get_legend_handles_labels()
    unique = dict(zip(names, handles))
    ax.legend(unique.values(), unique.keys(), fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(folder, "speed_accuracy.png"))
    plt.close(fig)
    with open(os.path.join(folder, "speed_accuracy.json"), "w") as f:
        json.dump({"points": [{"run": l, "ms": p[0], "de_mean": p[1], "pareto": i in front}
                              for i, (l, p) in enumerate(zip(labels, points))]}, f, indent=1)


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
    # How each colour model was made (auto: which k and the palette error that justified it).
    described = {}
    for run in report["runs"]:
        described.setdefault(run.get("model_asked", run["model"]), run.get("model_description", ""))
    parts.append("<ul class=models>" + "".join(
        f"<li><b>{e(asked)}</b>: {e(text)}</li>" for asked, text in described.items()) + "</ul>")
    parts.append(f"<img src='{embed(folder, 'speed_accuracy.png')}'>")
    parts.append("<table><tr><th>run</th><th>model</th><th>ms/frame</th><th>first frame ms</th>"
                 "<th>relight fps</th>"
                 "<th>light</th><th>mean ΔE</th><th>p95</th><th>max</th><th>vs raycast</th>"
                 "<th>ΔT</th><th>pass</th></tr>")
    for run in report["runs"]:
        for l in run["lights"]:
            fmt = lambda v: "–" if v is None else f"{v:.3f}"  # noqa: E731
            parts.append(
                f"<tr><td>{e(run['label'])}</td><td>{e(run['model'])}</td>"
                f"<td>{run['render_ms']:.1f}</td><td>{run.get('first_render_ms', run['render_ms']):.1f}</td>"
                f"<td>{run['relight_fps']:.0f}</td>"
                f"<td>{e(l['light'])}</td><td>{fmt(l['de_mean'])}</td><td>{fmt(l['de_p95'])}</td>"
                f"<td>{fmt(l['de_max'])}</td><td>{fmt(l['de_vs_raycast_mean'])}</td>"
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
        a2.plot(s["values"], curve["ms"], marker=".", label=curve["renderer"])
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
