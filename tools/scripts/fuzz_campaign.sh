#!/usr/bin/env bash
# A fuzz campaign: every libFuzzer target of a clang build (-DMOTIONBUS_BUILD_FUZZ=ON) for a
# given time or a given number of executions, each from its committed corpus
# (fuzz/corpus/<name>/) and a work corpus; new inputs are merged back into the committed corpus
# (-merge=1: only those that add coverage), crashes, leaks and timeouts kept under the work
# directory; one row per target: executions, wall-clock seconds, executions a second, coverage
# (libFuzzer's cov: edges), corpus entries before and after, findings.
#
# Usage: tools/scripts/fuzz_campaign.sh [--runs N] BUILD_DIR SECONDS [TARGET_REGEX]
#   SECONDS: the time each target runs (libFuzzer -max_total_time); with --runs N each target
#   runs N executions (libFuzzer -runs) and SECONDS is only a cap (0: none).
#   e.g. tools/scripts/fuzz_campaign.sh build/clang 600
#        tools/scripts/fuzz_campaign.sh build/clang 30 'cli_'
#        tools/scripts/fuzz_campaign.sh --runs 10000000 build/clang 0 '^(core_crc|cli_sr)$'
# Targets run in the order of the build's file names; TARGET_REGEX picks them (bash =~). A
# target whose source has a line `// fuzz-max-len: N` runs with -max_len=N (as under ctest).
# Environment: MOTIONBUS_CAMPAIGN_DIR (default BUILD_DIR/campaign), MOTIONBUS_CAMPAIGN_JOBS
# (libFuzzer -jobs/-workers per target, default 1). Runs under nice; one target at a time (run
# two instances with disjoint regexes to use two cores). Each target's row is also kept in
# <work>/<target>/row.md, so the rows of several instances can be put in one table.
# Exit status 1 when any target reported a finding.
# libFuzzer's -timeout (10 s here) is wall-clock time: a campaign under `nice` beside a job
# that keeps every core busy (a build, the test command) gets so little CPU that an input of
# a few tens of milliseconds can exceed it (cli_monitor, session 21: a 47-79 ms input timed
# out after 11 s beside a clean-clone test run). Run campaigns beside at most one busy core
# per free one, and replay any timeout alone before calling it a finding.
set -euo pipefail
usage="usage: fuzz_campaign.sh [--runs N] BUILD_DIR SECONDS [TARGET_REGEX]"
runs=""
if [ "${1:-}" = "--runs" ]; then
  runs="${2:?$usage}"
  [[ "$runs" =~ ^[0-9]+$ ]] || { echo "$usage" >&2; exit 2; }
  shift 2
fi
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:?$usage}"
seconds="${2:?$usage}"
filter="${3:-.}"
[[ "$seconds" =~ ^[0-9]+$ ]] || { echo "$usage" >&2; exit 2; }
work="$(mkdir -p "${MOTIONBUS_CAMPAIGN_DIR:-$build/campaign}" && cd "${MOTIONBUS_CAMPAIGN_DIR:-$build/campaign}" && pwd)"
build="$(cd "$build" && pwd)"
jobs="${MOTIONBUS_CAMPAIGN_JOBS:-1}"
table="$work/campaign.md"
findings=0
header='| target | executions | seconds | exec/s | coverage (edges) | corpus before | corpus after | findings |\n|---|---|---|---|---|---|---|---|\n'
printf "$header" >"$table"
shopt -s nullglob
for bin in "$build"/fuzz/motionbus_fuzz_*; do
  name="${bin##*/motionbus_fuzz_}"
  [[ "$name" =~ $filter ]] || continue
  corpus="$root/fuzz/corpus/$name"
  rm -rf "$work/$name/artifacts"
  mkdir -p "$corpus" "$work/$name/new" "$work/$name/artifacts"
  before=$(find "$corpus" -type f | wc -l)
  log="$work/$name/run.log"
  limits=()
  if [ -n "$runs" ]; then
    limits=(-runs="$runs")
    echo "=== $name: $runs executions" >&2
  else
    echo "=== $name: $seconds s" >&2
  fi
  if [ "$seconds" -gt 0 ]; then
    limits+=(-max_total_time="$seconds")
  fi
  # the input length the target's source names (`// fuzz-max-len: N`), as under ctest
  src="$root/fuzz/${name%%_*}/${name#*_}_fuzz.cpp"
  max_len=$(sed -nE 's|^// fuzz-max-len: ([0-9]+).*|\1|p' "$src" 2>/dev/null | head -n 1 || true)
  if [ -n "$max_len" ]; then
    limits+=(-max_len="$max_len")
  fi
  rc=0
  parallel=()
  if [ "$jobs" -gt 1 ]; then
    parallel=(-jobs="$jobs" -workers="$jobs")  # each job logs to fuzz-N.log in its directory
  fi
  start=$(date +%s)
  (cd "$work/$name" && nice "$bin" "${limits[@]}" -timeout=10 -print_final_stats=1 \
    "${parallel[@]}" -artifact_prefix="$work/$name/artifacts/" "$work/$name/new" "$corpus") \
    >"$log" 2>&1 || rc=$?
  elapsed=$(($(date +%s) - start))
  if [ "$jobs" -gt 1 ]; then
    cat "$work/$name"/fuzz-*.log >>"$log" 2>/dev/null || true
    rm -f "$work/$name"/fuzz-*.log
  fi
  execs=$(grep -E '^stat::number_of_executed_units' "$log" | awk '{s += $2} END {print s + 0}')
  rate=$(awk -v e="$execs" -v t="$elapsed" 'BEGIN {printf "%d", (t > 0 ? e / t : e)}')
  cov=$(grep -oE 'cov: [0-9]+' "$log" | tail -n 1 | awk '{print $2}')
  # only the inputs that add coverage go into the committed corpus
  nice "$bin" -merge=1 "$corpus" "$work/$name/new" >"$work/$name/merge.log" 2>&1 || true
  after=$(find "$corpus" -type f | wc -l)
  found=$(find "$work/$name/artifacts" -type f | wc -l)
  if [ "$rc" -ne 0 ] && [ "$found" -eq 0 ]; then
    found=1  # the fuzzer failed without leaving its input: see the log
  fi
  findings=$((findings + found))
  printf '| %s | %s | %s | %s | %s | %s | %s | %s |\n' "$name" "$execs" "$elapsed" "$rate" \
    "${cov:-?}" "$before" "$after" "$found" | tee "$work/$name/row.md" >>"$table"
done
cat "$table"
echo "campaign: table in $table; findings (inputs) under $work/*/artifacts/" >&2
[ "$findings" -eq 0 ]
