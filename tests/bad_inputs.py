#!/usr/bin/env python3
"""Runs `svr` on every malformed input in tests/data/bad/cases.txt and checks each refusal.

A case passes when svr exits with a non-zero status (a signal, e.g. a sanitizer abort or a
segfault, is a failure), prints "svr: error: " with the expected substring (which names the
file, key and value) and without naming them twice, and leaves no file behind in the output
folder it was given.

Usage: bad_inputs.py SVR_BINARY CASES_FILE [--data DATA_DIR]
Each line of CASES_FILE is `EXPECTED SUBSTRING :: ARGS`, with {bad} (the folder of the cases
file), {out} (an empty folder for this case) and {data} (the shipped data folder) substituted.
"""
import os
import re
import shlex
import subprocess
import sys
import tempfile


def main() -> int:
    if len(sys.argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    svr, cases_file = os.path.abspath(sys.argv[1]), sys.argv[2]
    data = sys.argv[4] if len(sys.argv) > 4 and sys.argv[3] == "--data" else ""
    bad = os.path.dirname(os.path.abspath(cases_file))
    failures, count = [], 0
    with open(cases_file, encoding="utf-8") as f:
        lines = [(n, l.rstrip("\n")) for n, l in enumerate(f, 1)]
    for number, line in lines:
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        expected, sep, args = line.partition(" :: ")
        if not sep:
            failures.append(f"line {number}: expected `SUBSTRING :: ARGS`")
            continue
        count += 1
        with tempfile.TemporaryDirectory(prefix="svr_bad_") as scratch:
            out = os.path.join(scratch, "out")
            argv = [a.format(bad=bad, out=out, data=data) for a in shlex.split(args)]
            try:
                # cwd = scratch, so a stray relative output would also be caught below.
                run = subprocess.run([svr] + argv, cwd=scratch, capture_output=True, timeout=120)
            except subprocess.TimeoutExpired:
                failures.append(f"line {number}: timed out (a hang): {args}")
                continue
            stderr = run.stderr.decode("utf-8", "replace")
            problems = []
            if run.returncode < 0:
                problems.append(f"killed by signal {-run.returncode}")
            elif run.returncode == 0:
                problems.append("exit status 0")
            elif run.returncode != 2:
                problems.append(f"exit status {run.returncode}, expected 2 (svr::Error)")
            expected = expected.format(bad=bad, out=out, data=data)
            if expected not in stderr:
                problems.append(f"message lacks '{expected}'")
            # An error re-wrapped by a caller that adds what it already says: "a.json: model:
            # a.json: model: …".
            doubled = re.search(r"((?:[^\s:]+: ){2,})\1", stderr)
            if doubled:
                problems.append(f"message repeats '{doubled.group(1)}'")
            left = [os.path.relpath(os.path.join(d, n), scratch)
                    for d, _, names in os.walk(scratch) for n in names]
            if left:
                problems.append(f"left files behind: {left}")
            if problems:
                failures.append(f"line {number}: {'; '.join(problems)}\n    svr {' '.join(argv)}"
                                f"\n    stderr: {stderr.strip()[-600:]}")
    for failure in failures:
        print("FAIL", failure)
    print(f"{count - len([f for f in failures if 'ARGS' not in f])} of {count} bad inputs refused "
          "correctly")
    return 1 if failures or count == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
