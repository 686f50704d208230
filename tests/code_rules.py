#!/usr/bin/env python3
"""The house rules the code keeps (issue 46, docs in README "Layout"), checked on the source tree:

- no function in spectral/, renderers/, harness/, api/, include/ or python/ is longer than 120 lines
  (Universal Ctags gives each function's first and last line; lambdas count in the function
  that holds them);
- a backend (a folder of renderers/ with its own CMakeLists.txt) includes no other backend's
  folder, nor the registry that lists them: what backends share lives in renderers/core/, and
  each takes its entry's type from renderers/core/backend_entry.h;
- the harness (and the public API) reaches backends only through renderers/registry.h: it
  includes no backend's folder.

Usage: code_rules.py SOURCE_DIR   Exit 0: every rule holds; 1: the violations, one a line.
"""
import os
import re
import subprocess
import sys

MAX_LINES = 120
FOLDERS = ["spectral", "renderers", "harness", "api", "include", "python"]
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
                                     f"takes its entry from renderers/core/backend_entry.h; only "
                                     f"registry.* names the backends)")
                        continue
                    m = INCLUDE.match(line)
                    if not m or m.group(1) not in backends or m.group(1) == owner:
                        continue
                    if owner:
                        found.append(f"{where}: backend {owner} includes backend {m.group(1)}'s "
                                     f"folder (shared code belongs in renderers/core/)")
                    else:
                        found.append(f"{where}: includes backend {m.group(1)}'s folder (reach "
                                     f"backends through renderers/registry.h)")
    return found


def main() -> int:
    root = os.path.abspath(sys.argv[1])
    problems = long_functions(root) + crossed_includes(root)
    for p in problems:
        print("FAIL:", p)
    if not problems:
        print(f"ok: no function over {MAX_LINES} lines in {', '.join(FOLDERS)}; no backend "
              f"includes another's folder or the registry; the harness reaches backends only through the "
              f"registry")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
