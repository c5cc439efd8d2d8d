#!/usr/bin/env python3
"""Line and branch coverage of include/ from a MOTIONBUS_COVERAGE build, after its tests ran.

Usage: coverage_check.py <source root> <coverage build dir>

Runs gcovr over the build's gcov data, writes <build>/coverage-report.txt (totals, each
header, every uncovered line with its justification) and <build>/coverage.json, prints the
totals, and fails when a line of include/ that no test executed carries no justification.

A justification is a comment in the header itself:
  ... code ...  // coverage: <why no test reaches this line>
on the uncovered line, or on a comment line of its own directly above it; or a region
  // coverage-begin: <why>
  ... lines ...
  // coverage-end
A justification on a line that the tests do execute is stale and fails the check too.
"""
import json
import os
import re
import subprocess
import sys

MARK = re.compile(r"//\s*coverage:\s*(\S.*)$")
BEGIN = re.compile(r"//\s*coverage-begin:\s*(\S.*)$")
END = re.compile(r"//\s*coverage-end\b")


def justifications(lines):
    """Line number -> reason for every line a justification covers, and the single-line
    markers as (marker line, line it justifies) pairs (for the stale check)."""
    out = {}
    marks = []
    region = None
    for i, text in enumerate(lines, start=1):
        begin = BEGIN.search(text)
        if begin:
            region = begin.group(1)
            continue
        if END.search(text):
            region = None
            continue
        if region is not None:
            out[i] = region
        m = MARK.search(text)
        if m:
            # a comment line of its own applies to the next line
            target = i + 1 if text.strip().startswith("//") else i
            out[target] = m.group(1)
            marks.append((i, target))
    return out, marks


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    root = os.path.abspath(sys.argv[1])
    build = os.path.abspath(sys.argv[2])
    data = os.path.join(build, "coverage.json")
    cmd = ["gcovr", "-r", root, "--filter", os.path.join(root, "include") + "/", build,
           "--exclude-unreachable-branches", "--exclude-throw-branches", "--json", data]
    rc = subprocess.run(cmd, check=False).returncode
    if rc != 0:
        print("coverage: gcovr failed", file=sys.stderr)
        return 1
    with open(data, encoding="utf-8") as f:
        files = json.load(f)["files"]
    if not files:
        print("coverage: no gcov data for include/ (did the tests run?)", file=sys.stderr)
        return 1
    total_lines = total_hit = total_br = total_br_hit = 0
    rows = []
    problems = []
    justified = []
    for entry in sorted(files, key=lambda e: e["file"]):
        path = entry["file"]
        with open(os.path.join(root, path), encoding="utf-8") as f:
            src = f.read().splitlines()
        why, marks = justifications(src)
        lines = [l for l in entry["lines"] if not l.get("gcovr/noncode")]
        executed = {l["line_number"] for l in lines if l["count"] > 0}
        missed = sorted(l["line_number"] for l in lines if l["count"] == 0)
        branches = [b for l in lines for b in l["branches"]]
        br_hit = sum(1 for b in branches if b["count"] > 0)
        total_lines += len(lines)
        total_hit += len(executed)
        total_br += len(branches)
        total_br_hit += br_hit
        rows.append((path, len(lines), len(executed), len(branches), br_hit))
        for n in missed:
            if n in why:
                justified.append(f"{path}:{n}: {why[n]}")
            else:
                problems.append(f"{path}:{n}: not executed by any test and not justified: "
                                f"{src[n - 1].strip()}")
        for at, target in marks:
            if target in executed:
                problems.append(f"{path}:{at}: stale justification (line {target} is executed)")

    def pct(a, b):
        return 100.0 * a / b if b else 100.0

    report = [f"motionbus coverage of include/ (gcov, -O0, every test of the coverage build)",
              f"lines:    {pct(total_hit, total_lines):.1f} % ({total_hit} of {total_lines})",
              f"branches: {pct(total_br_hit, total_br):.1f} % ({total_br_hit} of {total_br})",
              "", f"{'header':<48} {'lines':>14} {'branches':>16}"]
    for path, n, hit, nb, bhit in rows:
        report.append(f"{path:<48} {pct(hit, n):6.1f} % {hit:>4}/{n:<4} "
                      f"{pct(bhit, nb):6.1f} % {bhit:>4}/{nb:<4}")
    report += ["", f"uncovered lines justified in the headers: {len(justified)}"] + justified
    if problems:
        report += ["", f"problems: {len(problems)}"] + problems
    with open(os.path.join(build, "coverage-report.txt"), "w", encoding="utf-8") as f:
        f.write("\n".join(report) + "\n")
    print("\n".join(report[:3]))
    where = os.path.join(build, "coverage-report.txt")
    if problems:
        print(f"coverage: {len(problems)} problems (below); report in {where}")
        print("\n".join(problems), file=sys.stderr)
        return 1
    print(f"coverage: {len(justified)} uncovered lines, each justified; report in {where}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
