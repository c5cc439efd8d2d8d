#!/usr/bin/env python3
"""Self-test of tools/scripts/coverage_check.py's gates and of its merge of gcov's records on
synthetic gcov JSON documents (what `gcov --stdout --json-format --branch-probabilities`
prints, one document an object file): a header in a scratch source tree, records saying which
of its lines and branches ran, and the exit status, figures and problems the script must give
(ctest: coverage.gate)."""
import json
import os
import subprocess
import sys
import tempfile

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "tools",
                      "scripts", "coverage_check.py")

HEADER = """\
inline int f(int a, int b) {
  if (a > b) {  // coverage-branch: JUSTIFIED_BRANCH
    return a;
  }
  if (a < 0) {
    // coverage: JUSTIFIED_LINE
    return -a;
  }
  return b;
}
"""


def line(n, count, taken, fn="f", throw=()):
    """A gcov line record of function `fn` with one branch per entry of `taken` (its count):
    two-way decisions (a fallthrough edge, then a jump), or, at the positions in `throw`, the
    return edge of a call and its edge to the exception path."""
    branches = []
    for i, c in enumerate(taken):
        if i in throw:
            flags = {"fallthrough": True, "throw": False}
        elif i - 1 in throw:
            flags = {"fallthrough": False, "throw": True}
        else:
            flags = {"fallthrough": len(branches) % 2 == 0, "throw": False}
        branches.append({"count": c, **flags})
    return {"line_number": n, "count": count, "branches": branches, "function_name": fn,
            "unexecuted_block": count == 0}


def run(lines, header=HEADER, more=()):
    """The script on `lines` as one object file's records (and each list of `more` as one
    more object file's)."""
    with tempfile.TemporaryDirectory() as tmp:
        os.makedirs(os.path.join(tmp, "include"))
        with open(os.path.join(tmp, "include", "h.hpp"), "w", encoding="utf-8") as f:
            f.write(header)
        data = os.path.join(tmp, "gcov.jsonl")
        with open(data, "w", encoding="utf-8") as f:
            for records in [lines, *more]:
                f.write(json.dumps({"format_version": "1", "current_working_directory": tmp,
                                    "files": [{"file": "include/h.hpp", "lines": records}]})
                        + "\n")
        p = subprocess.run([sys.executable, SCRIPT, tmp, tmp, "--gcov-json", data],
                           capture_output=True, text=True, check=False)
        with open(os.path.join(tmp, "coverage-report.txt"), encoding="utf-8") as f:
            report = f.read()
    return p.returncode, p.stdout + p.stderr, report


failures = []


def expect(name, cond, detail):
    if not cond:
        failures.append(f"{name}: {detail}")


def base(extra_taken):
    """Lines 1-9: line 2's two branches (one untaken, justified), line 5's two taken, the
    justified line 7 not executed, and `extra_taken` more branches on line 9 (each taken when
    its count is > 0)."""
    return [line(1, 5, []), line(2, 5, [5, 0]), line(3, 2, []), line(5, 3, [3, 3]),
            line(7, 0, []), line(9, 3, extra_taken)]


# 9 of 10 branches taken: exactly the floor, passes; the justified ones listed as such.
rc, out, report = run(base([1, 1, 1, 1, 1, 1]))
expect("at 90 %", rc == 0, f"exit {rc}, expected 0\n{out}")
expect("at 90 %", "branches: 90.0 % (9 of 10)" in out, out)
expect("at 90 %", "JUSTIFIED_BRANCH" in report, "the branch justification is not reported")
# 8 of 10: below the floor, fails naming the figure.
rc, out, _ = run(base([1, 1, 1, 1, 1, 0]))
expect("below 90 %", rc == 1, f"exit {rc}, expected 1\n{out}")
expect("below 90 %", "branch coverage of include/ 80.0 % is below 90 %" in out, out)
expect("below 90 %", "h.hpp:9: 1 of 6 branches not taken" in _, "the open branch is not listed")
# an executed line with an untaken branch and no justification fails, though 20 of 22 branches
# (above the floor) are taken: the scratch-commit case, a decision no test takes both ways
rc, out, report = run(base([1] * 17 + [0]))
expect("open branch", rc == 1, f"exit {rc}, expected 1 (20 of 22 taken, one unjustified)\n{out}")
expect("open branch", "h.hpp:9: 1 of 18 branches not taken and not justified: return b;" in out,
       out)
