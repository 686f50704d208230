#!/usr/bin/env python3
"""The house rules the code keeps (issue 46, docs in README "Layout"), checked on the source tree:

- no function in spectral/, renderers/, harness/, api/, include/ or python/ is longer than 120 lines
  (Universal Ctags gives each function's first and last line; lambdas count in the function
  that holds them);
- every include points down the floors and rooms a frame passes through (design.md §2), never up:
    include/svr (the public headers) < base < spectral < renderers/simd, renderers/memory
    < renderers/volume < renderers/scene < renderers/classification < renderers/render
    < renderers/kernels < the backends < renderers/registry.* < renderers/model < harness < api
    < python;
- a backend (a folder of renderers/ with its own CMakeLists.txt) includes no other backend's
  folder, nor the registry that lists them: what backends share lives in the rooms below them
  (renderers/kernels/ and under), and each takes its entry's type from
  renderers/render/backend_entry.h;
- the harness (and the public API) reaches backends only through renderers/registry.h: it
  includes no backend's folder.

Usage: code_rules.py SOURCE_DIR   Exit 0: every rule holds; 1: the violations, one a line.
"""
import os
import re
import subprocess
import sys

MAX_LINES = 120
FOLDERS = ["base", "spectral", "renderers", "harness", "api", "include", "python"]
INCLUDE = re.compile(r'^\s*#\s*include\s+"renderers/([A-Za-z0-9_]+)/')
REGISTRY = re.compile(r'^\s*#\s*include\s+"renderers/registry\.h"')


def long_functions(root: str) -> list:
    out = subprocess.run(["ctags", "-R", "--languages=C++", "--kinds-C++=f", "--fields=+ne",
                          "--extras=-F", "-o", "-"] + FOLDERS, cwd=root, capture_output=True,
                         text=True, check=True).stdout
    found = []
    for line in out.splitlines():
        fields = line.split("\t")
        extra = dict(f.split(":", 1) for f in fields[3:] if ":" in f)
        if "line" in extra and "end" in extra:
            length = int(extra["end"]) - int(extra["line"]) + 1
            if length > MAX_LINES:
                found.append(f"{fields[1]}:{extra['line']}: {fields[0]} is {length} lines "
                             f"(at most {MAX_LINES})")
    return found


def sources(folder: str):
    for dirpath, _, files in os.walk(folder):
        for name in files:
            if name.endswith((".h", ".cpp", ".inc")):
                yield os.path.join(dirpath, name)


def crossed_includes(root: str) -> list:
    renderers = os.path.join(root, "renderers")
    backends = sorted(d for d in os.listdir(renderers)
                      if os.path.isfile(os.path.join(renderers, d, "CMakeLists.txt")))
    found = []
    owners = [(b, os.path.join(renderers, b)) for b in backends]
    owners += [(None, os.path.join(root, top)) for top in ("harness", "api", "include", "python")]
    for owner, folder in owners:
        for path in sources(folder):
            with open(path, encoding="utf-8") as f:
                for n, line in enumerate(f, 1):
                    where = f"{os.path.relpath(path, root)}:{n}"
                    if owner and REGISTRY.match(line):
                        found.append(f"{where}: backend {owner} includes the registry (a backend "
                                     f"takes its entry from renderers/render/backend_entry.h; only "
                                     f"registry.* names the backends)")
                        continue
                    m = INCLUDE.match(line)
                    if not m or m.group(1) not in backends or m.group(1) == owner:
                        continue
                    if owner:
                        found.append(f"{where}: backend {owner} includes backend {m.group(1)}'s "
                                     f"folder (shared code belongs in renderers/kernels/ or below)")
                    else:
                        found.append(f"{where}: includes backend {m.group(1)}'s folder (reach "
                                     f"backends through renderers/registry.h)")
    return found


# The floors and rooms from the bottom up; a path's level is that of its longest matching prefix.
# Backends (renderers/NAME/ with a CMakeLists.txt) sit at BACKEND_LEVEL.
LEVELS = [("include/", 0), ("svr/", 0), ("base/", 1), ("spectral/", 2), ("renderers/simd/", 3),
          ("renderers/memory/", 3), ("renderers/volume/", 4), ("renderers/scene/", 5),
          ("renderers/classification/", 6), ("renderers/render/", 7), ("renderers/kernels/", 8),
          ("renderers/registry.", 10), ("renderers/model/", 11), ("harness/", 12), ("api/", 13),
          ("python/", 14)]
BACKEND_LEVEL = 9
ANY_INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def level(path: str, backends: list):
    for b in backends:
        if path.startswith(f"renderers/{b}/"):
            return BACKEND_LEVEL
    best = None
    for prefix, lvl in LEVELS:
        if path.startswith(prefix) and (best is None or len(prefix) > len(best[0])):
            best = (prefix, lvl)
    return best[1] if best else None


def upward_includes(root: str) -> list:
    renderers = os.path.join(root, "renderers")
    backends = sorted(d for d in os.listdir(renderers)
                      if os.path.isfile(os.path.join(renderers, d, "CMakeLists.txt")))
    found = []
    for top in FOLDERS:
        for path in sources(os.path.join(root, top)):
            rel = os.path.relpath(path, root)
            own = level(rel, backends)
            if own is None:
                found.append(f"{rel}: in no room of the floor plan (add it to code_rules.LEVELS)")
                continue
            with open(path, encoding="utf-8") as f:
                for n, line in enumerate(f, 1):
                    m = ANY_INCLUDE.match(line)
                    if not m:
                        continue
                    target = level(m.group(1), backends)
                    if target is not None and target > own:
                        found.append(f"{rel}:{n}: includes {m.group(1)}, a room above its own "
                                     f"(includes point down the pipeline: design.md §2)")
    return found


def main() -> int:
    root = os.path.abspath(sys.argv[1])
    problems = long_functions(root) + crossed_includes(root) + upward_includes(root)
    for p in problems:
        print("FAIL:", p)
    if not problems:
        print(f"ok: no function over {MAX_LINES} lines in {', '.join(FOLDERS)}; every include "
              f"points down the rooms; no backend includes another's folder or the registry; the "
              f"harness reaches backends only through the registry")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
