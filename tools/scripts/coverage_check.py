#!/usr/bin/env python3
"""Line and branch coverage of include/ from a MOTIONBUS_COVERAGE build, after its tests ran.

Usage: coverage_check.py <source root> <coverage build dir> [--json GCOVR_JSON]

Runs gcovr over the build's gcov data (or, with --json, reads a gcovr JSON report instead: the
self-test, tests/checks/coverage_gate), writes <build>/coverage-report.txt (totals, each header,
every uncovered line with its justification, every uncovered branch) and <build>/coverage.json,
prints the totals, and fails
  - when a line of include/ that no test executed carries no justification, or
  - when the branch coverage of include/ is below BRANCH_MIN (90 %).

Branches are gcov's, as gcovr counts them with --exclude-unreachable-branches (the branches
gcc adds for lines that hold no code of their own, e.g. a closing brace) and
--exclude-throw-branches (the edges to the exception path of a call that may throw; include/
never throws, but the tests' doctest checks and the standard library may: those edges are the
compiler's, not the library's decisions). Every other branch counts.

A justification is a comment in the header itself:
  ... code ...  // coverage: <why no test reaches this line>
on the uncovered line, or on a comment line of its own directly above it; or a region
  // coverage-begin: <why>
  ... lines ...
  // coverage-end
A justification on a line that the tests do execute is stale and fails the check too.
An unexecuted line's justification covers its branches too. An uncovered branch of an executed
line is justified by
  ... code ...  // coverage-branch: <why no test takes this branch>
(on the line, or on a comment line of its own directly above it); a branch justification on a
line whose branches are all taken is stale and fails the check. Unjustified uncovered branches
are listed in the report; only their share counts against BRANCH_MIN.
"""
import json
import os
import re
import subprocess
import sys

BRANCH_MIN = 90.0
MARK = re.compile(r"//\s*coverage:\s*(\S.*)$")
BRANCH_MARK = re.compile(r"//\s*coverage-branch:\s*(\S.*)$")
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


def branch_justifications(lines):
    """Line number -> (marker line, reason) for every `coverage-branch:` marker."""
    out = {}
    for i, text in enumerate(lines, start=1):
        m = BRANCH_MARK.search(text)
        if m:
            target = i + 1 if text.strip().startswith("//") else i
            out[target] = (i, m.group(1))
    return out


def main():
    args = sys.argv[1:]
    given = None
    if len(args) == 4 and args[2] == "--json":
        given = args[3]
        args = args[:2]
    if len(args) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    root = os.path.abspath(args[0])
    build = os.path.abspath(args[1])
    data = os.path.join(build, "coverage.json")
    if given is not None:
        data = given
    else:
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
    branch_justified = []
    branch_open = []
    for entry in sorted(files, key=lambda e: e["file"]):
        path = entry["file"]
        with open(os.path.join(root, path), encoding="utf-8") as f:
            src = f.read().splitlines()
        why, marks = justifications(src)
        branch_why = branch_justifications(src)
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
        for l in lines:
            n = l["line_number"]
            untaken = sum(1 for b in l["branches"] if b["count"] == 0)
            if n in branch_why and untaken == 0:
                problems.append(f"{path}:{branch_why[n][0]}: stale branch justification "
                                f"(every branch of line {n} is taken)")
            if untaken == 0:
                continue
            where = f"{path}:{n}: {untaken} of {len(l['branches'])} branches not taken"
            if n in why and l["count"] == 0:
                branch_justified.append(f"{where} (line not executed: {why[n]})")
            elif n in branch_why:
                branch_justified.append(f"{where}: {branch_why[n][1]}")
            else:
                branch_open.append(f"{where}: {src[n - 1].strip()}")

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
    report += ["", f"lines with untaken branches, justified in the headers: "
               f"{len(branch_justified)}"] + branch_justified
    report += ["", f"lines with untaken branches, not justified: {len(branch_open)}"] + branch_open
    branch_pct = pct(total_br_hit, total_br)
    if branch_pct < BRANCH_MIN:
        problems.append(f"branch coverage of include/ {branch_pct:.1f} % is below "
                        f"{BRANCH_MIN:.0f} % ({total_br_hit} of {total_br} branches taken)")
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
    print(f"coverage: branches at or above {BRANCH_MIN:.0f} %; {len(justified)} uncovered lines, "
          f"each justified; lines with untaken branches: {len(branch_justified)} justified, "
          f"{len(branch_open)} not; report in {where}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
