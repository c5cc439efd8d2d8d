#!/usr/bin/env bash
# A fuzz campaign: every libFuzzer target of a clang build (-DMOTIONBUS_BUILD_FUZZ=ON) for a
# given time, each from its committed corpus (fuzz/corpus/<name>/) and a work corpus; new
# inputs are merged back into the committed corpus (-merge=1: only those that add coverage),
# crashes, leaks and timeouts kept under the work directory; one row per target: executions,
# executions a second, coverage (libFuzzer's cov: edges), corpus entries before and after,
# findings.
#
# Usage: tools/scripts/fuzz_campaign.sh BUILD_DIR SECONDS_PER_TARGET [TARGET_REGEX]
#   e.g. tools/scripts/fuzz_campaign.sh build/clang 600
#        tools/scripts/fuzz_campaign.sh build/clang 30 'cli_'
# Environment: MOTIONBUS_CAMPAIGN_DIR (default BUILD_DIR/campaign), MOTIONBUS_CAMPAIGN_JOBS
# (libFuzzer -jobs/-workers per target, default 1). Runs under nice; one target at a time.
# Exit status 1 when any target reported a finding.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:?usage: fuzz_campaign.sh BUILD_DIR SECONDS [TARGET_REGEX]}"
seconds="${2:?usage: fuzz_campaign.sh BUILD_DIR SECONDS [TARGET_REGEX]}"
filter="${3:-.}"
work="$(mkdir -p "${MOTIONBUS_CAMPAIGN_DIR:-$build/campaign}" && cd "${MOTIONBUS_CAMPAIGN_DIR:-$build/campaign}" && pwd)"
build="$(cd "$build" && pwd)"
jobs="${MOTIONBUS_CAMPAIGN_JOBS:-1}"
mkdir -p "$work"
table="$work/campaign.md"
findings=0
printf '| target | seconds | executions | exec/s | coverage (edges) | corpus before | corpus after | findings |\n|---|---|---|---|---|---|---|---|\n' >"$table"
shopt -s nullglob
for bin in "$build"/fuzz/motionbus_fuzz_*; do
  name="${bin##*/motionbus_fuzz_}"
  [[ "$name" =~ $filter ]] || continue
  corpus="$root/fuzz/corpus/$name"
  mkdir -p "$corpus" "$work/$name/new" "$work/$name/artifacts"
  before=$(find "$corpus" -type f | wc -l)
  log="$work/$name/run.log"
  echo "=== $name: $seconds s" >&2
  rc=0
  parallel=()
  if [ "$jobs" -gt 1 ]; then
    parallel=(-jobs="$jobs" -workers="$jobs")  # each job logs to fuzz-N.log in its directory
  fi
  (cd "$work/$name" && nice "$bin" -max_total_time="$seconds" -timeout=10 -print_final_stats=1 \
    "${parallel[@]}" -artifact_prefix="$work/$name/artifacts/" "$work/$name/new" "$corpus") \
    >"$log" 2>&1 || rc=$?
  if [ "$jobs" -gt 1 ]; then
    cat "$work/$name"/fuzz-*.log >>"$log" 2>/dev/null || true
    rm -f "$work/$name"/fuzz-*.log
  fi
  execs=$(grep -E '^stat::number_of_executed_units' "$log" | awk '{s += $2} END {print s + 0}')
  rate=$(grep -E '^stat::average_exec_per_sec' "$log" | awk '{s += $2} END {print s + 0}')
  cov=$(grep -oE 'cov: [0-9]+' "$log" | tail -n 1 | awk '{print $2}')
  # only the inputs that add coverage go into the committed corpus
  nice "$bin" -merge=1 "$corpus" "$work/$name/new" >"$work/$name/merge.log" 2>&1 || true
  after=$(find "$corpus" -type f | wc -l)
  found=$(find "$work/$name/artifacts" -type f | wc -l)
  if [ "$rc" -ne 0 ] && [ "$found" -eq 0 ]; then
    found=1  # the fuzzer failed without leaving its input: see the log
  fi
  findings=$((findings + found))
  printf '| %s | %s | %s | %s | %s | %s | %s | %s |\n' "$name" "$seconds" "$execs" "$rate" \
    "${cov:-?}" "$before" "$after" "$found" >>"$table"
done
cat "$table"
echo "campaign: table in $table; findings (inputs) under $work/*/artifacts/" >&2
[ "$findings" -eq 0 ]
