#!/usr/bin/env bash
# Runs every libFuzzer target (or the ones named) for SECONDS each, one after another, from its
# seed corpus in tests/fuzz/corpus/<target>/. The seeds are read, never written: new inputs go
# to a scratch corpus, crashes to OUT/<target>/. Prints one summary line per target
# (executions, exec/s, corpus size, coverage) and exits non-zero if any target found a crash,
# a leak, a timeout or an out-of-memory input.
#
# Usage: tests/fuzz/run.sh BUILD_DIR SECONDS [TARGET…]     (BUILD_DIR from `cmake --preset fuzz`)
#   e.g. tests/fuzz/run.sh build/fuzz 30                    (CI)
#        tests/fuzz/run.sh build/fuzz 600 fuzz_scene        (a longer local run)
# OUT defaults to BUILD_DIR/fuzz-out; set FUZZ_OUT to keep it elsewhere.
# A campaign (docs/robustness.md): FUZZ_RUNS=10000000 also stops a target after that many
# executions; FUZZ_MINIMIZE=1 then merges the seeds and what the run found into a minimal
# corpus, OUT/<target>/minimized, to check in as the new seeds. The summary line gives the CPU
# seconds each target used.
set -uo pipefail
if [ $# -lt 2 ]; then
  sed -n '2,15p' "$0" >&2
  exit 2
fi
here="$(cd "$(dirname "$0")" && pwd)"
build="$1" seconds="$2"
shift 2
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_nrrd fuzz_metaimage fuzz_nifti fuzz_tiff fuzz_dicom fuzz_scene fuzz_palette fuzz_csv fuzz_exr)
out="${FUZZ_OUT:-$build/fuzz-out}"
# Leaks inside third-party libraries (teem) are not ours to fix; see the file.
export LSAN_OPTIONS="suppressions=$here/../lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
failed=()
for t in "${targets[@]}"; do
  bin="$build/fuzz/$t" seeds="$here/corpus/${t#fuzz_}"
  [ -x "$bin" ] || { echo "run.sh: $bin not built (cmake --build --preset fuzz)" >&2; exit 2; }
  mkdir -p "$out/$t/corpus" "$out/$t/crashes"
  log="$out/$t/log.txt"
  # -rss_limit_mb / -malloc_limit_mb: an input that makes a parser allocate beyond what any
  # valid small input needs is a finding (the budget checks should have refused it).
  # -timeout: a single input taking 10 s is a hang. -print_final_stats: executions for the note.
  /usr/bin/time -f "%U %S" -o "$out/$t/cpu.txt" \
    "$bin" "$out/$t/corpus" "$seeds" -max_total_time="$seconds" -runs="${FUZZ_RUNS:--1}" \
    -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024 -max_len=8192 -print_final_stats=1 \
    -artifact_prefix="$out/$t/crashes/" >"$log" 2>&1
  status=$?
  cpu=$(awk '{printf "%.0f", $1 + $2}' "$out/$t/cpu.txt" 2>/dev/null)
  if [ "${FUZZ_MINIMIZE:-0}" = 1 ] && [ "$status" -eq 0 ]; then
    rm -rf "$out/$t/minimized" && mkdir -p "$out/$t/minimized"
    "$bin" -merge=1 -max_len=8192 "$out/$t/minimized" "$seeds" "$out/$t/corpus" \
      >"$out/$t/merge.txt" 2>&1
  fi
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$')
  speed=$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "$log" | grep -o '[0-9]*$')
  cov=$(grep -E '^#[0-9]+' "$log" | tail -1 | grep -o 'cov: [0-9]*' | grep -o '[0-9]*')
  corpus=$(find "$out/$t/corpus" -type f | wc -l)
  echo "$t: ${runs:-?} executions, ${cpu:-?} CPU s (${speed:-?}/s), coverage ${cov:-?}, ${corpus} new corpus inputs, exit ${status}"
  if [ "$status" -ne 0 ] || ls "$out/$t/crashes/" | grep -q .; then
    failed+=("$t")
    grep -E '^(==[0-9]+==|SUMMARY|.*ERROR)' "$log" | head -5
    echo "  log: $log; inputs: $out/$t/crashes/"
  fi
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "run.sh: findings in ${failed[*]}" >&2
  exit 1
fi
