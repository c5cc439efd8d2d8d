#!/usr/bin/env python3
"""Self-test of tools/scripts/coverage_check.py's gates on synthetic gcovr JSON reports: a
header in a scratch source tree, a report saying which of its lines and branches ran, and the
exit status and problems the script must give (ctest: coverage.gate)."""
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


def line(n, count, taken):
    """A gcovr line record with one branch per entry of `taken` (its count)."""
    return {"line_number": n, "count": count, "branches": [{"count": c} for c in taken]}


def run(lines, header=HEADER):
    with tempfile.TemporaryDirectory() as tmp:
        os.makedirs(os.path.join(tmp, "include"))
        with open(os.path.join(tmp, "include", "h.hpp"), "w", encoding="utf-8") as f:
            f.write(header)
        data = os.path.join(tmp, "cov.json")
        with open(data, "w", encoding="utf-8") as f:
            json.dump({"files": [{"file": "include/h.hpp", "lines": lines}]}, f)
        p = subprocess.run([sys.executable, SCRIPT, tmp, tmp, "--json", data],
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
# an executed line with an untaken branch and no justification: listed, not a failure by itself
rc, out, report = run(base([1] * 17 + [0]))
expect("open branch", rc == 0, f"exit {rc}, expected 0 (20 of 22 taken)\n{out}")
expect("open branch", "lines with untaken branches, not justified: 1" in report, report)
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
print("coverage gate: 6 cases as expected")