expect("open branch", "lines with untaken branches, not justified: 1" in report, report)
expect("open branch", "problems: 1" in report, report)
# the same report with that line justified in the header passes, the reason in the report
rc, out, report = run(base([1] * 17 + [0]),
                      HEADER.replace("  return b;", "  return b;  // coverage-branch: JUSTIFIED_9"))
expect("justified branch", rc == 0, f"exit {rc}, expected 0\n{out}")
expect("justified branch", "h.hpp:9: 1 of 18 branches not taken: JUSTIFIED_9" in report, report)
expect("justified branch", "lines with untaken branches, not justified: 0" in report, report)
# ... and so does a justification on a comment line of its own directly above the line (now
# line 10), but not one with a blank line between (the line is then 11)
lines = base([1] * 17 + [0])
lines[5] = line(10, 3, [1] * 17 + [0])
above = HEADER.replace("  return b;", "  // coverage-branch: JUSTIFIED_10\n  return b;")
rc, out, report = run(lines, above)
expect("justified above", rc == 0 and "JUSTIFIED_10" in report, f"exit {rc}\n{out}")
lines[5] = line(11, 3, [1] * 17 + [0])
rc, out, _ = run(lines, above.replace("JUSTIFIED_10\n", "JUSTIFIED_10\n\n"))
expect("justified too far above", rc == 1 and "h.hpp:11: 1 of 18 branches not taken and not "
       "justified" in out, f"exit {rc}\n{out}")
# the merge of gcov's records: line 5's decision taken one way by an instance in one object
# file and the other way by another instance in another: both ways taken, 9 of 10
lines = base([1, 1, 1, 1, 1, 1])
lines[3] = line(5, 3, [3, 0], fn="f<int>")
rc, out, _ = run(lines, more=[[line(5, 1, [0, 1], fn="f<long>")]])
expect("instances merged", rc == 0 and "branches: 90.0 % (9 of 10)" in out, f"exit {rc}\n{out}")
rc, out, _ = run(lines)
expect("one instance alone", rc == 1 and "branches: 80.0 % (8 of 10)" in out, f"exit {rc}\n{out}")
# a call that may throw: its throw edge and its return edge are not counted (taken or not)
lines = base([1, 1, 1, 1, 1, 1])
lines[5] = line(9, 3, [1, 1, 3, 0, 1, 1, 1, 1], throw=(2,))
rc, out, _ = run(lines)
expect("throw edges", rc == 0 and "branches: 90.0 % (9 of 10)" in out, f"exit {rc}\n{out}")
# a line with no code of its own (`}`): its branches are not counted, nor is it a line when
# no test executed it
lines = base([1, 1, 1, 1, 1, 1]) + [line(4, 0, [0, 0]), line(10, 1, [0, 0])]
rc, out, _ = run(lines)
expect("unreachable", rc == 0 and "lines:    85.7 % (6 of 7)" in out
       and "branches: 90.0 % (9 of 10)" in out, f"exit {rc}\n{out}")
# a record of three functions' branches appended (gcov's line of several functions) folds onto
# a function's record of the line: each way of line 9's decision taken by one of them
lines = base([1, 0, 1, 0, 1, 0])
rc, out, report = run(lines, more=[[line(9, 1, [0, 1], fn="h")]])
expect("folded", "branches: 83.3 % (5 of 6)" in out
       and "h.hpp:9: 6 branches folded onto 2" in report, f"exit {rc}\n{out}\n{report}")
# two records of different shapes that do not repeat one another each count on their own
rc, out, _ = run(base([1, 1, 1, 1]), more=[[line(9, 1, [1, 1, 1, 0, 1, 1], fn="h")]])
expect("shapes apart", "branches: 85.7 % (12 of 14)" in out, f"exit {rc}\n{out}")
# an unexecuted line with no justification fails, whatever the branches
lines = base([1, 1, 1, 1, 1, 1])
lines[3] = line(5, 0, [3, 3])
rc, out, _ = run(lines)
expect("unjustified line", rc == 1 and "h.hpp:5: not executed" in out, out)
# a branch justification on a line whose branches are all taken is stale
lines = base([1, 1, 1, 1, 1, 1])
lines[1] = line(2, 5, [5, 5])
rc, out, _ = run(lines)
expect("stale branch justification", rc == 1 and "stale branch justification" in out, out)
# a line justification on an executed line is stale
lines = base([1, 1, 1, 1, 1, 1])
lines[4] = line(7, 1, [])
rc, out, _ = run(lines)
expect("stale line justification", rc == 1 and "stale justification" in out, out)

if failures:
    print("\n".join(failures))
    sys.exit(1)
print("coverage gate: 15 cases as expected")
