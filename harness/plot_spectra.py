"""Plots the spectra written by `svr design` (spectra.csv): lights above, materials below.

Usage: plot_spectra.py SPECTRA.csv OUT.png N_LIGHTS
Run with Debian's /usr/bin/python3 (python3-matplotlib)."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    path, out, n_lights = sys.argv[1], sys.argv[2], int(sys.argv[3])
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    names = rows[0][1:]
    data = [[float(v) for v in r] for r in rows[1:]]
    wl = [r[0] for r in data]
    fig, axes = plt.subplots(2, 1, figsize=(8, 7), sharex=True)
    for j, name in enumerate(names):
        ax = axes[0] if j < n_lights else axes[1]
        ax.plot(wl, [r[j + 1] for r in data], label=name)
    axes[0].set_title("lights (flat E = 1 has Y = 1)")
    axes[1].set_title("reflectances")
    axes[1].set_xlabel("wavelength (nm)")
    for ax in axes:
        ax.legend(fontsize=7, ncol=2)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=100)


if __name__ == "__main__":
    main()
